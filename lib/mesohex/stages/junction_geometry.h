#pragma once
// What the connection surfaces (stage 3), frame propagation (stage 4) and the raw mesh agree on about the first chunk
// of a branch at a junction, in one place, so that stage 3's junction model evaluates the chunks that stage 4 and the
// raw mesh will build without knowing their internals: the frame transported along an edge (double reflection), the
// angular margin of a direction inside a connection quad, and the radius of the branch's next vertex within that
// margin.
#include <array>

#include "mesohex/core/vec.h"

namespace mesohex {

// Orthonormal right-handed frame (r, s, t): t points from the vertex into the edge the frame is stored on.
// The connection quad registered there is, from its start: (-s, +r, +s, -r) (reference-notes §6.1).
struct Frame {
    Vec3 r, s, t;
    friend bool operator==(const Frame&, const Frame&) = default;
};

// Frame with the given unit t and r as close as possible to r_hint (any perpendicular when r_hint is along t).
Frame orthonormal_frame(const Vec3& r_hint, const Vec3& t);

// Double-reflection step: transports frame f from x0 to x1 and turns it to the unit tangent t1.
Frame rotation_minimizing_step(const Frame& f, const Vec3& x0, const Vec3& x1, const Vec3& t1);

// Signed angular margin (radians) of unit direction d inside the spherical quad q (unit vectors, counter-clockwise
// seen from outside): the smallest angle from d to the great circles of the four sides, positive inside; -1 when the
// quad has a reflex corner (flat corners, as in the lunes of an orange partition, are allowed).
double spherical_quad_margin(const std::array<Vec3, 4>& q, const Vec3& d);

// Default of RawMeshOptions::margin_fraction, also the value connection surfaces assume in their junction model:
// a vertex next to a branching point u gets a radius of at most L sin(kBranchMarginFraction x m) (L the edge length,
// m = spherical_quad_margin of the edge direction in u's quad), so that its cross-section, seen from u, lies inside
// that quad. Dimensionless (fraction of the margin angle); 1 would allow flat corners.
inline constexpr double kBranchMarginFraction = 0.75;

// min(r, length x sin(fraction x margin)): the radius of a vertex at distance `length` from a branching point along a
// direction with angular margin `margin` (radians, > 0) inside its connection quad (see kBranchMarginFraction).
double margin_limited_radius(double r, double length, double margin, double fraction);

}  // namespace mesohex
