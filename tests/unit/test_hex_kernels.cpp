// The shared kernels of core/hex_kernels.h, and the vectorised scaled Jacobian of the surface fitter checked against
// them on random hexes.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/post/quality.h"
#include "mesohex/post/surface_fitting.h"

using namespace mesohex;

namespace {

std::array<Vec3, 8> unit_cube() {
    return {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{1, 1, 0}, Vec3{0, 1, 0},
            Vec3{0, 0, 1}, Vec3{1, 0, 1}, Vec3{1, 1, 1}, Vec3{0, 1, 1}};
}

}  // namespace

TEST(HexKernels, UnitCubeAndItsMirrorImage) {
    std::array<Vec3, 8> p = unit_cube();
    EXPECT_DOUBLE_EQ(hex_scaled_jacobian(p), 1.0);
    const std::array<Vec3, 3> c = hex_centre_frame(p);  // each axis: 4 x the unit vector
    EXPECT_EQ(c[0], (Vec3{4, 0, 0}));
    EXPECT_EQ(c[1], (Vec3{0, 4, 0}));
    EXPECT_EQ(c[2], (Vec3{0, 0, 4}));
    const std::array<Vec3, 3> f6 = hex_corner_frame(p, 6);  // corner (1,1,1): its edges point back along -x, -y, -z
    double d = 0;
    ASSERT_TRUE(normalized_frame_det(f6[0], f6[1], f6[2], d));
    EXPECT_DOUBLE_EQ(d, 1.0);
    for (Vec3& q : p) q.x = -q.x;
    EXPECT_DOUBLE_EQ(hex_scaled_jacobian(p), -1.0);
    p = unit_cube();
    p[1] = p[0];  // a zero-length edge: degenerate
    EXPECT_EQ(hex_scaled_jacobian(p), -1.0);
    EXPECT_EQ(frame_det_over_lengths(Vec3{}, Vec3{0, 1, 0}, Vec3{0, 0, 1}), -1.0);
}

TEST(HexKernels, IndexCheckNamesTheHex) {
    HexMesh m;
    m.points.resize(8);
    m.hexes = {{0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 8}};
    EXPECT_TRUE(hex_indices_in_range(m.hexes[0], 8));
    EXPECT_FALSE(hex_indices_in_range(m.hexes[1], 8));
    try {
        check_hex_indices(m, "stage");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        EXPECT_EQ(std::string(e.what()), "stage: hex 1 has vertex index 8 out of range");
        EXPECT_EQ(e.where().index, 1);
    }
}

// The two forms of the normalized determinant agree to rounding; scaled_jacobian (post/quality.h) is the core one.
TEST(HexKernels, BothDeterminantFormsAgreeOnRandomHexes) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.45, 0.45);
    for (int i = 0; i < 1000; ++i) {
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& q : p) q += Vec3{u(rng), u(rng), u(rng)};
        EXPECT_EQ(scaled_jacobian(p), hex_scaled_jacobian(p));
        for (std::size_t lv = 0; lv < 8; ++lv) {
            const std::array<Vec3, 3> f = hex_corner_frame(p, lv);
            double d = 0;
            ASSERT_TRUE(normalized_frame_det(f[0], f[1], f[2], d));
            EXPECT_NEAR(frame_det_over_lengths(f[0], f[1], f[2]), d, 1e-14);
        }
    }
}

// SurfaceFitter measures its hexes with its own vectorised kernel (blocks of hexes, structure of arrays): on random
// hexes (many inverted, some degenerate), its minimum equals the core kernel's within 1e-12.
TEST(HexKernels, VectorisedFittingKernelMatchesTheCoreOne) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.7, 0.7);
    const SurfaceProjector identity([](const std::vector<Vec3>& in, std::vector<Vec3>& out) { out = in; });
    int inverted = 0;
    for (int i = 0; i < 300; ++i) {
        HexMesh m;
        const std::array<Vec3, 8> cube = unit_cube();
        for (const Vec3& q : cube) m.points.push_back(q + Vec3{u(rng), u(rng), u(rng)});
        if (i % 50 == 0) m.points[3] = m.points[0];  // a degenerate hex now and then
        m.hexes = {{0, 1, 2, 3, 4, 5, 6, 7}};
        std::array<Vec3, 8> p;
        for (std::size_t k = 0; k < 8; ++k) p[k] = m.points[k];
        const double core = hex_scaled_jacobian(p);
        const SurfaceFitter fitter(m, identity);
        EXPECT_NEAR(fitter.sj_min(), core, 1e-12) << "hex " << i;
        EXPECT_EQ(fitter.inverted(), core > 0 ? 0 : 1) << "hex " << i;
        if (core <= 0) ++inverted;
    }
    EXPECT_GT(inverted, 10);  // the sample covers inverted hexes too
}

// The smoothing's nine frame values and the junction model's corner value: 1 on the unit cube, -1 on a degenerate
// frame, and on random hexes the same numbers as the normalized determinant up to rounding (their minimum is the
// scaled Jacobian).
TEST(HexKernels, FrameValuesAndCornerValueAgreeWithTheNormalizedDeterminant) {
    const std::array<Vec3, 8> cube = unit_cube();
    for (double q : hex_frame_values(cube)) EXPECT_DOUBLE_EQ(q, 1.0);
    for (std::size_t lv = 0; lv < 8; ++lv) EXPECT_DOUBLE_EQ(hex_corner_value(cube, lv), 1.0);
    std::array<Vec3, 8> flat = cube;
    flat[1] = flat[0];  // corner 0 loses its x edge, corner 1 its -x edge
    EXPECT_EQ(hex_frame_values(flat)[1], -1.0);
    EXPECT_EQ(hex_corner_value(flat, 0), -1.0);
    EXPECT_EQ(hex_corner_value(flat, 1), -1.0);
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    for (int i = 0; i < 500; ++i) {
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& q : p) q += Vec3{u(rng), u(rng), u(rng)};
        const std::array<double, 9> values = hex_frame_values(p);
        double d = 0;
        const std::array<Vec3, 3> c = hex_centre_frame(p);
        ASSERT_TRUE(normalized_frame_det(c[0], c[1], c[2], d));
        EXPECT_NEAR(values[0], d, 1e-14);
        double lowest = values[0];
        for (std::size_t lv = 0; lv < 8; ++lv) {
            const std::array<Vec3, 3> f = hex_corner_frame(p, lv);
            ASSERT_TRUE(normalized_frame_det(f[0], f[1], f[2], d));
            EXPECT_NEAR(values[lv + 1], d, 1e-14);
            EXPECT_NEAR(hex_corner_value(p, lv), d, 1e-14);
            lowest = std::min(lowest, values[lv + 1]);
        }
        EXPECT_NEAR(lowest, hex_scaled_jacobian(p), 1e-14);
    }
}
