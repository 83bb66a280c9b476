// Golden outputs: the exact bits of the meshes mesh_skeleton writes for a fixed set of inputs (every generated shape
// raw, three small shapes finished in their thickened domains), compared with tests/data/golden_hashes.txt. A
// refactoring must leave them unchanged; a deliberate change to the output re-records them with
// tests/golden/update.sh (MESOHEX_UPDATE_GOLDEN=1), after measuring the new meshes' quality.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <string>
#include <utility>

#include "mesohex/mesh.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/surface/skeletonize.h"
#include "mesohex/surface/thicken.h"

using namespace mesohex;

namespace {

const std::string golden_path = std::string(MESOHEX_TEST_DATA_DIR) + "/golden_hashes.txt";

// FNV-1a (64 bit) over the bit patterns of every coordinate and every hex vertex id, in storage order, preceded by
// the counts: any change of a single bit of the output changes the hash (up to 2^-64 collisions).
struct Fnv {
    std::uint64_t h = 14695981039346656037ull;
    void add(std::uint64_t word) {
        for (int b = 0; b < 8; ++b) {
            h ^= (word >> (8 * b)) & 0xffu;
            h *= 1099511628211ull;
        }
    }
};

template <std::size_t N>
std::string mesh_hash(const std::vector<Vec3>& points, const std::vector<std::array<int, N>>& cells) {
    Fnv f;
    f.add(points.size());
    f.add(cells.size());
    for (const Vec3& p : points)
        for (int c = 0; c < 3; ++c) f.add(std::bit_cast<std::uint64_t>(p[c]));
    for (const std::array<int, N>& cell : cells)
        for (int v : cell) f.add(static_cast<std::uint64_t>(static_cast<std::int64_t>(v)));
    std::ostringstream s;
    s << cells.size() << ' ' << points.size() << ' ' << std::hex << std::setw(16) << std::setfill('0') << f.h;
    return s.str();
}

// Every bit of a skeleton: points, radii, edges, faces (with their sizes).
std::string skeleton_hash(const Skeleton& s) {
    std::vector<Vec3> values = s.points;
    for (double r : s.radii) values.push_back({r, 0, 0});
    std::vector<std::array<int, 2>> ids = s.edges;
    for (const std::vector<int>& f : s.faces) {
        ids.push_back({-1, static_cast<int>(f.size())});
        for (int v : f) ids.push_back({v, -1});
    }
    return std::to_string(s.edges.size()) + "e " + std::to_string(s.faces.size()) + "f " + mesh_hash(values, ids);
}

// key -> "cells points hash", one line per key in the file ("key cells points hash"; '#' starts a comment).
std::map<std::string, std::string> read_golden() {
    std::map<std::string, std::string> m;
    std::ifstream in(golden_path);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        const std::size_t sp = line.find(' ');
        if (sp != std::string::npos) m[line.substr(0, sp)] = line.substr(sp + 1);
    }
    return m;
}

bool updating() {
    const char* v = std::getenv("MESOHEX_UPDATE_GOLDEN");
    return v != nullptr && std::string(v) == "1";
}

// Compares (or, when updating, records) one entry. Entries are rewritten in place so that the fixtures can run in
// any order and any subset.
void check(const std::string& key, const std::string& got) {
    std::map<std::string, std::string> golden = read_golden();
    if (updating()) {
        golden[key] = got;
        std::ofstream out(golden_path, std::ios::trunc);
        out << "# key cells points fnv1a64(bits of points and hexes); re-record with tests/golden/update.sh\n";
        for (const auto& [k, v] : golden) out << k << ' ' << v << '\n';
        return;
    }
    const auto it = golden.find(key);
    ASSERT_NE(it, golden.end()) << key << " has no recorded hash in " << golden_path;
    EXPECT_EQ(got, it->second) << key << ": the mesh differs from the recorded one";
}

}  // namespace

// Every generated shape, raw (the pipeline without a domain).
TEST(Golden, RawMeshOfEveryGeneratedShape) {
    for (const std::string& name : generator_names()) {
        const MeshRun run = mesh_skeleton(generate_skeleton(name), nullptr);
        check("raw/" + name, mesh_hash(run.mesh().points, run.mesh().hexes));
    }
}

// Small shapes finished in their own thickened domains (coarse grid: 2 cells per smallest radius), the whole
// mesh_skeleton path with its defaults: radii from the file, pad, subdivide, fit, untangle, improve, smooth, retry.
TEST(Golden, FinishedMeshOfSmallShapesInTheirThickenedDomains) {
    for (const std::string name : {"tfan", "twist", "plate"}) {
        const Skeleton skeleton = generate_skeleton(name);
        ThickenOptions t;
        t.cells_per_radius = 2;
        const TriangleMesh domain = thicken(skeleton, t);
        check("thicken/" + name, mesh_hash(domain.points, domain.triangles));
        const MeshRun run = mesh_in_domain(skeleton, domain);
        check("finished/" + name, mesh_hash(run.mesh().points, run.mesh().hexes));
    }
}

// A closed thickened domain skeletonized (curve skeleton), and generated shapes' quads split into triangles (with
// their diagonals as edges) imported as medial meshes: each hashed as every bit of the skeleton it returns.
TEST(Golden, SkeletonizedDomainAndImportedMedialMeshes) {
    {
        ThickenOptions t;
        t.cells_per_radius = 2;
        const TriangleMesh domain = thicken(generate_skeleton("tfan"), t);
        check("skeletonize/tfan", skeleton_hash(skeletonize_surface(domain).skeleton));
    }
    for (const std::string name : {"hand", "turbine", "torustwist"}) {
        Skeleton medial = generate_skeleton(name);
        std::vector<std::vector<int>> triangles;
        for (const std::vector<int>& f : medial.faces) {
            triangles.push_back({f[0], f[1], f[2]});
            triangles.push_back({f[0], f[2], f[3]});
            medial.edges.push_back({f[0], f[2]});
        }
        medial.faces = triangles;
        check("medial_import/" + name, skeleton_hash(import_medial_mesh(medial).skeleton));
    }
}
