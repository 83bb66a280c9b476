#pragma once
// Small hex meshes for the foundation tests, each checkable on paper.
#include <array>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex::test {

// nx * ny * nz unit cubes; vertex (i, j, k) has id i + (nx + 1) * (j + (ny + 1) * k) and position (i, j, k).
// Hex (i, j, k) has id i + nx * (j + ny * k).
inline HexMesh make_block(int nx, int ny, int nz) {
    HexMesh m;
    for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i) m.points.push_back({double(i), double(j), double(k)});
    auto vid = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                m.hexes.push_back({vid(i, j, k), vid(i + 1, j, k), vid(i + 1, j + 1, k), vid(i, j + 1, k),
                                   vid(i, j, k + 1), vid(i + 1, j, k + 1), vid(i + 1, j + 1, k + 1),
                                   vid(i, j + 1, k + 1)});
    return m;
}

// The 3 x 3 x 1 block without its centre hex: 8 hexes around a hole (a solid torus).
inline HexMesh make_ring8() {
    HexMesh m = make_block(3, 3, 1);
    m.hexes.erase(m.hexes.begin() + 4);  // hex (1, 1, 0)
    return m;
}

inline HexMesh make_unit_cube() { return make_block(1, 1, 1); }

inline std::array<Vec3, 8> corners_of(const HexMesh& m, int h) {
    std::array<Vec3, 8> c;
    for (int i = 0; i < 8; ++i) c[i] = m.points[m.hexes[h][i]];
    return c;
}

}  // namespace mesohex::test
