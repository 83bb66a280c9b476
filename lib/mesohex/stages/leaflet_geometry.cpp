#include "mesohex/stages/leaflet_geometry.h"

#include <algorithm>
#include <string>
#include <vector>

#include "mesohex/core/cone.h"
#include "mesohex/core/error.h"

namespace mesohex {

namespace {

// Per vertex: the unit normals of the faces that count at it (face_counts_at), in face order.
std::vector<std::vector<Vec3>> unit_face_normals(const SkeletonAnalysis& an, int nv) {
    std::vector<std::vector<Vec3>> face_normals(nv);
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int w : an.face_vertices[f])
            if (face_counts_at(an, f, w) && norm(an.face_normal[f]) > 0)
                face_normals[w].push_back(normalized(an.face_normal[f]));
    return face_normals;
}

bool leaflet_column(VertexClass c) { return c == VertexClass::LeafletInterior || c == VertexClass::LeafletBoundary; }

// Leaflet vertices (interior or boundary: one up / down column for all their faces) whose faces' normals the narrowest
// cone serves better than the mean by more than kCreaseNormalGainDeg get its axis as their normal; returns them (1).
std::vector<char> crease_normals(const SkeletonAnalysis& an, const std::vector<std::vector<Vec3>>& face_normals,
                                 std::vector<Vec3>& normal) {
    const int nv = static_cast<int>(normal.size());
    std::vector<char> crease(nv, 0);
    for (int w = 0; w < nv; ++w) {
        if (!leaflet_column(an.vertex_class[w]) || face_normals[w].size() < 2 || !(norm(normal[w]) > 0)) continue;
        const Vec3 axis = narrower_cone_axis(face_normals[w], normal[w], kCreaseNormalGainDeg);
        if (!(axis == normal[w])) {
            normal[w] = axis;
            crease[w] = 1;
        }
    }
    return crease;
}

// LeafletVertexFrames::up_scale / down_scale (kMiterMaxFactor): per leaflet vertex the smallest cosine between its
// normal and its faces' normals, and on which side of it the faces' centroids lie.
void crease_miters(const Skeleton& skeleton, const SkeletonAnalysis& an,
                   const std::vector<std::vector<Vec3>>& face_normals, LeafletVertexFrames& lf) {
    const int nv = static_cast<int>(lf.normal.size());
    lf.up_scale.assign(nv, 1.0);
    lf.down_scale.assign(nv, 1.0);
    std::vector<double> rise(nv, 0.0);
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f) {
        if (!(norm(an.face_normal[f]) > 0)) continue;
        Vec3 centroid{};
        for (int w : an.face_vertices[f]) centroid += 0.25 * skeleton.points[w];
        for (int w : an.face_vertices[f])
            if (face_counts_at(an, f, w)) rise[w] += dot(centroid - skeleton.points[w], lf.normal[w]);
    }
    for (int w = 0; w < nv; ++w) {
        const double min_cos = lowest_corner(face_normals[w], lf.normal[w]);
        if (!leaflet_column(an.vertex_class[w]) || !(min_cos > 0)) continue;
        const double k = std::min(kMiterMaxFactor, 1.0 / min_cos);
        if (k < kMiterMinFactor) continue;
        if (rise[w] > 0) lf.up_scale[w] = k;
        if (rise[w] < 0) lf.down_scale[w] = k;
    }
}

}  // namespace

Vec3 leaflet_normal_sum(const SkeletonAnalysis& an, int v) {
    Vec3 n{};
    for (std::size_t f = 0; f < an.face_vertices.size(); ++f)
        for (int w : an.face_vertices[f])
            if (w == v && face_counts_at(an, f, w)) n += an.face_normal[f];
    return n;
}

BorderPatch border_patch(const Skeleton& skeleton, const SkeletonAnalysis& an, int v, int branch_edge) {
    BorderPatch p;
    p.kind = an.vertex_border_root[v];
    int found = 0;
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (an.edge_degree[e] != 1 || found == 2) continue;
        p.border_edge[found] = e;
        p.border[found++] = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
    }
    if (found != 2 || p.kind == BorderRoot::None)
        throw Error(
            ErrorCode::UnsupportedConfiguration,
            "skeleton vertex " + std::to_string(v) +
                " cannot root a branch on the leaflet border there; edit: "
                "start the branch at a convex corner of the border, or leave the border within 60 degrees of its "
                "outward direction",
            ElementRef{ElementRef::Kind::SkeletonVertex, v});
    const Vec3& c = skeleton.points[v];
    const Vec3 n = leaflet_normal_sum(an, v);
    const int w = skeleton.edges[branch_edge][0] == v ? skeleton.edges[branch_edge][1] : skeleton.edges[branch_edge][0];
    const Vec3 b = skeleton.points[w] - c;
    p.up_first = dot(cross(skeleton.points[p.border[0]] - c, n), b) > 0;
    if (p.kind == BorderRoot::Side) {
        p.up = dot(b, n) >= 0;
        // face[0]: the face whose corner after v (counter-clockwise about the normal) is a border neighbour.
        int nf = 0;
        for (int f = 0; f < static_cast<int>(an.face_vertices.size()) && nf < 2; ++f)
            for (int k = 0; k < 4; ++k)
                if (an.face_vertices[f][k] == v) {
                    p.face[nf] = f;
                    p.corner[nf++] = k;
                }
        const int after0 = an.face_vertices[p.face[0]][(p.corner[0] + 1) & 3];
        if (after0 != p.border[0] && after0 != p.border[1]) {
            std::swap(p.face[0], p.face[1]);
            std::swap(p.corner[0], p.corner[1]);
        }
        const int x = an.face_vertices[p.face[0]][(p.corner[0] + 1) & 3];
        p.first = x == p.border[0] ? 0 : 1;
        p.middle = an.face_vertices[p.face[0]][(p.corner[0] + 3) & 3];
    }
    return p;
}

LeafletPatch leaflet_patch(const Skeleton& skeleton, const SkeletonAnalysis& an, int v, int branch_edge) {
    std::vector<std::array<int, 2>> fc;  // (face, corner of v), in face order
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int k = 0; k < 4; ++k)
            if (an.face_vertices[f][k] == v) fc.push_back({f, k});
    const std::string where = "skeleton vertex " + std::to_string(v);
    if (fc.size() != 4)
        throw Error(ErrorCode::UnsupportedConfiguration,
                    where + ": a branch rooted inside a leaflet needs 4 faces there, not " + std::to_string(fc.size()) +
                        "; edit: re-sample the leaflet so that 4 faces meet at the branch's first vertex",
                    ElementRef{ElementRef::Kind::SkeletonVertex, v});
    // Counter-clockwise about the oriented normal, face f spans from its corner after v to its corner before v.
    std::array<std::array<int, 2>, 4> ccw{};
    ccw[0] = fc[0];
    std::array<bool, 4> used{true, false, false, false};
    for (int i = 1; i < 4; ++i) {
        const auto [f, k] = ccw[i - 1];
        const int next_start = an.face_vertices[f][(k + 3) & 3];
        bool found = false;
        for (int j = 0; j < 4 && !found; ++j) {
            const auto [g, c] = fc[j];
            if (used[j] || an.face_vertices[g][(c + 1) & 3] != next_start) continue;
            ccw[i] = fc[j];
            used[j] = found = true;
        }
        if (!found)
            throw Error(ErrorCode::UnsupportedConfiguration,
                        where +
                            ": the 4 faces around it do not form one consistently oriented fan; edit: check the "
                            "faces at it for a duplicate, a missing face or a fold",
                        ElementRef{ElementRef::Kind::SkeletonVertex, v});
    }
    Vec3 normal{};
    for (const auto& [f, k] : ccw) normal += an.face_normal[f];
    const int w = skeleton.edges[branch_edge][0] == v ? skeleton.edges[branch_edge][1] : skeleton.edges[branch_edge][0];
    LeafletPatch p;
    p.up = dot(skeleton.points[w] - skeleton.points[v], normal) >= 0;
    for (int k = 0; k < 4; ++k) {
        // Seen from the branch's side the order is counter-clockwise: as built on the up side, reversed below.
        const int j = p.up ? k : (3 - k) & 3;
        const auto [f, c] = ccw[j];
        p.face[k] = f;
        p.corner_centre[k] = c;
        p.corner_point[k] = p.up ? (c + 1) & 3 : (c + 3) & 3;
        p.corner_diagonal[k] = (c + 2) & 3;
        p.neighbour[k] = an.face_vertices[f][p.corner_point[k]];
    }
    return p;
}

Vec3 leaflet_neighbour_direction_sum(const Skeleton& skeleton, const SkeletonAnalysis& an, int v) {
    Vec3 d{};
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (an.edge_degree[e] == 0) continue;
        const int o = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
        d += normalized(skeleton.points[o] - skeleton.points[v]);
    }
    return d;
}

LeafletVertexFrames leaflet_vertex_frames(const Skeleton& skeleton, const SkeletonAnalysis& an) {
    const int nv = static_cast<int>(skeleton.points.size());
    const int nf = static_cast<int>(an.face_vertices.size());
    LeafletVertexFrames lf;
    lf.normal.assign(nf > 0 ? nv : 0, Vec3{});
    lf.out.assign(nf > 0 ? nv : 0, Vec3{});
    if (nf == 0) return lf;
    for (int f = 0; f < nf; ++f)
        for (int w : an.face_vertices[f])
            if (face_counts_at(an, f, w)) lf.normal[w] += an.face_normal[f];  // a docked chain vertex: its plate's
    for (Vec3& n : lf.normal)
        if (norm(n) > 0) n = normalized(n);
    const std::vector<std::vector<Vec3>> face_normals = unit_face_normals(an, nv);
    const std::vector<char> crease = crease_normals(an, face_normals, lf.normal);
    crease_miters(skeleton, an, face_normals, lf);
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) {
            const int fe = an.face_edges[f][k];
            const bool flange =
                !an.edge_docked.empty() && an.edge_docked[fe] == 3;  // its plate's border (docked_walls.h)
            if (an.edge_degree[fe] != 1 && !flange) continue;
            const int a = an.face_vertices[f][k], b = an.face_vertices[f][(k + 1) & 3];
            const Vec3 t = normalized(skeleton.points[b] - skeleton.points[a]);
            for (int w : {a, b})
                if (an.vertex_boundary_edges[w] == 2 && face_counts_at(an, f, w))
                    lf.out[w] += cross(t, crease[w] ? normalized(an.face_normal[f]) : lf.normal[w]);
        }
    for (int w = 0; w < nv; ++w) {
        if (an.vertex_boundary_edges[w] != 2) continue;
        if (norm(lf.out[w]) > 1e-6) {
            lf.out[w] = normalized(lf.out[w]);
            continue;
        }
        // Hairpin (the border turns back on itself): minus the mean of the unit vectors to the leaflet neighbours.
        const Vec3 d = leaflet_neighbour_direction_sum(skeleton, an, w);
        lf.out[w] = norm(d) > 0 ? -1.0 * normalized(d) : Vec3{};
    }
    return lf;
}

double leaflet_out_distance(const Skeleton& skeleton, const SkeletonAnalysis& an, const LeafletVertexFrames& frames,
                            int w, double r) {
    if (an.vertex_boundary_edges[w] != 2 || frames.out.empty()) return r;
    double d = r;
    const Vec3& c = skeleton.points[w];
    for (int i = an.vertex_edge_begin[w]; i < an.vertex_edge_begin[w + 1]; ++i) {
        const int e = an.vertex_edges[i];
        const char docked = an.edge_docked.empty() ? 0 : an.edge_docked[e];
        if ((an.edge_degree[e] != 1 && docked != 3) || (docked == 2 && an.vertex_plate[w] >= 0))
            continue;  // (a wall's border edge at a docked chain vertex is not its plate's border; a flange's chain is)
        const int x = skeleton.edges[e][0] == w ? skeleton.edges[e][1] : skeleton.edges[e][0];
        const Vec3 ev = skeleton.points[x] - c;
        const double L = norm(ev);
        const double along = L > 0 ? dot(frames.out[w], ev) / L : 0;
        if (along > 1e-9) d = std::min(d, kReflexOutFraction * L / along);
    }
    return d;
}

}  // namespace mesohex
