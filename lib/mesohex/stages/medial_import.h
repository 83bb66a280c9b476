#pragma once
// Medial mesh (curve edges + triangle sheets, e.g. read from a .ma file) -> meso-skeleton (curve branches + quad
// leaflets). Method (docs/skeletons.md):
//   0. irregular fans (an edge in 3+ triangles, two of them in the same leaflet) lose removable triangles (see
//      MedialImportOptions::resolve_irregular_fans); (optionally) curve edges ending inside a sheet move to the
//      sheet's nearest boundary vertex (reattach_interior_curves, off by default);
//   1. sheets = triangles connected through shared edges; a sheet with fewer than min_sheet_triangles triangles or an
//      area below min_sheet_area_factor x (its mean radius)^2 collapses to a curve: a new vertex at its centroid,
//      joined to each sheet vertex that has an attachment (a curve edge or another sheet); unattached sheet vertices
//      are dropped;
//   2. leaflets = triangles connected through manifold edges (edges in exactly two triangles); edges in three or more
//      triangles are fan edges between leaflets; each leaflet is oriented consistently (breadth-first flips);
//   3. adjacent triangles of a leaflet are paired greedily into quads, best shape first (corner angles closest to
//      90 degrees, small fold); every face (pair quad or lone triangle) is then split at its centroid and its edge
//      midpoints into 4 or 3 quads that share the midpoints: an all-quad, conforming subdivision of every sheet;
//   4. curve edges (in no triangle) stay branch edges; one ending inside a leaflet where other than 4 quads meet moves
//      to a regular neighbour (root_interior_curves). Radii are kept at input vertices, averaged at new ones;
//   5. BL-joints on a straight stretch of leaflet boundary are pushed out to make a corner, further when their branch
//      heads back over the leaflet (bl_joint_corners, bl_joint_back_push); so are joints at a sharp notch of the
//      border and joints of several curves, at most a fraction of their shortest curve (bl_joint_reflex_corners,
//      bl_joint_corners_with_branches, bl_joint_max_push_curve_fraction); such a join of several curves cut short by
//      that fraction hands its curves to a convex border corner nearby (bl_joint_corner_reach);
//   6. leaflets are smoothed: interior vertices by Laplacian sweeps, boundary vertices along their normal (and along
//      the border at reflex corners) (smoothing_iterations, smooth_boundary), optionally kept near the input sheet
//      (max_sheet_offset).
// The Euler characteristic V - E + F is preserved by pairing, splitting and by collapsing a sheet whose vertices are
// all attached.
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex {

struct MedialImportOptions {
    // Before everything else: an edge in 3+ triangles of which two lie in the same leaflet (an irregular fan, which
    // the mesher cannot mesh) loses triangles, one at a time, flattest remaining fan first, as long as a triangle can
    // go without changing the Euler characteristic (one side free: the triangle and that side go; two sides free and
    // the third vertex in nothing else: the triangle, both sides and the vertex go).
    bool resolve_irregular_fans = true;
    // Then: a pinch, a vertex where two leaflets touch through their borders only (an LL-joint for the mesher), whose
    // nearest two border sides of different leaflets are less than this apart (degrees; 0 = off), gets the triangle
    // across that gap (fill_pinch_gap): the two leaflets become one through the vertex. The mesher's LL-joint pillow
    // puts one point in each gap between the leaflets, so a gap narrower than 60 degrees leaves its two half-chunks
    // with corners below 30 degrees (they flatten or invert); the filled triangle's corner is the whole gap. Only
    // between two leaflets (one leaflet touching itself is left: it stays orientable); Euler characteristic unchanged.
    double fill_pinch_max_angle_deg = 60;
    // A curve edge ending inside a sheet (cup.ma's handle) stays there: after the quad split, an end at a vertex where
    // other than 4 faces meet moves to the regular (4-face) neighbour most in the curve's direction, where the mesher
    // roots the branch on the plates (root_interior_curves). Counts and Euler characteristic unchanged.
    bool root_interior_curves = true;
    // The former way, before everything else (paper limitation 1): re-attach such an end to the nearest boundary
    // vertex of its sheet. It can drag a handle's ends along the wall, out of the domain (docs/tuning.md).
    bool reattach_interior_curves = false;
    int min_sheet_triangles = 2;         // sheets with fewer triangles collapse to a curve
    double min_sheet_area_factor = 1.0;  // sheets with area < factor x (mean vertex radius)^2 collapse to a curve
    bool pair_triangles = true;          // pair triangles into quads before splitting (fewer irregular vertices)
    double max_pair_corner_deviation_deg = 60;  // a pair quad is accepted if every corner is within this of 90 deg
    double max_pair_fold_deg = 45;              // ... and the two triangle normals differ by at most this angle
    // After quadrangulation: a BL-joint (a leaflet boundary vertex with exactly one curve edge) where the leaflet
    // boundary is nearly straight (angle between its two boundary edges above bl_joint_max_angle_deg) is moved out of
    // the leaflet, against the mean direction to its leaflet neighbours, by bl_joint_push x the mean length of its two
    // boundary edges: the boundary then makes a corner there, the layout the mesher's BL-joint blocks need (on a
    // straight boundary their half-chunks fold). Topology and radii are unchanged.
    bool bl_joint_corners = true;
    double bl_joint_max_angle_deg = 110;  // degrees (see bl_joint_corners)
    // ... except a joint the mesher roots on the border's plates (border_root: a branch leaving a straight border
    // outward, or a branch along the normal where 2 faces meet), where no corner is needed.
    bool keep_rooted_bl_joints = true;
    double bl_joint_push = 1.25;  // x the mean of the two boundary edges at the joint
    // A joint whose branch heads back over the leaflet (angle to the inward direction below 90 degrees, cosine c > 0:
    // a plane between the branch and the leaflet's border edges needs a sharper corner) is pushed by
    // bl_joint_push x (1 + bl_joint_back_push x c) x that length instead (dimensionless).
    double bl_joint_back_push = 1.0;
    // A joint at a sharp notch of the border (the two boundary edges at most bl_joint_max_angle_deg apart, the
    // faces' angles at the joint summing to more than 180 degrees: the leaflet wraps around it) is pushed into the
    // notch's gap too, along the bisector of its two boundary edges: past the chord of its two border neighbours,
    // then by the push above (the back push measured against the opposite of that bisector), so that the join
    // becomes a convex leaflet corner instead of a join inside the notch, where the mesher's BL-joint half-chunks
    // fold.
    bool bl_joint_reflex_corners = true;
    // A border vertex where several curves join (a branching point on the border) gets a corner the same way (a
    // straight stretch: the push above; a sharp notch: as bl_joint_reflex_corners), unless it is a corner already
    // (faces' angles summing to less than 150 degrees); no border_root exception.
    bool bl_joint_corners_with_branches = true;
    // The two moves above go at most this x the length of the shortest curve leaving the joint (curve edges up to
    // the next vertex that is not a plain curve joint; dimensionless): the curve's first chunk keeps its direction.
    double bl_joint_max_push_curve_fraction = 0.2;
    // A join of several curves whose push that cap cuts short moves its curves onto the nearest convex leaflet corner
    // (a border vertex whose faces' angles sum to less than 150 degrees, reached through border vertices without
    // curves) at most this x the mean of its two boundary edges away along the border (dimensionless; 0 = off):
    // the curves leave from a corner that is there already (a curve whose far end the corner reaches already merges
    // with that edge); the join itself still goes out by the capped push.
    double bl_joint_corner_reach = 3.0;
    // Finally, leaflet interior vertices (all incident edges in exactly two faces, no curve edge) are smoothed:
    // p <- p + smoothing_factor x (neighbour mean - p), smoothing_iterations Jacobi sweeps (0 = off). Evens out the
    // quads the split makes (corners up to 150 degrees) and the sheet's folds, over which the mesher's plates invert.
    int smoothing_iterations = 30;
    double smoothing_factor = 0.5;  // fraction of the way to the neighbour mean per sweep
    // In the same sweeps, regular leaflet boundary vertices (two boundary edges, no curve or fan edge) move along
    // their normal only, by smoothing_factor x the normal component of (neighbour mean - p): folds that reach the
    // border flatten (hand.ma's wrist), the outline stays. At a reflex corner (face angles at the vertex summing to
    // more than reflex_corner_deg: the sheet wraps around it) the vertex also moves by smoothing_factor x (midpoint of
    // its two boundary neighbours - p): the half-chunks the mesher puts outside such a corner converge and fold.
    bool smooth_boundary = true;
    double reflex_corner_deg = 220;  // degrees (sum of the face angles at the vertex)
    // After every sweep, each smoothed vertex farther than max_sheet_offset x its radius from its leaflet's input
    // triangles (along the closest one's normal) goes back to that distance: the smoothing then evens out the quads
    // within the medial sheet instead of flattening a curved sheet and pulling its border in, off the medial axis,
    // where the spheres no longer reach the surface (docs/sheets.md, "Smoothing on the medial sheet"). Off by default
    // for `import` (a folded sheet border needs the free smoothing; measurements in docs/sheets.md); `auto`, whose
    // medial meshes are fitted to the surface (sphere quadrics), uses 0.25 (meso_import_options).
    double max_sheet_offset = -1;  // x the vertex's medial radius; < 0: off (the smoothing moves freely)
    // After every sweep (and the sheet limit), a leaflet border side shorter than min_border_side_fraction x its
    // length before the smoothing has the sweep's move of its two ends halved (then undone) until it is not, except at
    // a notch deeper than 270 degrees, which must open (dimensionless; 0 = off): where the smoothing rounds a crease of
    // the sheet it slides border vertices along the other wall onto their neighbours, until a side is a few times
    // shorter than the radius, and the half-chunks and plates on it fold (measurements: docs/sheets.md, "Border sides
    // kept").
    double min_border_side_fraction = 0.5;
};

struct MedialImport {
    Skeleton skeleton;              // all faces are quads; every face side is in edges; radii one per point
    std::vector<int> face_leaflet;  // per output face, its leaflet id (0..leaflets-1); faces of one leaflet are
                                    // consistently oriented
    int sheets = 0;                 // triangle sheets in the input (components through shared edges)
    int collapsed_sheets = 0;
    int leaflets = 0;
    int paired_quads = 0;           // triangle pairs merged into a quad before splitting
    int split_triangles = 0;        // triangles left unpaired (each split into 3 quads)
    int moved_bl_joints = 0;        // BL-joints moved to make a corner (bl_joint_corners), all kinds
    int notch_corners = 0;          // ... of them, one-curve joints at a sharp notch (bl_joint_reflex_corners)
    int branch_corners = 0;         // ... joints of several curves (bl_joint_corners_with_branches)
    int joins_to_corners = 0;       // joins of several curves whose curves moved onto a corner (bl_joint_corner_reach)
    int smoothed_vertices = 0;      // leaflet interior and regular boundary vertices moved by the smoothing
    int reattached_curve_ends = 0;  // curve-edge ends moved from a sheet interior to its boundary
    int rooted_curve_ends = 0;      // curve-edge ends moved inside a leaflet to a regular vertex
    int fan_triangles_removed = 0;  // triangles removed to make irregular fans regular (resolve_irregular_fans)
    int filled_pinches = 0;         // triangles added across narrow gaps at pinches (fill_pinch_max_angle_deg)
    int fan_edges = 0;              // input edges in 3 or more triangles (each becomes 2 fan edges when split)
};

// Preconditions (checked, InvalidInput naming the element): radii present (one per point, > 0), every face a
// triangle with 3 distinct in-range vertices, edges in range with distinct ends and no duplicate, every triangle
// side in edges. UnsupportedConfiguration if a leaflet is not orientable (a Moebius band).
// Complexity: O((V + E + F) log(V + E + F)), plus O(iterations x V x F) with max_sheet_offset >= 0 (each smoothed
// vertex against its leaflet's input triangles; a few hundred of each in `auto`).
MedialImport import_medial_mesh(const Skeleton& medial, const MedialImportOptions& options = {});

// Sum of the face angles at every vertex of the polygons `faces` over `points`, in degrees: 360 inside a flat
// leaflet, 180 on a straight border, more at a notch (a reflex border corner). 0 at a vertex in no face. O(sum of
// face sizes).
std::vector<double> face_angle_sums(const std::vector<Vec3>& points, const std::vector<std::vector<int>>& faces);

}  // namespace mesohex
