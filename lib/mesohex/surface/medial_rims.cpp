#include "mesohex/surface/medial_rims.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <tuple>
#include <vector>

#include "mesohex/core/vec.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex {
namespace {

constexpr int kStepsPerRadius = 20;  // march step: 1/20 of the border vertex's ball radius
constexpr int kFoldHalvings = 3;     // the moves of a triangle's vertices that turn it by more than kMaxTurnDeg are
                                     // halved up to 3 times, then undone
constexpr double kMaxTurnDeg = 30;   // degrees

using Side = std::array<int, 2>;

Side side_key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// Per vertex: its border sides' triangle-opposite vertices {u, w} (u the other end of the side, w the third vertex of
// its triangle), or empty when the vertex is no regular border vertex (not on exactly two border sides, on a side of
// three or more triangles, or on a curve edge).
std::vector<std::vector<std::array<int, 2>>> regular_border_sides(const Skeleton& m) {
    const size_t nv = m.points.size();
    std::map<Side, std::vector<int>> side_faces;
    for (size_t f = 0; f < m.faces.size(); ++f)
        for (size_t k = 0; k < m.faces[f].size(); ++k)
            side_faces[side_key(m.faces[f][k], m.faces[f][(k + 1) % m.faces[f].size()])].push_back(static_cast<int>(f));
    std::vector<char> irregular(nv, 0);
    for (const std::array<int, 2>& e : m.edges)
        if (!side_faces.count(side_key(e[0], e[1])))
            irregular[static_cast<size_t>(e[0])] = irregular[static_cast<size_t>(e[1])] = 1;  // a curve edge
    std::vector<std::vector<std::array<int, 2>>> sides(nv);
    for (const auto& [s, faces] : side_faces) {
        if (faces.size() >= 3) irregular[static_cast<size_t>(s[0])] = irregular[static_cast<size_t>(s[1])] = 1;
        if (faces.size() != 1) continue;
        const std::vector<int>& t = m.faces[static_cast<size_t>(faces[0])];
        int w = -1;
        for (int x : t)
            if (x != s[0] && x != s[1]) w = x;
        if (w < 0) continue;
        sides[static_cast<size_t>(s[0])].push_back({s[1], w});
        sides[static_cast<size_t>(s[1])].push_back({s[0], w});
    }
    for (size_t v = 0; v < nv; ++v)
        if (irregular[v] || sides[v].size() != 2) sides[v].clear();
    return sides;
}

// The outward direction at v in its sheet: the mean of its two border sides' perpendiculars pointing away from their
// triangles (zero at a spike, where they nearly cancel).
Vec3 outward_direction(const Skeleton& m, int v, const std::vector<std::array<int, 2>>& sides) {
    const Vec3& p = m.points[static_cast<size_t>(v)];
    Vec3 sum{};
    for (const std::array<int, 2>& uw : sides) {
        const Vec3 e = normalized(m.points[static_cast<size_t>(uw[0])] - p);
        const Vec3 away = p - m.points[static_cast<size_t>(uw[1])];
        sum += normalized(away - e * dot(away, e));
    }
    return norm(sum) < 0.5 ? Vec3{} : normalized(sum);
}

// How far the border vertex at p marches along t: 0 when it stays, -1 when it stays at a sharp edge ahead.
double rim_march(const SurfaceQuery& query, const Vec3& p, const Vec3& t, double reach_factor,
                 double min_radius_fraction, double max_move) {
    const double d0 = std::sqrt(query.squared_distance(p));
    if (!(d0 > 0)) return 0;
    const std::optional<RayHit> hit = query.first_hit(p, t);
    if (!hit || hit->distance <= reach_factor * d0) return 0;
    const double step = d0 / kStepsPerRadius;
    for (int i = 1; i * step <= max_move * d0 && i * step < hit->distance; ++i) {
        const double s = i * step;
        const double d = std::sqrt(query.squared_distance(p + t * s));
        if (d < min_radius_fraction * d0) return -1;  // a sharp edge ahead
        if (hit->distance - s <= reach_factor * d) return s;
    }
    return 0;
}

// The triangles with a moving vertex whose normal turns by more than kMaxTurnDeg (or that become degenerate) when
// the points go from m.points to `after`.
std::vector<int> turned_triangles(const Skeleton& m, const std::vector<Vec3>& after, const std::vector<double>& move) {
    const double cos_max = std::cos(kMaxTurnDeg * 3.14159265358979323846 / 180);
    std::vector<int> out;
    for (size_t f = 0; f < m.faces.size(); ++f) {
        const std::vector<int>& t = m.faces[f];
        if (std::none_of(t.begin(), t.end(), [&](int v) { return move[static_cast<size_t>(v)] > 0; })) continue;
        const auto normal = [&](const std::vector<Vec3>& p) {
            return normalized(cross(p[static_cast<size_t>(t[1])] - p[static_cast<size_t>(t[0])],
                                    p[static_cast<size_t>(t[2])] - p[static_cast<size_t>(t[0])]));
        };
        if (!(dot(normal(m.points), normal(after)) > cos_max)) out.push_back(static_cast<int>(f));
    }
    return out;
}

// Points sorted by (x, y, z, radius, old id); edges {a, b} with a < b, sorted; faces rotated to their smallest id
// first (orientation kept), sorted.
void sort_medial_points(Skeleton& m) {
    std::vector<int> order(m.points.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        const Vec3& p = m.points[static_cast<size_t>(a)];
        const Vec3& q = m.points[static_cast<size_t>(b)];
        return std::tie(p.x, p.y, p.z, m.radii[static_cast<size_t>(a)], a) <
               std::tie(q.x, q.y, q.z, m.radii[static_cast<size_t>(b)], b);
    });
    std::vector<int> id(order.size());
    Skeleton out;
    for (size_t i = 0; i < order.size(); ++i) {
        id[static_cast<size_t>(order[i])] = static_cast<int>(i);
        out.points.push_back(m.points[static_cast<size_t>(order[i])]);
        out.radii.push_back(m.radii[static_cast<size_t>(order[i])]);
    }
    for (const std::array<int, 2>& e : m.edges)
        out.edges.push_back(side_key(id[static_cast<size_t>(e[0])], id[static_cast<size_t>(e[1])]));
    std::sort(out.edges.begin(), out.edges.end());
    for (const std::vector<int>& f : m.faces) {
        std::vector<int> g;
        for (int v : f) g.push_back(id[static_cast<size_t>(v)]);
        std::rotate(g.begin(), std::min_element(g.begin(), g.end()), g.end());
        out.faces.push_back(std::move(g));
    }
    std::sort(out.faces.begin(), out.faces.end());
    m = std::move(out);
}

}  // namespace

RimExtension extend_rim_borders(Skeleton& m, const SurfaceQuery& query, double reach_factor, double min_radius_fraction,
                                double max_move) {
    RimExtension out;
    if (!(reach_factor >= 1) || !(min_radius_fraction > 0 && min_radius_fraction < 1) || !(max_move > 0)) return out;
    const std::vector<std::vector<std::array<int, 2>>> sides = regular_border_sides(m);
    std::vector<Vec3> direction(m.points.size());
    std::vector<double> move(m.points.size(), 0);
    for (size_t v = 0; v < m.points.size(); ++v) {
        if (sides[v].empty()) continue;
        ++out.border_vertices;
        direction[v] = outward_direction(m, static_cast<int>(v), sides[v]);
        if (norm(direction[v]) == 0) continue;
        const double s = rim_march(query, m.points[v], direction[v], reach_factor, min_radius_fraction, max_move);
        if (s < 0) ++out.sharp;
        if (s > 0) move[v] = s;
    }
    // Moves that fold the sheet (two border vertices of a triangle going apart, a thin triangle turned over) are
    // halved, then undone; every round past the halvings undoes at least one move, so the loop ends.
    std::vector<Vec3> target = m.points;
    for (int round = 0;; ++round) {
        for (size_t v = 0; v < m.points.size(); ++v) target[v] = m.points[v] + direction[v] * move[v];
        const std::vector<int> turned = turned_triangles(m, target, move);
        if (turned.empty()) break;
        for (int f : turned)
            for (int v : m.faces[static_cast<size_t>(f)])
                move[static_cast<size_t>(v)] *= round < kFoldHalvings ? 0.5 : 0.0;
    }
    std::vector<double> radius = m.radii;
    for (size_t v = 0; v < m.points.size(); ++v) {
        if (!(move[v] > 0)) continue;
        radius[v] = std::sqrt(query.squared_distance(target[v]));
        out.largest_move = std::max(out.largest_move, move[v] / m.radii[v]);
        ++out.moved;
    }
    if (out.moved == 0) return out;
    m.points = std::move(target);
    m.radii = std::move(radius);
    sort_medial_points(m);
    return out;
}

}  // namespace mesohex
