// Topology of small blocks, counts derived on paper.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "hex_fixtures.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/core/topology.h"
#include "mesohex/core/unordered_pairs.h"

using namespace mesohex;
using mesohex::test::make_block;

namespace {
bool reversed_cyclic(const std::array<int, 4>& a, const std::array<int, 4>& b) {
    for (int k = 0; k < 4; ++k)
        if (b[k] == a[0]) return b[(k + 1) % 4] == a[3] && b[(k + 2) % 4] == a[2] && b[(k + 3) % 4] == a[1];
    return false;
}
}  // namespace

TEST(Topology, SingleHex) {
    const HexMesh m = mesohex::test::make_unit_cube();
    const HexTopology t = compute_hex_topology(m);
    EXPECT_EQ(t.faces.size(), 6u);
    EXPECT_EQ(t.edges.size(), 12u);
    EXPECT_EQ(t.boundary_quads.size(), 6u);
    for (int lf = 0; lf < 6; ++lf) {
        EXPECT_EQ(t.hex_faces[0][lf], lf);  // ids by first appearance
        EXPECT_EQ(t.face_hex_count[lf], 1);
        EXPECT_EQ(t.face_hexes[lf][0], 0);
        EXPECT_EQ(t.face_hexes[lf][1], -1);
    }
    for (int le = 0; le < 12; ++le) {
        EXPECT_EQ(t.hex_edges[0][le], le);
        EXPECT_EQ(t.edge_valence[le], 1);
        EXPECT_TRUE(t.edge_on_boundary[le]);
        EXPECT_LT(t.edges[le][0], t.edges[le][1]);
    }
    // block numbering: hex 0 = {0,1,3,2,4,5,7,6}; bottom face (local 0 3 2 1), outward (-z): vertices 0 2 3 1
    EXPECT_EQ(m.hexes[0], (std::array<int, 8>{0, 1, 3, 2, 4, 5, 7, 6}));
    EXPECT_EQ(t.boundary_quads[0], (std::array<int, 4>{0, 2, 3, 1}));
}

TEST(Topology, Block2x2x2) {
    const HexMesh m = make_block(2, 2, 2);
    const HexTopology t = compute_hex_topology(m);
    // V=27, E = 3 directions * 2 * 9 = 54, F = 3 * 3 * 4 = 36, boundary quads = 6 * 4 = 24.
    EXPECT_EQ(t.edges.size(), 54u);
    EXPECT_EQ(t.faces.size(), 36u);
    EXPECT_EQ(t.boundary_quads.size(), 24u);
    int interior_faces = 0;
    for (std::size_t f = 0; f < t.faces.size(); ++f) {
        if (t.face_hex_count[f] == 2) {
            ++interior_faces;
            // the same face seen from the second hex is the reverse
            const int h1 = t.face_hexes[f][1];
            int lf1 = -1;
            for (int lf = 0; lf < 6; ++lf)
                if (t.hex_faces[h1][lf] == static_cast<int>(f)) lf1 = lf;
            ASSERT_GE(lf1, 0);
            std::array<int, 4> q1;
            for (int i = 0; i < 4; ++i) q1[i] = m.hexes[h1][kHexFaces[lf1][i]];
            EXPECT_TRUE(reversed_cyclic(t.faces[f], q1));
        }
    }
    EXPECT_EQ(interior_faces, 12);
    // 6 interior edges (at the centre vertex 13) of valence 4; boundary: 24 on cube edges (1), 24 on faces (2).
    int interior = 0, val1 = 0, val2 = 0;
    for (std::size_t e = 0; e < t.edges.size(); ++e) {
        if (!t.edge_on_boundary[e]) {
            ++interior;
            EXPECT_EQ(t.edge_valence[e], 4);
            EXPECT_TRUE(t.edges[e][0] == 13 || t.edges[e][1] == 13);
        } else {
            val1 += t.edge_valence[e] == 1;
            val2 += t.edge_valence[e] == 2;
        }
    }
    EXPECT_EQ(interior, 6);
    EXPECT_EQ(val1, 24);
    EXPECT_EQ(val2, 24);
    // boundary quads point outward: their normal agrees with the direction from the centre (1,1,1)
    for (const auto& q : t.boundary_quads) {
        const Vec3 a = m.points[q[0]], b = m.points[q[1]], c = m.points[q[2]];
        const Vec3 n = cross(b - a, c - b);
        const Vec3 mid = (m.points[q[0]] + m.points[q[1]] + m.points[q[2]] + m.points[q[3]]) / 4.0;
        EXPECT_GT(dot(n, mid - Vec3{1, 1, 1}), 0);
    }
}

TEST(Topology, ExtractBoundaryOfBlock) {
    const HexMesh m = make_block(2, 2, 2);
    const HexTopology t = compute_hex_topology(m);
    const BoundarySurface b = extract_boundary(m, t);
    EXPECT_EQ(b.surface.points.size(), 26u);  // all but the centre
    EXPECT_EQ(b.surface.quads.size(), 24u);
    EXPECT_EQ(std::count(b.vertex_of.begin(), b.vertex_of.end(), 13), 0);
    for (std::size_t q = 0; q < b.surface.quads.size(); ++q)
        for (int i = 0; i < 4; ++i) EXPECT_EQ(b.vertex_of[b.surface.quads[q][i]], t.boundary_quads[q][i]);
    for (std::size_t i = 0; i < b.vertex_of.size(); ++i) EXPECT_EQ(b.surface.points[i], m.points[b.vertex_of[i]]);
}

TEST(Topology, Ring8HasValence3And1OnTheBoundary) {
    const HexMesh m = mesohex::test::make_ring8();
    const HexTopology t = compute_hex_topology(m);
    EXPECT_EQ(t.edges.size(), 64u);
    EXPECT_EQ(t.faces.size(), 40u);
    EXPECT_EQ(t.boundary_quads.size(), 32u);
    std::multiset<int> vertical_valences;  // z-edges: 4 outer corners (1), 4 inner corners (3), 8 others (2)
    for (std::size_t e = 0; e < t.edges.size(); ++e)
        if (m.points[t.edges[e][1]].z != m.points[t.edges[e][0]].z) vertical_valences.insert(t.edge_valence[e]);
    EXPECT_EQ(vertical_valences.count(1), 4u);
    EXPECT_EQ(vertical_valences.count(2), 8u);
    EXPECT_EQ(vertical_valences.count(3), 4u);
}

TEST(Topology, NonManifoldFaceIsCounted) {
    HexMesh m = mesohex::test::make_unit_cube();
    // two more hexes sharing the top face 4 5 6 7 from above
    for (int i = 0; i < 4; ++i) m.points.push_back(m.points[4 + i] + Vec3{0, 0, 1});
    m.hexes.push_back({4, 5, 6, 7, 8, 9, 10, 11});
    m.hexes.push_back({4, 5, 6, 7, 8, 9, 10, 11});
    const HexTopology t = compute_hex_topology(m);
    const int top = t.hex_faces[0][1];
    EXPECT_EQ(t.face_hex_count[top], 3);
    EXPECT_EQ(t.face_hexes[top][0], 0);
    EXPECT_EQ(t.face_hexes[top][1], 1);
}

TEST(Topology, DeterministicAndIndependentOfRepeats) {
    const HexMesh m = make_block(5, 4, 3);
    const HexTopology a = compute_hex_topology(m);
    const HexTopology b = compute_hex_topology(m);
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(a.edges, b.edges);
    EXPECT_EQ(a.hex_faces, b.hex_faces);
    EXPECT_EQ(a.boundary_quads, b.boundary_quads);
    // Euler characteristic of a box: V - E + F - C = 1
    const long V = static_cast<long>(m.points.size());
    EXPECT_EQ(
        V - static_cast<long>(a.edges.size()) + static_cast<long>(a.faces.size()) - static_cast<long>(m.hexes.size()),
        1);
}

// One unit hex repeated 30 times (its own vertices, degenerate on purpose): vertex 0 is the smallest vertex of 3 faces
// and 3 edges of every copy, 90 slots each, more than the buckets sorted by insertion (64). Ids by first appearance as
// for the single hex; every face has 30 hexes (the first two recorded: 0 and 1), every edge valence 30.
TEST(Topology, VertexOfManyHexesGroupsLikeOne) {
    HexMesh m = mesohex::test::make_unit_cube();
    const std::array<int, 8> hex = m.hexes[0];
    for (int i = 1; i < 30; ++i) m.hexes.push_back(hex);
    const HexTopology t = compute_hex_topology(m);
    ASSERT_EQ(t.faces.size(), 6u);
    ASSERT_EQ(t.edges.size(), 12u);
    for (std::size_t h = 0; h < m.hexes.size(); ++h) {
        for (int lf = 0; lf < 6; ++lf) EXPECT_EQ(t.hex_faces[h][lf], lf);
        for (int le = 0; le < 12; ++le) EXPECT_EQ(t.hex_edges[h][le], le);
    }
    for (int lf = 0; lf < 6; ++lf) {
        EXPECT_EQ(t.face_hex_count[lf], 30);
        EXPECT_EQ(t.face_hexes[lf], (std::array<int, 2>{0, 1}));
    }
    for (int le = 0; le < 12; ++le) EXPECT_EQ(t.edge_valence[le], 30);
    EXPECT_TRUE(t.boundary_quads.empty());
}

TEST(Topology, EmptyMesh) {
    const HexTopology t = compute_hex_topology(HexMesh{});
    EXPECT_TRUE(t.faces.empty());
    EXPECT_TRUE(t.edges.empty());
    EXPECT_TRUE(t.boundary_quads.empty());
}

// Vertex -> hexes of the 2 x 2 x 2 block: the centre vertex (1, 1, 1), id 13, is in all 8 hexes, listed in ascending
// order; the corner (0, 0, 0) is in hex 0 only; the face centre (1, 1, 0), id 4, in the 4 bottom hexes 0..3.
TEST(Topology, VertexHexesOfBlock2x2x2) {
    const HexMesh m = mesohex::test::make_block(2, 2, 2);
    const VertexHexes vh = vertex_hexes(m);
    ASSERT_EQ(vh.begin.size(), m.points.size() + 1);
    EXPECT_EQ(vh.begin.back(), 8 * 8);
    auto of = [&](int v) {
        return std::vector<int>(vh.hexes.begin() + vh.begin[static_cast<std::size_t>(v)],
                                vh.hexes.begin() + vh.begin[static_cast<std::size_t>(v) + 1]);
    };
    EXPECT_EQ(of(13), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
    EXPECT_EQ(of(0), (std::vector<int>{0}));
    EXPECT_EQ(of(4), (std::vector<int>{0, 1, 2, 3}));
}

TEST(Topology, FaceSideEdgesTable) {
    // Bottom face 0-3-2-1: sides (0,3) (3,2) (2,1) (1,0) are edges 3, 2, 1, 0; top face 4-5-6-7: edges 4, 5, 6, 7.
    EXPECT_EQ(kHexFaceSideEdges[0], (std::array<int, 4>{3, 2, 1, 0}));
    EXPECT_EQ(kHexFaceSideEdges[1], (std::array<int, 4>{4, 5, 6, 7}));
    for (std::size_t lf = 0; lf < 6; ++lf)
        for (std::size_t i = 0; i < 4; ++i) {
            const std::array<int, 2>& e = kHexEdges[static_cast<std::size_t>(kHexFaceSideEdges[lf][i])];
            const int a = kHexFaces[lf][i], b = kHexFaces[lf][(i + 1) % 4];
            EXPECT_TRUE((e[0] == a && e[1] == b) || (e[0] == b && e[1] == a)) << lf << " " << i;
        }
}

// Repeated unordered pairs (core/unordered_pairs.h, skeleton.h), counts by hand.
TEST(SkeletonPairs, FirstOfEachPair) {
    const std::vector<std::array<int, 2>> pairs{{1, 2}, {2, 1}, {0, 3}, {1, 2}, {3, 0}, {2, 2}};
    EXPECT_EQ(first_of_each_pair(pairs, 4), (std::vector<char>{1, 0, 1, 0, 0, 1}));
    const std::vector<std::array<int, 2>> wild{{1, 2}, {-5, 7}, {2, 1}, {7, -5}};  // ids outside [0, 4): sorted
    EXPECT_EQ(first_of_each_pair(wild, 4), (std::vector<char>{1, 1, 0, 0}));
}

TEST(SkeletonPairs, FanSidesBranchEdgesAndAddedFaceSides) {
    Skeleton s;
    s.points.assign(9, Vec3{0, 0, 0});
    s.faces = {{0, 1, 2, 3}, {1, 4, 5, 2}};
    EXPECT_EQ(add_face_edges(s), 7);  // 4 + 3: side (2, 1) of the second face is (1, 2) of the first
    EXPECT_EQ(s.edges[4], (std::array<int, 2>{1, 4}));
    EXPECT_EQ(s.edges[6], (std::array<int, 2>{5, 2}));
    EXPECT_FALSE(has_side_of_three_faces(s));  // side (1, 2) on two faces
    EXPECT_FALSE(has_edge_off_faces(s));
    s.faces.push_back({1, 2, 7, 6});  // a third face on (1, 2): a fan
    EXPECT_EQ(add_face_edges(s), 3);
    EXPECT_TRUE(has_side_of_three_faces(s));
    s.edges.push_back({0, 8});  // a branch
    EXPECT_TRUE(has_edge_off_faces(s));
}

// The local boundary neighbours equal the whole topology's (sorted, without repeats) on every vertex of meshes with
// interior vertices, a hole, a non-manifold face, repeated hexes and a hex with a repeated vertex; by hand on the
// 2 x 2 x 2 block: the centre (13) has none, the corner 0 has (1, 0, 0) = 1, (0, 1, 0) = 3, (0, 0, 1) = 9, the bottom
// face centre 4 its four bottom neighbours 1, 3, 5, 7 (its edge up to 13 is interior).
TEST(Topology, LocalBoundaryNeighboursEqualTheWholeTopologys) {
    const auto whole = [](const HexMesh& m) {
        std::vector<std::vector<int>> n = boundary_edge_neighbours(compute_hex_topology(m), m.points.size());
        for (std::vector<int>& l : n) {
            std::sort(l.begin(), l.end());
            l.erase(std::unique(l.begin(), l.end()), l.end());
        }
        return n;
    };
    const auto all_vertices = [](const HexMesh& m) {
        std::vector<int> v(m.points.size());
        for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<int>(i);
        return v;
    };
    const HexMesh block = make_block(2, 2, 2);
    const std::vector<std::vector<int>> local = boundary_edge_neighbours(block, {0, 4, 13});
    EXPECT_EQ(local[0], (std::vector<int>{1, 3, 9}));
    EXPECT_EQ(local[4], (std::vector<int>{1, 3, 5, 7}));
    EXPECT_TRUE(local[13].empty());
    EXPECT_TRUE(local[1].empty());  // not listed

    std::vector<HexMesh> meshes = {block, make_block(4, 3, 2), mesohex::test::make_ring8()};
    HexMesh holed = make_block(3, 3, 3);
    holed.hexes.erase(holed.hexes.begin() + 13);  // the centre hex: its 8 corners get interior boundary faces
    meshes.push_back(holed);
    HexMesh nonmanifold = mesohex::test::make_unit_cube();
    for (int i = 0; i < 4; ++i) nonmanifold.points.push_back(nonmanifold.points[4 + i] + Vec3{0, 0, 1});
    nonmanifold.hexes.push_back({4, 5, 6, 7, 8, 9, 10, 11});
    nonmanifold.hexes.push_back({4, 5, 6, 7, 8, 9, 10, 11});
    meshes.push_back(nonmanifold);
    HexMesh degenerate = make_block(2, 1, 1);
    degenerate.hexes[1][6] = degenerate.hexes[1][7];  // a collapsed edge: two faces of hex 1 become triangles
    degenerate.hexes.push_back(degenerate.hexes[0]);  // hex 0 twice: none of its faces is on the boundary
    meshes.push_back(degenerate);
    for (const HexMesh& m : meshes) EXPECT_EQ(boundary_edge_neighbours(m, all_vertices(m)), whole(m));

    // The listed vertices run in parallel ranges: every vertex of a 6 x 6 x 6 block (343, several ranges) listed in
    // reverse order and then once more gets the whole topology's list, each neighbour once.
    const HexMesh big = make_block(6, 6, 6);
    std::vector<int> twice = all_vertices(big);
    std::reverse(twice.begin(), twice.end());
    const std::vector<int> once = all_vertices(big);
    twice.insert(twice.end(), once.begin(), once.end());
    EXPECT_EQ(boundary_edge_neighbours(big, twice), whole(big));
}
