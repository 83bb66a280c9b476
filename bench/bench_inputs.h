#pragma once
// Synthetic curve skeletons for the speed benchmarks (and the thread-count determinism test): deterministic for a
// given seed (std::mt19937's raw 32-bit draws only, so the result does not depend on the standard library's
// distribution implementations).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/core/vec.h"

namespace mesohex::bench {

// Uniform double in [0, 1) from a 32-bit draw (portable, unlike std::uniform_real_distribution).
inline double unit_draw(std::mt19937& rng) { return static_cast<double>(rng()) / 4294967296.0; }

// Uniformly random unit vector (rejection in the cube, portable).
inline Vec3 random_direction(std::mt19937& rng) {
    for (;;) {
        const Vec3 v{2 * unit_draw(rng) - 1, 2 * unit_draw(rng) - 1, 2 * unit_draw(rng) - 1};
        const double r = norm(v);
        if (r > 0.1 && r <= 1) return v / r;
    }
}

// A random tree of `vertices` vertices with unit edges, radius 0.5 everywhere (adaptation keeps roughly one edge per
// input edge: about 4 raw hexes per vertex). Each new vertex continues the chain of the previous one with
// probability 0.75 (its direction turned by up to ~30 degrees), else starts a branch at a random earlier vertex of
// degree 1-4 (so branching points have degree 3-5, a few 6), in a direction at least 45 degrees away from that
// vertex's edges. Branching and extremity vertices are then about a quarter of the vertices each.
inline Skeleton random_tree(int vertices, std::uint32_t seed) {
    std::mt19937 rng(seed);
    Skeleton s;
    std::vector<std::vector<int>> nbr(1);
    std::vector<Vec3> last_dir{random_direction(rng)};
    s.points.push_back({0, 0, 0});
    auto far_from_edges = [&](int v, const Vec3& d) {
        for (int w : nbr[v])
            if (dot(d, normalized(s.points[w] - s.points[v])) > 0.7071) return false;
        return true;
    };
    while (static_cast<int>(s.points.size()) < vertices) {
        const int prev = static_cast<int>(s.points.size()) - 1;
        int parent = -1;
        Vec3 d{};
        if (unit_draw(rng) < 0.75 && nbr[prev].size() <= 1) {
            for (int attempt = 0; attempt < 32 && parent < 0; ++attempt) {
                const Vec3 c = normalized(last_dir[prev] + 0.6 * random_direction(rng));
                if (far_from_edges(prev, c)) parent = prev, d = c;
            }
        }
        for (int attempt = 0; attempt < 64 && parent < 0; ++attempt) {
            const int v = static_cast<int>(rng() % s.points.size());
            if (nbr[v].empty() || nbr[v].size() > 4) continue;
            const Vec3 c = random_direction(rng);
            if (far_from_edges(v, c)) parent = v, d = c;
        }
        if (parent < 0) continue;  // every attempt failed: draw again (consumes randomness, stays deterministic)
        const int v = static_cast<int>(s.points.size());
        s.points.push_back(s.points[parent] + d);
        s.edges.push_back({parent, v});
        nbr.emplace_back();
        nbr[parent].push_back(v);
        nbr[v].push_back(parent);
        last_dir.push_back(d);
    }
    s.radii.assign(s.points.size(), 0.5);
    return s;
}

// A star of three bent chains from one branching point (vertex 0), `vertices` vertices in all, unit edges, radius
// 0.5; the chains leave 120 degrees apart in the xy plane and curl slowly upwards.
inline Skeleton three_branch_star(int vertices) {
    Skeleton s;
    s.points.push_back({0, 0, 0});
    const int per_chain = (vertices - 1) / 3;
    for (int c = 0; c < 3; ++c) {
        const int len = c < (vertices - 1) % 3 ? per_chain + 1 : per_chain;
        const double a0 = 2.0943951023931953 * c;
        int prev = 0;
        Vec3 p{0, 0, 0};
        for (int k = 0; k < len; ++k) {
            const double a = a0 + 0.02 * k, up = 0.01 * k;
            p = p + normalized(Vec3{std::cos(a), std::sin(a), up});
            s.points.push_back(p);
            const int v = static_cast<int>(s.points.size()) - 1;
            s.edges.push_back({prev, v});
            prev = v;
        }
    }
    s.radii.assign(s.points.size(), 0.5);
    return s;
}

}  // namespace mesohex::bench
