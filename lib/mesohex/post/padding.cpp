// Padding: one prism (hex) per boundary quad, glued through one new vertex per boundary vertex.
#include "mesohex/post/padding.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"
#include "mesohex/post/quality.h"

namespace mesohex {
namespace {

void check_input(const HexMesh& mesh, const PaddingOptions& options) {
    if (options.layers < 0) throw Error(ErrorCode::InvalidInput, "pad: layers must be >= 0");
    if (!(options.thickness > 0) || !std::isfinite(options.thickness))
        throw Error(ErrorCode::InvalidInput, "pad: thickness must be a positive finite number");
    if (!(options.absolute_thickness >= 0) || !std::isfinite(options.absolute_thickness))
        throw Error(ErrorCode::InvalidInput, "pad: absolute_thickness must be >= 0");
    check_hex_indices(mesh, "pad");
}

}  // namespace

std::vector<char> concave_vertices(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                                   const std::vector<Vec3>& unit_normal, const std::vector<int>& local) {
    const std::size_t nb = unit_normal.size();
    std::vector<double> rise(nb, 0.0), size(nb, 0.0);
    for (const std::array<int, 4>& q : quads) {
        Vec3 centroid;
        for (int v : q) centroid += mesh.points[static_cast<std::size_t>(v)] * 0.25;
        for (int v : q) {
            const std::size_t l = static_cast<std::size_t>(local[static_cast<std::size_t>(v)]);
            const Vec3 arm = centroid - mesh.points[static_cast<std::size_t>(v)];
            rise[l] += dot(unit_normal[l], arm);
            size[l] += norm(arm);
        }
    }
    std::vector<char> concave(nb, 0);
    for (std::size_t i = 0; i < nb; ++i) concave[i] = rise[i] > 1e-9 * size[i] ? 1 : 0;
    return concave;
}

void shorten_to_inward_edges(const HexMesh& mesh, const std::vector<int>& local, std::vector<double>& shortest) {
    for (const std::array<int, 8>& hex : mesh.hexes)
        for (const std::array<int, 2>& e : kHexEdges) {
            const int a = hex[static_cast<std::size_t>(e[0])], b = hex[static_cast<std::size_t>(e[1])];
            const int la = local[static_cast<std::size_t>(a)], lb = local[static_cast<std::size_t>(b)];
            if ((la >= 0) == (lb >= 0)) continue;  // both or neither on the boundary: not an edge into the mesh
            const std::size_t l = static_cast<std::size_t>(la >= 0 ? la : lb);
            shortest[l] = std::min(shortest[l], distance(mesh.points[static_cast<std::size_t>(a)],
                                                         mesh.points[static_cast<std::size_t>(b)]));
        }
}

namespace {

// One layer over the whole boundary of `mesh` (in place); `origin` is extended for the new vertices.
std::array<int, 4> sorted_quad(std::array<int, 4> q) {
    std::sort(q.begin(), q.end());
    return q;
}

// The boundary quads to pad (those not in options.bare_quads, in boundary-quad order); the bare ones go to `bare`.
std::vector<std::array<int, 4>> quads_to_pad(const HexTopology& topo, const PaddingOptions& options,
                                             std::vector<std::array<int, 4>>& bare) {
    std::vector<std::array<int, 4>> keys;
    for (const std::array<int, 4>& q : options.bare_quads) keys.push_back(sorted_quad(q));
    std::sort(keys.begin(), keys.end());
    std::vector<std::array<int, 4>> padded;
    for (const std::array<int, 4>& q : topo.boundary_quads)
        (std::binary_search(keys.begin(), keys.end(), sorted_quad(q)) ? bare : padded).push_back(q);
    return padded;
}

// At the vertices of bare quads: the direction projected onto the plane of their mean normal (the padding hex's side
// face then continues the bare face); left as it is where the projection degenerates.
void project_on_bare(const HexMesh& mesh, const std::vector<std::array<int, 4>>& bare, const std::vector<int>& local,
                     std::vector<Vec3>& unit_normal) {
    std::vector<Vec3> bare_sum(unit_normal.size());
    for (const std::array<int, 4>& q : bare) {
        const Vec3 n = quad_normal(mesh, q);
        for (int v : q)
            if (local[static_cast<std::size_t>(v)] >= 0)
                bare_sum[static_cast<std::size_t>(local[static_cast<std::size_t>(v)])] += n;
    }
    for (std::size_t i = 0; i < unit_normal.size(); ++i) {
        if (squared_norm(bare_sum[i]) == 0) continue;
        const Vec3 nb = normalized(bare_sum[i]);
        const Vec3 d = unit_normal[i] - nb * dot(unit_normal[i], nb);
        if (squared_norm(d) > 1e-6) unit_normal[i] = normalized(d);
    }
}

// Per boundary vertex (by local index): the corner vectors of its padded quads, (next - p) x (previous - p) over the
// product of the two edge lengths: the bottom corner of the new hex on that quad has scaled Jacobian dot(w, m) for the
// unit direction m at the vertex (sin of the quad's corner angle x cos of m to the corner's normal).
std::vector<std::vector<Vec3>> corner_vectors(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                                              const std::vector<int>& local, std::size_t nb) {
    std::vector<std::vector<Vec3>> w(nb);
    for (const std::array<int, 4>& q : quads)
        for (std::size_t i = 0; i < 4; ++i) {
            const Vec3& p = mesh.points[static_cast<std::size_t>(q[i])];
            const Vec3 a = mesh.points[static_cast<std::size_t>(q[(i + 1) % 4])] - p;
            const Vec3 b = mesh.points[static_cast<std::size_t>(q[(i + 3) % 4])] - p;
            const double l = norm(a) * norm(b);
            w[static_cast<std::size_t>(local[static_cast<std::size_t>(q[i])])].push_back(l > 0 ? cross(a, b) / l
                                                                                               : Vec3{});
        }
    return w;
}

// Per boundary vertex (local index, nb of them): 1 when it is a vertex of a bare quad (such vertices keep their
// direction: the corner guard and the direction search skip them).
std::vector<char> on_bare_quads(const std::vector<std::array<int, 4>>& bare, const std::vector<int>& local,
                                std::size_t nb) {
    std::vector<char> on_bare(nb, 0);
    for (const std::array<int, 4>& q : bare)
        for (int v : q)
            if (local[static_cast<std::size_t>(v)] >= 0)
                on_bare[static_cast<std::size_t>(local[static_cast<std::size_t>(v)])] = 1;
    return on_bare;
}

// PaddingOptions::corner_guard: at a vertex whose mean normal leaves some new hex's bottom corner below the guard,
// the direction turns along the great circle towards the maximin direction of its corner vectors, as little as
// reaches min(guard, the maximin value) (bisection on the turn). Vertices of bare quads keep their direction.
void guard_directions(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                      const std::vector<std::array<int, 4>>& bare, const std::vector<int>& local, double guard,
                      std::vector<Vec3>& unit_normal) {
    const std::vector<std::vector<Vec3>> w = corner_vectors(mesh, quads, local, unit_normal.size());
    const std::vector<char> on_bare = on_bare_quads(bare, local, unit_normal.size());
    for (std::size_t i = 0; i < unit_normal.size(); ++i) {
        if (on_bare[i] || lowest_corner(w[i], unit_normal[i]) >= guard) continue;
        const Vec3 axis = maximin_direction(w[i], unit_normal[i]);
        const double target = std::min(guard, lowest_corner(w[i], axis));
        const Vec3 from = unit_normal[i];
        auto at = [&](double t) { return normalized(from * (1 - t) + axis * t); };
        double lo = 0, hi = 1;
        if (!(squared_norm(from + axis) > 1e-12)) lo = hi = 1;  // opposite: no great circle to follow, take the axis
        for (int step = 0; step < 40 && hi - lo > 1e-9; ++step) {
            const double mid = 0.5 * (lo + hi);
            (lowest_corner(w[i], at(mid)) >= target ? hi : lo) = mid;
        }
        unit_normal[i] = hi >= 1 ? axis : at(hi);
    }
}

// One padding layer being placed: the new vertex of boundary vertex i (local index) lies at its point + unit_normal[i]
// x offset[i], at mesh.points[old_vertices + i]; the new hex on padded quad q has q as its bottom and the new vertices
// above as its top.
struct Layer {
    HexMesh& mesh;
    const std::vector<std::array<int, 4>>& quads;
    const std::vector<int>& new_id;             // per old vertex: its new vertex, -1 off the padded boundary
    const std::vector<int>& local;              // per old vertex: its local index, -1 off the padded boundary
    const std::vector<int>& boundary_vertices;  // per local index: the old vertex
    std::vector<Vec3> unit_normal;
    std::vector<double> offset;
    std::size_t old_vertices = 0;

    void place(std::size_t i) {
        mesh.points[old_vertices + i] =
            mesh.points[static_cast<std::size_t>(boundary_vertices[i])] + unit_normal[i] * offset[i];
    }
    std::array<Vec3, 8> corners(const std::array<int, 4>& q) const {
        std::array<Vec3, 8> c;
        for (std::size_t i = 0; i < 4; ++i) {
            c[i] = mesh.points[static_cast<std::size_t>(q[i])];
            c[i + 4] = mesh.points[static_cast<std::size_t>(new_id[static_cast<std::size_t>(q[i])])];
        }
        return c;
    }
    std::size_t local_of(int v) const { return static_cast<std::size_t>(local[static_cast<std::size_t>(v)]); }
    // Marks (per boundary vertex) the 4 vertices of every padded quad whose new hex is not positive; false if none.
    bool mark_inverted(std::vector<char>& marked) const {
        marked.assign(offset.size(), 0);
        bool any = false;
        for (const std::array<int, 4>& q : quads)
            if (!(scaled_jacobian(corners(q)) > 0))
                for (int v : q) {
                    marked[local_of(v)] = 1;
                    any = true;
                }
        return any;
    }
    // The outer vertices of an inverted new hex are pulled back (offset halved, up to 6 times).
    void shrink_inverted() {
        for (int round = 0; round < 6; ++round) {
            std::vector<char> shrink;
            if (!mark_inverted(shrink)) break;
            for (std::size_t i = 0; i < offset.size(); ++i)
                if (shrink[i]) {
                    offset[i] *= 0.5;
                    place(i);
                }
        }
    }
    // Where the boundary folds sharply (thin plates, saddles), the averaged normals of neighbouring vertices can
    // cross: shrink_inverted. A new hex still inverted then is inverted at any offset: the direction at one of its
    // vertices points behind one of the quads there. Tilt the direction of its vertices toward the normal of their
    // worst-facing quad (a quarter of it per step), back at the full offset, then shrink again; at most 20 times.
    // Ascending order, no parallelism: deterministic.
    void fix_inverted(const std::vector<Vec3>& quad_normals) {
        const std::vector<double> full_offset = offset;
        shrink_inverted();
        std::vector<std::vector<int>> quads_at(offset.size());
        for (std::size_t q = 0; q < quads.size(); ++q)
            for (int v : quads[q]) quads_at[local_of(v)].push_back(static_cast<int>(q));
        for (int tilt = 0; tilt < 20; ++tilt) {
            std::vector<char> bad;
            if (!mark_inverted(bad)) break;
            for (std::size_t i = 0; i < offset.size(); ++i) {
                if (!bad[i]) continue;
                double worst = 2.0;
                Vec3 worst_normal;
                for (int q : quads_at[i]) {
                    const double d = dot(unit_normal[i], quad_normals[static_cast<std::size_t>(q)]);
                    if (d < worst) {
                        worst = d;
                        worst_normal = quad_normals[static_cast<std::size_t>(q)];
                    }
                }
                unit_normal[i] = normalized(unit_normal[i] + 0.25 * worst_normal);
                offset[i] = full_offset[i];
                place(i);
            }
            shrink_inverted();
        }
    }
    // PaddingOptions::corner_guard: a new hex below half of min(guard, its worst bottom corner) gets the offsets of
    // its four outer vertices scaled by 0.7, up to 10 rounds. Its bottom corners depend on the directions only, and
    // as a neighbourhood's offsets shrink together its top corners tend to them: the converging directions of a
    // valley, the tangential slide of a steeply turned direction and the tilt of the top face between unequal
    // offsets all vanish with the thickness.
    void shrink_to_guard(double guard) {
        for (int round = 0; round < kGuardRounds; ++round) {
            std::vector<char> shrink(offset.size(), 0);
            bool any = false;
            for (const std::array<int, 4>& q : quads) {
                const std::array<Vec3, 8> c = corners(q);
                double bottom = 1;
                for (std::size_t lv = 0; lv < 4; ++lv) bottom = std::min(bottom, hex_corner_value(c, lv));
                if (!(scaled_jacobian(c) < kGuardShare * std::min(guard, bottom))) continue;
                for (int v : q) shrink[local_of(v)] = 1;
                any = true;
            }
            if (!any) break;
            for (std::size_t i = 0; i < offset.size(); ++i)
                if (shrink[i]) {
                    offset[i] *= kGuardShrink;
                    place(i);
                }
        }
    }
    // PaddingOptions::search_cos: at every vertex i with search[i], the best of kSearchSteps + 1 directions on the
    // great circle from its direction to axis[i] (the smallest scaled Jacobian of its new hexes, quads_at[i]; ties
    // keep the earlier candidate, so a direction turns only where its hexes get strictly better).
    void search_directions(const std::vector<char>& search, const std::vector<Vec3>& axis,
                           const std::vector<std::vector<int>>& quads_at) {
        auto worst_around = [&](std::size_t i) {
            double lo = 2;
            for (int q : quads_at[i]) lo = std::min(lo, scaled_jacobian(corners(quads[static_cast<std::size_t>(q)])));
            return lo;
        };
        for (int sweep = 0; sweep < kSearchSweeps; ++sweep)
            for (std::size_t i = 0; i < offset.size(); ++i) {
                if (!search[i]) continue;
                const Vec3 from = unit_normal[i];
                Vec3 best = from;
                double best_value = worst_around(i);
                for (int step = 1; step <= kSearchSteps; ++step) {
                    const double t = static_cast<double>(step) / kSearchSteps;
                    const Vec3 d = from * (1 - t) + axis[i] * t;
                    if (!(squared_norm(d) > 1e-12)) continue;
                    unit_normal[i] = normalized(d);
                    place(i);
                    const double value = worst_around(i);
                    if (value > best_value) {
                        best_value = value;
                        best = unit_normal[i];
                    }
                }
                unit_normal[i] = best;
                place(i);
            }
    }
    static constexpr int kSearchSteps = 4, kSearchSweeps = 2;
    static constexpr int kGuardRounds = 10;
    static constexpr double kGuardShare = 0.5, kGuardShrink = 0.7;
};

// PaddingOptions::search_cos: the vertices (not of bare quads) whose direction leaves a unit corner normal of their
// quads below search_cos, with the axis of the narrowest cone around those normals; then Layer::search_directions.
void search_at_folds(const std::vector<std::array<int, 4>>& quads, const std::vector<std::array<int, 4>>& bare,
                     const std::vector<int>& local, double search_cos, Layer& lay) {
    const std::size_t nb = lay.unit_normal.size();
    std::vector<std::vector<Vec3>> normals = corner_vectors(lay.mesh, quads, local, nb);
    for (std::vector<Vec3>& w : normals)
        for (Vec3& x : w)
            if (squared_norm(x) > 0) x = normalized(x);
    std::vector<char> search = on_bare_quads(bare, local, nb);
    for (std::size_t i = 0; i < nb; ++i)
        search[i] = !search[i] && lowest_corner(normals[i], lay.unit_normal[i]) < search_cos;
    std::vector<Vec3> axis(nb);
    std::vector<std::vector<int>> quads_at(nb);
    for (std::size_t q = 0; q < quads.size(); ++q)
        for (int v : quads[q])
            quads_at[static_cast<std::size_t>(local[static_cast<std::size_t>(v)])].push_back(static_cast<int>(q));
    for (std::size_t i = 0; i < nb; ++i)
        if (search[i]) axis[i] = maximin_direction(normals[i], lay.unit_normal[i]);
    lay.search_directions(search, axis, quads_at);
}

void pad_once(HexMesh& mesh, std::vector<int>& origin, std::vector<int>& layer_of_hex, int layer,
              const PaddingOptions& options, long& bare_count) {
    std::vector<std::array<int, 4>> bare;
    const std::vector<std::array<int, 4>> quads = quads_to_pad(compute_hex_topology(mesh), options, bare);
    bare_count += static_cast<long>(bare.size());
    const std::size_t old_vertices = mesh.points.size();
    std::vector<int> new_id(old_vertices, -1);
    std::vector<int> boundary_vertices;
    for (const std::array<int, 4>& q : quads)
        for (int v : q)
            if (new_id[static_cast<std::size_t>(v)] < 0) {
                new_id[static_cast<std::size_t>(v)] = static_cast<int>(old_vertices + boundary_vertices.size());
                boundary_vertices.push_back(v);
            }
    const std::size_t nb = boundary_vertices.size();
    std::vector<int> local(old_vertices, -1);
    for (std::size_t i = 0; i < nb; ++i) local[static_cast<std::size_t>(boundary_vertices[i])] = static_cast<int>(i);

    // Per boundary vertex: sum of unit quad normals, the normals themselves (for the scaling), shortest boundary edge.
    std::vector<Vec3> normal_sum(nb);
    std::vector<double> shortest_edge(nb, std::numeric_limits<double>::infinity());
    std::vector<double> edge_len_sum(nb, 0.0);
    std::vector<int> edge_count(nb, 0);
    std::vector<Vec3> quad_normals(quads.size());
    for (std::size_t q = 0; q < quads.size(); ++q) {
        const std::array<int, 4>& quad = quads[q];
        quad_normals[q] = quad_normal(mesh, quad);
        for (int i = 0; i < 4; ++i) {
            const int a = quad[static_cast<std::size_t>(i)], b = quad[static_cast<std::size_t>((i + 1) % 4)];
            const std::size_t la = static_cast<std::size_t>(local[static_cast<std::size_t>(a)]);
            const std::size_t lb = static_cast<std::size_t>(local[static_cast<std::size_t>(b)]);
            normal_sum[la] += quad_normals[q];
            const double len =
                distance(mesh.points[static_cast<std::size_t>(a)], mesh.points[static_cast<std::size_t>(b)]);
            shortest_edge[la] = std::min(shortest_edge[la], len);
            shortest_edge[lb] = std::min(shortest_edge[lb], len);
            edge_len_sum[la] += len;  // each edge is seen from its two quads: counted twice at both ends, as its count
            edge_len_sum[lb] += len;
            ++edge_count[la];
            ++edge_count[lb];
        }
    }
    if (options.inward_edges) shorten_to_inward_edges(mesh, local, shortest_edge);
    std::vector<Vec3> unit_normal(nb);
    for (std::size_t i = 0; i < nb; ++i) unit_normal[i] = normalized(normal_sum[i]);
    if (!bare.empty()) project_on_bare(mesh, bare, local, unit_normal);
    if (options.corner_guard > 0) guard_directions(mesh, quads, bare, local, options.corner_guard, unit_normal);
    std::vector<double> cos_sum(nb, 0.0);
    std::vector<int> cos_count(nb, 0);
    for (std::size_t q = 0; q < quads.size(); ++q)
        for (int v : quads[q]) {
            const std::size_t l = static_cast<std::size_t>(local[static_cast<std::size_t>(v)]);
            cos_sum[l] += dot(unit_normal[l], quad_normals[q]);
            ++cos_count[l];
        }

    const std::vector<char> concave = concave_vertices(mesh, quads, unit_normal, local);
    mesh.points.resize(old_vertices + nb);
    Layer lay{mesh,        quads, new_id, local, boundary_vertices, std::move(unit_normal), std::vector<double>(nb),
              old_vertices};
    for (std::size_t i = 0; i < nb; ++i) {
        const int v = boundary_vertices[i];
        const double t =
            options.absolute_thickness > 0 ? options.absolute_thickness : options.thickness * shortest_edge[i];
        const double mean_cos = cos_count[i] > 0 ? cos_sum[i] / cos_count[i] : 1.0;
        const double scale = mean_cos > 1.0 / 3.0 ? 1.0 / mean_cos : 3.0;
        lay.offset[i] = concave[i] ? t * std::min(scale, options.concave_scale) : t * scale;
        if (options.offset_rule) {
            const double mean_edge = edge_count[i] > 0 ? edge_len_sum[i] / edge_count[i] : 0.0;
            lay.offset[i] = options.offset_rule(mesh.points[static_cast<std::size_t>(v)], lay.unit_normal[i],
                                                lay.offset[i], t * scale, mean_edge);
        }
        lay.place(i);
        origin.push_back(origin[static_cast<std::size_t>(v)]);
    }
    if (options.search_cos > 0) search_at_folds(quads, bare, local, options.search_cos, lay);
    lay.fix_inverted(quad_normals);
    if (options.corner_guard > 0) lay.shrink_to_guard(options.corner_guard);
    mesh.hexes.reserve(mesh.hexes.size() + quads.size());
    for (const std::array<int, 4>& q : quads) {
        // q is outward from the mesh, i.e. its right-hand normal
        // points into the new hex: it is the hex's bottom 0-1-2-3.
        std::array<int, 8> hex{};
        for (int i = 0; i < 4; ++i) {
            hex[static_cast<std::size_t>(i)] = q[static_cast<std::size_t>(i)];
            hex[static_cast<std::size_t>(i + 4)] = new_id[static_cast<std::size_t>(q[static_cast<std::size_t>(i)])];
        }
        mesh.hexes.push_back(hex);
        layer_of_hex.push_back(layer);
    }
}

}  // namespace

PaddingResult pad(const HexMesh& mesh, const PaddingOptions& options) {
    check_input(mesh, options);
    PaddingResult result;
    result.mesh = mesh;
    result.first_new_vertex = static_cast<int>(mesh.points.size());
    result.first_new_hex = static_cast<int>(mesh.hexes.size());
    result.origin_vertex.resize(mesh.points.size());
    for (std::size_t v = 0; v < mesh.points.size(); ++v) result.origin_vertex[v] = static_cast<int>(v);
    result.layer_of_hex.assign(mesh.hexes.size(), 0);
    for (int layer = 1; layer <= options.layers; ++layer)
        pad_once(result.mesh, result.origin_vertex, result.layer_of_hex, layer, options, result.bare_quads);
    return result;
}

}  // namespace mesohex
