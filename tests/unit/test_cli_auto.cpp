// End-to-end runs of `mesohex auto`: surface -> skeleton (written beside the mesh) -> finished all-hex mesh, on the
// shared tubular surfaces (cactus, aorta), and the error for a surface that cannot be skeletonized.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/adaptation.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/skeleton_io.h"

namespace fs = std::filesystem;
using mesohex::test::run_cli;

namespace {

fs::path temp_dir() {
    const fs::path dir = fs::path(testing::TempDir()) / "mesohex_test_cli_auto";
    fs::create_directories(dir);
    return dir;
}

nlohmann::json read_json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

// Runs `auto` on a shared surface and checks what the issue asks: exit 0, a valid all-hex mesh without inverted hex,
// Hausdorff distance <= max_relative_hausdorff of the bbox diagonal, the skeleton written beside the mesh and
// readable, and a report naming that skeleton with the time of every step.
void check_auto(const std::string& model, const std::string& file, double max_relative_hausdorff) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / file;
    const fs::path out = temp_dir() / (model + ".mesh"), report = temp_dir() / (model + ".json");
    const fs::path skeleton_path = temp_dir() / (model + ".skeleton.obj");
    fs::remove(out);
    fs::remove(skeleton_path);
    const auto r =
        run_cli("auto " + surface.string() + " -o " + out.string() + " --report " + report.string() + " --quiet");
    ASSERT_EQ(r.status, 0) << r.output;

    const mesohex::QualityReport q = mesohex::compute_quality(mesohex::read_hex_mesh(out.string()));
    EXPECT_GT(q.hexes, 0);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.inverted, 0);
    EXPECT_GT(q.sj_min, 0.0);

    ASSERT_TRUE(fs::exists(skeleton_path));
    const mesohex::Skeleton skel = mesohex::read_skeleton(skeleton_path.string());
    EXPECT_GE(skel.points.size(), 2u);
    EXPECT_GE(skel.edges.size(), 1u);
    EXPECT_EQ(skel.radii.size(), skel.points.size());

    const nlohmann::json rep = read_json(report);
    EXPECT_EQ(rep["skeleton_used"]["path"], skeleton_path.string());
    // Tubes: the medial axis is nearly all curves (sheet fraction 0.013 on aorta, 0.023 on cactus, 2026-12-02), so
    // auto keeps the curve skeleton (issue 17).
    EXPECT_EQ(rep["skeleton_kind"], "curve");
    EXPECT_LT(rep["skeleton_decision"]["medial"]["sheet_fraction"].get<double>(), 0.1);
    EXPECT_EQ(rep["skeleton_used"]["vertices"].get<std::size_t>(), skel.points.size());
    EXPECT_EQ(rep["skeleton_used"]["edges"].get<std::size_t>(), skel.edges.size());
    EXPECT_EQ(rep["quality"]["hexes"].get<long>(), q.hexes);
    EXPECT_EQ(rep["quality"]["inverted"], 0);
    for (const char* step : {"read_surface", "skeletonize", "pipeline_total", "finish_total", "total"})
        EXPECT_TRUE(rep["timings_ms"].contains(step)) << step;
    EXPECT_GE(rep["timings_ms"]["total"].get<double>(), rep["timings_ms"]["skeletonize"].get<double>());
    ASSERT_TRUE(rep.contains("hausdorff"));
    EXPECT_LE(rep["hausdorff"]["relative_max"].get<double>(), max_relative_hausdorff);
    EXPECT_EQ(rep["hausdorff"]["mesh_to_surface_at"].size(), 3u);  // where each maximum is, for the user to look
    EXPECT_EQ(rep["hausdorff"]["surface_to_mesh_at"].size(), 3u);
    // Attempts: the default adaptation first; a second one only when the first missed a goal; the mesh written is the
    // attempt whose reach and subdivision levels the report names, with its numbers.
    const nlohmann::json& attempts = rep["attempts"];
    ASSERT_TRUE(attempts.size() == 1 || attempts.size() == 2) << attempts.dump();
    EXPECT_EQ(attempts[0]["free_branching_reach"].get<double>(), mesohex::AdaptationOptions{}.free_branching_reach);
    if (attempts.size() == 2) {
        EXPECT_GT(attempts[0]["missed_goals"].get<int>(), 0);
    }
    int kept = 0;
    for (const nlohmann::json& a : attempts)
        if (a["free_branching_reach"] == rep["free_branching_reach"] &&
            a["levels"] == rep["subdivision_levels"]) {  // the one-level-finer attempt shares the reach
            ++kept;
            EXPECT_EQ(a["hexes"].get<long>(), q.hexes);
            EXPECT_EQ(a["sj_min"].get<double>(), rep["quality"]["sj_min"].get<double>());
            EXPECT_EQ(a["hausdorff_relative_max"].get<double>(), rep["hausdorff"]["relative_max"].get<double>());
        }
    EXPECT_EQ(kept, 1);
    std::cout << model << ": skeleton " << skel.points.size() << " vertices, " << skel.edges.size() << " edges; "
              << q.hexes << " hexes, SJ min " << q.sj_min << " avg " << q.sj_avg << ", Hausdorff "
              << 100.0 * rep["hausdorff"]["relative_max"].get<double>() << " %, skeletonize "
              << rep["timings_ms"]["skeletonize"].get<double>() << " ms, total "
              << rep["timings_ms"]["total"].get<double>() << " ms\n";
}

std::string file_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Our standard: same input, same output bytes, whatever the thread count, every run. Runs `auto` three times (all
// cores, 1 thread, 2 threads) and compares the mesh and the skeleton written beside it byte for byte.
void check_auto_reproducible(const std::string& model, const std::string& file) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / file;
    std::string mesh0, skeleton0;
    for (const char* threads : {"0", "1", "2"}) {
        const fs::path out = temp_dir() / (model + "_repro_" + threads + ".mesh");
        const fs::path skeleton_path = temp_dir() / (model + "_repro_" + std::string(threads) + ".skeleton.obj");
        fs::remove(out);
        fs::remove(skeleton_path);
        const auto r =
            run_cli("auto " + surface.string() + " -o " + out.string() + " --threads " + threads + " --quiet");
        ASSERT_EQ(r.status, 0) << r.output;
        const std::string mesh = file_bytes(out), skeleton = file_bytes(skeleton_path);
        ASSERT_FALSE(mesh.empty());
        ASSERT_FALSE(skeleton.empty());
        if (mesh0.empty()) {
            mesh0 = mesh;
            skeleton0 = skeleton;
            continue;
        }
        EXPECT_TRUE(mesh == mesh0) << model << ": the mesh written with --threads " << threads << " differs";
        EXPECT_TRUE(skeleton == skeleton0)
            << model << ": the skeleton written with --threads " << threads << " differs";
    }
}

}  // namespace

TEST(AutoCli, SameSurfaceSameBytesWhateverTheThreadCount) {
    check_auto_reproducible("cactus", "cactus.obj");
    check_auto_reproducible("aorta", "aorta.stl");
}

// The target: Hausdorff distance <= 2 % of the bbox diagonal. Measured 2026-11-22 (with the surface fitting of
// that day): cactus 0.83 %, aorta 0.71 %, default options.
constexpr double kHausdorffTarget = 0.02;

TEST(AutoCli, CactusGivesAValidHexMeshCloseToTheSurface) { check_auto("cactus", "cactus.obj", kHausdorffTarget); }

TEST(AutoCli, AortaGivesAValidHexMeshCloseToTheSurface) { check_auto("aorta", "aorta.stl", kHausdorffTarget); }

// --no-retry: one attempt, with the default reach, whatever it gives; the report says so.
TEST(AutoCli, NoRetryKeepsTheFirstAttempt) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / "cactus.obj";
    const fs::path out = temp_dir() / "cactus_once.mesh", report = temp_dir() / "cactus_once.json";
    const auto r = run_cli("auto " + surface.string() + " -o " + out.string() + " --report " + report.string() +
                           " --quiet --no-retry");
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json rep = read_json(report);
    ASSERT_EQ(rep["attempts"].size(), 1u);
    EXPECT_EQ(rep["free_branching_reach"].get<double>(), mesohex::AdaptationOptions{}.free_branching_reach);
    EXPECT_EQ(rep["attempts"][0]["hexes"].get<long>(), rep["quality"]["hexes"].get<long>());
    EXPECT_EQ(r.output.find("attempt 2"), std::string::npos);
}

namespace {

// The mesh written to `out` is valid, has no inverted hex and meets min SJ >= 0.3, avg >= 0.85 and the report's
// Hausdorff distance <= 1 % of the bbox diagonal.
void expect_every_target(const fs::path& out, const nlohmann::json& rep) {
    const mesohex::QualityReport q = mesohex::compute_quality(mesohex::read_hex_mesh(out.string()));
    EXPECT_EQ(q.inverted, 0);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_GE(q.sj_min, 0.3);
    EXPECT_GE(q.sj_avg, 0.85);
    EXPECT_LE(rep["hausdorff"]["relative_max"].get<double>(), 0.01);
}

}  // namespace

// plate1 (a plate with sharp rims): auto takes the medial meso-skeleton at its full radii (the distance to the surface:
// the raw mesh at 1.0 x the distance has no inverted hex, min SJ 0.407) and the selective padding meets every target in
// the first attempt (0.345 / 0.955, Hausdorff 0.61 %; docs/sheets.md, "Full radii first").
// With the half radii only (--meso-full-radius-factor 0, auto before session 30) the selective padding leaves quads of
// its raw boundary bare (their rims match the plate's) but that raw boundary lies halfway inside the plate, so the fit
// stretches the bare hexes and a goal is missed. The same raw mesh fully padded meets every target and is kept; the
// report lists both attempts (numbers: docs/tuning.md, "Selective padding").
TEST(AutoCli, PlateAtFullRadiiMeetsTheTargetsWithSelectivePadding) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / "plate1.obj";
    const fs::path out = temp_dir() / "plate1.mesh", report = temp_dir() / "plate1.json";
    const auto r =
        run_cli("auto " + surface.string() + " -o " + out.string() + " --report " + report.string() + " --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json rep = read_json(report);
    EXPECT_EQ(rep["skeleton_kind"], "meso");
    EXPECT_EQ(rep["skeleton_decision"]["meso_radii"]["radius_factor_used"].get<double>(), 1.0);
    ASSERT_EQ(rep["attempts"].size(), 1u);
    EXPECT_EQ(rep["attempts"][0]["padding"], "selective");
    EXPECT_EQ(rep["attempts"][0]["missed_goals"].get<int>(), 0);
    expect_every_target(out, rep);
}

TEST(AutoCli, PlateAtHalfRadiiFullyPaddedWhenTheBareFinishMissesAGoal) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / "plate1.obj";
    const fs::path out = temp_dir() / "plate1h.mesh", report = temp_dir() / "plate1h.json";
    const auto r = run_cli("auto " + surface.string() + " -o " + out.string() + " --report " + report.string() +
                           " --quiet --meso-full-radius-factor 0");
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json rep = read_json(report);
    EXPECT_EQ(rep["skeleton_kind"], "meso");
    EXPECT_EQ(rep["skeleton_decision"]["meso_radii"]["radius_factor_used"].get<double>(), 0.5);
    ASSERT_GE(rep["attempts"].size(), 2u);
    EXPECT_EQ(rep["attempts"][0]["padding"], "selective");
    EXPECT_GT(rep["attempts"][0]["missed_goals"].get<int>(), 0);
    EXPECT_EQ(rep["attempts"][1]["padding"], "all");
    EXPECT_EQ(rep["padding"]["mode"], "all");
    expect_every_target(out, rep);
}

// sculpt (5 curved medial sheets): auto takes the medial meso-skeleton and meets every target. Before the import's
// smoothing was kept within a quarter radius of the medial sheet (MedialImportOptions::max_sheet_offset, set by
// meso_import_options), the smoothing flattened the curved sheets off the medial axis: forced meso missed by 8.8 %
// Hausdorff and the raw minimum (0.097) kept auto on the curve skeleton (9.65 %). Numbers: docs/sheets.md.
TEST(AutoCli, SculptsCurvedSheetsStayOnTheMedialAxisAndMeetTheTargets) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / "sculpt.ply";
    const fs::path out = temp_dir() / "sculpt.mesh", report = temp_dir() / "sculpt.json";
    const auto r = run_cli("auto " + surface.string() + " -o " + out.string() + " --report " + report.string() +
                           " --quiet --threads 1");
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json rep = read_json(report);
    EXPECT_EQ(rep["skeleton_kind"], "meso");
    expect_every_target(out, rep);
}

// hand.off: with its fingers' parts kept (MedialAxisOptions::cover_fraction; the default medial mesh's coverage gap
// 12.2 -> 6.2 % of the diagonal) the medial meso-skeleton's raw mesh at half radii has 11 inverted hexes (8 in plates
// or blocks, 1 next to a join; before, without the fingers, it was clean: min SJ 0.307, and its finished mesh missed
// with Hausdorff 9.67 %), so auto takes the curve skeleton at the raw check (min SJ 0.106, Hausdorff 2.80 %, two goals
// missed; 0.244 / 3.37 % before its joints were re-centred, docs/sheets.md; 0.101 before session 28's tip trim and
// bridge-quad inset, docs/junctions.md): the report's kind is "curve", its reason names the raw check, and the
// skeleton written beside the mesh is the curve skeleton (no leaflet faces).
TEST(AutoCli, HandsMesoRawMeshWithItsFingersFailsTheCheck) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / "hand.off";
    const fs::path out = temp_dir() / "hand.mesh", report = temp_dir() / "hand.json";
    const fs::path skeleton_path = temp_dir() / "hand.skeleton.obj";
    const auto r = run_cli("auto " + surface.string() + " -o " + out.string() + " --report " + report.string() +
                           " --quiet --threads 1");
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json rep = read_json(report);
    EXPECT_EQ(rep["skeleton_kind"], "curve");
    const std::string reason = rep["skeleton_decision"]["reason"];
    EXPECT_NE(reason.find("meso raw mesh 518 hexes, 11 inverted"), std::string::npos) << reason;
    EXPECT_NE(reason.find("curve skeleton instead"), std::string::npos) << reason;
    EXPECT_LT(rep["skeleton_decision"]["medial"]["coverage_gap_relative"].get<double>(), 0.07);
    EXPECT_TRUE(mesohex::read_skeleton(skeleton_path.string()).faces.empty());
    const mesohex::QualityReport q = mesohex::compute_quality(mesohex::read_hex_mesh(out.string()));
    EXPECT_EQ(q.hexes, 3264);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_NEAR(q.sj_min, 0.1057, 0.001);
}

// The same hand without the fingers' parts (--cover-fraction 0, the medial mesh before session 35): the medial
// meso-skeleton's raw mesh is clean (0 inverted, min SJ 0.307), so auto takes it, but its finished mesh misses two
// goals (min SJ 0.140, Hausdorff 9.67 %: the gap at the fingers). auto then finishes the curve skeleton too (min SJ
// 0.106, Hausdorff 2.80 %, a smaller distance) and keeps it: the path that compares a finished meso mesh with the
// curve skeleton's, its reason saying what was compared.
TEST(AutoCli, MesoMeshMissingAGoalIsComparedWithTheCurveSkeletons) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / "hand.off";
    const fs::path out = temp_dir() / "hand_c0.mesh", report = temp_dir() / "hand_c0.json";
    const fs::path skeleton_path = temp_dir() / "hand_c0.skeleton.obj";
    const auto r = run_cli("auto " + surface.string() + " -o " + out.string() + " --report " + report.string() +
                           " --cover-fraction 0 --quiet --threads 1");
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json rep = read_json(report);
    EXPECT_EQ(rep["skeleton_kind"], "curve");
    const std::string reason = rep["skeleton_decision"]["reason"];
    EXPECT_NE(reason.find("medial meso-skeleton; its finished mesh (min / avg SJ 0.14"), std::string::npos) << reason;
    EXPECT_NE(reason.find("better, curve skeleton kept"), std::string::npos) << reason;
    EXPECT_TRUE(mesohex::read_skeleton(skeleton_path.string()).faces.empty());
    const mesohex::QualityReport q = mesohex::compute_quality(mesohex::read_hex_mesh(out.string()));
    EXPECT_EQ(q.hexes, 3264);
    EXPECT_EQ(q.inverted, 0);
    EXPECT_NEAR(q.sj_min, 0.1057, 0.001);
}

// torque.obj (a rounded, twisted bar): the medial axis has a sheet (fraction 0.54 -> 1 after the spur pruning) but its
// meso raw mesh has an inverted hex, so auto takes the curve skeleton: 4 edges, 16 raw hexes, 56 padded. The level
// rule (padded mean edge against diagonal / 16) gives one level: 448 hexes, min / avg SJ 0.600 / 0.842, Hausdorff
// 1.24 %, two goals missed by a mesh too coarse to follow the surface. The same raw mesh one level finer
// (MeshOptions::finer_retry, 8 x 448 = 3 584 hexes within half of the 24 000 budget) meets every target and is kept
// (0.601 / 0.949, 0.95 %; docs/sheets.md, "One level finer"). With --no-finer-retry the 448-hex mesh meets the min SJ
// and misses the distance goal, so MeshOptions::refine_to_distance finishes it one level finer (the same 3 584 hexes);
// with --no-distance-refinement as well the first is kept.
TEST(AutoCli, CoarseCurveMeshIsFinishedOneLevelFinerAndMeetsTheTargets) {
    const fs::path surface = fs::path(MESOHEX_SHARED_DATA_DIR) / "surfaces" / "torque.obj";
    const fs::path out = temp_dir() / "torque.mesh", report = temp_dir() / "torque.json";
    const std::string args =
        "auto " + surface.string() + " -o " + out.string() + " --report " + report.string() + " --quiet --threads 1";
    const auto r = run_cli(args);
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json rep = read_json(report);
    EXPECT_EQ(rep["skeleton_kind"], "curve");
    ASSERT_EQ(rep["attempts"].size(), 2u) << rep["attempts"].dump();
    EXPECT_EQ(rep["attempts"][0]["levels"].get<int>(), 1);
    EXPECT_EQ(rep["attempts"][0]["hexes"].get<long>(), 448);
    EXPECT_GT(rep["attempts"][0]["missed_goals"].get<int>(), 0);
    EXPECT_EQ(rep["attempts"][1]["levels"].get<int>(), 2);
    EXPECT_EQ(rep["attempts"][1]["hexes"].get<long>(), 8 * 448);
    EXPECT_EQ(rep["attempts"][1]["missed_goals"].get<int>(), 0);
    EXPECT_EQ(rep["subdivision_levels"].get<int>(), 2);
    EXPECT_EQ(rep["distance_refinement"]["stop"], "distance met");
    EXPECT_TRUE(rep["distance_refinement"]["levels_tried"].empty());
    expect_every_target(out, rep);

    const auto by_distance = run_cli(args + " --no-finer-retry");
    ASSERT_EQ(by_distance.status, 0) << by_distance.output;
    const nlohmann::json finer = read_json(report);
    EXPECT_EQ(finer["distance_refinement"]["levels_before"].get<int>(), 1);
    EXPECT_EQ(finer["distance_refinement"]["levels_tried"], nlohmann::json::array({2}));
    EXPECT_EQ(finer["distance_refinement"]["stop"], "distance met");
    EXPECT_EQ(finer["quality"]["hexes"].get<long>(), 8 * 448);

    const auto coarse = run_cli(args + " --no-finer-retry --no-distance-refinement");
    ASSERT_EQ(coarse.status, 0) << coarse.output;
    const nlohmann::json first = read_json(report);
    ASSERT_EQ(first["attempts"].size(), 1u);
    EXPECT_EQ(first["quality"]["hexes"].get<long>(), 448);
}
