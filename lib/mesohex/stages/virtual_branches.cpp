#include "mesohex/stages/virtual_branches.h"

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

VirtualBranches add_virtual_branches(Skeleton& s, const VirtualBranchOptions& o, const CompatibleBlockOptions* blocks) {
    VirtualBranches out;
    if (!o.enabled) return out;
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
