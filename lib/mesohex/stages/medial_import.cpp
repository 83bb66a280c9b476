#include "mesohex/core/union_find.h"
#include "mesohex/stages/medial_import.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <queue>
#include <string>
#include <tuple>
#include <utility>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

Error bad(const std::string& what, ElementRef where = {}) {
    return Error(ErrorCode::InvalidInput, "medial import: " + what, where);
}

ElementRef vertex_ref(int v) { return {ElementRef::Kind::SkeletonVertex, v}; }
ElementRef edge_ref(int e) { return {ElementRef::Kind::SkeletonEdge, e}; }
ElementRef face_ref(int f) { return {ElementRef::Kind::SkeletonFace, f}; }

// Angle at p between the directions to a and b, in degrees (0 for a degenerate side).
double angle_deg(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 u = normalized(a - p), w = normalized(b - p);
    if (squared_norm(u) == 0 || squared_norm(w) == 0) return 0;
    return std::acos(std::clamp(dot(u, w), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// True if the cyclic triangle t traverses a -> b.
bool has_directed(const std::array<int, 3>& t, int a, int b) {
    for (int i = 0; i < 3; ++i)
        if (t[i] == a && t[(i + 1) % 3] == b) return true;
    return false;
}

int third_vertex(const std::array<int, 3>& t, int a, int b) {
    for (int x : t)
        if (x != a && x != b) return x;
    return -1;
}

}  // namespace

MedialImport import_medial_mesh(const Skeleton& m, const MedialImportOptions& opt) {
    const int nv = static_cast<int>(m.points.size());
    const int ne = static_cast<int>(m.edges.size());
    const int nt = static_cast<int>(m.faces.size());
    // ---- Validation (before anything is allocated for the output).
    if (m.radii.size() != m.points.size())
        throw bad("the medial mesh needs one radius per vertex (" + std::to_string(m.radii.size()) + " radii for "
                  + std::to_string(nv) + " vertices)");
    for (int v = 0; v < nv; ++v)
        if (!is_finite(m.points[static_cast<size_t>(v)]) || !std::isfinite(m.radii[static_cast<size_t>(v)])
            || !(m.radii[static_cast<size_t>(v)] > 0))
            throw bad("vertex " + std::to_string(v) + " has a non-finite coordinate or a radius that is not > 0",
                      vertex_ref(v));
    std::vector<std::pair<std::pair<int, int>, int>> keys;  // (min, max) -> edge id, sorted
    keys.reserve(static_cast<size_t>(ne));
    for (int e = 0; e < ne; ++e) {
        const std::array<int, 2>& ed = m.edges[static_cast<size_t>(e)];
        if (ed[0] < 0 || ed[0] >= nv || ed[1] < 0 || ed[1] >= nv || ed[0] == ed[1])
            throw bad("edge " + std::to_string(e) + " has an out-of-range or repeated vertex", edge_ref(e));
        keys.push_back({std::minmax(ed[0], ed[1]), e});
    }
    std::sort(keys.begin(), keys.end());
    for (size_t i = 1; i < keys.size(); ++i)
        if (keys[i].first == keys[i - 1].first)
            throw bad("edge " + std::to_string(keys[i].second) + " duplicates edge " + std::to_string(keys[i - 1].second),
                      edge_ref(keys[i].second));
    auto edge_id = [&](int a, int b) {
        const std::pair<int, int> k = std::minmax(a, b);
        auto it = std::lower_bound(keys.begin(), keys.end(), std::make_pair(k, -1));
        return (it != keys.end() && it->first == k) ? it->second : -1;
    };
    std::vector<std::array<int, 3>> tri(static_cast<size_t>(nt));
    std::vector<std::array<int, 3>> tri_edge(static_cast<size_t>(nt));  // side i = (tri[i], tri[i+1])
    for (int t = 0; t < nt; ++t) {
        const std::vector<int>& f = m.faces[static_cast<size_t>(t)];
        if (f.size() != 3)
            throw bad("face " + std::to_string(t) + " has " + std::to_string(f.size())
                          + " vertices (medial sheets are triangles)",
                      face_ref(t));
        for (int x : f)
            if (x < 0 || x >= nv) throw bad("face " + std::to_string(t) + " has a vertex out of range", face_ref(t));
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
            throw bad("face " + std::to_string(t) + " has a repeated vertex", face_ref(t));
        tri[static_cast<size_t>(t)] = {f[0], f[1], f[2]};
        for (int i = 0; i < 3; ++i) {
            const int e = edge_id(f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]);
            if (e < 0)
                throw bad("side " + std::to_string(i) + " of face " + std::to_string(t) + " is not in the edge list",
                          face_ref(t));
            tri_edge[static_cast<size_t>(t)][static_cast<size_t>(i)] = e;
        }
    }

    MedialImport result;
    // ---- Edge -> triangles; sheets (components through any shared edge).
    std::vector<std::vector<int>> edge_tris(static_cast<size_t>(ne));
    for (int t = 0; t < nt; ++t)
        for (int e : tri_edge[static_cast<size_t>(t)]) edge_tris[static_cast<size_t>(e)].push_back(t);
    UnionFind sheet_uf(nt);
    for (int e = 0; e < ne; ++e)
        for (size_t k = 1; k < edge_tris[static_cast<size_t>(e)].size(); ++k)
            sheet_uf.unite(edge_tris[static_cast<size_t>(e)][0], edge_tris[static_cast<size_t>(e)][k]);
    std::vector<int> tri_sheet(static_cast<size_t>(nt), -1);
    std::vector<int> sheet_root_id(static_cast<size_t>(nt), -1);
    for (int t = 0; t < nt; ++t) {
        const int root = sheet_uf.find(t);
        if (sheet_root_id[static_cast<size_t>(root)] < 0) sheet_root_id[static_cast<size_t>(root)] = result.sheets++;
        tri_sheet[static_cast<size_t>(t)] = sheet_root_id[static_cast<size_t>(root)];
    }
    const int ns = result.sheets;
    std::vector<std::vector<int>> sheet_vertices(static_cast<size_t>(ns));
    std::vector<int> sheet_tri_count(static_cast<size_t>(ns), 0);
    std::vector<double> sheet_area(static_cast<size_t>(ns), 0.0);
    for (int t = 0; t < nt; ++t) {
        const int s = tri_sheet[static_cast<size_t>(t)];
        const std::array<int, 3>& T = tri[static_cast<size_t>(t)];
        ++sheet_tri_count[static_cast<size_t>(s)];
        const Vec3& a = m.points[static_cast<size_t>(T[0])];
        sheet_area[static_cast<size_t>(s)] +=
            0.5 * norm(cross(m.points[static_cast<size_t>(T[1])] - a, m.points[static_cast<size_t>(T[2])] - a));
        for (int x : T) sheet_vertices[static_cast<size_t>(s)].push_back(x);
    }
    std::vector<bool> collapsed(static_cast<size_t>(ns), false);
    for (int s = 0; s < ns; ++s) {
        std::vector<int>& sv = sheet_vertices[static_cast<size_t>(s)];
        std::sort(sv.begin(), sv.end());
        sv.erase(std::unique(sv.begin(), sv.end()), sv.end());
        double mean_r = 0;
        for (int v : sv) mean_r += m.radii[static_cast<size_t>(v)];
        mean_r /= static_cast<double>(sv.size());
        collapsed[static_cast<size_t>(s)] = sheet_tri_count[static_cast<size_t>(s)] < opt.min_sheet_triangles
                                            || sheet_area[static_cast<size_t>(s)] < opt.min_sheet_area_factor * mean_r * mean_r;
        if (collapsed[static_cast<size_t>(s)]) ++result.collapsed_sheets;
    }

    // ---- Which vertices survive. A vertex is attached to sheet s if it has a curve edge or lies in another sheet.
    std::vector<bool> has_curve_edge(static_cast<size_t>(nv), false);
    for (int e = 0; e < ne; ++e)
        if (edge_tris[static_cast<size_t>(e)].empty())
            for (int x : m.edges[static_cast<size_t>(e)]) has_curve_edge[static_cast<size_t>(x)] = true;
    std::vector<std::vector<int>> vertex_sheets(static_cast<size_t>(nv));
    for (int s = 0; s < ns; ++s)
        for (int v : sheet_vertices[static_cast<size_t>(s)]) vertex_sheets[static_cast<size_t>(v)].push_back(s);
    auto attached = [&](int v) {
        return has_curve_edge[static_cast<size_t>(v)] || vertex_sheets[static_cast<size_t>(v)].size() > 1;
    };
    std::vector<bool> keep(static_cast<size_t>(nv), true);
    std::vector<std::vector<int>> star(static_cast<size_t>(ns));  // vertices joined to each collapsed sheet's centroid
    for (int s = 0; s < ns; ++s) {
        if (!collapsed[static_cast<size_t>(s)]) continue;
        const std::vector<int>& sv = sheet_vertices[static_cast<size_t>(s)];
        for (int v : sv)
            if (attached(v)) star[static_cast<size_t>(s)].push_back(v);
        if (star[static_cast<size_t>(s)].empty())
            star[static_cast<size_t>(s)] = sv;  // an isolated tiny sheet: keep its corners so something remains
        for (int v : sv)
            if (!std::binary_search(star[static_cast<size_t>(s)].begin(), star[static_cast<size_t>(s)].end(), v))
                keep[static_cast<size_t>(v)] = false;
    }

    Skeleton& out = result.skeleton;
    std::vector<int> new_id(static_cast<size_t>(nv), -1);
    for (int v = 0; v < nv; ++v) {
        if (!keep[static_cast<size_t>(v)]) continue;
        new_id[static_cast<size_t>(v)] = static_cast<int>(out.points.size());
        out.points.push_back(m.points[static_cast<size_t>(v)]);
        out.radii.push_back(m.radii[static_cast<size_t>(v)]);
    }
    auto add_point = [&](const Vec3& p, double r) {
        out.points.push_back(p);
        out.radii.push_back(r);
        return static_cast<int>(out.points.size()) - 1;
    };
    // Curve edges, in input order.
    for (int e = 0; e < ne; ++e)
        if (edge_tris[static_cast<size_t>(e)].empty())
            out.edges.push_back({new_id[static_cast<size_t>(m.edges[static_cast<size_t>(e)][0])],
                                 new_id[static_cast<size_t>(m.edges[static_cast<size_t>(e)][1])]});
    // Collapsed sheets: centroid + star edges.
    for (int s = 0; s < ns; ++s) {
        if (!collapsed[static_cast<size_t>(s)]) continue;
        const std::vector<int>& sv = sheet_vertices[static_cast<size_t>(s)];
        Vec3 c{};
        double r = 0;
        for (int v : sv) {
            c += m.points[static_cast<size_t>(v)];
            r += m.radii[static_cast<size_t>(v)];
        }
        const int cv = add_point(c / static_cast<double>(sv.size()), r / static_cast<double>(sv.size()));
        for (int v : star[static_cast<size_t>(s)]) out.edges.push_back({cv, new_id[static_cast<size_t>(v)]});
    }

    // ---- Leaflets: components of kept triangles through manifold edges, oriented by breadth-first flips.
    auto live = [&](int t) { return !collapsed[static_cast<size_t>(tri_sheet[static_cast<size_t>(t)])]; };
    for (int e = 0; e < ne; ++e)
        if (edge_tris[static_cast<size_t>(e)].size() >= 3 && live(edge_tris[static_cast<size_t>(e)][0])) ++result.fan_edges;
    std::vector<int> tri_leaflet(static_cast<size_t>(nt), -1);
    for (int t0 = 0; t0 < nt; ++t0) {
        if (!live(t0) || tri_leaflet[static_cast<size_t>(t0)] >= 0) continue;
        const int leaf = result.leaflets++;
        std::queue<int> queue;
        tri_leaflet[static_cast<size_t>(t0)] = leaf;
        queue.push(t0);
        while (!queue.empty()) {
            const int u = queue.front();
            queue.pop();
            for (int e : tri_edge[static_cast<size_t>(u)]) {
                const std::vector<int>& et = edge_tris[static_cast<size_t>(e)];
                if (et.size() != 2) continue;
                const int w = et[0] == u ? et[1] : et[0];
                const int a = m.edges[static_cast<size_t>(e)][0], b = m.edges[static_cast<size_t>(e)][1];
                const bool u_ab = has_directed(tri[static_cast<size_t>(u)], a, b);
                if (tri_leaflet[static_cast<size_t>(w)] < 0) {
                    if (has_directed(tri[static_cast<size_t>(w)], a, b) == u_ab)
                        std::swap(tri[static_cast<size_t>(w)][1], tri[static_cast<size_t>(w)][2]);
                    tri_leaflet[static_cast<size_t>(w)] = leaf;
                    queue.push(w);
                } else if (has_directed(tri[static_cast<size_t>(w)], a, b) == u_ab) {
                    throw Error(ErrorCode::UnsupportedConfiguration,
                                "medial import: the sheet containing face " + std::to_string(w)
                                    + " is not orientable (a Moebius band); cut it first",
                                face_ref(w));
                }
            }
        }
    }

    // ---- Greedy pairing of adjacent triangles into quads, best shape first.
    std::vector<int> partner(static_cast<size_t>(nt), -1);
    std::vector<std::array<int, 4>> pair_quad(static_cast<size_t>(nt));
    if (opt.pair_triangles) {
        struct Candidate {
            double score;
            int e;
        };
        std::vector<Candidate> candidates;
        for (int e = 0; e < ne; ++e) {
            const std::vector<int>& et = edge_tris[static_cast<size_t>(e)];
            if (et.size() != 2 || !live(et[0])) continue;
            int t1 = et[0], t2 = et[1];
            int a = m.edges[static_cast<size_t>(e)][0], b = m.edges[static_cast<size_t>(e)][1];
            if (!has_directed(tri[static_cast<size_t>(t1)], a, b)) std::swap(a, b);
            const int c = third_vertex(tri[static_cast<size_t>(t1)], a, b);
            const int d = third_vertex(tri[static_cast<size_t>(t2)], a, b);
            if (c == d) continue;
            const Vec3 &pa = m.points[static_cast<size_t>(a)], &pb = m.points[static_cast<size_t>(b)],
                       &pc = m.points[static_cast<size_t>(c)], &pd = m.points[static_cast<size_t>(d)];
            // Quad (b, c, a, d); corners at a and b are the sums of the two triangle angles.
            const std::array<double, 4> corners = {angle_deg(pb, pc, pa) + angle_deg(pb, pa, pd), angle_deg(pc, pa, pb),
                                                   angle_deg(pa, pb, pc) + angle_deg(pa, pd, pb), angle_deg(pd, pb, pa)};
            double deviation = 0;
            for (double x : corners) deviation = std::max(deviation, std::abs(x - 90.0));
            const Vec3 n1 = normalized(cross(pb - pa, pc - pa)), n2 = normalized(cross(pa - pb, pd - pb));
            if (squared_norm(n1) == 0 || squared_norm(n2) == 0) continue;
            const double fold = std::acos(std::clamp(dot(n1, n2), -1.0, 1.0)) * 180.0 / std::numbers::pi;
            if (deviation <= opt.max_pair_corner_deviation_deg && fold <= opt.max_pair_fold_deg)
                candidates.push_back({deviation + fold, e});
        }
        std::sort(candidates.begin(), candidates.end(),
                  [](const Candidate& x, const Candidate& y) { return std::tie(x.score, x.e) < std::tie(y.score, y.e); });
        for (const Candidate& cand : candidates) {
            const std::vector<int>& et = edge_tris[static_cast<size_t>(cand.e)];
            int t1 = et[0], t2 = et[1];
            if (partner[static_cast<size_t>(t1)] >= 0 || partner[static_cast<size_t>(t2)] >= 0) continue;
            int a = m.edges[static_cast<size_t>(cand.e)][0], b = m.edges[static_cast<size_t>(cand.e)][1];
            if (!has_directed(tri[static_cast<size_t>(t1)], a, b)) std::swap(a, b);
            const std::array<int, 4> q = {b, third_vertex(tri[static_cast<size_t>(t1)], a, b), a,
                                          third_vertex(tri[static_cast<size_t>(t2)], a, b)};
            partner[static_cast<size_t>(t1)] = t2;
            partner[static_cast<size_t>(t2)] = t1;
            pair_quad[static_cast<size_t>(std::min(t1, t2))] = q;
            ++result.paired_quads;
        }
    }

    // ---- Split every face (pair quad or lone triangle) at its centroid and edge midpoints into quads.
    std::vector<int> midpoint(static_cast<size_t>(ne), -1);
    for (int t = 0; t < nt; ++t) {
        if (!live(t)) continue;
        const int p = partner[static_cast<size_t>(t)];
        if (p >= 0 && p < t) continue;  // emitted with its partner
        std::vector<int> poly;
        if (p >= 0)
            poly.assign(pair_quad[static_cast<size_t>(t)].begin(), pair_quad[static_cast<size_t>(t)].end());
        else {
            poly.assign(tri[static_cast<size_t>(t)].begin(), tri[static_cast<size_t>(t)].end());
            ++result.split_triangles;
        }
        const size_t k = poly.size();
        std::vector<int> mids(k);
        Vec3 centre{};
        double centre_r = 0;
        for (size_t i = 0; i < k; ++i) {
            const int a = poly[i], b = poly[(i + 1) % k];
            const int e = edge_id(a, b);
            if (midpoint[static_cast<size_t>(e)] < 0)
                midpoint[static_cast<size_t>(e)] =
                    add_point(0.5 * (m.points[static_cast<size_t>(a)] + m.points[static_cast<size_t>(b)]),
                              0.5 * (m.radii[static_cast<size_t>(a)] + m.radii[static_cast<size_t>(b)]));
            mids[i] = midpoint[static_cast<size_t>(e)];
            centre += m.points[static_cast<size_t>(a)];
            centre_r += m.radii[static_cast<size_t>(a)];
        }
        const int c = add_point(centre / static_cast<double>(k), centre_r / static_cast<double>(k));
        for (size_t i = 0; i < k; ++i) {
            out.faces.push_back({new_id[static_cast<size_t>(poly[i])], mids[i], c, mids[(i + k - 1) % k]});
            result.face_leaflet.push_back(tri_leaflet[static_cast<size_t>(t)]);
        }
    }
    add_face_edges(out);
    return result;
}

}  // namespace mesohex
