#pragma once
// Medial axis of a closed surface as a simplified medial mesh: sphere vertices (centre + radius), curve
// edges and triangle sheets, the input `import_medial_mesh` (stages/medial_import.h) turns into a meso-skeleton.
// CGAL (3D Delaunay triangulation) is included only by medial_axis.cpp. Method (docs/skeletons.md, `mesohex medial`):
//   1. sampling: the surface vertices, points every sample_spacing along every edge, and pseudo-random points (fixed
//      hash of the triangle id) inside every triangle at a density of one per sample_spacing^2; where the solid is thin
//      (a ray along the inward normal from each cell of a grid of the spacing hits the other side within
//      thickness_samples x the spacing), stratified extra samples at the local spacing thickness / thickness_samples;
//   2. inner Voronoi diagram: the Delaunay triangulation of the samples (CGAL::Delaunay_triangulation_3, inexact
//      constructions kernel); a cell whose circumcentre lies inside the surface (SurfaceQuery::inside) gives a medial
//      sphere (its circumcentre and circumradius);
//   3. angle filter: the Voronoi face dual to the Delaunay edge pq is kept when all its Voronoi vertices c are inside
//      and see p and q under an angle pcq of at least min_angle_deg (a noise face between two neighbouring samples
//      sees them under a small angle; a face between the two sides of a plate under 180 degrees; the wedges going to
//      90-degree edges of the surface, under 90 degrees: a sheet ends where the shape's edges begin, which trims it);
//      where both samples lie in thin parts, the face is also kept when they are at least thin_separation x the local
//      thickness apart (a lambda-medial criterion scaled to the thickness: keeps a thin sheet's ligature into a thicker
//      part, which the angle cuts);
//      with keep_topology the filter is an erosion by elementary collapses instead (narrow faces go only from a free
//      side), followed by keep_parts_and_paths (wide-face parts of extent >= part_extent_factor x radius and the
//      shortest curve paths linking them); join_factor > 0 joins parts the plain filter cut off; cover_fraction > 0
//      keeps the cut-off parts that cover enough of the surface the others leave uncovered, joined by a curve edge;
//      keep_limbs keeps the cut-off parts longer than thick that reach uncovered surface as trees of curves (all but
//      cover_fraction off by default);
//   4. simplification (in the spirit of Q-MAT, Li et al. 2015): every sphere carries the sphere quadric of the
//      tangent planes at its touching samples (error of a sphere (c, r) against the plane through p with unit normal
//      n: (n . (c - p) + r)^2); edges are collapsed cheapest first to the sphere minimizing the summed quadric, only
//      when the link condition holds (homotopy type and Euler characteristic kept) and no sheet triangle flips, down
//      to target_vertices (further while the error stays below error_tolerance), or (max_edge_radius) while no edge
//      grows longer than max_edge_radius x the smaller radius of its ends;
//   5. curves and sheets by measured geometry: a triangle is wide when its smallest height is at least
//      sheet_width_factor x its mean radius; a thin triangle with a side in no other triangle is removed with that
//      side (an elementary collapse: homotopy kept), until none is left: tubes become curve edges; terminal curve
//      branches that barely leave the sphere they start from are pruned (spurs); only the largest connected part is
//      kept; curve chains between sheet vertices (or curve branching points) that run along a sheet (fringe_factor) are
//      removed (remove_fringe_curves);
//   6. sheet borders trimmed short of a rounded rim are carried out to it (extend_rims, surface/medial_rims.h).
// Deterministic: same surface and options, same output (the samples, the Delaunay insertion order and every later
// loop are fixed; ties go to the lower id).
#include <vector>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"

namespace mesohex {

struct MedialAxisOptions {
    double sample_spacing = 0.015;  // x bounding-box diagonal: largest gap between surface samples
    int max_samples = 60000;        // the spacing grows until the samples fit (memory and time of the Delaunay)
    // Thin parts (step 1): where the solid, measured along the inward normal, is thinner than thickness_samples x the
    // sample spacing, extra samples bring the local spacing down to thickness / thickness_samples (so the poles of a
    // thin sheet's two sides see each other under wide angles and the angle filter keeps its mid-sheet); 0 = off
    // (samples across the local thickness, dimensionless).
    double thickness_samples = 4;
    double max_refinement = 8;  // the local spacing never goes below sample_spacing / this (dimensionless)
    // Thin parts (step 3): a Voronoi face whose two samples both lie in thin parts is also kept when they are at least
    // this x the local thickness apart (and 2.5 x the local spacing): the lambda-medial criterion scaled to the
    // thickness. It keeps the mid-sheet (samples one thickness apart) and its ligature into a thicker part (a disk's
    // sheet inside its hub: the two reflex rims one thickness apart, seen under less than min_angle_deg), and drops the
    // wedges going to 90-degree edges (at most 0.71 x the thickness apart). 0 = angle filter only (x local thickness).
    double thin_separation = 0.85;
    double min_angle_deg = 110;  // angle filter of step 3 (a surface edge of 90 degrees has no medial sheet)
    // true: the angle filter erodes the inner Voronoi complex by elementary collapses (narrow faces go only from a free
    // side), which keeps its topology (no holes punched into thin sheets, no parts cut off) but leaves narrow strips
    // as curve edges; false: narrow faces are simply dropped (holes and cut-off parts possible).
    bool keep_topology = false;
    // keep_topology: a part of wide faces is kept when its extent is at least this x its largest radius, with the
    // shortest curve paths that link the kept parts; other curve edges (debris near the surface) go (x radius).
    double part_extent_factor = 2.0;
    int target_vertices = 60;    // simplification stops at this many medial vertices ...
    double error_tolerance = 0;  // > 0: stop earlier, when the next collapse costs more than (tolerance x diag)^2
                                 //     and fewer than max_vertices are left (0 = off: always target_vertices)
    int max_vertices = 400;      // the simplification never stops above this many vertices
    // > 0: the simplification stops by resolution instead of at target_vertices: a collapse is refused when an edge of
    // the merged sphere would be longer than this x the smaller radius of its two ends, and collapses go on until every
    // one left is refused (target_vertices and error_tolerance are then unused). A sheet's triangles end up about this
    // many radii wide wherever it is (a fixed count leaves some shapes' sheets far coarser than others'; measured in
    // docs/sheets.md). 0 = off: target_vertices (x sphere radius).
    double max_edge_radius = 0;
    // > 0: likewise by the spheres' fit (with or without max_edge_radius): a collapse is refused when the merged
    // sphere's root-mean-square distance to the tangent planes of its samples (its quadric error per plane) exceeds
    // this x its radius (0 = off; x sphere radius).
    double max_relative_error = 0;
    // > 0: after the stop above, collapses go on (cheapest first, with the link condition) on the edges shorter than
    // this x the smaller radius of their two ends, until none is left that can go; a collapse is refused when a sheet
    // triangle (sheet_width_factor) of its star would turn by more than max_fold_deg or become thin (the thin strips
    // a simplified tube leaves may turn and go). No sheet or curve edge stays short against the spheres it joins,
    // whatever the count (a medial sheet is as thick as its radius: sides shorter than it give leaflet hexes taller
    // than wide; docs/skeletons.md, "Short edges against the radius"). 0 = off (x sphere radius).
    double min_edge_radius = 0;
    double max_fold_deg = 60;          // a collapse that turns a sheet triangle by more than this is refused
    double sheet_width_factor = 0.25;  // a triangle is sheet-like when its smallest height >= this x mean radius
    // Parts of the medial complex the angle filter cut apart (a hub's axis from its disk's mid-sheet) are joined back
    // by a curve edge between their closest spheres when those are at most join_factor x the larger radius apart and
    // the segment stays inside (0 = off: only the largest part is kept, as before); parts with fewer than
    // min_part_vertices Voronoi vertices are noise and dropped.
    double join_factor = 0;     // x sphere radius (off by default: it joins corner debris on a plate)
    int min_part_vertices = 8;  // Voronoi vertices (also for limbs)
    // ... and (join_factor > 0) only parts whose extent (bounding-box diagonal of their centres) is at least this x
    // their largest radius: substantial parts (a finger, a strap), not the corner debris of a plate (0 = every part of
    // min_part_vertices; x sphere radius).
    double join_min_extent = 4;
    // Limbs: a part the angle filter cut off (a finger from the palm) whose spheres touch a surface sample farther than
    // limb_gap x the bbox diagonal and limb_radius_factor x the radius of the nearest kept sphere from every kept
    // sphere is kept as a tree of curves (shortest paths from its sphere nearest the kept ones to its spheres on such
    // samples) joined by one curve edge; its triangles and other spheres go (no cycles; corner debris stays out: a
    // 90-degree edge lies 0.41 x the sheet's radius from it). false: only the largest part is kept (off by default: it
    // changed no `auto` answer where measured; docs/sheets.md, "Limbs").
    bool keep_limbs = false;
    // Covering parts: a part the angle filter cut off (a fuselage's axis from the wings' sheet, one loop of a double
    // torus from the other) is kept whole, joined by one curve edge between its sphere and the kept sphere closest to
    // each other, when its spheres touch at least this fraction of all surface samples that the kept spheres leave
    // uncovered (limb_gap, limb_radius_factor); in decreasing size, before the limbs (0 = off: only the largest part,
    // and what join_factor and keep_limbs add; fraction of the surface samples).
    double cover_fraction = 0.01;
    double limb_gap = 0.01;           // x bbox diagonal
    double limb_radius_factor = 1.0;  // x radius of the nearest kept sphere
    // ... when its centres' bounding-box diagonal is at least this x its largest radius (a limb is longer than thick;
    // the islands of a plate's sheet and the corner debris are not).
    double limb_extent_factor = 4.0;  // x largest radius of the part
    // ... and only when its tree describes it: every sphere centre of the part lies within this x the radius of a tree
    // sphere (a tube; the fragments of a sheet the filter cut apart lie wider and are dropped, as before).
    double limb_width_factor = 1.0;  // x tree sphere radius
    // Curve chains with both ends on sheets that run along a sheet (every sampled point within fringe_factor x its
    // radius of the sheet triangles: at 3 the chain's tube comes within one radius of the sheet's slab all along) are
    // removed when their ends stay connected without them (remove_fringe_curves; 0 = off). They are the remains of
    // thin sheet triangles at a sheet's border and bridges over it, not limbs: they add cycles and joins where the
    // mesher's half-chunks fold (x curve radius; docs/sheets.md).
    double fringe_factor = 3.0;
    // ... and so are such chains that end where 3 or more curves branch off the sheet (not only at sheet vertices):
    // the webs of short chains between a sheet's border and the curves near it, whose border joins of several curves
    // fold the mesher's half-chunks (docs/sheets.md, "Fringe webs"). A chain ending at a tip is never removed.
    bool fringe_node_ends = true;
    // ... except the chains between two interior sheet vertices (on no border side of the sheet): a handle over a sheet
    // (the strap of a cup; the paper's limitation 1, which the
    // mesher supports), not fringe (docs/sheets.md, session 30).
    bool fringe_spare_interior = true;
    double prune_factor = 2.0;  // a terminal curve branch goes when its length + tip radius < this x the radius
                                // where it joins the rest (it barely leaves that sphere: a spur, not a limb)
    // The same spur rule (prune_factor) applied again as the last step, after the fringe removal (prune_spurs):
    // removing a web's chains along a sheet leaves its nodes as tips one short edge from the sheet's border, shorter
    // than the join's radius, whose first chunk lies inside the join's own block and inverts (docs/sheets.md, "Stubs
    // the fringe removal leaves"). Runs whatever fringe_factor is (with fringe_factor 0 it found nothing to
    // prune on the shared surfaces).
    bool prune_after_fringe = true;
    // Last: sheet borders carried out to the rounded rims the angle filter trimmed them short of (extend_rim_borders,
    // surface/medial_rims.h): a regular border vertex marches along its sheet's outward direction until the surface
    // straight ahead is within rim_reach_factor x its ball's radius (the end of a rounded rim's medial sheet, its
    // centre of curvature: 1); it stays when its ball first shrinks below rim_min_radius_fraction x its radius (a sharp
    // edge ahead, where the ratio stays 1 / sin(half the dihedral angle), 1.41 at 90 degrees) or the rim lies farther
    // than rim_max_move x its radius (docs/sheets.md, "Borders out to rounded rims"). Off by default: measured without
    // a gain in `auto`'s answers, fewer raw inversions on some medial meshes and more on others (docs/tuning.md).
    bool extend_rims = false;
    double rim_reach_factor = 1.2;         // x the ball radius at the marching point (>= 1)
    double rim_min_radius_fraction = 0.5;  // x the border vertex's ball radius
    double rim_max_move = 2.0;             // x the border vertex's ball radius
};

struct MedialAxis {
    // The medial mesh: points = sphere centres, radii = sphere radii (> 0), faces = triangles (3 ids each), edges =
    // every triangle side plus the curve edges (in no triangle). Points sorted by (x, y, z); edges {a, b} with a < b,
    // sorted; faces with the smallest id first, sorted. A valid input for import_medial_mesh and write_medial_mesh.
    Skeleton medial;
    int samples = 0;             // surface samples (Delaunay vertices)
    int thin_faces = 0;          // Voronoi faces the thin-part criterion (thin_separation) keeps below min_angle_deg
    int refinement_samples = 0;  // of the samples generated, those added in thin parts
    int inner_poles = 0;         // Delaunay cells with their circumcentre inside
    int voronoi_faces = 0;       // Voronoi faces kept by the angle filter
    int initial_vertices = 0, initial_triangles = 0;  // the medial complex before simplification
    long initial_euler = 0;                           // V - E + F of the medial complex before simplification
    int joined_parts = 0;                             // parts joined back to the main part (join_factor)
    int covering_parts = 0;                           // cut-off parts kept whole (cover_fraction)
    int limbs = 0;                                    // cut-off parts kept as trees (limb_gap)
    int limb_branches = 0;                            // paths of those trees
    int collapses = 0;                                // edge collapses performed
    int thin_triangles_removed = 0;                   // triangles turned into curves (step 5)
    int pruned_tips = 0;                              // curve tips pruned
    int fringe_curves = 0;                            // curve chains removed by remove_fringe_curves
    int pruned_spurs = 0;                             // spurs pruned after the fringe removal (prune_spurs)
    int rim_border_vertices = 0;                      // regular sheet border vertices examined (extend_rims)
    int rim_moved = 0;                                // ... moved out toward a rounded rim
    int rim_sharp = 0;                                // ... kept: a sharp edge ahead
    int sheets = 0;                                   // triangle components through shared edges
    int curves = 0;              // curve branches: chains of curve edges between vertices that are not on exactly
                                 // two curve edges and in no triangle (a closed chain counts once)
    long euler = 0;              // V - E + F of the medial mesh
    double sheet_area = 0;       // total triangle area
    double curve_band_area = 0;  // sum over curve edges of length x (sum of its two radii): the area of the band a
                                 // curve would cover as wide as its spheres
    double sheet_fraction = 0;   // sheet_area / (sheet_area + curve_band_area) (0 when both are 0)
    double bbox_diagonal = 0;    // of the surface
};

// Preconditions (InvalidInput naming the element otherwise): a closed, edge- and vertex-manifold, consistently
// oriented triangle surface with no degenerate triangle, in one connected component (check_surface). NumericalFailure
// when no medial sphere survives the filter (a surface too thin for the sampling). Complexity: O(N log N) for N samples
// (Delaunay, inside tests, simplification with a priority queue).
MedialAxis compute_medial_axis(const TriangleMesh& surface, const MedialAxisOptions& options = {});

// Step 5 of compute_medial_axis, on a medial mesh (points with radii, edges, triangle faces): every curve chain (curve
// edges, in no triangle, between nodes: vertices in a triangle or not on exactly two curve edges) whose two ends are
// triangle vertices (with node_ends: or vertices on 3 or more curve edges) and whose points at 1/4, 1/2 and 3/4 of each
// edge all lie within factor x their interpolated radius of the nearest triangle is removed, with its inner vertices,
// if its ends stay connected without it (chains in vertex order; ties to the lower id). Vertex order is kept (ids
// compacted). Returns the number of chains removed. With spare_interior, a chain whose two ends are interior sheet
// vertices (in a triangle, on no triangle side that lies in one triangle
// only) stays: a handle over a sheet (cup's strap), not a border's fringe.
int remove_fringe_curves(Skeleton& medial, double factor, bool node_ends = false, bool spare_interior = false);

// Terminal curve branches of a medial mesh (from a tip, a vertex with one curve edge and in no triangle, through
// vertices with two curve edges and in no triangle, to its node: a sheet vertex or a vertex with 3 or more curve
// edges) whose length + tip radius is below prune_factor x the node's radius go, shortest first (ties: the smaller
// vertex ids), one at a time, until none is left; a spur's points but its node are dropped (a lone point stays), the
// order of the others kept. A path (both ends tips) stays. Elementary collapses: the Euler characteristic and the
// components do not change. Returns the number of branches removed.
int prune_spurs(Skeleton& medial, double prune_factor);

}  // namespace mesohex
