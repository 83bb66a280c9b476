// Thickening: volumes and topology of simple skeletons, checkable on paper.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <tbb/global_control.h>

#include "mesohex/core/error.h"
#include "mesohex/surface/surface_check.h"
#include "mesohex/surface/thicken.h"
#include "mesohex_io/surface_io.h"

using namespace mesohex;

namespace {

constexpr double kPi = 3.14159265358979323846;

SurfaceCheck expect_closed_outward(const TriangleMesh& m) {
    const SurfaceCheck c = check_surface(m);
    EXPECT_TRUE(c.is_closed_manifold());
    EXPECT_EQ(c.boundary_edges, 0);
    EXPECT_EQ(c.non_manifold_edges, 0);
    EXPECT_EQ(c.non_manifold_vertices, 0);
    EXPECT_EQ(c.inconsistent_edges, 0);
    EXPECT_EQ(c.unreferenced_vertices, 0);
    EXPECT_GT(c.signed_volume, 0);
    return c;
}

}  // namespace

TEST(Thicken, SingleSphereVolumeAndGenus) {
    Skeleton s;
    s.points = {{0.3, -0.2, 1.0}};
    s.radii = {1.0};
    ThickenStats stats;
    const TriangleMesh m = thicken(s, {}, &stats);
    const SurfaceCheck c = expect_closed_outward(m);
    ASSERT_EQ(c.components.size(), 1u);
    EXPECT_EQ(c.components[0].genus, 0);
    const double exact = 4.0 / 3.0 * kPi;
    EXPECT_NEAR(c.signed_volume, exact, 0.02 * exact);
    EXPECT_NEAR(stats.cell_size, 1.0 / 4.0, 1e-12);  // default: 4 cells per smallest radius
    // Every vertex lies within one cell of the sphere.
    for (const Vec3& p : m.points) EXPECT_NEAR(distance(p, s.points[0]), 1.0, stats.cell_size);
}

TEST(Thicken, RadiusFromOptionsWhenSkeletonHasNone) {
    Skeleton s;
    s.points = {{0, 0, 0}};
    EXPECT_THROW(thicken(s), Error);
    ThickenOptions o;
    o.radius = 0.5;
    const SurfaceCheck c = expect_closed_outward(thicken(s, o));
    const double exact = 4.0 / 3.0 * kPi * 0.125;
    EXPECT_NEAR(c.signed_volume, exact, 0.02 * exact);
}

TEST(Thicken, CapsuleVolume) {
    Skeleton s;
    s.points = {{0, 0, 0}, {2, 1, 0}};
    s.radii = {0.5, 0.5};
    s.edges = {{0, 1}};
    const SurfaceCheck c = expect_closed_outward(thicken(s));
    ASSERT_EQ(c.components.size(), 1u);
    EXPECT_EQ(c.components[0].genus, 0);
    const double r = 0.5, L = std::sqrt(5.0);
    const double exact = kPi * r * r * L + 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_NEAR(c.signed_volume, exact, 0.02 * exact);
}

TEST(Thicken, RoundConeVolume) {
    // Cone frustum + caps: hull of spheres r=1 at 0 and r=0.5 at (3,0,0). Volume by the Pappus-free formula:
    // sin(a) = (r1 - r2) / L; caps are spherical caps beyond the tangent circles.
    const double r1 = 1.0, r2 = 0.5, L = 3.0;
    const double s = (r1 - r2) / L, c = std::sqrt(1 - s * s);
    // Tangent circles at x1 = r1 s (radius r1 c) and x2 = L + r2 s (radius r2 c).
    const double x1 = r1 * s, x2 = L + r2 * s;
    const double frustum = kPi * (x2 - x1) / 3.0 * (r1 * c * r1 * c + r1 * c * r2 * c + r2 * c * r2 * c);
    auto cap = [](double r, double hgt) { return kPi * hgt * hgt * (3 * r - hgt) / 3.0; };
    const double exact = frustum + cap(r1, r1 + x1) + cap(r2, r2 - r2 * s);
    Skeleton sk;
    sk.points = {{0, 0, 0}, {L, 0, 0}};
    sk.radii = {r1, r2};
    sk.edges = {{0, 1}};
    const SurfaceCheck chk = expect_closed_outward(thicken(sk));
    EXPECT_NEAR(chk.signed_volume, exact, 0.02 * exact);
}

TEST(Thicken, RingHasGenusOne) {
    Skeleton s;
    const int n = 12;
    const double R = 2.0;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * kPi * i / n;
        s.points.push_back({R * std::cos(a), R * std::sin(a), 0});
        s.radii.push_back(0.4);
        s.edges.push_back({i, (i + 1) % n});
    }
    const SurfaceCheck c = expect_closed_outward(thicken(s));
    ASSERT_EQ(c.components.size(), 1u);
    EXPECT_EQ(c.components[0].genus, 1);
    // A torus of tube radius 0.4 around a 12-gon inscribed in the circle: between the polygon's and the circle's tube.
    const double torus = 2 * kPi * kPi * R * 0.4 * 0.4;
    EXPECT_NEAR(c.signed_volume, torus, 0.04 * torus);
}

TEST(Thicken, SquareLeafletFollowsSteinerFormula) {
    // Unit square thickened by r = 0.2 (Minkowski sum with a ball): V = 2 r A + (pi r^2 / 2) P + 4/3 pi r^3.
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.radii = {0.2, 0.2, 0.2, 0.2};
    s.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
    s.faces = {{0, 1, 2, 3}};
    const double r = 0.2;
    const double exact = 2 * r * 1.0 + kPi * r * r / 2 * 4.0 + 4.0 / 3.0 * kPi * r * r * r;
    const SurfaceCheck c = expect_closed_outward(thicken(s));
    ASSERT_EQ(c.components.size(), 1u);
    EXPECT_EQ(c.components[0].genus, 0);
    EXPECT_NEAR(c.signed_volume, exact, 0.02 * exact);
}

TEST(Thicken, TwoSeparateSpheresGiveTwoComponents) {
    Skeleton s;
    s.points = {{0, 0, 0}, {5, 0, 0}};
    s.radii = {1.0, 0.5};
    const SurfaceCheck c = expect_closed_outward(thicken(s));
    EXPECT_EQ(c.components.size(), 2u);
}

TEST(Thicken, GridBoundRespected) {
    Skeleton s;
    s.points = {{0, 0, 0}, {10, 0, 0}};
    s.radii = {0.05, 0.05};
    s.edges = {{0, 1}};
    ThickenOptions o;
    o.max_grid_points = 50000;  // at 4 cells per radius the grid would have 815 x 15 x 15 = 183k points
    ThickenStats st;
    const TriangleMesh m = thicken(s, o, &st);
    EXPECT_LE(static_cast<long>(st.nx) * st.ny * st.nz, o.max_grid_points);
    EXPECT_GT(st.cell_size, 0.05 / 4.0);
    const SurfaceCheck c = check_surface(m);
    EXPECT_TRUE(c.is_closed_manifold());
}

TEST(Thicken, RejectsBadInput) {
    Skeleton s;
    EXPECT_THROW(thicken(s), Error);  // no point
    s.points = {{0, 0, 0}, {1, 0, 0}};
    s.radii = {1.0, -1.0};
    EXPECT_THROW(thicken(s), Error);
    s.radii = {1.0, 1.0};
    s.edges = {{0, 2}};
    EXPECT_THROW(thicken(s), Error);
}

TEST(Thicken, DeterministicForAnyThreadCount) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.3}, {0, 1, 0}};
    s.radii = {0.3, 0.2, 0.25, 0.2};
    s.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
    s.faces = {{0, 1, 2, 3}};
    TriangleMesh one_thread;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one_thread = thicken(s);
    }
    EXPECT_EQ(thicken(s), one_thread);
    EXPECT_EQ(thicken(s), thicken(s));
}

TEST(Thicken, FinerGridIsMoreAccurate) {
    Skeleton s;
    s.points = {{0, 0, 0}};
    s.radii = {1.0};
    const double exact = 4.0 / 3.0 * kPi;
    ThickenOptions coarse, fine;
    coarse.cells_per_radius = 3;
    fine.cells_per_radius = 8;
    const double e_coarse = std::abs(check_surface(thicken(s, coarse)).signed_volume - exact);
    const double e_fine = std::abs(check_surface(thicken(s, fine)).signed_volume - exact);
    EXPECT_LT(e_fine, e_coarse);
    EXPECT_LT(e_fine, 0.005 * exact);
}

TEST(Thicken, CommandLine) {
    // A two-point skeleton without radii: the command asks for --radius, then writes a closed surface.
    const std::string dir = ::testing::TempDir();
    const std::string skel = dir + "/mesohex_thicken_cli.obj", out = dir + "/mesohex_thicken_cli.off";
    {
        std::ofstream f(skel);
        f << "v 0 0 0\nv 1 0 0\nl 1 2\n";
    }
    const std::string cli = MESOHEX_CLI_PATH;
    const int no_radius = std::system((cli + " thicken " + skel + " -o " + out + " > /dev/null 2>&1").c_str());
    ASSERT_TRUE(WIFEXITED(no_radius));
    EXPECT_EQ(WEXITSTATUS(no_radius), exit_code(ErrorCode::InvalidInput));
    EXPECT_FALSE(std::ifstream(out).good());
    const int ok = std::system((cli + " thicken " + skel + " -o " + out + " --radius 0.25 > /dev/null 2>&1").c_str());
    ASSERT_TRUE(WIFEXITED(ok));
    EXPECT_EQ(WEXITSTATUS(ok), 0);
    const TriangleMesh m = read_surface(out);
    const SurfaceCheck c = check_surface(m);
    EXPECT_TRUE(c.is_closed_manifold());
    const double exact = kPi * 0.0625 * 1.0 + 4.0 / 3.0 * kPi * 0.015625;
    EXPECT_NEAR(c.signed_volume, exact, 0.02 * exact);
    std::remove(skel.c_str());
    std::remove(out.c_str());
}
