#pragma once
// Small skeletons built in memory for the stage tests.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex::test {

// A random rotation (three Euler angles, uniform enough for coverage), as its three columns.
inline std::array<Vec3, 3> random_rotation(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0, 2 * 3.14159265358979323846);
    const double a = u(rng), b = u(rng), c = u(rng);
    auto rz = [](double t, const Vec3& p) {
        return Vec3{std::cos(t) * p.x - std::sin(t) * p.y, std::sin(t) * p.x + std::cos(t) * p.y, p.z};
    };
    auto rx = [](double t, const Vec3& p) {
        return Vec3{p.x, std::cos(t) * p.y - std::sin(t) * p.z, std::sin(t) * p.y + std::cos(t) * p.z};
    };
    std::array<Vec3, 3> f{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
    for (Vec3& e : f) e = rz(c, rx(b, rz(a, e)));
    return f;
}

// p expressed in the frame f (columns): p.x f[0] + p.y f[1] + p.z f[2].
inline Vec3 apply(const std::array<Vec3, 3>& f, const Vec3& p) { return p.x * f[0] + p.y * f[1] + p.z * f[2]; }

// The surface of the cube [0, 2]^3 with 2 x 2 unit quads per side (26 vertices, 24 faces, 48 edges). outward: every
// face counter-clockwise seen from outside; otherwise the faces on the sides x, y, z = 0 are listed the other way
// round (inconsistent orientations, which the analysis must fix).
inline Skeleton cube_surface(bool outward) {
    Skeleton s;
    std::map<std::array<int, 3>, int> id;
    auto vertex = [&](std::array<int, 3> c) {
        auto [it, fresh] = id.emplace(c, static_cast<int>(s.points.size()));
        if (fresh) s.points.push_back({double(c[0]), double(c[1]), double(c[2])});
        return it->second;
    };
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {0, 2})
            for (int i = 0; i < 2; ++i)
                for (int j = 0; j < 2; ++j) {
                    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                    std::vector<int> f;
                    for (auto [du, dv] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
                        std::array<int, 3> c{};
                        c[axis] = side;
                        c[u] = i + du;
                        c[v] = j + dv;
                        f.push_back(vertex(c));
                    }
                    if (outward && side == 0) std::reverse(f.begin(), f.end());
                    s.faces.push_back(f);
                }
    add_face_edges(s);
    return s;
}

// n x m unit quads in the plane z = 0, vertex (i, j) = j * (n + 1) + i, faces counter-clockwise seen from +z.
inline Skeleton plate(int n, int m) {
    Skeleton s;
    for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= n; ++i) s.points.push_back({double(i), double(j), 0});
    for (int j = 0; j < m; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i;
            s.faces.push_back({a, a + 1, a + n + 2, a + n + 1});
        }
    add_face_edges(s);
    return s;
}

// plate(n, m) with walls of unit quads one row high on `chain`: one standing at +z when `up`, one hanging at -z when
// `down` (a flange when the chain runs on the plate's border); the walls' far vertices are appended in chain order,
// the upper wall's first; radius 0.3 everywhere.
inline Skeleton plate_with_walls(int n, int m, const std::vector<int>& chain, bool up, bool down) {
    Skeleton s = plate(n, m);
    for (double z : {1.0, -1.0}) {
        if (!(z > 0 ? up : down)) continue;
        const int far = static_cast<int>(s.points.size());
        for (int v : chain) s.points.push_back(s.points[v] + Vec3{0, 0, z});
        for (int k = 0; k + 1 < static_cast<int>(chain.size()); ++k)
            s.faces.push_back({chain[k], chain[k + 1], far + k + 1, far + k});
    }
    add_face_edges(s);
    s.radii.assign(s.points.size(), 0.3);
    return s;
}

// plate(n, m) with a wall of unit quads one row high standing at +z on `chain` (plate vertex ids, one grid edge per
// step); the wall's top vertices are appended in chain order (ids from (n + 1)(m + 1)); radius 0.3 everywhere.
inline Skeleton plate_with_wall(int n, int m, const std::vector<int>& chain) {
    return plate_with_walls(n, m, chain, true, false);
}

// n seeded random unit directions, pairwise at least min_angle (radians) apart.
inline std::vector<Vec3> random_directions(int n, unsigned seed, double min_angle) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<Vec3> d;
    while (static_cast<int>(d.size()) < n) {
        const Vec3 c = normalized(Vec3{g(rng), g(rng), g(rng)});
        bool ok = norm(c) > 0.5;
        for (const Vec3& o : d) ok = ok && dot(o, c) < std::cos(min_angle);
        if (ok) d.push_back(c);
    }
    return d;
}

// A medial mesh (as read from a .ma file): points, curve edges (in no triangle) and triangles, every radius `radius`;
// the triangle sides are added to the edges.
inline Skeleton medial_mesh(std::vector<Vec3> points, std::vector<std::array<int, 2>> curve_edges,
                            std::vector<std::vector<int>> triangles, double radius = 0.01) {
    Skeleton s;
    s.points = std::move(points);
    s.radii.assign(s.points.size(), radius);
    s.edges = std::move(curve_edges);
    s.faces = std::move(triangles);
    add_face_edges(s);
    return s;
}

// An L of three unit squares in the plane z = 0 (two triangles each; vertex 4 = (1, 1, 0) is the notch, its faces'
// angles sum to 270 degrees) with one curve edge from the notch to `to` (vertex 8).
inline Skeleton notch_l_with_a_curve(const Vec3& to, double radius = 0.01) {
    return medial_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {0, 2, 0}, {1, 2, 0}, to},
                       {{4, 8}}, {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {3, 4, 7}, {3, 7, 6}}, radius);
}

// A pinch: two fans of two triangles each in the plane z = 0 around vertex 0 = (0, 0, 0), touching only there. Fan A
// spans the directions 0 to 120 degrees (vertices 1, 2, 3 at 0, 60, 120, distance 1), fan B the directions
// 120 + gap to 260 degrees (vertices 4, 5, 6 at 120 + gap, (380 + gap) / 2, 260): gaps of `gap` and 100 degrees.
inline Skeleton pinch_of_two_fans(double gap_deg, double radius = 0.01) {
    const auto at = [](double deg) {
        const double a = deg * std::numbers::pi / 180;
        return Vec3{std::cos(a), std::sin(a), 0};
    };
    return medial_mesh({{0, 0, 0}, at(0), at(60), at(120), at(120 + gap_deg), at((380 + gap_deg) / 2), at(260)}, {},
                       {{0, 1, 2}, {0, 2, 3}, {0, 4, 5}, {0, 5, 6}}, radius);
}

// Two unit squares side by side (border y = 0) with two curves from the border's middle vertex 1 = (1, 0, 0): one of
// two edges through `joint` to `end` (vertices 6, 7), one edge to `other` (vertex 8).
inline Skeleton two_curves_on_a_straight_border(const Vec3& joint, const Vec3& end, const Vec3& other,
                                                double radius = 0.01) {
    return medial_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, joint, end, other},
                       {{1, 6}, {6, 7}, {1, 8}}, {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}}, radius);
}

// Three unit squares in a row (border y = 0: vertices 0 to 3 at x = 0 to 3; 4 to 7 at y = 1) with two curves from
// border vertex 1 = (1, 0, 0): one of two edges through `joint` to `end` (vertices 8, 9), one edge to `other`
// (vertex 10). Vertex 0 is the nearest convex corner (1 away along the border; vertex 3 is 2 away).
inline Skeleton two_curves_next_to_a_corner(const Vec3& joint, const Vec3& end, const Vec3& other,
                                            double radius = 0.01) {
    return medial_mesh(
        {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {3, 1, 0}, joint, end, other},
        {{1, 8}, {8, 9}, {1, 10}}, {{0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}}, radius);
}

// Dino's hip by hand (the shared dino.skel's adapted hip, docs/junctions.md): a degree-4 point at the origin of
// radius 0.223 with body (1), tail (2) and two legs (3, 4) 46 degrees apart, all three children opposite the body.
inline Skeleton dino_hip() {
    Skeleton s;
    s.points = {
        {0, 0, 0}, {0.219, 0.193, -0.035}, {0.212, -0.144, 0.149}, {-0.138, -0.305, 0.024}, {-0.002, -0.266, -0.197}};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
    s.radii = {0.223, 0.221, 0.112, 0.100, 0.105};
    return s;
}

}  // namespace mesohex::test
