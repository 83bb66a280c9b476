// Surface file formats: small hand-written files in every supported format, round trips, and error positions.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex_io/surface_io.h"

using namespace mesohex;
namespace fs = std::filesystem;

namespace {

class SurfaceIo : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("mesohex_surface_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string write(const std::string& name, const std::string& content) {
        const std::string p = (dir_ / name).string();
        std::ofstream(p, std::ios::binary) << content;
        return p;
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    fs::path dir_;
};

// A tetrahedron.
TriangleMesh tetrahedron() {
    TriangleMesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {0, 2, 3}};  // first appearance order 0, 1, 2, 3
    return m;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

template <typename T>
void put(std::string& s, T v, bool big) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
}

// Binary PLY of the unit square: vertices with x y z (float) + red green blue (uchar) + quality (double), one quad
// face with a per-face uchar flag after the list, and an unrelated 'edge' element.
std::string binary_ply(bool big) {
    std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment test\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty double quality\n"
                    "element face 1\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
                    "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    const float xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& p : xy) {
        put<float>(s, p[0], big);
        put<float>(s, p[1], big);
        put<float>(s, 0.5f, big);
        put<std::uint8_t>(s, 255, big);
        put<std::uint8_t>(s, 10, big);
        put<std::uint8_t>(s, 0, big);
        put<double>(s, 0.25, big);
    }
    put<std::uint8_t>(s, 4, big);
    for (int v : {0, 1, 2, 3}) put<std::int32_t>(s, v, big);
    put<std::uint8_t>(s, 7, big);
    put<std::int32_t>(s, 0, big);
    put<std::int32_t>(s, 1, big);
    return s;
}

}  // namespace

TEST_F(SurfaceIo, OffWithQuadAndComments) {
    const TriangleMesh m =
        read_surface(write("a.off", "OFF\n# comment\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0 # c\n4 0 1 2 3 255 0 0\n"));
    ASSERT_EQ(m.points.size(), 4u);
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[0], (std::array<int, 3>{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (std::array<int, 3>{0, 2, 3}));
    EXPECT_EQ(m.points[2], (Vec3{1, 1, 0}));
    // Counts on the header line.
    EXPECT_EQ(read_surface(write("b.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")).triangles.size(), 1u);
}

TEST_F(SurfaceIo, ObjWithSlashesNegativeIndicesAndPolygons) {
    const TriangleMesh m = read_surface(write("a.obj",
                                              "# obj\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
                                              "f 1/1/1 2/1/1 3/1/1 4/1/1\nf -4//1 -2//1 -1//1\nl 1 2\n"));
    ASSERT_EQ(m.points.size(), 4u);
    ASSERT_EQ(m.triangles.size(), 3u);
    EXPECT_EQ(m.triangles[2], (std::array<int, 3>{0, 2, 3}));
}

TEST_F(SurfaceIo, AsciiStlMergesCorners) {
    const std::string stl =
        "solid t\n"
        " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n  endloop\n endfacet\n"
        " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n  endloop\n endfacet\n"
        "endsolid t\n";
    const TriangleMesh m = read_surface(write("a.stl", stl));
    EXPECT_EQ(m.points.size(), 4u);  // 6 corners, 4 distinct positions
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[0], (std::array<int, 3>{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (std::array<int, 3>{0, 2, 3}));
}

TEST_F(SurfaceIo, BinaryStlRoundTrip) {
    const TriangleMesh t = tetrahedron();
    const std::string p = path("t.stl");
    write_surface(p, t);
    EXPECT_EQ(fs::file_size(p), 84u + 50u * 4u);
    EXPECT_EQ(read_surface(p), t);  // exact floats; first-appearance order equals the original order here
}

TEST_F(SurfaceIo, BinaryStlStartingWithSolidIsBinary) {
    const TriangleMesh t = tetrahedron();
    const std::string p = path("t.stl");
    write_surface(p, t);
    std::string bytes;
    {
        std::ifstream in(p, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    bytes.replace(0, 5, "solid");
    EXPECT_EQ(read_surface(write("s.stl", bytes)), t);
    EXPECT_NE(error_of([&] { read_surface(write("trunc.stl", bytes.substr(0, 150))); }).find("truncated"),
              std::string::npos);
}

TEST_F(SurfaceIo, OffAndObjRoundTrip) {
    TriangleMesh t = tetrahedron();
    t.points[3] = {0.1, 1.0 / 3.0, -2.5e-7};
    for (const char* name : {"r.off", "r.obj"}) {
        write_surface(path(name), t);
        EXPECT_EQ(read_surface(path(name)), t) << name;
    }
    EXPECT_THROW(write_surface(path("r.ply"), t), Error);
    // No temporary file is left behind.
    int files = 0;
    for (const auto& e : fs::directory_iterator(dir_)) files += e.is_regular_file() ? 1 : 0;
    EXPECT_EQ(files, 2);
}

TEST_F(SurfaceIo, AsciiPlyWithColours) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\n"
        "property list uchar int vertex_indices\nend_header\n"
        "0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 1 2 3\n3 0 1 2\n3 0 2 3\n";
    const TriangleMesh m = read_surface(write("a.ply", ply));
    ASSERT_EQ(m.points.size(), 4u);
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.points[3], (Vec3{0, 1, 0}));
    EXPECT_EQ(m.triangles[1], (std::array<int, 3>{0, 2, 3}));
}

TEST_F(SurfaceIo, BinaryPlyBothEndians) {
    for (bool big : {false, true}) {
        const TriangleMesh m = read_surface(write(big ? "be.ply" : "le.ply", binary_ply(big)));
        ASSERT_EQ(m.points.size(), 4u) << big;
        ASSERT_EQ(m.triangles.size(), 2u) << big;
        EXPECT_EQ(m.points[2], (Vec3{1, 1, 0.5})) << big;
        EXPECT_EQ(m.triangles[0], (std::array<int, 3>{0, 1, 2})) << big;
        EXPECT_EQ(m.triangles[1], (std::array<int, 3>{0, 2, 3})) << big;
    }
    const std::string b = binary_ply(false);
    EXPECT_NE(error_of([&] { read_surface(write("cut.ply", b.substr(0, b.size() - 20))); }).find("end of file"),
              std::string::npos);
}

TEST_F(SurfaceIo, ErrorsNameFileAndLine) {
    const std::string p = write("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n");
    EXPECT_NE(error_of([&] { read_surface(p); }).find(p + ":4:"), std::string::npos);
    const std::string q = write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n");
    EXPECT_NE(error_of([&] { read_surface(q); }).find(q + ":4:"), std::string::npos);
    const std::string r = write("bad2.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    const std::string e = error_of([&] { read_surface(r); });
    EXPECT_NE(e.find(r + ":6:"), std::string::npos) << e;
    EXPECT_NE(error_of([&] { read_surface(write("short.off", "OFF\n3 1 0\n0 0 0\n")); }).find("missing"),
              std::string::npos);
    EXPECT_NE(error_of([&] {
                  read_surface(write("x.ply", "ply\nformat ascii 1.0\nelement vertex 1\nend_header\n"));
              }).find(":3:"),
              std::string::npos);
    try {
        read_surface(path("does_not_exist.off"));
        FAIL();
    } catch (const Error& ex) {
        EXPECT_EQ(ex.code(), ErrorCode::IoError);
    }
    // A corrupt header announcing 900 million vertices is an error, not an allocation failure.
    EXPECT_NE(error_of([&] { read_surface(write("huge.off", "OFF\n900000000 1 0\n0 0 0\n")); }).find("missing"),
              std::string::npos);
    EXPECT_THROW(read_surface(write("a.xyz", "")), Error);
    EXPECT_THROW(read_surface(write("empty.obj", "v 0 0 0\n")), Error);  // no triangle
    // A face size of the largest long long is "fewer vertices listed" at its line (it used to overflow n + 1: UBSan).
    EXPECT_NE(error_of([] {
                  read_surface_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n9223372036854775807 0 1 2\n", "off", "big");
              }).find("big:6: face lists fewer than 9223372036854775807 vertices"),
              std::string::npos);
}
