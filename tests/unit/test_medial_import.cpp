// Medial mesh (.ma) reading and medial mesh -> meso-skeleton conversion on tiny inputs checkable on paper.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex_io/medial_io.h"
#include "quad_skeleton_checks.h"
#include "skeleton_fixtures.h"

namespace mesohex {
namespace {

using test::medial_mesh;

// Unit square split along its diagonal 0-2 into two triangles, oriented the same way.
Skeleton unit_square() { return medial_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {}, {{0, 1, 2}, {0, 2, 3}}); }

TEST(MedialImport, SquareOfTwoTrianglesPairsIntoOneQuadSplitInFour) {
    const MedialImport r = import_medial_mesh(unit_square());
    EXPECT_EQ(r.paired_quads, 1);
    EXPECT_EQ(r.split_triangles, 0);
    EXPECT_EQ(r.leaflets, 1);
    // 4 corners + 4 side midpoints + 1 centre; 8 boundary halves + 4 spokes; 4 quads.
    EXPECT_EQ(r.skeleton.points.size(), 9u);
    EXPECT_EQ(r.skeleton.edges.size(), 12u);
    EXPECT_EQ(r.skeleton.faces.size(), 4u);
    testing::expect_valid_quad_skeleton(r.skeleton);
    testing::expect_leaflets_oriented(r.skeleton, r.face_leaflet);
    // The centre vertex is the square's centre; the diagonal 0-2 is gone.
    EXPECT_NEAR(distance(r.skeleton.points[8], Vec3{0.5, 0.5, 0}), 0.0, 1e-12);
    for (const std::array<int, 2>& e : r.skeleton.edges)
        EXPECT_FALSE(std::min(e[0], e[1]) == 0 && std::max(e[0], e[1]) == 2);
    EXPECT_EQ(euler_characteristic(r.skeleton), 1);
}

TEST(MedialImport, WithoutPairingEveryTriangleSplitsInThree) {
    MedialImportOptions opt;
    opt.pair_triangles = false;
    const MedialImport r = import_medial_mesh(unit_square(), opt);
    EXPECT_EQ(r.split_triangles, 2);
    // 4 corners + 5 edge midpoints + 2 centres; 10 halves + 6 spokes; 6 quads.
    EXPECT_EQ(r.skeleton.points.size(), 11u);
    EXPECT_EQ(r.skeleton.edges.size(), 16u);
    EXPECT_EQ(r.skeleton.faces.size(), 6u);
    testing::expect_valid_quad_skeleton(r.skeleton);
    testing::expect_leaflets_oriented(r.skeleton, r.face_leaflet);
    // Radii interpolated: the midpoint of side 0-1 gets the mean of radii 1 and 3.
    Skeleton s = unit_square();
    s.radii = {1, 3, 1, 1};
    opt.min_sheet_area_factor = 0;  // area 1 < (mean radius 1.5)^2 would collapse the sheet
    const MedialImport r2 = import_medial_mesh(s, opt);
    bool found = false;
    for (size_t v = 0; v < r2.skeleton.points.size(); ++v)
        if (distance(r2.skeleton.points[v], Vec3{0.5, 0, 0}) < 1e-12) {
            EXPECT_DOUBLE_EQ(r2.skeleton.radii[v], 2.0);
            found = true;
        }
    EXPECT_TRUE(found);
}

TEST(MedialImport, InconsistentInputOrientationIsFixed) {
    // Same square, second triangle listed the other way round (traverses 0->2 like the first).
    const Skeleton s = medial_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {}, {{0, 1, 2}, {0, 3, 2}});
    MedialImportOptions opt;
    opt.pair_triangles = false;
    const MedialImport r = import_medial_mesh(s, opt);
    EXPECT_EQ(r.leaflets, 1);
    testing::expect_valid_quad_skeleton(r.skeleton);
    testing::expect_leaflets_oriented(r.skeleton, r.face_leaflet);
    const MedialImport paired = import_medial_mesh(s);
    EXPECT_EQ(paired.paired_quads, 1);
    testing::expect_leaflets_oriented(paired.skeleton, paired.face_leaflet);
}

TEST(MedialImport, EdgeInThreeTrianglesBecomesFanEdges) {
    // Three triangles around edge 0-1 (like hand.ma's medial junction): three leaflets, nothing to pair.
    const Skeleton s = medial_mesh({{0, 0, 0}, {0, 0, 1}, {1, 0, 0.5}, {-0.5, 0.87, 0.5}, {-0.5, -0.87, 0.5}}, {},
                                   {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}}, 0.001);
    const MedialImport r = import_medial_mesh(s);
    EXPECT_EQ(r.fan_edges, 1);
    EXPECT_EQ(r.leaflets, 3);
    EXPECT_EQ(r.paired_quads, 0);
    EXPECT_EQ(r.skeleton.faces.size(), 9u);
    testing::expect_valid_quad_skeleton(r.skeleton);
    testing::expect_leaflets_oriented(r.skeleton, r.face_leaflet);
    // The two halves of the fan edge are each in three quads, one per leaflet.
    std::map<std::pair<int, int>, std::set<int>> edge_leaflets;
    for (size_t f = 0; f < r.skeleton.faces.size(); ++f)
        for (size_t i = 0; i < 4; ++i)
            edge_leaflets[std::minmax(r.skeleton.faces[f][i], r.skeleton.faces[f][(i + 1) % 4])].insert(
                r.face_leaflet[f]);
    int fan_halves = 0;
    for (const auto& [e, leaflets] : edge_leaflets)
        if (leaflets.size() == 3) ++fan_halves;
    EXPECT_EQ(fan_halves, 2);
    // V: 5 + 7 midpoints + 3 centres = 15; E: 2 fan halves + 6 side halves x 2 + 9 spokes = 23; F 9; chi = 1 as input.
    EXPECT_EQ(r.skeleton.points.size(), 15u);
    EXPECT_EQ(r.skeleton.edges.size(), 23u);
    EXPECT_EQ(euler_characteristic(r.skeleton), euler_characteristic(s));
    EXPECT_EQ(r.fan_triangles_removed, 0);  // three distinct leaflets: a regular fan, kept
}

TEST(MedialImport, IrregularFanLosesTheTriangleThatLeavesTheFlattestFan) {
    // Fan edge 0-1 along z with wings towards 2 (0 deg), 3 (90 deg) and 4 (200 deg). Triangle D = (1, 2, 3) joins
    // wings A = (0,1,2) and B = (0,1,3) through manifold edges: A and B are one leaflet, so the fan is irregular.
    // Candidates: A (side 0-2 free), B (side 0-3 free), C = (0,1,4) (both sides free, vertex 4 in nothing else).
    // Remaining wing angles: without A 110 deg, without B 160 deg, without C 90 deg -> B goes, with side 0-3.
    auto at = [](double deg) {
        const double a = deg * std::numbers::pi / 180;
        return Vec3{std::cos(a), std::sin(a), 0.5};
    };
    const Skeleton s = medial_mesh({{0, 0, 0}, {0, 0, 1}, at(0), at(90), at(200)}, {},
                                   {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}, {1, 2, 3}}, 0.001);
    MedialImportOptions unsmoothed;  // the midpoints checked below stay where the split puts them
    unsmoothed.smoothing_iterations = 0;
    const MedialImport r = import_medial_mesh(s, unsmoothed);
    EXPECT_EQ(r.fan_triangles_removed, 1);
    EXPECT_EQ(r.fan_edges, 0);
    EXPECT_EQ(r.leaflets, 1);
    // V 5 - E 7 + F 3 = 1 = 5 - 8 + 4: the Euler characteristic is kept.
    EXPECT_EQ(euler_characteristic(r.skeleton), euler_characteristic(s));
    testing::expect_valid_quad_skeleton(r.skeleton);
    testing::expect_leaflets_oriented(r.skeleton, r.face_leaflet);
    // Side 0-3 is gone (no point at its midpoint); sides 0-2 and 0-4 remain (points at their midpoints).
    auto has_point = [&](const Vec3& p) {
        for (const Vec3& q : r.skeleton.points)
            if (distance(p, q) < 1e-12) return true;
        return false;
    };
    EXPECT_FALSE(has_point(0.5 * (s.points[0] + s.points[3])));
    EXPECT_TRUE(has_point(0.5 * (s.points[0] + s.points[2])));
    EXPECT_TRUE(has_point(0.5 * (s.points[0] + s.points[4])));

    MedialImportOptions keep;
    keep.resolve_irregular_fans = false;
    const MedialImport kept = import_medial_mesh(s, keep);
    EXPECT_EQ(kept.fan_triangles_removed, 0);
    EXPECT_EQ(kept.fan_edges, 1);
}

TEST(MedialImport, PinchBetweenTwoLeafletsIsFilledAcrossItsNarrowGap) {
    // Fans A (0 to 120 degrees) and B (135 to 260) around vertex 0, touching only there: gaps of 15 and 100 degrees.
    // Filled below 60 degrees (the default): triangle (0, 3, 4) and side 3-4 are added (V 7, E 10 + 1, F 4 + 1:
    // Euler characteristic 1 kept), one leaflet, no LL-joint. Below 10 degrees, or off, nothing changes.
    const Skeleton m = test::pinch_of_two_fans(15);
    ASSERT_EQ(euler_characteristic(m), 1);
    MedialImportOptions fill;
    fill.fill_pinch_max_angle_deg = 60;
    const MedialImport on = import_medial_mesh(m, fill);
    EXPECT_EQ(on.filled_pinches, 1);
    EXPECT_EQ(on.leaflets, 1);
    EXPECT_EQ(euler_characteristic(on.skeleton), 1);
    testing::expect_valid_quad_skeleton(on.skeleton);
    testing::expect_leaflets_oriented(on.skeleton, on.face_leaflet);
    EXPECT_EQ(analyze_skeleton(on.skeleton).counts.ll_joints, 0);
    // The filled triangle is split in 3 quads around its centroid (0 + 3 + 4) / 3.
    const Vec3 centroid = (m.points[0] + m.points[3] + m.points[4]) / 3.0;
    MedialImportOptions unsmoothed = fill;
    unsmoothed.smoothing_iterations = 0;
    const MedialImport still = import_medial_mesh(m, unsmoothed);
    EXPECT_EQ(std::count_if(still.skeleton.points.begin(), still.skeleton.points.end(),
                            [&](const Vec3& p) { return distance(p, centroid) < 1e-12; }),
              1);
    for (double max_angle : {0.0, 10.0}) {
        MedialImportOptions o;
        o.fill_pinch_max_angle_deg = max_angle;
        const MedialImport off = import_medial_mesh(m, o);
        EXPECT_EQ(off.filled_pinches, 0);
        EXPECT_EQ(off.leaflets, 2);
        EXPECT_EQ(euler_characteristic(off.skeleton), 1);
        EXPECT_EQ(analyze_skeleton(off.skeleton).counts.ll_joints, 1);
    }
}

TEST(MedialImport, PinchOfOneLeafletTouchingItselfIsNotFilled) {
    // The pinch above with fans A and B joined below the plane, far from vertex 0, through vertex 7 by the triangles
    // (1, 2, 7), (1, 7, 6), (7, 5, 6) (sides 1-2, 1-7, 6-7, 5-6 manifold): one leaflet touching itself at vertex 0,
    // left as it is.
    Skeleton m = test::pinch_of_two_fans(15);
    m.points.push_back({0.3, -0.3, -1.5});
    m.radii.push_back(m.radii[0]);
    for (const std::vector<int>& t : std::vector<std::vector<int>>{{1, 2, 7}, {1, 7, 6}, {7, 5, 6}})
        m.faces.push_back(t);
    add_face_edges(m);
    MedialImportOptions fill;
    fill.fill_pinch_max_angle_deg = 60;
    const MedialImport r = import_medial_mesh(m, fill);
    EXPECT_EQ(r.filled_pinches, 0);
    EXPECT_EQ(r.leaflets, 1);
}

// Curve edges = edges in no face, as (min, max) pairs.
std::vector<std::pair<int, int>> curve_edges_of(const Skeleton& s) {
    std::set<std::pair<int, int>> face_sides;
    for (const std::vector<int>& f : s.faces)
        for (size_t i = 0; i < f.size(); ++i) face_sides.insert(std::minmax(f[i], f[(i + 1) % f.size()]));
    std::vector<std::pair<int, int>> curve;
    for (const std::array<int, 2>& e : s.edges)
        if (!face_sides.count(std::minmax(e[0], e[1]))) curve.push_back(std::minmax(e[0], e[1]));
    return curve;
}

// Square 0-1-2-3 fanned around interior vertex 4 = (1.2, 0.9); curve edge 4-5 goes up from it (cup.ma's handle).
Skeleton fanned_square_with_a_curve() {
    return medial_mesh({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1.2, 0.9, 0}, {1.2, 0.9, 1}}, {{4, 5}},
                       {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
}

TEST(MedialImport, CurveOnASheetInteriorStaysWhereFourQuadsMeet) {
    const Skeleton s = fanned_square_with_a_curve();
    // Without pairing every triangle splits into 3 quads: 4 quads meet at vertex 4, which keeps the curve.
    MedialImportOptions split;
    split.pair_triangles = false;
    const MedialImport r = import_medial_mesh(s, split);
    EXPECT_EQ(r.rooted_curve_ends, 0);
    EXPECT_EQ(r.reattached_curve_ends, 0);
    ASSERT_EQ(curve_edges_of(r.skeleton).size(), 1u);
    EXPECT_EQ(curve_edges_of(r.skeleton)[0], std::make_pair(4, 5));
    EXPECT_EQ(analyze_skeleton(r.skeleton).vertex_class[4], VertexClass::LeafletInterior);
}

TEST(MedialImport, CurveOnASheetInteriorMovesToARegularNeighbour) {
    // A pentagon of 5 triangles around vertex 0, the curve 0-6 straight up. Split without pairing, 5 quads meet at 0;
    // the end moves to a neighbour of 0 where 4 quads meet (the midpoint of a spoke: every in-plane neighbour is at
    // 90 degrees to the curve, so the lowest id, the midpoint of spoke 0-1, the first new vertex: 7).
    std::vector<Vec3> pts{{0, 0, 0}};
    for (int k = 0; k < 5; ++k)
        pts.push_back({std::cos(2 * std::numbers::pi * k / 5), std::sin(2 * std::numbers::pi * k / 5), 0});
    pts.push_back({0, 0, 1});
    std::vector<std::vector<int>> tris;
    for (int k = 0; k < 5; ++k) tris.push_back({0, 1 + k, 1 + (k + 1) % 5});
    const Skeleton s = medial_mesh(pts, {{0, 6}}, tris);
    MedialImportOptions split;
    split.pair_triangles = false;
    const MedialImport p = import_medial_mesh(s, split);
    EXPECT_EQ(p.rooted_curve_ends, 1);
    EXPECT_EQ(euler_characteristic(p.skeleton), euler_characteristic(s));
    testing::expect_valid_quad_skeleton(p.skeleton);
    const std::vector<std::pair<int, int>> curve = curve_edges_of(p.skeleton);
    ASSERT_EQ(curve.size(), 1u);
    EXPECT_EQ(curve[0], std::make_pair(6, 7));
    int faces_at_root = 0, faces_at_centre = 0;
    for (const std::vector<int>& f : p.skeleton.faces) {
        faces_at_root += static_cast<int>(std::count(f.begin(), f.end(), 7));
        faces_at_centre += static_cast<int>(std::count(f.begin(), f.end(), 0));
    }
    EXPECT_EQ(faces_at_root, 4);
    EXPECT_EQ(faces_at_centre, 5);
    const SkeletonAnalysis an = analyze_skeleton(p.skeleton);
    EXPECT_EQ(an.vertex_class[7], VertexClass::LeafletInterior);
    EXPECT_EQ(an.vertex_branch_edges[7], 1);
    // Kept in place on request: the mesher then names vertex 0.
    MedialImportOptions keep = split;
    keep.root_interior_curves = false;
    EXPECT_THROW((void)analyze_skeleton(import_medial_mesh(s, keep).skeleton), Error);
}

TEST(MedialImport, CurveOnASheetInteriorCanMoveToTheNearestBoundaryVertex) {
    // Distances from 4 to the corners: 1.50, 1.20, 1.36, 1.63 -> the curve end moves to corner 1.
    const Skeleton s = fanned_square_with_a_curve();
    MedialImportOptions reattach;
    reattach.reattach_interior_curves = true;
    const MedialImport r = import_medial_mesh(s, reattach);
    EXPECT_EQ(r.reattached_curve_ends, 1);
    EXPECT_EQ(euler_characteristic(r.skeleton), euler_characteristic(s));
    testing::expect_valid_quad_skeleton(r.skeleton);
    // Exactly one curve edge, from corner 1 (input vertices keep their ids) to 5.
    const std::vector<std::pair<int, int>> curve = curve_edges_of(r.skeleton);
    ASSERT_EQ(curve.size(), 1u);
    EXPECT_EQ(curve[0], std::make_pair(1, 5));

    EXPECT_EQ(import_medial_mesh(s).reattached_curve_ends, 0);  // not by default
}

TEST(MedialImport, SingleTriangleSheetCollapsesToCentroidStar) {
    // A triangle whose corners each continue as a curve edge (dtorus.ma's situation).
    const Skeleton s = medial_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {2, 0, 0}, {0, 2, 0}},
                                   {{0, 3}, {1, 4}, {2, 5}}, {{0, 1, 2}}, 0.1);
    const MedialImport r = import_medial_mesh(s);
    EXPECT_EQ(r.sheets, 1);
    EXPECT_EQ(r.collapsed_sheets, 1);
    EXPECT_TRUE(r.skeleton.faces.empty());
    // 6 vertices + centroid; 3 curve edges + 3 spokes; chi unchanged (1).
    ASSERT_EQ(r.skeleton.points.size(), 7u);
    EXPECT_EQ(r.skeleton.edges.size(), 6u);
    EXPECT_NEAR(distance(r.skeleton.points[6], Vec3{1.0 / 3, 1.0 / 3, 0}), 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(r.skeleton.radii[6], 0.1);
    EXPECT_EQ(euler_characteristic(r.skeleton), euler_characteristic(s));
    testing::expect_valid_quad_skeleton(r.skeleton);
}

TEST(MedialImport, UnattachedCornerOfCollapsedSheetIsDropped) {
    // Corner 2 has no curve edge: the collapsed triangle becomes a path 3-0-c-1-4.
    const Skeleton s =
        medial_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {2, 0, 0}}, {{0, 3}, {1, 4}}, {{0, 1, 2}}, 0.1);
    const MedialImport r = import_medial_mesh(s);
    EXPECT_EQ(r.collapsed_sheets, 1);
    EXPECT_EQ(r.skeleton.points.size(), 5u);
    EXPECT_EQ(r.skeleton.edges.size(), 4u);
    testing::expect_valid_quad_skeleton(r.skeleton);
}

TEST(MedialImport, SmallAreaSheetCollapses) {
    // Two triangles, but their area (1) is below (mean radius 2)^2 = 4.
    Skeleton s = unit_square();
    s.radii.assign(4, 2.0);
    EXPECT_EQ(import_medial_mesh(s).collapsed_sheets, 1);
    s.radii.assign(4, 0.5);
    EXPECT_EQ(import_medial_mesh(s).collapsed_sheets, 0);
}

TEST(MedialImport, BoundaryVerticesFlattenAFoldAlongTheirNormal) {
    // Two unit squares folded by 90 degrees about their shared side 1-2 (the second stands in the plane x = 1). One
    // sweep: vertex 1 = (1, 0, 0) has the neighbours (0.5, 0, 0), (1, 0.5, 0), (1, 0, 0.5) (mean - p = (-1, 1, 1) / 6)
    // and the normal (-1, 0, 1) / sqrt 2 (two quads of equal area, normals +z and -x); it moves by
    // 0.5 x n (n . (mean - p)) = (-1, 0, 1) / 12. Vertex 0, a flat corner, does not move.
    const Skeleton s = medial_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 1}, {1, 1, 1}}, {},
                                   {{0, 1, 2}, {0, 2, 3}, {2, 1, 4}, {2, 4, 5}});
    MedialImportOptions opt;
    opt.smoothing_iterations = 1;
    const MedialImport r = import_medial_mesh(s, opt);
    ASSERT_EQ(r.paired_quads, 2);
    EXPECT_NEAR(distance(r.skeleton.points[1], Vec3{11.0 / 12, 0, 1.0 / 12}), 0.0, 1e-12);
    EXPECT_NEAR(distance(r.skeleton.points[0], Vec3{0, 0, 0}), 0.0, 1e-12);
    // 3 interior vertices (2 face centres, the midpoint of side 1-2) + 12 boundary vertices (6 corners, 6 midpoints).
    EXPECT_EQ(r.smoothed_vertices, 15);
    opt.smooth_boundary = false;
    const MedialImport fixed = import_medial_mesh(s, opt);
    EXPECT_NEAR(distance(fixed.skeleton.points[1], Vec3{1, 0, 0}), 0.0, 1e-12);
    EXPECT_EQ(fixed.smoothed_vertices, 3);
}

TEST(MedialImport, SmoothingKeepsARingSheetOnItsCylinder) {
    // The medial sheet of a thick ring (a tube of rectangular section 2 x 4 around the z axis, centre line radius 5):
    // a band on the cylinder of radius 5, heights 0..2, 24 segments (48 triangles), medial radius 1. Laplacian
    // smoothing alone pulls every vertex towards the axis (the band shrinks, and the hexes no longer reach the ring's
    // outer side; knob's medial ring went in by 0.8 x its radius). Kept within max_sheet_offset (0.25)
    // x radius of the input triangles, no vertex is farther than 0.25 from the cylinder's chords, whose distance to
    // the axis is between 5 cos(pi / 24) and 5.
    const int n = 24;
    std::vector<Vec3> points;
    std::vector<std::vector<int>> triangles;
    for (int level = 0; level < 2; ++level)
        for (int i = 0; i < n; ++i) {
            const double a = 2 * std::numbers::pi * i / n;
            points.push_back({5 * std::cos(a), 5 * std::sin(a), 2.0 * level});
        }
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        triangles.push_back({i, j, n + j});
        triangles.push_back({i, n + j, n + i});
    }
    const Skeleton band = medial_mesh(points, {}, triangles, 1.0);
    auto axis_distances = [](const Skeleton& s) {
        double lo = 1e9, hi = 0;
        for (const Vec3& p : s.points) {
            lo = std::min(lo, std::hypot(p.x, p.y));
            hi = std::max(hi, std::hypot(p.x, p.y));
        }
        return std::pair<double, double>{lo, hi};
    };
    MedialImportOptions opt;
    opt.max_sheet_offset = 0.25;  // as `auto` imports (meso_import_options)
    const MedialImport kept = import_medial_mesh(band, opt);
    // 24 pair quads split in 4: corners 48, side midpoints 24 x 3, centres 24.
    ASSERT_EQ(kept.paired_quads, n);
    ASSERT_EQ(kept.skeleton.points.size(), static_cast<size_t>(2 * n + 3 * n + n));
    const auto [lo, hi] = axis_distances(kept.skeleton);
    EXPECT_GE(lo, 5 * std::cos(std::numbers::pi / n) - 0.25 - 1e-9);
    EXPECT_LE(hi, 5 + 1e-9);
    // Free smoothing (the default of `import`): the band's vertices go 0.39 inside the chords (4.57 from the axis).
    opt.max_sheet_offset = -1;
    EXPECT_LT(axis_distances(import_medial_mesh(band, opt).skeleton).first, 5 * std::cos(std::numbers::pi / n) - 0.3);
}

TEST(MedialImport, ReflexBorderCornerMovesTowardsItsBoundaryNeighbours) {
    // An L of three unit squares in the plane z = 0: the border vertex 4 = (1, 1) has face angles summing to 270
    // degrees. One sweep moves it by 0.5 x (midpoint of its boundary neighbours (1.5, 1) and (1, 1.5) - p) =
    // (0.125, 0.125); the sheet is flat, so nothing moves along the normal. Below reflex_corner_deg it stays.
    const Skeleton s =
        medial_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {0, 2, 0}, {1, 2, 0}}, {},
                    {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {3, 4, 7}, {3, 7, 6}});
    MedialImportOptions opt;
    opt.smoothing_iterations = 1;
    const MedialImport r = import_medial_mesh(s, opt);
    ASSERT_EQ(r.paired_quads, 3);
    EXPECT_NEAR(distance(r.skeleton.points[4], Vec3{1.125, 1.125, 0}), 0.0, 1e-12);
    EXPECT_NEAR(distance(r.skeleton.points[1], Vec3{1, 0, 0}), 0.0, 1e-12);
    opt.reflex_corner_deg = 280;
    EXPECT_NEAR(distance(import_medial_mesh(s, opt).skeleton.points[4], Vec3{1, 1, 0}), 0.0, 1e-12);
}

// Two unit squares side by side; a curve leaves vertex 1 = (1, 0, 0), in the middle of the straight border y = 0,
// towards `to`. After the split its boundary neighbours are (0.5, 0, 0) and (1.5, 0, 0) (mean length 0.5), 2 quads
// meet there and its inward direction is +y.
Skeleton straight_border_with_a_curve(const Vec3& to) {
    return medial_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, to}, {{1, 6}},
                       {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}});
}

TEST(MedialImport, BLJointOnAStraightBorderIsPushedOutMoreWhenItsCurveHeadsBackOverTheLeaflet) {
    // A curve towards (2, -0.3, 0.3) (74 degrees from the outward -y and from the normal: not rooted by the mesher)
    // has no component along +y: pushed by 1.25 x 0.5 to (1, -0.625, 0). A curve towards (1, 1, 0.5) heads back over
    // the leaflet (cosine 1 / sqrt(1.25) with +y; 63 degrees from the normal): pushed 1 + 1 / sqrt(1.25) times as far.
    for (const Vec3& to : {Vec3{2, -0.3, 0.3}, Vec3{1, 1, 0.5}}) {
        const Skeleton s = straight_border_with_a_curve(to);
        const MedialImport r = import_medial_mesh(s);
        EXPECT_EQ(r.moved_bl_joints, 1);
        const double push = 1.25 * 0.5 * (to.y > 0 ? 1 + 1 / std::sqrt(1.25) : 1.0);
        EXPECT_NEAR(distance(r.skeleton.points[1], Vec3{1, -push, 0}), 0.0, 1e-12) << "y " << to.y;
        MedialImportOptions plain;
        plain.bl_joint_back_push = 0;
        EXPECT_NEAR(distance(import_medial_mesh(s, plain).skeleton.points[1], Vec3{1, -0.625, 0}), 0.0, 1e-12);
    }
}

TEST(MedialImport, BLJointTheMesherRootsOnTheBorderStaysWhereItIs) {
    // Outward in the plane (border_root Out) and along the normal where 2 quads meet (Side): no corner is made, and
    // the mesher classifies vertex 1 as a leaflet boundary vertex rooting the branch.
    for (const Vec3& to : {Vec3{1, -1, 0}, Vec3{1.2, -0.5, 0.3}, Vec3{1, 0, 1}, Vec3{1, 0.3, -1}}) {
        SCOPED_TRACE(::testing::Message() << to.x << " " << to.y << " " << to.z);
        const Skeleton s = straight_border_with_a_curve(to);
        const MedialImport r = import_medial_mesh(s);
        EXPECT_EQ(r.moved_bl_joints, 0);
        EXPECT_NEAR(distance(r.skeleton.points[1], Vec3{1, 0, 0}), 0.0, 1e-12);
        const SkeletonAnalysis an = analyze_skeleton(r.skeleton);
        EXPECT_EQ(an.vertex_class[1], VertexClass::LeafletBoundary);
        EXPECT_EQ(an.vertex_border_root[1], to.z > 0.5 || to.z < -0.5 ? BorderRoot::Side : BorderRoot::Out);
        MedialImportOptions corner;
        corner.keep_rooted_bl_joints = false;
        EXPECT_EQ(import_medial_mesh(s, corner).moved_bl_joints, 1);
    }
}

// The import of s with `off`: no joint moved, vertex v still at p.
void expect_join_stays(const Skeleton& s, const MedialImportOptions& off, int v, const Vec3& p) {
    const MedialImport kept = import_medial_mesh(s, off);
    EXPECT_EQ(kept.moved_bl_joints, 0);
    EXPECT_NEAR(distance(kept.skeleton.points[static_cast<size_t>(v)], p), 0.0, 1e-12);
}

TEST(MedialImport, BLJointInASharpNotchBecomesALeafletCorner) {
    // The L of three unit squares (above) with a curve from its notch vertex 4 = (1, 1) into the gap, towards
    // (5, 5, 0) (length 4 sqrt 2). After the split the border neighbours are a = (1.5, 1), b = (1, 1.5): they make 90
    // degrees (no straight stretch), the faces' angles sum to 270 (a notch). The join moves along the bisector
    // (1, 1) / sqrt 2 past the chord of a and b (0.25 sqrt 2) and then 1.25 x 0.5 further: to 1.25 + 0.625 / sqrt 2
    // on both axes, a convex corner (the chord's midpoint is (1.25, 1.25)). A curve towards (2, 2, 0) (length
    // sqrt 2) caps the move at 0.2 x sqrt 2: the join lands at (1.2, 1.2). Without the option it stays.
    for (const double far : {5.0, 2.0}) {
        SCOPED_TRACE(far);
        const Skeleton s = test::notch_l_with_a_curve({far, far, 0});
        const MedialImport r = import_medial_mesh(s);
        EXPECT_EQ(r.moved_bl_joints, 1);
        EXPECT_EQ(r.notch_corners, 1);
        EXPECT_EQ(r.branch_corners, 0);
        const double at = far > 3 ? 1.25 + 0.625 / std::sqrt(2.0) : 1.2;
        EXPECT_NEAR(distance(r.skeleton.points[4], Vec3{at, at, 0}), 0.0, 1e-12);
        MedialImportOptions off;
        off.bl_joint_reflex_corners = false;
        expect_join_stays(s, off, 4, {1, 1, 0});
    }
}

TEST(MedialImport, JoinOfSeveralCurvesOnAStraightBorderBecomesACornerAtMostAFifthOfItsShortestCurveOut) {
    // Two unit squares; vertex 1 = (1, 0, 0) in the middle of the straight border y = 0 has two curves: one of two
    // edges (to (1, -1, 0), then (1, -2, 0): length 2, through a plain joint) and one edge to (0, -3, 0) (length
    // sqrt 10). The push on a straight border, 1.25 x 0.5 along -y, is capped at 0.2 x 2: the join lands at
    // (1, -0.4, 0). Without the option it stays (a join of several curves is no BL-joint).
    const Skeleton s = test::two_curves_on_a_straight_border({1, -1, 0}, {1, -2, 0}, {0, -3, 0});
    const MedialImport r = import_medial_mesh(s);
    EXPECT_EQ(r.moved_bl_joints, 1);
    EXPECT_EQ(r.branch_corners, 1);
    EXPECT_EQ(r.notch_corners, 0);
    EXPECT_NEAR(distance(r.skeleton.points[1], Vec3{1, -0.4, 0}), 0.0, 1e-12);
    MedialImportOptions wider;
    wider.bl_joint_max_push_curve_fraction = 0.5;  // 1.0 > 0.625: the straight border's push itself
    EXPECT_NEAR(distance(import_medial_mesh(s, wider).skeleton.points[1], Vec3{1, -0.625, 0}), 0.0, 1e-12);
    MedialImportOptions off;
    off.bl_joint_corners_with_branches = false;
    expect_join_stays(s, off, 1, {1, 0, 0});
}

bool has_edge(const Skeleton& s, int a, int b) {
    return std::any_of(s.edges.begin(), s.edges.end(), [&](const std::array<int, 2>& e) {
        return (e[0] == a && e[1] == b) || (e[0] == b && e[1] == a);
    });
}

TEST(MedialImport, ShortCurvesOfAJoinMoveOntoTheNearestConvexCorner) {
    // Three unit squares in a row; border vertex 1 = (1, 0, 0) has a curve of two edges (through (1, -1, -1) to
    // (1, -2, -1): length 1 + sqrt 2) and one to (0, -3, 0) (sqrt 10). Its push on the straight border, 1.25 along -y,
    // is capped at 0.2 x (1 + sqrt 2) = 0.483: cut short, so both curves move onto the convex corner 0 (1 away along
    // the border, reach 3 x 1) and vertex 1 still goes out by the cap, to (1, -0.2 (1 + sqrt 2), 0).
    const Skeleton s = test::two_curves_next_to_a_corner({1, -1, -1}, {1, -2, -1}, {0, -3, 0});
    const MedialImport r = import_medial_mesh(s);
    EXPECT_EQ(r.joins_to_corners, 1);
    EXPECT_EQ(r.moved_bl_joints, 1);
    EXPECT_EQ(r.branch_corners, 1);
    EXPECT_TRUE(has_edge(r.skeleton, 0, 8));
    EXPECT_TRUE(has_edge(r.skeleton, 0, 10));
    EXPECT_TRUE(has_edge(r.skeleton, 8, 9));
    EXPECT_FALSE(has_edge(r.skeleton, 1, 8));
    EXPECT_FALSE(has_edge(r.skeleton, 1, 10));
    EXPECT_EQ(r.skeleton.edges.size(), 35u);  // 12 quads' 32 sides + 3 curve edges: none lost
    EXPECT_NEAR(distance(r.skeleton.points[1], Vec3{1, -0.2 * (1 + std::sqrt(2.0)), 0}), 0.0, 1e-12);
    EXPECT_EQ(r.skeleton.points[0], (Vec3{0, 0, 0}));
    // Reach 0.9 (< 1): no corner in reach, the curves stay at vertex 1.
    MedialImportOptions near;
    near.bl_joint_corner_reach = 0.9;
    const MedialImport kept = import_medial_mesh(s, near);
    EXPECT_EQ(kept.joins_to_corners, 0);
    EXPECT_TRUE(has_edge(kept.skeleton, 1, 8));
    EXPECT_TRUE(has_edge(kept.skeleton, 1, 10));
    EXPECT_EQ(kept.skeleton.points[1], r.skeleton.points[1]);
    // A curve from the corner to the same end merges with the moved one: one curve edge fewer.
    Skeleton twin = s;
    twin.edges.push_back({0, 10});
    const MedialImport merged = import_medial_mesh(twin);
    EXPECT_EQ(merged.joins_to_corners, 1);
    EXPECT_EQ(merged.skeleton.edges.size(), 35u);
    EXPECT_FALSE(has_edge(merged.skeleton, 1, 10));
}

TEST(MedialImport, MoebiusBandIsRejected) {
    // 6 cross-sections t_i = (cos, sin, +w), b_i = (cos, sin, -w) around a circle, the last one glued twisted.
    const int n = 6;
    std::vector<Vec3> pts;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * 3.14159265358979 * i / n;
        pts.push_back({std::cos(a), std::sin(a), 0.2});
        pts.push_back({std::cos(a), std::sin(a), -0.2});
    }
    std::vector<std::vector<int>> tris;
    for (int i = 0; i < n; ++i) {
        const int t0 = 2 * i, b0 = 2 * i + 1;
        int t1 = 2 * ((i + 1) % n), b1 = 2 * ((i + 1) % n) + 1;
        if (i == n - 1) std::swap(t1, b1);
        tris.push_back({t0, b0, b1});
        tris.push_back({t0, b1, t1});
    }
    try {
        import_medial_mesh(medial_mesh(pts, {}, tris));
        FAIL() << "a Moebius band must be rejected";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::UnsupportedConfiguration);
        EXPECT_NE(std::string(e.what()).find("orientable"), std::string::npos);
    }
    // The untwisted band is fine and keeps chi = 0.
    std::vector<std::vector<int>> ring;
    for (int i = 0; i < n; ++i) {
        const int t0 = 2 * i, b0 = 2 * i + 1, t1 = 2 * ((i + 1) % n), b1 = 2 * ((i + 1) % n) + 1;
        ring.push_back({t0, b0, b1});
        ring.push_back({t0, b1, t1});
    }
    const MedialImport r = import_medial_mesh(medial_mesh(pts, {}, ring));
    testing::expect_valid_quad_skeleton(r.skeleton);
    testing::expect_leaflets_oriented(r.skeleton, r.face_leaflet);
    EXPECT_EQ(euler_characteristic(r.skeleton), 0);
}

TEST(MedialImport, BadInputNamesTheElement) {
    Skeleton s = unit_square();
    s.radii.pop_back();
    EXPECT_THROW(import_medial_mesh(s), Error);
    s = unit_square();
    s.faces[1].push_back(1);
    try {
        import_medial_mesh(s);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        EXPECT_EQ(e.where().kind, ElementRef::Kind::SkeletonFace);
        EXPECT_EQ(e.where().index, 1);
    }
    s = unit_square();
    s.edges.pop_back();  // a triangle side no longer listed
    EXPECT_THROW(import_medial_mesh(s), Error);
}

// ---- .ma reader
std::string write_temp(const std::string& name, const std::string& text) {
    const std::string path = (std::filesystem::temp_directory_path() / ("mesohex_test_" + name)).string();
    std::ofstream(path) << text;
    return path;
}

TEST(MedialIo, ReadsCountsRadiiAndAddsMissingTriangleSides) {
    const std::string path = write_temp(
        "ok.ma", "4 4 1\nv 0 0 0 0.5\nv 1 0 0 0.25\nv 0 1 0 0.5\n\nv 5 5 5 1\ne 0 1\ne 1 2\ne 2 0\ne 2 3\nf 0 1 2\n");
    const Skeleton s = read_medial_mesh(path);
    EXPECT_EQ(s.points.size(), 4u);
    EXPECT_EQ(s.edges.size(), 4u);
    ASSERT_EQ(s.faces.size(), 1u);
    EXPECT_EQ(s.faces[0], (std::vector<int>{0, 1, 2}));
    EXPECT_DOUBLE_EQ(s.radii[1], 0.25);
    const std::string missing = write_temp("missing.ma", "3 1 1\nv 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1\ne 0 1\nf 0 1 2\n");
    EXPECT_EQ(read_medial_mesh(missing).edges.size(), 3u);
    std::remove(path.c_str());
    std::remove(missing.c_str());
}

TEST(MedialIo, ErrorsNameFileAndLine) {
    struct Case {
        const char* text;
        int line;
    };
    const Case cases[] = {
        {"2 1 0\nv 0 0 0 1\nv 1 0 0 1\ne 0 2\n", 4},           // index out of range
        {"2 1 0\nv 0 0 0 1\nv 1 0 0 -1\ne 0 1\n", 3},          // negative radius
        {"2 2 0\nv 0 0 0 1\nv 1 0 0 1\ne 0 1\n", 4},           // fewer edges than announced
        {"2 1 0\nv 0 0 0 1\nv 1 0 0 1\ne 0 1\nf 0 1 1\n", 5},  // data after the announced counts
        {"2 1 x\n", 1},                                        // bad header
        {"2 1 0\nv 0 0 0 1\nv 1 0 0 1\ne 1 1\n", 4},           // loop edge
        {"2 1 0\nv 0 0 1\nv 1 0 0 1\ne 0 1\n", 2},             // short vertex line
    };
    int i = 0;
    for (const Case& c : cases) {
        const std::string path = write_temp("bad" + std::to_string(i++) + ".ma", c.text);
        try {
            read_medial_mesh(path);
            ADD_FAILURE() << "no error for: " << c.text;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
            EXPECT_EQ(e.where().index, c.line) << e.what();
            EXPECT_NE(std::string(e.what()).find(path + ":" + std::to_string(c.line)), std::string::npos) << e.what();
        }
        std::remove(path.c_str());
    }
    EXPECT_THROW(read_medial_mesh("/nonexistent/x.ma"), Error);
}

// Issue 18: a header count the file cannot hold is refused before anything is reserved (no bad_alloc, no
// terabytes), as InvalidInput naming file and line 1; an empty file says so instead of naming line 0; a long
// binary token is quoted short and escaped.
TEST(MedialIo, HeaderCountsBoundedByFileSize) {
    const char* headers[] = {"2147483648 0 0\n", "1e12 0 0\n", "0 4000000000 0\n", "3 0 0\nv 0 0 0 1\n",
                             "0 0 9223372036854775807\n"};
    int i = 0;
    for (const char* text : headers) {
        const std::string path = write_temp("huge" + std::to_string(i++) + ".ma", text);
        try {
            read_medial_mesh(path);
            ADD_FAILURE() << "no error for: " << text;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidInput) << e.what();
            EXPECT_EQ(e.where().index, 1) << e.what();
            EXPECT_NE(std::string(e.what()).find(path + ":1: "), std::string::npos) << e.what();
        }
        std::remove(path.c_str());
    }
    const std::string empty = write_temp("empty.ma", " \n\n");
    try {
        read_medial_mesh(empty);
        ADD_FAILURE() << "no error for an empty file";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        EXPECT_EQ(std::string(e.what()), empty + ":1: empty file (expected the header 'nv ne nf')");
    }
    std::remove(empty.c_str());
    std::string binary = "1 0 0\nq";
    for (int k = 0; k < 100000; ++k) binary += static_cast<char>(0x80 + k % 100);
    const std::string bin_path = write_temp("binary.ma", binary + "\n");
    try {
        read_medial_mesh(bin_path);
        ADD_FAILURE() << "no error for a binary line";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_LT(msg.size(), 400u) << msg;
        EXPECT_NE(msg.find("\\x80"), std::string::npos) << msg;
        EXPECT_EQ(std::count_if(msg.begin(), msg.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x80; }),
                  0);
    }
    std::remove(bin_path.c_str());
}

}  // namespace
}  // namespace mesohex
