#pragma once
// Step 1 of the paper (§3.1): radius-aware adaptation of the curve branches of a meso-skeleton.
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex {

struct AdaptationOptions {
    // Bisection test: a sub-branch [t0, t1] (arc length) is cut at its arc-length midpoint while
    //   r(t0) + r(t1) < density * (t1 - t0).
    // On a straight branch of constant radius r the final edges are in (r/density, 2r/density], i.e. close to
    // 2r/density. The reference uses 0.5 (edges about 4r long); 1.0 gives edges of one to two radii, close to
    // cube-shaped hexes (the cross-section quads span about one radius).
    double density = 1.0;
    // Smoothing pass of reference-notes §5.2 step 2: each inserted vertex moves to the mean arc parameter of its two
    // neighbours (Jacobi, one pass), then is re-evaluated on the original polyline.
    bool smooth = true;
    // Section criterion (anti-overlap of consecutive cross-sections; derivation in adaptation.cpp): for every edge
    // (a, b) of a resampled branch, |b - a| >= turn_safety * (reach(a) + reach(b)), with
    //   reach = r sin(theta / 2) at a joint turning by theta,
    //   reach = 0 at an extremity,
    //   reach = branching_reach * max(r_end, r_next * cot(gamma)) at a leaflet vertex (free_branching_reach in place of
    //           branching_reach at a branching point without a leaflet), where r_next
    //           is the radius at the other end of the edge and gamma = clamp(beta / 2, 7.5, 60 degrees), beta the
    //           smallest angle between this branch and any other branch or leaflet edge leaving that vertex (a branch
    //           leaves towards the point of its original polyline at arc length min(2 r, its length)).
    // Joints violating it are removed (the end of the edge with the larger reach). An edge with no joint left to
    // remove (e.g. a short branch from a branching point to an extremity) stays as it is. 0 disables the criterion.
    // Both dimensionless (x radius). Measurements on the shared skeletons: docs/tuning.md.
    double turn_safety = 1.25;
    double branching_reach = 1.0;  // x radius at branching points with a leaflet (see above)
    // The same factor at branching points without a leaflet (both terms of the reach; branching_reach stays at leaflet
    // vertices). Dimensionless. Smaller keeps the first joints of fat branches leaving close together near the
    // junction, so that the raw hexes there are fine enough to follow its shape; too small inverts raw hexes
    // (docs/tuning.md). The mesh command retries with branching_reach here when the result misses its goals
    // (MeshGoals, MeshOptions::retry).
    double free_branching_reach = 0.7;
    // A joint the criterion would remove from an edge that ends at a branching point or leaflet vertex is kept when the
    // edge replacing it misses a ball by at least keep_cut_joint x that ball's radius (the joint's own ball or an input
    // vertex's between the replacing edge's ends; miss = distance from the centre to the edge + its radius - the
    // edge's interpolated radius there): a sharp turn whose corner the edge would cut, or a bulge on a short bridge.
    // Its radius is then lowered to the largest value for which the edge to the end meets the criterion (the end's
    // reach uses it as r_next; times 0.999), and it is kept only if that is at least half its own radius (a thinner
    // joint pinches the tube more than the kept corner gains: then it is removed as before). Dimensionless; 0
    // disables (docs/junctions.md, "A cut joint kept thinner").
    double keep_cut_joint = 0.0;
    // A joint the criterion would remove from an edge that ends at a branching point or leaflet vertex slides instead,
    // along the branch's input polyline away from that end, to the nearest position (of 31 evenly spaced ones before
    // its next joint) where both its edges meet the criterion; it keeps the input radius there. The edge from the end
    // then stays closer to the corner the removed joint carried (a sharp turn next to a junction). Only where the edge
    // replacing the joint cuts a ball (the joint's or an input vertex's between the end and the next joint) by at
    // least 1 % of its radius, and not at a branching point without a leaflet that is or was made from a junction of
    // degree >= 4 (its sphere partition's pattern depends on the branch directions; a degree-4 junction the repair
    // split in two or gave a trunk counts at each part, adapt_skeleton's junction_degree, and so do two points of
    // degree 3 whose short bridge adaptation collapses into one of degree 4). Removed as before when the gate fails or
    // no position passes. Tried before keep_cut_joint (docs/junctions.md, "Cut joints slid away from the junction" and
    // "The cut-joint slide's gate").
    bool slide_cut_joint = false;
    // On a bridge (a branch whose two ends are free branching points, no leaflet) that the resampling would leave as
    // one edge, the input vertex with the largest ratio of its radius to the linear interpolation of the end radii at
    // its arc length becomes a held pin when that ratio is at least bridge_peak_ratio: the bridge keeps a joint there
    // with its input radius (the first edges at both junctions then point at it), and the pin does not yield to the
    // section criterion (the raw mesh's margin limit, RawMeshOptions::margin_fraction, bounds its section inside both
    // junction quads instead). A radius peak between two junctions (a fat torso or neck whose ends are branching
    // points) is otherwise stepped over. Dimensionless (a radius ratio); 0 disables (docs/junctions.md, "A radius
    // peak held on its bridge").
    double bridge_peak_ratio = 0.0;
    // A branch rooted on a leaflet's plates (inside the leaflet where 4 faces meet, or on its border: border_root in
    // skeleton_analysis.h) stands on a patch of faces about one leaflet edge wide: its end also reaches root_extent x
    // the mean length of the leaflet edges at the vertex (dimensionless), so the first cross-section clears the patch
    // (docs/tuning.md). 0 disables.
    double root_extent = 0.5;
    // The same end also reaches as far along the branch as the raw-mesh points of its patch (the plate vertices r
    // off the leaflet, the border's out vertices r beyond it), so that the first cross-section lies beyond them
    // (adaptation.cpp, patch_reach; docs/blocks.md). Off: root_extent alone.
    bool root_patch_clearance = true;
    // The patch's reach models a fan end's out vertex as raised up to its lowest border neighbour, the way the raw mesh
    // builds it with RawMeshOptions::fan_end_cap_to_border (raw_mesh.h). Not an option of its own: the pipeline sets it
    // from that one (prepare_skeleton), so that the adaptation and the raw mesh agree.
    bool raised_fan_end_caps = false;
    // Radius floor used by the bisection test only (never written): max(r, min_radius_fraction * largest radius on the
    // branch; dimensionless). Keeps a near-zero radius at an extremity from bisecting towards it forever.
    double min_radius_fraction = 0.25;
    // Bisection depth limit (at most 2^max_depth edges per branch), a guard against absurd radius/length ratios.
    int max_depth = 16;
    // Merge the two ends of a single-edge branch between two branching points (no leaflet) when r_a + r_b > length
    // (and collapse_spread allows it), to their midpoint (mean position and radius). Skipped when another branch
    // joins the same two vertices (it would become a loop); then the bridge stays as it is.
    bool collapse_short_bridges = true;
    // A collapse is made only if every vertex merged into the new vertex (a bridge's two ends; more when bridges chain)
    // lies within collapse_spread x the merged radius of the merged position: for a pair, chord < collapse_spread x
    // (r_a + r_b) (dimensionless). Chains of bridges merged whole drift away from the balls at their ends and the
    // mesh then misses them (docs/tuning.md).
    double collapse_spread = 0.7;
    // Two free branching points joined by a bridge that the resampling leaves as one edge are merged into one junction
    // when their balls overlap by (r_a + r_b) / |ab| >= overlap_merge_ratio, even where collapse_spread refuses (it
    // needs a ratio above 1 / collapse_spread, 1.43 by default). The merged vertex is overlap_ball(a, r_a, b, r_b)
    // (below), not the mean: along the bridge's axis the union of the two balls spans the interval from min(-r_a, d -
    // r_b) to max(r_a, d + r_b) (d = |ab|, from a); the ball is centred at that interval's midpoint, its radius the
    // mean of the interval's half-length and the larger radius (for equal radii r: the midpoint and r + d / 4, the
    // stubs' absorbed ball, SkeletonRepairOptions::absorbed_ball_width). Both points' other branches leave it. Only
    // pairs of points no other collapse merged, neither made by the skeleton repair from a larger junction (its
    // junction_degree above its own degree: a split's half, a trunk's t or root; the merge would undo the repair), and
    // without a branch each to one same branching point (the triangle would become a cycle of two branches); a merged
    // pair takes part in no further collapse. Where collapse_spread would merge the pair too, this rule places it.
    // Dimensionless (a ratio of lengths); 0 = off, 1.2 by default (docs/junctions.md, "Overlapping junction balls").
    double overlap_merge_ratio = 1.2;
    // With overlap_merge_ratio: the largest degree of the merged junction (the two points' degrees less the bridge
    // at each), number of branch edges; 0 = no limit. Two points of degree 3 make one of degree 4; two of degree 4
    // one of degree 6, whose sphere partition has more flat corners and narrower quads.
    int overlap_merge_max_degree = 4;
    // Repairs of degenerate branch configurations, made first (they would stop the sphere partition with "directions
    // i and j coincide", or leave a zero direction):
    // - a branch edge shorter than merge_distance x the smaller radius of its ends (unitless; 0 = exactly zero length
    //   only) is contracted: its ends become one vertex (a leaflet vertex keeps its position, else the midpoint; the
    //   larger radius), unless both ends are on leaflet faces or both are joints (inside a branch the resampling
    //   steps over it); repeated edges are dropped (AdaptationResult counts);
    double merge_distance = 1e-3;
    // - two branch edges (v, a), (v, b) at one vertex whose directions are less than coincident_angle apart (at a
    //   joint: a hairpin, the branch folding back along itself) (radians;
    //   0 disables), |va| <= |vb|: (v, b) is re-attached as (a, b) (the nearer edge becomes their shared trunk; the far
    //   branch's first segment moves by at most |va| sin(coincident_angle)), or dropped if (a, b) exists (a flat
    //   cycle: V - E + F then rises by 1). Not when a is a leaflet vertex. Repeated until no such pair is left.
    //   Default 2 degrees.
    double coincident_angle = 0.0349066;
};

// Returns the adapted skeleton. Every curve branch (maximal chain of edges through vertices of degree 2 that lie on no
// leaflet face; closed rings included) is simplified to one segment and bisected (AdaptationOptions::density),
// smoothed, then cleaned by the section criterion; new joints are evaluated (position and radius, linearly) on the
// ORIGINAL polyline by arc length (a polyline whose end vertex was merged by a collapse starts at the merged
// position instead). Leaflet faces, their edges and vertices are copied unchanged.
// Preconditions (else Error InvalidInput naming the element): one radius per vertex, finite and > 0; finite
// positions; edge indices in range; no self-loop; density > 0. Repeated edges, zero-length branch edges and coincident
// branch directions are repaired first (merge_distance, coincident_angle; counted in AdaptationResult).
// Postconditions: V - E + F unchanged (collapses remove one vertex and one edge each) except by the repairs (a dropped
// repeated edge raises it by 1); no two branch edges at a vertex closer than coincident_angle (except towards a
// leaflet vertex); rings and loops at one vertex
// keep >= 3 edges; no two edges join the same two vertices. Output order: the kept original vertices (every vertex
// that is not a branch joint, plus one anchor per ring: its smallest vertex id) in their original order, then the new
// joints branch by branch; edges: leaflet edges in their original order, then branch edges branch by branch; faces in
// their original order. Deterministic. Complexity O(V + E + output size) (a few log factors).
// pinned: input vertices that stay joints of the output wherever they are joints of a resampled branch (its pieces
// between them are resampled separately and the section criterion removes their neighbours instead): the balls that
// repair_skeleton puts where a stub was absorbed (SkeletonRepairResult::absorbed_balls), a radius peak that the
// bisection's samples would step over; the former branching points of trunks (SkeletonRepairResult::trunk_joints).
// A pin yields where an edge at it still violates the section criterion after every other joint that could go has
// gone (its neighbour is a branch end or another pin): the branch is then sampled again without that pin, so pins
// never leave overlapping cross-sections (except the radius peak AdaptationOptions::bridge_peak_ratio holds, which
// never yields). Ids out of range and vertices that are no joints are ignored.
// junction_degree: per vertex of s (may be shorter or empty: 0 for the rest), the degree of the input junction it was
// made from (SkeletonRepairResult::junction_degree); a free branching point whose value or own degree is 4 or more
// gets no slide (AdaptationOptions::slide_cut_joint). Only that option reads it.
// The ball that replaces two overlapping balls (a, r_a) and (b, r_b) merged by AdaptationOptions::
// overlap_merge_ratio (its comment gives the rule); a == b gives the larger ball.
struct OverlapBall {
    Vec3 centre;
    double radius = 0;
};
OverlapBall overlap_ball(const Vec3& a, double ra, const Vec3& b, double rb);

Skeleton adapt_skeleton(const Skeleton& s, const AdaptationOptions& o = {}, const std::vector<int>& pinned = {},
                        const std::vector<int>& junction_degree = {});

// The same, with what happened (for reports and tests).
struct AdaptationResult {
    Skeleton skeleton;
    // Per input vertex: its output vertex, or -1 for a branch joint that was resampled away. Both ends of a collapsed
    // bridge map to the merged vertex.
    std::vector<int> vertex_map;
    int collapsed_bridges = 0;    // each one removes one branching point, one vertex and one edge
    int turn_removed_joints = 0;  // joints removed by the turn criterion (final branches only)
    int merged_vertices = 0;      // zero-length (merge_distance) branch edges contracted: one vertex and edge each
    int duplicate_edges = 0;      // repeated edges dropped (input repeats, or made by a merge or re-attachment)
    int reattached_edges = 0;     // branch edges moved from a shared vertex to the nearer edge's end
                                  // (coincident_angle)
};
AdaptationResult adapt_skeleton_detailed(const Skeleton& s, const AdaptationOptions& o = {},
                                         const std::vector<int>& pinned = {},
                                         const std::vector<int>& junction_degree = {});

}  // namespace mesohex
