// `mesohex analyze` gives the verdict of `mesohex mesh` (exit statuses) on every generated shape, on skeletons whose
// configurations mesh repairs before meshing (branches on fan-edge ends, walls docked on plates) and on ones it
// refuses: analyze runs the same repairs (pipeline.h prepare_skeleton) before its analysis.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"

namespace {

namespace fs = std::filesystem;
using mesohex::test::CliRun;
using mesohex::test::run_cli;

fs::path test_dir() {
    const fs::path d = fs::temp_directory_path() / ("mesohex_cli_analyze_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// mesh's exit status as a verdict: 0 and 5 (a mesh written, with inverted hexes) are both "accepted".
int mesh_verdict(int status) { return status == 5 ? 0 : status; }

struct Verdicts {
    CliRun analyze, analyze_only, mesh;
};

// analyze (with and without the verdict) and mesh (raw mesh, nothing else) of `skeleton` with `flags`.
Verdicts verdicts(const std::string& skeleton, const std::string& flags) {
    const std::string out = (test_dir() / "raw.mesh").string();
    fs::remove(out);
    return {run_cli("analyze " + skeleton + flags), run_cli("analyze " + skeleton + flags + " --no-verdict"),
            run_cli("mesh " + skeleton + flags + " -q -o " + out)};
}

// Checks the agreement and returns the shared verdict (-1 when they disagree).
int expect_same_verdict(const std::string& what, const Verdicts& v) {
    const int m = mesh_verdict(v.mesh.status);
    EXPECT_EQ(v.analyze.status, m) << what << "\nanalyze:\n" << v.analyze.output << "\nmesh:\n" << v.mesh.output;
    // Without the verdict analyze stops after the repairs and the analysis: it may accept a skeleton that mesh
    // refuses later (connection surfaces, raw mesh), never refuse one mesh accepts.
    if (m == 0) {
        EXPECT_EQ(v.analyze_only.status, 0) << what << "\nanalyze --no-verdict:\n" << v.analyze_only.output;
    }
    return v.analyze.status == m ? m : -1;
}

std::vector<std::string> generator_names() {
    const CliRun list = run_cli("generate --list", false);
    std::vector<std::string> names;
    std::istringstream in(list.output);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) names.push_back(line);
    return names;
}

std::string generate(const std::string& file, const std::string& args) {
    const std::string path = (test_dir() / file).string();
    const CliRun g = run_cli("generate " + args + " -o " + path);
    EXPECT_EQ(g.status, 0) << args << ": " << g.output;
    return path;
}

}  // namespace

// Every generated shape, resampled (the default) and with its input sampling: same exit status. Most are accepted;
// the count is a fact of the generator list (every shape meshes with resampling, docs/generators).
TEST(CliAnalyze, SameVerdictAsMeshOnEveryGeneratedShape) {
    const std::vector<std::string> names = generator_names();
    ASSERT_GE(names.size(), 20u);
    int accepted = 0;
    for (const std::string& name : names) {
        const std::string path = generate(name + ".obj", name);
        for (const char* flags : {"", " --no-resample"}) {
            const int v = expect_same_verdict(name + flags, verdicts(path, flags));
            if (v == 0 && flags[0] == '\0') ++accepted;
        }
    }
    EXPECT_EQ(accepted, static_cast<int>(names.size()));  // every shape meshes with the defaults
}

// Branches on fan-edge ends: the T and X fans with a branch continuing the fan line stand on the fan block's cap
// (design note C1; analyze names the input vertex, with and without resampling) and, with --no-fan-cap-branches, are
// meshed after the retraction (refused without resampling: no repair then); perpendicular ones after the root moves
// onto a leaflet border; a branch leaning back (135 degrees) has its first edge bent. A branch on the end of a single
// fan edge stands on the cap too, and with --no-fan-cap-branches is meshed after the repair splits the fan edge and
// retracts one half (refused without resampling). Docked walls (inside the plate, on both sides, from the border) are
// accepted by both.
TEST(CliAnalyze, SameVerdictAsMeshOnRepairedConfigurations) {
    const std::string retract = " --no-fan-cap-branches";
    for (const char* n : {"3", "4"}) {
        const std::string cont = generate(std::string("fanend") + n + "c.obj", std::string("fanend -n ") + n + " -m 1");
        const Verdicts c = verdicts(cont, "");
        EXPECT_EQ(expect_same_verdict(cont, c), 0);
        EXPECT_TRUE(contains(c.analyze.output,
                             "repairs: none\nbranches standing on fan blocks' caps (not retracted): at input "
                             "vertices 2\n"))
            << c.analyze.output;
        EXPECT_EQ(expect_same_verdict(cont + " --no-resample", verdicts(cont, " --no-resample")), 0);
        const Verdicts r = verdicts(cont, retract);
        EXPECT_EQ(expect_same_verdict(cont + retract, r), 0);
        EXPECT_TRUE(contains(r.analyze.output,
                             "repairs: fan edges retracted from branches on fan-edge ends: at input "
                             "vertices "))
            << r.analyze.output;
        EXPECT_TRUE(contains(r.analyze_only.output, "repairs: fan edges retracted")) << r.analyze_only.output;
        EXPECT_FALSE(contains(r.analyze.output, "caps")) << r.analyze.output;
        EXPECT_EQ(expect_same_verdict(cont + retract + " --no-resample", verdicts(cont, retract + " --no-resample")),
                  3);
        const std::string perp = generate(std::string("fanend") + n + "p.obj", std::string("fanend -n ") + n + " -m 2");
        EXPECT_EQ(expect_same_verdict(perp, verdicts(perp, "")), 0);  // the root moved onto a leaflet border
        const std::string back = generate(std::string("fanend") + n + "b.obj", std::string("fanend -n ") + n + " -m 5");
        EXPECT_EQ(expect_same_verdict(back, verdicts(back, "")), 0);  // moved, its first edge bent onto the normal
    }
    // T fan on a single fan edge (0,0,0)-(1,0,0), three 1 x 1 strips, a 2-edge branch from (1,0,0) along +x.
    const std::string single = (test_dir() / "single_fan_edge.obj").string();
    std::ofstream(single) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 -1 0\nv 1 -1 0\nv 0 0 1\nv 1 0 1\n"
                             "v 2 0 0\nv 3 0 0\nf 1 2 4 3\nf 2 1 5 6\nf 1 2 8 7\nl 2 9\nl 9 10\n";
    const Verdicts cap = verdicts(single, " --radius 0.3");
    EXPECT_EQ(expect_same_verdict(single, cap), 0);
    EXPECT_TRUE(contains(cap.analyze.output, "caps (not retracted): at input vertices 1\n")) << cap.analyze.output;
    const Verdicts s = verdicts(single, " --radius 0.3" + retract);
    EXPECT_EQ(expect_same_verdict(single, s), 0);
    EXPECT_EQ(s.mesh.status, 0) << s.mesh.output;  // no inverted raw hex
    EXPECT_TRUE(contains(s.analyze.output, "repairs: fan-edge chains split")) << s.analyze.output;
    EXPECT_TRUE(contains(s.analyze.output, "branches on fan-edge ends: at input vertices 1")) << s.analyze.output;
    const Verdicts raw = verdicts(single, " --radius 0.3 --no-resample" + retract);
    EXPECT_EQ(expect_same_verdict(single + " --no-resample", raw), 3);
    EXPECT_TRUE(contains(raw.analyze.output, "skeleton vertex 1")) << raw.analyze.output;
    for (const char* wall : {"wall", "wallboth", "walledge", "walledgeboth"}) {
        const std::string path = generate(std::string(wall) + ".obj", wall);
        EXPECT_EQ(expect_same_verdict(path, verdicts(path, "")), 0);
        EXPECT_EQ(expect_same_verdict(path + " --no-resample", verdicts(path, " --no-resample")), 0);
    }
}

// The random evaluation set's first seeds (trees and sheets): same verdict.
TEST(CliAnalyze, SameVerdictAsMeshOnRandomSkeletons) {
    for (int seed = 1; seed <= 8; ++seed) {
        const std::string path = generate("random" + std::to_string(seed) + ".obj", "--random " + std::to_string(seed));
        expect_same_verdict(path, verdicts(path, ""));
    }
}

// With --surface, analyze makes mesh's trims: a straight branch (r 0.25, joints at x = 0.5 ... 3.5, then 4.2 and 4.6)
// in the box [0, 4] x [0, 1]^2 loses its two joints outside; the verdict is the raw mesh of the 3-long branch, 8 edges
// of 0.375 (MeshSkeleton.BranchTipsOutsideTheDomainAreTrimmed), 32 hexes; with --no-trim-tips 16 edges, 64 hexes.
TEST(CliAnalyze, WithASurfaceTipsOutsideItAreTrimmed) {
    const fs::path skel = test_dir() / "branch.skel";
    const fs::path box = test_dir() / "box.off";
    std::ofstream(skel) << "ID Cx Cy Cz RADIUS #NEIGHBORS NEIGHBORS_LIST\n6\n0 0.5 0.5 0.5 0.25 1 1\n"
                           "1 1.5 0.5 0.5 0.25 2 0 2\n2 2.5 0.5 0.5 0.25 2 1 3\n3 3.5 0.5 0.5 0.25 2 2 4\n"
                           "4 4.2 0.5 0.5 0.25 2 3 5\n5 4.6 0.5 0.5 0.25 1 4\n";
    std::ofstream(box) << "OFF\n8 12 0\n0 0 0\n4 0 0\n4 1 0\n0 1 0\n0 0 1\n4 0 1\n4 1 1\n0 1 1\n"
                          "3 0 3 2\n3 0 2 1\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n"
                          "3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";
    const CliRun on = run_cli("analyze " + skel.string() + " --surface " + box.string());
    EXPECT_EQ(on.status, 0) << on.output;
    EXPECT_TRUE(contains(on.output,
                         "repairs: branch tips outside the domain trimmed: input vertices 4 5 removed; "
                         "the branch now ends at input vertices 3"))
        << on.output;
    EXPECT_TRUE(contains(on.output, "raw mesh of 32 hexes")) << on.output;
    const CliRun off = run_cli("analyze " + skel.string() + " --surface " + box.string() + " --no-trim-tips");
    EXPECT_FALSE(contains(off.output, "trimmed")) << off.output;
    EXPECT_TRUE(contains(off.output, "raw mesh of 64 hexes")) << off.output;
    const CliRun no_surface = run_cli("analyze " + skel.string());
    EXPECT_TRUE(contains(no_surface.output, "raw mesh of 64 hexes")) << no_surface.output;
}
