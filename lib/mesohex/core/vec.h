#pragma once
// Small 3D vector value type used everywhere in mesohex (positions, directions, frames).
#include <algorithm>
#include <cmath>

namespace mesohex {

struct Vec3 {
    double x = 0, y = 0, z = 0;

    constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3& operator+=(const Vec3& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    constexpr Vec3& operator-=(const Vec3& o) {
        x -= o.x;
        y -= o.y;
        z -= o.z;
        return *this;
    }
    constexpr Vec3& operator*=(double s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
    constexpr Vec3& operator/=(double s) {
        x /= s;
        y /= s;
        z /= s;
        return *this;
    }
    friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
constexpr Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
constexpr Vec3 operator*(Vec3 a, double s) { return a *= s; }
constexpr Vec3 operator*(double s, Vec3 a) { return a *= s; }
constexpr Vec3 operator/(Vec3 a, double s) { return a /= s; }

constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
constexpr double squared_norm(const Vec3& a) { return dot(a, a); }
inline double distance(const Vec3& a, const Vec3& b) { return norm(a - b); }
// Unit vector along a; the zero vector stays zero (never NaN).
inline Vec3 normalized(const Vec3& a) {
    const double n = norm(a);
    return n > 0 ? a / n : Vec3{};
}
// A unit vector perpendicular to the unit t: t x the coordinate axis least aligned with t (deterministic).
inline Vec3 any_perpendicular(const Vec3& t) {
    const double ax = std::abs(t.x), ay = std::abs(t.y), az = std::abs(t.z);
    const Vec3 axis = (ax <= ay && ax <= az) ? Vec3{1, 0, 0} : (ay <= az ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
    return normalized(cross(t, axis));
}
// Distance from p to the segment ab (to a when the segment is a point).
inline double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return distance(p, a + ab * t);
}

// The angle (radians, in [0, pi]) between f and g seen around the line through p and q: each taken from the
// segment's midpoint and projected perpendicular to it. With f, g on two faces of a hex at its edge pq (e.g. their
// centroids), the hex's dihedral angle there. 0 when a projection vanishes.
inline double angle_about_edge(const Vec3& p, const Vec3& q, const Vec3& f, const Vec3& g) {
    const Vec3 e = normalized(q - p), mid = (p + q) * 0.5;
    const Vec3 a = (f - mid) - e * dot(f - mid, e), b = (g - mid) - e * dot(g - mid, e);
    return std::atan2(norm(cross(a, b)), dot(a, b));
}

inline bool is_finite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
// det of the 3x3 matrix with columns a, b, c.
constexpr double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return dot(a, cross(b, c)); }

// The point of triangle abc closest to p (the triangle's Voronoi regions: corner, edge or interior). A degenerate
// triangle gives a point of one of its edges or corners.
inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
    const Vec3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    const double sum = va + vb + vc;
    if (!(sum > 0)) return a;  // degenerate (zero area) and not caught above
    return a + (vb / sum) * ab + (vc / sum) * ac;
}

}  // namespace mesohex
