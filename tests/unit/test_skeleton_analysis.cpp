// Skeleton analysis (paper step 2) on tiny skeletons checkable on paper.
#include <gtest/gtest.h>

#include "skeleton_fixtures.h"

#include "mesohex/core/error.h"
#include "mesohex/stages/skeleton_analysis.h"

using namespace mesohex;

namespace {

Skeleton polyline(int n_edges, bool closed) {
    Skeleton s;
    const int nv = closed ? n_edges : n_edges + 1;
    for (int i = 0; i < nv; ++i) s.points.push_back({double(i), double(i % 2) * 0.3, 0});
    if (closed) {
        s.points.clear();
        for (int i = 0; i < nv; ++i) s.points.push_back({std::cos(2 * M_PI * i / nv), std::sin(2 * M_PI * i / nv), 0});
    }
    for (int i = 0; i < n_edges; ++i) s.edges.push_back({i, (i + 1) % nv});
    return s;
}

using mesohex::test::plate;

}  // namespace

TEST(SkeletonAnalysis, OneEdge) {
    const SkeletonAnalysis an = analyze_skeleton(polyline(1, false));
    EXPECT_EQ(an.vertex_class[0], VertexClass::Extremity);
    EXPECT_EQ(an.vertex_class[1], VertexClass::Extremity);
    ASSERT_EQ(an.branches.size(), 1u);
    EXPECT_EQ(an.branches[0].vertices, (std::vector<int>{0, 1}));
    EXPECT_EQ(an.branches[0].edges, (std::vector<int>{0}));
    EXPECT_EQ(an.predicted_hexes, 4);
    EXPECT_EQ(an.counts.extremities, 2);
    EXPECT_EQ(an.counts.cycles, 0);
    EXPECT_EQ(an.counts.components, 1);
}

TEST(SkeletonAnalysis, ThreeStar) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    s.edges = {{0, 1}, {2, 0}, {0, 3}};
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(an.vertex_class[0], VertexClass::BranchingPoint);
    EXPECT_EQ(an.counts.branching_points, 1);
    EXPECT_EQ(an.counts.extremities, 3);
    ASSERT_EQ(an.branches.size(), 3u);
    for (const Branch& b : an.branches) {
        EXPECT_EQ(b.vertices.front(), 0);  // walked from the branching point
        EXPECT_EQ(b.edges.size(), 1u);
    }
    EXPECT_EQ(an.predicted_hexes, 12);
}

TEST(SkeletonAnalysis, IsolatedPolylineIsOneOrderedBranch) {
    const SkeletonAnalysis an = analyze_skeleton(polyline(4, false));
    ASSERT_EQ(an.branches.size(), 1u);
    EXPECT_EQ(an.branches[0].vertices, (std::vector<int>{0, 1, 2, 3, 4}));
    EXPECT_EQ(an.branches[0].edges, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_FALSE(an.branches[0].ring);
    EXPECT_EQ(an.counts.joints, 3);
    EXPECT_EQ(an.predicted_hexes, 16);
}

TEST(SkeletonAnalysis, ClosedRingWithoutBranchingPoint) {
    const SkeletonAnalysis an = analyze_skeleton(polyline(6, true));
    EXPECT_EQ(an.counts.joints, 6);
    ASSERT_EQ(an.branches.size(), 1u);
    const Branch& b = an.branches[0];
    EXPECT_TRUE(b.ring);
    EXPECT_EQ(b.vertices.size(), 7u);
    EXPECT_EQ(b.vertices.front(), b.vertices.back());
    EXPECT_EQ(b.edges.size(), 6u);
    EXPECT_EQ(an.counts.cycles, 1);
    EXPECT_EQ(an.counts.rings, 1);
    EXPECT_EQ(an.predicted_hexes, 24);
}

TEST(SkeletonAnalysis, LoopAtBranchingPoint) {
    // Tail 0-1 and loop 0-2-3-0: vertex 0 has degree 3.
    Skeleton s;
    s.points = {{0, 0, 0}, {-1, 0, 0}, {1, 1, 0}, {1, -1, 0}};
    s.edges = {{0, 1}, {0, 2}, {2, 3}, {3, 0}};
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(an.vertex_class[0], VertexClass::BranchingPoint);
    ASSERT_EQ(an.branches.size(), 2u);
    EXPECT_EQ(an.branches[0].vertices, (std::vector<int>{0, 1}));
    EXPECT_EQ(an.branches[1].vertices, (std::vector<int>{0, 2, 3, 0}));
    EXPECT_FALSE(an.branches[1].ring);
    EXPECT_EQ(an.counts.cycles, 1);
    for (int e = 0; e < 4; ++e) EXPECT_GE(an.edge_branch[e], 0);
}

TEST(SkeletonAnalysis, IsolatedVertexProducesNothing) {
    Skeleton s = polyline(1, false);
    s.points.push_back({5, 5, 5});
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(an.vertex_class[2], VertexClass::Isolated);
    EXPECT_EQ(an.counts.isolated, 1);
    EXPECT_EQ(an.counts.components, 1);
    EXPECT_EQ(an.predicted_hexes, 4);
}

TEST(SkeletonAnalysis, SingleQuadLeaflet) {
    const SkeletonAnalysis an = analyze_skeleton(plate(1, 1));
    EXPECT_EQ(an.counts.leaflets, 1);
    EXPECT_EQ(an.counts.boundary_edges, 4);
    EXPECT_EQ(an.counts.leaflet_boundary, 4);
    EXPECT_EQ(an.predicted_hexes, 10);  // 1 plate (2) + 4 half-chunks (8)
    EXPECT_NEAR(an.face_normal[0].z, 1.0, 1e-12);
}

TEST(SkeletonAnalysis, ThreeByThreePlate) {
    const SkeletonAnalysis an = analyze_skeleton(plate(3, 3));
    EXPECT_EQ(an.counts.leaflets, 1);
    EXPECT_EQ(an.counts.boundary_edges, 12);
    EXPECT_EQ(an.counts.leaflet_interior, 4);
    EXPECT_EQ(an.counts.leaflet_boundary, 12);
    EXPECT_EQ(an.predicted_hexes, 42);
}

TEST(SkeletonAnalysis, LeafletFacesAreReorientedConsistently) {
    Skeleton s = plate(2, 1);
    std::swap(s.faces[1][1], s.faces[1][3]);  // second face given clockwise
    const SkeletonAnalysis an = analyze_skeleton(s);
    ASSERT_EQ(an.leaflets.size(), 1u);
    EXPECT_TRUE(an.leaflets[0].orientable);
    EXPECT_NEAR(an.face_normal[0].z, 1.0, 1e-12);
    EXPECT_NEAR(an.face_normal[1].z, 1.0, 1e-12);
    // Shared edge (1, 4): traversed 1->4 by one face and 4->1 by the other.
    for (int k = 0; k < 4; ++k)
        EXPECT_EQ(s.edges[an.face_edges[1][k]][0] + s.edges[an.face_edges[1][k]][1],
                  an.face_vertices[1][k] + an.face_vertices[1][(k + 1) % 4]);
}

TEST(SkeletonAnalysis, MoebiusStripIsReportedNonOrientable) {
    // top t0..t2 = 0..2, bottom b0..b2 = 3..5; the last face closes the strip with a half twist.
    Skeleton s;
    s.points = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}, {0, 0, 0}, {1, 0, 0}, {2, 0.5, 0}};
    s.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}, {2, 3, 0, 5}};
    add_face_edges(s);
    const SkeletonAnalysis an = analyze_skeleton(s);
    ASSERT_EQ(an.leaflets.size(), 1u);
    EXPECT_FALSE(an.leaflets[0].orientable);
    EXPECT_EQ(an.counts.boundary_edges, 6);
}

TEST(SkeletonAnalysis, TFanClassifiesFanVertices) {
    // Three quads sharing edge (0, 1).
    Skeleton s;
    s.points = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}, {-1, 0, 1}, {-1, 0, 0}, {0, 1, 1}, {0, 1, 0}};
    s.faces = {{0, 1, 2, 3}, {1, 0, 5, 4}, {0, 1, 6, 7}};
    add_face_edges(s);
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(an.counts.fan_edges, 1);
    EXPECT_EQ(an.vertex_class[0], VertexClass::FanEdgeEnd);
    EXPECT_EQ(an.vertex_class[1], VertexClass::FanEdgeEnd);
    EXPECT_EQ(an.counts.leaflets, 3);
}

TEST(SkeletonAnalysis, BranchAtLeafletCornerIsBLJoint) {
    Skeleton s = plate(1, 1);
    s.points.push_back({-1, -1, 0});
    s.edges.push_back({0, 4});
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(an.vertex_class[0], VertexClass::BLJoint);
    EXPECT_EQ(an.vertex_class[4], VertexClass::Extremity);
    EXPECT_EQ(an.predicted_hexes, 14);
}

// A leaflet corner opened past kBorderRootAngleDeg (one quad, border edges 105 degrees apart: vertex 1 moved to
// (1, -tan 15 deg)) with its branch along the outward bisector (217.5 degrees) stays a BL-joint; 40 degrees off
// the bisector (inside kBorderRootBranchDeg, outside kBorderCornerBranchDeg) it is rooted on the out patch.
TEST(SkeletonAnalysis, BranchAtOpenLeafletCorner) {
    for (const double off_deg : {0.0, 40.0}) {
        Skeleton s = plate(1, 1);
        s.points[1] = {1, -std::tan(15 * M_PI / 180), 0};
        const double a = (217.5 + off_deg) * M_PI / 180;
        s.points.push_back({std::cos(a), std::sin(a), 0});
        s.edges.push_back({0, 4});
        const SkeletonAnalysis an = analyze_skeleton(s);
        EXPECT_EQ(an.vertex_class[0], off_deg == 0 ? VertexClass::BLJoint : VertexClass::LeafletBoundary);
        EXPECT_EQ(an.vertex_border_root[0], off_deg == 0 ? BorderRoot::None : BorderRoot::Out);
    }
}

// border_root on hand-made frames: border edges 110 degrees apart in the xy plane, inward along +x, normal +z.
TEST(SkeletonAnalysis, BorderRootAtCornersAndStraightBorders) {
    auto dir = [](double deg) { return Vec3{std::cos(deg * M_PI / 180), std::sin(deg * M_PI / 180), 0}; };
    const Vec3 d1 = dir(55), d2 = dir(-55), in{1, 0, 0}, up{0, 0, 1};
    EXPECT_EQ(border_root(d1, d2, in, up, dir(180), 1), BorderRoot::None);  // one-face corner, bisector branch
    EXPECT_EQ(border_root(d1, d2, in, up, dir(180 + 29), 1), BorderRoot::None);
    EXPECT_EQ(border_root(d1, d2, in, up, dir(180 + 31), 1), BorderRoot::Out);   // off the bisector: out patch
    EXPECT_EQ(border_root(d1, d2, in, 2.0 * up, dir(180), 2), BorderRoot::Out);  // two faces: out patch
    // Radius 0.9 / 1.5 x the shorter border edge (kBorderCornerMaxRadiusEdge 1): a BL-joint / the out patch.
    EXPECT_EQ(border_root(d1, d2, in, up, dir(180), 1, 0.9), BorderRoot::None);
    EXPECT_EQ(border_root(d1, d2, in, up, dir(180), 1, 1.5), BorderRoot::Out);
    // Border edges 130 degrees apart (>= kBorderCornerMaxDeg): the out patch even on one face.
    EXPECT_EQ(border_root(dir(65), dir(-65), in, up, dir(180), 1), BorderRoot::Out);
    // Border edges 95 degrees apart (< kBorderRootAngleDeg): never the out patch.
    EXPECT_EQ(border_root(dir(47.5), dir(-47.5), in, up, dir(180 + 40), 1), BorderRoot::None);
}

TEST(SkeletonAnalysis, RejectsBadInput) {
    Skeleton loop = polyline(2, false);
    loop.edges.push_back({1, 1});
    EXPECT_THROW(analyze_skeleton(loop), Error);
    Skeleton out_of_range = polyline(1, false);
    out_of_range.edges.push_back({0, 7});
    EXPECT_THROW(analyze_skeleton(out_of_range), Error);
    Skeleton tri;
    tri.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    tri.faces = {{0, 1, 2}};
    add_face_edges(tri);
    try {
        analyze_skeleton(tri);
        FAIL() << "a triangle face must be rejected";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        EXPECT_EQ(e.where().kind, ElementRef::Kind::SkeletonFace);
        EXPECT_EQ(e.where().index, 0);
    }
    Skeleton interior = plate(2, 2);  // centre vertex 4 is interior: one branch is rooted there, two are refused
    interior.points.push_back({1, 1, 1});
    interior.edges.push_back({4, 9});
    EXPECT_EQ(analyze_skeleton(interior).vertex_class[4], VertexClass::LeafletInterior);
    interior.points.push_back({1, 1, -1});
    interior.edges.push_back({4, 10});
    try {
        analyze_skeleton(interior);
        FAIL() << "two branches on a leaflet interior vertex must be rejected";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::UnsupportedConfiguration);
        EXPECT_EQ(e.where().index, 4);
    }
    Skeleton zero = polyline(1, false);
    zero.points[1] = zero.points[0];
    EXPECT_THROW(analyze_skeleton(zero), Error);
}

// extract_branches over plain data: a star with one two-edge arm (0-1-2), two one-edge arms and a separate ring of
// three joints (ids 5, 6, 7 listed as 5-6, 6-7, 7-5), plus an isolated vertex 8. Walks start at the non-joints in
// vertex order (0: its edges 0, 2, 3 in order), then the ring from its smallest vertex along its smaller edge id.
TEST(SkeletonAnalysis, ExtractBranchesFromPlainFlags) {
    Skeleton s;
    for (int i = 0; i < 9; ++i) s.points.push_back({double(i), double(i * i % 5), 0});
    s.edges = {{0, 1}, {1, 2}, {0, 3}, {0, 4}, {5, 6}, {6, 7}, {7, 5}};
    const std::vector<int> begin{0, 3, 5, 6, 7, 8, 10, 12, 14, 14};
    const std::vector<int> vertex_edges{0, 2, 3, 0, 1, 1, 2, 3, 4, 6, 4, 5, 5, 6};
    const std::vector<char> branch_edge(7, 1);
    const std::vector<char> joint{0, 1, 0, 0, 0, 1, 1, 1, 0};
    std::vector<int> edge_branch;
    const std::vector<Branch> b = extract_branches(s, begin, vertex_edges, branch_edge, joint, edge_branch);
    ASSERT_EQ(b.size(), 4u);
    EXPECT_EQ(b[0], (Branch{{0, 1, 2}, {0, 1}, false}));
    EXPECT_EQ(b[1], (Branch{{0, 3}, {2}, false}));
    EXPECT_EQ(b[2], (Branch{{0, 4}, {3}, false}));
    EXPECT_EQ(b[3], (Branch{{5, 6, 7, 5}, {4, 5, 6}, true}));
    EXPECT_EQ(edge_branch, (std::vector<int>{0, 0, 1, 2, 3, 3, 3}));
    // The analysis gives the same branches (its joints and branch edges are these flags).
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(an.branches, b);
    EXPECT_EQ(an.vertex_edge_begin, begin);
    EXPECT_EQ(an.vertex_edges, vertex_edges);
    // Without branch edge 1, vertex 1 is an end: the arm ends there and vertex 2 is isolated.
    std::vector<char> fewer = branch_edge;
    fewer[1] = 0;
    const std::vector<char> no_joint_1{0, 0, 0, 0, 0, 1, 1, 1, 0};
    const std::vector<Branch> c = extract_branches(s, begin, vertex_edges, fewer, no_joint_1, edge_branch);
    ASSERT_EQ(c.size(), 4u);
    EXPECT_EQ(c[0], (Branch{{0, 1}, {0}, false}));
    EXPECT_EQ(edge_branch[1], -1);
}
