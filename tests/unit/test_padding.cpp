// Padding: counts, validity, Euler characteristic and singular edges, derived on paper.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "hex_fixtures.h"
#include "mesohex/core/cone.h"
#include "mesohex/core/error.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"
#include "mesohex/core/validate.h"
#include "mesohex/post/pad_inset.h"
#include "mesohex/post/padding.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/connection_surfaces.h"
#include "mesohex/stages/frame_propagation.h"
#include "mesohex/stages/raw_mesh.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "skeleton_fixtures.h"

using namespace mesohex;
using mesohex::test::make_block;

namespace {

PaddingOptions options(int layers, double thickness = 0.25) {
    PaddingOptions o;
    o.layers = layers;
    o.thickness = thickness;
    return o;
}

// Number of boundary quads of each hex.
std::vector<int> exposed_faces(const HexMesh& m) {
    const HexTopology t = compute_hex_topology(m);
    std::vector<int> count(m.hexes.size(), 0);
    for (int f : t.boundary_face) ++count[static_cast<std::size_t>(t.face_hexes[static_cast<std::size_t>(f)][0])];
    return count;
}

// The 3x3x3 block without its centre hex: a box shell with two boundary components (outer 54 quads, inner 6).
HexMesh make_box_shell() {
    HexMesh m = make_block(3, 3, 3);
    m.hexes.erase(m.hexes.begin() + 13);  // hex (1, 1, 1)
    return m;
}

// A U: the 3 x 3 x 3 block without its middle column's upper two layers, the slot (open in y) squeezed to 0.2 wide
// (x = 0.9 .. 1.1).
HexMesh make_narrow_slot() {
    HexMesh u = make_block(3, 3, 3);
    std::vector<std::array<int, 8>> kept;
    for (std::size_t h = 0; h < u.hexes.size(); ++h) {
        const int i = static_cast<int>(h) % 3, k = static_cast<int>(h) / 9;
        if (!(i == 1 && k >= 1)) kept.push_back(u.hexes[h]);
    }
    u.hexes = kept;
    for (Vec3& p : u.points) {
        if (p.x == 1)
            p.x = 0.9;
        else if (p.x == 2)
            p.x = 1.1;
        else if (p.x == 3)
            p.x = 2.1;
    }
    return u;
}

}  // namespace

TEST(Padding, SingleHexGivesSeven) {
    const PaddingResult r = pad(mesohex::test::make_unit_cube());
    EXPECT_EQ(r.mesh.hexes.size(), 7u);
    EXPECT_EQ(r.mesh.points.size(), 16u);  // 8 old + 8 pushed copies
    EXPECT_EQ(r.first_new_vertex, 8);
    EXPECT_EQ(r.first_new_hex, 1);
    const QualityReport q = compute_quality(r.mesh);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, 1);
    EXPECT_EQ(q.inverted, 0);
    // Old boundary edges (12) had valence 1; now interior with valence 3. The 8 pushed edges v-v' at the cube corners
    // see 3 hexes too. Nothing else is irregular inside; the new boundary is a cube skin (valence 2 everywhere).
    EXPECT_EQ(q.singular_interior_edges.at(3), 20);
    EXPECT_EQ(q.singular_interior_edges.size(), 1u);
    EXPECT_TRUE(q.singular_boundary_edges.empty());
    // Every boundary hex exposes exactly one face; the old hex is interior.
    const std::vector<int> exposed = exposed_faces(r.mesh);
    EXPECT_EQ(exposed[0], 0);
    for (int h = 1; h < 7; ++h) EXPECT_EQ(exposed[static_cast<std::size_t>(h)], 1);
    // Maps.
    for (int v = 0; v < 8; ++v) EXPECT_EQ(r.origin_vertex[static_cast<std::size_t>(v)], v);
    for (int v = 8; v < 16; ++v) {
        const int o = r.origin_vertex[static_cast<std::size_t>(v)];
        ASSERT_GE(o, 0);
        ASSERT_LT(o, 8);
    }
    EXPECT_EQ(r.layer_of_hex, (std::vector<int>{0, 1, 1, 1, 1, 1, 1}));
}

TEST(Padding, CubeCornerMovesToTheOffsetCube) {
    // thickness 0.25 x mean boundary edge length 1: the 8 new vertices are the corners of [-0.25, 1.25]^3.
    const PaddingResult r = pad(mesohex::test::make_unit_cube());
    for (int v = 8; v < 16; ++v) {
        const Vec3 o = r.mesh.points[static_cast<std::size_t>(r.origin_vertex[static_cast<std::size_t>(v)])];
        const Vec3 p = r.mesh.points[static_cast<std::size_t>(v)];
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(p[a], o[a] == 0 ? -0.25 : 1.25, 1e-12);
    }
    for (double sj : compute_quality(r.mesh).sj) EXPECT_GT(sj, 0.5);
}

// A hex of 1 x 1 x 3: the layer is thickness x the SHORTEST boundary edge at each vertex (1), so the new vertices are
// the corners of [-0.25, 1.25]^2 x [-0.25, 3.25] (the mean edge at a corner, 5/3, would give 0.42). An offset rule
// replaces that offset: it receives the corner's offset (0.25 sqrt(3) along the diagonal, twice: no concave vertex)
// and the mean edge 5/3.
TEST(Padding, LayerFollowsTheShortestEdgeAndTheOffsetRule) {
    HexMesh tall = mesohex::test::make_unit_cube();
    for (Vec3& p : tall.points) p.z *= 3;
    const PaddingResult r = pad(tall);
    for (int v = 8; v < 16; ++v) {
        const Vec3 o = r.mesh.points[static_cast<std::size_t>(r.origin_vertex[static_cast<std::size_t>(v)])];
        const Vec3 p = r.mesh.points[static_cast<std::size_t>(v)];
        EXPECT_NEAR(p.x, o.x == 0 ? -0.25 : 1.25, 1e-12);
        EXPECT_NEAR(p.y, o.y == 0 ? -0.25 : 1.25, 1e-12);
        EXPECT_NEAR(p.z, o.z == 0 ? -0.25 : 3.25, 1e-12);
    }
    PaddingOptions o = options(1);
    int calls = 0;
    o.offset_rule = [&calls](const Vec3&, const Vec3& d, double t, double t_scaled, double mean_edge) {
        ++calls;
        EXPECT_NEAR(norm(d), 1.0, 1e-12);
        EXPECT_NEAR(t, 0.25 * std::sqrt(3.0), 1e-12);
        EXPECT_EQ(t_scaled, t);  // planar quads: no vertex is concave
        EXPECT_NEAR(mean_edge, 5.0 / 3.0, 1e-12);
        return 0.1 * std::sqrt(3.0);
    };
    const PaddingResult q = pad(tall, o);
    EXPECT_EQ(calls, 8);
    for (int v = 8; v < 16; ++v) {
        const Vec3 c = q.mesh.points[static_cast<std::size_t>(q.origin_vertex[static_cast<std::size_t>(v)])];
        const Vec3 p = q.mesh.points[static_cast<std::size_t>(v)];
        EXPECT_NEAR(p.x, c.x == 0 ? -0.1 : 1.1, 1e-12);
        EXPECT_NEAR(p.z, c.z == 0 ? -0.1 : 3.1, 1e-12);
    }
}

TEST(Padding, Block2x2x2Gives8Plus24) {
    const PaddingResult r = pad(make_block(2, 2, 2), options(1, 0.5));
    EXPECT_EQ(r.mesh.hexes.size(), 32u);
    EXPECT_EQ(r.mesh.points.size(), 27u + 26u);
    const QualityReport q = compute_quality(r.mesh);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, 1);
    EXPECT_EQ(q.inverted, 0);
    // The 12 feature edges of the old cube, 2 segments each, become valence-3 interior edges; plus the 8 corner
    // edges v-v'. Face-interior old edges get valence 4 (2 old + 2 new).
    EXPECT_EQ(q.singular_interior_edges.at(3), 24 + 8);
    EXPECT_EQ(q.singular_interior_edges.size(), 1u);
    const std::vector<int> exposed = exposed_faces(r.mesh);
    for (std::size_t h = 0; h < 8; ++h) EXPECT_EQ(exposed[h], 0);
    for (std::size_t h = 8; h < 32; ++h) EXPECT_EQ(exposed[h], 1);
}

TEST(Padding, HollowBoxShellGetsBothComponentsPadded) {
    const HexMesh shell = make_box_shell();
    ASSERT_EQ(shell.hexes.size(), 26u);
    ASSERT_EQ(compute_quality(shell).boundary_components, 2);
    const PaddingResult r = pad(shell);
    EXPECT_EQ(r.mesh.hexes.size(), 26u + 54u + 6u);
    EXPECT_EQ(r.mesh.points.size(), 64u + 56u + 8u);
    const QualityReport q = compute_quality(r.mesh);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.inverted, 0);
    EXPECT_EQ(q.boundary_components, 2);
    EXPECT_EQ(q.euler_characteristic, compute_quality(shell).euler_characteristic);
    // The inner skin moved into the cavity [1, 2]^3: its new vertices are strictly inside it.
    int inside = 0;
    for (std::size_t v = 64; v < r.mesh.points.size(); ++v) {
        const Vec3& p = r.mesh.points[v];
        if (p.x > 1 && p.x < 2 && p.y > 1 && p.y < 2 && p.z > 1 && p.z < 2) ++inside;
    }
    EXPECT_EQ(inside, 8);
    const std::vector<int> exposed = exposed_faces(r.mesh);
    for (std::size_t h = 0; h < 26; ++h) EXPECT_EQ(exposed[h], 0);
    for (std::size_t h = 26; h < r.mesh.hexes.size(); ++h) EXPECT_EQ(exposed[h], 1);
}

TEST(Padding, RingOfEightIsPaddedInsideAndOutside) {
    // 8 hexes around a hole (solid torus, one boundary component of genus 1): 32 boundary quads.
    const HexMesh ring = mesohex::test::make_ring8();
    const PaddingResult r = pad(ring);
    EXPECT_EQ(r.mesh.hexes.size(), 8u + 32u);
    const QualityReport q = compute_quality(r.mesh);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.inverted, 0);
    EXPECT_EQ(q.euler_characteristic, 0);
}

TEST(Padding, TwoLayersAndZeroLayers) {
    const PaddingResult r2 = pad(mesohex::test::make_unit_cube(), options(2));
    EXPECT_EQ(r2.mesh.hexes.size(), 13u);  // 7 + the 6 boundary quads of the padded cube
    EXPECT_TRUE(validate(r2.mesh).valid());
    EXPECT_EQ(std::count(r2.layer_of_hex.begin(), r2.layer_of_hex.end(), 2), 6);
    for (std::size_t v = 16; v < r2.mesh.points.size(); ++v) EXPECT_LT(r2.origin_vertex[v], 8);
    const PaddingResult r0 = pad(mesohex::test::make_unit_cube(), options(0));
    EXPECT_EQ(r0.mesh, mesohex::test::make_unit_cube());
}

TEST(Padding, RejectsBadInput) {
    HexMesh m = mesohex::test::make_unit_cube();
    m.hexes[0][3] = 99;
    EXPECT_THROW(pad(m), Error);
    EXPECT_THROW(pad(mesohex::test::make_unit_cube(), options(1, -1)), Error);
}

// The narrow slot (make_narrow_slot). At the slot's floor the two bottom corners' normals (45 degrees, toward each
// other) would carry their outer vertices past each other (offset ~0.25 each, half width 0.1) and invert the new hexes
// on the floor; the padding pulls those outer vertices back instead.
TEST(Padding, NarrowSlotDoesNotInvert) {
    const HexMesh u = make_narrow_slot();
    ASSERT_EQ(u.hexes.size(), 21u);
    ASSERT_EQ(compute_quality(u).inverted, 0);
    const long boundary_quads = static_cast<long>(compute_hex_topology(u).boundary_quads.size());
    const PaddingResult r = pad(u);
    EXPECT_EQ(static_cast<long>(r.mesh.hexes.size()), 21 + boundary_quads);
    const QualityReport q = compute_quality(r.mesh);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_GT(q.sj_min, 0.0);
}

// A thin slab of 3 x 3 x 2 hexes of 1 x 1 x 0.1 (a plate of two layers, as a leaflet's up and down plates): the top
// vertex (1, 1) sees boundary edges of length 1 and the edge of 0.1 down into the slab, so with inward_edges its new
// vertex is 0.25 x 0.1 above it (the layer follows the slab's thickness), without it 0.25 x 1.
TEST(Padding, ThinSlabLayerFollowsTheEdgeIntoTheMesh) {
    HexMesh slab = make_block(3, 3, 2);
    for (Vec3& p : slab.points) p.z *= 0.1;
    auto new_top_height = [&](bool inward) {
        PaddingOptions o = options(1);
        o.inward_edges = inward;
        const PaddingResult r = pad(slab, o);
        for (std::size_t v = static_cast<std::size_t>(r.first_new_vertex); v < r.mesh.points.size(); ++v) {
            const Vec3& from = slab.points[static_cast<std::size_t>(r.origin_vertex[v])];
            if (from.x == 1 && from.y == 1 && from.z == 0.2) return r.mesh.points[v].z;
        }
        return -1.0;
    };
    EXPECT_NEAR(new_top_height(true), 0.2 + 0.025, 1e-12);
    EXPECT_NEAR(new_top_height(false), 0.2 + 0.25, 1e-12);
}

// shorten_to_inward_edges on one hex of 2 x 3 x 0.5 whose bottom face (z = 0) is marked as the boundary: each bottom
// corner's edge into the mesh is its vertical edge, 0.5; an unmarked vertex is left alone, and a shorter value stays.
TEST(Padding, ShortestEdgeIntoTheMesh) {
    HexMesh box = mesohex::test::make_unit_cube();
    for (Vec3& p : box.points) p = {2 * p.x, 3 * p.y, 0.5 * p.z};
    std::vector<int> local(8, -1);
    int n = 0;
    for (std::size_t v = 0; v < 8; ++v)
        if (box.points[v].z == 0) local[v] = n++;
    ASSERT_EQ(n, 4);
    std::vector<double> shortest{10, 10, 10, 0.2};
    shorten_to_inward_edges(box, local, shortest);
    EXPECT_EQ(shortest, (std::vector<double>{0.5, 0.5, 0.5, 0.2}));
}

// A dimple: the 2 x 2 x 1 block of unit hexes with the centre of its top face, (1, 1, 1), lowered by h = 0.5. Its four
// top quads (diagonal-cross normals (-+0.5, -+0.5, 2) / sqrt(4.5)) fold into a valley through it: concave. Its padding
// direction is +z by symmetry, the mean cosine 2 / sqrt(4.5), its shortest boundary edge sqrt(1 + h^2). With
// concave_scale 1 the new vertex lies thickness x sqrt(1.25) = 0.279508 above it; with 3 (the convex rule) that times
// sqrt(4.5) / 2 = 0.296464. The same vertex raised by h instead (a bump, convex) moves 0.296464 under both.
TEST(Padding, ConcaveVertexIsNotScaledOutwards) {
    for (const double h : {0.5, -0.5}) {
        HexMesh m = make_block(2, 2, 1);
        int centre = -1;
        for (std::size_t v = 0; v < m.points.size(); ++v)
            if (m.points[v] == Vec3{1, 1, 1}) centre = static_cast<int>(v);
        ASSERT_GE(centre, 0);
        m.points[static_cast<std::size_t>(centre)].z = 1 - h;
        for (const double cap : {1.0, 3.0}) {
            SCOPED_TRACE(h > 0 ? "dimple" : "bump");
            PaddingOptions o;
            o.concave_scale = cap;
            const PaddingResult r = pad(m, o);
            int moved = 0;
            for (std::size_t v = static_cast<std::size_t>(r.first_new_vertex); v < r.mesh.points.size(); ++v) {
                if (r.origin_vertex[v] != centre) continue;
                ++moved;
                const Vec3 d = r.mesh.points[v] - m.points[static_cast<std::size_t>(centre)];
                EXPECT_NEAR(d.x, 0, 1e-12);
                EXPECT_NEAR(d.y, 0, 1e-12);
                EXPECT_NEAR(d.z, h > 0 && cap == 1.0 ? 0.25 * std::sqrt(1.25) : 0.25 * std::sqrt(1.25 * 4.5) / 2, 1e-9);
            }
            EXPECT_EQ(moved, 1);
            EXPECT_EQ(compute_quality(r.mesh).inverted, 0);
        }
    }
}

// Dino's hip by hand (RawMesh.CloseDegreeFourPairGetsNoFlatPointInItsCrotch): a degree-4 point c of radius 0.223 with
// body, tail and two legs 46 degrees apart. The raw boundary vertex on c's sphere closest to the legs' bisector (20
// and 38 degrees from them) is the crotch's connection-surface point; the boundary is concave there, so concave_scale 1
// moves it by thickness x its shortest boundary edge exactly, where the convex rule (3) carried it 1.67 x as far out
// into the crotch. Only 6 boundary vertices are concave, all on c's sphere (between branches); the cross-sections of
// the branches (convex tube walls) move as before, and neither padding inverts a hex.
TEST(Padding, JunctionCrotchPointOfACloseLegPairIsNotScaledOutwards) {
    const Skeleton s = mesohex::test::dino_hip();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const HexMesh raw = build_raw_mesh(s, an, cs, propagate_frames(s, an, cs)).mesh;
    const Vec3 leg1 = normalized(s.points[3]), leg2 = normalized(s.points[4]);
    const Vec3 bisector = normalized(leg1 + leg2);
    int crotch = -1;
    for (std::size_t v = 0; v < raw.points.size(); ++v)
        if (std::abs(norm(raw.points[v]) - 0.223) < 1e-9 &&
            (crotch < 0 || dot(raw.points[v], bisector) > dot(raw.points[static_cast<std::size_t>(crotch)], bisector)))
            crotch = static_cast<int>(v);
    ASSERT_GE(crotch, 0);
    const Vec3 p = raw.points[static_cast<std::size_t>(crotch)];
    EXPECT_NEAR(std::acos(dot(normalized(p), leg1)) * 180 / std::numbers::pi, 19.7, 0.1);
    EXPECT_NEAR(std::acos(dot(normalized(p), leg2)) * 180 / std::numbers::pi, 38.2, 0.1);
    double shortest = 1e9;
    for (const std::array<int, 4>& q : compute_hex_topology(raw).boundary_quads)
        for (std::size_t i = 0; i < 4; ++i)
            if (q[i] == crotch)
                for (const std::size_t j : {(i + 1) % 4, (i + 3) % 4})
                    shortest = std::min(shortest, distance(p, raw.points[static_cast<std::size_t>(q[j])]));
    PaddingOptions unscaled, convex_rule;
    unscaled.concave_scale = 1;
    convex_rule.concave_scale = 3;
    const PaddingResult r1 = pad(raw, unscaled), r3 = pad(raw, convex_rule);
    EXPECT_EQ(pad(raw).mesh, r3.mesh);  // the default: the convex rule everywhere
    ASSERT_EQ(r1.mesh.points.size(), r3.mesh.points.size());
    EXPECT_EQ(compute_quality(r1.mesh).inverted, 0);
    EXPECT_EQ(compute_quality(r3.mesh).inverted, 0);
    int differ = 0;
    for (std::size_t v = static_cast<std::size_t>(r1.first_new_vertex); v < r1.mesh.points.size(); ++v) {
        const int o = r1.origin_vertex[v];
        const Vec3 q = raw.points[static_cast<std::size_t>(o)];
        const double d1 = distance(r1.mesh.points[v], q), d3 = distance(r3.mesh.points[v], q);
        if (o == crotch) {
            EXPECT_NEAR(d1, 0.25 * shortest, 1e-12);
            EXPECT_NEAR(d3 / d1, 1.67, 0.01);
        }
        if (d1 == d3) continue;
        ++differ;
        EXPECT_LT(d1, d3);
        EXPECT_NEAR(norm(q), 0.223, 1e-9);  // on c's sphere
    }
    EXPECT_EQ(differ, 6);
}

// inset_padding (pad_inset.h) over padded boxes whose domain is the box itself: the overshoot of p + t u is the part of
// that segment outside [lo, hi]^3 (all of it when p is on or outside the box).
namespace {

double box_overshoot(const Vec3& lo, const Vec3& hi, const Vec3& p, const Vec3& u, double t) {
    double exit = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        const double x = a == 0 ? p.x : a == 1 ? p.y : p.z, d = a == 0 ? u.x : a == 1 ? u.y : u.z;
        const double l = a == 0 ? lo.x : a == 1 ? lo.y : lo.z, h = a == 0 ? hi.x : a == 1 ? hi.y : hi.z;
        if (!(x > l && x < h)) return t;  // on or outside the box
        if (d > 0) exit = std::min(exit, (h - x) / d);
        if (d < 0) exit = std::min(exit, (l - x) / d);
    }
    return std::max(0.0, t - exit);
}

}  // namespace

// The unit cube padded (thickness 0.25: each corner moves by 0.25 along every axis, offset 0.25 sqrt 3) in the unit
// cube as its domain: the whole layer lies outside, so every raw corner moves 0.25 sqrt 3 inward along its diagonal
// and its padding vertex lands on the raw corner's old place. The padded mesh then fills the cube exactly: inner cube
// [0.25, 0.75]^3 (SJ 1), six frustum hexes whose worst corner frame has two square edges and the unit diagonal,
// SJ 1 / sqrt 3.
TEST(PadInset, CubeFillingItsDomainEndsAtTheSurface) {
    const HexMesh cube = mesohex::test::make_unit_cube();
    PaddingResult p = pad(cube, options(1));
    ASSERT_EQ(p.mesh.hexes.size(), 7u);
    const Vec3 lo{0, 0, 0}, hi{1, 1, 1};
    const PadInsetResult r =
        inset_padding(p.mesh, p.first_new_vertex, p.origin_vertex,
                      [&](const Vec3& q, const Vec3& u, double t) { return box_overshoot(lo, hi, q, u, t); }, {});
    EXPECT_EQ(r.moved_vertices, 8);
    EXPECT_NEAR(r.max_inset, 0.25 * std::sqrt(3.0), 1e-12);
    for (std::size_t v = 0; v < 8; ++v) {
        const Vec3& c = cube.points[v];
        const Vec3 inner{0.25 + 0.5 * c.x, 0.25 + 0.5 * c.y, 0.25 + 0.5 * c.z};
        EXPECT_NEAR(distance(p.mesh.points[v], inner), 0, 1e-12);
        const std::size_t w = 8 + v;  // the padding vertices, numbered in boundary-quad order
        const Vec3& o = p.mesh.points[w];
        EXPECT_NEAR(distance(o, cube.points[static_cast<std::size_t>(p.origin_vertex[w])]), 0, 1e-12);
    }
    const std::vector<double> sj = scaled_jacobians(p.mesh);
    EXPECT_NEAR(sj[0], 1.0, 1e-12);
    for (std::size_t h = 1; h < 7; ++h) EXPECT_NEAR(sj[h], 1 / std::sqrt(3.0), 1e-9) << h;
}

// A slab 1 x 1 x 0.1 padded by 0.2 in the slab as its domain: moving its corners 0.2 sqrt 3 inward would turn the raw
// hex inside out, so the guard halves the moves until no hex is below min(0.2, its SJ before) (the raw hex keeps a
// positive height); kept vertices (and their padding vertices) do not move, nor does anything when nothing overshoots.
TEST(PadInset, GuardKeepsTheRawHexValid) {
    HexMesh slab = mesohex::test::make_unit_cube();
    for (Vec3& q : slab.points) q.z *= 0.1;
    PaddingOptions o = options(1);
    o.absolute_thickness = 0.2;
    const PaddingResult padded = pad(slab, o);
    const std::vector<double> before = scaled_jacobians(padded.mesh);
    const Vec3 lo{0, 0, 0}, hi{1, 1, 0.1};
    auto overshoot = [&](const Vec3& q, const Vec3& u, double t) { return box_overshoot(lo, hi, q, u, t); };

    PaddingResult p = padded;
    const PadInsetResult r = inset_padding(p.mesh, p.first_new_vertex, p.origin_vertex, overshoot, {});
    const std::vector<double> after = scaled_jacobians(p.mesh);
    for (std::size_t h = 0; h < after.size(); ++h) EXPECT_GE(after[h], std::min(0.2, before[h])) << h;
    EXPECT_GT(after[0], 0);
    const double full = distance(padded.mesh.points[8], padded.mesh.points[0]);  // every corner's offset
    EXPECT_LT(r.max_inset, 0.5 * full);
    EXPECT_GT(r.moved_vertices, 0);

    std::vector<char> keep(8, 0);
    keep[0] = 1;
    PaddingResult k = padded;
    inset_padding(k.mesh, k.first_new_vertex, k.origin_vertex, overshoot, keep);
    EXPECT_EQ(k.mesh.points[0], padded.mesh.points[0]);
    for (std::size_t w = 8; w < k.mesh.points.size(); ++w)
        if (k.origin_vertex[w] == 0) {
            EXPECT_EQ(k.mesh.points[w], padded.mesh.points[w]);
        }

    PaddingResult z = padded;
    const PadInsetResult none = inset_padding(z.mesh, z.first_new_vertex, z.origin_vertex,
                                              [](const Vec3&, const Vec3&, double) { return 0.0; }, {});
    EXPECT_EQ(none.moved_vertices, 0);
    EXPECT_EQ(z.mesh.points, padded.mesh.points);
}

// PadInsetOptions::concave_only on the dimple above (the 2 x 2 x 1 block, the centre of its top face lowered to
// z = 0.5), with every padding vertex wholly outside the domain (overshoot t: a raw mesh lying on its domain's surface,
// as the random set's skeletons give). Every boundary vertex overshoots; only the dimple's centre is concave, so only
// it (with its padding vertex) moves, straight down by its whole offset 0.25 sqrt(1.25) sqrt(4.5) / 2 = 0.296464 (the
// raw hexes beneath keep SJ >= 0.6: no halving); without concave_only more vertices move.
TEST(PadInset, ConcaveOnlyMovesTheDimpleAlone) {
    HexMesh m = make_block(2, 2, 1);
    int centre = -1;
    for (std::size_t v = 0; v < m.points.size(); ++v)
        if (m.points[v] == Vec3{1, 1, 1}) centre = static_cast<int>(v);
    ASSERT_GE(centre, 0);
    m.points[static_cast<std::size_t>(centre)].z = 0.5;
    const PaddingResult padded = pad(m, PaddingOptions{});
    const std::vector<double> before = scaled_jacobians(padded.mesh);
    auto all_outside = [](const Vec3&, const Vec3&, double t) { return t; };
    PadInsetOptions o;
    o.concave_only = true;
    PaddingResult p = padded;
    const PadInsetResult r = inset_padding(p.mesh, p.first_new_vertex, p.origin_vertex, all_outside, {}, o);
    EXPECT_EQ(r.moved_vertices, 1);
    const double offset = 0.25 * std::sqrt(1.25 * 4.5) / 2;
    EXPECT_NEAR(r.max_inset, offset, 1e-9);
    for (std::size_t v = 0; v < m.points.size(); ++v) {
        const Vec3 want = static_cast<int>(v) == centre ? Vec3{1, 1, 0.5 - offset} : m.points[v];
        EXPECT_NEAR(distance(p.mesh.points[v], want), 0, 1e-9) << v;
    }
    const std::vector<double> after = scaled_jacobians(p.mesh);
    for (std::size_t h = 0; h < after.size(); ++h) EXPECT_GE(after[h], std::min(0.2, before[h])) << h;
    PaddingResult every = padded;
    EXPECT_GT(inset_padding(every.mesh, every.first_new_vertex, every.origin_vertex, all_outside, {}).moved_vertices,
              1);
}

namespace {

// The L of three unit cubes: the 2 x 1 x 2 block without its cube at (1, 0, 1) (hex index i + 2 k).
HexMesh make_l_of_three_cubes() {
    HexMesh l = make_block(2, 1, 2);
    l.hexes.erase(l.hexes.begin() + 3);
    return l;
}

// The smallest scaled Jacobian of the padding's new hexes.
double worst_new_hex(const PaddingResult& r) {
    double lo = 1;
    for (std::size_t h = static_cast<std::size_t>(r.first_new_hex); h < r.mesh.hexes.size(); ++h)
        lo = std::min(lo, scaled_jacobian(mesohex::test::corners_of(r.mesh, static_cast<int>(h))));
    return lo;
}

}  // namespace

// PaddingOptions::corner_guard on an L of three unit cubes (the 2 x 1 x 2 block without its cube at (1, 0, 1)). At
// the two ends of the concave edge, (1, 0, 1) and (1, 1, 1), five quads meet: three on the side face (normal -y or
// +y), the floor (+z) and the wall (+x). Their mean normal (1, -+3, 1) / sqrt 11 leaves the new hexes on the floor and
// the wall a bottom corner of 1 / sqrt 11 = 0.3015 (the quads' corners are right angles: the value is the cosine to
// the corner's normal). The direction that maximises the worst corner is (1, -+1, 1) / sqrt 3 (0.577); with the guard
// at 0.5 the direction turns from the mean normal just far enough: (1, -+sqrt 2, 1) / 2, whose cosine to +x and +z is
// 0.5. Every other boundary vertex is flat (1), on a convex edge (0.707) or a convex corner (0.577): untouched. So
// every bottom corner of the layer is at least 0.5, and every new hex at least 0.25 (half of min(guard, its bottom
// corners): the thickness guard).
TEST(Padding, CornerGuardTurnsTheDirectionAtAConcaveEdgeEnd) {
    const HexMesh l = make_l_of_three_cubes();
    auto worst_bottom_corner = [&](const PaddingResult& r) {
        double lo = 1;
        for (std::size_t h = static_cast<std::size_t>(r.first_new_hex); h < r.mesh.hexes.size(); ++h)
            for (std::size_t lv = 0; lv < 4; ++lv)
                lo = std::min(lo, hex_corner_value(mesohex::test::corners_of(r.mesh, static_cast<int>(h)), lv));
        return lo;
    };
    const PaddingResult plain = pad(l);
    EXPECT_NEAR(worst_bottom_corner(plain), 1 / std::sqrt(11.0), 1e-12);
    EXPECT_LE(worst_new_hex(plain), 1 / std::sqrt(11.0) + 1e-12);
    PaddingOptions o;
    o.corner_guard = 0.5;
    const PaddingResult guarded = pad(l, o);
    EXPECT_NEAR(worst_bottom_corner(guarded), 0.5, 1e-8);
    EXPECT_GE(worst_new_hex(guarded), 0.25);
    EXPECT_EQ(compute_quality(guarded.mesh).inverted, 0);
    int turned = 0;
    for (std::size_t v = static_cast<std::size_t>(guarded.first_new_vertex); v < guarded.mesh.points.size(); ++v) {
        const Vec3& p = l.points[static_cast<std::size_t>(guarded.origin_vertex[v])];
        const Vec3 d = normalized(guarded.mesh.points[v] - p);
        const Vec3 d0 = normalized(plain.mesh.points[v] - p);
        if (!(p.x == 1 && p.z == 1)) {
            EXPECT_NEAR(distance(d, d0), 0, 1e-12);  // the same direction as without the guard
            continue;
        }
        ++turned;
        const double side = p.y == 0 ? -1 : 1;
        EXPECT_NEAR(distance(d0, Vec3{1, 3 * side, 1} / std::sqrt(11.0)), 0, 1e-12);
        EXPECT_NEAR(distance(d, Vec3{0.5, side * std::sqrt(0.5), 0.5}), 0, 1e-7);
    }
    EXPECT_EQ(turned, 2);
}

// The thickness guard where directions converge: the narrow slot of NarrowSlotDoesNotInvert (0.2 wide) under a layer
// of 0.5 x the shortest edge. The slot's floor corners lean towards each other across it (their mean normals take in
// the walls), so the new vertices over the floor slide towards the other wall and the floor's new hexes skew: the
// worst is 0.139, below half of min(0.3, its worst bottom corner). Every bottom corner is at least 1 / sqrt 11 =
// 0.3015 (the slot's ends, as the L's concave edge ends in CornerGuardTurnsTheDirectionAtAConcaveEdgeEnd), so a guard
// of 0.3 turns no direction; it only shrinks the offsets of the skewed hexes' vertices together (x 0.7 per round)
// until every new hex is at least half of min(0.3, its worst bottom corner). The other new vertices stay.
TEST(Padding, CornerGuardThinsTheLayerWhereDirectionsConverge) {
    const HexMesh u = make_narrow_slot();
    // The smallest ratio of a new hex's scaled Jacobian to min(0.3, its worst bottom corner), and that corner.
    auto worst_ratio = [&](const PaddingResult& r, double& bottom_min) {
        double ratio = 1e9;
        bottom_min = 1;
        for (std::size_t h = static_cast<std::size_t>(r.first_new_hex); h < r.mesh.hexes.size(); ++h) {
            const std::array<Vec3, 8> c = mesohex::test::corners_of(r.mesh, static_cast<int>(h));
            double bottom = 1;
            for (std::size_t lv = 0; lv < 4; ++lv) bottom = std::min(bottom, hex_corner_value(c, lv));
            bottom_min = std::min(bottom_min, bottom);
            ratio = std::min(ratio, scaled_jacobian(c) / std::min(0.3, bottom));
        }
        return ratio;
    };
    PaddingOptions o;
    o.thickness = 0.5;
    const PaddingResult plain = pad(u, o);
    o.corner_guard = 0.3;
    const PaddingResult guarded = pad(u, o);
    double bottom_plain = 0, bottom_guarded = 0;
    EXPECT_LT(worst_ratio(plain, bottom_plain), 0.47);
    EXPECT_GE(worst_ratio(guarded, bottom_guarded), 0.5);
    EXPECT_NEAR(bottom_plain, 1 / std::sqrt(11.0), 1e-12);
    EXPECT_NEAR(bottom_guarded, 1 / std::sqrt(11.0), 1e-12);
    EXPECT_EQ(compute_quality(guarded.mesh).inverted, 0);
    int shrunk = 0;
    for (std::size_t v = static_cast<std::size_t>(guarded.first_new_vertex); v < guarded.mesh.points.size(); ++v) {
        const Vec3& p = u.points[static_cast<std::size_t>(guarded.origin_vertex[v])];
        const Vec3 a = guarded.mesh.points[v] - p, b = plain.mesh.points[v] - p;
        EXPECT_NEAR(distance(normalized(a), normalized(b)), 0, 1e-12);  // no direction turned
        EXPECT_LE(norm(a), norm(b) + 1e-15);
        if (norm(a) < norm(b)) ++shrunk;
    }
    EXPECT_GT(shrunk, 0);
}

// PaddingOptions::search_cos on the L of CornerGuardTurnsTheDirectionAtAConcaveEdgeEnd: only the two ends of the
// concave edge leave a quad corner's normal below 0.5 (1 / sqrt 11 = 0.3015 to the floor's and the wall's; a convex
// corner leaves 1 / sqrt 3, an edge 1 / sqrt 2). There the direction is one of the five on the great circle from the
// mean normal (1, -+3, 1) / sqrt 11 to the narrowest cone's axis (1, -+1, 1) / sqrt 3, chosen for the worst new hex
// around the vertex: here the axis itself (the last candidate), whose cosine to every corner is 1 / sqrt 3. Every
// other new vertex stays where it was; the worst new hex of the layer goes from below 1 / sqrt 11 (the floor's and the
// wall's bottom corner) to above 0.5 (at most 1 / sqrt 3, the new bottom corners).
TEST(Padding, SearchTurnsTheDirectionAtAConcaveEdgeEndOnly) {
    const HexMesh l = make_l_of_three_cubes();
    const PaddingResult plain = pad(l);
    PaddingOptions o;
    o.search_cos = 0.5;
    const PaddingResult searched = pad(l, o);
    EXPECT_LE(worst_new_hex(plain), 1 / std::sqrt(11.0) + 1e-12);
    EXPECT_GT(worst_new_hex(searched), 0.5);
    EXPECT_LE(worst_new_hex(searched), 1 / std::sqrt(3.0) + 1e-12);
    int turned = 0;
    for (std::size_t v = static_cast<std::size_t>(searched.first_new_vertex); v < searched.mesh.points.size(); ++v) {
        const Vec3& p = l.points[static_cast<std::size_t>(searched.origin_vertex[v])];
        const Vec3 d = normalized(searched.mesh.points[v] - p);
        const Vec3 d0 = normalized(plain.mesh.points[v] - p);
        if (!(p.x == 1 && p.z == 1)) {
            EXPECT_EQ(distance(searched.mesh.points[v], plain.mesh.points[v]), 0);
            continue;
        }
        ++turned;
        const double side = p.y == 0 ? -1 : 1;
        EXPECT_NEAR(distance(d0, Vec3{1, 3 * side, 1} / std::sqrt(11.0)), 0, 1e-12);
        EXPECT_NEAR(distance(d, Vec3{1, side, 1} / std::sqrt(3.0)), 0, 1e-12);
    }
    EXPECT_EQ(turned, 2);
    EXPECT_EQ(compute_quality(searched.mesh).inverted, 0);
}

// maximin_direction: for three orthonormal vectors the cone axis (1, 1, 1) / sqrt 3 (each dot 1 / sqrt 3); for (0, 0,
// 1) and (0.5, 0, 0) (a right-angled corner next to one of sine 0.5) the direction where both dots are equal, m_z = 0.5
// m_x: (2, 0, 1) / sqrt 5, value 1 / sqrt 5; neither vector's own direction does better than 0.
TEST(Padding, MaximinDirectionOfCornerVectors) {
    const std::vector<Vec3> axes{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const Vec3 a = maximin_direction(axes, Vec3{1, 0, 0});
    EXPECT_NEAR(distance(a, Vec3{1, 1, 1} / std::sqrt(3.0)), 0, 1e-12);
    EXPECT_NEAR(lowest_corner(axes, a), 1 / std::sqrt(3.0), 1e-12);
    const std::vector<Vec3> uneven{{0, 0, 1}, {0.5, 0, 0}};
    const Vec3 b = maximin_direction(uneven, Vec3{0, 0, 1});
    EXPECT_NEAR(distance(b, Vec3{2, 0, 1} / std::sqrt(5.0)), 0, 1e-12);
    EXPECT_NEAR(lowest_corner(uneven, b), 1 / std::sqrt(5.0), 1e-12);
    EXPECT_EQ(lowest_corner(uneven, Vec3{0, 0, 1}), 0.0);
}

// narrower_cone_axis (core/cone.h): the flange's outs at a fan end, -y (the plate's) and -x twice (the walls'), from
// d = -x (widest angle 90 degrees) -> the axis (-1, -1, 0) / sqrt 2 (45 degrees); the gap above the flange's plate,
// normals z, z and y from their unit sum (2z + y) / sqrt 5 (widest acos(1 / sqrt 5) = 63.4 degrees) -> (0, 1, 1) /
// sqrt 2 (45). Two unit vectors 8 degrees apart from one of them: the axis halves the widest angle, a gain of 4 <= 5
// degrees keeps d; 12 degrees apart gains 6 and takes the axis. No vectors: d, widest angle 0.
TEST(Padding, NarrowerConeAxisOnlyWhenItGainsMoreThanTheThreshold) {
    const double pi = std::numbers::pi;
    const Vec3 flange = narrower_cone_axis({{0, -1, 0}, {-1, 0, 0}, {-1, 0, 0}}, Vec3{-1, 0, 0}, 5.0);
    EXPECT_NEAR(distance(flange, Vec3{-1, -1, 0} / std::sqrt(2.0)), 0, 1e-12);
    const std::vector<Vec3> gap{{0, 0, 1}, {0, 0, 1}, {0, 1, 0}};
    const Vec3 sum = Vec3{0, 1, 2} / std::sqrt(5.0);
    EXPECT_NEAR(widest_angle_deg(gap, sum), std::acos(1 / std::sqrt(5.0)) * 180 / pi, 1e-9);
    EXPECT_NEAR(distance(narrower_cone_axis(gap, sum, 5.0), Vec3{0, 1, 1} / std::sqrt(2.0)), 0, 1e-12);
    const Vec3 x{1, 0, 0};
    for (double deg : {8.0, 12.0}) {
        const std::vector<Vec3> two{x, {std::cos(deg * pi / 180), std::sin(deg * pi / 180), 0}};
        const Vec3 m = narrower_cone_axis(two, x, 5.0);
        EXPECT_NEAR(widest_angle_deg(two, m), deg > 10 ? deg / 2 : deg, 1e-9) << deg;
        if (deg < 10) {
            EXPECT_EQ(m, x);
        }
    }
    EXPECT_EQ(narrower_cone_axis({}, x, 5.0), x);
    EXPECT_EQ(widest_angle_deg({}, x), 0.0);
}
