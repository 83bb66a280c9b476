// smooth_quality on blocks of unit cubes with one vertex displaced: checkable by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hex_fixtures.h"
#include "mesohex/core/error.h"
#include "mesohex/post/quality.h"
#include "mesohex/post/smoothing.h"

using namespace mesohex;

namespace {

// n x n x m block of unit cubes; vertex (i, j, k) has id i + (n + 1) (j + (n + 1) k).
HexMesh block(int n, int m) { return test::make_block(n, n, m); }

double min_sj(const HexMesh& m) {
    double s = 1;
    for (double v : scaled_jacobians(m)) s = std::min(s, v);
    return s;
}

}  // namespace

// 2 x 2 x 2 block, centre vertex (id 13) moved by (0.3, 0.2, 0.1): the 8 cubes around it are skewed (min SJ 0.80).
// Boundary vertices stay fixed (no projector). By default the vertex stops moving once its hexes are all above
// skip_above = 0.97; with skip_above 1 the centre returns to (1, 1, 1) within a small tolerance.
TEST(Smoothing, DisplacedCentreReturns) {
    HexMesh m = block(2, 2);
    m.points[13] = {1.3, 1.2, 1.1};
    const double before = min_sj(m);
    ASSERT_LT(before, 0.9);
    SmoothOptions o;
    o.move_boundary = false;
    const SmoothResult coarse = smooth_quality(m, {}, o);
    EXPECT_GT(coarse.sj_min_after, 0.97);
    o.skip_above = 1;
    std::vector<SmoothProgress> sweeps;  // one report per sweep, adding up to the result
    o.progress = [&sweeps](const SmoothProgress& p) { sweeps.push_back(p); };
    const SmoothResult r = smooth_quality(m, {}, o);
    ASSERT_EQ(static_cast<int>(sweeps.size()), r.sweeps);
    long moves = 0;
    for (std::size_t i = 0; i < sweeps.size(); ++i) {
        EXPECT_EQ(sweeps[i].sweep, static_cast<int>(i) + 1);
        moves += sweeps[i].moves;
    }
    EXPECT_EQ(moves, r.moves);
    EXPECT_NEAR(r.sj_min_before, before, 1e-12);
    EXPECT_GT(r.moves, 0);
    EXPECT_NEAR(r.mesh.points[13].x, 1.0, 0.02);
    EXPECT_NEAR(r.mesh.points[13].y, 1.0, 0.02);
    EXPECT_NEAR(r.mesh.points[13].z, 1.0, 0.02);
    EXPECT_GT(r.sj_min_after, 0.99);
    for (std::size_t v = 0; v < m.points.size(); ++v)
        if (v != 13) {
            EXPECT_EQ(r.mesh.points[v], m.points[v]) << v;
        }
}

// 2 x 2 x 1 block: the top-face centre (id 13 = (1, 1, 1)) slid to (1.3, 1.2, 1). With the projector onto the plane
// z = 1 it slides back inside the plane; the block's edge and corner vertices (feature vertices: their boundary quads
// turn by 90 degrees) and the other face centres stay where they are. Without the projector it cannot move at all.
TEST(Smoothing, BoundaryVertexSlidesOnTheSurface) {
    HexMesh m = block(2, 1);
    m.points[13] = {1.3, 1.2, 1.0};
    auto plane = [](const Vec3& p) { return Vec3{p.x, p.y, 1.0}; };
    SmoothOptions o;
    o.skip_above = 1;
    const SmoothResult r = smooth_quality(m, plane, o);
    EXPECT_GT(r.moves, 0);
    EXPECT_DOUBLE_EQ(r.mesh.points[13].z, 1.0);
    EXPECT_NEAR(r.mesh.points[13].x, 1.0, 0.02);
    EXPECT_NEAR(r.mesh.points[13].y, 1.0, 0.02);
    EXPECT_GT(r.sj_min_after, 0.99);
    for (std::size_t v = 0; v < m.points.size(); ++v)
        if (v != 13 && v != 4) {  // 4: the bottom-face centre, free too
            EXPECT_EQ(r.mesh.points[v], m.points[v]) << v;
        }
    const SmoothResult fixed = smooth_quality(m, {});
    EXPECT_EQ(fixed.moves, 0);
    EXPECT_EQ(fixed.mesh, m);
}

// Never inverts and never lowers the minimum: an inverted input is returned unchanged; bad input throws.
TEST(Smoothing, InvertedInputUnchangedAndBadInputRejected) {
    HexMesh m = block(2, 2);
    m.points[13] = {2.5, 1.0, 1.0};  // through the neighbouring cubes' faces
    ASSERT_LE(min_sj(m), 0.0);
    const SmoothResult r = smooth_quality(m, {});
    EXPECT_EQ(r.moves, 0);
    EXPECT_EQ(r.mesh, m);
    HexMesh bad = block(1, 1);
    bad.hexes[0][3] = 99;
    EXPECT_THROW(smooth_quality(bad, {}), Error);
    SmoothOptions o;
    o.frozen = {true};
    EXPECT_THROW(smooth_quality(block(1, 1), {}, o), Error);
}

// The max-min pass alone (no sweeps before or after it): 2 x 2 x 2 block, centre vertex (id 13) moved by
// (0.3, 0.2, 0.1), boundary fixed. Every move raises the smallest scaled Jacobian of the hexes it touches, so the
// centre walks back toward (1, 1, 1): the min SJ rises from 0.80 toward 1
// and nothing else moves. worst_below 0: the pass is off, nothing moves.
TEST(Smoothing, MaxMinPassRaisesTheWorstHex) {
    HexMesh m = block(2, 2);
    m.points[13] = {1.3, 1.2, 1.1};
    const double before = min_sj(m);
    SmoothOptions o;
    o.move_boundary = false;
    o.max_sweeps = 0;
    o.resweeps = 0;
    o.worst_below = 1;
    const SmoothResult r = smooth_quality(m, {}, o);
    EXPECT_EQ(r.sweeps, 0);
    EXPECT_EQ(r.moves, 0);
    EXPECT_GT(r.worst_moves, 0);
    EXPECT_GE(r.worst_rounds, 1);
    EXPECT_NEAR(r.sj_min_before, before, 1e-12);
    EXPECT_GT(r.sj_min_after, 0.95);
    EXPECT_NEAR(r.sj_min_after, min_sj(r.mesh), 1e-12);
    EXPECT_LT(distance(r.mesh.points[13], Vec3{1, 1, 1}), 0.1 * distance(m.points[13], Vec3{1, 1, 1}));
    for (std::size_t v = 0; v < m.points.size(); ++v)
        if (v != 13) {
            EXPECT_EQ(r.mesh.points[v], m.points[v]) << v;
        }
    o.worst_below = 0;
    const SmoothResult off = smooth_quality(m, {}, o);
    EXPECT_EQ(off.worst_moves, 0);
    EXPECT_EQ(off.mesh, m);
}

namespace {

// 2 x 2 x 1 block whose top is the roof z = base + s |x - 1| (s = +1: a valley, a concave crease of the domain along
// x = 1; s = -1, base 2: a ridge, a convex crease), with the closest point and the outward normal of that roof.
struct Roof {
    double base, s;
    HexMesh block() const {
        HexMesh m = test::make_block(2, 2, 1);
        for (Vec3& p : m.points)
            if (p.z == 1) p.z = base + s * std::abs(p.x - 1);
        return m;
    }
    Vec3 closest(const Vec3& p) const {  // the nearest of the two half-planes and the crease line
        Vec3 best{1, p.y, base};
        for (const double side : {-1.0, 1.0}) {  // side -1: x <= 1, the plane -side*s*x + z = base - side*s
            const Vec3 n{-side * s, 0, 1};
            const Vec3 q = p - (0.5 * (dot(n, p) - (base - side * s))) * n;
            if (side * (q.x - 1) >= 0 && distance(q, p) < distance(best, p)) best = q;
        }
        return best;
    }
    Vec3 normal(const Vec3& p) const { return normalized(Vec3{(p.x < 1 ? s : -s), 0, 1}); }
};

}  // namespace

// Features follow the domain: vertex 13 (the middle of the roof's crease, (1, 1, top)) moved 0.3 along the crease; all
// other vertices frozen, max-min pass off. Its boundary quads turn by 90 degrees, so by their normals alone it is a
// feature and stays. Given the domain's normals: at the valley the domain is concave, not a feature, and the vertex
// slides back to y = 1 on the domain; at the ridge (convex) it stays a feature and does not move.
TEST(Smoothing, FeaturesAreConvexCreasesOfTheDomain) {
    for (const bool valley : {true, false}) {
        const Roof roof = valley ? Roof{1, 1} : Roof{2, -1};
        HexMesh m = roof.block();
        ASSERT_EQ(m.points[13], (Vec3{1, 1, roof.base}));
        m.points[13].y = 1.3;
        SmoothOptions o;
        o.skip_above = 1;
        o.worst_below = 0;
        o.frozen.assign(m.points.size(), true);
        o.frozen[13] = false;
        auto project = [&roof](const Vec3& p) { return roof.closest(p); };
        const SmoothResult by_mesh = smooth_quality(m, project, o);
        EXPECT_EQ(by_mesh.moves, 0) << valley;
        EXPECT_EQ(by_mesh.mesh, m);
        o.surface_normal = [&roof](const Vec3& p) { return roof.normal(p); };
        const SmoothResult by_domain = smooth_quality(m, project, o);
        if (valley) {
            EXPECT_GT(by_domain.moves, 0);
            EXPECT_NEAR(by_domain.mesh.points[13].y, 1.0, 0.02);
            EXPECT_LT(distance(by_domain.mesh.points[13], roof.closest(by_domain.mesh.points[13])), 1e-12);
            EXPECT_GT(by_domain.sj_min_after, by_domain.sj_min_before);
        } else {
            EXPECT_EQ(by_domain.moves, 0);
            EXPECT_EQ(by_domain.mesh, m);
        }
    }
}

// smooth_region on a 10 x 2 x 2 block (vertex (i, j, k) has id i + 11 (j + 3 k)) whose interior vertex (2, 1, 1)
// (id 46) is moved by (0.3, 0.2, 0.1): its 8 cubes (x in [1, 3]) have scaled Jacobians 0.65-0.95, all others 1.
// Below 0.96 the seeds are those 8; `rings` rings reach the cubes up to x = 2 + rings, so the vertices at
// i >= 3 + rings are used by cubes outside the region (frozen) or by those only: they keep their coordinates bit for
// bit. Boundary fixed (no projector).
// rings 0: only the centre moves (every other vertex of a seed is also one of a cube outside, or on the boundary); no
// hex below the threshold: nothing moves.
TEST(Smoothing, RegionMovesOnlyTheRingsAroundTheBadHexes) {
    HexMesh m = test::make_block(10, 2, 2);
    const std::size_t centre = 2 + 11 * (1 + 3 * 1);
    ASSERT_EQ(m.points[centre], (Vec3{2, 1, 1}));
    m.points[centre] = {2.3, 1.2, 1.1};
    const std::vector<double> sj = scaled_jacobians(m);
    long seeds = 0;
    for (double s : sj) seeds += s < 0.96 ? 1 : 0;
    ASSERT_EQ(seeds, 8);
    SmoothOptions o;
    o.move_boundary = false;
    for (int rings : {0, 1, 2}) {
        const SmoothResult r = smooth_region(m, {}, 0.96, rings, o);
        EXPECT_GT(r.moves, 0) << rings;
        EXPECT_GT(min_sj(r.mesh), 0.97) << rings;
        EXPECT_LT(distance(r.mesh.points[centre], Vec3{2, 1, 1}), 0.5 * distance(m.points[centre], Vec3{2, 1, 1}));
        for (std::size_t v = 0; v < m.points.size(); ++v)
            if (static_cast<int>(v % 11) >= 3 + rings) {
                EXPECT_EQ(r.mesh.points[v], m.points[v]) << rings << " " << v;
            }
        EXPECT_EQ(r.mesh.hexes, m.hexes);
        // The scaled Jacobians handed in give the same result as those computed.
        EXPECT_EQ(smooth_region(m, {}, 0.96, rings, o, sj).mesh, r.mesh);
    }
    const SmoothResult seeds_only = smooth_region(m, {}, 0.96, 0, o);
    for (std::size_t v = 0; v < m.points.size(); ++v)
        if (v != centre) {
            EXPECT_EQ(seeds_only.mesh.points[v], m.points[v]) << v;
        }
    const SmoothResult good = smooth_region(m, {}, 0.5, 2, o);
    EXPECT_EQ(good.sweeps, 0);
    EXPECT_EQ(good.mesh, m);
    EXPECT_THROW(smooth_region(m, {}, 0.96, 1, o, std::vector<double>(3, 1.0)), Error);
}
