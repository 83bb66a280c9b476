#include "mesohex/stages/skeleton_repair.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

namespace mesohex {
namespace {

// A branch walked from a branching point c through its joints: vertices (c first), their positions, radii and
// cumulative arc length.
struct Walk {
    std::vector<int> verts;
    std::vector<double> s;
    bool loop = false;  // came back to c
    double length() const { return s.back(); }
};

struct Graph {
    std::vector<std::vector<int>> inc;  // per vertex: incident branch edges (not leaflet sides)
    std::vector<bool> on_face;
    std::vector<int> degree;  // all edges, leaflet sides included
};

Graph make_graph(const Skeleton& s) {
    const int n = static_cast<int>(s.points.size());
    Graph g;
    g.inc.assign(n, {});
    g.on_face.assign(n, false);
    g.degree.assign(n, 0);
    std::set<std::pair<int, int>> sides;
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i) {
            if (f[i] < 0 || f[i] >= n) continue;
            g.on_face[f[i]] = true;
            sides.insert(std::minmax(f[i], f[(i + 1) % f.size()]));
        }
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e) {
        const auto [a, b] = s.edges[e];
        if (a < 0 || a >= n || b < 0 || b >= n || a == b) continue;
        ++g.degree[a], ++g.degree[b];
        if (sides.count(std::minmax(a, b))) continue;
        g.inc[a].push_back(e);
        g.inc[b].push_back(e);
    }
    return g;
}

Walk walk(const Skeleton& s, const Graph& g, int c, int e0) {
    Walk w;
    w.verts = {c};
    w.s = {0.0};
    int prev_e = e0, cur = s.edges[e0][0] == c ? s.edges[e0][1] : s.edges[e0][0];
    for (std::size_t guard = 0; guard <= s.points.size(); ++guard) {
        w.s.push_back(w.s.back() + distance(s.points[w.verts.back()], s.points[cur]));
        w.verts.push_back(cur);
        if (cur == c) {
            w.loop = true;
            break;
        }
        const bool joint = g.degree[cur] == 2 && g.inc[cur].size() == 2 && !g.on_face[cur];
        if (!joint) break;
        const int next_e = g.inc[cur][0] == prev_e ? g.inc[cur][1] : g.inc[cur][0];
        prev_e = next_e;
        cur = s.edges[next_e][0] == cur ? s.edges[next_e][1] : s.edges[next_e][0];
    }
    return w;
}

// Position and radius at arc length t (clamped), and the index k of the segment [verts[k], verts[k+1]] holding it.
struct AtArc {
    Vec3 x;
    double r = 0;
    std::size_t k = 0;
    double u = 0;  // position inside segment k, 0..1
};

AtArc at_arc(const Skeleton& s, const Walk& w, double t) {
    const std::size_t last = w.verts.size() - 1;
    t = std::clamp(t, 0.0, w.length());
    std::size_t k = static_cast<std::size_t>(std::upper_bound(w.s.begin(), w.s.end(), t) - w.s.begin());
    k = k == 0 ? 0 : std::min(k - 1, last - 1);
    const double len = w.s[k + 1] - w.s[k];
    const double u = len > 0 ? std::clamp((t - w.s[k]) / len, 0.0, 1.0) : 0.0;
    const int a = w.verts[k], b = w.verts[k + 1];
    return {s.points[a] + u * (s.points[b] - s.points[a]), s.radii[a] + u * (s.radii[b] - s.radii[a]), k, u};
}

struct Candidate {
    double score = 0;  // x / r_c
    int c = -1, ei = -1, ej = -1;
    double sep = 0;  // l*: arc length where the tubes separate
    Vec3 t;
    double rt = 0;
    bool absorb = false;  // ej is a stub (ends at an extremity inside ei's tube): it disappears into t
};

bool is_extremity(const Graph& g, int v) { return g.degree[v] == 1 && !g.on_face[v]; }

// The arc length where the tubes of walks i and j separate, or -1 if they do not before the shorter one ends.
double separation(const Skeleton& s, const Walk& wi, const Walk& wj) {
    const double len = std::min(wi.length(), wj.length());
    const auto apart = [&](double t) {
        const AtArc a = at_arc(s, wi, t), b = at_arc(s, wj, t);
        return distance(a.x, b.x) >= a.r + b.r;
    };
    constexpr int steps = 128;
    double lo = 0;
    for (int k = 1; k <= steps; ++k) {
        const double t = len * k / steps;
        if (!apart(t)) {
            lo = t;
            continue;
        }
        double hi = t;
        for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (apart(mid) ? hi : lo) = mid;
        }
        return hi;
    }
    return -1;
}

}  // namespace

SkeletonRepairResult repair_skeleton(const Skeleton& input, const SkeletonRepairOptions& o) {
    SkeletonRepairResult res;
    res.skeleton = input;
    res.vertex_map.resize(input.points.size());
    for (std::size_t v = 0; v < input.points.size(); ++v) res.vertex_map[v] = static_cast<int>(v);
    Skeleton& s = res.skeleton;
    if (!o.trunks || s.radii.size() != s.points.size()) return res;
    const std::size_t budget = input.edges.size();
    std::set<std::pair<int, int>> unseparated;  // of the last scan: (c, pair of first vertices)
    for (std::size_t round = 0; round < budget; ++round) {
        unseparated.clear();
        const Graph g = make_graph(s);
        const int n = static_cast<int>(s.points.size());
        Candidate best;
        for (int c = 0; c < n; ++c) {
            if (g.on_face[c] || g.inc[c].size() < 3 || !(s.radii[c] > 0)) continue;
            const std::vector<int>& inc = g.inc[c];
            std::vector<Walk> walks;
            for (const int e : inc) walks.push_back(walk(s, g, c, e));
            for (std::size_t i = 0; i < inc.size(); ++i)
                for (std::size_t j = i + 1; j < inc.size(); ++j) {
                    const Walk &wi = walks[i], &wj = walks[j];
                    if (wi.loop || wj.loop || wi.verts[1] == wj.verts[1]) continue;
                    const double li = wi.s[1], lj = wj.s[1];
                    const double ri = s.radii[wi.verts[1]], rj = s.radii[wj.verts[1]];
                    if (!(li > 1e-9 * ri) || !(lj > 1e-9 * rj)) continue;
                    const Vec3 di = (s.points[wi.verts[1]] - s.points[c]) / li;
                    const Vec3 dj = (s.points[wj.verts[1]] - s.points[c]) / lj;
                    if (dot(di, dj) <= 0) continue;  // 90 degrees or more apart: the tubes part at the ball
                    const double sep = separation(s, wi, wj);
                    if (sep < 0) {
                        // The tubes do not separate before the shorter walk ends. A stub (the shorter walk ends at an
                        // extremity) is absorbed: t at the midpoint of its end and the other walk's point at the same
                        // arc length, with a radius covering both tubes there; otherwise the pair stays.
                        const bool i_short = wi.length() <= wj.length();
                        const Walk &stub = i_short ? wi : wj, &keep = i_short ? wj : wi;
                        const double len = stub.length();
                        if (!o.absorb_stubs || !is_extremity(g, stub.verts.back())) {
                            unseparated.insert(
                                {c, std::min(wi.verts[1], wj.verts[1]) * n + std::max(wi.verts[1], wj.verts[1])});
                            continue;
                        }
                        const AtArc a = at_arc(s, stub, len), b = at_arc(s, keep, len);
                        const double score = len / s.radii[c];
                        if (score > best.score)
                            best = {score,
                                    c,
                                    i_short ? inc[j] : inc[i],
                                    i_short ? inc[i] : inc[j],
                                    len,
                                    0.5 * (a.x + b.x),
                                    0.5 * distance(a.x, b.x) + std::max(a.r, b.r),
                                    true};
                        continue;
                    }
                    const AtArc a = at_arc(s, wi, sep), b = at_arc(s, wj, sep);
                    const double r = 0.5 * (a.r + b.r);
                    const double sin_a = std::min(r / sep, 0.99);
                    const double x = (sep - r) / (1 + sin_a);
                    if (!(x >= o.trunk_clearance * (s.radii[c] + r + x * sin_a))) continue;
                    const Vec3 m = 0.5 * (a.x + b.x);
                    const Vec3 dir = normalized(m - s.points[c]);
                    if (dir == Vec3{}) continue;
                    const double score = x / s.radii[c];
                    if (score > best.score)
                        best = {score, c, inc[i], inc[j], sep, s.points[c] + x * dir, r + x * sin_a, false};
                }
        }
        if (best.c < 0) break;

        // Apply: drop both walks' vertices before l*, add t, the crotch points (or reuse a vertex there), and the
        // edges (c, t), (t, p), (p, next vertex).
        const int c = best.c;
        std::vector<bool> drop_vertex(n, false), drop_edge(s.edges.size(), false);
        std::vector<std::array<int, 2>> new_edges;
        const int t = n;
        s.points.push_back(best.t);
        s.radii.push_back(best.rt);
        new_edges.push_back({c, t});
        for (const int e0 : {best.ei, best.ej}) {
            const Walk w = walk(s, g, c, e0);
            if (best.absorb && e0 == best.ej) {  // the stub: every vertex after c and every edge go
                int cur = e0;
                for (std::size_t q = 1; q < w.verts.size(); ++q) {
                    drop_edge[cur] = true;
                    const int v = w.verts[q];
                    drop_vertex[v] = true;
                    if (q + 1 < w.verts.size()) cur = g.inc[v][0] == cur ? g.inc[v][1] : g.inc[v][0];
                }
                continue;
            }
            const AtArc p = at_arc(s, w, best.sep);
            // Segment k holds l*: vertices 1..k are dropped (joints), edges 0..k too; a new vertex at p unless p is
            // (almost) verts[k + 1], then that vertex is the re-attachment. Absorbing a stub, the walk re-attaches
            // at t itself, to its first vertex after l* (the joints after it keep the branch's shape for adaptation).
            const bool at_end = p.u > 1 - 1e-9 || best.absorb;
            const std::size_t k = p.k;
            int cur = e0;
            for (std::size_t q = 0;; ++q) {
                drop_edge[cur] = true;
                if (q == k) break;
                const int v = w.verts[q + 1];  // a joint: two branch edges
                drop_vertex[v] = true;
                cur = g.inc[v][0] == cur ? g.inc[v][1] : g.inc[v][0];
            }
            const int after = w.verts[k + 1];
            if (at_end) {
                new_edges.push_back({t, after});
            } else {
                const int pv = static_cast<int>(s.points.size());
                s.points.push_back(p.x);
                s.radii.push_back(p.r);
                new_edges.push_back({t, pv});
                new_edges.push_back({pv, after});
            }
        }
        // Compact.
        const int total = static_cast<int>(s.points.size());
        std::vector<int> id(total, -1);
        Skeleton out;
        for (int v = 0; v < total; ++v) {
            if (v < n && drop_vertex[v]) continue;
            id[v] = static_cast<int>(out.points.size());
            out.points.push_back(s.points[v]);
            out.radii.push_back(s.radii[v]);
        }
        for (std::size_t e = 0; e < s.edges.size(); ++e)
            if (!drop_edge[e]) out.edges.push_back({id[s.edges[e][0]], id[s.edges[e][1]]});
        for (const std::array<int, 2>& e : new_edges) out.edges.push_back({id[e[0]], id[e[1]]});
        out.faces = s.faces;
        for (std::vector<int>& f : out.faces)
            for (int& v : f) v = id[v];
        for (int& v : res.vertex_map)
            if (v >= 0) v = id[v];
        s = std::move(out);
        ++(best.absorb ? res.absorbed_stubs : res.trunks);
    }
    res.unseparated = static_cast<int>(unseparated.size());
    return res;
}

}  // namespace mesohex
