// The readers' in-memory forms (read_hex_mesh_text, read_surface_text, read_skeleton_text, read_medial_mesh_text)
// against their file forms: on the same bytes, named by the same path, both give the same mesh or the same error
// (code and message). Inputs: the project's test files and every saved fuzz input (fuzz/corpus/<family>, whose first
// byte selects the format). Also the bounded file read under all of them (read_whole_file).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"
#include "mesohex_io/text_input.h"

namespace mesohex {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() {
    const fs::path d = fs::temp_directory_path() / ("mesohex_text_readers_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// What a reader gave: the value, or the error's code and message.
template <class T>
struct Outcome {
    bool ok = false;
    T value{};
    ErrorCode code = ErrorCode::InvalidInput;
    std::string message;
};

template <class T>
Outcome<T> run(const std::function<T()>& read) {
    Outcome<T> o;
    try {
        o.value = read();
        o.ok = true;
    } catch (const Error& e) {
        o.code = e.code();
        o.message = e.what();
    }
    return o;
}

// Writes `bytes` to a file with extension `format`, reads it with both forms (the text form named by the file's
// path) and expects the same outcome. Returns true when the input was accepted.
template <class T>
bool expect_same(const std::string& bytes, const std::string& format, const std::string& what,
                 const std::function<T(const std::string&)>& read_file,
                 const std::function<T(std::string_view, std::string_view, std::string_view)>& read_text) {
    const std::string path = (test_dir() / ("input." + format)).string();
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    const Outcome<T> from_file = run<T>([&] { return read_file(path); });
    const Outcome<T> from_text = run<T>([&] { return read_text(bytes, format, path); });
    EXPECT_EQ(from_file.ok, from_text.ok) << what << ": " << from_file.message << " | " << from_text.message;
    if (from_file.ok && from_text.ok) {
        EXPECT_TRUE(from_file.value == from_text.value) << what;
    }
    if (!from_file.ok && !from_text.ok) {
        EXPECT_EQ(from_file.code, from_text.code) << what;
        EXPECT_EQ(from_file.message, from_text.message) << what;
        EXPECT_EQ(from_file.message.rfind(path + ":", 0), 0u) << what << ": " << from_file.message;
    }
    return from_file.ok;
}

bool same_hex(const std::string& bytes, const std::string& format, const std::string& what) {
    return expect_same<HexMesh>(bytes, format, what, read_hex_mesh, read_hex_mesh_text);
}
bool same_surface(const std::string& bytes, const std::string& format, const std::string& what) {
    return expect_same<TriangleMesh>(bytes, format, what, read_surface, read_surface_text);
}
bool same_skeleton(const std::string& bytes, const std::string& format, const std::string& what) {
    return expect_same<Skeleton>(bytes, format, what, read_skeleton, read_skeleton_text);
}
bool same_medial(const std::string& bytes, const std::string& what) {
    return expect_same<Skeleton>(bytes, "ma", what, read_medial_mesh,
                                 [](std::string_view text, std::string_view, std::string_view name) {
                                     return read_medial_mesh_text(text, name);
                                 });
}

// The saved fuzz inputs of one family: (format selected by the first byte, the rest).
std::vector<std::pair<std::string, std::string>> corpus(const std::string& family,
                                                        const std::vector<std::string>& formats) {
    std::vector<fs::path> files;
    for (const fs::directory_entry& e : fs::directory_iterator(fs::path(MESOHEX_PROJECT_DIR) / "fuzz/corpus" / family))
        if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    std::vector<std::pair<std::string, std::string>> out;
    for (const fs::path& f : files) {
        const std::string bytes = slurp(f);
        if (bytes.empty()) continue;
        out.emplace_back(formats[static_cast<unsigned char>(bytes[0]) % formats.size()], bytes.substr(1));
    }
    return out;
}

TEST(TextReaders, HexFormsAgreeOnTestFilesAndCorpus) {
    int accepted = 0, inputs = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(fs::path(MESOHEX_TEST_DATA_DIR) / "hex")) {
        const std::string name = e.path().filename().string();
        accepted += same_hex(slurp(e.path()), name.substr(name.rfind('.') + 1), name);
        ++inputs;
    }
    for (const auto& [format, bytes] : corpus("hex", {"mesh", "vtk", "vtu", "msh"})) {
        accepted += same_hex(bytes, format, "corpus input " + std::to_string(inputs));
        ++inputs;
    }
    EXPECT_GT(accepted, 5);  // two_hexes.{msh,vtk,vtu}, two_hexes_crlf.mesh, two_hexes_v51.vtk, cube.mesh, ...
    EXPECT_GT(inputs - accepted, 15);  // bad_index.*, truncated.*, garbage.mesh, ...
}

TEST(TextReaders, SurfaceFormsAgreeOnCorpus) {
    int accepted = 0, inputs = 0;
    for (const auto& [format, bytes] : corpus("surface", {"off", "obj", "stl", "ply"})) {
        accepted += same_surface(bytes, format, "corpus input " + std::to_string(inputs));
        ++inputs;
    }
    EXPECT_GT(accepted, 0);
    EXPECT_GT(inputs - accepted, 0);
}

TEST(TextReaders, SkeletonFormsAgreeOnTestFilesAndCorpus) {
    int accepted = 0, inputs = 0;
    for (const fs::directory_entry& e :
         fs::recursive_directory_iterator(fs::path(MESOHEX_TEST_DATA_DIR) / "skeletons")) {
        if (!e.is_regular_file()) continue;
        const std::string name = e.path().filename().string();
        const std::string format = name.substr(name.rfind('.') + 1);
        if (format != "ig" && format != "cg" && format != "cgr" && format != "skel" && format != "obj") continue;
        accepted += same_skeleton(slurp(e.path()), format, name);
        ++inputs;
    }
    for (const auto& [format, bytes] : corpus("skeleton", {"ig", "cg", "cgr", "skel", "obj"})) {
        accepted += same_skeleton(bytes, format, "corpus input " + std::to_string(inputs));
        ++inputs;
    }
    EXPECT_GT(accepted, 5);
    EXPECT_GT(inputs - accepted, 5);
}

TEST(TextReaders, MedialFormsAgreeOnCorpus) {
    int accepted = 0, inputs = 0;
    for (const auto& [format, bytes] : corpus("medial", {"ma"})) {
        accepted += same_medial(bytes, "corpus input " + std::to_string(inputs));
        ++inputs;
    }
    EXPECT_GT(accepted, 0);
    EXPECT_GT(inputs - accepted, 0);
}

// A hand-checked case per family: what each form reads, and the same "<name>:<line>:" on a malformed line.
TEST(TextReaders, TextFormsNameTheGivenNameAndLine) {
    const HexMesh hex = read_hex_mesh_text(
        "MeshVersionFormatted 2\nDimension 3\nVertices\n8\n0 0 0 0\n1 0 0 0\n1 1 0 0\n0 1 0 0\n0 0 1 0\n1 0 1 0\n"
        "1 1 1 0\n0 1 1 0\nHexahedra\n1\n1 2 3 4 5 6 7 8 0\nEnd\n",
        "MESH", "unit.mesh");
    EXPECT_EQ(hex.points.size(), 8u);
    ASSERT_EQ(hex.hexes.size(), 1u);
    EXPECT_EQ(hex.hexes[0][6], 6);
    const TriangleMesh tri = read_surface_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "off", "tri.off");
    EXPECT_EQ(tri.points.size(), 3u);
    EXPECT_EQ(tri.triangles.size(), 1u);
    const Skeleton skel = read_skeleton_text("v 0 0 0\nv 1 0 0\nl 1 2\n", "obj", "seg.obj");
    EXPECT_EQ(skel.edges.size(), 1u);
    const Skeleton ma = read_medial_mesh_text("2 1 0\nv 0 0 0 1\nv 1 0 0 1\ne 0 1\n", "seg.ma");
    EXPECT_EQ(ma.radii.size(), 2u);

    const auto message = [](const std::function<void()>& read) {
        try {
            read();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(
        message([] { read_hex_mesh_text("MeshVersionFormatted 2\nDimension 2\n", "mesh", "m"); }).rfind("m:2: ", 0),
        0u);
    EXPECT_EQ(message([] { read_surface_text("OFF\n3 1 0\n0 0 0\n1 0 x\n", "off", "s"); }).rfind("s:4: ", 0), 0u);
    EXPECT_EQ(message([] { read_skeleton_text("v 0 0 0\nl 1 2\n", "obj", "k"); }).rfind("k:2: ", 0), 0u);
    EXPECT_EQ(message([] { read_medial_mesh_text("1 0 0\nv 0 0 0 -1\n", "a"); }).rfind("a:2: ", 0), 0u);
    // An unknown format names the input, and the format quoted short.
    EXPECT_EQ(message([] { read_hex_mesh_text("x", "stl", "n1"); }).rfind("n1: unknown hex mesh format 'stl'", 0), 0u);
    EXPECT_EQ(message([] { read_surface_text("x", "mesh", "n2"); }).rfind("n2: unknown surface format 'mesh'", 0), 0u);
    EXPECT_EQ(message([] { read_skeleton_text("x", "", "n3"); }).rfind("n3: unknown skeleton format ''", 0), 0u);
}

// read_whole_file reads at most max_bytes + 1 bytes: a larger file, or a device without end, is an IoError.
TEST(TextReaders, FileReadIsBounded) {
    const std::string path = (test_dir() / "bytes.bin").string();
    std::ofstream(path, std::ios::binary | std::ios::trunc) << std::string(3000000, 'x');  // 3 MB: several chunks
    EXPECT_EQ(read_whole_file(path).size(), 3000000u);
    EXPECT_EQ(read_whole_file(path, 3000000).size(), 3000000u);
    try {
        (void)read_whole_file(path, 2999999);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::IoError);
        EXPECT_EQ(std::string(e.what()).rfind(path + ": larger than 2999999 bytes", 0), 0u) << e.what();
    }
    if (fs::exists("/dev/zero")) {
        EXPECT_THROW((void)read_whole_file("/dev/zero", 5000000), Error);  // ends: never more than 5 MB read
    }
    EXPECT_THROW((void)read_whole_file((test_dir() / "missing.off").string()), Error);
}

}  // namespace
}  // namespace mesohex
