#pragma once
// Skeleton file formats, chosen by extension: .ig (CGoGN incidence graph), .cg / .cgr (CGoGN graphs), .skel
// (adjacency lists with radius), .obj (v / l / f lines; radius convention documented in docs/formats.md).
// Readers: errors throw mesohex::Error naming file:line. Writers: .ig, .obj (atomic).
#include <string>

#include "mesohex/core/skeleton.h"

namespace mesohex {

Skeleton read_skeleton(const std::string& path);
void write_skeleton(const std::string& path, const Skeleton& skeleton);

}  // namespace mesohex
