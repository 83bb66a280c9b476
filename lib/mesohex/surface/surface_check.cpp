// Surface checks and orientation repair. See surface_check.h.
#include "mesohex/surface/surface_check.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <queue>
#include <string>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

constexpr double kPi = std::numbers::pi;

struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[static_cast<std::size_t>(x)] != x) {
            parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
            x = parent[static_cast<std::size_t>(x)];
        }
        return x;
    }
    void unite(int a, int b) {
        a = find(a);
        b = find(b);
        if (a == b) return;
        if (a < b) std::swap(a, b);
        parent[static_cast<std::size_t>(a)] = b;  // the smaller id is the root
    }
};

// One side of a triangle: undirected key (lo, hi), the triangle and whether it runs lo -> hi.
struct HalfEdge {
    int lo, hi, tri, local;  // local: index of the side in the triangle (side k = corner k -> corner k+1)
    bool forward;
};

bool is_degenerate(const std::array<int, 3>& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

void validate_indices(const TriangleMesh& mesh) {
    const long nv = static_cast<long>(mesh.points.size());
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
        for (int v : mesh.triangles[f])
            if (v < 0 || v >= nv)
                throw Error(ErrorCode::InvalidInput,
                            "triangle " + std::to_string(f) + ": vertex index " + std::to_string(v) +
                                " out of range [0, " + std::to_string(nv) + ")",
                            ElementRef{ElementRef::Kind::None, static_cast<int>(f)});
}

// Half-edges of the non-degenerate triangles, sorted by (lo, hi, tri).
std::vector<HalfEdge> sorted_half_edges(const TriangleMesh& mesh) {
    std::vector<HalfEdge> he;
    he.reserve(3 * mesh.triangles.size());
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        const std::array<int, 3>& t = mesh.triangles[f];
        if (is_degenerate(t)) continue;
        for (int k = 0; k < 3; ++k) {
            const int a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
            he.push_back({std::min(a, b), std::max(a, b), static_cast<int>(f), k, a < b});
        }
    }
    std::sort(he.begin(), he.end(), [](const HalfEdge& x, const HalfEdge& y) {
        if (x.lo != y.lo) return x.lo < y.lo;
        if (x.hi != y.hi) return x.hi < y.hi;
        return x.tri < y.tri;
    });
    return he;
}

// Signed volume of a set of triangles relative to `origin` (reduces cancellation far from the coordinate origin).
double tri_volume(const TriangleMesh& m, const std::array<int, 3>& t, const Vec3& origin) {
    const Vec3 a = m.points[static_cast<std::size_t>(t[0])] - origin;
    const Vec3 b = m.points[static_cast<std::size_t>(t[1])] - origin;
    const Vec3 c = m.points[static_cast<std::size_t>(t[2])] - origin;
    return det3(a, b, c) / 6.0;
}

Vec3 bbox_centre(const TriangleMesh& m) {
    if (m.points.empty()) return {};
    Vec3 lo = m.points[0], hi = m.points[0];
    for (const Vec3& p : m.points)
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], p[i]);
            hi[i] = std::max(hi[i], p[i]);
        }
    return 0.5 * (lo + hi);
}

// Solid angle of triangle (a, b, c) seen from p (Van Oosterom & Strackee).
double solid_angle(const Vec3& p, const Vec3& a0, const Vec3& b0, const Vec3& c0) {
    const Vec3 a = a0 - p, b = b0 - p, c = c0 - p;
    const double la = norm(a), lb = norm(b), lc = norm(c);
    const double num = det3(a, b, c);
    const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    return 2.0 * std::atan2(num, den);
}

}  // namespace

SurfaceCheck check_surface(const TriangleMesh& mesh) {
    validate_indices(mesh);
    SurfaceCheck r;
    r.vertices = static_cast<int>(mesh.points.size());
    r.triangles = static_cast<int>(mesh.triangles.size());
    const std::size_t nt = mesh.triangles.size();

    std::vector<char> referenced(mesh.points.size(), 0);
    for (const std::array<int, 3>& t : mesh.triangles) {
        if (is_degenerate(t)) {
            ++r.degenerate_triangles;
            continue;
        }
        for (int v : t) referenced[static_cast<std::size_t>(v)] = 1;
    }
    r.unreferenced_vertices = static_cast<int>(std::count(referenced.begin(), referenced.end(), 0));

    const std::vector<HalfEdge> he = sorted_half_edges(mesh);
    UnionFind corners(3 * nt);  // corner (f, k) = 3 f + k; joined across manifold edges -> fans
    auto corner_of = [&](int tri, int v) {
        const std::array<int, 3>& t = mesh.triangles[static_cast<std::size_t>(tri)];
        const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        return 3 * tri + k;
    };
    UnionFind tris(nt);
    std::vector<char> tri_bad_edge(nt, 0), tri_open(nt, 0), tri_inconsistent(nt, 0);
    for (std::size_t i = 0; i < he.size();) {
        std::size_t j = i + 1;
        while (j < he.size() && he[j].lo == he[i].lo && he[j].hi == he[i].hi) ++j;
        const std::size_t n = j - i;
        ++r.edges;
        if (n == 1) {
            ++r.boundary_edges;
            tri_open[static_cast<std::size_t>(he[i].tri)] = 1;
        } else if (n == 2) {
            const HalfEdge& a = he[i];
            const HalfEdge& b = he[i + 1];
            if (a.forward == b.forward) {
                ++r.inconsistent_edges;
                tri_inconsistent[static_cast<std::size_t>(a.tri)] = tri_inconsistent[static_cast<std::size_t>(b.tri)] =
                    1;
            }
            corners.unite(corner_of(a.tri, a.lo), corner_of(b.tri, a.lo));
            corners.unite(corner_of(a.tri, a.hi), corner_of(b.tri, a.hi));
        } else {
            ++r.non_manifold_edges;
            for (std::size_t k = i; k < j; ++k) tri_bad_edge[static_cast<std::size_t>(he[k].tri)] = 1;
        }
        for (std::size_t k = i + 1; k < j; ++k) tris.unite(he[i].tri, he[k].tri);
        i = j;
    }
    // Fans per vertex; triangles sharing a vertex are in the same component.
    std::vector<int> first_fan(mesh.points.size(), -1);
    std::vector<char> vertex_bad(mesh.points.size(), 0);
    std::vector<int> first_tri(mesh.points.size(), -1);
    for (std::size_t f = 0; f < nt; ++f) {
        const std::array<int, 3>& t = mesh.triangles[f];
        if (is_degenerate(t)) continue;
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = static_cast<std::size_t>(t[static_cast<std::size_t>(k)]);
            const int fan = corners.find(3 * static_cast<int>(f) + k);
            if (first_fan[v] < 0)
                first_fan[v] = fan;
            else if (first_fan[v] != fan)
                vertex_bad[v] = 1;
            if (first_tri[v] < 0)
                first_tri[v] = static_cast<int>(f);
            else
                tris.unite(first_tri[v], static_cast<int>(f));
        }
    }
    r.non_manifold_vertices = static_cast<int>(std::count(vertex_bad.begin(), vertex_bad.end(), 1));
    r.closed = r.boundary_edges == 0;
    r.edge_manifold = r.non_manifold_edges == 0;
    r.vertex_manifold = r.non_manifold_vertices == 0;
    r.consistently_oriented = r.inconsistent_edges == 0;

    // Components, numbered by their smallest triangle id.
    r.triangle_component.assign(nt, -1);
    std::vector<int> root_component(nt, -1);
    for (std::size_t f = 0; f < nt; ++f) {
        if (is_degenerate(mesh.triangles[f])) continue;
        const std::size_t root = static_cast<std::size_t>(tris.find(static_cast<int>(f)));
        if (root_component[root] < 0) {
            root_component[root] = static_cast<int>(r.components.size());
            r.components.push_back({});
            r.components.back().closed = r.components.back().manifold = r.components.back().oriented = true;
        }
        const int c = root_component[root];
        r.triangle_component[f] = c;
        SurfaceComponent& comp = r.components[static_cast<std::size_t>(c)];
        ++comp.triangles;
        if (tri_open[f]) comp.closed = false;
        if (tri_bad_edge[f]) comp.manifold = false;
        if (tri_inconsistent[f]) comp.oriented = false;
    }
    const Vec3 origin = bbox_centre(mesh);
    for (std::size_t f = 0; f < nt; ++f) {
        const int c = r.triangle_component[f];
        if (c >= 0)
            r.components[static_cast<std::size_t>(c)].signed_volume += tri_volume(mesh, mesh.triangles[f], origin);
    }
    for (std::size_t v = 0; v < mesh.points.size(); ++v) {
        if (first_tri[v] < 0) continue;
        SurfaceComponent& comp =
            r.components[static_cast<std::size_t>(r.triangle_component[static_cast<std::size_t>(first_tri[v])])];
        ++comp.vertices;
        if (vertex_bad[v]) comp.manifold = false;
    }
    for (std::size_t i = 0; i < he.size();) {
        std::size_t j = i + 1;
        while (j < he.size() && he[j].lo == he[i].lo && he[j].hi == he[i].hi) ++j;
        ++r.components[static_cast<std::size_t>(r.triangle_component[static_cast<std::size_t>(he[i].tri)])].edges;
        i = j;
    }
    for (SurfaceComponent& comp : r.components) {
        if (comp.closed && comp.manifold && comp.oriented) {
            const int chi = comp.vertices - comp.edges + comp.triangles;
            comp.genus = (2 - chi) / 2;
        }
        r.signed_volume += comp.signed_volume;
    }
    return r;
}

OrientResult orient_outward(TriangleMesh& mesh) {
    OrientResult result;
    const SurfaceCheck check = check_surface(mesh);
    const std::size_t nt = mesh.triangles.size();
    const std::size_t nc = check.components.size();

    // 1. Consistent orientation per edge-manifold component: BFS across two-triangle edges.
    std::vector<std::vector<std::pair<int, bool>>> adj(nt);  // neighbour, same direction on the shared edge
    const std::vector<HalfEdge> he = sorted_half_edges(mesh);
    std::vector<char> comp_ok(nc, 1);
    for (std::size_t i = 0; i < he.size();) {
        std::size_t j = i + 1;
        while (j < he.size() && he[j].lo == he[i].lo && he[j].hi == he[i].hi) ++j;
        if (j - i == 2) {
            const bool same = he[i].forward == he[i + 1].forward;
            adj[static_cast<std::size_t>(he[i].tri)].push_back({he[i + 1].tri, same});
            adj[static_cast<std::size_t>(he[i + 1].tri)].push_back({he[i].tri, same});
        } else if (j - i > 2) {
            comp_ok[static_cast<std::size_t>(check.triangle_component[static_cast<std::size_t>(he[i].tri)])] = 0;
        }
        i = j;
    }
    std::vector<signed char> flip(nt, -1);  // -1 unvisited, 0 keep, 1 flip
    std::vector<char> comp_changed(nc, 0);
    for (std::size_t seed = 0; seed < nt; ++seed) {
        const int c = check.triangle_component[seed];
        if (c < 0 || flip[seed] >= 0) continue;
        if (!comp_ok[static_cast<std::size_t>(c)]) continue;
        flip[seed] = 0;
        std::queue<int> q;
        q.push(static_cast<int>(seed));
        while (!q.empty()) {
            const int f = q.front();
            q.pop();
            for (const auto& [g, same] : adj[static_cast<std::size_t>(f)]) {
                const signed char want = static_cast<signed char>(same ? 1 - flip[static_cast<std::size_t>(f)]
                                                                       : flip[static_cast<std::size_t>(f)]);
                if (flip[static_cast<std::size_t>(g)] < 0) {
                    flip[static_cast<std::size_t>(g)] = want;
                    q.push(g);
                } else if (flip[static_cast<std::size_t>(g)] != want) {
                    comp_ok[static_cast<std::size_t>(c)] = 0;  // not orientable
                }
            }
        }
    }
    for (std::size_t c = 0; c < nc; ++c)
        if (!comp_ok[c]) ++result.unorientable_components;
    for (std::size_t f = 0; f < nt; ++f) {
        const int c = check.triangle_component[f];
        if (c < 0 || !comp_ok[static_cast<std::size_t>(c)]) {
            flip[f] = 0;
            continue;
        }
        if (flip[f] == 1) comp_changed[static_cast<std::size_t>(c)] = 1;
    }
    for (std::size_t c = 0; c < nc; ++c)
        if (comp_changed[c]) ++result.reoriented_components;
    auto oriented = [&](std::size_t f) {
        std::array<int, 3> t = mesh.triangles[f];
        if (flip[f] == 1) std::swap(t[1], t[2]);
        return t;
    };

    // 2. Closed components: sign from the nesting depth (generalized winding number against the other ones).
    const Vec3 origin = bbox_centre(mesh);
    std::vector<double> volume(nc, 0.0);
    std::vector<std::vector<int>> comp_tris(nc);
    std::vector<Vec3> lo(nc, Vec3{1e300, 1e300, 1e300}), hi(nc, Vec3{-1e300, -1e300, -1e300});
    for (std::size_t f = 0; f < nt; ++f) {
        const int c = check.triangle_component[f];
        if (c < 0) continue;
        const std::size_t cc = static_cast<std::size_t>(c);
        comp_tris[cc].push_back(static_cast<int>(f));
        volume[cc] += tri_volume(mesh, oriented(f), origin);
        for (int v : mesh.triangles[f]) {
            const Vec3& p = mesh.points[static_cast<std::size_t>(v)];
            for (int i = 0; i < 3; ++i) {
                lo[cc][i] = std::min(lo[cc][i], p[i]);
                hi[cc][i] = std::max(hi[cc][i], p[i]);
            }
        }
    }
    std::vector<char> closed_ok(nc, 0);
    for (std::size_t c = 0; c < nc; ++c) closed_ok[c] = comp_ok[c] && check.components[c].closed;
    for (std::size_t c = 0; c < nc; ++c) {
        if (!closed_ok[c]) continue;
        const Vec3 p =
            mesh.points[static_cast<std::size_t>(mesh.triangles[static_cast<std::size_t>(comp_tris[c][0])][0])];
        int depth = 0;
        for (std::size_t d = 0; d < nc; ++d) {
            if (d == c || !closed_ok[d]) continue;
            bool in_box = true;
            for (int i = 0; i < 3; ++i) in_box = in_box && p[i] >= lo[d][i] && p[i] <= hi[d][i];
            if (!in_box) continue;
            double omega = 0;
            for (int f : comp_tris[d]) {
                const std::array<int, 3> t = oriented(static_cast<std::size_t>(f));
                omega += solid_angle(p, mesh.points[static_cast<std::size_t>(t[0])],
                                     mesh.points[static_cast<std::size_t>(t[1])],
                                     mesh.points[static_cast<std::size_t>(t[2])]);
            }
            if (std::abs(omega) > 2.0 * kPi) ++depth;  // |winding number| > 1/2
        }
        const bool want_positive = depth % 2 == 0;
        if ((volume[c] > 0) != want_positive && volume[c] != 0) {
            ++result.inverted_components;
            for (int f : comp_tris[c])
                flip[static_cast<std::size_t>(f)] = static_cast<signed char>(1 - flip[static_cast<std::size_t>(f)]);
        }
    }
    for (std::size_t f = 0; f < nt; ++f) {
        if (flip[f] == 1) {
            std::swap(mesh.triangles[f][1], mesh.triangles[f][2]);
            ++result.flipped_triangles;
        }
    }
    return result;
}

std::vector<int> remove_unreferenced_vertices(TriangleMesh& mesh) {
    validate_indices(mesh);
    std::vector<int> old_to_new(mesh.points.size(), -1);
    for (const std::array<int, 3>& t : mesh.triangles)
        for (int v : t) old_to_new[static_cast<std::size_t>(v)] = 0;
    int next = 0;
    std::vector<Vec3> points;
    for (std::size_t v = 0; v < old_to_new.size(); ++v) {
        if (old_to_new[v] < 0) continue;
        old_to_new[v] = next++;
        points.push_back(mesh.points[v]);
    }
    mesh.points = std::move(points);
    for (std::array<int, 3>& t : mesh.triangles)
        for (int& v : t) v = old_to_new[static_cast<std::size_t>(v)];
    return old_to_new;
}

}  // namespace mesohex
