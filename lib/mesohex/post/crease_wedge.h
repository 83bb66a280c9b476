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
    // Optional, the crotch cut: the distance from a point along a unit direction to where the domain ends (0 when the
    // point lies outside it, +infinity when nothing is hit). Set: before the wedges are built, each of the two hexes
    // on a selected crease is cut, with the whole sheet of hexes it lies in (dual to its quad's edges leaving the
    // crease: a branch chunk's 4 hexes), by a section across that sheet, so that the wedge's new vertex c_v lands
    // crotch_reach x this distance from v along its bisector: the wedge then spans only the gap up to the domain's
    // crotch and the chunks go on beyond the section (docs/junctions.md, "The close pair's wedge only as long as the
    // crotch"). A crease with an end outside the domain, or whose sheets are not closed sheets of at most
    // kMaxCrotchSheetHexes hexes, gets no wedge; a sheet whose crease ends all reach the domain's crotch with the uncut
    // wedge is not cut. Empty: no cut (the wedge spans the quads' whole length).
    std::function<double(const Vec3&, const Vec3&)> crotch_distance;
    // With crotch_distance: the multiple of the distance to the domain along the bisector at which the wedge's new
    // vertices stand (dimensionless, > 0; 1 = where the bisector leaves the domain, the crotch's deepest line;
    // measurements in docs/tuning.md).
    double crotch_reach = 2.0;
};

// The largest sheet the crotch cut splits (hexes; a branch chunk has 4, a chunk whose quads a wedge and a cut already
// share more).
inline constexpr int kMaxCrotchSheetHexes = 16;

struct CreaseWedgeResult {
    HexMesh mesh;  // the input's vertices and hexes first (ids kept), then the wedges' new vertices and hexes
    std::vector<std::array<int, 2>> wedge_edges;  // the crease edge (v0 < v1) of each new hex, in new-hex order
    int first_new_vertex = 0;                     // = input vertex count
    int first_new_hex = 0;                        // = input hex count
    // With CreaseWedgeOptions::crotch_distance: the sheets cut at the crotch. Each cut hex keeps its id for the part on
    // the crease's side and its other part is appended after the input's hexes (first_new_hex counts them), the cut
    // sheet's new vertices after the input's vertices (first_new_vertex counts them); the input's other hexes and
    // vertices are unchanged.
    int crotch_sheets = 0;
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
// With options.crotch_distance: first the crotch cut (see there), then the same on the cut mesh for the creases it
// kept (up to 3 passes, each from the input, cutting only the sheets of the previous pass's wedges).
// Postconditions: hex count = input + cut hexes + wedge_edges.size(); every new hex has scaled Jacobian >= min_sj and
// its new vertices pass keep_vertex; input hexes and vertices unchanged. Complexity: O(#hexes log #hexes) per round.
CreaseWedgeResult insert_crease_wedges(const HexMesh& mesh, const CreaseWedgeOptions& options = {});

// The interior dihedral of the edge (a, b), in degrees: the sum over the hexes containing it of the angle between the
// hex's two faces at the edge (each measured between the faces' mid-lines, perpendicular to the edge). O(hexes at a).
double interior_dihedral_deg(const HexMesh& mesh, const std::vector<int>& hexes_at_a, int a, int b);

}  // namespace mesohex
