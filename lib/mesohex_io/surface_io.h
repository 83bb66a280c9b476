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
#include <string_view>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

// Reads the file (at most kMaxInputBytes of text_input.h) and parses it as read_surface_text does.
TriangleMesh read_surface(const std::string& path);
// The same reader on a file's content held in memory: `format` is the extension without the dot (off, obj, stl, ply;
// case-insensitive), `name` stands for the file name in error messages ("<name>:<line>: <what>").
TriangleMesh read_surface_text(std::string_view text, std::string_view format, std::string_view name);

void write_surface(const std::string& path, const TriangleMesh& mesh);

}  // namespace mesohex
