// End-to-end runs of the built `mesohex` binary: quality and convert on good and malformed files.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include "cli_run.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;

namespace {

using mesohex::test::CliRun;

CliRun run(const std::string& args) { return mesohex::test::run_cli(args); }

std::string data(const std::string& name) { return std::string(MESOHEX_TEST_DATA_DIR) + "/hex/" + name; }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(Cli, HelpTextsHaveExamples) {
    const CliRun top = run("--help");
    EXPECT_EQ(top.status, 0);
    EXPECT_TRUE(contains(top.output, "quality")) << top.output;
    EXPECT_TRUE(contains(top.output, "convert")) << top.output;
    const CliRun q = run("quality --help");
    EXPECT_EQ(q.status, 0);
    EXPECT_TRUE(contains(q.output, "Example: mesohex quality")) << q.output;
    EXPECT_TRUE(contains(q.output, "5 = ")) << q.output;
    const CliRun c = run("convert --help");
    EXPECT_EQ(c.status, 0);
    EXPECT_TRUE(contains(c.output, "Example: mesohex convert")) << c.output;
}

TEST(Cli, QualityOfAValidMesh) {
    const CliRun r = run("quality " + data("two_hexes.vtk"));
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "hexes: 2")) << r.output;
    EXPECT_TRUE(contains(r.output, "euler characteristic (V-E+F-C): 1")) << r.output;
    EXPECT_TRUE(contains(r.output, "valid: yes")) << r.output;
}

TEST(Cli, QualityJson) {
    const CliRun r = run("quality --json " + data("cube.mesh"));
    EXPECT_EQ(r.status, 0) << r.output;
    for (const char* key : {"\"vertices\": 8", "\"hexes\": 1", "\"sj_min\": 1.0", "\"sj_avg\": 1.0", "\"inverted\": 0",
                            "\"euler_characteristic\": 1", "\"singular_edges\"", "\"valid\": true", "\"problems\": []"})
        EXPECT_TRUE(contains(r.output, key)) << key << "\n" << r.output;
}

TEST(Cli, QualityOfAnInvertedMeshExitsFive) {
    const CliRun r = run("quality " + data("inverted.mesh"));
    EXPECT_EQ(r.status, 5) << r.output;
    EXPECT_TRUE(contains(r.output, "inverted (<= 0): 1")) << r.output;
    EXPECT_TRUE(contains(r.output, "same_orientation_face")) << r.output;
    const CliRun j = run("quality --json " + data("inverted.mesh"));
    EXPECT_EQ(j.status, 5);
    EXPECT_TRUE(contains(j.output, "\"valid\": false")) << j.output;
}

TEST(Cli, MalformedFilesGiveFileAndLine) {
    const CliRun bad_index = run("quality " + data("bad_index.mesh"));
    EXPECT_EQ(bad_index.status, 2);
    EXPECT_TRUE(contains(bad_index.output, "bad_index.mesh:22:")) << bad_index.output;
    const CliRun nan = run("quality " + data("nan.vtk"));
    EXPECT_EQ(nan.status, 2);
    EXPECT_TRUE(contains(nan.output, "nan.vtk:8:")) << nan.output;
    const CliRun truncated = run("quality " + data("truncated.msh"));
    EXPECT_EQ(truncated.status, 2);
    EXPECT_TRUE(contains(truncated.output, "truncated.msh:30:")) << truncated.output;
    const CliRun tet = run("convert " + data("tet.vtk") + " /tmp/never_written.mesh");
    EXPECT_EQ(tet.status, 2);
    EXPECT_TRUE(contains(tet.output, "tet.vtk:17:")) << tet.output;
    EXPECT_FALSE(fs::exists("/tmp/never_written.mesh"));
}

TEST(Cli, MissingFileAndUnknownExtension) {
    const CliRun missing = run("quality " + data("missing.mesh"));
    EXPECT_EQ(missing.status, 4);
    EXPECT_TRUE(contains(missing.output, "missing.mesh")) << missing.output;
    const CliRun ext = run("quality " + data("cube.stl"));
    EXPECT_EQ(ext.status, 3);
    EXPECT_TRUE(contains(ext.output, "unknown hex mesh extension")) << ext.output;
    const CliRun usage = run("quality");
    EXPECT_NE(usage.status, 0);
}

TEST(Cli, ConvertRoundTrip) {
    const fs::path dir = fs::temp_directory_path() / ("mesohex_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string previous = data("two_hexes_crlf.mesh");
    for (const char* ext : {".vtu", ".msh", ".vtk", ".mesh"}) {
        const std::string out = (dir / (std::string("m") + ext)).string();
        const CliRun r = run("convert " + previous + " " + out);
        EXPECT_EQ(r.status, 0) << r.output;
        EXPECT_TRUE(contains(r.output, "wrote " + out + " (12 vertices, 2 hexes)")) << r.output;
        EXPECT_TRUE(contains(r.output, "valid: yes")) << r.output;
        previous = out;
    }
    const CliRun inp = run("convert " + previous + " " + (dir / "m.inp").string());
    EXPECT_EQ(inp.status, 0) << inp.output;
    EXPECT_TRUE(fs::exists(dir / "m.inp"));
    const CliRun q = run("quality --json " + previous);
    EXPECT_EQ(q.status, 0);
    EXPECT_TRUE(contains(q.output, "\"hexes\": 2")) << q.output;
    fs::remove_all(dir);
}

// The import's shape options reject values outside their range before reading anything, naming the option; nothing
// is written.
TEST(Cli, ImportRejectsOutOfRangeOptions) {
    const fs::path in = fs::temp_directory_path() / "mesohex_test_opt.ma",
                   out = fs::temp_directory_path() / "mesohex_test_opt.obj";
    std::FILE* f = std::fopen(in.string().c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("3 3 1\nv 0 0 0 0.1\nv 1 0 0 0.1\nv 0 1 0 0.1\ne 0 1\ne 1 2\ne 2 0\nf 0 1 2\n", f);
    std::fclose(f);
    fs::remove(out);
    for (const std::string bad : {"--bl-corner-back-push -1", "--reflex-corner-angle 400"}) {
        const CliRun r = run("import " + in.string() + " -o " + out.string() + " " + bad);
        EXPECT_NE(r.status, 0) << bad;
        EXPECT_TRUE(contains(r.output, bad.substr(0, bad.find(' ')))) << r.output;
        EXPECT_FALSE(fs::exists(out)) << bad;
    }
    const CliRun good = run("import " + in.string() + " -o " + out.string() + " --bl-corner-back-push 0.5");
    EXPECT_EQ(good.status, 0) << good.output;
    EXPECT_TRUE(fs::exists(out));
}
