// `mesohex auto` on surfaces that cannot be skeletonized: a non-zero exit, the reason on stderr, nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"

namespace fs = std::filesystem;
using mesohex::test::run_cli;

namespace {

fs::path temp_dir() {
    const fs::path dir = fs::path(testing::TempDir()) / "mesohex_test_cli_auto_errors";
    fs::create_directories(dir);
    return dir;
}

void expect_rejected(const fs::path& surface, const std::string& name) {
    const fs::path out = temp_dir() / (name + ".mesh"), report = temp_dir() / (name + ".json");
    const fs::path skeleton = temp_dir() / (name + ".skeleton.obj");
    fs::remove(out);
    fs::remove(report);
    fs::remove(skeleton);
    const auto r = run_cli("auto " + surface.string() + " -o " + out.string() + " --report " + report.string());
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(report));
    EXPECT_FALSE(fs::exists(skeleton));
}

}  // namespace

// One triangle: its three edges each lie in one triangle only, so the surface is open.
TEST(AutoCliErrors, SingleTriangleIsRejectedAndNothingIsWritten) {
    const fs::path surface = temp_dir() / "triangle.obj";
    std::ofstream(surface) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    expect_rejected(surface, "triangle");
}

// A unit cube without its top face (10 triangles): the 4 top edges are boundary edges.
TEST(AutoCliErrors, OpenBoxIsRejectedAndNothingIsWritten) {
    const fs::path surface = temp_dir() / "open_box.obj";
    std::ofstream(surface) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                              "f 1 3 2\nf 1 4 3\n"   // bottom (z = 0), facing -z
                              "f 1 2 6\nf 1 6 5\n"   // y = 0
                              "f 2 3 7\nf 2 7 6\n"   // x = 1
                              "f 3 4 8\nf 3 8 7\n"   // y = 1
                              "f 4 1 5\nf 4 5 8\n";  // x = 0
    expect_rejected(surface, "open_box");
}

// Two disjoint closed tetrahedra: several components.
TEST(AutoCliErrors, TwoComponentsAreRejectedAndNothingIsWritten) {
    const fs::path surface = temp_dir() / "two_tets.obj";
    std::ofstream(surface) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                              "v 5 0 0\nv 6 0 0\nv 5 1 0\nv 5 0 1\n"
                              "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"
                              "f 5 7 6\nf 5 6 8\nf 6 7 8\nf 5 8 7\n";
    expect_rejected(surface, "two_tets");
}
