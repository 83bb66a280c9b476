// choose_skeleton on a generated thick plate (4 x 4 x 0.6 box): Auto takes the medial meso-skeleton, its radii are
// meso_radius_factor x the distance to the surface, and the raw check's numbers are those its options require.
#include <gtest/gtest.h>

#include <cmath>

#include "mesohex/auto_skeleton.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex {
namespace {

// Axis-aligned box [-a, a] x [-a, a] x [-t, t], 12 outward triangles.
TriangleMesh box(double a, double t) {
    TriangleMesh m;
    for (int k = 0; k < 8; ++k) m.points.push_back({k & 1 ? a : -a, k & 2 ? a : -a, k & 4 ? t : -t});
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return m;
}

TEST(AutoSkeleton, ThickPlateTakesTheMesoSkeletonWithHalfDistanceRadii) {
    const TriangleMesh s = box(2, 0.3);
    const AutoSkeletonOptions o;
    const AutoSkeleton a = choose_skeleton(s, o);
    ASSERT_EQ(a.kind, SkeletonKind::Meso) << a.reason;
    ASSERT_TRUE(a.raw_checked);
    EXPECT_LE(a.raw_inverted, o.max_raw_inverted);
    EXPECT_GE(a.raw_sj_min, o.min_raw_sj);
    const SurfaceQuery q(s);
    const RadiusFromSurface d = radius_from_surface(a.skeleton, q, {1.0});
    ASSERT_EQ(a.skeleton.radii.size(), a.skeleton.points.size());
    for (size_t v = 0; v < a.skeleton.points.size(); ++v) {
        EXPECT_NEAR(a.skeleton.radii[v], 0.5 * d.distance[v], 1e-12);
        // The sheet is the mid-plane: half the distance is about half the half-thickness, at most 0.15.
        EXPECT_LE(a.skeleton.radii[v], 0.15 + 1e-9);
    }
}

TEST(AutoSkeleton, ZeroRadiusFactorKeepsTheMedialRadii) {
    const TriangleMesh s = box(2, 0.3);
    AutoSkeletonOptions o;
    o.kind = SkeletonKind::Meso;
    o.meso_radius_factor = 0;
    const AutoSkeleton a = choose_skeleton(s, o);
    ASSERT_EQ(a.kind, SkeletonKind::Meso);
    EXPECT_EQ(a.skeleton.radii, a.import.skeleton.radii);
    // Medial radii of the plate's mid-sheet: about the half-thickness 0.3 (poles overestimate by up to 20 %).
    for (double r : a.skeleton.radii) EXPECT_NEAR(r, 0.3, 0.07);
}

}  // namespace
}  // namespace mesohex
