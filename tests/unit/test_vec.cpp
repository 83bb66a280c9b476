#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "mesohex/core/vec.h"

using mesohex::Vec3;

TEST(Vec3, CrossOfAxesIsRightHanded) {
    EXPECT_EQ(mesohex::cross(Vec3{1, 0, 0}, Vec3{0, 1, 0}), (Vec3{0, 0, 1}));
    EXPECT_DOUBLE_EQ(mesohex::det3(Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}), 1.0);
}

// cross(b, a) == -cross(a, b) and dot(b, a) == dot(a, b) bit for bit: each product is rounded on its own and
// x - y == -(y - x) exactly in IEEE arithmetic. margin_bounds (sphere_partition.cpp) takes each pair's angle once on
// this; a build that fuses cross's products into multiply-adds fails here (GCC -march=haswell: 7 154 of the pairs).
TEST(Vec3, CrossIsAntisymmetricBitForBit) {
    std::uint64_t state = 35;
    const auto next = [&] {  // a fixed LCG: the same inputs on every platform, in [-1, 1)
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * 0x1.0p-52 - 1;
    };
    constexpr int kPairs = 10000;
    std::vector<Vec3> a(kPairs), b(kPairs), ab(kPairs), ba(kPairs);
    for (int i = 0; i < kPairs; ++i) {
        a[i] = {next(), next(), next()};
        b[i] = {next(), next(), next()};
    }
    // Two separate loops, as margin_bounds' callers see one order at a time (no product shared between the orders).
    for (int i = 0; i < kPairs; ++i) ab[i] = mesohex::cross(a[i], b[i]);
    for (int i = 0; i < kPairs; ++i) ba[i] = mesohex::cross(b[i], a[i]);
    int asymmetric = 0;
    for (int i = 0; i < kPairs; ++i)
        if (!(ba[i].x == -ab[i].x && ba[i].y == -ab[i].y && ba[i].z == -ab[i].z) ||
            mesohex::dot(a[i], b[i]) != mesohex::dot(b[i], a[i]))
            ++asymmetric;
    EXPECT_EQ(asymmetric, 0);
}

TEST(Vec3, NormalizedZeroStaysZero) {
    EXPECT_EQ(mesohex::normalized(Vec3{}), (Vec3{}));
    EXPECT_DOUBLE_EQ(mesohex::norm(mesohex::normalized(Vec3{3, 4, 0})), 1.0);
}

// Triangle (0,0,0) (1,0,0) (0,1,0): every Voronoi region of it, by hand.
TEST(Vec3, ClosestPointOnTriangle) {
    const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
    auto closest = [&](const Vec3& p) { return mesohex::closest_point_on_triangle(p, a, b, c); };
    const Vec3 inside = closest({0.2, 0.2, 1});  // above the interior: (0.2, 0.2, 0), up to rounding
    EXPECT_NEAR(inside.x, 0.2, 1e-15);
    EXPECT_NEAR(inside.y, 0.2, 1e-15);
    EXPECT_EQ(inside.z, 0.0);
    EXPECT_EQ(closest({-1, -1, 0}), a);  // corners
    EXPECT_EQ(closest({2, -1, 0}), b);
    EXPECT_EQ(closest({0, 2, 0.5}), c);
    EXPECT_EQ(closest({0.5, -1, 3}), (Vec3{0.5, 0, 0}));    // edge ab
    EXPECT_EQ(closest({-1, 0.25, 0}), (Vec3{0, 0.25, 0}));  // edge ca
    const Vec3 on_bc = closest({1, 1, 0});                  // edge bc: its midpoint
    EXPECT_NEAR(on_bc.x, 0.5, 1e-15);
    EXPECT_NEAR(on_bc.y, 0.5, 1e-15);
    EXPECT_EQ(on_bc.z, 0.0);
    // A degenerate triangle (three collinear points) still gives a point of the segment.
    const Vec3 d = mesohex::closest_point_on_triangle({0.5, 1, 0}, a, b, Vec3{2, 0, 0});
    EXPECT_NEAR(d.x, 0.5, 1e-15);
    EXPECT_EQ(d.y, 0.0);
}
