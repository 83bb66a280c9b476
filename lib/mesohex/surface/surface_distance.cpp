// Two-sided sampled Hausdorff distance. See surface_distance.h.
#include "mesohex/surface/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

// The samples of one side: the referenced vertices of m (once each, in index order), then per triangle the barycentric
// grid points of step 1/n inside it and on its edges, corners excluded (edge points are sampled by both incident
// triangles; harmless); n = 1: the centroid.
template <class F>
void for_triangle_samples(const TriangleMesh& m, int n, F&& f) {
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const std::array<int, 3>& tri = m.triangles[t];
        const Vec3& a = m.points[static_cast<std::size_t>(tri[0])];
        const Vec3& b = m.points[static_cast<std::size_t>(tri[1])];
        const Vec3& c = m.points[static_cast<std::size_t>(tri[2])];
        if (n <= 1) {
            f(t, (a + b + c) / 3.0);
            continue;
        }
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const int k = n - i - j;
                if (i == n || j == n || k == n) continue;  // corners: sampled as vertices
                f(t, (static_cast<double>(i) * a + static_cast<double>(j) * b + static_cast<double>(k) * c) /
                         static_cast<double>(n));
            }
    }
}

// Squared distance of every point to the surface of `query`. Points come in runs of neighbours (the samples of one
// triangle, triangles in mesh order), so each query starts from the triangle its predecessor in the block found: the
// traversal then skips most of the tree. The closest point does not depend on the hint, so neither does the result
// (nor on the blocks: the same for any thread count).
std::vector<double> chained_squared_distances(const SurfaceQuery& query, const std::vector<Vec3>& points) {
    std::vector<double> d2(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          int hint = -1;
                          for (std::size_t i = r.begin(); i < r.end(); ++i) {
                              const ClosestPoint c = query.closest(points[i], hint);
                              hint = c.triangle;
                              d2[i] = c.squared_distance;
                          }
                      });
    return d2;
}

struct Side {
    double max = 0, mean = 0;
    Vec3 at{};
    long samples = 0;
};

// Distance from the samples of m to the surface of `to`: the largest (and the first sample in sample order attaining
// it) and the mean over m's vertices. The vertices are measured first; a triangle sample s is measured only if its
// bound min over the corners v of (d(v) + |s - v|) (the distance is 1-Lipschitz) reaches the vertices' largest
// distance: a sample below it cannot be the largest. So the largest is that of every sample measured, at a fraction of
// the queries (those near the farthest places).
Side side_distance(const TriangleMesh& m, const SurfaceQuery& to, int n) {
    std::vector<int> sample_of(m.points.size(), -1);
    for (const std::array<int, 3>& t : m.triangles)
        for (int v : t) sample_of[static_cast<std::size_t>(v)] = 0;
    std::vector<Vec3> vertices;
    for (std::size_t v = 0; v < m.points.size(); ++v)
        if (sample_of[v] == 0) {
            sample_of[v] = static_cast<int>(vertices.size());
            vertices.push_back(m.points[v]);
        }
    std::vector<double> dv = chained_squared_distances(to, vertices);
    Side side;
    double sum = 0, vertex_max = 0;
    for (std::size_t i = 0; i < dv.size(); ++i) {
        dv[i] = std::sqrt(dv[i]);
        sum += dv[i];
        vertex_max = std::max(vertex_max, dv[i]);
    }
    side.mean = dv.empty() ? 0.0 : sum / static_cast<double>(dv.size());
    // A margin far above the rounding of the distances and the bound: skipping is safe, never wrong.
    const double skip_below = vertex_max * (1 - 1e-9);
    std::vector<Vec3> candidates;
    long triangle_samples = 0;
    for_triangle_samples(m, n, [&](std::size_t t, const Vec3& s) {
        ++triangle_samples;
        double bound = std::numeric_limits<double>::infinity();
        for (int v : m.triangles[t]) {
            const std::size_t vi = static_cast<std::size_t>(v);
            bound = std::min(bound, dv[static_cast<std::size_t>(sample_of[vi])] + distance(s, m.points[vi]));
        }
        if (!(bound < skip_below)) candidates.push_back(s);
    });
    const std::vector<double> dc = chained_squared_distances(to, candidates);
    side.samples = static_cast<long>(vertices.size()) + triangle_samples;
    bool first = true;
    auto take = [&](double d, const Vec3& p) {
        if (d > side.max || first) {
            side.max = d;
            side.at = p;
        }
        first = false;
    };
    for (std::size_t i = 0; i < dv.size(); ++i) take(dv[i], vertices[i]);
    for (std::size_t i = 0; i < dc.size(); ++i) take(std::sqrt(dc[i]), candidates[i]);
    return side;
}

}  // namespace

SurfaceDistance surface_distance(const TriangleMesh& boundary, const SurfaceQuery& domain,
                                 const SurfaceDistanceOptions& options) {
    const SurfaceQuery mesh_query(boundary, /*accelerate=*/false);  // validates indices / degenerate surfaces
    const int n = std::max(1, options.face_subdivision);
    SurfaceDistance r;
    const Side to_surface = side_distance(boundary, domain, n);
    const Side to_mesh = side_distance(domain.surface(), mesh_query, n);
    r.mesh_to_surface_max = to_surface.max;
    r.mesh_to_surface_mean = to_surface.mean;
    r.mesh_to_surface_at = to_surface.at;
    r.mesh_samples = to_surface.samples;
    r.surface_to_mesh_max = to_mesh.max;
    r.surface_to_mesh_mean = to_mesh.mean;
    r.surface_to_mesh_at = to_mesh.at;
    r.surface_samples = to_mesh.samples;
    r.max = std::max(r.mesh_to_surface_max, r.surface_to_mesh_max);
    r.mean = 0.5 * (r.mesh_to_surface_mean + r.surface_to_mesh_mean);
    r.diagonal = domain.bbox_diagonal();
    r.relative_max = r.diagonal > 0 ? r.max / r.diagonal : 0.0;
    r.relative_mean = r.diagonal > 0 ? r.mean / r.diagonal : 0.0;
    return r;
}

SurfaceDistance surface_distance(const QuadMesh& boundary, const SurfaceQuery& domain,
                                 const SurfaceDistanceOptions& options) {
    TriangleMesh tri;
    tri.points = boundary.points;
    tri.triangles.reserve(2 * boundary.quads.size());
    for (const std::array<int, 4>& q : boundary.quads) {
        tri.triangles.push_back({q[0], q[1], q[2]});
        tri.triangles.push_back({q[0], q[2], q[3]});
    }
    return surface_distance(tri, domain, options);
}

}  // namespace mesohex
