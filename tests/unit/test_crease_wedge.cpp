// Crease wedges: two hexes folded to a 320-degree concave crease (the crotch between two chunks of a junction, in
// cross-section), the wedge derived on paper.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"
#include "mesohex/core/validate.h"
#include "mesohex/post/crease_wedge.h"

using namespace mesohex;

namespace {

constexpr double kPi = std::numbers::pi;

// Cross-section: A = (0, 0) the crease, K = (-1, 0) the face shared by the two hexes (the kite), X1 = (cos 20, sin 20)
// and X2 = (cos 20, -sin 20) the boundary quads' directions, so each hex has 160 degrees at A (the crease 320, the gap
// 40 degrees around +x); D1 = (-0.3, 1.2), D2 = (-0.3, -1.2).
// Extruded over z = 0 .. layers, one hex per layer and side.
HexMesh folded_pair(int layers) {
    const double c = std::cos(20 * kPi / 180), s = std::sin(20 * kPi / 180);
    const std::array<Vec3, 6> section = {
        {{0, 0, 0}, {c, s, 0}, {-0.3, 1.2, 0}, {-1, 0, 0}, {-0.3, -1.2, 0}, {c, -s, 0}}};
    HexMesh m;
    for (int z = 0; z <= layers; ++z)
        for (const Vec3& p : section) m.points.push_back(p + Vec3{0, 0, static_cast<double>(z)});
    for (int z = 0; z < layers; ++z) {
        const int o = 6 * z, u = 6 * (z + 1);
        m.hexes.push_back({o + 0, o + 1, o + 2, o + 3, u + 0, u + 1, u + 2, u + 3});  // A X1 D1 K (counter-clockwise)
        m.hexes.push_back({o + 0, o + 3, o + 4, o + 5, u + 0, u + 3, u + 4, u + 5});  // A K D2 X2
    }
    return m;
}

double sj(const HexMesh& m, std::size_t h) {
    std::array<Vec3, 8> p{};
    for (std::size_t lv = 0; lv < 8; ++lv) p[lv] = m.points[static_cast<std::size_t>(m.hexes[h][lv])];
    return hex_scaled_jacobian(p);
}

int hexes_on_edge(const HexMesh& m, int a, int b) {
    const HexTopology t = compute_hex_topology(m);
    for (std::size_t e = 0; e < t.edges.size(); ++e)
        if (t.edges[e][0] == std::min(a, b) && t.edges[e][1] == std::max(a, b)) return t.edge_valence[e];
    return -1;
}

}  // namespace

// One layer: the crease (0, 6) measures 320 degrees; one wedge (A, X, C, X') x 2 whose new vertex C = (1 / cos 20, 0)
// gives its cross-section right angles at X1 and X2, 40 degrees at A and 140 at C: scaled Jacobian sin 40 degrees.
// The crease then has three hexes; the boundary goes from 10 quads to 12 (q1, q2 inside, 4 wedge faces out).
TEST(CreaseWedge, OneWedgeFillsTheGapOfAFoldedCrease) {
    const HexMesh m = folded_pair(1);
    const VertexHexes vh = vertex_hexes(m);
    const std::vector<int> at_a(vh.hexes.begin() + vh.begin[0], vh.hexes.begin() + vh.begin[1]);
    EXPECT_NEAR(interior_dihedral_deg(m, at_a, 0, 6), 320.0, 1e-9);
    CreaseWedgeOptions o;
    o.min_dihedral_deg = 270;
    const CreaseWedgeResult r = insert_crease_wedges(m, o);
    ASSERT_EQ(r.mesh.hexes.size(), 3u);
    ASSERT_EQ(r.mesh.points.size(), 14u);
    ASSERT_EQ(r.wedge_edges.size(), 1u);
    EXPECT_EQ(r.wedge_edges[0], (std::array<int, 2>{0, 6}));
    const double reach = 1 / std::cos(20 * kPi / 180);
    EXPECT_NEAR(distance(r.mesh.points[12], Vec3{reach, 0, 0}), 0, 1e-12);
    EXPECT_NEAR(distance(r.mesh.points[13], Vec3{reach, 0, 1}), 0, 1e-12);
    EXPECT_NEAR(sj(r.mesh, 2), std::sin(40 * kPi / 180), 1e-9);
    EXPECT_GT(sj(r.mesh, 0), 0.3);
    EXPECT_GT(sj(r.mesh, 1), 0.3);
    EXPECT_EQ(hexes_on_edge(m, 0, 6), 2);
    EXPECT_EQ(hexes_on_edge(r.mesh, 0, 6), 3);
    EXPECT_TRUE(validate(r.mesh).valid());
    EXPECT_EQ(compute_hex_topology(m).boundary_quads.size(), 10u);
    EXPECT_EQ(compute_hex_topology(r.mesh).boundary_quads.size(), 12u);
    // Input hexes and vertices unchanged.
    for (std::size_t v = 0; v < m.points.size(); ++v) EXPECT_EQ(r.mesh.points[v], m.points[v]);
    for (std::size_t h = 0; h < m.hexes.size(); ++h) EXPECT_EQ(r.mesh.hexes[h], m.hexes[h]);
}

// A threshold above the crease's 320 degrees, or 0 (off): the input, unchanged.
TEST(CreaseWedge, NoEdgeAboveTheThresholdLeavesTheMeshUnchanged) {
    const HexMesh m = folded_pair(1);
    CreaseWedgeOptions o;
    o.min_dihedral_deg = 325;
    EXPECT_EQ(insert_crease_wedges(m, o).mesh, m);
    o.min_dihedral_deg = 0;
    EXPECT_EQ(insert_crease_wedges(m, o).mesh, m);
}

// keep_vertex refusing the new vertex on the gap's side (x >
// 1): the one wedge is dropped; refusing only x > 2 keeps it.
TEST(CreaseWedge, RefusedNewVertexDropsTheWedge) {
    const HexMesh m = folded_pair(1);
    CreaseWedgeOptions o;
    o.min_dihedral_deg = 270;
    o.keep_vertex = [](const Vec3& p) { return p.x <= 1; };
    const CreaseWedgeResult r = insert_crease_wedges(m, o);
    EXPECT_EQ(r.mesh, m);
    EXPECT_TRUE(r.wedge_edges.empty());
    o.keep_vertex = [](const Vec3& p) { return p.x <= 2; };
    EXPECT_EQ(insert_crease_wedges(m, o).mesh.hexes.size(), 3u);
}

// Two layers: the crease is the chain 0-6-12; two wedges sharing their middle face, so three new vertices, not four;
// the middle crease vertex 6 has its four boundary quads covered and becomes interior (on 4 hexes + 2 wedges = 3
// hexes per crease edge). Every wedge sin 40 degrees.
TEST(CreaseWedge, ConsecutiveWedgesShareTheirEndFace) {
    const HexMesh m = folded_pair(2);
    CreaseWedgeOptions o;
    o.min_dihedral_deg = 270;
    const CreaseWedgeResult r = insert_crease_wedges(m, o);
    ASSERT_EQ(r.mesh.hexes.size(), 6u);
    ASSERT_EQ(r.mesh.points.size(), 18u + 3u);
    EXPECT_NEAR(sj(r.mesh, 4), std::sin(40 * kPi / 180), 1e-9);
    EXPECT_NEAR(sj(r.mesh, 5), std::sin(40 * kPi / 180), 1e-9);
    EXPECT_EQ(hexes_on_edge(r.mesh, 0, 6), 3);
    EXPECT_EQ(hexes_on_edge(r.mesh, 6, 12), 3);
    EXPECT_TRUE(validate(r.mesh).valid());
    const HexTopology t = compute_hex_topology(r.mesh);
    for (const std::array<int, 4>& q : t.boundary_quads)
        for (int v : q) EXPECT_NE(v, 6) << "the middle crease vertex stays on the boundary";
}

// listed_only (the close-pair restriction, MeshOptions::crease_wedge_pair_deg): on the one-layer fold, listing the
// crease edge (0, 6) gives the unrestricted wedge (3 hexes, 14 points); listing only another edge, (1, 7) (a side
// edge of one hex), or nothing gives no wedge: the input.
TEST(CreaseWedge, ListedOnlyKeepsTheWedgeOnTheListedCreaseAlone) {
    const HexMesh m = folded_pair(1);
    CreaseWedgeOptions o;
    o.min_dihedral_deg = 270;
    o.listed_only = true;
    o.listed = {{0, 6}};
    const CreaseWedgeResult on = insert_crease_wedges(m, o);
    ASSERT_EQ(on.wedge_edges.size(), 1u);
    EXPECT_EQ(on.mesh.hexes.size(), 3u);
    EXPECT_EQ(on.mesh.points.size(), 14u);
    for (const std::vector<std::array<int, 2>>& listed :
         {std::vector<std::array<int, 2>>{{1, 7}}, std::vector<std::array<int, 2>>{}}) {
        o.listed = listed;
        const CreaseWedgeResult off = insert_crease_wedges(m, o);
        EXPECT_TRUE(off.wedge_edges.empty());
        EXPECT_EQ(off.mesh.points, m.points);
        EXPECT_EQ(off.mesh.hexes, m.hexes);
    }
}

// The crotch cut on the one-layer fold, the domain the half-space x < 0.5 (its distance along the bisector +x from the
// crease vertices A, A' is 0.5), crotch_reach 1: the uncut wedge would reach 1 / cos 20 = 1.0642, so each hex is cut
// (its sheet is that hex alone: the fold is one layer) at f = 0.5 cos 20 = 0.4698 of its quad edges A-X1 (A-X2) and, at
// the same mean fraction, K-D1 (K-D2); the wedge's new vertices then stand at (0.5, 0, z), on the domain, and its
// cross-section is the uncut one scaled by f: scaled Jacobian sin 40 degrees. Counts by hand: 2 hexes -> 4 (each cut
// in two) -> 5 with the wedge; 12 points + 4 per cut sheet + 2 new wedge vertices = 22; boundary quads 10 -> 18 (4
// hexes, 3 inner faces: the kite and the two cuts) -> 20 (the wedge covers 2, adds 4); the crease (0, 6) on three
// hexes. With the half-space x < 2 (beyond the uncut reach) nothing is cut: the uncut wedge (3 hexes, 14 points); with
// every point outside (distance 0) no wedge: the input.
TEST(CreaseWedge, CrotchCutEndsTheWedgeAtTheDomain) {
    const HexMesh m = folded_pair(1);
    CreaseWedgeOptions o;
    o.min_dihedral_deg = 270;
    o.crotch_reach = 1;
    const auto half_space = [](double x0) {
        return [x0](const Vec3& p, const Vec3& d) {
            if (p.x >= x0) return 0.0;
            return d.x > 0 ? (x0 - p.x) / d.x : std::numeric_limits<double>::infinity();
        };
    };
    o.crotch_distance = half_space(0.5);
    const CreaseWedgeResult r = insert_crease_wedges(m, o);
    ASSERT_EQ(r.wedge_edges.size(), 1u);
    EXPECT_EQ(r.crotch_sheets, 2);
    ASSERT_EQ(r.mesh.hexes.size(), 5u);
    ASSERT_EQ(r.mesh.points.size(), 22u);
    const double c = std::cos(20 * kPi / 180), s = std::sin(20 * kPi / 180), f = 0.5 * c;
    EXPECT_NEAR(distance(r.mesh.points[20], Vec3{0.5, 0, 0}), 0, 1e-12);
    EXPECT_NEAR(distance(r.mesh.points[21], Vec3{0.5, 0, 1}), 0, 1e-12);
    // The cut on A-X1 and on K-D1 (every edge of the one-hex sheet is a boundary edge: the mean fraction).
    const auto has_point = [&](const Vec3& p) {
        return std::any_of(r.mesh.points.begin(), r.mesh.points.end(),
                           [&](const Vec3& q) { return distance(p, q) < 1e-12; });
    };
    EXPECT_TRUE(has_point(Vec3{f * c, f * s, 0}));
    EXPECT_TRUE(has_point(Vec3{f * c, -f * s, 1}));
    EXPECT_TRUE(has_point(Vec3{-1 + f * 0.7, f * 1.2, 0}));
    EXPECT_NEAR(sj(r.mesh, 4), std::sin(40 * kPi / 180), 1e-9);
    for (std::size_t h = 0; h < 4; ++h) EXPECT_GT(sj(r.mesh, h), 0.3) << h;
    EXPECT_EQ(hexes_on_edge(r.mesh, 0, 6), 3);
    EXPECT_TRUE(validate(r.mesh).valid());
    EXPECT_EQ(compute_hex_topology(r.mesh).boundary_quads.size(), 20u);
    // Input vertices kept (the cut's and the wedge's come after them).
    for (std::size_t v = 0; v < m.points.size(); ++v) EXPECT_EQ(r.mesh.points[v], m.points[v]);

    o.crotch_distance = half_space(2);
    const CreaseWedgeResult far = insert_crease_wedges(m, o);
    EXPECT_EQ(far.crotch_sheets, 0);
    EXPECT_EQ(far.mesh.hexes.size(), 3u);
    EXPECT_EQ(far.mesh.points.size(), 14u);
    o.crotch_distance = half_space(-1);
    EXPECT_EQ(insert_crease_wedges(m, o).mesh, m);
}
