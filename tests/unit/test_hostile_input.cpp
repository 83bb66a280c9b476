// Issue 18: hostile input and interruptions. Every reader bounds its work by the file size, quotes at most ~80
// escaped characters, names empty files; stale temporaries of a killed run are removed; every subcommand gives the
// same verdict on the same input. Large inputs are generated here (nothing big is committed).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <new>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_run.h"
#include "mesohex/core/error.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() {
    const fs::path d = fs::temp_directory_path() / ("mesohex_hostile_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}

std::string write_file(const std::string& name, const std::string& bytes) {
    const std::string path = (test_dir() / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

// Runs `read` on `path` and returns the Error it must throw.
Error expect_error(const std::function<void()>& read, const std::string& path) {
    try {
        read();
    } catch (const Error& e) {
        return e;
    }
    ADD_FAILURE() << "no error for " << path;
    return Error(ErrorCode::NumericalFailure, "none");
}

bool printable_ascii(const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](char c) { return c >= 0x20 && c < 0x7f; });
}

// All the readers, by extension.
void read_any(const std::string& path) {
    const std::string ext = path.substr(path.rfind('.') + 1);
    if (ext == "mesh" || ext == "vtk" || ext == "vtu" || ext == "msh")
        (void)read_hex_mesh(path);
    else if (ext == "ma")
        (void)read_medial_mesh(path);
    else if (ext == "off" || ext == "stl" || ext == "ply")
        (void)read_surface(path);
    else
        (void)read_skeleton(path);
}

// A face of 100 000 edges listed in random order: chained in O(k log k) (it took 13.8 s when each step rescanned the
// face), into the ring's vertex cycle.
TEST(HostileInput, IgLongFaceIsChainedInLinearTime) {
    const int n = 100000;
    std::string text = "IG\n" + std::to_string(n) + " " + std::to_string(n) + " 1\n";
    for (int v = 0; v < n; ++v) text += std::to_string(v % 317) + " " + std::to_string(v / 317) + " 0\n";
    for (int e = 0; e < n; ++e) text += std::to_string(e) + " " + std::to_string((e + 1) % n) + "\n";
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin() + 2, order.end(), std::mt19937(18));  // the first two fix the direction
    text += std::to_string(n);
    for (const int e : order) {
        text += ' ';
        text += std::to_string(e);
    }
    text += "\n";
    const Skeleton s = read_skeleton(write_file("ring.ig", text));
    ASSERT_EQ(s.faces.size(), 1u);
    ASSERT_EQ(static_cast<int>(s.faces[0].size()), n);
    for (int i = 0; i < n; ++i) EXPECT_EQ(s.faces[0][i], i) << i;  // 0, 1, 2, ... : edge 0 then edge 1
    EXPECT_EQ(static_cast<int>(s.edges.size()), n);
    // A face whose edges are not one cycle (two triangles) is still refused, naming the face's line.
    const std::string bad = write_file("two.ig",
                                       "IG\n6 6 1\n0 0 0\n1 0 0\n0 1 0\n5 0 0\n6 0 0\n5 1 0\n"
                                       "0 1\n1 2\n2 0\n3 4\n4 5\n5 3\n6 0 1 2 3 4 5\n");
    const Error e = expect_error([&] { (void)read_skeleton(bad); }, bad);
    EXPECT_NE(std::string(e.what()).find(bad + ":15: face edges do not form a single closed cycle"), std::string::npos)
        << e.what();
}

std::string binary_tetra_ply(const std::string& extra_elements) {
    std::string head = "ply\nformat binary_little_endian 1.0\n" + extra_elements +
                       "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                       "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
    const float pts[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int tris[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto& p : pts) head.append(reinterpret_cast<const char*>(p), sizeof p);
    for (const auto& t : tris) {
        head += static_cast<char>(3);
        head.append(reinterpret_cast<const char*>(t), sizeof t);
    }
    return head;
}

// A binary PLY element without properties and a count of 2e9 (100 of them) takes no bytes: skipped at once (it was
// "read" 2e9 times, 6.6 s each). An element with a property and a count the file cannot hold is refused at its line.
TEST(HostileInput, PlyElementsBoundedByTheFile) {
    std::string empties;
    for (int i = 0; i < 100; ++i) empties += "element nothing" + std::to_string(i) + " 2000000000\n";
    const TriangleMesh m = read_surface(write_file("empties.ply", binary_tetra_ply(empties)));
    EXPECT_EQ(m.points.size(), 4u);
    EXPECT_EQ(m.triangles.size(), 4u);
    const std::string big = write_file("big.ply", binary_tetra_ply("element extra 2000000000\nproperty uchar a\n"));
    const Error e = expect_error([&] { (void)read_surface(big); }, big);
    EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
    EXPECT_EQ(e.where().index, 3) << e.what();
    EXPECT_NE(std::string(e.what()).find(big + ":3: 'extra' element count 2000000000 is more than"), std::string::npos)
        << e.what();
}

// Header counts larger than the file can hold are refused at the header line, or (OFF) only what the file can hold
// is reserved and the reader fails where the data ends: no huge allocation either way.
TEST(HostileInput, HeaderCountsBoundedByFileSize) {
    struct Case {
        const char* name;
        const char* text;
        int line;
    };
    const Case cases[] = {
        {"huge.ma", "2147483648 0 0\n", 1},
        {"huge.off", "OFF\n1000000000 1 0\n0 0 0\n", 3},  // reserves what 12 bytes hold, fails where data ends
        {"huge.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n999999999\n0 0 0 0\nEnd\n", 4},
        {"huge.vtk",
         "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 100000000 double\n0 0 0\n", 5},
        {"huge.vtu",
         "<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"1000000000\" "
         "NumberOfCells=\"1\">\n</Piece></UnstructuredGrid></VTKFile>\n",
         3},
        {"huge.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 500000000 1 500000000\n", 5},
    };
    for (const Case& c : cases) {
        const std::string path = write_file(c.name, c.text);
        const Error e = expect_error([&] { read_any(path); }, path);
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput) << e.what();
        EXPECT_NE(std::string(e.what()).find(path + ":" + std::to_string(c.line) + ": "), std::string::npos)
            << e.what();
    }
}

// A 2 MB token (with binary bytes) is quoted at most 80 characters long, escaped; the message stays short and
// printable whatever the reader.
TEST(HostileInput, LongAndBinaryTokensAreQuotedShortAndEscaped) {
    std::string token = "\x01\xff";
    while (token.size() < 2'000'000) token += "abc\x80\x1b[31m";
    const std::pair<const char*, std::string> cases[] = {
        {"long.ma", "1 0 0\nv 0 0 0 " + token + "\n"},
        {"long.off", "OFF\n1 1 0\n0 0 " + token + "\n3 0 0 0\n"},
        {"long.obj", "v 0 0 " + token + "\n"},
        {"long.cg", "# D:3 NV:1 NE:0\nv 0 0 " + token + "\n"},
        {"long.mesh", "MeshVersionFormatted 2\n" + token + "\n"},
        {"long.vtk", "# vtk DataFile Version 2.0\nt\nASCII\nDATASET " + token + "\n"},
        {"long.msh", "$MeshFormat\n" + token + " 0 8\n$EndMeshFormat\n"},
        {"long.ply", "ply\nformat ascii 1.0\n" + token + "\nend_header\n"},
    };
    for (const auto& [name, text] : cases) {
        const std::string path = write_file(name, text);
        const Error e = expect_error([&] { read_any(path); }, path);
        const std::string msg = e.what();
        EXPECT_LT(msg.size(), path.size() + 300) << name << ": " << msg.substr(0, 400);
        EXPECT_TRUE(printable_ascii(msg)) << name;
        if (std::string(name) != "long.ma") {  // the .ma reader says "malformed 'v' line", quoting nothing
            EXPECT_NE(msg.find("bytes)"), std::string::npos) << name << ": " << msg.substr(0, 400);
        }
        fs::remove(path);
    }
}

// An empty (or all-whitespace) file is named as such, never "line 0".
TEST(HostileInput, EmptyFilesAreReportedAsEmpty) {
    for (const char* name :
         {"e.ma", "e.off", "e.ply", "e.stl", "e.ig", "e.cg", "e.skel", "e.obj", "e.mesh", "e.vtk", "e.vtu", "e.msh"}) {
        for (const char* text : {"", " \n\r\n\t"}) {
            const std::string path = write_file(name, text);
            const Error e = expect_error([&] { read_any(path); }, path);
            EXPECT_EQ(e.code(), ErrorCode::InvalidInput) << e.what();
            EXPECT_EQ(std::string(e.what()).rfind(path + ":1: empty file (", 0), 0u) << e.what();
            EXPECT_EQ(std::string(e.what()).find(":0:"), std::string::npos) << e.what();
        }
    }
}

// Temporaries "<target>.tmp.<pid>.<n>" of a dead process are removed by the next write to the same target; a live
// process's, another target's and other names are kept.
TEST(HostileInput, StaleTemporariesAreRemovedOnTheNextWrite) {
    const fs::path dir = test_dir() / "tmpclean";
    fs::create_directories(dir);
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ASSERT_GT(child, 0);
    ::waitpid(child, nullptr, 0);  // `child` is now a pid of no process
    const std::string dead = std::to_string(child), alive = std::to_string(::getppid());
    const std::string target = (dir / "out.mesh").string();
    const std::vector<std::string> stale = {"out.mesh.tmp." + dead + ".0", "out.mesh.tmp." + dead + ".17"};
    const std::vector<std::string> kept = {"out.mesh.tmp." + alive + ".3", "out.mesh.tmp.x" + dead + ".0",
                                           "other.mesh.tmp." + dead + ".0", "out.mesh.tmp." + dead,
                                           "out.mesh.tmp." + dead + ".1.bak"};
    for (const std::string& f : stale) std::ofstream(dir / f) << "half-written";
    for (const std::string& f : kept) std::ofstream(dir / f) << "keep";
    write_file_atomically(target, "content\n");
    for (const std::string& f : stale) EXPECT_FALSE(fs::exists(dir / f)) << f;
    for (const std::string& f : kept) EXPECT_TRUE(fs::exists(dir / f)) << f;
    std::ifstream in(target);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "content");
    fs::remove_all(dir);
}

// Foreign exceptions (std::bad_alloc, CGAL::Failure_exception which is a std::logic_error, Eigen, TBB) become
// NumericalFailure naming the context, with the documented exit status 6.
TEST(HostileInput, ForeignExceptionsBecomeDocumentedErrors) {
    const Error oom = foreign_error(std::bad_alloc(), "in.off: skeletonize");
    EXPECT_EQ(oom.code(), ErrorCode::NumericalFailure);
    EXPECT_EQ(std::string(oom.what()), "in.off: skeletonize: out of memory");
    EXPECT_EQ(exit_code(oom.code()), 6);
    const Error cgal = foreign_error(std::logic_error("CGAL ERROR: precondition violation!"), "in.off: skeletonize");
    EXPECT_EQ(cgal.code(), ErrorCode::NumericalFailure);
    EXPECT_EQ(std::string(cgal.what()), "in.off: skeletonize: internal failure: CGAL ERROR: precondition violation!");
}

// ---------------------------------------------------------------------------------------------------------------
// One error contract across subcommands (the built `mesohex`).

TEST(HostileInputCli, MedialParseErrorsExit2) {
    const std::string ma = write_file("bad.ma", "2 1 0\nv 0 0 0 1\nv 1 0 0 1\ne 0 7\n");
    const std::string out = (test_dir() / "never.obj").string();
    const test::CliRun r = test::run_cli("import " + ma + " -o " + out);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(ma + ":4: vertex index 7 out of range"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    const std::string huge = write_file("huge2.ma", "1e12 0 0\n");
    const test::CliRun h = test::run_cli("import " + huge + " -o " + out);
    EXPECT_EQ(h.status, 2) << h.output;
    EXPECT_NE(h.output.find(huge + ":1: "), std::string::npos) << h.output;
}

// A tetrahedron whose 4 points coincide, a flat one, and one with a zero-area triangle: skeletonize and auto stop at
// once with exit 2 naming the file (it never finished in a release build, and was a bare CGAL precondition failure
// under a sanitizer).
TEST(HostileInputCli, DegenerateSurfacesAreRefusedBeforeCgal) {
    const std::string tris = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const std::pair<const char*, std::string> cases[] = {
        {"point.off", "OFF\n4 4 0\n1 1 1\n1 1 1\n1 1 1\n1 1 1\n" + tris},
        {"flat.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n" + tris},
        {"sliver.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n2 0 0\n0 0 1\n" + tris},
    };
    for (const auto& [name, text] : cases) {
        const std::string path = write_file(name, text);
        const std::string out = (test_dir() / "never_sk.obj").string();
        const test::CliRun s = test::run_cli("skeletonize " + path + " -o " + out);
        EXPECT_EQ(s.status, 2) << name << ": " << s.output;
        EXPECT_NE(s.output.find(path + ": surface cannot be skeletonized: "), std::string::npos) << s.output;
        EXPECT_EQ(s.output.find("CGAL"), std::string::npos) << s.output;
        EXPECT_FALSE(fs::exists(out));
        const std::string mesh_out = (test_dir() / "never_auto.mesh").string();
        const test::CliRun a = test::run_cli("auto " + path + " -o " + mesh_out + " -q");
        EXPECT_EQ(a.status, 2) << name << ": " << a.output;
        EXPECT_NE(a.output.find(path + ": surface cannot be skeletonized: "), std::string::npos) << a.output;
        EXPECT_FALSE(fs::exists(mesh_out));
    }
}

// Two edges leaving vertex 0 in the same direction: analyze gives the verdict mesh gives. With the input sampling
// (--no-resample, no adaptation) the sphere partition refuses the vertex (exit 6, the message names it) in both;
// resampled, adaptation repairs it (the nearer edge becomes a shared trunk) and both accept it. An ordinary skeleton
// is accepted by both.
TEST(HostileInputCli, AnalyzeGivesTheVerdictOfMesh) {
    const std::string same = write_file("same_dir.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nl 1 2\nl 1 3\nl 1 4\n");
    const std::string out = (test_dir() / "same_dir.mesh").string();
    const test::CliRun m = test::run_cli("mesh " + same + " --no-resample -o " + out + " -q");
    const test::CliRun a = test::run_cli("analyze " + same + " --no-resample");
    EXPECT_EQ(m.status, 6) << m.output;
    EXPECT_EQ(a.status, m.status) << "analyze:\n" << a.output << "\nmesh:\n" << m.output;
    EXPECT_NE(a.output.find("vertex"), std::string::npos) << a.output;
    EXPECT_FALSE(fs::exists(out));
    const test::CliRun mr = test::run_cli("mesh " + same + " -o " + out + " -q");
    const test::CliRun ar = test::run_cli("analyze " + same);
    EXPECT_EQ(mr.status, 0) << mr.output;
    EXPECT_EQ(ar.status, 0) << ar.output;
    const std::string good = write_file("tripod.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nl 1 2\nl 1 3\nl 1 4\n");
    const test::CliRun ga = test::run_cli("analyze " + good);
    EXPECT_EQ(ga.status, 0) << ga.output;
    EXPECT_NE(ga.output.find("verdict: mesh accepts it: raw mesh of "), std::string::npos) << ga.output;
}

// A hex whose 8 corners are the same vertex: quality calls it invalid (exit 5); convert writes it and exits 5 too.
TEST(HostileInputCli, ConvertGivesTheVerdictOfQuality) {
    const std::string in = write_file("collapsed.mesh",
                                      "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 0 0\n"
                                      "Hexahedra\n1\n1 1 1 1 1 1 1 1 0\nEnd\n");
    const std::string out = (test_dir() / "collapsed.vtk").string();
    const test::CliRun q = test::run_cli("quality " + in);
    const test::CliRun c = test::run_cli("convert " + in + " " + out);
    EXPECT_EQ(q.status, 5) << q.output;
    EXPECT_EQ(c.status, q.status) << c.output;
    EXPECT_NE(c.output.find("exit status 5"), std::string::npos) << c.output;
    EXPECT_TRUE(fs::exists(out));
}

}  // namespace
}  // namespace mesohex
