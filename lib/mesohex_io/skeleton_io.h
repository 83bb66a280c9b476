#pragma once
// Skeleton file formats, chosen by extension: .ig (CGoGN incidence graph), .cg / .cgr (CGoGN graphs), .skel
// (adjacency lists with radius), .obj (v / l / f lines; radius convention documented in docs/formats.md).
// Readers: errors throw mesohex::Error naming file:line. Writers: .ig, .obj (atomic).
#include <string>
#include <string_view>

#include "mesohex/core/skeleton.h"

namespace mesohex {

// Reads the file (at most kMaxInputBytes of text_input.h) and parses it as read_skeleton_text does.
Skeleton read_skeleton(const std::string& path);
void write_skeleton(const std::string& path, const Skeleton& skeleton);

// The same readers on a file's text held in memory (for the studio server, which never opens request paths):
// `format` is the extension without the dot (ig, cg, cgr, skel, obj; case-insensitive) or mhsk (the binary form
// below), `name` stands for the file name in error messages ("<name>:<line>: <what>").
Skeleton read_skeleton_text(std::string_view content, std::string_view format, std::string_view name);
// The text write_skeleton writes for `format` (ig or obj); `name` stands for the file name in error messages.
std::string skeleton_text(const Skeleton& skeleton, const std::string& format, const std::string& name);

// The binary skeleton the studio page uploads (format=mhsk; docs/formats.md, "Binary skeleton"): little-endian,
//   bytes 0-3 "MHSK", then uint32 version (1), V, R (0 or V), E, F, S (the sum of the face sizes), 0 (reserved);
//   then float64 points[3 V], float64 radii[R], uint32 edges[2 E], uint32 face_sizes[F], uint32 face_vertices[S].
// The length must be exactly that. Checks and clean-up as the text readers (finite coordinates, radii > 0, indices in
// range, no self-loop, faces of >= 3 distinct vertices; repeated edges dropped, missing face sides added); errors
// name the byte offset or the skeleton element (Error::where). Values are taken bit for bit (the page writes -0 as 0,
// as its OBJ text does), so skeleton_binary then read_skeleton_binary gives back the identical skeleton.
Skeleton read_skeleton_binary(std::string_view bytes, std::string_view name);
std::string skeleton_binary(const Skeleton& skeleton);

}  // namespace mesohex
