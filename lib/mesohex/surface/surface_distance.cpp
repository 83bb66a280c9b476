// Two-sided sampled Hausdorff distance. See surface_distance.h.
#include "mesohex/surface/surface_distance.h"

#include <algorithm>
#include <cmath>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

// Vertices (once each, referenced ones only) + barycentric grid points of step 1/n inside / on the edges of every
// triangle (edge points are sampled by both incident triangles; harmless). n = 1: vertices + centroids.
std::vector<Vec3> sample(const TriangleMesh& m, int n) {
    std::vector<Vec3> out;
    std::vector<char> used(m.points.size(), 0);
    for (const std::array<int, 3>& t : m.triangles)
        for (int v : t) used[static_cast<std::size_t>(v)] = 1;
    for (std::size_t v = 0; v < m.points.size(); ++v)
        if (used[v]) out.push_back(m.points[v]);
    for (const std::array<int, 3>& t : m.triangles) {
        const Vec3& a = m.points[static_cast<std::size_t>(t[0])];
        const Vec3& b = m.points[static_cast<std::size_t>(t[1])];
        const Vec3& c = m.points[static_cast<std::size_t>(t[2])];
        if (n <= 1) {
            out.push_back((a + b + c) / 3.0);
            continue;
        }
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const int k = n - i - j;
                if (i == n || j == n || k == n) continue;  // corners: already sampled
                out.push_back((static_cast<double>(i) * a + static_cast<double>(j) * b + static_cast<double>(k) * c) /
                              static_cast<double>(n));
            }
    }
    return out;
}

// Largest and mean distance over the samples (squared distances in), and where the largest is (the first sample
// attaining it: deterministic).
void max_mean(const std::vector<double>& d2, const std::vector<Vec3>& samples, double& mx, double& mean, Vec3& at) {
    mx = 0;
    double sum = 0;
    for (std::size_t i = 0; i < d2.size(); ++i) {
        const double d = std::sqrt(d2[i]);
        if (d > mx || i == 0) {
            mx = d;
            at = samples[i];
        }
        sum += d;
    }
    mean = d2.empty() ? 0.0 : sum / static_cast<double>(d2.size());
}

}  // namespace

SurfaceDistance surface_distance(const TriangleMesh& boundary, const SurfaceQuery& domain,
                                 const SurfaceDistanceOptions& options) {
    const SurfaceQuery mesh_query(boundary);  // validates indices / degenerate surfaces
    const int n = std::max(1, options.face_subdivision);
    const std::vector<Vec3> mesh_samples = sample(boundary, n);
    const std::vector<Vec3> surface_samples = sample(domain.surface(), n);
    SurfaceDistance r;
    max_mean(domain.squared_distances(mesh_samples), mesh_samples, r.mesh_to_surface_max, r.mesh_to_surface_mean,
             r.mesh_to_surface_at);
    max_mean(mesh_query.squared_distances(surface_samples), surface_samples, r.surface_to_mesh_max,
             r.surface_to_mesh_mean, r.surface_to_mesh_at);
    r.mesh_samples = static_cast<long>(mesh_samples.size());
    r.surface_samples = static_cast<long>(surface_samples.size());
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
