// Where the raw mesh of a surface's medial meso-skeleton inverts, hex by hex (issue 17; docs/sheets.md, "Notch and
// branch joins"). Runs what `auto --skeleton meso --raw` runs (choose_skeleton with SkeletonKind::Meso: medial axis,
// import, radii and caps; mesh_skeleton without finishing) and prints every inverted raw hex with the skeleton
// element it comes from: the skeleton edge of its chunk or half-chunk (a plate: the skeleton vertex nearest to its
// centroid), the element's site (the end of that edge that is a join, else the nearer end) and the site's kind:
//   bl-joint  a leaflet border vertex with one curve edge (VertexClass::BLJoint);
//   junction  a branching point with leaflet sides, or a border vertex where a branch is rooted;
//   leaflet   a plate or border half-chunk away from any curve;   branch  a curve chunk away from any sheet.
// For each site: its curve edges, its leaflet corner angle (sum of the face angles, degrees; above 180 a notch) and
// its radius. Then the count per kind.
//   mesohex_meso_trace SURFACE [--no-bl-notch-corners] [--no-bl-branch-corners] [--bl-corner-max-push F]
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string>
#include <vector>

#include "mesohex/auto_skeleton.h"
#include "mesohex/mesh.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex_io/surface_io.h"

namespace {

using namespace mesohex;

std::string site_kind(const SkeletonAnalysis& an, int v) {
    const VertexClass c = an.vertex_class[static_cast<size_t>(v)];
    const bool faces = an.vertex_boundary_edges[static_cast<size_t>(v)] > 0;
    if (c == VertexClass::BLJoint) return "bl-joint";
    if ((c == VertexClass::BranchingPoint && faces) || roots_branch(an, v)) return "junction";
    if (c == VertexClass::LeafletInterior || c == VertexClass::LeafletBoundary || c == VertexClass::LLJoint ||
        c == VertexClass::FanEdgeVertex || c == VertexClass::FanEdgeEnd)
        return "leaflet";
    return "branch";
}

bool is_join(const SkeletonAnalysis& an, int v) {
    const std::string k = site_kind(an, v);
    return k == "bl-joint" || k == "junction";
}

// The skeleton vertex nearest to p (ties: lowest id).
int nearest_vertex(const Skeleton& s, const Vec3& p) {
    int best = 0;
    for (size_t v = 1; v < s.points.size(); ++v)
        if (distance(s.points[v], p) < distance(s.points[static_cast<size_t>(best)], p)) best = static_cast<int>(v);
    return best;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: %s SURFACE [--no-bl-notch-corners] [--no-bl-branch-corners] [--bl-corner-max-push F]\n",
                     argv[0]);
        return 2;
    }
    AutoSkeletonOptions o;
    o.kind = SkeletonKind::Meso;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--no-bl-notch-corners") o.import.bl_joint_reflex_corners = false;
        if (a == "--no-bl-branch-corners") o.import.bl_joint_corners_with_branches = false;
        if (a == "--bl-corner-max-push" && i + 1 < argc)
            o.import.bl_joint_max_push_curve_fraction = std::atof(argv[++i]);
        if (a == "--bl-corner-reach" && i + 1 < argc) o.import.bl_joint_corner_reach = std::atof(argv[++i]);
    }
    const TriangleMesh surface = read_surface(argv[1]);
    MeshRun run;
    AutoSkeleton chosen;
    try {
        chosen = choose_skeleton(surface, o);
        MeshOptions mo;
        mo.finish = false;
        run = mesh_skeleton(chosen.skeleton, &surface, mo);
    } catch (const std::exception& e) {
        std::printf("refused: %s\n", e.what());
        return 0;
    }
    std::printf(
        "import: %d leaflets, %d BL-joints moved to a corner (%d at notches, %d with several curves), %d "
        "joins moved onto a corner\n",
        chosen.import.leaflets, chosen.import.moved_bl_joints, chosen.import.notch_corners,
        chosen.import.branch_corners, chosen.import.joins_to_corners);
    const Skeleton& s = run.pipeline.skeleton;
    const SkeletonAnalysis& an = run.pipeline.analysis;
    const HexMesh& mesh = run.pipeline.raw.mesh;
    const std::vector<double> sj = scaled_jacobians(mesh);
    const std::vector<double> angle = face_angle_sums(s.points, s.faces);
    std::map<std::string, int> per_kind;
    long inverted = 0;
    for (size_t h = 0; h < sj.size(); ++h) {
        if (sj[h] > 0) continue;
        ++inverted;
        Vec3 c{};
        for (int x : mesh.hexes[h]) c += mesh.points[static_cast<size_t>(x)] / 8.0;
        const int e = run.pipeline.raw.hex_edge[h];
        int site = nearest_vertex(s, c);
        std::string element = "plate";
        if (e >= 0) {
            const int a = s.edges[static_cast<size_t>(e)][0], b = s.edges[static_cast<size_t>(e)][1];
            site = is_join(an, a)                                                                                   ? a
                   : is_join(an, b)                                                                                 ? b
                   : distance(s.points[static_cast<size_t>(a)], c) <= distance(s.points[static_cast<size_t>(b)], c) ? a
                                                                                                                    : b;
            element = (an.edge_degree[static_cast<size_t>(e)] == 0 ? "chunk e" : "half-chunk e") + std::to_string(e);
        }
        const std::string kind = site_kind(an, site);
        ++per_kind[kind];
        const Vec3& p = s.points[static_cast<size_t>(site)];
        std::printf(
            "hex %6zu sj %7.3f  %-16s site v%-5d %-9s %-15s curves %d corner %5.1f deg r %.4g at (%.4g %.4g %.4g)\n", h,
            sj[h], element.c_str(), site, kind.c_str(), to_string(an.vertex_class[static_cast<size_t>(site)]),
            an.vertex_branch_edges[static_cast<size_t>(site)], angle[static_cast<size_t>(site)],
            site < static_cast<int>(s.radii.size()) ? s.radii[static_cast<size_t>(site)] : 0.0, p.x, p.y, p.z);
    }
    std::printf("raw %zu hexes, %ld inverted, min SJ %.3f\n", sj.size(), inverted, run.raw_quality.sj_min);
    for (const auto& [k, n] : per_kind) std::printf("  %-9s %d\n", k.c_str(), n);
    return 0;
}
