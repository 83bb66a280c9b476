#include "mesohex/surface/medial_axis.h"
#include "mesohex/surface/medial_rims.h"
#include "mesohex/surface/skeletonize.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/core/union_find.h"
#include "mesohex/surface/surface_check.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<int, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------- sampling

std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}
double unit_double(std::uint64_t h) { return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0); }

std::vector<std::array<int, 2>> unique_edges(const TriangleMesh& m) {
    std::vector<std::array<int, 2>> edges;
    edges.reserve(m.triangles.size() * 3);
    for (const std::array<int, 3>& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const int a = t[static_cast<size_t>(k)], b = t[static_cast<size_t>((k + 1) % 3)];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

// Surface vertices (referenced ones), points every <= h along every edge, and floor(area / h^2) points inside every
// triangle at barycentric coordinates from a fixed hash of (triangle, k). Writes `h` used (grown until the count, with
// extra_count(h) more samples, fits).
// source[i] = {0, vertex}, {1, index in unique_edges(m)} or {2, triangle}: where sample i was made.
std::vector<Vec3> sample_surface(const TriangleMesh& m, double& h, int max_samples,
                                 const std::function<long(double)>& extra_count,
                                 std::vector<std::array<int, 2>>& source) {
    const std::vector<std::array<int, 2>> edges = unique_edges(m);
    std::vector<char> used(m.points.size(), 0);
    for (const std::array<int, 3>& t : m.triangles)
        for (int v : t) used[static_cast<size_t>(v)] = 1;
    const long vertex_count = std::count(used.begin(), used.end(), 1);
    auto count_for = [&](double step) {
        long n = vertex_count;
        for (const std::array<int, 2>& e : edges)
            n += std::max(
                0L, static_cast<long>(std::ceil(
                        distance(m.points[static_cast<size_t>(e[0])], m.points[static_cast<size_t>(e[1])]) / step)) -
                        1);
        for (const std::array<int, 3>& t : m.triangles) {
            const Vec3& a = m.points[static_cast<size_t>(t[0])];
            const double area =
                0.5 * norm(cross(m.points[static_cast<size_t>(t[1])] - a, m.points[static_cast<size_t>(t[2])] - a));
            n += static_cast<long>(std::floor(area / (step * step)));
        }
        return n;
    };
    for (int round = 0; round < 60 && count_for(h) + extra_count(h) > max_samples; ++round) h *= 1.15;

    std::vector<Vec3> samples;
    for (size_t v = 0; v < m.points.size(); ++v)
        if (used[v]) {
            samples.push_back(m.points[v]);
            source.push_back({0, static_cast<int>(v)});
        }
    for (size_t e = 0; e < edges.size(); ++e) {
        const Vec3& a = m.points[static_cast<size_t>(edges[e][0])];
        const Vec3& b = m.points[static_cast<size_t>(edges[e][1])];
        const int n = static_cast<int>(std::ceil(distance(a, b) / h));
        for (int i = 1; i < n; ++i) {
            samples.push_back(a + (b - a) * (static_cast<double>(i) / n));
            source.push_back({1, static_cast<int>(e)});
        }
    }
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const Vec3& a = m.points[static_cast<size_t>(m.triangles[t][0])];
        const Vec3 ab = m.points[static_cast<size_t>(m.triangles[t][1])] - a;
        const Vec3 ac = m.points[static_cast<size_t>(m.triangles[t][2])] - a;
        const long k = static_cast<long>(std::floor(0.5 * norm(cross(ab, ac)) / (h * h)));
        for (long j = 0; j < k; ++j) {
            const std::uint64_t key = splitmix64((static_cast<std::uint64_t>(t) << 24) ^ static_cast<std::uint64_t>(j));
            double u = unit_double(key), w = unit_double(splitmix64(key));
            if (u + w > 1) {
                u = 1 - u;
                w = 1 - w;
            }
            samples.push_back(a + u * ab + w * ac);
            source.push_back({2, static_cast<int>(t)});
        }
    }
    return samples;
}

// ---------------------------------------------------------------- thin parts: samples where the solid is thin

// Calls fn(a, b, c, index) for the k^2 triangles of the barycentric k-grid of triangle (A, B, C) (k >= 1), index
// 0 .. k^2 - 1 in a fixed order.
template <typename Fn>
void for_each_grid_triangle(const Vec3& A, const Vec3& B, const Vec3& C, int k, Fn&& fn) {
    auto at = [&](int i, int j) {
        return A + (B - A) * (static_cast<double>(i) / k) + (C - A) * (static_cast<double>(j) / k);
    };
    int index = 0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; i + j < k; ++j) {
            fn(at(i, j), at(i + 1, j), at(i, j + 1), index++);
            if (i + j + 1 < k) fn(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), index++);
        }
}

// One cell of the thickness probe grid: a triangle of the k-grid of a surface triangle (k = ceil(longest edge /
// sample spacing)), with the solid's thickness at its centroid along the inward normal (infinity when the ray misses).
struct ProbeCell {
    int triangle;  // surface triangle
    int index;     // in that triangle's grid
    std::array<Vec3, 3> corners;
    double thickness;
};

// The probe cells of the surface and their thickness (first ray hit from the centroid along the inward normal: the
// distance to the opposite side of the solid; on a plate its thickness, on a tube its diameter). Serial: a fixed order.
std::vector<ProbeCell> probe_thickness(const TriangleMesh& m, const SurfaceQuery& query, double h, double diag) {
    // Orientation: the signed volume says whether the triangles' normals point out (> 0) or in.
    double volume6 = 0;
    for (const std::array<int, 3>& t : m.triangles)
        volume6 += dot(m.points[static_cast<size_t>(t[0])],
                       cross(m.points[static_cast<size_t>(t[1])], m.points[static_cast<size_t>(t[2])]));
    const double inward = volume6 > 0 ? -1.0 : 1.0;
    std::vector<ProbeCell> cells;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const Vec3& A = m.points[static_cast<size_t>(m.triangles[t][0])];
        const Vec3& B = m.points[static_cast<size_t>(m.triangles[t][1])];
        const Vec3& C = m.points[static_cast<size_t>(m.triangles[t][2])];
        const Vec3 n = cross(B - A, C - A);
        if (norm(n) <= 0) continue;
        const Vec3 dir = normalized(n) * inward;
        const double longest = std::max({distance(A, B), distance(B, C), distance(C, A)});
        const int k = std::clamp(static_cast<int>(std::ceil(longest / h)), 1, 4096);
        for_each_grid_triangle(A, B, C, k, [&](const Vec3& a, const Vec3& b, const Vec3& c, int index) {
            const Vec3 g = (a + b + c) * (1.0 / 3.0);
            const std::optional<RayHit> hit = query.first_hit(g, dir, 1e-9 * diag);
            cells.push_back(
                {static_cast<int>(t), index, {a, b, c}, hit ? hit->distance : std::numeric_limits<double>::infinity()});
        });
    }
    return cells;
}

// Extra samples in a probe cell: where the cell is thinner than thickness_samples x h0 (the base spacing asked for),
// one per spacing^2 of its area, the local spacing being scale x thickness / thickness_samples, at least scale x h0 /
// max_refinement; none elsewhere. scale (>= 1) is the factor the base spacing grew by to fit max_samples: the same
// cells are refined, all spacings grow alike. The count is k^2 (k = sqrt(area) / spacing, rounded) when that is at
// least 1, else 1 or 0 from a fixed hash of the cell (expected count area / spacing^2).
std::uint64_t cell_key(const ProbeCell& c) {
    return splitmix64((static_cast<std::uint64_t>(c.triangle) << 32) ^ static_cast<std::uint64_t>(c.index) ^
                      0x5bd1e995ull);
}
double refinement_spacing(const ProbeCell& c, double h0, double scale, double thickness_samples,
                          double max_refinement) {
    return scale * std::max(c.thickness / thickness_samples, h0 / std::max(1.0, max_refinement));
}
int refinement_grid(const ProbeCell& c, double h0, double scale, double thickness_samples, double max_refinement) {
    if (thickness_samples <= 0 || !(c.thickness < thickness_samples * h0)) return 0;
    const double spacing = refinement_spacing(c, h0, scale, thickness_samples, max_refinement);
    const double expected =
        0.5 * norm(cross(c.corners[1] - c.corners[0], c.corners[2] - c.corners[0])) / (spacing * spacing);
    if (expected < 1) return unit_double(cell_key(c)) < expected ? 1 : 0;
    return std::min(4096, static_cast<int>(std::floor(std::sqrt(expected) + 0.5)));
}

// Stratified extra samples: one point per triangle of the cell's k-grid, at barycentric coordinates from a fixed hash
// of (surface triangle, cell, grid triangle): no gaps wider than a grid triangle, no cospherical grid.
void add_refinement_samples(const ProbeCell& c, int k, std::vector<Vec3>& samples) {
    const std::uint64_t base = cell_key(c);
    for_each_grid_triangle(c.corners[0], c.corners[1], c.corners[2], k,
                           [&](const Vec3& a, const Vec3& b, const Vec3& d, int index) {
                               const std::uint64_t key = splitmix64(base ^ (static_cast<std::uint64_t>(index) << 1));
                               double u = unit_double(key), w = unit_double(splitmix64(key));
                               if (u + w > 1) {
                                   u = 1 - u;
                                   w = 1 - w;
                               }
                               samples.push_back(a + (b - a) * u + (d - a) * w);
                           });
}

// A sample's local thickness and spacing where it lies in a refined (thin) probe cell; infinity / 0 elsewhere.
struct ThinSample {
    double thickness = std::numeric_limits<double>::infinity();
    double spacing = 0;
};

// The probe cell of triangle t (cells first[t] .. first[t] + k[t]^2 - 1, in for_each_grid_triangle order) that holds
// the point x of that triangle (by its barycentric coordinates).
int cell_at(const TriangleMesh& m, int t, int first, int k, const Vec3& x) {
    const Vec3& A = m.points[static_cast<size_t>(m.triangles[static_cast<size_t>(t)][0])];
    const Vec3 e1 = m.points[static_cast<size_t>(m.triangles[static_cast<size_t>(t)][1])] - A;
    const Vec3 e2 = m.points[static_cast<size_t>(m.triangles[static_cast<size_t>(t)][2])] - A;
    const Vec3 d = x - A;
    const double a = dot(e1, e1), b = dot(e1, e2), c = dot(e2, e2), det = a * c - b * b;
    const double u = det > 0 ? (c * dot(d, e1) - b * dot(d, e2)) / det : 0;
    const double w = det > 0 ? (a * dot(d, e2) - b * dot(d, e1)) / det : 0;
    const int i = std::clamp(static_cast<int>(std::floor(u * k)), 0, k - 1);
    const int j = std::clamp(static_cast<int>(std::floor(w * k)), 0, k - 1 - i);
    const bool up = (u * k - i) + (w * k - j) < 1 || i + j + 1 >= k;
    return first + 2 * k * i - i * i + 2 * j + (up ? 0 : 1);
}

// ---------------------------------------------------------------- sphere quadrics

// E(x) = x^T A x - 2 b.x + c for x = (centre, radius); A symmetric 4 x 4.
struct SphereQuadric {
    std::array<double, 16> A{};
    std::array<double, 4> b{};
    double c = 0;

    // Tangent plane through p with unit outward normal n: error (n . centre + r - n . p)^2.
    void add_plane(const Vec3& n, const Vec3& p) {
        const std::array<double, 4> m = {n.x, n.y, n.z, 1.0};
        const double d = dot(n, p);
        for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j)
                A[static_cast<size_t>(4 * i + j)] += m[static_cast<size_t>(i)] * m[static_cast<size_t>(j)];
            b[static_cast<size_t>(i)] += d * m[static_cast<size_t>(i)];
        }
        c += d * d;
    }
    // w |x - x0|^2 (keeps the system definite where the planes leave a direction free).
    void add_point(const std::array<double, 4>& x0, double w) {
        for (int i = 0; i < 4; ++i) {
            A[static_cast<size_t>(5 * i)] += w;
            b[static_cast<size_t>(i)] += w * x0[static_cast<size_t>(i)];
            c += w * x0[static_cast<size_t>(i)] * x0[static_cast<size_t>(i)];
        }
    }
    SphereQuadric& operator+=(const SphereQuadric& o) {
        for (size_t i = 0; i < 16; ++i) A[i] += o.A[i];
        for (size_t i = 0; i < 4; ++i) b[i] += o.b[i];
        c += o.c;
        return *this;
    }
    double eval(const std::array<double, 4>& x) const {
        double e = c;
        for (size_t i = 0; i < 4; ++i) {
            double row = 0;
            for (size_t j = 0; j < 4; ++j) row += A[4 * i + j] * x[j];
            e += x[i] * row - 2 * b[i] * x[i];
        }
        return std::max(0.0, e);
    }
    // Minimizer of E (Gaussian elimination with partial pivoting); false when singular.
    bool minimize(std::array<double, 4>& x) const {
        double M[4][5];
        for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j) M[i][j] = A[static_cast<size_t>(4 * i + j)];
            M[i][4] = b[static_cast<size_t>(i)];
        }
        const double scale = std::max(1e-300, std::abs(A[0]) + std::abs(A[5]) + std::abs(A[10]) + std::abs(A[15]));
        for (int col = 0; col < 4; ++col) {
            int piv = col;
            for (int i = col + 1; i < 4; ++i)
                if (std::abs(M[i][col]) > std::abs(M[piv][col])) piv = i;
            if (std::abs(M[piv][col]) < 1e-12 * scale) return false;
            if (piv != col)
                for (int j = 0; j < 5; ++j) std::swap(M[piv][j], M[col][j]);
            for (int i = col + 1; i < 4; ++i) {
                const double f = M[i][col] / M[col][col];
                for (int j = col; j < 5; ++j) M[i][j] -= f * M[col][j];
            }
        }
        for (int i = 3; i >= 0; --i) {
            double s = M[i][4];
            for (int j = i + 1; j < 4; ++j) s -= M[i][j] * x[static_cast<size_t>(j)];
            x[static_cast<size_t>(i)] = s / M[i][i];
        }
        return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]) && std::isfinite(x[3]);
    }
};

// ---------------------------------------------------------------- medial complex

// Vertices (spheres), triangles and the edge relation (sorted neighbour lists) of the medial mesh being simplified.
struct MedialComplex {
    std::vector<Vec3> centre;
    std::vector<double> radius;
    std::vector<SphereQuadric> quadric;
    std::vector<char> alive;
    std::vector<int> version;
    std::vector<std::vector<int>> neighbours;  // sorted, unique
    std::vector<std::vector<int>> vertex_triangles;
    std::vector<std::array<int, 3>> triangles;
    std::vector<char> triangle_alive;
    std::vector<std::array<int, 4>> touching;  // per vertex: the 4 surface samples on its sphere (Delaunay cell)
};

void insert_sorted(std::vector<int>& v, int x) {
    auto it = std::lower_bound(v.begin(), v.end(), x);
    if (it == v.end() || *it != x) v.insert(it, x);
}
void erase_sorted(std::vector<int>& v, int x) {
    auto it = std::lower_bound(v.begin(), v.end(), x);
    if (it != v.end() && *it == x) v.erase(it);
}
bool contains(const std::array<int, 3>& t, int v) { return t[0] == v || t[1] == v || t[2] == v; }

// Angle filter as an erosion that keeps the homotopy type (elementary collapses of the inner Voronoi complex, which
// is homotopy equivalent to the solid): a face whose angle is below the threshold (cos_angle > cos_min) goes with one
// free side (a side in no other face), smallest angle first; a side left in no face stays as a curve edge, and a curve
// edge with an end on nothing else goes with that end. What stays: the wide-angle faces (the medial sheets and the
// sliver bundles around tube axes) and whatever narrow-angle faces and edges hold them together (the ligature
// where a disk's mid-sheet meets its hub's axis, the faces that close the holes noise would punch into a thin
// plate's sheet). Returns the faces kept (in input order) and writes the curve edges left (cell ids, a < b, sorted).
std::vector<std::vector<int>> erode_by_angle(const std::vector<std::vector<int>>& faces,
                                             const std::vector<double>& face_cos, double cos_min,
                                             std::vector<std::array<int, 2>>& curve_edges) {
    // Edges of the complex: sorted cell-id pairs, with their faces' count.
    std::vector<std::array<int, 2>> edges;
    for (const std::vector<int>& f : faces)
        for (size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    auto edge_id = [&](int a, int b) {
        const std::array<int, 2> key = {std::min(a, b), std::max(a, b)};
        return static_cast<int>(std::lower_bound(edges.begin(), edges.end(), key) - edges.begin());
    };
    std::vector<std::vector<int>> face_edges(faces.size());
    std::vector<std::vector<int>> edge_faces(edges.size());
    for (size_t f = 0; f < faces.size(); ++f)
        for (size_t k = 0; k < faces[f].size(); ++k) {
            const int e = edge_id(faces[f][k], faces[f][(k + 1) % faces[f].size()]);
            face_edges[f].push_back(e);
            edge_faces[static_cast<size_t>(e)].push_back(static_cast<int>(f));
        }
    std::vector<int> face_count(edges.size());
    for (size_t e = 0; e < edges.size(); ++e) face_count[e] = static_cast<int>(edge_faces[e].size());
    // Vertex -> edges (cell ids are sparse: a map keeps memory to the vertices used).
    std::map<int, std::vector<int>> vertex_edges;
    for (size_t e = 0; e < edges.size(); ++e)
        for (int v : edges[e]) vertex_edges[v].push_back(static_cast<int>(e));
    std::map<int, int> degree;
    for (const auto& [v, es] : vertex_edges) degree[v] = static_cast<int>(es.size());
    std::vector<char> face_alive(faces.size(), 1), edge_alive(edges.size(), 1);

    std::vector<int> tips;  // vertices of degree 1 to check
    auto erode_curves = [&]() {
        while (!tips.empty()) {
            const int v = tips.back();
            tips.pop_back();
            if (degree[v] != 1) continue;
            int e = -1;
            for (int x : vertex_edges[v])
                if (edge_alive[static_cast<size_t>(x)]) e = x;
            if (e < 0 || face_count[static_cast<size_t>(e)] != 0) continue;
            edge_alive[static_cast<size_t>(e)] = 0;
            for (int w : edges[static_cast<size_t>(e)])
                if (--degree[w] == 1) tips.push_back(w);
        }
    };
    using Item = std::pair<double, int>;  // (-cos angle: smallest angle first, face)
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    auto push_if_free = [&](int f) {
        if (!face_alive[static_cast<size_t>(f)] || face_cos[static_cast<size_t>(f)] <= cos_min) return;
        for (int e : face_edges[static_cast<size_t>(f)])
            if (face_count[static_cast<size_t>(e)] == 1) {
                heap.push({-face_cos[static_cast<size_t>(f)], f});
                return;
            }
    };
    for (size_t f = 0; f < faces.size(); ++f) push_if_free(static_cast<int>(f));
    while (!heap.empty()) {
        const int f = heap.top().second;
        heap.pop();
        if (!face_alive[static_cast<size_t>(f)]) continue;
        int free_edge = -1;
        for (int e : face_edges[static_cast<size_t>(f)])
            if (face_count[static_cast<size_t>(e)] == 1) {
                free_edge = e;
                break;
            }
        if (free_edge < 0) continue;
        face_alive[static_cast<size_t>(f)] = 0;
        for (int e : face_edges[static_cast<size_t>(f)]) --face_count[static_cast<size_t>(e)];
        edge_alive[static_cast<size_t>(free_edge)] = 0;
        for (int w : edges[static_cast<size_t>(free_edge)])
            if (--degree[w] == 1) tips.push_back(w);
        for (int e : face_edges[static_cast<size_t>(f)]) {
            if (!edge_alive[static_cast<size_t>(e)]) continue;
            if (face_count[static_cast<size_t>(e)] == 1)
                for (int g : edge_faces[static_cast<size_t>(e)]) push_if_free(g);
            if (face_count[static_cast<size_t>(e)] == 0)
                for (int w : edges[static_cast<size_t>(e)])
                    if (degree[w] == 1) tips.push_back(w);
        }
        erode_curves();
    }
    std::vector<std::vector<int>> kept;
    for (size_t f = 0; f < faces.size(); ++f)
        if (face_alive[f]) kept.push_back(faces[f]);
    curve_edges.clear();
    for (size_t e = 0; e < edges.size(); ++e)
        if (edge_alive[e] && face_count[e] == 0) curve_edges.push_back(edges[e]);
    return kept;
}

// keep_topology: the cells of the solid's tetrahedralization (centroid inside) whose circumcentre fell outside (flat
// cells at the surface, at thin places) still count as inner: without their Voronoi vertices the inner complex has
// holes the solid has not. Their faces are narrow and go in the erosion unless the topology needs them.
void add_flat_inner_cells(const std::vector<Vec3>& samples, const SurfaceQuery& query, double diag,
                          const std::vector<Vec3>& centres, const std::vector<double>& radii,
                          const std::vector<std::array<int, 4>>& cell_samples, std::vector<char>& inside) {
    std::vector<int> flat;
    std::vector<Vec3> centroids;
    for (size_t i = 0; i < centres.size(); ++i) {
        if (inside[i] || !std::isfinite(radii[i]) || radii[i] >= diag) continue;
        Vec3 g{0, 0, 0};
        for (int v : cell_samples[i]) g = g + 0.25 * samples[static_cast<size_t>(v)];
        flat.push_back(static_cast<int>(i));
        centroids.push_back(g);
    }
    const std::vector<char> in = query.inside(centroids);
    for (size_t k = 0; k < flat.size(); ++k)
        if (in[k]) inside[static_cast<size_t>(flat[k])] = 1;
}

// The inner faces in Delaunay-edge order, filtered by angle
// (dropped, or eroded with keep_topology; see erode_by_angle).
using KeyedFace = std::tuple<std::array<int, 2>, std::vector<int>, double>;
std::vector<std::vector<int>> select_faces(std::vector<KeyedFace>& keyed_faces, double cos_min, bool keep_topology,
                                           std::vector<std::array<int, 2>>& curve_edges) {
    std::sort(keyed_faces.begin(), keyed_faces.end(),
              [](const auto& x, const auto& y) { return std::get<0>(x) < std::get<0>(y); });
    std::vector<std::vector<int>> all_faces;
    std::vector<double> face_cos;
    for (auto& kf : keyed_faces) {
        all_faces.push_back(std::move(std::get<1>(kf)));
        face_cos.push_back(std::get<2>(kf));
    }
    std::vector<std::vector<int>> faces;
    if (keep_topology) {
        faces = erode_by_angle(all_faces, face_cos, cos_min, curve_edges);
    } else {
        for (size_t f = 0; f < all_faces.size(); ++f)
            if (face_cos[f] <= cos_min) faces.push_back(std::move(all_faces[f]));
    }
    return faces;
}

// Inner poles and angle-filtered Voronoi faces of the samples, fan-triangulated into a medial complex.
// thin (per sample; empty = none): a face whose two samples both lie in thin parts is also kept when they are at least
// thin_separation x the smaller local thickness and kThinNoiseSpacings x that sample's local spacing apart.
constexpr double kThinNoiseSpacings = 2.5;  // x local spacing: faces between neighbouring samples (noise) are shorter

// The thin-part rule of voronoi_medial_complex for the face between samples p and q (at P and Q).
bool thin_pair_kept(const std::vector<ThinSample>& thin, double thin_separation, int p, int q, const Vec3& P,
                    const Vec3& Q) {
    if (thin.empty() || thin_separation <= 0) return false;
    const ThinSample& a = thin[static_cast<size_t>(p)];
    const ThinSample& b = thin[static_cast<size_t>(q)];
    const ThinSample& t = a.thickness <= b.thickness ? a : b;
    const double pq = distance(P, Q);
    return std::isfinite(a.thickness) && std::isfinite(b.thickness) && pq >= thin_separation * t.thickness &&
           pq >= kThinNoiseSpacings * t.spacing;
}

// The medial complex of the kept Voronoi faces and curve edges: the cells they use become its vertices (in cell
// order, each with the sphere quadric of its four samples' tangent planes), the faces its triangles (fans from each
// face's first cell), the curve edges its other edges.
MedialComplex complex_of_faces(const std::vector<Vec3>& samples, const std::vector<Vec3>& centres,
                               const std::vector<double>& radii, const std::vector<std::array<int, 4>>& cell_samples,
                               const std::vector<std::vector<int>>& faces,
                               const std::vector<std::array<int, 2>>& curve_edges) {
    std::vector<int> cell_to_vertex(centres.size(), -1);
    MedialComplex mc;
    for (const std::vector<int>& f : faces)
        for (int id : f) cell_to_vertex[static_cast<size_t>(id)] = 0;
    for (const std::array<int, 2>& e : curve_edges)
        for (int id : e) cell_to_vertex[static_cast<size_t>(id)] = 0;
    for (size_t i = 0; i < centres.size(); ++i)
        if (cell_to_vertex[i] == 0) {
            cell_to_vertex[i] = static_cast<int>(mc.centre.size());
            mc.centre.push_back(centres[i]);
            mc.radius.push_back(radii[i]);
            SphereQuadric q;
            for (int s : cell_samples[i]) {
                const Vec3& p = samples[static_cast<size_t>(s)];
                q.add_plane(normalized(p - centres[i]), p);
            }
            // A light pull to the pole itself: 1e-3 of one tangent plane.
            q.add_point({centres[i].x, centres[i].y, centres[i].z, radii[i]}, 1e-3);
            mc.quadric.push_back(q);
            mc.touching.push_back(cell_samples[i]);
        }
    const size_t nv = mc.centre.size();
    mc.alive.assign(nv, 1);
    mc.version.assign(nv, 0);
    mc.neighbours.assign(nv, {});
    mc.vertex_triangles.assign(nv, {});
    for (const std::vector<int>& f : faces) {
        const int v0 = cell_to_vertex[static_cast<size_t>(f[0])];
        for (size_t k = 1; k + 1 < f.size(); ++k) {
            const std::array<int, 3> t = {v0, cell_to_vertex[static_cast<size_t>(f[k])],
                                          cell_to_vertex[static_cast<size_t>(f[k + 1])]};
            const int id = static_cast<int>(mc.triangles.size());
            mc.triangles.push_back(t);
            for (int j = 0; j < 3; ++j) {
                mc.vertex_triangles[static_cast<size_t>(t[static_cast<size_t>(j)])].push_back(id);
                const int a = t[static_cast<size_t>(j)], b = t[static_cast<size_t>((j + 1) % 3)];
                mc.neighbours[static_cast<size_t>(a)].push_back(b);
                mc.neighbours[static_cast<size_t>(b)].push_back(a);
            }
        }
    }
    mc.triangle_alive.assign(mc.triangles.size(), 1);
    for (const std::array<int, 2>& e : curve_edges) {
        const int a = cell_to_vertex[static_cast<size_t>(e[0])], b = cell_to_vertex[static_cast<size_t>(e[1])];
        mc.neighbours[static_cast<size_t>(a)].push_back(b);
        mc.neighbours[static_cast<size_t>(b)].push_back(a);
    }
    for (std::vector<int>& n : mc.neighbours) {
        std::sort(n.begin(), n.end());
        n.erase(std::unique(n.begin(), n.end()), n.end());
    }
    return mc;
}

MedialComplex voronoi_medial_complex(const std::vector<Vec3>& samples, const std::vector<ThinSample>& thin,
                                     double thin_separation, const SurfaceQuery& query, double diag,
                                     double min_angle_deg, bool keep_topology, MedialAxis& out) {
    // Insertion in Hilbert order (no randomness: CGAL's range insertion shuffles with the global default random
    // generator, so a second call in the same process gave another triangulation of the cospherical samples).
    std::vector<K::Point_3> points;
    points.reserve(samples.size());
    for (const Vec3& p : samples) points.emplace_back(p.x, p.y, p.z);
    std::vector<std::size_t> order(points.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    using SortTraits = CGAL::Spatial_sort_traits_adapter_3<K, CGAL::Pointer_property_map<K::Point_3>::type>;
    CGAL::hilbert_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(points)));
    Delaunay dt;
    Delaunay::Cell_handle hint;
    for (std::size_t i : order) {
        const std::size_t before = dt.number_of_vertices();
        const Delaunay::Vertex_handle v = dt.insert(points[i], hint);
        if (dt.number_of_vertices() > before) v->info() = static_cast<int>(i);
        hint = v->cell();
    }
    out.samples = static_cast<int>(dt.number_of_vertices());

    // Cells numbered by their sorted sample ids (the TDS's storage order follows heap addresses: a second call in
    // the same process stored the cells in another order).
    std::vector<std::pair<std::array<int, 4>, Delaunay::Cell_handle>> cells;
    for (Delaunay::Cell_handle ch : dt.finite_cell_handles()) {
        std::array<int, 4> key = {ch->vertex(0)->info(), ch->vertex(1)->info(), ch->vertex(2)->info(),
                                  ch->vertex(3)->info()};
        std::sort(key.begin(), key.end());
        cells.emplace_back(key, ch);
    }
    std::sort(cells.begin(), cells.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<Vec3> centres;
    std::vector<double> radii;
    std::vector<std::array<int, 4>> cell_samples;
    for (const auto& [key, ch] : cells) {
        ch->info() = static_cast<int>(centres.size());
        const K::Point_3 cc = CGAL::circumcenter(ch->vertex(0)->point(), ch->vertex(1)->point(), ch->vertex(2)->point(),
                                                 ch->vertex(3)->point());
        const Vec3 c{cc.x(), cc.y(), cc.z()};
        centres.push_back(c);
        radii.push_back(distance(c, samples[static_cast<size_t>(key[0])]));
        cell_samples.push_back(key);
    }
    for (Delaunay::Cell_handle ch : dt.all_cell_handles())
        if (dt.is_infinite(ch)) ch->info() = -1;
    // Only cells of reasonable size can be inner poles (a flat cell on the hull has a huge circumsphere).
    std::vector<int> candidates;
    std::vector<Vec3> candidate_points;
    for (size_t i = 0; i < centres.size(); ++i)
        if (std::isfinite(radii[i]) && radii[i] < diag) {
            candidates.push_back(static_cast<int>(i));
            candidate_points.push_back(centres[i]);
        }
    const std::vector<char> inside_flags = query.inside(candidate_points);
    std::vector<char> inside(centres.size(), 0);
    for (size_t k = 0; k < candidates.size(); ++k) inside[static_cast<size_t>(candidates[k])] = inside_flags[k];
    out.inner_poles = static_cast<int>(std::count(inside.begin(), inside.end(), 1));
    if (keep_topology) add_flat_inner_cells(samples, query, diag, centres, radii, cell_samples, inside);
    // Inner Voronoi faces: one per finite Delaunay edge pq whose incident cells are all inner, with its angle: the
    // smallest angle pcq over its Voronoi vertices c (as a cosine: the largest cos pcq).
    std::vector<KeyedFace> keyed_faces;
    for (const Delaunay::Edge& e : dt.finite_edges()) {
        const int p = e.first->vertex(e.second)->info(), q = e.first->vertex(e.third)->info();
        const Vec3& P = samples[static_cast<size_t>(p)];
        const Vec3& Q = samples[static_cast<size_t>(q)];
        std::vector<int> poly;
        bool keep = true;
        double cos_angle = -1;
        Delaunay::Cell_circulator cc = dt.incident_cells(e), done = cc;
        do {
            const int id = cc->info();
            if (id < 0 || !inside[static_cast<size_t>(id)]) {
                keep = false;
                break;
            }
            const Vec3& C = centres[static_cast<size_t>(id)];
            const double r2 = radii[static_cast<size_t>(id)] * radii[static_cast<size_t>(id)];
            cos_angle = std::max(cos_angle, dot(P - C, Q - C) / std::max(1e-300, r2));
            poly.push_back(id);
        } while (++cc != done);
        if (!keep || poly.size() < 3) continue;
        if (thin_pair_kept(thin, thin_separation, p, q, P, Q)) {
            if (cos_angle > std::cos(min_angle_deg * kPi / 180.0)) ++out.thin_faces;
            cos_angle = -1;  // kept as if seen under 180 degrees
        }
        // Canonical polygon: from its smallest cell id, towards the smaller of its two neighbours.
        std::rotate(poly.begin(), std::min_element(poly.begin(), poly.end()), poly.end());
        if (poly.back() < poly[1]) std::reverse(poly.begin() + 1, poly.end());
        keyed_faces.emplace_back(std::array<int, 2>{std::min(p, q), std::max(p, q)}, std::move(poly), cos_angle);
    }
    std::vector<std::array<int, 2>> curve_edges;
    const std::vector<std::vector<int>> faces =
        select_faces(keyed_faces, std::cos(min_angle_deg * kPi / 180.0), keep_topology, curve_edges);
    out.voronoi_faces = static_cast<int>(faces.size());

    return complex_of_faces(samples, centres, radii, cell_samples, faces, curve_edges);
}

// The segment a-b lies inside the surface and its points keep at least clearance x the radius interpolated between
// a's and b's spheres from the surface (points every quarter of the smaller radius, at most 64).
bool segment_inside(const SurfaceQuery& query, const Vec3& a, double ra, const Vec3& b, double rb, double clearance) {
    const int n =
        std::clamp(static_cast<int>(std::ceil(4 * distance(a, b) / std::max(1e-300, std::min(ra, rb)))), 2, 64);
    std::vector<Vec3> points;
    for (int i = 0; i <= n; ++i) points.push_back(a + (b - a) * (static_cast<double>(i) / n));
    const std::vector<char> in = query.inside(points);
    for (int i = 0; i <= n; ++i) {
        if (!in[static_cast<size_t>(i)]) return false;
        const double t = static_cast<double>(i) / n;
        const double r = (1 - t) * ra + t * rb;
        if (query.squared_distance(points[static_cast<size_t>(i)]) < clearance * clearance * r * r) return false;
    }
    return true;
}

// The connected parts of the complex (alive vertices, sorted), largest first (ties: lowest vertex id first).
std::vector<std::vector<int>> complex_parts(const MedialComplex& mc) {
    const int nv = static_cast<int>(mc.centre.size());
    UnionFind uf(nv);
    for (int v = 0; v < nv; ++v)
        if (mc.alive[static_cast<size_t>(v)])
            for (int n : mc.neighbours[static_cast<size_t>(v)]) uf.unite(v, n);
    std::map<int, std::vector<int>> by_root;
    std::vector<int> first_root;
    for (int v = 0; v < nv; ++v)
        if (mc.alive[static_cast<size_t>(v)]) {
            std::vector<int>& part = by_root[uf.find(v)];
            if (part.empty()) first_root.push_back(uf.find(v));
            part.push_back(v);
        }
    std::vector<std::vector<int>> parts;
    for (int root : first_root) parts.push_back(std::move(by_root[root]));
    std::stable_sort(parts.begin(), parts.end(),
                     [](const std::vector<int>& x, const std::vector<int>& y) { return x.size() > y.size(); });
    return parts;
}

// Bounding-box diagonal of the part's sphere centres.
double part_extent(const MedialComplex& mc, const std::vector<int>& part) {
    Vec3 lo = mc.centre[static_cast<size_t>(part[0])], hi = lo;
    for (int v : part)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], mc.centre[static_cast<size_t>(v)][k]);
            hi[k] = std::max(hi[k], mc.centre[static_cast<size_t>(v)][k]);
        }
    return distance(lo, hi);
}

double part_max_radius(const MedialComplex& mc, const std::vector<int>& part) {
    double r = 0;
    for (int v : part) r = std::max(r, mc.radius[static_cast<size_t>(v)]);
    return r;
}

// Parts the angle filter cut apart (a disk's mid-sheet from its hub's axis where the two meet, fins from a rim) are
// joined back by one curve edge each: in decreasing size, a part of at least min_part_vertices vertices is joined to
// the growing main part (the largest) through its closest vertex pair, when that pair is at most join_factor x the
// larger of their radii apart and the segment between them stays inside (segment_inside, clearance 0.25). One edge
// per part: the homotopy type is the disjoint union's, plus a tree. With min_extent > 0 only the substantial parts
// join: those whose extent (part_extent) is at least min_extent x their largest radius. Returns the number of joins.
int join_components(MedialComplex& mc, const SurfaceQuery& query, double join_factor, int min_part_vertices,
                    double min_extent) {
    const std::vector<std::vector<int>> order = complex_parts(mc);
    if (order.size() < 2) return 0;
    std::vector<int> main = order[0];
    std::vector<char> joined(order.size(), 0);
    joined[0] = 1;
    int joins = 0;
    for (bool changed = true; changed;) {
        changed = false;
        for (size_t c = 1; c < order.size(); ++c) {
            if (joined[c] || static_cast<int>(order[c].size()) < min_part_vertices) continue;
            if (min_extent > 0 && part_extent(mc, order[c]) < min_extent * part_max_radius(mc, order[c])) continue;
            double best = std::numeric_limits<double>::infinity();
            int ba = -1, bb = -1;
            for (int a : order[c])
                for (int b : main) {
                    const double d =
                        distance(mc.centre[static_cast<size_t>(a)], mc.centre[static_cast<size_t>(b)]) -
                        std::max(mc.radius[static_cast<size_t>(a)], mc.radius[static_cast<size_t>(b)]) * 1e-9;
                    if (d < best) {
                        best = d;
                        ba = a;
                        bb = b;
                    }
                }
            const double ra = mc.radius[static_cast<size_t>(ba)], rb = mc.radius[static_cast<size_t>(bb)];
            if (best > join_factor * std::max(ra, rb)) continue;
            if (!segment_inside(query, mc.centre[static_cast<size_t>(ba)], ra, mc.centre[static_cast<size_t>(bb)], rb,
                                0.25))
                continue;
            insert_sorted(mc.neighbours[static_cast<size_t>(ba)], bb);
            insert_sorted(mc.neighbours[static_cast<size_t>(bb)], ba);
            main.insert(main.end(), order[c].begin(), order[c].end());
            joined[c] = 1;
            ++joins;
            changed = true;
        }
    }
    return joins;
}

// ---------------------------------------------------------------- limbs

// The spheres of the kept medial complex bucketed by centre on a grid, for the gap of a surface point to their union.
struct SphereGrid {
    double cell = 1;        // grid step (length)
    double max_radius = 0;  // of the spheres inserted
    std::unordered_map<std::int64_t, std::vector<int>> buckets;
};

std::array<long, 3> grid_cell(const SphereGrid& g, const Vec3& p) {
    return {static_cast<long>(std::floor(p.x / g.cell)), static_cast<long>(std::floor(p.y / g.cell)),
            static_cast<long>(std::floor(p.z / g.cell))};
}

std::int64_t grid_key(long i, long j, long k) {
    return ((static_cast<std::int64_t>(i) & 0x1FFFFF) << 42) | ((static_cast<std::int64_t>(j) & 0x1FFFFF) << 21) |
           (static_cast<std::int64_t>(k) & 0x1FFFFF);
}

void grid_insert(SphereGrid& g, const MedialComplex& mc, int v) {
    const std::array<long, 3> c = grid_cell(g, mc.centre[static_cast<size_t>(v)]);
    g.buckets[grid_key(c[0], c[1], c[2])].push_back(v);
    g.max_radius = std::max(g.max_radius, mc.radius[static_cast<size_t>(v)]);
}

struct Gap {
    double gap = std::numeric_limits<double>::infinity();  // min over spheres of |p - c| - r
    double radius = 0;                                     // of the sphere reaching it
};

void update_gap(Gap& g, const MedialComplex& mc, int v, const Vec3& p) {
    const double d = distance(p, mc.centre[static_cast<size_t>(v)]) - mc.radius[static_cast<size_t>(v)];
    if (d < g.gap) g = {d, mc.radius[static_cast<size_t>(v)]};
}

// Gap of p to the union of the grid's spheres: cells in rings of growing Chebyshev distance k around p's cell, until
// no centre in ring k (at least (k - 1) x cell from p) can beat the best gap.
Gap union_gap(const SphereGrid& g, const MedialComplex& mc, const Vec3& p) {
    Gap best;
    const std::array<long, 3> c = grid_cell(g, p);
    for (long k = 0; k < 1000000; ++k) {
        if (static_cast<double>(k - 1) * g.cell - g.max_radius >= best.gap) break;
        for (long i = -k; i <= k; ++i)
            for (long j = -k; j <= k; ++j) {
                const bool rim = std::max(std::labs(i), std::labs(j)) == k;
                for (long l = -k; l <= k; l += (rim || k == 0) ? 1 : 2 * k) {
                    const auto it = g.buckets.find(grid_key(c[0] + i, c[1] + j, c[2] + l));
                    if (it == g.buckets.end()) continue;
                    for (int v : it->second) update_gap(best, mc, v, p);
                }
            }
        if (k > 0 && g.buckets.empty()) break;
    }
    return best;
}

// A cut-off part's surface: the samples on its spheres, with their gap to the kept spheres and the largest radius of
// the part's spheres touching them (and that sphere).
struct PartSamples {
    std::vector<int> sample;
    std::vector<Gap> gap;
    std::vector<int> deepest;  // part vertex: the largest sphere on the sample
};

PartSamples part_samples(const MedialComplex& mc, const std::vector<int>& part, const std::vector<Vec3>& samples,
                         const SphereGrid& kept) {
    std::map<int, int> deepest;
    for (int v : part)
        for (int s : mc.touching[static_cast<size_t>(v)]) {
            auto [it, fresh] = deepest.emplace(s, v);
            if (!fresh && mc.radius[static_cast<size_t>(v)] > mc.radius[static_cast<size_t>(it->second)])
                it->second = v;
        }
    PartSamples ps;
    for (const auto& [s, v] : deepest) {
        ps.sample.push_back(s);
        ps.deepest.push_back(v);
        ps.gap.push_back(union_gap(kept, mc, samples[static_cast<size_t>(s)]));
    }
    return ps;
}

// Shortest paths (edge length) from root inside the part: distance and predecessor per vertex (-1: none).
void part_paths(const MedialComplex& mc, const std::vector<char>& in_part, int root, std::vector<double>& dist,
                std::vector<int>& from) {
    dist.assign(mc.centre.size(), std::numeric_limits<double>::infinity());
    from.assign(mc.centre.size(), -1);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    dist[static_cast<size_t>(root)] = 0;
    heap.push({0.0, root});
    while (!heap.empty()) {
        const auto [d, v] = heap.top();
        heap.pop();
        if (d > dist[static_cast<size_t>(v)]) continue;
        for (int n : mc.neighbours[static_cast<size_t>(v)]) {
            if (!in_part[static_cast<size_t>(n)]) continue;
            const double nd = d + distance(mc.centre[static_cast<size_t>(v)], mc.centre[static_cast<size_t>(n)]);
            if (nd < dist[static_cast<size_t>(n)]) {
                dist[static_cast<size_t>(n)] = nd;
                from[static_cast<size_t>(n)] = v;
                heap.push({nd, n});
            }
        }
    }
}

// The closest pair (part vertex, kept vertex) by centre distance (ties: lower ids); {-1, -1} when none.
std::array<int, 2> closest_pair(const MedialComplex& mc, const std::vector<int>& part, const std::vector<int>& kept) {
    double best = std::numeric_limits<double>::infinity();
    std::array<int, 2> pair = {-1, -1};
    for (int a : part)
        for (int b : kept) {
            const double d = squared_norm(mc.centre[static_cast<size_t>(a)] - mc.centre[static_cast<size_t>(b)]);
            if (d < best) {
                best = d;
                pair = {a, b};
            }
        }
    return pair;
}

// A sample is uncovered when its gap to the kept spheres exceeds limb_gap x diag and limb_radius_factor x the radius
// of the kept sphere nearest to it.
bool uncovered(const Gap& g, const MedialAxisOptions& o, double diag) {
    return g.gap > o.limb_gap * diag && g.gap > o.limb_radius_factor * g.radius;
}

// Grows the tree of a limb part from its root: while a sample of the part is uncovered, the shortest path from the
// root to the largest sphere on the uncovered sample whose sphere is farthest (path length; ties: lower sample) joins
// the tree and covers it (each sample is picked at most once: its gap to its own sphere is 0 only up to rounding, which
// thresholds of 0 would see as uncovered). Returns the tree edges; branches counts the paths.
std::vector<std::array<int, 2>> limb_tree(const MedialComplex& mc, const std::vector<int>& part, int root,
                                          PartSamples& ps, const std::vector<Vec3>& samples, const MedialAxisOptions& o,
                                          double diag, int& branches) {
    std::vector<char> in_part(mc.centre.size(), 0), in_tree(mc.centre.size(), 0);
    for (int v : part) in_part[static_cast<size_t>(v)] = 1;
    std::vector<double> dist;
    std::vector<int> from;
    part_paths(mc, in_part, root, dist, from);
    in_tree[static_cast<size_t>(root)] = 1;
    std::vector<std::array<int, 2>> edges;
    std::vector<char> picked(ps.sample.size(), 0);
    for (;;) {
        int pick = -1;
        for (size_t i = 0; i < ps.sample.size(); ++i)
            if (!picked[i] && uncovered(ps.gap[i], o, diag) &&
                (pick < 0 || dist[static_cast<size_t>(ps.deepest[i])] >
                                 dist[static_cast<size_t>(ps.deepest[static_cast<size_t>(pick)])]))
                pick = static_cast<int>(i);
        if (pick < 0) break;
        picked[static_cast<size_t>(pick)] = 1;
        std::vector<int> added;
        for (int v = ps.deepest[static_cast<size_t>(pick)]; !in_tree[static_cast<size_t>(v)];
             v = from[static_cast<size_t>(v)]) {
            in_tree[static_cast<size_t>(v)] = 1;
            added.push_back(v);
            edges.push_back({std::min(v, from[static_cast<size_t>(v)]), std::max(v, from[static_cast<size_t>(v)])});
        }
        if (added.empty()) added.push_back(ps.deepest[static_cast<size_t>(pick)]);  // on the tree: the gap is stale
        for (size_t i = 0; i < ps.sample.size(); ++i)
            for (int v : added) update_gap(ps.gap[i], mc, v, samples[static_cast<size_t>(ps.sample[i])]);
        ++branches;
    }
    return edges;
}

// How far the part's spheres lie from its tree: the largest, over the part's vertices, of the smallest distance to a
// tree vertex's centre in units of that vertex's radius (at most 1: every centre inside a tree sphere, a tube; a
// sheet's centres between the paths lie farther).
double tree_width(const MedialComplex& mc, const std::vector<int>& part, const std::vector<std::array<int, 2>>& edges,
                  int root) {
    std::vector<int> tree = {root};
    for (const std::array<int, 2>& e : edges) tree.insert(tree.end(), e.begin(), e.end());
    std::sort(tree.begin(), tree.end());
    tree.erase(std::unique(tree.begin(), tree.end()), tree.end());
    double width = 0;
    for (int v : part) {
        double best = std::numeric_limits<double>::infinity();
        for (int t : tree)
            best = std::min(best, distance(mc.centre[static_cast<size_t>(v)], mc.centre[static_cast<size_t>(t)]) /
                                      std::max(1e-300, mc.radius[static_cast<size_t>(t)]));
        width = std::max(width, best);
    }
    return width;
}

// Replaces a limb part by its tree (curve edges; its triangles and other vertices go) joined to the kept vertex.
void keep_tree_of_part(MedialComplex& mc, const std::vector<int>& part, const std::vector<std::array<int, 2>>& edges,
                       int root, int anchor) {
    for (int v : part) {
        mc.alive[static_cast<size_t>(v)] = 0;
        for (int t : mc.vertex_triangles[static_cast<size_t>(v)]) mc.triangle_alive[static_cast<size_t>(t)] = 0;
        mc.vertex_triangles[static_cast<size_t>(v)].clear();
        mc.neighbours[static_cast<size_t>(v)].clear();
    }
    mc.alive[static_cast<size_t>(root)] = 1;
    for (const std::array<int, 2>& e : edges) {
        mc.alive[static_cast<size_t>(e[0])] = mc.alive[static_cast<size_t>(e[1])] = 1;
        insert_sorted(mc.neighbours[static_cast<size_t>(e[0])], e[1]);
        insert_sorted(mc.neighbours[static_cast<size_t>(e[1])], e[0]);
    }
    insert_sorted(mc.neighbours[static_cast<size_t>(root)], anchor);
    insert_sorted(mc.neighbours[static_cast<size_t>(anchor)], root);
}

// A grid of one part's spheres, its step the part's mean radius (at least 1e-3 x diag).
SphereGrid part_grid(const MedialComplex& mc, const std::vector<int>& part, double diag) {
    SphereGrid grid;
    double mean_radius = 0;
    for (int v : part) mean_radius += mc.radius[static_cast<size_t>(v)] / static_cast<double>(part.size());
    grid.cell = std::max(mean_radius, 1e-3 * diag);
    for (int v : part) grid_insert(grid, mc, v);
    return grid;
}

// Limbs (docs/sheets.md, "Limbs the angle filter cut off"): every part the angle filter cut off the largest one, in
// decreasing size, whose spheres touch a surface sample that the kept spheres (the largest part and the limbs kept
// before) leave uncovered (gap above limb_gap x diag and limb_radius_factor x the nearest kept radius) is kept as a
// tree of its curves: the shortest paths from its sphere closest to the kept ones to the spheres on its uncovered
// samples, farthest first, until none is uncovered, joined by one curve edge (when that segment stays inside with
// clearance 0.25 x radius). Its triangles and other spheres go: no cycles, no corner debris (a 90-degree edge of a
// plate lies 0.41 x the sheet's radius from its spheres). Returns the number of limbs; branches counts their paths.
int keep_limb_trees(MedialComplex& mc, const std::vector<Vec3>& samples, const SurfaceQuery& query,
                    const MedialAxisOptions& o, double diag, int& branches) {
    if (!o.keep_limbs) return 0;
    std::vector<std::vector<int>> parts = complex_parts(mc);
    if (parts.size() < 2) return 0;
    SphereGrid kept = part_grid(mc, parts[0], diag);
    std::vector<int> kept_vertices = parts[0];
    int limbs = 0;
    for (size_t p = 1; p < parts.size(); ++p) {
        const std::vector<int>& part = parts[p];
        if (static_cast<int>(part.size()) < o.min_part_vertices) break;  // sorted by size: the rest is noise too
        if (part_extent(mc, part) < o.limb_extent_factor * part_max_radius(mc, part)) continue;
        PartSamples ps = part_samples(mc, part, samples, kept);
        if (std::none_of(ps.gap.begin(), ps.gap.end(), [&](const Gap& g) { return uncovered(g, o, diag); })) continue;
        const std::array<int, 2> pair = closest_pair(mc, part, kept_vertices);
        const int root = pair[0], anchor = pair[1];
        if (root < 0 ||
            !segment_inside(query, mc.centre[static_cast<size_t>(root)], mc.radius[static_cast<size_t>(root)],
                            mc.centre[static_cast<size_t>(anchor)], mc.radius[static_cast<size_t>(anchor)], 0.25))
            continue;
        int part_branches = 0;
        const std::vector<std::array<int, 2>> edges = limb_tree(mc, part, root, ps, samples, o, diag, part_branches);
        const double width = tree_width(mc, part, edges, root);
        if (width > o.limb_width_factor) continue;
        branches += part_branches;
        keep_tree_of_part(mc, part, edges, root, anchor);
        for (int v : part)
            if (mc.alive[static_cast<size_t>(v)]) {
                grid_insert(kept, mc, v);
                kept_vertices.push_back(v);
            }
        ++limbs;
    }
    return limbs;
}

// Covering parts (docs/skeletons.md, "Parts that cover the shape"): the angle filter cuts the inner Voronoi complex
// where a part's medial axis meets another's (a fuselage's axis and a wing's sheet, the two loops of a double torus),
// and keeping only the largest part loses the others whole. In decreasing size, a part of at least min_part_vertices
// vertices whose spheres touch at least cover_fraction x all samples that the kept spheres (the largest part and the
// parts kept before) leave uncovered (limb_gap, limb_radius_factor) is kept whole and joined to the kept vertex
// closest to it by one curve edge, when that segment stays inside (clearance 0.25 x radius). One edge per part: the
// homotopy type is the disjoint union's plus a tree. Returns the number of parts kept.
int keep_covering_parts(MedialComplex& mc, const std::vector<Vec3>& samples, const SurfaceQuery& query,
                        const MedialAxisOptions& o, double diag) {
    if (o.cover_fraction <= 0) return 0;
    const std::vector<std::vector<int>> parts = complex_parts(mc);
    if (parts.size() < 2) return 0;
    SphereGrid kept = part_grid(mc, parts[0], diag);
    std::vector<int> kept_vertices = parts[0];
    const double needed = o.cover_fraction * static_cast<double>(samples.size());
    int joins = 0;
    for (size_t p = 1; p < parts.size(); ++p) {
        const std::vector<int>& part = parts[p];
        if (static_cast<int>(part.size()) < o.min_part_vertices) break;  // sorted by size: the rest is noise too
        const PartSamples ps = part_samples(mc, part, samples, kept);
        const auto covers =
            std::count_if(ps.gap.begin(), ps.gap.end(), [&](const Gap& g) { return uncovered(g, o, diag); });
        if (static_cast<double>(covers) < needed) continue;
        const std::array<int, 2> pair = closest_pair(mc, part, kept_vertices);
        const int a = pair[0], b = pair[1];
        if (a < 0 || !segment_inside(query, mc.centre[static_cast<size_t>(a)], mc.radius[static_cast<size_t>(a)],
                                     mc.centre[static_cast<size_t>(b)], mc.radius[static_cast<size_t>(b)], 0.25))
            continue;
        insert_sorted(mc.neighbours[static_cast<size_t>(a)], b);
        insert_sorted(mc.neighbours[static_cast<size_t>(b)], a);
        for (int v : part) grid_insert(kept, mc, v);
        kept_vertices.insert(kept_vertices.end(), part.begin(), part.end());
        ++joins;
    }
    return joins;
}

// After the erosion (keep_topology): the triangle parts (vertices joined through triangles) whose extent (bounding-box
// diagonal of their centres) is at least extent_factor x their largest radius are kept (sheets and tube bundles; the
// small islands of wide faces at corners go), joined by the shortest curve paths (Dijkstra, edge length; free inside a
// kept part) that link each kept part to the largest one, nearest first. Every other curve edge and triangle goes:
// the curve debris the inner Voronoi complex leaves near the surface (cycles around its own holes, spurs to corners).
// Returns the number of kept parts.
int keep_parts_and_paths(MedialComplex& mc, double extent_factor) {
    const int nv = static_cast<int>(mc.centre.size());
    UnionFind uf(nv);
    std::vector<char> in_triangle(static_cast<size_t>(nv), 0);
    for (size_t t = 0; t < mc.triangles.size(); ++t)
        if (mc.triangle_alive[t]) {
            for (int v : mc.triangles[t]) in_triangle[static_cast<size_t>(v)] = 1;
            uf.unite(mc.triangles[t][0], mc.triangles[t][1]);
            uf.unite(mc.triangles[t][0], mc.triangles[t][2]);
        }
    std::map<int, std::vector<int>> parts;
    for (int v = 0; v < nv; ++v)
        if (mc.alive[static_cast<size_t>(v)] && in_triangle[static_cast<size_t>(v)]) parts[uf.find(v)].push_back(v);
    std::vector<std::vector<int>> kept_parts;
    for (const auto& [root, members] : parts) {
        Vec3 lo = mc.centre[static_cast<size_t>(members[0])], hi = lo;
        double rmax = 0;
        for (int v : members) {
            const Vec3& c = mc.centre[static_cast<size_t>(v)];
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], c[k]);
                hi[k] = std::max(hi[k], c[k]);
            }
            rmax = std::max(rmax, mc.radius[static_cast<size_t>(v)]);
        }
        if (distance(lo, hi) >= extent_factor * rmax) kept_parts.push_back(members);
    }
    if (kept_parts.empty()) return 0;
    std::stable_sort(kept_parts.begin(), kept_parts.end(),
                     [](const std::vector<int>& x, const std::vector<int>& y) { return x.size() > y.size(); });
    std::vector<int> part_of(static_cast<size_t>(nv), -1);
    for (size_t p = 0; p < kept_parts.size(); ++p)
        for (int v : kept_parts[p]) part_of[static_cast<size_t>(v)] = static_cast<int>(p);
    // Edge weights: 0 between two vertices of one kept part, else the length.
    auto weight = [&](int a, int b) {
        const int pa = part_of[static_cast<size_t>(a)];
        return pa >= 0 && pa == part_of[static_cast<size_t>(b)]
                   ? 0.0
                   : distance(mc.centre[static_cast<size_t>(a)], mc.centre[static_cast<size_t>(b)]);
    };
    std::set<std::array<int, 2>> kept_edges;
    std::vector<char> connected(kept_parts.size(), 0);
    connected[0] = 1;
    std::vector<int> sources = kept_parts[0];
    for (size_t round = 1; round < kept_parts.size(); ++round) {
        std::vector<double> dist(static_cast<size_t>(nv), std::numeric_limits<double>::infinity());
        std::vector<int> from(static_cast<size_t>(nv), -1);
        using Item = std::pair<double, int>;
        std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
        for (int v : sources) {
            dist[static_cast<size_t>(v)] = 0;
            heap.push({0.0, v});
        }
        int reached = -1;
        while (!heap.empty()) {
            const auto [d, v] = heap.top();
            heap.pop();
            if (d > dist[static_cast<size_t>(v)]) continue;
            const int pv = part_of[static_cast<size_t>(v)];
            if (pv >= 0 && !connected[static_cast<size_t>(pv)]) {
                reached = v;
                break;
            }
            for (int n : mc.neighbours[static_cast<size_t>(v)]) {
                const double nd = d + weight(v, n);
                if (nd < dist[static_cast<size_t>(n)]) {
                    dist[static_cast<size_t>(n)] = nd;
                    from[static_cast<size_t>(n)] = v;
                    heap.push({nd, n});
                }
            }
        }
        if (reached < 0) break;  // the rest is not reachable: keep_largest_component drops it
        for (int v = reached; from[static_cast<size_t>(v)] >= 0; v = from[static_cast<size_t>(v)]) {
            const int u = from[static_cast<size_t>(v)];
            if (weight(u, v) > 0) kept_edges.insert({std::min(u, v), std::max(u, v)});
        }
        const int p = part_of[static_cast<size_t>(reached)];
        connected[static_cast<size_t>(p)] = 1;
        sources.insert(sources.end(), kept_parts[static_cast<size_t>(p)].begin(),
                       kept_parts[static_cast<size_t>(p)].end());
        for (int v = reached; from[static_cast<size_t>(v)] >= 0; v = from[static_cast<size_t>(v)]) sources.push_back(v);
    }
    // Rebuild: triangles of connected parts, their sides and the kept path edges.
    std::vector<std::vector<int>> neighbours(static_cast<size_t>(nv));
    for (size_t t = 0; t < mc.triangles.size(); ++t) {
        if (!mc.triangle_alive[t]) continue;
        const int p = part_of[static_cast<size_t>(mc.triangles[t][0])];
        if (p < 0 || !connected[static_cast<size_t>(p)]) {
            mc.triangle_alive[t] = 0;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const int a = mc.triangles[t][static_cast<size_t>(k)],
                      b = mc.triangles[t][static_cast<size_t>((k + 1) % 3)];
            neighbours[static_cast<size_t>(a)].push_back(b);
            neighbours[static_cast<size_t>(b)].push_back(a);
        }
    }
    for (const std::array<int, 2>& e : kept_edges) {
        neighbours[static_cast<size_t>(e[0])].push_back(e[1]);
        neighbours[static_cast<size_t>(e[1])].push_back(e[0]);
    }
    for (int v = 0; v < nv; ++v) {
        std::vector<int>& n = neighbours[static_cast<size_t>(v)];
        std::sort(n.begin(), n.end());
        n.erase(std::unique(n.begin(), n.end()), n.end());
        if (n.empty()) mc.alive[static_cast<size_t>(v)] = 0;
        std::vector<int> tris;
        for (int t : mc.vertex_triangles[static_cast<size_t>(v)])
            if (mc.triangle_alive[static_cast<size_t>(t)]) tris.push_back(t);
        mc.vertex_triangles[static_cast<size_t>(v)] = std::move(tris);
    }
    mc.neighbours = std::move(neighbours);
    return static_cast<int>(std::count(connected.begin(), connected.end(), 1));
}

// Keeps only the connected component with the most vertices (ties: the one with the lowest vertex id).
void keep_largest_component(MedialComplex& mc) {
    const int nv = static_cast<int>(mc.centre.size());
    UnionFind uf(nv);
    for (int v = 0; v < nv; ++v)
        if (mc.alive[static_cast<size_t>(v)])
            for (int n : mc.neighbours[static_cast<size_t>(v)]) uf.unite(v, n);
    std::vector<int> size(static_cast<size_t>(nv), 0);
    for (int v = 0; v < nv; ++v)
        if (mc.alive[static_cast<size_t>(v)]) ++size[static_cast<size_t>(uf.find(v))];
    int best = -1;
    for (int v = 0; v < nv; ++v)
        if (mc.alive[static_cast<size_t>(v)] &&
            (best < 0 || size[static_cast<size_t>(uf.find(v))] > size[static_cast<size_t>(best)]))
            best = uf.find(v);
    for (int v = 0; v < nv; ++v)
        if (mc.alive[static_cast<size_t>(v)] && uf.find(v) != best) mc.alive[static_cast<size_t>(v)] = 0;
    for (size_t t = 0; t < mc.triangles.size(); ++t)
        if (mc.triangle_alive[t] && !mc.alive[static_cast<size_t>(mc.triangles[t][0])]) mc.triangle_alive[t] = 0;
}

// ---------------------------------------------------------------- edge collapse

struct Candidate {
    double cost;
    int a, b;
    int version_a, version_b;
    std::array<double, 4> x;
    double rms = 0;  // sqrt(cost / planes): the merged sphere's root-mean-square distance to its tangent planes
    bool operator>(const Candidate& o) const { return std::tie(cost, a, b) > std::tie(o.cost, o.a, o.b); }
};

// Whether a queued collapse no longer applies: an end collapsed away, or changed since the candidate was made.
bool stale(const MedialComplex& mc, const Candidate& c) {
    const auto a = static_cast<size_t>(c.a), b = static_cast<size_t>(c.b);
    return !mc.alive[a] || !mc.alive[b] || c.version_a != mc.version[a] || c.version_b != mc.version[b];
}

Candidate make_candidate(const MedialComplex& mc, int a, int b) {
    if (a > b) std::swap(a, b);
    SphereQuadric q = mc.quadric[static_cast<size_t>(a)];
    q += mc.quadric[static_cast<size_t>(b)];
    const Vec3& ca = mc.centre[static_cast<size_t>(a)];
    const Vec3& cb = mc.centre[static_cast<size_t>(b)];
    const double ra = mc.radius[static_cast<size_t>(a)], rb = mc.radius[static_cast<size_t>(b)];
    std::array<double, 4> x{};
    const std::array<double, 4> mid = {0.5 * (ca.x + cb.x), 0.5 * (ca.y + cb.y), 0.5 * (ca.z + cb.z), 0.5 * (ra + rb)};
    if (!q.minimize(x) || x[3] <= 0.05 * std::min(ra, rb)) {
        // Fall back to the best of the two ends and the midpoint.
        x = mid;
        for (const std::array<double, 4>& y :
             {std::array<double, 4>{ca.x, ca.y, ca.z, ra}, std::array<double, 4>{cb.x, cb.y, cb.z, rb}})
            if (q.eval(y) < q.eval(x)) x = y;
    }
    const double cost = q.eval(x);
    const double rms = q.A[15] > 0 ? std::sqrt(cost / q.A[15]) : 0;  // A[15]: the planes' count (+ point weights)
    return {cost, a, b, mc.version[static_cast<size_t>(a)], mc.version[static_cast<size_t>(b)], x, rms};
}

// Link condition for collapsing edge ab in a 2-complex: the common neighbours of a and b are exactly the third vertices
// of the triangles on ab, and no two triangles acd, bcd exist. Then the collapse keeps the homotopy type.
bool link_condition(const MedialComplex& mc, int a, int b) {
    std::vector<int> common;
    std::set_intersection(mc.neighbours[static_cast<size_t>(a)].begin(), mc.neighbours[static_cast<size_t>(a)].end(),
                          mc.neighbours[static_cast<size_t>(b)].begin(), mc.neighbours[static_cast<size_t>(b)].end(),
                          std::back_inserter(common));
    std::vector<int> apex;
    std::vector<std::array<int, 2>> opposite_a, opposite_b;
    for (int t : mc.vertex_triangles[static_cast<size_t>(a)]) {
        if (!mc.triangle_alive[static_cast<size_t>(t)]) continue;
        const std::array<int, 3>& tri = mc.triangles[static_cast<size_t>(t)];
        if (contains(tri, b)) {
            for (int v : tri)
                if (v != a && v != b) apex.push_back(v);
        } else {
            std::array<int, 2> e{};
            int k = 0;
            for (int v : tri)
                if (v != a) e[static_cast<size_t>(k++)] = v;
            opposite_a.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
        }
    }
    std::sort(apex.begin(), apex.end());
    apex.erase(std::unique(apex.begin(), apex.end()), apex.end());
    if (apex != common) return false;
    for (int t : mc.vertex_triangles[static_cast<size_t>(b)]) {
        if (!mc.triangle_alive[static_cast<size_t>(t)]) continue;
        const std::array<int, 3>& tri = mc.triangles[static_cast<size_t>(t)];
        if (contains(tri, a)) continue;
        std::array<int, 2> e{};
        int k = 0;
        for (int v : tri)
            if (v != b) e[static_cast<size_t>(k++)] = v;
        opposite_b.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
    }
    std::sort(opposite_a.begin(), opposite_a.end());
    std::sort(opposite_b.begin(), opposite_b.end());
    std::vector<std::array<int, 2>> both;
    std::set_intersection(opposite_a.begin(), opposite_a.end(), opposite_b.begin(), opposite_b.end(),
                          std::back_inserter(both));
    return both.empty();
}

// No triangle of a or b (other than those on ab) turns by more than max_fold when a and b move to x.
bool no_fold(const MedialComplex& mc, int a, int b, const Vec3& x, double cos_max_fold) {
    for (int v : {a, b})
        for (int t : mc.vertex_triangles[static_cast<size_t>(v)]) {
            if (!mc.triangle_alive[static_cast<size_t>(t)]) continue;
            const std::array<int, 3>& tri = mc.triangles[static_cast<size_t>(t)];
            if (contains(tri, a) && contains(tri, b)) continue;
            std::array<Vec3, 3> p{}, q{};
            for (size_t k = 0; k < 3; ++k) {
                p[k] = mc.centre[static_cast<size_t>(tri[k])];
                q[k] = (tri[k] == a || tri[k] == b) ? x : p[k];
            }
            const Vec3 n0 = cross(p[1] - p[0], p[2] - p[0]);
            const Vec3 n1 = cross(q[1] - q[0], q[2] - q[0]);
            const double l0 = norm(n0), l1 = norm(n1);
            if (l0 <= 0 || l1 <= 0) continue;  // degenerate before or after: no direction to keep
            if (dot(n0, n1) < cos_max_fold * l0 * l1) return false;
        }
    return true;
}

// Every edge of the sphere the collapse of ab makes (x, to the other neighbours of a and b) is at most ratio x the
// smaller radius of its two ends.
bool edges_within(const MedialComplex& mc, const Candidate& cand, double ratio) {
    const Vec3 x{cand.x[0], cand.x[1], cand.x[2]};
    for (int v : {cand.a, cand.b})
        for (int n : mc.neighbours[static_cast<size_t>(v)]) {
            if (n == cand.a || n == cand.b) continue;
            const double r = std::min(cand.x[3], mc.radius[static_cast<size_t>(n)]);
            if (distance(x, mc.centre[static_cast<size_t>(n)]) > ratio * r) return false;
        }
    return true;
}

void collapse(MedialComplex& mc, const Candidate& cand) {
    const int a = cand.a, b = cand.b;
    mc.centre[static_cast<size_t>(a)] = {cand.x[0], cand.x[1], cand.x[2]};
    mc.radius[static_cast<size_t>(a)] = cand.x[3];
    mc.quadric[static_cast<size_t>(a)] += mc.quadric[static_cast<size_t>(b)];
    mc.alive[static_cast<size_t>(b)] = 0;
    ++mc.version[static_cast<size_t>(a)];
    ++mc.version[static_cast<size_t>(b)];
    std::vector<int>& ta = mc.vertex_triangles[static_cast<size_t>(a)];
    for (int t : mc.vertex_triangles[static_cast<size_t>(b)]) {
        if (!mc.triangle_alive[static_cast<size_t>(t)]) continue;
        std::array<int, 3>& tri = mc.triangles[static_cast<size_t>(t)];
        if (contains(tri, a)) {
            mc.triangle_alive[static_cast<size_t>(t)] = 0;
            continue;
        }
        for (int& v : tri)
            if (v == b) v = a;
        ta.push_back(t);
    }
    std::vector<int> kept;
    for (int t : ta)
        if (mc.triangle_alive[static_cast<size_t>(t)]) kept.push_back(t);
    std::sort(kept.begin(), kept.end());
    kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
    ta = std::move(kept);
    mc.vertex_triangles[static_cast<size_t>(b)].clear();
    for (int n : mc.neighbours[static_cast<size_t>(b)]) {
        erase_sorted(mc.neighbours[static_cast<size_t>(n)], b);
        if (n != a) {
            insert_sorted(mc.neighbours[static_cast<size_t>(n)], a);
            insert_sorted(mc.neighbours[static_cast<size_t>(a)], n);
        }
    }
    mc.neighbours[static_cast<size_t>(b)].clear();
}

// ab is shorter than ratio x the smaller radius of a and b.
bool short_edge(const MedialComplex& mc, int a, int b, double ratio) {
    const double r = std::min(mc.radius[static_cast<size_t>(a)], mc.radius[static_cast<size_t>(b)]);
    return distance(mc.centre[static_cast<size_t>(a)], mc.centre[static_cast<size_t>(b)]) < ratio * r;
}

// Smallest height of triangle p over the mean of radii r (0 when degenerate).
double height_over_radius(const std::array<Vec3, 3>& p, const std::array<double, 3>& r) {
    const double area2 = norm(cross(p[1] - p[0], p[2] - p[0]));
    const double longest = std::max({distance(p[0], p[1]), distance(p[1], p[2]), distance(p[2], p[0])});
    const double mean_r = (r[0] + r[1] + r[2]) / 3.0;
    return longest > 0 && mean_r > 0 ? area2 / longest / mean_r : 0.0;
}

// No triangle of a or b (other than those on ab) that is a sheet triangle (smallest height >= width x mean radius)
// stops being one or turns by more than the fold limit when a and b merge into the candidate's sphere. Thin triangles
// (the strips a simplified tube leaves, curves after step 5) may turn and collapse freely.
bool keeps_sheet_triangles(const MedialComplex& mc, const Candidate& cand, double width, double cos_fold) {
    const Vec3 x{cand.x[0], cand.x[1], cand.x[2]};
    for (int v : {cand.a, cand.b})
        for (int t : mc.vertex_triangles[static_cast<size_t>(v)]) {
            if (!mc.triangle_alive[static_cast<size_t>(t)]) continue;
            const std::array<int, 3>& tri = mc.triangles[static_cast<size_t>(t)];
            if (contains(tri, cand.a) && contains(tri, cand.b)) continue;
            std::array<Vec3, 3> p{}, q{};
            std::array<double, 3> rp{}, rq{};
            for (size_t k = 0; k < 3; ++k) {
                const bool moved = tri[k] == cand.a || tri[k] == cand.b;
                p[k] = mc.centre[static_cast<size_t>(tri[k])];
                rp[k] = mc.radius[static_cast<size_t>(tri[k])];
                q[k] = moved ? x : p[k];
                rq[k] = moved ? cand.x[3] : rp[k];
            }
            if (height_over_radius(p, rp) < width) continue;
            if (height_over_radius(q, rq) < width) return false;
            const Vec3 n0 = cross(p[1] - p[0], p[2] - p[0]);
            const Vec3 n1 = cross(q[1] - q[0], q[2] - q[0]);
            if (dot(n0, n1) < cos_fold * norm(n0) * norm(n1)) return false;
        }
    return true;
}

// The second stop of simplify (min_edge_radius): collapse, cheapest first, the edges shorter than ratio x the smaller
// radius of their ends (link condition and fold limit as before) until none is left that can go.
int collapse_short_edges(MedialComplex& mc, double ratio, double cos_fold, double sheet_width) {
    if (ratio <= 0) return 0;
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap;
    for (size_t v = 0; v < mc.centre.size(); ++v) {
        if (!mc.alive[v]) continue;
        for (int n : mc.neighbours[v])
            if (static_cast<int>(v) < n && short_edge(mc, static_cast<int>(v), n, ratio))
                heap.push(make_candidate(mc, static_cast<int>(v), n));
    }
    int collapses = 0;
    while (!heap.empty()) {
        const Candidate cand = heap.top();
        heap.pop();
        if (stale(mc, cand)) continue;
        if (!link_condition(mc, cand.a, cand.b)) continue;
        if (!keeps_sheet_triangles(mc, cand, sheet_width, cos_fold)) continue;
        collapse(mc, cand);
        ++collapses;
        // The merged sphere's short edges, and those of its neighbours (a refused collapse may pass now).
        for (int n : mc.neighbours[static_cast<size_t>(cand.a)])
            for (int m : mc.neighbours[static_cast<size_t>(n)])
                if (short_edge(mc, n, m, ratio)) heap.push(make_candidate(mc, n, m));
    }
    return collapses;
}

int simplify(MedialComplex& mc, const MedialAxisOptions& o, double diag) {
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap;
    int alive = 0;
    for (size_t v = 0; v < mc.centre.size(); ++v) {
        if (!mc.alive[v]) continue;
        ++alive;
        for (int n : mc.neighbours[v])
            if (static_cast<int>(v) < n) heap.push(make_candidate(mc, static_cast<int>(v), n));
    }
    const double tolerance2 = (o.error_tolerance * diag) * (o.error_tolerance * diag);
    const double cos_fold = std::cos(o.max_fold_deg * kPi / 180.0);
    int collapses = 0;
    const bool by_resolution = o.max_edge_radius > 0 || o.max_relative_error > 0;
    while (!heap.empty() && (by_resolution || alive > o.target_vertices)) {
        const Candidate cand = heap.top();
        heap.pop();
        if (stale(mc, cand)) continue;
        if (!by_resolution && o.error_tolerance > 0 && cand.cost > tolerance2 && alive <= o.max_vertices) break;
        if (o.max_edge_radius > 0 && !edges_within(mc, cand, o.max_edge_radius)) continue;
        if (o.max_relative_error > 0 && cand.rms > o.max_relative_error * cand.x[3]) continue;
        if (!link_condition(mc, cand.a, cand.b)) continue;
        if (!no_fold(mc, cand.a, cand.b, {cand.x[0], cand.x[1], cand.x[2]}, cos_fold)) continue;
        collapse(mc, cand);
        --alive;
        ++collapses;
        for (int n : mc.neighbours[static_cast<size_t>(cand.a)]) heap.push(make_candidate(mc, cand.a, n));
        // By resolution, a collapse refused before may pass now that a neighbour moved: the edges of the merged
        // sphere's neighbours are queued again (a count stop never refuses by position, so it needs none).
        if (by_resolution)
            for (int n : mc.neighbours[static_cast<size_t>(cand.a)])
                for (int m : mc.neighbours[static_cast<size_t>(n)])
                    if (m != cand.a) heap.push(make_candidate(mc, n, m));
    }
    return collapses + collapse_short_edges(mc, o.min_edge_radius, cos_fold, o.sheet_width_factor);
}

// ---------------------------------------------------------------- curves and sheets

struct SmallComplex {
    std::vector<Vec3> centre;
    std::vector<double> radius;
    std::set<std::array<int, 2>> edges;  // a < b
    std::vector<std::array<int, 3>> triangles;
    std::vector<char> triangle_alive;
};

SmallComplex compact(const MedialComplex& mc) {
    SmallComplex s;
    std::vector<int> id(mc.centre.size(), -1);
    for (size_t v = 0; v < mc.centre.size(); ++v)
        if (mc.alive[v]) {
            id[v] = static_cast<int>(s.centre.size());
            s.centre.push_back(mc.centre[v]);
            s.radius.push_back(mc.radius[v]);
        }
    for (size_t v = 0; v < mc.centre.size(); ++v)
        if (mc.alive[v])
            for (int n : mc.neighbours[v])
                if (id[static_cast<size_t>(n)] >= 0 && static_cast<int>(v) < n)
                    s.edges.insert(
                        {std::min(id[v], id[static_cast<size_t>(n)]), std::max(id[v], id[static_cast<size_t>(n)])});
    for (size_t t = 0; t < mc.triangles.size(); ++t)
        if (mc.triangle_alive[t]) {
            const std::array<int, 3>& tri = mc.triangles[t];
            s.triangles.push_back(
                {id[static_cast<size_t>(tri[0])], id[static_cast<size_t>(tri[1])], id[static_cast<size_t>(tri[2])]});
        }
    s.triangle_alive.assign(s.triangles.size(), 1);
    return s;
}

std::array<int, 2> side(const std::array<int, 3>& t, int k) {
    const int a = t[static_cast<size_t>(k)], b = t[static_cast<size_t>((k + 1) % 3)];
    return {std::min(a, b), std::max(a, b)};
}

double triangle_area(const SmallComplex& s, const std::array<int, 3>& t) {
    const Vec3& a = s.centre[static_cast<size_t>(t[0])];
    return 0.5 * norm(cross(s.centre[static_cast<size_t>(t[1])] - a, s.centre[static_cast<size_t>(t[2])] - a));
}

bool is_wide(const SmallComplex& s, const std::array<int, 3>& t, double factor) {
    double longest = 0, r = 0;
    for (int k = 0; k < 3; ++k) {
        const std::array<int, 2> e = side(t, k);
        longest = std::max(longest, distance(s.centre[static_cast<size_t>(e[0])], s.centre[static_cast<size_t>(e[1])]));
        r += s.radius[static_cast<size_t>(t[static_cast<size_t>(k)])] / 3;
    }
    return longest > 0 && 2 * triangle_area(s, t) / longest >= factor * r;
}

// Thin (and lone) triangles with a free side go with their longest free side (elementary collapses) until none is left.
int remove_thin_triangles(SmallComplex& s, double factor) {
    int removed = 0;
    for (bool changed = true; changed;) {
        changed = false;
        std::map<std::array<int, 2>, int> side_count;
        for (size_t t = 0; t < s.triangles.size(); ++t)
            if (s.triangle_alive[t])
                for (int k = 0; k < 3; ++k) ++side_count[side(s.triangles[t], k)];
        for (size_t t = 0; t < s.triangles.size(); ++t) {
            if (!s.triangle_alive[t]) continue;
            // A lone triangle (no side shared) is no sheet either, however wide (as in import_medial_mesh).
            const bool lone = side_count[side(s.triangles[t], 0)] == 1 && side_count[side(s.triangles[t], 1)] == 1 &&
                              side_count[side(s.triangles[t], 2)] == 1;
            if (!lone && is_wide(s, s.triangles[t], factor)) continue;
            int best = -1;
            double best_len = -1;
            for (int k = 0; k < 3; ++k) {
                const std::array<int, 2> e = side(s.triangles[t], k);
                if (side_count[e] != 1) continue;
                const double len = distance(s.centre[static_cast<size_t>(e[0])], s.centre[static_cast<size_t>(e[1])]);
                if (len > best_len) {
                    best_len = len;
                    best = k;
                }
            }
            if (best < 0) continue;
            const std::array<int, 2> e = side(s.triangles[t], best);
            s.triangle_alive[t] = 0;
            s.edges.erase(e);
            for (int k = 0; k < 3; ++k) --side_count[side(s.triangles[t], k)];
            ++removed;
            changed = true;
        }
    }
    return removed;
}

// A terminal curve branch: its vertices from the tip to its node, and its length (the points' unit).
struct TerminalBranch {
    std::vector<int> chain;  // tip first, node last
    double length = 0;
};

// The branch from tip v (adj: curve neighbours) through the vertices with exactly two of them and in no triangle to
// the first other vertex, its node (the tip itself when v has no neighbour).
TerminalBranch terminal_branch(const std::vector<std::vector<int>>& adj, const std::vector<char>& in_triangle,
                               const std::vector<Vec3>& points, int v) {
    TerminalBranch b;
    b.chain = {v};
    for (int prev = -1, cur = v;;) {
        int next = -1;
        for (int n : adj[static_cast<size_t>(cur)])
            if (n != prev) next = n;
        if (next < 0) break;
        b.length += distance(points[static_cast<size_t>(cur)], points[static_cast<size_t>(next)]);
        b.chain.push_back(next);
        prev = cur;
        cur = next;
        if (adj[static_cast<size_t>(cur)].size() != 2 || in_triangle[static_cast<size_t>(cur)]) break;
    }
    return b;
}

// Terminal curve branches (from a tip: one edge, no triangle, to the first vertex that is in a triangle or not on
// exactly two edges) whose tube barely leaves the node's sphere (length + tip radius < prune_factor x node radius)
// go, repeatedly, shortest first within a pass (elementary collapses: homotopy kept). A graph that is a single path
// keeps its longest part.
int prune_tips(SmallComplex& s, std::vector<char>& vertex_alive, double prune_factor) {
    int pruned = 0;
    for (bool changed = true; changed;) {
        changed = false;
        std::vector<std::vector<int>> adj(s.centre.size());
        std::vector<char> in_triangle(s.centre.size(), 0);
        for (const std::array<int, 2>& e : s.edges) {
            adj[static_cast<size_t>(e[0])].push_back(e[1]);
            adj[static_cast<size_t>(e[1])].push_back(e[0]);
        }
        for (size_t t = 0; t < s.triangles.size(); ++t)
            if (s.triangle_alive[t])
                for (int v : s.triangles[t]) in_triangle[static_cast<size_t>(v)] = 1;
        struct Branch {
            double score;
            std::vector<int> chain;  // tip first, node last
        };
        std::vector<Branch> branches;
        for (size_t v = 0; v < s.centre.size(); ++v) {
            if (!vertex_alive[v] || adj[v].size() != 1 || in_triangle[v]) continue;
            TerminalBranch b = terminal_branch(adj, in_triangle, s.centre, static_cast<int>(v));
            const int node = b.chain.back();
            if (adj[static_cast<size_t>(node)].size() < 2 && !in_triangle[static_cast<size_t>(node)])
                continue;  // a path
            if (b.length + s.radius[v] < prune_factor * s.radius[static_cast<size_t>(node)])
                branches.push_back({b.length, std::move(b.chain)});
        }
        std::sort(branches.begin(), branches.end(), [](const Branch& x, const Branch& y) {
            return std::tie(x.score, x.chain) < std::tie(y.score, y.chain);
        });
        if (!branches.empty()) {
            const std::vector<int>& chain = branches.front().chain;
            for (size_t k = 0; k + 1 < chain.size(); ++k) {
                s.edges.erase({std::min(chain[k], chain[k + 1]), std::max(chain[k], chain[k + 1])});
                vertex_alive[static_cast<size_t>(chain[k])] = 0;
            }
            ++pruned;
            changed = true;
        }
    }
    return pruned;
}

// Curve edges (in no triangle) shorter than min_length are contracted to their first end when the two ends have no
// common neighbour (then the contraction keeps the homotopy type): two spheres the simplification put at one place.
int merge_short_curve_edges(SmallComplex& s, std::vector<char>& vertex_alive, double min_length) {
    int merged = 0;
    for (bool changed = true; changed;) {
        changed = false;
        std::set<std::array<int, 2>> sides;
        for (size_t t = 0; t < s.triangles.size(); ++t)
            if (s.triangle_alive[t])
                for (int k = 0; k < 3; ++k) sides.insert(side(s.triangles[t], k));
        for (const std::array<int, 2>& e : s.edges) {
            if (sides.count(e) ||
                distance(s.centre[static_cast<size_t>(e[0])], s.centre[static_cast<size_t>(e[1])]) >= min_length)
                continue;
            std::set<int> na, nb;
            for (const std::array<int, 2>& f : s.edges) {
                if (f[0] == e[0] || f[1] == e[0]) na.insert(f[0] == e[0] ? f[1] : f[0]);
                if (f[0] == e[1] || f[1] == e[1]) nb.insert(f[0] == e[1] ? f[1] : f[0]);
            }
            bool common = false;
            for (int n : na)
                if (nb.count(n)) common = true;
            if (common) continue;
            const int keep = e[0], gone = e[1];
            std::set<std::array<int, 2>> edges;
            for (const std::array<int, 2>& f : s.edges) {
                if (f == e) continue;
                const int a = f[0] == gone ? keep : f[0], b = f[1] == gone ? keep : f[1];
                edges.insert({std::min(a, b), std::max(a, b)});
            }
            s.edges = std::move(edges);
            for (size_t t = 0; t < s.triangles.size(); ++t)
                for (int& v : s.triangles[t])
                    if (v == gone) v = keep;
            vertex_alive[static_cast<size_t>(gone)] = 0;
            ++merged;
            changed = true;
            break;
        }
    }
    return merged;
}

// Canonical output: live vertices sorted by (x, y, z, r), edges and faces sorted.
Skeleton to_medial_mesh(const SmallComplex& s, const std::vector<char>& vertex_alive, double min_radius) {
    std::vector<int> order;
    for (size_t v = 0; v < s.centre.size(); ++v)
        if (vertex_alive[v]) order.push_back(static_cast<int>(v));
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        const Vec3& p = s.centre[static_cast<size_t>(a)];
        const Vec3& q = s.centre[static_cast<size_t>(b)];
        return std::tie(p.x, p.y, p.z, s.radius[static_cast<size_t>(a)], a) <
               std::tie(q.x, q.y, q.z, s.radius[static_cast<size_t>(b)], b);
    });
    std::vector<int> id(s.centre.size(), -1);
    Skeleton m;
    for (int v : order) {
        id[static_cast<size_t>(v)] = static_cast<int>(m.points.size());
        m.points.push_back(s.centre[static_cast<size_t>(v)]);
        m.radii.push_back(std::max(min_radius, s.radius[static_cast<size_t>(v)]));
    }
    for (const std::array<int, 2>& e : s.edges) {
        const int a = id[static_cast<size_t>(e[0])], b = id[static_cast<size_t>(e[1])];
        m.edges.push_back({std::min(a, b), std::max(a, b)});
    }
    std::sort(m.edges.begin(), m.edges.end());
    std::vector<std::array<int, 3>> faces;
    for (size_t t = 0; t < s.triangles.size(); ++t)
        if (s.triangle_alive[t]) {
            std::array<int, 3> f = {id[static_cast<size_t>(s.triangles[t][0])],
                                    id[static_cast<size_t>(s.triangles[t][1])],
                                    id[static_cast<size_t>(s.triangles[t][2])]};
            std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
            faces.push_back(f);
        }
    std::sort(faces.begin(), faces.end());
    for (const std::array<int, 3>& f : faces) m.faces.push_back({f[0], f[1], f[2]});
    return m;
}

void measure(MedialAxis& out) {
    const Skeleton& m = out.medial;
    std::set<std::array<int, 2>> face_sides;
    std::vector<char> in_triangle(m.points.size(), 0);
    UnionFind sheets(static_cast<int>(m.faces.size()));
    std::map<std::array<int, 2>, int> first_face;
    out.sheet_area = 0;
    for (size_t f = 0; f < m.faces.size(); ++f) {
        const std::vector<int>& t = m.faces[f];
        out.sheet_area += 0.5 * norm(cross(m.points[static_cast<size_t>(t[1])] - m.points[static_cast<size_t>(t[0])],
                                           m.points[static_cast<size_t>(t[2])] - m.points[static_cast<size_t>(t[0])]));
        for (size_t k = 0; k < 3; ++k) {
            in_triangle[static_cast<size_t>(t[k])] = 1;
            const int a = t[k], b = t[(k + 1) % 3];
            const std::array<int, 2> e = {std::min(a, b), std::max(a, b)};
            face_sides.insert(e);
            auto [it, fresh] = first_face.emplace(e, static_cast<int>(f));
            if (!fresh) sheets.unite(it->second, static_cast<int>(f));
        }
    }
    out.sheets = 0;
    for (size_t f = 0; f < m.faces.size(); ++f)
        if (sheets.find(static_cast<int>(f)) == static_cast<int>(f)) ++out.sheets;
    // Curve edges, and branches between nodes (vertices not on exactly two curve edges, or in a triangle).
    std::vector<std::vector<int>> curve_adj(m.points.size());
    out.curve_band_area = 0;
    for (const std::array<int, 2>& e : m.edges) {
        if (face_sides.count({std::min(e[0], e[1]), std::max(e[0], e[1])})) continue;
        curve_adj[static_cast<size_t>(e[0])].push_back(e[1]);
        curve_adj[static_cast<size_t>(e[1])].push_back(e[0]);
        out.curve_band_area += distance(m.points[static_cast<size_t>(e[0])], m.points[static_cast<size_t>(e[1])]) *
                               (m.radii[static_cast<size_t>(e[0])] + m.radii[static_cast<size_t>(e[1])]);
    }
    auto is_node = [&](int v) {
        return curve_adj[static_cast<size_t>(v)].size() != 2 || in_triangle[static_cast<size_t>(v)];
    };
    std::set<std::array<int, 2>> visited;
    out.curves = 0;
    auto walk = [&](int from, int to) {
        int prev = from, cur = to;
        visited.insert({std::min(prev, cur), std::max(prev, cur)});
        while (!is_node(cur)) {
            const std::vector<int>& adj = curve_adj[static_cast<size_t>(cur)];
            const int next = adj[0] == prev ? adj[1] : adj[0];
            if (!visited.insert({std::min(cur, next), std::max(cur, next)}).second) break;  // closed chain
            prev = cur;
            cur = next;
        }
    };
    for (int v = 0; v < static_cast<int>(m.points.size()); ++v)
        if (is_node(v))
            for (int n : curve_adj[static_cast<size_t>(v)])
                if (!visited.count({std::min(v, n), std::max(v, n)})) {
                    ++out.curves;
                    walk(v, n);
                }
    for (int v = 0; v < static_cast<int>(m.points.size()); ++v)
        for (int n : curve_adj[static_cast<size_t>(v)])
            if (!visited.count({std::min(v, n), std::max(v, n)})) {
                ++out.curves;  // a closed chain without nodes
                walk(v, n);
            }
    out.euler = euler_characteristic(m);
    const double total = out.sheet_area + out.curve_band_area;
    out.sheet_fraction = total > 0 ? out.sheet_area / total : 0;
}

// Removes the points that no edge or face uses, keeping the order of the others (and so the medial mesh's sorting).
// `used`, when given (one entry a point), marks points kept in any case.
void drop_unused_vertices(Skeleton& m, std::vector<char> used = {}) {
    const int nv = static_cast<int>(m.points.size());
    used.resize(static_cast<size_t>(nv), 0);
    for (const std::array<int, 2>& e : m.edges) used[static_cast<size_t>(e[0])] = used[static_cast<size_t>(e[1])] = 1;
    for (const std::vector<int>& f : m.faces)
        for (int v : f) used[static_cast<size_t>(v)] = 1;
    std::vector<int> id(static_cast<size_t>(nv), -1);
    Skeleton out;
    for (int v = 0; v < nv; ++v)
        if (used[static_cast<size_t>(v)]) {
            id[static_cast<size_t>(v)] = static_cast<int>(out.points.size());
            out.points.push_back(m.points[static_cast<size_t>(v)]);
            out.radii.push_back(m.radii[static_cast<size_t>(v)]);
        }
    for (const std::array<int, 2>& e : m.edges)
        out.edges.push_back({id[static_cast<size_t>(e[0])], id[static_cast<size_t>(e[1])]});
    for (const std::vector<int>& f : m.faces) {
        std::vector<int> g;
        for (int v : f) g.push_back(id[static_cast<size_t>(v)]);
        out.faces.push_back(std::move(g));
    }
    m = std::move(out);
}

}  // namespace

int remove_fringe_curves(Skeleton& m, double factor, bool node_ends, bool spare_interior) {
    const int nv = static_cast<int>(m.points.size());
    std::map<std::array<int, 2>, int> side_count;  // triangle side -> triangles on it
    std::vector<char> in_triangle(static_cast<size_t>(nv), 0), on_border(static_cast<size_t>(nv), 0);
    for (const std::vector<int>& f : m.faces)
        for (size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            ++side_count[{std::min(a, b), std::max(a, b)}];
            in_triangle[static_cast<size_t>(a)] = 1;
        }
    std::set<std::array<int, 2>> sides;
    for (const auto& [side, count] : side_count) {
        sides.insert(side);
        if (count == 1) on_border[static_cast<size_t>(side[0])] = on_border[static_cast<size_t>(side[1])] = 1;
    }
    // A chain between two interior sheet vertices (in a triangle, on no border side) is a handle, not fringe.
    auto interior = [&](int x) { return in_triangle[static_cast<size_t>(x)] && !on_border[static_cast<size_t>(x)]; };
    std::vector<std::vector<int>> curve_adj(static_cast<size_t>(nv));
    for (const std::array<int, 2>& e : m.edges)
        if (!sides.count({std::min(e[0], e[1]), std::max(e[0], e[1])})) {
            curve_adj[static_cast<size_t>(e[0])].push_back(e[1]);
            curve_adj[static_cast<size_t>(e[1])].push_back(e[0]);
        }
    for (std::vector<int>& a : curve_adj) std::sort(a.begin(), a.end());
    auto is_node = [&](int v) {
        return curve_adj[static_cast<size_t>(v)].size() != 2 || in_triangle[static_cast<size_t>(v)];
    };
    auto key = [](int a, int b) { return std::array<int, 2>{std::min(a, b), std::max(a, b)}; };
    auto near_sheet = [&](const Vec3& p, double r) {
        const double limit = factor * r;
        for (const std::vector<int>& f : m.faces) {
            const Vec3 q =
                closest_point_on_triangle(p, m.points[static_cast<size_t>(f[0])], m.points[static_cast<size_t>(f[1])],
                                          m.points[static_cast<size_t>(f[2])]);
            if (squared_norm(p - q) <= limit * limit) return true;
        }
        return false;
    };
    std::set<std::array<int, 2>> removed, visited;
    int chains = 0;
    for (int v = 0; v < nv; ++v) {
        if (!is_node(v)) continue;
        for (int n : curve_adj[static_cast<size_t>(v)]) {
            if (visited.count(key(v, n))) continue;
            std::vector<int> chain = {v, n};
            visited.insert(key(v, n));
            while (!is_node(chain.back())) {
                const std::vector<int>& a = curve_adj[static_cast<size_t>(chain.back())];
                const int next = a[0] == chain[chain.size() - 2] ? a[1] : a[0];
                if (!visited.insert(key(chain.back(), next)).second) break;
                chain.push_back(next);
            }
            // A chain end on a sheet, or (node_ends) where 3 or more curves branch: a web of chains along the sheet.
            const auto attached = [&](int x) {
                return in_triangle[static_cast<size_t>(x)] ||
                       (node_ends && curve_adj[static_cast<size_t>(x)].size() >= 3);
            };
            if (!attached(chain.front()) || !attached(chain.back())) continue;
            if (spare_interior && interior(chain.front()) && interior(chain.back())) continue;
            bool along = true;
            for (size_t k = 0; along && k + 1 < chain.size(); ++k)
                for (double t : {0.25, 0.5, 0.75}) {
                    const size_t a = static_cast<size_t>(chain[k]), b = static_cast<size_t>(chain[k + 1]);
                    if (!near_sheet(m.points[a] + (m.points[b] - m.points[a]) * t,
                                    (1 - t) * m.radii[a] + t * m.radii[b])) {
                        along = false;
                        break;
                    }
                }
            if (!along) continue;
            // The ends must stay connected without the chain (and without the chains removed before).
            UnionFind uf(nv);
            std::set<std::array<int, 2>> gone = removed;
            for (size_t k = 0; k + 1 < chain.size(); ++k) gone.insert(key(chain[k], chain[k + 1]));
            for (const std::array<int, 2>& e : m.edges)
                if (!gone.count(key(e[0], e[1]))) uf.unite(e[0], e[1]);
            if (uf.find(chain.front()) != uf.find(chain.back())) continue;
            removed = std::move(gone);
            ++chains;
        }
    }
    if (chains == 0) return 0;
    std::erase_if(m.edges, [&](const std::array<int, 2>& e) { return removed.count(key(e[0], e[1])) > 0; });
    drop_unused_vertices(m);
    return chains;
}

int prune_spurs(Skeleton& m, double prune_factor) {
    if (!(prune_factor > 0)) return 0;
    int pruned = 0;
    for (bool changed = true; changed;) {
        changed = false;
        const size_t nv = m.points.size();
        std::set<std::array<int, 2>> sides;
        std::vector<char> in_triangle(nv, 0);
        for (const std::vector<int>& f : m.faces)
            for (size_t k = 0; k < f.size(); ++k) {
                const int a = f[k], b = f[(k + 1) % f.size()];
                sides.insert({std::min(a, b), std::max(a, b)});
                in_triangle[static_cast<size_t>(a)] = 1;
            }
        std::vector<std::vector<int>> adj(nv);
        for (const std::array<int, 2>& e : m.edges)
            if (!sides.count({std::min(e[0], e[1]), std::max(e[0], e[1])})) {
                adj[static_cast<size_t>(e[0])].push_back(e[1]);
                adj[static_cast<size_t>(e[1])].push_back(e[0]);
            }
        // The shortest spur: from a tip (one curve edge, in no triangle) through plain joints to its node.
        double best_length = std::numeric_limits<double>::infinity();
        std::vector<int> best;
        for (size_t v = 0; v < nv; ++v) {
            if (adj[v].size() != 1 || in_triangle[v]) continue;
            TerminalBranch b = terminal_branch(adj, in_triangle, m.points, static_cast<int>(v));
            const size_t node = static_cast<size_t>(b.chain.back());
            if (b.chain.size() < 2 || (adj[node].size() < 2 && !in_triangle[node])) continue;  // a path or a loop
            if (!(b.length + m.radii[v] < prune_factor * m.radii[node])) continue;  // NaN radii prune nothing
            if (b.length < best_length || (b.length == best_length && b.chain < best)) {
                best_length = b.length;
                best = std::move(b.chain);
            }
        }
        if (best.empty()) break;
        std::set<std::array<int, 2>> gone;
        for (size_t k = 0; k + 1 < best.size(); ++k)
            gone.insert({std::min(best[k], best[k + 1]), std::max(best[k], best[k + 1])});
        std::erase_if(m.edges, [&](const std::array<int, 2>& e) {
            return gone.count({std::min(e[0], e[1]), std::max(e[0], e[1])}) > 0;
        });
        // Only the spur's own points go (a point alone, a component of its own, stays).
        std::vector<char> keep(nv, 1);
        for (size_t k = 0; k + 1 < best.size(); ++k) keep[static_cast<size_t>(best[k])] = 0;
        drop_unused_vertices(m, std::move(keep));
        ++pruned;
        changed = true;
    }
    return pruned;
}

MedialAxis compute_medial_axis(const TriangleMesh& surface, const MedialAxisOptions& options) {
    const SurfaceCheck check = check_surface(surface);
    if (!check.is_closed_manifold())
        throw Error(ErrorCode::InvalidInput,
                    "medial axis needs a closed, manifold, consistently oriented surface without degenerate "
                    "triangles (boundary edges " +
                        std::to_string(check.boundary_edges) + ", non-manifold edges " +
                        std::to_string(check.non_manifold_edges) + ", non-manifold vertices " +
                        std::to_string(check.non_manifold_vertices) + ", inconsistent edges " +
                        std::to_string(check.inconsistent_edges) + ", degenerate triangles " +
                        std::to_string(check.degenerate_triangles) + ")");
    if (check.components.size() != 1)
        throw Error(ErrorCode::InvalidInput, "medial axis needs a single connected surface (found " +
                                                 std::to_string(check.components.size()) + " components)");
    check_surface_for_skeleton(surface);  // degenerate geometry (flat, collapsed) never reaches CGAL's Delaunay
    const SurfaceQuery query(surface);
    MedialAxis out;
    const double diag = query.bbox_diagonal();
    out.bbox_diagonal = diag;
    const double h0 = options.sample_spacing * diag;
    double h = h0;
    // Thin parts: the thickness probed on a grid of the base spacing; extra samples where it is below
    // thickness_samples x the spacing (counted in max_samples: the spacing grows until both fit).
    const std::vector<ProbeCell> probes =
        options.thickness_samples > 0 ? probe_thickness(surface, query, h, diag) : std::vector<ProbeCell>{};
    auto extra_count = [&](double step) {
        long n = 0;
        for (const ProbeCell& c : probes) {
            const long k = refinement_grid(c, h0, step / h0, options.thickness_samples, options.max_refinement);
            n += k * k;
        }
        return n;
    };
    std::vector<std::array<int, 2>> source;
    std::vector<Vec3> samples = sample_surface(surface, h, options.max_samples, extra_count, source);
    const size_t base_samples = samples.size();
    auto is_thin = [&](const ProbeCell& c) { return c.thickness < options.thickness_samples * h0; };
    auto thin_of = [&](const ProbeCell& c) {
        return ThinSample{c.thickness,
                          refinement_spacing(c, h0, h / h0, options.thickness_samples, options.max_refinement)};
    };
    std::vector<ThinSample> thin(samples.size());
    for (const ProbeCell& c : probes)
        if (const int k = refinement_grid(c, h0, h / h0, options.thickness_samples, options.max_refinement); k > 0) {
            add_refinement_samples(c, k, samples);
            thin.resize(samples.size(), thin_of(c));
        }
    out.refinement_samples = static_cast<int>(samples.size() - base_samples);
    thin.resize(samples.size());
    if (std::any_of(probes.begin(), probes.end(), is_thin)) {
        // Base samples in thin cells: the thinnest cell holding them over the triangles they lie on (a vertex or an
        // edge sample lies on several: a reflex rim between a thin disk and its hub is thin).
        std::vector<int> first(surface.triangles.size(), -1), grid(surface.triangles.size(), 0);
        for (size_t i = 0; i < probes.size(); ++i) {
            const size_t t = static_cast<size_t>(probes[i].triangle);
            if (first[t] < 0) first[t] = static_cast<int>(i);
            grid[t] = static_cast<int>(std::lround(std::sqrt(static_cast<double>(i + 1 - first[t]))));
        }
        const std::vector<std::array<int, 2>> edges = unique_edges(surface);
        std::vector<std::vector<int>> vertex_triangles(surface.points.size());
        std::map<std::array<int, 2>, std::vector<int>> edge_triangles;
        for (size_t t = 0; t < surface.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) {
                const int a = surface.triangles[t][static_cast<size_t>(k)];
                const int b = surface.triangles[t][static_cast<size_t>((k + 1) % 3)];
                vertex_triangles[static_cast<size_t>(a)].push_back(static_cast<int>(t));
                edge_triangles[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(t));
            }
        for (size_t i = 0; i < base_samples; ++i) {
            const std::array<int, 2>& src = source[i];
            const std::vector<int> one = {src[1]};
            const std::vector<int>& triangles =
                src[0] == 0 ? vertex_triangles[static_cast<size_t>(src[1])]
                            : (src[0] == 1 ? edge_triangles[edges[static_cast<size_t>(src[1])]] : one);
            for (int t : triangles) {
                if (first[static_cast<size_t>(t)] < 0) continue;
                const ProbeCell& c = probes[static_cast<size_t>(
                    cell_at(surface, t, first[static_cast<size_t>(t)], grid[static_cast<size_t>(t)], samples[i]))];
                if (is_thin(c) && c.thickness < thin[i].thickness) thin[i] = thin_of(c);
            }
        }
    } else {
        thin.clear();
    }
    MedialComplex mc = voronoi_medial_complex(samples, thin, options.thin_separation, query, diag,
                                              options.min_angle_deg, options.keep_topology, out);
    if (mc.centre.empty())
        throw Error(ErrorCode::NumericalFailure, "medial axis: no Voronoi face passed the angle filter (" +
                                                     std::to_string(out.inner_poles) + " inner poles from " +
                                                     std::to_string(out.samples) + " samples)");
    out.joined_parts =
        join_components(mc, query, options.join_factor, options.min_part_vertices, options.join_min_extent);
    if (options.keep_topology) keep_parts_and_paths(mc, options.part_extent_factor);
    out.covering_parts = keep_covering_parts(mc, samples, query, options, diag);
    out.limbs = keep_limb_trees(mc, samples, query, options, diag, out.limb_branches);
    keep_largest_component(mc);
    out.initial_vertices = static_cast<int>(std::count(mc.alive.begin(), mc.alive.end(), 1));
    out.initial_triangles = static_cast<int>(std::count(mc.triangle_alive.begin(), mc.triangle_alive.end(), 1));
    long initial_edges = 0;
    for (size_t v = 0; v < mc.centre.size(); ++v)
        if (mc.alive[v]) initial_edges += static_cast<long>(mc.neighbours[v].size());
    out.initial_euler = out.initial_vertices - initial_edges / 2 + out.initial_triangles;
    out.collapses = simplify(mc, options, diag);
    SmallComplex s = compact(mc);
    out.thin_triangles_removed = remove_thin_triangles(s, options.sheet_width_factor);
    std::vector<char> vertex_alive(s.centre.size(), 1);
    out.pruned_tips = prune_tips(s, vertex_alive, options.prune_factor);
    merge_short_curve_edges(s, vertex_alive, 1e-4 * diag);
    out.medial = to_medial_mesh(s, vertex_alive, 1e-6 * diag);
    if (options.fringe_factor > 0)
        out.fringe_curves = remove_fringe_curves(out.medial, options.fringe_factor, options.fringe_node_ends,
                                                 options.fringe_spare_interior);
    // The fringe removal leaves the webs' stubs (a curve node of a web next to a sheet becomes a tip one short edge
    // from the sheet's border): the same spur rule once more, on the final medial mesh.
    if (options.prune_after_fringe) out.pruned_spurs = prune_spurs(out.medial, options.prune_factor);
    if (options.extend_rims) {
        const RimExtension rims = extend_rim_borders(out.medial, query, options.rim_reach_factor,
                                                     options.rim_min_radius_fraction, options.rim_max_move);
        out.rim_border_vertices = rims.border_vertices;
        out.rim_moved = rims.moved;
        out.rim_sharp = rims.sharp;
    }
    measure(out);
    return out;
}

}  // namespace mesohex
