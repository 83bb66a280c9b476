#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "direction_fixtures.h"
#include "mesohex/stages/orange_three.h"
#include "mesohex/stages/sphere_partition.h"

using mesohex::Vec3;
using mesohex::test::random_direction_triple;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;
constexpr double kScoreWeight = kPi / 2;  // quality_score's margin weight (a margin ratio of 1 counts as 90 degrees)
constexpr double kThreeWeight = kPi / 3;  // the weight partition_sphere's three-direction orange uses

// The solver's starts of one setting (coarse scan, table) against another's, on 3 000 triples of the five kinds (the
// same triples for every call): how often the second ends higher / lower than the first (by more than 1e-9), its
// largest loss and the sum of its score differences (radians).
struct StartSetting {
    bool coarse = false;
    bool tabled = false;
};
struct StartComparison {
    int higher = 0, lower = 0;
    double largest_loss = 0, sum = 0;
};
StartComparison compare_starts(StartSetting base, StartSetting tried) {
    std::mt19937_64 rng(20261207);
    StartComparison c;
    for (int set = 0; set < 3000; ++set) {
        const std::vector<Vec3> d = random_direction_triple(rng, set % 5);
        const std::array<Vec3, 3> a = {d[0], d[1], d[2]};
        const Vec3 base_axis = mesohex::detail::exact_three_orange_axis(d, base.coarse, base.tabled);
        const Vec3 tried_axis = mesohex::detail::exact_three_orange_axis(d, tried.coarse, tried.tabled);
        const double base_score =
            mesohex::orange_score_three(a, mesohex::test::orange_bounds(a), kThreeWeight, base_axis);
        const double tried_score =
            mesohex::orange_score_three(a, mesohex::test::orange_bounds(a), kThreeWeight, tried_axis);
        c.sum += tried_score - base_score;
        if (tried_score > base_score + 1e-9) ++c.higher;
        if (tried_score < base_score - 1e-9) {
            ++c.lower;
            c.largest_loss = std::max(c.largest_loss, base_score - tried_score);
        }
    }
    return c;
}

}  // namespace

// A planar Y (three directions 120 degrees apart): around the plane normal every lune is 120 degrees wide at the poles
// (min(w, 180 - w) = 60 degrees) and every direction lies 60 degrees from its lune's sides, its margin bound (half of
// 120 degrees): margin ratio 1, term 90 (or 60) degrees. The score is 60 degrees there, the most any three directions
// can have (the three widths sum to 360 degrees, so one is >= 120). From tilted starts the solver returns to the
// normal, with either margin weight.
TEST(OrangeThree, PlanarYStarPeaksAtThePlaneNormalWithSixtyDegrees) {
    const std::array<Vec3, 3> d = {Vec3{1, 0, 0}, Vec3{std::cos(2 * kPi / 3), std::sin(2 * kPi / 3), 0},
                                   Vec3{std::cos(4 * kPi / 3), std::sin(4 * kPi / 3), 0}};
    const std::array<double, 3> b = mesohex::test::orange_bounds(d);
    EXPECT_NEAR(b[0], 60 * kDeg, 1e-12);
    for (const double weight : {kScoreWeight, kThreeWeight}) {
        EXPECT_NEAR(mesohex::orange_score_three(d, b, weight, {0, 0, 1}), 60 * kDeg, 1e-12);
        for (const Vec3& start : {Vec3{0.3, 0.1, 1}, Vec3{-0.4, 0.5, 1}, Vec3{0.2, -0.6, -1}}) {
            const mesohex::OrangeAxisThree best =
                mesohex::best_orange_axis_three(d, b, weight, {mesohex::normalized(start)});
            EXPECT_NEAR(best.score, 60 * kDeg, 1e-9);
            EXPECT_NEAR(std::abs(best.axis.z), 1, 1e-9);
        }
    }
}

// A T (x, -x, y): the gap between x and -x is 180 degrees around any axis, so the two other gaps sum to 180 degrees
// and the lunes of x and -x, (180 + g) / 2 wide, have min(w, 180 - w) = g / 2 for the gap g on the far side: the
// smaller is at most 45 degrees. Around z (the gaps 90, 90, 180) the widths are 135, 135 and 90 degrees and every
// direction lies in the plane z = 0 as far from its lune's sides as its margin bound allows (45 degrees; margin ratio
// 1): score 45 with either margin weight.
TEST(OrangeThree, TPeaksAtFortyFiveDegrees) {
    const std::array<Vec3, 3> d = {Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}};
    const std::array<double, 3> b = mesohex::test::orange_bounds(d);
    for (const double weight : {kScoreWeight, kThreeWeight}) {
        EXPECT_NEAR(mesohex::orange_score_three(d, b, weight, {0, 0, 1}), 45 * kDeg, 1e-12);
        std::mt19937_64 rng(7);
        std::normal_distribution<double> g(0, 1);
        for (int k = 0; k < 20; ++k) {
            const Vec3 start = mesohex::normalized(Vec3{g(rng), g(rng), g(rng)});
            EXPECT_LE(mesohex::orange_score_three(d, b, weight, start), 45 * kDeg + 1e-12);
            EXPECT_LE(mesohex::best_orange_axis_three(d, b, weight, {start}).score, 45 * kDeg + 1e-12);
        }
        const mesohex::OrangeAxisThree from_near_z =
            mesohex::best_orange_axis_three(d, b, weight, {mesohex::normalized(Vec3{0.2, 0.3, 1})});
        EXPECT_NEAR(from_near_z.score, 45 * kDeg, 1e-9);
    }
}

// With the margin weight 90 degrees the pieces' minimum is partition_sphere's exact orange quality
// (sphere_partition.cpp, OrangeEvaluator, the search's objective) up to rounding, on random triples and axes.
TEST(OrangeThree, ScoreIsTheOrangeEvaluatorsQuality) {
    std::mt19937_64 rng(20261206);
    std::normal_distribution<double> g(0, 1);
    int compared = 0;
    for (int set = 0; set < 2000; ++set) {
        const std::vector<Vec3> v = random_direction_triple(rng, set % 5);
        const std::array<Vec3, 3> d = {v[0], v[1], v[2]};
        const Vec3 axis = mesohex::normalized(Vec3{g(rng), g(rng), g(rng)});
        const double exact = mesohex::detail::orange_quality_exact(v, axis);
        if (!(exact > 0)) continue;  // (the evaluator returns early below 0)
        ASSERT_NEAR(mesohex::orange_score_three(d, mesohex::test::orange_bounds(d), kScoreWeight, axis), exact, 1e-12)
            << "set " << set;
        ++compared;
    }
    EXPECT_GT(compared, 500);
}

// On the pattern search's own objective (margin weight 90 degrees) and from its starts (the scan's three best axes),
// the solver ends at least as high as the pattern search (sphere_partition.cpp, refine_orange_axis: 8 trial
// directions, halving steps down to 1e-4 rad), which stops on ridges where two pieces meet. 3 000 triples of five
// kinds: never below it by more than 1e-9 rad, above it by more than 1e-9 on most (when it was written: on all 3 000,
// by up to 2.6 degrees; without the ridge correction, 8e-6 rad below it on set 394, a long flat ridge of a near-T).
TEST(OrangeThree, AtLeastAsHighAsThePatternSearch) {
    std::mt19937_64 rng(20261205);
    int above = 0;
    double largest_gain = 0;
    for (int set = 0; set < 3000; ++set) {
        const std::vector<Vec3> d = random_direction_triple(rng, set % 5);
        double searched = -1e300;
        for (const Vec3& axis : mesohex::detail::searched_orange_axes(d))
            searched = std::max(searched, mesohex::detail::orange_quality_exact(d, axis));
        const std::array<Vec3, 3> a = {d[0], d[1], d[2]};
        const mesohex::OrangeAxisThree best = mesohex::best_orange_axis_three(
            a, mesohex::test::orange_bounds(a), kScoreWeight, mesohex::detail::scanned_orange_axes(d));
        const double solved = mesohex::detail::orange_quality_exact(d, best.axis);
        ASSERT_GE(solved, searched - 1e-9) << "set " << set;
        if (solved > searched + 1e-9) ++above;
        largest_gain = std::max(largest_gain, solved - searched);
    }
    std::printf("solver above the pattern search on %d of 3000 triples, by up to %.3f degrees\n", above,
                largest_gain / kDeg);
    EXPECT_GT(above, 2500);
}

// partition_sphere's three-direction orange (exact_three_orange, the default) is the one around the solver's axis with
// the weight 60 degrees (point 0 of the orange is its axis, up to the rounding of partition_sphere normalising the
// directions again), valid, and that axis scores at least as high on that weight as the pattern search's axes (which
// maximise the 90-degree score); nearly planar triples, whose planar orange partition_sphere returns at once, are
// skipped.
TEST(OrangeThree, PartitionUsesTheSolversAxis) {
    std::mt19937_64 rng(20261207);
    int compared = 0;
    for (int set = 0; set < 300; ++set) {
        const std::vector<Vec3> d = random_direction_triple(rng, set % 5);
        const mesohex::SpherePartition p = mesohex::partition_sphere(d);
        ASSERT_EQ(mesohex::verify_sphere_partition(p, d), "");
        const Vec3 axis = mesohex::detail::exact_three_orange_axis(d);
        if (!(mesohex::norm(p.points[0] - axis) < 1e-12)) continue;  // the planar path's orange
        ++compared;
        const std::array<Vec3, 3> a = {d[0], d[1], d[2]};
        const double solved = mesohex::orange_score_three(a, mesohex::test::orange_bounds(a), kThreeWeight, axis);
        for (const Vec3& searched : mesohex::detail::searched_orange_axes(d))
            ASSERT_GE(solved,
                      mesohex::orange_score_three(a, mesohex::test::orange_bounds(a), kThreeWeight, searched) - 1e-9)
                << "set " << set;
    }
    EXPECT_GT(compared, 200);
}

// An axis through a direction (its projection on the axis' tangent plane exactly zero): that direction lies on the
// orange's poles, its margin is 0 (cos of its elevation), so the score is <= 0 and finite, as the exact evaluation's
// (cos(pi / 2) ~ 6e-17 for its elevation); the gaps next to it are read from the azimuths (no 0 / 0: before, the
// pieces reading them were NaN and dropped from the minimum, 0.279 here). A climb that starts there (partition_sphere
// starts only from valid scan axes) has no slope to leave by and reports that score, not a valid orange's.
TEST(OrangeThree, AxisThroughADirectionScoresZero) {
    const std::array<Vec3, 3> d = {Vec3{0, 0, 1}, mesohex::normalized(Vec3{1, 0, 0.2}),
                                   mesohex::normalized(Vec3{-0.5, 0.8, -0.3})};
    const std::array<double, 3> b = mesohex::test::orange_bounds(d);
    for (const double weight : {kScoreWeight, kThreeWeight}) {
        const double at_pole = mesohex::orange_score_three(d, b, weight, d[0]);
        EXPECT_TRUE(std::isfinite(at_pole));
        EXPECT_LT(at_pole, 1e-12);
        const mesohex::OrangeAxisThree best = mesohex::best_orange_axis_three(d, b, weight, {d[0]});
        EXPECT_LT(best.score, 1e-12);
        EXPECT_EQ(best.score, mesohex::orange_score_three(d, b, weight, best.axis));
    }
    const std::vector<Vec3> v(d.begin(), d.end());
    EXPECT_LT(mesohex::detail::orange_quality_exact(v, d[0]), 1e-12);
}

// SpherePartitionOptions::coarse_three_scan: the solver's starts from the 60-axis scan, each more than 0.5 rad from the
// better ones, against the 400-axis scan's three best, on 3 000 triples of the five kinds. Measured: the coarse starts
// end lower (by more than 1e-9) on 3 triples (a near-T and two tree-like ones, by 0.02 / 0.06 / 0.25 degrees) and
// higher on 11 (where two of the 400-axis scan's best lie in one basin and a distinct start finds another maximum),
// mean +0.001 degrees. A start set that misses the global basin more often (a single start of the 100-axis scan:
// lower on 4 % of random triples, by up to 16 degrees) fails here.
TEST(OrangeThree, CoarseScanStartsReachTheFullScansMaximum) {
    const StartComparison c = compare_starts({false, false}, {true, false});
    std::printf("coarse starts higher on %d, lower on %d of 3000 triples (by up to %.3f degrees), mean %+.5f degrees\n",
                c.higher, c.lower, c.largest_loss / kDeg, c.sum / 3000 / kDeg);
    EXPECT_LE(c.lower, 6);
    EXPECT_LT(c.largest_loss, 0.5 * kDeg);
    EXPECT_GE(c.higher, c.lower);
    EXPECT_GE(c.sum, 0);
}

// The committed table (orange_three_table.inc) is what orange_three_table_axis gives at its nodes, rounded to 1/127
// per coordinate (the zero vector where a node is no valid triple): checked at every 7th node (314 of 2 197).
TEST(OrangeThree, CommittedTableHoldsTheNodesMaxima) {
    const int n = mesohex::kOrangeTableNodes;
    const signed char* table = mesohex::orange_three_table();
    int valid = 0;
    for (int index = 0; index < n * n * n; index += 7) {
        const int a = index / (n * n), b = index / n % n, c = index % n;
        const auto at = [&](int k) { return mesohex::orange_table_angle(static_cast<double>(k) / (n - 1)); };
        const Vec3 axis = mesohex::orange_three_table_axis(at(a), at(b), at(c), kThreeWeight);
        EXPECT_EQ(table[3 * index], std::lround(127 * axis.x)) << index;
        EXPECT_EQ(table[3 * index + 1], std::lround(127 * axis.y)) << index;
        EXPECT_EQ(table[3 * index + 2], std::lround(127 * axis.z)) << index;
        valid += mesohex::norm(axis) > 0;
    }
    // 317 of the 2 197 nodes hold an axis (339 meet the triangle inequality: the cube's corners and, with the nodes
    // dense near 0 and pi, most nodes lie outside), 37 of the 314 checked
    EXPECT_GT(valid, 25);
}

// The table's node angles: 0 and pi at the ends, pi / 2 in the middle, inverse of each other.
TEST(OrangeThree, TableAnglesRunFromZeroToPi) {
    EXPECT_NEAR(mesohex::orange_table_angle(0), 0, 1e-15);
    EXPECT_NEAR(mesohex::orange_table_angle(0.5), kPi / 2, 1e-15);
    EXPECT_NEAR(mesohex::orange_table_angle(1), kPi, 1e-15);
    for (const double angle : {0.01, 0.3, 1.0, 2.0, 3.1})
        EXPECT_NEAR(mesohex::orange_table_angle(mesohex::orange_table_coordinate(angle)), angle, 1e-12);
}

// SpherePartitionOptions::tabled_three_start: the solver's 2 starts from the table (and the pair normals, the tips'
// plane normal, the mean) against the coarse scan's distinct starts, on 3 000 triples of the five kinds. Measured:
// lower (by more than 1e-9) on 8 triples, by at most 0.32 degrees, higher on 4, mean -0.0003 degrees. The table's own
// axes alone (1-3 starts from the 8 nodes around, without the geometric axes) end lower on 114 triples, by up to 43
// degrees at close pairs; one start of the ranked candidates lower on 75: such a start set fails here.
TEST(OrangeThree, TabledStartsReachTheCoarseScansMaximum) {
    const StartComparison c = compare_starts({true, false}, {true, true});
    std::printf("tabled starts higher on %d, lower on %d of 3000 triples (by up to %.3f degrees), mean %+.5f degrees\n",
                c.higher, c.lower, c.largest_loss / kDeg, c.sum / 3000 / kDeg);
    EXPECT_LE(c.lower, 12);
    EXPECT_LT(c.largest_loss, 0.5 * kDeg);
    EXPECT_GT(c.sum / 3000, -0.002 * kDeg);
}
