#pragma once
// Triangle surface file formats, chosen by extension (case-insensitive):
//   read:  .off (ASCII), .obj (v / f lines; polygons fan-triangulated; v/vt/vn and negative indices accepted),
//          .stl (ASCII or binary, detected from the content; identical positions are merged into one vertex),
//          .ply (ASCII, binary little- and big-endian; any extra vertex / face properties such as colours are skipped;
//                other elements are skipped)
//   write: .off, .obj, .stl (binary), always atomically (temporary file + rename).
// Polygons with more than three vertices are split into a fan (v0, vi, vi+1). Faces with fewer than three vertices
// and indices out of range are errors. Parse errors throw mesohex::Error (InvalidInput) naming file:line (for binary
// files: the byte offset); unreadable files throw IoError.
#include <string>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

TriangleMesh read_surface(const std::string& path);

void write_surface(const std::string& path, const TriangleMesh& mesh);

}  // namespace mesohex
