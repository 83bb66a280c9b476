#include "mesohex/stages/virtual_branches.h"

#include "mesohex/stages/junction_cover.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mesohex {

namespace {

// Point i of n on the Fibonacci (golden-angle) spiral on the unit sphere.
Vec3 fibonacci_point(int i, int n) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = i * std::numbers::pi * (3.0 - std::sqrt(5.0));
    return {rho * std::cos(phi), rho * std::sin(phi), z};
}

double angle_deg(const Vec3& a, const Vec3& b) {
    return std::acos(std::clamp(dot(a, b), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// The Voronoi vertices of unit directions d on the sphere at most max_deg from their nearest directions: for each
// triple, the unit vector equidistant from the three (on their side), kept when no direction is nearer.
std::vector<Vec3> voronoi_vertices(const std::vector<Vec3>& d, double max_deg) {
    std::vector<Vec3> out;
    const int n = static_cast<int>(d.size());
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            for (int k = j + 1; k < n; ++k) {
                Vec3 v = cross(d[j] - d[i], d[k] - d[i]);
                if (!(norm(v) > 1e-9)) continue;
                v = normalized(v);
                if (dot(v, d[i]) < 0) v = v * -1.0;
                const double c = dot(v, d[i]);
                bool nearest = angle_deg(v, d[i]) <= max_deg;
                for (int l = 0; l < n && nearest; ++l) nearest = dot(v, d[l]) <= c + 1e-9;
                if (nearest) out.push_back(v);
            }
    return out;
}

// A pit branch at c (VirtualBranchOptions::pit_excess): appended to s when a Voronoi vertex's ray leaves the domain's
// union far enough beyond c's ball. Returns whether one was added.
bool add_pit_branch(Skeleton& s, int c, const std::vector<Vec3>& d, const Skeleton& domain,
                    const VirtualBranchOptions& o) {
    const double rc = s.radii[c];
    std::vector<RoundCone> cones{{s.points[c], s.points[c], rc, rc}};
    for (const std::array<int, 2>& e : domain.edges) {
        const Vec3 &a = domain.points[e[0]], &b = domain.points[e[1]];
        if (distance_to_segment(s.points[c], a, b) <= 3 * rc)
            cones.push_back({a, b, domain.radii[e[0]], domain.radii[e[1]]});
    }
    double best = (1 + o.pit_excess) * rc;
    Vec3 pit{};
    for (const Vec3& v : voronoi_vertices(d, o.pit_max_deg)) {
        const double t = ray_exit(cones, s.points[c], v, 0.02 * rc, 4 * rc);
        if (t >= best) best = t, pit = v;
    }
    if (pit == Vec3{}) return false;
    s.points.push_back(s.points[c] + pit * std::max(rc, best - o.pit_inset * rc));
    s.radii.push_back(rc);
    s.edges.push_back({c, static_cast<int>(s.points.size()) - 1});
    return true;
}

}  // namespace

double covering_radius_deg(const std::vector<Vec3>& dirs, int grid_points, Vec3* far) {
    double best = -1;
    Vec3 best_x = fibonacci_point(0, std::max(grid_points, 1));
    for (int i = 0; i < grid_points; ++i) {
        const Vec3 x = fibonacci_point(i, grid_points);
        double nearest = 180;
        for (const Vec3& d : dirs) nearest = std::min(nearest, angle_deg(x, d));
        if (nearest > best) best = nearest, best_x = x;
    }
    if (far) *far = best_x;
    return dirs.empty() ? 180.0 : best;
}

VirtualBranches add_virtual_branches(Skeleton& s, const VirtualBranchOptions& o, const CompatibleBlockOptions* blocks,
                                     const Skeleton* domain) {
    VirtualBranches out;
    const bool pits = o.pit_excess > 0 && domain && domain->radii.size() == domain->points.size();
    if (!o.enabled && !pits) return out;
    const int nv = static_cast<int>(s.points.size());
    std::vector<char> in_face(nv, 0);
    for (const std::vector<int>& f : s.faces)
        for (const int v : f)
            if (v >= 0 && v < nv) in_face[v] = 1;
    std::vector<std::vector<Vec3>> dirs(nv);
    for (const std::array<int, 2>& e : s.edges) {
        if (e[0] < 0 || e[1] < 0 || e[0] >= nv || e[1] >= nv) continue;
        const Vec3 d = s.points[e[1]] - s.points[e[0]];
        if (!(norm(d) > 0)) continue;
        dirs[e[0]].push_back(normalized(d));
        dirs[e[1]].push_back(normalized(d * -1.0));
    }
    for (int c = 0; c < nv; ++c) {
        const int degree = static_cast<int>(dirs[c].size());
        if (in_face[c] || degree < 3 || degree >= o.max_degree) continue;
        if (blocks && blocks->enabled && fit_cube_frame(dirs[c], *blocks).accepted) continue;
        if (pits && degree >= o.pit_min_degree && add_pit_branch(s, c, dirs[c], *domain, o)) out.at.push_back(c);
        if (!o.enabled) continue;
        std::vector<Vec3> d = dirs[c];
        Vec3 v;
        while (static_cast<int>(d.size()) < o.max_degree && covering_radius_deg(d, o.grid_points, &v) > o.max_cap_deg) {
            d.push_back(v);
            const double r = s.radii[c];
            s.points.push_back(s.points[c] + v * (o.length_factor * r));
            s.radii.push_back(r);
            s.edges.push_back({c, static_cast<int>(s.points.size()) - 1});
            out.at.push_back(c);
        }
    }
    return out;
}

}  // namespace mesohex
