#pragma once
// Small skeletons built in memory for the stage tests.
#include <cmath>
#include <random>
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex::test {

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

}  // namespace mesohex::test
