#pragma once
// Skeleton repair for a branch on a fan-edge end (the paper's limitation 3; design note
// ../shared/design/beyond-the-paper.md, section C2 "Retract the fan edge"). Called by repair_skeleton
// (SkeletonRepairOptions::fan_end_retraction), before adaptation.
//
// Configuration: a vertex w on exactly one fan edge (u, w) (an edge shared by g >= 3 faces) and on at least one branch
// edge, where every face at w is one of the g faces around (u, w) and leaves w by its own border side (w, x_i) (one
// face of each fan leaflet at w: the leaflet corner there), and the branches leave w within 45 degrees of the fan
// line's direction e = unit(w - u) (d . e >= kFanEndBranchCos, d = unit(sum of the unit branch directions at w)), and
// the fan-edge chain goes on past u (u on two fan edges).
// The analysis refuses it: the fan end has no cap for a branch to stand on. The repair pulls every face back from the
// fan line at w along its border side (w, x_i), by t_i = clamp(kRetractionRadii r_w / |x_i - w|, 0.3, 0.7), and
// slides u along the fan line towards w, to w + clamp(kRetractionRadii r_w / |u - w|, 0.5, 1) (u - w):
//   - the carrier, the face maximising d . o_i, o_i = unit(unit(w - u) + unit(w - x_i)) (its outward corner direction
//     at w; ties within 1e-9 go to the lowest face id), keeps w, which moves to w + t_k (x_k - w);
//   - every other face f_i = (.. u, w, x_i ..) gets a new vertex w_i = w + t_i (x_i - w) of radius r_w in w's place
//     (same corner, so the orientation is kept); the border side (w, x_i) becomes (w_i, x_i) in place, the side
//     (u, w_i) is appended.
// Thick radii (kRetractionRadii r_w > kRetractionMax |x_i - w|): the corner goes kRetractionRadii r_w along the
// leaflet's straight border run from w (w, x_i, and on through plain straight border vertices), at most kRetractionMax
// of the run, and the run's inner vertices slide along it, keeping their proportions (the shape is unchanged); a run of
// one side may be retracted up to kRetractionMaxAtCorner of it. A branch whose run on some face cannot give
// kRetractionMinRadii r_w is not retracted (refused, with the ratio: fan_end_refusal).
// Result: (u, w) has one face (a border side of the carrier); w is a corner of the carrier carrying the branch (a
// BL-joint, a border root or a branching point with several branches); the w_i are plain border corners; u is a
// regular fan end (every fan leaflet leaves it by a border side). The shape changes on the fan's faces at u and w only
// (w by t_k |x_k - w|, with the branch's root; u by at most half the fan edge, along the fan line, so every face stays
// in its plane).
// Deviation from the design note (which keeps w in place): the carrier's border (u, w) would then continue the fan
// line at u, where a fan end puts the out vertex of every half-chunk on the fan line (u + r e): the carrier's half-
// chunk on (u, w) is flat there (inverted raw hexes; docs/blocks.md); moving w turns that border by
// atan(t_k |x_k - w| / |w - u|) away from the fan line, like the others. Sliding u (not in the note): the faces pulled
// back leave a notch between the leaflets above u's fan-end cap (which reaches r_u above u) that the finished mesh
// cannot fill (a large Hausdorff distance there; docs/blocks.md); with u within 2 r_w of w the cap covers most of it,
// and the borders at u turn farther off the fan line.
// Branches far from the fan line (perpendicular to it) are not retracted: the moved corner would have the branch more
// than 60 degrees off its outward direction and fold its first hexes for most radii; their root is moved (below).
// A chain of one fan edge (u, w) is not retracted as it is (u would become a leaflet-only branching point whose raw
// mesh folds; docs/blocks.md, "Branches on fan-edge ends"): when u is a plain fan end (no branch, every face there one
// of the g around (u, w), each leaving u by its own border side) and every face around (u, w) starts a strip of faces
// that crosses its leaflet to a border side (sides of 2 faces only, no face twice), the fan edge is first split at its
// midpoint m and every face of those strips cut in two through the midpoints of the two sides it crosses (the edit the
// analysis suggests); the chain u - m - w then has two fan edges and (m, w) is retracted from w as above.
// Split counts: +1 vertex and +1 edge per cut side (the fan edge and 1 + strip length per strip), +1 edge and +1 face
// per cut face: Euler unchanged.
// A chain of fewer than 3 fan edges with such a branch at both ends (each end of the configuration above but for u) is
// first cut into at least 3 fan edges: each of its k edges into ceil(3 / k) equal pieces (one edge: thirds; two:
// halves) with the strips of its faces, as above (the same conditions on the strips); both ends are then retracted
// (the lower first), leaving the middle fan edges between two regular fan ends. Two retractions on a chain of 2 edges
// would leave its middle vertex a leaflet-only branching point (see above); a chain of 3 or more needs no cut.
// Raw hexes: the standard count on the repaired skeleton, i.e. +2 (g - 1) (one border side more per retracted face),
// plus, after a split, 2 per cut face and 2 per cut border side (one leaflet face and one border side more each).
//
// Branches far from the fan line (d . e < kFanEndBranchCos: perpendicular to it, or leaning back) are not retracted:
// their root moves off the fan edge instead, onto the border of one leaflet there (the edit the analysis used to
// suggest). First the row under w: when kRootRowRadii r_w is less than half of |u - w| and every face around (u, w)
// starts a strip that crosses its leaflet (as for a split), the fan edge and those strips are cut at kRootRowRadii r_w
// from w (the cut point becomes w's fan neighbour u). Then the carrier: the face around (u, w) whose border side
// (w, x_k) points most towards the branch (max d . unit(x_k - w); ties within 1e-9 to the lowest face id); the strip
// of faces from that side across its leaflet to a border side is cut in two at the fraction
// t = clamp((b - w) . (x_k - w) / |x_k - w|^2, lo, kRootMoveMax), lo = clamp(kRootMoveRadii r_w / |x_k - w|,
// kRootMoveMin, kRootMoveMax), of every side it crosses (measured from the side's end on w's side of the strip; b =
// the mean of the branches' first vertices: t puts the new root where the branch's first edge is closest to
// perpendicular to the border), and every branch edge at w moves to the cut point m on (w, x_k). w is then a plain
// fan end (the chain's fan block, if accepted, caps it), m a straight-border vertex of the carrier's leaflet carrying
// the branch (a border root on the half-chunks and the two faces there: the row cut keeps those faces about as tall
// as the branch's tube). The move is made only when the moved first edge is a clean out or side root (kMovedOutDeg,
// kMovedSideOffOutDeg, kMovedSideDeg), or, for a single branch edge, when it can be bent at a new vertex p into one
// (between the out and side limits: kBendOutDeg off out; leaning back: along the normal; kBendRadii, kBendMaxTurnDeg,
// kBendMaxRadius; +1 vertex and +1 edge, p pinned for the resampling); else the branch stays refused with the angles
// measured. Counts: as a split, +1
// vertex and +1 edge per cut side, +1 edge and +1 face per cut face (Euler unchanged); raw hexes the standard formula
// on the repaired skeleton (2 per cut face and 2 per cut border side more). Only the branch's first edge changes
// direction (its root moves by t |x_k - w| along the border). Recorded as a FanEndRetraction with moved_root = m and
// fan_edge_split = the row cut's point (or -1).
// Thick radii (kRootMoveRadii r_w > kRootMoveMax |x_k - w|): the root goes kRootMoveRadii r_w (up to the branch's
// projection) along the straight border run from w through x_k, leaving at least kRootMoveRunRestRadii r_w of the run
// beyond it, and the run's inner vertices slide along it as for a thick retraction (the border keeps its line; the cut
// stays on the first side, now longer); a run of one side or too short is refused, naming the radius bound.
// A single branch edge that is not bent has its first joint y (a plain joint: two edges, no face) moved to
// kFirstJointRadii r_w from m along the edge (FanEndRetraction::first_joint), pinned for the resampling like p.
// Moves are made after the retractions (in increasing w; a single fan edge whose other end u carries a branch to be
// moved counts u as a plain fan end, so it is split and retracted first): a retraction at the chain's other end then
// sees uncut leaflets (moved first, its carrier's border side would be the cut column's, 0.3 long: 4 inverted raw
// hexes); the retraction rounds then run once more (an end whose other end carried a moved branch may now be taken).

#include <optional>
#include <string>
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex {

// The branches' mean direction must make at most 45 degrees with the fan line's direction (cos 45 degrees).
inline constexpr double kFanEndBranchCos = 0.70710678118654752;
// Retraction length along each border side at w, and the fan edge's length left between u and w, x the radius at w
// (clamped to [0.3, 0.7] x the side's length, and to [0.5, 1] x the fan edge's): 2 turns the borders at u by
// atan(0.6 / 0.6) = 45 degrees off the fan line for leaflet edges of 3.3 radii (the generators' default); 1.5 (the
// design note's, u fixed) leaves the retracted faces' half-chunks at u flat (raw min SJ -0.01, measured).
inline constexpr double kRetractionRadii = 2.0;
// The retraction along a border side at w, as a fraction of it: at least kRetractionMin, at most kRetractionMax (the
// remaining side keeps 0.3 of its length). When kRetractionRadii r_w is longer than kRetractionMax of the first side
// (thick radii: r_w > 0.35 x the leaflet edge) and the border goes on straight past it, the retraction goes on along
// the straight run (up to kRetractionMax of the run) and the run's inner vertices slide along it (docs/blocks.md).
inline constexpr double kRetractionMin = 0.3;
inline constexpr double kRetractionMax = 0.7;
// A border side at w that ends at a vertex that cannot slide (a leaflet corner, a vertex with more faces or edges):
// the retraction may go up to this fraction of it (the remaining side 0.1 of its length).
inline constexpr double kRetractionMaxAtCorner = 0.9;
// Least retraction length, x r_w: the border half-chunk at u runs from u's cap (its gap vertices r_w from the fan line,
// lifted r_w along it) to the corner's out column (r_w inwards along the corner's out direction, about 0.55 r_w
// towards the fan line): it folds when the corner is less than about (1 + 0.55) r_w from the fan line; 1.6 is that
// bound with a margin (measurements: docs/blocks.md, "Thick radii at a retracted fan end"). A branch with a face whose
// border run cannot give this much is refused, naming the ratio.
inline constexpr double kRetractionMinRadii = 1.6;
// ... for a branch within acos(kRetractionAlignedCos) = 5 degrees of the fan line's continuation; a branch leaning
// further needs the full kRetractionRadii r_w (retracted 20 - 45 degrees off the fan line with 1.79 - 1.94 radii of
// reach, radius 0.72 - 0.78 x the generators' unit leaflet edge: 1 - 2 inverted raw hexes; the aligned branch meshes
// down to 1.67 radii; bench/fanend_sweep.py, docs/blocks.md "Sweep of the check configurations").
inline constexpr double kRetractionAlignedCos = 0.99619469809174553;  // cos 5 degrees
// Largest turn of the border at a vertex that a straight run may pass, degrees.
inline constexpr double kBorderRunTurnDeg = 5;
// Range of the moved root's place on the carrier's border side, as a fraction of the side from w: at least 0.3, and
// at least kRootMoveRadii r_w / |x_k - w| (both clamped to 0.7), keeps the column of faces cut off beside the fan line
// wider than the fan block's half size h = r (its leaflet corners stand at r from the fan line: a column of width r
// flattens the plates there); at most 0.7 keeps it off the side's far end. Within that range the place is the
// branch's first vertex projected on the side (measurements: docs/blocks.md, "Branches across the fan line: the root
// moved").
// A moved branch's first edge (from the cut point to the mean of the branches' first vertices) must leave the border
// within kMovedOutDeg degrees of its outward in-plane direction (an out root), or more than kMovedSideOffOutDeg off it
// and within kMovedSideDeg of the leaflet's normal (a side root); else the move is not made and the branch stays
// refused (the moved roots outside these limits gave inverted raw hexes: docs/blocks.md). The analysis' own limits
// are 60 (out) and 45 (side): stricter here because the fan end is one face away.
inline constexpr double kMovedOutDeg = 45;
inline constexpr double kMovedSideOffOutDeg = 60;
inline constexpr double kMovedSideDeg = 45;
// A single moved branch edge outside those limits is bent instead: a new vertex p on it, min(kBendRadii r_w, |b - m|)
// from the cut point m (b its first vertex) in a clean direction c, where the branch then turns towards b. Between the
// out and side limits c is kBendOutDeg off the outward direction, turned towards the branch; leaning back (more than
// kMovedSideOffOutDeg off out and kMovedSideDeg off the normal), c is the normal on the branch's side. The pipeline
// pins p (SkeletonRepairResult::fan_end_pins: the resampling keeps it). kBendRadii 2 keeps the edge (m, p) unbisected
// by the adaptation (density 1: edges up to 2 r), so its first cross-section is p's; a longer edge is bisected and its
// first section sits on the root's patch, a shorter one fails the section criterion and the pin yields (inverted raw
// hexes either way, measured). A bend turning the branch by more than kBendMaxTurnDeg degrees is not made (the branch
// stays refused): beyond it the pin yields or the tube meets the next leaflet (measured: docs/blocks.md).
inline constexpr double kBendRadii = 2.0;
inline constexpr double kBendOutDeg = 30;
inline constexpr double kBendMaxTurnDeg = 55;
// Nor when r_w exceeds kBendMaxRadius x the carrier's border side |x_k - w| (dimensionless): thicker tubes (2 r of
// bent edge, the leaflets' plates as thick) fold between the leaflets (measurements: docs/blocks.md, "Moved first
// edges bent"). A limit of its own, measured on the bent roots: independent of kRetractionMax / kRetractionRadii (the
// retraction's thick-radius threshold, 0.35 on those constants' current values, set by another fold). 0.3 since issue
// 22's sweep: at 0.303 - 0.35 the pin at p yields and the X leaning back (`fanend -n 4 -m 5`) gets 8 - 10 inverted raw
// hexes, the T leaning back 130 - 135 degrees between two leaflets 10 (docs/blocks.md, "Sweep of the check
// configurations").
// Above it a branch leaning back (bent onto the leaflet's normal) is still bent when its tube clears the leaflets'
// plates (plate_overlap of its centre line past kPlateOverlapRootRadii r_w at least 1: no plate closer than the tube's
// and the plate's radii): the folds measured above were branches leaning back over a neighbouring leaflet (between
// two leaflets of a T or X), whose tube runs into that leaflet's plate; one leaning back over the empty side of a T
// stays clear at any radius (docs/blocks.md, "Refusals left at fan ends, traced"). Branches bent between the out and
// side limits keep the bound, and so does a branch that the fallback retraction takes above it (kFallbackCornerDeg):
// it is retracted as before.
// The refusal of a branch not bent names the first of these conditions that fails, with its value.
inline constexpr double kBendMaxRadius = 0.3;
// Height of the row cut under a moved root, x r_w: the fan edge (u, w) and its faces' strips are cut at that distance
// from w first (when the strips cross and it is less than half the fan edge), so that the root's side patch (its two
// faces below the border) is about as tall as the branch's tube, not the whole fan edge (measured: docs/blocks.md).
inline constexpr double kRootRowRadii = 1.0;
inline constexpr double kRootMoveMin = 0.3;
inline constexpr double kRootMoveMax = 0.7;
inline constexpr double kRootMoveRadii = 1.5;  // radii (at w) of plate left beside the fan line, at least
// Where the moved branch runs on past its root along the carrier's border (its polyline reaching one radius r_w beyond
// the moved root's border coordinate, past the root's patch), it must stand at least kRunOnClearanceRadii r_w off the
// border line there (dimensionless: the branch's tube, r, over the border's own rounded plates, r); closer, the tube
// folds against the plates (1 - 11 inverted raw hexes, measured with bench/fanend_sweep.py: branches in or near a
// leaflet's plane 50 - 100 degrees off the fan line, docs/blocks.md "Sweep of the check configurations"). And a root
// is not moved when kRootMoveRadii r_w exceeds kRootMoveMax of the border side (the clamp put the root closer to the
// fan line than kRootMoveRadii radii: 1 - 8 inverted raw hexes from radius 0.63 x the side, measured there).
inline constexpr double kRunOnClearanceRadii = 2.0;
// A moved root's first joint (the far end of its single branch edge, not bent), x r_w from the root along the edge
// (moved in or out), pinned for the resampling (SkeletonRepairResult::fan_end_pins), so that the branch's first
// cross-section stands clear of the root's patch and the section criterion does not drop the joint. 2.5, not the bend's
// 2: the criterion at a border root asks 1.25 (r cot(beta / 2) + ...), about 1.9 - 2.1 r for a branch 60 - 70 degrees
// off the border, where a pin at 2 r yields (the T's perpendicular branch); the midpoint that the bisection puts on a
// 2.5 r edge fails the criterion and goes. Measured on the sweep (docs/blocks.md, "Moved roots: first joint and thick
// radii"): 2.5 against 2.
inline constexpr double kFirstJointRadii = 2.5;
// Reach of the raw-mesh check at a moved root (pipeline.h, check_moved_roots), x r_w from the cut point m: an inverted
// raw hex whose centroid lies this close refuses the run. It covers the branch's first chunks (the first joint at
// kFirstJointRadii r_w, a bend at kBendRadii r_w) and the root's half-chunks on the border.
inline constexpr double kMovedRootCheckRadii = 4.0;
// A moved root thicker than its first border side allows (kRootMoveRadii r_w > kRootMoveMax of the side) slides the
// straight border run from w instead (like a thick retraction): the root kRootMoveRadii r_w from w along the run, at
// least this many radii of the run left beyond it (the border's plates past the branch's tube); else refused.
inline constexpr double kRootMoveRunRestRadii = 1.6;
// Such a thick moved root's first edge may lean back (towards the fan edge's other end) at most this many degrees past
// the plane normal to the border's outward direction (off out <= 90 + this); leaning further it folds against the
// leaflets' thick plates (measured: docs/blocks.md, "Moved roots: first joint and thick radii").
inline constexpr double kThickRootBackDeg = 20;

// A branch more than 45 degrees off the fan line whose moved root is refused (root_move's limits) is retracted instead
// (the carrier's moved corner carries it) when it leaves within this many degrees of the carrier's outward corner
// direction o_k = unit(unit(w - u) + unit(w - x_k)) (the branch 60 degrees off the fan line between two leaflets of a
// T or X: 38 degrees; perpendicular branches 55 - 65, which fold), and only when its tube clears the plates
// (kPlateOverlapRootRadii). Such a retraction is checked on the raw mesh like a moved root (check_moved_roots, around
// the retracted corner w). Degrees.
inline constexpr double kFallbackCornerDeg = 40;
// A refused branch whose tube runs into a leaflet's plate is refused naming that first (fan_end_refusal): past this
// many radii r_w of arc length from the fan end along the branch (the root's own reach: a branch leaving w at any
// angle is within r of the plates at w itself), its centre line closer to a face than the tube's radius plus the
// face's (the mean of its corners' radii). Dimensionless. Only the refusal's words: nothing meshed changes.
inline constexpr double kPlateOverlapRootRadii = 3.0;

struct FanEndRetraction {
    int vertex = -1;                // w: the fan-edge end carrying the branch (keeps its index)
    int fan_neighbour = -1;         // u: the other end of the former fan edge (u, w)
    int carrier_face = -1;          // the face that keeps w, moved along its border (its leaflet carries the branch)
    std::vector<int> new_vertices;  // w_i, one per retracted face, in face id order
    int fan_edge_split = -1;        // a single fan edge split first: its midpoint (then u); a short chain with branches
                                    // at both ends cut first (recorded at its lower end): the first cut point; else -1
    int strip_faces_split = 0;      // faces cut in two by that split (the strips from the fan edge to the borders)
    int border_vertices_slid = 0;   // thick radii: border vertices slid along their straight run (either kind)
    int moved_root = -1;            // a branch far from the fan line moved off w: the cut point on the carrier's border
                                    // side that now carries it (new_vertices then empty, w and u not moved; its row
                                    // cut's point on the fan edge in fan_edge_split, or -1); else -1
    int bend = -1;                  // a moved first edge bent (kBendRadii): the new vertex p on it; else -1
    int first_joint = -1;           // a moved root's single branch edge not bent: its first joint, moved to
                                    // kFirstJointRadii r_w from the root along the edge; else -1
    bool far_branch = false;        // retracted though more than 45 degrees off the fan line (its moved root refused,
                                    // kFallbackCornerDeg): the raw mesh is checked around w like a moved root's
    friend bool operator==(const FanEndRetraction&, const FanEndRetraction&) = default;
};

// Why the repair leaves the branch on vertex w as it is: the first of the repair's own conditions (the configuration
// above, walked in the order the repair checks it) that fails at w, with the value measured (faces, border edges,
// angle in degrees, fan edges at u, the strip that does not cross, ...) and an edit of the skeleton that removes the
// obstacle. Worded to follow "skeleton vertex w: ... the fan-end repair does not take: " (skeleton_analysis.cpp).
struct FanEndRefusal {
    std::string reason;  // the failing condition and its measured value
    std::string edit;    // a concrete edit suggestion
    // The failing condition is the moved root's border budget (thick_root_run: the root too thick for the straight
    // border run beside the fan line) and the branch's tube clears the plates: the pipeline then stands the branch on
    // the fan block's side section or notch where one carries it (CompatibleBlockOptions::fan_side_branches).
    bool thick_root = false;
};

// std::nullopt when retract_fan_ends(s) would retract the fan edge from w (with its split or cut first), given the
// skeleton as it is (radii are read only for the room the retraction needs, kRetractionMinRadii, when there is one per
// vertex); a reason otherwise, also for a vertex that is no fan-edge end with a branch. When the branch is refused and
// its tube runs into a leaflet's plate (kPlateOverlapRootRadii), the reason names that first (the face, the distance,
// the radii needed), then the repair's own failing condition; the edit turns the branch away or thins it.
// A chain of 2 fan edges with branches at both ends whose strips do not cross is retracted at its lower end only: the
// higher end is refused (on the skeleton after that retraction, its reason is then that u is not a plain fan end).
// O((V + E + F) log E).
std::optional<FanEndRefusal> fan_end_refusal(const Skeleton& s, int w);

// The first vertex (increasing index) of s with a branch edge on exactly one fan edge (an edge of 3 or more faces), the
// configuration the analysis refuses after the repair, with fan_end_refusal's reason and the fan edge's face count;
// std::nullopt when there is none, or fan_end_refusal would take it. Called by the pipeline on the repaired input
// sampling, before the resampling moves the branch's first vertices: the reason is then measured where the repair
// measured it (on the resampled skeleton a failing condition may not show, and the analysis could only say that the
// repair did not run). O(V + E + F) plus fan_end_refusal at each such vertex.
struct FanEndRefusalAt {
    int vertex = -1;
    int fan_degree = 0;
    FanEndRefusal why;
};
// Vertices in fan_caps (sorted) are skipped: left to a fan block's cap (retract_fan_ends).
std::optional<FanEndRefusalAt> first_fan_end_refusal(const Skeleton& s, const std::vector<int>& fan_caps = {});

// Preconditions: one radius > 0 per vertex, faces quads, indices in range (else nothing is done: analysis reports
// the input). Postconditions: V - E + F unchanged (each retracted face adds w_i and the side (u, w_i)); input vertices,
// edges and faces keep their indices (new vertices, edges and faces appended in repair order: a split's midpoints, the
// fan edge's first, then strip by strip in face id order, then the retraction's); no fan-edge end with a branch of the
// configuration above is left. Retractions are made one vertex at a time, in increasing vertex index, each preceded by
// its split when its fan edge is single; chains of 1 or 2 fan edges with branches at both ends are cut first (in
// increasing index of their lower end), then retracted at both ends; such a chain whose strips do not cross to a
// border is not cut (the rounds still retract an end where the configuration above allows; what is left is refused
// by the analysis). Then the roots of branches far from the fan line are moved (increasing w, each after its row
// cut), then the retraction rounds run again. Edges keep their indices (a moved branch edge changes its end w to m).
// Deterministic. O(repairs x (V + E + F) log E).
// fan_caps (sorted vertex ids): fan-edge ends whose branch stands on the fan block's cap (design note C1,
// CompatibleBlockOptions::fan_cap_branches; the pipeline finds them with find_fan_blocks on the input): left as they
// are, neither retracted nor cut (a chain with such an end has no other end to retract: the block accepts only chains
// whose ends are plain or carry such a branch).
std::vector<FanEndRetraction> retract_fan_ends(Skeleton& s, const std::vector<int>& fan_caps = {});

}  // namespace mesohex
