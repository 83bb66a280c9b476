// Scaled Jacobian (Verdict definition) and the topology numbers of the quality report.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "hex_fixtures.h"
#include "mesohex/post/quality.h"

using namespace mesohex;
using mesohex::test::corners_of;
using mesohex::test::make_block;

namespace {

// Second formulation, written from Verdict's V_hex.cpp listing: the 8 corner Jacobians J(xi, eta, zeta) as explicit
// node triples (xxi, xet, xze) relative to the corner, and the centre Jacobian from the "efg" face sums; each
// det / sqrt(|xxi|^2 |xet|^2 |xze|^2) with an explicitly expanded 3x3 determinant.
double reference_scaled_jacobian(const std::array<Vec3, 8>& p) {
    const int table[8][4] = {
        // corner, xxi, xet, xze
        {0, 1, 3, 4}, {1, 2, 0, 5}, {2, 3, 1, 6}, {3, 0, 2, 7}, {4, 7, 5, 0}, {5, 4, 6, 1}, {6, 5, 7, 2}, {7, 6, 4, 3}};
    auto det = [](const double a[3], const double b[3], const double c[3]) {
        return a[0] * (b[1] * c[2] - b[2] * c[1]) - b[0] * (a[1] * c[2] - a[2] * c[1]) +
               c[0] * (a[1] * b[2] - a[2] * b[1]);
    };
    auto value = [&](const double a[3], const double b[3], const double c[3]) {
        const double la = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
        const double lb = b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
        const double lc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        return det(a, b, c) / std::sqrt(la * lb * lc);
    };
    double a[3], b[3], c[3];
    for (int i = 0; i < 3; ++i) {
        a[i] = p[1][i] + p[2][i] + p[5][i] + p[6][i] - p[0][i] - p[3][i] - p[4][i] - p[7][i];
        b[i] = p[2][i] + p[3][i] + p[6][i] + p[7][i] - p[0][i] - p[1][i] - p[4][i] - p[5][i];
        c[i] = p[4][i] + p[5][i] + p[6][i] + p[7][i] - p[0][i] - p[1][i] - p[2][i] - p[3][i];
    }
    double best = value(a, b, c);
    for (const auto& row : table) {
        for (int i = 0; i < 3; ++i) {
            a[i] = p[row[1]][i] - p[row[0]][i];
            b[i] = p[row[2]][i] - p[row[0]][i];
            c[i] = p[row[3]][i] - p[row[0]][i];
        }
        best = std::min(best, value(a, b, c));
    }
    return best;
}

std::array<Vec3, 8> unit_cube() { return corners_of(mesohex::test::make_unit_cube(), 0); }

}  // namespace

TEST(ScaledJacobian, UnitCubeIsExactlyOne) { EXPECT_EQ(scaled_jacobian(unit_cube()), 1.0); }

TEST(ScaledJacobian, MirrorIsMinusOne) {
    std::array<Vec3, 8> p = unit_cube();
    for (Vec3& v : p) v.x = -v.x;
    EXPECT_EQ(scaled_jacobian(p), -1.0);
    // bottom and top swapped: also a mirror image
    std::array<Vec3, 8> q = unit_cube();
    std::array<Vec3, 8> r = {q[4], q[5], q[6], q[7], q[0], q[1], q[2], q[3]};
    EXPECT_EQ(scaled_jacobian(r), -1.0);
}

TEST(ScaledJacobian, ShearedHexByHand) {
    // Top face shifted by (1, 0, 0): a parallelepiped; every frame has two unit columns and one of length sqrt(2),
    // and determinant 1 (volume), so the value is 1 / sqrt(2).
    std::array<Vec3, 8> p = unit_cube();
    for (int i = 4; i < 8; ++i) p[i].x += 1.0;
    EXPECT_NEAR(scaled_jacobian(p), 1.0 / std::sqrt(2.0), 1e-15);
}

TEST(ScaledJacobian, RaisedCornerByHand) {
    // Unit cube with vertex 6 raised from (1,1,1) to (1,1,2). Corner 6: columns (0,-1,-1), (-1,0,-1), (0,0,-2),
    // det 2, lengths sqrt2 sqrt2 2 -> 0.5. Corners 5 and 7: 1/sqrt2. Centre: (4,0,1), (0,4,1), (0,0,5) -> 80/85.
    std::array<Vec3, 8> p = unit_cube();
    p[6] = {1, 1, 2};
    EXPECT_NEAR(scaled_jacobian(p), 0.5, 1e-15);
    // with corner 6 flattened into the plane of its neighbours... pushing it far below makes it inverted
    p[6] = {1, 1, -1};
    EXPECT_LT(scaled_jacobian(p), 0.0);
}

TEST(ScaledJacobian, DegenerateAndNonFiniteAreMinusOne) {
    std::array<Vec3, 8> p = unit_cube();
    p[6] = p[7];  // zero-length edge
    EXPECT_EQ(scaled_jacobian(p), -1.0);
    std::array<Vec3, 8> flat = unit_cube();
    for (Vec3& v : flat) v.z = 0;  // all flat: zero-length vertical edges
    EXPECT_EQ(scaled_jacobian(flat), -1.0);
    std::array<Vec3, 8> nan = unit_cube();
    nan[2].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(scaled_jacobian(nan), -1.0);
    std::array<Vec3, 8> inf = unit_cube();
    inf[5].x = std::numeric_limits<double>::infinity();
    EXPECT_EQ(scaled_jacobian(inf), -1.0);
}

TEST(ScaledJacobian, AgreesWithSecondFormulationOnRandomHexes) {
    std::mt19937 rng(12345);
    int inverted = 0;
    for (int trial = 0; trial < 600; ++trial) {
        const double amplitude = trial < 300 ? 0.3 : 1.2;  // the second half has many inverted hexes
        std::uniform_real_distribution<double> noise(-amplitude, amplitude);
        std::uniform_real_distribution<double> scale(0.01, 100.0);
        const double s = scale(rng);
        std::array<Vec3, 8> p = unit_cube();
        for (Vec3& v : p) v = (v + Vec3{noise(rng), noise(rng), noise(rng)}) * s;
        const double expected = reference_scaled_jacobian(p);
        const double got = scaled_jacobian(p);
        EXPECT_NEAR(got, expected, 1e-12) << "trial " << trial;
        EXPECT_LE(got, 1.0 + 1e-12);
        EXPECT_GE(got, -1.0 - 1e-12);
        inverted += got <= 0;
    }
    EXPECT_GT(inverted, 20);  // the comparison covered the negative range too
}

TEST(ScaledJacobian, PerHexVectorMatchesSingle) {
    HexMesh m = make_block(3, 2, 2);
    m.points[5].z += 0.4;
    m.hexes[3][1] = 1000;  // out of range: -1, never a crash
    const std::vector<double> sj = scaled_jacobians(m);
    ASSERT_EQ(sj.size(), m.hexes.size());
    for (std::size_t h = 0; h < m.hexes.size(); ++h) {
        if (h == 3)
            EXPECT_EQ(sj[h], -1.0);
        else
            EXPECT_EQ(sj[h], scaled_jacobian(corners_of(m, static_cast<int>(h))));
    }
}

TEST(Quality, Block2x2x2) {
    const QualityReport r = compute_quality(make_block(2, 2, 2));
    EXPECT_EQ(r.vertices, 27);
    EXPECT_EQ(r.hexes, 8);
    EXPECT_EQ(r.sj_min, 1.0);
    EXPECT_EQ(r.sj_avg, 1.0);
    EXPECT_EQ(r.inverted, 0);
    EXPECT_EQ(r.euler_characteristic, 1);  // 27 - 54 + 36 - 8
    EXPECT_TRUE(r.singular_interior_edges.empty());
    // boundary: 24 edges on the cube's edges have valence 1
    ASSERT_EQ(r.singular_boundary_edges.size(), 1u);
    EXPECT_EQ(r.singular_boundary_edges.at(1), 24);
    EXPECT_EQ(r.boundary_components, 1);
    EXPECT_EQ(r.boundary_euler_characteristic, 2);  // 26 - 48 + 24
    EXPECT_EQ(r.boundary_genus, 0.0);
    EXPECT_EQ(r.sj_histogram[9], 8);
    EXPECT_TRUE(r.validation.valid());
    EXPECT_EQ(r.worst_hexes, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
}

// The overload handing over its topology: the same report, and the topology compute_hex_topology gives (ring8: 32
// vertices, 8 hexes, 48 - 8 shared = 40 faces of which 32 on the boundary: 8 top, 8 bottom, 12 outer, 4 inner; 64
// edges); empty when an index is out of range.
TEST(Quality, HandsOverTheTopologyItComputed) {
    const HexMesh m = mesohex::test::make_ring8();
    HexTopology topo;
    const QualityReport r = compute_quality(m, topo);
    const QualityReport plain = compute_quality(m);
    EXPECT_EQ(r.sj, plain.sj);
    EXPECT_EQ(r.singular_boundary_edges, plain.singular_boundary_edges);
    EXPECT_EQ(r.euler_characteristic, plain.euler_characteristic);
    const HexTopology direct = compute_hex_topology(m);
    EXPECT_EQ(topo.faces, direct.faces);
    EXPECT_EQ(topo.edges, direct.edges);
    EXPECT_EQ(topo.edge_valence, direct.edge_valence);
    EXPECT_EQ(topo.boundary_quads, direct.boundary_quads);
    EXPECT_EQ(topo.faces.size(), 40u);
    EXPECT_EQ(topo.boundary_quads.size(), 32u);
    EXPECT_EQ(topo.edges.size(), 64u);
    HexMesh bad = m;
    bad.hexes[2][5] = 1000;
    compute_quality(bad, topo);
    EXPECT_TRUE(topo.faces.empty());
    EXPECT_TRUE(topo.hex_faces.empty());
}

TEST(Quality, Ring8IsASolidTorus) {
    const QualityReport r = compute_quality(mesohex::test::make_ring8());
    EXPECT_EQ(r.hexes, 8);
    EXPECT_EQ(r.euler_characteristic, 0);  // 32 - 64 + 40 - 8
    EXPECT_EQ(r.boundary_components, 1);
    EXPECT_EQ(r.boundary_euler_characteristic, 0);
    EXPECT_EQ(r.boundary_genus, 1.0);
    EXPECT_TRUE(r.singular_interior_edges.empty());
    // boundary valences: the 4 inner vertical corner edges have 3 hexes; valence 1: the 4 outer vertical corner
    // edges, the outer rim (12 edges per layer, 2 layers) and the inner rim (4 edges per layer, 2 layers).
    EXPECT_EQ(r.singular_boundary_edges.at(3), 4);
    EXPECT_EQ(r.singular_boundary_edges.at(1), 4 + 2 * 12 + 2 * 4);
    EXPECT_EQ(r.singular_boundary_edges.size(), 2u);
    EXPECT_TRUE(r.validation.valid());
}

TEST(Quality, TwoSeparateCubesHaveTwoSpheres) {
    HexMesh m = mesohex::test::make_unit_cube();
    for (int i = 0; i < 8; ++i) m.points.push_back(m.points[i] + Vec3{5, 0, 0});
    m.hexes.push_back({8, 9, 11, 10, 12, 13, 15, 14});
    const QualityReport r = compute_quality(m);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_EQ(r.boundary_components, 2);
    EXPECT_EQ(r.boundary_euler_characteristic, 4);
    EXPECT_EQ(r.boundary_genus, 0.0);
}

TEST(Quality, InvertedHexHistogramAndWorst) {
    HexMesh m = make_block(4, 1, 1);
    std::array<int, 8>& h = m.hexes[2];
    h = {h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]};  // mirrored: -1
    m.points[0].x = -0.5;                                  // hex 0 sheared a little
    const QualityReport r = compute_quality(m);
    EXPECT_EQ(r.inverted, 1);
    EXPECT_EQ(r.sj_min, -1.0);
    EXPECT_EQ(r.sj_histogram[0], 1);
    EXPECT_EQ(r.sj_histogram[9], 2);
    ASSERT_EQ(r.worst_hexes.size(), 4u);
    EXPECT_EQ(r.worst_hexes[0], 2);
    EXPECT_EQ(r.worst_hexes[1], 0);
    EXPECT_FALSE(r.validation.valid());  // the mirrored hex's faces have the wrong orientation
    EXPECT_NEAR(r.sj_avg, (r.sj[0] + 1.0 + 1.0 - 1.0) / 4.0, 1e-15);
}

TEST(Quality, JsonAndText) {
    HexMesh m = make_block(2, 2, 2);
    const QualityReport r = compute_quality(m);
    const std::string json = quality_to_json(r);
    for (const char* key : {"\"vertices\": 27", "\"hexes\": 8", "\"sj_min\": 1.0", "\"sj_avg\": 1.0", "\"inverted\": 0",
                            "\"euler_characteristic\": 1", "\"singular_edges\"", "\"interior\": {}", "\"valid\": true",
                            "\"problems\": []"})
        EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
    const std::string text = quality_to_text(r);
    EXPECT_NE(text.find("hexes: 8"), std::string::npos) << text;
    EXPECT_NE(text.find("valid: yes"), std::string::npos) << text;

    m.hexes[0][0] = 77;
    const QualityReport bad = compute_quality(m);
    const std::string bad_json = quality_to_json(bad, -1);
    EXPECT_NE(bad_json.find("\"valid\":false"), std::string::npos) << bad_json;
    EXPECT_NE(bad_json.find("index_out_of_range"), std::string::npos) << bad_json;
}
