// Where a finished mesh's worst hexes come from (issue 16): meshes SKELETON in DOMAIN with the given first-joint
// reach (one attempt, no retry), then finishes its raw mesh three times: padded and subdivided only, fitted (no
// quality pass, no smoothing), and in full. The subdivided hexes keep their ids through the later stages, so for
// the COUNT worst hexes of the full finish it prints their scaled Jacobian after each stage, the raw hex they come
// from (id / 8^levels; a padding hex when >= the raw hex count), its skeleton edge and raw SJ, and the input skeleton
// vertices nearest to the hex's centre. Not a test, not a Google benchmark: a measuring tool.
//
//   mesohex_stage_trace SKELETON DOMAIN [--reach R] [--count N] [--near X Y Z RADIUS] [-o PREFIX]
//
// --near: trace the worst hexes of the full finish within RADIUS of (X, Y, Z) instead of the model's worst.
// -o PREFIX: writes PREFIX_raw.mesh, PREFIX_pad.mesh, PREFIX_fit.mesh, PREFIX_full.mesh.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "mesohex/core/hex_kernels.h"
#include "mesohex/mesh.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

using namespace mesohex;

namespace {

struct Args {
    std::string skeleton, domain, prefix;
    double reach = 0.7;
    int count = 8;
    bool near = false;
    Vec3 centre;
    double radius = 0;
};

Args parse(int argc, char** argv) {
    Args a;
    a.skeleton = argv[1];
    a.domain = argv[2];
    for (int i = 3; i < argc; ++i) {
        const std::string s = argv[i];
        if (s == "--reach" && i + 1 < argc)
            a.reach = std::atof(argv[++i]);
        else if (s == "--count" && i + 1 < argc)
            a.count = std::atoi(argv[++i]);
        else if (s == "-o" && i + 1 < argc)
            a.prefix = argv[++i];
        else if (s == "--near" && i + 4 < argc) {
            a.near = true;
            a.centre = Vec3{std::atof(argv[i + 1]), std::atof(argv[i + 2]), std::atof(argv[i + 3])};
            a.radius = std::atof(argv[i + 4]);
            i += 4;
        }
    }
    return a;
}

Vec3 hex_centre(const HexMesh& m, std::size_t h) {
    Vec3 c;
    for (int v : m.hexes[h]) c += m.points[static_cast<std::size_t>(v)];
    return c / 8.0;
}

FinishResult finish_variant(const HexMesh& raw, const TriangleMesh& domain, FinishOptions o, int variant) {
    o.measure_distance = false;
    if (variant == 0) {
        o.fit = false;
        o.untangle = false;
    }
    if (variant <= 1) {
        o.improve_sj = 0;
        o.smooth = false;
    }
    return finish_mesh(raw, domain, o);
}

// The two input vertices nearest to p (by distance / radius).
std::string nearest_inputs(const Skeleton& s, const Vec3& p) {
    int best[2] = {-1, -1};
    double d[2] = {1e300, 1e300};
    for (std::size_t v = 0; v < s.points.size(); ++v) {
        const double r = s.radii.empty() ? 1.0 : std::max(s.radii[v], 1e-12);
        const double q = distance(s.points[v], p) / r;
        if (q < d[0]) {
            best[1] = best[0], d[1] = d[0];
            best[0] = static_cast<int>(v), d[0] = q;
        } else if (q < d[1]) {
            best[1] = static_cast<int>(v), d[1] = q;
        }
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, "v%d (%.2f r) v%d (%.2f r)", best[0], d[0], best[1], d[1]);
    return buf;
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc < 3) {
        std::fprintf(
            stderr,
            "usage: mesohex_stage_trace SKELETON DOMAIN [--reach R] [--count N] [--near X Y Z R] [-o PREFIX]\n");
        return 2;
    }
    const Args a = parse(argc, argv);
    const Skeleton input = read_skeleton(a.skeleton);
    const TriangleMesh domain = read_surface(a.domain);
    MeshOptions mo;
    mo.retry = false;
    mo.finish = false;
    mo.pipeline.adaptation.free_branching_reach = a.reach;
    if (const char* k = std::getenv("KEEP_CUT_JOINT")) mo.pipeline.adaptation.keep_cut_joint = std::atof(k);
    if (const char* k = std::getenv("SLIDE_CUT_JOINT")) mo.pipeline.adaptation.slide_cut_joint = std::atoi(k) != 0;
    if (const char* k = std::getenv("BRIDGE_PEAK")) mo.pipeline.adaptation.bridge_peak_ratio = std::atof(k);
    if (const char* k = std::getenv("OVERLAP_MERGE")) mo.pipeline.adaptation.overlap_merge_ratio = std::atof(k);
    if (const char* k = std::getenv("OVERLAP_MERGE_MAX_DEGREE"))
        mo.pipeline.adaptation.overlap_merge_max_degree = std::atoi(k);
    const MeshRun run = mesh_skeleton(input, &domain, mo);
    const HexMesh& raw = run.pipeline.raw.mesh;
    const std::vector<double> raw_sj = scaled_jacobians(raw);
    FinishResult f[3];
    for (int v = 0; v < 3; ++v) {
        f[v] = finish_variant(raw, domain, mo.finishing, v);
        std::printf("variant %d:", v);
        for (const FinishStage& s : f[v].stages) std::printf(" %s %.3f", s.stage.c_str(), s.sj_min);
        std::printf("\n");
    }
    if (!a.prefix.empty()) {
        write_hex_mesh(a.prefix + "_raw.mesh", raw);
        const char* names[3] = {"_pad.mesh", "_fit.mesh", "_full.mesh"};
        for (int v = 0; v < 3; ++v) write_hex_mesh(a.prefix + names[v], f[v].mesh);
    }
    std::vector<double> sj[3];
    for (int v = 0; v < 3; ++v) sj[v] = scaled_jacobians(f[v].mesh);
    if (sj[0].size() != sj[2].size() || sj[1].size() != sj[2].size()) {
        std::fprintf(stderr, "the three finishes differ in hex count (%zu, %zu, %zu): no common hex ids\n",
                     sj[0].size(), sj[1].size(), sj[2].size());
        return 1;
    }
    std::vector<std::size_t> order;
    for (std::size_t h = 0; h < sj[2].size(); ++h)
        if (!a.near || distance(hex_centre(f[2].mesh, h), a.centre) < a.radius) order.push_back(h);
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return sj[2][x] < sj[2][y]; });
    std::size_t per_raw = 1;
    for (int l = 0; l < f[2].subdivision_levels; ++l) per_raw *= 8;
    std::printf("raw hexes %zu, levels %d\n", raw.hexes.size(), f[2].subdivision_levels);
    std::printf("hex     pad   fit  full | padded-hex raw-sj edge | centre | nearest input\n");
    for (std::size_t i = 0; i < order.size() && i < static_cast<std::size_t>(a.count); ++i) {
        const std::size_t h = order[i];
        const std::size_t ph = h / per_raw;
        const bool is_raw = ph < raw.hexes.size();
        const Vec3 c = hex_centre(f[2].mesh, h);
        std::printf("%-6zu %.3f %.3f %.3f | %zu %s %.3f e%d | %.3f %.3f %.3f | %s\n", h, sj[0][h], sj[1][h], sj[2][h],
                    ph, is_raw ? "raw" : "pad", is_raw ? raw_sj[ph] : -1.0, is_raw ? run.pipeline.raw.hex_edge[ph] : -1,
                    c.x, c.y, c.z, nearest_inputs(input, c).c_str());
    }
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "mesohex_stage_trace: %s\n", e.what());
    return 1;
}
