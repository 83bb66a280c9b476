#include "mesohex/post/crease_wedge.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

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

// The new vertex's position proposed by one wedge end v (v1 in q1, v2 in q2, t the unit edge direction): on the
// bisector of the two quads' directions perpendicular to the edge, where the cross-section has right angles at v1, v2.
Vec3 cap_point(const HexMesh& mesh, int v, int v1, int v2, const Vec3& t) {
    const Vec3& p = mesh.points[static_cast<std::size_t>(v)];
    const Vec3 d1 = mesh.points[static_cast<std::size_t>(v1)] - p, d2 = mesh.points[static_cast<std::size_t>(v2)] - p;
    const Vec3 u1 = d1 - t * dot(d1, t), u2 = d2 - t * dot(d2, t);
    const double gap = std::atan2(norm(cross(u1, u2)), dot(u1, u2));
    const Vec3 bisector = normalized(normalized(u1) + normalized(u2));
    const double reach = 0.5 * (norm(u1) + norm(u2)) / std::max(std::cos(0.5 * gap), 0.1);
    return p + bisector * reach + t * (0.5 * (dot(d1, t) + dot(d2, t)));
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

CreaseWedgeResult insert_crease_wedges(const HexMesh& mesh, const CreaseWedgeOptions& options) {
    CreaseWedgeResult unchanged;
    unchanged.mesh = mesh;
    unchanged.first_new_vertex = static_cast<int>(mesh.points.size());
    unchanged.first_new_hex = static_cast<int>(mesh.hexes.size());
    if (!(options.min_dihedral_deg > 0)) return unchanged;
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

}  // namespace mesohex
