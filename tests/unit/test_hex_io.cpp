// Hex mesh formats: hand-written files, round trips, malformed input, and an independent reader (meshio).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hex_fixtures.h"
#include "mesohex/core/error.h"
#include "mesohex_io/hex_io.h"

using namespace mesohex;
namespace fs = std::filesystem;

namespace {

std::string data(const std::string& name) { return std::string(MESOHEX_TEST_DATA_DIR) + "/hex/" + name; }

// A fresh empty directory per test.
fs::path temp_dir() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path dir = fs::temp_directory_path() / ("mesohex_hex_io_" + std::to_string(::getpid())) /
                         (std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// The two side-by-side unit cubes every hand-written file describes.
HexMesh two_hexes() {
    HexMesh m = mesohex::test::make_block(2, 1, 1);
    return m;
}

// A mesh with non-trivial coordinates (exact round trip of doubles).
HexMesh wobbly_block() {
    HexMesh m = mesohex::test::make_block(3, 2, 2);
    for (std::size_t v = 0; v < m.points.size(); ++v) {
        m.points[v].x += 0.1 / (1.0 + static_cast<double>(v));
        m.points[v].y -= 1e-7 * static_cast<double>(v);
        m.points[v].z *= 1.0 / 3.0;
    }
    return m;
}

// Runs `fn`, expects a mesohex::Error whose message contains every string in `parts`.
template <class Fn>
void expect_error(Fn fn, std::initializer_list<std::string> parts, ErrorCode code = ErrorCode::InvalidInput) {
    try {
        fn();
        ADD_FAILURE() << "no error thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), code) << e.what();
        for (const std::string& part : parts)
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(HexIo, ReadsHandWrittenFiles) {
    const HexMesh cube = read_hex_mesh(data("cube.mesh"));
    EXPECT_EQ(cube.points.size(), 8u);
    ASSERT_EQ(cube.hexes.size(), 1u);
    EXPECT_EQ(cube.hexes[0], (std::array<int, 8>{0, 1, 2, 3, 4, 5, 6, 7}));
    EXPECT_EQ(cube.points[6], (Vec3{1, 1, 1}));
    for (const char* name :
         {"two_hexes_crlf.mesh", "two_hexes.vtk", "two_hexes_v51.vtk", "two_hexes.vtu", "two_hexes.msh"}) {
        SCOPED_TRACE(name);
        EXPECT_EQ(read_hex_mesh(data(name)), two_hexes());
    }
}

TEST(HexIo, RoundTripEveryFormat) {
    const fs::path dir = temp_dir();
    const HexMesh m = wobbly_block();
    std::vector<double> sj(m.hexes.size());
    for (std::size_t h = 0; h < sj.size(); ++h) sj[h] = 1.0 - 0.1 * static_cast<double>(h);
    for (const char* ext : {".mesh", ".vtk", ".vtu", ".msh", ".MESH"}) {
        SCOPED_TRACE(ext);
        const std::string path = (dir / (std::string("out") + ext)).string();
        write_hex_mesh(path, m, sj);
        EXPECT_EQ(read_hex_mesh(path), m);
        write_hex_mesh(path, m);  // without cell data, overwriting
        EXPECT_EQ(read_hex_mesh(path), m);
    }
    // no temporary files left behind
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

TEST(HexIo, CellDataIsWritten) {
    const fs::path dir = temp_dir();
    const HexMesh m = two_hexes();
    const std::vector<double> sj = {0.25, -0.5};
    write_hex_mesh((dir / "a.vtk").string(), m, sj);
    write_hex_mesh((dir / "a.vtu").string(), m, sj);
    write_hex_mesh((dir / "a.msh").string(), m, sj);
    EXPECT_NE(
        slurp(dir / "a.vtk").find("CELL_DATA 2\nSCALARS scaled_jacobian double 1\nLOOKUP_TABLE default\n0.25\n-0.5\n"),
        std::string::npos);
    EXPECT_NE(slurp(dir / "a.vtu").find("Name=\"scaled_jacobian\""), std::string::npos);
    EXPECT_NE(slurp(dir / "a.msh")
                  .find("$ElementData\n1\n\"scaled_jacobian\"\n1\n0\n3\n0\n1\n2\n1 0.25\n2 -0.5\n$EndElementData"),
              std::string::npos);
    expect_error([&] { write_hex_mesh((dir / "b.vtk").string(), m, {1.0}); }, {"1 cell values for 2 hexes"});
    EXPECT_FALSE(fs::exists(dir / "b.vtk"));
}

TEST(HexIo, AbaqusInp) {
    const fs::path dir = temp_dir();
    write_hex_mesh((dir / "a.inp").string(), two_hexes());
    const std::string text = slurp(dir / "a.inp");
    EXPECT_NE(text.find("*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n"), std::string::npos) << text;
    EXPECT_NE(text.find("*ELEMENT, TYPE=C3D8, ELSET=EALL\n1, 1, 2, 5, 4, 7, 8, 11, 10\n2, 2, 3, 6, 5, 8, 9, 12, 11\n"),
              std::string::npos)
        << text;
    expect_error([&] { read_hex_mesh((dir / "a.inp").string()); }, {"a.inp", "unknown hex mesh extension"},
                 ErrorCode::UnsupportedConfiguration);
}

TEST(HexIo, MalformedFilesNameFileAndLine) {
    struct Case {
        const char* file;
        std::string where;    // "file:line"
        std::string message;  // part of the message
    };
    const std::vector<Case> cases = {
        {"truncated.mesh", "truncated.mesh:12:", "end of file"},
        {"bad_index.mesh", "bad_index.mesh:22:", "vertex index 9 out of range"},
        {"nan.mesh", "nan.mesh:11:", "'nan'"},
        {"wrong_count.mesh", "wrong_count.mesh:17:", "found 'Quadrilaterals'"},
        {"tet.mesh", "tet.mesh:9:", "only hexahedral meshes"},
        {"garbage.mesh", "garbage.mesh:1:", "unknown MEDIT keyword 'this'"},
        {"huge_count.mesh", "huge_count.mesh:8:", "more than the rest of the file can hold"},
        {"truncated.vtk", "truncated.vtk:9:", "end of file"},
        {"bad_index.vtk", "bad_index.vtk:14:", "vertex index 12 out of range"},
        {"nan.vtk", "nan.vtk:8:", "NaN"},
        {"wrong_count.vtk", "wrong_count.vtk:15:", "found 'CELL_TYPES'"},
        {"tet.vtk", "tet.vtk:17:", "VTK type 10, not a hexahedron"},
        {"truncated.vtu", "truncated.vtu:15:", "</Piece> missing"},
        {"garbled.vtu", "garbled.vtu:19:", "found 'x'"},
        {"bad_index.msh", "bad_index.msh:47:", "unknown node 111"},
        {"old_version.msh", "old_version.msh:2:", "version 2.2 is not supported"},
        {"tet.msh", "tet.msh:45:", "not a hexahedron (type 5)"},
        {"truncated.msh", "truncated.msh:30:", "end of file"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file);
        expect_error([&] { read_hex_mesh(data(c.file)); }, {c.where, c.message});
    }
}

TEST(HexIo, MissingFileAndUnknownExtension) {
    expect_error([] { read_hex_mesh(data("does_not_exist.mesh")); }, {"does_not_exist.mesh", "cannot open"},
                 ErrorCode::IoError);
    expect_error([] { read_hex_mesh(data("cube.stl")); }, {"cube.stl", "unknown hex mesh extension"},
                 ErrorCode::UnsupportedConfiguration);
    expect_error([] { write_hex_mesh("/tmp/x.obj", two_hexes()); }, {"unknown hex mesh extension '.obj'"},
                 ErrorCode::UnsupportedConfiguration);
}

// VTK 5.1 OFFSETS that leave the connectivity array (0 8 16 8 with 8 entries: a cell at 8..16) or decrease are
// refused at their line; they used to make the reader index past the connectivity (found by review, fuzz/corpus/hex).
TEST(HexIo, Vtk51OffsetsStayWithinTheConnectivity) {
    const std::string head =
        "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 double\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n";
    const std::string tail = "\nCONNECTIVITY vtktypeint64\n0 1 2 3 4 5 6 7\nCELL_TYPES 1\n12\n";
    const HexMesh one = read_hex_mesh_text(head + "CELLS 2 8\nOFFSETS vtktypeint64\n0 8" + tail, "vtk", "ok.vtk");
    ASSERT_EQ(one.hexes.size(), 1u);
    EXPECT_EQ(one.hexes[0][7], 7);
    expect_error([&] { read_hex_mesh_text(head + "CELLS 4 8\nOFFSETS vtktypeint64\n0 8 16 8" + tail, "vtk", "a.vtk"); },
                 {"a.vtk:16: offset 16 (entry 2)"});
    expect_error([&] { read_hex_mesh_text(head + "CELLS 3 8\nOFFSETS vtktypeint64\n0 8 0" + tail, "vtk", "b.vtk"); },
                 {"b.vtk:16: offset 0 (entry 2)"});
    expect_error([&] { read_hex_mesh_text(head + "CELLS 2 8\nOFFSETS vtktypeint64\n1 8" + tail, "vtk", "c.vtk"); },
                 {"c.vtk:16: offset 1 (entry 0)"});
    // A second CELLS or POINTS section is refused (the arrays of the first one are never mixed with it).
    expect_error(
        [&] {
            read_hex_mesh_text(head +
                                   "CELLS 2 8\nOFFSETS vtktypeint64\n0 8\nCONNECTIVITY vtktypeint64\n"
                                   "0 1 2 3 4 5 6 7\nCELLS 2 8\n",
                               "vtk", "d.vtk");
        },
        {"d.vtk:19: second CELLS section"});
    expect_error([&] { read_hex_mesh_text(head + "POINTS 1 double\n0 0 0\n", "vtk", "e.vtk"); },
                 {"e.vtk:14: second POINTS section"});
}

// Indices and offsets of the smallest long are out of range, not an overflow of "index - 1" or "offset - begin"
// (UBSan findings; fuzz/corpus/hex/medit_index_min, vtu_offset_min).
TEST(HexIo, SmallestLongIndicesAreOutOfRange) {
    expect_error(
        [] {
            read_hex_mesh_text(
                "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 0 0\nHexahedra\n1\n"
                "-9223372036854775808 1 1 1 1 1 1 1 0\nEnd\n",
                "mesh", "m.mesh");
        },
        {"m.mesh:8: hexahedron 1: vertex index -9223372036854775808 out of range (1..1)"});
    expect_error(
        [] {
            read_hex_mesh_text(
                "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>\n"
                "<Piece NumberOfPoints=\"1\" NumberOfCells=\"2\"><Points>\n"
                "<DataArray NumberOfComponents=\"3\" format=\"ascii\">0 0 0</DataArray></Points><Cells>\n"
                "<DataArray Name=\"connectivity\" format=\"ascii\">0 0 0 0 0 0 0 0</DataArray>\n"
                "<DataArray Name=\"offsets\" format=\"ascii\">8 -9223372036854775808</DataArray>\n"
                "<DataArray Name=\"types\" format=\"ascii\">12 12</DataArray></Cells></Piece>\n"
                "</UnstructuredGrid></VTKFile>\n",
                "vtu", "v.vtu");
        },
        {"v.vtu:7: cell 1 does not have 8 vertices"});
}

TEST(HexIo, FailedWriteLeavesNothingBehind) {
    const fs::path dir = temp_dir();
    // out-of-range index: rejected before anything is written
    HexMesh bad = two_hexes();
    bad.hexes[1][3] = 40;
    expect_error([&] { write_hex_mesh((dir / "bad.mesh").string(), bad); }, {"hex 1 refers to vertex 40"});
    // a directory that does not exist
    expect_error([&] { write_file_atomically((dir / "no" / "such" / "dir.mesh").string(), "x"); }, {"cannot create"},
                 ErrorCode::IoError);
    // an existing file is replaced as a whole, never left half-written
    write_file_atomically((dir / "f.txt").string(), "first");
    write_file_atomically((dir / "f.txt").string(), "second");
    EXPECT_EQ(slurp(dir / "f.txt"), "second");
    int files = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
        (void)e;
        ++files;
    }
    EXPECT_EQ(files, 1);
}

TEST(HexIo, MeshioReadsWhatWeWrite) {
    if (std::system("/usr/bin/python3 -c 'import meshio' > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "/usr/bin/python3 has no meshio";
    const fs::path dir = temp_dir();
    const HexMesh m = wobbly_block();  // 36 points, 12 hexes
    std::vector<double> sj(m.hexes.size(), 0.5);
    for (const char* ext : {".mesh", ".vtk", ".vtu", ".msh", ".inp"}) {
        SCOPED_TRACE(ext);
        const fs::path path = dir / (std::string("m") + ext);
        write_hex_mesh(path.string(), m, sj);
        const fs::path script = dir / "check.py";
        std::ofstream(script) << "import sys, meshio, numpy\n"
                                 "m = meshio.read(sys.argv[1])\n"
                                 "hexes = [c.data for c in m.cells if c.type == 'hexahedron']\n"
                                 "assert len(m.points) == 36, len(m.points)\n"
                                 "assert len(hexes) == 1 and hexes[0].shape == (12, 8), [c.type for c in m.cells]\n"
                                 "assert hexes[0][0].tolist() == [0, 1, 5, 4, 12, 13, 17, 16], hexes[0][0]\n"
                                 "assert abs(m.points[35][2] - 2.0 / 3.0) < 1e-15\n"
                                 "if sys.argv[2] == '1':\n"
                                 "    vals = m.cell_data['scaled_jacobian'][0]\n"
                                 "    assert len(vals) == 12 and abs(vals[3] - 0.5) < 1e-15, vals\n";
        const std::string cmd = "/usr/bin/python3 " + script.string() + " " + path.string() + " " +
                                (std::string(ext) == ".mesh" || std::string(ext) == ".inp" ? "0" : "1") + " 2>&1";
        EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
}

TEST(HexIo, WeReadWhatMeshioWrites) {
    if (std::system("/usr/bin/python3 -c 'import meshio' > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "/usr/bin/python3 has no meshio";
    const fs::path dir = temp_dir();
    const fs::path script = dir / "write.py";
    std::ofstream(script)
        << "import sys, meshio, numpy as np\n"
           "pts = np.array([[i, j, k] for k in range(2) for j in range(2) for i in range(3)], dtype=float)\n"
           "cells = [('hexahedron', np.array([[0, 1, 4, 3, 6, 7, 10, 9], [1, 2, 5, 4, 7, 8, 11, 10]]))]\n"
           "m = meshio.Mesh(pts, cells, cell_data={'q': [np.array([1.0, 2.0])]})\n"
           "d = sys.argv[1]\n"
           "m.write(d + '/m.vtk', binary=False)\n"
           "m.write(d + '/m.vtu', binary=False)\n"
           "m.write(d + '/m.msh', file_format='gmsh', binary=False)\n"
           "m.write(d + '/m.mesh')\n";
    const std::string cmd = "/usr/bin/python3 " + script.string() + " " + dir.string() + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    for (const char* name : {"m.vtk", "m.vtu", "m.msh", "m.mesh"}) {
        SCOPED_TRACE(name);
        EXPECT_EQ(read_hex_mesh((dir / name).string()), two_hexes());
    }
}
