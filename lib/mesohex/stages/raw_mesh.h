#pragma once
// Paper steps 5-7: block insertion, sewing and geometry transfer, as one indexed construction.
//
// Sewing is implicit (design choice 1, STYLE rule 7, second option): every raw-mesh vertex gets its id up front from
// the skeleton element it stems from, by a prefix sum over the connection surfaces:
//   surface of skeleton vertex v (ids from vertex_base[v]):  C_v = base,  Q_v(x) = base + 1 + x (x local surface
//   point),  M_v(j) = base + 1 + (#points of v) + j (j local surface edge).
// Each hex is then written directly as 8 ids (reference-notes §8.1) into a slot reserved for its block (4 per branch
// edge, in branch-edge order), so blocks that share a connection-surface vertex or edge share the id: that is the
// sewing. Both the hex loop and the geometry loop are oneTBB parallel loops over preallocated slots: the output is
// bit-identical for any thread count.
// Leaflets: a leaflet interior vertex owns 3 ids (centre, up, down), a regular leaflet
// boundary vertex 6 (centre, up, down, out, out-up, out-down); a plate of 2 hexes per leaflet face and a half-chunk of
// 2 hexes per boundary edge (docs/design-basis.md) take the hex slots after the chunks. At a BL-joint the
// leaflet's up/down/out vertices are the ids of its connection quad B (§8.5, rotation k = 0); at an LL-joint and at a
// branching point with leaflets, of the leaflet's quad with the rotation ConnectionSurfaces::quad_rotation chosen
// from the leaflet's own normal. A fan-edge vertex owns 1 + g ids (centre, one vertex per gap between the sorted
// faces around its fan edges, on the gap bisector), a fan-edge end 2 + 2g (also O_w and one out-copy per gap)
// (§6.9, §8.6, §10); the gap count g must equal the degree of the vertex's fan edges (checked; otherwise
// Error(UnsupportedConfiguration) naming the vertex).
#include <map>
#include <vector>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/stages/connection_surfaces.h"
#include "mesohex/stages/frame_propagation.h"
#include "mesohex/stages/junction_cover.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

// A fan vertex's gap vertex leaves the bisector (the unit sum of the gap's face normals) and a fan end's O_w the fan
// line's continuation for the axis of the narrowest cone around those normals (around the leaflets' own out
// directions at the fan end) when that axis narrows their widest angle by more than this (degrees;
// narrower_cone_axis of core/cone.h, called in raw_mesh.cpp place_fan_vertices). 5,
// as kCreaseNormalGainDeg: a T / X fan gains 0; a leaflet running on past a fan end (a
// flange: the fan chain on part of a plate's border) moves them.
inline constexpr double kFanDirectionGainDeg = 5.0;

// What the raw mesh will be, known before any hex is built (analysis + connection-surface valences).
struct RawMeshPrediction {
    long vertices = 0;
    long hexes = 0;
    // Interior edges of valence != 4, by valence: the ray from a branching-point centre to a connection-surface
    // point of valence k has 2k hexes.
    std::map<int, long> interior_irregular_edges;
    // Boundary edges of valence != 2, by valence (the definition of post/quality.h): every branch edge has 4
    // longitudinal edges through the surface-edge midpoints with 1 hex; every extremity cap has 8 rim edges with 1 hex;
    // every leaflet boundary edge has 2 (out-up and out-down) with 1 hex. Leaflet vertices add 2 interior edges
    // (to up and down) of valence (faces around it) + 2 at a boundary vertex, when that is not 4. A branch rooted on a
    // leaflet (LeafletPatch, BorderPatch) adds its first chunk's hex to each of its patch's 8 outer edges.
    std::map<int, long> boundary_irregular_edges;
    // Compatible blocks: the 8-hex blocks (ConnectionSurfaces::blocks: 8 hexes and 27 vertices each) plus the fan edges
    // with a fan block (ConnectionSurfaces::fan_blocks: 4 hexes per fan edge and per open chain end, fan_block_caps;
    // 9 vertices per chain vertex, 18 at an open end), included in hexes / vertices.
    long compatible_blocks = 0;
    long fan_blocks = 0;      // fan edges with a fan block (counted in compatible_blocks)
    long fan_block_caps = 0;  // open fan-block chain ends (a cap of 4 hexes each)
    // Virtual branches (stages/virtual_branches.h): ordinary one-edge branches of the meshed skeleton, 4 hexes each,
    // included in hexes / vertices (set by run_pipeline).
    long virtual_branches = 0;
    friend bool operator==(const RawMeshPrediction&, const RawMeshPrediction&) = default;
};

RawMeshPrediction predict_raw_mesh(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                                   const ConnectionSurfaces& surfaces);

struct RawMesh {
    HexMesh mesh;
    std::vector<int> hex_edge;     // per hex: the skeleton edge of its chunk or half-chunk; -1 for a plate hex
    std::vector<int> vertex_base;  // per skeleton vertex: id of its centre (first of its ids), or -1
};

struct RawMeshOptions {
    // A vertex adjacent to a branching point u by an edge of length L gets the radius min(r, L sin(margin_fraction *
    // m)), m = angular margin of the edge direction inside u's connection quad: its cross-section, seen from u, then
    // lies inside that quad and every raw hex corner on u's sphere is positive. 1 would allow flat corners.
    double margin_fraction = kBranchMarginFraction;  // 0.75 (junction_geometry.h)
    // At a branching point v joined to another branching point u by a bridge edge: only the surface points of v's
    // quad on that bridge (its corners and side midpoints) take the bridge's margin limit above; v's other surface
    // points stay on the sphere of v's input radius (edge midpoints between a limited and a free point at the mean).
    // Off: the whole sphere of v shrinks to the limit (a fat junction next to a thinner one is meshed at a fraction
    // of its radius all round). Guarded: the free points move by the largest of 1, 1/2, 1/4 of the way that leaves no
    // hex at v's centre below min(0.3, before), else they stay. docs/junctions.md, "Bridge quads". Does not compose
    // with the junction cover (cover.fraction, inset, crease_deg): a junction whose points the cover moves is placed
    // again from the limited radius, so its raise is lost (with fraction or crease_deg at nearly every
    // such junction: their targets lie beyond the limited radius). On by default together with bridge_quad_inset
    // (alone, on the ball, the padding laid over the raised points bulges past the input ball).
    bool bridge_quad_radius = true;
    // With bridge_quad_radius: each raised point (off v's bridge quads) stops bridge_quad_inset x its shortest raw
    // boundary edge (measured with every point raised) short of v's input radius, never below the limited radius,
    // so that the padding layer laid over it (PaddingOptions::thickness 0.25 x the shortest boundary edge) ends on
    // the input ball instead of beyond it (docs/junctions.md, "Bridge quads raised one layer short"). Dimensionless
    // (0.25 = one padding layer, the default; measurements in docs/tuning.md); 0: the raised points on the input ball.
    double bridge_quad_inset = 0.25;
    // A joint turning by theta gets at most turn_fraction * (shorter incident edge) / (2 sin(theta / 2)): its
    // cross-section then reaches at most turn_fraction of half of each incident edge (the adaptation stage normally
    // guarantees this already; this only acts on inputs meshed with their own sampling).
    double turn_fraction = 0.8;
    // Leaflet offsets that fold over each other: for every two corners of one leaflet face (sides and diagonals),
    // their up copies (and their down copies), r x normal off the sheet, may bring the two closer along the line
    // between them by at most leaflet_offset_fraction x their distance; a pair past that has both its vertices' copies
    // on that side (with their out-up / out-down copies) pulled in by the same factor (a vertex: the smallest of its
    // pairs). Where a coarse sheet bends by phi between neighbours at distance e, the copies pass each other once
    // r sin(phi) is about e (our medial sheets at their full radii: docs/sheets.md, "Where the full-radius meso raw
    // meshes fold"). Dimensionless, like turn_fraction for joints; 0 = off (every copy at r).
    double leaflet_offset_fraction = 0.5;
    // Out rays that cross along a short border side: for every leaflet border edge (a, b) of length L, the out points
    // of its half-chunk (out a, out b; at a junction end the half-chunk's point on its sphere) may come closer along
    // a -> b than a and b by at most leaflet_out_fraction x L; past that the out points that can move (a leaflet
    // border vertex's out column, a junction's sphere point; not a fan vertex's) are pulled towards their vertex by
    // one factor (a point: the smallest of its sides; a column's out-up / out-down copies move with its out, a
    // junction's sphere midpoints next to it go halfway). The out rays cross once the two leans along the side add
    // up to L: a junction's out point leaning along a border side shorter than its radius (a thick BL-joint corner),
    // or a concave border of curvature radius R closing in by r / R of each side (docs/sheets.md, "Out rays crossing
    // along short border sides"). Dimensionless, the in-plane pair of leaflet_offset_fraction; 0 = off (every out
    // point where it was placed). Off by default: pulling a border column's out point in also pulls in the rim the
    // padding and the fit must reach (measurements: docs/sheets.md and docs/tuning.md).
    double leaflet_out_fraction = 0;
    // With leaflet_out_fraction: the leaflet border columns' out points may move too; false: only junctions' sphere
    // points do (the thick joins' out rays; a border's own out rays keep their distance, so the rims stay reached).
    bool leaflet_out_columns = true;
    // With leaflet_out_fraction, how a plain border column's out point moves: false, towards its vertex (its whole
    // offset shortened by the side's factor); true, only its lean along the side is cut (per side the movable out
    // points' positive leans by one factor; the point goes to the nearest position within the caps of its sides), so
    // its offset across the side and off the sheet stays. Out points a branch's first chunk stands on (a junction's
    // sphere point, a column turned towards a branch rooted on its out patch) are pulled either way: slid along the
    // side, their patch turns away from the branch and the chunk folds. Off by default: no gain over the pull
    // (measurements: docs/sheets.md, "Only the lean along the side").
    bool leaflet_out_lean_only = false;
    // A leaflet border vertex rooting a branch on its out patch (BorderRoot::Out) turns its out column (out, out-up,
    // out-down) in the leaflet's plane towards the branch by border_root_turn x their angle there, then about the
    // border by border_root_tilt x the branch's tilt out of the plane (0, 0 = the column along the border's outward
    // bisector and normal). Dimensionless fractions of the angle. Without them, branches leaving a border steeply
    // out of the sheet's plane or far off its outward direction fold their first chunks (docs/tuning.md).
    double border_root_turn = 1.0;
    double border_root_tilt = 1.0;  // (see border_root_turn; fraction of the tilt, dimensionless)
    // A fan end's cap (the out vertex O_w on the fan line and the gaps' out-copies; with a fan block, its cap section)
    // stands r_w beyond w along the fan end's out direction e. With this on, it stands at least as far as the
    // lowest of w's leaflet border neighbours: max(r_w, min over the border sides (w, x) at w of (x - w) . e), so
    // that the half-chunks of leaflet borders leaning out past the fan end (a fan edge retracted from a branch,
    // fan_end_repair.h: the retracted corners 2 r_w along the old border, w's fan neighbour slid to 2 r_w below them)
    // reach over the fan line up to those corners instead of leaving a notch between the leaflets above the cap.
    // A fan end whose borders leave it across the fan line (T / X fans, flanges) keeps r_w (docs/blocks.md, "The
    // notch closed by the cap"). Off by default: it raises the raw minimum at retracted fan ends but a finished far
    // retraction gets inverted hexes and a finished single T loses its Hausdorff target (measured there).
    bool fan_end_cap_to_border = false;
    // Surface points of plain branching points moved out along their rays towards where the union of the skeleton's
    // balls ends (junction_cover.h); cover.fraction 0 = every point on the sphere of the vertex's radius.
    JunctionCoverOptions cover;
};

// Per raw-mesh vertex id: the skeleton vertex whose ids hold it (vertex_base is a prefix sum in vertex order), or -1.
std::vector<int> raw_vertex_owner(const RawMesh& raw);

// The raw boundary edges a close pair of branches shares at a branching point: every edge (v0 < v1) between two
// surface ids of a branching point c (a surface point and a surface-edge midpoint on c's sphere) held by exactly two
// chunk hexes, of two branch edges of c whose directions from c (to their other ends) are less than pair_deg degrees
// apart. These are the halves of the surface edge the pair's two quads share: the crease between the two chunks,
// folded nearly onto itself when the branches are close (docs/junctions.md, "The close pair's crease carried by a
// wedge"). Sorted, no duplicates; empty when pair_deg <= 0. O(hexes log hexes).
std::vector<std::array<int, 2>> close_pair_crease_edges(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                                                        const RawMesh& raw, double pair_deg);

// Preconditions: skeleton.radii has one finite radius > 0 per vertex (Error(InvalidInput) naming the vertex
// otherwise); analysis, surfaces and frames computed from this skeleton.
// Postconditions: mesh.hexes.size() == analysis.predicted_hexes + 8 x surfaces.blocks.size() + 4 x (fan-block edges +
// open fan-block chain ends) (== predict_raw_mesh().hexes); the fan blocks' hexes after the 8-hex blocks (hex_edge -1),
// a fan-block chain vertex's ids its section (fan_blocks.h),
// mesh.points.size() == predict_raw_mesh().vertices; a compatible block's 8 hexes come last (hex_edge -1), its 27
// vertices K(i, j, k) = c + h (i F_x + j F_y + k F_z), h = min(r_c, half its shortest edge), are the vertex's ids;
// every hex in VTK order; positions: C_v at the skeleton vertex, Q_v(x) = c + r_v * d_x, M_v(x, y) =
// c + r_v * unit(d_x + d_y) (on the sphere of local radius r_v, reduced next to branching points, see
// RawMeshOptions::margin_fraction); leaflet vertex w: up/down = w +- r n (n = LeafletVertexFrames::normal; on the
// concave side of a sharp crease r x up_scale / down_scale, the miter; on a side where two corners of one face would
// close in by more than leaflet_offset_fraction of their distance, both copies pulled in),
// out = w + d o (o = LeafletVertexFrames::out, the bisector of the exterior angle of the border; d = r, shortened at
// reflex corners, see leaflet_out_distance, and where two out points of a border side close in by more than
// leaflet_out_fraction of it: pulled in, or with leaflet_out_lean_only their lean along the side cut),
// out-up/out-down = out +- r n, pulled in as up/down (at a border vertex rooting a branch on its out patch, the
// column out / out-up / out-down turns towards the branch: border_root_turn, border_root_tilt).
// A branch rooted on a leaflet (LeafletPatch, BorderPatch) has no vertices of its own at its root: its first chunk's
// bottom kites are the 4 plate / half-chunk faces of the patch.
// Complexity: O(hexes + surface points), parallel.
// domain: the skeleton whose round cones the junction cover fills (RawMeshOptions::cover; the input before repairs
// and adaptation); null or without radii: the meshed skeleton.
RawMesh build_raw_mesh(const Skeleton& skeleton, const SkeletonAnalysis& analysis, const ConnectionSurfaces& surfaces,
                       const BranchFrames& frames, const RawMeshOptions& options = {},
                       const Skeleton* domain = nullptr);

}  // namespace mesohex
