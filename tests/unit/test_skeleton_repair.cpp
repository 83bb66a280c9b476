#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "bench_inputs.h"
#include "mesohex/core/error.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/raw_mesh.h"
#include "mesohex/stages/skeleton_repair.h"

using mesohex::Skeleton;
using mesohex::Vec3;

namespace {

constexpr double kDeg = std::numbers::pi / 180;

int degree(const Skeleton& s, int v) {
    int d = 0;
    for (const auto& e : s.edges) d += (e[0] == v) + (e[1] == v);
    return d;
}

// Parent (0,0,-1) -> c = (0,0,0) -> two straight children of length `len` at +-half_angle from +z in the xz plane;
// radius r everywhere. Vertices: 0 parent end, 1 c, 2 child +x, 3 child -x.
Skeleton y_pair(double half_angle, double len, double r) {
    Skeleton s;
    s.points = {{0, 0, -1},
                {0, 0, 0},
                {len * std::sin(half_angle), 0, len * std::cos(half_angle)},
                {-len * std::sin(half_angle), 0, len * std::cos(half_angle)}};
    s.radii = {r, r, r, r};
    s.edges = {{0, 1}, {1, 2}, {1, 3}};
    return s;
}

}  // namespace

// Two straight branches 20 degrees apart, radius 0.1: the tubes separate at l* = 0.1 / sin(10 deg) = 0.5759; the
// trunk vertex lies on the bisector at x = (l* - r) / (1 + r / l*) = 0.4055 with radius r + x r / l* = 0.1704; the
// branches leave it towards their points at l*.
TEST(SkeletonRepair, TrunkForTwoStraightBranches20DegreesApart) {
    const double r = 0.1, half = 10 * kDeg;
    const Skeleton in = y_pair(half, 2.0, r);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in);
    EXPECT_EQ(res.trunks, 1);
    EXPECT_EQ(res.absorbed_stubs, 0);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 7u);  // 4 + t + 2 crotch points
    ASSERT_EQ(s.edges.size(), 6u);   // V - E unchanged (1)
    for (int v = 0; v < 4; ++v) EXPECT_EQ(res.vertex_map[v], v);
    const double l = r / std::sin(half), x = (l - r) / (1 + r / l);
    EXPECT_NEAR(s.points[4].x, 0, 1e-9);
    EXPECT_NEAR(s.points[4].z, x, 1e-7);
    EXPECT_NEAR(s.radii[4], r + x * r / l, 1e-7);
    EXPECT_NEAR(s.points[5].x, r, 1e-7);  // the crotch point of the +x branch: l* (sin 10, 0, cos 10)
    EXPECT_NEAR(s.points[5].z, l * std::cos(half), 1e-7);
    EXPECT_EQ(degree(s, 1), 2);  // c is a joint now: parent -> c -> t
    EXPECT_EQ(degree(s, 4), 3);  // t branches
    // At t the branches are 2 atan((l* sin 10) / (l* cos 10 - x)) = 61 degrees apart instead of 20.
    const Vec3 a = normalized(s.points[5] - s.points[4]), b = normalized(s.points[6] - s.points[4]);
    EXPECT_GT(std::acos(dot(a, b)), 55 * kDeg);
}

// 60 degrees apart: l* = 0.2, x = 0.067 < 0.7 (r_c + r_t) = 0.163: no trunk (the adaptation would collapse it again).
TEST(SkeletonRepair, NoTrunkForBranchesFarApart) {
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(y_pair(30 * kDeg, 2.0, 0.1));
    EXPECT_EQ(res.trunks, 0);
    EXPECT_EQ(res.absorbed_stubs, 0);
    EXPECT_EQ(res.skeleton.points.size(), 4u);
    EXPECT_EQ(res.skeleton.edges.size(), 3u);
}

// 40 degrees apart, radius 0.1: l* = 0.1 / sin 20 = 0.2924, sin a = 0.342, x = 0.1924 / 1.342 = 0.1434, radius 0.1 +
// 0.1434 x 0.342 = 0.1490. x is below trunk_clearance x (r_c + r_t) = 0.174, but c has degree 3 and becomes a joint
// (no bridge to collapse): with joint_trunks the trunk is built because t lies outside c's ball (x > r_c = 0.1). With a
// fourth branch at c (it stays a branching point) the clearance rule applies without wide_junction_trunks: no trunk.
TEST(SkeletonRepair, JointTrunkAtDegreeThree) {
    const double r = 0.1, half = 20 * kDeg;
    const Skeleton in = y_pair(half, 2.0, r);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in);
    EXPECT_EQ(res.trunks, 1);
    const double l = r / std::sin(half), x = (l - r) / (1 + r / l);
    EXPECT_NEAR(x, 0.1434, 1e-4);
    ASSERT_EQ(res.skeleton.points.size(), 7u);
    EXPECT_NEAR(res.skeleton.points[4].z, x, 1e-7);
    EXPECT_NEAR(res.skeleton.radii[4], 0.1490, 1e-4);
    EXPECT_EQ(degree(res.skeleton, 1), 2);
    EXPECT_EQ(res.trunk_joints, std::vector<int>{1});  // c, now a joint: pinned by the pipeline (pin_trunk_joints)
    mesohex::SkeletonRepairOptions old;
    old.joint_trunks = false;
    EXPECT_EQ(mesohex::repair_skeleton(in, old).trunks, 0);
    Skeleton four = in;
    four.points.push_back({0, 1, 0});
    four.radii.push_back(r);
    four.edges.push_back({1, 4});
    mesohex::SkeletonRepairOptions clearance;
    clearance.wide_junction_trunks = false;
    clearance.junction_split = 0;  // the degree-4 split would take the pair (test DegreeFourJunctionSplit)
    const mesohex::SkeletonRepairResult res4 = mesohex::repair_skeleton(four, clearance);
    EXPECT_EQ(res4.trunks, 0);
    EXPECT_EQ(res4.skeleton, four);
    EXPECT_TRUE(res4.trunk_joints.empty());
}

// The same pair (40 degrees, radius 0.1) with a fourth branch at c towards +y: with wide_junction_trunks the ball rule
// of degree 3 applies (x = 0.1434 > r_c = 0.1): one trunk. x is below 0.7 (r_c + r_t) = 0.174, so t moves out to
// x' = 0.7 (0.1 + 0.1) / (1 - 0.7 sin a) = 0.14 / 0.7606 = 0.1841 (sin a = 0.342; below 0.9 l* = 0.263), radius 0.1 +
// 0.1841 x 0.342 = 0.1630, where adaptation keeps the trunk (x' = 0.7 (r_c + r_t)). c keeps the parent, the fourth
// branch and the trunk (degree 3), t = vertex 5 (after the 5 input vertices) gets the pair; the crotch points 6 and 7
// lie at l* = 0.2924 on the two branches. V = 5 + 3 = 8, E = 4 - 2 + 5 = 7 (V - E = 1 as before).
TEST(SkeletonRepair, WideJunctionTrunkAtDegreeFour) {
    const double r = 0.1, half = 20 * kDeg;
    Skeleton four = y_pair(half, 2.0, r);
    four.points.push_back({0, 1, 0});
    four.radii.push_back(r);
    four.edges.push_back({1, 4});
    mesohex::SkeletonRepairOptions wide;
    wide.wide_junction_trunks = true;
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(four, wide);
    EXPECT_EQ(res.trunks, 1);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 8u);
    ASSERT_EQ(s.edges.size(), 7u);
    const double l = r / std::sin(half), sin_a = r / l, xt = 0.7 * 2 * r / (1 - 0.7 * sin_a);
    EXPECT_NEAR(xt, 0.1841, 1e-4);
    EXPECT_NEAR(s.points[5].x, 0, 1e-9);
    EXPECT_NEAR(s.points[5].y, 0, 1e-9);
    EXPECT_NEAR(s.points[5].z, xt, 1e-6);
    EXPECT_NEAR(s.radii[5], 0.1630, 1e-4);
    EXPECT_NEAR(s.points[5].z, 0.7 * (s.radii[1] + s.radii[5]), 1e-6);  // just long enough to stay
    EXPECT_NEAR(s.points[6].x, l * std::sin(half), 1e-7);
    EXPECT_NEAR(s.points[6].z, l * std::cos(half), 1e-7);
    EXPECT_EQ(degree(s, 1), 3);  // parent, the fourth branch, the trunk
    EXPECT_EQ(degree(s, 5), 3);  // the trunk and the pair
    EXPECT_EQ(degree(s, 4), 1);
    // c and t are the two parts of the input's degree-4 junction; extremities and crotch points 0.
    EXPECT_EQ(res.junction_degree, (std::vector<int>{0, 4, 0, 0, 0, 4, 0, 0}));
    // 60 degrees apart (x = 0.067 < r_c): no trunk, with or without the fourth branch.
    Skeleton wide_pair = y_pair(30 * kDeg, 2.0, r);
    wide_pair.points.push_back({0, 1, 0});
    wide_pair.radii.push_back(r);
    wide_pair.edges.push_back({1, 4});
    EXPECT_EQ(mesohex::repair_skeleton(wide_pair, wide).trunks, 0);
}

// A branching point c = (0,0,0) of degree 4, radius 0.1: a close pair 60 degrees apart (+-30 degrees from +z in the xz
// plane, length `pair_len`, end radius 0.05) and two branches +-50 degrees from -z in the yz plane (length `rest_len`,
// radius 0.1; 100 degrees apart, not a close pair). No trunk (the pair's tubes
// separate inside c's ball). Vertices: 0 c, 1 2 the pair, 3 4 the others.
Skeleton degree_four(double pair_len, double rest_len) {
    Skeleton s;
    const double a = 30 * kDeg, b = 50 * kDeg;
    s.points = {{0, 0, 0},
                {pair_len * std::sin(a), 0, pair_len * std::cos(a)},
                {-pair_len * std::sin(a), 0, pair_len * std::cos(a)},
                {0, rest_len * std::sin(b), -rest_len * std::cos(b)},
                {0, -rest_len * std::sin(b), -rest_len * std::cos(b)}};
    s.radii = {0.1, 0.05, 0.05, 0.1, 0.1};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
    return s;
}

// The split (junction_split 0.75, h = 0.075): u = +z (from the other pair's bisector -z to the pair's +z). The first
// vertices lie p1 = cos 30 = 0.8660 beyond c along u (the pair) and p2 = cos 50 = 0.6428 along -u (the others); the
// split points sit m = (p1 + p2) / 2 - h = 0.6794 before them: c' = (0, 0, a), a = p1 - m = (p1 - p2) / 2 + h = 0.1866,
// takes the pair, radius 0.1 + 0.1866 x (0.05 - 0.1) = 0.0907 (the pair's radius there); c moves to (0, 0, -b),
// b = 2 h - a = -0.0366 (on the pair's side of its old place), radius 0.1. V and E grow by one.
TEST(SkeletonRepair, DegreeFourJunctionSplit) {
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(degree_four(1.0, 1.0));
    EXPECT_EQ(res.trunks, 0);
    EXPECT_EQ(res.junction_splits, 1);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 6u);
    ASSERT_EQ(s.edges.size(), 5u);
    const double p1 = std::cos(30 * kDeg), p2 = std::cos(50 * kDeg), a = 0.5 * (p1 - p2) + 0.075;
    EXPECT_NEAR(a, 0.1866, 1e-4);
    EXPECT_NEAR(distance(s.points[0], Vec3{0, 0, a - 0.15}), 0, 1e-12);
    EXPECT_NEAR(s.points[0].z, 0.0366, 1e-4);
    EXPECT_NEAR(s.radii[0], 0.1, 1e-12);
    EXPECT_NEAR(distance(s.points[5], Vec3{0, 0, a}), 0, 1e-12);
    EXPECT_NEAR(s.radii[5], 0.1 - 0.05 * a, 1e-12);
    EXPECT_NEAR(s.radii[5], 0.0907, 1e-4);
    EXPECT_NEAR(distance(s.points[0], s.points[5]), 0.15, 1e-12);  // 2 h
    EXPECT_EQ(degree(s, 0), 3);                                    // the two others and the bridge
    EXPECT_EQ(degree(s, 5), 3);                                    // the pair and the bridge
    // Both halves carry the degree of the input's junction; extremities 0.
    EXPECT_EQ(res.junction_degree, (std::vector<int>{4, 0, 0, 0, 0, 4}));
    for (const int v : {1, 2}) {
        bool to_split = false;
        for (const auto& e : s.edges) to_split |= (e[0] == v && e[1] == 5) || (e[0] == 5 && e[1] == v);
        EXPECT_TRUE(to_split) << v;
    }
    mesohex::SkeletonRepairOptions off;
    off.junction_split = 0;
    EXPECT_EQ(mesohex::repair_skeleton(degree_four(1.0, 1.0), off).junction_splits, 0);

    // The other two first edges 0.1 long (p2 = 0.0643): the bridge moves towards the pair, into the middle of the
    // room: a = (p1 - p2) / 2 + h = 0.4759, c at z = a - 2 h = 0.3259.
    const mesohex::SkeletonRepairResult shifted = mesohex::repair_skeleton(degree_four(1.0, 0.1));
    EXPECT_EQ(shifted.trunks + shifted.absorbed_stubs + shifted.side_stubs, 0);
    ASSERT_EQ(shifted.junction_splits, 1);
    const double a2 = 0.5 * (p1 - 0.1 * p2) + 0.075;
    EXPECT_NEAR(a2, 0.4759, 1e-4);
    EXPECT_NEAR(shifted.skeleton.points[5].z, a2, 1e-12);
    EXPECT_NEAR(shifted.skeleton.points[0].z, a2 - 0.15, 1e-12);
    // An ambiguous pair: a third branch 95 degrees from +z in the xz plane lies 65 degrees from the pair's +x branch,
    // only 5 degrees more than the pair's own 60 (junction_split_gap_deg 10): no split; with the gap at 0, split.
    Skeleton ambiguous;
    ambiguous.points = {{0, 0, 0},
                        {std::sin(30 * kDeg), 0, std::cos(30 * kDeg)},
                        {-std::sin(30 * kDeg), 0, std::cos(30 * kDeg)},
                        {std::sin(95 * kDeg), 0, std::cos(95 * kDeg)},
                        {0, 0, -1}};
    ambiguous.radii = {0.1, 0.1, 0.1, 0.1, 0.1};
    ambiguous.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
    const mesohex::SkeletonRepairResult kept = mesohex::repair_skeleton(ambiguous);
    EXPECT_EQ(kept.trunks + kept.absorbed_stubs + kept.side_stubs + kept.junction_splits, 0);
    mesohex::SkeletonRepairOptions no_gap;
    no_gap.junction_split_gap_deg = 0;
    EXPECT_EQ(mesohex::repair_skeleton(ambiguous, no_gap).junction_splits, 1);
    // Every first edge 0.08 long: p1 + p2 = 0.069 + 0.051 < 2 h, no room for the bridge: no split.
    EXPECT_EQ(mesohex::repair_skeleton(degree_four(0.08, 0.08)).junction_splits, 0);
    // No pair closer than 90 degrees (a planar cross): no split.
    Skeleton cross;
    cross.points = {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    cross.radii = {0.1, 0.1, 0.1, 0.1, 0.1};
    cross.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
    EXPECT_EQ(mesohex::repair_skeleton(cross).junction_splits, 0);
}

// A branching point c = (0,0,0) of degree 5, radius 0.1 (the character family's end of a torso): the close pair of
// degree_four (+-30 degrees from +z in the xz plane, length 1, end radius 0.05) and three branches 65 degrees from -z
// at azimuths 90, 210 and 330 degrees (length 1, radius 0.1; 103 degrees apart, the nearest 88.5 degrees from a pair
// branch: gap 28.5 >= 10). Vertices: 0 c, 1 2 the pair, 3 4 5 the others.
Skeleton degree_five() {
    Skeleton s;
    const double a = 30 * kDeg, b = 65 * kDeg;
    s.points = {{0, 0, 0}, {std::sin(a), 0, std::cos(a)}, {-std::sin(a), 0, std::cos(a)}};
    for (const double phi : {90.0, 210.0, 330.0})
        s.points.push_back({std::sin(b) * std::cos(phi * kDeg), std::sin(b) * std::sin(phi * kDeg), -std::cos(b)});
    s.radii = {0.1, 0.05, 0.05, 0.1, 0.1, 0.1};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {0, 5}};
    return s;
}

// junction_split_degree_five: the three others sum to (0, 0, -3 cos 65), so u = +z as at degree 4; p1 = cos 30, p2 =
// cos 65 = 0.4226, a = (p1 - p2) / 2 + h = 0.2967 (h = 0.075): c' = (0, 0, a), radius 0.1 - 0.05 a; c moves to
// (0, 0, a - 2 h), radius 0.1 (the others' edges at b < 0). c is left with degree 4 (the others and the bridge), whose
// closest pair (two others, about 94 degrees apart seen from the moved c) is not below 90 degrees: no second split.
// Off (the default): the degree-5 point stays.
TEST(SkeletonRepair, DegreeFiveJunctionSplit) {
    EXPECT_EQ(mesohex::repair_skeleton(degree_five()).junction_splits, 0);
    EXPECT_EQ(mesohex::repair_skeleton(degree_five()).skeleton, degree_five());
    mesohex::SkeletonRepairOptions five;
    five.junction_split_degree_five = true;
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(degree_five(), five);
    EXPECT_EQ(res.trunks, 0);
    EXPECT_EQ(res.junction_splits, 1);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 7u);
    ASSERT_EQ(s.edges.size(), 6u);
    const double a = 0.5 * (std::cos(30 * kDeg) - std::cos(65 * kDeg)) + 0.075;
    EXPECT_NEAR(a, 0.2967, 1e-4);
    EXPECT_NEAR(distance(s.points[6], Vec3{0, 0, a}), 0, 1e-12);
    EXPECT_NEAR(s.radii[6], 0.1 - 0.05 * a, 1e-12);
    EXPECT_NEAR(distance(s.points[0], Vec3{0, 0, a - 0.15}), 0, 1e-12);
    EXPECT_NEAR(s.radii[0], 0.1, 1e-12);
    EXPECT_EQ(degree(s, 0), 4);  // the three others and the bridge
    EXPECT_EQ(degree(s, 6), 3);  // the pair and the bridge
    mesohex::SkeletonRepairOptions five_off = five;
    five_off.junction_split = 0;  // junction_split 0 turns both degrees off
    EXPECT_EQ(mesohex::repair_skeleton(degree_five(), five_off).junction_splits, 0);
}

// Issue 22's acceptance audit (bench/issue22_check.py, docs/blocks.md "Acceptance audit (session 24)"): a planar cross
// +x, (cos 78, sin 78, 0), -x, -y (arms of 2 unit edges, radius 0.1) is near-orthogonal: pair angles 78, 90, 102,
// 168, 180, 90 (errors 12 <= 25 degrees), each direction about 6 degrees off its axis, so fit_cube_frame accepts it.
// Its closest pair (78 < 90) is unambiguous (the smallest angle across, 90, exceeds it by 12 >= 10), and the first
// edges leave room (u at about 42 degrees: p1 = cos 42 = 0.743, p2 = sin 42 = 0.669, m = 0.631 > 0), so the degree-4
// split takes it when no block is possible (no block options, or blocks off); with the pipeline's block options
// (enabled) it is left for the block.
Skeleton near_orthogonal_cross(double radius) {
    Skeleton s;
    const Vec3 dirs[4] = {{1, 0, 0}, {std::cos(78 * kDeg), std::sin(78 * kDeg), 0}, {-1, 0, 0}, {0, -1, 0}};
    s.points.push_back({0, 0, 0});
    for (const Vec3& d : dirs) {
        const int first = static_cast<int>(s.points.size());
        s.points.push_back(d);
        s.points.push_back(2 * d);
        s.edges.push_back({0, first});
        s.edges.push_back({first, first + 1});
    }
    s.radii.assign(s.points.size(), radius);
    return s;
}

TEST(SkeletonRepair, NearOrthogonalCrossKeptForItsBlock) {
    const Skeleton in = near_orthogonal_cross(0.1);
    EXPECT_EQ(mesohex::repair_skeleton(in).junction_splits, 1);  // no block options: split as before
    mesohex::CompatibleBlockOptions blocks;
    EXPECT_EQ(mesohex::repair_skeleton(in, {}, &blocks).junction_splits, 0);
    EXPECT_EQ(mesohex::repair_skeleton(in, {}, &blocks).skeleton, in);
    blocks.enabled = false;  // --no-blocks: the paper's layout, split
    EXPECT_EQ(mesohex::repair_skeleton(in, {}, &blocks).junction_splits, 1);
}

// Through the pipeline (resampling; radius 0.25): one block, no interior irregular edge. Hexes 4 per meshed branch
// edge E + 8; boundary irregular edges by hand: 4 corner edges per chunk (4 E) and 8 per extremity cap (4 x 8) of
// valence 1; the cube's docked faces +-x, +-y meet at 4 cube edges (2 mesh edges each) of valence 3, its free faces
// +-z are opposite (no valence-1 cube edge). Blocks off: split into two degree-3 points (2 branching points, interior
// irregular edges at both partitions) and no block.
TEST(SkeletonRepair, NearOrthogonalCrossGetsItsBlockThroughThePipeline) {
    const Skeleton in = near_orthogonal_cross(0.25);
    const mesohex::PipelineResult with = mesohex::run_pipeline(in);
    EXPECT_EQ(with.junction_splits, 0);
    EXPECT_EQ(with.predicted.compatible_blocks, 1);
    EXPECT_EQ(with.analysis.counts.branching_points, 1);
    const long e = static_cast<long>(with.skeleton.edges.size());
    const mesohex::QualityReport q = mesohex::compute_quality(with.raw.mesh);
    EXPECT_EQ(q.hexes, 4 * e + 8);
    EXPECT_TRUE(q.singular_interior_edges.empty());
    EXPECT_EQ(q.singular_boundary_edges, (std::map<int, long>{{1, 4 * e + 32}, {3, 8}}));
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, 1);
    EXPECT_EQ(q.inverted, 0);
    mesohex::PipelineOptions paper;
    paper.connection_surfaces.blocks.enabled = false;
    const mesohex::PipelineResult without = mesohex::run_pipeline(in, paper);
    EXPECT_EQ(without.junction_splits, 1);
    EXPECT_EQ(without.predicted.compatible_blocks, 0);
    EXPECT_EQ(without.analysis.counts.branching_points, 2);
    const mesohex::QualityReport qp = mesohex::compute_quality(without.raw.mesh);
    EXPECT_EQ(qp.hexes, 4 * static_cast<long>(without.skeleton.edges.size()));
    long interior = 0;
    for (const auto& [valence, count] : qp.singular_interior_edges) interior += count;
    EXPECT_GT(interior, 0);
    EXPECT_GT(q.sj_min, qp.sj_min);
}

namespace {

// A raw mesh with `hexes` hexes, valid, not inverted, Euler characteristic 1, irregular edges as predicted.
void expect_raw_as_predicted(const mesohex::PipelineResult& r, int hexes) {
    const mesohex::QualityReport q = mesohex::compute_quality(r.raw.mesh);
    EXPECT_EQ(q.hexes, hexes);
    EXPECT_EQ(q.singular_interior_edges, r.predicted.interior_irregular_edges);
    EXPECT_EQ(q.singular_boundary_edges, r.predicted.boundary_irregular_edges);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, 1);
    EXPECT_EQ(q.inverted, 0);
}

}  // namespace

// Valley trunks (valley_trunk_degree): c = origin, radius 0.1, of degree 4: a fat pair 60 degrees apart (+-30 degrees
// from +z in the xz plane), one branch along -z and one along +y (90 and 150 degrees from the pair: no other close
// pair); every branch 1 long, radius 0.1. Vertices: 0 c, 1 2 the pair, 3 -z, 4 +y.
Skeleton valley_four() {
    Skeleton s;
    const double a = 30 * kDeg;
    s.points = {{0, 0, 0}, {std::sin(a), 0, std::cos(a)}, {-std::sin(a), 0, std::cos(a)}, {0, 0, -1}, {0, 1, 0}};
    s.radii.assign(5, 0.1);
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
    return s;
}

// The pair's tubes separate at l* = 0.1 / sin 30 = 0.2 (sin a = 0.5); its medial junction x = (l* - r) / (1 + sin a) =
// 0.0667 lies inside c's ball (r_c = 0.1): no trunk by the ball rule (the degree-4 split takes the pair instead).
// Valley trunk: x_v = 0.7 (r_c + l*) / 1.7 = 0.12353 > r_c, r_t = min(l* - x_v, r + x_v sin a) = min(0.07647, 0.1618)
// = 0.07647 >= 0.6 r: t = (0, 0, 0.12353) (vertex 5), its ball reaching the crotch (0, 0, 0.2); the pair leaves t
// towards its points at l* (vertices 6, 7: (+-0.1, 0, 0.17321)), 2 atan(0.1 / 0.04968) = 127.1 degrees apart. c keeps
// -z, +y and the trunk (degree 3). V = 5 + 3 = 8, E = 4 - 2 + 5 = 7. The raw mesh of that skeleton (no adaptation):
// 4 hexes per edge, 28, none inverted. With valley_trunk_min_radius 0.8 (r_t = 0.765 r): no trunk.
TEST(SkeletonRepair, ValleyTrunkForAFatPairAtDegreeFour) {
    const Skeleton in = valley_four();
    const mesohex::SkeletonRepairResult off = mesohex::repair_skeleton(in);
    EXPECT_EQ(off.trunks, 0);
    EXPECT_EQ(off.junction_splits, 1);
    mesohex::SkeletonRepairOptions o;
    o.valley_trunk_degree = 4;
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(res.trunks, 1);
    EXPECT_EQ(res.junction_splits, 0);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 8u);
    ASSERT_EQ(s.edges.size(), 7u);
    const double xv = 0.7 * 0.3 / 1.7;
    EXPECT_NEAR(xv, 0.12353, 1e-5);
    EXPECT_NEAR(distance(s.points[5], Vec3{0, 0, xv}), 0, 1e-6);
    EXPECT_NEAR(s.radii[5], 0.2 - xv, 1e-6);
    EXPECT_NEAR(s.points[5].z + s.radii[5], 0.2, 1e-12);  // t's ball reaches the crotch
    EXPECT_NEAR(distance(s.points[5], s.points[0]), 0.7 * (s.radii[0] + s.radii[5]), 1e-6);
    EXPECT_EQ(degree(s, 0), 3);
    EXPECT_EQ(degree(s, 5), 3);
    for (const int v : {6, 7}) {
        EXPECT_NEAR(std::abs(s.points[v].x), 0.1, 1e-9);
        EXPECT_NEAR(s.points[v].z, 0.2 * std::cos(30 * kDeg), 1e-9);
    }
    const Vec3 da = normalized(s.points[6] - s.points[5]), db = normalized(s.points[7] - s.points[5]);
    EXPECT_NEAR(std::acos(dot(da, db)) / kDeg, 127.1, 0.1);
    const mesohex::SkeletonAnalysis an = mesohex::analyze_skeleton(s);
    const mesohex::ConnectionSurfaces cs = mesohex::build_connection_surfaces(s, an);
    const mesohex::RawMesh raw = mesohex::build_raw_mesh(s, an, cs, mesohex::propagate_frames(s, an, cs));
    const mesohex::QualityReport q = mesohex::compute_quality(raw.mesh);
    EXPECT_EQ(q.hexes, 28);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, 1);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_NEAR(q.sj_min, 0.420, 0.005);
    // Through the pipeline (adaptation resamples the branches): the raw minimum 0.333 with the degree-4 split (off),
    // 0.422 with the valley trunk; both raw meshes as predicted (4 hexes per meshed edge, no block).
    const mesohex::PipelineResult po = mesohex::run_pipeline(in);
    mesohex::PipelineOptions valley;
    valley.repair.valley_trunk_degree = 4;
    const mesohex::PipelineResult pv = mesohex::run_pipeline(in, valley);
    expect_raw_as_predicted(po, 4 * static_cast<int>(po.skeleton.edges.size()));
    expect_raw_as_predicted(pv, 4 * static_cast<int>(pv.skeleton.edges.size()));
    EXPECT_NEAR(mesohex::compute_quality(po.raw.mesh).sj_min, 0.333, 0.005);
    EXPECT_NEAR(mesohex::compute_quality(pv.raw.mesh).sj_min, 0.422, 0.005);
    mesohex::SkeletonRepairOptions strict = o;
    strict.valley_trunk_min_radius = 0.8;
    EXPECT_EQ(mesohex::repair_skeleton(in, strict).trunks, 0);
}

// A ring of four at c = origin (radius 0.1): two fat pairs, each 60 degrees apart about its bisector u1 =
// (-sin 40, 0, cos 40) or u2 = (sin 40, 0, cos 40) (80 degrees apart), the pair in the plane of u and y: limbs
// cos 30 u +- sin 30 y; every limb 1 long, radius 0.1. Vertices: 0 c, 1 2 pair one, 3 4 pair two.
Skeleton valley_ring() {
    Skeleton s;
    s.points = {{0, 0, 0}};
    for (const double side : {-1.0, 1.0}) {
        const Vec3 u{side * std::sin(40 * kDeg), 0, std::cos(40 * kDeg)};
        for (const double y : {1.0, -1.0})
            s.points.push_back(std::cos(30 * kDeg) * u + y * std::sin(30 * kDeg) * Vec3{0, 1, 0});
    }
    s.points.push_back({0, 0, -1});
    s.radii.assign(6, 0.1);
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {0, 5}};
    return s;
}

// Both pairs are valley pairs as in ValleyTrunkForAFatPairAtDegreeFour (l* = 0.2, x = 0.0667 < r_c, score x / r_c =
// 0.667 each; the pairs across, limbs of different pairs on the same side of y, are cos^-1(0.75 cos 80 + 0.25) = 67.6
// degrees apart and score lower: l* = 0.1 / sin 33.8 = 0.180, x = 0.051). The first pair in order (1, 2) gets its
// trunk t1 along u1 (t1 = 0.12353 u1, r_t 0.07647, two crotch vertices: V + 3, E + 3), leaving c of degree 4 (pair
// two, -z, t1). Without valley_trunks_apart pair two then gets its own trunk along u2, 80 degrees from t1: two trunks
// at c, V 6 + 6 = 12, E 5 + 6 = 11, c of degree 3 (-z and the two trunks). With it (the default) the second trunk,
// less than 90 degrees from t1, is refused: one trunk, and c (degree 4, pair two 60 degrees apart) is split by the
// degree-4 junction split (pair two moves to a new vertex c': V + 1, E + 1): V 6 + 3 + 1 = 10, E 5 + 3 + 1 = 9.
TEST(SkeletonRepair, ValleyTrunksApartAtARingOfFour) {
    const Skeleton in = valley_ring();
    mesohex::SkeletonRepairOptions o;
    o.valley_trunk_degree = 4;
    o.valley_trunks_apart = false;
    const mesohex::SkeletonRepairResult two = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(two.trunks, 2);
    EXPECT_EQ(two.junction_splits, 0);
    ASSERT_EQ(two.skeleton.points.size(), 12u);
    EXPECT_EQ(two.skeleton.edges.size(), 11u);
    EXPECT_EQ(degree(two.skeleton, 0), 3);
    const Vec3 t1 = two.skeleton.points[6], t2 = two.skeleton.points[9];
    EXPECT_NEAR(distance(t1, 0.12353 * Vec3{-std::sin(40 * kDeg), 0, std::cos(40 * kDeg)}), 0, 1e-5);
    EXPECT_NEAR(std::acos(dot(normalized(t1), normalized(t2))) / kDeg, 80, 1e-6);
    o.valley_trunks_apart = true;
    const mesohex::SkeletonRepairResult one = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(one.trunks, 1);
    EXPECT_EQ(one.junction_splits, 1);
    ASSERT_EQ(one.skeleton.points.size(), 10u);
    EXPECT_EQ(one.skeleton.edges.size(), 9u);
    EXPECT_NEAR(distance(one.skeleton.points[6], t1), 0, 1e-12);
    EXPECT_NEAR(one.skeleton.radii[6], 0.2 - 0.7 * 0.3 / 1.7, 1e-6);
}

// valley_trunk_min_radius is a fraction of the fatter branch's radius at l*: valley_four with the branch along
// (-sin 30, 0, cos 30) thin (a joint 0.02 out, then radius 0.05 to its end). The tubes part where the axes are r_fat
// + r_thin = 0.15 apart, at l* = 0.15 (60 degrees: the axes are l apart at arc l); r = 0.075, sin a = 0.5, x = 0.05 <
// r_c: a valley pair. x_v = 0.7 x 0.25 / 1.7 = 0.10294 > r_c, r_t = min(0.15 - x_v, 0.075 + x_v / 2) = 0.04706:
// 0.627 of the mean radius but 0.471 of the fatter branch's 0.1. So no trunk at 0.6 (nor 0.48), a trunk at 0.47:
// t = (0, 0, x_v) (vertex 5 once the joint before l*, inside the trunk, is gone), V 6 - 1 + 3 = 8.
TEST(SkeletonRepair, ValleyTrunkMinRadiusAgainstTheFatterBranch) {
    Skeleton in = valley_four();
    const Vec3 d = normalized(in.points[2]);
    in.points.push_back(0.02 * d);
    in.radii.push_back(0.05);
    in.radii[2] = 0.05;
    in.edges[1] = {0, 5};
    in.edges.push_back({5, 2});
    mesohex::SkeletonRepairOptions o;
    o.valley_trunk_degree = 4;
    EXPECT_EQ(mesohex::repair_skeleton(in, o).trunks, 0);
    o.valley_trunk_min_radius = 0.48;
    EXPECT_EQ(mesohex::repair_skeleton(in, o).trunks, 0);
    o.valley_trunk_min_radius = 0.47;
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, o);
    ASSERT_EQ(res.trunks, 1);
    const double xv = 0.7 * 0.25 / 1.7;
    ASSERT_EQ(res.skeleton.points.size(), 8u);  // the joint 0.02 out (before l*) goes: 6 - 1 + 3
    EXPECT_NEAR(distance(res.skeleton.points[5], xv * Vec3{0, 0, 1}), 0, 1e-6);
    EXPECT_NEAR(res.skeleton.radii[5], 0.15 - xv, 1e-6);
    EXPECT_NEAR(res.skeleton.radii[5] / 0.1, 0.4706, 1e-4);
}

// Docked walls' feet (docked_foot_split, 2 by default; docs/blocks.md "Acceptance audit (session 24)"): the
// generated wall (6 x 6 unit plate at z = 0, x and y from -3 to 3; a wall of 2 edges and 2 rows on x = 0 from y = -1
// to 1), radius 0.1, split at 2 r = 0.2 from the chain: the plate columns x in [-1, 0] and [0, 1] at x = -0.2 and 0.2
// (beside the chain, through the whole plate), the rows y in [-2, -1] and [1, 2] at y = -1.2 and 1.2 (beyond both
// inside ends, through the whole plate). 4 strips of 6 faces, 7 cut edges each: +28 vertices; the 4 faces crossed
// twice become 4 quads (+3 faces, +1 centre vertex, +4 edges each), the 16 crossed once 2 quads (+1 face, +1 edge).
// V 55 + 28 + 4 = 87, E 94 + 28 + 16 + 16 = 154, F 40 + 16 + 12 = 68 (Euler 1); boundary edges 30 + 8 = 38 (each
// strip cuts 2 border edges); raw hexes 2 F + 2 B = 212 (140 unsplit). From the border (walledge: chain from y = -3):
// 2 strips beside, 1 beyond its inside end; across the whole plate (a T fan, which cuts the plate in two): none.
TEST(SkeletonRepair, DockedWallFeetSplitTheirPlateStrips) {
    mesohex::WallPlate w;
    const Skeleton in = mesohex::make_wall_plate(w, 1.0, 0.1);
    ASSERT_EQ(in.points.size(), 55u);
    mesohex::SkeletonRepairOptions o;
    EXPECT_EQ(o.docked_foot_split, 2);  // the default
    mesohex::SkeletonRepairOptions off;
    off.docked_foot_split = 0;
    EXPECT_EQ(mesohex::repair_skeleton(in, off).skeleton, in);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(res.docked_foot_splits, 4);
    const Skeleton& s = res.skeleton;
    EXPECT_EQ(s.points.size(), 87u);
    EXPECT_EQ(s.edges.size(), 154u);
    EXPECT_EQ(s.faces.size(), 68u);
    int beside = 0, beyond = 0;
    for (std::size_t v = 55; v < s.points.size(); ++v) {
        beside += std::abs(std::abs(s.points[v].x) - 0.2) < 1e-12 && std::abs(std::abs(s.points[v].y) - 1.2) > 1e-9;
        beyond += std::abs(std::abs(s.points[v].y) - 1.2) < 1e-12 && std::abs(std::abs(s.points[v].x) - 0.2) > 1e-9;
        EXPECT_EQ(s.points[v].z, 0.0);
        EXPECT_NEAR(s.radii[v], 0.1, 1e-12);
    }
    EXPECT_EQ(beside, 2 * 7);
    EXPECT_EQ(beyond, 2 * 7);
    const mesohex::PipelineResult r = mesohex::run_pipeline(in);
    EXPECT_EQ(r.docked_foot_splits, 4);
    EXPECT_EQ(r.analysis.counts.boundary_edges, 38);
    EXPECT_EQ(r.predicted.hexes, 212);
    expect_raw_as_predicted(r, 212);
    mesohex::PipelineOptions unsplit;
    unsplit.repair.docked_foot_split = 0;
    EXPECT_EQ(mesohex::compute_quality(mesohex::run_pipeline(in, unsplit).raw.mesh).hexes, 140);
    w.start = 0;  // from the border
    EXPECT_EQ(mesohex::repair_skeleton(mesohex::make_wall_plate(w, 1.0, 0.1), o).docked_foot_splits, 3);
    w.length = 6;  // across: a T fan
    EXPECT_EQ(mesohex::repair_skeleton(mesohex::make_wall_plate(w, 1.0, 0.1), o).docked_foot_splits, 0);
}

// Walls of unequal extents on the two sides of one chain (bench/issue22_check.py wall_0002, docs/blocks.md
// "Acceptance audit (session 24)"): 4 x 4 unit plate at z = 0 (x, y in 0..4), chain on x = 2 from y = 1 to 3, a wall
// of 1 row above (z = 1) over the whole chain, one below (z = -1) over y in [1, 2] only, radius 0.1. V 30, E 48, F 19,
// boundary edges 16 + 4 + 3 = 23. The lower wall ends at the chain vertex (2, 2), where the chain goes on with 3
// faces: the strip of that chain side, (2, 2)-(2, 3), is cut at 2 r = 0.2 beyond it (the row y in [2, 3] of the plate
// and the upper wall's face, y = 2.2: 6 cut edges), besides the 4 strips the chain's ends give (columns x in [1, 2],
// [2, 3] at 1.8 / 2.2 and rows y in [0, 1], [3, 4] at 0.8 / 3.2, 5 cut edges each): 26 cut edges; 6 plate faces
// crossed twice (+3 faces, +1 centre, +4 edges each), 8 plate faces and the upper wall's face crossed once (+1 face,
// +1 edge). V 30 + 26 + 6 = 62, E 48 + 26 + 24 + 9 = 107, F 19 + 18 + 9 = 46 (Euler 1); boundary edges 23 + 4 + 4 +
// 3 = 34 (the new strip cuts the plate's two border edges and the upper wall's top); raw hexes 2 F + 2 B = 160.
// Without the cut beyond the lower wall's end (the 4 strips only): the lower wall's foot stands on the whole face row
// y in [2, 3] and its finished mesh bulges below the plate there (wall_0002: Hausdorff 3.47 % against 0.43 %).
TEST(SkeletonRepair, DockedFootSplitBeyondAWallEndingInsideTheChain) {
    Skeleton s;
    const double r = 0.1;
    const auto at = [](int x, int y) { return 5 * x + y; };
    for (int x = 0; x <= 4; ++x)
        for (int y = 0; y <= 4; ++y) s.points.push_back({double(x), double(y), 0.0});
    for (int x = 0; x < 4; ++x)
        for (int y = 0; y < 4; ++y) s.faces.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)});
    for (int y = 1; y <= 3; ++y) s.points.push_back({2.0, double(y), 1.0});   // 25, 26, 27
    for (int y = 1; y <= 2; ++y) s.points.push_back({2.0, double(y), -1.0});  // 28, 29
    s.faces.push_back({at(2, 1), at(2, 2), 26, 25});
    s.faces.push_back({at(2, 2), at(2, 3), 27, 26});
    s.faces.push_back({at(2, 1), at(2, 2), 29, 28});
    s.radii.assign(s.points.size(), r);
    std::map<std::pair<int, int>, int> sides;
    for (const std::vector<int>& f : s.faces)
        for (int i = 0; i < 4; ++i) ++sides[std::minmax(f[i], f[(i + 1) % 4])];
    int border = 0;
    for (const auto& [e, count] : sides) {
        s.edges.push_back({e.first, e.second});
        border += count == 1;
    }
    ASSERT_EQ(s.points.size(), 30u);
    ASSERT_EQ(s.edges.size(), 48u);
    ASSERT_EQ(border, 23);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(s, {});
    EXPECT_EQ(res.docked_foot_splits, 5);
    EXPECT_EQ(res.skeleton.points.size(), 62u);
    EXPECT_EQ(res.skeleton.edges.size(), 107u);
    EXPECT_EQ(res.skeleton.faces.size(), 46u);
    int beyond = 0;  // the new strip's points: 5 plate edges, the upper wall's top edge, 2 face centres
    for (const Vec3& p : res.skeleton.points) beyond += std::abs(p.y - 2.2) < 1e-12;
    EXPECT_EQ(beyond, 8);
    const mesohex::PipelineResult pr = mesohex::run_pipeline(s);
    EXPECT_EQ(pr.docked_foot_splits, 5);
    EXPECT_EQ(pr.analysis.counts.boundary_edges, 34);
    EXPECT_EQ(pr.predicted.hexes, 160);
    expect_raw_as_predicted(pr, 160);
}

// A pair whose first edges are short against the room the other two leave (junction_split_clearance): c = origin,
// radius 0.2; the pair at +-30 degrees from +z in the xz plane, length L, radius 0.1; the other two at +-80 degrees
// from -z in the yz plane, length 1, radius 0.2 (angles across 98.7 degrees: unambiguous). Pair tubes separate at
// arc length 0.222 (L = 0.25) resp. 0.267 (L = 0.4), inside c's ball: no trunk, no stub.
Skeleton degree_four_short_pair(double len) {
    Skeleton s;
    const double a = 30 * kDeg, b = 80 * kDeg;
    s.points = {{0, 0, 0},
                {len * std::sin(a), 0, len * std::cos(a)},
                {-len * std::sin(a), 0, len * std::cos(a)},
                {0, std::sin(b), -std::cos(b)},
                {0, -std::sin(b), -std::cos(b)}};
    s.radii = {0.2, 0.1, 0.1, 0.2, 0.2};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
    return s;
}

// L = 0.25: h = 0.15, p1 = 0.25 cos 30 = 0.2165, p2 = cos 80 = 0.1736, m = (p1 + p2) / 2 - h = 0.0451, c' = (0, 0, a),
// a = p1 - m = 0.1714, radius 0.2 - 0.1 a / 0.25 = 0.1314. The pair's first vertices (+-0.125, 0, 0.2165) would lie
// hypot(0.125, 0.0451) = 0.1329 from c', less than 0.7 x (0.1314 + 0.1) = 0.1620: no split (with the clearance at 0,
// the split is made at exactly that c'). L = 0.4: a = 0.2364, radius 0.1409, the first vertices 0.2283 from c' >=
// 0.7 x 0.2409 = 0.1686: split.
TEST(SkeletonRepair, DegreeFourJunctionSplitKeepsFirstEdges) {
    const mesohex::SkeletonRepairResult kept = mesohex::repair_skeleton(degree_four_short_pair(0.25));
    EXPECT_EQ(kept.trunks + kept.absorbed_stubs + kept.side_stubs + kept.junction_splits, 0);
    EXPECT_EQ(kept.skeleton.points.size(), 5u);
    mesohex::SkeletonRepairOptions unchecked;
    unchecked.junction_split_clearance = 0;
    const mesohex::SkeletonRepairResult split = mesohex::repair_skeleton(degree_four_short_pair(0.25), unchecked);
    EXPECT_EQ(split.trunks + split.absorbed_stubs + split.side_stubs, 0);
    ASSERT_EQ(split.junction_splits, 1);
    ASSERT_EQ(split.skeleton.points.size(), 6u);
    const double p1 = 0.25 * std::cos(30 * kDeg), p2 = std::cos(80 * kDeg), a = p1 - (0.5 * (p1 + p2) - 0.15);
    EXPECT_NEAR(a, 0.1714, 1e-4);
    EXPECT_NEAR(distance(split.skeleton.points[5], Vec3{0, 0, a}), 0, 1e-12);
    EXPECT_NEAR(split.skeleton.radii[5], 0.2 - 0.1 * a / 0.25, 1e-12);
    const double first = distance(split.skeleton.points[5], split.skeleton.points[1]);
    EXPECT_NEAR(first, 0.1329, 1e-4);
    EXPECT_LT(first, 0.7 * (split.skeleton.radii[5] + 0.1));
    const mesohex::SkeletonRepairResult longer = mesohex::repair_skeleton(degree_four_short_pair(0.4));
    EXPECT_EQ(longer.trunks + longer.absorbed_stubs + longer.side_stubs, 0);
    ASSERT_EQ(longer.junction_splits, 1);
    EXPECT_NEAR(longer.skeleton.points[5].z, 0.2364, 1e-4);
    EXPECT_NEAR(distance(longer.skeleton.points[5], longer.skeleton.points[1]), 0.2283, 1e-4);
}

// Random seed 181: two degree-4 points whose split would put a pair's first vertex within the new junction's reach
// (input vertex 36: 0.26 from c' = 0.48 x the radii sum; vertex 15, turning by 60 degrees: 0.30 = 0.70 x, just below
// the clearance). Split, adaptation drops vertex 15's sample and the chord from c' passes 0.96 of its radius from it
// (0.44 unsplit); the finished mesh missed (min SJ 0.106, Hausdorff 1.61 %, docs/tuning.md). With the clearance
// neither point is split and the raw mesh is the unsplit one.
TEST(SkeletonRepair, RandomSeedSplitWouldCutFirstCorner) {
    const Skeleton in = mesohex::generate_random_skeleton(181);
    mesohex::PipelineOptions unsplit, unchecked;
    unsplit.repair.junction_split = 0;
    unchecked.repair.junction_split_clearance = 0;
    const mesohex::PipelineResult def = mesohex::run_pipeline(in);
    const mesohex::PipelineResult none = mesohex::run_pipeline(in, unsplit);
    const mesohex::PipelineResult cut = mesohex::run_pipeline(in, unchecked);
    EXPECT_EQ(def.junction_splits, 0);
    EXPECT_EQ(cut.junction_splits, 2);
    ASSERT_EQ(def.raw.mesh.hexes.size(), none.raw.mesh.hexes.size());
    EXPECT_EQ(def.raw.mesh.hexes, none.raw.mesh.hexes);
    EXPECT_EQ(def.raw.mesh.points, none.raw.mesh.points);
    // How far input vertex 15 lies off the adapted skeleton, in its radius.
    const auto off = [&](const Skeleton& s) {
        double best = 1e300;
        for (const auto& e : s.edges) {
            const Vec3 p = s.points[e[0]], d = s.points[e[1]] - p;
            const double t = std::clamp(dot(in.points[15] - p, d) / dot(d, d), 0.0, 1.0);
            best = std::min(best, distance(p + t * d, in.points[15]));
        }
        return best / in.radii[15];
    };
    EXPECT_NEAR(in.radii[15], 0.178, 5e-4);
    EXPECT_NEAR(off(def.skeleton), 0.44, 0.01);
    EXPECT_NEAR(off(cut.skeleton), 0.96, 0.01);
}

// Random seed 4 (issue 16's random set): a degree-4 branching point of radius 0.205 with a pair 63 degrees apart and
// first edges 2.7 radii long (no trunk: the pair's tubes separate inside the ball). Split, its raw mesh's worst hex
// (at that junction) rises from SJ 0.176 to 0.462 and the raw mesh gains 8 hexes (the bridge's chunk). The split's two
// degree-3 points are each other's neighbours (a bridge): by default (ConnectionSurfaceOptions::
// degree_three_chunks_at_bridges) each is chosen by its chunks, the bridge ending on the other's quad: the one the gap
// rule left with the general partition takes the orange (the other has it already), 0.462, the value the square model
// (degree_three_chunks_next_to_branching_points) gets too; with the gap rule at both (the option off) 0.462 as well
// (0.324 with the pattern search's degree-3 orange, before SpherePartitionOptions::exact_three_orange).
TEST(SkeletonRepair, RandomSeedWithDegreeFourJunction) {
    const Skeleton in = mesohex::generate_random_skeleton(4);
    mesohex::PipelineOptions unsplit, gap_rule;
    unsplit.repair.junction_split = 0;
    // The degree-4 point as the paper partitions it (an orange); its close pair's crotch-free partition
    // (no_flat_point_in_close_pair, on by default) already raises the unsplit raw mesh to 0.200.
    mesohex::PipelineOptions unsplit_crotch_free = unsplit;
    unsplit.connection_surfaces.no_flat_point_in_close_pair = false;
    EXPECT_NEAR(mesohex::compute_quality(mesohex::run_pipeline(in, unsplit_crotch_free).raw.mesh).sj_min, 0.200, 0.005);
    gap_rule.connection_surfaces.degree_three_chunks_at_bridges = false;
    const mesohex::PipelineResult before = mesohex::run_pipeline(in, unsplit);
    const mesohex::PipelineResult after = mesohex::run_pipeline(in);
    EXPECT_NEAR(mesohex::compute_quality(mesohex::run_pipeline(in, gap_rule).raw.mesh).sj_min, 0.462, 0.005);
    EXPECT_EQ(before.junction_splits, 0);
    EXPECT_EQ(after.junction_splits, 1);
    EXPECT_EQ(after.trunks + after.absorbed_stubs + after.side_stubs, 0);
    EXPECT_EQ(after.analysis.counts.branching_points, before.analysis.counts.branching_points + 1);
    EXPECT_EQ(after.raw.mesh.hexes.size(), before.raw.mesh.hexes.size() + 8);
    const mesohex::QualityReport qb = mesohex::compute_quality(before.raw.mesh);
    const mesohex::QualityReport qa = mesohex::compute_quality(after.raw.mesh);
    EXPECT_TRUE(qa.validation.valid());
    EXPECT_EQ(qa.inverted, 0);
    EXPECT_NEAR(qb.sj_min, 0.176, 0.005);
    EXPECT_NEAR(qa.sj_min, 0.462, 0.005);
}

// A stub of length 0.3 at 20 degrees from a long branch (radius 0.1: the tubes separate only at 0.576): absorbed
// into t = midpoint of its end (0.1026, 0, 0.2819) and (0, 0, 0.3), radius 0.1042 / 4 + 0.1 = 0.1261
// (absorbed_ball_width 0.25). c becomes a
// joint: the skeleton is one branch, no junction.
TEST(SkeletonRepair, StubAbsorbed) {
    Skeleton in;
    const double r = 0.1;
    in.points = {{0, 0, -1}, {0, 0, 0}, {0, 0, 2}, {0.3 * std::sin(20 * kDeg), 0, 0.3 * std::cos(20 * kDeg)}};
    in.radii = {r, r, r, r};
    in.edges = {{0, 1}, {1, 2}, {1, 3}};
    // The stub's end lies 0.3 sin 20 = 0.1026 = 1.03 r off the sibling: by default (side_stub_reach 0.7) a side branch
    // (test StubKeptAsSideBranch); absorption is under test here.
    mesohex::PipelineOptions absorb;
    absorb.repair.side_stub_reach = 0;
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, absorb.repair);
    EXPECT_EQ(res.trunks, 0);
    EXPECT_EQ(res.absorbed_stubs, 1);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 4u);  // parent end, c, long end, t (the stub's end is gone)
    ASSERT_EQ(s.edges.size(), 3u);
    EXPECT_EQ(res.vertex_map[3], -1);
    const Vec3 e = in.points[3], p{0, 0, 0.3};
    const Vec3 t = s.points[3];
    EXPECT_NEAR(distance(t, 0.5 * (e + p)), 0, 1e-9);
    EXPECT_NEAR(s.radii[3], 0.25 * distance(e, p) + r, 1e-9);
    EXPECT_NEAR(s.radii[3], 0.1261, 1e-4);
    EXPECT_EQ(res.absorbed_balls, std::vector<int>{3});
    for (int v = 0; v < 4; ++v) EXPECT_LE(degree(s, v), 2);
    // The pipeline pins t (pin_absorbed_balls): the meshed skeleton, one resampled branch from (0, 0, -1) to (0, 0,
    // 2), keeps t as a joint with its radius 0.1261; without the pin no joint is t (the samples lie at dyadic
    // fractions of the branch's arc length, about 3.0; t at arc 1.2955).
    const auto has_t = [&](const Skeleton& m) {
        for (std::size_t v = 0; v < m.points.size(); ++v)
            if (distance(m.points[v], t) < 1e-12 && std::abs(m.radii[v] - s.radii[3]) < 1e-12) return true;
        return false;
    };
    EXPECT_TRUE(has_t(mesohex::prepare_skeleton(in, absorb).skeleton));
    mesohex::PipelineOptions unpinned = absorb;
    unpinned.repair.pin_absorbed_balls = false;
    EXPECT_FALSE(has_t(mesohex::prepare_skeleton(in, unpinned).skeleton));
    EXPECT_FALSE(
        mesohex::repair_skeleton(in, {.trunks = true, .trunk_clearance = 0.7, .absorb_stubs = false}).absorbed_stubs);
}

// A stub whose end lies far off its sibling is kept as a side branch of it. c = (0, 0, 0), parent (0, 0, -1), the
// sibling straight up to (0, 0, 2), the stub 0.3 long at 35 degrees towards +x, radius 0.1: at arc s the points are
// 2 s sin 17.5 = 0.6014 s apart, below 0.2 up to s = 0.3326 > 0.3 (no separation: a stub). Its end e = (0.3 sin 35, 0,
// 0.3 cos 35) = (0.17207, 0, 0.24575) lies 0.17207 = 1.72 r from the sibling's nearest point q = (0, 0, 0.24575)
// (arc 0.246 > r_c = 0.1, before the sibling's end). side_stub_reach 1.5: q becomes a branching point of degree 3
// with the edge (q, e) at a right angle to the sibling; c a joint. side_stub_reach 2 (1.72 < 2): absorbed as before.
TEST(SkeletonRepair, StubKeptAsSideBranch) {
    Skeleton in;
    const double r = 0.1, sin35 = std::sin(35 * kDeg), cos35 = std::cos(35 * kDeg);
    in.points = {{0, 0, -1}, {0, 0, 0}, {0, 0, 2}, {0.3 * sin35, 0, 0.3 * cos35}};
    in.radii = {r, r, r, r};
    in.edges = {{0, 1}, {1, 2}, {1, 3}};
    mesohex::SkeletonRepairOptions o;
    o.side_stub_reach = 1.5;
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(res.side_stubs, 1);
    EXPECT_EQ(res.absorbed_stubs + res.trunks, 0);
    EXPECT_TRUE(res.absorbed_balls.empty());
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 5u);  // the 4 input vertices, then q
    const std::vector<std::array<int, 2>> edges{{0, 1}, {1, 4}, {4, 2}, {4, 3}};
    EXPECT_EQ(s.edges, edges);
    EXPECT_NEAR(distance(s.points[4], Vec3{0, 0, 0.3 * cos35}), 0, 1e-12);
    EXPECT_NEAR(s.radii[4], r, 1e-12);
    EXPECT_NEAR(distance(s.points[3], in.points[3]), 0, 1e-12);  // e stays
    EXPECT_NEAR(dot(s.points[3] - s.points[4], Vec3{0, 0, 1}), 0, 1e-12);
    EXPECT_NEAR(distance(s.points[3], s.points[4]), 0.17207, 1e-5);
    EXPECT_EQ(degree(s, 1), 2);
    EXPECT_EQ(degree(s, 4), 3);
    for (int v = 0; v < 4; ++v) EXPECT_EQ(res.vertex_map[v], v);
    o.side_stub_reach = 2;
    const mesohex::SkeletonRepairResult absorbed = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(absorbed.side_stubs, 0);
    EXPECT_EQ(absorbed.absorbed_stubs, 1);
}

// A fat stub kept as the main line (fat_stub_main_line). c = 0 of degree 3: parent (0, 0, -1), a thin sibling up to
// (0, 0, 2) (radius 0.2 at c to 0.1 there: 0.2 - 0.05 s at arc s), a stub 0.8 long 20 degrees off it towards +x,
// radius 0.2 throughout. At s = 0.8 the axes are 2 x 0.8 x sin 10 = 0.2778 apart, less than 0.2 + 0.16: the tubes do
// not separate before the stub ends, and e lies 0.8 sin 20 = 0.2736 off the sibling, more than 0.7 x r_q (q at arc 0.8
// cos 20 = 0.7518, r_q 0.1624): a side stub, and r_e 0.2 > r_q. The sibling's axis, sampled at l_k = 2 k / 128, lies
// l sin 20 off the stub's; the first at the stub's radius 0.2 is k = 38 (37.42), l = 0.59375: x = (0, 0, 0.59375),
// radius 0.2 - 0.05 l = 0.1703125; t is the stub's point nearest it, at arc l cos 20 = 0.55794 (beyond c's ball, 0.242
// before e >= 1 x 0.2), radius 0.2. Edges: (parent, c), (c, t), (t, e), (t, x), (x, sibling end). A stub thinner than
// the sibling at q (r_e 0.15) or the option off: the side stub.
TEST(SkeletonRepair, FatStubKeptAsTheMainLine) {
    Skeleton in;
    const double sin20 = std::sin(20 * kDeg), cos20 = std::cos(20 * kDeg);
    in.points = {{0, 0, -1}, {0, 0, 0}, {0, 0, 2}, {0.8 * sin20, 0, 0.8 * cos20}};
    in.radii = {0.2, 0.2, 0.1, 0.2};
    in.edges = {{0, 1}, {1, 2}, {1, 3}};
    mesohex::SkeletonRepairOptions o;
    o.fat_stub_main_line = true;
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(res.main_stubs, 1);
    EXPECT_EQ(res.side_stubs + res.absorbed_stubs + res.trunks + res.junction_splits, 0);
    const std::vector<int> joints{1};
    EXPECT_EQ(res.trunk_joints, joints);  // c pinned as a joint
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 6u);  // the 4 input vertices, then t and x
    const double at = 0.59375 * cos20;
    EXPECT_NEAR(distance(s.points[4], Vec3{at * sin20, 0, at * cos20}), 0, 1e-12);
    EXPECT_NEAR(s.radii[4], 0.2, 1e-12);
    EXPECT_NEAR(distance(s.points[5], Vec3{0, 0, 0.59375}), 0, 1e-12);
    EXPECT_NEAR(s.radii[5], 0.1703125, 1e-12);
    std::vector<std::array<int, 2>> edges;
    for (const auto& e : s.edges) edges.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
    std::sort(edges.begin(), edges.end());
    const std::vector<std::array<int, 2>> expected{{0, 1}, {1, 4}, {2, 5}, {3, 4}, {4, 5}};
    EXPECT_EQ(edges, expected);
    EXPECT_NEAR(distance(s.points[3], in.points[3]), 0, 1e-12);  // e stays
    Skeleton thin = in;
    thin.radii[3] = 0.15;
    const mesohex::SkeletonRepairResult side = mesohex::repair_skeleton(thin, o);
    EXPECT_EQ(side.main_stubs, 0);
    EXPECT_EQ(side.side_stubs, 1);
    o.fat_stub_main_line = false;
    const mesohex::SkeletonRepairResult off = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(off.main_stubs, 0);
    EXPECT_EQ(off.side_stubs, 1);
}

// fat_stub_main_line on two random seeds (docs/junctions.md, "Fat stubs kept as the main line"). Seed 144: the stub
// of v2 (end radius 0.185, the sibling 0.132 at its point nearest the end) becomes the main line, v2 a pinned joint.
// Seed 422: the thin walk from t would turn back along the stub (a close pair at t whose tubes do not part before the
// stub ends, absorbed by a second round without parted_at_root): the side stub stays, the repaired skeleton is the
// one the option off gives.
TEST(SkeletonRepair, FatStubMainLineOnRandomSeeds) {
    mesohex::SkeletonRepairOptions on, off;
    on.fat_stub_main_line = true;
    off.fat_stub_main_line = false;
    const Skeleton s144 = mesohex::generate_random_skeleton(144);
    const mesohex::SkeletonRepairResult a = mesohex::repair_skeleton(s144, on);
    EXPECT_EQ(a.main_stubs, 1);
    EXPECT_EQ(a.side_stubs + a.absorbed_stubs + a.trunks, 0);
    const std::vector<int> joints{2};
    EXPECT_EQ(a.trunk_joints, joints);
    EXPECT_EQ(mesohex::repair_skeleton(s144, off).side_stubs, 1);
    const Skeleton s422 = mesohex::generate_random_skeleton(422);
    const mesohex::SkeletonRepairResult b = mesohex::repair_skeleton(s422, on), c = mesohex::repair_skeleton(s422, off);
    EXPECT_EQ(b.main_stubs, 0);
    EXPECT_EQ(b.side_stubs, 1);
    EXPECT_EQ(b.skeleton.points, c.skeleton.points);
    EXPECT_EQ(b.skeleton.edges, c.skeleton.edges);
}

// A side stub rooted where its axis leaves the sibling's tube (side_stub_root_exit). The configuration of
// StubKeptAsSideBranch (c = 0, parent (0, 0, -1), sibling up to (0, 0, 2), the stub 0.3 long at 35 degrees towards
// +x, every radius 0.1) with a fourth branch along -x (90 degrees from the sibling and the parent: no other close
// pair), so that c stays a branching point without the stub. The stub's axis at arc t lies t sin 35 off the
// sibling's; sampled at t_k = 0.3 k / 128, the first reaching exit x 0.1 is k = ceil(exit x 0.1 x 128 / (0.3 sin
// 35)): exit 1 gives k = 75 (74.38), q = (0, 0, 0.3 x 75 / 128 x cos 35) = (0, 0, 0.14399), beyond c's ball (0.1)
// and the bridge clearance 0.7 x (0.1 + 0.1) = 0.14; the edge (q, e) is 0.19991 long (e stays) and leaves the sibling
// 59.4 degrees from +z instead of 90. exit 0.9 gives k = 67 (66.95), arc 0.3 x 67 / 128 x cos 35 = 0.12863 < 0.14,
// so q moves out to the clearance (bisection, 1e-9). q stays at the point nearest e, (0, 0, 0.24575), with exit 0,
// with the stub's end thinner than the sibling (r_e 0.09 < r_q 0.1; 0.172 off it, still a side stub at reach 1.5),
// and without the fourth branch (c becomes a joint).
TEST(SkeletonRepair, SideStubRootedWhereTheStubLeaves) {
    Skeleton in;
    const double r = 0.1, sin35 = std::sin(35 * kDeg), cos35 = std::cos(35 * kDeg);
    in.points = {{0, 0, -1}, {0, 0, 0}, {0, 0, 2}, {0.3 * sin35, 0, 0.3 * cos35}, {-1, 0, 0}};
    in.radii = {r, r, r, r, r};
    in.edges = {{0, 1}, {1, 2}, {1, 3}, {1, 4}};
    mesohex::SkeletonRepairOptions o;
    o.side_stub_reach = 1.5;
    const auto root = [&](const Skeleton& sk, double exit) {
        o.side_stub_root_exit = exit;
        const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(sk, o);
        EXPECT_EQ(res.side_stubs, 1);
        EXPECT_EQ(res.absorbed_stubs + res.trunks + res.junction_splits, 0);
        const Skeleton& s = res.skeleton;
        EXPECT_EQ(s.points.size(), sk.points.size() + 1);  // q appended
        const int q = static_cast<int>(s.points.size()) - 1;
        EXPECT_EQ(degree(s, q), 3);
        EXPECT_NEAR(distance(s.points[3], sk.points[3]), 0, 1e-12);  // e stays
        EXPECT_NEAR(s.radii[q], r, 1e-12);
        EXPECT_NEAR(s.points[q].x, 0, 1e-12);
        EXPECT_NEAR(s.points[q].y, 0, 1e-12);
        return s.points[q].z;
    };
    const double z1 = 0.3 * 75 / 128 * cos35;
    EXPECT_NEAR(z1, 0.14399, 1e-5);
    EXPECT_NEAR(root(in, 1.0), z1, 1e-12);
    EXPECT_NEAR(distance(Vec3{0, 0, z1}, in.points[3]), 0.19991, 1e-5);
    EXPECT_NEAR(0.3 * 67 / 128 * cos35, 0.12863, 1e-5);
    EXPECT_NEAR(root(in, 0.9), 0.7 * (1 + 1e-6) * (r + r), 1e-9);  // trunk_clearance, strictly above
    EXPECT_NEAR(root(in, 0.0), 0.3 * cos35, 1e-12);
    Skeleton thin = in;
    thin.radii[3] = 0.09;
    EXPECT_NEAR(root(thin, 1.0), 0.3 * cos35, 1e-12);
    Skeleton three = in;  // without the fourth branch c becomes a joint
    three.points.pop_back();
    three.radii.pop_back();
    three.edges.pop_back();
    EXPECT_NEAR(root(three, 1.0), 0.3 * cos35, 1e-12);
}

// A side stub whose end lies inside its root's ball is lengthened. The sibling straight up from c = (0, 0, 0) (parent
// (0, 0, -1)), the stub 0.3 long at theta = asin(0.85 / 3) = 16.46 degrees towards +x, radius 0.1 everywhere: at arc s
// the branches are 2 s sin(theta / 2) = 0.2863 s apart, below 0.2 up to s = 0.70 > 0.3 (a stub); its end e = (0.085, 0,
// 0.3 cos theta) lies 0.85 r off the sibling (>= side_stub_reach 0.7: a side branch from q = (0, 0, 0.2877)). The edge
// (q, e), 0.085 long, is shorter than side_stub_min_length x max(r_q, r_e) = 0.1: e moves outwards to (0.1, 0, 0.2877),
// radius kept. With side_stub_min_length 0, e stays.
TEST(SkeletonRepair, ShortSideStubLengthened) {
    Skeleton in;
    const double r = 0.1, sin_t = 0.85 / 3, cos_t = std::sqrt(1 - sin_t * sin_t);
    in.points = {{0, 0, -1}, {0, 0, 0}, {0, 0, 2}, {0.3 * sin_t, 0, 0.3 * cos_t}};
    in.radii = {r, r, r, r};
    in.edges = {{0, 1}, {1, 2}, {1, 3}};
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in);
    EXPECT_EQ(res.side_stubs, 1);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 5u);  // the 4 input vertices, then q
    EXPECT_NEAR(distance(s.points[4], Vec3{0, 0, 0.3 * cos_t}), 0, 1e-12);
    EXPECT_NEAR(distance(s.points[3], Vec3{0.1, 0, 0.3 * cos_t}), 0, 1e-12);
    EXPECT_EQ(s.radii[3], r);
    mesohex::SkeletonRepairOptions kept;
    kept.side_stub_min_length = 0;
    const mesohex::SkeletonRepairResult res0 = mesohex::repair_skeleton(in, kept);
    ASSERT_EQ(res0.skeleton.points.size(), 5u);
    EXPECT_NEAR(distance(res0.skeleton.points[3], in.points[3]), 0, 1e-12);
}

// Held-out seed 251: the stub v3 -> v6 (0.55 long, 34 degrees from its sibling v3 -> v4) ends 0.208 = 0.86 r_q off the
// sibling, inside q's ball (r_q 0.243, r_e 0.164). Kept at that length, the side edge has overlapping cross-sections
// (no joint for the section criterion to remove) and 2 raw hexes invert next to it (min SJ -0.133); lengthened to
// r_q, none (min SJ 0.152). Measured without the plane orange at degree 3 (ConnectionSurfaceOptions::
// plane_orange_at_degree_three), which removes the inversion by itself: with it, 0.233 short and 0.363 lengthened; and
// with the pattern search's degree-3 orange (exact_three_orange off): the solver's orange removes it too (0.009 short,
// 0.233 lengthened).
TEST(SkeletonRepair, RandomSeedSideStubInsideRootBall) {
    const Skeleton in = mesohex::generate_random_skeleton(251);
    mesohex::PipelineOptions paper_partition;
    paper_partition.connection_surfaces.plane_orange_at_degree_three = false;
    paper_partition.connection_surfaces.degree_three_partition_by_chunks = false;
    paper_partition.connection_surfaces.exact_three_orange = false;
    mesohex::PipelineOptions kept = paper_partition;
    kept.repair.side_stub_min_length = 0;
    const mesohex::PipelineResult def = mesohex::run_pipeline(in, paper_partition),
                                  short_side = mesohex::run_pipeline(in, kept);
    EXPECT_EQ(def.side_stubs, 1);
    EXPECT_EQ(short_side.side_stubs, 1);
    const mesohex::QualityReport q = mesohex::compute_quality(def.raw.mesh);
    const mesohex::QualityReport q0 = mesohex::compute_quality(short_side.raw.mesh);
    EXPECT_EQ(q0.inverted, 2);
    EXPECT_NEAR(q0.sj_min, -0.133, 1e-3);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_NEAR(q.sj_min, 0.152, 1e-3);
    mesohex::PipelineOptions kept_plane;
    kept_plane.repair.side_stub_min_length = 0;
    const mesohex::QualityReport qp = mesohex::compute_quality(mesohex::run_pipeline(in).raw.mesh);
    const mesohex::QualityReport qp0 = mesohex::compute_quality(mesohex::run_pipeline(in, kept_plane).raw.mesh);
    EXPECT_EQ(qp0.inverted, 0);
    EXPECT_NEAR(qp0.sj_min, 0.233, 1e-3);
    EXPECT_NEAR(qp.sj_min, 0.363, 1e-3);
}

// A stub whose sibling turns inside the absorbed stretch. c = (0, 0, 0), parent (0, 0, -1); the sibling goes up to its
// joint j = (0, 0, 0.4), then turns by 30 degrees towards +x (to j + 1.6 (sin 30, 0, cos 30)); the stub, 0.6 long,
// leaves c at 20 degrees towards +x. Radius 0.1: at arc 0.6 the points are (0.2052, 0, 0.5638) and (0.1, 0, 0.5732),
// 0.1056 apart (< 0.2): no separation, a stub. t is their midpoint (0.1526, 0, 0.5685), radius 0.1056 / 4 + 0.1. The
// sibling's joint stays, moved to the midpoint of j and the stub's point at arc 0.4, (0.1368, 0, 0.3759): (0.0684, 0,
// 0.3879), radius 0.1389 / 4 + 0.1 = 0.1347. Edges: parent-c, c-j, j-t, t-end (the chord c-t would leave j 0.11 = 1.1
// radii off the skeleton; without keep_sibling_joints, the default, j goes).
TEST(SkeletonRepair, StubAbsorbedKeepsSiblingJoint) {
    Skeleton in;
    const double r = 0.1, s20 = std::sin(20 * kDeg), c20 = std::cos(20 * kDeg);
    const Vec3 j{0, 0, 0.4}, turn{0.5, 0, std::sqrt(0.75)};
    in.points = {{0, 0, -1}, {0, 0, 0}, j, j + 1.6 * turn, {0.6 * s20, 0, 0.6 * c20}};
    in.radii.assign(5, r);
    in.edges = {{0, 1}, {1, 2}, {2, 3}, {1, 4}};
    mesohex::SkeletonRepairOptions keep;
    keep.keep_sibling_joints = true;
    keep.side_stub_reach = 0;  // the end lies 0.96 r off the sibling: a side branch by default
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, keep);
    EXPECT_EQ(res.absorbed_stubs, 1);
    EXPECT_EQ(res.trunks + res.merged_ends, 0);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 5u);  // 0, 1, j, end kept; the stub's end (4) gone; t appended (4)
    EXPECT_EQ(res.vertex_map[4], -1);
    const Vec3 stub_at_04{0.4 * s20, 0, 0.4 * c20}, stub_end = in.points[4], sib_at_06 = j + 0.2 * turn;
    EXPECT_NEAR(distance(s.points[2], 0.5 * (j + stub_at_04)), 0, 1e-12);
    EXPECT_NEAR(s.points[2].x, 0.0684, 1e-4);
    EXPECT_NEAR(s.radii[2], 0.25 * distance(j, stub_at_04) + r, 1e-12);
    EXPECT_NEAR(s.radii[2], 0.1347, 1e-4);
    EXPECT_NEAR(distance(s.points[4], 0.5 * (stub_end + sib_at_06)), 0, 1e-12);
    EXPECT_NEAR(s.radii[4], 0.25 * distance(stub_end, sib_at_06) + r, 1e-12);
    const std::vector<std::array<int, 2>> edges{{0, 1}, {1, 2}, {2, 4}, {4, 3}};
    EXPECT_EQ(s.edges, edges);
    // Without (the default): j goes, t joins c and the sibling's end directly.
    mesohex::SkeletonRepairOptions absorb_only;
    absorb_only.side_stub_reach = 0;
    const mesohex::SkeletonRepairResult old = mesohex::repair_skeleton(in, absorb_only);
    ASSERT_EQ(old.skeleton.points.size(), 4u);
    EXPECT_EQ(old.vertex_map[2], -1);
    const std::vector<std::array<int, 2>> old_edges{{0, 1}, {1, 3}, {3, 2}};
    EXPECT_EQ(old.skeleton.edges, old_edges);
}

// A close pair whose shorter branch ends at a branching point b inside the other's tube: the long branch goes up the
// z axis from c = (0, 0, 0) to (0, 0, 2); the short one leaves at 20 degrees towards +x, 0.3 long, to b = (0.1026, 0,
// 0.2819), where two children leave sideways (to b + (1, 0, -0.2) and b + (0, 1, -0.2)). Radius 0.1: b and the long
// branch's point at 0.3 are 0.1042 apart: merged into t = their midpoint, radius 0.1042 / 4 + 0.1 = 0.1261; the
// children leave t, c is a joint, t has degree 4 (c, the long branch's end, the two children).
TEST(SkeletonRepair, BranchingEndMerged) {
    Skeleton in;
    const double r = 0.1;
    const Vec3 b{0.3 * std::sin(20 * kDeg), 0, 0.3 * std::cos(20 * kDeg)};
    in.points = {{0, 0, -1}, {0, 0, 0}, {0, 0, 2}, b, b + Vec3{1, 0, -0.2}, b + Vec3{0, 1, -0.2}};
    in.radii.assign(6, r);
    in.edges = {{0, 1}, {1, 2}, {1, 3}, {3, 4}, {3, 5}};
    mesohex::SkeletonRepairOptions on;  // off by default (it cascades on dense trees)
    on.merge_branching_ends = true;
    on.junction_split = 0;  // t gets degree 4 (a merge is tested here, not the split after it)
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, on);
    EXPECT_EQ(res.merged_ends, 1);
    EXPECT_EQ(res.trunks + res.absorbed_stubs + res.unseparated, 0);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 6u);  // b (3) gone, t appended (5)
    EXPECT_EQ(res.vertex_map[3], -1);
    EXPECT_EQ(res.vertex_map[4], 3);
    const Vec3 p{0, 0, 0.3};
    EXPECT_NEAR(distance(s.points[5], 0.5 * (b + p)), 0, 1e-12);
    EXPECT_NEAR(s.radii[5], 0.25 * distance(b, p) + r, 1e-12);
    EXPECT_NEAR(s.radii[5], 0.1261, 1e-4);
    const std::vector<std::array<int, 2>> edges{{0, 1}, {5, 3}, {5, 4}, {1, 5}, {5, 2}};
    EXPECT_EQ(s.edges, edges);
    EXPECT_EQ(degree(s, 1), 2);
    EXPECT_EQ(degree(s, 5), 4);
    // Disabled: the pair stays, counted as unseparated.
    mesohex::SkeletonRepairOptions off;
    off.merge_branching_ends = false;
    const mesohex::SkeletonRepairResult kept = mesohex::repair_skeleton(in, off);
    EXPECT_EQ(kept.merged_ends, 0);
    EXPECT_EQ(kept.unseparated, 1);
    EXPECT_EQ(kept.skeleton, in);
}

// Merges do not chain. The long branch goes up the z axis from c = (0, 0, 0) to (0, 0, 3) (and down to (0, 0, -1));
// the short one leaves at 20 degrees towards +x, 0.3 long, to b1, as in BranchingEndMerged: merged into t1 = the
// midpoint of b1 and (0, 0, 0.3) = (0.0513, 0, 0.2910), radius 0.1261. One of b1's children goes on up, 0.3 from t1 at
// 20 degrees towards -x, to a second branching point b2 (two children sideways). At t1 the pair (the long branch's
// rest, the branch to b2) is the same situation again (shown by the control, where t1 is an input vertex: merged),
// but t1 was made by a merge and takes part in no further merge: 1 merge and 1 unseparated pair, not 2 merges.
TEST(SkeletonRepair, MergedBallNotMergedAgain) {
    const double r = 0.1;
    const Vec3 b1{0.3 * std::sin(20 * kDeg), 0, 0.3 * std::cos(20 * kDeg)};
    const Vec3 t1 = 0.5 * (b1 + Vec3{0, 0, 0.3});
    const Vec3 b2 = t1 + Vec3{-0.3 * std::sin(20 * kDeg), 0, 0.3 * std::cos(20 * kDeg)};
    Skeleton in;
    in.points = {{0, 0, -1},
                 {0, 0, 0},
                 {0, 0, 3},
                 b1,
                 b1 + Vec3{1, 0, -0.2},
                 b2,
                 b2 + Vec3{-1, 0, -0.2},
                 b2 + Vec3{0, -1, -0.2}};
    in.radii.assign(in.points.size(), r);
    in.edges = {{0, 1}, {1, 2}, {1, 3}, {3, 4}, {3, 5}, {5, 6}, {5, 7}};
    mesohex::SkeletonRepairOptions o;
    o.merge_branching_ends = true;
    o.junction_split = 0;  // the merges are tested here, not the split after them
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, o);
    EXPECT_EQ(res.merged_ends, 1);
    EXPECT_EQ(res.unseparated, 1);
    EXPECT_EQ(res.trunks + res.absorbed_stubs + res.side_stubs, 0);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 8u);  // b1 (3) gone, t1 appended (7)
    EXPECT_EQ(res.vertex_map[3], -1);
    EXPECT_EQ(res.vertex_map[5], 4);  // b2 stays
    EXPECT_NEAR(distance(s.points[7], t1), 0, 1e-12);
    EXPECT_NEAR(s.radii[7], 0.1261, 1e-4);
    EXPECT_EQ(degree(s, 7), 4);  // c, the long branch's end, b1's two children
    EXPECT_EQ(degree(s, 4), 3);  // b2 as it was
    // Control: t1 (radius 0.1261) as an input branching point with the same branches; the pair at it is merged.
    Skeleton ctrl;
    ctrl.points = in.points;
    ctrl.points[3] = t1;  // b1's place, its children kept
    ctrl.radii.assign(ctrl.points.size(), r);
    ctrl.radii[3] = s.radii[7];
    ctrl.edges = {{0, 1}, {1, 3}, {3, 2}, {3, 4}, {3, 5}, {5, 6}, {5, 7}};
    const mesohex::SkeletonRepairResult again = mesohex::repair_skeleton(ctrl, o);
    EXPECT_EQ(again.merged_ends, 1);
    EXPECT_EQ(again.vertex_map[5], -1);  // b2 merged
}

// Merged ends on real inputs (docs/junctions.md, "Merged ends"). Seed 62: the trunk's t is merged (its tubes do not
// separate from c's third branch). Seeds 106 and 107: the shorter walk of the close pair ends at a side stub's root q,
// which is not merged (q only carries the side stub; merging it re-rooted the stub at t, where it was absorbed after
// all). The determinism test's random tree, whose tubes overlap along whole branches: without the guard against
// chained merges 782 merges took the 1 500-vertex tree down to 65 vertices; with it 28 merges.
TEST(SkeletonRepair, MergedEndsOnRandomInputs) {
    mesohex::SkeletonRepairOptions o;
    o.merge_branching_ends = true;
    const auto seed_run = [&](int seed) {
        return mesohex::repair_skeleton(mesohex::generate_random_skeleton(static_cast<std::uint64_t>(seed)), o);
    };
    const mesohex::SkeletonRepairResult s62 = seed_run(62);
    EXPECT_EQ(s62.trunks, 1);
    EXPECT_EQ(s62.merged_ends, 1);
    EXPECT_EQ(s62.unseparated, 0);
    for (const int seed : {106, 107}) {
        const mesohex::SkeletonRepairResult r = seed_run(seed);
        EXPECT_EQ(r.side_stubs, 1) << seed;
        EXPECT_EQ(r.merged_ends, 0) << seed;
        EXPECT_EQ(r.absorbed_stubs, 0) << seed;
        EXPECT_EQ(r.unseparated, 1) << seed;
    }
    const auto branching = [](const Skeleton& s) {
        int n = 0;
        for (int v = 0; v < static_cast<int>(s.points.size()); ++v) n += degree(s, v) >= 3 ? 1 : 0;
        return n;
    };
    const Skeleton tree = mesohex::bench::random_tree(1500, 7);
    ASSERT_EQ(branching(tree), 237);
    const mesohex::SkeletonRepairResult on = mesohex::repair_skeleton(tree, o);
    EXPECT_EQ(on.merged_ends, 28);
    EXPECT_EQ(on.skeleton.points.size(), 1517u);
    EXPECT_EQ(branching(on.skeleton), 226);
    o.merge_branching_ends = false;  // for comparison: 1 538 vertices, 249 branching points
    const mesohex::SkeletonRepairResult off = mesohex::repair_skeleton(tree, o);
    EXPECT_EQ(off.skeleton.points.size(), 1538u);
    EXPECT_EQ(branching(off.skeleton), 249);
}

// Leaflet vertices are never branching points of the repair; faces and their edges stay as they are.
TEST(SkeletonRepair, LeafletsUntouched) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.1, -0.3, 0.0}, {-0.1, -0.3, 0.05}};
    s.radii.assign(6, 0.1);
    s.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 4}, {0, 5}};
    s.faces = {{0, 1, 2, 3}};
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(s);
    EXPECT_EQ(res.trunks + res.absorbed_stubs, 0);
    EXPECT_EQ(res.skeleton.edges, s.edges);
}

// Seeds of the random set (bench/random_set.sh) whose raw mesh the repair fixes (raw min SJ before -> after, measured):
// seed 72, a stub 14 degrees from its sibling (radius 0.155, length 0.56), -0.133 (one inverted hex) -> 0.619; seed 37,
// a stub 24 degrees from its sibling, 0.035 -> 0.630; seed 17, a short fat branch beside a long one, 0.060 -> 0.512;
// seed 12, two stubs, 0.009 -> 0.288. Finished in their domains they went from missing the targets to 0.618 / 0.918 /
// 1.17 % (37), 0.688 / 0.929 / 0.85 % (17), 0.619 / 0.929 / 0.70 % (12, 1 inverted hex before) (docs/tuning.md).
// Absorbed (side_stub_reach 0), with the pinned balls and absorbed_ball_width 0.25, the raw min SJ is 0.565 (72), 0.654
// (37), 0.551 (17), 0.305 (12). By default (side_stub_reach 0.7) the stubs whose end lies 0.7 r or more off the sibling
// are side branches: 37, 17 and one of 12's two (raw min SJ 0.466, 0.566, 0.179; finished, 37 meets every target only
// this way, docs/tuning.md); 72's end lies nearer and its stub is absorbed.
TEST(SkeletonRepair, RandomSeedsWithStubs) {
    struct Case {
        int seed, stubs, side;  // stubs: all; side: kept as side branches by default (the others absorbed)
        double bound, absorbed_bound;
        int joints_now;  // absorbed: branching points of degree 3 that lost their stub and became joints
    };
    for (const Case& c : std::vector<Case>{{72, 1, 0, 0.55, 0.55, 1},
                                           {37, 1, 1, 0.45, 0.55, 1},
                                           {17, 1, 1, 0.5, 0.45, 1},
                                           {12, 2, 1, 0.15, 0.25, 1}}) {
        const Skeleton in = mesohex::generate_random_skeleton(static_cast<std::uint64_t>(c.seed));
        mesohex::PipelineOptions without;
        without.repair.trunks = false;
        without.repair.absorb_stubs = false;
        without.repair.junction_split = 0;
        mesohex::PipelineOptions absorb;
        absorb.repair.side_stub_reach = 0;
        const mesohex::PipelineResult before = mesohex::run_pipeline(in, without);
        const mesohex::PipelineResult after = mesohex::run_pipeline(in);
        const mesohex::PipelineResult absorbed = mesohex::run_pipeline(in, absorb);
        const mesohex::QualityReport qb = mesohex::compute_quality(before.raw.mesh);
        const mesohex::QualityReport qa = mesohex::compute_quality(after.raw.mesh);
        const mesohex::QualityReport qab = mesohex::compute_quality(absorbed.raw.mesh);
        EXPECT_LT(qb.sj_min, 0.1) << c.seed;
        EXPECT_EQ(after.side_stubs, c.side) << c.seed;
        EXPECT_EQ(after.absorbed_stubs, c.stubs - c.side) << c.seed;
        EXPECT_EQ(after.trunks, 0) << c.seed;
        EXPECT_EQ(qa.inverted, 0) << c.seed;
        EXPECT_GT(qa.sj_min, c.bound) << c.seed;
        EXPECT_EQ(absorbed.absorbed_stubs, c.stubs) << c.seed;
        EXPECT_EQ(absorbed.side_stubs + absorbed.trunks, 0) << c.seed;
        EXPECT_EQ(qab.inverted, 0) << c.seed;
        EXPECT_GT(qab.sj_min, c.absorbed_bound) << c.seed;
        // Seed 12: one of its two stubs left a branching point of degree 4 (3 now).
        EXPECT_EQ(absorbed.analysis.counts.branching_points + c.joints_now, before.analysis.counts.branching_points)
            << c.seed;
        // A side stub moves the branching point from c to q on the sibling: c's degree falls by one and q of degree 3
        // is added, so each side stub adds one branching point to the absorbed count.
        EXPECT_EQ(after.analysis.counts.branching_points, absorbed.analysis.counts.branching_points + c.side) << c.seed;
    }
}

namespace {

// A 4 x 4 plate of unit quads in z = 0 (vertex y * 5 + x at (x, y, 0), radius 0.1 + 0.01 x) with a branch rooted at
// its centre (vertex 12): 25 at (2, 2, 1), 26 at (2, 2, 2), both of radius `branch_r`.
Skeleton rooted_plate(double branch_r) {
    Skeleton s;
    for (int y = 0; y <= 4; ++y)
        for (int x = 0; x <= 4; ++x) {
            s.points.push_back({double(x), double(y), 0});
            s.radii.push_back(0.1 + 0.01 * x);
        }
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const int a = y * 5 + x;
            s.faces.push_back({a, a + 1, a + 6, a + 5});
        }
    s.points.push_back({2, 2, 1});
    s.points.push_back({2, 2, 2});
    s.radii.push_back(branch_r);
    s.radii.push_back(branch_r);
    s.edges = {{12, 25}, {25, 26}};
    mesohex::add_face_edges(s);
    return s;
}

std::vector<int> side_neighbours(const Skeleton& s, int v) {
    std::vector<int> nb;
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i)
            if (f[i] == v) nb.push_back(f[(i + 1) % f.size()]);
    return nb;
}

}  // namespace

// Branch radius 0.25 (> the root's 0.12), factor 0.8: target 0.2 < the edge length 1, so the 4 strips crossing the
// root's sides (columns x in [1, 2], [2, 3], rows y in [1, 2], [2, 3]) are split at 0.2 from the root. Each strip
// crosses 5 edges (20 new points); the 4 faces around the root are crossed twice (4 quads and a centre each), the 8
// other faces of the strips once: V = 27 + 20 + 4 = 51 (the plate a 7 x 7 grid, x and y in {0, 1, 1.8, 2, 2.2, 3, 4}),
// F = 16 + 8 + 4 x 3 = 36 (6 x 6), E = 40 + 2 + 20 + 8 + 16 = 86 (2 x 7 x 6 + the branch's 2).
TEST(SkeletonRepair, RootPatchSplitOnPlate) {
    const Skeleton in = rooted_plate(0.25);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in);
    EXPECT_EQ(res.root_strip_splits, 4);
    EXPECT_EQ(res.trunks + res.absorbed_stubs, 0);
    const Skeleton& s = res.skeleton;
    ASSERT_EQ(s.points.size(), 51u);
    EXPECT_EQ(s.faces.size(), 36u);
    EXPECT_EQ(s.edges.size(), 86u);
    EXPECT_EQ(mesohex::euler_characteristic(s), mesohex::euler_characteristic(in));
    for (int v = 0; v < 27; ++v) EXPECT_EQ(distance(s.points[v], in.points[v]), 0.0) << v;  // kept in place
    const std::vector<double> grid{0, 1, 1.8, 2, 2.2, 3, 4};
    for (std::size_t v = 27; v < s.points.size(); ++v) {
        const Vec3 p = s.points[v];
        const auto on_grid = [&](double c) {
            for (const double g : grid)
                if (std::abs(c - g) < 1e-12) return true;
            return false;
        };
        EXPECT_TRUE(on_grid(p.x) && on_grid(p.y) && p.z == 0) << v;
        EXPECT_NEAR(s.radii[v], 0.1 + 0.01 * p.x, 1e-12) << v;  // interpolated (linear in x: exact)
    }
    const std::vector<int> nb = side_neighbours(s, 12);
    ASSERT_EQ(nb.size(), 4u);
    for (const int u : nb) {
        EXPECT_GE(u, 27);
        EXPECT_NEAR(distance(s.points[u], s.points[12]), 0.8 * 0.25, 1e-12);
    }
    for (const std::vector<int>& f :
         s.faces) {  // every face a quad, normal +z (orientation kept), the smallest 0.2 x 0.2
        ASSERT_EQ(f.size(), 4u);
        const Vec3 n = cross(s.points[f[1]] - s.points[f[0]], s.points[f[3]] - s.points[f[0]]);
        EXPECT_GT(n.z, 0.039);
    }
    // The raw mesh of the split plate: no inverted hex.
    const mesohex::PipelineResult run = mesohex::run_pipeline(in);
    EXPECT_EQ(run.root_strip_splits, 4);
    EXPECT_EQ(mesohex::compute_quality(run.raw.mesh).inverted, 0);
}

// A patch that already fits is not refined: branch radius 1.25 puts the target at 0.8 x 1.25 = 1, the edge length;
// factor 0 disables the split.
TEST(SkeletonRepair, RootPatchThatFitsIsKept) {
    const Skeleton fat = rooted_plate(1.25);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(fat);
    EXPECT_EQ(res.root_strip_splits, 0);
    EXPECT_EQ(res.skeleton, fat);
    mesohex::SkeletonRepairOptions off;
    off.root_patch_factor = 0;
    const Skeleton thin = rooted_plate(0.25);
    EXPECT_EQ(mesohex::repair_skeleton(thin, off).root_strip_splits, 0);
    EXPECT_EQ(mesohex::repair_skeleton(thin, off).skeleton, thin);
}

// An open cylinder of 6 x 4 unit quads (hexagonal section of side 1, rings z = 0..4), a branch rooted at ring 2: the
// two strips crossing its axial sides go round the cylinder (closed loops of 6 faces, cut once each), the two crossing
// its ring sides run along it (4 faces). Cut edges 2 x 6 + 2 x 5 = 22; faces crossed twice 2 x 2 = 4, once 12 + 8 - 8
// = 12: V = 31 + 22 + 4 = 57 (an 8 x 7 grid on the cylinder and the branch's end), F = 24 + 12 + 12 = 48 (8 x 6),
// E = 54 + 1 + 22 + 12 + 16 = 105 (8 x 7 + 8 x 6 and the branch edge).
TEST(SkeletonRepair, RootPatchSplitLoopsOnce) {
    Skeleton s;
    for (int z = 0; z <= 4; ++z)
        for (int k = 0; k < 6; ++k) {
            const double a = k * std::numbers::pi / 3;
            s.points.push_back({std::cos(a), std::sin(a), double(z)});
            s.radii.push_back(0.1);
        }
    for (int z = 0; z < 4; ++z)
        for (int k = 0; k < 6; ++k)
            s.faces.push_back({z * 6 + k, z * 6 + (k + 1) % 6, (z + 1) * 6 + (k + 1) % 6, (z + 1) * 6 + k});
    s.points.push_back({2, 0, 2});  // 30, rooted at vertex 12 = (1, 0, 2)
    s.radii.push_back(0.25);
    s.edges = {{12, 30}};
    mesohex::add_face_edges(s);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(s);
    EXPECT_EQ(res.root_strip_splits, 4);
    EXPECT_EQ(res.skeleton.points.size(), 31u + 22u + 4u);
    EXPECT_EQ(res.skeleton.faces.size(), 48u);
    EXPECT_EQ(res.skeleton.edges.size(), 105u);
    for (const int u : side_neighbours(res.skeleton, 12))
        EXPECT_NEAR(distance(res.skeleton.points[u], res.skeleton.points[12]), 0.2, 1e-12);
}

// Seeds of the random set with a branch rooted inside a leaflet (docs/tuning.md "Sheets: the rooted branch's patch"):
// the 4 strips around the root are split, the raw mesh has no inverted hex.
TEST(SkeletonRepair, RandomSeedsWithRootedBranch) {
    for (const int seed : {25, 40}) {
        const mesohex::PipelineResult run =
            mesohex::run_pipeline(mesohex::generate_random_skeleton(static_cast<std::uint64_t>(seed)));
        EXPECT_EQ(run.root_strip_splits, 4) << seed;
        EXPECT_EQ(mesohex::compute_quality(run.raw.mesh).inverted, 0) << seed;
    }
}

// The repair rescans only the branching points whose walks the previous repair touched (skeleton_repair.cpp,
// stale_points); a full rescan after every repair must give the same skeleton bit for bit and the same counts. Random
// trees (about 20-30 trunks and 50-80 absorbed stubs each at 5 120 vertices; smaller ones here), also with the
// non-default repairs (kept sibling joints, merged branching ends) that edit the walks differently.
TEST(SkeletonRepair, IncrementalScanEqualsFullRescan) {
    int repairs = 0;
    for (const std::uint32_t seed : {1u, 2u, 3u})
        for (const bool variants : {false, true}) {
            const Skeleton s = mesohex::bench::random_tree(800, seed);
            mesohex::SkeletonRepairOptions o;
            o.keep_sibling_joints = variants;
            o.merge_branching_ends = variants;
            const mesohex::SkeletonRepairResult a = mesohex::repair_skeleton(s, o);
            o.rescan_all = true;
            const mesohex::SkeletonRepairResult b = mesohex::repair_skeleton(s, o);
            EXPECT_TRUE(a.skeleton == b.skeleton) << "seed " << seed;
            EXPECT_EQ(a.vertex_map, b.vertex_map);
            EXPECT_EQ(a.trunks, b.trunks);
            EXPECT_EQ(a.absorbed_stubs, b.absorbed_stubs);
            EXPECT_EQ(a.merged_ends, b.merged_ends);
            EXPECT_EQ(a.unseparated, b.unseparated);
            EXPECT_EQ(a.side_stubs, b.side_stubs);
            repairs += a.trunks + a.absorbed_stubs + a.merged_ends + a.side_stubs;
        }
    EXPECT_GT(repairs, 100);  // the trees do need many repairs (else the test checks nothing)
}

// The repair's rounds keep vertex and edge ids (dead ones marked, new ones appended) and renumber once at the end
// (skeleton_repair.cpp, Tombstones). Random trees with the default repairs, with kept joints and merged ends, and with
// every stub absorbed (side_stub_reach 0) give the bits recorded with the code that renumbered after every round (main
// 15e8afe): the repaired skeleton (points, radii, edges, faces), the vertex map, the result's vertex lists and counts.
// Checked to fail when a repair's stale points miss the far ends of its walks (another hash, 295 repairs instead of
// 290).
TEST(SkeletonRepair, RepairedTreesGiveTheRecordedBits) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a
    const auto mix = [&h](const void* data, std::size_t size) {
        for (std::size_t i = 0; i < size; ++i) {
            h ^= static_cast<const unsigned char*>(data)[i];
            h *= 1099511628211ull;
        }
    };
    const auto mix_ints = [&](const std::vector<int>& v) {
        mix(v.data(), v.size() * sizeof(int));
        const int end = -7;
        mix(&end, sizeof end);
    };
    int repairs = 0;
    for (const std::uint32_t seed : {1u, 2u, 3u, 4u})
        for (const int variant : {0, 1, 2}) {
            const Skeleton s = mesohex::bench::random_tree(800, seed);
            mesohex::SkeletonRepairOptions o;
            o.keep_sibling_joints = variant == 1;
            o.merge_branching_ends = variant == 1;
            if (variant == 2) o.side_stub_reach = 0;
            o.side_stub_root_exit = 0;  // the side stubs' roots of the recording (the point nearest the stub's end)
            const mesohex::SkeletonRepairResult r = mesohex::repair_skeleton(s, o);
            mix(r.skeleton.points.data(), r.skeleton.points.size() * sizeof(Vec3));
            mix(r.skeleton.radii.data(), r.skeleton.radii.size() * sizeof(double));
            mix(r.skeleton.edges.data(), r.skeleton.edges.size() * sizeof(std::array<int, 2>));
            for (const std::vector<int>& f : r.skeleton.faces) mix_ints(f);
            mix_ints(r.vertex_map);
            mix_ints(r.absorbed_balls);
            mix_ints(r.trunk_joints);
            mix_ints(r.fan_end_pins);
            const int counts[] = {r.trunks, r.absorbed_stubs, r.merged_ends, r.side_stubs, r.unseparated};
            mix(counts, sizeof counts);
            repairs += r.trunks + r.absorbed_stubs + r.merged_ends + r.side_stubs;
        }
    EXPECT_EQ(repairs, 290);  // 64 trunks, 69 absorbed stubs, 62 merged ends, 95 side stubs
    EXPECT_EQ(h, 0xb17c958f7127dae8ull);
}

namespace {

// A hand-written wall on a chain turning in a plate's grid (docs/blocks.md "Docked walls turning in the plate's grid:
// the band pillow"): an n x n unit plate at z = 0 (x, y in 0..n), a chain through the grid corners `corners` (each leg
// along x or y), a wall of `rows` unit rows standing on it at +z (one leaflet, folded along each turn's vertical
// line), with `both` a second one at -z. Radius r everywhere. Faces listed, then every side once.
Skeleton turning_wall(int n, const std::vector<std::array<int, 2>>& corners, int rows, bool both, double r) {
    Skeleton s;
    const auto at = [n](int x, int y) { return (n + 1) * x + y; };
    for (int x = 0; x <= n; ++x)
        for (int y = 0; y <= n; ++y) s.points.push_back({double(x), double(y), 0.0});
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y) s.faces.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)});
    std::vector<int> chain{at(corners[0][0], corners[0][1])};
    for (std::size_t c = 1; c < corners.size(); ++c) {
        std::array<int, 2> p = corners[c - 1];
        while (p != corners[c]) {
            for (int k = 0; k < 2; ++k) p[k] += p[k] < corners[c][k] ? 1 : p[k] > corners[c][k] ? -1 : 0;
            chain.push_back(at(p[0], p[1]));
        }
    }
    for (const double z : both ? std::vector<double>{1.0, -1.0} : std::vector<double>{1.0}) {
        std::vector<std::vector<int>> w(chain.size());
        for (std::size_t j = 0; j < chain.size(); ++j) {
            w[j].push_back(chain[j]);
            for (int k = 1; k <= rows; ++k) {
                w[j].push_back(static_cast<int>(s.points.size()));
                s.points.push_back(s.points[chain[j]] + Vec3{0, 0, k * z});
            }
        }
        for (std::size_t j = 0; j + 1 < chain.size(); ++j)
            for (int k = 0; k < rows; ++k) s.faces.push_back({w[j][k], w[j + 1][k], w[j + 1][k + 1], w[j][k + 1]});
    }
    s.radii.assign(s.points.size(), r);
    std::map<std::pair<int, int>, int> sides;
    for (const std::vector<int>& f : s.faces)
        for (int i = 0; i < 4; ++i)
            if (sides.insert({std::minmax(f[i], f[(i + 1) % 4]), 0}).second) s.edges.push_back({f[i], f[(i + 1) % 4]});
    return s;
}

int boundary_sides(const Skeleton& s) {
    std::map<std::pair<int, int>, int> sides;
    for (const std::vector<int>& f : s.faces)
        for (int i = 0; i < 4; ++i) ++sides[std::minmax(f[i], f[(i + 1) % 4])];
    int b = 0;
    for (const auto& [e, count] : sides) b += count == 1;
    return b;
}

// The 4 x 4 plate (unit faces, z = 0, x and y from -2 to 2) with a wall of 2 rows over the chain x = 0 (vertices
// 10 .. 14) and, on the other side, a shorter wall of 1 row over y in [-1, 1] (vertices 35 .. 37), radius 0.3.
Skeleton wall_across_with_shorter_bottom() {
    mesohex::WallPlate w;
    w.plate = 4;
    w.start = 0;
    w.length = 4;
    w.column = 2;
    Skeleton in = mesohex::make_wall_plate(w, 1.0, 0.3);
    for (int j = 1; j <= 3; ++j) in.points.push_back(in.points[2 * 5 + j] + Vec3{0, 0, -1});
    in.radii.resize(in.points.size(), 0.3);
    for (int j = 1; j <= 2; ++j) in.faces.push_back({2 * 5 + j, 2 * 5 + j + 1, 35 + j, 35 + j - 1});
    mesohex::add_face_edges(in);
    return in;
}

}  // namespace

// A wall across the plate with a shorter wall on the other side (test_docked_walls.cpp,
// WallAcrossThePlateWithAShorterWallOnTheOtherSideByHand: plate 4 x 4 unit at z = 0, x and y from -2 to 2, chain x = 0;
// top wall 2 rows over y in [-2, 2], bottom wall 1 row over y in [-1, 1], radius 0.3): the repair joins the plate's
// halves like the analysis, so the feet are split at 2 r = 0.6, capped at half the side: the columns x in [-1, 0] and
// [0, 1] at x = -0.5, 0.5 (beside the chain: 4 faces, 5 cut sides each) and, beyond the bottom wall's ends, the rows y
// in [-2, -1] and [1, 2] at y = -1.5, 1.5 through the plate and the top wall (4 plate + 2 wall faces, 7 cut sides). V
// 38 + 24 cut
// sides + 4 centres of the faces crossed twice = 66; F 26 + 12 (crossed once) + 3 x 4 = 50; E 63 + 24 + 12 + 4 x 4 =
// 115 (Euler 1); boundary 28 + 2 x 2 (beside: the plate's border at y = -2, 2) + 2 x 3 (beyond: x = -2, 2 and the top
// wall's top) = 38; raw hexes 2 F + 2 B = 176 (108 unsplit).
TEST(SkeletonRepair, FeetOfAWallAcrossThePlateWithAShorterWallOnTheOtherSideAreSplit) {
    const Skeleton in = wall_across_with_shorter_bottom();
    ASSERT_EQ(in.points.size(), 38u);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, {});
    EXPECT_EQ(res.docked_foot_splits, 4);
    const Skeleton& s = res.skeleton;
    EXPECT_EQ(s.points.size(), 66u);
    EXPECT_EQ(s.edges.size(), 115u);
    EXPECT_EQ(s.faces.size(), 50u);
    EXPECT_EQ(boundary_sides(s), 38);
    int beside = 0, beyond = 0;
    for (std::size_t v = 38; v < s.points.size(); ++v) {
        const Vec3& p = s.points[v];
        beside += std::abs(std::abs(p.x) - 0.5) < 1e-12 && std::abs(std::abs(p.y) - 1.5) > 1e-9;
        beyond += std::abs(std::abs(p.y) - 1.5) < 1e-12 && std::abs(std::abs(p.x) - 0.5) > 1e-9;
    }
    EXPECT_EQ(beside, 2 * 5);
    EXPECT_EQ(beyond, 2 * 7);
    const mesohex::PipelineResult r = mesohex::run_pipeline(in);
    EXPECT_EQ(r.docked_foot_splits, 4);
    EXPECT_EQ(r.analysis.counts.docked_edges, 6);  // the chain's 4 edges, 2 of them split at y = -1.5 and 1.5
    EXPECT_EQ(r.predicted.hexes, 176);
    expect_raw_as_predicted(r, 176);
    EXPECT_GT(mesohex::compute_quality(r.raw.mesh).sj_min, 0.6);  // measured, not derived
    mesohex::PipelineOptions unsplit;
    unsplit.repair.docked_foot_split = 0;
    EXPECT_EQ(mesohex::compute_quality(mesohex::run_pipeline(in, unsplit).raw.mesh).hexes, 108);
}

// The repair splits the feet of a wall across a plate exactly where the analysis joins the plate's halves and docks the
// chain (one test: join_plates_across_chains, docked_walls.h). The plate of the test above (4 x 4, chain x = 0 from y
// = -2 to 2, vertices 10 .. 14; top wall over the whole chain, a shorter bottom wall over y in [-1, 1]), changed so
// that the analysis' conditions fail on one chain edge other than the first, where the repair's own test (session 29:
// the halves' angle measured on the first chain side only, no wall check) joined them and split 4 strips:
//  (a) the right half bent up at the last chain edge: vertices (1, 1), (1, 2) lifted by tan 40 degrees, (2, 1), (2,
//      2) by twice that. The right face on chain side (13, 14) leaves the chain at 40 degrees above the plane (into
//      direction (1, 0, tan 40)), 140 degrees from the left face's (-1, 0, 0), below kDockPlateAngleDeg (150); on
//      (12, 13) atan(tan 40 / 2) = 22.8 degrees, 157.2 apart; on (10, 11), (11, 12) 180. No pair of leaflets continues
//      across every chain edge (the walls make 90 - 130 degrees with the halves): no join;
//  (b) the plate flat, the top wall leaning 55 degrees towards +x (its vertex k rows up at (k sin 55, y, k cos 55)):
//      the halves are 180 degrees apart on every edge (the wall 145 from the left half, 35 from the right: not a
//      pair), but after the join every chain edge's wall leans 55 degrees from the plate's normal, above
//      kDockWallTiltDeg (45): no join.
// Either way no chain is docked, so no strip is split (the skeleton is returned unchanged, V 38, F 26), and the
// analysis refuses the irregular fan at vertex 11, where the chain edges of 3 and 4 faces meet (word for word as with
// the repair off).
TEST(SkeletonRepair, FeetOfAnAcrossChainAreSplitOnlyWhereTheAnalysisDocksIt) {
    const Skeleton flat = wall_across_with_shorter_bottom();
    ASSERT_EQ(flat.points.size(), 38u);
    ASSERT_EQ(mesohex::repair_skeleton(flat, {}).docked_foot_splits, 4);  // the test above: docked, split
    Skeleton bent = flat;
    const double lift = std::tan(40 * std::numbers::pi / 180);
    for (const int v : {18, 19}) bent.points[v].z = lift;
    for (const int v : {23, 24}) bent.points[v].z = 2 * lift;
    Skeleton leaning = flat;
    const double a = 55 * std::numbers::pi / 180;
    for (int j = 0; j <= 4; ++j)
        for (int k = 1; k <= 2; ++k) {
            Vec3& p = leaning.points[25 + 2 * j + (k - 1)];
            ASSERT_DOUBLE_EQ(p.z, k);  // the top wall's vertex k rows up
            p.x = k * std::sin(a);
            p.z = k * std::cos(a);
        }
    for (const Skeleton* in : {&bent, &leaning}) {
        const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(*in, {});
        EXPECT_EQ(res.docked_foot_splits, 0);
        EXPECT_EQ(res.skeleton.points.size(), 38u);
        EXPECT_EQ(res.skeleton.faces.size(), 26u);
        std::string why;
        try {
            (void)mesohex::analyze_skeleton(res.skeleton);
        } catch (const mesohex::Error& e) {
            why = e.what();
        }
        EXPECT_NE(why.find("skeleton vertex 11"), std::string::npos) << why;
        EXPECT_NE(why.find("2 fan edges shared by 3 and 4 faces meet here"), std::string::npos) << why;
    }
}

// The band pillow on an L-shaped wall (docs/blocks.md "Docked walls turning in the plate's grid: the band pillow").
// 6 x 6 plate, chain (1, 3) -> (3, 3) -> (3, 5) (4 edges, both ends inside, a 90-degree turn at (3, 3) with 1 plate
// face on the inner side and 3 on the outer), a wall of 2 rows at +z, radius 0.1: V 49 + 10 = 59, E 84 + 18 = 102, F
// 36 + 8 = 44, boundary edges 24 + 8 = 32 (before: refused at (3, 3)). The band's path runs on beyond both inside ends
// to the plate's border: (0, 3) ... (3, 3) ... (3, 6), 7 vertices, 6 edges. Pillow: 2 copies per path vertex (+14 V),
// 2 faces per path edge (+12 F), edges (v, v') and (p', q') (+14 + 12 E), 2 new border sides per path end (+4 B):
// V 73, E 128, F 56, B 36 (Euler 1); raw hexes 2 F + 2 B = 184 without the foot split. With it (2 r = 0.2; the sides
// to the band copies are left): the strips beyond the two inside ends, the column x in [0, 1] (6 plate faces + 2 band
// faces, 9 cut edges) and the row y in [5, 6] (the same), crossing in the face [0, 1] x [5, 6]: V 73 + 18 + 1 = 92,
// E 128 + 18 + 14 + 4 = 164, F 56 + 14 + 3 = 73, B 36 + 4 = 40; raw hexes 2 F + 2 B = 226.
TEST(SkeletonRepair, BandPillowDocksAnLShapedWall) {
    const Skeleton in = turning_wall(6, {{{1, 3}, {3, 3}, {3, 5}}}, 2, false, 0.1);
    ASSERT_EQ(in.points.size(), 59u);
    ASSERT_EQ(in.edges.size(), 102u);
    ASSERT_EQ(in.faces.size(), 44u);
    ASSERT_EQ(boundary_sides(in), 32);
    EXPECT_THROW(mesohex::analyze_skeleton(in), mesohex::Error);  // the turn: 1 plate face inside, 3 outside
    mesohex::SkeletonRepairOptions no_split;
    no_split.docked_foot_split = 0;
    const mesohex::SkeletonRepairResult bare = mesohex::repair_skeleton(in, no_split);
    EXPECT_EQ(bare.docked_band_pillows, 1);
    EXPECT_EQ(bare.skeleton.points.size(), 73u);
    EXPECT_EQ(bare.skeleton.edges.size(), 128u);
    EXPECT_EQ(bare.skeleton.faces.size(), 56u);
    EXPECT_EQ(boundary_sides(bare.skeleton), 36);
    const mesohex::SkeletonAnalysis an = mesohex::analyze_skeleton(bare.skeleton);
    EXPECT_EQ(an.counts.docked_edges, 4);
    EXPECT_TRUE(an.docked_unmatched.empty());
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(in, {});
    EXPECT_EQ(res.docked_band_pillows, 1);
    EXPECT_EQ(res.docked_foot_splits, 2);
    EXPECT_EQ(res.skeleton.points.size(), 92u);
    EXPECT_EQ(res.skeleton.edges.size(), 164u);
    EXPECT_EQ(res.skeleton.faces.size(), 73u);
    EXPECT_EQ(boundary_sides(res.skeleton), 40);
    // The copies at the turn: the miter, 2 r along each side's normal (inner (2.8, 3.2), outer (3.2, 2.8)).
    int miters = 0;
    for (std::size_t v = 59; v < res.skeleton.points.size(); ++v) {
        const Vec3& p = res.skeleton.points[v];
        miters += (std::abs(p.x - 2.8) < 1e-12 && std::abs(p.y - 3.2) < 1e-12) ||
                  (std::abs(p.x - 3.2) < 1e-12 && std::abs(p.y - 2.8) < 1e-12);
    }
    EXPECT_EQ(miters, 2);
    const mesohex::PipelineResult r = mesohex::run_pipeline(in);
    EXPECT_EQ(r.docked_band_pillows, 1);
    EXPECT_EQ(r.predicted.hexes, 226);
    expect_raw_as_predicted(r, 226);
    EXPECT_GT(mesohex::compute_quality(r.raw.mesh).sj_min, 0.65);  // 0.671 measured
    mesohex::PipelineOptions bare_options;
    bare_options.repair.docked_foot_split = 0;
    const mesohex::PipelineResult rb = mesohex::run_pipeline(in, bare_options);
    EXPECT_EQ(rb.predicted.hexes, 184);
    expect_raw_as_predicted(rb, 184);
    mesohex::PipelineOptions off;
    off.repair.docked_band_pillow = false;
    EXPECT_THROW(mesohex::run_pipeline(in, off), mesohex::Error);
}

// The same L from the border and on both sides. From the border: chain (3, 0) -> (3, 2) -> (5, 2) (4 edges, the end
// (5, 2) inside), wall of 2 rows at +z, radius 0.1: V 59, F 44, B 24 + 8 = 32 (the wall's end at the border has its
// border edge too). Path (3, 0) ... (3, 2) ... (6, 2): 6 vertices, 5 edges: V + 12, F + 10, B + 4; the foot split
// cuts the column x in [5, 6] beyond the inside end (6 + 2 faces, 9 edges, B + 2; the border end's sides are band
// sides): F 44 + 10 + 8 = 62, B 32 + 4 + 2 = 38, raw hexes 2 F + 2 B = 200. Both sides (the first case with a second
// wall of 2 rows at -z: + 8 faces, + 8 boundary edges): 226 + 32 = 258.
TEST(SkeletonRepair, BandPillowDocksLShapedWallsFromTheBorderAndOnBothSides) {
    const Skeleton edge = turning_wall(6, {{{3, 0}, {3, 2}, {5, 2}}}, 2, false, 0.1);
    ASSERT_EQ(edge.faces.size(), 44u);
    ASSERT_EQ(boundary_sides(edge), 32);
    const mesohex::SkeletonRepairResult res = mesohex::repair_skeleton(edge, {});
    EXPECT_EQ(res.docked_band_pillows, 1);
    EXPECT_EQ(res.docked_foot_splits, 1);
    EXPECT_EQ(res.skeleton.faces.size(), 62u);
    EXPECT_EQ(boundary_sides(res.skeleton), 38);
    const mesohex::PipelineResult r = mesohex::run_pipeline(edge);
    EXPECT_EQ(r.predicted.hexes, 200);
    expect_raw_as_predicted(r, 200);
    EXPECT_GT(mesohex::compute_quality(r.raw.mesh).sj_min, 0.65);  // 0.671
    const mesohex::PipelineResult both =
        mesohex::run_pipeline(turning_wall(6, {{{1, 3}, {3, 3}, {3, 5}}}, 2, true, 0.1));
    EXPECT_EQ(both.docked_band_pillows, 1);
    EXPECT_EQ(both.predicted.hexes, 258);
    expect_raw_as_predicted(both, 258);
    EXPECT_GT(mesohex::compute_quality(both.raw.mesh).sj_min, 0.65);  // 0.671
}

// A chain vertex where 3 plate faces meet (the other case the band pillow takes): a hexagonal plate, centre c (the
// origin) split into 3 quads (c, h0, h1, h2), (c, h2, h3, h4), (c, h4, h5, h0) with h_i at radius 1 and 60 i degrees,
// and two rings of 6 quads out to radius 3 (vertices at radius 2 and 3 on the same rays): V 19, F 15, border 6. The
// chain h0 -> c -> h2 (turning by 60 degrees at c, 1 plate face on one side, 2 on the other), a wall of 2 unit rows
// at +z, radius 0.1: V 25, F 19, boundary edges 6 + 6 = 12. The band's path runs on along the rays 0 and 120 degrees
// to the border: 7 vertices, 6 edges: F + 12, B + 4; without the foot split raw hexes 2 (19 + 12) + 2 (12 + 4) = 94.
// With it (2 r = 0.2): the strips beyond the two inside ends are one, the ring between radius 1 and 2 (its 6 quads
// and the 4 band faces on the two rays), closed, cut at 0.2 from the inner ring: + 10 faces, no boundary edge:
// 2 (31 + 10) + 2 x 16 = 114.
TEST(SkeletonRepair, BandPillowDocksAWallOnAChainVertexOfThreePlateFaces) {
    Skeleton s;
    s.points.push_back({0, 0, 0});
    for (int ring = 1; ring <= 3; ++ring)
        for (int i = 0; i < 6; ++i)
            s.points.push_back({ring * std::cos(i * 60 * kDeg), ring * std::sin(i * 60 * kDeg), 0.0});
    const auto h = [](int ring, int i) { return 1 + 6 * (ring - 1) + i % 6; };
    for (const int a : {0, 2, 4}) s.faces.push_back({0, h(1, a), h(1, a + 1), h(1, a + 2)});
    for (int ring = 2; ring <= 3; ++ring)
        for (int i = 0; i < 6; ++i) s.faces.push_back({h(ring - 1, i), h(ring, i), h(ring, i + 1), h(ring - 1, i + 1)});
    const std::array<int, 3> chain{h(1, 0), 0, h(1, 2)};
    std::array<std::array<int, 3>, 3> w{};
    for (int j = 0; j < 3; ++j) {
        w[j][0] = chain[j];
        for (int k = 1; k <= 2; ++k) {
            w[j][k] = static_cast<int>(s.points.size());
            s.points.push_back(s.points[chain[j]] + Vec3{0, 0, double(k)});
        }
    }
    for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k) s.faces.push_back({w[j][k], w[j + 1][k], w[j + 1][k + 1], w[j][k + 1]});
    s.radii.assign(s.points.size(), 0.1);
    std::map<std::pair<int, int>, int> sides;
    for (const std::vector<int>& f : s.faces)
        for (int i = 0; i < 4; ++i)
            if (sides.insert({std::minmax(f[i], f[(i + 1) % 4]), 0}).second) s.edges.push_back({f[i], f[(i + 1) % 4]});
    ASSERT_EQ(s.points.size(), 25u);
    ASSERT_EQ(s.faces.size(), 19u);
    ASSERT_EQ(boundary_sides(s), 12);
    EXPECT_THROW(mesohex::analyze_skeleton(s), mesohex::Error);  // 3 plate faces at c
    mesohex::PipelineOptions bare;
    bare.repair.docked_foot_split = 0;
    const mesohex::PipelineResult rb = mesohex::run_pipeline(s, bare);
    EXPECT_EQ(rb.docked_band_pillows, 1);
    EXPECT_EQ(rb.predicted.hexes, 94);
    expect_raw_as_predicted(rb, 94);
    const mesohex::PipelineResult r = mesohex::run_pipeline(s);
    EXPECT_EQ(r.predicted.hexes, 114);
    expect_raw_as_predicted(r, 114);
    EXPECT_GT(mesohex::compute_quality(r.raw.mesh).sj_min, 0.68);  // 0.707
}

// Where the band's path cannot run on, the wall is refused as before, naming the vertex: a spiral chain (2, 2) -> (4,
// 2) -> (4, 4) -> (1, 4) -> (1, 1) on a 6 x 6 plate, whose
// inside end (2, 2), run on straight, meets the chain at (1, 2).
TEST(SkeletonRepair, BandPillowLeavesAPathThatCannotRunOn) {
    const Skeleton spiral = turning_wall(6, {{{2, 2}, {4, 2}, {4, 4}, {1, 4}, {1, 1}}}, 1, false, 0.1);
    EXPECT_EQ(mesohex::repair_skeleton(spiral, {}).docked_band_pillows, 0);
    try {
        mesohex::run_pipeline(spiral);
        ADD_FAILURE() << "meshed";
    } catch (const mesohex::Error& e) {
        EXPECT_EQ(e.code(), mesohex::ErrorCode::UnsupportedConfiguration);
        EXPECT_NE(std::string(e.what()).find("band pillow, which makes the grid match, did not take this chain"),
                  std::string::npos)
            << e.what();
        // The pillow's turn limit, from its constant: acos(-0.25) = 104.48 degrees.
        EXPECT_NE(std::string(e.what()).find("turns of at most about 104 degrees"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("edit:"), std::string::npos) << e.what();
    }
    // With the pillow off the refusal says so (and names no condition of the pillow's).
    const Skeleton l_wall = turning_wall(6, {{{1, 3}, {3, 3}, {3, 5}}}, 2, false, 0.1);
    mesohex::PipelineOptions off;
    off.repair.docked_band_pillow = false;
    for (const Skeleton* s : {&spiral, &l_wall}) {
        try {
            mesohex::run_pipeline(*s, off);
            ADD_FAILURE() << "meshed";
        } catch (const mesohex::Error& e) {
            EXPECT_EQ(e.where().kind, mesohex::ElementRef::Kind::SkeletonVertex);
            EXPECT_NE(std::string(e.what()).find("band pillow, which makes such a grid match, is off"),
                      std::string::npos)
                << e.what();
            EXPECT_EQ(std::string(e.what()).find("did not take"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("edit: mesh with the band pillow"), std::string::npos) << e.what();
        }
    }
}
