// Mean-curvature skeletons of the shared tubular surfaces (label shared_data): topology of the known skeletons and
// radii consistent with the distance to the surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "mesohex/surface/skeletonize.h"
#include "mesohex_io/surface_io.h"

namespace mesohex {
namespace {

struct Expected {
    const char* file;
    int extremities, min_branching_points, max_branching_points, cycles;
};

class SkeletonizeData : public ::testing::TestWithParam<std::tuple<Expected, bool>> {};

TEST_P(SkeletonizeData, TopologyAndRadii) {
    const Expected& x = std::get<0>(GetParam());
    const bool inscribed = std::get<1>(GetParam());
    const TriangleMesh surface = read_surface(std::string(MESOHEX_SHARED_DATA_DIR) + "/surfaces/" + x.file);
    SkeletonizeOptions options;
    options.inscribed_radii = inscribed;
    const Skeletonization sk = skeletonize_surface(surface, options);
    const Skeleton& s = sk.skeleton;
    std::vector<int> degree(s.points.size(), 0);
    for (const std::array<int, 2>& e : s.edges) {
        ++degree[static_cast<size_t>(e[0])];
        ++degree[static_cast<size_t>(e[1])];
    }
    EXPECT_EQ(std::count(degree.begin(), degree.end(), 1), x.extremities);
    // The number of branching points is not a topological invariant (a degree-4 junction or two degree-3 ones): the
    // reference skeletons give a range.
    const long branching = std::count_if(degree.begin(), degree.end(), [](int d) { return d >= 3; });
    EXPECT_GE(branching, x.min_branching_points);
    EXPECT_LE(branching, x.max_branching_points);
    EXPECT_EQ(static_cast<long>(s.edges.size()) - static_cast<long>(s.points.size()) + 1, x.cycles);
    EXPECT_EQ(std::count(degree.begin(), degree.end(), 0), 0);
    // Radius / distance to the nearest surface vertex (the data README's check for the reference skeletons), on the
    // flow's curve and on the re-centred one (SkeletonizeOptions::recentre_passes).
    const auto radius_ratios = [&](const Skeleton& k) {
        std::vector<double> ratio;
        for (size_t v = 0; v < k.points.size(); ++v) {
            double d2 = 1e300;
            for (const Vec3& p : surface.points) d2 = std::min(d2, squared_norm(p - k.points[v]));
            ratio.push_back(k.radii[v] / std::sqrt(d2));
        }
        std::sort(ratio.begin(), ratio.end());
        return std::pair{ratio[ratio.size() / 10], ratio[ratio.size() / 2]};
    };
    const auto [q10, median] = radius_ratios(sk.flow_skeleton);
    const auto [centred_q10, centred_median] = radius_ratios(s);
    if (inscribed) {
        // Distance to the surface vs to its nearest vertex: equal up to the triangle size (re-centred joints take
        // their distance again where they are).
        EXPECT_NEAR(median, 1.0, 0.1);
        EXPECT_GT(q10, 0.8);
        EXPECT_NEAR(centred_median, 1.0, 0.1);
        EXPECT_GT(centred_q10, 0.8);
    } else {
        // The median distance to some surface vertices is at least the distance to the nearest one (extension
        // vertices aside), and stays near it on these roughly circular tubes.
        EXPECT_GT(q10, 0.95);
        EXPECT_LT(median, 1.35);
        // A re-centred joint keeps the flow's median radius, taken where it was: moved towards the middle of its
        // section, its nearest surface vertex may lie a little farther than that (cactus: 10th percentile 0.94).
        EXPECT_GT(centred_q10, 0.9);
        EXPECT_LT(centred_median, 1.35);
    }
}

// Reference topologies: cactus.skel (4 leaves, 2 branch nodes), aorta.skel (one bifurcation), a hand (5 fingers +
// wrist: 6 extremities, junctions in the palm), dtorus (genus 2: two cycles, no extremity).
INSTANTIATE_TEST_SUITE_P(
    SharedData, SkeletonizeData,
    ::testing::Combine(::testing::Values(Expected{"cactus.obj", 4, 1, 2, 0}, Expected{"aorta.stl", 3, 1, 1, 0},
                                         Expected{"hand.off", 6, 1, 4, 0}, Expected{"dtorus.off", 0, 1, 2, 2}),
                       ::testing::Bool()),
    [](const ::testing::TestParamInfo<std::tuple<Expected, bool>>& i) {
        const std::string name = std::get<0>(i.param).file;
        return name.substr(0, name.find('.')) + (std::get<1>(i.param) ? "_inscribed" : "_median");
    });

}  // namespace
}  // namespace mesohex
