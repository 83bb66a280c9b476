#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/adaptation.h"

using mesohex::AdaptationOptions;
using mesohex::Skeleton;
using mesohex::Vec3;

namespace {

// Appends a polyline from vertex `from` to `to` (existing ids) through `inner` new points.
void add_path(Skeleton& s, int from, int to, const std::vector<Vec3>& inner, double r) {
    int prev = from;
    for (const Vec3& x : inner) {
        s.points.push_back(x);
        s.radii.push_back(r);
        const int v = static_cast<int>(s.points.size()) - 1;
        s.edges.push_back({prev, v});
        prev = v;
    }
    s.edges.push_back({prev, to});
}

// Straight oversampled branch from (0,0,0) to (L,0,0): vertices 0 and 1 are the extremities, then `inner` joints.
Skeleton straight(double length, int inner, double r) {
    Skeleton s;
    s.points = {{0, 0, 0}, {length, 0, 0}};
    s.radii = {r, r};
    std::vector<Vec3> xs;
    for (int i = 1; i <= inner; ++i) xs.push_back({length * i / (inner + 1), 0, 0});
    add_path(s, 0, 1, xs, r);
    return s;
}

std::vector<int> degrees(const Skeleton& s) {
    std::vector<int> d(s.points.size(), 0);
    for (const std::array<int, 2>& e : s.edges) ++d[e[0]], ++d[e[1]];
    return d;
}

// Smallest angle between two edges at one vertex (radians; pi when no vertex has two edges).
double smallest_angle_at_vertices(const Skeleton& s) {
    std::vector<std::vector<Vec3>> dirs(s.points.size());
    for (const std::array<int, 2>& e : s.edges) {
        dirs[e[0]].push_back(mesohex::normalized(s.points[e[1]] - s.points[e[0]]));
        dirs[e[1]].push_back(mesohex::normalized(s.points[e[0]] - s.points[e[1]]));
    }
    double best = 3.14159265358979323846;
    for (const std::vector<Vec3>& d : dirs)
        for (std::size_t i = 0; i < d.size(); ++i)
            for (std::size_t j = i + 1; j < d.size(); ++j)
                best = std::min(best, std::acos(std::clamp(mesohex::dot(d[i], d[j]), -1.0, 1.0)));
    return best;
}

int count_degree_at_least(const Skeleton& s, int k) {
    const std::vector<int> d = degrees(s);
    return static_cast<int>(std::count_if(d.begin(), d.end(), [k](int x) { return x >= k; }));
}

}  // namespace

// L = 16, r = 1, density 1: split while 2 < length: 16 -> 8 -> 4 -> 2 (2 < 2 fails): 8 edges of length 2 = 2r/density.
TEST(Adaptation, StraightConstantRadiusPowerOfTwo) {
    const Skeleton out = mesohex::adapt_skeleton(straight(16, 31, 1.0));
    ASSERT_EQ(out.points.size(), 9u);
    ASSERT_EQ(out.edges.size(), 8u);
    EXPECT_EQ(out.points[0], (Vec3{0, 0, 0}));  // extremities keep their ids, first
    EXPECT_EQ(out.points[1], (Vec3{16, 0, 0}));
    for (const std::array<int, 2>& e : out.edges)
        EXPECT_NEAR(mesohex::distance(out.points[e[0]], out.points[e[1]]), 2.0, 1e-12);
    for (int v = 2; v < 9; ++v) EXPECT_NEAR(out.points[v].x, 2.0 * (v - 1), 1e-12);  // joints in branch order
    for (const double r : out.radii) EXPECT_DOUBLE_EQ(r, 1.0);
}

TEST(Adaptation, DensityScalesEdgeLength) {
    AdaptationOptions o;
    o.density = 0.5;  // 2r/density = 4: 16 -> 8 -> 4 (2 < 2 fails): 4 edges
    EXPECT_EQ(mesohex::adapt_skeleton(straight(16, 31, 1.0), o).edges.size(), 4u);
    o.density = 2.0;  // 2r/density = 1: 16 edges
    EXPECT_EQ(mesohex::adapt_skeleton(straight(16, 31, 1.0), o).edges.size(), 16u);
    // L = 12 (not a power of two times 2r): 12 -> 6 -> 3 -> 1.5 (2 < 1.5 fails): 8 edges of 1.5, within (r, 2r].
    const Skeleton out = mesohex::adapt_skeleton(straight(12, 5, 1.0));
    ASSERT_EQ(out.edges.size(), 8u);
    for (const std::array<int, 2>& e : out.edges)
        EXPECT_NEAR(mesohex::distance(out.points[e[0]], out.points[e[1]]), 1.5, 1e-12);
}

// Radius linear in x (0.2 + 0.05 x): new joints lie on the original segment and get the interpolated radius.
TEST(Adaptation, SamplesLieOnOriginalPolylineWithInterpolatedRadius) {
    Skeleton s;
    s.points = {{0, 0, 0}, {20, 0, 0}};
    s.radii = {0.2, 1.2};
    std::vector<Vec3> xs;
    for (int i = 1; i < 40; ++i) xs.push_back({0.5 * i, 0, 0});
    add_path(s, 0, 1, xs, 0);
    for (std::size_t v = 2; v < s.points.size(); ++v) s.radii[v] = 0.2 + 0.05 * s.points[v].x;
    const Skeleton out = mesohex::adapt_skeleton(s);
    ASSERT_GT(out.points.size(), 3u);
    ASSERT_LT(out.points.size(), s.points.size());
    for (std::size_t v = 0; v < out.points.size(); ++v) {
        EXPECT_EQ(out.points[v].y, 0.0);
        EXPECT_EQ(out.points[v].z, 0.0);
        EXPECT_GE(out.points[v].x, 0.0);
        EXPECT_LE(out.points[v].x, 20.0);
        EXPECT_NEAR(out.radii[v], 0.2 + 0.05 * out.points[v].x, 1e-12);
    }
    // Edges where the radius is larger are longer.
    const auto len_at = [&](double x) {
        for (const std::array<int, 2>& e : out.edges) {
            const double a = out.points[e[0]].x, b = out.points[e[1]].x;
            if (std::min(a, b) <= x && x <= std::max(a, b)) return std::abs(b - a);
        }
        return 0.0;
    };
    EXPECT_LT(len_at(0.1), len_at(19.9));
}

// A pinned joint at x = 5 of the straight branch of length 16, radius 1 (vertex 11): the pieces [0, 5] and [5, 16]
// are bisected separately (r0 + r1 = 2 < length): [0, 5] -> 2.5 -> 1.25, 3.75 (edges of 1.25); [5, 16] -> 10.5 ->
// 7.75, 13.25 -> 6.375, 9.125, 11.875, 14.625 (edges of 1.375); the smoothing keeps uniform samples. 11 joints, 12
// edges, one joint exactly at the pin. Without the pin: 8 edges of 2 (StraightConstantRadiusPowerOfTwo).
TEST(Adaptation, PinnedJointSplitsTheResampling) {
    const Skeleton in = straight(16, 31, 1.0);
    ASSERT_EQ(in.points[11], (Vec3{5, 0, 0}));
    const Skeleton out = mesohex::adapt_skeleton(in, {}, {11});
    ASSERT_EQ(out.points.size(), 13u);
    ASSERT_EQ(out.edges.size(), 12u);
    const std::vector<double> xs{1.25, 2.5, 3.75, 5, 6.375, 7.75, 9.125, 10.5, 11.875, 13.25, 14.625};
    for (std::size_t k = 0; k < xs.size(); ++k) EXPECT_NEAR(out.points[2 + k].x, xs[k], 1e-12) << k;
    EXPECT_EQ(out.points[5], (Vec3{5, 0, 0}));  // the pin itself, not a resampled point near it
    // Out of range, extremities and branching points are ignored: the same output as without pins.
    EXPECT_EQ(mesohex::adapt_skeleton(in, {}, {-1, 0, 1, 99}), mesohex::adapt_skeleton(in));
    EXPECT_EQ(mesohex::adapt_skeleton(in, {}, {11, 11}), out);
}

// A radius bump (an absorbed stub's ball, SkeletonRepairResult::absorbed_balls): (0,0,0) r 0.1 -> (1,0,0) r 0.3 ->
// (3,0,0) r 0.1. The bisection samples [0, 3] at dyadic fractions of 3, never at 1: without the pin every output
// radius is below the bump's 0.3 (the bump is tapered away); pinned, the joint (1,0,0) keeps radius 0.3.
TEST(Adaptation, PinnedRadiusPeakIsKept) {
    Skeleton s;
    s.points = {{0, 0, 0}, {3, 0, 0}, {1, 0, 0}};
    s.radii = {0.1, 0.1, 0.3};
    s.edges = {{0, 2}, {2, 1}};
    const Skeleton free = mesohex::adapt_skeleton(s);
    EXPECT_LT(*std::max_element(free.radii.begin(), free.radii.end()), 0.3 - 1e-3);
    const Skeleton pinned = mesohex::adapt_skeleton(s, {}, {2});
    const auto at = std::find(pinned.points.begin(), pinned.points.end(), Vec3{1, 0, 0});
    ASSERT_NE(at, pinned.points.end());
    EXPECT_DOUBLE_EQ(pinned.radii[static_cast<std::size_t>(at - pinned.points.begin())], 0.3);
    EXPECT_EQ(mesohex::euler_characteristic(pinned), 1);
}

// A pin yields where its edges cannot meet the section criterion: extremity (0,0,0) -> pinned joint p = (d,0,0) ->
// extremity (d,3,0), radius 0.1, a 90-degree turn at p: p's reach is 0.1 sin 45 = 0.0707, an extremity's 0, so the
// edge (0, p) needs d >= turn_safety x 0.0707 = 0.0884. d = 1: the pin stays a vertex of the output. d = 0.05: the
// edge violates the criterion and only the pin could go, so the pin yields and the branch is sampled as without pins
// (the same output).
TEST(Adaptation, PinYieldsWhenItsEdgeCannotClear) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 3, 0}, {1, 0, 0}};
    s.radii = {0.1, 0.1, 0.1};
    s.edges = {{0, 2}, {2, 1}};
    const Skeleton kept = mesohex::adapt_skeleton(s, {}, {2});
    EXPECT_NE(std::find(kept.points.begin(), kept.points.end(), Vec3{1, 0, 0}), kept.points.end());
    s.points = {{0, 0, 0}, {0.05, 3, 0}, {0.05, 0, 0}};
    const Skeleton yielded = mesohex::adapt_skeleton(s, {}, {2});
    EXPECT_EQ(std::find(yielded.points.begin(), yielded.points.end(), Vec3{0.05, 0, 0}), yielded.points.end());
    EXPECT_EQ(yielded, mesohex::adapt_skeleton(s));
}

// A radius peak on a short bridge is stepped over (docs/junctions.md, "The armadillo's torso and neck"): degree-3
// points A = (0,0,0) and B = (0.4,0,0), r 0.1, each with two long arms (length 1, r 0.1) at 60 degrees from the
// bridge (A's in the xy-plane, B's in the xz-plane: they do not cross), joined through the input joint
// M = (0.2,0,0). Bisection of the bridge (density 1): r_A + r_B = 0.2 < 0.4
// cuts it at its midpoint, the sample at M with M's radius r_M; the halves stop (0.1 + r_M >= 0.2). Smallest angle at
// A and B 60 degrees: gamma 30, cot sqrt(3). Section criterion on the edge (A, M), length 0.2, M straight (reach 0):
// reach(A) = 0.7 max(0.1, r_M sqrt(3)). r_M = 0.1: 0.7 x 0.1732 = 0.1212, 1.25 x 0.1212 = 0.152 <= 0.2: the joint
// stays, the bridge has a vertex of radius 0.1 at M. r_M = 0.2 (a bulge twice the ends' radius): 0.7 x 0.3464 =
// 0.2425, 1.25 x 0.2425 = 0.303 > 0.2: the joint goes, A and B are joined by one edge and the meshed tube has radius
// 0.1 where the input's ball at M has 0.2.
TEST(Adaptation, RadiusPeakOnAShortBridgeIsSteppedOver) {
    const double c = 0.5, s3 = std::sqrt(3.0) / 2;
    Skeleton s;
    s.points = {{0, 0, 0}, {0.4, 0, 0}, {c, s3, 0}, {c, -s3, 0}, {0.4 - c, 0, s3}, {0.4 - c, 0, -s3}, {0.2, 0, 0}};
    s.radii = {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1};
    s.edges = {{0, 2}, {0, 3}, {1, 4}, {1, 5}, {0, 6}, {6, 1}};
    const auto has_edge = [](const Skeleton& k, int a, int b) {
        return std::any_of(k.edges.begin(), k.edges.end(), [&](const std::array<int, 2>& e) {
            return (e[0] == a && e[1] == b) || (e[0] == b && e[1] == a);
        });
    };
    const mesohex::AdaptationResult flat = mesohex::adapt_skeleton_detailed(s);
    const auto at = std::find(flat.skeleton.points.begin(), flat.skeleton.points.end(), Vec3{0.2, 0, 0});
    ASSERT_NE(at, flat.skeleton.points.end());
    EXPECT_DOUBLE_EQ(flat.skeleton.radii[static_cast<std::size_t>(at - flat.skeleton.points.begin())], 0.1);
    EXPECT_FALSE(has_edge(flat.skeleton, flat.vertex_map[0], flat.vertex_map[1]));
    s.radii[6] = 0.2;
    const mesohex::AdaptationResult bulge = mesohex::adapt_skeleton_detailed(s);
    EXPECT_TRUE(has_edge(bulge.skeleton, bulge.vertex_map[0], bulge.vertex_map[1]));
    for (std::size_t v = 0; v < bulge.skeleton.points.size(); ++v)
        if (std::abs(bulge.skeleton.points[v].y) + std::abs(bulge.skeleton.points[v].z) < 1e-12 &&
            bulge.skeleton.points[v].x > 0 && bulge.skeleton.points[v].x < 0.4)
            ADD_FAILURE() << "a vertex on the bridge at x " << bulge.skeleton.points[v].x;
}

// The same bridge with keep_cut_joint 0.45: the bridge edge 0 - 1 (radius 0.1) would miss the middle joint's ball
// (r 0.2) by (0 + 0.2 - 0.1) / 0.2 = 0.5 of its radius (>= 0.45, off the threshold), so the joint stays, its radius
// lowered to the largest value for which the edge from point 0 meets the criterion: 0.2 >= 1.25 x 0.7 x r sqrt(3)
// (gamma 30 degrees, the joint does not turn, the end's own term 0.7 x 0.1 is smaller), r = 0.2 / (1.25 x 0.7 sqrt(3))
// = 0.13197, times the 0.999 margin; the edge to point 1 is its mirror
// image. At 0.6 the miss is too small and the joint goes as before.
TEST(Adaptation, CutJointIsKeptThinner) {
    const double c = 0.5, s3 = std::sqrt(3.0) / 2;
    Skeleton s;
    s.points = {{0, 0, 0}, {0.4, 0, 0}, {c, s3, 0}, {c, -s3, 0}, {0.4 - c, 0, s3}, {0.4 - c, 0, -s3}, {0.2, 0, 0}};
    s.radii = {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.2};
    s.edges = {{0, 2}, {0, 3}, {1, 4}, {1, 5}, {0, 6}, {6, 1}};
    AdaptationOptions o;
    o.keep_cut_joint = 0.45;
    const mesohex::AdaptationResult kept = mesohex::adapt_skeleton_detailed(s, o);
    const auto at = std::find(kept.skeleton.points.begin(), kept.skeleton.points.end(), Vec3{0.2, 0, 0});
    ASSERT_NE(at, kept.skeleton.points.end());
    const double expected = 0.999 * 0.2 / (1.25 * 0.7 * std::sqrt(3.0));
    EXPECT_NEAR(kept.skeleton.radii[static_cast<std::size_t>(at - kept.skeleton.points.begin())], expected, 1e-12);
    o.keep_cut_joint = 0.6;
    const mesohex::AdaptationResult removed = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(std::find(removed.skeleton.points.begin(), removed.skeleton.points.end(), Vec3{0.2, 0, 0}),
              removed.skeleton.points.end());
}

// bridge_peak_ratio: the bridge of RadiusPeakOnAShortBridgeIsSteppedOver with its bulge off-centre, input vertices
// P = (0.1, 0, 0) r 0.12 and Q = (0.25, 0, 0) r 0.2 between the degree-3 points A = (0,0,0) and B = (0.4,0,0) (r 0.1,
// so the ends' interpolated radius is 0.1 all along): ratios 1.2 at P and 2 at Q, so Q is the peak. By default the
// bridge becomes one edge (the criterion removes every joint: RadiusPeakOnAShortBridgeIsSteppedOver). At 1.5 Q is held:
// bisection of the pieces [0, 0.25] (0.1 + 0.2 > 0.25) and [0.25, 0.4] (0.2 + 0.1 > 0.15) adds nothing, so the bridge
// is exactly A - Q - B with Q at its input position and radius, although the edge A - Q (0.25) fails the criterion
// (1.25 x 0.7 x 0.2 x cot 30 = 0.303). At 2.5 (above Q's ratio) A - B is one edge. Each arm (length 1, r 0.1)
// bisects to 8 edges of 0.125 and the criterion removes its first joint at the junction (0.125 < 1.25 x 0.7 x 0.1 x
// cot 30 = 0.152; 0.25 passes): 7 edges, 28 for the four arms. The raw mesh has 4 hexes per branch edge: 4 x (28 + 2)
// = 120 hexes held, 4 x 29 = 116 without, none inverted (the raw margin limit keeps Q's section inside both junction
// quads).
TEST(Adaptation, RadiusPeakOnABridgeIsHeld) {
    const double c = 0.5, s3 = std::sqrt(3.0) / 2;
    Skeleton s;
    s.points = {{0, 0, 0},        {0.4, 0, 0},       {c, s3, 0},  {c, -s3, 0},
                {0.4 - c, 0, s3}, {0.4 - c, 0, -s3}, {0.1, 0, 0}, {0.25, 0, 0}};
    s.radii = {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.12, 0.2};
    s.edges = {{0, 2}, {0, 3}, {1, 4}, {1, 5}, {0, 6}, {6, 7}, {7, 1}};
    const auto bridge_vertices = [](const Skeleton& k) {
        std::vector<int> on;
        for (std::size_t v = 0; v < k.points.size(); ++v)
            if (std::abs(k.points[v].y) + std::abs(k.points[v].z) < 1e-12 && k.points[v].x > 0 && k.points[v].x < 0.4)
                on.push_back(static_cast<int>(v));
        return on;
    };
    mesohex::PipelineOptions po;
    po.adaptation.bridge_peak_ratio = 1.5;
    const mesohex::AdaptationResult held = mesohex::adapt_skeleton_detailed(s, po.adaptation);
    const std::vector<int> on = bridge_vertices(held.skeleton);
    ASSERT_EQ(on.size(), 1u);
    EXPECT_EQ(held.skeleton.points[on[0]], (Vec3{0.25, 0, 0}));
    EXPECT_DOUBLE_EQ(held.skeleton.radii[on[0]], 0.2);
    EXPECT_EQ(held.skeleton.edges.size(), 30u);
    const mesohex::PipelineResult raw_held = mesohex::run_pipeline(s, po);
    EXPECT_EQ(raw_held.raw.mesh.hexes.size(), 120u);
    EXPECT_EQ(mesohex::compute_quality(raw_held.raw.mesh).inverted, 0);
    for (const double ratio : {2.5, 0.0}) {
        po.adaptation.bridge_peak_ratio = ratio;
        const mesohex::AdaptationResult stepped = mesohex::adapt_skeleton_detailed(s, po.adaptation);
        EXPECT_TRUE(bridge_vertices(stepped.skeleton).empty()) << ratio;
        EXPECT_EQ(stepped.skeleton.edges.size(), 29u) << ratio;
        EXPECT_EQ(mesohex::run_pipeline(s, po).raw.mesh.hexes.size(), 116u) << ratio;
    }
}

// slide_cut_joint: a branch leaves the degree-3 point A = (0,0,0) along +x to the corner C = (0.5,0,0) and turns 90
// degrees to the extremity E = (0.5,0.5,0), r 0.25 everywhere; A's other two arms leave at 60 degrees from +x (in the
// xz-plane): gamma 30, cot sqrt(3). Bisection (density 1): 0.5 < 1.0 cuts at arc 0.5 = C, the halves stop (0.5 < 0.5
// fails). Edge (A, C): reach(A) = 0.7 max(0.25, 0.25 sqrt 3) = 0.3031, reach(C) = 0.25 sin 45 = 0.1768, 1.25 x 0.4799 =
// 0.600 > 0.5: C is removed and A - E is one edge that passes 0.354 = 1.41 r from C. With the slide, C moves along
// C - E to arc 0.5 + 0.5 k / 32 for the first k whose edges pass: P_k = (0.5, u/2, 0), u = k / 32, |AP| = 0.5
// sqrt(1 + u^2), the turn at P has cos = u / sqrt(1 + u^2). k = 14: |AP| 0.5458 < 1.25 (0.3031 + 0.25 sin(turn / 2)) =
// 0.5499; k = 15: 0.5522 >= 0.5465, and |PE| = 0.2656 >= 1.25 x 0.25 sin(turn / 2) = 0.1676. So the joint sits at
// (0.5, 0.234375, 0) with radius 0.25, and nothing is removed.
TEST(Adaptation, CutJointSlidesAwayFromTheJunction) {
    const double c = 0.5, s3 = std::sqrt(3.0) / 2;
    Skeleton s;
    s.points = {{0, 0, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}, {c, 0, s3}, {c, 0, -s3}};
    s.radii = {0.25, 0.25, 0.25, 0.25, 0.25};
    s.edges = {{0, 1}, {1, 2}, {0, 3}, {0, 4}};
    const mesohex::AdaptationResult removed = mesohex::adapt_skeleton_detailed(s);
    EXPECT_EQ(removed.vertex_map[1], -1);
    EXPECT_EQ(removed.turn_removed_joints, 1);
    AdaptationOptions o;
    o.slide_cut_joint = true;
    const mesohex::AdaptationResult slid = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(slid.turn_removed_joints, 0);
    const Vec3 p{0.5, 0.234375, 0};
    const auto at = std::find_if(slid.skeleton.points.begin(), slid.skeleton.points.end(),
                                 [&](const Vec3& x) { return mesohex::distance(x, p) < 1e-12; });
    ASSERT_NE(at, slid.skeleton.points.end());
    EXPECT_DOUBLE_EQ(slid.skeleton.radii[static_cast<std::size_t>(at - slid.skeleton.points.begin())], 0.25);
    EXPECT_EQ(mesohex::euler_characteristic(slid.skeleton), 1);
}

// The slide's gate (slide_cut_joint). (1) Nothing cut: the degree-3 point A = (0,0,0) with the arms of the test above
// (gamma 30, cot sqrt 3), one straight edge A - E, E = (1,0,0), r 0.35. Bisection: 0.7 < 1.0 cuts at J = (0.5,0,0);
// 0.7 < 0.5 fails. Edge (A, J): 1.25 x (0.7 x 0.35 sqrt 3 + 0) = 0.5304 > 0.5: J goes. Ungated it would slide to
// arc 0.5 + 0.5 x 2 / 32 = 0.53125 >= 0.5304 (k = 1: 0.515625 fails), but A - E passes through J's ball with
// J's radius: cut (0 + 0.35 - 0.35) / 0.35 = 0 < 0.01, so J is removed and A - E is one edge. The two arms (length 1,
// r 0.35, 60 degrees from A - E) are the same straight case: 3 joints removed in all, none slid.
// (2) The corner of the test above (cut (0.354 + 0.25 - 0.25) / 0.25 = 1.41) at a degree-4 point: a fourth arm along
// -x leaves gamma 30 (its 120 and 180 degrees are not the smallest angle), so the ungated slide would again reach
// (0.5, 0.234375, 0); a degree-4 point's partition pattern may switch: C is removed as with the slide off.
TEST(Adaptation, CutJointSlideGate) {
    const double c = 0.5, s3 = std::sqrt(3.0) / 2;
    Skeleton straight;
    straight.points = {{0, 0, 0}, {1, 0, 0}, {c, 0, s3}, {c, 0, -s3}};
    straight.radii = {0.35, 0.35, 0.35, 0.35};
    straight.edges = {{0, 1}, {0, 2}, {0, 3}};
    AdaptationOptions o;
    o.slide_cut_joint = true;
    const mesohex::AdaptationResult a = mesohex::adapt_skeleton_detailed(straight, o);
    EXPECT_EQ(a.turn_removed_joints, 3);
    EXPECT_EQ(a.skeleton.points.size(), 4u);
    for (const Vec3& x : a.skeleton.points) EXPECT_FALSE(x.y == 0 && x.z == 0 && x.x > 0 && x.x < 1) << x.x;
    EXPECT_EQ(mesohex::euler_characteristic(a.skeleton), 1);

    Skeleton corner;
    corner.points = {{0, 0, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}, {c, 0, s3}, {c, 0, -s3}, {-1, 0, 0}};
    corner.radii = {0.25, 0.25, 0.25, 0.25, 0.25, 0.25};
    corner.edges = {{0, 1}, {1, 2}, {0, 3}, {0, 4}, {0, 5}};
    const mesohex::AdaptationResult off = mesohex::adapt_skeleton_detailed(corner);
    const mesohex::AdaptationResult on = mesohex::adapt_skeleton_detailed(corner, o);
    EXPECT_EQ(off.vertex_map[1], -1);
    EXPECT_EQ(on.vertex_map[1], -1);
    EXPECT_EQ(on.turn_removed_joints, off.turn_removed_joints);
    EXPECT_EQ(on.skeleton.points, off.skeleton.points);
    for (const Vec3& x : on.skeleton.points) EXPECT_GT(mesohex::distance(x, Vec3{0.5, 0.234375, 0}), 1e-3);

    // (3) The degree-3 corner of CutJointSlidesAwayFromTheJunction, its end A marked as a part of a degree-4 junction
    // of the input (junction_degree 4 at A: a split's half, a trunk's root or t): no slide, C removed as with the
    // slide off; marked 3 (its own degree) or with an empty list it slides to (0.5, 0.234375, 0).
    Skeleton part;
    part.points = {{0, 0, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}, {c, 0, s3}, {c, 0, -s3}};
    part.radii = {0.25, 0.25, 0.25, 0.25, 0.25};
    part.edges = {{0, 1}, {1, 2}, {0, 3}, {0, 4}};
    const mesohex::AdaptationResult plain = mesohex::adapt_skeleton_detailed(part);
    const mesohex::AdaptationResult held = mesohex::adapt_skeleton_detailed(part, o, {}, {4});
    EXPECT_EQ(held.vertex_map[1], -1);
    EXPECT_EQ(held.skeleton.points, plain.skeleton.points);
    const mesohex::AdaptationResult three = mesohex::adapt_skeleton_detailed(part, o, {}, {3, 0, 0, 0, 0});
    EXPECT_EQ(three.turn_removed_joints, 0);
    EXPECT_EQ(three.skeleton.points, mesohex::adapt_skeleton_detailed(part, o).skeleton.points);
    EXPECT_NE(three.skeleton.points, plain.skeleton.points);

    // (4) Two points of degree 3 joined by a bridge of length 0.1 < collapse_spread (r_A + r_B) = 0.35: A = (0.05, 0,
    // 0) with the corner branch of CutJointSlidesAwayFromTheJunction (C = (0.5, 0, 0), E = (0.5, 0.5, 0)) and an arm to
    // (0.05 + c, 0, s3), B = (-0.05, 0, 0) with arms to (0.05 + c, 0, -s3) and (-1, 0, 0). Adaptation collapses the
    // bridge into one point of degree 3 + 3 - 2 = 4 at the origin (merge_drifts: 0.05 < 0.7 x 0.25): the corner of (2),
    // its two arms 57.6 degrees from +x (gamma 28.8; ungated the joint slides to (0.5, 0.265625, 0), the 17th of 32
    // steps). The merged point's partition pattern may switch: no slide, the output is the slide-off one.
    Skeleton pair;
    pair.points = {{0.05, 0, 0},  {0.5, 0, 0},        {0.5, 0.5, 0}, {0.05 + c, 0, s3},
                   {-0.05, 0, 0}, {0.05 + c, 0, -s3}, {-1, 0, 0}};
    pair.radii.assign(pair.points.size(), 0.25);
    pair.edges = {{0, 1}, {1, 2}, {0, 3}, {0, 4}, {4, 5}, {4, 6}};
    const mesohex::AdaptationResult merged_off = mesohex::adapt_skeleton_detailed(pair);
    const mesohex::AdaptationResult merged_on = mesohex::adapt_skeleton_detailed(pair, o);
    EXPECT_EQ(merged_on.collapsed_bridges, 1);
    EXPECT_EQ(merged_on.vertex_map[0], merged_on.vertex_map[4]);
    EXPECT_EQ(merged_on.skeleton.points, merged_off.skeleton.points);
    EXPECT_EQ(merged_on.skeleton.radii, merged_off.skeleton.radii);
}

// An L-shaped polyline: every new joint lies on one of the two original segments.
TEST(Adaptation, SamplesOnBentPolyline) {
    Skeleton s;
    s.points = {{0, 0, 0}, {10, 10, 0}};
    s.radii = {0.3, 0.3};
    std::vector<Vec3> xs;
    for (int i = 1; i <= 10; ++i) xs.push_back({double(i), 0, 0});
    for (int i = 1; i < 10; ++i) xs.push_back({10, double(i), 0});
    add_path(s, 0, 1, xs, 0.3);
    AdaptationOptions o;
    o.turn_safety = 0;  // keep every bisection sample
    const Skeleton out = mesohex::adapt_skeleton(s, o);
    ASSERT_EQ(mesohex::euler_characteristic(out), 1);
    for (const Vec3& x : out.points) {
        const bool on_first = std::abs(x.y) < 1e-12 && x.x >= 0 && x.x <= 10;
        const bool on_second = std::abs(x.x - 10) < 1e-12 && x.y >= 0 && x.y <= 10;
        EXPECT_TRUE(on_first || on_second) << x.x << " " << x.y;
    }
}

// Two branching points 1 apart with radius 0.8 (1 < 0.7 x (0.8 + 0.8) = 1.12: collapse_spread), each with two long
// arms: the mean rule (overlap_merge_ratio 0) merges them at the midpoint with the mean radius. By default the balls'
// overlap (0.8 + 0.8) / 1 = 1.6 >= overlap_merge_ratio 1.2 places the merged ball on the union's span [-0.8, 1.8]:
// centre 0.5, radius (1.3 + 0.8) / 2 = 1.05.
TEST(Adaptation, ShortBridgeCollapsesToMidpoint) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {-10, 5, 0}, {-10, -5, 0}, {11, 5, 0}, {11, -5, 0}};
    s.radii = {0.8, 0.8, 0.5, 0.5, 0.5, 0.5};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}};
    const mesohex::AdaptationResult d = mesohex::adapt_skeleton_detailed(s);
    EXPECT_EQ(d.collapsed_bridges, 1);
    EXPECT_EQ(d.skeleton.points[0], (Vec3{0.5, 0, 0}));
    EXPECT_DOUBLE_EQ(d.skeleton.radii[0], 1.05);
    AdaptationOptions mean;
    mean.overlap_merge_ratio = 0;
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s, mean);
    EXPECT_EQ(r.collapsed_bridges, 1);
    EXPECT_EQ(r.vertex_map[0], r.vertex_map[1]);
    EXPECT_EQ(r.vertex_map[0], 0);
    EXPECT_EQ(r.skeleton.points[0], (Vec3{0.5, 0, 0}));
    EXPECT_DOUBLE_EQ(r.skeleton.radii[0], 0.8);
    EXPECT_EQ(degrees(r.skeleton)[0], 4);
    EXPECT_EQ(count_degree_at_least(r.skeleton, 3), 1);
    EXPECT_EQ(mesohex::euler_characteristic(r.skeleton), 1);
    // The same bridge 2 long (0.8 + 0.8 < 2) stays.
    s.points[1] = {2, 0, 0};
    const mesohex::AdaptationResult kept = mesohex::adapt_skeleton_detailed(s, mean);
    EXPECT_EQ(kept.collapsed_bridges, 0);
    EXPECT_EQ(count_degree_at_least(kept.skeleton, 3), 2);
    // With collapsing off, the short bridge stays too.
    s.points[1] = {1, 0, 0};
    AdaptationOptions o = mean;
    o.collapse_short_bridges = false;
    EXPECT_EQ(count_degree_at_least(mesohex::adapt_skeleton(s, o), 3), 2);
    // Radius 0.6: the balls overlap (1.2 > 1) but the ends would lie 0.5 from the midpoint, more than 0.7 x 0.6 = 0.42:
    // no collapse by the mean rule; with collapse_spread 1 (the reference's rule, r_a + r_b > chord) it collapses.
    s.radii[0] = s.radii[1] = 0.6;
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s, mean).collapsed_bridges, 0);
    o.collapse_short_bridges = true;
    o.collapse_spread = 1;
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s, o).collapsed_bridges, 1);
}

// Two branching points whose balls overlap: A = (0, 0, 0), r 0.6 and B = (0.8, 0, 0), r 0.4, (r_A + r_B) / |AB| =
// 1.25, each with two long arms. The mean rule alone (overlap_merge_ratio 0) refuses (the ends would lie 0.4 from the
// midpoint, more than collapse_spread x 0.5 = 0.35). With overlap_merge_ratio 1.2 (the default) they merge into one
// vertex of degree 4 on the union's
// span along x, [-0.6, 1.2]: centre 0.3, radius (0.9 + 0.6) / 2 = 0.75. At 1.3 (above 1.25) they stay. Where the mean
// rule would collapse too (collapse_spread 2), the overlap rule places the pair (0.3, r 0.75; the mean: 0.4, r 0.5).
// Not for points the repair made from a larger junction, nor beyond overlap_merge_max_degree.
TEST(Adaptation, OverlappingJunctionBallsMergeOnTheUnionsSpan) {
    Skeleton s;
    s.points = {{0, 0, 0}, {0.8, 0, 0}, {-10, 5, 0}, {-10, -5, 0}, {10.8, 5, 0}, {10.8, -5, 0}};
    s.radii = {0.6, 0.4, 0.3, 0.3, 0.3, 0.3};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}};
    AdaptationOptions o;
    o.overlap_merge_ratio = 0;
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s, o).collapsed_bridges, 0);
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s).collapsed_bridges, 1);
    o.overlap_merge_ratio = 1.2;
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(r.collapsed_bridges, 1);
    EXPECT_EQ(r.vertex_map[0], 0);
    EXPECT_EQ(r.vertex_map[1], 0);
    EXPECT_NEAR(mesohex::distance(r.skeleton.points[0], Vec3{0.3, 0, 0}), 0.0, 1e-12);
    EXPECT_NEAR(r.skeleton.radii[0], 0.75, 1e-12);
    EXPECT_EQ(degrees(r.skeleton)[0], 4);
    EXPECT_EQ(count_degree_at_least(r.skeleton, 3), 1);
    EXPECT_EQ(mesohex::euler_characteristic(r.skeleton), 1);
    o.overlap_merge_ratio = 1.3;
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s, o).collapsed_bridges, 0);
    o.collapse_spread = 2;
    const mesohex::AdaptationResult mean = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(mean.collapsed_bridges, 1);
    EXPECT_NEAR(mesohex::distance(mean.skeleton.points[0], Vec3{0.4, 0, 0}), 0.0, 1e-12);
    EXPECT_NEAR(mean.skeleton.radii[0], 0.5, 1e-12);
    o.overlap_merge_ratio = 1.2;
    const mesohex::AdaptationResult span = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_NEAR(mesohex::distance(span.skeleton.points[0], Vec3{0.3, 0, 0}), 0.0, 1e-12);
    EXPECT_NEAR(span.skeleton.radii[0], 0.75, 1e-12);
    // Points the repair made from a junction of degree 4 (junction_degree 4 above their own 3: a split's halves) are
    // not merged by overlap (the mean rule, collapse_spread 2, still merges them at its midpoint).
    const mesohex::AdaptationResult split = mesohex::adapt_skeleton_detailed(s, o, {}, {4, 4});
    EXPECT_EQ(split.collapsed_bridges, 1);
    EXPECT_NEAR(mesohex::distance(split.skeleton.points[0], Vec3{0.4, 0, 0}), 0.0, 1e-12);
    o.collapse_spread = 0.7;
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s, o, {}, {4, 4}).collapsed_bridges, 0);
    // A third arm at B: the merged junction would have degree 5
    // > overlap_merge_max_degree 4; with no limit (0) it merges.
    s.points.push_back({10.8, 0, 5});
    s.radii.push_back(0.3);
    s.edges.push_back({1, 6});
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s, o).collapsed_bridges, 0);
    o.overlap_merge_max_degree = 0;
    const mesohex::AdaptationResult five = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(five.collapsed_bridges, 1);
    EXPECT_EQ(degrees(five.skeleton)[0], 5);
}

// overlap_ball by hand: equal radii 0.5 at distance 0.4 -> the midpoint, radius 0.5 + 0.4 / 4 = 0.6 (the absorbed
// ball's rule); a ball inside the other (r 1 at the origin, r 0.3 at 0.2) -> the larger ball; coincident centres ->
// the larger radius.
// A triangle of branching points: A = (0, 0, 0) and C = (0.75, 0, 0), radius 0.5 ((0.5 + 0.5) / 0.75 = 1.33 >= 1.2,
// below the mean rule's 1 / 0.7 = 1.43), both joined to X = (0.375, 2, 0) (radius 0.3; its bridges 2.03 long, ratio
// 0.39), each with one long arm. Merging A and C would turn the triangle into a cycle of two branches: no collapse.
// Without the edge C - X (C with two arms instead) the pair merges by overlap.
TEST(Adaptation, OverlapMergeSkipsAPairWithACommonNeighbour) {
    Skeleton s;
    s.points = {{0, 0, 0}, {0.75, 0, 0}, {0.375, 2, 0}, {-10, -5, 0}, {10.75, -5, 0}, {0.375, 12, 0}};
    s.radii = {0.5, 0.5, 0.3, 0.3, 0.3, 0.3};
    s.edges = {{0, 1}, {0, 2}, {1, 2}, {0, 3}, {1, 4}, {2, 5}};
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s).collapsed_bridges, 0);
    s.edges = {{0, 1}, {0, 2}, {1, 5}, {0, 3}, {1, 4}};
    s.points[5] = {10.75, 5, 0};
    const mesohex::AdaptationResult tree = mesohex::adapt_skeleton_detailed(s);
    EXPECT_EQ(tree.collapsed_bridges, 1);
    EXPECT_EQ(tree.vertex_map[0], tree.vertex_map[1]);
}

TEST(Adaptation, OverlapBallByHand) {
    const mesohex::OverlapBall equal = mesohex::overlap_ball({0, 0, 0}, 0.5, {0, 0.4, 0}, 0.5);
    EXPECT_NEAR(mesohex::distance(equal.centre, Vec3{0, 0.2, 0}), 0.0, 1e-12);
    EXPECT_NEAR(equal.radius, 0.6, 1e-12);
    const mesohex::OverlapBall inside = mesohex::overlap_ball({0, 0, 0}, 1, {0.2, 0, 0}, 0.3);
    EXPECT_NEAR(mesohex::distance(inside.centre, Vec3{0, 0, 0}), 0.0, 1e-12);
    EXPECT_NEAR(inside.radius, 1.0, 1e-12);
    const mesohex::OverlapBall same = mesohex::overlap_ball({1, 2, 3}, 0.2, {1, 2, 3}, 0.7);
    EXPECT_EQ(same.centre, (Vec3{1, 2, 3}));
    EXPECT_EQ(same.radius, 0.7);
}

// Three branching points in a row 1 apart, radius 0.8: each bridge alone may collapse (1 < 1.12), but merging the
// chain whole would put its ends 1 from the mean position, more than 0.7 x 0.8 = 0.56: one collapse, two branching
// points left (the merged one of degree 4, the third of degree 3).
TEST(Adaptation, ChainOfShortBridgesDoesNotDrift) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {-10, 5, 0}, {-10, -5, 0}, {1, 10, 0}, {12, 5, 0}, {12, -5, 0}};
    s.radii = {0.8, 0.8, 0.8, 0.5, 0.5, 0.5, 0.5, 0.5};
    s.edges = {{0, 1}, {1, 2}, {0, 3}, {0, 4}, {1, 5}, {2, 6}, {2, 7}};
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s);
    EXPECT_EQ(r.collapsed_bridges, 1);
    EXPECT_EQ(count_degree_at_least(r.skeleton, 3), 2);
    EXPECT_EQ(count_degree_at_least(r.skeleton, 4), 1);
    EXPECT_EQ(mesohex::euler_characteristic(r.skeleton), 1);
    // With collapse_spread 2 (and the mean rule alone: overlap_merge_ratio 0) the whole chain merges into one vertex of
    // degree 5 at (1, 0, 0).
    AdaptationOptions o;
    o.collapse_spread = 2;
    o.overlap_merge_ratio = 0;
    const mesohex::AdaptationResult all = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(all.collapsed_bridges, 2);
    EXPECT_EQ(count_degree_at_least(all.skeleton, 3), 1);
    EXPECT_EQ(count_degree_at_least(all.skeleton, 5), 1);
    EXPECT_EQ(all.skeleton.points[static_cast<std::size_t>(all.vertex_map[1])], (Vec3{1, 0, 0}));
}

// Closed ring of 6 joints with a radius too large to bisect: it keeps 3 edges, anchored at its smallest id.
TEST(Adaptation, RingKeepsThreeEdges) {
    Skeleton s;
    for (int i = 0; i < 6; ++i) {
        const double a = 2 * M_PI * i / 6;
        s.points.push_back({std::cos(a), std::sin(a), 0});
        s.radii.push_back(5.0);
        s.edges.push_back({i, (i + 1) % 6});
    }
    const Skeleton out = mesohex::adapt_skeleton(s);
    EXPECT_EQ(out.points.size(), 3u);
    EXPECT_EQ(out.edges.size(), 3u);
    EXPECT_EQ(out.points[0], s.points[0]);
    for (const int d : degrees(out)) EXPECT_EQ(d, 2);
    // A thin ring is resampled to more edges and stays closed (V - E = 0).
    for (double& r : s.radii) r = 0.05;
    const Skeleton thin = mesohex::adapt_skeleton(s);
    EXPECT_GE(thin.edges.size(), 6u);
    EXPECT_EQ(mesohex::euler_characteristic(thin), 0);
    for (const int d : degrees(thin)) EXPECT_EQ(d, 2);
}

// A loop starting and ending at one branching point (plus a tail): the loop keeps at least 3 edges.
TEST(Adaptation, LoopAtBranchingPointKeepsThreeEdges) {
    Skeleton s;
    s.points = {{0, 0, 0}, {-5, 0, 0}};
    s.radii = {3.0, 1.0};
    s.edges = {{0, 1}};
    add_path(s, 0, 0, {{1, 1, 0}, {2, 0, 0}, {1, -1, 0}}, 3.0);
    const Skeleton out = mesohex::adapt_skeleton(s);
    EXPECT_EQ(mesohex::euler_characteristic(out), 0);
    EXPECT_EQ(degrees(out)[0], 3);
    EXPECT_GE(out.edges.size(), 4u);  // tail + at least 3 loop edges
    for (std::size_t i = 0; i < out.edges.size(); ++i)
        for (std::size_t j = i + 1; j < out.edges.size(); ++j)
            EXPECT_NE(std::minmax(out.edges[i][0], out.edges[i][1]), std::minmax(out.edges[j][0], out.edges[j][1]));
}

// A 2x1 quad leaflet with a long oversampled branch at a corner: leaflet unchanged, branch resampled.
TEST(Adaptation, LeafletsUntouchedBranchesResampled) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {12, 0, 0}};
    s.radii = {0.2, 0.2, 0.2, 0.2, 0.2, 0.2, 0.2};
    s.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}};
    s.edges = {{0, 1}, {1, 2}, {3, 4}, {4, 5}, {0, 3}, {1, 4}, {2, 5}};
    std::vector<Vec3> xs;
    for (int i = 1; i < 100; ++i) xs.push_back({2 + 0.1 * i, 0, 0});
    add_path(s, 2, 6, xs, 0.2);
    const Skeleton out = mesohex::adapt_skeleton(s);
    for (int v = 0; v < 7; ++v) {
        EXPECT_EQ(out.points[v], s.points[v]);
        EXPECT_EQ(out.radii[v], s.radii[v]);
    }
    EXPECT_EQ(out.faces, s.faces);
    using Edges = std::vector<std::array<int, 2>>;
    EXPECT_EQ(Edges(out.edges.begin(), out.edges.begin() + 7), Edges(s.edges.begin(), s.edges.begin() + 7));
    // Branch of length 10 at r = 0.2, density 1: 10 -> 5 -> ... -> 0.3125 (0.4 < 0.3125 fails): 32 edges. At the
    // leaflet corner the nearest other edge is at 90 degrees (gamma 45, cot 1): reach max(0.2, 0.2) = 0.2, so the
    // first edge must be >= 1.25 * 0.2 = 0.25 <= 0.3125: every joint stays.
    EXPECT_EQ(out.edges.size(), 7u + 32u);
    EXPECT_NEAR(mesohex::distance(out.points[2], out.points[out.edges[7][1]]), 0.3125, 1e-12);
    // With branching_reach 1.5 the demand is 1.25 * 0.3 = 0.375 > 0.3125: the first joint goes, the first edge is
    // 0.625 and there are 31.
    AdaptationOptions cautious;
    cautious.branching_reach = 1.5;
    const Skeleton out2 = mesohex::adapt_skeleton(s, cautious);
    EXPECT_EQ(out2.edges.size(), 7u + 31u);
    EXPECT_NEAR(mesohex::distance(out2.points[2], out2.points[out2.edges[7][1]]), 0.625, 1e-12);
    EXPECT_EQ(mesohex::euler_characteristic(out), mesohex::euler_characteristic(s));
}

// A near-zero radius at an extremity must not make the bisection run towards it.
TEST(Adaptation, TinyExtremityRadiusStaysBounded) {
    Skeleton s = straight(1.0, 99, 0.1);
    s.radii[1] = 7e-5;  // the far extremity
    const Skeleton out = mesohex::adapt_skeleton(s);
    // Radius floor 0.25 * 0.1: no edge shorter than (0.025 + 0.025) / 2 / density.
    EXPECT_LE(out.edges.size(), 40u);
    for (const std::array<int, 2>& e : out.edges)
        EXPECT_GT(mesohex::distance(out.points[e[0]], out.points[e[1]]), 0.02);
}

// A U-turn (two right-angle corners 3 apart, r = 1): after adaptation every edge satisfies the documented
// anti-overlap bound |ab| >= turn_safety * (r_a sin(theta_a/2) + r_b sin(theta_b/2)).
TEST(Adaptation, SharpTurnsSatisfySectionBound) {
    Skeleton s;
    s.points = {{0, 0, 0}, {0, 3, 0}};
    s.radii = {1, 1};
    std::vector<Vec3> xs;
    for (int i = 1; i <= 16; ++i) xs.push_back({0.5 * i, 0, 0});
    for (int i = 1; i <= 5; ++i) xs.push_back({8, 0.5 * i, 0});
    for (int i = 16; i >= 1; --i) xs.push_back({0.5 * i, 3, 0});
    add_path(s, 0, 1, xs, 1.0);
    for (const double density : {1.0, 2.0, 4.0}) {
        AdaptationOptions o;
        o.density = density;
        const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s, o);
        const Skeleton& out = r.skeleton;
        // Walk the output chain from vertex 0.
        std::vector<int> chain{0};
        std::vector<bool> used(out.edges.size(), false);
        for (bool grew = true; grew;) {
            grew = false;
            for (std::size_t e = 0; e < out.edges.size(); ++e) {
                if (used[e] || (out.edges[e][0] != chain.back() && out.edges[e][1] != chain.back())) continue;
                used[e] = true;
                chain.push_back(out.edges[e][0] == chain.back() ? out.edges[e][1] : out.edges[e][0]);
                grew = true;
            }
        }
        ASSERT_EQ(chain.size(), out.points.size());
        const auto reach = [&](std::size_t k) {
            if (k == 0 || k + 1 == chain.size()) return 0.0;  // extremities
            const Vec3 u = mesohex::normalized(out.points[chain[k]] - out.points[chain[k - 1]]);
            const Vec3 w = mesohex::normalized(out.points[chain[k + 1]] - out.points[chain[k]]);
            return out.radii[chain[k]] * std::sqrt(std::max(0.0, 0.5 * (1 - mesohex::dot(u, w))));
        };
        for (std::size_t k = 0; k + 1 < chain.size(); ++k)
            EXPECT_GE(mesohex::distance(out.points[chain[k]], out.points[chain[k + 1]]),
                      o.turn_safety * (reach(k) + reach(k + 1)) - 1e-12);
        if (density == 4.0) {
            EXPECT_GT(r.turn_removed_joints, 0);  // edges of 0.5 cannot carry a 45-degree turn
        }
    }
}

// Star of 3 orthogonal straight arms of length 16, r = 1, density 2: arms are cut into 16 edges of 1. At the branching
// point beta = 90 degrees, gamma = 45 (cot 1): reach f * max(1, 1 * 1) = f, so the first edge must be at least
// 1.25 f. With f = free_branching_reach = 1: the first joint (1 away) goes, the next (2 away) stays: 15 edges per arm.
// With the default f = 0.7: 1 >= 0.875, every joint stays: 16 edges per arm.
TEST(Adaptation, FirstJointKeepsClearOfBranchingPoint) {
    Skeleton s;
    s.points = {{0, 0, 0}, {16, 0, 0}, {0, 16, 0}, {0, 0, 16}};
    s.radii = {1, 1, 1, 1};
    s.edges = {{0, 1}, {0, 2}, {0, 3}};
    AdaptationOptions o;
    o.density = 2;
    o.free_branching_reach = 1.0;
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(r.turn_removed_joints, 3);
    EXPECT_EQ(r.skeleton.edges.size(), 45u);
    EXPECT_EQ(r.skeleton.points.size(), 46u);
    for (const std::array<int, 2>& e : r.skeleton.edges) {
        const double len = mesohex::distance(r.skeleton.points[e[0]], r.skeleton.points[e[1]]);
        EXPECT_NEAR(len, (e[0] == 0 || e[1] == 0) ? 2.0 : 1.0, 1e-12);
    }
    o.free_branching_reach = AdaptationOptions{}.free_branching_reach;
    ASSERT_EQ(o.free_branching_reach, 0.7);
    const mesohex::AdaptationResult d = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(d.turn_removed_joints, 0);
    EXPECT_EQ(d.skeleton.edges.size(), 48u);
    for (const std::array<int, 2>& e : d.skeleton.edges)
        EXPECT_NEAR(mesohex::distance(d.skeleton.points[e[0]], d.skeleton.points[e[1]]), 1.0, 1e-12);
}

// The free reach applies at branching points without a leaflet only: the same star whose branching point is also the
// corner of a unit leaflet square keeps branching_reach there. The square's edges leave at 90 degrees from the arms
// along x and y and the z arm (beta = 90, cot 1), so each arm's first joint (1 away) goes again: 15 edges per arm.
TEST(Adaptation, LeafletVertexKeepsTheBranchingReach) {
    Skeleton s;
    s.points = {{0, 0, 0}, {-16, 0, 0}, {0, -16, 0}, {0, 0, 16}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.radii = {1, 1, 1, 1, 0.3, 0.3, 0.3};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {4, 5}, {5, 6}, {6, 0}};
    s.faces = {{0, 4, 5, 6}};
    AdaptationOptions o;
    o.density = 2;
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s, o);
    EXPECT_EQ(r.turn_removed_joints, 3);
    EXPECT_EQ(r.skeleton.edges.size(), 4u + 45u);
}

// A branch rooted inside a 2 x 2 plate of unit quads (centre vertex 4), straight up 3, radius 0.1 everywhere.
// Bisection: 0.1 + 0.1 < 3 / 2^k until k = 4: 16 edges of 0.1875. Rooted, the end reaches root_extent x the mean
// leaflet edge = 0.5 (the sphere and cone terms give 0.1): the first edge needs 1.25 x 0.5 = 0.625, so the joints at
// 0.1875, 0.375 and 0.5625 go and the first joint is at 0.75: 13 edges. With root_extent 0 all 16 stay.
TEST(Adaptation, RootedBranchClearsItsPatch) {
    Skeleton s;
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i) s.points.push_back({double(i), double(j), 0});
    s.points.push_back({1, 1, 3});
    s.radii.assign(s.points.size(), 0.1);
    s.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}};
    mesohex::add_face_edges(s);
    s.edges.push_back({4, 9});
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s);
    EXPECT_EQ(r.turn_removed_joints, 3);
    EXPECT_EQ(r.skeleton.edges.size(), 12u + 13u);
    double lowest = 1e9;
    for (std::size_t v = 10; v < r.skeleton.points.size(); ++v) lowest = std::min(lowest, r.skeleton.points[v].z);
    EXPECT_NEAR(lowest, 0.75, 1e-12);
    AdaptationOptions off;
    off.root_extent = 0;
    EXPECT_EQ(mesohex::adapt_skeleton(s, off).edges.size(), 12u + 16u);
}

TEST(Adaptation, DeterministicAndEulerPreserving) {
    Skeleton s;
    s.points = {{0, 0, 0}, {5, 0, 0}, {0, 5, 0}, {0, 0, 5}};
    s.radii = {0.5, 0.2, 0.3, 0.1};
    s.edges = {{0, 1}, {0, 2}};
    add_path(s, 0, 3, {{0, 0, 1}, {0.1, 0, 2}, {0, 0.2, 3}, {0, 0, 4}}, 0.2);
    add_path(s, 1, 2, {{3, 2, 0}, {2, 3, 0}}, 0.25);
    const Skeleton a = mesohex::adapt_skeleton(s);
    const Skeleton b = mesohex::adapt_skeleton(s);
    EXPECT_EQ(a, b);
    EXPECT_EQ(mesohex::euler_characteristic(a), mesohex::euler_characteristic(s));
    EXPECT_EQ(count_degree_at_least(a, 3), count_degree_at_least(s, 3));
}

// Seeded random graphs (trees with extra cycle edges, random radii, oversampled branches): invariants hold.
TEST(Adaptation, RandomGraphsKeepInvariants) {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> u(-1.0, 1.0), ur(0.01, 0.5);
    for (int trial = 0; trial < 200; ++trial) {
        Skeleton s;
        const int nodes = 2 + static_cast<int>(rng() % 12);
        for (int v = 0; v < nodes; ++v) {
            s.points.push_back({3 * u(rng), 3 * u(rng), 3 * u(rng)});
            s.radii.push_back(ur(rng));
        }
        std::set<std::pair<int, int>> links;
        for (int v = 1; v < nodes; ++v) links.insert({static_cast<int>(rng() % v), v});
        for (int extra = static_cast<int>(rng() % 3); extra > 0; --extra) {
            const int a = static_cast<int>(rng() % nodes), b = static_cast<int>(rng() % nodes);
            if (a != b) links.insert(std::minmax(a, b));
        }
        for (const auto& [a, b] : links) {  // each link becomes an oversampled polyline with a little noise
            std::vector<Vec3> inner;
            const int k = static_cast<int>(rng() % 8);
            for (int i = 1; i <= k; ++i) {
                const double f = double(i) / (k + 1);
                inner.push_back(s.points[a] + f * (s.points[b] - s.points[a]) + 0.05 * Vec3{u(rng), u(rng), u(rng)});
            }
            add_path(s, a, b, inner, ur(rng));
        }
        const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s);
        const Skeleton& out = r.skeleton;
        // Each dropped repeated edge (a flat cycle after a re-attachment) raises V - E + F by one.
        ASSERT_EQ(mesohex::euler_characteristic(out), mesohex::euler_characteristic(s) + r.duplicate_edges) << trial;
        if (r.reattached_edges == 0 && r.merged_vertices == 0) {
            EXPECT_EQ(count_degree_at_least(out, 3), count_degree_at_least(s, 3) - r.collapsed_bridges) << trial;
        }
        EXPECT_GE(smallest_angle_at_vertices(out), AdaptationOptions{}.coincident_angle) << trial;
        std::set<std::pair<int, int>> seen;
        for (const std::array<int, 2>& e : out.edges) {
            EXPECT_NE(e[0], e[1]);
            EXPECT_TRUE(seen.insert(std::minmax(e[0], e[1])).second) << trial;
        }
        for (std::size_t v = 0; v < out.points.size(); ++v) {
            EXPECT_TRUE(mesohex::is_finite(out.points[v]));
            EXPECT_GT(out.radii[v], 0.0);
        }
        EXPECT_EQ(mesohex::adapt_skeleton(s), out);
    }
}

TEST(Adaptation, RejectsMissingOrBadRadii) {
    Skeleton s = straight(4, 3, 1.0);
    s.radii.clear();
    try {
        (void)mesohex::adapt_skeleton(s);
        ADD_FAILURE();
    } catch (const mesohex::Error& e) {
        EXPECT_EQ(e.code(), mesohex::ErrorCode::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("radius"), std::string::npos) << e.what();
    }
    s = straight(4, 3, 1.0);
    s.radii[2] = 0;
    EXPECT_THROW((void)mesohex::adapt_skeleton(s), mesohex::Error);
}

// Repeated and folded edges. The straight branch 0 -> 2 -> 3 -> 4 -> 1 (L = 4, r = 1, along +x), a branch 0 -> 5 =
// (-3.6, 0, 0) (so 0 is a branching point), and the edge (0, 1) given twice. (1, 0) repeats (0, 1): dropped (1).
// (0, 1) and (0, 2) leave 0 along +x: (0, 1) moves to (2, 1) (2 is now a branching point), then to (3, 1), then to
// (4, 1), which exists: dropped (2). Re-attachments: at 0, 2, 3 = 3. What is left is the straight branch 5 -> 0 -> 1 of
// length 7.6, resampled to 4 edges of 1.9 (7.6 -> 3.8 -> 1.9, 2 < 1.9 fails): 5 vertices, 4 edges; V - E = 1 (input:
// 6 - 7 = -1, +1 per dropped edge).
TEST(Adaptation, RepeatedAndCoincidentEdgesAreRepaired) {
    Skeleton s = straight(4, 3, 1.0);
    s.points.push_back({-3.6, 0, 0});
    s.radii.push_back(1.0);
    s.edges.push_back({0, 5});
    s.edges.push_back({0, 1});
    s.edges.push_back({1, 0});
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s);
    EXPECT_EQ(r.duplicate_edges, 2);
    EXPECT_EQ(r.reattached_edges, 3);
    EXPECT_EQ(r.merged_vertices, 0);
    EXPECT_EQ(r.skeleton.points.size(), 5u);
    EXPECT_EQ(r.skeleton.edges.size(), 4u);
    EXPECT_EQ(mesohex::euler_characteristic(r.skeleton), 1);
    EXPECT_EQ(count_degree_at_least(r.skeleton, 3), 0);
}

// A zero-length edge at a branching point: vertices 0 = (0,0,0) and 1 = (1e-6,0,0) (1e-6 <= 1e-3 x r), branches
// 1 -> 2 = (3.6,0,0), 0 -> 3 = (0,3.6,0), 0 -> 4 = (0,-3.6,0), r = 1. 0 and 1 merge at (5e-7, 0, 0): a T junction of
// three branches of length 3.6, each resampled to 2 edges (2 < 3.6, 2 >= 1.8; the first joint at 1.8 clears 0.7 x
// max(1, 1 x cot 45 deg) x 1.25): 1 + 3 + 3 = 7 vertices, 6 edges; input vertices 0 and 1 map to output vertex 0.
TEST(Adaptation, ZeroLengthEdgeIsContracted) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1e-6, 0, 0}, {3.6, 0, 0}, {0, 3.6, 0}, {0, -3.6, 0}};
    s.radii.assign(5, 1.0);
    s.edges = {{0, 1}, {1, 2}, {0, 3}, {0, 4}};
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s);
    EXPECT_EQ(r.merged_vertices, 1);
    EXPECT_EQ(r.duplicate_edges, 0);
    EXPECT_EQ(r.skeleton.points.size(), 7u);
    EXPECT_EQ(r.skeleton.edges.size(), 6u);
    EXPECT_EQ(r.vertex_map[0], 0);
    EXPECT_EQ(r.vertex_map[1], 0);
    EXPECT_NEAR(r.skeleton.points[0].x, 5e-7, 1e-15);
    EXPECT_EQ(degrees(r.skeleton)[0], 3);
    AdaptationOptions off;
    off.merge_distance = 0;  // only exactly zero-length edges: this one stays (a bridge of length 1e-6)
    EXPECT_EQ(mesohex::adapt_skeleton_detailed(s, off).merged_vertices, 0);
}

// A small tree with a (nearly) duplicate direction: branching point c = (0,0,0), r = 1 everywhere, branches to
// a = (2,0,0), b = (6, y, 0), d = (0,3.6,0), e = (0,-3.6,0). For y = 0 (collinear) and y = 0.1 (0.95 degrees) the
// edges (c, a) and (c, b) leave c less than 2 degrees apart: (c, b) becomes (a, b), a becomes a joint of the branch
// c -> a -> b (length ~6: bisected 6 -> 3 -> 1.5, 4 edges), d and e 2 edges each (3.6 -> 1.8). Raw mesh: 4 hexes per
// branch edge = 4 x 8 = 32, plus 8 for the compatible block at c (a T: +x, +y, -y; docs/blocks.md) = 40, as
// predicted, none inverted. Without the repair the collinear case stops in the sphere partition (directions
// coincide).
TEST(Adaptation, CoincidentBranchesMeshThroughSharedTrunk) {
    for (const double y : {0.0, 0.1}) {
        Skeleton s;
        s.points = {{0, 0, 0}, {2, 0, 0}, {6, y, 0}, {0, 3.6, 0}, {0, -3.6, 0}};
        s.radii.assign(5, 1.0);
        s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
        const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s);
        EXPECT_EQ(r.reattached_edges, 1) << y;
        EXPECT_EQ(r.skeleton.edges.size(), 8u) << y;
        EXPECT_EQ(r.vertex_map[1], -1) << y;  // a is a joint now, resampled away
        // (0, 1) is a stub of (0, 2) (it ends inside its tube): by default skeleton_repair absorbs it before
        // adaptation; here adaptation's own repair is under test.
        mesohex::PipelineOptions adaptation_only;
        adaptation_only.repair.absorb_stubs = false;
        // Without the absorption c keeps degree 4 and the junction split would take the coincident pair first (it
        // does not know adaptation's coincident_angle: 3 inverted raw hexes then, docs/junctions.md).
        adaptation_only.repair.junction_split = 0;
        const mesohex::PipelineResult res = mesohex::run_pipeline(s, adaptation_only);
        EXPECT_EQ(res.predicted.compatible_blocks, 1) << y;
        EXPECT_EQ(res.raw.mesh.hexes.size(), 40u) << y;
        EXPECT_EQ(res.predicted.hexes, 40) << y;
        EXPECT_EQ(mesohex::compute_quality(res.raw.mesh).inverted, 0) << y;
        const mesohex::PipelineResult absorbed = mesohex::run_pipeline(s, {});
        EXPECT_EQ(absorbed.absorbed_stubs, 1) << y;
        EXPECT_EQ(mesohex::compute_quality(absorbed.raw.mesh).inverted, 0) << y;
        EXPECT_EQ(absorbed.analysis.counts.branching_points, 1) << y;  // t's degree: the other three branches
        if (y == 0.0) {
            mesohex::PipelineOptions no_repair = adaptation_only;
            no_repair.adaptation.coincident_angle = 0;
            EXPECT_THROW((void)mesohex::run_pipeline(s, no_repair), mesohex::Error);
        }
    }
}

// Degeneracies of lattice (voxel) graphs like the reference's 5 120-vertex sample: at c = (0,0,0) (parent (0,0,-1))
// one child (0,0,2) and one (1,0,1) whose branch comes back to (0,0,1), the midpoint of the first child's edge; at
// (0,0,-1) siblings (1,0,-1) and (2,0,-1) on one ray. Without the repairs the mesher stops; with them the whole run
// works, the raw mesh has the predicted hex count, and no two edges at a vertex are closer than coincident_angle.
TEST(Adaptation, LatticeGraphDegeneraciesMesh) {
    Skeleton s;
    s.points = {{0, 0, 0}, {0, 0, 2}, {1, 0, 1}, {0, 0, 1}, {0, 0, -1}, {1, 0, -1}, {2, 0, -1}, {0, 0, -2}};
    s.edges = {{0, 1}, {0, 2}, {2, 3}, {4, 0}, {4, 5}, {4, 6}, {4, 7}};
    s.radii.assign(s.points.size(), 0.25);
    const mesohex::AdaptationResult r = mesohex::adapt_skeleton_detailed(s);
    EXPECT_GE(r.reattached_edges, 1);  // (4, 6) -> (5, 6)
    EXPECT_GE(smallest_angle_at_vertices(r.skeleton), AdaptationOptions{}.coincident_angle);
    const mesohex::PipelineResult res = mesohex::run_pipeline(s, {});
    EXPECT_EQ(static_cast<long>(res.raw.mesh.hexes.size()), res.predicted.hexes);
    EXPECT_EQ(static_cast<long>(res.raw.mesh.hexes.size()),
              4 * static_cast<long>(res.skeleton.edges.size()) + 8 * res.predicted.compatible_blocks);
    mesohex::PipelineOptions no_repair;
    no_repair.adaptation.coincident_angle = 0;
    no_repair.repair.absorb_stubs = false;  // (4, 5) is a stub of (4, 6): skeleton_repair would absorb it
    no_repair.repair.trunks = false;
    EXPECT_THROW((void)mesohex::run_pipeline(s, no_repair), mesohex::Error);
}
