#pragma once
// Random direction triples for the three-direction orange tests and the table's check (bench/orange_table.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex::test {

// Half the angle from each direction to its nearest other one (sphere_partition's margin bound), radians.
inline std::array<double, 3> orange_bounds(const std::array<Vec3, 3>& d) {
    std::array<double, 3> b{std::numbers::pi, std::numbers::pi, std::numbers::pi};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (j != i) b[i] = std::min(b[i], 0.5 * std::atan2(norm(cross(d[i], d[j])), dot(d[i], d[j])));
    return b;
}

// Random triples of five kinds (0 uniform, 1 near a plane (Y-like), 2 in a cone, 3 tree-like (one back, two
// forward), 4 a near-T (two nearly opposite)); pairs closer than 0.05 rad are redrawn.
inline std::vector<Vec3> random_direction_triple(std::mt19937_64& rng, int kind) {
    std::normal_distribution<double> g(0, 1);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> d;
    while (d.size() < 3) {
        Vec3 v{g(rng), g(rng), g(rng)};
        if (kind == 1) v.z *= 0.2;
        if (kind == 2) v.z = std::abs(v.z) + 1.5;
        if (kind == 3 && d.empty()) v = Vec3{0, 0, -1};
        if (kind == 3 && !d.empty()) v.z = std::abs(v.z) * 0.7 + 0.3;
        if (kind == 4 && d.size() == 1) v = -1.0 * d[0] + 0.3 * u(rng) * v;
        v = normalized(v);
        bool apart = true;
        for (const Vec3& o : d) apart = apart && std::acos(std::clamp(dot(o, v), -1.0, 1.0)) > 0.05;
        if (apart) d.push_back(v);
    }
    return d;
}

}  // namespace mesohex::test
