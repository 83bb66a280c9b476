// End-to-end runs of `mesohex mesh` on generated shapes in their own thickened domains (label slow: each runs the
// whole pipeline; together a few minutes): the quality targets for procedural shapes, and padding without inversions.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"

namespace fs = std::filesystem;
using mesohex::test::run_cli;

namespace {

fs::path temp_dir() {
    const fs::path dir = fs::path(testing::TempDir()) / "mesohex_test_cli_mesh_slow";
    fs::create_directories(dir);
    return dir;
}

nlohmann::json read_json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

}  // namespace

namespace {

// generate NAME, thicken it (--resolution 3) and mesh the skeleton in that domain with `options` (file names tagged
// with `tag`): the JSON report.
void mesh_generated(const std::string& name, const std::string& options, const std::string& tag, nlohmann::json& rep) {
    const fs::path skeleton = temp_dir() / (name + ".obj"), domain = temp_dir() / (name + ".off"),
                   out = temp_dir() / (name + tag + ".mesh"), report = temp_dir() / (name + tag + ".json");
    ASSERT_EQ(run_cli("generate " + name + " -o " + skeleton.string()).status, 0) << name;
    ASSERT_EQ(run_cli("thicken " + skeleton.string() + " -o " + domain.string() + " --resolution 3").status, 0) << name;
    const auto r = run_cli("mesh " + skeleton.string() + " --surface " + domain.string() + " -o " + out.string() +
                           " --report " + report.string() + " --quiet " + options);
    ASSERT_EQ(r.status, 0) << name << "\n" << r.output;
    rep = read_json(report);
}

}  // namespace

// Procedural meso-skeletons with leaflets in their own thickened domains (thicken --resolution 3), default command:
// the targets for procedural shapes. Measured (smoothing pass with its max-min pass, features only where the
// domain is convex-sharp, levels from the domain size): plate 6912 hexes (2 levels), SJ min 0.738, avg 0.979,
// Hausdorff 0.42 %; twist 2112, 0.814 / 0.954, 0.35 %; tfan 1248, 0.723 / 0.918, 0.63 %; xfan 1664, 0.688 / 0.903,
// 0.43 %; box 6144 (2 levels), 0.600 / 0.962, 0.71 %; bird 2880, 0.532 / 0.914, 0.74 % and turbine 4128,
// 0.501 / 0.913, 0.80 % (without the max-min pass 0.462 and 0.329: their worst hexes sit at the fans of quads around
// boundary vertices of valence 10 / 8).
// pan (branches rooted on its plates: a handle on a straight border, an arch inside; Euler characteristic 0): 2816
// hexes, 0.600 / 0.928, 0.58 % (2026-12-02).
// (Also meeting them, not run here for time: torus, hand, chair 5280 hexes 0.750 / 0.940 0.37 %, torustwist.)
TEST(MeshCli, GeneratedShapesMeetTheQualityTargets) {
    for (const std::string name : {"plate", "twist", "tfan", "xfan", "box", "bird", "turbine", "pan"}) {
        nlohmann::json rep;
        ASSERT_NO_FATAL_FAILURE(mesh_generated(name, "", "", rep));
        EXPECT_EQ(rep["quality"]["inverted"], 0) << name;
        EXPECT_EQ(rep["quality"]["valid"], true) << name;
        EXPECT_GE(rep["quality"]["sj_min"].get<double>(), 0.5) << name;
        EXPECT_GE(rep["quality"]["sj_avg"].get<double>(), 0.9) << name;
        EXPECT_LE(rep["hausdorff"]["relative_max"].get<double>(), 0.01) << name;
        // The mesh has the skeleton's Euler characteristic (1; 2 for the closed box surface).
        EXPECT_EQ(rep["quality"]["euler_characteristic"], rep["skeleton"]["euler_characteristic"]) << name;
    }
}

// The generated dualocta (a cube frame and an octahedron frame crossing at their edges' midpoints, 4-valent
// crossings, fat tubes: raw mean SJ 0.41) meets the targets too. Its raw mesh is poor, so it gets 2 levels (1 level:
// 11520 hexes, average 0.876). At 2 levels the fit leaves the boundary folded back and forth along the concave creases
// where the tubes cross; the smoothing irons those folds out only because they are not convex creases of the domain
// (as features fixed: min 0.43). The quality pass after the fit used to pull the boundary off the caps of the
// octahedron's tips (Hausdorff 1.46 %); its result is dropped when it moves the boundary away from the domain.
// Measured 92160 hexes, SJ 0.522 / 0.961, Hausdorff 0.74 %, 34 s.
TEST(MeshCli, GeneratedDualOctahedronMeetsTheTargets) {
    nlohmann::json rep;
    ASSERT_NO_FATAL_FAILURE(mesh_generated("dualocta", "", "", rep));
    EXPECT_EQ(rep["subdivision_levels"], 2);
    EXPECT_EQ(rep["quality"]["hexes"], 92160);
    EXPECT_EQ(rep["quality"]["inverted"], 0);
    EXPECT_GE(rep["quality"]["sj_min"].get<double>(), 0.5);
    EXPECT_GE(rep["quality"]["sj_avg"].get<double>(), 0.9);
    EXPECT_LE(rep["hausdorff"]["relative_max"].get<double>(), 0.01);
    EXPECT_EQ(rep["quality"]["euler_characteristic"], rep["skeleton"]["euler_characteristic"]);
}

// The generated bird's raw mesh has boundary vertices (around its valence-20 centre) whose mean normal points behind
// one of their quads: padding there gave 2 hexes inverted at any offset before the direction tilt; now none.
TEST(MeshCli, PaddingOfTheGeneratedBirdInvertsNothing) {
    nlohmann::json rep;
    ASSERT_NO_FATAL_FAILURE(mesh_generated("bird", "--no-fit --levels 0 --improve-below 0", "_pad", rep));
    ASSERT_EQ(rep["stages"][1]["stage"], "pad");
    EXPECT_EQ(rep["stages"][1]["inverted"], 0);
    EXPECT_GT(rep["stages"][1]["sj_min"].get<double>(), 0.0);
    EXPECT_EQ(rep["quality"]["inverted"], 0);
    // Its padding hexes at the valence-10 vertices are near-flat (min SJ 0.004): the pad-improve pass relaxes the
    // padded mesh before subdivision (measured 0.293).
    EXPECT_LT(rep["stages"][1]["sj_min"].get<double>(), 0.2);
    ASSERT_EQ(rep["stages"][2]["stage"], "pad-improve");
    EXPECT_EQ(rep["stages"][2]["inverted"], 0);
    EXPECT_GE(rep["stages"][2]["sj_min"].get<double>(), 0.25);
}
