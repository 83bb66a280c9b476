// finish_mesh on a case checkable on paper: one unit hex inside its own cube surface.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdio>

#include <tbb/global_control.h>

#include "hex_fixtures.h"
#include "mesohex/finish.h"

using namespace mesohex;

namespace {

HexMesh unit_hex() {
    HexMesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    m.hexes = {{0, 1, 2, 3, 4, 5, 6, 7}};
    return m;
}

// The unit cube [0, 1]^3 as 12 triangles, counter-clockwise seen from outside.
TriangleMesh unit_cube_surface() {
    TriangleMesh s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    for (const auto& q : quads) {
        s.triangles.push_back({q[0], q[1], q[2]});
        s.triangles.push_back({q[0], q[2], q[3]});
    }
    return s;
}

// The chain with the padding layer over the whole boundary. The unit hex fills its cube (and the stretched block's
// rims land on its box's rims), so the selective padding (the default) would leave faces bare
// (SelectivePaddingLeavesAMatchingBoxBare); the cases below count the padding hexes.
FinishOptions full_padding() {
    FinishOptions o;
    o.pad_selective = false;
    return o;
}

}  // namespace

TEST(Finish, UnitHexInItsCube) {
    FinishOptions o = full_padding();
    o.levels = 1;  // the default would choose 2 here (see LevelsFromTheDomainSize)
    const FinishResult r = finish_mesh(unit_hex(), unit_cube_surface(), o);
    // input, pad, subdivide, fit, smooth (no untangle: nothing inverted; no quality pass: min SJ above 0.3).
    ASSERT_EQ(r.stages.size(), 5u);
    EXPECT_EQ(r.stages[0].stage, "input");
    EXPECT_EQ(r.stages[0].hexes, 1);
    EXPECT_DOUBLE_EQ(r.stages[0].sj_min, 1.0);
    // Padding a cube: one hex per face -> 7 hexes, 8 new vertices.
    EXPECT_EQ(r.stages[1].stage, "pad");
    EXPECT_EQ(r.stages[1].hexes, 7);
    EXPECT_EQ(r.stages[1].vertices, 16);
    // One 1 -> 8 level: 56 hexes; vertices = V + E + F + C = 16 + 32 + 24 + 7 = 79.
    EXPECT_EQ(r.subdivision_levels, 1);
    EXPECT_EQ(r.stages[2].stage, "subdivide");
    EXPECT_EQ(r.stages[2].hexes, 56);
    EXPECT_EQ(r.stages[2].vertices, 79);
    EXPECT_EQ(r.stages[3].stage, "fit");
    EXPECT_EQ(r.stages[4].stage, "smooth");
    EXPECT_GE(r.stages[4].sj_min, r.stages[3].sj_min);
    EXPECT_FALSE(r.untangled);
    EXPECT_EQ(r.domain_flipped_triangles, 0);
    // Final mesh: valid, nothing inverted, boundary on the cube.
    EXPECT_EQ(r.mesh.hexes.size(), 56u);
    EXPECT_TRUE(r.quality.validation.valid());
    EXPECT_EQ(r.quality.inverted, 0);
    EXPECT_GT(r.quality.sj_min, 0.0);
    EXPECT_EQ(r.quality.euler_characteristic, 1);
    ASSERT_TRUE(r.distance_measured);
    EXPECT_NEAR(r.distance.diagonal, std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(r.distance.max, r.distance.relative_max * r.distance.diagonal, 1e-12);
    // The boundary rows are a penalty (weight lambda = 10): the boundary stops short of the cube by O(1 / lambda)
    // (measured 1.37 % of the diagonal).
    EXPECT_LT(r.distance.relative_max, 0.02);
}

// Selective padding: the unit hex fills its cube, every rim of the raw boundary (12 edges, normal angle 90) lands on
// the cube's rim, so the 6 faces stay bare and the pad stage adds nothing; one level gives 8 hexes, already on the
// cube (a fixed point of the fit: scaled Jacobian 1 up to the solver's tolerance).
TEST(Finish, SelectivePaddingLeavesAMatchingBoxBare) {
    FinishOptions o;
    o.levels = 1;
    o.pad_selective = true;
    const FinishResult r = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(r.pad_mode, "selective");
    EXPECT_EQ(r.pad_boundary_quads, 6);
    EXPECT_EQ(r.pad_bare_quads, 6);
    EXPECT_EQ(r.pad_regions, 6);
    EXPECT_EQ(r.pad_bare_regions, 6);
    EXPECT_EQ(r.pad_sharp_edges, 12);
    EXPECT_EQ(r.pad_matched_edges, 12);
    ASSERT_GE(r.stages.size(), 2u);
    EXPECT_EQ(r.stages[1].stage, "pad");
    EXPECT_EQ(r.stages[1].hexes, 1);
    EXPECT_EQ(r.stages[1].vertices, 8);
    EXPECT_EQ(r.mesh.hexes.size(), 8u);
    EXPECT_EQ(r.quality.inverted, 0);
    EXPECT_GT(r.quality.sj_min, 0.99);
    ASSERT_TRUE(r.distance_measured);
    EXPECT_LT(r.distance.relative_max, 1e-3);
}

// Two levels with one fitted: the second is inherited (stage "refine" after the smoothing, then "refine-smooth"):
// 56 x 8 hexes, the fit ran on the 56-hex mesh, nothing inverted, the boundary still within the level-1 bound of the
// cube.
TEST(Finish, InheritedLevelIsRefinedNotFitted) {
    FinishOptions o = full_padding();
    o.levels = 2;
    o.fit_levels = 1;
    const FinishResult r = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(r.subdivision_levels, 2);
    EXPECT_EQ(r.inherited_levels, 1);
    ASSERT_EQ(r.stages.size(), 7u);
    EXPECT_EQ(r.stages[2].stage, "subdivide");
    EXPECT_EQ(r.stages[2].hexes, 56);
    EXPECT_EQ(r.stages[3].stage, "fit");
    EXPECT_EQ(r.stages[3].hexes, 56);
    EXPECT_EQ(r.stages[4].stage, "smooth");
    EXPECT_EQ(r.stages[5].stage, "refine");
    EXPECT_EQ(r.stages[5].hexes, 448);
    // Hexes below inherit_smooth_sj (0.8) after the refinement: the local smoothing runs on them and their rings. It
    // never takes the worst hex at a vertex below min(its value, the smoothing's target 0.6), and raises the average.
    ASSERT_LT(r.stages[5].sj_min, o.inherit_smooth_sj);
    EXPECT_EQ(r.stages[6].stage, "refine-smooth");
    EXPECT_EQ(r.stages[6].hexes, 448);
    EXPECT_GE(r.stages[6].sj_min, std::min(r.stages[5].sj_min, o.smoothing.target_sj));
    EXPECT_GT(r.stages[6].sj_avg, r.stages[5].sj_avg);
    EXPECT_EQ(r.quality.sj_min, r.stages[6].sj_min);
    EXPECT_EQ(r.mesh.hexes.size(), 448u);
    EXPECT_TRUE(r.quality.validation.valid());
    EXPECT_EQ(r.quality.inverted, 0);
    ASSERT_TRUE(r.distance_measured);
    EXPECT_LT(r.distance.relative_max, 0.02);
    // Local smoothing off: the refinement is the last stage, the mesh its result.
    FinishOptions no_smoothing = o;
    no_smoothing.inherit_smooth_sj = 0;
    const FinishResult refined = finish_mesh(unit_hex(), unit_cube_surface(), no_smoothing);
    ASSERT_EQ(refined.stages.size(), 6u);
    EXPECT_EQ(refined.stages[5].stage, "refine");
    EXPECT_EQ(refined.stages[5].sj_min, r.stages[5].sj_min);
    EXPECT_EQ(refined.quality.sj_min, r.stages[5].sj_min);
    EXPECT_EQ(refined.mesh.hexes, r.mesh.hexes);
    EXPECT_NE(refined.mesh.points, r.mesh.points);  // the local smoothing moved vertices
    // fit_levels < 0: every level fitted, as before.
    o.fit_levels = -1;
    const FinishResult all = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(all.inherited_levels, 0);
    EXPECT_EQ(all.stages[2].hexes, 448);
}

// With a 100x larger surface weight the boundary lands on the cube (every boundary vertex projects onto the face,
// edge or corner it is pushed to, so the boundary quads tile the cube surface): the distance shrinks ~100x.
// The progress callback is passed through: one call per fit step.
TEST(Finish, SurfaceWeightAndProgress) {
    FinishOptions o = full_padding();
    int calls = 0;
    o.fitting.progress = [&calls](const FitProgress&) { ++calls; };
    const FinishResult soft = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(calls, soft.fit_iterations);
    EXPECT_GT(calls, 0);
    // Every stage records its iterations: the fit's are the fit's count, one-pass stages have none.
    int fits = 0, smooths = 0;
    for (const FinishStage& st : soft.stages) {
        if (st.stage == "fit") {
            ++fits;
            EXPECT_EQ(st.iterations, soft.fit_iterations);
        } else if (st.stage == "input" || st.stage == "pad" || st.stage == "subdivide") {
            EXPECT_EQ(st.iterations, 0);
        } else if (st.stage == "smooth") {
            ++smooths;
            EXPECT_GE(st.iterations, 1);
        }
    }
    EXPECT_EQ(fits, 1);
    EXPECT_EQ(smooths, 1);
    o.fitting.lambda = 1000;
    const FinishResult hard = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_LT(hard.distance.max, 1e-4);
    EXPECT_LT(hard.distance.max, soft.distance.max / 50);
    EXPECT_EQ(hard.quality.inverted, 0);
}

TEST(Finish, InwardDomainIsFlippedAndStagesCanBeSkipped) {
    TriangleMesh inward = unit_cube_surface();
    for (auto& t : inward.triangles) std::swap(t[1], t[2]);
    FinishOptions o;
    o.pad = false;
    o.subdivide = false;
    o.fit = false;
    const FinishResult r = finish_mesh(unit_hex(), inward, o);
    EXPECT_EQ(r.domain_flipped_triangles, 12);
    ASSERT_EQ(r.stages.size(), 1u);  // input only
    EXPECT_EQ(r.mesh, unit_hex());
    // The hex is its own domain: every sample of either side lies on the other.
    ASSERT_TRUE(r.distance_measured);
    EXPECT_LT(r.distance.max, 1e-12);
}

TEST(Finish, LevelsFromSize) {
    FinishOptions o;
    o.pad = false;
    o.fit = false;
    o.size = 0.3;  // unit edges: 1 -> 0.5 -> 0.25, two levels
    const FinishResult r = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(r.subdivision_levels, 2);
    EXPECT_EQ(r.mesh.hexes.size(), 64u);
    EXPECT_EQ(r.quality.inverted, 0);
    EXPECT_NEAR(r.quality.sj_min, 1.0, 1e-12);
    EXPECT_LT(r.distance.max, 1e-12);
}

// Default levels from the domain size: the padded unit hex has 32 edges (12 of length 1, 12 of 1.5, 8 of
// 0.25 sqrt(3)), mean 1.046; the cube's diagonal is sqrt(3) = 1.732. min_resolution 16 asks for edges <= 0.108:
// 4 halvings, capped at max_auto_levels = 2 (7 x 64 = 448 hexes); min_resolution 1 asks for <= 1.732: no halving,
// at least 1 level (56 hexes).
TEST(Finish, LevelsFromTheDomainSize) {
    FinishOptions o = full_padding();
    o.fit = false;
    const FinishResult fine = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(fine.subdivision_levels, 2);
    EXPECT_EQ(fine.mesh.hexes.size(), 448u);
    o.min_resolution = 1;
    const FinishResult coarse = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(coarse.subdivision_levels, 1);
    EXPECT_EQ(coarse.mesh.hexes.size(), 56u);
}

// The work budget max_hexes lowers the levels chosen from the domain size: the padded unit hex (7 hexes) asks for 2
// levels (448 hexes); a budget of 447 leaves 1 level (56), of 55 none (7 hexes), of 448 both; given levels stay.
TEST(Finish, HexBudgetLowersTheAutomaticLevels) {
    FinishOptions o = full_padding();
    o.fit = false;
    o.max_hexes = 447;
    const FinishResult one = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(one.subdivision_levels, 1);
    EXPECT_EQ(one.mesh.hexes.size(), 56u);
    o.max_hexes = 55;
    const FinishResult none = finish_mesh(unit_hex(), unit_cube_surface(), o);
    EXPECT_EQ(none.subdivision_levels, 0);
    EXPECT_EQ(none.mesh.hexes.size(), 7u);
    o.max_hexes = 448;
    EXPECT_EQ(finish_mesh(unit_hex(), unit_cube_surface(), o).subdivision_levels, 2);
    o.max_hexes = 55;
    o.levels = 2;
    EXPECT_EQ(finish_mesh(unit_hex(), unit_cube_surface(), o).subdivision_levels, 2);
}

// A raw mesh of poor hexes gets one level more: the unit hex sheared by 2 along x (every corner frame 1 / sqrt(5) =
// 0.447, below poor_raw_sj_avg = 0.5) gets 2 levels where the domain size asks for 1 (min_resolution 0.01), 7 x 64 =
// 448 hexes; not when 448 exceeds max_auto_hexes, nor with the rule off, nor for the unit hex itself, nor when a hex
// is inverted before the subdivision.
TEST(Finish, PoorRawMeshGetsOneLevelMore) {
    HexMesh sheared = unit_hex();
    for (Vec3& p : sheared.points) p.x += 2 * p.z;
    ASSERT_NEAR(scaled_jacobians(sheared)[0], 1 / std::sqrt(5.0), 1e-12);
    FinishOptions o = full_padding();
    o.fit = false;
    o.min_resolution = 0.01;
    const FinishResult poor = finish_mesh(sheared, unit_cube_surface(), o);
    EXPECT_EQ(poor.subdivision_levels, 2);
    EXPECT_EQ(poor.mesh.hexes.size(), 448u);
    o.max_auto_hexes = 447;
    EXPECT_EQ(finish_mesh(sheared, unit_cube_surface(), o).subdivision_levels, 1);
    o.max_auto_hexes = 448;
    o.poor_raw_sj_avg = 0;
    EXPECT_EQ(finish_mesh(sheared, unit_cube_surface(), o).subdivision_levels, 1);
    o.poor_raw_sj_avg = 0.5;  // the unit hex itself is not poor
    EXPECT_EQ(finish_mesh(unit_hex(), unit_cube_surface(), o).subdivision_levels, 1);
    // Not when the mesh to subdivide has an inverted hex (here without padding: the sheared hex beside an inverted
    // unit hex, its top face listed first).
    o.pad = false;
    EXPECT_EQ(finish_mesh(sheared, unit_cube_surface(), o).subdivision_levels, 2);
    HexMesh folded = sheared;
    const HexMesh u = unit_hex();
    for (const Vec3& p : u.points) folded.points.push_back(p + Vec3{5, 0, 0});
    folded.hexes.push_back({12, 13, 14, 15, 8, 9, 10, 11});
    ASSERT_LT(scaled_jacobians(folded)[1], 0);
    EXPECT_EQ(finish_mesh(folded, unit_cube_surface(), o).subdivision_levels, 1);
}

// The whole chain (pad, subdivide, fit with the two-sided pull, quality pass) gives the same mesh, bit for bit, with 1
// and with 2 threads: here the unit hex grows into the larger cube [-0.5, 1.5]^3.
TEST(Finish, SameMeshForAnyThreadCount) {
    TriangleMesh big = unit_cube_surface();
    for (Vec3& p : big.points) p = Vec3{-0.5, -0.5, -0.5} + 2.0 * p;
    FinishOptions options;
    options.levels = 2;
    FinishResult one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = finish_mesh(unit_hex(), big, options);
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = finish_mesh(unit_hex(), big, options);
    }
    EXPECT_EQ(one.mesh, two.mesh);
    EXPECT_EQ(one.fit_iterations, two.fit_iterations);
    EXPECT_EQ(one.quality.inverted, 0);
    std::printf("[finish] unit hex in [-0.5, 1.5]^3, 2 levels: %zu hexes, SJ min %.3f, Hausdorff %.2f %%\n",
                one.mesh.hexes.size(), one.quality.sj_min, 100 * one.distance.relative_max);
}

namespace {

// A finished result set by hand: its inverted count, min / avg SJ and Hausdorff distance (fraction of the diagonal).
FinishResult result(long inverted, double sj_min, double sj_avg, double hausdorff) {
    FinishResult r;
    r.quality.inverted = inverted;
    r.quality.sj_min = sj_min;
    r.quality.sj_avg = sj_avg;
    r.distance_measured = true;
    r.distance.relative_max = hausdorff;
    return r;
}

}  // namespace

// The goals a second attempt is weighed by (MeshGoals: min 0.3, average 0.85, Hausdorff 1 %), on hand-set results.
TEST(Finish, GoalsAndTheBetterOfTwoResults) {
    const FinishResult meets = result(0, 0.66, 0.92, 0.0076);    // auto cactus, cautious reach
    const FinishResult far = result(0, 0.23, 0.91, 0.042);       // auto cactus, default reach: min and distance
    const FinishResult fat = result(0, 0.104, 0.899, 0.0179);    // dino, default reach
    const FinishResult fat1 = result(0, 0.097, 0.877, 0.0316);   // dino, cautious reach
    const FinishResult inverted = result(2, -0.1, 0.95, 0.002);  // everything but the inversions is fine
    EXPECT_EQ(mesohex::missed_goals(meets), 0);
    EXPECT_EQ(mesohex::missed_goals(far), 2);
    EXPECT_EQ(mesohex::missed_goals(inverted), 2);                    // inverted, and min < 0.3
    EXPECT_EQ(mesohex::missed_goals(result(0, 0.3, 0.85, 0.01)), 0);  // the goals are inclusive
    FinishResult unmeasured = far;
    unmeasured.distance_measured = false;
    EXPECT_EQ(mesohex::missed_goals(unmeasured), 1);
    EXPECT_TRUE(mesohex::better_finish(meets, far));
    EXPECT_FALSE(mesohex::better_finish(far, meets));
    EXPECT_TRUE(mesohex::better_finish(fat, fat1));  // both miss 2 goals: the smaller distance wins
    EXPECT_FALSE(mesohex::better_finish(fat1, fat));
    EXPECT_TRUE(mesohex::better_finish(far, inverted));  // no inverted hex first, whatever the rest
    EXPECT_FALSE(mesohex::better_finish(meets, meets));  // strict
    mesohex::MeshGoals loose;
    loose.hausdorff = 0.05;
    EXPECT_EQ(mesohex::missed_goals(far, loose), 1);
}

// The choice between two results that both miss (MeshOptions::retry_by_shortfall): goal_shortfall is the sum of the
// logs of the factors by which each missed goal is missed. Armadillo's two attempts (both miss min SJ and Hausdorff):
// 0.190 / 2.39 % gives ln(0.3 / 0.19) + ln(2.39) = 0.45676 + 0.87129 = 1.32805, 0.133 / 2.31 % gives
// ln(0.3 / 0.133) + ln(2.31) = 0.81343 + 0.83725 = 1.65068: the first is kept, where better_finish (the smaller
// distance) keeps the second.
TEST(Finish, ShortfallRanksTwoResultsThatMissTheSameGoals) {
    const FinishResult first = result(0, 0.190, 0.911, 0.0239);
    const FinishResult second = result(0, 0.133, 0.906, 0.0231);
    EXPECT_NEAR(mesohex::goal_shortfall(first), std::log(0.3 / 0.19) + std::log(2.39), 1e-12);
    EXPECT_NEAR(mesohex::goal_shortfall(first), 1.32805, 1e-5);
    EXPECT_NEAR(mesohex::goal_shortfall(second), 1.65068, 1e-5);
    EXPECT_EQ(mesohex::goal_shortfall(result(0, 0.3, 0.85, 0.01)), 0.0);  // every goal met (inclusive)
    // The average counts like the others: 0.8 against 0.85 is ln(0.85 / 0.8) = 0.06062.
    EXPECT_NEAR(mesohex::goal_shortfall(result(0, 0.5, 0.8, 0.005)), std::log(0.85 / 0.8), 1e-12);
    EXPECT_TRUE(std::isinf(mesohex::goal_shortfall(result(0, 0.0, 0.9, 0.005))));  // a flat hex
    EXPECT_TRUE(mesohex::better_finish_by_shortfall(first, second));
    EXPECT_FALSE(mesohex::better_finish_by_shortfall(second, first));
    EXPECT_TRUE(mesohex::better_finish(second, first));  // the default order: the smaller distance
    // Fewer goals missed still comes first: 0.29 / 5 % (two goals, shortfall 1.64) is not kept over 0.05 / 0.9 %
    // (one goal, ln 6 = 1.79), nor is a mesh with an inverted hex over either.
    const FinishResult one_goal = result(0, 0.05, 0.9, 0.009);
    EXPECT_TRUE(mesohex::better_finish_by_shortfall(one_goal, result(0, 0.29, 0.9, 0.05)));
    EXPECT_TRUE(mesohex::better_finish_by_shortfall(one_goal, result(1, 0.29, 0.9, 0.009)));
    EXPECT_FALSE(mesohex::better_finish_by_shortfall(first, first));  // strict
}

// Padding towards the domain (FinishOptions::pad_to_domain): the 2 x 2 x 2 block stretched to 2 x 2 x 6. The vertex in
// the middle of its face y = 0, (1, 0, 3), has boundary edges of 1 (along x) and 3 (along z): the layer's own offset
// is 0.25 x 1, the cap 0.25 x mean edge 2 = 0.5. Its new vertex goes along -y as far as the domain's face y = -h,
// within [0.25, 0.5]; with pad_to_domain 0 it stays at 0.25.
TEST(Finish, PaddingReachesTowardsTheDomain) {
    HexMesh block = mesohex::test::make_block(2, 2, 2);
    for (Vec3& p : block.points) p.z *= 3;
    const auto padded_y = [&](double h, double pad_to_domain, bool inset = false) {
        TriangleMesh box = unit_cube_surface();
        for (Vec3& p : box.points) p = Vec3{-1 + 4 * p.x, -h + (2 + 2 * h) * p.y, -1 + 8 * p.z};
        FinishOptions o = full_padding();
        o.subdivide = false;
        o.fit = false;
        o.smooth = false;
        o.pad_improve_sj = 0;
        o.measure_distance = false;
        o.pad_to_domain = pad_to_domain;
        o.pad_inset = inset;
        const FinishResult r = finish_mesh(block, box, o);
        double y = 1;
        for (std::size_t v = block.points.size(); v < r.mesh.points.size(); ++v)
            if (std::abs(r.mesh.points[v].x - 1) < 1e-12 && std::abs(r.mesh.points[v].z - 3) < 1e-12 &&
                r.mesh.points[v].y < 0)
                y = r.mesh.points[v].y;
        return y;
    };
    EXPECT_NEAR(padded_y(0.4, 0.25), -0.4, 1e-12);   // the domain's face
    EXPECT_NEAR(padded_y(1.0, 0.25), -0.5, 1e-12);   // the cap
    EXPECT_NEAR(padded_y(0.1, 0.25), -0.25, 1e-12);  // the layer's own offset
    EXPECT_NEAR(padded_y(1.0, 0.0), -0.25, 1e-12);   // off
    // With the inset (pad_inset): the layer that reaches 0.15 past the face is moved back to end on it; where it does
    // not reach past it, nothing moves.
    EXPECT_NEAR(padded_y(0.1, 0.25, true), -0.1, 1e-12);
    EXPECT_NEAR(padded_y(0.4, 0.25, true), -0.4, 1e-12);
}
