// Where the raw mesh of a surface's medial meso-skeleton inverts, hex by hex (issue 17; docs/sheets.md, "Notch and
// branch joins"). Runs what `auto --skeleton meso --raw` runs (choose_skeleton with SkeletonKind::Meso: medial axis,
// import, radii and caps; mesh_skeleton without finishing) and prints every inverted raw hex with the skeleton
// element it comes from: the skeleton edge of its chunk or half-chunk (a plate: the skeleton vertex nearest to its
// centroid), the element's site (the end of that edge that is a join, else the nearer end) and the site's kind:
//   bl-joint  a leaflet border vertex with one curve edge (VertexClass::BLJoint);
//   junction  a branching point with leaflet sides, or a border vertex where a branch is rooted;
//   leaflet   a plate or border half-chunk away from any curve;   branch  a curve chunk away from any sheet.
// For each site: its curve edges, its leaflet corner angle (sum of the face angles, degrees; above 180 a notch) and
// its radius. Then the count per kind, junctions also by layout (rooted branch / several curves on the border / inner).
//   mesohex_meso_trace SURFACE [--no-bl-notch-corners] [--no-bl-branch-corners] [--bl-corner-max-push F]
#include <algorithm>
#include <array>
#include <cmath>
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

// A junction's layout: "rooted" (a border vertex whose one branch the mesher roots on the border's plates),
// "border" (a branching point on the leaflet border: several curves join there) or "inner" (a branching point with
// leaflet sides off the border, e.g. on a fan edge); "" for the other kinds.
std::string junction_layout(const SkeletonAnalysis& an, int v) {
    if (site_kind(an, v) != "junction") return "";
    if (an.vertex_class[static_cast<size_t>(v)] != VertexClass::BranchingPoint) return "rooted";
    return an.vertex_boundary_edges[static_cast<size_t>(v)] == 2 ? "border" : "inner";
}

// At a site with curves: the largest angle (degrees) between one of its curves and the plane of its leaflet faces
// (the sum of their normals), and the largest angle between a curve's in-plane part and the outward direction
// (against the mean direction to the leaflet neighbours); -1, -1 without faces or curves.
std::array<double, 2> curve_angles(const Skeleton& s, const SkeletonAnalysis& an, int v) {
    Vec3 n{}, inward{};
    for (std::size_t f = 0; f < an.face_vertices.size(); ++f)
        for (int w : an.face_vertices[f])
            if (w == v) n += an.face_normal[f];
    std::vector<Vec3> curves;
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[static_cast<size_t>(i)];
        const int w = s.edges[static_cast<size_t>(e)][0] == v ? s.edges[static_cast<size_t>(e)][1]
                                                              : s.edges[static_cast<size_t>(e)][0];
        const Vec3 d = normalized(s.points[static_cast<size_t>(w)] - s.points[static_cast<size_t>(v)]);
        if (an.edge_degree[static_cast<size_t>(e)] == 0)
            curves.push_back(d);
        else
            inward += d;
    }
    std::array<double, 2> worst{-1, -1};
    if (norm(n) == 0 || curves.empty()) return worst;
    n = normalized(n);
    Vec3 out = -1.0 * (inward - n * dot(inward, n));
    out = normalized(out);
    constexpr double deg = 180.0 / 3.14159265358979323846;
    for (const Vec3& d : curves) {
        worst[0] = std::max(worst[0], std::asin(std::clamp(std::abs(dot(d, n)), 0.0, 1.0)) * deg);
        const Vec3 in_plane = normalized(d - n * dot(d, n));
        if (norm(out) > 0 && norm(in_plane) > 0)
            worst[1] = std::max(worst[1], std::acos(std::clamp(dot(in_plane, out), -1.0, 1.0)) * deg);
    }
    return worst;
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
        if (a == "--fringe-factor" && i + 1 < argc) o.medial.fringe_factor = std::atof(argv[++i]);
        if (a == "--fringe-node-ends") o.medial.fringe_node_ends = true;
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
        double edge_length = 0;  // the element's skeleton edge (0 for a plate)
        if (e >= 0) {
            const int a = s.edges[static_cast<size_t>(e)][0], b = s.edges[static_cast<size_t>(e)][1];
            site = is_join(an, a)                                                                                   ? a
                   : is_join(an, b)                                                                                 ? b
                   : distance(s.points[static_cast<size_t>(a)], c) <= distance(s.points[static_cast<size_t>(b)], c) ? a
                                                                                                                    : b;
            element = (an.edge_degree[static_cast<size_t>(e)] == 0 ? "chunk e" : "half-chunk e") + std::to_string(e);
            edge_length = distance(s.points[static_cast<size_t>(a)], s.points[static_cast<size_t>(b)]);
        }
        const std::string kind = site_kind(an, site);
        ++per_kind[kind];
        const std::string layout = junction_layout(an, site);
        if (!layout.empty()) ++per_kind["junction " + layout];
        const Vec3& p = s.points[static_cast<size_t>(site)];
        const std::array<double, 2> ca = curve_angles(s, an, site);
        std::printf(
            "hex %6zu sj %7.3f  %-16s len %-7.4g site v%-5d %-9s %-15s curves %d corner %5.1f deg off-plane %5.1f "
            "off-out %5.1f r "
            "%.4g at (%.4g %.4g %.4g)\n",
            h, sj[h], element.c_str(), edge_length, site, kind.c_str(),
            to_string(an.vertex_class[static_cast<size_t>(site)]), an.vertex_branch_edges[static_cast<size_t>(site)],
            angle[static_cast<size_t>(site)], ca[0], ca[1],
            site < static_cast<int>(s.radii.size()) ? s.radii[static_cast<size_t>(site)] : 0.0, p.x, p.y, p.z);
    }
    std::printf("raw %zu hexes, %ld inverted, min SJ %.3f\n", sj.size(), inverted, run.raw_quality.sj_min);
    for (const auto& [k, n] : per_kind) std::printf("  %-16s %d\n", k.c_str(), n);
    return 0;
}
