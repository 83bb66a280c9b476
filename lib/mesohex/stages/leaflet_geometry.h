#pragma once
// Leaflet geometry shared by the connection surfaces (stage 3, to place and model junction surfaces) and the raw mesh
// (to place the leaflet vertices and to take a rooted branch's ids from its patch): the patch a branch rooted on a
// leaflet stands on, the normal and outward directions at leaflet vertices, and the distance of a border vertex's out
// column. Functions of the skeleton and its analysis only.
#include <array>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/core/vec.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

// The 2 x 2 patch of leaflet faces around a leaflet interior vertex v that roots a branch (4 faces of one leaflet,
// branch edge `branch_edge`), as the branch sees it: up = the branch leaves to the side of the faces' oriented
// normals (its first chunk stands on the plates' up faces, else on their down faces); seen from that side, point k
// (the edge neighbour neighbour[k], corner corner_point[k] of face[k]) and point k + 1 bound face[k],
// counter-clockwise; corner_diagonal[k] is the corner of face[k] opposite v, corner_centre[k] the corner of v. The
// connection quad of the branch at v is (0, 1, 2, 3) with these points and edge k = (k, k + 1) at the diagonal of
// face[k]. Throws Error(UnsupportedConfiguration) naming v unless exactly 4 faces meet at v in one oriented fan.
struct LeafletPatch {
    bool up = true;
    std::array<int, 4> face{}, corner_centre{}, corner_point{}, corner_diagonal{}, neighbour{};
};
LeafletPatch leaflet_patch(const Skeleton& skeleton, const SkeletonAnalysis& analysis, int v, int branch_edge);

// The patch a branch rooted on a leaflet border vertex v stands on (border_root_at(v) != None), seen from the branch,
// counter-clockwise; border[i] is the other end of v's boundary edge border_edge[i] (in increasing edge id).
//   Out:  the 4 half-chunk out faces around v's out vertex. Points (border[0]'s out vertex, v's out-up vertex,
//         border[1]'s out vertex, v's out-down vertex) when up_first, else with out-up and out-down swapped; edge k
//         joins points k and k + 1 at the out-up / out-down vertex of the border neighbour it touches.
//   Side: the 2 plate faces (face[0] with border[first] and middle, face[1] with middle and the other border
//         neighbour) and the 2 half-chunk faces around v's up vertex (up) or down vertex. Up: points (border[first],
//         middle, border[1 - first], out) copies on the up side (out = v's out-up), edges at face[0]'s and face[1]'s
//         diagonal corner and at the border neighbours' out-up; down: the reverse order on the down side.
struct BorderPatch {
    BorderRoot kind = BorderRoot::None;
    std::array<int, 2> border{}, border_edge{};
    bool up_first = true;                 // Out
    bool up = true;                       // Side
    int first = 0, middle = -1;           // Side
    std::array<int, 2> face{}, corner{};  // Side: the two faces and v's corner in each
};
BorderPatch border_patch(const Skeleton& skeleton, const SkeletonAnalysis& analysis, int v, int branch_edge);
// Sum of the oriented normals of the faces at v.
Vec3 leaflet_normal_sum(const SkeletonAnalysis& analysis, int v);
// Sum of the unit vectors from v to its neighbours along leaflet edges (edges with at least one face).
Vec3 leaflet_neighbour_direction_sum(const Skeleton& skeleton, const SkeletonAnalysis& analysis, int v);

// Directions of the raw-mesh vertices around every leaflet vertex (reference-notes §10), shared by the connection
// surfaces (to place junction surfaces) and the raw mesh (to place the leaflet vertices):
//   normal[w] = unit sum of the oriented normals of the faces at w (zero for a vertex without faces); at a leaflet
//               interior or boundary vertex on a crease (see kCreaseNormalGainDeg) the axis of the narrowest cone
//               around its faces' normals instead;
//   out[w]    = at a vertex with exactly two leaflet boundary edges: the unit sum of the outward in-plane normals
//               t x normal[w] of its two boundary edges (t = the edge's direction as its face traverses it, and at a
//               crease vertex its face's own normal in place of normal[w]; the face
//               lies to the left of t seen from its normal), i.e. the bisector of the EXTERIOR angle of the border,
//               right at convex, straight and reflex corners alike (the mean of the unit vectors to all neighbours,
//               negated, points into the leaflet at a reflex corner); falls back to that mean for a hairpin; zero for
//               every other vertex.
// Serial, in face order: deterministic. O(F + E).
// A leaflet vertex's up / down copies serve every face at it, so the worst of its plate hexes is the one whose face
// normal is farthest from normal[w]. Where the faces fold sharply and unevenly (a flange standing on part of a plate's
// border: 2 plate faces and 1 wall face at its end, whose mean normal is 63 degrees off the wall's against 45 for the
// narrowest cone), the cone's axis replaces the mean when it lowers that largest angle by more than this many degrees.
// Smooth and evenly creased sheets (mean within this of the optimum) keep the mean normal.
inline constexpr double kCreaseNormalGainDeg = 5.0;
// The concave side of a sharp crease: the domain (balls swept over the faces) has its corner where the faces' offset
// planes meet, r / cos(theta) along normal[w] (theta the largest angle between normal[w] and a face normal at w:
// r / sin(a / 2) for two halves meeting at a degrees), while a copy r along normal[w] lies r cos(theta) from the
// faces; the padding cannot fill that wedge when it is deep (a fold of 30 degrees missed its concave corner by 2.9 r).
// The copy on the concave side (the faces' centroids lie on its side of w on the whole) goes the miter distance, at
// most kMiterMaxFactor x r (a fold of 29 degrees), where the miter is at least kMiterMinFactor x r (a fold of 47
// degrees or sharper; at milder creases the padding fills the wedge and the longer column only skews the hexes).
inline constexpr double kMiterMaxFactor = 4.0;  // (see below; in units of r)
inline constexpr double kMiterMinFactor = 2.5;  // (see above; in units of r)
struct LeafletVertexFrames {
    std::vector<Vec3> normal;
    std::vector<Vec3> out;
    // Distance of the up / down copy of a leaflet interior or boundary vertex in units of its radius: 1, or the miter
    // factor on the concave side of a sharp crease (kMiterMaxFactor).
    std::vector<double> up_scale, down_scale;
};
LeafletVertexFrames leaflet_vertex_frames(const Skeleton& skeleton, const SkeletonAnalysis& analysis);

// Distance from a regular leaflet boundary vertex w (two boundary edges) of radius r to its out vertex (the raw mesh
// puts it at w + distance x frames.out[w]): r, except at a reflex corner of the border, where out leans along a
// boundary edge (angle phi < 90 degrees to the edge w -> x, length L): there at most kReflexOutFraction x L / cos phi,
// so that the out vertex stays within that fraction of the edge, measured along it, and the half-chunks on both sides
// of the corner cannot fold over each other (they do once r cos phi exceeds L: a sheet as thick as its edges are
// long, wrapping around the corner). Convex and straight corners (and vertices without two boundary edges) give r.
inline constexpr double kReflexOutFraction = 0.3;
double leaflet_out_distance(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                            const LeafletVertexFrames& frames, int w, double r);

}  // namespace mesohex
