#include "mesohex/stages/skeleton_repair.h"

// An exception to one stage per file pair: the repair splits a docked wall's feet exactly where the analysis will dock
// it, so it takes the analysis' leaflets and joins across chains (analyze_leaflets, join_plates_across_chains) rather
// than a second test of its own that could disagree (docs/blocks.md, "Audit against issue 22's check list").
#include "mesohex/stages/docked_walls.h"
#include "mesohex/stages/skeleton_analysis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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
    std::vector<int> degree;   // all edges, leaflet sides included
    std::vector<bool> frozen;  // not scanned: the roots of side stubs (their pairs are the stub's own repair)
    std::vector<bool> merged;  // balls t made by a merge: no further merge at them (as c or as b)
    std::vector<int> trunks;   // per vertex: trunks built at it as c (valley_trunks_per_point)
    // per vertex: the unit directions of the trunks built at it as c, and whether each is a valley trunk
    // (valley_trunks_apart)
    std::vector<std::vector<std::pair<Vec3, bool>>> trunk_dirs;
};

// Fills g for s, reusing g's arrays (called once per repair round).
void make_graph(const Skeleton& s, Graph& g) {
    const int n = static_cast<int>(s.points.size());
    g.inc.resize(n);
    for (std::vector<int>& inc : g.inc) inc.clear();
    g.on_face.assign(n, false);
    g.degree.assign(n, 0);
    std::vector<std::pair<int, int>> sides;  // sorted: binary search
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i) {
            if (f[i] < 0 || f[i] >= n) continue;
            g.on_face[f[i]] = true;
            sides.push_back(std::minmax(f[i], f[(i + 1) % f.size()]));
        }
    std::sort(sides.begin(), sides.end());
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e) {
        const auto [a, b] = s.edges[e];
        if (a < 0 || a >= n || b < 0 || b >= n || a == b) continue;
        ++g.degree[a], ++g.degree[b];
        if (std::binary_search(sides.begin(), sides.end(), std::pair<int, int>(std::minmax(a, b)))) continue;
        g.inc[a].push_back(e);
        g.inc[b].push_back(e);
    }
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

// at_arc given `above`: the first position of w.s whose arc length is above t (clamped), i.e. std::upper_bound's.
AtArc at_arc_above(const Skeleton& s, const Walk& w, double t, std::size_t above) {
    const std::size_t last = w.verts.size() - 1;
    t = std::clamp(t, 0.0, w.length());
    std::size_t k = above;
    k = k == 0 ? 0 : std::min(k - 1, last - 1);
    const double len = w.s[k + 1] - w.s[k];
    const double u = len > 0 ? std::clamp((t - w.s[k]) / len, 0.0, 1.0) : 0.0;
    const int a = w.verts[k], b = w.verts[k + 1];
    return {s.points[a] + u * (s.points[b] - s.points[a]), s.radii[a] + u * (s.radii[b] - s.radii[a]), k, u};
}

AtArc at_arc(const Skeleton& s, const Walk& w, double t) {
    const double c = std::clamp(t, 0.0, w.length());
    return at_arc_above(s, w, t, static_cast<std::size_t>(std::upper_bound(w.s.begin(), w.s.end(), c) - w.s.begin()));
}

// at_arc for a t at least as large as the one that left `above` (0 at first): walks `above` up from there to t's
// position (w.s is non-decreasing, so the same position as std::upper_bound's) and leaves it there.
AtArc at_arc_from(const Skeleton& s, const Walk& w, double t, std::size_t& above) {
    const double c = std::clamp(t, 0.0, w.length());
    while (above < w.s.size() && !(w.s[above] > c)) ++above;
    return at_arc_above(s, w, t, above);
}

// What a repair does to a close pair (see the header).
enum class PairRepair {
    trunk,      // the tubes separate: a trunk vertex on the pair's medial axis
    stub,       // the shorter branch ends at an extremity inside the other's tube: absorbed
    merge,      // the shorter branch ends at a branching point inside the other's tube: absorbed, its children leave t
    side,       // a stub whose end lies far off the other branch: kept as a side branch of it (side_stub_reach)
    main_stub,  // a stub fatter than the other branch at a degree-3 point: the other rooted on it (fat_stub_main_line)
};

struct Candidate {
    double score = 0;              // x / r_c (trunk), length of the absorbed walk / r_c (stub, merge)
    int c = -1, ei = -1, ej = -1;  // ej: the absorbed walk (stub, merge)
    double sep = 0;                // l*: arc length where the tubes separate (trunk); the absorbed walk's length
    Vec3 t;
    double rt = 0;
    PairRepair kind = PairRepair::trunk;
    bool valley = false;  // a valley trunk (valley_trunk_degree)
};

bool is_extremity(const Graph& g, int v) { return g.degree[v] == 1 && !g.on_face[v]; }

// The point of walk w's polyline nearest p (the first of equals): its arc length and segment (AtArc::k, u).
AtArc nearest_on_walk(const Skeleton& s, const Walk& w, const Vec3& p, double& arc) {
    AtArc best;
    double best_d = 1e300;
    arc = 0;
    for (std::size_t k = 0; k + 1 < w.verts.size(); ++k) {
        const Vec3 a = s.points[w.verts[k]], b = s.points[w.verts[k + 1]];
        const double l2 = dot(b - a, b - a);
        const double u = l2 > 0 ? std::clamp(dot(p - a, b - a) / l2, 0.0, 1.0) : 0.0;
        const Vec3 x = a + u * (b - a);
        const double d = distance(x, p);
        if (d < best_d) {
            best_d = d;
            best = {x, s.radii[w.verts[k]] + u * (s.radii[w.verts[k + 1]] - s.radii[w.verts[k]]), k, u};
            arc = w.s[k] + u * (w.s[k + 1] - w.s[k]);
        }
    }
    return best;
}

// How fast the tube gap (distance of the axes minus the sum of the radii) of walk w and any other walk can rise per
// unit of arc length on w's side: per segment, at_arc's point moves by its chord and its radius by its change over the
// segment's arc length (1 + the radius slope, up to the roundings of w.s); the steepest segment's. Infinity when a
// segment has zero arc length (at_arc jumps there).
double gap_slope(const Skeleton& s, const Walk& w) {
    double slope = 0;
    for (std::size_t k = 0; k + 1 < w.verts.size(); ++k) {
        const int a = w.verts[k], b = w.verts[k + 1];
        const double len = w.s[k + 1] - w.s[k];
        if (!(len > 0)) return std::numeric_limits<double>::infinity();
        slope = std::max(slope, (distance(s.points[a], s.points[b]) + std::abs(s.radii[b] - s.radii[a])) / len);
    }
    return slope;
}

// The largest coordinate or radius magnitude on walk w: the scale of the roundings of at_arc and distance on it.
double walk_extent(const Skeleton& s, const Walk& w) {
    double m = 0;
    for (const int v : w.verts)
        m = std::max({m, std::abs(s.points[v].x), std::abs(s.points[v].y), std::abs(s.points[v].z), s.radii[v]});
    return m;
}

// The arc length where the tubes of walks i and j separate, or -1 if they do not before the shorter one ends.
// The arc lengths it tries grow (the scan) or stay at or above lo (the bisection), so each walk's segment is found
// from the last one at lo (at_arc_from) rather than by a binary search: the same segments, the same values. The scan
// skips the steps that provably do not part the tubes (gap_slope): the same lo, the same result.
double separation(const Skeleton& s, const Walk& wi, const Walk& wj) {
    const double len = std::min(wi.length(), wj.length());
    std::array<std::size_t, 2> at_lo{0, 0};  // per walk: at_arc_from's position for lo
    double gap = 0;                          // of the last `apart`: the distance of the axes minus the radii
    const auto apart = [&](double t, std::array<std::size_t, 2>& at) {
        const AtArc a = at_arc_from(s, wi, t, at[0]), b = at_arc_from(s, wj, t, at[1]);
        const double d = distance(a.x, b.x), r = a.r + b.r;
        gap = d - r;
        return d >= r;
    };
    const double slope = (gap_slope(s, wi) + gap_slope(s, wj)) * (1 + 1e-6);
    const double slack = 1e-9 * std::max(walk_extent(s, wi), walk_extent(s, wj));
    constexpr int steps = 128;
    double lo = 0;
    for (int k = 1; k <= steps; ++k) {
        const double t = len * k / steps;
        std::array<std::size_t, 2> at_t = at_lo;
        if (!apart(t, at_t)) {
            lo = t;
            at_lo = at_t;
            // The next steps whose gap cannot have risen to -slack are not apart either: lo moves to the last of them.
            int last = k;
            while (last < steps && gap + slope * (len * (last + 1) / steps - t) < -slack) ++last;
            if (last > k) lo = len * last / steps;
            k = last;
            continue;
        }
        double hi = t;
        for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            std::array<std::size_t, 2> at_mid = at_lo;
            if (apart(mid, at_mid)) {
                hi = mid;
            } else {
                lo = mid;
                at_lo = at_mid;
            }
        }
        return hi;
    }
    return -1;
}

// Root patch splits (SkeletonRepairOptions::root_patch_factor).
using EdgeKey = std::pair<int, int>;  // (min, max) of a leaflet side

// A strip's cut on one edge: the new point at t from vertex `from`.
struct Cut {
    int from = -1;
    double t = 0;
    int vertex = -1;  // index of the new point, once created
};

struct Leaflets {
    std::map<EdgeKey, std::vector<int>> side_faces;  // side -> faces having it (quads only)
    std::vector<int> faces_at;                       // per vertex: faces containing it
};

Leaflets make_leaflets(const Skeleton& s) {
    Leaflets l;
    l.faces_at.assign(s.points.size(), 0);
    for (int f = 0; f < static_cast<int>(s.faces.size()); ++f)
        for (int i = 0; i < 4; ++i) {
            ++l.faces_at[s.faces[f][i]];
            l.side_faces[std::minmax(s.faces[f][i], s.faces[f][(i + 1) % 4])].push_back(f);
        }
    return l;
}

// Marks the strip through the oriented edge (a, b) (cut at t from a): every edge reached through opposite sides of
// quads, each with the same t from its vertex on a's side. Edges already cut keep their cut and stop the walk there.
void mark_strip(const Skeleton& s, const Leaflets& l, int a, int b, double t, std::map<EdgeKey, Cut>& cuts) {
    std::vector<std::pair<int, int>> todo{{a, b}};
    while (!todo.empty()) {
        const auto [p, q] = todo.back();
        todo.pop_back();
        const auto [it, fresh] = cuts.insert({std::minmax(p, q), Cut{p, t, -1}});
        if (!fresh) continue;
        const auto sf = l.side_faces.find(it->first);
        if (sf == l.side_faces.end()) continue;
        for (const int fi : sf->second) {
            const std::vector<int>& f = s.faces[fi];
            for (int i = 0; i < 4; ++i) {
                const int x = f[i], y = f[(i + 1) % 4];
                if (x == p && y == q) todo.push_back({f[(i + 3) % 4], f[(i + 2) % 4]});
                if (x == q && y == p) todo.push_back({f[(i + 2) % 4], f[(i + 3) % 4]});
            }
        }
    }
}

// Parameter of edge (x, y)'s cut measured from x.
double cut_from(const Cut& c, int x) { return c.from == x ? c.t : 1 - c.t; }

// Splits every marked edge and every face crossed by a marked strip (see the header's output order).
void apply_cuts(Skeleton& s, std::map<EdgeKey, Cut>& cuts) {
    const auto place = [&s](Cut& c, int b) {  // the new point of edge (c.from, b)
        const int a = c.from;
        c.vertex = static_cast<int>(s.points.size());
        s.points.push_back(s.points[a] + c.t * (s.points[b] - s.points[a]));
        s.radii.push_back(s.radii[a] + c.t * (s.radii[b] - s.radii[a]));
    };
    std::vector<std::array<int, 2>> edges;
    for (const std::array<int, 2>& e : s.edges) {
        const auto it = cuts.find(std::minmax(e[0], e[1]));
        if (it == cuts.end() || e[0] == e[1]) {
            edges.push_back(e);
            continue;
        }
        Cut& c = it->second;
        if (c.vertex < 0) place(c, c.from == e[0] ? e[1] : e[0]);
        edges.push_back({e[0], c.vertex});
        edges.push_back({c.vertex, e[1]});
    }
    for (auto& [key, c] : cuts)  // a side missing from s.edges (not from the readers): its point all the same
        if (c.vertex < 0) place(c, c.from == key.first ? key.second : key.first);
    const auto cut = [&](int x, int y) -> const Cut* {
        const auto it = cuts.find(std::minmax(x, y));
        return it == cuts.end() || it->second.vertex < 0 ? nullptr : &it->second;
    };
    const std::size_t nf = s.faces.size();
    for (std::size_t fi = 0; fi < nf; ++fi) {
        std::vector<int> f = s.faces[fi];
        const bool along = cut(f[0], f[1]) && cut(f[3], f[2]);   // sides 0 and 2
        const bool across = cut(f[1], f[2]) && cut(f[0], f[3]);  // sides 1 and 3
        if (!along && !across) continue;
        if (along != across) {
            if (across) f = {f[1], f[2], f[3], f[0]};
            const int m01 = cut(f[0], f[1])->vertex, m32 = cut(f[3], f[2])->vertex;
            s.faces[fi] = {f[0], m01, m32, f[3]};
            s.faces.push_back({m01, f[1], f[2], m32});
            edges.push_back({m01, m32});
            continue;
        }
        const Cut *c01 = cut(f[0], f[1]), *c32 = cut(f[3], f[2]), *c03 = cut(f[0], f[3]), *c12 = cut(f[1], f[2]);
        const double u = 0.5 * (cut_from(*c01, f[0]) + cut_from(*c32, f[3]));
        const double w = 0.5 * (cut_from(*c03, f[0]) + cut_from(*c12, f[1]));
        const std::array<double, 4> k{(1 - u) * (1 - w), u * (1 - w), u * w, (1 - u) * w};  // bilinear weights
        Vec3 x{};
        double r = 0;
        for (int i = 0; i < 4; ++i) {
            x = x + k[i] * s.points[f[i]];
            r += k[i] * s.radii[f[i]];
        }
        const int c = static_cast<int>(s.points.size());
        s.points.push_back(x);
        s.radii.push_back(r);
        const int m01 = c01->vertex, m12 = c12->vertex, m32 = c32->vertex, m03 = c03->vertex;
        s.faces[fi] = {f[0], m01, c, m03};
        s.faces.push_back({m01, f[1], m12, c});
        s.faces.push_back({c, m12, f[2], m32});
        s.faces.push_back({m03, c, m32, f[3]});
        for (const int m : {m01, m12, m32, m03}) edges.push_back({m, c});
    }
    s.edges = std::move(edges);
}

// Whether a strip split by `factor` applies to s at all: factor > 0, radii, and only quads with valid vertex ids
// (analysis rejects other leaflet faces).
bool strips_splittable(const Skeleton& s, double factor) {
    const int n = static_cast<int>(s.points.size());
    if (!(factor > 0) || s.faces.empty() || s.radii.size() != s.points.size()) return false;
    for (const std::vector<int>& f : s.faces) {
        if (f.size() != 4) return false;
        for (const int v : f)
            if (v < 0 || v >= n) return false;
    }
    return true;
}

// Splits the strips around every interior leaflet vertex rooting one branch (SkeletonRepairOptions::
// root_patch_factor). Returns the number of strips split.
int split_root_patches(Skeleton& s, double factor) {
    const int n = static_cast<int>(s.points.size());
    if (!strips_splittable(s, factor)) return 0;
    if (!has_edge_off_faces(s)) return 0;  // a root has a branch edge
    const Leaflets l = make_leaflets(s);
    std::vector<std::vector<int>> side_nb(n), branch_nb(n);
    for (const std::array<int, 2>& e : s.edges) {
        if (e[0] < 0 || e[0] >= n || e[1] < 0 || e[1] >= n || e[0] == e[1]) continue;
        const auto sf = l.side_faces.find(std::minmax(e[0], e[1]));
        for (int k = 0; k < 2; ++k) {
            if (sf == l.side_faces.end())
                branch_nb[e[k]].push_back(e[1 - k]);
            else if (sf->second.size() == 2)
                side_nb[e[k]].push_back(e[1 - k]);
            else
                branch_nb[e[k]].push_back(-1);  // a border or non-manifold side: not interior
        }
    }
    std::map<EdgeKey, Cut> cuts;
    int strips = 0;
    for (int v = 0; v < n; ++v) {
        // Interior: 4 faces, 4 sides each between two faces, no border side (counted as -1 in branch_nb).
        if (l.faces_at[v] != 4 || side_nb[v].size() != 4 || branch_nb[v].size() != 1 || branch_nb[v][0] < 0) continue;
        const double target = factor * std::max(s.radii[v], s.radii[branch_nb[v][0]]);
        std::vector<int> nb = side_nb[v];
        std::sort(nb.begin(), nb.end());
        for (const int u : nb) {
            const double d = distance(s.points[u], s.points[v]);
            if (!(d > target) || cuts.count(std::minmax(u, v))) continue;
            mark_strip(s, l, v, u, std::min(0.5, target / d), cuts);
            ++strips;
        }
    }
    if (strips) apply_cuts(s, cuts);
    return strips;
}

// The leaflets of docked walls' plates: the face strips split by docked_foot_split and what decides them. A chain
// vertex u: 1 or 2 of its sides shared by 3 or more faces (the chain sides). Its plate: the leaflet (faces joined
// through sides of exactly 2 faces) with 2 faces at a chain side (a regular fan, which cuts its leaflets, has none).
struct DockedPlates {
    Leaflets l;
    std::vector<int> leaflet;             // per face: its leaflet (the lowest face id in it)
    std::vector<std::vector<int>> sides;  // per vertex: its face sides' other ends
    std::vector<std::vector<int>> chain;  // per vertex: its chain sides' other ends
    std::vector<int> plate;               // per vertex: its plate (-1: none)
    std::vector<char> branch;             // per vertex: 1 when a branch edge (not a face side) ends there
    std::vector<char> across;             // per vertex: 1 on a chain whose plate halves were joined
};

const std::vector<int>& faces_of(const DockedPlates& dp, int a, int b) { return dp.l.side_faces.at(std::minmax(a, b)); }

// Per face: its leaflet as the analysis finds it (faces joined through sides of exactly 2 faces), named by its lowest
// face, after the analysis' joins across chains (join_plates_across_chains, docked_walls.h: a chain from border to
// border cuts its plate into two leaflets; when a leaflet stops on it, a wall across the plate with a shorter wall on
// the other side, the analysis joins the halves and docks the chain). The same test as the analysis', so that the feet
// are split exactly on the chains it docks. across: per vertex, 1 on such a chain.
std::vector<int> docked_leaflets(const Skeleton& s, std::vector<char>& across) {
    across.assign(s.points.size(), 0);
    SkeletonAnalysis an = analyze_leaflets(s);
    const std::vector<char> joined = join_plates_across_chains(s, an);
    for (std::size_t e = 0; e < joined.size(); ++e)
        if (joined[e]) across[s.edges[e][0]] = across[s.edges[e][1]] = 1;
    std::vector<int> leaflet(s.faces.size());
    for (std::size_t f = 0; f < leaflet.size(); ++f) leaflet[f] = an.leaflets[an.face_leaflet[f]].faces.front();
    return leaflet;
}

DockedPlates docked_plates(const Skeleton& s) {
    const int n = static_cast<int>(s.points.size());
    DockedPlates dp;
    dp.l = make_leaflets(s);
    dp.leaflet = docked_leaflets(s, dp.across);
    dp.sides.resize(n);
    for (const auto& [key, fs] : dp.l.side_faces) {
        dp.sides[key.first].push_back(key.second);
        dp.sides[key.second].push_back(key.first);
    }
    dp.branch.assign(n, 0);
    for (const std::array<int, 2>& e : s.edges)
        if (e[0] >= 0 && e[0] < n && e[1] >= 0 && e[1] < n && !dp.l.side_faces.count(std::minmax(e[0], e[1])))
            dp.branch[e[0]] = dp.branch[e[1]] = 1;
    dp.chain.resize(n);
    dp.plate.assign(n, -1);
    for (int u = 0; u < n; ++u)
        for (const int v : dp.sides[u])
            if (faces_of(dp, u, v).size() >= 3) dp.chain[u].push_back(v);
    for (int u = 0; u < n; ++u) {
        for (const int w : dp.chain[u]) {
            std::map<int, int> per_leaflet;
            for (const int f : faces_of(dp, u, w)) ++per_leaflet[dp.leaflet[f]];
            for (const auto& [id, count] : per_leaflet)
                if (count == 2) dp.plate[u] = id;
        }
    }
    return dp;
}

// Whether the side (u, v) is shared by exactly 2 faces of u's plate.
bool plate_side(const DockedPlates& dp, int u, int v) {
    const std::vector<int>& fs = faces_of(dp, u, v);
    return fs.size() == 2 && dp.leaflet[fs[0]] == dp.plate[u] && dp.leaflet[fs[1]] == dp.plate[u];
}

// An inside end of a docked chain: a vertex on one chain side whose plate goes on past it (a side of 2 plate faces
// sharing no face with the chain side).
bool inside_end(const DockedPlates& dp, int u) {
    if (dp.chain[u].size() != 1 || dp.plate[u] < 0) return false;
    const std::vector<int>& cf = faces_of(dp, u, dp.chain[u][0]);
    for (const int v : dp.sides[u]) {
        if (!plate_side(dp, u, v)) continue;
        const std::vector<int>& fs = faces_of(dp, u, v);
        if (std::none_of(fs.begin(), fs.end(), [&](int f) { return std::find(cf.begin(), cf.end(), f) != cf.end(); }))
            return true;
    }
    return false;
}

// Per vertex: 1 on a docked chain (vertices joined by chain sides, with an inside end, or across a plate whose halves
// were joined). Not a closed chain (e.g.
// torustwist's core, whose opposite arms are one leaflet) nor a fan cutting its leaflets.
std::vector<char> docked_chain_vertices(const DockedPlates& dp) {
    const int n = static_cast<int>(dp.chain.size());
    std::vector<char> docked(n, 0);
    for (int e = 0; e < n; ++e) {
        if (docked[e] || !(inside_end(dp, e) || dp.across[e])) continue;
        std::vector<int> todo{e};
        docked[e] = 1;
        while (!todo.empty()) {
            const int u = todo.back();
            todo.pop_back();
            for (const int w : dp.chain[u])
                if (!docked[w]) docked[w] = 1, todo.push_back(w);
        }
    }
    return docked;
}

// A side's wall ending at u inside the chain (the other side's wall goes on): the chain side with fewer faces is the
// foot beyond that wall's end, split like the plate's strip beyond an inside end (through the plate and the walls that
// go on). Returns 1 when it marked a strip.
int split_beyond_wall_end(const Skeleton& s, const DockedPlates& dp, int u, double factor,
                          std::map<EdgeKey, Cut>& cuts) {
    if (dp.chain[u].size() != 2) return 0;
    const std::size_t n0 = faces_of(dp, u, dp.chain[u][0]).size(), n1 = faces_of(dp, u, dp.chain[u][1]).size();
    if (n0 == n1) return 0;
    const int v = dp.chain[u][n0 < n1 ? 0 : 1];
    const double d = distance(s.points[u], s.points[v]);
    const double target = factor * s.radii[u];
    if (!(d > target) || cuts.count(std::minmax(u, v))) return 0;
    mark_strip(s, dp.l, u, v, std::min(0.5, target / d), cuts);
    return 1;
}

// Narrows the feet of docked walls (SkeletonRepairOptions::docked_foot_split). At every vertex u of a docked chain
// (docked_chain_vertices) without a branch edge, every side (u, v) of 2 faces of u's plate, v not on the chain, has its
// strip split at factor x r_u from u: beside the chain when the side shares a face with a chain side, beyond an inside
// end otherwise; and where one side's wall ends at u inside the chain (its two chain sides have different face
// counts), the chain side with fewer faces at factor x r_u from u (the foot beyond that wall's end). A side to a band
// copy (band[v], pillow_docked_bands) is left: the band is the foot. Returns the number of strips split.
int split_docked_feet(Skeleton& s, double factor, const std::vector<char>& band) {
    if (!strips_splittable(s, factor) || !has_side_of_three_faces(s)) return 0;  // a docked chain is a fan line
    const DockedPlates dp = docked_plates(s);
    const std::vector<char> docked = docked_chain_vertices(dp);
    std::map<EdgeKey, Cut> cuts;
    int strips = 0;
    for (int u = 0; u < static_cast<int>(s.points.size()); ++u) {
        if (dp.branch[u] || !docked[u] || dp.chain[u].size() > 2 || dp.plate[u] < 0) continue;
        for (const int v : dp.sides[u]) {
            if (!plate_side(dp, u, v) || cuts.count(std::minmax(u, v))) continue;
            if (static_cast<std::size_t>(v) < band.size() && band[v]) continue;  // the band pillow's side: as wide
            const double d = distance(s.points[u], s.points[v]);
            const double target = factor * s.radii[u];
            if (!(d > target)) continue;
            mark_strip(s, dp.l, u, v, std::min(0.5, target / d), cuts);
            ++strips;
        }
        strips += split_beyond_wall_end(s, dp, u, factor, cuts);
    }
    if (strips) apply_cuts(s, cuts);
    return strips;
}

// Band pillow (SkeletonRepairOptions::docked_band_pillow). The band's width factor without a foot split: the copies
// then lie half the shortest side from their vertex.
constexpr double kUnboundedBand = 1e6;

// Per vertex: the faces containing it, in face order.
std::vector<std::vector<int>> faces_at_vertices(const Skeleton& s) {
    std::vector<std::vector<int>> at(s.points.size());
    for (int f = 0; f < static_cast<int>(s.faces.size()); ++f)
        for (const int v : s.faces[f]) at[v].push_back(f);
    return at;
}

bool has_face(const std::vector<int>& fs, int f) { return std::find(fs.begin(), fs.end(), f) != fs.end(); }

// Whether chain vertex u's plate grid matches a docked wall's foot, the analysis' condition (docked_walls.h): 2 chain
// sides and 4 plate faces, each on one chain side; or 1 chain side with 4 plate faces and no border side, or 2 faces
// and 2 border sides.
bool foot_matches(const DockedPlates& dp, const std::vector<std::vector<int>>& at, int u) {
    const int nc = static_cast<int>(dp.chain[u].size());
    int faces = 0, border = 0;
    bool straight = true;
    for (const int f : at[u]) {
        if (dp.leaflet[f] != dp.plate[u]) continue;
        ++faces;
        int on = 0;
        for (const int w : dp.chain[u]) on += has_face(faces_of(dp, u, w), f) ? 1 : 0;
        straight = straight && on <= 1 && (nc == 1 || on == 1);
    }
    for (const int v : dp.sides[u]) {
        const std::vector<int>& fs = faces_of(dp, u, v);
        border += fs.size() == 1 && dp.leaflet[fs[0]] == dp.plate[u] ? 1 : 0;
    }
    return docked_foot_matches(nc, faces, border, straight);
}

// A vertex on plate P's border: a side of exactly one face, of P.
bool plate_border_vertex(const DockedPlates& dp, int v, int P) {
    for (const int w : dp.sides[v]) {
        const std::vector<int>& fs = faces_of(dp, v, w);
        if (fs.size() == 1 && dp.leaflet[fs[0]] == P) return true;
    }
    return false;
}

// The plate side of x that continues the side (p, x) straight through P's grid: x has 4 faces of P, and exactly one of
// its sides of 2 faces of P, other than (p, x), shares no face with (p, x). -1 when there is none.
int straight_on(const DockedPlates& dp, const std::vector<std::vector<int>>& at, int p, int x, int P) {
    int plate_faces = 0;
    for (const int f : at[x]) plate_faces += dp.leaflet[f] == P ? 1 : 0;
    if (plate_faces != 4) return -1;
    const std::vector<int>& pf = faces_of(dp, p, x);
    int y = -1, found = 0;
    for (const int v : dp.sides[x]) {
        const std::vector<int>& fs = faces_of(dp, x, v);
        if (v == p || fs.size() != 2 || dp.leaflet[fs[0]] != P || dp.leaflet[fs[1]] != P) continue;
        if (!has_face(pf, fs[0]) && !has_face(pf, fs[1])) y = v, ++found;
    }
    return found == 1 ? y : -1;
}

// The band's path: a docked chain from its end e (vertices joined by chain sides), run on straight through the plate's
// grid beyond every end inside the plate up to its border (through vertices of 4 plate faces only, no branch, no
// other chain, no vertex twice). Empty when the chain is not a simple path or cannot run on.
std::vector<int> band_path(const DockedPlates& dp, const std::vector<std::vector<int>>& at,
                           const std::vector<char>& docked, int e) {
    const int P = dp.plate[e];
    std::vector<int> path{e};
    for (int prev = -1, u = e;;) {  // the chain
        int next = -1;
        for (const int w : dp.chain[u])
            if (w != prev) next = w;
        if (dp.chain[u].size() > 2 || dp.plate[u] != P || dp.branch[u]) return {};
        if (next < 0) break;
        if (std::find(path.begin(), path.end(), next) != path.end()) return {};
        path.push_back(next);
        prev = u, u = next;
    }
    const auto run_on = [&](std::vector<int>& p) {  // beyond p.back(), coming from p[p.size() - 2]
        while (!plate_border_vertex(dp, p.back(), P)) {
            const int y = straight_on(dp, at, p[p.size() - 2], p.back(), P);
            if (y < 0 || docked[y] || dp.branch[y] || std::find(p.begin(), p.end(), y) != p.end()) return false;
            for (const int f : at[y])
                if (dp.leaflet[f] != P) return false;
            p.push_back(y);
        }
        return true;
    };
    if (path.size() < 2 || !run_on(path)) return {};
    std::reverse(path.begin(), path.end());
    if (!run_on(path)) return {};
    return path;
}

// Unit direction from side (a, b) into face f, perpendicular to the side (towards the opposite side's midpoint).
Vec3 into_quad(const Skeleton& s, int f, int a, int b) {
    const Vec3 t = normalized(s.points[b] - s.points[a]);
    Vec3 c{};
    for (const int v : s.faces[f])
        if (v != a && v != b) c = c + 0.5 * s.points[v];
    const Vec3 d = c - 0.5 * (s.points[a] + s.points[b]);
    return normalized(d - dot(d, t) * t);
}

// The plate faces at path vertex path[i] on one side of the path: those joined to face f0 through sides at it that are
// not path sides.
std::vector<int> band_arc(const Skeleton& s, const DockedPlates& dp, const std::vector<std::vector<int>>& at,
                          const std::vector<int>& path, std::size_t i, int f0) {
    const int v = path[i], P = dp.leaflet[f0];
    const auto path_side = [&](int w) {
        return (i > 0 && path[i - 1] == w) || (i + 1 < path.size() && path[i + 1] == w);
    };
    std::vector<int> arc{f0};
    for (std::size_t k = 0; k < arc.size(); ++k) {
        const std::vector<int>& f = s.faces[arc[k]];
        const int c = static_cast<int>(std::find(f.begin(), f.end(), v) - f.begin());
        for (const int w : {f[(c + 1) % 4], f[(c + 3) % 4]}) {
            if (path_side(w)) continue;
            for (const int g : faces_of(dp, v, w))
                if (dp.leaflet[g] == P && has_face(at[v], g) && !has_face(arc, g)) arc.push_back(g);
        }
    }
    std::sort(arc.begin(), arc.end());
    return arc;
}

// One side of a band path: per path vertex its faces on that side, per path edge its face there.
struct BandSide {
    std::vector<std::vector<int>> arcs;
    std::vector<int> edge_face;
};

// The two sides of the path on plate P (plus: the face containing the directed first side, else the first face), or
// false when a path side is not shared by 2 faces of the plate or a vertex's faces do not part in two at the path.
bool band_sides(const Skeleton& s, const DockedPlates& dp, const std::vector<std::vector<int>>& at,
                const std::vector<int>& path, int P, std::array<BandSide, 2>& sides) {
    std::vector<std::array<int, 2>> ef;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        std::vector<int> fs;
        for (const int f : faces_of(dp, path[i], path[i + 1]))
            if (dp.leaflet[f] == P) fs.push_back(f);
        if (fs.size() != 2) return false;
        ef.push_back({fs[0], fs[1]});
    }
    const std::vector<int>& f0 = s.faces[ef[0][1]];
    for (int k = 0; k < 4; ++k)
        if (f0[k] == path[0] && f0[(k + 1) % 4] == path[1]) std::swap(ef[0][0], ef[0][1]);
    for (BandSide& side : sides) side = BandSide{std::vector<std::vector<int>>(path.size()), {}};
    for (std::size_t i = 0; i < path.size(); ++i) {
        const std::size_t e = i == 0 ? 0 : i - 1;  // the path edge whose sides are known at vertex i
        for (int k = 0; k < 2; ++k) sides[k].arcs[i] = band_arc(s, dp, at, path, i, ef[e][k]);
        if (has_face(sides[1].arcs[i], ef[e][0])) return false;  // one side all around: not parted
        if (i == 0 || i + 1 == path.size()) continue;
        const bool first = has_face(sides[0].arcs[i], ef[i][0]), second = has_face(sides[0].arcs[i], ef[i][1]);
        if (first == second) return false;
        if (second) std::swap(ef[i][0], ef[i][1]);
    }
    for (const std::array<int, 2>& x : ef)
        for (int k = 0; k < 2; ++k) sides[k].edge_face.push_back(x[k]);
    return true;
}

// The direction of path vertex i's copy on side k, per unit of band width: the miter of the side's directions into
// its faces at an inner vertex (1 / cos of half the turn long), along its border side on that side at a path end (1 /
// cos of the border's angle off the side's direction long). False for a turn sharper than acos(kBandPillowMinTurnCos)
// (104.5 degrees, docked_walls.h) or a
// border leaving the path at a grazing angle.
bool band_copy(const Skeleton& s, const DockedPlates& dp, const std::vector<int>& path, const BandSide& side,
               std::size_t i, Vec3& m) {
    const int v = path[i];
    const auto into = [&](std::size_t e) { return into_quad(s, side.edge_face[e], path[e], path[e + 1]); };
    if (i > 0 && i + 1 < path.size()) {
        const Vec3 d1 = into(i - 1), d2 = into(i);
        if (!(dot(d1, d2) > kBandPillowMinTurnCos)) return false;
        m = (1 / (1 + dot(d1, d2))) * (d1 + d2);
        return true;
    }
    const Vec3 d = into(i == 0 ? 0 : i - 1);
    for (const int b : dp.sides[v]) {
        const std::vector<int>& fs = faces_of(dp, v, b);
        if (fs.size() != 1 || !has_face(side.arcs[i], fs[0])) continue;
        const Vec3 along = normalized(s.points[b] - s.points[v]);
        const double c = dot(along, d);
        if (!(c > 0.3)) return false;
        m = (1 / c) * along;
        return true;
    }
    return false;
}

// Pillows the band of `path` in place: every path vertex v gets a copy on each side (band_copy, radius r_v), the
// plate faces at v on that side take the copy instead of v, and every path side (p, q) two new faces (p, q, q', p')
// oriented like the side's old faces; new edges (v, v') and (p', q'). copies: set to 1 for every new vertex. False
// (s untouched) when a copy cannot be placed.
bool pillow_band(Skeleton& s, const DockedPlates& dp, const std::vector<int>& path,
                 const std::array<BandSide, 2>& sides, double factor, std::vector<char>& copies) {
    const int n0 = static_cast<int>(s.points.size()), np = static_cast<int>(path.size());
    // The width: factor x r_v, at most, along the whole path, half of every path vertex's shortest plate side off the
    // path divided by |m|^2 (the copy at most half that side / |m| from v: at a right turn a quarter of the side, half
    // way to where the outer face's diagonal crosses).
    std::vector<Vec3> m(2 * np);
    double cap = 1e300;
    for (int i = 0; i < np; ++i) {
        const int v = path[i];
        double shortest = 1e300;
        for (const int x : dp.sides[v]) {
            const bool on_plate = std::any_of(faces_of(dp, v, x).begin(), faces_of(dp, v, x).end(), [&](int f) {
                return has_face(sides[0].arcs[i], f) || has_face(sides[1].arcs[i], f);
            });
            if (on_plate && (i == 0 || x != path[i - 1]) && (i + 1 == np || x != path[i + 1]))
                shortest = std::min(shortest, distance(s.points[v], s.points[x]));
        }
        for (int k = 0; k < 2; ++k) {
            if (!band_copy(s, dp, path, sides[k], i, m[2 * i + k])) return false;
            cap = std::min(cap, 0.5 * shortest / dot(m[2 * i + k], m[2 * i + k]));
        }
    }
    std::vector<Vec3> at(2 * np);
    for (int i = 0; i < np; ++i)
        for (int k = 0; k < 2; ++k)
            at[2 * i + k] = s.points[path[i]] + std::min(factor * s.radii[path[i]], cap) * m[2 * i + k];
    const auto copy = [&](int i, int k) { return n0 + 2 * i + k; };
    const auto index = [&](int v) { return static_cast<int>(std::find(path.begin(), path.end(), v) - path.begin()); };
    // Every side (v, x) off the path at a path vertex v takes v's copy on the side of its faces.
    const auto side_of = [&](int i, int x) {
        for (const int f : faces_of(dp, path[i], x))
            for (int k = 0; k < 2; ++k)
                if (has_face(sides[k].arcs[i], f)) return k;
        return -1;
    };
    for (std::array<int, 2>& e : s.edges) {
        const std::array<int, 2> old = e;
        for (int j = 0; j < 2; ++j) {
            const int i = index(old[j]);
            if (i == np || (i > 0 && old[1 - j] == path[i - 1]) || (i + 1 < np && old[1 - j] == path[i + 1])) continue;
            if (const int k = side_of(i, old[1 - j]); k >= 0) e[j] = copy(i, k);
        }
    }
    for (int i = 0; i < np; ++i)
        for (int k = 0; k < 2; ++k)
            for (const int f : sides[k].arcs[i])
                std::replace(s.faces[f].begin(), s.faces[f].end(), path[i], copy(i, k));
    for (int i = 0; i < np; ++i)
        for (int k = 0; k < 2; ++k) {
            s.points.push_back(at[2 * i + k]);
            s.radii.push_back(s.radii[path[i]]);
            s.edges.push_back({path[i], copy(i, k)});
        }
    for (int i = 0; i + 1 < np; ++i)
        for (int k = 0; k < 2; ++k) {
            const int p = path[i], q = path[i + 1], pc = copy(i, k), qc = copy(i + 1, k);
            const std::vector<int>& f = s.faces[sides[k].edge_face[i]];
            bool forward = false;  // the old face runs p' -> q': the new one q' -> p'
            for (int c = 0; c < 4; ++c) forward = forward || (f[c] == pc && f[(c + 1) % 4] == qc);
            s.faces.push_back(forward ? std::vector<int>{p, q, qc, pc} : std::vector<int>{q, p, pc, qc});
            s.edges.push_back({pc, qc});
        }
    copies.resize(s.points.size(), 0);
    std::fill(copies.begin() + n0, copies.end(), 1);
    return true;
}

// Pillows the band of every docked chain whose feet do not match its plate's grid (foot_matches fails at a chain
// vertex) and whose band path exists (band_path, band_sides, pillow_band); chains that match are left as they are.
// copies: per vertex of the result, 1 for a band copy. Returns the number of bands pillowed.
int pillow_docked_bands(Skeleton& s, double factor, std::vector<char>& copies) {
    copies.assign(s.points.size(), 0);
    if (!strips_splittable(s, factor) || !has_side_of_three_faces(s)) return 0;
    int bands = 0;
    std::set<int> tried;  // chain ends whose band could not be pillowed
    for (bool again = true; again;) {
        again = false;
        const DockedPlates dp = docked_plates(s);
        const std::vector<char> docked = docked_chain_vertices(dp);
        const std::vector<std::vector<int>> at = faces_at_vertices(s);
        for (int e = 0; e < static_cast<int>(s.points.size()) && !again; ++e) {
            if (!docked[e] || dp.chain[e].size() != 1 || tried.count(e)) continue;
            std::vector<int> path = band_path(dp, at, docked, e);
            bool unmatched = false;
            for (const int u : path) unmatched = unmatched || (docked[u] && !foot_matches(dp, at, u));
            std::array<BandSide, 2> sides;
            if (!unmatched || !band_sides(s, dp, at, path, dp.plate[e], sides) ||
                !pillow_band(s, dp, path, sides, factor, copies)) {
                tried.insert(e);
                continue;
            }
            ++bands;
            tried.insert(e);  // pillowed once at most: the loop ends even if a pillow left a foot unmatched
            again = true;
        }
    }
    copies.resize(s.points.size(), 0);
    return bands;
}

// The shorter walk of a close pair whose tubes do not separate before it ends: a stub (ends at an extremity), a
// merge (ends at a branching point without leaflet whose other edges lead elsewhere than to the pair), or neither.
bool absorbable(const Skeleton& s, const Graph& g, const SkeletonRepairOptions& o, const Walk& shorter,
                const Walk& keep, PairRepair& kind) {
    const int b = shorter.verts.back();
    if (is_extremity(g, b)) {
        kind = PairRepair::stub;
        return o.absorb_stubs;
    }
    kind = PairRepair::merge;
    // A ball made by a merge takes part in no further merge, neither as the pair's point c nor as the merged end b:
    // each merge moves a junction onto a pair's midpoint, and chained merges would walk it along whole branches.
    // Nor is a side stub's root q merged: q lies on the other branch's polyline only to carry the side stub, the branch
    // goes on through it, and merging q would re-root the stub at t, where its end, which side_stub_reach kept off
    // the branch, is absorbed after all (docs/junctions.md, "Merged ends").
    const auto marked = [&](const std::vector<bool>& m, int v) {
        return static_cast<std::size_t>(v) < m.size() && m[v];
    };
    if (!o.merge_branching_ends || marked(g.merged, b) || marked(g.merged, shorter.verts[0]) || marked(g.frozen, b) ||
        g.on_face[b] || g.inc[b].size() < 3 || g.degree[b] != static_cast<int>(g.inc[b].size()) ||
        !(keep.length() > shorter.length()))
        return false;
    // b's other edges must lead away from the pair (no cycle through c, the other walk or this one).
    std::set<int> pair(keep.verts.begin(), keep.verts.end());
    pair.insert(shorter.verts.begin(), shorter.verts.end());
    bool own_edge = false;  // the walk's last edge, into b
    for (const int e : g.inc[b]) {
        const int u = s.edges[e][0] == b ? s.edges[e][1] : s.edges[e][0];
        if (u == shorter.verts[shorter.verts.size() - 2] && !own_edge)
            own_edge = true;
        else if (pair.count(u))
            return false;
    }
    return true;
}

// One branching point's scan: its best repair (ei, ej hold positions in g.inc[c], not edge ids, so the scan stays
// valid when a repair elsewhere renumbers the edges) and its unseparated pairs (positions i < j in g.inc[c]).
struct PointScan {
    Candidate best;
    std::vector<std::pair<int, int>> unseparated;
};

// Whether the two branches leaving a fat stub's new root t (the stub on from t, the thin walk on from its arc l) part
// there: 90 degrees or more apart (to rounding), or their tubes separating before the shorter ends (`separation` on
// the two polylines from t), i.e. t is not itself a close pair that the repair would absorb or trunk again.
bool parted_at_root(const Skeleton& s, const Walk& stub, const Walk& thin, const AtArc& t, double l) {
    Skeleton p;  // the two polylines from t, as a scratch skeleton: t, the stub's vertices after t, then x and on
    Walk a, b;
    const auto add = [&](Walk& w, const Vec3& x, double r) {
        w.s.push_back(w.verts.empty() ? 0 : w.s.back() + distance(p.points[w.verts.back()], x));
        w.verts.push_back(static_cast<int>(p.points.size()));
        p.points.push_back(x);
        p.radii.push_back(r);
    };
    add(a, t.x, t.r);
    for (std::size_t k = t.k + 1; k < stub.verts.size(); ++k) add(a, s.points[stub.verts[k]], s.radii[stub.verts[k]]);
    b.verts.push_back(0);
    b.s.push_back(0);
    const AtArc x = at_arc(s, thin, l);
    add(b, x.x, x.r);
    for (std::size_t k = x.k + 1; k < thin.verts.size(); ++k)
        if (thin.s[k] > l) add(b, s.points[thin.verts[k]], s.radii[thin.verts[k]]);
    if (a.verts.size() < 2 || b.verts.size() < 2 || !(a.length() > 0) || !(b.length() > 0)) return true;
    const Vec3 da = p.points[a.verts[1]] - t.x, db = p.points[b.verts[1]] - t.x;
    // x abeam of t inside a stub segment leaves t at a right angle: 1e-9 keeps rounding from calling it a close pair.
    return dot(da, db) <= 1e-9 * norm(da) * norm(db) || separation(p, a, b) >= 0;
}

// The root of a thin branch on a fat stub (fat_stub_main_line): the first point x of the thin walk's axis (sampled in
// 128 steps from c) whose distance to the stub's polyline reaches the stub's radius at its nearest point; t is that
// nearest point. x moves on to the end of its segment when less than its radius is left of it (no edge shorter than
// its ball). Returns x's arc length on the thin walk, or -1 when the axis never leaves the stub's tube before the thin
// walk ends, t lies inside c's ball, or the stub's end e lies nearer t than min_length x max(r_t, r_e) (the side
// edge's rule, side_stub_min_length).
double main_stub_root(const Skeleton& s, const Walk& stub, const Walk& thin, double min_length, AtArc& t) {
    constexpr int steps = 128;
    const int c = stub.verts[0], e = stub.verts.back();
    double a = 0;
    for (int k = 1; k < steps; ++k) {
        double l = thin.length() * k / steps;
        const AtArc x = at_arc(s, thin, l);
        t = nearest_on_walk(s, stub, x.x, a);
        if (distance(x.x, t.x) < t.r) continue;
        const double seg = thin.s[x.k + 1] - thin.s[x.k];
        if ((1 - x.u) * seg < x.r) l = thin.s[x.k] + (1 - 1e-12) * seg;
        const bool clear = distance(t.x, s.points[e]) >= min_length * std::max(t.r, s.radii[e]);
        if (!(distance(t.x, s.points[c]) > s.radii[c]) || !clear) return -1;
        return parted_at_root(s, stub, thin, t, l) ? l : -1;
    }
    return -1;
}

// The trunk length at a branching point that stays one (degree 4 and more, wide_junction_trunks): x, or, when x is
// below trunk_clearance x (r_c + r_t), the length x' = k (r_c + r) / (1 - k sin a) (k = trunk_clearance) at which
// the trunk edge is just long enough for adaptation to keep it (r_t = r + x' sin a), at most 0.9 l*: the junction
// becomes two branching points of degree 3 (c and t) instead of one of degree 4 and more.
double survivable_trunk(double x, double rc, double r, double sin_a, double sep, const SkeletonRepairOptions& o) {
    const double k = o.trunk_clearance * (1 + 1e-6);  // strictly above: adaptation collapses chord < 0.7 (r_a + r_b)
    if (!o.wide_junction_trunks || x >= k * (rc + r + x * sin_a) || !(k * sin_a < 1)) return x;
    return std::max(x, std::min(k * (rc + r) / (1 - k * sin_a), 0.9 * sep));
}

// A valley trunk (SkeletonRepairOptions::valley_trunk_degree) for a pair whose medial junction lies inside c's ball:
// t at x_v = k (r_c + l*) / (1 + k) along the bisector (k = trunk_clearance, strictly above it as adaptation's
// collapse rule needs), radius r_t = min(l* - x_v, r + x_v sin a): the trunk edge is then k (r_c + r_t) when the
// crotch binds. False (no trunk) when r_t < valley_trunk_min_radius x r_fat (the fatter branch's radius at l*) or
// x_v <= r_c.
bool valley_trunk(double rc, double r, double r_fat, double sin_a, double sep, const SkeletonRepairOptions& o,
                  double& xt, double& rt) {
    const double k = o.trunk_clearance * (1 + 1e-6);
    xt = k * (rc + sep) / (1 + k);
    rt = std::min(sep - xt, r + xt * sin_a);
    const double off = xt * sin_a;  // the tubes' axes' distance from the bisector at t
    if (o.valley_trunk_fit_across) rt = std::min(rt, std::sqrt(std::max(0.0, r * r - off * off)));
    return xt > rc && rt >= o.valley_trunk_min_radius * r_fat && rt > 0;
}

// Whether a trunk from c along unit direction dir (a valley trunk or not) keeps 90 degrees or more from every trunk
// already built at c of which at least one of the two is a valley trunk (SkeletonRepairOptions::valley_trunks_apart).
bool apart_from_trunks(const Graph& g, int c, const Vec3& dir, bool valley) {
    if (static_cast<std::size_t>(c) >= g.trunk_dirs.size()) return true;
    for (const auto& [d, was_valley] : g.trunk_dirs[c])
        if ((valley || was_valley) && dot(d, dir) > 0) return false;
    return true;
}

// The close pair (walks i, j at c): updates scan.best when its repair scores higher; records it in
// scan.unseparated when its tubes do not separate and the shorter walk is not absorbable.
void consider_pair(const Skeleton& s, const Graph& g, const SkeletonRepairOptions& o, int c,
                   const std::vector<int>& inc, const std::vector<Walk>& walks, int i, int j, PointScan& scan) {
    Candidate& best = scan.best;
    const Walk &wi = walks[static_cast<std::size_t>(i)], &wj = walks[static_cast<std::size_t>(j)];
    if (wi.loop || wj.loop || wi.verts[1] == wj.verts[1]) return;
    const double li = wi.s[1], lj = wj.s[1];
    const double ri = s.radii[wi.verts[1]], rj = s.radii[wj.verts[1]];
    if (!(li > 1e-9 * ri) || !(lj > 1e-9 * rj)) return;
    const Vec3 di = (s.points[wi.verts[1]] - s.points[c]) / li;
    const Vec3 dj = (s.points[wj.verts[1]] - s.points[c]) / lj;
    if (dot(di, dj) <= 0) return;  // 90 degrees or more apart: the tubes part at the ball
    const double sep = separation(s, wi, wj);
    if (sep < 0) {
        // The tubes do not separate before the shorter walk ends. A stub or a merge is absorbed: t at the midpoint of
        // its end and the other walk's point at the same arc length, with a radius covering both tubes there.
        const bool i_short = wi.length() <= wj.length();
        const Walk &shorter = i_short ? wi : wj, &keep = i_short ? wj : wi;
        PairRepair kind = PairRepair::stub;
        if (!absorbable(s, g, o, shorter, keep, kind)) {
            scan.unseparated.push_back({i, j});
            return;
        }
        const double len = shorter.length();
        const double score = len / s.radii[c];
        if (kind == PairRepair::stub && o.side_stub_reach > 0) {
            // Far off the other branch: a side branch from its nearest point q (beyond c's ball, before its end).
            const Vec3 e = s.points[shorter.verts.back()];
            double arc = 0;
            const AtArc q = nearest_on_walk(s, keep, e, arc);
            const bool at_end = q.k + 2 == keep.verts.size() && q.u > 1 - 1e-9;
            if (arc > s.radii[c] && !at_end && distance(e, q.x) >= o.side_stub_reach * q.r) {
                // A stub fatter than the other branch at a degree-3 point: the other rooted on it.
                AtArc t;
                const bool fat =
                    o.fat_stub_main_line && inc.size() == 3 && g.degree[c] == 3 && s.radii[shorter.verts.back()] > q.r;
                const double x = fat ? main_stub_root(s, shorter, keep, o.side_stub_min_length, t) : -1;
                if (x > 0) {
                    if (score > best.score)
                        best = {score, c, i_short ? j : i, i_short ? i : j, x, t.x, t.r, PairRepair::main_stub};
                    return;
                }
                if (score > best.score)
                    best = {score, c, i_short ? j : i, i_short ? i : j, arc, q.x, q.r, PairRepair::side};
                return;
            }
        }
        const AtArc a = at_arc(s, shorter, len), b = at_arc(s, keep, len);
        if (score > best.score)
            best = {score,
                    c,
                    i_short ? j : i,
                    i_short ? i : j,
                    len,
                    0.5 * (a.x + b.x),
                    o.absorbed_ball_width * distance(a.x, b.x) + std::max(a.r, b.r),
                    kind};
        return;
    }
    const AtArc a = at_arc(s, wi, sep), b = at_arc(s, wj, sep);
    const double r = 0.5 * (a.r + b.r);
    const double sin_a = std::min(r / sep, 0.99);
    const double x = (sep - r) / (1 + sin_a);
    // c of degree 3 becomes a joint (parent, t): no bridge for adaptation to collapse; t only has to lie outside c's
    // ball (joint_trunks). At degree 4 and more c stays a branching point: the same rule with wide_junction_trunks
    // (adaptation may collapse a short trunk, moving the junction towards the pair), else a long enough bridge.
    const bool c_joint = o.joint_trunks && inc.size() == 3 && g.degree[c] == 3;
    const bool plain = g.degree[c] == static_cast<int>(inc.size());
    const bool ball_rule = c_joint || (o.wide_junction_trunks && inc.size() >= 4 && plain);
    double xt = 0, rt = 0;
    const bool valley = !(ball_rule ? x > s.radii[c] : x >= o.trunk_clearance * (s.radii[c] + r + x * sin_a));
    if (valley) {
        const bool room = o.valley_trunks_per_point <= 0 ||
                          (static_cast<std::size_t>(c) < g.trunks.size() && g.trunks[c] < o.valley_trunks_per_point);
        const bool on = o.valley_trunk_degree > 0 && plain && room &&
                        static_cast<int>(inc.size()) >= std::max(o.valley_trunk_degree, 4);
        if (!on || !valley_trunk(s.radii[c], r, std::max(a.r, b.r), sin_a, sep, o, xt, rt)) return;
    } else {
        xt = c_joint ? x : survivable_trunk(x, s.radii[c], r, sin_a, sep, o);
        rt = r + xt * sin_a;
    }
    const Vec3 m = 0.5 * (a.x + b.x);
    const Vec3 dir = normalized(m - s.points[c]);
    if (dir == Vec3{}) return;
    if (o.valley_trunk_degree > 0 && o.valley_trunks_apart && !apart_from_trunks(g, c, dir, valley)) return;
    const double score = x / s.radii[c];
    if (score > best.score) best = {score, c, i, j, sep, s.points[c] + xt * dir, rt, PairRepair::trunk, valley};
}

// Branching points whose pairs are scanned: no leaflet, 3 or more branch edges, a radius.
bool scanned(const Skeleton& s, const Graph& g, int c) {
    if (static_cast<std::size_t>(c) < g.frozen.size() && g.frozen[c]) return false;
    return !g.on_face[c] && g.inc[c].size() >= 3 && s.radii[c] > 0;
}

// Every pair of branches at c (first best by score, in pair order).
PointScan scan_point(const Skeleton& s, const Graph& g, const SkeletonRepairOptions& o, int c) {
    PointScan scan;
    const std::vector<int>& inc = g.inc[c];
    std::vector<Walk> walks;
    for (const int e : inc) walks.push_back(walk(s, g, c, e));
    const int k = static_cast<int>(inc.size());
    for (int i = 0; i < k; ++i)
        for (int j = i + 1; j < k; ++j) consider_pair(s, g, o, c, inc, walks, i, j, scan);
    return scan;
}

// Edits of one repair, applied by `apply_edit` (a vertex or edge may be listed twice).
struct Edit {
    std::vector<int> drop_vertex, drop_edge;
    std::vector<std::array<int, 2>> new_edges;
};

// The absorbed walk: every vertex after c and every edge go; a merged branching point's other edges leave t.
void drop_absorbed(Skeleton& s, const Graph& g, const Walk& w, int e0, int t, Edit& ed) {
    int cur = e0;
    for (std::size_t q = 1; q < w.verts.size(); ++q) {
        ed.drop_edge.push_back(cur);
        const int v = w.verts[q];
        ed.drop_vertex.push_back(v);
        if (q + 1 < w.verts.size()) cur = g.inc[v][0] == cur ? g.inc[v][1] : g.inc[v][0];
    }
    const int b = w.verts.back();
    if (is_extremity(g, b)) return;
    for (const int e : g.inc[b])
        if (e != cur)
            for (int& v : s.edges[e])
                if (v == b) v = t;
}

// The kept walk of an absorbed pair: t joins it at arc length len. Its joints before len become balls over both
// tubes at their arc length (midpoint of the two polyline points, radius width x their distance + the larger radius,
// as t's), so its first turns stay in the skeleton (keep_joints; otherwise they go and t joins the first vertex after
// len).
void join_kept(Skeleton& s, const Graph& g, const Walk& keep, const Walk& absorbed, int e0, int t, bool keep_joints,
               double width, Edit& ed) {
    const double len = absorbed.length();
    const std::size_t k = at_arc(s, keep, len).k;
    std::vector<std::pair<Vec3, double>> moved;
    for (std::size_t q = 1; q <= k; ++q) {
        const AtArc a = at_arc(s, absorbed, keep.s[q]);
        const Vec3 p = s.points[keep.verts[q]];
        moved.push_back({0.5 * (a.x + p), width * distance(a.x, p) + std::max(a.r, s.radii[keep.verts[q]])});
    }
    int cur = e0;
    for (std::size_t q = 0;; ++q) {
        if (q == k || !keep_joints) ed.drop_edge.push_back(cur);
        if (q == k) break;
        const int v = keep.verts[q + 1];
        if (keep_joints) {
            s.points[v] = moved[q].first;
            s.radii[v] = moved[q].second;
        } else {
            ed.drop_vertex.push_back(v);
        }
        cur = g.inc[v][0] == cur ? g.inc[v][1] : g.inc[v][0];
    }
    if (keep_joints && k > 0) ed.new_edges.push_back({keep.verts[k], t});
    ed.new_edges.push_back({t, keep.verts[k + 1]});
}

// A trunk's walk: vertices before l* (joints) and their edges go; the walk leaves t towards its point at l* (a new
// vertex unless it is (almost) the next vertex).
void join_trunk(Skeleton& s, const Graph& g, const Walk& w, int e0, double sep, int t, Edit& ed) {
    const AtArc p = at_arc(s, w, sep);
    const std::size_t k = p.k;
    int cur = e0;
    for (std::size_t q = 0;; ++q) {
        ed.drop_edge.push_back(cur);
        if (q == k) break;
        const int v = w.verts[q + 1];  // a joint: two branch edges
        ed.drop_vertex.push_back(v);
        cur = g.inc[v][0] == cur ? g.inc[v][1] : g.inc[v][0];
    }
    const int after = w.verts[k + 1];
    if (p.u > 1 - 1e-9) {
        ed.new_edges.push_back({t, after});
        return;
    }
    const int pv = static_cast<int>(s.points.size());
    s.points.push_back(p.x);
    s.radii.push_back(p.r);
    ed.new_edges.push_back({t, pv});
    ed.new_edges.push_back({pv, after});
}

// The arc length on the kept walk of a side stub's root q (side_stub_root_exit): abeam of the first point of the
// stub's axis (sampled in 128 steps from c) whose distance to the kept polyline reaches exit x the kept radius there,
// moved out until q lies beyond c's ball and |q - c| >= clearance x (r_c + r_q) (the caller passes exit > 0 only where
// c stays a branching point, so (c, q) is a bridge adaptation keeps); `nearest`, the arc of the point nearest e, when
// exit is 0, the axis never leaves, or the root would lie beyond it.
double side_root_arc(const Skeleton& s, const Walk& keep, const Walk& stub, double exit, double clearance,
                     double nearest) {
    if (!(exit > 0)) return nearest;
    constexpr int steps = 128;
    double arc = -1, a = 0;
    for (int k = 1; k <= steps && arc < 0; ++k) {
        const Vec3 p = at_arc(s, stub, stub.length() * k / steps).x;
        const AtArc q = nearest_on_walk(s, keep, p, a);
        if (distance(p, q.x) >= exit * q.r) arc = a;
    }
    if (arc < 0) return nearest;
    const Vec3 c = s.points[keep.verts[0]];
    const double rc = s.radii[keep.verts[0]], k = clearance * (1 + 1e-6);
    const auto clear = [&](double t) {
        const AtArc q = at_arc(s, keep, t);
        const double d = distance(q.x, c);
        return d > rc && d >= k * (rc + q.r);
    };
    if (!clear(arc)) {
        if (!clear(nearest)) return nearest;
        double lo = arc, hi = nearest;
        for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (clear(mid) ? hi : lo) = mid;
        }
        arc = hi;
    }
    return std::min(arc, nearest);
}

// A side stub: q (an existing joint of the kept walk, or a new vertex splitting its segment) gets the edge (q, e);
// the stub's edges and vertices before e go. q lies at the point of the kept walk nearest e, or where the stub leaves
// the kept tube (side_root_arc). Returns q's id before the renumbering.
int join_side(Skeleton& s, const Graph& g, const Walk& keep, int e_keep, const Walk& stub, int e_stub,
              const SkeletonRepairOptions& o, Edit& ed) {
    const int e = stub.verts.back();
    double nearest = 0;
    const AtArc qn = nearest_on_walk(s, keep, s.points[e], nearest);
    const bool bridge = g.degree[keep.verts[0]] >= 4;  // c stays a branching point without the stub
    // Rooted where it leaves (side_stub_root_exit) only at a point that stays a branching point, for a stub at least as
    // fat at its end as the other branch there.
    const double exit = s.radii[e] >= qn.r && bridge ? o.side_stub_root_exit : 0.0;
    const double arc = side_root_arc(s, keep, stub, exit, o.trunk_clearance, nearest);
    const AtArc q = arc == nearest ? qn : at_arc(s, keep, arc);
    const double min_length = o.side_stub_min_length;
    int cur = e_keep;
    for (std::size_t k = 0; k < q.k; ++k) {
        const int v = keep.verts[k + 1];
        cur = g.inc[v][0] == cur ? g.inc[v][1] : g.inc[v][0];
    }
    int qv = -1;
    if (q.u < 1e-9 && q.k > 0) {
        qv = keep.verts[q.k];
    } else if (q.u > 1 - 1e-9) {
        qv = keep.verts[q.k + 1];
    } else {
        qv = static_cast<int>(s.points.size());
        s.points.push_back(q.x);
        s.radii.push_back(q.r);
        ed.drop_edge.push_back(cur);
        ed.new_edges.push_back({keep.verts[q.k], qv});
        ed.new_edges.push_back({qv, keep.verts[q.k + 1]});
    }
    cur = e_stub;
    for (std::size_t k = 1; k < stub.verts.size(); ++k) {
        ed.drop_edge.push_back(cur);
        const int v = stub.verts[k];
        if (k + 1 == stub.verts.size()) break;
        ed.drop_vertex.push_back(v);
        cur = g.inc[v][0] == cur ? g.inc[v][1] : g.inc[v][0];
    }
    // The side edge is at least min_length x the larger radius of its ends long: e moves outwards along (e - q).
    const double d = distance(s.points[e], s.points[qv]);
    const double len = min_length * std::max(s.radii[qv], s.radii[e]);
    if (d < len && d > 0) s.points[e] = s.points[qv] + (len / d) * (s.points[e] - s.points[qv]);
    ed.new_edges.push_back({qv, e});
    return qv;
}

// The repairs' rounds keep every vertex and edge id: dropped ones are only marked dead (tombstones), new ones are
// appended, and the graph is updated where a repair changed it. `compact` renumbers once at the end, keeping the
// order of the live vertices and edges, which is what renumbering after every round gave. A deliberate exception
// to "derived topology is computed, not maintained" (STYLE.md): rebuilding the graph every round was a fifth of the
// raw path's instructions on large trees (docs/performance.md, "Fifth pass"); the test
// SkeletonRepair.RepairedTreesGiveTheRecordedBits holds the maintained graph to the rebuilt one's results.
struct Tombstones {
    std::vector<char> vertex, edge;          // 1: dead
    std::vector<std::pair<int, int>> sides;  // leaflet sides (min, max), sorted: the faces do not change
};

bool is_side(const Tombstones& dead, int a, int b) {
    return std::binary_search(dead.sides.begin(), dead.sides.end(), std::pair<int, int>(std::minmax(a, b)));
}

// Adds (sign 1) or removes (sign -1) edge e with ends (a, b) in g, by make_graph's rules; g.inc stays sorted by id.
void graph_edge(const Skeleton& s, const Tombstones& dead, Graph& g, int e, int a, int b, int sign) {
    const int n = static_cast<int>(s.points.size());
    if (a < 0 || a >= n || b < 0 || b >= n || a == b) return;
    g.degree[a] += sign, g.degree[b] += sign;
    if (is_side(dead, a, b)) return;
    for (const int v : {a, b}) {
        std::vector<int>& inc = g.inc[v];
        if (sign > 0)
            inc.insert(std::lower_bound(inc.begin(), inc.end(), e), e);
        else
            inc.erase(std::find(inc.begin(), inc.end(), e));
    }
}

// What a repair may edit in place, saved before it: the points and radii of its two walks' vertices and every
// branch edge at them (the edges it drops or re-attaches are among these).
struct Saved {
    std::vector<std::pair<int, std::pair<Vec3, double>>> vertices;
    std::vector<std::pair<int, std::array<int, 2>>> edges;
};

Saved save_walks(const Skeleton& s, const Graph& g, const Walk& wi, const Walk& wj) {
    Saved saved;
    for (const Walk* w : {&wi, &wj})
        for (const int v : w->verts) {
            saved.vertices.push_back({v, {s.points[v], s.radii[v]}});
            for (const int e : g.inc[v]) saved.edges.push_back({e, s.edges[e]});
        }
    std::sort(saved.edges.begin(), saved.edges.end());
    saved.edges.erase(std::unique(saved.edges.begin(), saved.edges.end()), saved.edges.end());
    return saved;
}

// Marks the dropped vertices and edges dead, appends the new edges and updates g (its arrays grow to the new
// vertices). Returns the vertices whose surroundings the repair changed (live ones, possibly repeated): new
// vertices, moved ones (position or radius), and both ends (before and after) of every dropped, re-attached or new
// edge.
std::vector<int> apply_edit(Skeleton& s, Graph& g, Tombstones& dead, int n, const Saved& saved, const Edit& ed) {
    const std::size_t total = s.points.size();
    dead.vertex.resize(total, 0);
    g.inc.resize(total);
    g.on_face.resize(total, false);
    g.degree.resize(total, 0);
    g.frozen.resize(total, false);
    g.merged.resize(total, false);
    g.trunks.resize(total, 0);
    g.trunk_dirs.resize(total);
    std::vector<int> touched;
    for (int v = n; v < static_cast<int>(total); ++v) touched.push_back(v);
    for (const auto& [v, before] : saved.vertices)
        if (!(s.points[v] == before.first) || !(s.radii[v] == before.second)) touched.push_back(v);
    std::vector<int> dropped = ed.drop_edge;
    std::sort(dropped.begin(), dropped.end());
    for (const auto& [e, before] : saved.edges) {
        const std::array<int, 2>& now = s.edges[e];
        const bool drop = std::binary_search(dropped.begin(), dropped.end(), e);
        if (!drop && now == before) continue;
        touched.insert(touched.end(), {before[0], before[1], now[0], now[1]});
        graph_edge(s, dead, g, e, before[0], before[1], -1);
        if (drop)
            dead.edge[e] = 1;
        else
            graph_edge(s, dead, g, e, now[0], now[1], 1);
    }
    for (const std::array<int, 2>& e : ed.new_edges) {
        s.edges.push_back(e);
        dead.edge.push_back(0);
        graph_edge(s, dead, g, static_cast<int>(s.edges.size()) - 1, e[0], e[1], 1);
        touched.insert(touched.end(), {e[0], e[1]});
    }
    for (const int v : ed.drop_vertex) dead.vertex[v] = 1;
    std::erase_if(touched, [&](int v) { return v < 0 || v >= static_cast<int>(total); });
    return touched;
}

// Drops the dead vertices and edges, renumbering the rest in order (faces, the vertex map and the result's vertex
// lists too; a list entry whose vertex died goes).
void compact(Skeleton& s, const Tombstones& dead, SkeletonRepairResult& res) {
    const int total = static_cast<int>(s.points.size());
    std::vector<int> id(total, -1);
    int kept = 0;
    for (int v = 0; v < total; ++v) {
        if (dead.vertex[v]) continue;
        s.points[kept] = s.points[v];
        s.radii[kept] = s.radii[v];
        id[v] = kept++;
    }
    s.points.resize(kept);
    s.radii.resize(kept);
    for (int v = 0, k = 0; v < total; ++v)
        if (!dead.vertex[v]) res.junction_degree[k++] = res.junction_degree[v];
    res.junction_degree.resize(kept);
    const auto new_id = [&](int v) { return v >= 0 && v < total ? id[v] : -1; };  // -1 too for an invalid id
    std::size_t kept_edges = 0;
    for (std::size_t e = 0; e < s.edges.size(); ++e) {
        const int a = new_id(s.edges[e][0]), b = new_id(s.edges[e][1]);
        // A self-loop at a dropped joint (invalid input) loses both ends: it goes, no edge leaves with a -1 end.
        if (!dead.edge[e] && a >= 0 && b >= 0) s.edges[kept_edges++] = {a, b};
    }
    s.edges.resize(kept_edges);
    for (std::vector<int>& f : s.faces)
        for (int& v : f) v = new_id(v);
    for (int& v : res.vertex_map)
        if (v >= 0) v = new_id(v);
    for (std::vector<int>* list : {&res.absorbed_balls, &res.trunk_joints, &res.fan_end_pins}) {
        for (int& v : *list) v = new_id(v);
        std::erase(*list, -1);
    }
}

// What a repair made that later rounds must know about (-1: none).
struct Made {
    int side_root = -1;  // a side stub's root q (frozen)
    int merge_t = -1;    // a merge's ball t
    int junction = -1;   // the vertex the repair made of c's junction: t, or a side stub's root q
};

// Applies one repair (best.ei, best.ej: edge ids): t, the edge (c, t), and per walk its edits. Returns the touched
// vertices (apply_edit).
std::vector<int> apply_candidate(Skeleton& s, Graph& g, Tombstones& dead, const Candidate& best,
                                 const SkeletonRepairOptions& o, SkeletonRepairResult& res, Made& made) {
    const int n = static_cast<int>(s.points.size()), c = best.c, t = n;
    const Walk wi = walk(s, g, c, best.ei), wj = walk(s, g, c, best.ej);
    const Saved saved = save_walks(s, g, wi, wj);
    Edit ed;
    if (best.kind == PairRepair::side) {
        made.side_root = join_side(s, g, wi, best.ei, wj, best.ej, o, ed);
        made.junction = made.side_root;
        ++res.side_stubs;
        return apply_edit(s, g, dead, n, saved, ed);
    }
    s.points.push_back(best.t);
    s.radii.push_back(best.rt);
    made.junction = t;
    if (best.kind == PairRepair::main_stub) {  // the stub leaves t towards its next vertex, the thin walk towards x
        double a = 0;
        const AtArc at = nearest_on_walk(s, wj, best.t, a);
        const std::size_t k = at.k + (at.u > 1 - 1e-9 ? 1 : 0);  // t on a joint: that joint goes, t takes its place
        const double next = wj.s[k] + (1 - 1e-12) * (wj.s[k + 1] - wj.s[k]);
        ed.new_edges.push_back({c, t});
        join_trunk(s, g, wj, best.ej, next, t, ed);
        join_trunk(s, g, wi, best.ei, best.sep, t, ed);
        ++res.main_stubs;
        res.trunk_joints.push_back(c);  // c becomes a joint (parent, stub)
        made.side_root = t;             // frozen like a side stub's root: its pair parts (parted_at_root)
        return apply_edit(s, g, dead, n, saved, ed);
    }
    if (best.kind == PairRepair::trunk) {
        ed.new_edges.push_back({c, t});
        join_trunk(s, g, wi, best.ei, best.sep, t, ed);
        join_trunk(s, g, wj, best.ej, best.sep, t, ed);
        ++res.trunks;
        if (g.inc[c].size() == 3 && g.degree[c] == 3) res.trunk_joints.push_back(c);  // c becomes a joint
    } else {
        const bool keep_joints = o.keep_sibling_joints;
        if (!keep_joints || at_arc(s, wi, best.sep).k == 0) ed.new_edges.push_back({c, t});
        join_kept(s, g, wi, wj, best.ei, t, keep_joints, o.absorbed_ball_width, ed);
        drop_absorbed(s, g, wj, best.ej, t, ed);
        ++(best.kind == PairRepair::stub ? res.absorbed_stubs : res.merged_ends);
        if (best.kind == PairRepair::merge) made.merge_t = t;
        res.absorbed_balls.push_back(t);
    }
    return apply_edit(s, g, dead, n, saved, ed);
}

// Branching points whose scan a repair may have changed: every scanned vertex whose walks (from it through joints to
// the next non-joint vertex) meet a touched vertex, i.e. the non-joint vertices reached from a touched vertex through
// joints, and the touched vertices themselves. Returned in vertex order, once each (`flag`: all 0, a scratch array).
std::vector<int> mark_stale(const Skeleton& s, const Graph& g, const std::vector<int>& touched,
                            std::vector<char>& flag) {
    std::vector<int> stale;
    const auto add = [&](int v) {
        if (!flag[v]) stale.push_back(v), flag[v] = 1;
    };
    const auto joint = [&](int v) { return g.degree[v] == 2 && g.inc[v].size() == 2 && !g.on_face[v]; };
    for (const int x : touched) {
        add(x);
        for (const int e0 : g.inc[x]) {
            int prev_e = e0, cur = s.edges[e0][0] == x ? s.edges[e0][1] : s.edges[e0][0];
            for (std::size_t guard = 0; guard <= s.points.size() && cur != x && joint(cur); ++guard) {
                const int next_e = g.inc[cur][0] == prev_e ? g.inc[cur][1] : g.inc[cur][0];
                prev_e = next_e;
                cur = s.edges[next_e][0] == cur ? s.edges[next_e][1] : s.edges[next_e][0];
            }
            add(cur);
        }
    }
    for (const int v : stale) flag[v] = 0;
    std::sort(stale.begin(), stale.end());
    return stale;
}

// Distinct unseparated pairs of the current scans: (c, pair of the pair's first vertices).
int count_unseparated(const Skeleton& s, const Graph& g, const std::vector<PointScan>& scans) {
    std::set<std::array<int, 3>> unseparated;  // (c, smaller first vertex, larger first vertex)
    const int n = static_cast<int>(s.points.size());
    for (int c = 0; c < n; ++c) {
        if (!scanned(s, g, c)) continue;
        const std::vector<int>& inc = g.inc[c];
        const auto first = [&](int i) { return s.edges[inc[i]][0] == c ? s.edges[inc[i]][1] : s.edges[inc[i]][0]; };
        for (const auto& [i, j] : scans[c].unseparated)
            unseparated.insert({c, std::min(first(i), first(j)), std::max(first(i), first(j))});
    }
    return static_cast<int>(unseparated.size());
}

// The trunks and absorbed walks (see the header), one pair at a time: the pair with the highest score over every
// pair of branches at every scanned branching point (the first in vertex and pair order among equals). A point's
// scan depends only on its walks (positions, radii, the degrees at their ends), so after a repair only the stale
// points (mark_stale) are scanned again; the others keep their scan. Vertex and edge ids stay fixed over the rounds
// (Tombstones); `compact` renumbers at the end.
void repair_trunks(Skeleton& s, const SkeletonRepairOptions& o, SkeletonRepairResult& res) {
    if (!o.trunks || s.radii.size() != s.points.size()) return;
    const std::size_t budget = s.edges.size();
    std::vector<PointScan> scans(s.points.size());
    Graph g;
    make_graph(s, g);
    g.frozen.assign(s.points.size(), false);  // side stub roots
    g.merged.assign(s.points.size(), false);  // balls made by merges
    g.trunks.assign(s.points.size(), 0);
    g.trunk_dirs.assign(s.points.size(), {});
    Tombstones dead{std::vector<char>(s.points.size(), 0), std::vector<char>(s.edges.size(), 0), {}};
    const int n0 = static_cast<int>(s.points.size());
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i)
            if (f[i] >= 0 && f[i] < n0) dead.sides.push_back(std::minmax(f[i], f[(i + 1) % f.size()]));
    std::sort(dead.sides.begin(), dead.sides.end());
    // every point: in parallel (each task writes its own scans[c]; the same bits for any count)
    tbb::parallel_for(tbb::blocked_range<int>(0, n0, 64), [&](const tbb::blocked_range<int>& range) {
        for (int c = range.begin(); c < range.end(); ++c)
            if (scanned(s, g, c)) scans[c] = scan_point(s, g, o, c);
    });
    // The scanned points whose best repair scores above 0, by (-score, c): the first is the highest score, the first
    // in vertex order among equals. Only a stale point can change its scan or whether it is scanned at all (frozen,
    // its branch edges and its radius change only where a repair touched it; a dropped point is stale too).
    std::set<std::pair<double, int>> ranked;
    std::vector<double> rank_key(s.points.size(), 0);  // the key a point is ranked by (0: not ranked)
    const auto update = [&](int c, bool rescan) {
        if (rank_key[c] > 0) ranked.erase({-rank_key[c], c});
        rank_key[c] = 0;
        if (!scanned(s, g, c)) return;
        if (rescan) scans[c] = scan_point(s, g, o, c);
        if (scans[c].best.score > 0) ranked.insert({-(rank_key[c] = scans[c].best.score), c});
    };
    for (int c = 0; c < n0; ++c) update(c, false);
    std::vector<char> stale(s.points.size(), 0);
    bool repaired = false;
    for (std::size_t round = 0; round < budget; ++round) {
        if (ranked.empty() || round + 1 == budget) res.unseparated = count_unseparated(s, g, scans);
        if (ranked.empty()) break;
        repaired = true;
        const int c = ranked.begin()->second;
        Candidate best = scans[c].best;
        best.c = c;
        best.ei = g.inc[c][best.ei], best.ej = g.inc[c][best.ej];
        Made made;
        const std::vector<int> touched = apply_candidate(s, g, dead, best, o, res, made);
        res.junction_degree.resize(s.points.size(), 0);
        if (made.junction >= 0)
            res.junction_degree[made.junction] = std::max(res.junction_degree[made.junction], res.junction_degree[c]);
        scans.resize(s.points.size());
        stale.resize(s.points.size(), 0);
        rank_key.resize(s.points.size(), 0);
        if (made.side_root >= 0) g.frozen[made.side_root] = true;
        if (made.merge_t >= 0) g.merged[made.merge_t] = true;
        if (best.kind == PairRepair::trunk) {
            ++g.trunks[c];
            g.trunk_dirs[c].push_back({normalized(best.t - s.points[c]), best.valley});
        }
        const std::vector<int> points = mark_stale(s, g, touched, stale);
        if (o.rescan_all) {
            for (int v = 0; v < static_cast<int>(s.points.size()); ++v) update(v, true);
        } else {
            for (const int v : points) update(v, true);
        }
    }
    if (repaired) compact(s, dead, res);  // without a repair the skeleton is as it came (no renumbering, as before)
}

// Splits every branching point of `degree` (4 or 5) left by the trunks (no leaflet, `degree` branch edges) whose
// closest pair is less than 90 degrees apart (and unambiguous: junction_split_gap_deg) into a branching point of
// degree 3 and one of degree - 1 (SkeletonRepairOptions::junction_split, placement and radii there): the close pair
// moves to a new vertex c', the others stay at c (moved), joined by the edge (c, c'). A point whose directions
// fit_cube_frame accepts under `blocks` (when given and enabled) keeps its degree: it gets a compatible block. c' takes
// c's junction degree (junction_degree: per vertex, grows with s; at least 4 at both halves). Returns the number of
// points split.
int split_wide_junctions(Skeleton& s, double factor, double gap_deg, double clearance,
                         const CompatibleBlockOptions* blocks, std::vector<int>& junction_degree, int degree = 4) {
    if (!(factor > 0) || s.radii.size() != s.points.size()) return 0;
    Graph g;
    make_graph(s, g);
    const int n = static_cast<int>(s.points.size());
    const std::size_t nd = static_cast<std::size_t>(degree);
    int splits = 0;
    for (int c = 0; c < n; ++c) {
        if (g.on_face[c] || g.inc[c].size() != nd || g.degree[c] != degree || !(s.radii[c] > 0)) continue;
        std::vector<int> other(nd);
        std::vector<Vec3> d(nd);
        bool ok = true;
        for (int k = 0; k < degree; ++k) {
            const std::array<int, 2>& e = s.edges[g.inc[c][k]];
            other[k] = e[0] == c ? e[1] : e[0];
            const double len = distance(s.points[other[k]], s.points[c]);
            if (!(len > 1e-9 * s.radii[c])) ok = false;
            d[k] = ok ? (s.points[other[k]] - s.points[c]) / len : Vec3{};
        }
        if (!ok) continue;
        if (blocks && blocks->enabled && fit_cube_frame(d, *blocks).accepted) continue;
        int bi = -1, bj = -1;
        double best = 0;  // the closest pair: largest cosine, above 0 (less than 90 degrees apart)
        for (int i = 0; i < degree; ++i)
            for (int j = i + 1; j < degree; ++j)
                if (dot(d[i], d[j]) > best) best = dot(d[i], d[j]), bi = i, bj = j;
        if (bi < 0) continue;
        std::vector<int> rest;
        for (int k = 0; k < degree; ++k)
            if (k != bi && k != bj) rest.push_back(k);
        // An unambiguous pair: every angle across (a pair branch, another branch) exceeds the pair's by gap_deg.
        const auto angle = [&](int x, int y) { return std::acos(std::clamp(dot(d[x], d[y]), -1.0, 1.0)); };
        double across = 1e300;
        for (const int k : rest) across = std::min({across, angle(bi, k), angle(bj, k)});
        if (!(across - angle(bi, bj) >= gap_deg * std::numbers::pi / 180)) continue;
        Vec3 rest_sum = d[rest[0]];
        for (std::size_t k = 1; k < rest.size(); ++k) rest_sum = rest_sum + d[rest[k]];
        const Vec3 u = normalized(normalized(d[bi] + d[bj]) - normalized(rest_sum));
        if (u == Vec3{}) continue;
        // p1, p2: how far the first vertices lie beyond c along u (the close pair, nearest of the two) and along -u
        // (the others). The split points c + a u and c - b u, a + b = 2 h, sit at the same distance m = (p1 + p2)
        // / 2 - h before the nearest first vertex on either side (centred in the room the first edges leave); no
        // split when m <= 0.
        const double h = factor * s.radii[c];
        double p1 = 1e300, p2 = 1e300;
        for (const int k : {bi, bj}) p1 = std::min(p1, dot(s.points[other[k]] - s.points[c], u));
        for (const int k : rest) p2 = std::min(p2, -dot(s.points[other[k]] - s.points[c], u));
        const double m = 0.5 * (p1 + p2) - h;
        if (!(m > 0)) continue;
        // Radii: the largest of the edges' radii at that distance along them (linear from r_c to the first vertex's).
        const auto radius_at = [&](const std::vector<int>& ks, double x) {
            double r = 0;
            for (const int k : ks) {
                const double len = distance(s.points[other[k]], s.points[c]);
                const double f = std::clamp(x / len, 0.0, 1.0);  // x < 0: the split point lies on the other side
                r = std::max(r, s.radii[c] + f * (s.radii[other[k]] - s.radii[c]));
            }
            return r;
        };
        const double a = p1 - m, b = 2 * h - a;
        const Vec3 near = s.points[c] + a * u, far = s.points[c] - b * u;
        const double r_near = radius_at({bi, bj}, a), r_far = radius_at(rest, b);
        // Every moved first edge stays an edge (junction_split_clearance): else no split.
        bool clear = true;
        for (int k = 0; k < degree; ++k) {
            const bool pair = k == bi || k == bj;
            const double len = distance(s.points[other[k]], pair ? near : far);
            clear = clear && len >= clearance * ((pair ? r_near : r_far) + s.radii[other[k]]);
        }
        if (!clear) continue;
        const int cp = static_cast<int>(s.points.size());
        s.points.push_back(near);
        s.radii.push_back(r_near);
        s.points[c] = far;
        s.radii[c] = r_far;
        junction_degree[c] = std::max(junction_degree[c], 4);
        junction_degree.push_back(junction_degree[c]);
        for (const int k : {bi, bj})
            for (int& v : s.edges[g.inc[c][k]])
                if (v == c) v = cp;
        s.edges.push_back({c, cp});
        ++splits;
    }
    return splits;
}

// Per vertex of s: its number of edges when that is 3 or more and it lies on no leaflet face, else 0
// (SkeletonRepairResult::junction_degree before any repair). Edges with an end out of range or a self-loop are skipped.
std::vector<int> junction_degrees(const Skeleton& s) {
    const int n = static_cast<int>(s.points.size());
    std::vector<int> degree(static_cast<std::size_t>(n), 0);
    for (const auto& [a, b] : s.edges)
        if (a >= 0 && a < n && b >= 0 && b < n && a != b) ++degree[a], ++degree[b];
    for (const std::vector<int>& f : s.faces)
        for (const int v : f)
            if (v >= 0 && v < n) degree[v] = 0;
    for (int& d : degree)
        if (d < 3) d = 0;
    return degree;
}

}  // namespace

SkeletonRepairResult repair_skeleton(const Skeleton& input, const SkeletonRepairOptions& o,
                                     const CompatibleBlockOptions* blocks, const std::vector<int>& fan_caps) {
    SkeletonRepairResult res;
    res.skeleton = input;
    res.vertex_map.resize(input.points.size());
    for (std::size_t v = 0; v < input.points.size(); ++v) res.vertex_map[v] = static_cast<int>(v);
    Skeleton& s = res.skeleton;
    res.junction_degree = junction_degrees(input);
    if (o.fan_end_retraction) res.fan_end_retractions = retract_fan_ends(s, fan_caps);
    res.junction_degree.resize(s.points.size(), 0);
    for (const FanEndRetraction& r : res.fan_end_retractions)
        for (const int v : {r.bend, r.first_joint})
            if (v >= 0) res.fan_end_pins.push_back(v);
    repair_trunks(s, o, res);
    if (o.junction_split_degree_five)  // degree 5 first: the degree-4 point each split leaves is split below
        res.junction_splits = split_wide_junctions(s, o.junction_split, o.junction_split_gap_deg,
                                                   o.junction_split_clearance, blocks, res.junction_degree, 5);
    res.junction_splits += split_wide_junctions(s, o.junction_split, o.junction_split_gap_deg,
                                                o.junction_split_clearance, blocks, res.junction_degree);
    std::vector<char> band;  // the band pillow's copies
    if (o.docked_band_pillow)
        res.docked_band_pillows =
            pillow_docked_bands(s, o.docked_foot_split > 0 ? o.docked_foot_split : kUnboundedBand, band);
    res.docked_foot_splits = split_docked_feet(s, o.docked_foot_split, band);
    res.root_strip_splits = split_root_patches(s, o.root_patch_factor);
    res.junction_degree.resize(s.points.size(), 0);
    return res;
}

}  // namespace mesohex
