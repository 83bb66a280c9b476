#include "mesohex/stages/fan_blocks.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mesohex/stages/compatible_blocks.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;

// Angle wrapped into (-pi, pi].
double wrap(double a) {
    a = std::remainder(a, 2 * kPi);
    return a <= -kPi ? a + 2 * kPi : a;
}

// Nearest of the 4 axes at angles theta + k pi / 2 to the angle phi.
int nearest_axis(double phi, double theta) {
    const long k = std::lround(std::floor((wrap(phi - theta) + 0.25 * kPi) / (0.5 * kPi)));
    return static_cast<int>(((k % 4) + 4) % 4);
}

// The angle theta maximising sum_i cos(phi_i - theta - k_i pi / 2) (the 2D rotation fit to the labels).
double fit_angle(const std::vector<double>& phi, const std::vector<int>& labels) {
    double c = 0, s = 0;
    for (std::size_t i = 0; i < phi.size(); ++i) {
        const double a = phi[i] - labels[i] * 0.5 * kPi;
        c += std::cos(a);
        s += std::sin(a);
    }
    return std::atan2(s, c);
}

bool is_fan_edge(const SkeletonAnalysis& an, int e) {
    return an.edge_degree[e] >= 3 && (an.edge_docked.empty() || an.edge_docked[e] == 0);
}

int other_end(const Skeleton& s, int e, int v) { return s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0]; }

// The fan edges at v (at most 2 in an analysed skeleton), increasing id.
std::vector<int> fan_edges_at(const SkeletonAnalysis& an, int v) {
    std::vector<int> out;
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i)
        if (is_fan_edge(an, an.vertex_edges[i])) out.push_back(an.vertex_edges[i]);
    return out;
}

// Walks a chain from vertex v0 along fan edge e0 until an end or back at v0; marks the edges taken.
FanBlockChain walk_chain(const Skeleton& s, const SkeletonAnalysis& an, int v0, int e0, std::vector<char>& taken) {
    FanBlockChain c;
    int v = v0, e = e0;
    while (true) {
        c.vertices.push_back(v);
        c.edges.push_back(e);
        taken[e] = 1;
        v = other_end(s, e, v);
        if (v == v0) {
            c.closed = true;
            return c;
        }
        int next = -1;
        for (const int f : fan_edges_at(an, v))
            if (!taken[f]) next = f;
        if (next < 0) {
            c.vertices.push_back(v);
            return c;
        }
        e = next;
    }
}

struct Incidence {
    std::vector<std::vector<std::array<int, 2>>> edge_faces;  // per edge: (face, side index)
    std::vector<int> vertex_faces;                            // per vertex: number of faces containing it
};

Incidence make_incidence(const SkeletonAnalysis& an, int nv, int ne) {
    Incidence in{std::vector<std::vector<std::array<int, 2>>>(ne), std::vector<int>(nv, 0)};
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int k = 0; k < 4; ++k) {
            in.edge_faces[an.face_edges[f][k]].push_back({f, k});
            ++in.vertex_faces[an.face_vertices[f][k]];
        }
    return in;
}

// Face f's neighbour of w other than y (w, y adjacent in f).
int across(const SkeletonAnalysis& an, int f, int w, int y) {
    const int k = face_corner(an, f, w);
    const int next = an.face_vertices[f][(k + 1) & 3], prev = an.face_vertices[f][(k + 3) & 3];
    return next == y ? prev : next;
}

// The branch edge at chain end position i that may stand on its cap (CompatibleBlockOptions::fan_cap_branches: one
// branch edge at the end, unit(b - w) . e >= cap_cos), or -1.
int cap_branch_edge(const Skeleton& s, const SkeletonAnalysis& an, const FanBlockChain& c, int i, double cap_cos) {
    const int v = c.vertices[i], n = static_cast<int>(c.vertices.size());
    if (an.vertex_branch_edges[v] != 1) return -1;
    const int e = first_branch_edge(an, v);
    const Vec3 out = normalized(s.points[v] - s.points[c.vertices[i == 0 ? 1 : n - 2]]);
    const Vec3 d = normalized(s.points[other_end(s, e, v)] - s.points[v]);
    return dot(d, out) >= cap_cos ? e : -1;
}

constexpr int kSidePending = 4;  // FanBlockChain::side_axis before the frames are fitted

// Vertex conditions of the header: inner vertices without branch, with the 2g faces of their fan edges; open ends
// fan-edge ends with g faces, g border edges and no branch (or, with options.fan_cap_branches, one branch standing on
// the cap: c.cap_branch).
bool chain_vertices_fit(const Skeleton& s, const SkeletonAnalysis& an, const Incidence& in,
                        const CompatibleBlockOptions& options, double cap_cos, FanBlockChain& c) {
    const int n = static_cast<int>(c.vertices.size());
    for (int i = 0; i < n; ++i) {
        const int v = c.vertices[i];
        const bool end = !c.closed && (i == 0 || i == n - 1);
        if (end && an.vertex_branch_edges[v] != 0) {
            int e = options.fan_cap_branches ? cap_branch_edge(s, an, c, i, cap_cos) : -1;
            if (e < 0 && options.fan_cap_branches && options.fan_side_branches && an.vertex_branch_edges[v] == 1) {
                e = first_branch_edge(an, v);
                c.side_axis[i == 0 ? 0 : 1] =
                    kSidePending;  // its free axis is checked on the frames (side_branches_fit)
            }
            if (e < 0) return false;
            c.cap_branch[i == 0 ? 0 : 1] = e;
        } else if (an.vertex_branch_edges[v] != 0) {
            return false;
        }
        if (end && (an.vertex_class[v] != VertexClass::FanEdgeEnd || an.vertex_boundary_edges[v] != c.degree ||
                    in.vertex_faces[v] != c.degree))
            return false;
        if (!end && (an.vertex_class[v] != VertexClass::FanEdgeVertex || in.vertex_faces[v] != 2 * c.degree))
            return false;
    }
    return true;
}

// Per chain edge: the fitted labels of its faces (in edge_faces order); false if an edge is rejected.
bool fit_chain_edges(const Skeleton& s, const SkeletonAnalysis& an, const Incidence& in, const FanBlockChain& c,
                     const CompatibleBlockOptions& options, std::vector<std::vector<int>>& labels) {
    Vec3 seed{};
    for (std::size_t i = 0; i < c.edges.size(); ++i) {
        const int e = c.edges[i], a = c.vertices[i], b = other_end(s, e, a);
        const Vec3 t = normalized(s.points[b] - s.points[a]);
        const Vec3 mid = 0.5 * (s.points[a] + s.points[b]);
        std::vector<Vec3> dirs;
        for (const auto& [f, k] : in.edge_faces[e]) {
            const std::array<int, 4>& fv = an.face_vertices[f];
            dirs.push_back(0.5 * (s.points[fv[(k + 2) & 3]] + s.points[fv[(k + 3) & 3]]) - mid);
        }
        const SquareFit fit = fit_square_frame(t, dirs, seed, options);
        if (!fit.accepted) return false;
        labels.push_back(fit.labels);
        seed = fit.u;
    }
    return true;
}

// The label of the face on chain edge i (position j in edge_faces) that contains the spoke (v, x), or -1.
int spoke_label(const SkeletonAnalysis& an, const Incidence& in, const FanBlockChain& c,
                const std::vector<std::vector<int>>& labels, int i, int v, int x) {
    const int e = c.edges[i];
    for (std::size_t j = 0; j < in.edge_faces[e].size(); ++j) {
        const int f = in.edge_faces[e][j][0];
        if (face_corner(an, f, x) >= 0 && face_corner(an, f, v) >= 0) return labels[i][j];
    }
    return -1;
}

// Each leaflet keeps its label across every inner vertex (and the closing vertex of a closed chain); fills the corner
// labels of the chain's faces (corner_axis, -1 elsewhere) and the labelled axes.
bool label_corners(const Skeleton& s, const SkeletonAnalysis& an, const Incidence& in, FanBlockChain& c,
                   const std::vector<std::vector<int>>& labels, FanBlocks& fb, std::vector<std::array<int, 2>>& set) {
    const int n = static_cast<int>(c.vertices.size()), m = static_cast<int>(c.edges.size());
    c.labelled.assign(4, 0);
    for (int i = 0; i < m; ++i) {
        const int e = c.edges[i];
        for (std::size_t j = 0; j < in.edge_faces[e].size(); ++j) {
            const int f = in.edge_faces[e][j][0], l = labels[i][j];
            c.labelled[l] = 1;
            for (const int w : s.edges[e]) {
                int& slot = fb.corner_axis[f][face_corner(an, f, w)];
                if (slot >= 0) return false;  // a face on two chain edges
                slot = l;
                set.push_back({f, face_corner(an, f, w)});
            }
        }
    }
    for (int i = 0; i < n; ++i) {
        const bool end = !c.closed && (i == 0 || i == n - 1);
        if (end) continue;
        const int v = c.vertices[i], prev = (i + m - 1) % m;
        const int u = other_end(s, c.edges[prev], v);
        for (std::size_t j = 0; j < in.edge_faces[c.edges[prev]].size(); ++j) {
            const int f = in.edge_faces[c.edges[prev]][j][0];
            const int x = across(an, f, v, u);
            if (spoke_label(an, in, c, labels, i, v, x) != labels[prev][j]) return false;
        }
    }
    return true;
}

// The chain edges at position i (one at an open end, else two: the previous one first).
std::vector<int> edges_at(const FanBlockChain& c, int i) {
    const int n = static_cast<int>(c.vertices.size()), m = static_cast<int>(c.edges.size());
    std::vector<int> out;
    if (c.closed || i > 0) out.push_back(c.edges[(i + m - 1) % m]);
    if (c.closed || i < n - 1) out.push_back(c.edges[i % m]);
    return out;
}

// Per-vertex frames: t along the chain (mean of the two edge directions inside), u fitted to the directions of the
// vertex's faces (x - v perpendicular to t) with their labels; the up / down section corners of every face corner.
void chain_frames(const Skeleton& s, const SkeletonAnalysis& an, const Incidence& in, FanBlockChain& c, FanBlocks& fb) {
    const int n = static_cast<int>(c.vertices.size());
    c.tangent.assign(n, Vec3{});
    c.axis_u.assign(n, Vec3{});
    for (int i = 0; i < n; ++i) {
        const int v = c.vertices[i];
        const Vec3& p = s.points[v];
        Vec3 t{};
        if (c.closed || i > 0) t += normalized(p - s.points[c.vertices[(i + n - 1) % n]]);
        if (c.closed || i < n - 1) t += normalized(s.points[c.vertices[(i + 1) % n]] - p);
        t = normalized(t);
        c.tangent[i] = t;
        std::vector<double> phi;
        std::vector<int> lab;
        std::vector<std::array<int, 2>> corners;  // (face, corner) at v
        Vec3 a{}, b{};
        for (const int e : edges_at(c, i)) {
            const int y = other_end(s, e, v);
            for (const auto& fk : in.edge_faces[e]) {
                const int f = fk[0], k = face_corner(an, f, v);
                Vec3 d = s.points[across(an, f, v, y)] - p;
                d = normalized(d - dot(d, t) * t);
                if (phi.empty()) a = d, b = cross(t, d);
                phi.push_back(std::atan2(dot(d, b), dot(d, a)));
                lab.push_back(fb.corner_axis[f][k]);
                corners.push_back({f, k});
            }
        }
        const double theta = fit_angle(phi, lab);
        c.axis_u[i] = std::cos(theta) * a + std::sin(theta) * b;
        const Vec3 w = cross(t, c.axis_u[i]);
        for (const auto& [f, k] : corners) {
            const int l = fb.corner_axis[f][k];
            const Vec3 next = std::cos((l + 1) * 0.5 * kPi) * c.axis_u[i] + std::sin((l + 1) * 0.5 * kPi) * w;
            const bool plus = dot(an.face_normal[f], next) > 0;  // the up side is towards axis l + 1
            fb.corner_up[f][k] = plus ? l : (l + 3) & 3;
            fb.corner_down[f][k] = plus ? (l + 3) & 3 : l;
        }
    }
}

// The free axis s (no leaflet labelled s) whose side section carries each pending end branch (side_axis
// kSidePending): the one nearest the branch's first edge d, accepted when d . A_s >= cap_cos; false if none.
bool side_branches_fit(const Skeleton& s, FanBlockChain& c, double cap_cos) {
    const int n = static_cast<int>(c.vertices.size());
    for (int end = 0; end < 2; ++end) {
        if (c.side_axis[end] != kSidePending) continue;
        const int i = end == 0 ? 0 : n - 1, v = c.vertices[i];
        const Vec3 t = c.tangent[i], u = c.axis_u[i], w = cross(t, u);
        const std::array<Vec3, 4> axis{u, w, -1.0 * u, -1.0 * w};
        const Vec3 d = normalized(s.points[other_end(s, c.cap_branch[end], v)] - s.points[v]);
        int best = -1;
        for (int k = 0; k < 4; ++k)
            if (!c.labelled[k] && dot(d, axis[k]) >= cap_cos && (best < 0 || dot(d, axis[k]) > dot(d, axis[best])))
                best = k;
        c.side_axis[end] = best;
        if (best >= 0) continue;
        for (int j = 0; j < 4; ++j)  // else the notch between two labelled axes
            if (c.labelled[j] && c.labelled[(j + 1) & 3] && dot(d, normalized(axis[j] + axis[(j + 1) & 3])) >= cap_cos)
                c.notch[end] = j;
        if (c.notch[end] < 0) return false;
    }
    return true;
}

}  // namespace

SquareFit fit_square_frame(const Vec3& t_in, const std::vector<Vec3>& directions, const Vec3& seed,
                           const CompatibleBlockOptions& options) {
    SquareFit fit;
    const int n = static_cast<int>(directions.size());
    fit.labels.assign(n, -1);
    if (n < 2 || !is_finite(t_in) || !(norm(t_in) > 0)) return fit;
    const Vec3 t = normalized(t_in);
    std::vector<Vec3> d(n);
    for (int i = 0; i < n; ++i) {
        const Vec3 p = directions[i] - dot(directions[i], t) * t;
        if (!is_finite(p) || !(norm(p) > 1e-12)) return fit;
        d[i] = normalized(p);
    }
    Vec3 a = is_finite(seed) ? seed - dot(seed, t) * t : Vec3{};
    a = norm(a) > 1e-9 ? normalized(a) : d[0];
    const Vec3 b = cross(t, a);
    std::vector<double> phi(n);
    for (int i = 0; i < n; ++i) phi[i] = std::atan2(dot(d[i], b), dot(d[i], a));
    double theta = 0;
    for (int round = 0; round < 3; ++round) {
        for (int i = 0; i < n; ++i) fit.labels[i] = nearest_axis(phi[i], theta);
        theta = fit_angle(phi, fit.labels);
    }
    for (int i = 0; i < n; ++i) {
        fit.labels[i] = nearest_axis(phi[i], theta);
        fit.max_axis_angle = std::max(fit.max_axis_angle, std::abs(wrap(phi[i] - theta - fit.labels[i] * 0.5 * kPi)));
    }
    bool distinct = true;
    for (int i = 0; i < n; ++i)
        for (int k = i + 1; k < n; ++k) {
            distinct = distinct && fit.labels[i] != fit.labels[k];
            const double want = ((fit.labels[i] - fit.labels[k]) & 3) == 2 ? kPi : 0.5 * kPi;
            fit.max_pair_error = std::max(fit.max_pair_error, std::abs(std::abs(wrap(phi[i] - phi[k])) - want));
        }
    fit.u = std::cos(theta) * a + std::sin(theta) * b;
    fit.accepted = distinct && fit.max_axis_angle <= options.axis_tolerance_deg * kDeg &&
                   fit.max_pair_error <= options.pair_tolerance_deg * kDeg;
    return fit;
}

FanBlocks find_fan_blocks(const Skeleton& skeleton, const SkeletonAnalysis& an, const CompatibleBlockOptions& options,
                          double cap_cos) {
    FanBlocks fb;
    if (!options.enabled || !options.fan_blocks || an.counts.fan_edges == 0) return fb;
    const int nv = static_cast<int>(an.vertex_class.size()), ne = static_cast<int>(an.edge_degree.size());
    const int nf = static_cast<int>(an.face_vertices.size());
    std::vector<char> taken(ne, 0);
    std::vector<FanBlockChain> chains;
    for (int v = 0; v < nv; ++v)
        if (an.vertex_class[v] == VertexClass::FanEdgeEnd)
            for (const int e : fan_edges_at(an, v))
                if (!taken[e]) chains.push_back(walk_chain(skeleton, an, v, e, taken));
    for (int e = 0; e < ne; ++e)
        if (is_fan_edge(an, e) && !taken[e]) chains.push_back(walk_chain(skeleton, an, skeleton.edges[e][0], e, taken));
    const Incidence in = make_incidence(an, nv, ne);
    fb.vertex_chain.assign(nv, -1);
    fb.vertex_index.assign(nv, -1);
    fb.corner_axis.assign(nf, {-1, -1, -1, -1});
    fb.corner_up.assign(nf, {-1, -1, -1, -1});
    fb.corner_down.assign(nf, {-1, -1, -1, -1});
    for (FanBlockChain& c : chains) {
        c.degree = an.edge_degree[c.edges[0]];
        bool ok = c.degree <= 4 && chain_vertices_fit(skeleton, an, in, options, cap_cos, c);
        for (const int e : c.edges) ok = ok && an.edge_degree[e] == c.degree;
        std::vector<std::vector<int>> labels;
        ok = ok && fit_chain_edges(skeleton, an, in, c, options, labels);
        std::vector<std::array<int, 2>> set;  // corners labelled (undone when the chain is rejected)
        ok = ok && label_corners(skeleton, an, in, c, labels, fb, set);
        if (!ok) {
            for (const auto& [f, k] : set) fb.corner_axis[f][k] = -1;
            continue;
        }
        chain_frames(skeleton, an, in, c, fb);
        if (!side_branches_fit(skeleton, c, cap_cos)) {
            for (const auto& [f, k] : set) fb.corner_axis[f][k] = fb.corner_up[f][k] = fb.corner_down[f][k] = -1;
            continue;
        }
        for (int i = 0; i < static_cast<int>(c.vertices.size()); ++i) {
            fb.vertex_chain[c.vertices[i]] = static_cast<int>(fb.chains.size());
            fb.vertex_index[c.vertices[i]] = i;
        }
        fb.chains.push_back(std::move(c));
    }
    if (fb.chains.empty()) fb = FanBlocks{};
    return fb;
}

long fan_block_edges(const FanBlocks& blocks) {
    long n = 0;
    for (const FanBlockChain& c : blocks.chains) n += static_cast<long>(c.edges.size());
    return n;
}

long fan_block_caps(const FanBlocks& blocks) {
    long n = 0;
    for (const FanBlockChain& c : blocks.chains) n += c.closed ? 0 : 2;
    return n;
}

int fan_cap_branch_at(const FanBlocks& blocks, int v) {
    if (blocks.vertex_chain.empty() || blocks.vertex_chain[v] < 0) return -1;
    const FanBlockChain& c = blocks.chains[blocks.vertex_chain[v]];
    const int i = blocks.vertex_index[v], n = static_cast<int>(c.vertices.size());
    if (c.closed || (i != 0 && i != n - 1)) return -1;
    return c.cap_branch[i == 0 ? 0 : 1];
}

std::vector<int> fan_cap_roots(const FanBlocks& blocks) {
    std::vector<int> out;
    for (const FanBlockChain& c : blocks.chains)
        for (int end = 0; end < 2; ++end)
            if (c.cap_branch[end] >= 0) out.push_back(end == 0 ? c.vertices.front() : c.vertices.back());
    std::sort(out.begin(), out.end());
    return out;
}

std::array<Vec3, 4> fan_cap_directions(const FanBlockChain& c, int i) {
    const Vec3 t = c.tangent[i], u = c.axis_u[i], w = cross(t, u);
    const std::array<Vec3, 4> axis{u, w, -1.0 * u, -1.0 * w};
    const int side = c.side_axis[i == 0 ? 0 : 1], notch = c.notch[i == 0 ? 0 : 1];
    if (notch >= 0) {
        const Vec3 a = normalized(axis[(notch + 1) & 3] - axis[notch]);
        return {a, t, -1.0 * a, -1.0 * t};
    }
    if (side >= 0) {
        const Vec3 a = axis[(side + 1) & 3];
        return {a, t, -1.0 * a, -1.0 * t};
    }
    std::array<Vec3, 4> out;
    for (int x = 0; x < 4; ++x) out[x] = axis[i == 0 ? (4 - x) & 3 : x];
    return out;
}

std::array<std::array<int, 2>, 9> fan_side_section_ids(const FanBlockChain& c, int i) {
    const int n = static_cast<int>(c.vertices.size()), s = c.side_axis[i == 0 ? 0 : 1];
    const int sm = (s + 3) & 3, l = i == 0 ? 1 : n - 2;
    // The rows of +t and -t: (chain position, first section id); the cap section K is beyond w along e.
    const std::array<int, 2> cap{i, kFanSectionIds}, next{l, 0};
    const std::array<int, 2> plus = i == 0 ? next : cap, minus = i == 0 ? cap : next;
    return {{{i, 1 + s},
             {i, 5 + s},
             {plus[0], plus[1] + 1 + s},
             {i, 5 + sm},
             {minus[0], minus[1] + 1 + s},
             {plus[0], plus[1] + 5 + s},
             {plus[0], plus[1] + 5 + sm},
             {minus[0], minus[1] + 5 + sm},
             {minus[0], minus[1] + 5 + s}}};
}

std::array<int, 9> fan_cap_section_ids(const FanBlockChain& /*chain*/, int i) {
    std::array<int, 9> ids{};
    ids[0] = kFanSectionIds;
    for (int x = 0; x < 4; ++x) {
        // point x is Q_k; the edge (x, x + 1) is M_k at the last vertex, M_(k - 1) (between Q_(k - 1) and Q_k,
        // k - 1 = -(x + 1)) at the first
        ids[1 + x] = kFanSectionIds + 1 + (i == 0 ? (4 - x) & 3 : x);
        ids[5 + x] = kFanSectionIds + 5 + (i == 0 ? (3 - x) & 3 : x);
    }
    return ids;
}

int fan_block_vertex_ids(const FanBlocks& blocks, int v) {
    if (blocks.vertex_chain.empty() || blocks.vertex_chain[v] < 0) return 0;
    const FanBlockChain& c = blocks.chains[blocks.vertex_chain[v]];
    const int i = blocks.vertex_index[v], n = static_cast<int>(c.vertices.size());
    return !c.closed && (i == 0 || i == n - 1) ? 2 * kFanSectionIds : kFanSectionIds;
}

std::vector<std::array<std::array<int, 2>, 8>> fan_chain_hexes(const FanBlockChain& c) {
    std::vector<std::array<std::array<int, 2>, 8>> hexes;
    const int n = static_cast<int>(c.vertices.size()), m = static_cast<int>(c.edges.size());
    // One chunk from section (i, offset a) to section (j, offset b).
    auto chunk = [&](int i, int a, int j, int b) {
        for (int k = 0; k < 4; ++k) {
            const std::array<int, 4> s{0, 1 + k, 5 + k, 1 + ((k + 1) & 3)};
            std::array<std::array<int, 2>, 8> h{};
            for (int q = 0; q < 4; ++q) {
                h[q] = {i, a + s[q]};
                h[4 + q] = {j, b + s[q]};
            }
            hexes.push_back(h);
        }
    };
    for (int i = 0; i < m; ++i) chunk(i, 0, (i + 1) % n, 0);
    if (!c.closed) {
        chunk(0, kFanSectionIds, 0, 0);
        chunk(n - 1, 0, n - 1, kFanSectionIds);
    }
    return hexes;
}

void fan_section_points(const FanBlockChain& c, int i, const Vec3& centre, double h, double cap,
                        std::vector<Vec3>& out) {
    const int n = static_cast<int>(c.vertices.size());
    const Vec3 t = c.tangent[i], u = c.axis_u[i], w = cross(t, u);
    const std::array<Vec3, 4> axis{u, w, -1.0 * u, -1.0 * w};
    auto section = [&](const Vec3& o) {
        out.push_back(o);
        for (int k = 0; k < 4; ++k) out.push_back(o + h * axis[k]);
        for (int k = 0; k < 4; ++k) out.push_back(o + h * (axis[k] + axis[(k + 1) & 3]));
    };
    out.clear();
    section(centre);
    if (c.closed) return;
    if (i == 0) section(centre - cap * t);
    if (i == n - 1) section(centre + cap * t);
}

namespace {

// count edges of valence `from` become valence `to` (irregular boundary valences only: 2 is regular).
void revalue(std::map<int, long>& edges, int from, int to, long count) {
    if (from != 2 && (edges[from] -= count) == 0) edges.erase(from);
    if (to != 2) edges[to] += count;
}

// The branch's first chunk on side section s (fan_side_section_ids): +1 hex on the patch's 8 rim edges.
void add_side_branch_edges(const FanBlockChain& c, int s, std::map<int, long>& edges) {
    if (s < 0) return;
    for (const int m : {(s + 3) & 3, s}) {  // the longitudinal edges through M_s-1 and M_s: fan edge and cap rows
        const int valence = 1 + c.labelled[m] + c.labelled[(m + 1) & 3];
        revalue(edges, valence, valence + 1, 2);
    }
    revalue(edges, 2, 3, 2);  // the rim at L (between the last fan edge's chunk and the one before, or L's cap)
    revalue(edges, 1, 2, 2);  // the rim on the cap's end face (the cap's hex only)
}

// The branch's first chunk in the notch at M_j (notch): the fold's 2 edges get 2 hexes each.
void add_notch_branch_edges(int j, std::map<int, long>& boundary, std::map<int, long>& interior) {
    if (j < 0) return;
    revalue(boundary, 3, 2, 2);  // the fold (block hex + 2 plates or half-chunks): interior now, counted below
    interior[5] += 2;
    revalue(boundary, 2, 3, 6);  // the rim on the plates' sides and the half-chunks' sides
    revalue(boundary, 1, 2, 2);  // the rim on the half-chunks' outer edges
}

}  // namespace

void add_fan_block_irregular_edges(const FanBlockChain& c, std::map<int, long>& boundary_irregular_edges,
                                   std::map<int, long>& interior_irregular_edges) {
    const long rows = static_cast<long>(c.edges.size()) + (c.closed ? 0 : 2);
    for (int k = 0; k < 4; ++k) {
        const int docked = c.labelled[k] + c.labelled[(k + 1) & 3];
        if (docked != 1) boundary_irregular_edges[1 + docked] += rows;
        if (!c.labelled[k] && !c.closed) boundary_irregular_edges[1] += 2 * 2;  // two rim edges at each cap
        for (int end = 0; end < 2; ++end) {  // the branch's first chunk on the cap: +1 on each rim edge
            if (c.cap_branch[end] < 0 || c.side_axis[end] >= 0 || c.notch[end] >= 0) continue;
            if (c.labelled[k]) {
                boundary_irregular_edges[3] += 2;
            } else {
                boundary_irregular_edges[1] -= 2;
            }
        }
    }
    for (int end = 0; end < 2; ++end) {
        add_side_branch_edges(c, c.side_axis[end], boundary_irregular_edges);
        add_notch_branch_edges(c.notch[end], boundary_irregular_edges, interior_irregular_edges);
    }
}

}  // namespace mesohex
