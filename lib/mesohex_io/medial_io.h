#pragma once
// Medial meshes (.ma, Q-MAT style): header `nv ne nf`, then nv lines `v x y z r`, ne lines `e i j`, nf lines
// `f i j k` (0-based). The edge list includes the triangle sides; "curve-only" edges are those in no triangle.
#include <string>
#include <string_view>

#include "mesohex/core/skeleton.h"

namespace mesohex {

// Reads a .ma file into a Skeleton whose faces are the medial triangles (3 vertices each) and whose edges are the
// file's edges in file order, followed by any triangle side the file omitted (add_face_edges). Radii: one per point.
// Errors: IoError when the file cannot be read; InvalidInput (naming file:line) for an empty file, a bad header, a
// header count larger than the file can hold (nothing is reserved from the header alone), a count that does not
// match the lines present, a malformed line, an index out of range, a repeated vertex in an edge or triangle, a
// duplicated edge, a non-positive or non-finite radius or coordinate. Blank lines and lines starting with '#' are
// skipped. Time and memory are linear in the file size.
// The file is read whole (at most kMaxInputBytes of text_input.h), then parsed as read_medial_mesh_text does.
Skeleton read_medial_mesh(const std::string& path);
// The same on the file's text held in memory; `name` stands for the file name in messages.
Skeleton read_medial_mesh_text(std::string_view content, std::string_view name);

// Writes `medial` (radii one per point, faces triangles, every face side in edges) as a .ma file that
// read_medial_mesh reads back with the same points, radii (17 significant digits), edges and faces. Atomic (a
// temporary file renamed). IoError when the file cannot be written; InvalidInput when radii are missing or a face is
// not a triangle.
void write_medial_mesh(const std::string& path, const Skeleton& medial);

}  // namespace mesohex
