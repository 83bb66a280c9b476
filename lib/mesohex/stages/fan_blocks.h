#pragma once
// Fan blocks (paper §4 remark; ../shared/design/beyond-the-paper.md section D2): along a chain of fan edges of degree
// 3 or 4 whose leaflets meet at near 90 / 180 degrees (a T or an X), a square 2 x 2 section at every chain vertex and
// a chunk of 4 hexes per fan edge replace the paper's gap vertices; each open chain end gets a cap chunk of 4 hexes.
// Each leaflet stands on the block's side face of its axis: its corner at a chain vertex v moves to Q_a(v) = v + h a,
// its up / down copies are the section corners next to it. The paper's layout has one valence-2g interior edge per fan
// edge and per chain end; the block has no interior irregular edge.
//
// Section at chain vertex v with frame (t, u, w) (t along the chain, u and w = t x u the block axes), axes
// A_k = cos(k pi / 2) u + sin(k pi / 2) w (k = 0..3: +u, +w, -u, -w, counter-clockwise about t), half size h:
// id 0 = C (v), 1 + k = Q_k (v + h A_k), 5 + k = M_k (v + h (A_k + A_k+1)). A chain end has a second section (ids
// 9..17) at v + h e, e = the chain's outward direction there (with RawMeshOptions::fan_end_cap_to_border, off by
// default, farther at a retracted fan end: raw_mesh.h). The chunk of a fan edge (and a cap) between section S (start,
// lower along t) and S' is, for k = 0..3, [S(C) S(Q_k) S(M_k) S(Q_k+1) | S'(C) S'(Q_k) S'(M_k) S'(Q_k+1)].
//
// Acceptance by measured angles only (fit_square_frame, the 2D version of compatible_blocks' fit_cube_frame): per fan
// edge, the directions of its faces perpendicular to the edge get distinct signed axes of a frame fitted to them,
// every direction within axis_tolerance of its axis and every pair angle within pair_tolerance of the angle of its two
// axes (90 or 180 degrees). A 120-degree Y fan is never accepted: 3 distinct labels among 4 signed axes in a plane
// always contain an opposite pair, which needs >= 155 degrees (the tolerance 25 included), and a Y has no pair above
// 120 + 2 x jitter. Along the chain: every fan edge passes (frame carried over from the previous edge, so the labels
// follow the chain), each leaflet keeps its label (the two faces of a leaflet at an interior chain vertex carry the
// same label, also across the closing vertex of a closed chain), the chain's inner vertices have no branch and only the
// 2g faces of its fan edges, its ends are fan-edge ends (g faces, g border edges, no branch) or the chain is closed,
// and no edge is docked (docked_walls.h).
// With CompatibleBlockOptions::fan_cap_branches an open end may also carry one branch edge (w, b) leaving within 35
// degrees of the chain's outward direction e there (unit(b - w) . e >= cap_cos): the branch stands on the cap
// (design note C1); with fan_side_branches, a T's end branch leaving within 35 degrees of its free axis stands on
// the block's side section there (fan_side_section_ids). The cap section at w + h e is its first chunk's bottom
// (fan_cap_section_ids, in the order of the connection quad fan_cap_directions gives): the branch is shortened by h, no
// hex is added (4 per branch edge as always), and the cap's end face becomes
// interior (its 8 rim edges get the chunk's hex: add_fan_block_irregular_edges).
#include <array>
#include <map>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/core/vec.h"

namespace mesohex {

struct SkeletonAnalysis;
struct CompatibleBlockOptions;

// The 2D frame fitted to directions perpendicular to a line t.
struct SquareFit {
    bool accepted = false;
    Vec3 u{};                   // the fitted first axis (unit, perpendicular to t); the second is cross(t, u)
    std::vector<int> labels;    // per direction: k = 0..3 (+u, +w, -u, -w)
    double max_axis_angle = 0;  // radians
    double max_pair_error = 0;  // radians
};

// Directions are projected onto the plane perpendicular to unit t and normalised. The frame is seeded with `seed`
// (projected; the first direction when seed is zero or parallel to t), then 3 rounds of: label every direction with
// the nearest signed axis, refit the frame's angle (closed form: the angle maximising sum d_i . A_{l_i}). Accepted iff
// the labels are distinct and both tolerances (options.axis_tolerance_deg, pair_tolerance_deg) hold. Fewer than 2
// directions, zero or non-finite ones are rejected (never throws). Deterministic. O(n).
SquareFit fit_square_frame(const Vec3& t, const std::vector<Vec3>& directions, const Vec3& seed,
                           const CompatibleBlockOptions& options);

inline constexpr int kFanSectionIds = 9;  // ids per section: C, Q_0..Q_3, M_0..M_3
inline constexpr int kFanChunkHexes = 4;  // hexes per fan edge and per cap
// A branch stands on a chain end's cap when it leaves within 35 degrees of the chain's outward direction (cos 35
// degrees): beyond it the first chunk on the cap can fold (measurements: docs/tuning.md, docs/blocks.md "Branches on
// the fan block's cap"); the others keep the retraction (fan_end_repair.h, within 45 degrees).
inline constexpr double kFanCapBranchCos = 0.81915204428899179;
// The connection surfaces accept a cap branch up to 45 degrees off (cos 45 degrees): the pipeline decides on the input
// sampling with kFanCapBranchCos, and the resampling may turn the branch's first edge by a few degrees.
inline constexpr double kFanCapKeepCos = 0.70710678118654752;

// One fan chain with a block.
struct FanBlockChain {
    std::vector<int> vertices;  // in chain order; a closed chain does not repeat its first vertex
    std::vector<int> edges;     // edges[i] joins vertices[i] and vertices[(i + 1) % n]
    bool closed = false;
    std::vector<Vec3> tangent;   // per vertex: t (unit, along the chain order)
    std::vector<Vec3> axis_u;    // per vertex: u (unit, perpendicular to t); the second axis is cross(t, u)
    int degree = 0;              // faces around each fan edge (3 or 4)
    std::vector<char> labelled;  // per axis k = 0..3: a leaflet stands on it (else that side stays boundary)
    // Per open end (0: vertices.front(), 1: vertices.back()): the branch edge standing on its cap, or -1
    // (CompatibleBlockOptions::fan_cap_branches).
    std::array<int, 2> cap_branch{-1, -1};
    // Per open end: the free axis s whose side section the branch (cap_branch) stands on instead of the cap, or -1
    // (CompatibleBlockOptions::fan_side_branches).
    std::array<int, 2> side_axis{-1, -1};
    // Per open end: the section corner M_j (between two labelled axes j and j + 1) whose notch between the two
    // leaflets' plates the branch (cap_branch) stands in instead of the cap, or -1 (fan_side_branches; an X's
    // branch between two leaflets).
    std::array<int, 2> notch{-1, -1};
    friend bool operator==(const FanBlockChain&, const FanBlockChain&) = default;
};

struct FanBlocks {
    std::vector<FanBlockChain> chains;
    // Per skeleton vertex: its chain and position there, or -1 (empty vectors when there is no chain).
    std::vector<int> vertex_chain, vertex_index;
    // Per face and corner at a chain vertex: the axis k of the face's leaflet there and the section corners M of its up
    // and down side (k or k - 1 mod 4: the one on the side of the face normal is up); -1 elsewhere.
    std::vector<std::array<int, 4>> corner_axis, corner_up, corner_down;
    friend bool operator==(const FanBlocks&, const FanBlocks&) = default;
};

// The chains of the skeleton that get a block (none unless options.enabled and options.fan_blocks): first the open
// chains, each from its end with the smaller vertex id, in the order of those ends, then the closed chains in the
// order of their smallest fan edge, each from that edge's first vertex. Deterministic. O(V + E + F).
// cap_cos: the least unit(b - w) . e of a branch on a cap (kFanCapBranchCos; the connection surfaces pass
// kFanCapKeepCos).
FanBlocks find_fan_blocks(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                          const CompatibleBlockOptions& options, double cap_cos = kFanCapBranchCos);

// Fan edges and caps with a block (their hex count is 4 x (edges + caps)).
long fan_block_edges(const FanBlocks& blocks);
long fan_block_caps(const FanBlocks& blocks);

// The branch edge standing on the cap of chain end v (FanBlockChain::cap_branch), or -1.
int fan_cap_branch_at(const FanBlocks& blocks, int v);

// The vertices whose cap carries a branch, increasing.
std::vector<int> fan_cap_roots(const FanBlocks& blocks);

// The connection quad of the branch on the cap of chain end position i (0 or n - 1 of an open chain): point x's unit
// direction, the cap section's axis A_k seen from the end, counter-clockwise about the outward direction (k = x at the
// last vertex, where e = t; k = -x mod 4 at the first, where e = -t). On a side section (side_axis s >= 0): A_s+1, t,
// -A_s+1, -t (counter-clockwise about A_s); in a notch M_j (notch j >= 0): unit(A_j+1 - A_j), t, unit(A_j - A_j+1),
// -t (counter-clockwise about A_j + A_j+1).
std::array<Vec3, 4> fan_cap_directions(const FanBlockChain& chain, int i);

// The cap section ids (offsets from the vertex's first id, 9..17) in the connection quad's order: centre, the 4 points
// Q of fan_cap_directions, the 4 edge midpoints M between points x and x + 1.
std::array<int, 9> fan_cap_section_ids(const FanBlockChain& chain, int i);

// The side section (CompatibleBlockOptions::fan_side_branches): a branch at open end position i leaving across the
// chain, d = unit(b - w) with d . A_s >= cap_cos for a free axis s (no leaflet labelled s: a T's empty side), stands
// on the block's side s: the 2 x 2 quads M_s-1 Q_s M_s of three sections (the end's neighbour L on the chain, the end
// w, its cap section K). The patch's centre is Q_s(w); its points, counter-clockwise about A_s, are M_s(w) (direction
// A_s+1), the section of +t (K at the last vertex, L at the first), M_s-1(w) (-A_s+1) and the section of -t; its
// edge midpoints the corners M between them. No hex is added (4 per branch edge as always). Per point: (chain
// position, section id 0..17), in fan_cap_directions' order (centre, the 4 points, the 4 corners between points x
// and x + 1).
std::array<std::array<int, 2>, 9> fan_side_section_ids(const FanBlockChain& chain, int i);

// The notch (CompatibleBlockOptions::fan_side_branches): a branch at open end position i leaving between two
// labelled axes, d . unit(A_j + A_j+1) >= cap_cos, stands on the 2 x 2 patch folded along the block's corner M_j:
// centre M_j(w); points, counter-clockwise about A_j + A_j+1: the plate copy of leaflet j + 1's face on the last fan
// edge at its border neighbour of w (direction A_j+1), M_j of the +t row (K at the last vertex, L at the first), the
// copy of leaflet j's face (A_j), M_j of the -t row; corners: those faces' copies at L's border neighbours (the L row)
// and the out copies of their border half-chunks (the K row). Its two edges on the fold M_j get 2 chunk hexes each
// (interior valence 5). fan_cap_directions gives the points' directions projected normal to A_j + A_j+1.

// The section at a notch end has half size min(r, kFanNotchHalf x its shortest leaflet border edge) (raw_mesh.cpp,
// fan_notch_half_size): the plates' first faces keep at least 1 - kFanNotchHalf of their border side.
inline constexpr double kFanNotchHalf = 0.8;

// Raw-mesh ids at a chain vertex: 9 (18 at an open end).
int fan_block_vertex_ids(const FanBlocks& blocks, int v);

// The chunk hexes of a chain (4 per edge in edge order, then 4 for the cap at vertices.front() and 4 for the one at
// vertices.back() of an open chain) as section ids: for each hex 8 pairs (chain position, section id 0..17).
std::vector<std::array<std::array<int, 2>, 8>> fan_chain_hexes(const FanBlockChain& chain);

// Positions of the ids of chain vertex position i (9 or 18) with half size h, centre c; an open end's cap section
// (ids 9..17) cap beyond c along the chain's outward direction (h at a plain end).
void fan_section_points(const FanBlockChain& chain, int i, const Vec3& c, double h, double cap, std::vector<Vec3>& out);

// Boundary edges of valence != 2 that the chain's chunks and caps add (the chain has no interior irregular edge):
// per fan edge and per cap, the longitudinal edge through M_k has 1 block hex plus one plate (half-chunk) per labelled
// neighbouring axis: valence 3 between two labelled axes, 1 between two free ones; on a cap's end face, the two rim
// edges at a free axis' Q_k have 1 hex. A cap carrying a branch (cap_branch) adds the chunk's hex to its 8 rim edges:
// 2 at a free axis' Q_k (regular), 3 at a labelled one's (the half-chunk's out column). A branch on the side
// section s adds the chunk's hex to the patch's 8 rim edges: the 4 through M_s-1 and M_s (fan edge and cap rows,
// valence 2 + the labelled axes beside them), the 2 at L (2 -> 3), the 2 at the cap's end face (1 -> 2); its 4
// inner edges become interior and regular (2 + 2).
// A branch in the notch at M_j (notch) adds the chunk's hexes to the patch: the 2 fold edges on M_j's column (boundary
// valence 3) become interior of valence 5; the 6 rim edges on the plates and the half-chunks' sides 2 -> 3, the 2 on
// the half-chunks' outer edges 1 -> 2.
void add_fan_block_irregular_edges(const FanBlockChain& chain, std::map<int, long>& boundary_irregular_edges,
                                   std::map<int, long>& interior_irregular_edges);

}  // namespace mesohex
