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
//                      [--bl-corner-reach F] [--fringe-factor F] [--fringe-node-ends] [--fill-pinch DEG] [--min-side F]
//                      [--geometry] [--radius-factor F] [--leaflet-offset-fraction F] [--leaflet-out-fraction F]
//                      [--leaflet-out-junctions-only] [--leaflet-out-lean-only | --leaflet-out-pull]
// --radius-factor F: the radii F x the distance to the surface (capped as auto caps them) on the skeleton auto
// imports; F 1 traces the full-radius raw mesh auto tries first, the default the one it keeps. A raw mesh that the
// raw output's checks refuse (check_border_creases, check_moved_roots: auto then falls back) is traced without them.
// Each site line also gives the site's local leaflet numbers: its radius over its shortest leaflet edge (r/e) and the
// largest dihedral fold between two faces at one of its leaflet edges (0 = flat; faces of two leaflets: the smaller
// of the two readings).
// --geometry adds a line per inverted plate or half-chunk (hex_geometry; bench/classify_meso_trace.py counts them).
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
#include "mesohex/core/error.h"
#include "mesohex/mesh.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"
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

constexpr double kDeg = 180.0 / 3.14159265358979323846;

// At a skeleton vertex v: its radius over its shortest leaflet edge (0 without one) and the largest fold (degrees)
// between the normals of two faces that share a leaflet edge at v (0 for a flat sheet or a single face).
std::array<double, 2> local_leaflet_numbers(const Skeleton& s, const SkeletonAnalysis& an, int v) {
    double emin = 1e300, fold = 0;
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[static_cast<size_t>(i)];
        if (an.edge_degree[static_cast<size_t>(e)] == 0) continue;
        const std::array<int, 2>& ends = s.edges[static_cast<size_t>(e)];
        emin = std::min(emin, distance(s.points[static_cast<size_t>(ends[0])], s.points[static_cast<size_t>(ends[1])]));
        std::vector<int> faces;
        for (size_t f = 0; f < an.face_edges.size(); ++f)
            for (int fe : an.face_edges[f])
                if (fe == e) faces.push_back(static_cast<int>(f));
        for (size_t a = 0; a < faces.size(); ++a)
            for (size_t b = a + 1; b < faces.size(); ++b) {
                const size_t fa = static_cast<size_t>(faces[a]), fb = static_cast<size_t>(faces[b]);
                double c = dot(an.face_normal[fa], an.face_normal[fb]);
                if (an.face_leaflet[fa] != an.face_leaflet[fb]) c = std::abs(c);  // orientations unrelated
                fold = std::max(fold, std::acos(std::clamp(c, -1.0, 1.0)) * kDeg);
            }
    }
    const double r = v < static_cast<int>(s.radii.size()) ? s.radii[static_cast<size_t>(v)] : 0.0;
    return {emin < 1e300 ? r / emin : 0.0, fold};
}

double angle_between(const Vec3& a, const Vec3& b) {
    const double na = norm(a), nb = norm(b);
    if (na == 0 || nb == 0) return -1;
    return std::acos(std::clamp(dot(a, b) / (na * nb), -1.0, 1.0)) * kDeg;
}

// Normalized corner Jacobians of a VTK hex (corner i: its three edges, right-handed).
std::array<double, 8> corner_jacobians(const std::array<Vec3, 8>& p) {
    static constexpr int nb[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7},
                                     {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};
    std::array<double, 8> j{};
    for (int i = 0; i < 8; ++i) {
        const Vec3 a = p[nb[i][0]] - p[i], b = p[nb[i][1]] - p[i], c = p[nb[i][2]] - p[i];
        const double l = norm(a) * norm(b) * norm(c);
        j[i] = l > 0 ? dot(cross(a, b), c) / l : 0;
    }
    return j;
}

// Geometry of an inverted plate or half-chunk hex, from its corners (raw_mesh.cpp's layouts): the smallest corner
// Jacobian on its skeleton level (corners 0-3) and on its offset level (4-7); a plate: the quad's largest corner angle
// and twist (angle between the normals of its two diagonal splits), the largest angle between a corner's offset (up)
// and the quad's corner normal, the largest radius over the shortest side; a half-chunk (a, out_a, out_b, b): the
// side's length, out distances and radii, the angles of the out rays to the side (lean: 90 = square, below 90 towards
// the other end), between the two out rays and between the two offsets (normals).
std::string hex_geometry(const std::array<Vec3, 8>& p, bool plate, bool b_second) {
    const std::array<double, 8> j = corner_jacobians(p);
    const double jb = std::min({j[0], j[1], j[2], j[3]}), jt = std::min({j[4], j[5], j[6], j[7]});
    char buf[400];
    if (plate) {
        double corner = 0, normal_off = 0, emin = 1e300, rmax = 0;
        for (int k = 0; k < 4; ++k) {
            const Vec3 &c = p[k], &n = p[(k + 1) % 4], &m = p[(k + 3) % 4];
            corner = std::max(corner, angle_between(n - c, m - c));
            normal_off = std::max(normal_off, angle_between(cross(n - c, m - c), p[k + 4] - c));
            emin = std::min(emin, distance(c, n));
            rmax = std::max(rmax, distance(p[k + 4], c));
        }
        const double twist = std::max(angle_between(cross(p[1] - p[0], p[2] - p[0]), cross(p[2] - p[0], p[3] - p[0])),
                                      angle_between(cross(p[2] - p[1], p[3] - p[1]), cross(p[3] - p[1], p[0] - p[1])));
        std::snprintf(buf, sizeof buf,
                      "    plate: J skeleton %.2f offset %.2f | corner max %.0f twist %.0f normal-off %.0f r/e %.2f",
                      jb, jt, corner, twist, normal_off, rmax / emin);
    } else {
        // Up: {a, oa, ob, b, ua, oua, oub, ub}; down: {a, b, ob, oa, da, db, odb, oda} (b_second: p[1] is b).
        const Vec3 a = p[0], ob = p[2], ua = p[4];
        const Vec3 b = b_second ? p[1] : p[3], oa = b_second ? p[3] : p[1], ub = b_second ? p[5] : p[7];
        const double L = distance(a, b);
        std::snprintf(
            buf, sizeof buf,
            "    half-chunk: J skeleton %.2f offset %.2f | side %.3g out %.3g %.3g r %.3g %.3g lean %.0f %.0f "
            "outs %.0f normals %.0f",
            jb, jt, L, distance(oa, a), distance(ob, b), distance(ua, a), distance(ub, b), angle_between(oa - a, b - a),
            angle_between(ob - b, a - b), angle_between(oa - a, ob - b), angle_between(ua - a, ub - b));
    }
    return buf;
}

// --radius-factor F: the imported meso-skeleton's radii F x each vertex's distance to the surface (a vertex on the
// surface keeps its medial radius), capped at joins and borders: auto_skeleton.cpp's meso_with_radii.
void with_radius_factor(Skeleton& s, const TriangleMesh& surface, const AutoSkeletonOptions& o, double factor) {
    const SurfaceQuery query(surface);
    RadiusFromSurfaceOptions ro;
    ro.factor = factor;
    const RadiusFromSurface rs = radius_from_surface(s, query, ro);
    for (size_t v = 0; v < rs.radii.size(); ++v)
        if (rs.radii[v] > 0) s.radii[v] = rs.radii[v];
    cap_leaflet_radii(s, o.meso_leaflet_radius_edge_factor);
    cap_border_radii(s, o.meso_border_radius_edge_factor);
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
                     "usage: %s SURFACE [--no-bl-notch-corners] [--no-bl-branch-corners] [--bl-corner-max-push F] "
                     "[--bl-corner-reach F] [--fringe-factor F] [--fringe-node-ends] [--fill-pinch DEG] [--min-side F] "
                     "[--geometry] [--radius-factor F] [--leaflet-offset-fraction F] [--leaflet-out-fraction F] "
                     "[--leaflet-out-junctions-only] [--leaflet-out-lean-only | --leaflet-out-pull]\n",
                     argv[0]);
        return 2;
    }
    AutoSkeletonOptions o;
    o.kind = SkeletonKind::Meso;
    bool geometry = false;     // --geometry: a second line per hex (hex_geometry)
    double radius_factor = 0;  // --radius-factor F (0: the radii auto keeps)
    MeshOptions mo;
    mo.finish = false;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--no-bl-notch-corners") o.import.bl_joint_reflex_corners = false;
        if (a == "--no-bl-branch-corners") o.import.bl_joint_corners_with_branches = false;
        if (a == "--bl-corner-max-push" && i + 1 < argc)
            o.import.bl_joint_max_push_curve_fraction = std::atof(argv[++i]);
        if (a == "--bl-corner-reach" && i + 1 < argc) o.import.bl_joint_corner_reach = std::atof(argv[++i]);
        if (a == "--fringe-factor" && i + 1 < argc) o.medial.fringe_factor = std::atof(argv[++i]);
        if (a == "--fringe-node-ends") o.medial.fringe_node_ends = true;
        if (a == "--no-prune-after-fringe") o.medial.prune_after_fringe = false;
        if (a == "--geometry") geometry = true;
        if (a == "--leaflet-offset-fraction" && i + 1 < argc)
            mo.pipeline.raw_mesh.leaflet_offset_fraction = std::atof(argv[++i]);
        if (a == "--leaflet-out-fraction" && i + 1 < argc)
            mo.pipeline.raw_mesh.leaflet_out_fraction = std::atof(argv[++i]);
        if (a == "--leaflet-out-junctions-only") mo.pipeline.raw_mesh.leaflet_out_columns = false;
        if (a == "--leaflet-out-lean-only") mo.pipeline.raw_mesh.leaflet_out_lean_only = true;
        if (a == "--leaflet-out-pull") mo.pipeline.raw_mesh.leaflet_out_lean_only = false;
        if (a == "--radius-factor" && i + 1 < argc) radius_factor = std::atof(argv[++i]);
        if (a == "--fill-pinch" && i + 1 < argc) o.import.fill_pinch_max_angle_deg = std::atof(argv[++i]);
        if (a == "--min-side" && i + 1 < argc) o.import.min_border_side_fraction = std::atof(argv[++i]);
    }
    o.raw_mesh = mo.pipeline.raw_mesh;  // auto's raw checks with the same raw mesh options
    const TriangleMesh surface = read_surface(argv[1]);
    MeshRun run;
    AutoSkeleton chosen;
    try {
        if (radius_factor > 0) {  // auto's meso path up to the radii (choose_skeleton with SkeletonKind::Meso)
            chosen.medial = compute_medial_axis(surface, o.medial);
            chosen.import = import_medial_mesh(chosen.medial.medial, o.import);
            chosen.skeleton = chosen.import.skeleton;
            with_radius_factor(chosen.skeleton, surface, o, radius_factor);
        } else {
            chosen = choose_skeleton(surface, o);
        }
    } catch (const std::exception& e) {
        std::printf("refused: %s\n", e.what());
        return 0;
    }
    try {
        run = mesh_skeleton(chosen.skeleton, &surface, mo);
    } catch (const Error& e) {
        // The raw output's own checks (check_border_creases, check_moved_roots) refuse some inverted raw meshes;
        // auto then falls back as for any failed raw check. Traced from the pipeline without those checks.
        if (e.code() != ErrorCode::UnsupportedConfiguration) {
            std::printf("refused: %s\n", e.what());
            return 0;
        }
        std::printf("raw check refused (%s); traced without it\n", e.what());
        run.pipeline = run_pipeline(chosen.skeleton, mo.pipeline);
    } catch (const std::exception& e) {
        std::printf("refused: %s\n", e.what());
        return 0;
    }
    std::printf(
        "import: %d leaflets, %d BL-joints moved to a corner (%d at notches, %d with several curves), %d "
        "joins moved onto a corner, %d pinches filled\n",
        chosen.import.leaflets, chosen.import.moved_bl_joints, chosen.import.notch_corners,
        chosen.import.branch_corners, chosen.import.joins_to_corners, chosen.import.filled_pinches);
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
        const std::array<double, 2> ln = local_leaflet_numbers(s, an, site);
        std::printf(
            "hex %6zu sj %7.3f  %-16s len %-7.4g site v%-5d %-9s %-15s curves %d corner %5.1f deg off-plane %5.1f "
            "off-out %5.1f r "
            "%.4g r/e %.2f fold %.0f at (%.4g %.4g %.4g)\n",
            h, sj[h], element.c_str(), edge_length, site, kind.c_str(),
            to_string(an.vertex_class[static_cast<size_t>(site)]), an.vertex_branch_edges[static_cast<size_t>(site)],
            angle[static_cast<size_t>(site)], ca[0], ca[1],
            site < static_cast<int>(s.radii.size()) ? s.radii[static_cast<size_t>(site)] : 0.0, ln[0], ln[1], p.x, p.y,
            p.z);
        if (geometry && (e < 0 || an.edge_degree[static_cast<size_t>(e)] > 0)) {
            std::array<Vec3, 8> corners{};
            for (int k = 0; k < 8; ++k)
                corners[static_cast<size_t>(k)] = mesh.points[static_cast<size_t>(mesh.hexes[h][k])];
            const bool b_second = std::find(run.pipeline.raw.vertex_base.begin(), run.pipeline.raw.vertex_base.end(),
                                            mesh.hexes[h][1]) != run.pipeline.raw.vertex_base.end();
            std::printf("%s", hex_geometry(corners, e < 0, b_second).c_str());
            if (e >= 0) {
                // The half-chunk's ends in the order of its hex (a first): id, class, faces' angle sum, faces.
                const std::array<int, 2> ends = s.edges[static_cast<size_t>(e)];
                const Vec3 a0 = mesh.points[static_cast<size_t>(mesh.hexes[h][0])];
                const bool first = distance(a0, s.points[static_cast<size_t>(ends[0])]) <
                                   distance(a0, s.points[static_cast<size_t>(ends[1])]);
                for (int w : {first ? ends[0] : ends[1], first ? ends[1] : ends[0]}) {
                    int faces = 0;
                    for (const auto& f : an.face_vertices) faces += static_cast<int>(std::count(f.begin(), f.end(), w));
                    std::printf(" | v%d %s %.0f deg %d faces", w, to_string(an.vertex_class[static_cast<size_t>(w)]),
                                angle[static_cast<size_t>(w)], faces);
                }
            }
            std::printf("\n");
        }
    }
    std::printf("raw %zu hexes, %ld inverted, min SJ %.3f\n", sj.size(), inverted,
                sj.empty() ? 0.0 : *std::min_element(sj.begin(), sj.end()));
    for (const auto& [k, n] : per_kind) std::printf("  %-16s %d\n", k.c_str(), n);
    return 0;
}
