#pragma once
// Which sheets to split for directional refinement along the branches of a skeleton-guided mesh (paper §4: "control
// the subdivisions to be made in either longitudinal or radial directions along branches").
#include <vector>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/topology.h"

namespace mesohex {

enum class SheetDirection {
    Longitudinal,  // split the edges that run along the branches: more cross-sections per branch edge
    Radial,        // split the edges of the cross-sections: finer cross-sections
};

// `chunk_hex[h]` (may be shorter than mesh.hexes; missing entries count as false) marks the hexes of branch chunks in
// the raw-mesh layout: face 0-1-2-3 at one end of the branch edge, face 4-5-6-7 at the other, so the edges 0-4, 1-5,
// 2-6, 3-7 run along the branch. Returns, per edge of `topo` (compute_hex_topology(mesh)), whether it is selected:
// the along-branch edges of the chunk hexes (Longitudinal), or their cross-section edges (Radial). Pass the result to
// subdivide_sheets, which splits every sheet containing a selected edge (sheets run through branching points, leaflets
// and padding layers, so the mesh stays conforming).
std::vector<bool> select_branch_sheets(const HexMesh& mesh, const HexTopology& topo, const std::vector<char>& chunk_hex,
                                       SheetDirection direction);

}  // namespace mesohex
