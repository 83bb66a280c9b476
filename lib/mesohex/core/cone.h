#pragma once
// The narrowest cone around a few directions: the direction whose smallest dot product with given vectors is largest.
// Shared by the padding's corner guard (post/padding.h), the leaflet frames at creases (stages/leaflet_geometry.h) and
// the fan vertices (stages/raw_mesh.cpp: gap vertices and a fan end's O_w).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex {

// min over x in w of x . m (for unit vectors: the cosine of the widest angle between m and w).
inline double lowest_corner(const std::vector<Vec3>& w, const Vec3& m) {
    double lo = std::numeric_limits<double>::infinity();
    for (const Vec3& x : w) lo = std::min(lo, dot(x, m));
    return lo;
}

// The unit vector m that maximises lowest_corner(w, m) (a small linear program on the sphere; for unit vectors w, the
// axis of their smallest enclosing cone), or `fallback` when no candidate beats it. The optimum is fixed by one, two
// or three active vectors: each w's own direction, each pair's direction in the plane where their dots are equal (w_i
// projected onto the plane orthogonal to w_i - w_j) and each triple's equidistant direction ((w_j - w_i) x (w_k -
// w_i), on the side of w_i); the best candidate is taken (the first best in enumeration order). O(k^4) for k vectors
// (a few: the corners or faces at one vertex).
inline Vec3 maximin_direction(const std::vector<Vec3>& w, const Vec3& fallback) {
    Vec3 best = fallback;
    double best_value = lowest_corner(w, fallback);
    auto consider = [&](const Vec3& a) {
        if (!(squared_norm(a) > 1e-24)) return;
        const Vec3 m = normalized(a);
        const double value = lowest_corner(w, m);
        if (value > best_value) {
            best_value = value;
            best = m;
        }
    };
    for (std::size_t i = 0; i < w.size(); ++i) {
        consider(w[i]);
        for (std::size_t j = i + 1; j < w.size(); ++j) {
            const Vec3 d = w[i] - w[j];
            if (squared_norm(d) > 1e-24) consider(w[i] - d * (dot(w[i], d) / squared_norm(d)));
            for (std::size_t k = j + 1; k < w.size(); ++k) {
                const Vec3 a = cross(w[j] - w[i], w[k] - w[i]);
                consider(dot(a, w[i]) < 0 ? a * -1.0 : a);
            }
        }
    }
    return best;
}

// The widest angle (degrees) between the unit vector m and the unit vectors w (0 for no w).
inline double widest_angle_deg(const std::vector<Vec3>& w, const Vec3& m) {
    return std::acos(std::clamp(lowest_corner(w, m), -1.0, 1.0)) * 180 / std::numbers::pi;
}

// The axis of the narrowest cone around the unit vectors w (maximin_direction, fallback d) when it narrows their
// widest angle from the unit vector d by more than min_gain_deg (degrees); otherwise d.
inline Vec3 narrower_cone_axis(const std::vector<Vec3>& w, const Vec3& d, double min_gain_deg) {
    if (w.empty()) return d;
    const Vec3 axis = maximin_direction(w, d);
    return widest_angle_deg(w, d) - widest_angle_deg(w, axis) > min_gain_deg ? axis : d;
}

}  // namespace mesohex
