// Virtual branches at branching points with an empty cap (stages/virtual_branches.h): covering radius, where and how
// many are added, and the raw mesh's exact counts with them.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesohex/core/topology.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/virtual_branches.h"

namespace mesohex {
namespace {

double deg(double rad) { return rad * 180.0 / std::numbers::pi; }

// Star at the origin: n branches at polar angle `half_deg` from +z, azimuths 2 pi i / n, `edges` unit edges each,
// radius r everywhere.
Skeleton cone_star(int n, double half_deg, int edges, double r) {
    Skeleton s;
    s.points.push_back({0, 0, 0});
    const double t = half_deg * std::numbers::pi / 180.0;
    for (int i = 0; i < n; ++i) {
        const double p = 2 * std::numbers::pi * i / n;
        const Vec3 d{std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
        int prev = 0;
        for (int k = 1; k <= edges; ++k) {
            s.points.push_back(d * static_cast<double>(k));
            s.edges.push_back({prev, static_cast<int>(s.points.size()) - 1});
            prev = static_cast<int>(s.points.size()) - 1;
        }
    }
    s.radii.assign(s.points.size(), r);
    return s;
}

// The grid's covering radius against the exact one: the 6 cube axes leave 54.74 degrees (acos(1/sqrt 3), at the cube
// corners); a single direction leaves 180 at its antipode. The 512-point grid's spacing is about 9 degrees, its points
// within 4.5 of any point of the sphere, so the grid value is within 4.5 degrees below the exact value.
TEST(VirtualBranches, CoveringRadiusOnTheGrid) {
    const std::vector<Vec3> axes = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    Vec3 far;
    const double cube = covering_radius_deg(axes, 512, &far);
    EXPECT_LE(cube, deg(std::acos(1 / std::sqrt(3.0))) + 1e-9);
    EXPECT_GT(cube, deg(std::acos(1 / std::sqrt(3.0))) - 4.5);
    const double one = covering_radius_deg({{0, 0, 1}}, 512, &far);
    EXPECT_GT(one, 175.5);
    EXPECT_LT(far.z, -0.99);
}

// A 3-star in a cone of half-angle 45 degrees: covering radius 135 (at -z) > 100: one virtual branch towards -z (the
// grid point, within 4.5 degrees), of length r, radius r; then the cap is below 100 and none more. A 60-degree 3-star
// in one plane (a Y, 120 degrees apart: covering radius 90) gets none; neither does the cube corner x, y, z when
// blocks are on (its compatible block), while it gets one with blocks off (covering radius 125.3).
TEST(VirtualBranches, OneAtTheEmptyCapOfANarrowCone) {
    VirtualBranchOptions o;
    o.enabled = true;
    Skeleton s = cone_star(3, 45, 2, 0.3);
    const std::size_t nv = s.points.size(), ne = s.edges.size();
    const long chi = euler_characteristic(s);
    const VirtualBranches vb = add_virtual_branches(s, o);
    ASSERT_EQ(vb.at.size(), 1u);
    EXPECT_EQ(vb.at[0], 0);
    ASSERT_EQ(s.points.size(), nv + 1);
    ASSERT_EQ(s.edges.size(), ne + 1);
    EXPECT_EQ(euler_characteristic(s), chi);
    const Vec3 v = s.points.back();
    EXPECT_NEAR(norm(v), 0.3, 1e-12);
    EXPECT_LT(deg(std::acos(-v.z / norm(v))), 4.5);
    EXPECT_EQ(s.radii.back(), 0.3);

    Skeleton y = cone_star(3, 90, 2, 0.3);
    EXPECT_TRUE(add_virtual_branches(y, o).at.empty());
    Skeleton corner;
    corner.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    corner.edges = {{0, 1}, {0, 2}, {0, 3}};
    corner.radii.assign(4, 0.3);
    Skeleton c2 = corner;
    const CompatibleBlockOptions blocks;
    EXPECT_TRUE(add_virtual_branches(corner, o, &blocks).at.empty());
    EXPECT_EQ(add_virtual_branches(c2, o, nullptr).at.size(), 1u);
    o.enabled = false;
    Skeleton off = cone_star(3, 45, 2, 0.3);
    EXPECT_TRUE(add_virtual_branches(off, o).at.empty());
}

// Raw mesh of the 45-degree 3-star with arms of 2 edges, input sampling: 6 branch edges + 1 virtual = 7 chunks of 4
// hexes = 28 hexes (24 without); predicted exactly (hexes, vertices, irregular edges; predicted.virtual_branches = 1);
// Euler characteristic 1 (a ball, like the skeleton); no inverted hex. Blocks off: with them, this star (pair angles
// 75.5 degrees, within 25 of 90) gets a compatible block (+8 hexes) and no virtual branch.
TEST(VirtualBranches, RawMeshCountsExact) {
    PipelineOptions po;
    po.resample = false;
    po.virtual_branches.enabled = true;
    const PipelineResult block = run_pipeline(cone_star(3, 45, 2, 0.3), po);
    EXPECT_EQ(block.virtual_branches, 0);
    EXPECT_EQ(block.predicted.compatible_blocks, 1);
    EXPECT_EQ(block.raw.mesh.hexes.size(), 32u);
    po.virtual_branches.enabled = false;
    po.connection_surfaces.blocks.enabled = false;
    const PipelineResult off = run_pipeline(cone_star(3, 45, 2, 0.3), po);
    po.virtual_branches.enabled = true;
    const PipelineResult on = run_pipeline(cone_star(3, 45, 2, 0.3), po);
    EXPECT_EQ(off.raw.mesh.hexes.size(), 24u);
    EXPECT_EQ(on.raw.mesh.hexes.size(), 28u);
    EXPECT_EQ(on.virtual_branches, 1);
    EXPECT_EQ(on.predicted.virtual_branches, 1);
    EXPECT_EQ(off.predicted.virtual_branches, 0);
    EXPECT_EQ(on.predicted.hexes, 28);
    EXPECT_EQ(on.predicted.vertices, static_cast<long>(on.raw.mesh.points.size()));
    HexTopology topo;
    const QualityReport q = compute_quality(on.raw.mesh, topo);
    EXPECT_EQ(q.euler_characteristic, 1);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_GT(q.sj_min, 0.0);
    EXPECT_EQ(q.singular_interior_edges, on.predicted.interior_irregular_edges);
    EXPECT_EQ(q.singular_boundary_edges, on.predicted.boundary_irregular_edges);
}

// Pit branches (VirtualBranchOptions::pit_excess): a ring of 4 branches 40 degrees from +z (cone_star) with a fifth
// along -z, every radius 0.1, one unit edge each, the skeleton its own domain. The Voronoi vertices of the five
// directions within 70 degrees of their branches: +z only (40 degrees from the ring; the vertices between two ring
// branches and -z lie 75.6 degrees from theirs: acos(0.249)). Along +z the ray leaves c's ball and enters the ring's
// tubes, which it leaves at t = 0.1 / sin 40 = 0.155572 (distance t sin 40 from each axis): above (1 + 0.3) x 0.1, so
// one branch to (0, 0, t - 0.25 x 0.1), radius 0.1; pit_excess 0.6 (0.16 > t) or a degree-3 point (min degree 4):
// none; no domain or pit_excess 0 (the default): none.
TEST(VirtualBranches, PitBranchIntoTheRingsCentre) {
    Skeleton ring = cone_star(4, 40, 1, 0.1);
    ring.points.push_back({0, 0, -1});
    ring.radii.push_back(0.1);
    ring.edges.push_back({0, 5});
    VirtualBranchOptions o;
    o.pit_excess = 0.3;
    Skeleton s = ring;
    const VirtualBranches vb = add_virtual_branches(s, o, nullptr, &ring);
    ASSERT_EQ(vb.at.size(), 1u);
    EXPECT_EQ(vb.at[0], 0);
    ASSERT_EQ(s.points.size(), 7u);
    const double t = 0.1 / std::sin(40 * std::numbers::pi / 180);
    EXPECT_NEAR(t, 0.155572, 1e-6);
    EXPECT_NEAR(distance(s.points[6], Vec3{0, 0, t - 0.025}), 0, 1e-9);
    EXPECT_EQ(s.radii[6], 0.1);
    EXPECT_EQ(s.edges.back(), (std::array<int, 2>{0, 6}));
    o.pit_excess = 0.6;
    Skeleton deep = ring;
    EXPECT_TRUE(add_virtual_branches(deep, o, nullptr, &ring).at.empty());
    EXPECT_EQ(deep, ring);
    o.pit_excess = 0.3;
    Skeleton three = cone_star(3, 40, 1, 0.1);
    const Skeleton three_domain = three;
    EXPECT_TRUE(add_virtual_branches(three, o, nullptr, &three_domain).at.empty());
    Skeleton no_domain = ring;
    EXPECT_TRUE(add_virtual_branches(no_domain, o).at.empty());
    Skeleton off = ring;
    EXPECT_TRUE(add_virtual_branches(off, VirtualBranchOptions{}, nullptr, &ring).at.empty());
}

}  // namespace
}  // namespace mesohex
