// Subdivision: counts and invariants derived on paper.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hex_fixtures.h"
#include "mesohex/core/error.h"
#include "mesohex/core/topology.h"
#include "mesohex/core/validate.h"
#include "mesohex/post/quality.h"
#include "mesohex/post/subdivision.h"

using namespace mesohex;
using mesohex::test::make_block;

namespace {

// Edge id of the edge (a, b) in compute_hex_topology(m), -1 if absent.
int edge_id(const HexMesh& m, int a, int b) {
    const HexTopology t = compute_hex_topology(m);
    for (std::size_t e = 0; e < t.edges.size(); ++e)
        if (t.edges[e] == std::array<int, 2>{std::min(a, b), std::max(a, b)}) return static_cast<int>(e);
    return -1;
}

std::vector<bool> select(const HexMesh& m, std::initializer_list<std::array<int, 2>> edges) {
    std::vector<bool> sel(compute_hex_topology(m).edges.size(), false);
    for (const std::array<int, 2>& e : edges) {
        const int id = edge_id(m, e[0], e[1]);
        EXPECT_GE(id, 0);
        if (id >= 0) sel[static_cast<std::size_t>(id)] = true;
    }
    return sel;
}

double total_volume(const HexMesh& m) {
    // Exact for parallelepiped-like cells: (1/6 of the sum over the 6 tets of the standard split) is overkill here;
    // unit-cube children of axis-aligned blocks are boxes, volume = product of the box extents.
    double v = 0;
    for (const std::array<int, 8>& h : m.hexes) {
        const Vec3& p0 = m.points[static_cast<std::size_t>(h[0])];
        v += det3(m.points[static_cast<std::size_t>(h[1])] - p0, m.points[static_cast<std::size_t>(h[3])] - p0,
                  m.points[static_cast<std::size_t>(h[4])] - p0);
    }
    return v;
}

}  // namespace

TEST(Subdivision, OneToEightOnSingleHex) {
    const SubdivisionResult r = subdivide(mesohex::test::make_unit_cube());
    EXPECT_EQ(r.mesh.hexes.size(), 8u);
    EXPECT_EQ(r.mesh.points.size(), 27u);  // 8 corners + 12 edges + 6 faces + 1 cell
    EXPECT_EQ(r.parent_hex, std::vector<int>(8, 0));
    const QualityReport q = compute_quality(r.mesh);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, 1);
    EXPECT_DOUBLE_EQ(q.sj_min, 1.0);
    EXPECT_EQ(r.mesh.points[26], (Vec3{0.5, 0.5, 0.5}));  // the cell centroid is the last point
    // Child 0 sits at corner 0 and keeps the orientation: its corners are the unit cube scaled by 1/2.
    const std::array<int, 8>& c0 = r.mesh.hexes[0];
    EXPECT_EQ(c0[0], 0);
    EXPECT_EQ(r.mesh.points[static_cast<std::size_t>(c0[6])], (Vec3{0.5, 0.5, 0.5}));
    EXPECT_NEAR(total_volume(r.mesh), 1.0, 1e-12);
}

TEST(Subdivision, OneToEightKeepsEulerAndValidity) {
    for (const HexMesh& m : {make_block(2, 3, 1), mesohex::test::make_ring8()}) {
        const QualityReport before = compute_quality(m);
        const SubdivisionResult r = subdivide(m);
        EXPECT_EQ(r.mesh.hexes.size(), 8 * m.hexes.size());
        const QualityReport after = compute_quality(r.mesh);
        EXPECT_TRUE(after.validation.valid());
        EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
        EXPECT_EQ(after.boundary_components, before.boundary_components);
        EXPECT_EQ(after.inverted, 0);
        // V' = V + E + F + C.
        const HexTopology t = compute_hex_topology(m);
        EXPECT_EQ(r.mesh.points.size(), m.points.size() + t.edges.size() + t.faces.size() + m.hexes.size());
    }
}

TEST(Subdivision, IsDeterministic) {
    const HexMesh m = mesohex::test::make_ring8();
    EXPECT_EQ(subdivide(m).mesh, subdivide(m).mesh);
    EXPECT_EQ(subdivide(m).mesh,
              subdivide_sheets(m, std::vector<bool>(compute_hex_topology(m).edges.size(), true)).mesh);
}

TEST(Subdivision, SheetAlongTheBarGivesSix) {
    // 3x1x1 bar along x: vertex (i,j,k) = i + 4 (j + 2 k). The y-edge 0-4 lies in the sheet of all y-edges of the bar.
    const HexMesh bar = make_block(3, 1, 1);
    const SubdivisionResult r = subdivide_sheets(bar, select(bar, {{0, 4}}));
    EXPECT_EQ(r.mesh.hexes.size(), 6u);
    EXPECT_EQ(r.mesh.points.size(), 16u + 8u);  // the 8 y-edges get midpoints, no face or cell centroid
    EXPECT_EQ(r.parent_hex, (std::vector<int>{0, 0, 1, 1, 2, 2}));
    const QualityReport q = compute_quality(r.mesh);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, 1);
    EXPECT_DOUBLE_EQ(q.sj_min, 1.0);
    EXPECT_NEAR(total_volume(r.mesh), 3.0, 1e-12);
}

TEST(Subdivision, SheetAcrossTheBarSplitsOneHex) {
    // The x-edge 1-2 belongs to hex 1 only (with its 3 parallel edges): that sheet is hex 1.
    const HexMesh bar = make_block(3, 1, 1);
    const SubdivisionResult r = subdivide_sheets(bar, select(bar, {{1, 2}}));
    EXPECT_EQ(r.mesh.hexes.size(), 4u);
    EXPECT_TRUE(validate(r.mesh).valid());
    // Both an x-sheet and the y-sheet: hex 1 gets 4 children, hexes 0 and 2 get 2.
    const SubdivisionResult r2 = subdivide_sheets(bar, select(bar, {{1, 2}, {0, 4}}));
    EXPECT_EQ(r2.mesh.hexes.size(), 8u);
    EXPECT_EQ(std::count(r2.parent_hex.begin(), r2.parent_hex.end(), 1), 4);
    const QualityReport q = compute_quality(r2.mesh);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, 1);
    // All three directions of a 1x1x1: 8 children, like subdivide().
    const HexMesh cube = mesohex::test::make_unit_cube();
    EXPECT_EQ(subdivide_sheets(cube, select(cube, {{0, 1}, {0, 2}, {0, 4}})).mesh, subdivide(cube).mesh);
}

TEST(Subdivision, RingSheetClosesAroundTheHole) {
    // In the ring of 8 (3x3x1 minus centre), the vertical (z) edges form one sheet: splitting it doubles every hex.
    const HexMesh ring = mesohex::test::make_ring8();
    const SubdivisionResult r = subdivide_sheets(ring, select(ring, {{0, 16}}));
    EXPECT_EQ(r.mesh.hexes.size(), 16u);
    // A radial sheet (x-edge 0-1 of the corner hex) crosses hexes (0,0) and (0,1)... and the ring on the other side:
    // hexes in column i = 0: (0,0), (0,1), (0,2) -> 3 hexes split in two.
    const SubdivisionResult r2 = subdivide_sheets(ring, select(ring, {{0, 1}}));
    EXPECT_EQ(r2.mesh.hexes.size(), 8u + 3u);
    EXPECT_TRUE(validate(r2.mesh).valid());
    EXPECT_EQ(compute_quality(r2.mesh).euler_characteristic, 0);
}

TEST(Subdivision, NothingSelectedIsIdentity) {
    const HexMesh m = make_block(2, 2, 1);
    const SubdivisionResult r = subdivide_sheets(m, std::vector<bool>(compute_hex_topology(m).edges.size(), false));
    EXPECT_EQ(r.mesh, m);
}

TEST(Subdivision, LevelsForSize) {
    const HexMesh m = make_block(2, 2, 2);  // every edge has length 1
    EXPECT_DOUBLE_EQ(mean_edge_length(m), 1.0);
    EXPECT_EQ(levels_for_size(m, 1.0), 0);
    EXPECT_EQ(levels_for_size(m, 2.0), 0);
    EXPECT_EQ(levels_for_size(m, 0.5), 1);
    EXPECT_EQ(levels_for_size(m, 0.4), 2);
    EXPECT_EQ(levels_for_size(m, 0.25), 2);
    EXPECT_EQ(levels_for_size(m, 1e-9), 8);  // capped
    EXPECT_THROW(levels_for_size(m, 0.0), Error);
    EXPECT_THROW(levels_for_size(m, std::nan("")), Error);
}

TEST(Subdivision, RejectsBadInput) {
    HexMesh m = make_block(1, 1, 1);
    EXPECT_THROW(subdivide_sheets(m, {true}), Error);
    m.hexes[0][0] = -1;
    EXPECT_THROW(subdivide(m), Error);
}

TEST(Subdivision, MarksTheBoundaryPoints) {
    // One cube: 8 corners, 12 edge midpoints and 6 face centroids lie on the boundary, the cell centroid does not.
    const SubdivisionResult one = subdivide(mesohex::test::make_unit_cube());
    ASSERT_EQ(one.on_boundary.size(), 27u);
    EXPECT_EQ(std::count(one.on_boundary.begin(), one.on_boundary.end(), 1), 26);
    EXPECT_EQ(one.on_boundary[26], 0);
    // A 2 x 2 x 2 block subdivided is the 4 x 4 x 4 lattice: 5^3 - 3^3 = 98 boundary points of 125.
    const SubdivisionResult block = subdivide(make_block(2, 2, 2));
    ASSERT_EQ(block.on_boundary.size(), 125u);
    EXPECT_EQ(std::count(block.on_boundary.begin(), block.on_boundary.end(), 1), 98);
    for (std::size_t v = 0; v < 125; ++v) {
        const Vec3& p = block.mesh.points[v];
        const bool outer = p.x == 0 || p.y == 0 || p.z == 0 || p.x == 2 || p.y == 2 || p.z == 2;
        EXPECT_EQ(block.on_boundary[v] != 0, outer) << v;
    }
}
