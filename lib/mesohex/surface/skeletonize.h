#pragma once
// Curve skeleton of a closed surface by mean curvature flow (CGAL::Mean_curvature_flow_skeletonization), with a
// radius per skeleton vertex and the cleaning a mesher needs. CGAL is included only by skeletonize.cpp.
#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"

namespace mesohex {

struct SkeletonizeOptions {
    // Mean curvature flow. 0 keeps CGAL's default, which is already relative to the model size
    // (min_edge_length = 0.002 x bounding-box diagonal).
    double min_edge_length = 0;                     // absolute length; 0 = CGAL default
    int max_iterations = 500;                       // contraction iterations at most (CGAL default)
    double quality_speed_tradeoff = 0.1;            // CGAL omega_H
    double medially_centered_speed_tradeoff = 0.2;  // CGAL omega_P
    // Radius of each flow-skeleton vertex: the median distance to the surface vertices the flow maps to it (default;
    // the mean size of the cross-section), or, with inscribed_radii, its distance to the surface (the radius of
    // the largest ball centred there; smaller on non-circular cross-sections). Cleaning always decides with the
    // median radius, so both settings give the same graph.
    bool inscribed_radii = false;
    // Cleaning.
    bool prune = true;
    double prune_factor = 2.0;        // a terminal branch is removed when its length + its extremity's radius is
                                      // below prune_factor x its branching point's radius (its tube barely leaves
                                      // the branching point's ball)
    bool merge_branch_points = true;  // merge branching points joined by a short branch
    double merge_factor = 1.0;        // two branching points joined by a branch shorter than
                                      // merge_factor x (larger of their radii) become one
    bool extend_extremities = true;   // extend every extremity towards the surface
    double extension_gap = 0.5;       // an extended extremity stops extension_gap x (its radius) before the surface
    // Re-centring of the joints (vertices of degree 2) after pruning and merging: the mean curvature flow's curve
    // smooths over one-sided bulges (lobes: the curve runs off the middle of its cross-section there), and
    // the raw mesh then fills them with stretched padding. Each pass moves every joint, in the plane normal to its
    // branch (the chord between the points one radius along it on either side), by the mean of the half-differences
    // of recentre_rays opposite pairs of ray hits with the surface, capped at recentre_max_move x its radius. Only
    // where the section is a closed tube: every ray hits within recentre_reach x the joint's radius, else the joint
    // stays (slabs, walls, junctions). The radii stay the flow's (with inscribed_radii: the distance to the surface
    // where the joint now is). 0 passes = off. Measurements: docs/sheets.md, "Curve skeletons re-centred".
    int recentre_passes = 3;          // Jacobi passes (count)
    int recentre_rays = 8;            // opposite ray pairs, spread over 180 degrees in the normal plane (count)
    double recentre_reach = 2.0;      // x radius (dimensionless): farther hits are another part of the solid
    double recentre_max_move = 0.25;  // x radius (dimensionless), per pass
};

struct Skeletonization {
    Skeleton skeleton;  // curve only (no faces); radii always present, one per point
    // The same cleaning without the re-centring (recentre_passes 0): what auto falls back to when the re-centred
    // skeleton's raw mesh inverts hexes the flow's does not. Equal to skeleton when no joint was re-centred.
    Skeleton flow_skeleton;
    int mcf_vertices = 0;  // vertices of the raw MCF skeleton
    int pruned_branches = 0;
    int merged_branch_points = 0;  // merges performed (each removes one branching point)
    int extended_extremities = 0;
    int recentred_joints = 0;       // joints the re-centring moved (counted once, over all passes)
    double recentre_max_shift = 0;  // largest total move of a joint by the re-centring (model units)
};

// Skeletonizes `surface`.
// Preconditions (checked, InvalidInput naming the offending element otherwise): indices in range, no degenerate
// triangle (repeated vertex), closed (every edge in exactly two triangles), edge- and vertex-manifold, consistently
// oriented, a single connected component. Unreferenced vertices are ignored.
// Postconditions: every point has a radius > 0 (see inscribed_radii; the distance to the surface for a vertex with no
// corresponding surface vertex); the graph is connected, has no loop edge and no duplicate edge; its cycle
// count (E - V + 1) equals the MCF skeleton's. The radius of extension vertices is the distance to the surface
// clamped to [0.5, 1] x the radius of the extremity they extend.
// Determinism: the result depends only on `surface` and `options` (not on the heap, the thread count or earlier calls):
// same input, same output bits. Output order is canonical: points sorted lexicographically by (x, y, z), every edge
// {a, b} with a < b, edges sorted.
// Complexity: dominated by the MCF (sparse Cholesky per iteration on the remeshed surface).
// The checks skeletonize_surface and compute_medial_axis make before CGAL sees the surface: closed, manifold,
// consistently oriented, one component, finite, no (near) zero-area triangle, a non-zero enclosed volume.
// Error(InvalidInput) "surface cannot be skeletonized: <why>" otherwise.
void check_surface_for_skeleton(const TriangleMesh& surface);

Skeletonization skeletonize_surface(const TriangleMesh& surface, const SkeletonizeOptions& options = {});

}  // namespace mesohex
