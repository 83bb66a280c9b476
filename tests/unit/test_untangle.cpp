// Untangling: folded blocks get unfolded, untangled meshes are left alone.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include "hex_fixtures.h"
#include "mesohex/core/error.h"
#include "mesohex/core/validate.h"
#include "mesohex/post/quality.h"
#include "mesohex/post/untangle.h"

using namespace mesohex;
using mesohex::test::make_block;

namespace {
// Vertex (i, j, k) of make_block(n, n, n).
int vid(int n, int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); }

// A quality pass (target SJ 0.8, max_rounds rounds) on a mesh of make_block(4, 4, 4)'s vertices with the 8 vertices of
// the hex [1, 2]^3 frozen.
UntangleOptions quality_pass_with_frozen_hex(const HexMesh& m, int max_rounds) {
    UntangleOptions options;
    options.target_sj = 0.8;
    options.max_rounds = max_rounds;
    options.frozen.assign(m.points.size(), false);
    for (int k = 1; k <= 2; ++k)
        for (int j = 1; j <= 2; ++j)
            for (int i = 1; i <= 2; ++i) options.frozen[static_cast<std::size_t>(vid(4, i, j, k))] = true;
    return options;
}
}  // namespace

TEST(Untangle, CentreVertexPushedThroughAFace) {
    // 2x2x2 block: the centre vertex (1,1,1) pushed through the top faces of the 4 upper hexes, to (1.1, 0.9, 2.4):
    // the 4 upper hexes fold.
    HexMesh m = make_block(2, 2, 2);
    m.points[static_cast<std::size_t>(vid(2, 1, 1, 1))] = {1.1, 0.9, 2.4};
    const QualityReport before = compute_quality(m);
    ASSERT_GT(before.inverted, 0);
    std::vector<UntangleProgress> rounds;
    UntangleOptions options;
    options.progress = [&](const UntangleProgress& p) { rounds.push_back(p); };
    const UntangleResult r = untangle(m, options);
    EXPECT_EQ(r.inverted_before, before.inverted);
    EXPECT_EQ(r.inverted_after, 0);
    EXPECT_TRUE(r.inverted_hexes.empty());
    EXPECT_GT(r.sj_min_after, 0);
    EXPECT_EQ(compute_quality(r.mesh).inverted, 0);
    EXPECT_EQ(static_cast<int>(rounds.size()), r.rounds);
    // Only the interior vertex moved; by symmetry of the ideal it goes back near the centre.
    for (std::size_t v = 0; v < m.points.size(); ++v)
        if (v != static_cast<std::size_t>(vid(2, 1, 1, 1))) {
            EXPECT_EQ(r.mesh.points[v], m.points[v]);
        }
    EXPECT_LT(distance(r.mesh.points[static_cast<std::size_t>(vid(2, 1, 1, 1))], Vec3{1, 1, 1}), 0.1);
}

TEST(Untangle, Block3x3x3WithAnInteriorVertexThroughItsNeighbour) {
    // Interior vertex (1,1,1) moved past the interior vertex (2,1,1) and through the faces between them.
    HexMesh m = make_block(3, 3, 3);
    m.points[static_cast<std::size_t>(vid(3, 1, 1, 1))] = {2.4, 1.2, 1.1};
    ASSERT_GT(compute_quality(m).inverted, 0);
    const UntangleResult r = untangle(m);
    EXPECT_GT(r.inverted_before, 0);
    EXPECT_EQ(r.inverted_after, 0);
    const QualityReport q = compute_quality(r.mesh);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_GT(q.sj_min, 0.3);
}

TEST(Untangle, SeveralFoldsAndWholeMeshRegion) {
    HexMesh m = make_block(4, 4, 4);
    m.points[static_cast<std::size_t>(vid(4, 1, 1, 1))] = {1.0, 1.0, -0.3};  // through the bottom skin
    m.points[static_cast<std::size_t>(vid(4, 3, 3, 3))] = {2.2, 2.1, 3.0};
    m.points[static_cast<std::size_t>(vid(4, 2, 2, 2))] = {2.6, 2.7, 2.4};
    ASSERT_GT(compute_quality(m).inverted, 0);
    UntangleOptions options;
    options.region_rings = -1;
    const UntangleResult r = untangle(m, options);
    EXPECT_EQ(r.inverted_after, 0);
    EXPECT_EQ(compute_quality(r.mesh).inverted, 0);
}

TEST(Untangle, UntangledMeshIsUnchanged) {
    HexMesh m = make_block(3, 2, 2);
    m.points[static_cast<std::size_t>(1 + 4 * (1 + 3 * 1))] += Vec3{0.2, -0.1, 0.1};  // skewed, not inverted
    ASSERT_EQ(compute_quality(m).inverted, 0);
    const UntangleResult r = untangle(m);
    EXPECT_EQ(r.mesh, m);
    EXPECT_EQ(r.rounds, 0);
    EXPECT_EQ(r.inverted_before, 0);
    EXPECT_EQ(r.inverted_after, 0);
    EXPECT_TRUE(validate(r.mesh).valid());
}

TEST(Untangle, ReportsWhatCannotBeFixed) {
    // A single mirrored hex: all its vertices are on the boundary, which is fixed: it stays inverted, and says so.
    HexMesh m = mesohex::test::make_unit_cube();
    for (Vec3& p : m.points) p.x = -p.x;
    const UntangleResult r = untangle(m);
    EXPECT_EQ(r.inverted_before, 1);
    EXPECT_EQ(r.inverted_after, 1);
    EXPECT_EQ(r.inverted_hexes, std::vector<int>{0});
    EXPECT_EQ(r.mesh, m);
}

TEST(Untangle, DeterministicForAnyThreadCount) {
    HexMesh m = make_block(4, 4, 4);
    m.points[static_cast<std::size_t>(vid(4, 2, 2, 2))] = {3.4, 2.2, 1.9};
    UntangleResult one, two;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = untangle(m);
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = untangle(m);
    }
    EXPECT_EQ(one.mesh, two.mesh);
    EXPECT_EQ(one.inverted_after, 0);
}

TEST(Untangle, RejectsBadInput) {
    HexMesh m = mesohex::test::make_unit_cube();
    m.hexes[0][5] = 8;
    EXPECT_THROW(untangle(m), Error);
}

TEST(Untangle, BoundaryVertexFoldNeedsAMovingBoundary) {
    // 2x2x2 block, the bottom face centre (1,1,0) pushed up to z = 2.5, above the top face centre: the centre vertex
    // cannot lie above the one and below the other, so with the boundary fixed
    // nothing can repair it (and the result says so); with the boundary softly attached it is repaired.
    HexMesh m = make_block(2, 2, 2);
    m.points[static_cast<std::size_t>(vid(2, 1, 1, 0))] = {1.0, 1.0, 2.5};
    const long folded = compute_quality(m).inverted;
    ASSERT_GT(folded, 0);
    const UntangleResult fixed = untangle(m);
    EXPECT_GT(fixed.inverted_after, 0);
    EXPECT_EQ(static_cast<long>(fixed.inverted_hexes.size()), fixed.inverted_after);
    UntangleOptions options;
    options.fix_boundary = false;
    const UntangleResult moving = untangle(m, options);
    EXPECT_EQ(moving.inverted_after, 0);
    EXPECT_EQ(compute_quality(moving.mesh).inverted, 0);
    EXPECT_LT(moving.mesh.points[static_cast<std::size_t>(vid(2, 1, 1, 0))].z, 1.0);
}

TEST(Untangle, HexWithPositiveCornersAndANegativeCentreFrame) {
    // A twisted hex (half-integer corners): its 8 corner frames are positive (smallest normalized determinant 0.075)
    // but its centre frame is not (xi = (2.5, 3, -1.5), eta = (1.5, 0, 0.5), zeta = (1.5, 1, 0.5): det -3.5,
    // normalized -0.28), so its scaled Jacobian is negative and it
    // counts as inverted. The untangling energy includes the centre
    // frame: with its vertices free (softly attached) it is repaired.
    HexMesh m;
    m.points = {{1, 0.5, 1}, {0.5, 1, 0}, {2, 2, 1.5}, {1, 0, 1}, {1, 1.5, 2.5}, {2, 1, 0}, {2, 1.5, 1.5}, {1, 0.5, 0}};
    m.hexes = {{0, 1, 2, 3, 4, 5, 6, 7}};
    const QualityReport before = compute_quality(m);
    ASSERT_EQ(before.inverted, 1);
    EXPECT_NEAR(before.sj_min, -0.2828, 1e-4);
    UntangleOptions options;
    options.fix_boundary = false;
    const UntangleResult r = untangle(m, options);
    EXPECT_EQ(r.inverted_before, 1);
    EXPECT_EQ(r.inverted_after, 0);
    EXPECT_GT(compute_quality(r.mesh).sj_min, 0);
}

// A quality pass that cannot raise the minimum: in a 4 x 4 x 4 block the squeezed hex [1, 2]^3 has all 8 vertices
// frozen, so its scaled Jacobian (the minimum) is fixed whatever the 19 other interior vertices do. The pass stops
// after quality_patience rounds and returns the start; with quality_patience 0 it runs every round.
TEST(Untangle, QualityPassThatCannotRaiseTheMinimumStopsAfterItsPatience) {
    HexMesh m = make_block(4, 4, 4);
    m.points[static_cast<std::size_t>(vid(4, 1, 1, 1))] = {1.3, 1.32, 1.28};
    const QualityReport before = compute_quality(m);
    ASSERT_EQ(before.inverted, 0);
    ASSERT_LT(before.sj_min, 0.5);
    UntangleOptions options = quality_pass_with_frozen_hex(m, 12);
    const UntangleResult r = untangle(m, options);
    EXPECT_EQ(r.rounds, 5);
    EXPECT_GT(r.iterations, 0);  // the 19 free interior vertices did move in those rounds
    EXPECT_EQ(r.mesh.points, m.points);
    EXPECT_EQ(r.sj_min_after, r.sj_min_before);
    EXPECT_NEAR(r.sj_min_before, before.sj_min, 1e-12);
    options.quality_patience = 0;
    const UntangleResult all = untangle(m, options);
    EXPECT_EQ(all.rounds, 12);
    EXPECT_EQ(all.sj_min_after, all.sj_min_before);  // the minimum is the frozen hex's in every state
}

// A quality pass whose minimum rises once and then cannot rise further: the frozen squeezed hex [1, 2]^3 of the test
// above, and the hex [2, 3]^3 squeezed harder by its free corner (3, 3, 3) moved about 0.32 towards (2, 2, 2) (scaled
// Jacobian 0.07 against the frozen hex's 0.18). Round 1 puts (3, 3, 3) back near its place, so the minimum rises to
// the frozen hex's scaled Jacobian, which no round can change. The pass stops once quality_patience rounds in a row
// leave its best state unchanged and returns that state, the same minimum as a pass that runs every round.
TEST(Untangle, QualityPassStopsWhenItsBestStateStopsImproving) {
    HexMesh m = make_block(4, 4, 4);
    m.points[static_cast<std::size_t>(vid(4, 1, 1, 1))] = {1.3, 1.32, 1.28};
    const double frozen_sj = compute_quality(m).sj_min;
    m.points[static_cast<std::size_t>(vid(4, 3, 3, 3))] = {2.68, 2.664, 2.696};
    const QualityReport before = compute_quality(m);
    ASSERT_EQ(before.inverted, 0);
    ASSERT_LT(before.sj_min, frozen_sj - 0.05);
    UntangleOptions options = quality_pass_with_frozen_hex(m, 30);
    const UntangleResult r = untangle(m, options);
    EXPECT_NEAR(r.sj_min_after, frozen_sj, 1e-9);
    EXPECT_GE(r.rounds, options.quality_patience + 1);  // the round that rose, then the patience
    EXPECT_LT(r.rounds, options.max_rounds);
    options.quality_patience = 0;
    const UntangleResult all = untangle(m, options);
    EXPECT_EQ(all.rounds, options.max_rounds);
    EXPECT_NEAR(all.sj_min_after, r.sj_min_after, 1e-12);
}

// Quality pass (target_sj > 0): no hex is inverted, but an interior vertex pushed toward a corner leaves thin hexes
// around it; the pass moves the interior vertices near them back toward the regular grid and keeps the boundary.
TEST(Untangle, QualityPassRaisesTheMinimumAndKeepsTheBoundary) {
    HexMesh m = make_block(3, 3, 3);
    m.points[static_cast<std::size_t>(vid(3, 1, 1, 1))] = {1.3, 1.32,
                                                           1.28};  // toward (2, 2, 2): SJ ~0.18, not inverted
    const QualityReport before = compute_quality(m);
    ASSERT_EQ(before.inverted, 0);
    ASSERT_LT(before.sj_min, 0.5);
    UntangleOptions options;
    const UntangleResult plain = untangle(m, options);  // nothing inverted: unchanged
    EXPECT_EQ(plain.rounds, 0);
    options.target_sj = 0.8;
    const UntangleResult r = untangle(m, options);
    EXPECT_GT(r.rounds, 0);
    EXPECT_EQ(r.inverted_after, 0);
    const QualityReport after = compute_quality(r.mesh);
    EXPECT_GT(after.sj_min, 0.8);  // the regular grid (SJ 1) is the optimum
    EXPECT_NEAR(after.sj_min, r.sj_min_after, 1e-12);
    for (int k = 0; k <= 3; ++k)
        for (int j = 0; j <= 3; ++j)
            for (int i = 0; i <= 3; ++i)
                if (i == 0 || i == 3 || j == 0 || j == 3 || k == 0 || k == 3) {
                    const std::size_t v = static_cast<std::size_t>(vid(3, i, j, k));
                    EXPECT_EQ(r.mesh.points[v], m.points[v]);
                }
    options.target_sj = 1.0;
    EXPECT_THROW(untangle(m, options), Error);
}

// A padded block by hand: make_block(2, 2, 2), its upper layer the padding, the corner vertex (2, 2, 2) pushed inward
// along the diagonal to (1.7, 1.7, 1.7) (its hex skewed, not inverted). The domain is the half-space
// x + y + z <= 5.05: of all vertices only that corner (x + y + z = 5.1; the next ones 5) lies outside it. A quality
// pass with a softly held boundary (as the finishing's pad-improve) moves the corner back out along the diagonal,
// farther from the domain (measured: 0.029 -> 0.258 outside); untangle_holding_outside holds it at its place and leaves
// the other vertices free.
TEST(Untangle, HoldingOutsideKeepsTheVertexOutsideThePlaneDomain) {
    HexMesh m = make_block(2, 2, 2);
    const std::size_t corner = static_cast<std::size_t>(vid(2, 2, 2, 2));
    m.points[corner] = {1.7, 1.7, 1.7};
    ASSERT_EQ(compute_quality(m).inverted, 0);
    const SignedDistancesFn plane = [](const std::vector<Vec3>& p) {
        std::vector<double> d;
        for (const Vec3& x : p) d.push_back((x.x + x.y + x.z - 5.05) / std::sqrt(3.0));
        return d;
    };
    const std::vector<double> start = plane(m.points);
    for (std::size_t v = 0; v < m.points.size(); ++v) EXPECT_EQ(start[v] > 0, v == corner) << v;
    UntangleOptions options;
    options.fix_boundary = false;
    options.boundary_attach = 10;
    options.region_rings = 1;
    options.target_sj = 0.8;
    const UntangleResult free = untangle(m, options);
    ASSERT_GT(free.rounds, 0);
    EXPECT_GT(plane({free.mesh.points[corner]})[0], start[corner] + 0.01);  // moved out
    const UntangleResult held = untangle_holding_outside(m, options, plane, 3);
    EXPECT_EQ(held.mesh.points[corner], m.points[corner]);
    EXPECT_EQ(held.inverted_after, 0);
    EXPECT_GE(held.iterations, free.iterations);
    std::size_t moved = 0;
    for (std::size_t v = 0; v < m.points.size(); ++v) moved += held.mesh.points[v] == m.points[v] ? 0 : 1;
    EXPECT_GT(moved, 0u);
    EXPECT_GT(held.sj_min_after, held.sj_min_before);  // the others still raise the skewed hex (0.18 -> 0.55)
    // Without reruns the first pass is returned as it is.
    EXPECT_EQ(untangle_holding_outside(m, options, plane, 0).mesh, free.mesh);
}
