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
// `format` is the extension without the dot (ig, cg, cgr, skel, obj; case-insensitive), `name` stands for the file
// name in error messages ("<name>:<line>: <what>").
Skeleton read_skeleton_text(std::string_view content, std::string_view format, std::string_view name);
// The text write_skeleton writes for `format` (ig or obj); `name` stands for the file name in error messages.
std::string skeleton_text(const Skeleton& skeleton, const std::string& format, const std::string& name);

}  // namespace mesohex
