// Boundary projection (the inherited levels of finish_mesh): moves derived on paper on a block, and the guard.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hex_fixtures.h"
#include "mesohex/core/error.h"
#include "mesohex/post/boundary_projection.h"
#include "mesohex/post/quality.h"

using namespace mesohex;
using mesohex::test::make_block;

namespace {

std::vector<char> outer(const HexMesh& m, double lo, double hi) {
    std::vector<char> on(m.points.size(), 0);
    for (std::size_t v = 0; v < m.points.size(); ++v) {
        const Vec3& p = m.points[v];
        on[v] = p.x == lo || p.y == lo || p.z == lo || p.x == hi || p.y == hi || p.z == hi;
    }
    return on;
}

}  // namespace

TEST(BoundaryProjection, MovesFadeLinearlyOverTheRings) {
    // 8^3 unit cubes; the "surface" lies 0.01 above every boundary vertex. A vertex at lattice (i, j, k) is
    // r = min(i, 8 - i, j, 8 - j, k, 8 - k) edges from the boundary; with 3 rings it moves 0.01 (1 - r / 4) up.
    HexMesh m = make_block(8, 8, 8);
    const HexMesh before = m;
    const ClosestPointsFn up = [](const std::vector<Vec3>& in, std::vector<Vec3>& out) {
        out = in;
        for (Vec3& p : out) p.z += 0.01;
    };
    ProjectionOptions o;
    o.rings = 3;
    const ProjectionResult r = project_boundary(m, outer(m, 0, 8), up, o);
    EXPECT_EQ(r.boundary_vertices, 9 * 9 * 9 - 7 * 7 * 7);
    EXPECT_EQ(r.moved_vertices, 9 * 9 * 9 - 1);  // all but the centre (ring 4)
    EXPECT_EQ(r.damped_vertices, 0);
    EXPECT_NEAR(r.max_move, 0.01, 1e-15);
    for (std::size_t v = 0; v < m.points.size(); ++v) {
        const Vec3& p = before.points[v];
        const double ring = std::min({p.x, 8 - p.x, p.y, 8 - p.y, p.z, 8 - p.z});
        const double expected = 0.01 * std::max(0.0, 1 - ring / 4);
        EXPECT_NEAR(m.points[v].z - p.z, expected, 1e-15) << v;
        EXPECT_EQ(m.points[v].x, p.x);
        EXPECT_EQ(m.points[v].y, p.y);
    }
}

TEST(BoundaryProjection, GuardKeepsEveryHexNearItsQuality) {
    // A "surface" that pulls corner (0, 0, 0) through its hex to (2, 2, 2): the full move would invert it. The guard
    // halves that move until no hex is inverted nor below min(guard_sj, its scaled Jacobian before) = 0.3.
    HexMesh m = make_block(2, 2, 2);
    const ClosestPointsFn pull = [](const std::vector<Vec3>& in, std::vector<Vec3>& out) {
        out = in;
        for (Vec3& p : out)
            if (p == Vec3{0, 0, 0}) p = Vec3{2, 2, 2};
    };
    ProjectionOptions o;
    o.rings = 0;
    const ProjectionResult r = project_boundary(m, outer(m, 0, 2), pull, o);
    EXPECT_EQ(r.damped_vertices, 1);
    EXPECT_EQ(r.moved_vertices, 1);
    EXPECT_GT(m.points[0].x, 0);          // moved a little along the diagonal ...
    EXPECT_LT(m.points[0].x, 2.0 / 2.0);  // ... by at most half the way (one halving at least)
    for (double sj : scaled_jacobians(m)) EXPECT_GE(sj, 0.3);
}

TEST(BoundaryProjection, RejectsMismatchedFlags) {
    HexMesh m = make_block(1, 1, 1);
    const ClosestPointsFn same = [](const std::vector<Vec3>& in, std::vector<Vec3>& out) { out = in; };
    EXPECT_THROW(project_boundary(m, std::vector<char>(3, 1), same), Error);
}
