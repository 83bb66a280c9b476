#pragma once
// Subdivision of hex meshes: primal 1 -> 8 refinement and directional (sheet) refinement.
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct SubdivisionResult {
    HexMesh mesh;
    std::vector<int> parent_hex;  // per new hex: the input hex it lies in
    // Per new point: 1 when it lies on the boundary of the mesh (an input boundary vertex, the midpoint of a boundary
    // edge or the centroid of a boundary face), else 0.
    std::vector<char> on_boundary;
};

// Directional refinement. `edge_selected` is indexed by the edge ids of compute_hex_topology(mesh) (size = its edge
// count). Edges are grouped into sheets: the 4 parallel edges of one direction of a hex are in one sheet, and sheets
// sharing an edge are merged (a sheet of hexes is dual to its edge set). Every sheet containing a selected edge is
// split in two: its edges are cut at their midpoints, and every
// hex is cut once per split direction (2, 4 or 8 children).
// Numbering: input vertices keep their ids; then one midpoint per split edge (edge-id order), one centroid (mean of the
// 4 corners) per face with both directions split (face-id order), one centroid (mean of the 8 corners) per hex with
// all 3 directions split (hex order). Children of hex h are consecutive, in lattice order (first axis 0-1 fastest,
// then 0-3, then 0-4), with the orientation of h. Conforming by construction.
// Preconditions: indices in range and edge_selected.size() == edge count (InvalidInput otherwise).
// Complexity: O(#hexes log #hexes).
SubdivisionResult subdivide_sheets(const HexMesh& mesh, const std::vector<bool>& edge_selected);

// Primal 1 -> 8 subdivision (all sheets split; same numbering as subdivide_sheets with every edge selected):
// hex count x 8, Euler characteristic and validity preserved.
SubdivisionResult subdivide(const HexMesh& mesh);

// Number of 1 -> 8 levels so that the mean edge length (halved per level) is at most h (with a 1e-9 relative
// tolerance); 0 when it already is. Capped at 8 levels. InvalidInput when h is not a positive finite number.
int levels_for_size(const HexMesh& mesh, double h);

// Mean length of the unique edges of the mesh (0 for an empty mesh).
double mean_edge_length(const HexMesh& mesh);

}  // namespace mesohex
