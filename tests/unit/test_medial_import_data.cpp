// Every medial mesh of ../shared/data/medial-meshes loads with the counts of the data README and converts to a valid
// quad meso-skeleton (label shared_data).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "quad_skeleton_checks.h"

namespace mesohex {
namespace {

struct Expected {
    const char* name;
    size_t v, e, f, curve_only;
    int sheets, fan_edges;      // fan edges left after fan resolution
    int fan_triangles_removed;  // irregular-fan triangles removed
};

class MedialData : public ::testing::TestWithParam<Expected> {};

TEST_P(MedialData, LoadsAndConverts) {
    const Expected& x = GetParam();
    const std::string path = std::string(MESOHEX_SHARED_DATA_DIR) + "/medial-meshes/" + x.name + ".ma";
    const Skeleton m = read_medial_mesh(path);
    EXPECT_EQ(m.points.size(), x.v);
    EXPECT_EQ(m.edges.size(), x.e);  // the files list every triangle side: nothing added
    EXPECT_EQ(m.faces.size(), x.f);
    Skeleton only_faces = m;  // the triangle sides alone: curve-only edges = all edges - triangle sides
    only_faces.edges.clear();
    const int triangle_sides = add_face_edges(only_faces);
    EXPECT_EQ(m.edges.size() - static_cast<size_t>(triangle_sides), x.curve_only);

    const MedialImport r = import_medial_mesh(m);
    EXPECT_EQ(r.sheets, x.sheets);
    EXPECT_EQ(r.fan_edges, x.fan_edges);
    EXPECT_EQ(r.fan_triangles_removed, x.fan_triangles_removed);
    testing::expect_valid_quad_skeleton(r.skeleton);
    testing::expect_leaflets_oriented(r.skeleton, r.face_leaflet);
    if (r.collapsed_sheets == 0) {
        EXPECT_EQ(euler_characteristic(r.skeleton), euler_characteristic(m));
        EXPECT_EQ(r.skeleton.faces.size(),
                  4u * static_cast<size_t>(r.paired_quads) + 3u * static_cast<size_t>(r.split_triangles));
        EXPECT_EQ(2 * r.paired_quads + r.split_triangles, static_cast<int>(x.f) - r.fan_triangles_removed);
    }
}

INSTANTIATE_TEST_SUITE_P(SharedData, MedialData,
                         // hand.ma's one fan edge (3-10, triangles 7, 8, 9) has two wings in the same leaflet
                         // (an irregular fan): triangle 9 (free side 3-4) goes, leaving wings 7 and 8.
                         ::testing::Values(Expected{"hand", 40, 69, 30, 14, 1, 0, 1},
                                           Expected{"airplane1", 53, 103, 51, 6, 2, 0, 0},
                                           Expected{"dtorus", 29, 31, 1, 28, 1, 0, 0},
                                           Expected{"wrench", 42, 74, 32, 9, 1, 0, 0},
                                           Expected{"cup", 174, 473, 298, 5, 1, 0, 0}),
                         [](const ::testing::TestParamInfo<Expected>& i) { return std::string(i.param.name); });

TEST(MedialData, DtorusTriangleCollapses) {
    const MedialImport r =
        import_medial_mesh(read_medial_mesh(std::string(MESOHEX_SHARED_DATA_DIR) + "/medial-meshes/dtorus.ma"));
    EXPECT_EQ(r.collapsed_sheets, 1);
    EXPECT_TRUE(r.skeleton.faces.empty());
    testing::expect_valid_quad_skeleton(r.skeleton);
}

TEST(MedialData, CliImportWritesAReadableSkeleton) {
    const std::string input = std::string(MESOHEX_SHARED_DATA_DIR) + "/medial-meshes/hand.ma";
    const std::string output = (std::filesystem::temp_directory_path() / "mesohex_test_import_hand.obj").string();
    std::remove(output.c_str());
    const std::string command = std::string(MESOHEX_CLI_PATH) + " import " + input + " -o " + output + " > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const Skeleton written = read_skeleton(output);
    const MedialImport expected = import_medial_mesh(read_medial_mesh(input));
    EXPECT_EQ(written.points.size(), expected.skeleton.points.size());
    EXPECT_EQ(written.edges.size(), expected.skeleton.edges.size());
    EXPECT_EQ(written.faces, expected.skeleton.faces);
    ASSERT_EQ(written.radii.size(), expected.skeleton.radii.size());
    for (size_t v = 0; v < written.radii.size(); ++v)
        EXPECT_NEAR(written.radii[v], expected.skeleton.radii[v], 1e-5 * expected.skeleton.radii[v]);
    std::remove(output.c_str());
    // A missing input file is an IO error (exit status 4), and no output is left behind.
    const std::string bad = std::string(MESOHEX_CLI_PATH) + " import /nonexistent.ma -o " + output + " 2> /dev/null";
    const int rc = std::system(bad.c_str());
    EXPECT_EQ(WEXITSTATUS(rc), 4);
    EXPECT_FALSE(std::filesystem::exists(output));
}

// Imports a medial mesh, writes the skeleton, meshes it with its surface through the CLI (`mesh --surface`, with
// --raw or the whole finishing chain, as a user runs it: second attempt included) and checks what every model must
// give: a valid all-hex mesh whose Euler characteristic is the skeleton's (`extra`: more options of the command).
// Returns the quality report and, finished, the Hausdorff distance relative to the bounding-box diagonal from the
// command's JSON report.
struct Meshed {
    QualityReport q;
    double hausdorff = -1;
};
Meshed mesh_imported(const std::string& name, bool raw, const std::string& extra = "") {
    const std::filesystem::path dir = std::filesystem::temp_directory_path();
    // Another file name with extra options: the tests may run at the same time.
    const std::string stem = "mesohex_test_medial_" + name + (extra.empty() ? "" : "_options");
    const std::string skeleton_path = (dir / (stem + ".obj")).string();
    const std::string mesh_path = (dir / (stem + (raw ? "_raw" : "") + ".mesh")).string();
    const std::string report_path = (dir / (stem + ".json")).string();
    const Skeleton skeleton =
        import_medial_mesh(read_medial_mesh(std::string(MESOHEX_SHARED_DATA_DIR) + "/medial-meshes/" + name + ".ma"))
            .skeleton;
    write_skeleton(skeleton_path, skeleton);
    std::filesystem::remove(mesh_path);
    std::filesystem::remove(report_path);
    const auto run = test::run_cli("mesh " + skeleton_path + " --surface " + std::string(MESOHEX_SHARED_DATA_DIR) +
                                   "/surfaces/" + name + ".off -o " + mesh_path + (raw ? " --raw" : "") +
                                   " --quiet --report " + report_path + extra);
    // 0, or 5 when the mesh written has inverted hexes (checked by the callers).
    EXPECT_TRUE(run.status == 0 || run.status == 5) << run.output;
    if (!std::filesystem::exists(mesh_path)) {
        ADD_FAILURE() << name << ": no mesh written\n" << run.output;
        return {};
    }
    Meshed m;
    m.q = compute_quality(read_hex_mesh(mesh_path));
    EXPECT_GT(m.q.hexes, 0) << name;
    EXPECT_TRUE(m.q.validation.valid()) << name;
    EXPECT_EQ(m.q.euler_characteristic, euler_characteristic(skeleton)) << name;
    if (!raw) {
        std::ifstream in(report_path);
        const nlohmann::json rep = nlohmann::json::parse(in);
        m.hausdorff = rep.at("hausdorff").at("relative_max").get<double>();
    }
    std::cout << name << (raw ? " raw" : " finished") << ": " << m.q.hexes << " hexes, SJ min " << m.q.sj_min << " avg "
              << m.q.sj_avg << ", inverted " << m.q.inverted;
    if (!raw) std::cout << ", Hausdorff " << 100 * m.hausdorff << " %";
    std::cout << "\n";
    std::filesystem::remove(skeleton_path);
    std::filesystem::remove(mesh_path);
    std::filesystem::remove(report_path);
    return m;
}

// Every shared medial mesh, imported and meshed in its own surface by the default commands, meets issue 5's targets
// for real pairs: no inverted hex, min SJ >= 0.3, avg >= 0.85, Hausdorff <= 1 % of the diagonal (measured
// 2026-12-02: wrench 0.680 / 0.954, 0.21 %; dtorus 0.639 / 0.932, 0.40 % at the second attempt; hand 0.580 / 0.928,
// 0.86 %; airplane1 0.626 / 0.950, 0.48 %; cup 0.714 / 0.974, 0.38 % with the root patch split, 0.690 / 0.971, 0.39 %
// without). Raw meshes: no inverted hex (hand's one at its wrist, next to skeleton vertex 64, min SJ -0.054, went with
// RawMeshOptions::leaflet_offset_fraction 0.5 in session 31: raw min 0.019, finished 0.575 / 0.927, 0.87 %).
TEST(MedialData, FinishedMeshesMeetTheRealPairTargets) {
    for (const char* name : {"wrench", "dtorus", "hand", "airplane1", "cup"}) {
        SCOPED_TRACE(name);
        const Meshed raw = mesh_imported(name, true);
        EXPECT_EQ(raw.q.inverted, 0);
        const Meshed m = mesh_imported(name, false);
        EXPECT_EQ(m.q.inverted, 0);
        EXPECT_GE(m.q.sj_min, 0.3);
        EXPECT_GE(m.q.sj_avg, 0.85);
        EXPECT_LE(m.hausdorff, 0.01);
        EXPECT_GE(m.hausdorff, 0.0);
    }
}

// hand.ma with --leaflet-out-fraction 0.3: its padded mesh has no inverted hex, so the pad-improve pass runs; it
// relaxes the padding at a fingertip where the raw boundary already lies outside the domain farther out, and the fit
// crushes it back only to its SJ guard (1.89 %: docs/sheets.md, "What pad-improve does to hand.ma"). With
// --pad-improve-keep-distance that result is dropped (it moves the boundary away from the domain) and the targets are
// met (measured 0.576 / 0.928, 0.86 %).
TEST(MedialData, HandWithThePullMeetsWhenPadImproveKeepsTheDistance) {
    const Meshed m = mesh_imported("hand", false, " --leaflet-out-fraction 0.3 --pad-improve-keep-distance");
    EXPECT_EQ(m.q.inverted, 0);
    EXPECT_GE(m.q.sj_min, 0.3);
    EXPECT_GE(m.q.sj_avg, 0.85);
    EXPECT_LE(m.hausdorff, 0.01);
    EXPECT_GE(m.hausdorff, 0.0);
}

// cup.ma's handle ends on two interior vertices of the cup's sheet (53 and 6). The mesher roots a branch where 4 quads
// meet: 53 keeps its end, 6's end moves to a regular neighbour; nothing else is changed.
TEST(MedialData, CupHandleIsRootedInsideTheSheet) {
    const Skeleton m = read_medial_mesh(std::string(MESOHEX_SHARED_DATA_DIR) + "/medial-meshes/cup.ma");
    const MedialImport r = import_medial_mesh(m);
    EXPECT_EQ(r.reattached_curve_ends, 0);
    // Points: 174 input vertices + 344 midpoints (468 triangle sides - 124 pair diagonals) + 174 face centres (124
    // pairs + 50 lone triangles).
    EXPECT_EQ(r.paired_quads, 124);
    EXPECT_EQ(r.split_triangles, 50);
    EXPECT_EQ(r.skeleton.points.size(), 692u);
    EXPECT_EQ(euler_characteristic(r.skeleton), euler_characteristic(m));
    // The handle's ends: 53 (4 quads meet there) stays; 6 (5 quads) moves to a regular neighbour, one rooted end.
    EXPECT_EQ(r.rooted_curve_ends, 1);
    std::set<std::pair<int, int>> face_sides;
    std::vector<int> faces_at(r.skeleton.points.size(), 0);
    for (const std::vector<int>& f : r.skeleton.faces)
        for (size_t i = 0; i < f.size(); ++i) {
            face_sides.insert(std::minmax(f[i], f[(i + 1) % f.size()]));
            ++faces_at[static_cast<size_t>(f[i])];
        }
    std::vector<int> roots;
    for (const std::array<int, 2>& e : r.skeleton.edges)
        if (!face_sides.count(std::minmax(e[0], e[1])))
            for (int v : e)
                if (faces_at[static_cast<size_t>(v)] > 0) roots.push_back(v);
    ASSERT_EQ(roots.size(), 2u);
    EXPECT_EQ(std::count(roots.begin(), roots.end(), 53), 1);
    EXPECT_EQ(std::count(roots.begin(), roots.end(), 6), 0);
    for (int v : roots) EXPECT_EQ(faces_at[static_cast<size_t>(v)], 4) << v;
    const SkeletonAnalysis an = analyze_skeleton(r.skeleton);
    for (int v : roots) EXPECT_EQ(an.vertex_class[static_cast<size_t>(v)], VertexClass::LeafletInterior) << v;
}

}  // namespace
}  // namespace mesohex
