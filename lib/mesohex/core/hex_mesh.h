#pragma once
// The hex mesh: plain indexed arrays. Vertex order of each hex: see hex_convention.h.
#include <array>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex {

struct HexMesh {
    std::vector<Vec3> points;
    std::vector<std::array<int, 8>> hexes;
    friend bool operator==(const HexMesh&, const HexMesh&) = default;
};

// A quad surface (connection surfaces, mesh boundaries). Quads are counter-clockwise seen from outside.
struct QuadMesh {
    std::vector<Vec3> points;
    std::vector<std::array<int, 4>> quads;
    friend bool operator==(const QuadMesh&, const QuadMesh&) = default;
};

// A triangle surface (domain surfaces, thickened skeletons). Triangles counter-clockwise seen from outside.
struct TriangleMesh {
    std::vector<Vec3> points;
    std::vector<std::array<int, 3>> triangles;
    friend bool operator==(const TriangleMesh&, const TriangleMesh&) = default;
};

}  // namespace mesohex
