#pragma once
// Compatible blocks (paper §4 remark; ../shared/design/beyond-the-paper.md section D1): at a branching point whose
// branch directions are close to the face normals of a cube, an 8-hex block (a 2 x 2 x 2 cube of hexes) replaces the
// quad partition of the sphere. Each branch stands on the 4 block faces of its cube face (a 2 x 2 patch, exactly
// like a branch rooted on a leaflet's plates); the cube faces without a branch stay on the boundary. The block has no
// interior irregular edge where the paper's layout has one valence-2v edge per partition vertex of valence v != 2.
//
// Acceptance is by measured angles only (fit_cube_frame): the frame F is fitted to the directions, every direction
// must lie within axis_tolerance of its own signed axis of F (all axes distinct), and every pair of directions must
// make the angle of its two axes (90 or 180 degrees) within pair_tolerance. With the defaults (20, 25 degrees) every
// accepted pair angle lies in [65, 115] or [155, 180] degrees, so a star with a 120-degree pair (a Y) and a
// tetrahedral star (4 distinct axes among 3 always contain an opposite pair, which would need >= 155 degrees) are
// never accepted.
#include <array>
#include <map>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex {

struct Skeleton;
struct SkeletonAnalysis;
struct ConnectionSurfaces;

struct CompatibleBlockOptions {
    bool enabled = true;             // false (`--no-blocks`): the paper's layout (sphere partition) everywhere
    double axis_tolerance_deg = 20;  // degrees: largest angle between a branch direction and its cube axis
    double pair_tolerance_deg = 25;  // degrees: largest error of a pair angle against the angle of its two axes
    int min_branches = 3;            // branching points with fewer or more branch edges keep the partition
    int max_branches = 6;            // (see min_branches)
    // 4-hex fan blocks along T / X fan chains (fan_blocks.h; same two tolerances, 2D), on where accepted: no
    // valence-2g interior edge on the fan line, higher raw min / avg SJ. With a domain, mesh_skeleton also finishes
    // the paper's layout and keeps the better (MeshOptions::compare_fan_layouts; docs/blocks.md). false
    // (`--no-fan-blocks`): the paper's gap vertices on every fan edge.
    bool fan_blocks = true;
    // A branch on an open fan-block chain end w (one branch edge (w, b), d = unit(b - w) within 35 degrees of the
    // chain's outward direction e there: d . e >= kFanCapBranchCos, fan_blocks.h) stands on the block's cap: the cap
    // section at w + h e is the bottom of the branch's first chunk (design note C1). The pipeline then leaves such a
    // fan end to the block instead of retracting the fan edge from it (fan_end_repair.h, C2); without a block there
    // (fan_blocks off, `--no-blocks`, a Y fan, a chain refused) the retraction takes it as before. Needs fan_blocks.
    // On by default; false (`--no-fan-cap-branches`) retracts every such fan end (docs/blocks.md, "Branches on the
    // fan block's cap").
    bool fan_cap_branches = true;
    // A branch on an open fan-block chain end w whose first edge d leaves across the fan line stands on the block:
    // within 35 degrees of a free block axis A_s (a T's empty side: d . A_s >= kFanCapBranchCos) on the side section,
    // the 2 x 2 quads of side s over the last fan edge and the cap; within 35 degrees of the diagonal between two
    // leaflets (an X, or a T between its leaflets) in the notch, the 2 x 2 patch folded along the block's corner
    // there (its sections there r wide, up to kFanNotchHalf of the border edge). Both are the bottom of the branch's
    // first chunk (fan_blocks.h). The pipeline takes them only where the fan-end repair refuses the fan end for the
    // moved root's border budget, the branch's tube clear of the plates (FanEndRefusal::thick_root); every fan end
    // the repair takes keeps the repair. Needs fan_cap_branches. On by default; false (`--no-fan-side-branches`)
    // leaves those fan ends refused (docs/blocks.md, "Thick moved roots on the fan block's side section").
    bool fan_side_branches = true;
};

// Signed cube axes are numbered 2a + s: a = 0, 1, 2 (x, y, z of the block frame), s = 0 for +, 1 for -.
Vec3 signed_axis(int label);

// The frame fitted to a set of directions and its acceptance.
struct CubeFit {
    bool accepted = false;
    std::array<Vec3, 3> axes{};  // orthonormal, right-handed: the block's x, y, z in world coordinates
    std::vector<int> labels;     // per direction: its signed axis
    double max_axis_angle = 0;   // radians: largest angle between a direction and its axis
    double max_pair_error = 0;   // radians: largest |pair angle - angle of the two axes|
};

// Seeds the frame with d_0 and the direction most orthogonal to it (least |d_0 . d_j|, lowest j on ties), then 3
// rounds of: label every direction with the nearest signed axis, refit the rotation (least squares: the rotation F
// maximising sum d_i . F e_{l_i}, Horn's quaternion method). Accepted iff the labels are distinct and both tolerances
// hold. Directions need not be unit (normalised); fewer than 2, zero or non-finite directions are rejected (never
// throws). Deterministic. O(n).
CubeFit fit_cube_frame(const std::vector<Vec3>& directions, const CompatibleBlockOptions& options = {});

// A block at skeleton vertex `vertex`: its frame and, per local quad i of the vertex's connection surface (= its i-th
// branch edge in increasing edge id), the signed axis of the cube face the branch stands on.
struct CubeBlock {
    int vertex = -1;
    std::array<Vec3, 3> axes{};
    std::vector<int> labels;
    friend bool operator==(const CubeBlock&, const CubeBlock&) = default;
};

// Block-local vertex numbering: K(i, j, k), i, j, k in {-1, 0, 1} (coordinates along the block axes in units of the
// half size h), id (i + 1) * 9 + (j + 1) * 3 + (k + 1). The centre is 13.
inline constexpr int kBlockVertices = 27;
inline constexpr int kBlockHexes = 8;
constexpr int block_vertex(int i, int j, int k) { return (i + 1) * 9 + (j + 1) * 3 + (k + 1); }
// The integer coordinates (i, j, k) of block vertex id x.
std::array<int, 3> block_coordinates(int x);

// The 8 hexes of the block in VTK order (bottom counter-clockwise about +k, seen from above), hex
// (i0, j0, k0) in {-1, 0}^3 in the order k0, j0, i0 (slowest i0).
std::array<std::array<int, 8>, 8> block_hexes();

// The section a branch with signed axis `label` stands on, as block vertex ids (C; Q0..Q3; M0..M3): C = K(t) the
// face centre, Q_k = K(t + cos(k pi/2) r + sin(k pi/2) s) the face's edge midpoints counter-clockwise about t,
// M_k = K(Q_k + Q_k+1 - t) the face corner between Q_k and Q_k+1, with r = the next axis (x -> y -> z -> x, sign +)
// and s = t x r.
std::array<int, 9> block_section(int label);

// World position of block vertex x for a block centred at c with half size h.
Vec3 block_point(const CubeBlock& block, const Vec3& c, double h, int x);

// Boundary edges of valence != 2 that a block adds (the definition of post/quality.h): of its 12 cube edges (two mesh
// edges each), one with no labelled neighbouring face has valence 1 (1 block hex), one between two labelled faces
// valence 3 (1 block hex + the first chunk hex of each branch); one between a labelled and a free face is regular.
// Every other block edge is regular: the 6 rays from the centre (4 block hexes), the face edges of a labelled face (2
// block hexes + 2 chunk hexes) and of a free face (2 block hexes, on the boundary).
void add_block_irregular_edges(const CubeBlock& block, std::map<int, long>& boundary_irregular_edges);

// The blocks of a skeleton, in vertex order: one per branching point with only branch edges, min_branches to
// max_branches of them, each leading to a joint or an extremity, whose directions (to the edges' other ends)
// fit_cube_frame accepts; labels per branch edge in increasing edge id. None when options.enabled is false.
// Why the neighbours must be joints or extremities: a single edge from a block to another branching point (or any
// vertex with its own fixed frame) takes the whole angular defect between the two ends (up to 45 degrees) in one
// chunk that starts on a block face as wide as the tube; such chunks fold (measured: docs/blocks.md).
// Elsewhere frame propagation gives the chunk on a block face no twist. Deterministic. O(V + E).
std::vector<CubeBlock> find_compatible_blocks(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                                              const CompatibleBlockOptions& options);

// The connection surface of a block vertex (build_connection_surfaces): n disjoint squares, local quad i on its i-th
// branch edge = points 4i..4i+3, the unit directions from the vertex to Q0..Q3 of block_section(label_i), edges
// 4i..4i+3 between Q_k and Q_k+1, every point of valence 1. Writes the vertex's CSR ranges (sized 4n, n, 4n) and the
// edge_quad slots of its branch edges.
void set_block_surface(const Skeleton& skeleton, const SkeletonAnalysis& analysis, const CubeBlock& block,
                       ConnectionSurfaces& cs);

}  // namespace mesohex
