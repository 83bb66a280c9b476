#pragma once
// Crease wedges: a column of hexes filling the gap at a folded concave boundary crease, before padding.
#include <array>
#include <functional>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct CreaseWedgeOptions {
    // > 0: a boundary edge whose interior dihedral (the sum, over the hexes around it, of each hex's angle between its
    // two faces at the edge, in degrees) exceeds this gets a wedge hex; 0: off. The crotch between two chunks of a
    // junction is such a crease folded to 290-332 degrees and carried by two hexes (docs/junctions.md, "Padding
    // directions at folded valleys"); padding keeps two hexes on every new boundary edge, so the fit folds them into
    // the domain's crotch. Degrees, in (180, 360).
    double min_dihedral_deg = 0;
    // A wedge is kept only if its scaled Jacobian is at least this (dimensionless, in [0, 1]).
    double min_sj = 0.2;
    // Optional: whether a new vertex may stay (finish_mesh: inside the domain, FinishOptions::crease_wedge_inside). A
    // wedge with a new vertex refused is dropped and the selection redone without it, as for min_sj. Empty: every
    // position is kept.
    std::function<bool(const Vec3&)> keep_vertex;
    // true: only the edges in `listed` may get a wedge (mesh_skeleton fills it with the edges a close pair of
    // branches shares at a branching point: MeshOptions::crease_wedge_pair_deg); false: every boundary edge of two
    // hexes may.
    bool listed_only = false;
    // With listed_only: the edges that may get a wedge, as vertex pairs (v0 < v1), sorted ascending.
    std::vector<std::array<int, 2>> listed;
};

struct CreaseWedgeResult {
    HexMesh mesh;  // the input's vertices and hexes first (ids kept), then the wedges' new vertices and hexes
    std::vector<std::array<int, 2>> wedge_edges;  // the crease edge (v0 < v1) of each new hex, in new-hex order
    int first_new_vertex = 0;                     // = input vertex count
    int first_new_hex = 0;                        // = input hex count
};

// For every boundary edge (a, b) with exactly two hexes and two boundary quads q1 = (a, b, b1, a1) and
// q2 = (a, b, b2, a2) whose interior dihedral exceeds options.min_dihedral_deg, adds the hex with bottom
// (a, a1, c_a, a2) and top (b, b1, c_b, b2) (orientation fixed by the sign of its Jacobian): the gap between the two
// quads becomes a hex whose faces q1 and q2 are interior, so the edge (a, b) has three hexes (chunk i, the wedge,
// chunk j: the L-shape's three quads at a reentrant corner). c_v is a new vertex per (v, {v1, v2}): on the bisector of
// v1 - v and v2 - v (perpendicular to the edge) at the distance where the wedge's cross-section has right angles at
// v1 and v2 (the mean of |v1 - v|, |v2 - v| over cos of half the gap), averaged over the wedges that share it, so
// consecutive wedges along a crease share their end face. Selection: in order of decreasing dihedral (ties by edge
// id), an edge is taken when neither of its quads belongs to a taken wedge and every end vertex keeps 0 or at least 3
// boundary quads (no doublet on the new boundary); a wedge below options.min_sj is dropped and the selection redone
// without it (up to 8 rounds). Off (min_dihedral_deg <= 0) or no crease: the input, unchanged.
// Postconditions: hex count = input + wedge_edges.size(); every new hex has scaled Jacobian >= min_sj and its new
// vertices pass keep_vertex; input hexes and vertices unchanged. Complexity: O(#hexes log #hexes) per round.
CreaseWedgeResult insert_crease_wedges(const HexMesh& mesh, const CreaseWedgeOptions& options = {});

// The interior dihedral of the edge (a, b), in degrees: the sum over the hexes containing it of the angle between the
// hex's two faces at the edge (each measured between the faces' mid-lines, perpendicular to the edge). O(hexes at a).
double interior_dihedral_deg(const HexMesh& mesh, const std::vector<int>& hexes_at_a, int a, int b);

}  // namespace mesohex
