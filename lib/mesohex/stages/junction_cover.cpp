#include "mesohex/stages/junction_cover.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"

namespace mesohex {

namespace {

// The depth of x in the union of the balls swept along the cone (radius linear in the arc parameter s): the
// largest r(s) - |x - p(s)| over s in [0, 1], attained at s* = (z - k rho / sqrt(1 - k^2)) / L with
// k = (ra - rb) / L (z, rho: x's axial and radial coordinates), clamped (the function is concave in s); x is inside
// when it is >= 0. A cone with |rb - ra| >= L is the larger of its end balls.
double cone_depth(const RoundCone& k, const Vec3& x) {
    const Vec3 ab = k.b - k.a;
    const double len = norm(ab);
    const double dr = k.rb - k.ra;
    if (len < 1e-300 || std::abs(dr) >= len) return std::max(k.ra - distance(x, k.a), k.rb - distance(x, k.b));
    const Vec3 u = ab / len;
    const double z = dot(x - k.a, u);
    const double rho = norm(x - k.a - z * u);
    const double slope = -dr / len;
    const double s = std::clamp((z - slope * rho / std::sqrt(1 - slope * slope)) / len, 0.0, 1.0);
    return k.ra + s * dr - distance(x, k.a + s * ab);
}

bool inside_cone(const RoundCone& k, const Vec3& x) { return cone_depth(k, x) >= 0; }

bool inside_union(const std::vector<RoundCone>& cones, const Vec3& x) {
    return std::any_of(cones.begin(), cones.end(), [&](const RoundCone& k) { return inside_cone(k, x); });
}

int other_end(const Skeleton& s, int e, int v) { return s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0]; }

// c's ball (radius rc) and the round cones of the domain skeleton's edges that pass within reach of c.
std::vector<RoundCone> junction_cones(const Skeleton& domain, const Vec3& c, double rc, double reach) {
    std::vector<RoundCone> cones{{c, c, rc, rc}};
    for (const std::array<int, 2>& e : domain.edges) {
        const Vec3 &a = domain.points[e[0]], &b = domain.points[e[1]];
        if (distance_to_segment(c, a, b) <= reach) cones.push_back({a, b, domain.radii[e[0]], domain.radii[e[1]]});
    }
    return cones;
}

bool coverable(const Skeleton& s, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
               const std::vector<int>& vertex_base, const JunctionCoverOptions& o, int c) {
    if (an.vertex_class[c] != VertexClass::BranchingPoint || vertex_base[c] < 0) return false;
    if (!cs.vertex_block.empty() && cs.vertex_block[c] >= 0) return false;
    const int degree = an.vertex_edge_begin[c + 1] - an.vertex_edge_begin[c];
    if (degree < o.min_degree) return false;
    for (int i = an.vertex_edge_begin[c]; i < an.vertex_edge_begin[c + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (an.edge_degree[e] != 0 || other_end(s, e, c) == c) return false;
    }
    return true;
}

// One junction's surface points and edge midpoints at distance r + lambda_x (t_x - r) along their rays.
struct JunctionMove {
    int c = 0, base = 0, np = 0;
    double r = 0;
    std::vector<double> target;  // per surface point: the distance it moves to (r when it stays)
    std::vector<double> lambda;  // per surface point: the fraction of the move kept
    // JunctionCoverOptions::crease_midpoints: per surface edge, its midpoint where the raw mesh put it, its target (the
    // ray's exit from the union, or the start when that lies inside), the fraction of the move kept. Empty otherwise.
    std::vector<Vec3> mid_from, mid_to;
    std::vector<double> mid_lambda;
};

void place_junction(const Skeleton& s, const ConnectionSurfaces& cs, const BranchFrames& frames, const JunctionMove& m,
                    std::vector<Vec3>& points) {
    const Vec3& c = s.points[m.c];
    if (!m.mid_lambda.empty()) {
        for (std::size_t j = 0; j < m.mid_lambda.size(); ++j)
            points[m.base + 1 + m.np + static_cast<int>(j)] =
                m.mid_from[j] + m.mid_lambda[j] * (m.mid_to[j] - m.mid_from[j]);
        return;
    }
    const int p0 = cs.point_begin[m.c];
    std::vector<double> dist(m.np);
    for (int x = 0; x < m.np; ++x) {
        dist[x] = m.r + m.lambda[x] * (m.target[x] - m.r);
        points[m.base + 1 + x] = c + dist[x] * frames.directions[p0 + x];
    }
    for (int j = cs.edge_begin[m.c]; j < cs.edge_begin[m.c + 1]; ++j) {
        const std::array<int, 2>& ed = cs.edges[j];
        const Vec3 mid = normalized(frames.directions[p0 + ed[0]] + frames.directions[p0 + ed[1]]);
        points[m.base + 1 + m.np + (j - cs.edge_begin[m.c])] = c + 0.5 * (dist[ed[0]] + dist[ed[1]]) * mid;
    }
}

// The hexes of c's chunks (4 per incident branch edge).
std::vector<int> junction_hexes(const SkeletonAnalysis& an, const std::vector<int>& edge_hex, int c) {
    std::vector<int> hs;
    for (int i = an.vertex_edge_begin[c]; i < an.vertex_edge_begin[c + 1]; ++i) {
        const int h0 = edge_hex[an.vertex_edges[i]];
        if (h0 < 0) continue;
        for (int k = 0; k < 4; ++k) hs.push_back(h0 + k);
    }
    return hs;
}

// Halves (or, in the last round, drops) the moves of the surface points of every hex below its floor; false when
// no hex is below.
bool guard_round(const std::vector<std::array<int, 8>>& hexes, const std::vector<Vec3>& points,
                 const std::vector<int>& hs, const std::vector<double>& floor, bool last, JunctionMove& m) {
    std::vector<char> hit(m.np, 0), mid_hit(m.mid_lambda.size(), 0);
    bool any = false;
    for (std::size_t i = 0; i < hs.size(); ++i) {
        const std::array<int, 8>& h = hexes[hs[i]];
        const double sj = hex_scaled_jacobian(points, h);
        if (sj >= floor[i]) continue;
        for (int id : h) {
            const int x = id - m.base - 1;
            if (x >= 0 && x < m.np && m.lambda[x] > 0) hit[x] = 1, any = true;
            const int j = x - m.np;
            if (j >= 0 && j < static_cast<int>(m.mid_lambda.size()) && m.mid_lambda[j] > 0) mid_hit[j] = 1, any = true;
        }
    }
    for (int x = 0; x < m.np; ++x)
        if (hit[x]) m.lambda[x] = last ? 0.0 : 0.5 * m.lambda[x];
    for (std::size_t j = 0; j < mid_hit.size(); ++j)
        if (mid_hit[j]) m.mid_lambda[j] = last ? 0.0 : 0.5 * m.mid_lambda[j];
    return any;
}

// Per surface edge j of c (index from cs.edge_begin[c]): the interior dihedral, in degrees, of the sharper of its two
// raw boundary half-edges Q_x-M_j and M_j-Q_y, each the sum over its two hexes (one per chunk whose quad holds j) of
// the angle between the hex's kite face on c's sphere (c, Q, M, Q') and its boundary face; 0 where a half-edge does
// not have exactly two such hexes. A hex of c's chunk has c's centre, a point, an edge midpoint and a point as its
// bottom (or top) quad (write_branch_chunks).
std::vector<double> surface_edge_creases(const ConnectionSurfaces& cs, const JunctionMove& m,
                                         const std::vector<std::array<int, 8>>& hexes, const std::vector<Vec3>& points,
                                         const std::vector<int>& hs) {
    const int ne = cs.edge_begin[m.c + 1] - cs.edge_begin[m.c];
    std::vector<double> sum(2 * ne, 0.0);
    std::vector<int> count(2 * ne, 0);
    for (int h : hs) {
        const std::array<int, 8>& hex = hexes[h];
        const int off = hex[0] == m.base ? 0 : 4;
        if (hex[off] != m.base) continue;
        std::array<Vec3, 4> near, far;
        for (int k = 0; k < 4; ++k) near[k] = points[hex[off + k]], far[k] = points[hex[4 - off + k]];
        const int j = hex[off + 2] - m.base - 1 - m.np;
        if (j < 0 || j >= ne) continue;
        const Vec3 kite = 0.25 * (near[0] + near[1] + near[2] + near[3]);
        for (int k : {1, 3}) {
            const int x = hex[off + k] - m.base - 1;
            const int side = cs.edges[cs.edge_begin[m.c] + j][0] == x ? 0 : 1;
            const Vec3 face = 0.25 * (near[k] + near[2] + far[k] + far[2]);
            sum[2 * j + side] += angle_about_edge(near[k], near[2], kite, face);
            ++count[2 * j + side];
        }
    }
    std::vector<double> crease(ne, 0.0);
    for (int j = 0; j < ne; ++j)
        for (int side = 0; side < 2; ++side)
            if (count[2 * j + side] == 2) crease[j] = std::max(crease[j], sum[2 * j + side] * 180 / std::numbers::pi);
    return crease;
}

// Crease opening (JunctionCoverOptions::crease_deg): the end points of every surface edge whose crease exceeds the
// limit move a sixteenth of the way towards their targets, until no crease exceeds it or every such point is there.
void open_creases(const Skeleton& s, const ConnectionSurfaces& cs, const BranchFrames& frames,
                  const std::vector<std::array<int, 8>>& hexes, const std::vector<int>& hs, double limit_deg,
                  std::vector<Vec3>& points, JunctionMove& m) {
    constexpr int kSteps = 16;
    for (int step = 0; step <= kSteps; ++step) {
        place_junction(s, cs, frames, m, points);
        const std::vector<double> crease = surface_edge_creases(cs, m, hexes, points, hs);
        bool raised = false;
        for (std::size_t j = 0; j < crease.size(); ++j) {
            if (crease[j] <= limit_deg) continue;
            if (!m.mid_lambda.empty()) {
                if (m.mid_lambda[j] >= 1 || m.mid_to[j] == m.mid_from[j]) continue;
                m.mid_lambda[j] = std::min(1.0, m.mid_lambda[j] + 1.0 / kSteps);
                raised = true;
                continue;
            }
            for (int x : cs.edges[cs.edge_begin[m.c] + static_cast<int>(j)]) {
                if (m.lambda[x] >= 1 || m.target[x] <= m.r) continue;
                m.lambda[x] = std::min(1.0, m.lambda[x] + 1.0 / kSteps);
                raised = true;
            }
        }
        if (!raised) break;
    }
}

// JunctionCoverOptions::crease_pair_deg: per surface edge j of c (index from cs.edge_begin[c]), 1 when the two chunk
// hexes whose bottom (or top) quad holds j's midpoint belong to two branch edges of c whose directions from c (to
// their other ends) are less than pair_deg apart: the edge a close pair's two quads share.
std::vector<char> close_pair_edges(const Skeleton& s, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                                   const std::vector<int>& edge_hex, const std::vector<std::array<int, 8>>& hexes,
                                   const JunctionMove& m, double pair_deg) {
    const int ne = cs.edge_begin[m.c + 1] - cs.edge_begin[m.c];
    std::vector<std::vector<int>> holders(ne);
    for (int i = an.vertex_edge_begin[m.c]; i < an.vertex_edge_begin[m.c + 1]; ++i) {
        const int e = an.vertex_edges[i], h0 = edge_hex[e];
        for (int k = 0; h0 >= 0 && k < 4; ++k) {
            const std::array<int, 8>& hex = hexes[h0 + k];
            const int off = hex[0] == m.base ? 0 : 4;
            const int j = hex[off + 2] - m.base - 1 - m.np;
            if (hex[off] != m.base || j < 0 || j >= ne) continue;
            if (std::find(holders[j].begin(), holders[j].end(), e) == holders[j].end()) holders[j].push_back(e);
        }
    }
    const Vec3& c = s.points[m.c];
    const double cos_limit = std::cos(pair_deg * std::numbers::pi / 180);
    std::vector<char> close(ne, 0);
    for (int j = 0; j < ne; ++j) {
        if (holders[j].size() != 2) continue;
        const Vec3 a = normalized(s.points[other_end(s, holders[j][0], m.c)] - c);
        const Vec3 b = normalized(s.points[other_end(s, holders[j][1], m.c)] - c);
        close[j] = dot(a, b) > cos_limit ? 1 : 0;
    }
    return close;
}

int cover_junction(const Skeleton& s, const Skeleton& domain, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                   const BranchFrames& frames, const std::vector<double>& radius, const std::vector<int>& vertex_base,
                   const std::vector<int>& edge_hex, const std::vector<std::array<int, 8>>& hexes,
                   std::vector<Vec3>& points, const std::vector<double>& shortest_edge, const JunctionCoverOptions& o,
                   int c) {
    JunctionMove m;
    m.c = c;
    m.base = vertex_base[c];
    m.np = cs.point_begin[c + 1] - cs.point_begin[c];
    m.r = radius[c];
    const double rc = s.radii[c];
    const std::vector<RoundCone> cones = junction_cones(domain, s.points[c], rc, o.arc * rc);
    int moved = 0;
    for (int x = 0; x < m.np; ++x) {
        const double t =
            ray_exit(cones, s.points[c], frames.directions[cs.point_begin[c] + x], 0.02 * rc, (o.arc + 1) * rc);
        double target = t > m.r ? m.r + o.fraction * (t - m.r) : m.r;
        if (o.inset > 0) target = std::max(std::min(target, t - o.inset * shortest_edge[m.base + 1 + x]), 0.5 * m.r);
        if (o.crease_deg > 0) target = std::max(t, m.r);
        const bool move = target != m.r;
        m.target.push_back(target);
        m.lambda.push_back(move && !(o.crease_deg > 0) ? 1.0 : 0.0);
        moved += move ? 1 : 0;
    }
    if (o.crease_deg > 0 && o.crease_midpoints) {  // the folded edges' midpoints move, the points stay
        moved = 0;
        const int ne = cs.edge_begin[c + 1] - cs.edge_begin[c];
        const int p0 = cs.point_begin[c];
        const std::vector<char> pair = o.crease_pair_deg > 0
                                           ? close_pair_edges(s, an, cs, edge_hex, hexes, m, o.crease_pair_deg)
                                           : std::vector<char>(ne, 1);
        for (int j = 0; j < ne; ++j) {
            const std::array<int, 2>& ed = cs.edges[cs.edge_begin[c] + j];
            const Vec3 d = normalized(frames.directions[p0 + ed[0]] + frames.directions[p0 + ed[1]]);
            const double t = pair[j] ? ray_exit(cones, s.points[c], d, 0.02 * rc, (o.arc + 1) * rc) : 0.0;
            const Vec3 from = points[m.base + 1 + m.np + j];
            m.mid_from.push_back(from);
            const bool out = pair[j] && t > dot(from - s.points[c], d);
            m.mid_to.push_back(out ? s.points[c] + t * d : from);
            m.mid_lambda.push_back(0.0);
            if (out) ++moved;
        }
    }
    if (moved == 0) return 0;
    const std::vector<int> hs = junction_hexes(an, edge_hex, c);
    std::vector<double> floor(hs.size());
    for (std::size_t i = 0; i < hs.size(); ++i)
        floor[i] = std::min(o.sj_floor, hex_scaled_jacobian(points, hexes[hs[i]]));
    if (o.crease_deg > 0) open_creases(s, cs, frames, hexes, hs, o.crease_deg, points, m);
    constexpr int kRounds = 7;
    for (int round = 0; round < kRounds; ++round) {
        place_junction(s, cs, frames, m, points);
        if (!guard_round(hexes, points, hs, floor, round == kRounds - 1, m)) break;
        if (round == kRounds - 1) place_junction(s, cs, frames, m, points);
    }
    const auto kept = [](double l) { return l > 0; };
    return static_cast<int>(std::count_if(m.lambda.begin(), m.lambda.end(), kept) +
                            std::count_if(m.mid_lambda.begin(), m.mid_lambda.end(), kept));
}

// Per vertex: the length of its shortest boundary edge (infinity off the boundary).
std::vector<double> shortest_boundary_edges(const std::vector<std::array<int, 8>>& hexes,
                                            const std::vector<Vec3>& points) {
    HexMesh mesh;
    mesh.points = points;
    mesh.hexes = hexes;
    const std::vector<std::vector<int>> nbrs = boundary_edge_neighbours(compute_hex_topology(mesh), points.size());
    std::vector<double> shortest(points.size(), std::numeric_limits<double>::infinity());
    for (std::size_t v = 0; v < points.size(); ++v)
        for (int w : nbrs[v])
            shortest[v] = std::min(shortest[v], distance(points[v], points[static_cast<std::size_t>(w)]));
    return shortest;
}

// The bridge leaving branching point c by branch edge e: its vertices from c through joints to the next vertex that
// is no joint, when that is another branching point; empty otherwise (an extremity, a leaflet, a loop back to c).
std::vector<int> bridge_chain(const Skeleton& s, const SkeletonAnalysis& an, int c, int e) {
    std::vector<int> chain{c};
    int prev_edge = e, v = other_end(s, e, c);
    while (an.edge_degree[prev_edge] == 0 && an.vertex_class[v] == VertexClass::Joint && v != c) {
        chain.push_back(v);
        const int a = an.vertex_edges[an.vertex_edge_begin[v]], b = an.vertex_edges[an.vertex_edge_begin[v] + 1];
        prev_edge = a == prev_edge ? b : a;
        v = other_end(s, prev_edge, v);
    }
    if (an.edge_degree[prev_edge] != 0 || v == c || an.vertex_class[v] != VertexClass::BranchingPoint) return {};
    chain.push_back(v);
    return chain;
}

// Whether some point of the chain's polyline at arc fraction 1/16 .. 15/16 lies at depth >= ratio x the chain ends'
// radii interpolated at that fraction, in the union of the cones (JunctionCoverOptions::bridge_bulge).
bool chain_bulges(const Skeleton& s, const std::vector<RoundCone>& cones, const std::vector<int>& chain, double ratio) {
    std::vector<double> arc{0.0};
    for (std::size_t k = 1; k < chain.size(); ++k)
        arc.push_back(arc.back() + distance(s.points[chain[k - 1]], s.points[chain[k]]));
    const double total = arc.back();
    if (!(total > 0)) return false;
    constexpr int kSamples = 16;
    std::size_t k = 1;
    for (int i = 1; i < kSamples; ++i) {
        const double f = static_cast<double>(i) / kSamples, at = f * total;
        while (k + 1 < arc.size() && arc[k] < at) ++k;
        const double len = arc[k] - arc[k - 1];
        const double t = len > 0 ? (at - arc[k - 1]) / len : 0.0;
        const Vec3 p = s.points[chain[k - 1]] + t * (s.points[chain[k]] - s.points[chain[k - 1]]);
        const double interpolated = s.radii[chain.front()] + f * (s.radii[chain.back()] - s.radii[chain.front()]);
        for (const RoundCone& cone : cones)
            if (cone_depth(cone, p) >= ratio * interpolated) return true;
    }
    return false;
}

}  // namespace

double ray_exit(const std::vector<RoundCone>& cones, const Vec3& c, const Vec3& d, double step, double t_max) {
    double lo = 0;
    for (double t = step;; t += step) {
        if (t >= t_max) return t_max;
        if (inside_union(cones, c + t * d)) {
            lo = t;
            continue;
        }
        double hi = t;
        for (int k = 0; k < 40; ++k) {
            const double mid = 0.5 * (lo + hi);
            (inside_union(cones, c + mid * d) ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    }
}

std::vector<char> bulged_bridge_ends(const Skeleton& skeleton, const Skeleton& domain, const SkeletonAnalysis& an,
                                     double ratio) {
    std::vector<RoundCone> cones;
    for (const std::array<int, 2>& e : domain.edges)
        cones.push_back({domain.points[e[0]], domain.points[e[1]], domain.radii[e[0]], domain.radii[e[1]]});
    std::vector<char> ends(skeleton.points.size(), 0);
    for (int c = 0; c < static_cast<int>(skeleton.points.size()); ++c) {
        if (an.vertex_class[c] != VertexClass::BranchingPoint) continue;
        for (int i = an.vertex_edge_begin[c]; i < an.vertex_edge_begin[c + 1]; ++i) {
            const std::vector<int> chain = bridge_chain(skeleton, an, c, an.vertex_edges[i]);
            if (chain.empty() || !chain_bulges(skeleton, cones, chain, ratio)) continue;
            ends[static_cast<std::size_t>(c)] = ends[static_cast<std::size_t>(chain.back())] = 1;
        }
    }
    return ends;
}

std::vector<char> overlapping_bridge_ends(const Skeleton& skeleton, const SkeletonAnalysis& an, double ratio) {
    std::vector<char> ends(skeleton.points.size(), 0);
    for (int c = 0; c < static_cast<int>(skeleton.points.size()); ++c) {
        if (an.vertex_class[c] != VertexClass::BranchingPoint) continue;
        for (int i = an.vertex_edge_begin[c]; i < an.vertex_edge_begin[c + 1]; ++i) {
            const std::vector<int> chain = bridge_chain(skeleton, an, c, an.vertex_edges[i]);
            if (chain.empty()) continue;
            const int u = chain.back();
            const double gap = distance(skeleton.points[c], skeleton.points[u]);
            if (skeleton.radii[c] + skeleton.radii[u] >= ratio * gap)
                ends[static_cast<std::size_t>(c)] = ends[static_cast<std::size_t>(u)] = 1;
        }
    }
    return ends;
}

int cover_junctions(const Skeleton& skeleton, const Skeleton& domain, const SkeletonAnalysis& an,
                    const ConnectionSurfaces& cs, const BranchFrames& frames, const std::vector<double>& radius,
                    const std::vector<int>& vertex_base, const std::vector<int>& edge_hex,
                    const std::vector<std::array<int, 8>>& hexes, std::vector<Vec3>& points,
                    const JunctionCoverOptions& options) {
    if (!(options.fraction > 0) && !(options.inset > 0) && !(options.crease_deg > 0)) return 0;
    // Per raw vertex: its shortest boundary edge, every point still on its sphere (JunctionCoverOptions::inset).
    std::vector<double> shortest_edge;
    if (options.inset > 0) shortest_edge = shortest_boundary_edges(hexes, points);
    const bool bridges_only = options.bridge_bulge > 0 || options.bridge_overlap > 0;
    std::vector<char> bridge_end(skeleton.points.size(), 0);
    if (options.bridge_bulge > 0) bridge_end = bulged_bridge_ends(skeleton, domain, an, options.bridge_bulge);
    if (options.bridge_overlap > 0) {
        const std::vector<char> overlap = overlapping_bridge_ends(skeleton, an, options.bridge_overlap);
        for (std::size_t v = 0; v < overlap.size(); ++v) bridge_end[v] = bridge_end[v] || overlap[v];
    }
    int moved = 0;
    const int nv = static_cast<int>(skeleton.points.size());
    for (int c = 0; c < nv; ++c)
        if ((!bridges_only || bridge_end[static_cast<std::size_t>(c)]) &&
            coverable(skeleton, an, cs, vertex_base, options, c))
            moved += cover_junction(skeleton, domain, an, cs, frames, radius, vertex_base, edge_hex, hexes, points,
                                    shortest_edge, options, c);
    return moved;
}

}  // namespace mesohex
