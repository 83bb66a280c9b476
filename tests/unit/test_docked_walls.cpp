// Walls docked on a plate (issue 22 item 1; ../shared/design/beyond-the-paper.md section B; docs/blocks.md "Docked
// walls"): a fan edge chain ending inside (or on the border of) another leaflet, meshed with the wall standing on the
// plate's faces. Raw meshes of tiny plates with walls: exact hex / vertex / irregular-edge counts derived by hand,
// validity, Euler characteristic equal to the skeleton's, no inverted hex; the remaining refusals name the vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex/core/validate.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/docked_walls.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/raw_mesh.h"
#include "raw_run.h"

using namespace mesohex;

namespace {

using test::RawRun;

RawRun mesh_raw(const Skeleton& s) { return test::checked_raw_mesh(s); }

Skeleton wall_plate(const WallPlate& w) { return make_wall_plate(w, 1.0, 0.3); }

void expect_refused_at(const Skeleton& s, int vertex, const std::string& words) {
    try {
        (void)analyze_skeleton(s);
        ADD_FAILURE() << "not refused (expected vertex " << vertex << ", '" << words << "')";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::UnsupportedConfiguration);
        EXPECT_EQ(e.where().kind, ElementRef::Kind::SkeletonVertex);
        EXPECT_EQ(e.where().index, vertex) << e.what();
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("edit:"), std::string::npos) << e.what();
    }
}

// A docked wall's raw mesh as derived by hand: 2 docked fan edges, the hex / vertex counts and singular edges (valence
// -> count), valid, nothing inverted, Euler characteristic 1 (a disc with fins).
void expect_docked_raw(const RawRun& r, long hexes, long vertices, const std::map<int, long>& interior,
                       const std::map<int, long>& boundary) {
    EXPECT_EQ(r.analysis.counts.docked_edges, 2);
    EXPECT_EQ(r.quality.hexes, hexes);
    EXPECT_EQ(r.quality.vertices, vertices);
    EXPECT_EQ(r.quality.singular_interior_edges, interior);
    EXPECT_EQ(r.quality.singular_boundary_edges, boundary);
    EXPECT_TRUE(r.valid);
    EXPECT_EQ(r.quality.inverted, 0);
    EXPECT_EQ(r.quality.euler_characteristic, 1);
}

}  // namespace

// Plate 6 x 6 (49 vertices: 24 on the border with 6 ids, 25 inside with 3; 36 faces, 24 border edges), a wall of 2 x 2
// quads (2 rows high) on a 2-edge chain whose ends are both inside the plate.
//   hexes: 2 per face + 2 per boundary edge = 2 (36 + 4) + 2 (24 + 6) = 140 (the wall's 6 border edges: its perimeter
//          of 8 minus the 2 chain edges);
//   vertices: plate 24 x 6 + 25 x 3 = 219 (the 3 chain vertices are plate vertices only), wall 6 vertices off the
//          chain: row 1 = 6 + 3 + 6, row 2 = 3 x 6, so 252;
//   interior irregular: valence 3 at the up / down edges of the 4 plate corners (1 face + 2 half-chunks) and of the 2
//          wall top corners: 12; none along the chain (the paper would put a fan block there, one valence-6 edge per
//          fan edge, or refuse: limitation 2);
//   boundary: valence 1, 2 per boundary edge (60); valence 3, the outline of the foot (a band of 2 x 4 plate faces,
//          one face longer than the chain at each end: 12 edges, 2 plate hexes + 1 wall hex each).
TEST(DockedWalls, WallEndingInsideThePlateByHand) {
    const Skeleton s = wall_plate({});
    const RawRun r = mesh_raw(s);
    EXPECT_EQ(r.analysis.counts.docked_edges, 2);
    EXPECT_EQ(r.analysis.counts.fan_edges, 0);
    EXPECT_EQ(r.analysis.counts.fan_edge_ends + r.analysis.counts.fan_edge_vertices, 0);
    EXPECT_EQ(r.quality.hexes, 140);
    EXPECT_EQ(r.quality.vertices, 252);
    EXPECT_EQ(r.quality.singular_interior_edges, (std::map<int, long>{{3, 12}}));
    EXPECT_EQ(r.quality.singular_boundary_edges, (std::map<int, long>{{1, 60}, {3, 12}}));
    EXPECT_TRUE(r.valid);
    EXPECT_EQ(r.quality.inverted, 0);
    EXPECT_EQ(r.quality.euler_characteristic,
              r.analysis.counts.vertices - r.analysis.counts.edges + r.analysis.counts.faces);  // 1: a disc with a fin
    EXPECT_GT(r.quality.sj_min, 0.5);
}

// Off-centre (column 2 of 6, and column 1: the foot reaches the plate's border, whose plate-top edges also have 2
// hexes under them): same counts as centred.
TEST(DockedWalls, WallOffCentreByHand) {
    for (int column : {2, 1, 5}) {
        WallPlate w;
        w.column = column;
        const RawRun r = mesh_raw(wall_plate(w));
        EXPECT_EQ(r.quality.hexes, 140) << column;
        EXPECT_EQ(r.quality.vertices, 252) << column;
        EXPECT_EQ(r.quality.singular_interior_edges, (std::map<int, long>{{3, 12}})) << column;
        EXPECT_EQ(r.quality.singular_boundary_edges, (std::map<int, long>{{1, 60}, {3, 12}})) << column;
        EXPECT_TRUE(r.valid) << column;
        EXPECT_EQ(r.quality.inverted, 0) << column;
        EXPECT_EQ(r.quality.euler_characteristic, 1) << column;
    }
}

// Walls on both sides (z > 0 and z < 0) on the same chain: fan edges of degree 4. Hexes 2 (36 + 8) + 2 (24 + 12) = 160;
// vertices 219 + 2 x 33 = 285; interior valence 3: 8 plate corner edges + 4 per wall = 16; boundary valence 1: 72,
// valence 3: 12 per foot = 24 (the feet are on opposite sides of the plate).
TEST(DockedWalls, WallsOnBothSidesByHand) {
    WallPlate w;
    w.sides = 2;
    const RawRun r = mesh_raw(wall_plate(w));
    expect_docked_raw(r, 160, 285, {{3, 16}}, {{1, 72}, {3, 24}});
}

// The chain runs from the plate's border (vertex (3, 0)) to an interior vertex (3, 2). Hexes and vertices as centred
// (140, 252). The foot: 2 x 3 plate faces plus the tops of the 2 half-chunks of the plate's border edges at (3, 0).
// Boundary valence 3: the 8 outline edges on the plate faces, plus the 2 up / out-up edges at (2, 0) and (4, 0) = 10;
// the 2 out-up edges of those half-chunks get a wall hex (valence 1 -> 2): valence 1 = 60 - 2 = 58; the up / out-up
// edge at (3, 0) and the 2 border edges' plate-top edges are inside the foot (interior, valence 4).
TEST(DockedWalls, WallEndingOnThePlateBorderByHand) {
    WallPlate w;
    w.start = 0;
    const RawRun r = mesh_raw(wall_plate(w));
    expect_docked_raw(r, 140, 252, {{3, 12}}, {{1, 58}, {3, 10}});
    EXPECT_GT(r.quality.sj_min, 0.3);
}

// Walls on both sides of a chain from the plate's border (the two cases above together): hexes and vertices as walls
// on both sides ending inside (160, 285: the same faces, boundary edges and ids); each foot is the border foot above
// (boundary valence 3: 10 per foot = 20; valence 1: 72 - 2 x 2 = 68, the 2 out-up edges under each wall's border end
// get a wall hex); interior valence 3 unchanged (16).
TEST(DockedWalls, WallsOnBothSidesFromThePlateBorderByHand) {
    WallPlate w;
    w.start = 0;
    w.sides = 2;
    const RawRun r = mesh_raw(wall_plate(w));
    expect_docked_raw(r, 160, 285, {{3, 16}}, {{1, 68}, {3, 20}});
}

// A chain whose ends are both on the plate's border splits the plate into two leaflets: a regular T fan, meshed with
// the paper's layout as before (fan edges, not docked).
TEST(DockedWalls, ChainAcrossThePlateStaysARegularFan) {
    WallPlate w;
    w.start = 0;
    w.length = 6;
    const Skeleton s = wall_plate(w);
    const SkeletonAnalysis an = analyze_skeleton(s);
    EXPECT_EQ(an.counts.docked_edges, 0);
    EXPECT_EQ(an.counts.fan_edges, 6);
    EXPECT_EQ(an.counts.leaflets, 3);
}

// A wall across the plate (plate 4 x 4, column 2, 4 chain edges from border to border, 2 rows at +z) with a shorter
// wall on the other side (rows 1 to 3 of the chain, 1 row at -z): fan edges of degree 3 and 4 in one chain, refused as
// an irregular fan before; the chain cuts the plate into two leaflets, which are joined into one and the chain docks.
// By hand (raw, no repair): F = 16 + 8 + 2 = 26; B = 16 (plate border) + 8 (top wall: its top row 4, end columns
// 2 + 2) + 4 (bottom wall: 2 + 1 + 1) = 28; hexes 2 F + 2 B = 108. Vertices: plate 16 border x 6 + 9 inside x 3 = 123
// (the chain's 5 are plate vertices only), top wall off the chain 3 inside x 3 + 7 border x 6 = 51, bottom wall 3
// border x 6 = 18: 192. Skeleton V 38, E 40 + 18 + 5 = 63, F 26: Euler characteristic 1. Interior valence 3: the up /
// down edges of the 4 plate corners (8) and of the 2 top corners of each wall (4 + 4): 16; nothing along the chain.
TEST(DockedWalls, WallAcrossThePlateWithAShorterWallOnTheOtherSideByHand) {
    WallPlate w;
    w.plate = 4;
    w.start = 0;
    w.length = 4;
    w.column = 2;
    Skeleton s = wall_plate(w);
    ASSERT_EQ(s.points.size(), 35u);
    const int n0 = 35;
    for (int j = 1; j <= 3; ++j) s.points.push_back(s.points[2 * 5 + j] + Vec3{0, 0, -1});
    s.radii.resize(s.points.size(), 0.3);
    for (int j = 1; j <= 2; ++j) s.faces.push_back({2 * 5 + j, 2 * 5 + j + 1, n0 + j, n0 + j - 1});
    add_face_edges(s);
    const RawRun r = mesh_raw(s);
    EXPECT_EQ(r.analysis.counts.docked_edges, 4);
    EXPECT_EQ(r.analysis.counts.fan_edges, 0);
    EXPECT_EQ(r.analysis.counts.leaflets, 3);  // the plate's two halves joined, two walls
    EXPECT_EQ(r.analysis.counts.vertices - r.analysis.counts.edges + r.analysis.counts.faces, 1);
    EXPECT_EQ(r.analysis.predicted_hexes, 108);
    EXPECT_EQ(r.quality.hexes, 108);
    EXPECT_EQ(r.quality.vertices, 192);
    EXPECT_EQ(r.quality.singular_interior_edges, (std::map<int, long>{{3, 16}}));
    EXPECT_TRUE(r.valid);
    EXPECT_EQ(r.quality.inverted, 0);
    EXPECT_EQ(r.quality.euler_characteristic, 1);
    EXPECT_GT(r.quality.sj_min, 0.3);
    // Without the shorter wall the chain stays a regular T fan (two plate leaflets, not docked).
    const SkeletonAnalysis t = analyze_skeleton(wall_plate(w));
    EXPECT_EQ(t.counts.docked_edges, 0);
    EXPECT_EQ(t.counts.leaflets, 3);
}

// The remaining refusals name the vertex and the configuration, with an edit suggestion.
TEST(DockedWalls, RemainingRefusalsNameTheVertex) {
    {  // two walls on the same side of one chain: degree 4 with both walls at +z (one tilted)
        Skeleton s = wall_plate({});
        const int n0 = static_cast<int>(s.points.size());
        // chain vertices: plate lattice (3, 2), (3, 3), (3, 4) = ids 3 * 7 + 2.. (lattice order i * 7 + j)
        for (int j = 2; j <= 4; ++j) s.points.push_back(s.points[3 * 7 + j] + Vec3{0.7, 0, 0.7});
        s.radii.resize(s.points.size(), 0.3);
        s.faces.push_back({3 * 7 + 2, 3 * 7 + 3, n0 + 1, n0});
        s.faces.push_back({3 * 7 + 3, 3 * 7 + 4, n0 + 2, n0 + 1});
        add_face_edges(s);
        expect_refused_at(s, 3 * 7 + 2, "same side");
    }
    {  // a wall leaning 60 degrees from the plate's normal (its first hexes would be wedges of 30 degrees: inverted)
        Skeleton s = wall_plate({});
        for (std::size_t v = 49; v < s.points.size(); ++v) {
            const double h = s.points[v].z;
            s.points[v].x += h * std::sqrt(3.0);
        }
        expect_refused_at(s, 3 * 7 + 2, "leans 60 degrees");
    }
    {  // a branch on a chain vertex
        Skeleton s = wall_plate({});
        s.points.push_back(s.points[3 * 7 + 3] + Vec3{0, 0, -1});
        s.radii.push_back(0.3);
        s.edges.push_back({3 * 7 + 3, static_cast<int>(s.points.size()) - 1});
        expect_refused_at(s, 3 * 7 + 3, "branch");
    }
    {  // two walls whose feet overlap (parallel chains one plate face apart)
        Skeleton s = wall_plate({});
        WallPlate w2;
        w2.column = 4;
        const Skeleton b = wall_plate(w2);
        // b's wall vertices (after its 49 plate vertices) re-attached to the shared plate
        const int off = static_cast<int>(s.points.size()) - 49;
        for (std::size_t v = 49; v < b.points.size(); ++v) {
            s.points.push_back(b.points[v]);
            s.radii.push_back(0.3);
        }
        auto map = [&](int v) { return v < 49 ? v : v + off; };
        for (std::size_t f = 36; f < b.faces.size(); ++f)
            s.faces.push_back({map(b.faces[f][0]), map(b.faces[f][1]), map(b.faces[f][2]), map(b.faces[f][3])});
        add_face_edges(s);
        try {
            (void)analyze_skeleton(s);
            ADD_FAILURE() << "overlapping feet not refused";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::UnsupportedConfiguration);
            EXPECT_NE(std::string(e.what()).find("foot"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("edit:"), std::string::npos) << e.what();
        }
    }
}
