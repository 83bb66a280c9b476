// Padding inset: the padding layer moved inward where it reaches past the domain surface.
#include "mesohex/post/pad_inset.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numeric>

#include "mesohex/core/topology.h"
#include "mesohex/post/padding.h"
#include "mesohex/post/quality.h"

namespace mesohex {
namespace {

double hex_sj(const HexMesh& mesh, int h) {
    std::array<Vec3, 8> c;
    const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(h)];
    for (std::size_t i = 0; i < 8; ++i) c[i] = mesh.points[static_cast<std::size_t>(hex[i])];
    return scaled_jacobian(c);
}

// One moved pair: the raw vertex, its padding vertex, their common move (direction x length).
struct Move {
    int raw = 0, outer = 0;
    Vec3 dir;
    double length = 0;
};

// Sets both vertices of every move to start - scale x length x dir.
void apply(HexMesh& mesh, const std::vector<Move>& moves, const std::vector<Vec3>& start,
           const std::vector<double>& scale) {
    for (std::size_t i = 0; i < moves.size(); ++i)
        for (int v : {moves[i].raw, moves[i].outer})
            mesh.points[static_cast<std::size_t>(v)] =
                start[static_cast<std::size_t>(v)] - moves[i].dir * (scale[i] * moves[i].length);
}

// The pairs whose padding vertex overshoots the domain, in padding-vertex order.
std::vector<Move> overshooting(const HexMesh& mesh, int first_new_vertex, const std::vector<int>& origin_vertex,
                               const std::function<double(const Vec3& p, const Vec3& u, double t)>& overshoot,
                               const std::vector<char>& keep) {
    std::vector<Move> moves;
    for (std::size_t w = static_cast<std::size_t>(first_new_vertex); w < mesh.points.size(); ++w) {
        const int v = origin_vertex[w];
        if (!keep.empty() && keep[static_cast<std::size_t>(v)]) continue;
        const Vec3& p = mesh.points[static_cast<std::size_t>(v)];
        const Vec3 d = mesh.points[w] - p;
        const double t = norm(d);
        if (!(t > 0)) continue;
        const Vec3 u = d / t;
        const double s = std::clamp(overshoot(p, u, t), 0.0, t);
        if (s > 0) moves.push_back({v, static_cast<int>(w), u, s});
    }
    return moves;
}

// The hexes around the moved vertices (ascending); move_of[v] = the move of vertex v, -1 for none.
std::vector<int> hexes_around(const HexMesh& mesh, const std::vector<Move>& moves, std::vector<int>& move_of) {
    const VertexHexes vh = vertex_hexes(mesh);
    move_of.assign(mesh.points.size(), -1);
    std::vector<int> touched;
    for (std::size_t i = 0; i < moves.size(); ++i)
        for (int v : {moves[i].raw, moves[i].outer}) {
            move_of[static_cast<std::size_t>(v)] = static_cast<int>(i);
            for (int k = vh.begin[static_cast<std::size_t>(v)]; k < vh.begin[static_cast<std::size_t>(v) + 1]; ++k)
                touched.push_back(vh.hexes[static_cast<std::size_t>(k)]);
        }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    return touched;
}

// Per raw vertex (ids below first_new_vertex): concave_vertices (post/padding.h) over the padding hexes' bottom quads
// (the raw boundary quads: hexes (a, b, c, d, a', b', c', d') with a' >= first_new_vertex), each vertex's direction
// towards its padding copy.
std::vector<char> concave_raw_vertices(const HexMesh& mesh, int first_new_vertex,
                                       const std::vector<int>& origin_vertex) {
    std::vector<Vec3> dir(static_cast<std::size_t>(first_new_vertex));
    for (std::size_t w = static_cast<std::size_t>(first_new_vertex); w < mesh.points.size(); ++w) {
        const std::size_t v = static_cast<std::size_t>(origin_vertex[w]);
        dir[v] = normalized(mesh.points[w] - mesh.points[v]);
    }
    std::vector<std::array<int, 4>> bottoms;
    for (const std::array<int, 8>& h : mesh.hexes)
        if (h[4] >= first_new_vertex) bottoms.push_back({h[0], h[1], h[2], h[3]});
    std::vector<int> local(dir.size());
    std::iota(local.begin(), local.end(), 0);
    return concave_vertices(mesh, bottoms, dir, local);
}

}  // namespace

PadInsetResult inset_padding(HexMesh& mesh, int first_new_vertex, const std::vector<int>& origin_vertex,
                             const std::function<double(const Vec3& p, const Vec3& u, double t)>& overshoot,
                             const std::vector<char>& keep, const PadInsetOptions& options) {
    std::vector<char> kept = keep;
    if (options.concave_only) {
        const std::vector<char> concave = concave_raw_vertices(mesh, first_new_vertex, origin_vertex);
        kept.resize(concave.size(), 0);
        for (std::size_t v = 0; v < concave.size(); ++v) kept[v] = kept[v] || !concave[v];
    }
    const std::vector<Move> moves = overshooting(mesh, first_new_vertex, origin_vertex, overshoot, kept);
    PadInsetResult result;
    if (moves.empty()) return result;
    const std::vector<Vec3> start = mesh.points;
    std::vector<int> move_of;
    const std::vector<int> touched = hexes_around(mesh, moves, move_of);
    std::vector<double> floor(touched.size());
    for (std::size_t i = 0; i < touched.size(); ++i) floor[i] = std::min(options.guard_sj, hex_sj(mesh, touched[i]));
    std::vector<double> scale(moves.size(), 1.0);
    std::vector<int> halvings(moves.size(), 0);
    apply(mesh, moves, start, scale);
    // Halve the moves at every hex below its floor until none is (a move halved max_halvings times is dropped).
    for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t i = 0; i < touched.size(); ++i) {
            const double sj = hex_sj(mesh, touched[i]);
            if (sj > 0 && sj >= floor[i]) continue;
            for (int v : mesh.hexes[static_cast<std::size_t>(touched[i])]) {
                const int m = move_of[static_cast<std::size_t>(v)];
                if (m < 0 || scale[static_cast<std::size_t>(m)] == 0) continue;
                const std::size_t mi = static_cast<std::size_t>(m);
                scale[mi] = ++halvings[mi] > options.max_halvings ? 0.0 : 0.5 * scale[mi];
                changed = true;
            }
        }
        if (changed) apply(mesh, moves, start, scale);
    }
    for (std::size_t i = 0; i < moves.size(); ++i)
        if (scale[i] > 0) {
            ++result.moved_vertices;
            result.max_inset = std::max(result.max_inset, scale[i] * moves[i].length);
        }
    return result;
}

}  // namespace mesohex
