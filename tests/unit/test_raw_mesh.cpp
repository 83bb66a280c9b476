// Raw mesh (paper steps 5-7): exact counts, validity, Euler characteristic, predicted irregular edges == measured,
// determinism across thread counts.
#include <gtest/gtest.h>

#include "skeleton_fixtures.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include <tbb/global_control.h>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/topology.h"
#include "mesohex/core/validate.h"
#include "mesohex/post/crease_wedge.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/adaptation.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/raw_mesh.h"
#include "mesohex/stages/sphere_partition.h"
#include "raw_run.h"

using namespace mesohex;

namespace {

struct Built {
    SkeletonAnalysis an;
    ConnectionSurfaces cs;
    RawMeshPrediction prediction;
    RawMesh raw;
};

// fan_blocks = false: the paper's gap vertices on every fan edge (the default puts fan blocks where accepted).
Built build(Skeleton s, double radius, bool fan_blocks = true) {
    if (s.radii.empty()) s.radii.assign(s.points.size(), radius);
    Built b;
    b.an = analyze_skeleton(s);
    ConnectionSurfaceOptions co;
    co.blocks.fan_blocks = fan_blocks;
    b.cs = build_connection_surfaces(s, b.an, co);
    b.prediction = predict_raw_mesh(s, b.an, b.cs);
    const BranchFrames fr = propagate_frames(s, b.an, b.cs);
    b.raw = build_raw_mesh(s, b.an, b.cs, fr);
    return b;
}

// Everything the issue asks of a raw mesh of a curve skeleton.
void expect_good_raw_mesh(const Skeleton& s, const Built& b, bool expect_no_inverted = true) {
    const HexMesh& m = b.raw.mesh;
    EXPECT_EQ(static_cast<long>(m.hexes.size()), 4 * static_cast<long>(s.edges.size()));
    EXPECT_EQ(static_cast<long>(m.hexes.size()), b.prediction.hexes);
    EXPECT_EQ(static_cast<long>(m.points.size()), b.prediction.vertices);
    for (const Vec3& p : m.points) EXPECT_TRUE(is_finite(p));
    const ValidationReport vr = validate(m);
    EXPECT_TRUE(vr.valid()) << (vr.problems.empty() ? std::string() : vr.problems.front().message);
    const QualityReport q = compute_quality(m);
    EXPECT_EQ(q.euler_characteristic, euler_characteristic(s) - b.an.counts.isolated);
    EXPECT_EQ(q.singular_interior_edges, (std::map<int, long>(b.prediction.interior_irregular_edges.begin(),
                                                              b.prediction.interior_irregular_edges.end())));
    EXPECT_EQ(q.singular_boundary_edges, (std::map<int, long>(b.prediction.boundary_irregular_edges.begin(),
                                                              b.prediction.boundary_irregular_edges.end())));
    if (expect_no_inverted) {
        EXPECT_EQ(q.inverted, 0);
        EXPECT_GT(q.sj_min, 0.0);
    }
}

Skeleton star(const std::vector<Vec3>& dirs, int edges_per_arm, double arm_length) {
    Skeleton s;
    s.points.push_back({0, 0, 0});
    for (const Vec3& d : dirs) {
        int prev = 0;
        for (int k = 1; k <= edges_per_arm; ++k) {
            s.points.push_back(d * (arm_length * k / edges_per_arm));
            const int cur = static_cast<int>(s.points.size()) - 1;
            s.edges.push_back({prev, cur});
            prev = cur;
        }
    }
    return s;
}

Skeleton ring(int n) {
    Skeleton s;
    for (int i = 0; i < n; ++i) s.points.push_back({std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0});
    for (int i = 0; i < n; ++i) s.edges.push_back({i, (i + 1) % n});
    return s;
}

using mesohex::test::cube_surface;
using mesohex::test::plate;
using mesohex::test::plate_with_wall;
using mesohex::test::plate_with_walls;
using mesohex::test::random_directions;

// Leaflet meshes: hexes = 2 per face + 2 per boundary edge (+ 4 per fan edge and per cap of a fan block,
// docs/blocks.md), valid, Euler characteristic of the skeleton, predicted irregular edges == measured, no inverted hex.
void expect_good_leaflet_mesh(const Skeleton& s, const Built& b, long hexes) {
    const HexMesh& m = b.raw.mesh;
    EXPECT_EQ(static_cast<long>(m.hexes.size()), hexes + 4 * (b.prediction.fan_blocks + b.prediction.fan_block_caps));
    EXPECT_EQ(static_cast<long>(m.hexes.size()), b.prediction.hexes);
    EXPECT_EQ(static_cast<long>(m.points.size()), b.prediction.vertices);
    const QualityReport q = compute_quality(m);
    EXPECT_TRUE(q.validation.valid()) << (q.validation.problems.empty() ? "" : q.validation.problems[0].message);
    EXPECT_EQ(q.euler_characteristic, euler_characteristic(s));
    EXPECT_EQ(q.singular_interior_edges, b.prediction.interior_irregular_edges);
    EXPECT_EQ(q.singular_boundary_edges, b.prediction.boundary_irregular_edges);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_GT(q.sj_min, 0.0);
    static int n_recorded = 0;
    ::testing::Test::RecordProperty("sj_min_" + std::to_string(n_recorded++), std::to_string(q.sj_min));
}

// The fat Y of the degree-3 partition tests: branches at azimuths 0, 100 and 220 degrees, the 100-degree one 10
// degrees below the plane z = 0, the others 10 degrees above (beyond planarity_tolerance; no gap over 180 degrees).
std::vector<Vec3> tilted_y_directions() {
    const double e = 10 * std::numbers::pi / 180;
    std::vector<Vec3> dirs;
    for (const double az : {0.0, 100.0, 220.0}) {
        const double a = az * std::numbers::pi / 180;
        dirs.push_back(
            {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), az == 100.0 ? -std::sin(e) : std::sin(e)});
    }
    return dirs;
}

// Smallest angle (degrees) between a valence-3 point of branching point c's surface and one of dirs.
double pole_to_branch_deg(const ConnectionSurfaces& cs, const BranchFrames& fr, int c, const std::vector<Vec3>& dirs) {
    double best = 180;
    for (int x = cs.point_begin[c]; x < cs.point_begin[c + 1]; ++x)
        if (cs.point_valence[x] == 3)
            for (const Vec3& d : dirs)
                best =
                    std::min(best, std::acos(std::clamp(dot(fr.directions[x], d), -1.0, 1.0)) * 180 / std::numbers::pi);
    return best;
}

}  // namespace

TEST(RawMeshLeaflets, OneQuadIsOnePlateAndFourHalfChunks) {
    const Skeleton s = plate(1, 1);
    const Built b = build(s, 0.25);
    expect_good_leaflet_mesh(s, b, 10);
    EXPECT_EQ(b.raw.mesh.points.size(), 24u);  // 4 boundary vertices x 6
    // A free 90-degree corner with one face: up and down edges of valence 1 + 2 = 3.
    EXPECT_EQ(b.prediction.interior_irregular_edges, (std::map<int, long>{{3, 8}}));
}

TEST(RawMeshLeaflets, ThreeByThreePlate) {
    const Skeleton s = plate(3, 3);
    const Built b = build(s, 0.25);
    expect_good_leaflet_mesh(s, b, 42);
    EXPECT_EQ(b.raw.mesh.points.size(), 4u * 3 + 12 * 6);
}

TEST(RawMeshLeaflets, ClosedCubeSurfaceIsAShell) {
    const Skeleton s = cube_surface(false);
    ASSERT_EQ(s.points.size(), 26u);
    const Built b = build(s, 0.25);
    expect_good_leaflet_mesh(s, b, 48);
    const QualityReport q = compute_quality(b.raw.mesh);
    EXPECT_EQ(q.euler_characteristic, 2);
    EXPECT_EQ(q.boundary_components, 2);
    // 8 cube corners with 3 faces: their up and down edges have 3 hexes.
    EXPECT_EQ(b.prediction.interior_irregular_edges, (std::map<int, long>{{3, 16}}));
}

TEST(RawMeshLeaflets, CurvesAndLeafletsInOneSkeleton) {
    Skeleton s = plate(2, 1);
    const int base = static_cast<int>(s.points.size());
    s.points.push_back({0, 5, 0});
    s.points.push_back({1, 5, 0});
    s.points.push_back({2, 5, 0.5});
    s.edges.push_back({base, base + 1});
    s.edges.push_back({base + 1, base + 2});
    const Built b = build(s, 0.25);
    expect_good_leaflet_mesh(s, b, 2 * 2 + 2 * 6 + 4 * 2);
}

TEST(RawMeshLeaflets, PlateWithABranchAtACornerIsABLJoint) {
    // 3 x 3 plate (42 hexes) + a 3-edge branch leaving corner 0 along the outward diagonal (12 hexes) = 54.
    Skeleton s = plate(3, 3);
    int prev = 0;
    for (int k = 1; k <= 3; ++k) {
        s.points.push_back({-0.7 * k, -0.7 * k, 0});
        const int cur = static_cast<int>(s.points.size()) - 1;
        s.edges.push_back({prev, cur});
        prev = cur;
    }
    const Built b = build(s, 0.25);
    EXPECT_EQ(b.an.vertex_class[0], VertexClass::BLJoint);
    expect_good_leaflet_mesh(s, b, 54);
    // The corner has one face: its up and down rays have 2 + 2 + 1 = 5 hexes.
    EXPECT_EQ(b.prediction.interior_irregular_edges.at(5), 2);
}

// Strips of n x m unit quads sharing the fan edge chain (0,0,0)..(n,0,0); strip s extends along dirs[s]. Strip s
// is listed with the orientation sign flips[s] (the analysis orients each leaflet from its first face).
Skeleton fan(int n, int m, const std::vector<Vec3>& dirs, const std::vector<bool>& flips) {
    Skeleton s;
    for (int i = 0; i <= n; ++i) s.points.push_back({double(i), 0, 0});
    for (std::size_t l = 0; l < dirs.size(); ++l) {
        const int b = static_cast<int>(s.points.size());
        for (int j = 1; j <= m; ++j)
            for (int i = 0; i <= n; ++i) s.points.push_back(Vec3{double(i), 0, 0} + double(j) * dirs[l]);
        auto id = [&](int i, int j) { return j == 0 ? i : b + (j - 1) * (n + 1) + i; };
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < n; ++i) {
                std::vector<int> f{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
                if (flips[l]) std::reverse(f.begin(), f.end());
                s.faces.push_back(f);
            }
    }
    add_face_edges(s);
    return s;
}

TEST(RawMeshLeaflets, TFanOfThreeThreeByTwoStrips) {
    // The paper's layout: 18 faces (36 plate hexes) + 3 x 7 boundary edges (42 half-chunk hexes) = 78.
    const Skeleton s = fan(3, 2, {{0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, {false, true, false});
    const Built b = build(s, 0.25, false);
    EXPECT_EQ(b.an.counts.fan_edges, 3);
    EXPECT_EQ(b.an.counts.fan_edge_ends, 2);
    EXPECT_EQ(b.an.counts.fan_edge_vertices, 2);
    expect_good_leaflet_mesh(s, b, 78);
    // Per strip 2 interior (3 ids) + 6 boundary (6 ids) leaflet vertices; fan-edge vertices 1 + 3, fan ends 2 + 6.
    EXPECT_EQ(b.raw.mesh.points.size(), 3u * (2 * 3 + 6 * 6) + 2 * 4 + 2 * 8);
    // 3 fan edges and 2 fan-end extension edges with 6 hexes; 2 free corners per strip (up and down edges, 3 hexes).
    EXPECT_EQ(b.prediction.interior_irregular_edges, (std::map<int, long>{{3, 12}, {6, 5}}));
}

TEST(RawMeshLeaflets, ObliqueFanOfThreeStrips) {
    // Strips at 0, 60 and 200 degrees about the fan edge, mixed orientations: 3 x 2 faces + 3 x 4 boundary edges.
    const double a = std::numbers::pi / 3, c = 200 * std::numbers::pi / 180;
    const Skeleton s =
        fan(2, 1, {{0, 1, 0}, {0, std::cos(a), std::sin(a)}, {0, std::cos(c), std::sin(c)}}, {true, false, true});
    const Built b = build(s, 0.25);
    expect_good_leaflet_mesh(s, b, 2 * 6 + 2 * 12);
}

TEST(RawMeshLeaflets, GeneratedTAndXFans) {
    for (const auto& [name, hexes] : {std::pair<std::string, long>{"tfan", 60}, {"xfan", 80}}) {
        SCOPED_TRACE(name);
        const Skeleton s = generate_skeleton(name, {});
        const Built b = build(s, 0.0);
        EXPECT_GT(b.an.counts.fan_edges, 0);
        expect_good_leaflet_mesh(s, b, hexes);
    }
}

// Two 2 x 2 plates of unit quads touching only at the origin (an LL-joint): plate A = [0,2]^2 in z = 0, plate B
// spanned by the unit vectors bu, bw from the origin; flip reverses B's faces (opposite orientation).
Skeleton ll_joint(const Vec3& bu, const Vec3& bw, bool flip) {
    Skeleton s = plate(2, 2);  // vertex 0 is the origin
    const int base = static_cast<int>(s.points.size());
    auto id = [&](int i, int j) { return i == 0 && j == 0 ? 0 : base + j * 3 + i - 1; };
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i)
            if (i != 0 || j != 0) s.points.push_back(double(i) * bu + double(j) * bw);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            std::vector<int> f{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
            if (flip) std::reverse(f.begin(), f.end());
            s.faces.push_back(f);
        }
    s.edges.clear();
    add_face_edges(s);
    return s;
}

TEST(RawMeshLeaflets, LLJointsSameOppositeAndPerpendicular) {
    const std::vector<std::pair<Vec3, Vec3>> placements = {
        {{-1, 0, 0}, {0, -1, 0}},  // coplanar, diagonal
        {{-1, 0, 0}, {0, 0, 1}},   // perpendicular (plane y = 0)
        {{0, -1, 0}, {0, 0, -1}},  // perpendicular (plane x = 0)
    };
    for (const auto& [bu, bw] : placements)
        for (bool flip : {false, true}) {
            SCOPED_TRACE(std::to_string(bu.x) + " " + std::to_string(bu.y) + " " + std::to_string(bw.z) +
                         (flip ? " flipped" : ""));
            const Skeleton s = ll_joint(bu, bw, flip);
            const Built b = build(s, 0.25);
            ASSERT_EQ(b.an.vertex_class[0], VertexClass::LLJoint);
            // 2 x (4 faces x 2 + 8 boundary edges x 2) = 48; 2 x 8 leaflet vertices + the 9-vertex pillow.
            expect_good_leaflet_mesh(s, b, 48);
            EXPECT_EQ(b.raw.mesh.points.size(), 2u * (1 * 3 + 7 * 6) + 9);
        }
}

TEST(RawMeshLeaflets, PlateCornerWithTwoBranchesIsABranchingPoint) {
    // 3 x 3 plate (42 hexes) + two 3-edge branches at corner 0 (12 each): in-plane diagonal and perpendicular.
    for (const Vec3& d2 : {Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
        Skeleton s = plate(3, 3);
        for (const Vec3& d : {Vec3{-0.7, -0.7, 0}, d2}) {
            int prev = 0;
            for (int k = 1; k <= 3; ++k) {
                s.points.push_back(double(k) * d);
                const int cur = static_cast<int>(s.points.size()) - 1;
                s.edges.push_back({prev, cur});
                prev = cur;
            }
        }
        const Built b = build(s, 0.25);
        EXPECT_EQ(b.an.vertex_class[0], VertexClass::BranchingPoint);
        expect_good_leaflet_mesh(s, b, 66);
    }
}

TEST(RawMeshLeaflets, GeneratedShapesWithFanEdgesAndJunctions) {
    // chair: fan edges + BL-joints; torustwist: 24 fan edges (two crossing strips).
    for (const std::string name : {"chair", "torustwist"}) {
        SCOPED_TRACE(name);
        const Skeleton s = generate_skeleton(name, {});
        const Built b = build(s, 0.0);
        EXPECT_GT(b.an.counts.fan_edges, 0);
        expect_good_leaflet_mesh(s, b, b.an.predicted_hexes);
    }
}

TEST(RawMeshLeaflets, GeneratedHandBirdAndTurbineHaveNoInvertedHex) {
    // bird and turbine (branching points mixing branches and leaflets) and hand (BL-joints on a zigzag border): their
    // junction surfaces are relaxed on a model of the leaflet hexes (connection_surfaces.cpp), and leaflet border
    // vertices push their out vertex along the bisector of the exterior angle (right at the hand's reflex vertices).
    for (const std::string name : {"bird", "turbine", "hand"}) {
        SCOPED_TRACE(name);
        const Skeleton s = generate_skeleton(name, {});
        const Built b = build(s, 0.0);
        expect_good_leaflet_mesh(s, b, b.an.predicted_hexes);
    }
}

TEST(RawMeshLeaflets, PerpendicularBranchAtAPlateCorner) {
    // 3 x 3 plate + a 3-edge branch leaving corner 0 perpendicular to the plate (either side): 42 + 12 = 54. The
    // BL-joint pillow is tilted between the leaflet and the reversed branch, then relaxed.
    for (const double z : {1.0, -1.0}) {
        Skeleton s = plate(3, 3);
        int prev = 0;
        for (int k = 1; k <= 3; ++k) {
            s.points.push_back({0, 0, z * k});
            const int cur = static_cast<int>(s.points.size()) - 1;
            s.edges.push_back({prev, cur});
            prev = cur;
        }
        const Built b = build(s, 0.25);
        EXPECT_EQ(b.an.vertex_class[0], VertexClass::BLJoint);
        expect_good_leaflet_mesh(s, b, 54);
    }
}

// Beyond the paper's limitation 1: a branch rooted at the interior vertex 4 of a 2 x 2 plate (4 faces meet there).
// Hexes: 4 faces x 2 plates + 8 boundary edges x 2 half-chunks + 2 branch edges x 4 = 32. Vertices: 8 boundary
// vertices x 6 + the interior vertex's 3 + 9 at the joint + 9 at the extremity = 69: the first chunk stands on the
// plates' 2 x 2 patch on the branch's side and adds no vertex there. The patch's 8 outer edges get a third hex.
TEST(RawMeshLeaflets, BranchRootedInsideAPlateStandsOnItsPlates) {
    for (const double z : {1.0, -1.0}) {
        SCOPED_TRACE(z);
        Skeleton s = plate(2, 2);
        s.points.push_back({1, 1, z});
        s.points.push_back({1, 1, 2 * z});
        s.edges.push_back({4, 9});
        s.edges.push_back({9, 10});
        const Built b = build(s, 0.25);
        EXPECT_EQ(b.an.vertex_class[4], VertexClass::LeafletInterior);
        EXPECT_EQ(b.an.vertex_branch_edges[4], 1);
        expect_good_leaflet_mesh(s, b, 32);
        EXPECT_EQ(b.raw.mesh.points.size(), 69u);
        EXPECT_EQ(b.prediction.boundary_irregular_edges, (std::map<int, long>{{1, 8 + 8 + 16}, {3, 8}}));
        // The first chunk's 4 hexes (slots 0-3, edge 0 = 4-9) share the up (z > 0) or down vertex of 4, and each
        // has one face on a plate hex: its 4 root corners are the plate's corners on that side.
        const int centre = b.raw.vertex_base[4] + (z > 0 ? 1 : 2);
        for (int k = 0; k < 4; ++k) {
            const std::array<int, 8>& h = b.raw.mesh.hexes[k];
            EXPECT_EQ(h[0], centre);
            for (int c = 0; c < 4; ++c) EXPECT_NEAR(b.raw.mesh.points[h[c]].z, 0.25 * z, 1e-12);
        }
        const QualityReport q = compute_quality(b.raw.mesh);
        EXPECT_EQ(q.boundary_components, 1);
    }
}

// An arch rooted at two interior vertices of a 6 x 4 plate (cup.ma's handle): one handle, Euler characteristic 0.
// Hexes: 24 faces x 2 + 20 boundary edges x 2 + 6 branch edges x 4 = 112.
TEST(RawMeshLeaflets, ArchRootedAtTwoInteriorVerticesMakesAHandle) {
    Skeleton s = plate(6, 4);
    const int a = 2 * 7 + 1, c = 2 * 7 + 5, base = static_cast<int>(s.points.size());
    for (const Vec3& p : std::vector<Vec3>{{1, 2, 1}, {2, 2, 1.8}, {3, 2, 2}, {4, 2, 1.8}, {5, 2, 1}})
        s.points.push_back(p);
    s.edges.push_back({a, base});
    for (int k = 0; k < 4; ++k) s.edges.push_back({base + k, base + k + 1});
    s.edges.push_back({base + 4, c});
    const Built b = build(s, 0.3);
    expect_good_leaflet_mesh(s, b, 112);
    const QualityReport q = compute_quality(b.raw.mesh);
    EXPECT_EQ(q.euler_characteristic, 0);
    EXPECT_EQ(q.boundary_components, 1);
    EXPECT_EQ(q.boundary_euler_characteristic, 0);  // a torus
}

// A 2 x 2 plate with a 2-edge branch leaving the middle vertex 1 = (1, 0, 0) of its straight border y = 0 towards
// `to`: 32 hexes (8 plates + 16 half-chunks + 8 chunk hexes) and 8 x 6 + 3 + 9 + 9 = 69 vertices, as for a branch
// rooted inside; the branch stands on 4 half-chunk faces (Out) or on 2 plate and 2 half-chunk faces (Side).
Skeleton plate_with_a_border_branch(const Vec3& to) {
    Skeleton s = plate(2, 2);
    s.points.push_back(Vec3{1, 0, 0} + to);
    s.points.push_back(Vec3{1, 0, 0} + 2.0 * to);
    s.edges.push_back({1, 9});
    s.edges.push_back({9, 10});
    return s;
}

TEST(RawMeshLeaflets, BranchLeavingAStraightBorderStandsOnItsHalfChunks) {
    // Outward (-y), tilted 27 and 45 degrees out of the plane: Out. The out column turns with the branch, so the
    // first chunk's root centre (vertex 1's out copy, at 0.25 from it) lies along the branch.
    for (const Vec3& to : {Vec3{0, -1, 0}, Vec3{0, -1, 0.5}, Vec3{0, -1, -1}}) {
        SCOPED_TRACE(::testing::Message() << to.y << " " << to.z);
        const Skeleton s = plate_with_a_border_branch(to);
        const Built b = build(s, 0.25);
        EXPECT_EQ(b.an.vertex_class[1], VertexClass::LeafletBoundary);
        EXPECT_EQ(b.an.vertex_border_root[1], BorderRoot::Out);
        expect_good_leaflet_mesh(s, b, 32);
        EXPECT_EQ(b.raw.mesh.points.size(), 69u);
        const int out = b.raw.vertex_base[1] + 3;
        EXPECT_EQ(b.raw.mesh.hexes[0][0], out);
        EXPECT_NEAR(distance(b.raw.mesh.points[out], Vec3{1, 0, 0} + 0.25 * normalized(to)), 0.0, 1e-12);
        // 4 of the 8 patch edges were convex (1 hex) and are flat now; 4 go from 2 hexes to 3.
        EXPECT_EQ(b.prediction.boundary_irregular_edges, (std::map<int, long>{{1, 16 + 8 + 8 - 4}, {3, 4}}));
    }
}

TEST(RawMeshLeaflets, BranchAlongTheNormalAtABorderVertexOfTwoFacesStandsOnItsPlates) {
    // Up (+z) or down, or leaning 27 degrees outward: Side. On the up (down) side of vertex 1: 2 plates and 2
    // half-chunks; the 2 patch edges at vertex 1's out-up copy were convex and are flat now, the other 6 get a third
    // hex.
    for (const Vec3& to : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, Vec3{0, -0.5, 1}}) {
        SCOPED_TRACE(::testing::Message() << to.y << " " << to.z);
        const Skeleton s = plate_with_a_border_branch(to);
        const Built b = build(s, 0.25);
        EXPECT_EQ(b.an.vertex_border_root[1], BorderRoot::Side);
        expect_good_leaflet_mesh(s, b, 32);
        EXPECT_EQ(b.raw.mesh.points.size(), 69u);
        EXPECT_EQ(b.raw.mesh.hexes[0][0], b.raw.vertex_base[1] + (to.z > 0 ? 1 : 2));
        EXPECT_EQ(b.prediction.boundary_irregular_edges, (std::map<int, long>{{1, 16 + 8 + 8 - 2}, {3, 6}}));
    }
}

TEST(RawMeshLeaflets, NeighbouringBorderRootsShareAPatchEdge) {
    // A 4 x 1 strip with outward branches at border vertices 1 and 3 (both next to 2): the edges from 2's out copy to
    // its out-up and out-down copies carry 2 half-chunks and both first chunks (boundary valence 4).
    // Hexes: 4 x 2 + 10 x 2 + 2 x 4 = 36.
    Skeleton s = plate(4, 1);
    for (const int v : {1, 3}) {
        s.points.push_back({double(v), -1, 0});
        s.edges.push_back({v, static_cast<int>(s.points.size()) - 1});
    }
    const Built b = build(s, 0.2);
    EXPECT_EQ(b.an.vertex_border_root[1], BorderRoot::Out);
    EXPECT_EQ(b.an.vertex_border_root[3], BorderRoot::Out);
    expect_good_leaflet_mesh(s, b, 36);
    EXPECT_EQ(b.prediction.boundary_irregular_edges.at(4), 2);
}

// Branches rooted at the neighbouring interior vertices 5 and 6 of a 3 x 3 plate share 2 faces: on the same side
// they would stand on the same plate faces (refused, naming vertex 6); on opposite sides each takes its own side.
// Hexes: 9 x 2 + 12 x 2 + 2 x 4 = 50.
TEST(RawMeshLeaflets, NeighbouringRootsOnTheSameSideAreRefused) {
    for (const double z6 : {1.0, -1.0}) {
        Skeleton s = plate(3, 3);
        s.points.push_back({1, 1, 1});
        s.points.push_back({2, 1, z6});
        s.edges.push_back({5, 16});
        s.edges.push_back({6, 17});
        if (z6 > 0) {
            try {
                (void)analyze_skeleton(s);
                ADD_FAILURE() << "accepted";
            } catch (const Error& e) {
                EXPECT_EQ(e.code(), ErrorCode::UnsupportedConfiguration);
                EXPECT_EQ(e.where().index, 6);
                EXPECT_NE(std::string(e.what()).find("skeleton vertex 5"), std::string::npos) << e.what();
            }
        } else {
            const Built b = build(s, 0.25);
            expect_good_leaflet_mesh(s, b, 50);
        }
    }
}

// Seeded random plates with branches of 2 edges at random vertices in random directions: whatever the analysis
// accepts (roots inside, on the border's out or side patch, BL-joints at corners and where the border cannot root)
// gives a valid raw mesh with the skeleton's Euler characteristic and exactly the predicted vertices and irregular
// edges. Inverted hexes are allowed here (random directions).
TEST(RawMeshLeaflets, RandomRootsGiveValidMeshesAsPredicted) {
    std::mt19937 rng(2026);
    std::uniform_int_distribution<int> pick(0, 24);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int built = 0, refused = 0;
    std::map<int, int> classes;
    for (int trial = 0; trial < 200; ++trial) {
        Skeleton s = plate(4, 4);  // 25 vertices, 16 faces
        std::set<int> roots;
        const int k = 1 + trial % 3;
        while (static_cast<int>(roots.size()) < k) roots.insert(pick(rng));
        for (const int v : roots) {
            Vec3 d{u(rng), u(rng), u(rng)};
            if (!(norm(d) > 0.2)) d = {0, 0, 1};
            d = normalized(d);
            const int a = static_cast<int>(s.points.size());
            s.points.push_back(s.points[v] + 0.8 * d);
            s.points.push_back(s.points[v] + 1.6 * d);
            s.edges.push_back({v, a});
            s.edges.push_back({a, a + 1});
        }
        try {
            (void)analyze_skeleton(s);
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::UnsupportedConfiguration) << e.what();
            ++refused;
            continue;
        }
        SCOPED_TRACE(trial);
        const Built b = build(s, 0.2);
        for (const int v : roots)
            ++classes[static_cast<int>(b.an.vertex_class[v]) * 10 + static_cast<int>(b.an.vertex_border_root[v])];
        const QualityReport q = compute_quality(b.raw.mesh);
        EXPECT_TRUE(q.validation.valid()) << (q.validation.problems.empty() ? "" : q.validation.problems[0].message);
        EXPECT_EQ(q.euler_characteristic, euler_characteristic(s));
        EXPECT_EQ(static_cast<long>(b.raw.mesh.points.size()), b.prediction.vertices);
        EXPECT_EQ(q.singular_interior_edges, b.prediction.interior_irregular_edges);
        EXPECT_EQ(q.singular_boundary_edges, b.prediction.boundary_irregular_edges);
        ++built;
    }
    // Every kind of meeting occurred: inside (LeafletInterior), out / side patches (LeafletBoundary), BL-joints.
    EXPECT_GT(built, 100);
    EXPECT_GT(refused, 0);
    EXPECT_GT(classes[static_cast<int>(VertexClass::LeafletInterior) * 10], 0);
    EXPECT_GT(classes[static_cast<int>(VertexClass::LeafletBoundary) * 10 + static_cast<int>(BorderRoot::Out)], 0);
    EXPECT_GT(classes[static_cast<int>(VertexClass::LeafletBoundary) * 10 + static_cast<int>(BorderRoot::Side)], 0);
    EXPECT_GT(classes[static_cast<int>(VertexClass::BLJoint) * 10], 0);
}

TEST(RawMeshLeaflets, ReflexBorderVertexPushesItsOutVertexOutward) {
    // An L of three unit quads: the reflex border vertex (1, 1) pushes its out vertex along the exterior bisector
    // (+1, +1) / sqrt 2, away from the leaflet (the mean of the unit vectors to its 4 neighbours is zero there, and
    // at the hand's zigzag reflex vertices it pointed into the palm).
    Skeleton s;
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i) s.points.push_back({double(i), double(j), 0});
    s.points.pop_back();  // (2, 2) is not used
    // faces (0,0), (1,0), (0,1): the quad (1,1)-(2,2) is missing, so vertex 4 = (1,1) is a reflex border corner
    s.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}};
    add_face_edges(s);
    const Built b = build(s, 0.25);
    ASSERT_EQ(b.an.vertex_class[4], VertexClass::LeafletBoundary);
    const Vec3 out = b.raw.mesh.points[b.raw.vertex_base[4] + 3];
    EXPECT_NEAR(out.x, 1 + 0.25 * std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(out.y, 1 + 0.25 * std::sqrt(0.5), 1e-12);
    expect_good_leaflet_mesh(s, b, 2 * 3 + 2 * 8);
    // As thick as its edges are long (r = 1): at (1, 1) the out vertex would reach 0.71 along both border edges of
    // length 1; it stops at kReflexOutFraction (0.3) of the edge, measured along it: distance 0.3 / cos 45 deg, i.e.
    // at (1.3, 1.3). The convex corner (0, 0) keeps r; the mesh stays valid.
    const Built thick = build(s, 1.0);
    const Vec3 reflex_out = thick.raw.mesh.points[thick.raw.vertex_base[4] + 3];
    EXPECT_NEAR(reflex_out.x, 1.3, 1e-12);
    EXPECT_NEAR(reflex_out.y, 1.3, 1e-12);
    EXPECT_NEAR(distance(thick.raw.mesh.points[thick.raw.vertex_base[0] + 3], Vec3{0, 0, 0}), 1.0, 1e-12);
    EXPECT_EQ(compute_quality(thick.raw.mesh).inverted, 0);
}

TEST(RawMesh, OneEdgeIsOneChunkOfFourHexes) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}};
    s.edges = {{0, 1}};
    const Built b = build(s, 0.25);
    ASSERT_EQ(b.raw.mesh.hexes.size(), 4u);
    EXPECT_EQ(b.raw.mesh.points.size(), 18u);  // 2 x (centre + 4 quad vertices + 4 mids)
    EXPECT_EQ(b.prediction.boundary_irregular_edges.at(1), 4 + 2 * 8);
    EXPECT_TRUE(b.prediction.interior_irregular_edges.empty());
    expect_good_raw_mesh(s, b);
    // All 4 hexes share the axis (centres 0 and 9).
    for (const std::array<int, 8>& h : b.raw.mesh.hexes) {
        EXPECT_EQ(h[0], 0);
        EXPECT_EQ(h[4], 9);
    }
    // Cross-section points on the sphere of radius 0.25 around each centre.
    for (int i = 1; i < 9; ++i) EXPECT_NEAR(norm(b.raw.mesh.points[i] - s.points[0]), 0.25, 1e-12);
}

TEST(RawMesh, ThreeStarHasTwelveHexesAndPredictedIrregularEdges) {
    const double c = std::cos(2 * M_PI / 3), sn = std::sin(2 * M_PI / 3);
    const Skeleton s = star({{1, 0, 0}, {c, sn, 0}, {c, -sn, 0}}, 1, 1.0);
    const Built b = build(s, 0.25);
    EXPECT_EQ(b.raw.mesh.hexes.size(), 12u);
    // Any quad partition of the sphere into 3 quads has 5 vertices with valences summing to 12; the two "poles" of
    // valence 3 give two interior edges with 6 hexes.
    EXPECT_EQ(b.prediction.interior_irregular_edges, (std::map<int, long>{{6, 2}}));
    expect_good_raw_mesh(s, b);
}

// Seed 149's fat branching point as adaptation leaves it (docs/junctions.md, "Degree-3 partitions"): radius 0.381,
// the parent (0.393) and two thin children (0.209, 0.244) 50 degrees apart, every gap but one below 180 degrees. The
// orange around the branches' best-fit plane normal keeps both valence-3 poles 85 degrees from every branch (raw min
// SJ 0.218); partition_sphere's own choice (plane_orange_at_degree_three off) tilts its axis into that plane, one pole
// 26 degrees from a child, and the children's first chunks get a corner of SJ 0.084 (the pipeline's raw mesh of seed
// 149: 0.020 -> 0.217, measured with the pattern search's axis, before SpherePartitionOptions::exact_three_orange: 17
// degrees and 0.017).
TEST(RawMesh, FatDegreeThreeJunctionTakesThePlaneOrange) {
    Skeleton s;
    s.points = {{0, 0, 0}, {0.132, 0.034, -0.605}, {-0.615, 0.062, 0.365}, {-0.889, -0.063, -0.269}};
    s.edges = {{0, 1}, {0, 2}, {0, 3}};
    s.radii = {0.381, 0.393, 0.209, 0.244};
    const SkeletonAnalysis an = analyze_skeleton(s);
    for (const bool on : {true, false}) {
        SCOPED_TRACE(on ? "plane orange" : "partition_sphere's choice");
        ConnectionSurfaceOptions co;
        co.plane_orange_at_degree_three = on;
        co.degree_three_partition_by_chunks = false;  // the gap rule alone
        const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
        const BranchFrames fr = propagate_frames(s, an, cs);
        double pole_to_branch = 180;  // degrees, smallest angle between a valence-3 point of c and a branch
        int poles = 0;
        for (int x = cs.point_begin[0]; x < cs.point_begin[1]; ++x) {
            if (cs.point_valence[x] != 3) continue;
            ++poles;
            for (int w = 1; w < 4; ++w)
                pole_to_branch = std::min(
                    pole_to_branch, std::acos(std::clamp(dot(fr.directions[x], normalized(s.points[w])), -1.0, 1.0)) *
                                        180 / std::numbers::pi);
        }
        EXPECT_EQ(poles, 2);
        const QualityReport q = compute_quality(build_raw_mesh(s, an, cs, fr).mesh);
        EXPECT_EQ(q.inverted, 0);
        if (on) {
            EXPECT_NEAR(pole_to_branch, 85.1, 0.5);
            EXPECT_NEAR(q.sj_min, 0.218, 0.01);
        } else {
            EXPECT_NEAR(pole_to_branch, 25.7, 0.5);
            EXPECT_NEAR(q.sj_min, 0.084, 0.01);
        }
    }
}

// The same Y with its first arm ending at another branching point (two more arms there, 1 long, 60 degrees either
// side of the first arm's direction): the chunk model puts a square cross-section at that point, where the raw mesh
// has its partition quad. degree_three_chunks_next_to_branching_points on: the centre is still chosen by its chunks
// (the orange, poles 84.7 degrees from every branch, as above); off: the gap rule (no gap over 180 degrees: the general
// partition, poles 71.4 degrees from a branch; 45.2 with the pattern search's axis before exact_three_orange).
TEST(RawMesh, DegreeThreeChoiceNextToABranchingPoint) {
    const std::vector<Vec3> dirs = tilted_y_directions();
    Skeleton s = star(dirs, 1, 1.0);
    const double c60 = 0.5, s60 = std::sqrt(3.0) / 2;
    s.points.push_back(s.points[1] + Vec3{c60, s60, 0});
    s.points.push_back(s.points[1] + Vec3{c60, -s60, 0});
    s.edges.push_back({1, 4});
    s.edges.push_back({1, 5});
    s.radii = {0.4, 0.25, 0.25, 0.25, 0.2, 0.2};
    const SkeletonAnalysis an = analyze_skeleton(s);
    ASSERT_EQ(an.vertex_class[1], VertexClass::BranchingPoint);
    for (const bool next : {true, false}) {
        SCOPED_TRACE(next ? "chosen next to a branching point" : "gap rule there");
        ConnectionSurfaceOptions co;
        co.degree_three_chunks_next_to_branching_points = next;
        co.degree_three_chunks_at_bridges = false;  // the square model (BridgeEndsChosenByTheirChunks: the quad)
        const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
        const BranchFrames fr = propagate_frames(s, an, cs);
        const double pole_to_branch = pole_to_branch_deg(cs, fr, 0, dirs);
        EXPECT_NEAR(pole_to_branch, next ? 84.7 : 71.4, 0.5);
        EXPECT_EQ(compute_quality(build_raw_mesh(s, an, cs, fr).mesh).inverted, 0);
    }
}

// The tilted Y of DegreeThreePartitionChosenByItsChunks (centre radius 0.4, arms 0.6 long) whose first arm ends at a
// branching point with two arms 1 long, `spread_deg` either side of the first arm's direction in the plane through
// it at angle phi_deg about it from (d0 x z) (radii 0.25 at the arms' ends, 0.2 at the far arms' ends).
Skeleton bridged_y(double spread_deg, double phi_deg) {
    const std::vector<Vec3> dirs = tilted_y_directions();
    Skeleton s = star(dirs, 1, 0.6);
    const Vec3 u = normalized(cross(dirs[0], Vec3{0, 0, 1})), w = cross(dirs[0], u);
    const double a = phi_deg * std::numbers::pi / 180, sp = spread_deg * std::numbers::pi / 180;
    const Vec3 n = std::cos(a) * u + std::sin(a) * w;
    s.points.push_back(s.points[1] + std::cos(sp) * dirs[0] + std::sin(sp) * n);
    s.points.push_back(s.points[1] + std::cos(sp) * dirs[0] - std::sin(sp) * n);
    s.edges.push_back({1, 4});
    s.edges.push_back({1, 5});
    s.radii = {0.4, 0.25, 0.25, 0.25, 0.2, 0.2};
    return s;
}

// degree_three_chunks_at_bridges: the centre of bridged_y chooses between the general partition (poles 71.4 degrees
// from a branch) and the orange (84.7) by its first chunks, the bridge's chunk ending on the neighbour's own quad
// (both ends are such points; in the second round each models the other's first-round choice). Spread 45 degrees,
// phi 0: the orange, raw min SJ 0.490 where the gap rule (option off) leaves 0.394. Spread 80 degrees, phi 45: the
// general partition, 0.331, as the gap rule; the square model there (degree_three_chunks_next_to_branching_points,
// the bridge's far end a square) takes the orange and gets 0.221. (With the pattern search's axis, before
// exact_three_orange: the general partition's poles 45.2 degrees from a branch, 0.238 and 0.323.)
TEST(RawMesh, BridgeEndsChosenByTheirChunks) {
    const std::vector<Vec3> dirs = tilted_y_directions();
    struct Case {
        double spread, phi;
        bool bridges, square;
        double pole_to_branch, sj_min;
    };
    for (const Case& c : {Case{45, 0, true, false, 84.7, 0.490}, Case{45, 0, false, false, 71.4, 0.394},
                          Case{80, 45, true, false, 71.4, 0.331}, Case{80, 45, false, true, 84.7, 0.221}}) {
        SCOPED_TRACE(std::to_string(c.spread) + " / " + std::to_string(c.phi) + (c.bridges ? " quad model" : "") +
                     (c.square ? " square model" : ""));
        const Skeleton s = bridged_y(c.spread, c.phi);
        const SkeletonAnalysis an = analyze_skeleton(s);
        ASSERT_EQ(an.vertex_class[1], VertexClass::BranchingPoint);
        ConnectionSurfaceOptions co;
        co.degree_three_chunks_at_bridges = c.bridges;
        co.degree_three_chunks_next_to_branching_points = c.square;
        const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
        const BranchFrames fr = propagate_frames(s, an, cs);
        const QualityReport q = compute_quality(build_raw_mesh(s, an, cs, fr).mesh);
        EXPECT_NEAR(pole_to_branch_deg(cs, fr, 0, dirs), c.pole_to_branch, 0.5);
        EXPECT_NEAR(q.sj_min, c.sj_min, 0.005);
        EXPECT_EQ(q.inverted, 0);
    }
}

// The gap rule (plane_orange_at_degree_three, without degree_three_partition_by_chunks) leaves a degree-3 point alone
// when no gap between its branches exceeds 180 degrees: a Y whose branches
// are 100, 120 and 140 degrees apart in azimuth, 10 degrees out of one plane (beyond planarity_tolerance), gets the
// same surface with and without it.
TEST(RawMesh, SpreadDegreeThreeJunctionKeepsItsPartition) {
    const std::vector<Vec3> dirs = tilted_y_directions();
    // The plane's orange is not partition_sphere's choice here: only the gap rule keeps the surface.
    SpherePartitionOptions any_planarity;
    any_planarity.planarity_tolerance = 1;
    EXPECT_NE(partition_sphere(dirs).points, partition_sphere(dirs, any_planarity).points);
    const Skeleton s = star(dirs, 1, 1.0);
    const SkeletonAnalysis an = analyze_skeleton(s);
    ConnectionSurfaceOptions gap_rule, off;  // the gap rule alone (degree_three_partition_by_chunks off)
    gap_rule.degree_three_partition_by_chunks = false;
    off.degree_three_partition_by_chunks = false;
    off.plane_orange_at_degree_three = false;
    const ConnectionSurfaces a = build_connection_surfaces(s, an, gap_rule), b = build_connection_surfaces(s, an, off);
    EXPECT_EQ(a.directions, b.directions);
    EXPECT_EQ(a.quads, b.quads);
}

// Dino's hip as adaptation leaves it (docs/junctions.md, "The shared curve skeletons"): a branching point of radius
// 0.223 with the body (0.221) and, in a cone opposite it, the tail (0.112) and two legs (0.100, 0.105) 46 degrees
// apart, every other angle at a leg at least 79 degrees. partition_sphere's choice is an orange, whose valence-2
// point between the two legs (their quads meeting at 180 degrees) sits in the legs' crotch: raw min SJ 0.070 (the
// pipeline's raw mesh of dino, with its shoulders and tail beyond: 0.071). With no_flat_point_in_close_pair the hull
// path's partition puts a valence-3 point there: 0.100 (dino's raw mesh: 0.161).
TEST(RawMesh, CloseDegreeFourPairGetsNoFlatPointInItsCrotch) {
    const Skeleton s = mesohex::test::dino_hip();
    const SkeletonAnalysis an = analyze_skeleton(s);
    for (const bool on : {true, false}) {
        SCOPED_TRACE(on ? "no flat point in the crotch" : "partition_sphere's choice");
        ConnectionSurfaceOptions co;
        co.no_flat_point_in_close_pair = on;
        const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
        // Points of c held by exactly the legs' quads (quads 2 and 3: the branch edges in order).
        const int q0 = cs.quad_begin[0], np = cs.point_begin[1] - cs.point_begin[0];
        ASSERT_EQ(np, 6);
        int flat_in_crotch = 0, flat = 0;
        for (int x = 0; x < np; ++x) {
            std::vector<int> holders;
            for (int q = 0; q < 4; ++q)
                if (std::ranges::find(cs.quads[q0 + q], x) != cs.quads[q0 + q].end()) holders.push_back(q);
            flat += holders.size() == 2;
            flat_in_crotch += holders == std::vector<int>{2, 3};
        }
        const BranchFrames fr = propagate_frames(s, an, cs);
        const QualityReport q = compute_quality(build_raw_mesh(s, an, cs, fr).mesh);
        EXPECT_EQ(q.inverted, 0);
        if (on) {
            EXPECT_EQ(flat, 2);  // a hull partition: four valence-3 points, two valence-2 ones elsewhere
            EXPECT_EQ(flat_in_crotch, 0);
            EXPECT_NEAR(q.sj_min, 0.100, 0.01);
        } else {
            EXPECT_EQ(flat, 4);  // the orange: four equator points
            EXPECT_EQ(flat_in_crotch, 1);
            EXPECT_NEAR(q.sj_min, 0.070, 0.01);
        }
    }
}

// ray_exit on one round cone, derived on paper: balls from a = (0, 0, 0), radius 1, to b = (4, 0, 0), radius 0.5
// (radius slope m = -1/8 per unit length). The union's boundary at axial position z touches the ball centred at
// z_c = (z + r_a m) / (1 - m^2) of radius R = r_a + m z_c, at distance R sqrt(1 - m^2) from the axis: for the ray
// from (2, 0, 0) along y, z_c = 1.875 / 0.984375 = 1.9047619, R = 0.7619048, exit = 0.7559289 = 2 / sqrt(7).
TEST(JunctionCover, RayLeavesARoundConeOnItsTangentCone) {
    const std::vector<RoundCone> cone{{{0, 0, 0}, {4, 0, 0}, 1.0, 0.5}};
    EXPECT_NEAR(ray_exit(cone, {2, 0, 0}, {0, 1, 0}, 0.02, 10), 2 / std::sqrt(7.0), 1e-9);
    EXPECT_NEAR(ray_exit(cone, {0, 0, 0}, {0, 0, 1}, 0.02, 10), 1.0, 1e-9);    // inside the first ball only
    EXPECT_NEAR(ray_exit(cone, {0, 0, 0}, {1, 0, 0}, 0.02, 3.0), 3.0, 1e-12);  // never leaves before t_max
    EXPECT_NEAR(ray_exit(cone, {0, 0, 0}, {-1, 0, 0}, 0.02, 10), 1.0, 1e-9);   // behind the cone: a's ball
}

// The crotch of a close pair lies beyond the junction's ball (docs/junctions.md, "Dino's hip and knight's v9 traced
// through the stages"), derived on paper: two tubes of radius 0.5 leave c = 0 along the x-y plane 25 degrees either
// side of +x, c's ball has radius 0.6. A ray from c at angle b from +x (|b| < 25 degrees, in the plane) is at distance
// t sin(25 - |b|) from the nearer axis, so it leaves the union at 0.5 / sin(25 - |b|): 1.1831 on the bisector
// (0.5 / sin 25), 1.9319 at 10 degrees (0.5 / sin 15), both beyond c's ball; across the plane (along z) a point at
// distance t is t from both axes' start, inside only c's ball: 0.6; in the plane at 90 degrees the axis at 65
// degrees gives 0.5 / sin 65 = 0.5517 < 0.6: c's ball again.
TEST(JunctionCover, RayLeavesACloseTubePairBeyondTheJunctionBall) {
    const double a = 25 * std::numbers::pi / 180, rho = 0.5, rc = 0.6;
    const Vec3 c{0, 0, 0};
    const std::vector<RoundCone> balls{{c, c, rc, rc},
                                       {c, {4 * std::cos(a), 4 * std::sin(a), 0}, rho, rho},
                                       {c, {4 * std::cos(a), -4 * std::sin(a), 0}, rho, rho}};
    const double b = 10 * std::numbers::pi / 180;
    EXPECT_NEAR(ray_exit(balls, c, {1, 0, 0}, 0.02, 10), rho / std::sin(a), 1e-9);
    EXPECT_NEAR(ray_exit(balls, c, {std::cos(b), std::sin(b), 0}, 0.02, 10), rho / std::sin(a - b), 1e-9);
    EXPECT_NEAR(ray_exit(balls, c, {std::cos(b), -std::sin(b), 0}, 0.02, 10), rho / std::sin(a - b), 1e-9);
    EXPECT_NEAR(ray_exit(balls, c, {0, 0, 1}, 0.02, 10), rc, 1e-9);
    EXPECT_NEAR(ray_exit(balls, c, {0, 1, 0}, 0.02, 10), rc, 1e-9);
    EXPECT_NEAR(rho / std::sin(a), 1.1831, 1e-4);
    EXPECT_NEAR(rho / std::sin(a - b), 1.9319, 1e-4);
}

// A plane cross for the junction cover: 4 arms along +-x, +-y of one edge of length arm, radius r everywhere, no
// compatible block (the cross would get a cube, without a sphere surface).
struct PlaneCross {
    std::vector<Vec3> dirs{{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    Skeleton s;
    SkeletonAnalysis an;
    ConnectionSurfaces cs;
    BranchFrames fr;
    PlaneCross(double r, double arm) : s(star(dirs, 1, arm)) {
        s.radii.assign(s.points.size(), r);
        an = analyze_skeleton(s);
        ConnectionSurfaceOptions co;
        co.blocks.enabled = false;
        cs = build_connection_surfaces(s, an, co);
        fr = propagate_frames(s, an, cs);
    }
    RawMesh raw(double fraction, const Skeleton* domain = nullptr, double inset = 0) const {
        RawMeshOptions o;
        o.cover.fraction = fraction;
        o.cover.inset = inset;
        return build_raw_mesh(s, an, cs, fr, o, domain);
    }
};

// A plane cross (4 arms of 5 r along +-x, +-y, one edge each, r = 0.1 everywhere): the arms' capsules hold a ray
// from the centre at angle phi_k to arm k (cos phi_k > 0) out to r / sin phi_k (its axial reach r / tan phi_k < 5 r
// for phi_k > 11.3 degrees), c's ball to r, so a surface point of direction d moves from r to
// max(r, max_k r / sin phi_k); its surface edges' midpoints to the mean of their two points' distances. The
// partition's equator points lie 45 degrees from two arms: sqrt(2) r. Off (fraction 0) every point stays at r.
TEST(JunctionCover, PlaneCrossPointsMoveToTheArmsCapsules) {
    const double r = 0.1;
    const PlaneCross x4(r, 5 * r);
    const Skeleton& s = x4.s;
    const std::vector<Vec3>& dirs = x4.dirs;
    const ConnectionSurfaces& cs = x4.cs;
    const BranchFrames& fr = x4.fr;
    const RawMesh off = x4.raw(0.0);
    const RawMesh on = x4.raw(1.0);
    const int np = cs.point_begin[1] - cs.point_begin[0];
    int at_sqrt2 = 0;
    std::vector<double> expected(np);
    for (int x = 0; x < np; ++x) {
        const Vec3 d = fr.directions[cs.point_begin[0] + x];
        expected[x] = r;
        for (const Vec3& u : dirs)
            if (dot(d, u) > 0) expected[x] = std::max(expected[x], r / norm(cross(d, u)));
        EXPECT_NEAR(distance(off.mesh.points[off.vertex_base[0] + 1 + x], s.points[0]), r, 1e-12);
        EXPECT_NEAR(distance(on.mesh.points[on.vertex_base[0] + 1 + x], s.points[0]), expected[x], 1e-6 * r);
        at_sqrt2 += std::abs(expected[x] - std::sqrt(2.0) * r) < 1e-3 * r;
    }
    EXPECT_EQ(at_sqrt2, 4);  // the orange's four equator points, on the arms' bisectors
    for (int j = cs.edge_begin[0]; j < cs.edge_begin[1]; ++j) {
        const int id = on.vertex_base[0] + 1 + np + (j - cs.edge_begin[0]);
        EXPECT_NEAR(distance(on.mesh.points[id], s.points[0]),
                    0.5 * (expected[cs.edges[j][0]] + expected[cs.edges[j][1]]), 1e-6 * r);
    }
    const QualityReport qo = compute_quality(off.mesh), qn = compute_quality(on.mesh);
    EXPECT_EQ(qn.inverted, 0);
    EXPECT_GE(qn.sj_min, std::min(0.3, qo.sj_min));
}

// The union comes from the domain skeleton when one is given (the pipeline passes its input): the same cross meshed
// with r = 0.1 and a domain skeleton whose balls are 0.12 moves the equator points to 0.12 sqrt(2), not 0.1 sqrt(2).
TEST(JunctionCover, UnionOfTheDomainSkeletonsBalls) {
    const double r = 0.1;
    const PlaneCross x4(r, 5 * r);
    Skeleton domain = x4.s;
    domain.radii.assign(domain.points.size(), 1.2 * r);
    const RawMesh on = x4.raw(1.0, &domain);
    int at = 0;
    for (int x = 0; x < x4.cs.point_begin[1] - x4.cs.point_begin[0]; ++x)
        at += std::abs(distance(on.mesh.points[on.vertex_base[0] + 1 + x], x4.s.points[0]) - 1.2 * std::sqrt(2.0) * r) <
              1e-6 * r;
    EXPECT_EQ(at, 4);
}

// The guard: the same cross with arms of r. Moved to sqrt(2) r, an equator point would lie r along each of its two
// arms, level with their first cross-sections: the hexes between flatten below the floor (0.3). Every hex of the
// junction stays at or above min(sj_floor, its value on the sphere), and the equator points stop between r and
// sqrt(2) r (one halving: 1.207 r; with arms of 1.2 r they reach sqrt(2) r, min SJ 0.49 -> 0.48).
TEST(JunctionCover, GuardKeepsTheChunksOfShortArms) {
    const double r = 0.1;
    const PlaneCross x4(r, r);
    const Skeleton& s = x4.s;
    const RawMesh off = x4.raw(0.0);
    const RawMesh on = x4.raw(1.0);
    const std::vector<double> before = scaled_jacobians(off.mesh), after = scaled_jacobians(on.mesh);
    const double floor = JunctionCoverOptions{}.sj_floor;
    for (std::size_t h = 0; h < after.size(); ++h) EXPECT_GE(after[h], std::min(floor, before[h]) - 1e-12);
    const double rr = distance(off.mesh.points[off.vertex_base[0] + 1], s.points[0]);  // the raw radius (margin limit)
    double farthest = 0;
    for (int x = 0; x < x4.cs.point_begin[1] - x4.cs.point_begin[0]; ++x)
        farthest = std::max(farthest, distance(on.mesh.points[on.vertex_base[0] + 1 + x], s.points[0]));
    EXPECT_GT(farthest, rr);
    EXPECT_LT(farthest, std::sqrt(2.0) * r - 1e-3 * r);
}

// The junction inset on the same cross (r 0.1, arms 5 r): a surface point of c whose shortest boundary edge on the
// sphere is e_x goes to min(r + fraction (t_x - r), t_x - inset e_x), t_x its ray's exit from the arms' capsules
// (max(r, max_k r / sin phi_k), as above). With the cover (fraction 1) every point ends one layer (0.25 e_x) inside
// the union; without it (fraction 0) only the points whose sphere position lies within a layer of the union's surface
// (the poles and every other point at r) move inward, the equator points (t = sqrt(2) r) stay at r.
TEST(JunctionCover, InsetKeepsOneLayerInsideTheUnion) {
    const double r = 0.1, inset = 0.25;
    const PlaneCross x4(r, 5 * r);
    const RawMesh off = x4.raw(0.0);
    const HexTopology topo = compute_hex_topology(off.mesh);
    std::vector<double> shortest(off.mesh.points.size(), 1e300);
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        if (!topo.edge_on_boundary[e]) continue;
        const int a = topo.edges[e][0], b = topo.edges[e][1];
        const double len = distance(off.mesh.points[a], off.mesh.points[b]);
        shortest[a] = std::min(shortest[a], len);
        shortest[b] = std::min(shortest[b], len);
    }
    const int np = x4.cs.point_begin[1] - x4.cs.point_begin[0];
    for (const double fraction : {1.0, 0.0}) {
        SCOPED_TRACE(fraction);
        const RawMesh on = x4.raw(fraction, nullptr, inset);
        int stayed = 0;
        for (int x = 0; x < np; ++x) {
            const int id = on.vertex_base[0] + 1 + x;
            const Vec3 d = x4.fr.directions[x4.cs.point_begin[0] + x];
            double t = r;
            for (const Vec3& u : x4.dirs)
                if (dot(d, u) > 0) t = std::max(t, r / norm(cross(d, u)));
            ASSERT_LT(shortest[id], 1e300);  // every surface point of c lies on the boundary
            const double want = std::min(r + fraction * (t - r), t - inset * shortest[id]);
            EXPECT_NEAR(distance(on.mesh.points[id], x4.s.points[0]), want, 1e-6 * r);
            stayed += std::abs(want - r) < 1e-12;
        }
        EXPECT_EQ(stayed, fraction == 0 ? 4 : 0);  // the equator points, a layer and more inside the union
        const std::vector<double> before = scaled_jacobians(off.mesh), after = scaled_jacobians(on.mesh);
        for (std::size_t h = 0; h < after.size(); ++h)
            EXPECT_GE(after[h], std::min(JunctionCoverOptions{}.sj_floor, before[h]) - 1e-12);
    }
}

// The interior dihedral angle, in degrees, of the sharpest raw edge between a surface point and a surface-edge midpoint
// of c (the creases on c's sphere): per such edge, the sum over the hexes holding it of the angle between the two hex
// faces through it (measured at the edge's midpoint, normal to it, towards the faces' centroids).
double sharpest_sphere_crease(const RawMesh& raw, const ConnectionSurfaces& cs, int c) {
    const int base = raw.vertex_base[c], np = cs.point_begin[c + 1] - cs.point_begin[c];
    const int ne = cs.edge_begin[c + 1] - cs.edge_begin[c];
    std::map<std::pair<int, int>, double> angle;
    for (const std::array<int, 8>& hex : raw.mesh.hexes) {
        for (const std::array<int, 2>& le : kHexEdges) {
            const int a = std::min(hex[le[0]], hex[le[1]]), b = std::max(hex[le[0]], hex[le[1]]);
            if (a < base + 1 || a > base + np || b <= base + np || b > base + np + ne) continue;
            std::vector<Vec3> centroids;
            for (const std::array<int, 4>& f : kHexFaces)
                if (std::ranges::find(f, le[0]) != f.end() && std::ranges::find(f, le[1]) != f.end()) {
                    Vec3 g{0, 0, 0};
                    for (int lv : f) g = g + 0.25 * raw.mesh.points[hex[lv]];
                    centroids.push_back(g);
                }
            const Vec3 p = raw.mesh.points[a], q = raw.mesh.points[b];
            const Vec3 e = normalized(q - p), mid = 0.5 * (p + q);
            const Vec3 u = centroids[0] - mid - dot(centroids[0] - mid, e) * e;
            const Vec3 w = centroids[1] - mid - dot(centroids[1] - mid, e) * e;
            angle[{a, b}] += std::acos(std::clamp(dot(u, w) / (norm(u) * norm(w)), -1.0, 1.0)) * 180 / std::numbers::pi;
        }
    }
    double sharpest = 0;
    for (const auto& [edge, a] : angle) sharpest = std::max(sharpest, a);
    return sharpest;
}

// The union of the hip's input balls: vertex 0's ball and a round cone per edge.
std::vector<RoundCone> hip_balls(const Skeleton& s) {
    std::vector<RoundCone> balls{{s.points[0], s.points[0], s.radii[0], s.radii[0]}};
    for (const std::array<int, 2>& e : s.edges)
        balls.push_back({s.points[e[0]], s.points[e[1]], s.radii[e[0]], s.radii[e[1]]});
    return balls;
}

// Crease opening on dino's hip by hand (skeleton_fixtures.h: legs 46 degrees apart, first vertices 1.5 r_c out, the
// hip meshed in its own balls). On the sphere the legs' two chunks meet at a crease of 320.7 degrees through their two
// hexes (the padding's two hexes would share the 39 degrees left). With crease_deg 270 the end points of the folded
// surface edges move out along their rays; one of them (x = 4) can: it stops where its ray leaves the union of the
// hip's balls, 1.5174 r_c (ray_exit, computed here independently), the other end's ray leaves the union at r_c (it
// stays). The sharpest crease falls to 275.7 degrees: the rule never carries a point outside the balls. Every other
// point stays at the raw radius exactly, no hex below min(sj_floor, before). With crease_deg 360 nothing can exceed
// it: byte-identical to off.
TEST(JunctionCover, CreaseOpeningUnfoldsTheLegsCrotchOfDinosHip) {
    const Skeleton s = mesohex::test::dino_hip();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const BranchFrames fr = propagate_frames(s, an, cs);
    RawMeshOptions o;
    const RawMesh off = build_raw_mesh(s, an, cs, fr, o);
    o.cover.crease_deg = 360;
    EXPECT_EQ(build_raw_mesh(s, an, cs, fr, o).mesh.points, off.mesh.points);
    o.cover.crease_deg = 270;
    const RawMesh on = build_raw_mesh(s, an, cs, fr, o);
    EXPECT_NEAR(sharpest_sphere_crease(off, cs, 0), 320.7, 0.1);
    EXPECT_NEAR(sharpest_sphere_crease(on, cs, 0), 275.7, 0.1);
    const std::vector<RoundCone> balls = hip_balls(s);
    const int base = off.vertex_base[0], np = cs.point_begin[1] - cs.point_begin[0];
    const double r = s.radii[0];
    ASSERT_EQ(np, 6);
    for (int x = 0; x < np; ++x) {
        const Vec3 d = fr.directions[cs.point_begin[0] + x];
        const Vec3 p = on.mesh.points[base + 1 + x] - s.points[0];
        EXPECT_NEAR(norm(cross(p, d)), 0.0, 1e-12);
        const double expected = x == 4 ? ray_exit(balls, s.points[0], d, 0.02 * r, 4 * r) : r;
        EXPECT_NEAR(dot(p, d), expected, 1e-9 * r);
    }
    EXPECT_NEAR(distance(on.mesh.points[base + 5], s.points[0]) / r, 1.5174, 1e-4);
    const std::vector<double> before = scaled_jacobians(off.mesh), after = scaled_jacobians(on.mesh);
    for (std::size_t h = 0; h < after.size(); ++h)
        EXPECT_GE(after[h], std::min(JunctionCoverOptions{}.sj_floor, before[h]) - 1e-12);
    EXPECT_EQ(compute_quality(on.mesh).inverted, 0);
}

// The crease rule on the midpoints (JunctionCoverOptions::crease_midpoints) on the same hand-built hip: no surface
// point moves (each stays at r_c exactly), every midpoint of an unfolded surface edge stays where the raw mesh put it,
// a moved midpoint stays on its own ray (the direction of its edge's ends' sum) between its start and the ray's exit
// from the union of the balls, and no hex ends below min(0.3, before). Measured, not derived: on this hand-built hip
// the sharpest crease only falls from 320.7 to 318.0 degrees (on dino's own meshed hip the rule lifts the raw minimum
// 0.161 -> 0.173: docs/junctions.md).
TEST(JunctionCover, CreaseMidpointsOpenTheLegsCrotchOfDinosHipWithoutMovingItsPoints) {
    const Skeleton s = mesohex::test::dino_hip();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const BranchFrames fr = propagate_frames(s, an, cs);
    RawMeshOptions o;
    const RawMesh off = build_raw_mesh(s, an, cs, fr, o);
    o.cover.crease_deg = 270;
    o.cover.crease_midpoints = true;
    const RawMesh on = build_raw_mesh(s, an, cs, fr, o);
    const std::vector<RoundCone> balls = hip_balls(s);
    const int base = off.vertex_base[0], np = cs.point_begin[1] - cs.point_begin[0];
    const int ne = cs.edge_begin[1] - cs.edge_begin[0];
    const double r = s.radii[0];
    for (int x = 0; x < np; ++x) EXPECT_EQ(on.mesh.points[base + 1 + x], off.mesh.points[base + 1 + x]);
    int moved = 0;
    for (int j = 0; j < ne; ++j) {
        const int id = base + 1 + np + j;
        if (on.mesh.points[id] == off.mesh.points[id]) continue;
        ++moved;
        const std::array<int, 2>& ed = cs.edges[cs.edge_begin[0] + j];
        const Vec3 d = normalized(fr.directions[cs.point_begin[0] + ed[0]] + fr.directions[cs.point_begin[0] + ed[1]]);
        const Vec3 p = on.mesh.points[id] - s.points[0];
        EXPECT_NEAR(norm(cross(p, d)), 0.0, 1e-12);
        EXPECT_GT(dot(p, d), r);
        EXPECT_LE(dot(p, d), ray_exit(balls, s.points[0], d, 0.02 * r, 4 * r) + 1e-12);
    }
    EXPECT_GE(moved, 1);
    EXPECT_NEAR(sharpest_sphere_crease(off, cs, 0), 320.7, 0.1);
    EXPECT_NEAR(sharpest_sphere_crease(on, cs, 0), 318.0, 0.1);
    const std::vector<double> before = scaled_jacobians(off.mesh), after = scaled_jacobians(on.mesh);
    for (std::size_t h = 0; h < after.size(); ++h)
        EXPECT_GE(after[h], std::min(JunctionCoverOptions{}.sj_floor, before[h]) - 1e-12);
    EXPECT_EQ(compute_quality(on.mesh).inverted, 0);
}

// The sides (local edge ids of point 0's partition) that dino_hip's two close legs' quads share at the hip (edges 2
// and 3 are 0-3 and 0-4, the hip is their side 0).
static std::vector<int> legs_shared_sides(const ConnectionSurfaces& cs) {
    const int q3 = cs.edge_quad[2][0] - cs.quad_begin[0], q4 = cs.edge_quad[3][0] - cs.quad_begin[0];
    std::vector<int> shared;
    for (int k3 : cs.quad_edges[cs.quad_begin[0] + q3])
        for (int k4 : cs.quad_edges[cs.quad_begin[0] + q4])
            if (k3 == k4) shared.push_back(k3);
    return shared;
}

// The midpoint rule restricted to a close pair's shared edge (JunctionCoverOptions::crease_pair_deg) on the same
// hand-built hip. Its branches' directions from the hip: the legs (vertices 3 and 4) are 46.35 degrees apart, every
// other pair 79.4 degrees or more (computed here). The legs' two quads share exactly one surface edge (the quads'
// sides, ConnectionSurfaces::quad_edges). With crease_pair_deg 60 only that edge's midpoint may move (the others stay
// where the raw mesh put them, every surface point too); with 40 (below the legs' angle) nothing moves: the raw mesh
// is the one without the rule.
TEST(JunctionCover, CreasePairMovesOnlyTheEdgeTheCloseLegsShare) {
    const Skeleton s = mesohex::test::dino_hip();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const BranchFrames fr = propagate_frames(s, an, cs);
    const auto angle = [&](int a, int b) {
        return std::acos(dot(normalized(s.points[a]), normalized(s.points[b]))) * 180 / std::numbers::pi;
    };
    EXPECT_NEAR(angle(3, 4), 46.35, 0.01);
    for (int a = 1; a <= 4; ++a)
        for (int b = a + 1; b <= 4; ++b)
            if (!(a == 3 && b == 4)) {
                EXPECT_GT(angle(a, b), 79.4);
            }
    // The legs' quads at the hip (edges 2 and 3 are 0-3 and 0-4, the hip is their side 0) and their shared side.
    const std::vector<int> shared = legs_shared_sides(cs);
    ASSERT_EQ(shared.size(), 1u);
    RawMeshOptions o;
    const RawMesh off = build_raw_mesh(s, an, cs, fr, o);
    o.cover.crease_deg = 270;
    o.cover.crease_midpoints = true;
    o.cover.crease_pair_deg = 40;
    EXPECT_EQ(build_raw_mesh(s, an, cs, fr, o).mesh.points, off.mesh.points);
    o.cover.crease_pair_deg = 60;
    const RawMesh on = build_raw_mesh(s, an, cs, fr, o);
    const int base = off.vertex_base[0], np = cs.point_begin[1] - cs.point_begin[0];
    const int ne = cs.edge_begin[1] - cs.edge_begin[0];
    for (int x = 0; x < np; ++x) EXPECT_EQ(on.mesh.points[base + 1 + x], off.mesh.points[base + 1 + x]);
    for (int j = 0; j < ne; ++j) {
        const int id = base + 1 + np + j;
        if (j == shared[0]) {
            EXPECT_GT(distance(on.mesh.points[id], s.points[0]), distance(off.mesh.points[id], s.points[0]));
        } else {
            EXPECT_EQ(on.mesh.points[id], off.mesh.points[id]);
        }
    }
    EXPECT_EQ(compute_quality(on.mesh).inverted, 0);
}

// The crease a close pair shares (close_pair_crease_edges, MeshOptions::crease_wedge_pair_deg) on the same
// hand-built hip: the legs (46.35 degrees apart; every other pair 79.4 or more) share one side of their quads on the
// hip's sphere, (Q_a, Q_b) with midpoint M; at 60 degrees (and at 79, still below every other pair) the rule lists
// exactly its two halves (Q_a, M) and (M, Q_b) as raw vertex pairs; at 40 (below the legs' angle) nothing; at 180
// every side of the partition held by two chunks: each side's two halves (the hip's 6 points and 4 quads have 8 sides).
TEST(RawMesh, ClosePairCreaseEdgesAreTheHalvesOfTheLegsSharedSide) {
    const Skeleton s = mesohex::test::dino_hip();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const BranchFrames fr = propagate_frames(s, an, cs);
    const RawMesh raw = build_raw_mesh(s, an, cs, fr, RawMeshOptions{});
    const std::vector<int> shared = legs_shared_sides(cs);
    ASSERT_EQ(shared.size(), 1u);
    const int base = raw.vertex_base[0], np = cs.point_begin[1] - cs.point_begin[0];
    const int ne = cs.edge_begin[1] - cs.edge_begin[0];
    ASSERT_EQ(np, 6);
    ASSERT_EQ(ne, 8);
    const std::array<int, 2>& side = cs.edges[cs.edge_begin[0] + shared[0]];
    const int m = base + 1 + np + shared[0], qa = base + 1 + side[0], qb = base + 1 + side[1];
    std::vector<std::array<int, 2>> want = {{std::min(qa, m), std::max(qa, m)}, {std::min(qb, m), std::max(qb, m)}};
    std::sort(want.begin(), want.end());
    EXPECT_EQ(close_pair_crease_edges(s, an, raw, 60), want);
    EXPECT_EQ(close_pair_crease_edges(s, an, raw, 79), want);
    EXPECT_TRUE(close_pair_crease_edges(s, an, raw, 40).empty());
    EXPECT_TRUE(close_pair_crease_edges(s, an, raw, 0).empty());
    EXPECT_EQ(close_pair_crease_edges(s, an, raw, 180).size(), 2u * ne);
}

// The crotch wedge (MeshOptions::crotch_wedge_pair_deg) on the same hand-built hip, the domain the ball of radius
// R = 1.1 r_c around the hip (the legs' crotch lies 1.07-1.24 r_c out on dino), crotch_reach 1: of the two listed
// halves of the legs' shared side only (M, Q_b) is folded past 300 degrees (320.7; (Q_a, M) 166.3: the section "The
// close pair's crease carried by a wedge"), so it gets the one wedge, after both legs' chunks are cut across. Counts
// by hand: each leg's chunk is one closed sheet of 4 hexes with 9 edges along the leg (the axis, 4 corner and 4
// midpoint edges), so the cut adds 2 x 4 hexes and 2 x 9 vertices, the wedge 1 hex and 2 vertices: 16 -> 25 hexes.
// Every hex positive, the mesh valid, (M, Q_b) on three hexes (leg, wedge, leg), (Q_a, M) still on two, and the
// wedge's two new vertices just inside the ball (within 0.95 R .. R: their step along the bisector ends on the ball,
// the cut quads' slant along the crease then moves them a little along it).
TEST(RawMesh, CrotchWedgeCutsTheLegsChunksAtTheCrotch) {
    const Skeleton s = mesohex::test::dino_hip();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const BranchFrames fr = propagate_frames(s, an, cs);
    const RawMesh raw = build_raw_mesh(s, an, cs, fr, RawMeshOptions{});
    ASSERT_EQ(raw.mesh.hexes.size(), 16u);
    const double r = 1.1 * s.radii[0];
    CreaseWedgeOptions o;
    o.min_dihedral_deg = 300;
    o.listed_only = true;
    o.listed = close_pair_crease_edges(s, an, raw, 60);
    ASSERT_EQ(o.listed.size(), 2u);
    o.crotch_reach = 1;
    o.crotch_distance = [&](const Vec3& p, const Vec3& d) {
        const Vec3 x = p - s.points[0];
        const double b = dot(x, d), c = dot(x, x) - r * r;
        return c >= 0 ? 0.0 : -b + std::sqrt(b * b - c);
    };
    const CreaseWedgeResult w = insert_crease_wedges(raw.mesh, o);
    ASSERT_EQ(w.wedge_edges.size(), 1u);
    EXPECT_EQ(w.wedge_edges[0], o.listed[1]);
    EXPECT_EQ(w.crotch_sheets, 2);
    EXPECT_EQ(w.mesh.hexes.size(), 16u + 8u + 1u);
    EXPECT_EQ(w.mesh.points.size(), raw.mesh.points.size() + 18u + 2u);
    EXPECT_TRUE(validate(w.mesh).valid());
    EXPECT_EQ(compute_quality(w.mesh).inverted, 0);
    const HexTopology t = compute_hex_topology(w.mesh);
    for (std::size_t i = 0; i < 2; ++i) {
        const auto it = std::find(t.edges.begin(), t.edges.end(), o.listed[i]);
        ASSERT_NE(it, t.edges.end());
        EXPECT_EQ(t.edge_valence[static_cast<std::size_t>(it - t.edges.begin())], i == 0 ? 2 : 3);
    }
    for (std::size_t v = w.mesh.points.size() - 2; v < w.mesh.points.size(); ++v) {
        EXPECT_LE(distance(w.mesh.points[v], s.points[0]), r);
        EXPECT_GT(distance(w.mesh.points[v], s.points[0]), 0.95 * r);
    }
}

// A fat Y without a gap over 180 degrees (azimuths 0, 100, 220 degrees, 10 degrees out of one plane, centre radius 0.4,
// arms 1 long ending at radius 0.25): partition_sphere's general choice tilts its axis, a valence-3 pole 71.4 degrees
// from a branch; the orange around the branches' best-fit plane normal keeps its poles 84.7 degrees from every branch.
// degree_three_partition_by_chunks models both candidates' first chunks (4 hexes per arm) and keeps the orange: raw
// min SJ 0.535 -> 0.558. Off, the gap rule keeps the general choice (no gap over 180 degrees here). (With the pattern
// search's axis, before SpherePartitionOptions::exact_three_orange: 45.2 degrees, 0.405.)
TEST(RawMesh, DegreeThreePartitionChosenByItsChunks) {
    const std::vector<Vec3> dirs = tilted_y_directions();
    Skeleton s = star(dirs, 1, 1.0);
    s.radii = {0.4, 0.25, 0.25, 0.25};
    const SkeletonAnalysis an = analyze_skeleton(s);
    for (const bool on : {true, false}) {
        SCOPED_TRACE(on ? "chosen by chunks" : "gap rule");
        ConnectionSurfaceOptions co;
        co.degree_three_partition_by_chunks = on;
        const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
        const BranchFrames fr = propagate_frames(s, an, cs);
        const double pole_to_branch = pole_to_branch_deg(cs, fr, 0, dirs);
        const QualityReport q = compute_quality(build_raw_mesh(s, an, cs, fr).mesh);
        EXPECT_EQ(q.inverted, 0);
        if (on) {
            EXPECT_NEAR(pole_to_branch, 84.7, 0.5);
            EXPECT_NEAR(q.sj_min, 0.558, 0.01);
        } else {
            EXPECT_NEAR(pole_to_branch, 71.4, 0.5);
            EXPECT_NEAR(q.sj_min, 0.535, 0.01);
        }
    }
}

TEST(RawMesh, ClosedRingOfSixEdges) {
    const Skeleton s = ring(6);
    const Built b = build(s, 0.25);
    EXPECT_EQ(b.raw.mesh.hexes.size(), 24u);
    const QualityReport q = compute_quality(b.raw.mesh);
    EXPECT_EQ(q.euler_characteristic, 0);
    EXPECT_EQ(q.boundary_components, 1);
    expect_good_raw_mesh(s, b);
}

TEST(RawMesh, IsolatedPolyline) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {2, 0.5, 0}, {3, 0.5, 0.5}, {4, 0, 1}};
    for (int i = 0; i < 4; ++i) s.edges.push_back({i, i + 1});
    const Built b = build(s, 0.25);
    EXPECT_EQ(b.raw.mesh.hexes.size(), 16u);
    expect_good_raw_mesh(s, b);
}

TEST(RawMesh, LoopAtABranchingPoint) {
    Skeleton s;
    s.points = {{0, 0, 0}, {-1, 0, 0}, {1, 1, 0.2}, {2, 0, 0}, {1, -1, -0.2}};
    s.edges = {{0, 1}, {0, 2}, {2, 3}, {3, 4}, {4, 0}};
    const Built b = build(s, 0.2);
    expect_good_raw_mesh(s, b);
    EXPECT_EQ(compute_quality(b.raw.mesh).euler_characteristic, 0);
}

TEST(RawMesh, StarsOfDegree3To12WithRandomDirections) {
    for (int n = 3; n <= 12; ++n) {
        for (unsigned seed = 1; seed <= 3; ++seed) {
            SCOPED_TRACE("degree " + std::to_string(n) + " seed " + std::to_string(seed));
            const Skeleton s = star(random_directions(n, 1000 * seed + n, 0.35), 2, 2.0);
            const Built b = build(s, 0.2);
            expect_good_raw_mesh(s, b);
        }
    }
}

TEST(RawMesh, TwoJunctionsWithABridgeAndAnIsolatedVertex) {
    const double c = std::cos(2 * M_PI / 3), sn = std::sin(2 * M_PI / 3);
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {c, sn, 0}, {c, -sn, 0}, {2 - c, 0, sn}, {2 - c, 0, -sn}, {9, 9, 9}};
    s.edges = {{0, 1}, {1, 2}, {0, 3}, {0, 4}, {2, 5}, {2, 6}};
    const Built b = build(s, 0.2);
    EXPECT_EQ(b.an.counts.isolated, 1);
    expect_good_raw_mesh(s, b);
}

TEST(RawMesh, IdenticalForAnyThreadCount) {
    const Skeleton s = star(random_directions(9, 77, 0.35), 3, 2.0);
    Built one, two;
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
        one = build(s, 0.2);
    }
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
        two = build(s, 0.2);
    }
    EXPECT_TRUE(one.raw.mesh == two.raw.mesh);
}

TEST(RawMesh, RejectsMissingOrBadRadius) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}};
    s.edges = {{0, 1}};
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const BranchFrames fr = propagate_frames(s, an, cs);
    EXPECT_THROW(build_raw_mesh(s, an, cs, fr), Error);
    s.radii = {0.1, 0.0};
    try {
        build_raw_mesh(s, an, cs, fr);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        EXPECT_EQ(e.where().index, 1);
    }
}

// Issue 17 (docs/sheets.md, "BL-joint frames"): a branch leaving a convex corner off its bisector. 3 x 3 plate of unit
// edges, radius 0.25, a 3-edge branch leaving corner 0 in the plate's plane at 225 + off degrees (off 0: the
// outward bisector). The pillow's start frame T = unit(leaflet direction - branch) turns its in-plane corners
// off / 2 towards a border edge (off 30: one corner 30 degrees outside the edge instead of 45, reaching
// 0.25 cos 30 = 0.22 along it); the relaxation turns the frame back so that the corner's half-chunks are as good as
// for a bisector branch. Measured (min scaled Jacobian of the 4 half-chunk hexes of the corner's two border edges):
// relaxed 0.423 / 0.421 for off 0 / 30; unrelaxed 0.423 / 0.232. No raw hex inverts either way.
TEST(RawMeshLeaflets, BLJointBranchOffTheCornerBisector) {
    auto corner_min = [](bool relax, double off_deg, long& inverted) {
        Skeleton s = plate(3, 3);
        const double a = (225.0 + off_deg) * std::numbers::pi / 180;
        int prev = 0;
        for (int k = 1; k <= 3; ++k) {
            s.points.push_back({k * std::cos(a), k * std::sin(a), 0});
            const int cur = static_cast<int>(s.points.size()) - 1;
            s.edges.push_back({prev, cur});
            prev = cur;
        }
        s.radii.assign(s.points.size(), 0.25);
        const SkeletonAnalysis an = analyze_skeleton(s);
        EXPECT_EQ(an.vertex_class[0], VertexClass::BLJoint);
        ConnectionSurfaceOptions co;
        co.relax_partitions = relax;
        const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
        const RawMesh raw = build_raw_mesh(s, an, cs, propagate_frames(s, an, cs));
        const std::vector<double> sj = scaled_jacobians(raw.mesh);
        inverted = std::count_if(sj.begin(), sj.end(), [](double x) { return x <= 0; });
        double lo = 1;
        int n = 0;
        for (std::size_t h = 0; h < sj.size(); ++h) {
            const int e = raw.hex_edge[h];
            if (e < 0 || an.edge_degree[e] != 1) continue;  // the half-chunks of the corner's two border edges
            if (s.edges[e][0] != 0 && s.edges[e][1] != 0) continue;
            lo = std::min(lo, sj[h]);
            ++n;
        }
        EXPECT_EQ(n, 4);
        return lo;
    };
    long inv = -1;
    const double bisector = corner_min(true, 0, inv);
    EXPECT_EQ(inv, 0);
    const double relaxed = corner_min(true, 30, inv);
    EXPECT_EQ(inv, 0);
    const double unrelaxed = corner_min(false, 30, inv);
    EXPECT_EQ(inv, 0);
    EXPECT_NEAR(bisector, 0.423, 0.01);
    EXPECT_NEAR(relaxed, bisector, 0.01);
    EXPECT_NEAR(unrelaxed, 0.232, 0.01);
}

// A fan line turning inside a plate (the paper's layout): plate(4, 4) cut by a wall one row high on the chain (2, 0)
// -> (2, 2) -> (4, 2) (vertex (i, j) = 5 j + i), fan edges of degree 3. At the turn (2, 2) the plate's inner part has
// 1 face and its outer part 3, the wall 2: the rays to the three gap vertices carry 1 + 2 = 3 (inner side and wall),
// 3 + 2 = 5 (outer side and wall) and 1 + 3 = 4 hexes (below the plate), not (2 x 6) / 3 = 4 each. Interior
// irregular edges: 6 of valence 6 (4 fan edges, 2 extension edges at the fan ends on the border), 13 of valence 3 (2
// at each of the 6 one-face corners: 4 plate corners, 2 wall top corners; the turn's inner ray) and 1 of valence 5.
// Hexes: 2 x 20 faces + 2 x 22 boundary edges = 84.
TEST(RawMesh, FanLineTurningInsideAPlateIsPredicted) {
    const Skeleton s = plate_with_wall(4, 4, {2, 7, 12, 13, 14});
    const test::RawRun r = test::checked_raw_mesh(s);
    EXPECT_EQ(r.analysis.counts.fan_edges, 4);
    EXPECT_EQ(r.predicted.hexes, 84);
    EXPECT_EQ(r.predicted.interior_irregular_edges, (std::map<int, long>{{3, 13}, {5, 1}, {6, 6}}));
    EXPECT_TRUE(r.valid);
    EXPECT_EQ(r.quality.inverted, 0);
}

// A flange: plate(4, 4) with walls above and below on the chain (1, 0) -> (2, 0) -> (3, 0) of its border side y = 0
// (edges of degree 3: plate, upper and lower wall; the chain ends (1, 0) and (3, 0) in the middle of the side, where
// the plate's border runs on along the chain). Docked on the plate's border (docked_walls.h): the chain edges are the
// plate's border edges, no fan edge. Hexes: 2 x 20 faces + 2 x 24 border edges (the plate's 16, 4 per wall) = 88.
// Vertices: 9 interior x 3 + 16 plate border x 6 + 6 wall far x 6 = 159. Every hex valid at radius 0.15 - 0.75 (0.5 -
// 2.5 x 0.3); the worst is the wall's end half-chunk (one row: 0.500, bench/flange_dock_sj.py) or, here, next to the
// plate's corner (x = (0, 0) beyond the end (1, 0)).
// The same walls on the chain (0, 0) -> (1, 0) -> (2, 0) from the plate's corner, the corner (0, 0) (and the walls'
// vertices above and below it) moved to (0.6, -0.6): the plate's border turns there by 54 degrees, more than
// kCornerCubeMaxSkewDeg off a right angle, so no corner cube (RawMesh.FlangeFromThePlatesCornerGetsACornerCube) and
// the chain stays a fan (the paper's layout with the fan end's out column): 2 x 20 + 2 x 22 = 84 hexes. Its fan end
// (2, 0) has O_w between the walls' out (+x) and the plate's (-y), O_w = w + r (1, -1, 0) / sqrt 2, and the gap
// vertex above the plate on the bisector of the plate and the wall, w + r (0, 1, 1) / sqrt 2.
TEST(RawMesh, FlangeWithWallsAboveAndBelowHasNoInvertedHex) {
    {
        Skeleton s = plate_with_walls(4, 4, {1, 2, 3}, true, true);
        const test::RawRun r = test::checked_raw_mesh(s);
        EXPECT_EQ(r.analysis.counts.fan_edges, 0);
        EXPECT_EQ(r.predicted.hexes, 88);
        EXPECT_EQ(r.predicted.vertices, 159);
        EXPECT_TRUE(r.valid);
        EXPECT_EQ(r.quality.inverted, 0);
        for (double scale : {0.5, 1.5, 2.5}) {
            s.radii.assign(s.points.size(), 0.3 * scale);
            EXPECT_EQ(test::checked_raw_mesh(s).quality.inverted, 0) << scale;
        }
    }
    Skeleton s = plate_with_walls(4, 4, {0, 1, 2}, true, true);
    for (int v : {0, 25, 28}) s.points[v] += Vec3{0.6, -0.6, 0};  // the corner and the walls' vertices on it
    const test::RawRun r = test::checked_raw_mesh(s);
    EXPECT_EQ(r.analysis.counts.fan_edges, 2);
    EXPECT_EQ(r.predicted.hexes, 84);
    EXPECT_TRUE(r.valid);
    EXPECT_EQ(r.quality.inverted, 0);
    for (double scale : {0.5, 1.5}) {
        s.radii.assign(s.points.size(), 0.3 * scale);
        EXPECT_EQ(test::checked_raw_mesh(s).quality.inverted, 0) << scale;
    }
    s.radii.assign(s.points.size(), 0.3);
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const RawMesh raw = build_raw_mesh(s, an, cs, propagate_frames(s, an, cs));
    const double q = 0.3 / std::sqrt(2.0);
    const int base = raw.vertex_base[2];  // fan end (2, 0): centre, 3 gap vertices, O_w, 3 out-copies
    ASSERT_EQ(an.vertex_class[2], VertexClass::FanEdgeEnd);
    const Vec3& o = raw.mesh.points[base + 4];
    EXPECT_NEAR(distance(o, Vec3{2 + q, -q, 0}), 0, 1e-12);
    int above = 0;
    for (int j = 1; j <= 3; ++j) above += distance(raw.mesh.points[base + j], Vec3{2, q, q}) < 1e-12;
    EXPECT_EQ(above, 1);
}

// A flange from the plate's corner: plate(4, 4) with walls one row high above and below on the chain (0, 0) -> (1, 0)
// -> (2, 0) of its border side y = 0 from the corner c = (0, 0) (docs/blocks.md, "Flanges from the plate's corner: the
// corner cube"). Docked on the plate's border with a corner cube at c: hexes 2 x 20 faces + 2 x 24 border edges (the
// plate's 16 with the chain, 4 per wall) + 2 (the cube) = 90; vertices 9 interior x 3 + 15 plate border x 6 + 12 (c)
// + 6 wall far x 6 = 165. c's ids: centre, up, down, K (-r, -r, 0) with its up / down copies, then the columns
// (0, -r, 0) (the chain edge's: the plate's face (0, 1, 6, 5) leaves c by it) and (-r, 0, 0), each with up and down
// copies r z off; the 2 cube hexes are boxes r x r x r (scaled Jacobian 1), and the edge c - up(c) has 4 hexes (the
// plate, two half-chunks, the cube): 2 interior irregular edges fewer than at a plain corner (valence 3).
TEST(RawMesh, FlangeFromThePlatesCornerGetsACornerCube) {
    for (double r : {0.3, 0.45, 0.75}) {
        SCOPED_TRACE(r);
        Skeleton s = plate_with_walls(4, 4, {0, 1, 2}, true, true);
        s.radii.assign(s.points.size(), r);
        const test::RawRun run = test::checked_raw_mesh(s);
        EXPECT_EQ(run.analysis.counts.fan_edges, 0);
        ASSERT_TRUE(has_corner_cube(run.analysis, 0));
        EXPECT_EQ(std::count(run.analysis.corner_cube.begin(), run.analysis.corner_cube.end(), char{1}), 1);
        EXPECT_EQ(run.predicted.hexes, 90);
        EXPECT_EQ(run.predicted.vertices, 165);
        EXPECT_TRUE(run.valid);
        EXPECT_EQ(run.quality.euler_characteristic, 1);
        EXPECT_EQ(run.quality.inverted, 0);
        const ConnectionSurfaces cs = build_connection_surfaces(s, run.analysis);
        RawMeshOptions placed;  // the frames' placement (no leaflet offset limit above r = L / 2)
        placed.leaflet_offset_fraction = 0;
        const RawMesh raw = build_raw_mesh(s, run.analysis, cs, propagate_frames(s, run.analysis, cs), placed);
        const int base = raw.vertex_base[0];
        const std::vector<Vec3>& p = raw.mesh.points;
        const Vec3 z{0, 0, r};
        const std::array<Vec3, 3> column{Vec3{-r, -r, 0}, Vec3{0, -r, 0}, Vec3{-r, 0, 0}};
        for (int j = 0; j < 3; ++j) {
            EXPECT_NEAR(distance(p[base + 3 + 3 * j], column[j]), 0, 1e-12) << j;
            EXPECT_NEAR(distance(p[base + 4 + 3 * j], column[j] + z), 0, 1e-12) << j;
            EXPECT_NEAR(distance(p[base + 5 + 3 * j], column[j] - z), 0, 1e-12) << j;
        }
        const std::vector<double> sj = scaled_jacobians(raw.mesh);
        int cube_hexes = 0;
        for (std::size_t h = 0; h < raw.mesh.hexes.size(); ++h) {
            const std::array<int, 8>& hx = raw.mesh.hexes[h];
            if (std::find(hx.begin(), hx.end(), base + 3) == hx.end()) continue;  // K is in the cube hexes only
            ++cube_hexes;
            EXPECT_NEAR(sj[h], 1, 1e-12);
        }
        EXPECT_EQ(cube_hexes, 2);
        EXPECT_EQ(run.predicted.interior_irregular_edges.count(3) ? run.predicted.interior_irregular_edges.at(3) : 0,
                  (3 + 4) * 2);  // the plate's other 3 corners and the walls' 4 top corners (1 face + 2
                                 // half-chunks), up and down
    }
}

// The corner cube's foot and a branch rooted on a border's out faces are told apart whatever the numbering: a flange
// from the plate's corner plus a branch out of the border vertex (2, 0, 0) along +x is accepted, and stays accepted
// with the corner vertex renumbered to the id of a border edge at the branch's root (a shared key kind once made the
// second numbering a "foot on the same plate faces" refusal).
TEST(RawMesh, CornerCubeFootAndBorderBranchKeysDoNotDependOnNumbering) {
    Skeleton s = generate_skeleton("flangecorner", GeneratorOptions{});
    const int nv = static_cast<int>(s.points.size());
    int root = -1;
    for (int v = 0; v < nv; ++v)
        if (norm(s.points[v] - Vec3{2, 0, 0}) < 1e-9) root = v;
    ASSERT_GE(root, 0);
    s.points.push_back({3, 0, 0});
    s.points.push_back({4, 0, 0});
    s.radii.push_back(0.3);
    s.radii.push_back(0.3);
    s.edges.push_back({root, nv});
    s.edges.push_back({nv, nv + 1});
    const SkeletonAnalysis first = analyze_skeleton(s);
    const int corner = static_cast<int>(std::find(first.corner_cube.begin(), first.corner_cube.end(), char{1}) -
                                        first.corner_cube.begin());
    ASSERT_LT(corner, nv);
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e) {
        if (first.edge_degree[e] != 1 || (s.edges[e][0] != root && s.edges[e][1] != root)) continue;
        if (e >= nv + 2 || e == corner) continue;
        SCOPED_TRACE("corner renumbered to " + std::to_string(e));
        Skeleton swapped = s;  // vertices corner and e exchange ids
        const auto renumber = [&](int& w) { w = w == corner ? e : w == e ? corner : w; };
        std::swap(swapped.points[corner], swapped.points[e]);
        std::swap(swapped.radii[corner], swapped.radii[e]);
        for (auto& edge : swapped.edges) renumber(edge[0]), renumber(edge[1]);
        for (auto& face : swapped.faces)
            for (int& w : face) renumber(w);
        SkeletonAnalysis second;
        ASSERT_NO_THROW(second = analyze_skeleton(swapped));
        EXPECT_EQ(second.counts.fan_edges, first.counts.fan_edges);
        EXPECT_EQ(second.predicted_hexes, first.predicted_hexes);
        EXPECT_EQ(second.corner_cube[e], 1);
    }
}

// A T fan on the 2-edge fan line (0, 0, 0) -> (0, 0, 2): three strips of 2 unit quads at 120 degrees, strip A (along
// +x) twisted, its far corners at y = -0.6, 0, 0.6. At the fan vertex (0, 0, 1) every gap has 2 faces of each of its
// two leaflets, but A's two face normals differ (by 32 degrees), so the narrowest cone's axis around a gap's 4
// normals is not their unit sum. The gap vertices stay on the unit sum (the bisector of the paper): the axis is for a
// gap with more faces of one leaflet than the other (a plate running on past a fan end), not for a twisted leaflet.
TEST(RawMesh, GapVertexOfABalancedGapStaysOnTheNormalSum) {
    Skeleton s;
    s.points = {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {1, -0.6, 0}, {1, 0, 1}, {1, 0.6, 2}};
    const double c = -0.5, sn = std::sqrt(3.0) / 2;
    for (double sy : {1.0, -1.0})
        for (double z : {0.0, 1.0, 2.0}) s.points.push_back({c, sy * sn, z});
    s.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}, {0, 1, 7, 6}, {1, 2, 8, 7}, {0, 1, 10, 9}, {1, 2, 11, 10}};
    add_face_edges(s);
    s.radii.assign(s.points.size(), 0.3);
    const test::RawRun r = test::checked_raw_mesh(s);
    EXPECT_TRUE(r.valid);
    EXPECT_EQ(r.quality.inverted, 0);
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const RawMesh raw = build_raw_mesh(s, an, cs, propagate_frames(s, an, cs));
    ASSERT_EQ(an.vertex_class[1], VertexClass::FanEdgeVertex);  // its raw vertices: the centre, then its 3 gap vertices
    // Each leaflet's 2 face normals at (0, 0, 1), summed; a gap's bisector is the unit sum of two leaflets' sums, each
    // flipped into the gap: one of 3 pairs x 4 signs.
    std::vector<Vec3> leaflet_sum(3);
    for (int f = 0; f < 6; ++f) leaflet_sum[static_cast<std::size_t>(f / 2)] += an.face_normal[f];
    for (int j = 1; j <= 3; ++j) {
        const Vec3 d = (raw.mesh.points[raw.vertex_base[1] + j] - s.points[1]) / 0.3;
        double best = 1;
        for (int a = 0; a < 3; ++a)
            for (double sa : {1.0, -1.0})
                for (double sb : {1.0, -1.0}) {
                    const Vec3 bisector = normalized(sa * leaflet_sum[a] + sb * leaflet_sum[(a + 1) % 3]);
                    best = std::min(best, distance(d, bisector));
                }
        EXPECT_LT(best, 1e-12) << j;
    }
}

// RawMeshOptions::bridge_quad_radius on a fat degree-4 junction (r 0.6 at the origin, arms of length 2.4 along -x, +y,
// -y) joined by a bridge of length 0.7 to a thin degree-3 junction (r 0.3, two arms): the bridge's margin limit
// shrinks the fat junction's whole sphere to rr < 0.6 (off). On, only the surface points of its quad on the bridge
// (corners and side midpoints) keep rr; every other surface point goes back to the input radius 0.6 and the
// midpoint of an edge from a limited to a free point to the mean radius; no hex at the junction falls below min(0.3,
// before); on is the default (with bridge_quad_inset, set to 0 here: the raise onto the ball alone).
// The fat junction's quad on the bridge (edge 0, side 0) of the two bridge-quad tests below: its 4 corners and 4 side
// midpoints marked among the np points and ne edge midpoints of the connection surfaces.
static std::vector<bool> bridge_quad_marks(const ConnectionSurfaces& cs, int np, int ne) {
    const int gq = cs.edge_quad[0][0];
    std::vector<bool> limited(static_cast<std::size_t>(np + ne), false);
    for (int k = 0; k < 4; ++k) {
        limited[static_cast<std::size_t>(cs.quads[gq][k])] = true;
        limited[static_cast<std::size_t>(np + cs.quad_edges[gq][k])] = true;
    }
    return limited;
}

TEST(RawMesh, BridgeQuadRadiusKeepsTheFatJunctionsOtherPointsOnItsBall) {
    Skeleton s;
    s.points = {{0, 0, 0}, {0.7, 0, 0}, {-2.4, 0, 0}, {0, 2.4, 0}, {0, -2.4, 0}, {1.8, 0, 1.0}, {1.8, 0, -1.0}};
    s.radii = {0.6, 0.3, 0.3, 0.3, 0.3, 0.2, 0.2};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 5}, {1, 6}};
    const SkeletonAnalysis an = analyze_skeleton(s);
    ASSERT_EQ(an.vertex_class[0], VertexClass::BranchingPoint);
    ASSERT_EQ(an.vertex_class[1], VertexClass::BranchingPoint);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const BranchFrames fr = propagate_frames(s, an, cs);
    EXPECT_TRUE(RawMeshOptions{}.bridge_quad_radius);
    RawMeshOptions off_options, on_options;
    off_options.bridge_quad_radius = false;
    on_options.bridge_quad_inset = 0.0;  // the raise onto the ball alone (the inset: the next test)
    const RawMesh off = build_raw_mesh(s, an, cs, fr, off_options);
    const RawMesh on = build_raw_mesh(s, an, cs, fr, on_options);
    const int np = cs.point_begin[1] - cs.point_begin[0], ne = cs.edge_begin[1] - cs.edge_begin[0];
    const auto dist = [&](const RawMesh& raw, int x) {
        return distance(raw.mesh.points[raw.vertex_base[0] + 1 + x], s.points[0]);
    };
    const double rr = dist(off, 0);
    EXPECT_LT(rr, 0.6 - 1e-3);
    for (int x = 0; x < np + ne; ++x) EXPECT_NEAR(dist(off, x), rr, 1e-12);
    const std::vector<bool> limited = bridge_quad_marks(cs, np, ne);
    int raised = 0;
    for (int x = 0; x < np; ++x) {
        EXPECT_NEAR(dist(on, x), limited[static_cast<std::size_t>(x)] ? rr : 0.6, 1e-12);
        raised += limited[static_cast<std::size_t>(x)] ? 0 : 1;
    }
    EXPECT_GT(raised, 0);
    for (int j = 0; j < ne; ++j) {
        const std::array<int, 2>& ed = cs.edges[cs.edge_begin[0] + j];
        const double mean = 0.5 * (dist(on, ed[0]) + dist(on, ed[1]));
        EXPECT_NEAR(dist(on, np + j), limited[static_cast<std::size_t>(np + j)] ? rr : mean, 1e-12);
    }
    const std::vector<double> before = scaled_jacobians(off.mesh), after = scaled_jacobians(on.mesh);
    double worst_before = 1, worst_after = 1;
    for (std::size_t h = 0; h < before.size(); ++h) {
        worst_before = std::min(worst_before, before[h]);
        worst_after = std::min(worst_after, after[h]);
    }
    EXPECT_GE(worst_after, std::min(0.3, worst_before));
    // The thin junction keeps its points (its own radius is not limited by the fat one's quad here).
    for (int x = 0; x < cs.point_begin[2] - cs.point_begin[1]; ++x)
        EXPECT_EQ(on.mesh.points[on.vertex_base[1] + 1 + x], off.mesh.points[off.vertex_base[1] + 1 + x]);
}

// Issue 16 item 5: a radius jump along a branch is not what breaks the armadillo's minimum (docs/junctions.md, "The
// armadillo's claw"). Two generated cases of the jump its report named (a radius 2.6 x larger on one side, over an
// edge of 1.5 x the small radius), adapted with the defaults: (a) a straight branch, r 0.1 -> 0.1 / 2.6 between x =
// 0.5 and 0.56; (b) a fat branch (r 2.6 r_c) ending 2.7 r_c from a thin degree-3 point (r_c = 0.04) whose two thin
// branches leave at +-35 degrees (one tapering to 0.04 r_c): the armadillo's v74 next to its 2.6 x fatter parent.
// Measured raw min SJ 0.59 and 0.38 (the CLI's finished meshes of their thickened domains: 0.70 / 0.93 / 0.33 % and
// 0.73 / 0.94 / 0.44 %); asserted with a tolerance of 0.05 below them, nothing inverted.
TEST(RawMesh, RadiusJumpAlongABranchKeepsItsRawHexesAboveTheTargets) {
    const double rc = 0.04;
    Skeleton line;
    const std::vector<double> xs = {0, 0.2, 0.4, 0.5, 0.56, 0.7, 0.85, 1.0};
    for (std::size_t i = 0; i < xs.size(); ++i) {
        line.points.push_back({xs[i], 0, 0});
        line.radii.push_back(i < 4 ? 0.1 : 0.1 / 2.6);
        if (i > 0) line.edges.push_back({static_cast<int>(i) - 1, static_cast<int>(i)});
    }
    Skeleton fork;
    fork.points = {{-0.6, 0, 0}, {-0.3, 0, 0}, {0, 0, 0}, {2.7 * rc, 0, 0}};
    fork.radii = {2.6 * rc, 2.6 * rc, 2.6 * rc, rc};
    fork.edges = {{0, 1}, {1, 2}, {2, 3}};
    const double a = 35 * std::numbers::pi / 180;
    for (const double side : {1.0, -1.0}) {
        for (int k = 1; k <= 4; ++k) {
            const double t = 0.1 * k;
            fork.points.push_back({2.7 * rc + t * std::cos(a), side * t * std::sin(a), 0});
            fork.radii.push_back(side > 0 ? rc : rc * (1 - 0.24 * k));
            const int v = static_cast<int>(fork.points.size()) - 1;
            fork.edges.push_back({k == 1 ? 3 : v - 1, v});
        }
    }
    const std::vector<std::pair<Skeleton, double>> cases = {{line, 0.59}, {fork, 0.38}};
    for (const auto& [s, measured] : cases) {
        SCOPED_TRACE(measured);
        const test::RawRun r = test::checked_raw_mesh(adapt_skeleton(s));
        EXPECT_TRUE(r.valid);
        EXPECT_EQ(r.quality.inverted, 0);
        EXPECT_GE(r.quality.sj_min, measured - 0.05);
    }
}

// RawMeshOptions::bridge_quad_inset on a degree-4 junction like the one above (r 0.6 at the origin, arms of length 2.4
// along -x, +y, -y) with a shorter bridge, 0.5 along +x, to a degree-3 junction (r 0.3). With the points raised onto
// the ball (inset 0), each of the 2 points off the bridge quad has a shortest raw boundary edge e_x (0.4303 for the
// limit rr 0.3921, on paper below); with inset 0.25 it stands at exactly 0.6 - 0.25 e_x = 0.4924 (one padding layer
// inside the ball, so the padding's offset of 0.25 x its shortest edge ends on the ball), the bridge quad's 4 points
// keep rr, the midpoints of the other edges lie at the mean of their ends; no junction hex below min(0.3, before); the
// defaults are the raise with inset 0.25.
TEST(RawMesh, BridgeQuadInsetStopsTheRaisedPointsOneLayerShort) {
    Skeleton s;
    s.points = {{0, 0, 0}, {0.5, 0, 0}, {-2.4, 0, 0}, {0, 2.4, 0}, {0, -2.4, 0}, {1.6, 0, 1.0}, {1.6, 0, -1.0}};
    s.radii = {0.6, 0.3, 0.3, 0.3, 0.3, 0.2, 0.2};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 5}, {1, 6}};
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an);
    const BranchFrames fr = propagate_frames(s, an, cs);
    EXPECT_EQ(RawMeshOptions{}.bridge_quad_inset, 0.25);
    RawMeshOptions off_options, raise;
    off_options.bridge_quad_radius = false;
    raise.bridge_quad_inset = 0.0;
    RawMeshOptions inset = raise;
    inset.bridge_quad_inset = 0.25;
    const RawMesh off = build_raw_mesh(s, an, cs, fr, off_options);
    const RawMesh raised = build_raw_mesh(s, an, cs, fr, raise);
    const RawMesh on = build_raw_mesh(s, an, cs, fr, inset);
    EXPECT_EQ(build_raw_mesh(s, an, cs, fr).mesh.points, on.mesh.points);  // the defaults
    const int np = cs.point_begin[1] - cs.point_begin[0], ne = cs.edge_begin[1] - cs.edge_begin[0];
    const int base = raised.vertex_base[0];
    const auto dist = [&](const RawMesh& raw, int x) { return distance(raw.mesh.points[base + 1 + x], s.points[0]); };
    const double rr = dist(off, 0);
    // Shortest raw boundary edge of each raised point, measured on the raised mesh.
    const HexTopology topo = compute_hex_topology(raised.mesh);
    std::vector<double> shortest(raised.mesh.points.size(), 1e9);
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        if (!topo.edge_on_boundary[e]) continue;
        const auto [a, b] = topo.edges[e];
        const double len = distance(raised.mesh.points[a], raised.mesh.points[b]);
        shortest[a] = std::min(shortest[a], len);
        shortest[b] = std::min(shortest[b], len);
    }
    const std::vector<bool> limited = bridge_quad_marks(cs, np, ne);
    int inset_points = 0;
    for (int x = 0; x < np; ++x) {
        if (limited[static_cast<std::size_t>(x)]) {
            EXPECT_NEAR(dist(on, x), rr, 1e-12);
            continue;
        }
        const double e = shortest[static_cast<std::size_t>(base + 1 + x)];
        // On paper: the four arms lie in a plane 90 degrees apart, so the junction is an orange with poles +-z and
        // its free points on the bisectors (-1, +-1, 0) / sqrt 2; the shortest boundary edge runs from such a point
        // (at 0.6) to the midpoint of its edge to a pole (45 degrees away, at the mean (0.6 + rr) / 2).
        const double mid = 0.5 * (0.6 + rr);
        EXPECT_NEAR(e, std::sqrt(0.36 + mid * mid - 2 * 0.6 * mid * std::sqrt(0.5)), 1e-9);
        EXPECT_NEAR(std::abs(dot(normalized(raised.mesh.points[base + 1 + x] - s.points[0]), Vec3{0, 0, 1})), 0, 1e-9);
        EXPECT_NEAR(dist(raised, x), 0.6, 1e-12);
        EXPECT_NEAR(dist(on, x), std::max(rr, 0.6 - 0.25 * e), 1e-12) << x;
        EXPECT_LT(dist(on, x), 0.6 - 1e-3);
        EXPECT_GT(dist(on, x), rr + 1e-3);
        ++inset_points;
    }
    EXPECT_EQ(inset_points, 2);  // 6 points, 4 of them on the bridge quad
    for (int j = 0; j < ne; ++j) {
        const std::array<int, 2>& ed = cs.edges[cs.edge_begin[0] + j];
        const double mean = 0.5 * (dist(on, ed[0]) + dist(on, ed[1]));
        EXPECT_NEAR(dist(on, np + j), limited[static_cast<std::size_t>(np + j)] ? rr : mean, 1e-12);
    }
    const std::vector<double> before = scaled_jacobians(off.mesh), after = scaled_jacobians(on.mesh);
    EXPECT_GE(*std::min_element(after.begin(), after.end()),
              std::min(0.3, *std::min_element(before.begin(), before.end())));
}

// Dinopet's torso (docs/junctions.md, "Corners behind the branch"): a body through c (+-x) and two legs whose chords
// lean by beta = 46 degrees towards -y, (0, -sin beta, +-cos beta). The configuration is mirror-symmetric in x and in
// z, so the orange's axis is +-y, and the +y pole, a corner of every quad of the orange, lies 90 + beta = 136 degrees
// from each leg, behind it. On paper (in the plane through the leg and the pole): a leg chunk's boundary edge from
// the pole P = rho (cos a, sin a), a = 136 degrees, to its section's corner Q on the same side, at L along the leg
// with radius s, passes |P x Q| / |P - Q| from c: for rho = r = 0.5, L = 1.2, s = 0.25 that is 0.324 = 0.65 r,
// against 0.490 = 0.98 r for a pole at a = 90 degrees. So the raw boundary next to the pole dips inside c's ball.
TEST(RawMesh, LeaningLegsPutTheOrangesPoleBehindThem) {
    const double beta = 46 * std::numbers::pi / 180;
    const std::vector<Vec3> dirs{
        {1, 0, 0}, {0, -std::sin(beta), std::cos(beta)}, {-1, 0, 0}, {0, -std::sin(beta), -std::cos(beta)}};
    Skeleton s = star(dirs, 1, 1.2);
    s.radii.assign(s.points.size(), 0.25);
    s.radii[0] = 0.5;
    const SkeletonAnalysis an = analyze_skeleton(s);
    ConnectionSurfaceOptions co;
    co.blocks.enabled = false;
    const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
    const int p0 = cs.point_begin[0], np = cs.point_begin[1] - p0, q0 = cs.quad_begin[0];
    ASSERT_EQ(np, 6);
    int behind = -1;  // the pole on +y
    for (int x = 0; x < np; ++x)
        if (cs.point_valence[p0 + x] == 4 && cs.directions[p0 + x].y > 0) behind = x;
    ASSERT_GE(behind, 0);
    const Vec3 pole = cs.directions[p0 + behind];
    EXPECT_NEAR(pole.y, 1.0, 1e-6);
    for (int q = 0; q < 4; ++q)  // on every quad: the bridge's too, were one of the body's edges a bridge
        EXPECT_NE(std::ranges::find(cs.quads[q0 + q], behind), cs.quads[q0 + q].end());
    for (const int leg : {1, 3}) EXPECT_NEAR(std::acos(dot(pole, dirs[leg])) * 180 / std::numbers::pi, 136.0, 1e-4);
    // The paper value above, from the raw mesh: the nearest to c of the leg chunks' boundary edges from the pole (its
    // radius is r: no bridge here; the pole at 90 degrees would give 0.490).
    const BranchFrames fr = propagate_frames(s, an, cs);
    const RawMesh raw = build_raw_mesh(s, an, cs, fr);
    const int pole_id = raw.vertex_base[0] + 1 + behind;
    const auto segment_distance = [](const Vec3& a, const Vec3& b) {  // from the origin
        const Vec3 d = b - a;
        const double t = std::clamp(-dot(a, d) / dot(d, d), 0.0, 1.0);
        return norm(a + t * d);
    };
    double nearest = 1e9;
    for (std::size_t h = 0; h < raw.mesh.hexes.size(); ++h) {
        const std::array<int, 8>& hx = raw.mesh.hexes[h];
        const int e = raw.hex_edge[h];
        const int arm = s.edges[e][0] == 0 ? s.edges[e][1] : s.edges[e][0];
        if (arm != 2 && arm != 4) continue;  // the legs' chunks (star: arm i ends at vertex i + 1)
        for (int lv = 0; lv < 4; ++lv)
            if (hx[lv] == pole_id)
                nearest = std::min(nearest, segment_distance(raw.mesh.points[hx[lv]], raw.mesh.points[hx[lv + 4]]));
    }
    EXPECT_NEAR(nearest, 0.32425, 1e-4);  // the paper value: the matched section corner lies in that plane
    EXPECT_NEAR(raw.mesh.points[pole_id].y, 0.5, 1e-6);
}

TEST(RawMeshLeaflets, CreaseCopiesOnTheConcaveSideStopBeforeTheyPassEachOther) {
    // A V of two unit squares meeting at the crease x = 0, each 30 degrees off the horizontal (face normals 60 degrees
    // apart), radius 2.5. A crease vertex's normal is vertical; an outer vertex's is its face's normal, which is
    // perpendicular to the side from the crease. Along that side (length 1) the crease vertex's up copy moves
    // r sin 30 = 1.25 towards the outer vertex and the outer vertex's none: the copies pass each other (inverted
    // hexes). With leaflet_offset_fraction 0.5 the pair may close in by 0.5 x 1 at most: both up copies go
    // 0.5 / sin 30 = 1.0 (factor 0.4; the diagonals allow 0.8, the crease side and the outer sides 1); every down copy
    // (the convex side) stays at 2.5.
    const double c = std::cos(std::numbers::pi / 6), s30 = 0.5;
    Skeleton s;
    s.points = {{0, 0, 0}, {0, 1, 0}, {-c, 0, s30}, {-c, 1, s30}, {c, 0, s30}, {c, 1, s30}};
    s.faces = {{0, 1, 3, 2}, {4, 5, 1, 0}};
    add_face_edges(s);
    s.radii.assign(s.points.size(), 2.5);
    SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an, ConnectionSurfaceOptions{});
    const BranchFrames fr = propagate_frames(s, an, cs);
    RawMeshOptions o;
    ASSERT_EQ(o.leaflet_offset_fraction, 0.5);
    const RawMesh limited = build_raw_mesh(s, an, cs, fr, o);
    for (int v = 0; v < 6; ++v) {
        const int base = limited.vertex_base[v];
        for (int k : {1, 2}) {
            const Vec3 off = limited.mesh.points[base + k] - s.points[v];
            const bool concave = dot(off, Vec3{0, 0, 1}) > 0;
            EXPECT_NEAR(norm(off), concave ? 1.0 : 2.5, 1e-12) << "vertex " << v << " copy " << k;
        }
    }
    const QualityReport q = compute_quality(limited.mesh);
    EXPECT_EQ(q.hexes, 2 * 2 + 2 * 6);
    EXPECT_EQ(q.inverted, 0);
    o.leaflet_offset_fraction = 0;
    const RawMesh full = build_raw_mesh(s, an, cs, fr, o);
    EXPECT_NEAR(distance(full.mesh.points[full.vertex_base[0] + 1], s.points[0]), 2.5, 1e-12);
    EXPECT_GT(compute_quality(full.mesh).inverted, 0);
}

namespace {

// The out points of border edge e's half-chunk (a, out a, out b, b) from its up hex (a oa ob b | ...), and how far the
// two close in along a -> b (out a's lean towards b plus out b's towards a); a, b as the hex orders them.
struct SideOuts {
    Vec3 a, oa, ob, b;
    double closing = 0, length = 0;
};
SideOuts side_outs(const SkeletonAnalysis& an, const RawMesh& raw, int e) {
    SideOuts o;
    const auto centre = [&](int id) { return std::ranges::find(raw.vertex_base, id) != raw.vertex_base.end(); };
    for (std::size_t h = 0; h < raw.mesh.hexes.size(); ++h) {
        const std::array<int, 8>& hx = raw.mesh.hexes[h];
        if (raw.hex_edge[h] != e || an.edge_degree[e] != 1 || centre(hx[1])) continue;
        o.a = raw.mesh.points[hx[0]];
        o.oa = raw.mesh.points[hx[1]];
        o.ob = raw.mesh.points[hx[2]];
        o.b = raw.mesh.points[hx[3]];
    }
    o.length = distance(o.a, o.b);
    const Vec3 u = (o.b - o.a) / o.length;
    o.closing = dot(o.oa - o.a, u) + dot(o.b - o.ob, u);
    return o;
}

// A ring sector of 3 faces around the z axis: inner radius 1, outer 2, at 0, 30, 60, 90 degrees; radius 0.5 (the inner
// arc's chords L = 2 sin 15 degrees).
Skeleton ring_sector() {
    Skeleton s;
    for (const double rad : {1.0, 2.0})
        for (int k = 0; k <= 3; ++k) {
            const double t = k * std::numbers::pi / 6;
            s.points.push_back({rad * std::cos(t), rad * std::sin(t), 0});
        }
    for (int k = 0; k < 3; ++k) s.faces.push_back({k, 4 + k, 5 + k, k + 1});
    add_face_edges(s);
    s.radii.assign(s.points.size(), 0.5);
    return s;
}

}  // namespace

TEST(RawMeshLeaflets, OutPointsOnAConcaveBorderCloseInByAtMostTheOutFraction) {
    // A ring sector of 3 faces around the z axis: inner radius 1, outer 2, at 0, 30, 60, 90 degrees; radius 0.5. The
    // inner arc is concave: its middle vertices 1 and 2 (reflex, 210 degrees) have their out rays along -radial, so
    // along their side (length L = 2 sin 15 degrees) they close in by 2 d sin 15 = d x L (d their out distance, the
    // arc's radius 1): d = 0.5 (leaflet_out_distance's reflex limit 0.3 L / sin 15 = 0.6 does not act) closes in by
    // 0.5 L. With leaflet_out_fraction 0.3 both go to d = 0.3 exactly (factor 0.6); their sides to the corners 0 and
    // 3 close in by less (the corners' outs lean away), so every other out point stays.
    const Skeleton s = ring_sector();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an, ConnectionSurfaceOptions{});
    const BranchFrames fr = propagate_frames(s, an, cs);
    RawMeshOptions o;
    ASSERT_EQ(o.leaflet_out_fraction, 0);  // off by default
    const RawMesh off = build_raw_mesh(s, an, cs, fr, o);
    o.leaflet_out_fraction = 0.3;
    const RawMesh on = build_raw_mesh(s, an, cs, fr, o);
    for (const int v : {1, 2}) {
        ASSERT_EQ(an.vertex_class[v], VertexClass::LeafletBoundary);
        const Vec3 inward = -1.0 * s.points[v];  // unit: the inner arc has radius 1
        for (int k = 3; k <= 5; ++k) {           // out, out-up, out-down: the column moves as one
            const Vec3 before = off.mesh.points[off.vertex_base[v] + k], after = on.mesh.points[on.vertex_base[v] + k];
            EXPECT_NEAR(norm(after - before - (-0.2) * inward), 0.0, 1e-12) << "vertex " << v << " id " << k;
        }
        EXPECT_NEAR(distance(off.mesh.points[off.vertex_base[v] + 3], s.points[v]), 0.5, 1e-12);
        EXPECT_NEAR(distance(on.mesh.points[on.vertex_base[v] + 3], s.points[v]), 0.3, 1e-12);
    }
    int side12 = -1;
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e)
        if (std::min(s.edges[e][0], s.edges[e][1]) == 1 && std::max(s.edges[e][0], s.edges[e][1]) == 2) side12 = e;
    ASSERT_GE(side12, 0);
    const SideOuts b = side_outs(an, off, side12), a = side_outs(an, on, side12);
    EXPECT_NEAR(b.closing, 0.5 * b.length, 1e-12);
    EXPECT_NEAR(a.closing, 0.3 * a.length, 1e-12);
    ASSERT_EQ(off.mesh.points.size(), on.mesh.points.size());
    int moved = 0;  // every other point where it was
    for (std::size_t id = 0; id < on.mesh.points.size(); ++id) moved += on.mesh.points[id] != off.mesh.points[id];
    EXPECT_EQ(moved, 6);
    const QualityReport q = compute_quality(on.mesh);
    EXPECT_EQ(q.hexes, 3 * 2 + 8 * 2);
    EXPECT_EQ(q.inverted, 0);
}

TEST(RawMeshLeaflets, ThickCornerJointsOutPointsStopShortOfTheirNeighbours) {
    // plate(3, 3) with a 3-edge branch leaving its corner 0 (a BL-joint) 30 degrees off the corner's outward bisector;
    // radius 1.6 at the corner (thicker than its unit border edges are long), 0.1 elsewhere. The joint's sphere
    // points that its two border half-chunks take as out points lean along their sides: with leaflet_out_fraction
    // 0, on one side they close in by more than the side (the out rays cross: an inverted half-chunk; measured
    // 1.33 and 0.89 x L); with 0.3 each of the two sides closes in by at most 0.3 of its length (both are pulled to
    // exactly that), and no hex of the mesh is inverted.
    Skeleton s = plate(3, 3);
    const double t = 255.0 * std::numbers::pi / 180;
    for (int k = 1, prev = 0; k <= 3; ++k) {
        s.points.push_back({k * std::cos(t), k * std::sin(t), 0});
        s.edges.push_back({prev, static_cast<int>(s.points.size()) - 1});
        prev = static_cast<int>(s.points.size()) - 1;
    }
    s.radii.assign(s.points.size(), 0.1);
    s.radii[0] = 1.6;
    const SkeletonAnalysis an = analyze_skeleton(s);
    ASSERT_EQ(an.vertex_class[0], VertexClass::BLJoint);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an, ConnectionSurfaceOptions{});
    const BranchFrames fr = propagate_frames(s, an, cs);
    RawMeshOptions o;
    o.leaflet_out_fraction = 0;
    const RawMesh off = build_raw_mesh(s, an, cs, fr, o);
    o.leaflet_out_fraction = 0.3;
    const RawMesh on = build_raw_mesh(s, an, cs, fr, o);
    double worst_off = 0, worst_on = 0;
    int sides = 0;
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e) {
        if (an.edge_degree[e] != 1 || (s.edges[e][0] != 0 && s.edges[e][1] != 0)) continue;
        ++sides;
        const SideOuts b = side_outs(an, off, e), a = side_outs(an, on, e);
        worst_off = std::max(worst_off, b.closing / b.length);
        worst_on = std::max(worst_on, a.closing / a.length);
    }
    EXPECT_EQ(sides, 2);
    EXPECT_GT(worst_off, 1.0);
    EXPECT_LE(worst_on, 0.3 + 1e-12);
    EXPECT_GT(compute_quality(off.mesh).inverted, 0);
    EXPECT_EQ(compute_quality(on.mesh).inverted, 0);
    // Junction ends only: the neighbours' short out rays (0.1) stay; the joint's out points alone make up the limit.
    o.leaflet_out_columns = false;
    const RawMesh joint = build_raw_mesh(s, an, cs, fr, o);
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e)
        if (an.edge_degree[e] == 1 && (s.edges[e][0] == 0 || s.edges[e][1] == 0)) {
            const SideOuts j = side_outs(an, joint, e), b = side_outs(an, off, e);
            EXPECT_LE(j.closing, 0.3 * j.length + 1e-12);
            const bool joint_first = j.a == s.points[0];
            EXPECT_EQ(joint_first ? j.ob : j.oa, joint_first ? b.ob : b.oa);  // the neighbour's out point
        }
    EXPECT_EQ(compute_quality(joint.mesh).inverted, 0);
}

TEST(RawMeshLeaflets, OutPointsOnAConcaveBorderLoseOnlyTheirLeanWithLeanOnly) {
    // The inner arc's middle vertices 1 and 2 have radial out rays (d = 0.5) leaning 0.5 sin 15 = L / 4 each along
    // their common side (1, 2): it closes in by L / 2. With leaflet_out_fraction 0.3 and lean_only both leans are cut
    // by one factor to 0.3 L / 2 = 0.3 sin 15 (k = 0.6): out 1 moves by 0.2 sin 15 along 2 -> 1 (out 2 along 1 -> 2),
    // its offset across the side stays 0.5 cos 15 and off the sheet 0, so its distance becomes
    // sqrt((0.5 cos 15)^2 + (0.3 sin 15)^2) instead of the pull's 0.3. On the sides to the corners 0 and 3 the outs
    // still close in by less than 0.3 L (out 1 now leans 0.5 sin 15 + 0.2 sin 15 cos 30 towards 0, corner 0's out
    // 0.5 cos 127.5 away from 1): no cap there, so the columns of 1 and 2 (6 points) are all that moves.
    const Skeleton s = ring_sector();
    const SkeletonAnalysis an = analyze_skeleton(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an, ConnectionSurfaceOptions{});
    const BranchFrames fr = propagate_frames(s, an, cs);
    RawMeshOptions o;
    ASSERT_FALSE(o.leaflet_out_lean_only);  // off by default
    const RawMesh off = build_raw_mesh(s, an, cs, fr, o);
    o.leaflet_out_fraction = 0.3;
    o.leaflet_out_lean_only = true;
    const RawMesh on = build_raw_mesh(s, an, cs, fr, o);
    const double s15 = std::sin(std::numbers::pi / 12), c15 = std::cos(std::numbers::pi / 12);
    const Vec3 u12 = normalized(s.points[2] - s.points[1]), up{0, 0, 1};
    const Vec3 across = cross(u12, up);  // in the plane, perpendicular to the side
    for (const int v : {1, 2}) {
        const Vec3 along = v == 1 ? u12 : -1.0 * u12;  // towards the other end of the side
        const Vec3 expected_move = -0.2 * s15 * along;
        for (int k = 3; k <= 5; ++k) {  // out, out-up, out-down: the column moves as one
            const Vec3 before = off.mesh.points[off.vertex_base[v] + k], after = on.mesh.points[on.vertex_base[v] + k];
            EXPECT_NEAR(norm(after - before - expected_move), 0.0, 1e-12) << "vertex " << v << " id " << k;
        }
        const Vec3 offset = on.mesh.points[on.vertex_base[v] + 3] - s.points[v];
        EXPECT_NEAR(dot(offset, along), 0.3 * s15, 1e-12);
        EXPECT_NEAR(std::abs(dot(offset, across)), 0.5 * c15, 1e-12);
        EXPECT_NEAR(dot(offset, up), 0.0, 1e-12);
        EXPECT_NEAR(norm(offset), std::hypot(0.5 * c15, 0.3 * s15), 1e-12);
    }
    int side12 = -1;
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e)
        if (std::min(s.edges[e][0], s.edges[e][1]) == 1 && std::max(s.edges[e][0], s.edges[e][1]) == 2) side12 = e;
    ASSERT_GE(side12, 0);
    EXPECT_NEAR(side_outs(an, off, side12).closing, 0.5 * 2 * s15, 1e-12);
    EXPECT_NEAR(side_outs(an, on, side12).closing, 0.3 * 2 * s15, 1e-12);
    int moved = 0;
    for (std::size_t id = 0; id < on.mesh.points.size(); ++id) moved += on.mesh.points[id] != off.mesh.points[id];
    EXPECT_EQ(moved, 6);
    EXPECT_EQ(compute_quality(on.mesh).inverted, 0);
}

TEST(RawMeshLeaflets, OutColumnTurnedTowardsABranchIsPulledNotSlidWithLeanOnly) {
    // plate_with_a_border_branch: the branch leaves the straight border y = 0 at vertex 1 = (1, 0, 0) in the plate's
    // plane, 55 degrees off the outward -y towards +x (BorderRoot::Out: at most 60); radius 1.5 at vertex 1, 0.1
    // elsewhere. Vertex 1's out column turns with the branch: out 1 = (1, 0, 0) + 1.5 (sin 55, -cos 55, 0) leans
    // 1.5 sin 55 = 1.229 towards corner 2 along their side (L = 1); corner 2's out leans 0.1 / sqrt 2 away from 1.
    // The side closes in by 1.5 sin 55 - 0.1 / sqrt 2 = 1.158 L: the out rays cross (out 1 lies beyond out 2 along
    // the side). The branch's first chunk stands on the patch of vertex 1's column, so lean_only pulls that column
    // towards vertex 1 (slid along the side, the patch would turn away from the branch and the chunk fold): by
    // k = (0.3 + 0.1 / sqrt 2) / (1.5 sin 55), the factor of the only positive lean, so the side closes in by exactly
    // 0.3; corner 2, leaning away, stays. No hex is inverted (4 of the branch's first chunk are, off).
    const double t = 55 * std::numbers::pi / 180, r = 1.5;
    Skeleton s = plate_with_a_border_branch({std::sin(t), -std::cos(t), 0});
    s.radii.assign(s.points.size(), 0.1);
    s.radii[1] = r;
    const SkeletonAnalysis an = analyze_skeleton(s);
    ASSERT_EQ(an.vertex_border_root[1], BorderRoot::Out);
    const ConnectionSurfaces cs = build_connection_surfaces(s, an, ConnectionSurfaceOptions{});
    const BranchFrames fr = propagate_frames(s, an, cs);
    int side12 = -1;
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e)
        if (std::min(s.edges[e][0], s.edges[e][1]) == 1 && std::max(s.edges[e][0], s.edges[e][1]) == 2) side12 = e;
    ASSERT_GE(side12, 0);
    RawMeshOptions o;
    const RawMesh off = build_raw_mesh(s, an, cs, fr, o);
    o.leaflet_out_fraction = 0.3;
    o.leaflet_out_lean_only = true;
    const RawMesh on = build_raw_mesh(s, an, cs, fr, o);
    EXPECT_NEAR(side_outs(an, off, side12).closing, r * std::sin(t) - 0.1 / std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(side_outs(an, on, side12).closing, 0.3, 1e-12);
    const double k = (0.3 + 0.1 / std::sqrt(2.0)) / (r * std::sin(t));
    const Vec3 out1 = Vec3{1, 0, 0} + k * r * Vec3{std::sin(t), -std::cos(t), 0};
    EXPECT_NEAR(distance(on.mesh.points[on.vertex_base[1] + 3], out1), 0.0, 1e-12);
    for (int id = 3; id <= 5; ++id)
        EXPECT_EQ(on.mesh.points[on.vertex_base[2] + id], off.mesh.points[off.vertex_base[2] + id]);
    EXPECT_EQ(compute_quality(off.mesh).inverted, 4);
    EXPECT_EQ(compute_quality(on.mesh).inverted, 0);
}

// A short bridge with a bulge (JunctionCoverOptions::bridge_bulge): branching points A = (0, 0, 0) and B = (0.5, 0, 0),
// each with two limbs of one edge (length 0.5, 50 degrees off the torso's outward direction, in the x-y plane), radius
// 0.1 everywhere in the meshed skeleton. The domain skeleton has the bridge as A - P - B with P = (0.25, 0, 0):
// radius r_P 0.25 (bulged) or 0.1 (straight). The bridge test samples p = A + s (B - A), s = 1/16 .. 15/16: at s = 1/2
// the depth is P's radius, 0.25 = 2.5 x the ends' interpolated 0.1 (>= 1.5 x: A and B marked, also when the meshed
// bridge has a joint at P's place: the samples then run along its two edges, the same points); in the straight domain
// no point of the segment is deeper than 0.1 (< 1.5 x 0.1: nothing marked), and nothing is marked at ratio 2.6 either
// (the bulged depth elsewhere on the segment is below P's: A - P is a round cone from 0.1 to 0.25 whose depth on its
// axis is its radius there). On paper the raw mesh has 5 branch edges x 4 hexes = 20 hexes, the prediction, whatever
// the cover does (it only moves points), and is one ball (Euler characteristic 1). Covered from both ends, A's and B's
// surface points move out along their rays, never farther than the cover's march, (arc + 1) r = 0.4 from their
// centre, with no hex below min(0.3, before); with the straight domain the option leaves the raw mesh exactly as the
// cover off, while the cover of every junction (bridge_bulge 0) moves the points between the limbs.
TEST(JunctionCover, BulgedBridgeIsCoveredFromBothEnds) {
    const double r = 0.1, a = 50 * std::numbers::pi / 180, arm = 0.5;
    Skeleton s;
    s.points = {{0, 0, 0},
                {0.5, 0, 0},
                {-arm * std::cos(a), arm * std::sin(a), 0},
                {-arm * std::cos(a), -arm * std::sin(a), 0},
                {0.5 + arm * std::cos(a), arm * std::sin(a), 0},
                {0.5 + arm * std::cos(a), -arm * std::sin(a), 0}};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}};
    s.radii.assign(s.points.size(), r);
    auto domain_with_peak = [&](double rp) {
        Skeleton d = s;
        d.points.push_back({0.25, 0, 0});
        d.radii.push_back(rp);
        d.edges = {{0, 6}, {6, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}};
        return d;
    };
    const Skeleton bulged = domain_with_peak(0.25), straight = domain_with_peak(0.1);
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(bulged_bridge_ends(s, bulged, an, 1.5), (std::vector<char>{1, 1, 0, 0, 0, 0}));
    EXPECT_EQ(bulged_bridge_ends(s, bulged, an, 2.6), (std::vector<char>(6, 0)));
    EXPECT_EQ(bulged_bridge_ends(s, straight, an, 1.5), (std::vector<char>(6, 0)));
    {  // the same bridge meshed with a joint J = (0.25, 0, 0) in the middle: a bridge of two edges, the same samples
        Skeleton j = s;
        j.points.push_back({0.25, 0, 0});
        j.radii.push_back(r);
        j.edges = {{0, 6}, {6, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}};
        const SkeletonAnalysis aj = analyze_skeleton(j);
        EXPECT_EQ(bulged_bridge_ends(j, bulged, aj, 1.5), (std::vector<char>{1, 1, 0, 0, 0, 0, 0}));
        EXPECT_EQ(bulged_bridge_ends(j, straight, aj, 1.5), (std::vector<char>(7, 0)));
    }
    ConnectionSurfaceOptions co;
    co.blocks.enabled = false;
    const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
    const BranchFrames fr = propagate_frames(s, an, cs);
    auto raw = [&](double fraction, double bulge, const Skeleton& domain) {
        RawMeshOptions o;
        o.cover.fraction = fraction;
        o.cover.bridge_bulge = bulge;
        return build_raw_mesh(s, an, cs, fr, o, &domain);
    };
    const RawMesh off = raw(0.0, 0.0, bulged), on = raw(1.0, 1.5, bulged);
    EXPECT_EQ(an.predicted_hexes, 20);
    EXPECT_EQ(on.mesh.hexes.size(), 20u);
    const QualityReport qo = compute_quality(off.mesh), qn = compute_quality(on.mesh);
    EXPECT_EQ(qn.euler_characteristic, 1);
    EXPECT_EQ(qn.inverted, 0);
    const std::vector<double> before = scaled_jacobians(off.mesh), after = scaled_jacobians(on.mesh);
    for (std::size_t h = 0; h < after.size(); ++h)
        EXPECT_GE(after[h], std::min(JunctionCoverOptions{}.sj_floor, before[h]) - 1e-12);
    for (int c : {0, 1}) {
        const int np = cs.point_begin[c + 1] - cs.point_begin[c];
        double farthest = 0;
        for (int x = 0; x < np; ++x) {
            const double d = distance(on.mesh.points[on.vertex_base[c] + 1 + x], s.points[c]);
            EXPECT_GE(d, r - 1e-12);
            EXPECT_LE(d, (JunctionCoverOptions{}.arc + 1) * r + 1e-9);
            farthest = std::max(farthest, d);
        }
        EXPECT_GT(farthest, 1.5 * r);  // the bulge's ball reaches far past the end's sphere
    }
    auto owned_by_an_end = [&](int id) {  // a centre, surface point or edge midpoint of A or B
        for (int c : {0, 1}) {
            const int n = 1 + (cs.point_begin[c + 1] - cs.point_begin[c]) + (cs.edge_begin[c + 1] - cs.edge_begin[c]);
            if (id >= on.vertex_base[c] && id < on.vertex_base[c] + n) return true;
        }
        return false;
    };
    for (int id = 0; id < static_cast<int>(on.mesh.points.size()); ++id)  // the limbs' extremities: untouched
        if (!owned_by_an_end(id)) {
            EXPECT_EQ(on.mesh.points[id], off.mesh.points[id]);
        }
    EXPECT_EQ(raw(1.0, 1.5, straight).mesh.points, off.mesh.points);
    EXPECT_NE(raw(1.0, 0.0, straight).mesh.points, off.mesh.points);
}

// Overlapping bridge ends (JunctionCoverOptions::bridge_overlap): branching points A = (0, 0, 0), r 0.3, and
// B = (0.4, 0, 0), r 0.2, each with two one-edge limbs 0.6 long at 50 degrees off its outward direction in the x-y
// plane (extremity radius 0.1). (r_A + r_B) / |AB| = 0.5 / 0.4 = 1.25: both ends are marked at ratio 1.2 and 1.25 (the
// comparison is >=), nothing at 1.3; the same bridge meshed through a joint J = (0.2, 0, 0) is judged by its ends'
// chord (the same marks). On paper the raw mesh has 5 branch edges x 4 hexes = 20 hexes, the prediction, whatever the
// cover does, and is one ball (Euler characteristic 1). Covered at ratio 1.2 (fraction 1, the skeleton's own balls as
// the domain), no hex is inverted or below min(0.3, before), every extremity's raw point stays, and A's points reach
// past its sphere (the ray from A along the bridge leaves the union only at B's far side, 0.6 from A); at ratio 1.3 the
// raw mesh is exactly the cover off.
TEST(JunctionCover, OverlappingBridgeIsCoveredFromBothEnds) {
    const double a = 50 * std::numbers::pi / 180, arm = 0.6;
    Skeleton s;
    s.points = {{0, 0, 0},
                {0.4, 0, 0},
                {-arm * std::cos(a), arm * std::sin(a), 0},
                {-arm * std::cos(a), -arm * std::sin(a), 0},
                {0.4 + arm * std::cos(a), arm * std::sin(a), 0},
                {0.4 + arm * std::cos(a), -arm * std::sin(a), 0}};
    s.edges = {{0, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}};
    s.radii = {0.3, 0.2, 0.1, 0.1, 0.1, 0.1};
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(overlapping_bridge_ends(s, an, 1.2), (std::vector<char>{1, 1, 0, 0, 0, 0}));
    EXPECT_EQ(overlapping_bridge_ends(s, an, 1.25), (std::vector<char>{1, 1, 0, 0, 0, 0}));
    EXPECT_EQ(overlapping_bridge_ends(s, an, 1.3), (std::vector<char>(6, 0)));
    {  // the bridge through a joint J: its ends' chord decides
        Skeleton j = s;
        j.points.push_back({0.2, 0, 0});
        j.radii.push_back(0.25);
        j.edges = {{0, 6}, {6, 1}, {0, 2}, {0, 3}, {1, 4}, {1, 5}};
        const SkeletonAnalysis aj = analyze_skeleton(j);
        EXPECT_EQ(overlapping_bridge_ends(j, aj, 1.2), (std::vector<char>{1, 1, 0, 0, 0, 0, 0}));
        EXPECT_EQ(overlapping_bridge_ends(j, aj, 1.3), (std::vector<char>(7, 0)));
    }
    ConnectionSurfaceOptions co;
    co.blocks.enabled = false;
    const ConnectionSurfaces cs = build_connection_surfaces(s, an, co);
    const BranchFrames fr = propagate_frames(s, an, cs);
    auto raw = [&](double fraction, double overlap) {
        RawMeshOptions o;
        o.cover.fraction = fraction;
        o.cover.bridge_overlap = overlap;
        return build_raw_mesh(s, an, cs, fr, o, &s);
    };
    const RawMesh off = raw(0.0, 0.0), on = raw(1.0, 1.2);
    EXPECT_EQ(an.predicted_hexes, 20);
    EXPECT_EQ(on.mesh.hexes.size(), 20u);
    const QualityReport qn = compute_quality(on.mesh);
    EXPECT_EQ(qn.euler_characteristic, 1);
    EXPECT_EQ(qn.inverted, 0);
    const std::vector<double> before = scaled_jacobians(off.mesh), after = scaled_jacobians(on.mesh);
    for (std::size_t h = 0; h < after.size(); ++h)
        EXPECT_GE(after[h], std::min(JunctionCoverOptions{}.sj_floor, before[h]) - 1e-12);
    for (int v = 2; v < 6; ++v)  // the extremities' centres and cap points
        for (int id = on.vertex_base[v]; id < on.vertex_base[v] + 1; ++id)
            EXPECT_EQ(on.mesh.points[id], off.mesh.points[id]);
    double farthest = 0;
    for (int x = 0; x < cs.point_begin[1] - cs.point_begin[0]; ++x)
        farthest = std::max(farthest, distance(on.mesh.points[on.vertex_base[0] + 1 + x], s.points[0]));
    EXPECT_GT(farthest, 0.3 + 1e-6);
    EXPECT_EQ(raw(1.0, 1.3).mesh.points, off.mesh.points);
}
