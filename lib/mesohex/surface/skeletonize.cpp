// Mean-curvature-flow skeleton + radii + cleaning. The only file that includes CGAL's MCF header (heavy).
#include "mesohex/surface/skeletonize.h"
#include "mesohex/core/union_find.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "mesohex/core/error.h"

// CGAL types, outside the anonymous namespace so that the std::less specialization below can name them.
namespace mesohex::skeletonize_cgal {
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using CgalMesh = CGAL::Surface_mesh<Point>;
using Mcf = CGAL::Mean_curvature_flow_skeletonization<CgalMesh>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<CgalMesh>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
}  // namespace mesohex::skeletonize_cgal

// Determinism. CGAL's MCF contracts internally on a Polyhedron_3 and, in collapse_short_edges(), collapses the short
// edges in the order of a std::set<edge_descriptor>, whose default order compares halfedge ADDRESSES: the collapse
// order, hence the remeshed surface and the skeleton's sampling, then depends on the heap's history (a second run in
// the same process gave 95 instead of 108 vertices on cactus.obj). The set's comparator is std::less<edge_descriptor>;
// this specialization (for the edge type of our instantiation only) orders edges by the smaller id of their two
// halfedges. The MCF renumbers halfedges 0..2E-1 at initialisation and after every round of face splits, and a collapse
// round only removes halfedges, so these ids are unique and unchanged while an edge is in the set: a strict order that
// depends only on the mesh's history, never on addresses.
template <>
struct std::less<boost::graph_traits<mesohex::skeletonize_cgal::Mcf::Meso_skeleton>::edge_descriptor> {
    using Edge = boost::graph_traits<mesohex::skeletonize_cgal::Mcf::Meso_skeleton>::edge_descriptor;
    static std::size_t key(const Edge& e) { return std::min(e.halfedge()->id(), e.halfedge()->opposite()->id()); }
    bool operator()(const Edge& a, const Edge& b) const { return key(a) < key(b); }
};

namespace mesohex {
namespace {

using skeletonize_cgal::AabbTree;
using skeletonize_cgal::CgalMesh;
using skeletonize_cgal::Kernel;
using skeletonize_cgal::Mcf;
using skeletonize_cgal::Point;

Vec3 to_vec(const Point& p) { return {p.x(), p.y(), p.z()}; }
Point to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

Error invalid(const std::string& why, ElementRef where = {}) {
    return Error(ErrorCode::InvalidInput, "surface cannot be skeletonized: " + why, where);
}

// Geometry the mean curvature flow needs (checked before CGAL sees the mesh: on a degenerate surface it fails a
// precondition or never ends): a bounding box of non-zero size, no triangle of (near) zero area, a non-zero
// enclosed volume. The tolerances are relative to the bounding-box diagonal D.
constexpr double kMinTriangleArea = 1e-12;  // x D^2: below this a triangle has no usable normal or cotangent weight
constexpr double kMinVolume = 1e-9;         // x D^3: below this the surface encloses nothing (flat or collapsed)

void check_geometry(const TriangleMesh& m) {
    Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity()};
    Vec3 hi = -1.0 * lo;
    for (const std::array<int, 3>& tri : m.triangles)
        for (const int v : tri)
            for (int c = 0; c < 3; ++c) {
                lo[c] = std::min(lo[c], m.points[static_cast<size_t>(v)][c]);
                hi[c] = std::max(hi[c], m.points[static_cast<size_t>(v)][c]);
            }
    const double diag = norm(hi - lo);
    if (!(diag > 0) || !std::isfinite(diag))
        throw invalid("all its vertices coincide (the bounding box has size " + std::to_string(diag) + ")");
    double volume = 0;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const std::array<int, 3>& tri = m.triangles[t];
        const Vec3& a = m.points[static_cast<size_t>(tri[0])];
        const Vec3& b = m.points[static_cast<size_t>(tri[1])];
        const Vec3& c = m.points[static_cast<size_t>(tri[2])];
        const double area = 0.5 * norm(cross(b - a, c - a));
        if (!(area > kMinTriangleArea * diag * diag))
            throw invalid("triangle " + std::to_string(t) + " has (near) zero area (" + std::to_string(area) + ")");
        volume += dot(a, cross(b, c)) / 6.0;
    }
    if (!(std::abs(volume) > kMinVolume * diag * diag * diag))
        throw invalid("it encloses no volume (" + std::to_string(volume) + "): a flat or collapsed surface");
}

// Throws InvalidInput unless the surface is a closed, manifold, consistently oriented, single-component triangle mesh.
void check_skeletonizable(const TriangleMesh& m) {
    const int nv = static_cast<int>(m.points.size());
    const int nt = static_cast<int>(m.triangles.size());
    if (nt < 4) throw invalid("it has " + std::to_string(nt) + " triangles (a closed surface needs at least 4)");
    for (int t = 0; t < nt; ++t) {
        const std::array<int, 3>& tri = m.triangles[static_cast<size_t>(t)];
        for (int i = 0; i < 3; ++i)
            if (tri[i] < 0 || tri[i] >= nv)
                throw invalid("triangle " + std::to_string(t) + " has vertex index " + std::to_string(tri[i]) +
                              " out of range");
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
            throw invalid("triangle " + std::to_string(t) + " is degenerate (repeated vertex)");
    }
    for (int v = 0; v < nv; ++v)
        if (!is_finite(m.points[static_cast<size_t>(v)]))
            throw invalid("vertex " + std::to_string(v) + " has a non-finite coordinate");
    // Directed half-edges sorted by undirected key: each undirected edge must appear exactly twice, once per direction.
    struct HalfEdge {
        int lo, hi, from, tri;
    };
    std::vector<HalfEdge> half;
    half.reserve(static_cast<size_t>(nt) * 3);
    for (int t = 0; t < nt; ++t) {
        const std::array<int, 3>& tri = m.triangles[static_cast<size_t>(t)];
        for (int i = 0; i < 3; ++i) {
            const int a = tri[i], b = tri[(i + 1) % 3];
            half.push_back({std::min(a, b), std::max(a, b), a, t});
        }
    }
    std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
        return std::tie(x.lo, x.hi, x.tri) < std::tie(y.lo, y.hi, y.tri);
    });
    for (size_t i = 0; i < half.size();) {
        size_t j = i;
        while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) ++j;
        const std::string edge = "edge (" + std::to_string(half[i].lo) + ", " + std::to_string(half[i].hi) + ")";
        if (j - i == 1)
            throw invalid("the surface is open: " + edge + " belongs to triangle " + std::to_string(half[i].tri) +
                          " only");
        if (j - i > 2)
            throw invalid("the surface is not manifold: " + edge + " belongs to " + std::to_string(j - i) +
                          " triangles");
        if (half[i].from == half[i + 1].from)
            throw invalid("the surface is not consistently oriented: triangles " + std::to_string(half[i].tri) +
                          " and " + std::to_string(half[i + 1].tri) + " traverse " + edge + " in the same direction");
        i = j;
    }
    // Vertex-manifold: the link of every vertex (opposite edges of its triangles) is one cycle.
    std::vector<int> start(static_cast<size_t>(nv) + 1, 0);
    for (const std::array<int, 3>& tri : m.triangles)
        for (int i = 0; i < 3; ++i) ++start[static_cast<size_t>(tri[i]) + 1];
    for (int v = 0; v < nv; ++v) start[static_cast<size_t>(v) + 1] += start[static_cast<size_t>(v)];
    std::vector<int> fill(start.begin(), start.end() - 1);
    std::vector<int> incident(static_cast<size_t>(nt) * 3);
    for (int t = 0; t < nt; ++t)
        for (int i = 0; i < 3; ++i)
            incident[static_cast<size_t>(fill[static_cast<size_t>(m.triangles[static_cast<size_t>(t)][i])]++)] = t;
    std::vector<int> link_vertices;
    for (int v = 0; v < nv; ++v) {
        const int b = start[static_cast<size_t>(v)], e = start[static_cast<size_t>(v) + 1];
        if (b == e) continue;  // unreferenced: ignored
        link_vertices.clear();
        std::vector<std::array<int, 2>> link_edges;
        for (int k = b; k < e; ++k) {
            const std::array<int, 3>& tri = m.triangles[static_cast<size_t>(incident[static_cast<size_t>(k)])];
            const int i = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
            link_edges.push_back({tri[(i + 1) % 3], tri[(i + 2) % 3]});
            link_vertices.push_back(tri[(i + 1) % 3]);
            link_vertices.push_back(tri[(i + 2) % 3]);
        }
        std::sort(link_vertices.begin(), link_vertices.end());
        link_vertices.erase(std::unique(link_vertices.begin(), link_vertices.end()), link_vertices.end());
        UnionFind uf(static_cast<int>(link_vertices.size()));
        int components = static_cast<int>(link_vertices.size());
        auto local = [&](int x) {
            return static_cast<int>(std::lower_bound(link_vertices.begin(), link_vertices.end(), x) -
                                    link_vertices.begin());
        };
        for (const std::array<int, 2>& le : link_edges)
            if (uf.unite(local(le[0]), local(le[1]))) --components;
        if (components != 1)
            throw invalid("the surface is not manifold at vertex " + std::to_string(v) + " (" +
                          std::to_string(components) + " cones of triangles meet there)");
    }
    // One connected component (over referenced vertices).
    UnionFind uf(nv);
    for (const std::array<int, 3>& tri : m.triangles) {
        uf.unite(tri[0], tri[1]);
        uf.unite(tri[1], tri[2]);
    }
    int components = 0;
    for (int v = 0; v < nv; ++v)
        if (start[static_cast<size_t>(v)] != start[static_cast<size_t>(v) + 1] && uf.find(v) == v) ++components;
    if (components != 1)
        throw invalid("the surface has " + std::to_string(components) +
                      " connected components (skeletonize each one separately)");
    check_geometry(m);
}

// A mutable graph for cleaning: adjacency sets kept sorted, dead vertices flagged.
struct Graph {
    std::vector<Vec3> points;
    std::vector<double> radii;      // what cleaning decides with: median correspondence distance (the section's size)
    std::vector<double> out_radii;  // what is output (= radii, or the distance to the surface with inscribed_radii)
    std::vector<std::vector<int>> adj;
    std::vector<bool> alive;

    int degree(int v) const { return static_cast<int>(adj[static_cast<size_t>(v)].size()); }
    void add_edge(int a, int b) {
        std::vector<int>& la = adj[static_cast<size_t>(a)];
        std::vector<int>& lb = adj[static_cast<size_t>(b)];
        la.insert(std::lower_bound(la.begin(), la.end(), b), b);
        lb.insert(std::lower_bound(lb.begin(), lb.end(), a), a);
    }
    void remove_vertex(int v) {
        for (int u : adj[static_cast<size_t>(v)]) {
            std::vector<int>& lu = adj[static_cast<size_t>(u)];
            lu.erase(std::lower_bound(lu.begin(), lu.end(), v));
        }
        adj[static_cast<size_t>(v)].clear();
        alive[static_cast<size_t>(v)] = false;
    }
    int add_vertex(const Vec3& p, double r, double out_r) {
        points.push_back(p);
        radii.push_back(r);
        out_radii.push_back(out_r);
        adj.emplace_back();
        alive.push_back(true);
        return static_cast<int>(points.size()) - 1;
    }
};

// Walks from `from` through `next` along degree-2 vertices until a vertex of degree != 2 (or back to `from`).
// Returns the visited vertices, `from` first, the stop vertex last.
std::vector<int> walk_branch(const Graph& g, int from, int next) {
    std::vector<int> path{from, next};
    int prev = from, cur = next;
    while (g.degree(cur) == 2 && cur != from) {
        const std::vector<int>& n = g.adj[static_cast<size_t>(cur)];
        const int nxt = n[0] == prev ? n[1] : n[0];
        prev = cur;
        cur = nxt;
        path.push_back(cur);
    }
    return path;
}

double path_length(const Graph& g, const std::vector<int>& path) {
    double len = 0;
    for (size_t i = 0; i + 1 < path.size(); ++i)
        len += distance(g.points[static_cast<size_t>(path[i])], g.points[static_cast<size_t>(path[i + 1])]);
    return len;
}

// Removes, smallest first, terminal branches whose tube stays near their branching point's ball: length + radius at
// the extremity < prune_factor x radius at the branching point. Returns the number removed.
int prune_branches(Graph& g, double prune_factor) {
    int pruned = 0;
    for (;;) {
        double best_ratio = std::numeric_limits<double>::infinity();
        std::vector<int> best;
        for (int v = 0; v < static_cast<int>(g.points.size()); ++v) {
            if (!g.alive[static_cast<size_t>(v)] || g.degree(v) != 1) continue;
            std::vector<int> path = walk_branch(g, v, g.adj[static_cast<size_t>(v)][0]);
            if (g.degree(path.back()) < 3) continue;  // the whole graph is a path: nothing is spurious
            const double reach = path_length(g, path) + g.radii[static_cast<size_t>(v)];
            const double ratio = reach / (prune_factor * g.radii[static_cast<size_t>(path.back())]);
            if (ratio < 1 && ratio < best_ratio) {
                best_ratio = ratio;
                best = std::move(path);
            }
        }
        if (best.empty()) return pruned;
        for (size_t i = 0; i + 1 < best.size(); ++i) g.remove_vertex(best[i]);
        ++pruned;
    }
}

// Merges, shortest first, pairs of branching points joined by a branch shorter than merge_factor x the larger of
// their radii, unless the merge would destroy a cycle. Returns the number of merges.
int merge_branch_points(Graph& g, double merge_factor) {
    int merged = 0;
    std::vector<std::vector<int>> rejected;  // paths whose merge would change the cycle count
    for (;;) {
        double best_ratio = std::numeric_limits<double>::infinity();
        std::vector<int> best;
        for (int a = 0; a < static_cast<int>(g.points.size()); ++a) {
            if (!g.alive[static_cast<size_t>(a)] || g.degree(a) < 3) continue;
            for (int n : g.adj[static_cast<size_t>(a)]) {
                std::vector<int> path = walk_branch(g, a, n);
                const int b = path.back();
                if (b <= a || g.degree(b) < 3) continue;  // each junction-junction branch once, a < b
                const double limit =
                    merge_factor * std::max(g.radii[static_cast<size_t>(a)], g.radii[static_cast<size_t>(b)]);
                const double ratio = path_length(g, path) / limit;
                if (ratio < 1 && ratio < best_ratio &&
                    std::find(rejected.begin(), rejected.end(), path) == rejected.end()) {
                    best_ratio = ratio;
                    best = std::move(path);
                }
            }
        }
        if (best.empty()) return merged;
        // The contracted set S = the path. Merging keeps the cycle count iff the only edges inside S are the path
        // edges and no outside vertex is adjacent to two vertices of S (or twice to one).
        std::vector<int> s = best;
        std::sort(s.begin(), s.end());
        int inside = 0;
        std::vector<int> outside;
        for (int v : s)
            for (int u : g.adj[static_cast<size_t>(v)]) {
                if (std::binary_search(s.begin(), s.end(), u))
                    ++inside;
                else
                    outside.push_back(u);
            }
        std::vector<int> outside_unique = outside;
        std::sort(outside_unique.begin(), outside_unique.end());
        outside_unique.erase(std::unique(outside_unique.begin(), outside_unique.end()), outside_unique.end());
        if (inside / 2 != static_cast<int>(best.size()) - 1 || outside_unique.size() != outside.size()) {
            rejected.push_back(best);
            continue;
        }
        const int a = best.front(), b = best.back();
        const Vec3 p = 0.5 * (g.points[static_cast<size_t>(a)] + g.points[static_cast<size_t>(b)]);
        const double r = std::max(g.radii[static_cast<size_t>(a)], g.radii[static_cast<size_t>(b)]);
        for (size_t i = 1; i < best.size(); ++i) g.remove_vertex(best[i]);
        g.points[static_cast<size_t>(a)] = p;
        g.radii[static_cast<size_t>(a)] = r;
        g.out_radii[static_cast<size_t>(a)] =
            std::max(g.out_radii[static_cast<size_t>(a)], g.out_radii[static_cast<size_t>(b)]);
        for (int u : outside_unique)
            if (!std::binary_search(g.adj[static_cast<size_t>(a)].begin(), g.adj[static_cast<size_t>(a)].end(), u))
                g.add_edge(a, u);
        rejected.clear();
        ++merged;
    }
}

// Distance along `dir` from `from` to the first surface hit, or -1 when the ray misses or runs along a triangle.
double ray_hit_distance(const AabbTree& tree, const Vec3& from, const Vec3& dir) {
    const Kernel::Ray_3 ray(to_point(from), Kernel::Vector_3(dir.x, dir.y, dir.z));
    const auto hit = tree.first_intersection(ray);
    if (!hit) return -1;
    const Point* hp = boost::get<Point>(&hit->first);
    return hp == nullptr ? -1 : dot(to_vec(*hp) - from, dir);
}

// Extends every extremity along its terminal direction up to extension_gap x radius before the surface.
int extend_extremities(Graph& g, const AabbTree& tree, double gap, double spacing) {
    int extended = 0;
    const int n0 = static_cast<int>(g.points.size());
    for (int v = 0; v < n0; ++v) {
        if (!g.alive[static_cast<size_t>(v)] || g.degree(v) != 1) continue;
        const double r = g.radii[static_cast<size_t>(v)];
        // Terminal direction: from the branch point one radius back (or the branch's other end) to the extremity.
        std::vector<int> path = walk_branch(g, v, g.adj[static_cast<size_t>(v)][0]);
        Vec3 back = g.points[static_cast<size_t>(path.back())];
        double len = 0;
        for (size_t i = 0; i + 1 < path.size(); ++i) {
            len += distance(g.points[static_cast<size_t>(path[i])], g.points[static_cast<size_t>(path[i + 1])]);
            if (len >= r) {
                back = g.points[static_cast<size_t>(path[i + 1])];
                break;
            }
        }
        const Vec3 tip = g.points[static_cast<size_t>(v)];
        const Vec3 dir = normalized(tip - back);
        if (squared_norm(dir) == 0) continue;
        const double hit = ray_hit_distance(tree, tip, dir);
        if (hit < 0) continue;  // no hit, or the ray runs along a triangle: leave the extremity as it is
        const double reach = hit - gap * r;
        if (reach <= 0.05 * r) continue;
        // Spaced like the skeleton, but never denser than a quarter
        // radius (a blob's flow skeleton can be one tiny edge).
        const int steps = std::max(1, static_cast<int>(std::ceil(reach / std::max(spacing, 0.25 * r))));
        int prev = v;
        for (int k = 1; k <= steps; ++k) {
            const Vec3 p = tip + dir * (reach * k / steps);
            const double d = std::sqrt(tree.squared_distance(to_point(p)));
            const double out_r = g.out_radii[static_cast<size_t>(v)];
            const int w = g.add_vertex(p, std::clamp(d, 0.5 * r, r), std::clamp(d, 0.5 * out_r, out_r));
            g.add_edge(prev, w);
            prev = w;
        }
        ++extended;
    }
    return extended;
}

// The point reached from joint v through its neighbour `next` after an arc length of `length` along the branch, or
// the branch's end (a vertex of degree != 2) when it comes first: the flow's curve zigzags at the scale of its dense
// sampling, so the tangent is taken over a radius on each side.
Vec3 along_branch(const Graph& g, int v, int next, double length) {
    int prev = v, cur = next;
    double walked = distance(g.points[static_cast<size_t>(v)], g.points[static_cast<size_t>(cur)]);
    while (walked < length && g.degree(cur) == 2 && cur != v) {
        const std::vector<int>& n = g.adj[static_cast<size_t>(cur)];
        const int nxt = n[0] == prev ? n[1] : n[0];
        walked += distance(g.points[static_cast<size_t>(cur)], g.points[static_cast<size_t>(nxt)]);
        prev = cur;
        cur = nxt;
    }
    return g.points[static_cast<size_t>(cur)];
}

// The move of joint v towards the middle of its cross-section (SkeletonizeOptions::recentre_*), in the plane normal
// to the chord between the points one radius along its branch on either side: the mean over the counted ray pairs (d,
// -d) of (t+ - t-) / 2 d, capped. Zero unless every pair counts (a closed tube section).
Vec3 recentre_move(const Graph& g, int v, const AabbTree& tree, const SkeletonizeOptions& o) {
    const std::vector<int>& n = g.adj[static_cast<size_t>(v)];
    const double r = g.radii[static_cast<size_t>(v)];
    const Vec3 t = normalized(along_branch(g, v, n[1], r) - along_branch(g, v, n[0], r));
    if (squared_norm(t) == 0) return {};
    const Vec3 a = any_perpendicular(t);  // with b, the normal plane (a deterministic frame)
    const Vec3 b = cross(t, a);
    const Vec3 p = g.points[static_cast<size_t>(v)];
    Vec3 sum{};
    int counted = 0;
    for (int k = 0; k < o.recentre_rays; ++k) {
        const double angle = std::numbers::pi * k / o.recentre_rays;
        const Vec3 d = a * std::cos(angle) + b * std::sin(angle);
        const double plus = ray_hit_distance(tree, p, d), minus = ray_hit_distance(tree, p, d * -1.0);
        if (plus < 0 || minus < 0 || plus > o.recentre_reach * r || minus > o.recentre_reach * r) continue;
        sum = sum + d * (0.5 * (plus - minus));
        ++counted;
    }
    if (counted < o.recentre_rays) return {};
    const Vec3 move = sum * (1.0 / counted);
    const double len = norm(move), cap = o.recentre_max_move * r;
    return len > cap ? move * (cap / len) : move;
}

// Moves every joint (alive, degree 2) towards the middle of its cross-section, recentre_passes Jacobi passes (each
// from the positions of the previous one). Returns the joints moved; `max_shift` = the largest total move.
int recentre_joints(Graph& g, const AabbTree& tree, const SkeletonizeOptions& o, double& max_shift) {
    const std::vector<Vec3> start = g.points;
    std::vector<Vec3> next;
    for (int pass = 0; pass < o.recentre_passes; ++pass) {
        next = g.points;
        for (int v = 0; v < static_cast<int>(g.points.size()); ++v)
            if (g.alive[static_cast<size_t>(v)] && g.degree(v) == 2)
                next[static_cast<size_t>(v)] = g.points[static_cast<size_t>(v)] + recentre_move(g, v, tree, o);
        g.points = next;
    }
    int moved = 0;
    max_shift = 0;
    for (size_t v = 0; v < g.points.size(); ++v) {
        const double shift = distance(g.points[v], start[v]);
        if (shift > 0) {
            ++moved;
            // An inscribed radius is the distance to the surface: taken again where the joint now is.
            if (o.inscribed_radii) g.out_radii[v] = std::sqrt(tree.squared_distance(to_point(g.points[v])));
        }
        max_shift = std::max(max_shift, shift);
    }
    return moved;
}

// The skeleton of the alive vertices in canonical order: sorted lexicographically by (x, y, z) (ties: graph index,
// itself canonical), edges (a < b) in ascending order.
Skeleton output_skeleton(const Graph& g) {
    std::vector<int> alive;
    for (int v = 0; v < static_cast<int>(g.points.size()); ++v)
        if (g.alive[static_cast<size_t>(v)]) alive.push_back(v);
    std::sort(alive.begin(), alive.end(), [&](int a, int b) {
        const Vec3 &pa = g.points[static_cast<size_t>(a)], &pb = g.points[static_cast<size_t>(b)];
        return std::tie(pa.x, pa.y, pa.z, a) < std::tie(pb.x, pb.y, pb.z, b);
    });
    std::vector<int> new_id(g.points.size(), -1);
    Skeleton s;
    for (int v : alive) {
        new_id[static_cast<size_t>(v)] = static_cast<int>(s.points.size());
        s.points.push_back(g.points[static_cast<size_t>(v)]);
        s.radii.push_back(g.out_radii[static_cast<size_t>(v)]);
    }
    for (int v : alive)
        for (int u : g.adj[static_cast<size_t>(v)]) {
            const int a = new_id[static_cast<size_t>(v)], b = new_id[static_cast<size_t>(u)];
            if (a < b) s.edges.push_back({a, b});
        }
    std::sort(s.edges.begin(), s.edges.end());
    return s;
}

}  // namespace

void check_surface_for_skeleton(const TriangleMesh& surface) { check_skeletonizable(surface); }

Skeletonization skeletonize_surface(const TriangleMesh& surface, const SkeletonizeOptions& options) {
    check_skeletonizable(surface);
    if (!(options.prune_factor >= 0) || !(options.merge_factor >= 0) || !(options.extension_gap >= 0) ||
        options.max_iterations < 1 || !(options.min_edge_length >= 0) || options.recentre_passes < 0 ||
        options.recentre_rays < 1 || !(options.recentre_reach > 0) || !(options.recentre_max_move >= 0))
        throw Error(ErrorCode::InvalidInput,
                    "skeletonize: options out of range (factors must be >= 0, "
                    "max_iterations >= 1)");

    // Referenced vertices only, in input order.
    CgalMesh mesh;
    std::vector<CgalMesh::Vertex_index> vmap(surface.points.size(), CgalMesh::null_vertex());
    for (const std::array<int, 3>& tri : surface.triangles)
        for (int i = 0; i < 3; ++i) vmap[static_cast<size_t>(tri[i])] = CgalMesh::Vertex_index(0);
    for (size_t v = 0; v < surface.points.size(); ++v)
        if (vmap[v] != CgalMesh::null_vertex()) vmap[v] = mesh.add_vertex(to_point(surface.points[v]));
    for (size_t t = 0; t < surface.triangles.size(); ++t) {
        const std::array<int, 3>& tri = surface.triangles[t];
        const CgalMesh::Face_index f = mesh.add_face(
            vmap[static_cast<size_t>(tri[0])], vmap[static_cast<size_t>(tri[1])], vmap[static_cast<size_t>(tri[2])]);
        if (f == CgalMesh::null_face())
            throw invalid("triangle " + std::to_string(t) + " cannot be added to a manifold halfedge mesh");
    }

    Mcf mcf(mesh);
    if (options.min_edge_length > 0) mcf.set_min_edge_length(options.min_edge_length);
    mcf.set_max_iterations(static_cast<std::size_t>(options.max_iterations));
    mcf.set_quality_speed_tradeoff(options.quality_speed_tradeoff);
    mcf.set_medially_centered_speed_tradeoff(options.medially_centered_speed_tradeoff);
    Mcf::Skeleton mcf_skeleton;
    mcf(mcf_skeleton);

    const int n = static_cast<int>(boost::num_vertices(mcf_skeleton));
    if (n == 0) throw Error(ErrorCode::NumericalFailure, "skeletonize: the mean curvature flow gave an empty skeleton");

    AabbTree tree(faces(mesh).first, faces(mesh).second, mesh);
    tree.accelerate_distance_queries();

    // Raw flow skeleton: position, radii, edges, in CGAL's vertex order.
    std::vector<Vec3> raw_points(static_cast<size_t>(n));
    std::vector<double> raw_radii(static_cast<size_t>(n)), raw_out_radii(static_cast<size_t>(n));
    std::vector<double> dists;
    for (int v = 0; v < n; ++v) {
        const auto& sv = mcf_skeleton[static_cast<Mcf::Skeleton::vertex_descriptor>(v)];
        const Vec3 p = to_vec(sv.point);
        raw_points[static_cast<size_t>(v)] = p;
        dists.clear();
        for (CgalMesh::Vertex_index iv : sv.vertices) dists.push_back(distance(p, to_vec(mesh.point(iv))));
        double r = 0;
        if (!dists.empty()) {  // the median is a value of the multiset: independent of the correspondence order
            const size_t mid = dists.size() / 2;
            std::nth_element(dists.begin(), dists.begin() + static_cast<std::ptrdiff_t>(mid), dists.end());
            r = dists[mid];
        }
        const double surface_distance = std::sqrt(tree.squared_distance(sv.point));
        if (!(r > 0)) r = surface_distance;
        raw_radii[static_cast<size_t>(v)] = r;
        raw_out_radii[static_cast<size_t>(v)] = options.inscribed_radii ? surface_distance : r;
    }
    // Canonical vertex order: lexicographic (x, y, z), then radius, then CGAL's index. Everything after this point
    // (pruning, merging, extension, output) iterates in this order, so the result depends on the skeleton's geometry,
    // not on the order in which CGAL happened to emit it.
    std::vector<int> order(static_cast<size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        const Vec3 &pa = raw_points[static_cast<size_t>(a)], &pb = raw_points[static_cast<size_t>(b)];
        return std::tie(pa.x, pa.y, pa.z, raw_radii[static_cast<size_t>(a)], a) <
               std::tie(pb.x, pb.y, pb.z, raw_radii[static_cast<size_t>(b)], b);
    });
    std::vector<int> rank(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) rank[static_cast<size_t>(order[static_cast<size_t>(i)])] = i;
    Graph g;
    g.adj.resize(static_cast<size_t>(n));
    g.alive.assign(static_cast<size_t>(n), true);
    for (int old : order) {
        g.points.push_back(raw_points[static_cast<size_t>(old)]);
        g.radii.push_back(raw_radii[static_cast<size_t>(old)]);
        g.out_radii.push_back(raw_out_radii[static_cast<size_t>(old)]);
    }
    double total_length = 0;
    int edge_count = 0;
    for (auto [it, end] = boost::edges(mcf_skeleton); it != end; ++it) {
        const int a = rank[static_cast<size_t>(boost::source(*it, mcf_skeleton))];
        const int b = rank[static_cast<size_t>(boost::target(*it, mcf_skeleton))];
        if (a == b) continue;
        const std::vector<int>& la = g.adj[static_cast<size_t>(a)];
        if (std::binary_search(la.begin(), la.end(), b)) continue;
        g.add_edge(a, b);
        ++edge_count;
    }
    // Mean edge length summed in canonical edge order (a < b, ascending), so that it is the same bits however CGAL
    // listed the edges.
    for (int a = 0; a < n; ++a)
        for (int b : g.adj[static_cast<size_t>(a)])
            if (b > a) total_length += distance(g.points[static_cast<size_t>(a)], g.points[static_cast<size_t>(b)]);
    for (int v = 0; v < n; ++v)
        if (!(g.radii[static_cast<size_t>(v)] > 0) || !(g.out_radii[static_cast<size_t>(v)] > 0))
            throw Error(ErrorCode::NumericalFailure,
                        "skeletonize: skeleton vertex " + std::to_string(v) + " lies on the surface (zero radius)");

    Skeletonization result;
    result.mcf_vertices = n;
    if (options.prune) result.pruned_branches = prune_branches(g, options.prune_factor);
    if (options.merge_branch_points) result.merged_branch_points = merge_branch_points(g, options.merge_factor);
    Graph flow = g;  // the cleaned flow skeleton, before the re-centring
    if (options.recentre_passes > 0)
        result.recentred_joints = recentre_joints(g, tree, options, result.recentre_max_shift);
    if (options.extend_extremities) {
        const double spacing = edge_count > 0 ? total_length / edge_count : 1.0;
        result.extended_extremities = extend_extremities(g, tree, options.extension_gap, spacing);
        if (result.recentred_joints > 0) extend_extremities(flow, tree, options.extension_gap, spacing);
    }
    result.skeleton = output_skeleton(g);
    result.flow_skeleton = result.recentred_joints > 0 ? output_skeleton(flow) : result.skeleton;
    return result;
}

}  // namespace mesohex
