#pragma once
// Closed triangle surfaces written for the tests, small enough to check by hand.
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex::test {

// Torus of major radius R and tube radius r about the z axis: nu x nv vertices, 2 nu nv triangles, genus 1.
inline TriangleMesh torus_surface(double R, double r, int nu, int nv) {
    constexpr double kPi = std::numbers::pi;
    TriangleMesh m;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
            m.points.push_back(
                {(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
        }
    auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

// Prism over a polygon (counter-clockwise, star-shaped from its vertex mean) between z0 and z1; caps as fans from a
// centre vertex. Outward oriented.
inline TriangleMesh prism_surface(const std::vector<std::array<double, 2>>& poly, double z0, double z1) {
    TriangleMesh m;
    const int n = static_cast<int>(poly.size());
    double cx = 0, cy = 0;
    for (const std::array<double, 2>& p : poly) {
        cx += p[0] / n;
        cy += p[1] / n;
    }
    for (const std::array<double, 2>& p : poly) m.points.push_back({p[0], p[1], z0});
    for (const std::array<double, 2>& p : poly) m.points.push_back({p[0], p[1], z1});
    m.points.push_back({cx, cy, z0});
    m.points.push_back({cx, cy, z1});
    const int bottom = 2 * n, top = 2 * n + 1;
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        m.triangles.push_back({i, j, n + j});
        m.triangles.push_back({i, n + j, n + i});
        m.triangles.push_back({bottom, j, i});
        m.triangles.push_back({top, n + i, n + j});
    }
    return m;
}

}  // namespace mesohex::test
