// Where the raw mesh of `auto`'s medial meso-skeleton inverts, by join configuration (docs/sheets.md, "Classifying
// the misses"). Runs what choose_skeleton's raw check runs (compute_medial_axis, import_medial_mesh, radii 0.5 x the
// distance to the surface, optionally the leaflet radius cap at joins, mesh_skeleton without finishing) and prints
// every inverted raw hex under the configuration of the join its skeleton edge ends at: the join's kind (bl_joint, a
// branch rooted on a leaflet, BPleaf = branching point with leaflet sides) and, per branch leaving it, whether the
// branch is one edge long ("1edge") or longer and what ends it. Also the count of joins per configuration.
//   mesohex_join_diag SURFACE [LEAFLET_RADIUS_EDGE_FACTOR]
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string>

#include "mesohex/auto_skeleton.h"
#include "mesohex/mesh.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"
#include "mesohex_io/surface_io.h"

namespace {

using namespace mesohex;

// The meso-skeleton `auto` checks, with radii 0.5 x distance and the cap at joins when factor > 0.
Skeleton meso_skeleton(const TriangleMesh& surface, double cap_factor) {
    const AutoSkeletonOptions o;
    const MedialAxis medial = compute_medial_axis(surface, o.medial);
    MedialImport imp = import_medial_mesh(medial.medial, o.import);
    const SurfaceQuery query(surface);
    RadiusFromSurfaceOptions ro;
    ro.factor = o.meso_radius_factor;
    const RadiusFromSurface rs = radius_from_surface(imp.skeleton, query, ro);
    for (size_t v = 0; v < rs.radii.size(); ++v)
        if (rs.radii[v] > 0) imp.skeleton.radii[v] = rs.radii[v];
    const int capped = cap_leaflet_radii(imp.skeleton, cap_factor);
    if (cap_factor > 0)
        std::printf("capped %d leaflet radii at %.2f x their shortest leaflet edge\n", capped, cap_factor);
    return imp.skeleton;
}

std::string kind_of(const SkeletonAnalysis& an, int v) {
    if (roots_branch(an, v)) return "rooted";
    if (an.vertex_class[v] == VertexClass::BranchingPoint && an.vertex_boundary_edges[v] > 0) return "BPleaf";
    return to_string(an.vertex_class[v]);
}

// Per join of the meshed skeleton: its kind and its branches ("1edge->X" / "long->X"), joined by '|'.
std::map<int, std::string> join_configurations(const SkeletonAnalysis& an) {
    std::map<int, std::string> cfg;
    for (const Branch& b : an.branches) {
        if (b.ring) continue;
        for (int end = 0; end < 2; ++end) {
            const int v = end ? b.vertices.back() : b.vertices.front();
            const int w = end ? b.vertices.front() : b.vertices.back();
            const std::string k = kind_of(an, v);
            if (k != "bl_joint" && k != "rooted" && k != "BPleaf") continue;
            const std::string d = k + (b.edges.size() == 1 ? " 1edge->" : " long->") + kind_of(an, w);
            cfg[v] = cfg.count(v) ? cfg[v] + "|" + d : d;
        }
    }
    return cfg;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SURFACE [LEAFLET_RADIUS_EDGE_FACTOR]\n", argv[0]);
        return 2;
    }
    const TriangleMesh surface = read_surface(argv[1]);
    const Skeleton skeleton = meso_skeleton(surface, argc > 2 ? std::atof(argv[2]) : 0.0);
    MeshOptions mo;
    mo.finish = false;
    MeshRun run;
    try {
        run = mesh_skeleton(skeleton, &surface, mo);
    } catch (const std::exception& e) {
        std::printf("refused: %s\n", e.what());
        return 0;
    }
    const Skeleton& s = run.pipeline.skeleton;
    const SkeletonAnalysis& an = run.pipeline.analysis;
    const std::map<int, std::string> cfg = join_configurations(an);
    const std::vector<double> sj = scaled_jacobians(run.pipeline.raw.mesh);
    std::map<std::string, int> hexes, joins;
    for (const auto& [v, d] : cfg) ++joins[d];
    long inverted = 0;
    for (size_t h = 0; h < sj.size(); ++h) {
        if (sj[h] > 0) continue;
        ++inverted;
        const int e = run.pipeline.raw.hex_edge[h];
        std::string k = "plate/block";
        if (e >= 0) {
            const int a = s.edges[static_cast<size_t>(e)][0], b = s.edges[static_cast<size_t>(e)][1];
            k = cfg.count(a)   ? cfg.at(a)
                : cfg.count(b) ? cfg.at(b)
                               : "other(" + kind_of(an, a) + "-" + kind_of(an, b) + ")";
            k += an.edge_degree[e] == 0 ? " [chunk]" : " [half]";
        }
        ++hexes[k];
    }
    std::printf("raw %zu hexes, %ld inverted, min %.3f\n", sj.size(), inverted, run.raw_quality.sj_min);
    for (const auto& [k, n] : hexes) std::printf("  inv %4d  %s\n", n, k.c_str());
    for (const auto& [k, n] : joins) std::printf("  joins %3d  %s\n", n, k.c_str());
    return 0;
}
