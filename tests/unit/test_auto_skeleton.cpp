// choose_skeleton on a generated thick plate (4 x 4 x 0.6 box): Auto takes the medial meso-skeleton, its radii are
// meso_full_radius_factor x the distance to the surface (meso_radius_factor when those fail the raw check), and the raw
// check's numbers are those its options require.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "mesohex/auto_skeleton.h"
#include "mesohex/mesh.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/surface/medial_axis.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"
#include "skeleton_fixtures.h"
#include "surface_fixtures.h"

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

TEST(AutoSkeleton, InvertedRawHexesAreLocatedByTheirSkeletonElement) {
    // A quad leaflet 0-1-2-3 with a branch 2-4: vertex 2 is the one join. Five hexes: the unit cube (positive, not
    // counted) and four inverted ones (the cube with top and bottom swapped: scaled Jacobian -1), made by a plate
    // (hex_edge -1), the border edge 0-1 (a half-chunk away from the join), the branch edge 2-4 (a chunk at the join)
    // and the border edge 1-2 (a half-chunk at the join).
    Skeleton sk;
    sk.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 2, 0}};
    sk.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {2, 4}};
    sk.faces = {{0, 1, 2, 3}};
    RawMesh raw;
    for (int k = 0; k < 8; ++k) raw.mesh.points.push_back({k & 1 ? 1.0 : 0.0, k & 2 ? 1.0 : 0.0, k & 4 ? 1.0 : 0.0});
    const std::array<int, 8> cube = {0, 1, 3, 2, 4, 5, 7, 6};  // VTK order
    const std::array<int, 8> flipped = {4, 5, 7, 6, 0, 1, 3, 2};
    raw.mesh.hexes = {cube, flipped, flipped, flipped, flipped};
    raw.hex_edge = {-1, -1, 0, 4, 1};
    const RawInversionSites w = locate_raw_inversions(sk, raw);
    EXPECT_EQ(w.joins, 1);
    EXPECT_EQ(w.plates, 1);
    EXPECT_EQ(w.half_chunks, 2);
    EXPECT_EQ(w.chunks, 1);
    EXPECT_EQ(w.at_joins, 2);
}

TEST(AutoSkeleton, LeafletRadiiAreCappedOnlyOnTheFacesAtAJoin) {
    // Two unit-wide quads in a strip: A = 0-1-2-3 (sides 1), B = 1-4-5-2 (sides 2, 1, 2, 1), and a curve edge 0-6:
    // vertex 0 is the one join, so only A's other corners are capped, at 0.5 x their shortest side (1): 1 and 2 from
    // 0.8 to 0.5; 3 (0.3) is below the cap; the join 0, 4 and 5 (only on B) and the curve vertex 6 keep 0.8.
    Skeleton sk;
    sk.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {3, 0, 0}, {3, 1, 0}, {-1, 0, 0}};
    sk.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {1, 4}, {4, 5}, {5, 2}, {0, 6}};
    sk.faces = {{0, 1, 2, 3}, {1, 4, 5, 2}};
    sk.radii = {0.8, 0.8, 0.8, 0.3, 0.8, 0.8, 0.8};
    Skeleton none = sk;
    EXPECT_EQ(cap_leaflet_radii(none, 0), 0);
    EXPECT_EQ(none.radii, sk.radii);
    EXPECT_EQ(cap_leaflet_radii(sk, 0.5), 2);
    const std::vector<double> want = {0.8, 0.5, 0.5, 0.3, 0.8, 0.8, 0.8};
    EXPECT_EQ(sk.radii, want);
    Skeleton sheet = sk;  // without the curve edge there is no join: nothing changes
    sheet.edges.pop_back();
    sheet.points.pop_back();
    sheet.radii = {0.8, 0.8, 0.8, 0.3, 0.8, 0.8};
    EXPECT_EQ(cap_leaflet_radii(sheet, 0.5), 0);
}

// A creased strip like knob's ring band: two walls one quad tall (z = 0, 1) meeting along the crease x = y = 0 at an
// interior angle of `angle` degrees (100: the band turns by 80 degrees, as at knob's six creases). Wall B has a
// column at 1 and 2 along (cos angle, sin angle, 0), wall A at `short_side` and short_side + 1 along +x: the border
// sides 2-3 and 7-8 next to the crease are short against the radius 0.45 of every vertex (knob after the leaflet
// smoothing: sides of 0.12 to 0.34 against radii of 0.6 to 0.7).
Skeleton creased_strip(double angle, double short_side) {
    Skeleton sk;
    const double c = std::cos(angle * std::numbers::pi / 180), s = std::sin(angle * std::numbers::pi / 180);
    const std::vector<Vec3> base = {
        {2 * c, 2 * s, 0}, {c, s, 0}, {0, 0, 0}, {short_side, 0, 0}, {1 + short_side, 0, 0}};
    for (int z = 0; z < 2; ++z)
        for (const Vec3& b : base) sk.points.push_back({b[0], b[1], static_cast<double>(z)});
    for (int i = 0; i < 4; ++i) sk.faces.push_back({i, i + 1, i + 6, i + 5});
    add_face_edges(sk);
    sk.radii.assign(sk.points.size(), 0.45);
    return sk;
}

// Inverted hexes of sk's raw mesh, counted (mesh_skeleton would refuse a raw output that folds at a moved root or a
// crease's border end: check_moved_roots, check_border_creases). offset_fraction: RawMeshOptions::
// leaflet_offset_fraction (-1: the default). The tests of the border-side mechanisms below turn it off (0): they were
// written before it, and with it their uncapped strip and unguarded band invert no raw hex either (the copies at
// their creases are pulled in).
long raw_inverted(const Skeleton& sk, double offset_fraction = -1) {
    PipelineOptions o = MeshOptions{}.pipeline;
    if (offset_fraction >= 0) o.raw_mesh.leaflet_offset_fraction = offset_fraction;
    return compute_quality(run_pipeline(sk, o).raw.mesh).inverted;
}

TEST(AutoSkeleton, BorderRadiiAreCappedAtTheirShortestBorderSide) {
    Skeleton sk = creased_strip(100, 0.15);
    ASSERT_EQ(sk.points.size(), 10u);
    ASSERT_EQ(sk.edges.size(), 13u);
    Skeleton none = sk;
    EXPECT_EQ(cap_border_radii(none, 0), 0);
    EXPECT_EQ(none.radii, sk.radii);
    // Every vertex is on the border. The ends of the short sides (2, 3, 7, 8) go to 0.5 x 0.15; the others' shortest
    // border side is 1, and 0.5 x 1 is above their 0.45.
    EXPECT_EQ(cap_border_radii(sk, 0.5), 4);
    for (int v = 0; v < 10; ++v) {
        const bool short_end = v == 2 || v == 3 || v == 7 || v == 8;
        EXPECT_NEAR(sk.radii[static_cast<size_t>(v)], short_end ? 0.075 : 0.45, 1e-12) << v;
    }
}

TEST(AutoSkeleton, CreasedStripWithShortBorderSidesMeshesWithoutInversionOnceCapped) {
    // The short sides fold the raw mesh only at the crease: flat (180 degrees), the same strip has no inverted hex.
    // (leaflet_offset_fraction off; with its default 0.5 the uncapped creased strip has none either.)
    EXPECT_EQ(raw_inverted(creased_strip(180, 0.15), 0), 0);
    const Skeleton sk = creased_strip(100, 0.15);
    EXPECT_EQ(raw_inverted(sk, 0), 3);
    EXPECT_EQ(raw_inverted(sk), 0);
    Skeleton capped = sk;
    cap_border_radii(capped, 0.5);
    EXPECT_EQ(raw_inverted(capped, 0), 0);
}

// Inverted raw hexes of medial mesh m imported with `off`; asserts that the defaults' import moved exactly one join
// of the kind `moved` reads and returns its raw inverted hexes in *on_inverted.
long raw_inverted_without(const Skeleton& m, const MedialImportOptions& off, int MedialImport::*moved,
                          long* on_inverted) {
    const MedialImport on = import_medial_mesh(m);
    EXPECT_EQ(on.*moved, 1);
    *on_inverted = raw_inverted(on.skeleton);
    return raw_inverted(import_medial_mesh(m, off).skeleton);
}

TEST(AutoSkeleton, NotchJoinMadeALeafletCornerMeshesWithoutInversion) {
    // An L of three unit squares with a curve from its notch vertex (1, 1) into the gap (radius 0.1): the BL-joint's
    // half-chunks inside the notch fold (4 inverted raw hexes); moved past the chord of its border neighbours (the
    // long curve) or capped at 0.2 x the curve (the short one, to (1.2, 1.2)), none.
    for (const Vec3& to : {Vec3{5, 5, 0.5}, Vec3{2, 2, 0}}) {
        SCOPED_TRACE(to.x);
        MedialImportOptions off;
        off.bl_joint_reflex_corners = false;
        long on = -1;
        EXPECT_EQ(raw_inverted_without(test::notch_l_with_a_curve(to, 0.1), off, &MedialImport::notch_corners, &on), 4);
        EXPECT_EQ(on, 0);
    }
}

TEST(AutoSkeleton, JoinOfTwoCurvesMadeALeafletCornerMeshesWithoutInversion) {
    // Two unit squares; from the middle of their straight border (1, 0, 0) a curve of two edges goes down and below
    // the plane (to (1, -2, -1)), one edge goes to (0, -3, 0); radius 0.05. Left on the straight border, the join
    // folds 2 raw hexes (4 with the pattern search's degree-3 orange, before SpherePartitionOptions::
    // exact_three_orange); pushed out to a corner (0.2 x the shorter curve), none.
    MedialImportOptions off;
    off.bl_joint_corners_with_branches = false;
    long on = -1;
    EXPECT_EQ(raw_inverted_without(test::two_curves_on_a_straight_border({1, -1, -1}, {1, -2, -1}, {0, -3, 0}, 0.05),
                                   off, &MedialImport::branch_corners, &on),
              2);
    EXPECT_EQ(on, 0);
}

TEST(AutoSkeleton, JoinHandedToACornerMeshesWithoutInversion) {
    // Three unit squares in a row; the two short curves of border vertex 1 move onto corner 0 (see
    // MedialImport.ShortCurvesOfAJoinMoveOntoTheNearestConvexCorner); the raw mesh keeps 0 inverted hexes for thin to
    // thick radii.
    for (double r : {0.01, 0.05, 0.1}) {
        SCOPED_TRACE(r);
        const MedialImport im =
            import_medial_mesh(test::two_curves_next_to_a_corner({1, -1, -1}, {1, -2, -1}, {0, -3, 0}, r));
        EXPECT_EQ(im.joins_to_corners, 1);
        EXPECT_EQ(raw_inverted(im.skeleton), 0);
    }
}

TEST(AutoSkeleton, StubOnASheetBorderInvertsItsChunksAndIsPrunedAsASpur) {
    // Three unit squares in a row (6 triangles) with one curve edge from border vertex 1 = (1, 0, 0) straight out to
    // (1, -len, 0), every radius 0.3: torque's stubs after the fringe removal (one edge, 0.66 to 0.88 x the join's
    // radius). The branch's one chunk starts beyond the join's block, about one radius out, past its own end: its 4
    // hexes invert.
    // prune_spurs (length + 0.3 < 2 x 0.3) removes it; the sheet alone meshes without inversion.
    for (double len : {0.2, 0.25}) {
        SCOPED_TRACE(len);
        Skeleton m = test::medial_mesh(
            {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {3, 1, 0}, {1, -len, 0}},
            {{1, 8}}, {{0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}}, 0.3);
        EXPECT_EQ(raw_inverted(import_medial_mesh(m).skeleton), 4);  // the 4 hexes of its one chunk
        EXPECT_EQ(prune_spurs(m, 2.0), 1);
        ASSERT_EQ(m.points.size(), 8u);
        ASSERT_EQ(m.edges.size(), 13u);  // the sheet's sides only
        EXPECT_EQ(raw_inverted(import_medial_mesh(m).skeleton), 0);
    }
}

TEST(AutoSkeleton, PinchFilledAcrossItsNarrowGapMeshesWithoutInversion) {
    // Two leaflets touching at vertex 0 with gaps of 5 or 15 and 100 degrees between them (an LL-joint): the
    // pillow's in-plane points lie in the gaps, so the half-chunks on both sides of the narrow gap stand on corners
    // of at most half of it and invert, 2 hexes each (up and down) for radii from 0.1 (a tenth of the border sides).
    // With the narrow gap filled (60 degrees, the default) the pinch is a plain border vertex: none.
    MedialImportOptions off, fill;
    off.fill_pinch_max_angle_deg = 0;
    fill.fill_pinch_max_angle_deg = 60;
    for (double gap : {5.0, 15.0})
        for (double r : {0.1, 0.2, 0.3}) {
            SCOPED_TRACE(testing::Message() << gap << " " << r);
            const Skeleton m = test::pinch_of_two_fans(gap, r);
            EXPECT_EQ(raw_inverted(import_medial_mesh(m, off).skeleton), 4);
            const MedialImport on = import_medial_mesh(m, fill);
            EXPECT_EQ(on.filled_pinches, 1);
            EXPECT_EQ(raw_inverted(on.skeleton), 0);
        }
}

// A medial band like knob's ring wall at one of its creases: two walls of 3 segments of 1.5 along the base, one
// triangle pair tall (height 2), meeting at an interior angle of 100 degrees (the band turns by 80), medial radius 2.3
// (knob's band); 14 points, 12 triangles, 6 pair quads.
Skeleton creased_medial_band() {
    const double c = std::cos(100 * std::numbers::pi / 180), s = std::sin(100 * std::numbers::pi / 180);
    std::vector<Vec3> base;
    for (int i = 3; i >= 1; --i) base.push_back({1.5 * i * c, 1.5 * i * s, 0});
    for (int i = 0; i <= 3; ++i) base.push_back({1.5 * i, 0, 0});
    std::vector<Vec3> points;
    for (double z : {0.0, 2.0})
        for (const Vec3& b : base) points.push_back({b.x, b.y, z});
    std::vector<std::vector<int>> triangles;
    for (int i = 0; i < 6; ++i) {
        triangles.push_back({i, i + 1, 7 + i + 1});
        triangles.push_back({i, 7 + i + 1, 7 + i});
    }
    return test::medial_mesh(points, {}, triangles, 2.3);
}

// The shortest leaflet border side (a side in one face) of s.
double shortest_border_side(const Skeleton& s) {
    std::map<std::array<int, 2>, int> faces;
    for (const std::vector<int>& f : s.faces)
        for (size_t k = 0; k < f.size(); ++k)
            ++faces[{std::min(f[k], f[(k + 1) % f.size()]), std::max(f[k], f[(k + 1) % f.size()])}];
    double shortest = std::numeric_limits<double>::infinity();
    for (const auto& [side, n] : faces)
        if (n == 1) shortest = std::min(shortest, distance(s.points[side[0]], s.points[side[1]]));
    return shortest;
}

TEST(AutoSkeleton, CreasedBandKeepsItsBorderSidesAndMeshesWithoutInversion) {
    // Imported as `auto` does (the smoothing within 0.25 x the radius of the sheet) and meshed with radius 0.65
    // (knob's): 6 pair quads split in 4 = 24 faces; 14 corners + 19 side midpoints + 6 centres = 39 points; the border
    // sides are 0.75 after the split. Without the border-side guard the smoothing slides the crease's border ends
    // along the other wall to 0.150 of their neighbours and 4 raw hexes invert; with it (0.5) no border side is
    // below 0.5 x 0.75 and none does.
    const Skeleton m = creased_medial_band();
    for (const double fraction : {0.0, 0.5}) {
        SCOPED_TRACE(fraction);
        MedialImportOptions o = meso_import_options();
        o.min_border_side_fraction = fraction;
        MedialImport im = import_medial_mesh(m, o);
        ASSERT_EQ(im.skeleton.faces.size(), 24u);
        ASSERT_EQ(im.skeleton.points.size(), 39u);
        im.skeleton.radii.assign(im.skeleton.points.size(), 0.65);
        const double shortest = shortest_border_side(im.skeleton);
        // (leaflet_offset_fraction off; with its default 0.5 the unguarded band has none either.)
        if (fraction == 0) {
            EXPECT_NEAR(shortest, 0.150, 0.005);
            EXPECT_EQ(raw_inverted(im.skeleton, 0), 4);
            EXPECT_EQ(raw_inverted(im.skeleton), 0);
        } else {
            EXPECT_GE(shortest, 0.375 - 1e-12);
            EXPECT_EQ(raw_inverted(im.skeleton, 0), 0);
        }
    }
}

// The plate's medial axis is its mid-plane (one sheet, no curve): its raw mesh at the full radii (the distance to the
// surface, the half-thickness 0.3) has nothing inverted, so the full radii are kept.
TEST(AutoSkeleton, ThickPlateTakesTheMesoSkeletonWithFullRadii) {
    const TriangleMesh s = box(2, 0.3);
    const AutoSkeletonOptions o;
    const AutoSkeleton a = choose_skeleton(s, o);
    ASSERT_EQ(a.kind, SkeletonKind::Meso) << a.reason;
    ASSERT_TRUE(a.raw_checked);
    EXPECT_EQ(a.meso_radius_factor_used, o.meso_full_radius_factor);
    EXPECT_FALSE(a.full_raw_failed);
    EXPECT_NE(a.reason.find("full radii"), std::string::npos) << a.reason;
    EXPECT_LE(a.raw_inverted, o.max_raw_inverted);
    EXPECT_EQ(a.raw_sites.joins, 0);  // one sheet, no curve
    EXPECT_EQ(a.raw_sites.plates + a.raw_sites.half_chunks + a.raw_sites.chunks, a.raw_inverted);
    EXPECT_GE(a.raw_sj_min, o.min_raw_sj);
    const SurfaceQuery q(s);
    const RadiusFromSurface d = radius_from_surface(a.skeleton, q, {1.0});
    ASSERT_EQ(a.skeleton.radii.size(), a.skeleton.points.size());
    for (size_t v = 0; v < a.skeleton.points.size(); ++v) {
        EXPECT_NEAR(a.skeleton.radii[v], d.distance[v], 1e-12);
        // The sheet is the mid-plane: the distance is at most the half-thickness 0.3.
        EXPECT_LE(a.skeleton.radii[v], 0.3 + 1e-9);
    }
}

// When the raw mesh at the full radii fails the check (here: a budget of -1 inverted hexes, which no mesh passes), the
// meso-skeleton takes meso_radius_factor x the distance and says so; Auto then falls back to the curve skeleton (the
// half radii fail too), a forced meso-skeleton keeps the half radii.
TEST(AutoSkeleton, FullRadiiThatFailTheRawCheckFallBackToHalfRadii) {
    const TriangleMesh s = box(2, 0.3);
    AutoSkeletonOptions o;
    o.max_raw_inverted = -1;
    const AutoSkeleton a = choose_skeleton(s, o);
    EXPECT_EQ(a.kind, SkeletonKind::Curve) << a.reason;
    EXPECT_TRUE(a.full_raw_failed);
    EXPECT_EQ(a.full_raw_inverted, 0);
    EXPECT_TRUE(a.full_raw_valid);
    EXPECT_EQ(a.meso_radius_factor_used, o.meso_radius_factor);
    EXPECT_NE(a.reason.find("fails the check; 0.5 x distance instead"), std::string::npos) << a.reason;

    o.kind = SkeletonKind::Meso;
    const AutoSkeleton m = choose_skeleton(s, o);
    ASSERT_EQ(m.kind, SkeletonKind::Meso);
    EXPECT_TRUE(m.full_raw_failed);
    EXPECT_EQ(m.meso_radius_factor_used, 0.5);
    const SurfaceQuery q(s);
    const RadiusFromSurface d = radius_from_surface(m.skeleton, q, {1.0});
    for (size_t v = 0; v < m.skeleton.points.size(); ++v) EXPECT_NEAR(m.skeleton.radii[v], 0.5 * d.distance[v], 1e-12);

    o.meso_full_radius_factor = 0;  // off: the half radii only, nothing tried before
    const AutoSkeleton h = choose_skeleton(s, o);
    EXPECT_FALSE(h.full_raw_failed);
    EXPECT_EQ(h.meso_radius_factor_used, 0.5);
}

TEST(AutoSkeleton, ZeroRadiusFactorKeepsTheMedialRadii) {
    const TriangleMesh s = box(2, 0.3);
    AutoSkeletonOptions o;
    o.kind = SkeletonKind::Meso;
    o.meso_radius_factor = 0;
    o.meso_full_radius_factor = 0;  // the medial radii only
    const AutoSkeleton a = choose_skeleton(s, o);
    ASSERT_EQ(a.kind, SkeletonKind::Meso);
    EXPECT_EQ(a.skeleton.radii, a.import.skeleton.radii);
    // Medial radii of the plate's mid-sheet: about the half-thickness 0.3 (poles overestimate by up to 20 %).
    for (double r : a.skeleton.radii) EXPECT_NEAR(r, 0.3, 0.07);
}

// A torus (R 2, r 0.5) is a tube: Auto takes the curve skeleton and checks its raw mesh and the padding layer on it;
// a clean closed tube of hexes has nothing inverted, so there is no refusal. With a budget of -1 inverted hexes (none
// can pass) the same surface is refused, and the refusal gives the curve skeleton's numbers.
TEST(AutoSkeleton, TorusTakesTheCurveSkeletonAndIsAnswered) {
    const TriangleMesh s = test::torus_surface(2, 0.5, 48, 16);
    AutoSkeletonOptions o;
    const AutoSkeleton a = choose_skeleton(s, o);
    ASSERT_EQ(a.kind, SkeletonKind::Curve) << a.reason;
    ASSERT_TRUE(a.curve_raw_checked);
    EXPECT_TRUE(a.curve_raw_valid);
    EXPECT_GT(a.curve_raw_hexes, 0);
    EXPECT_EQ(a.curve_raw_inverted, 0);
    EXPECT_EQ(a.curve_padded_inverted, 0);
    EXPECT_GT(a.curve_raw_sj_min, 0);
    EXPECT_TRUE(a.refusal.empty()) << a.refusal;

    o.max_answer_inverted = -1;
    const AutoSkeleton r = choose_skeleton(s, o);
    EXPECT_EQ(r.skeleton, a.skeleton);  // the skeleton is still returned, for editing
    EXPECT_NE(r.refusal.find("curve skeleton " + std::to_string(a.curve_raw_hexes) + " raw hexes, 0 inverted"),
              std::string::npos)
        << r.refusal;
}

// Forced kinds are never refused (the user asked for that skeleton) and skip the raw checks.
TEST(AutoSkeleton, ForcedCurveIsNotChecked) {
    AutoSkeletonOptions o;
    o.kind = SkeletonKind::Curve;
    o.max_answer_inverted = -1;
    const AutoSkeleton a = choose_skeleton(test::torus_surface(2, 0.5, 48, 16), o);
    EXPECT_EQ(a.kind, SkeletonKind::Curve);
    EXPECT_FALSE(a.curve_raw_checked);
    EXPECT_TRUE(a.refusal.empty());
}

}  // namespace
}  // namespace mesohex
