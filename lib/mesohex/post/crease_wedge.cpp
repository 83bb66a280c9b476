#include "mesohex/post/crease_wedge.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"

namespace mesohex {

namespace {

constexpr int kMaxRounds = 8;

// A folded boundary edge (a, b) and its two boundary quads: q1 holds a1 (a's other neighbour) and b1, q2 a2 and b2.
struct Crease {
    int a = -1, b = -1, a1 = -1, b1 = -1, a2 = -1, b2 = -1, q1 = -1, q2 = -1;
    double deg = 0;
};

// The angle (radians) of one hex between its two faces at its edge (la, lb), measured between the faces' mid-lines
// perpendicular to the edge (each face's far edge midpoint, seen around the edge: angle_about_edge).
double hex_angle_at_edge(const std::array<Vec3, 8>& p, int la, int lb) {
    std::array<Vec3, 2> far{};
    int found = 0;
    for (const std::array<int, 4>& face : kHexFaces) {
        if (std::find(face.begin(), face.end(), la) == face.end()) continue;
        if (std::find(face.begin(), face.end(), lb) == face.end()) continue;
        Vec3 other{};
        for (int lv : face)
            if (lv != la && lv != lb) other += p[static_cast<std::size_t>(lv)] * 0.5;
        if (found < 2) far[static_cast<std::size_t>(found)] = other;
        ++found;
    }
    return angle_about_edge(p[static_cast<std::size_t>(la)], p[static_cast<std::size_t>(lb)], far[0], far[1]);
}

// The number of hexes containing the edge (a, b) among hexes_at_a; with deg, the sum of their angles at the edge
// (hex_angle_at_edge) in degrees: the edge's interior dihedral.
int edge_hex_count(const HexMesh& mesh, const std::vector<int>& hexes_at_a, int a, int b, double* deg) {
    int count = 0;
    double sum = 0;
    for (int h : hexes_at_a) {
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(h)];
        for (const std::array<int, 2>& le : kHexEdges) {
            const int v0 = hex[static_cast<std::size_t>(le[0])], v1 = hex[static_cast<std::size_t>(le[1])];
            if (!((v0 == a && v1 == b) || (v0 == b && v1 == a))) continue;
            std::array<Vec3, 8> p{};
            for (std::size_t lv = 0; lv < 8; ++lv) p[lv] = mesh.points[static_cast<std::size_t>(hex[lv])];
            sum += hex_angle_at_edge(p, le[0], le[1]);
            ++count;
        }
    }
    if (deg) *deg = sum * 180.0 / std::numbers::pi;
    return count;
}

// For boundary quad q holding the edge (a, b): a's and b's other neighbours in q.
std::array<int, 2> other_neighbours(const std::array<int, 4>& q, int a, int b) {
    for (std::size_t i = 0; i < 4; ++i) {
        const int x = q[i], y = q[(i + 1) % 4];
        if (x == a && y == b) return {q[(i + 3) % 4], q[(i + 2) % 4]};
        if (x == b && y == a) return {q[(i + 2) % 4], q[(i + 3) % 4]};
    }
    return {-1, -1};
}

// Every boundary edge with two hexes and two boundary quads whose interior dihedral exceeds min_deg, in order of
// decreasing dihedral (ties by the edge's vertex pair).
std::vector<Crease> find_creases(const HexMesh& mesh, const HexTopology& topo, const CreaseWedgeOptions& options) {
    const double min_deg = options.min_dihedral_deg;
    std::vector<std::pair<std::array<int, 2>, int>> edge_quads;  // (edge, boundary quad)
    for (std::size_t q = 0; q < topo.boundary_quads.size(); ++q)
        for (std::size_t i = 0; i < 4; ++i) {
            const int x = topo.boundary_quads[q][i], y = topo.boundary_quads[q][(i + 1) % 4];
            edge_quads.push_back({{std::min(x, y), std::max(x, y)}, static_cast<int>(q)});
        }
    std::sort(edge_quads.begin(), edge_quads.end());
    const VertexHexes vh = vertex_hexes(mesh);
    std::vector<Crease> out;
    for (std::size_t i = 0; i < edge_quads.size();) {
        std::size_t j = i;
        while (j < edge_quads.size() && edge_quads[j].first == edge_quads[i].first) ++j;
        const bool listed = !options.listed_only ||
                            std::binary_search(options.listed.begin(), options.listed.end(), edge_quads[i].first);
        if (j - i == 2 && listed) {
            Crease c;
            c.a = edge_quads[i].first[0];
            c.b = edge_quads[i].first[1];
            const auto begin = vh.hexes.begin() + vh.begin[static_cast<std::size_t>(c.a)];
            const auto end = vh.hexes.begin() + vh.begin[static_cast<std::size_t>(c.a) + 1];
            const std::vector<int> at_a(begin, end);
            if (edge_hex_count(mesh, at_a, c.a, c.b, &c.deg) == 2 && c.deg > min_deg) {
                c.q1 = edge_quads[i].second;
                c.q2 = edge_quads[i + 1].second;
                const std::array<int, 2> n1 =
                    other_neighbours(topo.boundary_quads[static_cast<std::size_t>(c.q1)], c.a, c.b);
                const std::array<int, 2> n2 =
                    other_neighbours(topo.boundary_quads[static_cast<std::size_t>(c.q2)], c.a, c.b);
                c.a1 = n1[0];
                c.b1 = n1[1];
                c.a2 = n2[0];
                c.b2 = n2[1];
                out.push_back(c);
            }
        }
        i = j;
    }
    std::stable_sort(out.begin(), out.end(), [](const Crease& x, const Crease& y) { return x.deg > y.deg; });
    return out;
}

// The key of the new vertex at the end v of a wedge whose quads hold v's other neighbours v1, v2.
std::array<int, 3> cap_key(int v, int v1, int v2) { return {v, std::min(v1, v2), std::max(v1, v2)}; }

// Greedy selection: a crease whose quads are free and whose end vertices keep 0 or >= 3 boundary quads.
std::vector<Crease> select_creases(const std::vector<Crease>& creases, const std::vector<char>& banned,
                                   const std::vector<int>& boundary_count, std::size_t quad_count) {
    std::vector<char> used(quad_count, 0);
    std::map<std::array<int, 3>, int> caps;  // cap key -> wedges using it
    std::map<int, int> wedges_at;            // end vertex -> wedges ending there
    const auto final_count = [&](int v) {
        int unshared = 0;
        for (auto it = caps.lower_bound({v, -1, -1}); it != caps.end() && it->first[0] == v; ++it)
            unshared += it->second == 1 ? 1 : 0;
        return boundary_count[static_cast<std::size_t>(v)] - 2 * wedges_at[v] + unshared;
    };
    std::vector<Crease> taken;
    for (std::size_t i = 0; i < creases.size(); ++i) {
        const Crease& c = creases[i];
        if (banned[i] || used[static_cast<std::size_t>(c.q1)] || used[static_cast<std::size_t>(c.q2)]) continue;
        const std::array<int, 3> ka = cap_key(c.a, c.a1, c.a2), kb = cap_key(c.b, c.b1, c.b2);
        ++caps[ka];
        ++caps[kb];
        ++wedges_at[c.a];
        ++wedges_at[c.b];
        const int fa = final_count(c.a), fb = final_count(c.b);
        if ((fa == 0 || fa >= 3) && (fb == 0 || fb >= 3)) {
            used[static_cast<std::size_t>(c.q1)] = used[static_cast<std::size_t>(c.q2)] = 1;
            taken.push_back(c);
            continue;
        }
        if (--caps[ka] == 0) caps.erase(ka);
        if (--caps[kb] == 0) caps.erase(kb);
        --wedges_at[c.a];
        --wedges_at[c.b];
    }
    return taken;
}

// One wedge end v (v1 in q1, v2 in q2, t the unit edge direction): the bisector of the two quads' directions
// perpendicular to the edge, the reach along it where the cross-section has right angles at v1, v2, and the mean of
// v1's and v2's offsets along the edge.
struct WedgeRay {
    Vec3 bisector;
    double reach = 0;
    double along = 0;
};

WedgeRay wedge_ray(const HexMesh& mesh, int v, int v1, int v2, const Vec3& t) {
    const Vec3& p = mesh.points[static_cast<std::size_t>(v)];
    const Vec3 d1 = mesh.points[static_cast<std::size_t>(v1)] - p, d2 = mesh.points[static_cast<std::size_t>(v2)] - p;
    const Vec3 u1 = d1 - t * dot(d1, t), u2 = d2 - t * dot(d2, t);
    const double gap = std::atan2(norm(cross(u1, u2)), dot(u1, u2));
    WedgeRay ray;
    ray.bisector = normalized(normalized(u1) + normalized(u2));
    ray.reach = 0.5 * (norm(u1) + norm(u2)) / std::max(std::cos(0.5 * gap), 0.1);
    ray.along = 0.5 * (dot(d1, t) + dot(d2, t));
    return ray;
}

// The new vertex's position proposed by one wedge end v: on its ray's bisector at the reach (wedge_ray).
Vec3 cap_point(const HexMesh& mesh, int v, int v1, int v2, const Vec3& t) {
    const WedgeRay ray = wedge_ray(mesh, v, v1, v2, t);
    return mesh.points[static_cast<std::size_t>(v)] + ray.bisector * ray.reach + t * ray.along;
}

struct Built {
    CreaseWedgeResult result;
    std::vector<double> sj;  // per wedge
};

Built build_wedges(const HexMesh& mesh, const std::vector<Crease>& taken) {
    Built out;
    out.result.mesh = mesh;
    out.result.first_new_vertex = static_cast<int>(mesh.points.size());
    out.result.first_new_hex = static_cast<int>(mesh.hexes.size());
    std::map<std::array<int, 3>, int> vertex_of;  // cap key -> new vertex
    std::vector<Vec3> sum;
    std::vector<int> uses;
    const auto new_vertex = [&](const std::array<int, 3>& key, const Vec3& proposal) {
        auto [it, fresh] = vertex_of.try_emplace(key, static_cast<int>(mesh.points.size() + sum.size()));
        if (fresh) {
            sum.push_back(Vec3{});
            uses.push_back(0);
        }
        const std::size_t i = static_cast<std::size_t>(it->second) - mesh.points.size();
        sum[i] += proposal;
        ++uses[i];
        return it->second;
    };
    for (const Crease& c : taken) {
        const Vec3 t =
            normalized(mesh.points[static_cast<std::size_t>(c.b)] - mesh.points[static_cast<std::size_t>(c.a)]);
        const int ca = new_vertex(cap_key(c.a, c.a1, c.a2), cap_point(mesh, c.a, c.a1, c.a2, t));
        const int cb = new_vertex(cap_key(c.b, c.b1, c.b2), cap_point(mesh, c.b, c.b1, c.b2, t));
        out.result.mesh.hexes.push_back({c.a, c.a1, ca, c.a2, c.b, c.b1, cb, c.b2});
        out.result.wedge_edges.push_back({c.a, c.b});
    }
    for (std::size_t i = 0; i < sum.size(); ++i) out.result.mesh.points.push_back(sum[i] / uses[i]);
    for (std::size_t w = 0; w < taken.size(); ++w) {
        std::array<int, 8>& hex = out.result.mesh.hexes[static_cast<std::size_t>(out.result.first_new_hex) + w];
        const auto sj_of = [&] {
            std::array<Vec3, 8> p{};
            for (std::size_t lv = 0; lv < 8; ++lv) p[lv] = out.result.mesh.points[static_cast<std::size_t>(hex[lv])];
            return hex_scaled_jacobian(p);
        };
        double sj = sj_of();
        if (sj < 0) {
            std::swap(hex[1], hex[3]);
            std::swap(hex[5], hex[7]);
            sj = sj_of();
        }
        out.sj.push_back(sj);
    }
    return out;
}

// Faces of the result shared by more than two hexes, or boundary edges without exactly two boundary quads: the
// wedges (indices into taken) with a vertex on such an element.
std::vector<int> non_manifold_wedges(const CreaseWedgeResult& r) {
    const HexTopology topo = compute_hex_topology(r.mesh);
    std::vector<char> bad(r.mesh.points.size(), 0);
    for (std::size_t f = 0; f < topo.faces.size(); ++f)
        if (topo.face_hex_count[f] > 2)
            for (int v : topo.faces[f]) bad[static_cast<std::size_t>(v)] = 1;
    std::map<std::array<int, 2>, int> quads_at_edge;
    for (const std::array<int, 4>& q : topo.boundary_quads)
        for (std::size_t i = 0; i < 4; ++i)
            ++quads_at_edge[{std::min(q[i], q[(i + 1) % 4]), std::max(q[i], q[(i + 1) % 4])}];
    for (const auto& [e, n] : quads_at_edge)
        if (n != 2) bad[static_cast<std::size_t>(e[0])] = bad[static_cast<std::size_t>(e[1])] = 1;
    std::vector<int> out;
    for (std::size_t w = 0; w < r.wedge_edges.size(); ++w) {
        const std::array<int, 8>& hex = r.mesh.hexes[static_cast<std::size_t>(r.first_new_hex) + w];
        if (std::any_of(hex.begin(), hex.end(), [&](int v) { return bad[static_cast<std::size_t>(v)] != 0; }))
            out.push_back(static_cast<int>(w));
    }
    return out;
}

// Whether wedge w's new vertices pass options.keep_vertex (true without one).
bool keeps_vertices(const CreaseWedgeResult& r, std::size_t w, const CreaseWedgeOptions& options) {
    if (!options.keep_vertex) return true;
    const std::array<int, 8>& hex = r.mesh.hexes[static_cast<std::size_t>(r.first_new_hex) + w];
    for (int v : hex)
        if (v >= r.first_new_vertex && !options.keep_vertex(r.mesh.points[static_cast<std::size_t>(v)])) return false;
    return true;
}

}  // namespace

double interior_dihedral_deg(const HexMesh& mesh, const std::vector<int>& hexes_at_a, int a, int b) {
    double deg = 0;
    edge_hex_count(mesh, hexes_at_a, a, b, &deg);
    return deg;
}

namespace {

constexpr int kCrotchPasses = 3;

CreaseWedgeResult unchanged_result(const HexMesh& mesh) {
    CreaseWedgeResult unchanged;
    unchanged.mesh = mesh;
    unchanged.first_new_vertex = static_cast<int>(mesh.points.size());
    unchanged.first_new_hex = static_cast<int>(mesh.hexes.size());
    return unchanged;
}

// The wedge rounds on one mesh: selection, build, drop the failed wedges and select again (up to kMaxRounds).
CreaseWedgeResult wedge_rounds(const HexMesh& mesh, const CreaseWedgeOptions& options) {
    const CreaseWedgeResult unchanged = unchanged_result(mesh);
    const HexTopology topo = compute_hex_topology(mesh);
    const std::vector<Crease> creases = find_creases(mesh, topo, options);
    if (creases.empty()) return unchanged;
    std::vector<int> boundary_count(mesh.points.size(), 0);
    for (const std::array<int, 4>& q : topo.boundary_quads)
        for (int v : q) ++boundary_count[static_cast<std::size_t>(v)];
    std::vector<char> banned(creases.size(), 0);
    for (int round = 0; round < kMaxRounds; ++round) {
        const std::vector<Crease> taken = select_creases(creases, banned, boundary_count, topo.boundary_quads.size());
        if (taken.empty()) return unchanged;
        Built built = build_wedges(mesh, taken);
        std::vector<int> failed = non_manifold_wedges(built.result);
        for (std::size_t w = 0; w < taken.size(); ++w)
            if (!(built.sj[w] >= options.min_sj) || !keeps_vertices(built.result, w, options))
                failed.push_back(static_cast<int>(w));
        if (failed.empty()) return std::move(built.result);
        for (int w : failed)
            for (std::size_t i = 0; i < creases.size(); ++i)
                if (creases[i].a == taken[static_cast<std::size_t>(w)].a &&
                    creases[i].b == taken[static_cast<std::size_t>(w)].b)
                    banned[i] = 1;
    }
    return unchanged;
}

// The first selection on the input (no wedge built): the creases a wedge would go on.
std::vector<Crease> first_selection(const HexMesh& mesh, const CreaseWedgeOptions& options) {
    const HexTopology topo = compute_hex_topology(mesh);
    const std::vector<Crease> creases = find_creases(mesh, topo, options);
    std::vector<int> boundary_count(mesh.points.size(), 0);
    for (const std::array<int, 4>& q : topo.boundary_quads)
        for (int v : q) ++boundary_count[static_cast<std::size_t>(v)];
    return select_creases(creases, std::vector<char>(creases.size(), 0), boundary_count, topo.boundary_quads.size());
}

// The three classes of four parallel local edges of a hex, each oriented the same way across it (first -> second).
constexpr std::array<std::array<std::array<int, 2>, 4>, 3> kParallelEdges = {{
    {{{0, 1}, {3, 2}, {4, 5}, {7, 6}}},
    {{{0, 3}, {1, 2}, {4, 7}, {5, 6}}},
    {{{0, 4}, {1, 5}, {2, 6}, {3, 7}}},
}};

// The sheet of hexes dual to an edge: its hexes with their class of parallel edges and whether it runs against the
// class's orientation, and its edges (key v0 < v1) oriented from the seed's start side. ok = false when the sheet
// meets itself (a hex twice, an edge in both orientations) or exceeds kMaxCrotchSheetHexes.
struct Sheet {
    std::vector<std::array<int, 3>> hexes;                   // (hex, class, reversed)
    std::map<std::array<int, 2>, std::array<int, 2>> edges;  // key -> (from, to)
    bool ok = true;
};

Sheet collect_sheet(const HexMesh& mesh, const VertexHexes& vh, int from, int to) {
    Sheet sheet;
    std::map<int, std::array<int, 2>> seen;  // hex -> (class, reversed)
    std::vector<std::array<int, 2>> queue = {{from, to}};
    sheet.edges[{std::min(from, to), std::max(from, to)}] = {from, to};
    for (std::size_t qi = 0; qi < queue.size() && sheet.ok; ++qi) {
        const int x = queue[qi][0], y = queue[qi][1];
        for (int i = vh.begin[static_cast<std::size_t>(x)]; i < vh.begin[static_cast<std::size_t>(x) + 1]; ++i) {
            const int h = vh.hexes[static_cast<std::size_t>(i)];
            const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(h)];
            for (int k = 0; k < 3; ++k)
                for (const std::array<int, 2>& p : kParallelEdges[static_cast<std::size_t>(k)]) {
                    const int h0 = hex[static_cast<std::size_t>(p[0])], h1 = hex[static_cast<std::size_t>(p[1])];
                    if (!((h0 == x && h1 == y) || (h0 == y && h1 == x))) continue;
                    const int reversed = h0 == x ? 0 : 1;
                    const auto [it, fresh] = seen.try_emplace(h, std::array<int, 2>{k, reversed});
                    if (!fresh) {
                        if (it->second != std::array<int, 2>{k, reversed}) sheet.ok = false;
                        continue;
                    }
                    sheet.hexes.push_back({h, k, reversed});
                    for (const std::array<int, 2>& q : kParallelEdges[static_cast<std::size_t>(k)]) {
                        int a = hex[static_cast<std::size_t>(q[0])], b = hex[static_cast<std::size_t>(q[1])];
                        if (reversed) std::swap(a, b);
                        const auto [e, added] =
                            sheet.edges.try_emplace({std::min(a, b), std::max(a, b)}, std::array<int, 2>{a, b});
                        if (added)
                            queue.push_back({a, b});
                        else if (e->second != std::array<int, 2>{a, b})
                            sheet.ok = false;
                    }
                }
        }
        if (static_cast<int>(sheet.hexes.size()) > kMaxCrotchSheetHexes) sheet.ok = false;
    }
    std::sort(sheet.hexes.begin(), sheet.hexes.end());
    return sheet;
}

// Fractions (from the sheet's start side) at which the crotch cut crosses a crease end's two quad edges: the
// distance to the domain along the end's bisector (x crotch_reach) over the uncut wedge's reach there (cap_point);
// {-1} when the end lies outside the domain.
double crotch_fraction(const HexMesh& mesh, int v, int v1, int v2, const Vec3& t, const CreaseWedgeOptions& options) {
    const WedgeRay ray = wedge_ray(mesh, v, v1, v2, t);
    const double room =
        options.crotch_distance(mesh.points[static_cast<std::size_t>(v)], ray.bisector) * options.crotch_reach;
    if (!(room > 0) || !(ray.reach > 0)) return -1;
    return room / ray.reach;
}

constexpr double kMinCut = 0.1, kMaxCut = 0.9;  // the cut's fraction along a crease end's quad edge

// A crease end's cut on one of its quad edges: the crease vertex and the fraction from it.
using Proposals = std::map<std::array<int, 2>, std::vector<std::pair<int, double>>>;

// Cuts one sheet across (see crotch_cut): its crease ends' quad edges at their proposed fractions (the mean of the
// proposals, clamped to [kMinCut, kMaxCut]), its other boundary edges at the mean of those, its interior edges at the
// point nearest the centroid of the boundary cuts (clamped to [0.05, 0.95]); each hex is replaced by its part on the
// start side and its other part appended. false (nothing cut) when every proposal is at least 1: the uncut wedge
// stays inside the domain there.
bool cut_sheet(const Sheet& sheet, const Proposals& proposals, const std::map<std::array<int, 2>, bool>& on_boundary,
               HexMesh& mesh) {
    std::map<std::array<int, 2>, double> frac;
    double sum = 0;
    bool needed = false;
    for (const auto& [key, fe] : sheet.edges) {
        const auto it = proposals.find(key);
        if (it == proposals.end()) continue;
        double f = 0;
        for (const auto& [v, x] : it->second) f += v == fe[0] ? x : 1 - x;
        f /= static_cast<double>(it->second.size());
        needed = needed || f < 1;
        frac[key] = std::clamp(f, kMinCut, kMaxCut);
        sum += frac[key];
    }
    if (!needed) return false;
    const double mean = sum / static_cast<double>(frac.size());
    const auto at = [&](const std::array<int, 2>& fe, double f) {
        const Vec3& p = mesh.points[static_cast<std::size_t>(fe[0])];
        return p + (mesh.points[static_cast<std::size_t>(fe[1])] - p) * f;
    };
    Vec3 centroid{};
    int boundary = 0;
    for (const auto& [key, fe] : sheet.edges) {
        if (!on_boundary.at(key)) continue;
        const double f = frac.try_emplace(key, mean).first->second;
        centroid += at(fe, f);
        ++boundary;
    }
    if (boundary > 0) centroid = centroid / static_cast<double>(boundary);
    std::map<std::array<int, 2>, int> id;
    for (const auto& [key, fe] : sheet.edges) {
        if (!frac.contains(key)) {
            const Vec3& p = mesh.points[static_cast<std::size_t>(fe[0])];
            const Vec3 d = mesh.points[static_cast<std::size_t>(fe[1])] - p;
            frac[key] = std::clamp(dot(centroid - p, d) / std::max(dot(d, d), 1e-300), 0.05, 0.95);
        }
        id[key] = static_cast<int>(mesh.points.size());
        mesh.points.push_back(at(fe, frac[key]));
    }
    for (const std::array<int, 3>& hk : sheet.hexes) {
        const std::array<int, 8> hex = mesh.hexes[static_cast<std::size_t>(hk[0])];
        std::array<int, 8> near = hex, far = hex;
        for (std::array<int, 2> p : kParallelEdges[static_cast<std::size_t>(hk[1])]) {
            if (hk[2]) std::swap(p[0], p[1]);
            const int x = hex[static_cast<std::size_t>(p[0])], y = hex[static_cast<std::size_t>(p[1])];
            const int n = id.at({std::min(x, y), std::max(x, y)});
            near[static_cast<std::size_t>(p[1])] = n;
            far[static_cast<std::size_t>(p[0])] = n;
        }
        mesh.hexes[static_cast<std::size_t>(hk[0])] = near;
        mesh.hexes.push_back(far);
    }
    return true;
}

// The crotch cut of the creases `taken` (see CreaseWedgeOptions::crotch_distance): the cut mesh, the creases kept
// (those whose ends lie inside the domain and whose two sheets are closed, small and disjoint from the other cut
// sheets) and the number of sheets cut.
struct CrotchCut {
    HexMesh mesh;
    std::vector<std::array<int, 2>> kept;  // crease edges (a < b), sorted
    int sheets = 0;
};

CrotchCut crotch_cut(const HexMesh& mesh, const std::vector<Crease>& taken, const CreaseWedgeOptions& options) {
    const VertexHexes vh = vertex_hexes(mesh);
    std::vector<Sheet> sheets;
    Proposals proposals;
    std::vector<int> owner(mesh.hexes.size(), -1);  // hex -> sheet
    CrotchCut out;
    for (const Crease& c : taken) {
        const Vec3 t =
            normalized(mesh.points[static_cast<std::size_t>(c.b)] - mesh.points[static_cast<std::size_t>(c.a)]);
        const double fa = crotch_fraction(mesh, c.a, c.a1, c.a2, t, options);
        const double fb = crotch_fraction(mesh, c.b, c.b1, c.b2, t, options);
        if (fa < 0 || fb < 0) continue;
        std::array<Sheet, 2> pair = {collect_sheet(mesh, vh, c.a, c.a1), collect_sheet(mesh, vh, c.a, c.a2)};
        bool ok = pair[0].ok && pair[1].ok;
        std::array<int, 2> index = {-1, -1};
        for (std::size_t i = 0; i < 2 && ok; ++i) {
            const int first = pair[i].hexes.front()[0];
            index[i] = owner[static_cast<std::size_t>(first)];
            for (const std::array<int, 3>& hk : pair[i].hexes)
                if (owner[static_cast<std::size_t>(hk[0])] != index[i]) ok = false;  // overlaps another sheet
        }
        if (!ok || (index[0] >= 0 && index[0] == index[1])) continue;
        for (std::size_t i = 0; i < 2; ++i)
            if (index[i] < 0) {
                for (const std::array<int, 3>& hk : pair[i].hexes)
                    owner[static_cast<std::size_t>(hk[0])] = static_cast<int>(sheets.size());
                sheets.push_back(std::move(pair[i]));
            }
        for (const auto& [x, y, f] : {std::tuple{c.a, c.a1, fa}, std::tuple{c.a, c.a2, fa}, std::tuple{c.b, c.b1, fb},
                                      std::tuple{c.b, c.b2, fb}})
            proposals[{std::min(x, y), std::max(x, y)}].push_back({x, f});
        out.kept.push_back({c.a, c.b});
    }
    std::sort(out.kept.begin(), out.kept.end());
    out.mesh = mesh;
    const HexTopology topo = compute_hex_topology(mesh);
    std::map<std::array<int, 2>, bool> on_boundary;
    for (std::size_t e = 0; e < topo.edges.size(); ++e) on_boundary[topo.edges[e]] = topo.edge_on_boundary[e];
    for (const Sheet& sheet : sheets) out.sheets += cut_sheet(sheet, proposals, on_boundary, out.mesh) ? 1 : 0;
    return out;
}

}  // namespace

CreaseWedgeResult insert_crease_wedges(const HexMesh& mesh, const CreaseWedgeOptions& options) {
    if (!(options.min_dihedral_deg > 0)) return unchanged_result(mesh);
    if (!options.crotch_distance) return wedge_rounds(mesh, options);
    std::vector<Crease> taken = first_selection(mesh, options);
    for (int pass = 0; pass < kCrotchPasses && !taken.empty(); ++pass) {
        const CrotchCut cut = crotch_cut(mesh, taken, options);
        CreaseWedgeOptions wo = options;
        wo.listed_only = true;
        wo.listed = cut.kept;
        CreaseWedgeResult r = wedge_rounds(cut.mesh, wo);
        if (r.wedge_edges.empty()) break;
        r.first_new_vertex = static_cast<int>(mesh.points.size());
        r.first_new_hex = static_cast<int>(mesh.hexes.size());
        r.crotch_sheets = cut.sheets;
        if (r.wedge_edges.size() == cut.kept.size() || pass + 1 == kCrotchPasses) return r;
        std::vector<std::array<int, 2>> got = r.wedge_edges;
        std::sort(got.begin(), got.end());
        std::erase_if(taken, [&](const Crease& c) {
            return !std::binary_search(got.begin(), got.end(), std::array<int, 2>{c.a, c.b});
        });
    }
    return unchanged_result(mesh);
}

}  // namespace mesohex
