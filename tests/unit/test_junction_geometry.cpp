// Junction geometry (stages/junction_geometry): quad margins, the margin-limited radius, frames; values checked by
// hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesohex/stages/junction_geometry.h"

using namespace mesohex;

namespace {

// The quad at 45 degrees from +z at azimuths 0, 90, 180, 270 degrees (counter-clockwise seen from +z).
std::array<Vec3, 4> cone_quad() {
    return {normalized(Vec3{1, 0, 1}), normalized(Vec3{0, 1, 1}), normalized(Vec3{-1, 0, 1}),
            normalized(Vec3{0, -1, 1})};
}

}  // namespace

TEST(JunctionGeometry, MarginOfTheAxisInsideASymmetricQuad) {
    // Side planes through (1,0,1) and (0,1,1): normal (-1,-1,1) / sqrt 3, so +z is asin(1 / sqrt 3) inside every side.
    const std::array<Vec3, 4> q = cone_quad();
    EXPECT_NEAR(spherical_quad_margin(q, {0, 0, 1}), std::asin(1 / std::sqrt(3.0)), 1e-12);
    EXPECT_NEAR(spherical_quad_margin(q, {0, 0, -1}), -std::asin(1 / std::sqrt(3.0)), 1e-12);
    // On a side's great circle: margin 0.
    EXPECT_NEAR(spherical_quad_margin(q, normalized(Vec3{1, 1, 2})), 0.0, 1e-12);
    // Listed clockwise, every corner is reflex: -1.
    EXPECT_EQ(spherical_quad_margin({q[0], q[3], q[2], q[1]}, {0, 0, 1}), -1.0);
}

TEST(JunctionGeometry, MarginLimitedRadius) {
    const double pi = std::numbers::pi;
    EXPECT_NEAR(margin_limited_radius(2.0, 2.0, pi / 6, 1.0), 1.0, 1e-15);  // 2 sin 30 deg
    EXPECT_EQ(margin_limited_radius(0.25, 2.0, pi / 6, 1.0), 0.25);         // already smaller
    EXPECT_NEAR(margin_limited_radius(2.0, 2.0, pi / 6, 0.5), 2 * std::sin(pi / 12), 1e-15);
    EXPECT_EQ(kBranchMarginFraction, 0.75);
}

TEST(JunctionGeometry, OrthonormalFrames) {
    const Frame f = orthonormal_frame({2, 0, 5}, {0, 0, 1});  // the hint's part along t is dropped
    EXPECT_EQ(f.r, (Vec3{1, 0, 0}));
    EXPECT_EQ(f.s, (Vec3{0, 1, 0}));
    EXPECT_EQ(f.t, (Vec3{0, 0, 1}));
    EXPECT_EQ(any_perpendicular({0, 0, 1}), (Vec3{0, 1, 0}));  // t x (1, 0, 0)
    const Frame g = orthonormal_frame({0, 0, 3}, {0, 0, 1});   // hint along t: any perpendicular
    EXPECT_NEAR(dot(g.r, g.t), 0.0, 1e-15);
    EXPECT_NEAR(norm(g.r), 1.0, 1e-15);
}

TEST(JunctionGeometry, StraightTransportKeepsTheFrameAndAQuarterTurnTurnsIt) {
    const Frame f{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const Frame g = rotation_minimizing_step(f, {0, 0, 0}, {0, 0, 2}, {0, 0, 1});
    EXPECT_NEAR(norm(g.r - f.r), 0.0, 1e-15);
    EXPECT_NEAR(norm(g.s - f.s), 0.0, 1e-15);
    // A quarter arc in the xz plane (chord (1, 0, 1), tangent +z -> +x): the first reflection (across the plane normal
    // to the chord) sends r = +x to -z and t to -x, the second (normal to t1 - (-x)) leaves -z: the frame turns by
    // 90 degrees about y, s = +y stays.
    const Frame h = rotation_minimizing_step(f, {0, 0, 0}, {1, 0, 1}, {1, 0, 0});
    EXPECT_NEAR(norm(h.r - Vec3{0, 0, -1}), 0.0, 1e-12);
    EXPECT_NEAR(norm(h.s - Vec3{0, 1, 0}), 0.0, 1e-12);
}
