// Leaflet geometry (stages/leaflet_geometry): directions at leaflet vertices, out distances, rooted-branch patches, on
// plates small enough to check by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "mesohex/post/quality.h"
#include "mesohex/stages/leaflet_geometry.h"
#include "raw_run.h"
#include "skeleton_fixtures.h"

using namespace mesohex;
using mesohex::test::plate;
using mesohex::test::plate_with_wall;

namespace {

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

// plate(2, 2) with one branch edge from vertex v to `tip` (added as vertex 9, edge id returned).
int add_branch(Skeleton& s, int v, const Vec3& tip) {
    s.points.push_back(tip);
    s.edges.push_back({v, static_cast<int>(s.points.size()) - 1});
    return static_cast<int>(s.edges.size()) - 1;
}

// An L of three unit quads: (0,0)-(2,0)-(2,1)-(1,1)-(1,2)-(0,2); the reflex border corner is (1,1) = vertex 4.
Skeleton l_shape() {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {0, 2, 0}, {1, 2, 0}};
    s.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}};
    add_face_edges(s);
    return s;
}

}  // namespace

TEST(LeafletGeometry, PlateNormalsAndOutwardBisectors) {
    const Skeleton s = plate(2, 2);
    const SkeletonAnalysis an = analyze_skeleton(s);
    const LeafletVertexFrames lf = leaflet_vertex_frames(s, an);
    ASSERT_EQ(lf.normal.size(), 9u);
    for (int w = 0; w < 9; ++w) expect_vec(lf.normal[w], {0, 0, 1}, 1e-15);
    // Straight border: the outward normal of the border; corner: the exterior bisector; interior: none.
    expect_vec(lf.out[1], {0, -1, 0}, 1e-15);
    expect_vec(lf.out[3], {-1, 0, 0}, 1e-15);
    expect_vec(lf.out[5], {1, 0, 0}, 1e-15);
    expect_vec(lf.out[7], {0, 1, 0}, 1e-15);
    expect_vec(lf.out[0], {-std::sqrt(0.5), -std::sqrt(0.5), 0}, 1e-15);
    expect_vec(lf.out[8], {std::sqrt(0.5), std::sqrt(0.5), 0}, 1e-15);
    expect_vec(lf.out[4], {0, 0, 0}, 0);
    // Normal sum: 4 faces at the centre, 1 at a corner (not normalized).
    expect_vec(leaflet_normal_sum(an, 4), {0, 0, 4}, 1e-15);
    expect_vec(leaflet_normal_sum(an, 0), {0, 0, 1}, 1e-15);
}

TEST(LeafletGeometry, NoFacesNoFrames) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}};
    s.edges = {{0, 1}};
    const LeafletVertexFrames lf = leaflet_vertex_frames(s, analyze_skeleton(s));
    EXPECT_TRUE(lf.normal.empty());
    EXPECT_TRUE(lf.out.empty());
}

TEST(LeafletGeometry, OutDistanceShrinksOnlyAtAReflexCorner) {
    const Skeleton p = plate(2, 2);
    const SkeletonAnalysis pa = analyze_skeleton(p);
    const LeafletVertexFrames pf = leaflet_vertex_frames(p, pa);
    EXPECT_EQ(leaflet_out_distance(p, pa, pf, 1, 0.7), 0.7);  // straight border
    EXPECT_EQ(leaflet_out_distance(p, pa, pf, 0, 0.7), 0.7);  // convex corner
    EXPECT_EQ(leaflet_out_distance(p, pa, pf, 4, 0.7), 0.7);  // interior vertex
    // Reflex corner (1, 1) of the L: out = unit(1, 1, 0), 45 degrees to both unit boundary edges, so the distance is
    // at most kReflexOutFraction x 1 / cos 45.
    const Skeleton s = l_shape();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const LeafletVertexFrames lf = leaflet_vertex_frames(s, an);
    expect_vec(lf.out[4], {std::sqrt(0.5), std::sqrt(0.5), 0}, 1e-15);
    EXPECT_NEAR(leaflet_out_distance(s, an, lf, 4, 1.0), kReflexOutFraction * std::sqrt(2.0), 1e-12);
    EXPECT_EQ(leaflet_out_distance(s, an, lf, 4, 0.2), 0.2);  // already within the fraction
}

TEST(LeafletGeometry, InteriorPatchIsCounterClockwiseSeenFromTheBranch) {
    for (const double side : {1.0, -1.0}) {
        Skeleton s = plate(2, 2);
        const int e = add_branch(s, 4, {1, 1, side});
        const SkeletonAnalysis an = analyze_skeleton(s);
        ASSERT_EQ(an.vertex_class[4], VertexClass::LeafletInterior);
        const LeafletPatch p = leaflet_patch(s, an, 4, e);
        EXPECT_EQ(p.up, side > 0);
        EXPECT_EQ(std::set<int>(p.neighbour.begin(), p.neighbour.end()), (std::set<int>{1, 3, 5, 7}));
        const Vec3& c = s.points[4];
        for (int k = 0; k < 4; ++k) {
            const std::array<int, 4>& fv = an.face_vertices[p.face[k]];
            EXPECT_EQ(fv[p.corner_centre[k]], 4);
            EXPECT_EQ(fv[p.corner_point[k]], p.neighbour[k]);
            const int diagonal = fv[p.corner_diagonal[k]];
            EXPECT_TRUE(diagonal == 0 || diagonal == 2 || diagonal == 6 || diagonal == 8);
            // points k and k + 1 bound face k, counter-clockwise about the branch direction
            EXPECT_NE(std::find(fv.begin(), fv.end(), p.neighbour[(k + 1) & 3]), fv.end());
            const Vec3 turn = cross(s.points[p.neighbour[k]] - c, s.points[p.neighbour[(k + 1) & 3]] - c);
            EXPECT_GT(side * turn.z, 0.5);
        }
    }
}

TEST(LeafletGeometry, OutPatchOfAStraightBorder) {
    // Vertex 1 = (1, 0) on the straight bottom border; the branch leaves outward in the plane: an Out root.
    Skeleton s = plate(2, 2);
    const int e = add_branch(s, 1, {1, -1, 0});
    const SkeletonAnalysis an = analyze_skeleton(s);
    ASSERT_EQ(an.vertex_border_root[1], BorderRoot::Out);
    const BorderPatch p = border_patch(s, an, 1, e);
    EXPECT_EQ(p.kind, BorderRoot::Out);
    EXPECT_EQ(std::set<int>(p.border.begin(), p.border.end()), (std::set<int>{0, 2}));
    EXPECT_LT(p.border_edge[0], p.border_edge[1]);
    for (int i = 0; i < 2; ++i) {
        const std::array<int, 2>& ed = s.edges[p.border_edge[i]];
        EXPECT_EQ(std::set<int>(ed.begin(), ed.end()), (std::set<int>{1, p.border[i]}));
    }
    // Seen from the branch (along -y), counter-clockwise from border[0]: the next point is v's out-up copy (+z)
    // exactly when border[0] is the vertex at +x.
    EXPECT_EQ(p.up_first, p.border[0] == 2);
}

// A flange on part of a plate's border: plate(3, 2) with a wall quad standing on the border edge 1-2 (vertices 12, 13
// on top), one leaflet creased along 1-2. The analysis cuts it there and docks the wall on the plate's border
// (docked_walls.h): 1 and 2 are the plate's border vertices, normal +z from its 2 faces alone, out -y from its border
// edges (the chain edge 1-2 included); the wall is a leaflet of its own. Raw 40 hexes = 2 x 7 faces + 2 x 13 border
// edges (the plate's 10, the wall's 3). (Before, the creased border vertex took the narrowest cone of its face normals,
// which still serves a flange from a plate's corner.)
TEST(LeafletGeometry, FlangeEndIsThePlatesBorderVertex) {
    const Skeleton s = plate_with_wall(3, 2, {1, 2});
    const SkeletonAnalysis an = analyze_skeleton(s);
    ASSERT_EQ(an.vertex_class[1], VertexClass::LeafletBoundary);
    EXPECT_EQ(an.counts.leaflets, 2);
    const LeafletVertexFrames lf = leaflet_vertex_frames(s, an);
    for (int w : {1, 2}) {
        SCOPED_TRACE(w);
        expect_vec(lf.normal[w], {0, 0, 1}, 1e-12);
        expect_vec(lf.out[w], {0, -1, 0}, 1e-12);
    }
    expect_vec(lf.normal[5], {0, 0, 1}, 1e-15);
    expect_vec(lf.out[4], {-1, 0, 0}, 1e-15);
    const test::RawRun r = test::checked_raw_mesh(s);
    EXPECT_EQ(r.quality.hexes, 40);
    EXPECT_TRUE(r.valid);
    EXPECT_EQ(r.quality.inverted, 0);
    EXPECT_GT(r.quality.sj_min, 0.3);
}

// A sheet folded evenly (the crease's vertices have as many faces on both sides) keeps its mean normal: plate(2, 2)
// folded 90 degrees along its middle column (x = 1), the crease vertices' normal unit(z + ...) is the cone's axis.
TEST(LeafletGeometry, EvenCreaseKeepsTheMeanNormal) {
    Skeleton s = plate(2, 2);
    for (Vec3& p : s.points)
        if (p.x > 1.5) p = {1, p.y, -1};
    const SkeletonAnalysis an = analyze_skeleton(s);
    const LeafletVertexFrames lf = leaflet_vertex_frames(s, an);
    const Vec3 sum = leaflet_normal_sum(an, 4);
    expect_vec(lf.normal[4], normalized(sum), 1e-15);
    EXPECT_NEAR(std::abs(lf.normal[4].x), std::sqrt(0.5), 1e-12);
}

namespace {

// plate(2, 2) folded along its middle column x = 1 so that its halves meet at `angle` degrees: the right half turns
// up over the left one (its direction from the crease (cos phi, 0, sin phi), phi = 180 - angle).
Skeleton folded_plate(double angle) {
    Skeleton s = plate(2, 2);
    const double phi = (180 - angle) * std::numbers::pi / 180;
    for (Vec3& p : s.points)
        if (p.x > 1.5) p = {1 + std::cos(phi), p.y, std::sin(phi)};
    return s;
}

}  // namespace

// The concave side of a sharp crease takes the miter (kMiterMaxFactor): halves meeting at 30 degrees, the crease
// vertices' copy on the side the faces lean to goes r / sin 15 = 3.8637 r along the normal, and lies r from both
// faces' planes; the convex copy stays at r. At 10 degrees the miter (11.5) is capped at 4; at 60 degrees (a miter of
// 2 < kMiterMinFactor) and on a flat plate every copy stays at r.
TEST(LeafletGeometry, SharpCreaseConcaveCopyTakesTheMiter) {
    for (const double angle : {30.0, 10.0, 60.0}) {
        SCOPED_TRACE(angle);
        const Skeleton s = folded_plate(angle);
        const SkeletonAnalysis an = analyze_skeleton(s);
        const LeafletVertexFrames lf = leaflet_vertex_frames(s, an);
        const double miter = 1 / std::sin(angle / 2 * std::numbers::pi / 180);
        const double expected = angle == 60.0 ? 1.0 : std::min(kMiterMaxFactor, miter);
        for (int w : {1, 4, 7}) {  // the crease: border, interior, border
            SCOPED_TRACE(w);
            EXPECT_NEAR(std::max(lf.up_scale[w], lf.down_scale[w]), expected, 1e-12);
            EXPECT_EQ(std::min(lf.up_scale[w], lf.down_scale[w]), 1.0);
            // The concave copy is on the side of the faces (the right half's far vertex 5 lies on it).
            const double side = lf.up_scale[w] > 1 ? 1.0 : -1.0;
            if (expected > 1) {
                EXPECT_GT(side * dot(s.points[5] - s.points[4], lf.normal[w]), 0.0);
            }
        }
        if (angle == 30.0)
            for (int f = 0; f < 4; ++f) {  // r from both faces' planes: (miter n) . n_f = 1
                const double up = std::max(lf.up_scale[4], lf.down_scale[4]);
                EXPECT_NEAR(std::abs(dot(up * lf.normal[4], normalized(an.face_normal[f]))), 1.0, 1e-12);
            }
    }
    const Skeleton flat = plate(2, 2);
    const LeafletVertexFrames lf = leaflet_vertex_frames(flat, analyze_skeleton(flat));
    for (int w = 0; w < 9; ++w) EXPECT_EQ(lf.up_scale[w] + lf.down_scale[w], 2.0);
}
