#include "mesohex/stages/junction_geometry.h"

#include <algorithm>
#include <cmath>

namespace mesohex {

namespace {

constexpr double kTiny = 1e-24;

}  // namespace

// Frame with the given unit t and r as close as possible to r_hint.
Frame orthonormal_frame(const Vec3& r_hint, const Vec3& t) {
    Vec3 r = r_hint - dot(r_hint, t) * t;
    const double n = norm(r);
    r = n > 1e-12 ? r / n : any_perpendicular(t);
    return {r, cross(t, r), t};
}

Frame rotation_minimizing_step(const Frame& f, const Vec3& x0, const Vec3& x1, const Vec3& t1) {
    const Vec3 v1 = x1 - x0;
    const double c1 = dot(v1, v1);
    Vec3 rl = f.r, tl = f.t;
    if (c1 > kTiny) {
        rl = f.r - (2.0 / c1) * dot(v1, f.r) * v1;
        tl = f.t - (2.0 / c1) * dot(v1, f.t) * v1;
    }
    const Vec3 v2 = t1 - tl;
    const double c2 = dot(v2, v2);
    Vec3 r1 = rl;
    if (c2 > kTiny) r1 = rl - (2.0 / c2) * dot(v2, rl) * v2;
    return orthonormal_frame(r1, t1);
}

double spherical_quad_margin(const std::array<Vec3, 4>& q, const Vec3& d) {
    double m = 10;
    for (int k = 0; k < 4; ++k) {
        const Vec3 n = cross(q[k], q[(k + 1) % 4]);
        const double nn = norm(n);
        if (!(nn > 1e-12)) return -1;
        if (dot(n, q[(k + 2) % 4]) < -1e-12 * nn) return -1;  // corner at q[k+1] reflex (flat is allowed: lunes)
        m = std::min(m, std::asin(std::clamp(dot(n, d) / nn, -1.0, 1.0)));
    }
    return m;
}

double margin_limited_radius(double r, double length, double margin, double fraction) {
    return std::min(r, length * std::sin(fraction * margin));
}

}  // namespace mesohex
