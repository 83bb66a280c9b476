// extend_rim_borders on hand-made medial sheets inside solids whose medial axis is known: a plate with elliptic rims
// (cross-section an ellipse of semi-axes 1.8 x 1, 96 segments, extruded 5 along z: its medial sheet is the plane
// y = 0, |x| <= 1.8 - 1 / 1.8 = 1.244, where the ball of radius d(x) = sqrt(1 - x^2 / 2.24) touches the rounded rim)
// and a square plate with sharp 90-degree edges (4 x 4 x 0.6: its mid-sheet ends 0.3 from the edges).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/surface/medial_axis.h"
#include "mesohex/surface/medial_rims.h"
#include "mesohex/surface/surface_query.h"
#include "surface_fixtures.h"

namespace mesohex {
namespace {

constexpr double kReach = 1.2, kMinRadius = 0.5, kMaxMove = 2.0;  // MedialAxisOptions' defaults

TriangleMesh elliptic_plate() {
    std::vector<std::array<double, 2>> ellipse;
    for (int i = 0; i < 96; ++i) {
        const double a = 2 * std::numbers::pi * i / 96;
        ellipse.push_back({1.8 * std::cos(a), std::sin(a)});
    }
    return test::prism_surface(ellipse, -2.5, 2.5);
}

// A grid sheet of n x n vertices in the plane `normal_axis` = 0, spanning [lo0, hi0] x [lo1, hi1] along the two other
// axes (first the lower one), two triangles a cell, radii the distance to the surface.
Skeleton grid_sheet(int normal_axis, double lo0, double hi0, double lo1, double hi1, int n, const SurfaceQuery& q) {
    const int a0 = normal_axis == 0 ? 1 : 0, a1 = normal_axis == 2 ? 1 : 2;
    Skeleton s;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            Vec3 p{};
            p[a0] = lo0 + (hi0 - lo0) * i / (n - 1);
            p[a1] = lo1 + (hi1 - lo1) * j / (n - 1);
            s.points.push_back(p);
            s.radii.push_back(std::sqrt(q.squared_distance(p)));
        }
    auto id = [n](int i, int j) { return i * n + j; };
    for (int i = 0; i + 1 < n; ++i)
        for (int j = 0; j + 1 < n; ++j) {
            s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            s.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    for (const std::vector<int>& f : s.faces)
        for (size_t k = 0; k < 3; ++k)
            s.edges.push_back({std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])});
    std::sort(s.edges.begin(), s.edges.end());
    s.edges.erase(std::unique(s.edges.begin(), s.edges.end()), s.edges.end());
    return s;
}

const Vec3* find_near(const Skeleton& s, double y, double z, double x_min) {
    for (const Vec3& p : s.points)
        if (std::abs(p.y - y) < 1e-9 && std::abs(p.z - z) < 1e-9 && p.x > x_min) return &p;
    return nullptr;
}

// The sheet's x borders (x = +-0.6, where the rim ahead lies 1.2 away against a ball of radius 0.916: ratio 1.31)
// march along +-x until 1.8 - x <= 1.2 d(x), which first holds at x = 0.772 (steps of 0.916 / 20 from 0.6: the 4th,
// x = 0.783). The z borders (z = +-1) face the flat ends at z = +-2.5 (ratio 1.5 at x = 0) and stop where the ball
// nears them: 2.5 - z <= 1.2 d, d <= 1 (z >= 1.3). The corners head for the rim at 45 degrees: beyond the medial end
// d = 1.8 - x and (D - s) / d = sqrt(2) until the ball is half its size. Topology and counts are kept, radii are the
// distances.
TEST(MedialRims, SheetBordersReachTheRoundedRimAndTheFlatEnds) {
    const TriangleMesh plate = elliptic_plate();
    const SurfaceQuery q(plate);
    Skeleton s = grid_sheet(1, -0.6, 0.6, -1, 1, 5, q);
    const Skeleton before = s;
    const RimExtension r = extend_rim_borders(s, q, kReach, kMinRadius, kMaxMove);
    EXPECT_EQ(r.border_vertices, 16);
    // The 4 corners head for the rim at 45 degrees ((D - s) / d >= sqrt(2) all the way): sharp; the other 12 move.
    EXPECT_EQ(r.sharp, 4);
    EXPECT_EQ(r.moved, 12);
    EXPECT_EQ(s.points.size(), before.points.size());
    EXPECT_EQ(s.edges.size(), before.edges.size());
    EXPECT_EQ(s.faces.size(), before.faces.size());
    EXPECT_EQ(euler_characteristic(s), 1);
    EXPECT_TRUE(std::is_sorted(s.points.begin(), s.points.end(), [](const Vec3& a, const Vec3& b) {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    }));
    for (size_t v = 0; v < s.points.size(); ++v) {
        EXPECT_NEAR(s.points[v].y, 0, 1e-12);  // in the sheet's plane
        EXPECT_NEAR(s.radii[v], std::sqrt(q.squared_distance(s.points[v])), 1e-12);
        EXPECT_TRUE(q.inside(s.points[v]));
    }
    for (double z : {-0.5, 0.0, 0.5}) {
        const Vec3* p = find_near(s, 0, z, 0.45);  // the border vertex (the grid's next column is at x = 0.3)
        ASSERT_NE(p, nullptr) << "x border at z = " << z;
        EXPECT_NEAR(p->x, 0.6 + 4 * std::sqrt(1 - 0.36 / 2.24) / 20, 0.01);
        EXPECT_LE(1.8 - p->x, kReach * std::sqrt(q.squared_distance(*p)) + 1e-9);
        EXPECT_GT(1.8 - p->x, 0.5);  // short of the medial end (1.244) and far from the rim
    }
    double z_max = 0;
    for (const Vec3& p : s.points) z_max = std::max(z_max, std::abs(p.z));
    EXPECT_GE(z_max, 1.3 - 0.05);
    EXPECT_LE(z_max, 1.5);  // the ball (radius <= 1) stays clear of the end at 2.5
}

// The square plate's mid-sheet out to 0.3 from its sharp edges: the surface ahead of every border side is one ball
// radius away (within reach: no move); at the 4 corners the bisector points at the vertical corner edge, where
// (D - s) / d stays sqrt(2) while the ball shrinks: sharp, no move. The sheet is unchanged.
TEST(MedialRims, SharpEdgesAndBordersWithinReachStay) {
    const TriangleMesh plate = test::prism_surface({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3);
    const SurfaceQuery q(plate);
    Skeleton s = grid_sheet(2, -1.7, 1.7, -1.7, 1.7, 5, q);
    const Skeleton before = s;
    const RimExtension r = extend_rim_borders(s, q, kReach, kMinRadius, kMaxMove);
    EXPECT_EQ(r.border_vertices, 16);
    EXPECT_EQ(r.moved, 0);
    EXPECT_EQ(r.sharp, 4);
    EXPECT_EQ(s, before);
}

// A border far inside a plate (a hole the angle filter punched into a sheet): the surface ahead lies beyond
// kMaxMove x the ball radius, so nothing moves; with a larger max_move the border marches on.
TEST(MedialRims, FarRimsBeyondMaxMoveStay) {
    const TriangleMesh plate = test::prism_surface({{-4, -4}, {4, -4}, {4, 4}, {-4, 4}}, -0.3, 0.3);
    const SurfaceQuery q(plate);
    Skeleton s = grid_sheet(2, -1, 1, -1, 1, 3, q);
    const Skeleton before = s;
    const RimExtension r = extend_rim_borders(s, q, kReach, kMinRadius, kMaxMove);
    EXPECT_EQ(r.moved, 0);
    EXPECT_EQ(s, before);
    Skeleton far = before;
    EXPECT_GT(extend_rim_borders(far, q, kReach, kMinRadius, 20.0).moved, 0);
}

// compute_medial_axis on the elliptic plate (about 6 s each): the step keeps the sheet's topology and widens it along
// x, within the medial sheet's end. Measured: the sheet reaches |x| = 0.897 without, 1.077 with it; 11 of its 34
// border vertices move, 11 give up (sharp).
TEST(MedialRims, MedialAxisOfTheEllipticPlateReachesFartherTowardItsRims) {
    const TriangleMesh plate = elliptic_plate();
    MedialAxisOptions on;
    on.extend_rims = true;
    const MedialAxis a = compute_medial_axis(plate, MedialAxisOptions{});  // off by default
    const MedialAxis b = compute_medial_axis(plate, on);
    EXPECT_EQ(a.rim_moved, 0);
    EXPECT_EQ(a.rim_border_vertices, 0);
    EXPECT_EQ(b.rim_moved, 11);
    EXPECT_EQ(b.rim_sharp, 11);
    EXPECT_EQ(b.sheets, a.sheets);
    EXPECT_EQ(b.curves, a.curves);
    EXPECT_EQ(b.euler, a.euler);
    EXPECT_EQ(b.medial.points.size(), a.medial.points.size());
    EXPECT_EQ(b.medial.faces.size(), a.medial.faces.size());
    auto x_extent = [](const MedialAxis& m) {
        double x = 0;
        for (const Vec3& p : m.medial.points) x = std::max(x, std::abs(p.x));
        return x;
    };
    EXPECT_LE(x_extent(b), 1.8 - 1 / 1.8 + 1e-6);  // never past the medial sheet's end
    EXPECT_LT(x_extent(a), 0.95);
    EXPECT_GT(x_extent(b), 1.05);
}

}  // namespace
}  // namespace mesohex
