#pragma once
// Junction cover (issue 16 item 1): the connection-surface points of a plain branching point placed from the
// skeleton's balls instead of on the sphere of its radius.
//
// The raw mesh puts every surface point Q_c(x) of a branching point c on the sphere c + r d_x. Between two fat
// branches the union of their balls reaches much farther (two tubes of radius r a angle 2 alpha apart overlap out to
// r / sin alpha along their bisector), so that sphere leaves a dent the fit must inflate. Here each surface point
// moves out along its ray to where the ray leaves the union of c's ball and the round cones of the branch edges
// near c, guarded so that no hex of c's chunks gets worse than it was (or than a floor).
#include <vector>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/stages/connection_surfaces.h"
#include "mesohex/stages/frame_propagation.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

struct JunctionCoverOptions {
    // Fraction of the way from the sphere (the raw radius r of c) to the ray's exit t from the union of balls a
    // surface point moves: distance r + fraction x (t - r) when t > r. 0 = off (every point on the sphere).
    double fraction = 0.0;
    // The domain skeleton's edges passing within arc x r_c of c count as round cones of the union; r_c = c's
    // radius in the meshed skeleton. Dimensionless.
    double arc = 3.0;
    // Only branching points with at least this many branch edges (and no leaflet face) are covered.
    int min_degree = 3;
    // Junction inset (issue 16): each surface point's distance from c is also capped at t - inset x (its shortest
    // raw boundary edge), t the ray's exit from the union above, so that the padding layer laid over the junction
    // (the padding's thickness 0.25 x the shortest boundary edge) starts inside the domain and ends near its surface
    // instead of starting on or beyond it, where the fit crushes it pulling it back. Points move inward as well as
    // outward, never below half of r; the guard below holds. Dimensionless (0.25 = one padding layer); 0 = off
    // (the default: mixed on the shared skeletons and the random set, docs/junctions.md, "Junction inset").
    double inset = 0.0;
    // Crease opening (issue 16 items 1 and 5): > 0 turns the cover into a crease rule. The raw boundary edges on c's
    // sphere (a surface point to a surface-edge midpoint) each carry two hexes, one of each chunk whose quads share the
    // surface edge; their interior dihedral (through the two hexes) folds to 290-330 degrees in the crotch of two
    // close fat branches, and the padding layer's two hexes there then share the 30-70 degrees left. With this set,
    // only the two end points of a surface edge whose crease exceeds crease_deg move, out along their rays towards
    // the union's exit t (fraction ignored), in steps of 1/16 of the way, until no crease at c exceeds crease_deg or
    // they reach t; then the guard below. Degrees (270: each padding hex gets at least 45 degrees); 0 = off (the
    // default: docs/junctions.md, "Creases opened from the balls").
    double crease_deg = 0.0;
    // With crease_deg > 0: the crease rule moves the *midpoint* of each folded surface edge instead of its two end
    // points, out along the midpoint's own ray towards the union's exit (never inwards), in the same steps and under
    // the same guard; the surface points, and the midpoints of unfolded edges, stay where the raw mesh put them (so it
    // composes with RawMeshOptions::bridge_quad_radius). Between two close fat branches the folded edge is the one
    // their two quads share; its end points are partition points whose rays leave the domain near c's sphere, its
    // middle faces the crotch, where the domain reaches farthest (docs/junctions.md, "Dino's hip and knight's v9
    // traced through the stages"). false: the end points move (the rule above).
    bool crease_midpoints = false;
    // With crease_midpoints: only the midpoint of a folded surface edge whose two quads belong to two branch edges
    // of c less than crease_pair_deg apart (their first edges' directions from c) moves: the edge a close pair's
    // two quads share, which faces the pair's crotch, where the union of two tubes reaches r / sin(angle / 2) from
    // c (docs/junctions.md, "The three shared skeletons that miss"). Degrees; 0 = every folded edge.
    double crease_pair_deg = 0.0;
    // Bulged bridges (issue 16 item 5): > 0 restricts the cover to the two ends of every bridge (the branch edges,
    // through joints, from one branching point c to another, u) along which the domain bulges: some point p of the
    // bridge's polyline, at arc fraction s = 1/16, 2/16, ..., 15/16 from c to u, lies at depth (the largest r(t) -
    // dist(p, x(t)) over the domain's round cones, the radius of the largest ball around p inside their union) of at
    // least bridge_bulge x the ends' radii interpolated there (r_c + s (r_u - r_c), the meshed skeleton's radii). Both
    // ends of such a bridge get their points placed from the union of the bridge's balls (fraction, inset, guard as
    // above; in vertex order, each end's guard reading the other's current points): on a bridge of one edge the chunk,
    // which runs from one end's quad straight to the other's, then spans the bulge instead of the ends' spheres
    // (docs/junctions.md, "Bulged bridges covered from both ends"). Every other junction keeps its sphere.
    // Dimensionless ratio (> 1); 0 = every coverable junction.
    double bridge_bulge = 0.0;
    // Overlapping bridge ends (issue 16 items 1 and 5): > 0 restricts the cover to the two ends c, u of every bridge
    // (branch edges through joints from one branching point to another, as for bridge_bulge) whose end balls overlap
    // by (r_c + r_u) / |c - u| >= bridge_overlap (the meshed skeleton's centres and radii). Two fat branching points so
    // close (dinopet's torso and shoulders, the twin-junction family) send their limbs out from inside each other's
    // balls: a limb of c and a limb of u on the same side fuse into one web across the bridge, which the spheres of c
    // and u leave as a slit between the two limbs' chunks; both ends' points are then placed from the union of the
    // balls (fraction, inset, guard as above; docs/junctions.md, "Twin junctions: the slit between the two ends'
    // limbs"). With bridge_bulge also > 0, an end either rule selects is covered. Dimensionless ratio (> 0);
    // 0 = off (bridge_bulge alone decides; both 0: every coverable junction).
    double bridge_overlap = 0.0;
    // Guard: a hex of c's chunks may not end below min(sj_floor, its scaled Jacobian with every point on the
    // sphere), nor be inverted; otherwise the moves of its moved points are halved (6 times, then dropped).
    double sj_floor = 0.3;
};

// Distance along the unit ray c + t d (t >= 0) at which it first leaves the union of the balls of `cones`
// (each a segment a-b with radii ra, rb, the union of the balls swept along it with linear radius), found by
// marching in steps of `step` up to t_max and bisecting; t_max when it never leaves.
struct RoundCone {
    Vec3 a, b;
    double ra = 0, rb = 0;
};
double ray_exit(const std::vector<RoundCone>& cones, const Vec3& c, const Vec3& d, double step, double t_max);

// domain: the skeleton whose balls make the union (the input before repairs and adaptation, whose round cones the
// thickened domain is; or the meshed skeleton itself), with one radius per point.
// Moves the surface points and surface-edge midpoints of every plain branching point (class BranchingPoint, all
// incident edges branch edges, no compatible block, degree >= min_degree) of the raw mesh `points` (ids from
// vertex_base, laid out as build_raw_mesh does), serially in vertex order. edge_hex[e]: the first of the 4 hexes of
// branch edge e's chunk. radius: the effective radius each vertex was placed with. Deterministic.
// With crease_deg > 0 only the end points of c's folded surface edges move (JunctionCoverOptions::crease_deg), as far
// as opening them needs, at most to their rays' exits (with crease_midpoints: the edges' midpoints instead).
// With bridge_bulge > 0 only the ends of bulged bridges (bulged_bridge_ends) are covered.
// Returns the number of surface points moved (with crease_midpoints: of edge midpoints moved). Complexity:
// O(branching points x domain edges) for the cones, plus O(surface points x cones x (arc + 1) / 0.02) for the rays,
// plus the raw mesh's topology with inset, plus 17 crease measures of c's chunk hexes per junction with crease_deg;
// nothing when fraction, inset and crease_deg are 0.
// JunctionCoverOptions::bridge_bulge: per vertex of `skeleton`, 1 when it ends a bridge (branch edges through joints
// to another branching point) along which the union of `domain`'s round cones reaches ratio x the ends' interpolated
// radii (the test as described there), else 0. O(bridge edges + bridges x 15 x domain edges).
std::vector<char> bulged_bridge_ends(const Skeleton& skeleton, const Skeleton& domain, const SkeletonAnalysis& an,
                                     double ratio);

// JunctionCoverOptions::bridge_overlap: per vertex of `skeleton`, 1 when it ends a bridge (branch edges through joints
// to another branching point u) with (r_c + r_u) >= ratio x |c - u|, else 0. O(bridge edges).
std::vector<char> overlapping_bridge_ends(const Skeleton& skeleton, const SkeletonAnalysis& an, double ratio);

int cover_junctions(const Skeleton& skeleton, const Skeleton& domain, const SkeletonAnalysis& an,
                    const ConnectionSurfaces& cs, const BranchFrames& frames, const std::vector<double>& radius,
                    const std::vector<int>& vertex_base, const std::vector<int>& edge_hex,
                    const std::vector<std::array<int, 8>>& hexes, std::vector<Vec3>& points,
                    const JunctionCoverOptions& options);

}  // namespace mesohex
