#pragma once
// Sheet borders of a medial mesh carried out to the rounded rims the angle filter trimmed them short of
// (compute_medial_axis, last step; docs/sheets.md, "Borders out to rounded rims").
//
// The angle filter keeps a Voronoi face only when its vertices see the face's two samples under min_angle_deg (110):
// at a rounded rim (an ellipse's end, a fillet) the medial sheet runs on to the rim's centre of curvature while the
// angle between its two touching points falls from 180 to 0 degrees, so the kept sheet ends short of it (an ellipse
// 1.8 x 1 keeps x <= 0.97 of its medial segment's 1.24), and the simplification pulls the border in further. The
// leaflet border then lies a radius and more from the surface, farther than the raw mesh (half a radius out of the
// border) and its padding reach.
//
// Each regular border vertex of a sheet (on exactly two border sides, sides of one triangle each; no side in three
// or more triangles, no curve edge) marches along the sheet's outward direction t (the mean of its two border sides'
// outward perpendiculars in their triangles' planes). Let D be the distance from the vertex to the surface along t
// (first ray hit) and d(x) the distance of a point x to the surface (its ball's radius). The rim is reached where the
// surface straight ahead is as near as the ball's radius: D - s <= reach_factor x d(x_s) at x_s = p + s t; at the
// end of a rounded rim's medial sheet (its centre of curvature) D - s = d exactly. Along the bisector of a sharp edge
// of dihedral angle a the ratio (D - s) / d stays 1 / sin(a / 2) (1.41 at 90 degrees) until the edge, so the march
// gives up where the ball has shrunk below min_radius_fraction x its radius at the border (the sheet rightly ends
// where the wedges to the edge begin), and so it does beyond max_move x that radius (a hole the filter punched into
// a plate's sheet: the surface ahead is the plate's far rim); a vertex already within reach_factor does not move. The
// vertex moves to the
// first such x_s (steps of 1/20 of its ball radius) and takes its distance to the surface as its radius; the moves of a
// triangle's vertices that turn it by more than 30 degrees (border vertices going apart, a thin triangle turned over)
// are halved, up to 3 times, then undone. Topology, counts and the order of edges and faces by vertex
// ids are kept; the points are sorted again by (x, y, z) as compute_medial_axis writes them.
#include "mesohex/core/skeleton.h"

namespace mesohex {

class SurfaceQuery;

struct RimExtension {
    int border_vertices = 0;  // regular border vertices examined
    int moved = 0;            // ... moved outward
    int sharp = 0;            // ... whose march gave up (a sharp edge ahead: the ball shrank first)
    double largest_move = 0;  // largest move, in units of the vertex's radius before it
};

// Preconditions: medial is a medial mesh as compute_medial_axis writes it (points with radii, triangle faces, every
// triangle side in edges) of the closed surface behind `query`, its points inside. reach_factor >= 1,
// min_radius_fraction in (0, 1), max_move > 0; otherwise nothing moves. Deterministic (each vertex from the positions
// before any move). Complexity: O(B x 20 max_move x Q) for B border vertices and Q a distance query.
RimExtension extend_rim_borders(Skeleton& medial, const SurfaceQuery& query, double reach_factor,
                                double min_radius_fraction, double max_move);

}  // namespace mesohex
