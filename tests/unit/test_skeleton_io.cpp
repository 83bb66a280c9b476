#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
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

// ------------------------------------------------------------------------------------------------ binary (MHSK)

namespace {

// The error read_skeleton_text(bytes, "mhsk") throws (fails the test if nothing is thrown).
Error binary_error(const std::string& bytes) {
    try {
        (void)mesohex::read_skeleton_text(bytes, "mhsk", "body");
    } catch (const Error& e) {
        return e;
    }
    ADD_FAILURE() << "accepted " << bytes.size() << " bytes";
    return Error(ErrorCode::NumericalFailure, "not thrown");
}

void put_u32_at(std::string& bytes, std::size_t at, std::uint32_t x) {
    for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<char>((x >> (8 * k)) & 0xffu);
}

}  // namespace

TEST(SkeletonIo, BinaryLayoutOnAHandCheckedSkeleton) {
    // 7 vertices with radii, 7 edges, one quad: 32 + 24 * 7 + 8 * 7 + 8 * 7 + 4 * 1 + 4 * 4 = 332 bytes.
    const Skeleton s = sample_skeleton(true);
    const std::string b = mesohex::skeleton_binary(s);
    ASSERT_EQ(b.size(), 332u);
    EXPECT_EQ(b.substr(0, 4), "MHSK");
    EXPECT_EQ(b[8], 7);                                            // V
    EXPECT_EQ(b[16], 7);                                           // E
    EXPECT_EQ(b[24], 4);                                           // S, the quad's 4 corners
    EXPECT_EQ(b[32 + 24 * 7 + 8 * 7 + 8 * 7], 4);                  // the face's size
    EXPECT_EQ(mesohex::read_skeleton_text(b, "MHSK", "body"), s);  // bit for bit, any case of the format name
    const Skeleton no_radii = sample_skeleton(false);
    EXPECT_EQ(mesohex::skeleton_binary(no_radii).size(), 332u - 8 * 7);
    EXPECT_EQ(mesohex::read_skeleton_binary(mesohex::skeleton_binary(no_radii), "body"), no_radii);
}

TEST(SkeletonIo, BinaryReadsAsTheObjTextOfTheSameSkeleton) {
    // Missing face sides are added and repeated edges dropped, as the text readers do: the binary of a skeleton with
    // only its branch edges (and one repeated) reads as the OBJ text written from it.
    Skeleton s = sample_skeleton(true);
    s.edges = {{1, 4}, {4, 5}, {5, 4}, {6, 0}};
    const Skeleton from_binary = mesohex::read_skeleton_binary(mesohex::skeleton_binary(s), "body");
    EXPECT_EQ(from_binary.edges.size(), 3u + 4u);
    EXPECT_EQ(from_binary, mesohex::read_skeleton_text(mesohex::skeleton_text(s, "obj", "s"), "obj", "s"));
    const Skeleton ig = mesohex::read_skeleton(data("two_quads_branch.ig"));
    EXPECT_EQ(mesohex::read_skeleton_binary(mesohex::skeleton_binary(ig), "body"), ig);
}

TEST(SkeletonIo, BinaryRefusalsNameTheByteOrTheElement) {
    const std::string good = mesohex::skeleton_binary(sample_skeleton(true));
    // Every truncation and one byte too many: a length error, nothing read past the end.
    for (std::size_t n = 0; n < good.size(); ++n)
        EXPECT_EQ(binary_error(good.substr(0, n)).code(), ErrorCode::InvalidInput);
    EXPECT_NE(std::string(binary_error(good + '\0').what()).find("length 333 bytes"), std::string::npos);
    // Counts far beyond the body: refused before allocating.
    std::string huge = good;
    put_u32_at(huge, 8, 2000000000u), put_u32_at(huge, 12, 0);
    EXPECT_NE(std::string(binary_error(huge).what()).find("need"), std::string::npos);
    std::string version = good;
    put_u32_at(version, 4, 2);
    EXPECT_NE(std::string(binary_error(version).what()).find("version 2"), std::string::npos);
    // An edge naming vertex 9 of 7: the edge's index in the body.
    std::string edge = good;
    put_u32_at(edge, 32 + 24 * 7 + 8 * 7 + 8 * 4 + 4, 9);
    Error e = binary_error(edge);
    EXPECT_EQ(e.where().kind, mesohex::ElementRef::Kind::SkeletonEdge);
    EXPECT_EQ(e.where().index, 4);
    EXPECT_NE(std::string(e.what()).find("names vertex 9 but there are 7"), std::string::npos);
    // A zero radius (vertex 2), a self-loop (edge 1: 2-2), a face repeating a vertex.
    Skeleton bad = sample_skeleton(true);
    bad.radii[2] = 0;
    e = binary_error(mesohex::skeleton_binary(bad));
    EXPECT_EQ(e.where().kind, mesohex::ElementRef::Kind::SkeletonVertex);
    EXPECT_EQ(e.where().index, 2);
    bad = sample_skeleton(true);
    bad.edges[1] = {2, 2};
    EXPECT_EQ(binary_error(mesohex::skeleton_binary(bad)).where().index, 1);
    bad = sample_skeleton(true);
    bad.faces[0] = {0, 1, 1, 3};
    e = binary_error(mesohex::skeleton_binary(bad));
    EXPECT_EQ(e.where().kind, mesohex::ElementRef::Kind::SkeletonFace);
    EXPECT_NE(std::string(e.what()).find("repeats a vertex"), std::string::npos);
    bad = sample_skeleton(true);
    bad.points[5].y = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(binary_error(mesohex::skeleton_binary(bad)).where().index, 5);
}
