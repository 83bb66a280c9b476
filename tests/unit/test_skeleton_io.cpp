#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex_io/skeleton_io.h"

using mesohex::Error;
using mesohex::ErrorCode;
using mesohex::Skeleton;
using mesohex::Vec3;

namespace {

std::string data(const std::string& name) { return std::string(MESOHEX_TEST_DATA_DIR) + "/skeletons/" + name; }

std::string temp_path(const std::string& name) {
    return (std::filesystem::path(testing::TempDir()) / ("mesohex_skeleton_io_" + name)).string();
}

// Reads a malformed file and returns the error (fails the test if nothing is thrown).
Error read_error(const std::string& path) {
    try {
        (void)mesohex::read_skeleton(path);
    } catch (const Error& e) {
        return e;
    }
    ADD_FAILURE() << path << " was accepted";
    return Error(ErrorCode::NumericalFailure, "not thrown");
}

// The message must start with "<path>:<line>: ".
void expect_file_line(const std::string& name, int line, const std::string& what_fragment) {
    const std::string path = data("bad/" + name);
    const Error e = read_error(path);
    EXPECT_EQ(e.code(), ErrorCode::InvalidInput) << name;
    const std::string prefix = path + ":" + std::to_string(line) + ": ";
    EXPECT_EQ(std::string(e.what()).substr(0, prefix.size()), prefix) << e.what();
    EXPECT_NE(std::string(e.what()).find(what_fragment), std::string::npos) << e.what();
    EXPECT_EQ(e.where().kind, mesohex::ElementRef::Kind::FileLine);
    EXPECT_EQ(e.where().index, line);
}

// A meso-skeleton with a quad leaflet, a branch and radii, with a face traversing an edge against its storage order.
Skeleton sample_skeleton(bool with_radii) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0.1, -0.25}, {0.1, 0.2, 0.3}};
    s.edges = {{0, 1}, {2, 1}, {2, 3}, {3, 0}, {1, 4}, {4, 5}, {6, 0}};
    s.faces = {{0, 1, 2, 3}};
    if (with_radii) s.radii = {0.1, 0.2, 0.3, 0.4, 0.123456789012345, 1e-5, 7.0};
    return s;
}

}  // namespace

TEST(SkeletonIo, CgReadsVerticesAndEdges) {
    const Skeleton s = mesohex::read_skeleton(data("path3.cg"));
    ASSERT_EQ(s.points.size(), 3u);
    EXPECT_EQ(s.points[2], (Vec3{2, 0.5, 0}));
    EXPECT_EQ(s.edges, (std::vector<std::array<int, 2>>{{0, 1}, {1, 2}}));
    EXPECT_TRUE(s.radii.empty());
    EXPECT_TRUE(s.faces.empty());
}

TEST(SkeletonIo, CgAcceptsAFourthValueAsRadius) {
    const Skeleton s = mesohex::read_skeleton(data("path3_radius.cg"));
    EXPECT_EQ(s.radii, (std::vector<double>{0.5, 0.5, 0.5}));
}

TEST(SkeletonIo, CgWithRadiusOnSomeLinesOnlyHasNoRadius) {
    const Skeleton s = mesohex::read_skeleton(data("mixed_radius.cg"));
    EXPECT_EQ(s.points.size(), 3u);
    EXPECT_EQ(s.points[1], (Vec3{0, -3, 0}));
    EXPECT_TRUE(s.radii.empty());
}

TEST(SkeletonIo, CgrHeaderVariantsCrlfAndNoFinalNewline) {
    // "# D:4 NV: 3 NE: 2", CRLF line ends, no newline after the last line.
    const Skeleton s = mesohex::read_skeleton(data("path3_variant.cgr"));
    ASSERT_EQ(s.points.size(), 3u);
    EXPECT_EQ(s.edges.size(), 2u);
    EXPECT_EQ(s.radii, (std::vector<double>{0.25, 0.25, 0.2}));
}

TEST(SkeletonIo, SkelMapsNonContiguousUnsortedIds) {
    // ids 10, 3, 7, 42 in file order -> rows 0, 1, 2, 3; edges 10-3, 3-7 (listed from both sides), 42-3 (one side).
    const Skeleton s = mesohex::read_skeleton(data("sparse_ids.skel"));
    ASSERT_EQ(s.points.size(), 4u);
    EXPECT_EQ(s.points[3], (Vec3{1, 1, 0}));
    EXPECT_EQ(s.radii, (std::vector<double>{0.1, 0.2, 0.3, 0.4}));
    EXPECT_EQ(s.edges, (std::vector<std::array<int, 2>>{{0, 1}, {1, 2}, {3, 1}}));
}

TEST(SkeletonIo, IgFacesBecomeVertexCycles) {
    const Skeleton s = mesohex::read_skeleton(data("two_quads_branch.ig"));
    ASSERT_EQ(s.points.size(), 7u);
    EXPECT_EQ(s.edges.size(), 8u);
    ASSERT_EQ(s.faces.size(), 2u);
    // Face A lists e0 (0-1), e5 (1-4), e2 (3-4), e4 (0-3): the cycle starts along e0 towards e5.
    EXPECT_EQ(s.faces[0], (std::vector<int>{0, 1, 4, 3}));
    // Face B lists e6 (2-5), e1 (1-2), e5 (1-4), e3 (4-5): e6 is entered at 5 so that e1 follows it.
    EXPECT_EQ(s.faces[1], (std::vector<int>{5, 2, 1, 4}));
    EXPECT_TRUE(s.radii.empty());
}

TEST(SkeletonIo, ObjPolylinesFacesSlashFormsNegativeIndicesAndRadiusComments) {
    const Skeleton s = mesohex::read_skeleton(data("blender.obj"));
    ASSERT_EQ(s.points.size(), 6u);
    EXPECT_EQ(s.points[4], (Vec3{2, 0, 0}));  // the 4th number on a 'v' line is not a radius
    // 'l 2 5 6' -> 1-4, 4-5; 'f 1 2 -4 -3' (6 vertices read) -> 0 1 2 3, whose 4 sides are added after.
    EXPECT_EQ(s.edges, (std::vector<std::array<int, 2>>{{1, 4}, {4, 5}, {0, 1}, {1, 2}, {2, 3}, {3, 0}}));
    EXPECT_EQ(s.faces, (std::vector<std::vector<int>>{{0, 1, 2, 3}}));
    EXPECT_EQ(s.radii, (std::vector<double>{0.1, 0.2, 0.3, 0.4, 0.5, 0.6}));
}

TEST(SkeletonIo, DuplicateEdgesAreDroppedInEitherOrientation) {
    const Skeleton s = mesohex::read_skeleton(data("duplicate_edges.cg"));
    EXPECT_EQ(s.edges, (std::vector<std::array<int, 2>>{{0, 1}, {1, 2}}));
}

TEST(SkeletonIo, MalformedFilesNameFileAndLine) {
    expect_file_line("empty.cg", 1, "empty file");
    expect_file_line("blank.skel", 1, "empty file");
    expect_file_line("truncated_header.cg", 1, "malformed header");
    expect_file_line("wrong_vertex_count.cg", 6, "NV 4");
    expect_file_line("missing_vertex.cg", 6, "vertex 7");
    expect_file_line("non_numeric.cgr", 3, "'abc'");
    expect_file_line("nan.cgr", 3, "non-finite");
    expect_file_line("missing_radius.cgr", 3, "radius");
    expect_file_line("self_loop.cg", 5, "self-loop");
    expect_file_line("negative_radius.skel", 4, "must be positive");
    expect_file_line("truncated.skel", 4, "truncated");
    expect_file_line("unknown_neighbour.skel", 4, "neighbour id 5");
    expect_file_line("neighbour_count.skel", 3, "neighbour count");
    expect_file_line("face_not_cycle.ig", 11, "cycle");
    expect_file_line("trailing.ig", 6, "after the last face");
    expect_file_line("truncated.ig", 4, "end of file");
    expect_file_line("missing_vertex.obj", 3, "vertex 9");
    expect_file_line("zero_index.obj", 4, "index 0");
    expect_file_line("partial_radius.obj", 4, "1 of 2");
}

// A radius comment naming vertex -9223372036854775808 (OBJ, 1-based) is out of range, not an overflow of
// "index - 1" (UBSan finding; fuzz/corpus/skeleton/obj_radius_index_min).
TEST(SkeletonIo, SmallestRadiusIndexIsOutOfRange) {
    try {
        mesohex::read_skeleton_text("v 0 0 0\nv 1 0 0\nl 1 2\n# mesohex radius -9223372036854775808 1\n", "obj",
                                    "r.obj");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "r.obj:4: radius vertex index out of range: -9223372036854775808");
    }
}

// Every prefix of every good test file (a file cut at any byte) either reads or throws mesohex::Error; nothing else.
TEST(SkeletonIo, TruncatedFilesNeverCrash) {
    for (const std::string name :
         {"path3.cg", "path3_variant.cgr", "sparse_ids.skel", "two_quads_branch.ig", "blender.obj"}) {
        std::ifstream in(data(name), std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ASSERT_FALSE(text.empty()) << name;
        const std::string path = temp_path("cut_" + name);
        int errors = 0;
        for (std::size_t len = 0; len <= text.size(); ++len) {
            {
                std::ofstream out(path, std::ios::binary | std::ios::trunc);
                out.write(text.data(), static_cast<std::streamsize>(len));
            }
            try {
                const Skeleton s = mesohex::read_skeleton(path);
                for (const std::array<int, 2>& e : s.edges) {
                    EXPECT_LT(e[0], static_cast<int>(s.points.size()));
                    EXPECT_LT(e[1], static_cast<int>(s.points.size()));
                }
            } catch (const Error& e) {
                ++errors;
                EXPECT_EQ(std::string(e.what()).rfind(path + ":", 0), 0u) << e.what();
            }
        }
        EXPECT_GT(errors, 0) << name;  // the empty prefix at least
        std::remove(path.c_str());
    }
}

TEST(SkeletonIo, MissingFileAndUnknownExtension) {
    try {
        (void)mesohex::read_skeleton(data("does_not_exist.cg"));
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::IoError);
    }
    try {
        (void)mesohex::read_skeleton(data("path3.xyz"));
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
    }
}

TEST(SkeletonIo, RoundTripIgAndObjWithAndWithoutRadii) {
    for (const bool radii : {true, false}) {
        const Skeleton s = sample_skeleton(radii);
        for (const std::string ext : {"ig", "obj"}) {
            const std::string path = temp_path(std::string(radii ? "r." : "nr.") + ext);
            mesohex::write_skeleton(path, s);
            EXPECT_EQ(mesohex::read_skeleton(path), s) << path;
            std::remove(path.c_str());
        }
    }
}

TEST(SkeletonIo, RoundTripOfAReadFile) {
    const Skeleton s = mesohex::read_skeleton(data("two_quads_branch.ig"));
    const std::string path = temp_path("again.ig");
    mesohex::write_skeleton(path, s);
    EXPECT_EQ(mesohex::read_skeleton(path), s);
    std::remove(path.c_str());
}

TEST(SkeletonIo, WriteFailuresLeaveNoFile) {
    const std::string dir = temp_path("no_such_dir");
    std::filesystem::remove_all(dir);
    try {
        mesohex::write_skeleton(dir + "/out.ig", sample_skeleton(true));
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::IoError);
    }
    EXPECT_FALSE(std::filesystem::exists(dir));
    // A face side missing from the edge list cannot be written as .ig; nothing is written.
    Skeleton bad = sample_skeleton(false);
    bad.edges.erase(bad.edges.begin());
    const std::string path = temp_path("bad_face.ig");
    std::remove(path.c_str());
    EXPECT_THROW(mesohex::write_skeleton(path, bad), Error);
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_THROW(mesohex::write_skeleton(temp_path("x.cg"), bad), Error);
}
