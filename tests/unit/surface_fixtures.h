#pragma once
// Closed triangle surfaces written for the tests, small enough to check by hand.
#include <cmath>
#include <numbers>

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

}  // namespace mesohex::test
