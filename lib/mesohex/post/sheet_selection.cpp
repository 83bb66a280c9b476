#include "mesohex/post/sheet_selection.h"

#include <algorithm>
#include <cstddef>

namespace mesohex {

std::vector<bool> select_branch_sheets(const HexMesh& mesh, const HexTopology& topo, const std::vector<char>& chunk_hex,
                                       SheetDirection direction) {
    std::vector<bool> selected(topo.edges.size(), false);
    const std::size_t n = std::min(chunk_hex.size(), mesh.hexes.size());
    // kHexEdges: 0..7 are the edges of the two end faces (cross-sections), 8..11 the edges joining them.
    const int first = direction == SheetDirection::Longitudinal ? 8 : 0;
    const int last = direction == SheetDirection::Longitudinal ? 12 : 8;
    for (std::size_t h = 0; h < n; ++h) {
        if (!chunk_hex[h]) continue;
        for (int le = first; le < last; ++le) selected[static_cast<std::size_t>(topo.hex_edges[h][le])] = true;
    }
    return selected;
}

}  // namespace mesohex
