// Boundary projection with fading layers and a per-hex guard. See boundary_projection.h.
#include "mesohex/post/boundary_projection.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/move_backtracking.h"
#include "mesohex/core/topology.h"
#include "mesohex/post/quality.h"

namespace mesohex {
namespace {

// Calls f(u) for every edge neighbour u of v (once per hex edge at v: a neighbour shared by several hexes repeats).
template <class F>
void for_neighbours(const HexMesh& mesh, const VertexHexes& vh, int v, F&& f) {
    const std::size_t vi = static_cast<std::size_t>(v);
    for (int i = vh.begin[vi]; i < vh.begin[vi + 1]; ++i) {
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(vh.hexes[static_cast<std::size_t>(i)])];
        for (std::size_t c = 0; c < 8; ++c) {
            if (hex[c] != v) continue;
            for (int k : kHexCornerNeighbors[c]) f(hex[static_cast<std::size_t>(k)]);
        }
    }
}

// The moves: boundary vertices to the surface, then ring by ring beneath. Returns the moved vertices, ring order.
std::vector<int> layer_moves(const HexMesh& mesh, const VertexHexes& vh, const std::vector<char>& on_boundary,
                             const ClosestPointsFn& closest_points, int rings, std::vector<Vec3>& move,
                             ProjectionResult& result) {
    const std::size_t nv = mesh.points.size();
    std::vector<int> layer;
    for (std::size_t v = 0; v < nv; ++v)
        if (on_boundary[v]) layer.push_back(static_cast<int>(v));
    std::vector<Vec3> query(layer.size()), closest;
    for (std::size_t i = 0; i < layer.size(); ++i) query[i] = mesh.points[static_cast<std::size_t>(layer[i])];
    closest_points(query, closest);
    if (closest.size() != query.size())
        throw Error(ErrorCode::InvalidInput, "project_boundary: the projector returned " +
                                                 std::to_string(closest.size()) + " points for " +
                                                 std::to_string(query.size()) + " queries");
    std::vector<std::int8_t> ring(nv, -1);
    move.assign(nv, Vec3{});
    for (std::size_t i = 0; i < layer.size(); ++i) {
        const std::size_t v = static_cast<std::size_t>(layer[i]);
        ring[v] = 0;
        move[v] = closest[i] - query[i];
        result.max_move = std::max(result.max_move, norm(move[v]));
    }
    result.boundary_vertices = static_cast<long>(layer.size());
    std::vector<int> moved = layer, next;
    for (int r = 1; r <= rings; ++r) {
        next.clear();
        for (int v : layer)
            for_neighbours(mesh, vh, v, [&](int u) {
                if (ring[static_cast<std::size_t>(u)] >= 0) return;
                ring[static_cast<std::size_t>(u)] = static_cast<std::int8_t>(r);
                next.push_back(u);
            });
        const double w_prev = 1.0 - (r - 1.0) / (rings + 1.0), w = 1.0 - r / (rings + 1.0);
        for (int u : next) {
            Vec3 sum;
            int count = 0;
            for_neighbours(mesh, vh, u, [&](int n) {
                if (ring[static_cast<std::size_t>(n)] != r - 1) return;
                sum += move[static_cast<std::size_t>(n)];
                ++count;
            });
            move[static_cast<std::size_t>(u)] = count > 0 ? (w / w_prev / count) * sum : Vec3{};
        }
        moved.insert(moved.end(), next.begin(), next.end());
        layer.swap(next);
    }
    return moved;
}

double hex_sj(const HexMesh& mesh, int h) {
    std::array<Vec3, 8> c;
    const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(h)];
    for (std::size_t i = 0; i < 8; ++i) c[i] = mesh.points[static_cast<std::size_t>(hex[i])];
    return scaled_jacobian(c);
}

}  // namespace

ProjectionResult project_boundary(HexMesh& mesh, const std::vector<char>& on_boundary,
                                  const ClosestPointsFn& closest_points, const ProjectionOptions& options) {
    check_hex_indices(mesh, "project_boundary");
    const std::size_t nv = mesh.points.size(), nh = mesh.hexes.size();
    if (on_boundary.size() != nv)
        throw Error(ErrorCode::InvalidInput, "project_boundary: on_boundary must have one entry per vertex");
    if (options.rings < 0 || options.rings > 100)
        throw Error(ErrorCode::InvalidInput, "project_boundary: rings must be in [0, 100]");
    ProjectionResult result;
    const VertexHexes vh = vertex_hexes(mesh);
    std::vector<Vec3> move;
    const std::vector<int> moved = layer_moves(mesh, vh, on_boundary, closest_points, options.rings, move, result);
    // The hexes around moved vertices, ascending, with their scaled Jacobians before the move.
    std::vector<char> touched(nh, 0);
    for (int v : moved)
        for (int i = vh.begin[static_cast<std::size_t>(v)]; i < vh.begin[static_cast<std::size_t>(v) + 1]; ++i)
            touched[static_cast<std::size_t>(vh.hexes[static_cast<std::size_t>(i)])] = 1;
    std::vector<int> hexes;
    for (std::size_t h = 0; h < nh; ++h)
        if (touched[h]) hexes.push_back(static_cast<int>(h));
    touched = {};
    std::vector<double> before(nh, 1.0), now(nh, 1.0);
    auto measure = [&](const std::vector<int>& list, std::vector<double>& sj) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, list.size(), 1024),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i < r.end(); ++i)
                                  sj[static_cast<std::size_t>(list[i])] = hex_sj(mesh, list[i]);
                          });
    };
    measure(hexes, before);
    std::vector<Vec3> start(nv);
    for (int v : moved) {
        start[static_cast<std::size_t>(v)] = mesh.points[static_cast<std::size_t>(v)];
        mesh.points[static_cast<std::size_t>(v)] += move[static_cast<std::size_t>(v)];
    }
    measure(hexes, now);
    auto bad = [&](int h) {
        const double b = before[static_cast<std::size_t>(h)], a = now[static_cast<std::size_t>(h)];
        return !(a > 0) || (a < b && a < options.guard_sj);
    };
    MoveBacktracking st{std::vector<double>(nv, 1.0), std::vector<std::uint8_t>(nv, 0),
                        std::vector<std::uint8_t>(nv, 0), std::vector<std::uint8_t>(nh, 0), options.max_backtracks};
    std::vector<int> check;
    for (int h : hexes)
        if (bad(h)) check.push_back(h);
    back_off_bad_hexes(
        mesh.hexes, vh, st, std::move(check), [&](int h, bool) { return bad(h); },
        [&](int v) { return squared_norm(move[static_cast<std::size_t>(v)]) != 0; },
        [&](int v) {
            const std::size_t vi = static_cast<std::size_t>(v);
            mesh.points[vi] = start[vi] + st.scale[vi] * move[vi];
        },
        [&](const std::vector<int>& list) { measure(list, now); });
    const std::vector<double>& scale = st.scale;
    const std::vector<std::uint8_t>& halvings = st.halvings;
    for (int v : moved) {
        const std::size_t vi = static_cast<std::size_t>(v);
        if (squared_norm(move[vi]) > 0 && scale[vi] > 0) ++result.moved_vertices;
        if (halvings[vi] > 0) ++result.damped_vertices;
    }
    return result;
}

}  // namespace mesohex
