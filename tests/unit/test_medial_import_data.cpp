// Every medial mesh of ../shared/data/medial-meshes loads with the counts of the data README and converts to a valid
// quad meso-skeleton (label shared_data).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>
#include <filesystem>
#include <string>

#include "mesohex/stages/medial_import.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "quad_skeleton_checks.h"

namespace mesohex {
namespace {

struct Expected {
    const char* name;
    size_t v, e, f, curve_only;
    int sheets, fan_edges;
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
    testing::expect_valid_quad_skeleton(r.skeleton);
    testing::expect_leaflets_oriented(r.skeleton, r.face_leaflet);
    if (r.collapsed_sheets == 0) {
        EXPECT_EQ(euler_characteristic(r.skeleton), euler_characteristic(m));
        EXPECT_EQ(r.skeleton.faces.size(), 4u * static_cast<size_t>(r.paired_quads) + 3u * static_cast<size_t>(r.split_triangles));
        EXPECT_EQ(2 * r.paired_quads + r.split_triangles, static_cast<int>(x.f));
    }
}

INSTANTIATE_TEST_SUITE_P(SharedData, MedialData,
                         ::testing::Values(Expected{"hand", 40, 69, 30, 14, 1, 1},
                                           Expected{"airplane1", 53, 103, 51, 6, 2, 0},
                                           Expected{"dtorus", 29, 31, 1, 28, 1, 0},
                                           Expected{"wrench", 42, 74, 32, 9, 1, 0},
                                           Expected{"cup", 174, 473, 298, 5, 1, 0}),
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

}  // namespace
}  // namespace mesohex
