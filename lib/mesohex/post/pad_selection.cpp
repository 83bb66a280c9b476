// Selective padding: the regions of the raw boundary whose sharp rims land on matching sharp rims of the domain.
#include "mesohex/post/pad_selection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <tuple>

#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"
#include "mesohex/core/union_find.h"

namespace mesohex {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

std::size_t at(int i) { return static_cast<std::size_t>(i); }

double angle_between(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(dot(a, b), -1.0, 1.0)) / kDegree; }

// A sharp edge of the domain: its segment, the angle between its two triangle normals (degrees), convex or not.
struct DomainEdge {
    Vec3 a, b;
    double angle = 0;
    bool convex = true;
};

// A boundary edge of the raw mesh and its (two, else q1 = -1) boundary quads.
struct RawEdge {
    int a = 0, b = 0;
    int q0 = -1, q1 = -1;
    bool sharp = false, convex = true, matched = false;
    double angle = 0;
};

Vec3 triangle_normal(const TriangleMesh& s, const std::array<int, 3>& t) {
    const Vec3& a = s.points[at(t[0])];
    return normalized(cross(s.points[at(t[1])] - a, s.points[at(t[2])] - a));
}

// The sharp edges of the domain: edges of exactly two triangles whose normals are more than sharp_angle apart.
std::vector<DomainEdge> domain_sharp_edges(const TriangleMesh& s, double sharp_angle) {
    std::vector<std::array<int, 4>> half;  // (min vertex, max vertex, triangle, opposite vertex)
    for (std::size_t t = 0; t < s.triangles.size(); ++t)
        for (int i = 0; i < 3; ++i) {
            const int u = s.triangles[t][at(i)], v = s.triangles[t][at((i + 1) % 3)];
            half.push_back({std::min(u, v), std::max(u, v), static_cast<int>(t), s.triangles[t][at((i + 2) % 3)]});
        }
    std::sort(half.begin(), half.end());
    std::vector<DomainEdge> sharp;
    for (std::size_t i = 0; i < half.size();) {
        std::size_t j = i;
        while (j < half.size() && half[j][0] == half[i][0] && half[j][1] == half[i][1]) ++j;
        if (j - i == 2) {
            const Vec3 n0 = triangle_normal(s, s.triangles[at(half[i][2])]);
            const Vec3 n1 = triangle_normal(s, s.triangles[at(half[i + 1][2])]);
            const double angle = angle_between(n0, n1);
            if (angle > sharp_angle) {
                const Vec3& a = s.points[at(half[i][0])];
                // Convex: the other triangle's far corner lies below this triangle's plane.
                const bool convex = dot(s.points[at(half[i + 1][3])] - a, n0) < 0;
                sharp.push_back({a, s.points[at(half[i][1])], angle, convex});
            }
        }
        i = j;
    }
    return sharp;
}

Vec3 quad_centre(const HexMesh& m, const std::array<int, 4>& q) {
    return (m.points[at(q[0])] + m.points[at(q[1])] + m.points[at(q[2])] + m.points[at(q[3])]) * 0.25;
}

// The boundary edges with their quads, sharpness, convexity and normal angle.
std::vector<RawEdge> raw_edges(const std::vector<std::array<int, 4>>& quads, const std::vector<Vec3>& normals,
                               const std::vector<Vec3>& centres, double sharp_angle) {
    std::vector<std::array<int, 3>> half;  // (min vertex, max vertex, quad)
    for (std::size_t q = 0; q < quads.size(); ++q)
        for (int i = 0; i < 4; ++i) {
            const int u = quads[q][at(i)], v = quads[q][at((i + 1) % 4)];
            half.push_back({std::min(u, v), std::max(u, v), static_cast<int>(q)});
        }
    std::sort(half.begin(), half.end());
    std::vector<RawEdge> edges;
    for (std::size_t i = 0; i < half.size();) {
        std::size_t j = i;
        while (j < half.size() && half[j][0] == half[i][0] && half[j][1] == half[i][1]) ++j;
        RawEdge e;
        e.a = half[i][0];
        e.b = half[i][1];
        e.q0 = half[i][2];
        e.sharp = true;  // not two quads: sharp, never matched
        if (j - i == 2) {
            e.q1 = half[i + 1][2];
            e.angle = angle_between(normals[at(e.q0)], normals[at(e.q1)]);
            e.sharp = e.angle > sharp_angle;
            e.convex = dot(centres[at(e.q1)] - centres[at(e.q0)], normals[at(e.q0)]) < 0;
        }
        edges.push_back(e);
        i = j;
    }
    return edges;
}

// Does the sharp raw edge e land on a matching sharp edge of the domain? Its midpoint, landed along the mean normal
// of its two quads, must be within r = search_radius x len + landing_slack x (distance travelled) of a sharp domain
// edge of the same convexity and a normal angle within angle_tolerance, and the raw edge's extent across that domain
// edge's direction (len x the sine of the angle between them) within r too: a long edge runs along the feature line,
// a very short one (whose direction says little) is judged by where it is.
bool edge_matches(const HexMesh& m, const RawEdge& e, const std::vector<Vec3>& normals,
                  const std::vector<DomainEdge>& features, const LandingFn& land, const PadSelectionOptions& o) {
    if (e.q1 < 0 || e.angle < o.min_rim_angle) return false;
    const Vec3& a = m.points[at(e.a)];
    const Vec3& b = m.points[at(e.b)];
    const Vec3 mid = (a + b) * 0.5;
    const double len = distance(a, b);
    const Landing l = land(mid, normalized(normals[at(e.q0)] + normals[at(e.q1)]));
    const double radius = o.search_radius * len + o.landing_slack * distance(mid, l.point);
    for (const DomainEdge& f : features) {
        if (f.convex != e.convex || std::abs(f.angle - e.angle) > o.angle_tolerance || f.angle < o.min_rim_angle)
            continue;
        if (distance_to_segment(l.point, f.a, f.b) > radius) continue;
        if (norm(cross(b - a, normalized(f.b - f.a))) <= radius) return true;
    }
    return false;
}

// Conditions (1) to (4) of select_bare_regions, per region (indexed by its root quad).
std::vector<char> bare_candidates(const HexMesh& m, const std::vector<std::array<int, 4>>& quads,
                                  const std::vector<Vec3>& normals, const std::vector<Vec3>& centres,
                                  const std::vector<RawEdge>& edges, const std::vector<int>& region,
                                  const LandingFn& land, const PadSelectionOptions& o) {
    std::vector<char> bounded(quads.size(), 0), ok(quads.size(), 1);
    std::vector<char> on_sharp(m.points.size(), 0);
    std::vector<int> quad_count(m.points.size(), 0);
    for (const RawEdge& e : edges) {
        if (!e.sharp) continue;
        on_sharp[at(e.a)] = on_sharp[at(e.b)] = 1;
        for (int q : {e.q0, e.q1}) {
            if (q < 0) continue;
            bounded[at(region[at(q)])] = 1;
            if (!e.matched) ok[at(region[at(q)])] = 0;
        }
        if (e.q1 < 0) ok[at(region[at(e.q0)])] = 0;
    }
    for (const std::array<int, 4>& q : quads)
        for (int v : q) ++quad_count[at(v)];
    const double min_cos = std::cos(o.normal_tolerance * kDegree);
    for (std::size_t q = 0; q < quads.size(); ++q) {
        const std::size_t r = at(region[q]);
        if (!bounded[r] || !ok[r]) continue;
        for (int v : quads[q])
            // 3 quads: a leaflet's convex corner (its plate and the two half-chunks of its border edges around its
            // up / down copy); its hexes keep that valence padded or not. 5 and more (a pinion's fin roots) need the
            // padding's layer to spread their distortion (docs/tuning.md, "Selective padding").
            if (!on_sharp[at(v)] && quad_count[at(v)] != 4 && quad_count[at(v)] != 3) ok[r] = 0;
        if (!ok[r]) continue;
        const Landing l = land(centres[q], normals[q]);
        if (dot(l.normal, normals[q]) < min_cos) ok[r] = 0;
    }
    for (std::size_t r = 0; r < quads.size(); ++r) ok[r] = ok[r] && bounded[r];
    return ok;
}

// The closing rules of select_bare_regions: a bare region meeting a padded quad along a concave edge, or at a vertex
// where the padded quads form more than one fan (more than two bare-padded edges there), becomes padded; repeated
// until nothing changes (each round pads at least one more region, so at most #regions rounds).
void repad_conflicts(std::size_t vertices, const std::vector<RawEdge>& edges, const std::vector<int>& region,
                     std::vector<char>& bare_region) {
    for (bool changed = true; changed;) {
        changed = false;
        std::vector<int> border(vertices, 0);
        auto bare = [&](int q) { return q >= 0 && bare_region[at(region[at(q)])]; };
        for (const RawEdge& e : edges) {
            if (e.q1 < 0 || bare(e.q0) == bare(e.q1)) continue;
            ++border[at(e.a)];
            ++border[at(e.b)];
            if (!e.convex) {
                bare_region[at(region[at(bare(e.q0) ? e.q0 : e.q1)])] = 0;
                changed = true;
            }
        }
        if (changed) continue;
        for (const RawEdge& e : edges)
            for (int v : {e.a, e.b})
                if (border[at(v)] > 2)
                    for (int q : {e.q0, e.q1})
                        if (bare(q)) {
                            bare_region[at(region[at(q)])] = 0;
                            changed = true;
                        }
    }
}

}  // namespace

PadSelection select_bare_regions(const HexMesh& mesh, const TriangleMesh& domain, const LandingFn& land,
                                 const PadSelectionOptions& options) {
    PadSelection sel;
    const HexTopology topo = compute_hex_topology(mesh);
    const std::vector<std::array<int, 4>>& quads = topo.boundary_quads;
    sel.bare.assign(quads.size(), 0);
    if (quads.empty()) return sel;
    std::vector<Vec3> normals(quads.size()), centres(quads.size());
    for (std::size_t q = 0; q < quads.size(); ++q) {
        normals[q] = quad_normal(mesh, quads[q]);
        centres[q] = quad_centre(mesh, quads[q]);
    }
    std::vector<RawEdge> edges = raw_edges(quads, normals, centres, options.sharp_angle);
    // The domain's sharp edges (a pass over all its triangles: the stage's largest cost on a dense domain) only when
    // the raw boundary has a sharp edge to match; without one no region can be bare (condition 1 below).
    std::vector<DomainEdge> features;
    if (std::any_of(edges.begin(), edges.end(), [](const RawEdge& e) { return e.sharp; }))
        features = domain_sharp_edges(domain, options.sharp_angle);
    sel.domain_sharp_edges = static_cast<long>(features.size());
    UnionFind regions(static_cast<int>(quads.size()));
    for (RawEdge& e : edges) {
        if (!e.sharp) {
            regions.unite(e.q0, e.q1);
            continue;
        }
        ++sel.sharp_edges;
        e.matched = edge_matches(mesh, e, normals, features, land, options);
        if (e.matched) ++sel.matched_edges;
    }
    std::vector<int> region(quads.size());
    for (std::size_t q = 0; q < quads.size(); ++q) {
        region[q] = regions.find(static_cast<int>(q));
        if (region[q] == static_cast<int>(q)) ++sel.regions;
    }
    std::vector<char> bare_region = bare_candidates(mesh, quads, normals, centres, edges, region, land, options);
    repad_conflicts(mesh.points.size(), edges, region, bare_region);
    for (std::size_t q = 0; q < quads.size(); ++q) {
        sel.bare[q] = bare_region[at(region[q])];
        if (sel.bare[q]) sel.bare_quads.push_back(quads[q]);
        if (region[q] == static_cast<int>(q) && bare_region[q]) ++sel.bare_regions;
    }
    return sel;
}

}  // namespace mesohex
