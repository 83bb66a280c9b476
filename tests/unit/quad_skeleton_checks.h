#pragma once
// Test helpers (issue 6): invariants of a meso-skeleton made of curve edges + quad leaflets.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex::testing {

// All faces quads with 4 distinct in-range vertices; edges unique, in range, no loop; every face side in edges; one
// radius > 0 per point.
inline void expect_valid_quad_skeleton(const Skeleton& s) {
    const int nv = static_cast<int>(s.points.size());
    ASSERT_EQ(s.radii.size(), s.points.size());
    for (double r : s.radii) EXPECT_GT(r, 0.0);
    std::set<std::pair<int, int>> edges;
    for (const std::array<int, 2>& e : s.edges) {
        ASSERT_TRUE(e[0] >= 0 && e[0] < nv && e[1] >= 0 && e[1] < nv);
        EXPECT_NE(e[0], e[1]);
        EXPECT_TRUE(edges.insert(std::minmax(e[0], e[1])).second) << "duplicate edge " << e[0] << "-" << e[1];
    }
    for (size_t f = 0; f < s.faces.size(); ++f) {
        const std::vector<int>& q = s.faces[f];
        ASSERT_EQ(q.size(), 4u) << "face " << f;
        std::set<int> distinct(q.begin(), q.end());
        EXPECT_EQ(distinct.size(), 4u) << "face " << f;
        for (size_t i = 0; i < 4; ++i) {
            ASSERT_TRUE(q[i] >= 0 && q[i] < nv);
            EXPECT_TRUE(edges.count(std::minmax(q[i], q[(i + 1) % 4])) == 1) << "side of face " << f << " not an edge";
        }
    }
}

// Within each leaflet, every edge shared by exactly two of its faces is traversed in opposite directions.
inline void expect_leaflets_oriented(const Skeleton& s, const std::vector<int>& face_leaflet) {
    ASSERT_EQ(face_leaflet.size(), s.faces.size());
    // (leaflet, min, max) -> directed uses (+1 if min->max, -1 otherwise), counted
    std::map<std::tuple<int, int, int>, std::vector<int>> uses;
    for (size_t f = 0; f < s.faces.size(); ++f) {
        const std::vector<int>& q = s.faces[f];
        for (size_t i = 0; i < q.size(); ++i) {
            const int a = q[i], b = q[(i + 1) % q.size()];
            uses[{face_leaflet[f], std::min(a, b), std::max(a, b)}].push_back(a < b ? 1 : -1);
        }
    }
    for (const auto& [key, dirs] : uses)
        if (dirs.size() == 2) {
            EXPECT_EQ(dirs[0] + dirs[1], 0) << "leaflet " << std::get<0>(key) << " edge " << std::get<1>(key) << "-"
                                            << std::get<2>(key) << " traversed twice the same way";
        }
}

}  // namespace mesohex::testing
