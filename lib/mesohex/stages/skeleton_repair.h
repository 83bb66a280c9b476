#pragma once
// Structural repair of a skeleton before adaptation: a shared trunk for close branches (below), and root patches of
// branches rooted inside a leaflet (SkeletonRepairOptions::root_patch_factor).
//
// Two branches leaving a branching point (no leaflet there) at a small angle beta have tubes (the balls swept along
// their polylines) that overlap far beyond the branching point's ball: for straight branches of radius r up to
// l* = r / sin(beta / 2), where the two tubes separate (the crotch of the domain). The branching point's connection
// quads then cover only a cone of about beta / 2 around each branch: the first cross-sections shrink (RawMeshOptions::
// margin_fraction) and the fit has to inflate two thin tubes into one fat one, crushing hexes in the crotch. The
// repair moves the junction of the pair to where the domain has it: a trunk vertex t on the pair's medial axis,
//   t = c + x unit(m - c),  x = (l* - r) / (1 + sin a),  radius r_t = r + x sin a,
// with l* the arc length where the tubes separate (|P_i(s) - P_j(s)| >= R_i(s) + R_j(s), found on the polylines, so
// turning branches and varying radii count), r the mean of the two radii there, sin a = r / l*, and m the midpoint of
// the two polyline points at l*. (For straight branches of equal radius: the ball at t touches both outer walls and
// the crotch, the branching point of the medial axis of the two overlapping tubes.) The edge (c, t) becomes the
// trunk; both branches leave t towards their polyline point at l* (a new vertex unless one is there) and continue as
// before; their joints before l* are dropped. At t the two branches are about 2 atan(1/2) = 53 degrees apart for
// straight branches, whatever beta was. Design note: ../shared/design/beyond-the-paper.md section E.
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/stages/compatible_blocks.h"
#include "mesohex/stages/fan_end_repair.h"

namespace mesohex {

struct SkeletonRepairOptions {
    // Build trunks for close branch pairs (see above).
    bool trunks = true;
    // A pair gets a trunk only if the trunk edge is long against the balls at its ends: x >= trunk_clearance x (r_c +
    // r_t) (dimensionless). 0.7 is AdaptationOptions::collapse_spread: a shorter trunk would be collapsed back into
    // one vertex by adaptation (a short bridge). For two straight branches of the branching point's radius this means
    // beta below about 35 degrees.
    double trunk_clearance = 0.7;
    // At a branching point of degree 3 (no leaflet), a trunk makes c a joint between its third branch and t: no short
    // bridge for adaptation to collapse, so trunk_clearance is not needed there; the trunk is built when t lies
    // outside c's ball (x > r_c: the junction of the two tubes, the branching point of their medial axis, is not at
    // c). false: trunk_clearance everywhere.
    bool joint_trunks = true;
    // At a branching point of degree 4 or more (no leaflet), the same rule as joint_trunks: a close pair gets its trunk
    // when t lies outside c's ball (x > r_c), even when x is below trunk_clearance x (r_c + r_t). c keeps its other
    // branches and the trunk, t the pair: two junctions of lower degree instead of one of degree 4 and more, whose
    // sphere partition has flat (180 degree) corners and narrow quads for fat branches. A trunk below the clearance
    // is lengthened along the same direction to x' = trunk_clearance (r_c + r_t) (at most 0.9 l*), so that adaptation
    // keeps it (it collapses shorter bridges back into one vertex). docs/junctions.md, docs/tuning.md.
    bool wide_junction_trunks = true;
    // Valley trunks (issue 16 item 1): at a branching point of degree >= valley_trunk_degree (no leaflet), a close
    // pair (less than 90 degrees apart) whose medial junction lies inside c's ball (x <= r_c: two fat branches 40-80
    // degrees apart, whose crotch, the valley between their tubes, lies l* = r / sin(beta / 2) out along their
    // bisector) gets a trunk all the same: t on the bisector at x_v = k (r_c + l*) / (1 + k) (k = trunk_clearance, so
    // the trunk edge is just long enough for adaptation to keep it), radius r_t = min(l* - x_v, r + x_v sin a) (its
    // ball reaches the crotch and stays between the tubes' outer walls). The pair then leaves t about 120 degrees
    // apart, and the valley vertex of t's partition lies at the crotch instead of on c's sphere. Not built when r_t <
    // valley_trunk_min_radius x the fatter branch's radius at l* (wide or unequal pairs: t's ball would be a small
    // fraction of the branches') or when the trunk is no longer than c's radius. Vertex degree (number of branch
    // edges); 0 = off; values below 4 act as 4 (degree 3 is the joint trunks' case; the CLI takes 0 or 4 to 64).
    // docs/junctions.md ("Valley trunks").
    int valley_trunk_degree = 0;
    // With valley_trunk_degree: the smallest radius of t, as a fraction of the fatter branch's radius at l*
    // (dimensionless; 0.6 admits straight equal pairs up to about 71 degrees apart when r = r_c). Against the fatter
    // branch, not the pair's mean: a branch much fatter than t's ball would leave t through a thin neck and flare
    // out of the domain beside it (a fat limb paired with a thin one).
    double valley_trunk_min_radius = 0.6;
    // With valley_trunk_degree: a valley trunk is built at c only while c has fewer than this many trunks (of either
    // rule: a wide-junction trunk counts); 0 = no limit. Two trunks at one point leave it as a new close pair about
    // 60-90 degrees apart, and the valley between them (between two of the input's branches that belong to
    // different pairs) stays on c's sphere, next to two trunk balls. Count of trunks (dimensionless); docs/junctions.md
    // ("Valley trunks") has both settings measured.
    int valley_trunks_per_point = 0;
    // With valley_trunk_degree: a trunk is built at c only 90 degrees or more from every trunk already at c when
    // either of the two is a valley trunk. Two trunks less than 90 degrees apart are a new close pair at c: the valley
    // between them (between two of the input's branches that belong to different pairs) stays on c's sphere and the
    // raw mesh webs across it. The trunk built is the pair's with the highest score (x / r_c: the medial junction
    // farthest out), the others are refused. false: no such test (valley_trunks_per_point alone).
    bool valley_trunks_apart = true;
    // With valley_trunk_degree: t's radius is at most the half-width of the pair's two tubes across the pair's plane
    // at t, sqrt(r^2 - (x_v sin a)^2) (the tubes' axes lie x_v sin a off the bisector there), so that t's ball stays
    // inside the union of the tubes in 3D, not only in the pair's plane. false: r_t as above.
    bool valley_trunk_fit_across = false;
    // A stub: the shorter branch of a close pair ends at an extremity before the two tubes separate (a bump on the
    // other branch's tube, a thumb). It is absorbed: t at the midpoint of its end and of the other branch's point at
    // the same arc length, radius absorbed_ball_width x their distance + the larger radius there (a ball over both
    // tubes); the stub's vertices and edges go, the other branch leaves t towards its first vertex after that arc
    // length. A branching point of degree 3 becomes a joint: the bump is meshed as a thicker stretch of tube, no
    // junction.
    bool absorb_stubs = true;
    // The radius of a ball over two overlapping tubes (an absorbed stub's t, a kept joint): the larger of the two radii
    // r + absorbed_ball_width x d, d the distance between the two tubes' centres there (dimensionless). The union of
    // the two balls reaches d / 2 + r from their midpoint in the pair's plane and r across it: 0.5 covers it whole (a
    // round tube d / 2 too fat across the pair), 0.25 is the round cross-section closest to it (at most d / 4 off,
    // too thin in the plane and too fat across by the same amount), which the fit bends into the union's shape. On the
    // random set 0.25 meets the targets on more of the seeds with a stub (docs/junctions.md).
    double absorbed_ball_width = 0.25;
    // A stub whose end e lies off the other branch is not absorbed but kept as a short side branch of it: q, the
    // point of the other branch's polyline nearest e (a new vertex on it unless a joint is there), becomes a branching
    // point of degree 3 with the edge (q, e) leaving it sideways (at a right angle when q lies inside a segment); the
    // stub's other vertices and edges go and c loses the stub (degree 3: a joint). Only when |e - q| >= side_stub_reach
    // x r_q (r_q the other branch's radius at q; dimensionless), q lies beyond c's ball (arc length > r_c) and before
    // the other branch's end; otherwise the stub is absorbed. A round ball over the two tubes is off their union by
    // about |e - q| / 4 (absorbed_ball_width), which the fit closes only when the end is near the other branch's axis
    // (docs/junctions.md, "Stubs as side branches"). Needs absorb_stubs. 0 disables (every stub absorbed). Measured on
    // the random set (0.5, 0.7 and 1; seeds 1-100 and 101-200): docs/tuning.md, "Stubs as side branches".
    double side_stub_reach = 0.7;
    // A side stub's edge (q, e) is at least side_stub_min_length x max(r_q, r_e) long (dimensionless): a shorter
    // edge gets e moved outwards along (e - q) to that length (its radius kept). The edge from the branching point q
    // to the extremity e has no joint for adaptation's section criterion to remove, so a shorter one keeps
    // overlapping cross-sections (at a right-angle T the criterion asks for turn_safety x free_branching_reach x
    // max(r_q, r_e), 0.875 x with the AdaptationOptions defaults), and raw hexes next to an end inside q's ball can
    // invert. 1: e outside q's ball, with a margin over the criterion. 0: e stays. docs/junctions.md ("Side stubs
    // inside their root's ball").
    double side_stub_min_length = 1.0;
    // Where a side stub is rooted when c keeps three or more branches without it and the stub's end e is at least as
    // fat as the other branch at its point nearest e (r_e >= r_q): abeam of the first point of the stub's axis (walked
    // from c in 128 steps) whose distance to the other branch's polyline reaches side_stub_root_exit x the other
    // branch's radius there (dimensionless; 1: where the axis leaves that tube), at the polyline point nearest it,
    // instead of at the point nearest e; never inside c's ball nor nearer c than the bridge adaptation keeps
    // (trunk_clearance x (r_c + r_q)), never beyond the point nearest e. The edge (q, e) then runs along the stub's
    // tube and c's pair leaves on a bridge (c, q), two junctions of degree 3; from the point nearest e the edge leaves
    // at a right angle and the wedge c, q, e is left to the fit, which on a stub as fat as its sibling ends with the
    // mesh's boundary through the stub's axis (a dent). 0: the point nearest e everywhere. docs/junctions.md ("Side
    // stubs rooted where the stub leaves").
    double side_stub_root_exit = 1.0;
    // A stub at a branching point c of degree 3 (no leaflet) whose end e is fatter than the other branch at its point
    // nearest e (r_e > r_q) is the fat line and the other branch the thin side branch: true keeps the stub as
    // the polyline and roots the thin branch on it where its tube leaves the stub's: the first point x of the thin
    // branch's axis (walked from c in 128 steps) at the stub's radius or more from the stub's polyline, rooted at t,
    // the stub's point nearest x (radius the stub's there). c becomes a joint between its parent and the stub (edge
    // (c, t), pinned like a joint trunk's c), t a branching point of degree 3 (frozen like a side stub's root): the
    // stub leaves t along its polyline, the thin branch towards x (its joints before x go). Only where x exists before
    // the thin branch's walk ends, t lies beyond c's ball, e at least side_stub_min_length x max(r_t, r_e) from t,
    // and the two branches leaving t part there (90 degrees or more apart, or their tubes separating before the
    // shorter ends: t is no close pair itself); otherwise the side stub as above. false: every such stub a side stub
    // of the thin branch, whose edge (q, e) leaves the wedge c, q, e of the fat tube to the fit (the mesh's boundary
    // then runs through the stub's axis). Off: measured without a verdict changed (docs/junctions.md, "Fat
    // stubs kept as the main line").
    bool fat_stub_main_line = false;
    // The ball t of an absorbed stub (or merged end) is a radius peak on the kept branch: the adaptation's
    // resampling, which evaluates its samples on the polyline at arc lengths of its own choosing, would step over it
    // and taper the bump away (the stub's tip uncovered, the tube after it too fat). true: the pipeline pins every t
    // (SkeletonRepairResult::absorbed_balls, adapt_skeleton's `pinned`), so it stays a joint of the meshed skeleton.
    bool pin_absorbed_balls = true;
    // A trunk at a branching point c of degree 3 makes c a joint between its parent and the trunk edge (c, t), with a
    // turn wherever t does not lie straight ahead of the parent (the pair leaving to one side). c's ball is part of
    // the domain, but adaptation resamples parent and trunk as one branch at arc lengths of its own choosing, and the
    // chord between the samples around c cuts the turn. true: the pipeline pins c (SkeletonRepairResult::trunk_joints,
    // adapt_skeleton's `pinned`), so it stays a joint of the meshed skeleton where the section criterion allows it (a
    // pin whose edges cannot clear the criterion yields: adaptation.h). docs/junctions.md ("Trunk joints pinned").
    bool pin_trunk_joints = true;
    // Absorbing a walk (stub or merge), the other branch's joints before t stay: each moves to the midpoint of its
    // point and the absorbed walk's point at the same arc length, radius absorbed_ball_width x their distance + the
    // larger radius (a ball over both tubes there, as t's; not pinned), so a turn of the other branch inside the
    // absorbed stretch is not cut off by a chord from c to t. false: they go, and the other branch leaves t towards its
    // first vertex after t. Off by default: on the random set it changed
    // 4 seeds, mixed (docs/tuning.md, "Joint trunks, kept joints").
    bool keep_sibling_joints = false;
    // A merge: the shorter branch of a close pair ends at a branching point b (no leaflet) before the tubes separate.
    // It is absorbed like a stub (t at the midpoint of b and the other branch's point at the same arc length, radius as
    // a stub's); b's other branches leave t. c loses a branch (degree 3: a joint), t gets b's. Not when b's
    // other edges lead back to the pair (a cycle), not when b is a side stub's root (the branch goes on through it),
    // and a ball t made by a merge takes part in no further merge (as c or b): without that guard merges chained on
    // dense trees whose tubes overlap along whole branches, absorbing most of the tree. Off: on the random set every
    // merge left acts on a trunk's t, and on seeds 201-400 it is no net gain (docs/junctions.md, "Merged ends").
    bool merge_branching_ends = false;
    // Branching points of degree 4 (no leaflet) that the pair repairs left as they are and whose closest pair of
    // branches is less than 90 degrees apart are split into two branching points of degree 3: the close pair leaves a
    // new vertex c' = c + a u, the other two branches stay at c, moved to c - b u, joined by the edge (c, c') of length
    // a + b = 2 h, h = junction_split x r_c (dimensionless, x the branching point's radius); u is the unit direction
    // from the other pair's bisector to the close pair's. The split points sit at the same distance m = (p1 + p2) / 2 -
    // h before the nearest first vertex on either side (p1, p2: that vertex's distance beyond c along u, resp. -u: the
    // bridge is centred in the room the first edges leave, not on c); no split when m <= 0.
    // Radii: the largest of the moved branches' radii at that distance along their first edges. A degree-4
    // junction's sphere partition (4 quads on 6 points) has flat corners and, with a close pair of fat branches,
    // narrow quads; two junctions of degree 3 have neither. 2 h must exceed AdaptationOptions::collapse_spread x
    // (r_c + r_c') (0.7 x 2) or adaptation collapses the edge back. 0 disables. docs/junctions.md ("Degree-4
    // junctions split"), docs/tuning.md.
    double junction_split = 0.75;
    // The junction split needs an unambiguous close pair: every angle between one of its branches and one of the other
    // two exceeds the pair's own angle by at least this (degrees). Below, a branch is about as close to a branch of the
    // other pair as to its partner (e.g. three branches 74, 74 and 80 degrees apart in a row), the pairing and the
    // split direction are arbitrary, and the split moved the junction the wrong way on the random set
    // (docs/tuning.md, "Degree-4 junctions split").
    double junction_split_gap_deg = 10;
    // The junction split keeps every moved branch's first edge: each first vertex f must lie at least
    // junction_split_clearance x (r_split + r_f) from its new split point (dimensionless; the same rule as
    // AdaptationOptions::collapse_spread and trunk_clearance, 0.7). A first edge shorter than that lies within the new
    // junction's reach: adaptation's section criterion drops f's sample and the chord from the split point cuts the
    // branch's corner at f. No split then (the point stays of degree 4). 0: no check. docs/junctions.md ("Split only
    // with clear first edges").
    double junction_split_clearance = 0.7;
    // Branching points of degree 5 (no leaflet) are split the same way first (junction_split, _gap_deg, _clearance:
    // the closest pair, unambiguous against the three others, moves to c' along u = from the others' mean direction
    // to the pair's bisector, the same placement and radii): a junction of degree 3 and one of degree 4, which the
    // degree-4 rule then splits when it can. A degree-5 sphere partition (5 quads on 7 points) has more flat corners
    // and, with fat branches in a narrow cone, folded creases between neighbouring quads. false: degree 4 only.
    // docs/junctions.md ("Degree-5 junctions split").
    bool junction_split_degree_five = false;
    // Root patches of branches standing inside a leaflet. A branch rooted at an interior leaflet vertex v (exactly 4
    // faces around v, every leaflet edge at v shared by 2 faces, exactly one branch edge) stands on the 4 faces around
    // v; its first chunk is as wide as that patch (about 2 leaflet edges) while its tube may be much thinner (a
    // frustum sticking out of the plate). Every leaflet edge (v, u) longer than root_patch_factor x the branch radius
    // (the larger radius of the branch edge's two ends) gets its face strip split (each face crossed by the strip cut
    // in two quads, through the whole leaflet) at root_patch_factor x radius from v (at most half the edge), so u's
    // replacement lies that far from v (dimensionless, x branch radius; 0 disables). A strip is split once (a strip
    // that loops, crosses itself or was already split for another root keeps its first cut; a face crossed in both
    // directions becomes 4 quads); new vertices get radii interpolated along their edge (bilinearly in a face).
    double root_patch_factor = 0.8;
    // Docked walls (docked_walls.h): the wall's first row of hexes stands on the plate faces beside the chain (the
    // foot, 2 plate faces wide, one face longer than the chain at an inside end), so a thin wall (radius well below the
    // plate edge) starts from a base a whole plate edge wide and long, a flare the fit leaves in the crease. The
    // plate's face strips beside the chain (both sides, through the whole plate) and beyond every inside end (of the
    // chain, or of one side's wall where the other side's goes on: the chain side's strip) are split at
    // docked_foot_split x the chain vertex's radius from the chain (at most half the edge): the foot is then as wide
    // as the wall. 0 disables (dimensionless, x the chain vertex's radius; 2 measured on thin and default walls).
    // docs/blocks.md ("Acceptance audit (session 24)").
    double docked_foot_split = 2;
    // Docked walls whose feet do not match the plate's grid (the analysis' straight-through condition fails at a chain
    // vertex: a chain turning in the grid, a chain vertex where other than 4 plate faces meet): the band pillow. The
    // chain's path, run on straight through the grid beyond every inside end up to the plate's border, gets a copy of
    // each vertex on each side, docked_foot_split x its radius from it (the miter at a turn; at most half its
    // shortest other side; half that side when docked_foot_split is 0), and a row of new plate faces between the path
    // and each side's copies (two chords of faces): every chain vertex then has 2 plate faces on each side, the foot
    // the analysis docks. Hexes: + 4 per path edge + 4 per path end on the border (before the foot split beyond the
    // inside ends). Chains that match are left as they are. Not done (the analysis refuses as before) when the path
    // cannot run on (a vertex of other than 4 plate faces, a branch, another chain, a vertex met twice) or turns by
    // more than acos(kBandPillowMinTurnCos) = 104.5 degrees (docked_walls.h). docs/blocks.md ("Docked walls turning in
    // the plate's grid: the band pillow").
    bool docked_band_pillow = true;
    // Branches on fan-edge ends (the paper's limitation 3): the fan edge is retracted from the branch's vertex, which
    // becomes a leaflet corner (stages/fan_end_repair.h; a single fan edge is split in two first, with the face strips
    // crossing it). Done first, on the input skeleton.
    bool fan_end_retraction = true;
    // Checking aid, not a tuning knob: after each trunk or absorption, scan every branching point again instead of
    // only those whose walks the repair touched. The result is the same (test SkeletonRepair.
    // IncrementalScanEqualsFullRescan); only slower (the full rescan is quadratic in the number of repairs).
    bool rescan_all = false;
};

struct SkeletonRepairResult {
    Skeleton skeleton;
    // Per input vertex: its output vertex, or -1 for a joint inside a trunk (dropped).
    std::vector<int> vertex_map;
    int trunks = 0;             // trunk vertices inserted (one per repaired pair)
    int absorbed_stubs = 0;     // stubs absorbed (one vertex t each)
    int side_stubs = 0;         // stubs kept as side branches of their sibling (side_stub_reach; one vertex q each)
    int main_stubs = 0;         // fat stubs kept as the main line, the thin sibling rooted on them (fat_stub_main_line)
    int merged_ends = 0;        // walks ending at a branching point absorbed (merge_branching_ends; one t each)
    int unseparated = 0;        // close pairs (t would clear the ball) left as they are: a branch ends before the tubes
                                // separate
    int root_strip_splits = 0;  // face strips split for root patches (root_patch_factor)
    int docked_foot_splits = 0;   // plate face strips split beside and beyond docked chains (docked_foot_split)
    int docked_band_pillows = 0;  // docked chains whose band was pillowed (docked_band_pillow)
    int junction_splits = 0;      // degree-4 branching points split in two (junction_split; one new vertex each)
    // The ball t of every absorbed stub or merged end, by output id: a radius peak the adaptation keeps as a joint
    // (adapt_skeleton's `pinned`), so that the resampling does not step over it and taper the bump away.
    std::vector<int> absorbed_balls;
    // Every branching point that a joint trunk made a joint (joint_trunks), by output id: pinned by the pipeline when
    // pin_trunk_joints (the turn from the parent into the trunk stays in the meshed skeleton).
    std::vector<int> trunk_joints;
    std::vector<FanEndRetraction> fan_end_retractions;  // fan_end_retraction, in the input's vertex numbering
    // Every bend of a moved root's first edge and every moved first joint (FanEndRetraction::bend, first_joint), by
    // output id: pinned by the pipeline, so that the resampling keeps the clean first edge (else it cuts the bend and
    // the first edge leans as before, or drops the joint by its section criterion and the hexes past it fold).
    std::vector<int> fan_end_pins;
    // Per output vertex: the degree of the input's junction it belongs to, or 0. An input vertex off every leaflet
    // face with three or more edges gives its own degree (counted in the skeleton passed in); the branching points a
    // repair makes of it take the same value: a trunk's t (c keeps its own), a split's c', a side stub's root q, a
    // main stub's t, an absorbed ball. So a junction of degree 4 that the repair turned into two of degree 3 (a split's
    // halves, a trunk's root and t) still reads 4 at each part. Every other vertex (joints, extremities, leaflet
    // vertices, the repairs' other new vertices) 0. Read by adaptation (AdaptationOptions::slide_cut_joint's gate).
    std::vector<int> junction_degree;
};

// Preconditions: one finite radius > 0 per vertex, edge indices in range (as after analyze_skeleton and check_radii;
// violations are not repaired but skipped); faces of 4 distinct vertices whose sides are edges, of non-zero area (as
// after analyze_skeleton: the docked plates' view takes the analysis' leaflets, analyze_leaflets, which throws
// Error(InvalidInput) on such a face). Pairs with a branch edge shorter than 1e-9 x its radius are skipped
// (adaptation's degenerate repairs handle them).
// Postconditions: V - E + F unchanged (each trunk adds t, the two crotch vertices and the trunk edge, and removes the
// dropped joints with one edge each, the two first edges of the pair replaced; a side stub adds q and splits the
// sibling's segment there unless a joint is at q, and replaces the stub's edges and joints by the edge (q, e), e moved
// outwards when that edge is short: side_stub_min_length);
// leaflet faces and their edges unchanged; every output edge joins two distinct vertices. Output order: the kept
// input vertices in their order, then per trunk t and the new crotch vertices (per side stub q); edges: the kept
// input edges in their order, then per repair its new edges.
// Repairs are made one pair at a time, the most overlapping first (largest x / r_c), until no pair qualifies (at most
// one per input branch edge). Deterministic. Complexity O(trunks x (pairs at branching points) x polyline length).
// Fan-end retractions (fan_end_repair.h) come first: input vertices, edges and faces keep their indices, new ones are
// appended (a split single fan edge cuts faces too).
// Degree-4 splits (junction_split) come after the trunks: each moves c, appends c' and the edge (c, c') and re-attaches
// the close pair's first edges to c' (V and E grow by one). With `blocks` (may be null; the pipeline passes its
// connection-surface block options) a point whose four directions fit_cube_frame accepts is not split when
// blocks->enabled: it gets a compatible block (no irregular interior edge), which a split into two degree-3 points
// (bridged by a branch edge) would rule out (docs/blocks.md, "Acceptance audit (session 24)").
// Root patch splits come after the trunks (they touch only leaflets): input vertices keep their indices, new vertices
// are appended (cut points in edge order, then face centres in face order); a cut edge becomes its two halves in its
// place; new edges inside split faces are appended in face order; a split face keeps its index for its first piece,
// the others are appended. Each split adds per strip edge one vertex and one edge, per cut face one edge and one face
// (4 edges and 3 faces and a centre vertex for a face cut twice): V - E + F unchanged. O(V + E + F) per root.
// The band pillow (docked_band_pillow) comes before the docked feet's strip splits: per pillowed chain its path's
// copies are appended (2 per path vertex, in path order), then its path's faces (2 per path edge) and edges (the
// (v, v') pairs, then the copies' path sides); plate faces and sides at a path vertex take its copy in place: V - E +
// F unchanged. O((V + E + F) x path length) per chain.
// fan_caps (sorted vertex ids): fan-edge ends whose branch stands on a fan block's cap, left as they are by the
// fan-end retraction (retract_fan_ends).
SkeletonRepairResult repair_skeleton(const Skeleton& s, const SkeletonRepairOptions& o = {},
                                     const CompatibleBlockOptions* blocks = nullptr,
                                     const std::vector<int>& fan_caps = {});

}  // namespace mesohex
