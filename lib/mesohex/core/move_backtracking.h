#pragma once
// Guarded vertex moves, shared by the surface fit and the boundary projection: after a batch of vertices moved, the
// corners of every bad hex take back half of their move (again and again, up to a limit, then the whole move), and
// the hexes around them are measured again, until no bad hex is left or nothing more can move.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesohex/core/topology.h"

namespace mesohex {

// The per-vertex and per-hex state of the halving loop (one entry per vertex / hex of the mesh).
struct MoveBacktracking {
    std::vector<double> scale;           // fraction of its move a vertex keeps (1 -> 1/2 -> ... -> 0)
    std::vector<std::uint8_t> halvings;  // how many times that fraction was halved
    std::vector<std::uint8_t> marked;    // scratch: vertex already in this round's list
    std::vector<std::uint8_t> queued;    // scratch: hex already in the next round's list
    int max_backtracks = 0;              // halvings after which the vertex keeps none of its move
};

// check: the bad hexes of the first round (ascending). bad(h, first_round) says whether hex h still needs a vertex
// to back off; movable(v) whether vertex v can (has a move and scale > 0); place(v) puts v at its move scaled by
// st.scale[v]; measure(check) measures the listed hexes again (ascending) before the next round. Deterministic: the
// order of vertices and hexes follows `check`.
template <class Bad, class Movable, class Place, class Measure>
void back_off_bad_hexes(const std::vector<std::array<int, 8>>& hexes, const VertexHexes& vh, MoveBacktracking& st,
                        std::vector<int> check, Bad&& bad, Movable&& movable, Place&& place, Measure&& measure) {
    std::vector<int> changed;
    for (bool first = true; !check.empty(); first = false) {
        changed.clear();
        for (int h : check)
            if (bad(h, first))
                for (int v : hexes[static_cast<std::size_t>(h)]) {
                    const std::size_t vi = static_cast<std::size_t>(v);
                    if (st.marked[vi] || st.scale[vi] == 0 || !movable(v)) continue;
                    st.marked[vi] = 1;
                    changed.push_back(v);
                }
        if (changed.empty()) break;
        check.clear();
        for (int v : changed) {
            const std::size_t vi = static_cast<std::size_t>(v);
            st.marked[vi] = 0;
            st.scale[vi] = ++st.halvings[vi] > st.max_backtracks ? 0.0 : 0.5 * st.scale[vi];
            place(v);
            for (int i = vh.begin[vi]; i < vh.begin[vi + 1]; ++i) {
                const int h = vh.hexes[static_cast<std::size_t>(i)];
                if (!st.queued[static_cast<std::size_t>(h)]) {
                    st.queued[static_cast<std::size_t>(h)] = 1;
                    check.push_back(h);
                }
            }
        }
        std::sort(check.begin(), check.end());
        for (int h : check) st.queued[static_cast<std::size_t>(h)] = 0;
        measure(check);
    }
}

}  // namespace mesohex
