// Exodus II output, read back by an independent reader (netCDF4 from Debian's python3-netcdf4, through
// exodus_dump.py; no Exodus library involved), and the `convert` command's .exo output and --partitions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "hex_fixtures.h"
#include "mesohex/core/error.h"
#include "mesohex/post/partition.h"
#include "mesohex_io/exodus_io.h"
#include "mesohex_io/hex_io.h"

using namespace mesohex;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path temp_dir() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path dir = fs::temp_directory_path() / ("mesohex_exodus_" + std::to_string(::getpid())) /
                         (std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string run(const std::string& cmd, int* status) {
    std::string out;
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) return out;
    std::array<char, 4096> buf;
    std::size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
    const int raw = ::pclose(pipe);
    *status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return out;
}

// The file as the independent reader sees it (see exodus_dump.py for the keys).
json dump(const fs::path& file) {
    int status = -1;
    const std::string out = run("/usr/bin/python3 " + std::string(MESOHEX_PROJECT_DIR) + "/tests/unit/exodus_dump.py " +
                                    file.string() + " 2>&1",
                                &status);
    EXPECT_EQ(status, 0) << out;
    if (status != 0) return json::object();
    return json::parse(out);
}

// 1-based Exodus HEX8 node positions of each side, from the Exodus documentation's side table (not from our code).
constexpr std::array<std::array<int, 4>, 6> kExodusSideNodes = {{
    {1, 2, 6, 5},
    {2, 3, 7, 6},
    {3, 4, 8, 7},
    {1, 5, 8, 4},
    {1, 4, 3, 2},
    {5, 6, 7, 8},
}};

// Every (element, side) of the side set names a face on the boundary of the box [0, n]^3: its 4 nodes share one
// coordinate equal to 0 or n. Returns the number of distinct faces (as sorted node quadruples).
std::size_t check_boundary_sides(const json& file, const json& side_set, const std::vector<std::vector<int>>& conn,
                                 double n) {
    std::set<std::array<int, 4>> faces;
    const json& coords = file["coords"];
    for (std::size_t i = 0; i < side_set["elements"].size(); ++i) {
        const int element = side_set["elements"][i].get<int>();
        const int side = side_set["sides"][i].get<int>();
        EXPECT_GE(side, 1);
        EXPECT_LE(side, 6);
        if (side < 1 || side > 6) continue;
        std::array<int, 4> nodes;
        for (int k = 0; k < 4; ++k)
            nodes[static_cast<std::size_t>(k)] = conn[static_cast<std::size_t>(element - 1)][static_cast<std::size_t>(
                kExodusSideNodes[static_cast<std::size_t>(side - 1)][static_cast<std::size_t>(k)] - 1)];
        bool on_boundary = false;
        for (int c = 0; c < 3; ++c) {
            const double x0 = coords[c][nodes[0] - 1].get<double>();
            bool same = x0 == 0.0 || x0 == n;
            for (int k = 1; k < 4; ++k)
                same = same && coords[c][nodes[static_cast<std::size_t>(k)] - 1].get<double>() == x0;
            on_boundary = on_boundary || same;
        }
        EXPECT_TRUE(on_boundary) << "element " << element << " side " << side;
        std::sort(nodes.begin(), nodes.end());
        faces.insert(nodes);
    }
    return faces.size();
}

// Element connectivity in file order (all blocks concatenated).
std::vector<std::vector<int>> all_connectivity(const json& file) {
    std::vector<std::vector<int>> conn;
    for (const json& block : file["blocks"])
        for (const json& element : block["connect"]) conn.push_back(element.get<std::vector<int>>());
    return conn;
}

}  // namespace

TEST(ExodusIo, SideNumberingMatchesTheExodusTable) {
    // kExodusSideOfHexFace maps our kHexFaces to Exodus sides: the same 4 corners (as a set) on both sides.
    const std::array<std::array<int, 4>, 6> our_faces = {{
        {0, 3, 2, 1},
        {4, 5, 6, 7},
        {0, 1, 5, 4},
        {1, 2, 6, 5},
        {2, 3, 7, 6},
        {3, 0, 4, 7},
    }};
    for (int lf = 0; lf < 6; ++lf) {
        std::array<int, 4> ours = our_faces[static_cast<std::size_t>(lf)];
        std::array<int, 4> theirs = kExodusSideNodes[static_cast<std::size_t>(kExodusSideOfHexFace[lf] - 1)];
        for (int& v : theirs) v -= 1;
        std::sort(ours.begin(), ours.end());
        std::sort(theirs.begin(), theirs.end());
        EXPECT_EQ(ours, theirs) << "local face " << lf;
    }
}

TEST(ExodusIo, BlockOfEightHexes) {
    const fs::path dir = temp_dir();
    const HexMesh m = mesohex::test::make_block(2, 2, 2);  // 27 nodes, 8 hexes
    std::vector<double> sj(8);
    for (std::size_t h = 0; h < 8; ++h) sj[h] = 0.125 * static_cast<double>(h);
    const fs::path path = dir / "block.exo";
    write_hex_mesh(path.string(), m, sj);
    const json f = dump(path);
    ASSERT_FALSE(f.empty());
    EXPECT_EQ(f["file_format"], "NETCDF3_64BIT_OFFSET");
    int status = -1;
    EXPECT_EQ(run("ncdump -k " + path.string() + " 2>&1", &status), "64-bit offset\n");  // netcdf-bin agrees
    EXPECT_EQ(status, 0);
    EXPECT_EQ(f["num_dim"], 3);
    EXPECT_EQ(f["num_nodes"], 27);
    EXPECT_EQ(f["num_elem"], 8);
    EXPECT_EQ(f["coord_names"], json({"x", "y", "z"}));
    for (std::size_t v = 0; v < 27; ++v)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(f["coords"][c][v].get<double>(), m.points[v][c]);
    ASSERT_EQ(f["blocks"].size(), 1u);
    const json& block = f["blocks"][0];
    EXPECT_EQ(block["id"], 1);
    EXPECT_EQ(block["name"], "hexes");
    EXPECT_EQ(block["elem_type"], "HEX8");
    ASSERT_EQ(block["connect"].size(), 8u);
    for (std::size_t h = 0; h < 8; ++h)
        for (std::size_t lv = 0; lv < 8; ++lv) EXPECT_EQ(block["connect"][h][lv].get<int>(), m.hexes[h][lv] + 1);
    EXPECT_EQ(f["elem_num_map"], json({1, 2, 3, 4, 5, 6, 7, 8}));
    EXPECT_EQ(f["elem_var_names"], json({"scaled_jacobian"}));
    EXPECT_EQ(f["elem_vars"]["1"], json(sj));

    // The boundary of a 2 x 2 x 2 block: 6 sides x 4 quads = 24; each hex is a corner hex with 3 boundary sides.
    // Hex (i, j, k) (id i + 2 j + 4 k) shows Exodus side 4 (-x) when i = 0, 2 (+x) when i = 1, 1 (-y) when j = 0,
    // 3 (+y) when j = 1, 5 (-z) when k = 0 and 6 (+z) when k = 1.
    ASSERT_EQ(f["side_sets"].size(), 1u);
    const json& ss = f["side_sets"][0];
    EXPECT_EQ(ss["name"], "boundary");
    EXPECT_EQ(ss["id"], 1);
    ASSERT_EQ(ss["elements"].size(), 24u);
    std::set<std::pair<int, int>> expected, found;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
                const int element = 1 + i + 2 * j + 4 * k;
                expected.insert({element, i == 0 ? 4 : 2});
                expected.insert({element, j == 0 ? 1 : 3});
                expected.insert({element, k == 0 ? 5 : 6});
            }
    for (std::size_t i = 0; i < 24; ++i) found.insert({ss["elements"][i].get<int>(), ss["sides"][i].get<int>()});
    EXPECT_EQ(found, expected);
    EXPECT_EQ(check_boundary_sides(f, ss, all_connectivity(f), 2.0), 24u);
}

TEST(ExodusIo, PartitionsBecomeElementBlocks) {
    const fs::path dir = temp_dir();
    const HexMesh m = mesohex::test::make_block(4, 4, 4);  // 125 nodes, 64 hexes, 96 boundary quads
    const Partition p = partition_hexes(m, {.parts = 4});
    const fs::path path = dir / "parts.e";
    write_hex_mesh(path.string(), m, {}, p.part);
    const json f = dump(path);
    ASSERT_FALSE(f.empty());
    EXPECT_EQ(f["num_nodes"], 125);
    EXPECT_EQ(f["num_elem"], 64);
    ASSERT_EQ(f["blocks"].size(), 4u);
    const std::vector<int> map = f["elem_num_map"].get<std::vector<int>>();
    ASSERT_EQ(map.size(), 64u);
    std::vector<int> sorted = map;
    std::sort(sorted.begin(), sorted.end());
    for (int e = 0; e < 64; ++e) EXPECT_EQ(sorted[static_cast<std::size_t>(e)], e + 1);  // a permutation of 1..64
    std::size_t element = 0;
    for (std::size_t b = 0; b < 4; ++b) {
        const json& block = f["blocks"][b];
        EXPECT_EQ(block["id"], static_cast<int>(b) + 1);
        EXPECT_EQ(block["name"], "partition_" + std::to_string(b));
        EXPECT_EQ(block["connect"].size(), static_cast<std::size_t>(p.part_sizes[b]));
        for (const json& conn : block["connect"]) {
            const std::size_t h = static_cast<std::size_t>(map[element] - 1);  // the element's hex
            EXPECT_EQ(p.part[h], static_cast<int>(b));
            for (std::size_t lv = 0; lv < 8; ++lv) EXPECT_EQ(conn[lv].get<int>(), m.hexes[h][lv] + 1);
            ++element;
        }
    }
    ASSERT_EQ(f["side_sets"].size(), 1u);
    EXPECT_EQ(f["side_sets"][0]["elements"].size(), 96u);
    EXPECT_EQ(check_boundary_sides(f, f["side_sets"][0], all_connectivity(f), 4.0), 96u);
    EXPECT_TRUE(f["elem_var_names"].empty());  // no scaled Jacobian given
}

TEST(ExodusIo, ErrorsLeaveNoFile) {
    const fs::path dir = temp_dir();
    HexMesh empty;
    try {
        write_hex_mesh((dir / "empty.exo").string(), empty);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("without hexes"), std::string::npos) << e.what();
    }
    try {
        write_hex_mesh((dir / "missing" / "m.exo").string(), mesohex::test::make_unit_cube());
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::IoError);
        EXPECT_NE(std::string(e.what()).find("missing/m.exo"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_empty(dir));
}

TEST(ExodusIo, WritingOverAnExistingFileReplacesIt) {
    const fs::path dir = temp_dir();
    const fs::path path = dir / "m.exo";
    std::ofstream(path) << "not an exodus file";
    write_hex_mesh(path.string(), mesohex::test::make_block(1, 1, 2));
    const json f = dump(path);
    EXPECT_EQ(f["num_elem"], 2);
    EXPECT_EQ(f["side_sets"][0]["elements"].size(), 10u);  // 2 hexes: 12 faces, 1 shared
    std::size_t files = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
        EXPECT_EQ(e.path().filename(), "m.exo");
        ++files;
    }
    EXPECT_EQ(files, 1u);
}

TEST(ExodusIo, ConvertWritesExodusAndPartitions) {
    const fs::path dir = temp_dir();
    const std::string mesh = (dir / "block.mesh").string();
    write_hex_mesh(mesh, mesohex::test::make_block(4, 4, 4));
    mesohex::test::CliRun r = mesohex::test::run_cli("convert " + mesh + " " + (dir / "block.exo").string());
    ASSERT_EQ(r.status, 0) << r.output;
    json f = dump(dir / "block.exo");
    EXPECT_EQ(f["num_elem"], 64);
    EXPECT_EQ(f["blocks"].size(), 1u);
    EXPECT_EQ(f["elem_vars"]["1"].size(), 64u);  // the scaled Jacobian (1 for unit cubes)
    EXPECT_EQ(f["elem_vars"]["1"][0], 1.0);

    r = mesohex::test::run_cli("convert " + mesh + " " + (dir / "parts.exo").string() + " --partitions 4 --json",
                               false);
    ASSERT_EQ(r.status, 0) << r.output;
    const json report = json::parse(r.output);
    EXPECT_EQ(report["partition"]["parts"], 4);
    EXPECT_LE(report["partition"]["imbalance"].get<double>(), 0.05);
    EXPECT_EQ(dump(dir / "parts.exo")["blocks"].size(), 4u);

    // .vtu carries the per-hex part as cell data "partition": read back with meshio.
    r = mesohex::test::run_cli("convert " + mesh + " " + (dir / "parts.vtu").string() + " --partitions 4");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("partition: 4 parts"), std::string::npos) << r.output;
    int status = -1;
    const std::string out =
        run("/usr/bin/python3 -c \"import meshio, sys; m = meshio.read(sys.argv[1]); "
            "p = m.cell_data['partition'][0]; print(len(p), sorted(set(p.tolist())))\" " +
                (dir / "parts.vtu").string() + " 2>&1",
            &status);
    EXPECT_EQ(status, 0) << out;
    EXPECT_EQ(out, "64 [0, 1, 2, 3]\n");

    r = mesohex::test::run_cli("convert " + mesh + " " + (dir / "too_many.vtu").string() + " --partitions 65");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("cannot split 64 hexes into 65"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "too_many.vtu"));
}
