#pragma once
// The one hex vertex numbering of mesohex: VTK / Verdict / MEDIT order.
//
//            7 -------- 6
//           /|         /|        bottom face 0-1-2-3 is counter-clockwise seen from above (+z),
//          / |        / |        top face 4-5-6-7 stacked above it (4 above 0, 5 above 1, ...).
//         4 -------- 5  |
//         |  3 ------|- 2        The unit cube with 0=(0,0,0) 1=(1,0,0) 2=(1,1,0) 3=(0,1,0)
//         | /        | /         and 4..7 = 0..3 + (0,0,1) has scaled Jacobian +1.
//         |/         |/          Its mirror image (any odd permutation of the axes) has -1.
//         0 -------- 1
//
// Faces are listed with their right-hand normal pointing OUT of the hex.
// Other tools' orders (e.g. CGoGN's outward-bottom convention) are converted in mesohex_io only.
#include <array>

namespace mesohex {

inline constexpr std::array<std::array<int, 2>, 12> kHexEdges = {{
    {0, 1},
    {1, 2},
    {2, 3},
    {3, 0},  // bottom
    {4, 5},
    {5, 6},
    {6, 7},
    {7, 4},  // top
    {0, 4},
    {1, 5},
    {2, 6},
    {3, 7},  // vertical
}};

inline constexpr std::array<std::array<int, 4>, 6> kHexFaces = {{
    {0, 3, 2, 1},  // bottom (-z)
    {4, 5, 6, 7},  // top    (+z)
    {0, 1, 5, 4},  // front  (-y)
    {1, 2, 6, 5},  // right  (+x)
    {2, 3, 7, 6},  // back   (+y)
    {3, 0, 4, 7},  // left   (-x)
}};

// For local face lf and its side i (corners kHexFaces[lf][i] and kHexFaces[lf][(i + 1) % 4]): the local edge
// (index into kHexEdges) along that side.
inline constexpr std::array<std::array<int, 4>, 6> kHexFaceSideEdges = [] {
    std::array<std::array<int, 4>, 6> table{};
    for (std::size_t lf = 0; lf < 6; ++lf)
        for (std::size_t i = 0; i < 4; ++i) {
            const int a = kHexFaces[lf][i], b = kHexFaces[lf][(i + 1) % 4];
            for (std::size_t le = 0; le < 12; ++le)
                if ((kHexEdges[le][0] == a && kHexEdges[le][1] == b) ||
                    (kHexEdges[le][0] == b && kHexEdges[le][1] == a))
                    table[lf][i] = static_cast<int>(le);
        }
    return table;
}();

// For corner lv: its three neighbours (a, b, c) such that (a-lv, b-lv, c-lv) is right-handed on the unit cube.
inline constexpr std::array<std::array<int, 3>, 8> kHexCornerNeighbors = {{
    {1, 3, 4},
    {2, 0, 5},
    {3, 1, 6},
    {0, 2, 7},
    {7, 5, 0},
    {4, 6, 1},
    {5, 7, 2},
    {6, 4, 3},
}};

}  // namespace mesohex
