#include "mesohex/stages/raw_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>

#include "mesohex/core/cone.h"
#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"
#include "mesohex/core/union_find.h"
#include "mesohex/stages/compatible_blocks.h"
#include "mesohex/stages/docked_walls.h"
#include "mesohex/stages/junction_geometry.h"
#include "mesohex/stages/leaflet_geometry.h"

namespace mesohex {

namespace {

bool has_surface(VertexClass c) {
    return c == VertexClass::Extremity || c == VertexClass::Joint || c == VertexClass::BranchingPoint ||
           c == VertexClass::BLJoint || c == VertexClass::LLJoint;
}

bool is_fan(VertexClass c) { return c == VertexClass::FanEdgeVertex || c == VertexClass::FanEdgeEnd; }

// The compatible block at v (compatible_blocks.h), or -1.
int block_at(const ConnectionSurfaces& cs, int v) { return cs.vertex_block.empty() ? -1 : cs.vertex_block[v]; }

// The fan-block chain through v (fan_blocks.h), or -1.
int fan_block_at(const ConnectionSurfaces& cs, int v) {
    return cs.fan_blocks.vertex_chain.empty() ? -1 : cs.fan_blocks.vertex_chain[v];
}

// Number of gaps expected at a fan-edge vertex: the number of faces around its first fan edge (every leaflet through
// the fan continues across the vertex; build_raw_mesh checks this against the gaps it finds).
int expected_gaps(const SkeletonAnalysis& an, int v) {
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i)
        if (an.edge_degree[an.vertex_edges[i]] >= 3) return an.edge_degree[an.vertex_edges[i]];
    return 0;
}

// The plate's one face at corner cube vertex v (SkeletonAnalysis::corner_cube); checked.
int corner_cube_face(const SkeletonAnalysis& an, int v) {
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        if (face_corner(an, f, v) >= 0 && face_counts_at(an, f, v)) return f;
    MESOHEX_CHECK(false, "corner cube vertex " + std::to_string(v) + " has no plate face");
    return -1;
}

// Per vertex: its plate's one face at a corner cube vertex (SkeletonAnalysis::corner_cube), else -1; empty without
// corner cubes.
std::vector<int> corner_cube_faces(const SkeletonAnalysis& an) {
    if (std::find(an.corner_cube.begin(), an.corner_cube.end(), char{1}) == an.corner_cube.end()) return {};
    std::vector<int> face(an.corner_cube.size(), -1);
    for (int v = 0; v < static_cast<int>(an.corner_cube.size()); ++v)
        if (an.corner_cube[v]) face[v] = corner_cube_face(an, v);
    return face;
}

// Rooted branches reuse the 9 vertices of their patch; each of the patch's 8 outer edges gets the first chunk's
// hex on top of what it had: 2 hexes (plates, half-chunks), or 1 where it was a convex half-chunk edge. Patches of
// neighbouring rooted vertices can share outer edges (fingers rooted at every other border vertex): counted per
// edge, keyed by its family and skeleton vertices. Families: U / D = the up / down copies of a and b (plate tops);
// OX / DX = x's out and out-up / out-down copies (base 2); XU / XD = x's up and out-up / down and out-down copies
// (base 2); OU / OD = the out-up / out-down copies of a border vertex and its neighbour (base 1). A side patch next to
// a fan-block chain (a branch moved off a fan-edge end onto a leaflet border, fan_end_repair.h): its U / D edge along
// the fan edge and its XU / XD edge at the chain end are the block's section-corner edges M(w) M(u) and M(w) M(cap),
// whose base is the block's, 1 + the leaflets on M's two axes (add_fan_block_irregular_edges), not 2. At a corner cube
// vertex c (its two out columns) XU is keyed by c and the border neighbour the column serves, and KX = the edge from
// that column's up (down) copy to K's (base 1, the cube's top).
void count_rooted_patch_edges(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                              RawMeshPrediction& p) {
    const int nv = static_cast<int>(an.vertex_class.size());
    enum Family { U, D, OX, DX, XU, XD, OU, OD, KU, KD };
    std::map<std::array<int, 3>, std::array<int, 2>> patch_edges;  // key -> (base hexes, patches)
    auto add = [&](int family, int a, int b, int base) {
        std::array<int, 2>& x = patch_edges[{family, std::min(a, b), std::max(a, b)}];
        x[0] = base;
        ++x[1];
    };
    for (int v = 0; v < nv; ++v) {
        if (!roots_branch(an, v)) continue;
        const int e = first_branch_edge(an, v);
        if (an.vertex_class[v] == VertexClass::LeafletInterior) {
            const LeafletPatch lp = leaflet_patch(skeleton, an, v, e);
            for (int k = 0; k < 4; ++k) {
                const std::array<int, 4>& fv = an.face_vertices[lp.face[k]];
                const int c = lp.corner_centre[k], d = fv[(c + 2) & 3];
                add(lp.up ? U : D, fv[(c + 1) & 3], d, 2);
                add(lp.up ? U : D, d, fv[(c + 3) & 3], 2);
            }
        } else {
            const BorderPatch bp = border_patch(skeleton, an, v, e);
            if (bp.kind == BorderRoot::Out) {
                for (int x : bp.border) {
                    add(OX, x, x, 2);
                    add(DX, x, x, 2);
                    add(OU, v, x, 1);
                    add(OD, v, x, 1);
                }
            } else {
                const int s = bp.up ? U : D;
                // The base of an edge at corner j of face f on a fan-block chain vertex (else 2).
                const auto base = [&](int f, int j) {
                    const int chain = fan_block_at(cs, an.face_vertices[f][j]);
                    if (chain < 0) return 2;
                    const FanBlockChain& c = cs.fan_blocks.chains[chain];
                    const int m = (bp.up ? cs.fan_blocks.corner_up : cs.fan_blocks.corner_down)[f][j];
                    return m < 0 ? 2 : 1 + c.labelled[m] + c.labelled[(m + 1) & 3];
                };
                for (int i = 0; i < 2; ++i) {
                    const int f = bp.face[i];
                    const std::array<int, 4>& fv = an.face_vertices[f];
                    const int c = bp.corner[i], d = fv[(c + 2) & 3];
                    const bool on_chain = fan_block_at(cs, d) >= 0;
                    add(s, fv[(c + 1) & 3], d,
                        on_chain && fan_block_at(cs, fv[(c + 1) & 3]) >= 0 ? base(f, (c + 1) & 3) : 2);
                    add(s, d, fv[(c + 3) & 3],
                        on_chain && fan_block_at(cs, fv[(c + 3) & 3]) >= 0 ? base(f, (c + 3) & 3) : 2);
                }
                for (int x : bp.border) {
                    int b = 2;
                    for (int i = 0; i < 2; ++i)
                        for (int j = 0; j < 4; ++j)
                            if (an.face_vertices[bp.face[i]][j] == x && fan_block_at(cs, x) >= 0)
                                b = base(bp.face[i], j);
                    add(bp.up ? XU : XD, x, x, b);
                    add(bp.up ? OU : OD, v, x, 1);
                }
            }
        }
    }
    // Walls docked on a plate (docked_walls.h): each foot quad gets one wall hex. An edge under two hexes of the same
    // wall (inside the foot) becomes interior with base + 2 hexes; an outline edge is a patch edge like the above.
    std::map<std::array<int, 3>, std::array<int, 3>> foot;  // key -> (base hexes, wall, hexes of that wall)
    const std::vector<int> cube_face = corner_cube_faces(an);
    auto add_foot = [&](int family, int a, int b, int base, int wall) {
        const std::array<int, 3> key{family, std::min(a, b), std::max(a, b)};
        std::array<int, 3>& x = foot[key];
        if (x[2] > 0 && x[1] != wall) {  // two walls' feet touch along it: an outline edge of both
            add(family, a, b, base);
            return;
        }
        x = {base, wall, x[2] + 1};
    };
    for (const FootQuad& q : docked_foot_quads(skeleton, an)) {
        if (q.kind == 0) {
            const std::array<int, 4>& fv = an.face_vertices[q.id];
            for (int k = 0; k < 4; ++k) add_foot(q.up ? U : D, fv[k], fv[(k + 1) & 3], 2, q.wall);
            continue;
        }
        if (q.kind == 2) {  // the corner cube's top (bottom) at vertex q.id: its two column edges and two K edges
            const int f = cube_face[q.id], k = face_corner(an, f, q.id);
            for (int n : {an.face_vertices[f][(k + 1) & 3], an.face_vertices[f][(k + 3) & 3]}) {
                add_foot(q.up ? XU : XD, q.id, n, 2, q.wall);
                add_foot(q.up ? KU : KD, q.id, n, 1, q.wall);
            }
            continue;
        }
        const int a = skeleton.edges[q.id][0], b = skeleton.edges[q.id][1];
        add_foot(q.up ? U : D, a, b, 2, q.wall);
        add_foot(q.up ? XU : XD, a, has_corner_cube(an, a) ? b : a, 2, q.wall);
        add_foot(q.up ? XU : XD, b, has_corner_cube(an, b) ? a : b, 2, q.wall);
        add_foot(q.up ? OU : OD, a, b, 1, q.wall);
    }
    for (const auto& [key, x] : foot) {
        if (x[2] == 1) {
            add(key[0], key[1], key[2], x[0]);
            continue;
        }
        if (x[0] != 2) --p.boundary_irregular_edges[x[0]];
        if (x[0] + 2 != 4) ++p.interior_irregular_edges[x[0] + 2];
    }
    for (const auto& [key, x] : patch_edges) {
        if (x[0] != 2) --p.boundary_irregular_edges[x[0]];
        if (x[0] + x[1] != 2) ++p.boundary_irregular_edges[x[0] + x[1]];
    }
}

// The gaps between the leaflets around fan edges, per (face, corner, side) node f * 8 + corner * 2 + side (0 up,
// 1 down); both empty when the skeleton has no fan edge.
struct FanGaps {
    std::vector<int> gap_of;    // per node at a fan-edge vertex: local gap index, else -1
    std::vector<Vec3> gap_dir;  // per node: the face normal pointing into its gap
};

// Is side k of face f a border edge of f's leaflet: an edge of degree 1, or a flange's chain edge (edge_docked 3,
// docked_walls.h) seen from its plate's face?
bool border_side(const SkeletonAnalysis& an, int f, int k) {
    const int e = an.face_edges[f][k];
    if (an.edge_degree[e] == 1) return true;
    return an.edge_docked[e] == 3 && an.face_leaflet[f] == an.vertex_plate[an.face_vertices[f][k]];
}

// Joins the (face, corner, side) nodes that face the same gap (see find_fan_gaps).
void unite_fan_gap_nodes(const Skeleton& skeleton, const SkeletonAnalysis& an, UnionFind& nodes) {
    const int ne = static_cast<int>(skeleton.edges.size());
    const int nf = static_cast<int>(an.face_vertices.size());
    std::vector<std::vector<std::pair<int, int>>> edge_faces(ne);  // (face, side index) in face order
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) edge_faces[an.face_edges[f][k]].push_back({f, k});
    for (int e = 0; e < ne; ++e) {
        const int p0 = skeleton.edges[e][0], p1 = skeleton.edges[e][1];
        if (an.edge_degree[e] == 2) {
            for (int w : {p0, p1}) {
                if (!is_fan(an.vertex_class[w])) continue;
                const int f = edge_faces[e][0].first, g = edge_faces[e][1].first;
                for (int side = 0; side < 2; ++side)
                    nodes.unite(f * 8 + face_corner(an, f, w) * 2 + side, g * 8 + face_corner(an, g, w) * 2 + side);
            }
            continue;
        }
        if (an.edge_degree[e] < 3 || an.edge_docked[e] != 0) continue;
        const Vec3 t = normalized(skeleton.points[p1] - skeleton.points[p0]);
        const Vec3 m = 0.5 * (skeleton.points[p0] + skeleton.points[p1]);
        std::vector<std::pair<double, int>> order;  // (angle, face)
        Vec3 l1, l2;
        for (const auto& [f, k] : edge_faces[e]) {
            const std::array<int, 4>& fv = an.face_vertices[f];
            Vec3 d = 0.5 * (skeleton.points[fv[(k + 2) & 3]] + skeleton.points[fv[(k + 3) & 3]]) - m;
            d = d - dot(d, t) * t;
            if (order.empty()) {
                l1 = normalized(d);
                l2 = cross(t, l1);
            }
            double a = std::atan2(dot(d, l2), dot(d, l1));
            if (order.empty() || a < 0) a = order.empty() ? 0.0 : a + 2 * std::numbers::pi;
            order.push_back({a, f});
        }
        std::sort(order.begin(), order.end());
        const int d = static_cast<int>(order.size());
        for (int i = 0; i < d; ++i) {
            const int f = order[i].second, g = order[(i + 1) % d].second;
            const int cf = face_corner(an, f, p0), cg = face_corner(an, g, p0);
            const bool bit_f = an.face_vertices[f][cf] != p0 || an.face_vertices[f][(cf + 1) & 3] != p1;
            const bool bit_g = an.face_vertices[g][cg] != p0 || an.face_vertices[g][(cg + 1) & 3] != p1;
            for (int w : {p0, p1})
                nodes.unite(f * 8 + face_corner(an, f, w) * 2 + (bit_f ? 1 : 0),
                            g * 8 + face_corner(an, g, w) * 2 + (bit_g ? 0 : 1));
        }
    }
}

// Fan edges (reference-notes §6.9, §8.6): sort the faces around each fan edge by angle about t = unit(p1 - p0);
// gap i lies between sorted faces i and i+1; face f faces gap i with its up side iff it traverses the edge from
// p0 to p1. A (face, corner, side) node joins the gap it faces; faces sharing an interior edge at a fan-edge
// vertex share both sides. The gaps at vertex w are the resulting classes, numbered by first appearance in
// (face, corner, side) order. Throws Error(UnsupportedConfiguration) naming a fan-edge vertex whose gap count differs
// from expected_gaps.
FanGaps find_fan_gaps(const Skeleton& skeleton, const SkeletonAnalysis& an) {
    FanGaps gaps;
    if (an.counts.fan_edges == 0) return gaps;
    const int nv = static_cast<int>(skeleton.points.size());
    const int nf = static_cast<int>(an.face_vertices.size());
    UnionFind nodes(8 * nf);
    unite_fan_gap_nodes(skeleton, an, nodes);
    gaps.gap_of.assign(8 * nf, -1);
    gaps.gap_dir.assign(8 * nf, Vec3{});
    std::vector<int> n_gaps(nv, 0);
    std::vector<int> root_gap(8 * nf, -1);
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) {
            const int w = an.face_vertices[f][k];
            if (!is_fan(an.vertex_class[w])) continue;
            for (int side = 0; side < 2; ++side) {
                const int node = f * 8 + k * 2 + side, r = nodes.find(node);
                if (root_gap[r] < 0) root_gap[r] = n_gaps[w]++;
                gaps.gap_of[node] = root_gap[r];
                gaps.gap_dir[node] = side == 0 ? an.face_normal[f] : -1.0 * an.face_normal[f];
            }
        }
    for (int v = 0; v < nv; ++v)
        if (is_fan(an.vertex_class[v]) && n_gaps[v] != expected_gaps(an, v))
            throw Error(ErrorCode::UnsupportedConfiguration,
                        "skeleton vertex " + std::to_string(v) + " has " + std::to_string(n_gaps[v]) +
                            " gaps between its fan leaflets instead of " + std::to_string(expected_gaps(an, v)) +
                            ": irregular fans are not meshed yet; edit: let every leaflet around its fan edges "
                            "go on across it (or end with its own border edge at a fan-edge end)",
                        ElementRef{ElementRef::Kind::SkeletonVertex, v});
    return gaps;
}

// Hexes on the ray from a fan-edge vertex w (without a fan block) to each of its gap vertices, counts[w][gap]: per
// (face, corner, side) node at w the plate on that side, per leaflet boundary edge at w its two half-chunks (each on
// its face's side of w). They sum to 2 faces + 2 boundary edges at w; each gap gets an equal share only when the
// leaflets have as many faces on both sides of it (a fan line turning inside a leaflet has 1 face on the inner side
// of the turn and 3 on the outer: rays of 3 and 5 hexes).
std::vector<std::vector<int>> fan_gap_ray_hexes(const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                                                const FanGaps& gaps) {
    const int nv = static_cast<int>(an.vertex_class.size());
    std::vector<std::vector<int>> counts(nv);
    if (gaps.gap_of.empty()) return counts;
    for (int v = 0; v < nv; ++v)
        if (is_fan(an.vertex_class[v]) && fan_block_at(cs, v) < 0) counts[v].assign(expected_gaps(an, v), 0);
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int k = 0; k < 4; ++k) {
            const bool boundary = an.edge_degree[an.face_edges[f][k]] == 1;  // from corner k to corner k + 1
            for (int j : {k, (k + 1) & 3}) {
                const int w = an.face_vertices[f][j];
                if (counts[w].empty() || (j != k && !boundary) || !face_counts_at(an, f, w)) continue;
                const int per_node = (j == k ? 1 : 0) + (boundary ? 1 : 0);
                // corner k's plate once; a boundary side's half-chunk at both of its ends
                for (int side = 0; side < 2; ++side) counts[w][gaps.gap_of[f * 8 + j * 2 + side]] += per_node;
            }
        }
    return counts;
}

}  // namespace

RawMeshPrediction predict_raw_mesh(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs) {
    RawMeshPrediction p;
    const int nv = static_cast<int>(an.vertex_class.size());
    for (int v = 0; v < nv; ++v) {
        const int np = cs.point_begin[v + 1] - cs.point_begin[v];
        const int ned = cs.edge_begin[v + 1] - cs.edge_begin[v];
        if (np > 0 && !roots_branch(an, v) && !roots_fan_cap(an, v))
            p.vertices += block_at(cs, v) >= 0 ? kBlockVertices : 1 + np + ned;
        if (an.vertex_class[v] == VertexClass::Extremity) p.boundary_irregular_edges[1] += 8;
        if (an.vertex_class[v] == VertexClass::LeafletInterior) p.vertices += 3;
        if (an.vertex_class[v] == VertexClass::LeafletBoundary) p.vertices += has_corner_cube(an, v) ? 12 : 6;
        // A corner cube: the 3 edges of each corner hex between two of its outer faces (at K) have 1 hex.
        if (has_corner_cube(an, v)) p.boundary_irregular_edges[1] += 6;
        if (an.vertex_class[v] != VertexClass::BranchingPoint || an.vertex_boundary_edges[v] > 0 ||
            block_at(cs, v) >= 0)
            continue;
        for (int x = cs.point_begin[v]; x < cs.point_begin[v + 1]; ++x)
            if (cs.point_valence[x] != 2) ++p.interior_irregular_edges[2 * cs.point_valence[x]];
    }
    if (an.counts.branch_edges > 0) p.boundary_irregular_edges[1] += 4 * an.counts.branch_edges;
    // Leaflets: the edge from a leaflet vertex to its up (down) copy has one plate hex per incident face, plus the two
    // half-chunks at a boundary vertex; each boundary edge has two outer longitudinal edges with one hex.
    std::vector<int> faces_at(nv, 0);  // leaflet faces (at a docked chain vertex: its plate's)
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int w : an.face_vertices[f]) faces_at[w] += face_counts_at(an, f, w) ? 1 : 0;
    for (int v = 0; v < nv; ++v) {
        const VertexClass c = an.vertex_class[v];
        if (c != VertexClass::LeafletInterior && c != VertexClass::LeafletBoundary) continue;
        const int k = faces_at[v] + (c == VertexClass::LeafletBoundary ? 2 : 0) + (has_corner_cube(an, v) ? 1 : 0);
        if (k != 4) p.interior_irregular_edges[k] += 2;
    }
    // Fan edges (reference-notes §8.6): the fan edge has 2 hexes per face, the extension edge w -> O_w at a fan end
    // one per half-chunk (also 2 per face); the ray from a fan-edge vertex to a gap vertex has the plates (and, at a
    // fan end, the half-chunks) facing that gap (fan_gap_ray_hexes; (2 faces + 2 boundary edges at w) / gaps each
    // when the fan is regular).
    // A fan edge with a fan block (fan_blocks.h) has none of these.
    for (int e = 0; e < static_cast<int>(an.edge_degree.size()); ++e)
        if (an.edge_degree[e] >= 3 && an.edge_docked[e] == 0 && fan_block_at(cs, skeleton.edges[e][0]) < 0)
            ++p.interior_irregular_edges[2 * an.edge_degree[e]];
    const std::vector<std::vector<int>> ray_hexes = fan_gap_ray_hexes(an, cs, find_fan_gaps(skeleton, an));
    for (int v = 0; v < nv; ++v) {
        if (!is_fan(an.vertex_class[v])) continue;
        if (fan_block_at(cs, v) >= 0) {
            p.vertices += fan_block_vertex_ids(cs.fan_blocks, v);
            continue;
        }
        const int g = expected_gaps(an, v);
        const bool end = an.vertex_class[v] == VertexClass::FanEdgeEnd;
        p.vertices += end ? 2 + 2 * g : 1 + g;
        if (end) ++p.interior_irregular_edges[2 * g];
        for (int k : ray_hexes[v])
            if (k != 4) ++p.interior_irregular_edges[k];
    }
    // Leaflet junctions (LL-joints, branching points with leaflets): the ray to a surface point x has, per quad
    // containing x, the 2 kites of a chunk for a branch quad; for a leaflet quad its plates + 2 half-chunks if x is
    // that leaflet's up or down vertex, else the 2 half-chunks of the boundary edge whose out vertex it is.
    {
        std::vector<int> quad_faces(cs.quads.size(), 0);
        for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
            for (int k = 0; k < 4; ++k)
                if (cs.face_corner_quad[f][k] >= 0)
                    ++quad_faces[cs.quad_begin[an.face_vertices[f][k]] + cs.face_corner_quad[f][k]];
        for (int v = 0; v < nv; ++v) {
            const bool ll = an.vertex_class[v] == VertexClass::LLJoint;
            if (!ll && !(an.vertex_class[v] == VertexClass::BranchingPoint && an.vertex_boundary_edges[v] > 0))
                continue;
            std::vector<int> ray(cs.point_begin[v + 1] - cs.point_begin[v], 0);
            for (int q = cs.quad_begin[v]; q < cs.quad_begin[v + 1]; ++q) {
                const int r = cs.quad_rotation[q];
                for (int i = 0; i < 4; ++i)
                    ray[cs.quads[q][i]] += r >= 0 && (((i - r) & 3) == 1 || ((i - r) & 3) == 3) ? quad_faces[q] + 2 : 2;
            }
            for (int k : ray)
                if (k != 4) ++p.interior_irregular_edges[k];
        }
    }
    for (int v = 0; v < nv; ++v) {
        // BL-joint: its up and down rays carry the 2 chunk kites, the 2 half-chunks and one plate per face.
        if (an.vertex_class[v] == VertexClass::BLJoint) p.interior_irregular_edges[4 + faces_at[v]] += 2;
    }
    if (an.counts.boundary_edges > 0) p.boundary_irregular_edges[1] += 2 * an.counts.boundary_edges;
    count_rooted_patch_edges(skeleton, an, cs, p);
    // Compatible blocks: 27 vertices and 8 hexes each, no interior irregular edge; boundary valence 1 / 3 at the cube
    // edges between two free / two docked faces.
    for (const CubeBlock& b : cs.blocks) add_block_irregular_edges(b, p.boundary_irregular_edges);
    // Fan blocks: 4 hexes per fan edge and per open chain end, no interior irregular edge (but the 2 of valence 5 of
    // a branch in a notch).
    for (const FanBlockChain& c : cs.fan_blocks.chains)
        add_fan_block_irregular_edges(c, p.boundary_irregular_edges, p.interior_irregular_edges);
    std::erase_if(p.boundary_irregular_edges, [](const auto& kv) { return kv.second == 0; });
    p.fan_blocks = fan_block_edges(cs.fan_blocks);
    p.fan_block_caps = fan_block_caps(cs.fan_blocks);
    p.compatible_blocks = static_cast<long>(cs.blocks.size()) + p.fan_blocks;
    p.hexes = an.predicted_hexes + kBlockHexes * static_cast<long>(cs.blocks.size()) +
              kFanChunkHexes * (p.fan_blocks + p.fan_block_caps);
    return p;
}

namespace {

// The steps of build_raw_mesh, in the order it calls them. Each is a free function over the stage's inputs and the
// plain arrays the previous steps produced.

void check_raw_mesh_inputs(const Skeleton& skeleton, const ConnectionSurfaces& cs, const BranchFrames& frames) {
    const int nv = static_cast<int>(skeleton.points.size());
    if (skeleton.radii.size() != skeleton.points.size())
        throw Error(ErrorCode::InvalidInput, "the skeleton needs one radius per vertex to build the raw mesh");
    for (int v = 0; v < nv; ++v)
        if (!(skeleton.radii[v] > 0) || !std::isfinite(skeleton.radii[v]))
            throw Error(ErrorCode::InvalidInput,
                        "skeleton vertex " + std::to_string(v) + " has radius " + std::to_string(skeleton.radii[v]) +
                            " (must be finite and > 0)",
                        ElementRef{ElementRef::Kind::SkeletonVertex, v});
    MESOHEX_CHECK(static_cast<int>(cs.point_begin.size()) == nv + 1, "connection surfaces do not match the skeleton");
    MESOHEX_CHECK(frames.directions.size() == cs.directions.size(), "frames do not match the connection surfaces");
}

// Vertex ids: prefix sum of (1 + points + edges) over the connection surfaces. Fills vertex_base (per skeleton
// vertex, -1 when it owns no ids) and returns the number of raw-mesh vertices.
// Leaflet vertices: interior -> centre, up, down; regular boundary -> also out, out-up, out-down.
int assign_vertex_ids(const SkeletonAnalysis& an, const ConnectionSurfaces& cs, int nv, std::vector<int>& vertex_base) {
    vertex_base.assign(nv, -1);
    int n_points = 0;
    for (int v = 0; v < nv; ++v) {
        const VertexClass c = an.vertex_class[v];
        if (has_surface(c)) {
            vertex_base[v] = n_points;
            n_points += block_at(cs, v) >= 0 ? kBlockVertices
                                             : 1 + (cs.point_begin[v + 1] - cs.point_begin[v]) +
                                                   (cs.edge_begin[v + 1] - cs.edge_begin[v]);
        } else if (c == VertexClass::LeafletInterior || c == VertexClass::LeafletBoundary) {
            vertex_base[v] = n_points;
            n_points += c == VertexClass::LeafletInterior ? 3 : has_corner_cube(an, v) ? 12 : 6;
        } else if (is_fan(c)) {
            // centre, one vertex per gap; at a fan end also O_w and one out-copy per gap; on a fan-block chain its
            // section (and cap section)
            const int g = expected_gaps(an, v);
            vertex_base[v] = n_points;
            n_points += fan_block_at(cs, v) >= 0       ? fan_block_vertex_ids(cs.fan_blocks, v)
                        : c == VertexClass::FanEdgeEnd ? 2 + 2 * g
                                                       : 1 + g;
        }
    }
    return n_points;
}

// Centre, up and down vertex id of each face corner; docked: a wall's corner ids on a docked chain (docked_walls.h:
// centre, up, down, out, out-up, out-down per face corner f * 4 + k; empty when nothing is docked).
struct FaceSideIds {
    std::vector<std::array<int, 4>> centre, up, dn;
    std::vector<std::array<int, 6>> docked;
};

FaceSideIds face_side_ids(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                          const std::vector<int>& vertex_base, const FanGaps& gaps) {
    const int nf = static_cast<int>(an.face_vertices.size());
    FaceSideIds ids{std::vector<std::array<int, 4>>(nf), std::vector<std::array<int, 4>>(nf),
                    std::vector<std::array<int, 4>>(nf), docked_corner_ids(skeleton, an, vertex_base)};
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) {
            const int w = an.face_vertices[f][k];
            const int c = vertex_base[w];
            ids.centre[f][k] = c;
            if (!ids.docked.empty() && ids.docked[4 * f + k][0] >= 0) {  // a wall's corner on a docked chain
                ids.centre[f][k] = ids.docked[4 * f + k][0];
                ids.up[f][k] = ids.docked[4 * f + k][1];
                ids.dn[f][k] = ids.docked[4 * f + k][2];
                continue;
            }
            const VertexClass vc = an.vertex_class[w];
            if (fan_block_at(cs, w) >= 0) {  // fan block: Q_a, and the section corners M next to it
                ids.centre[f][k] = c + 1 + cs.fan_blocks.corner_axis[f][k];
                ids.up[f][k] = c + 5 + cs.fan_blocks.corner_up[f][k];
                ids.dn[f][k] = c + 5 + cs.fan_blocks.corner_down[f][k];
            } else if (is_fan(vc)) {
                ids.up[f][k] = c + 1 + gaps.gap_of[f * 8 + k * 2];
                ids.dn[f][k] = c + 1 + gaps.gap_of[f * 8 + k * 2 + 1];
            } else if (cs.face_corner_quad[f][k] >= 0) {
                const int q = cs.quad_begin[w] + cs.face_corner_quad[f][k], r = cs.quad_rotation[q];
                ids.up[f][k] = c + 1 + cs.quads[q][(r + 1) & 3];
                ids.dn[f][k] = c + 1 + cs.quads[q][(r + 3) & 3];
            } else {
                const bool bl = vc == VertexClass::BLJoint;
                ids.up[f][k] = c + (bl ? 2 : 1);
                ids.dn[f][k] = c + (bl ? 4 : 2);
            }
        }
    return ids;
}

// Hex slots: 4 per branch edge (chunks) in edge order, then 2 per leaflet face (plates) in face order, then 2 per
// leaflet boundary edge (half-chunks) in edge order.
struct HexSlots {
    std::vector<int> edge_slot;                     // per edge: first chunk hex, or -1
    int face_slot0 = 0;                             // first plate hex
    std::vector<int> boundary_slot;                 // per edge: first half-chunk hex, or -1
    std::vector<std::array<int, 2>> boundary_side;  // per boundary edge: (face, side index) traversing it
    int block_slot0 = 0;                            // first compatible-block hex (8 per block, in block order)
    int fan_slot0 = 0;                              // first fan-block hex (fan_chain_hexes, in chain order)
    int cube_slot0 = 0;                             // first corner-cube hex (2 per corner cube, in vertex order)
    int n_hex = 0;
};

HexSlots reserve_hex_slots(const SkeletonAnalysis& an, const ConnectionSurfaces& cs, int ne) {
    const int nf = static_cast<int>(an.face_vertices.size());
    HexSlots s;
    s.edge_slot.assign(ne, -1);
    for (int e = 0; e < ne; ++e)
        if (an.edge_degree[e] == 0) {
            s.edge_slot[e] = s.n_hex;
            s.n_hex += 4;
        }
    s.face_slot0 = s.n_hex;
    s.n_hex += 2 * nf;
    s.boundary_slot.assign(ne, -1);
    s.boundary_side.assign(ne, {-1, -1});
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k)
            if (border_side(an, f, k)) s.boundary_side[an.face_edges[f][k]] = {f, k};
    for (int e = 0; e < ne; ++e)
        if (an.edge_degree[e] == 1 || an.edge_docked[e] == 3) {
            s.boundary_slot[e] = s.n_hex;
            s.n_hex += 2;
        }
    s.block_slot0 = s.n_hex;
    const int blocks = static_cast<int>(cs.blocks.size());
    s.n_hex += kBlockHexes * blocks;
    s.fan_slot0 = s.n_hex;
    const long fan = kFanChunkHexes * (fan_block_edges(cs.fan_blocks) + fan_block_caps(cs.fan_blocks));
    s.n_hex += static_cast<int>(fan);
    s.cube_slot0 = s.n_hex;
    s.n_hex += 2 * static_cast<int>(std::count(an.corner_cube.begin(), an.corner_cube.end(), char{1}));
    MESOHEX_CHECK(s.n_hex == an.predicted_hexes + kBlockHexes * blocks + fan, "hex slots differ from the prediction");
    return s;
}

// Compatible blocks: the 8 hexes of the 2 x 2 x 2 cube on the block vertex's 27 ids (no skeleton edge).
void write_block_hexes(const ConnectionSurfaces& cs, const HexSlots& slots, RawMesh& raw) {
    const std::array<std::array<int, 8>, 8> cube = block_hexes();
    for (int b = 0; b < static_cast<int>(cs.blocks.size()); ++b)
        for (int i = 0; i < kBlockHexes; ++i) {
            const int h = slots.block_slot0 + kBlockHexes * b + i, base = raw.vertex_base[cs.blocks[b].vertex];
            for (int k = 0; k < 8; ++k) raw.mesh.hexes[h][k] = base + cube[i][k];
            raw.hex_edge[h] = -1;
        }
}

// Fan blocks: the chunks and caps of every chain (fan_chain_hexes) on its vertices' section ids (no skeleton edge).
void write_fan_block_hexes(const ConnectionSurfaces& cs, const HexSlots& slots, RawMesh& raw) {
    int h = slots.fan_slot0;
    for (const FanBlockChain& c : cs.fan_blocks.chains)
        for (const std::array<std::array<int, 2>, 8>& hex : fan_chain_hexes(c)) {
            for (int k = 0; k < 8; ++k) raw.mesh.hexes[h][k] = raw.vertex_base[c.vertices[hex[k][0]]] + hex[k][1];
            raw.hex_edge[h++] = -1;
        }
}

// Corner cubes (docked_walls.h): at corner cube vertex c with ids c, U, D, K, KU, KD, A, AU, AD, B, BU, BD (offsets
// 0 .. 11; A serves the border edge by which c's plate face leaves c, B the one it arrives by), the hexes
// (c, B, K, A | U, BU, KU, AU) and (c, A, K, B | D, AD, KD, BD), in vertex order.
void write_corner_cubes(const SkeletonAnalysis& an, const HexSlots& slots, RawMesh& raw) {
    int h = slots.cube_slot0;
    for (int v = 0; v < static_cast<int>(an.corner_cube.size()); ++v) {
        if (!an.corner_cube[v]) continue;
        const int c = raw.vertex_base[v];
        raw.mesh.hexes[h] = {c, c + 9, c + 3, c + 6, c + 1, c + 10, c + 4, c + 7};
        raw.mesh.hexes[h + 1] = {c, c + 6, c + 3, c + 9, c + 2, c + 8, c + 5, c + 11};
        raw.hex_edge[h] = raw.hex_edge[h + 1] = -1;
        h += 2;
    }
}

// Leaflet plates (reference-notes §8.2-8.3, VTK order). Ids at a leaflet vertex: base = centre, +1 up, +2 down,
// +3 out, +4 out-up, +5 out-down; "up" is the side of the leaflet's oriented face normals.
void write_leaflet_plates(const SkeletonAnalysis& an, const FaceSideIds& sides, const HexSlots& slots, RawMesh& raw) {
    const int nf = static_cast<int>(an.face_vertices.size());
    tbb::parallel_for(tbb::blocked_range<int>(0, nf, 1024), [&](const tbb::blocked_range<int>& range) {
        for (int f = range.begin(); f != range.end(); ++f) {
            const std::array<int, 4>& c = sides.centre[f];
            const std::array<int, 4>& up = sides.up[f];
            const std::array<int, 4>& dn = sides.dn[f];
            const int h = slots.face_slot0 + 2 * f;
            raw.mesh.hexes[h] = {c[0], c[1], c[2], c[3], up[0], up[1], up[2], up[3]};
            raw.mesh.hexes[h + 1] = {c[0], c[3], c[2], c[1], dn[0], dn[3], dn[2], dn[1]};
            raw.hex_edge[h] = raw.hex_edge[h + 1] = -1;
        }
    });
}

// The two hexes of the half-chunk of leaflet boundary edge e (slot h, traversed by side k of face f).
void write_half_chunk(const SkeletonAnalysis& an, const ConnectionSurfaces& cs, const FanGaps& gaps,
                      const FaceSideIds& sides, int e, int h, int f, int k, RawMesh& raw) {
    // The face traverses e from wa to wb. Offsets from each end's first id (a regular boundary vertex:
    // centre, up, down, out, out-up, out-down; a BL-joint: its connection quad B = (q0..q3) = points
    // (2, 1, 0, 3), with up = q1, down = q3, and §8.5 with k = 0: e arrives at wb -> out = q0,
    // out-up = mid(q0, q1), out-down = mid(q3, q0); e leaves wa -> out = q2, out-up = mid(q1, q2),
    // out-down = mid(q2, q3); ids: Q(x) = base + 1 + x, M(j) = base + 5 + j).
    const int wa = an.face_vertices[f][k], wb = an.face_vertices[f][(k + 1) % 4];
    const int a = sides.centre[f][k], b = sides.centre[f][(k + 1) % 4];
    const bool bla = an.vertex_class[wa] == VertexClass::BLJoint;
    const bool blb = an.vertex_class[wb] == VertexClass::BLJoint;
    const int ua = sides.up[f][k], da = sides.dn[f][k];
    const int ub = sides.up[f][(k + 1) % 4], db = sides.dn[f][(k + 1) % 4];
    int oa = a + (bla ? 1 : 3), oua = a + (bla ? 5 : 4), oda = a + (bla ? 8 : 5);
    int ob = b + 3, oub = b + (blb ? 6 : 4), odb = b + (blb ? 7 : 5);
    // Fan-edge end (§8.6): out = O_w, out-up / out-down = out-copies of the gaps on the face's sides; on a fan block,
    // the cap section's Q_a, M (fan_blocks.h).
    if (fan_block_at(cs, wa) >= 0) {
        const int c = raw.vertex_base[wa] + kFanSectionIds;
        oa = c + 1 + cs.fan_blocks.corner_axis[f][k];
        oua = c + 5 + cs.fan_blocks.corner_up[f][k];
        oda = c + 5 + cs.fan_blocks.corner_down[f][k];
    } else if (an.vertex_class[wa] == VertexClass::FanEdgeEnd) {
        const int g = expected_gaps(an, wa);
        oa = a + 1 + g;
        oua = a + 2 + g + gaps.gap_of[f * 8 + k * 2];
        oda = a + 2 + g + gaps.gap_of[f * 8 + k * 2 + 1];
    }
    // Leaflet junction (§8.5): e leaves wa (q_{k+2}, mid(q_{k+1}, q_{k+2}), mid(q_{k+2}, q_{k+3})) and
    // arrives at wb (q_k, mid(q_k, q_{k+1}), mid(q_{k+3}, q_k)), with the rotation k of the face's quad.
    if (cs.face_corner_quad[f][k] >= 0) {
        const int q = cs.quad_begin[wa] + cs.face_corner_quad[f][k], r = cs.quad_rotation[q];
        const int m0 = a + 1 + (cs.point_begin[wa + 1] - cs.point_begin[wa]);
        oa = a + 1 + cs.quads[q][(r + 2) & 3];
        oua = m0 + cs.quad_edges[q][(r + 1) & 3];
        oda = m0 + cs.quad_edges[q][(r + 2) & 3];
    }
    if (cs.face_corner_quad[f][(k + 1) % 4] >= 0) {
        const int q = cs.quad_begin[wb] + cs.face_corner_quad[f][(k + 1) % 4], r = cs.quad_rotation[q];
        const int m0 = b + 1 + (cs.point_begin[wb + 1] - cs.point_begin[wb]);
        ob = b + 1 + cs.quads[q][r & 3];
        oub = m0 + cs.quad_edges[q][r & 3];
        odb = m0 + cs.quad_edges[q][(r + 3) & 3];
    }
    if (fan_block_at(cs, wb) >= 0) {
        const int c = raw.vertex_base[wb] + kFanSectionIds, kb = (k + 1) % 4;
        ob = c + 1 + cs.fan_blocks.corner_axis[f][kb];
        oub = c + 5 + cs.fan_blocks.corner_up[f][kb];
        odb = c + 5 + cs.fan_blocks.corner_down[f][kb];
    } else if (an.vertex_class[wb] == VertexClass::FanEdgeEnd) {
        const int kb = (k + 1) % 4, g = expected_gaps(an, wb);
        ob = b + 1 + g;
        oub = b + 2 + g + gaps.gap_of[f * 8 + kb * 2];
        odb = b + 2 + g + gaps.gap_of[f * 8 + kb * 2 + 1];
    }
    // A corner cube (docked_walls.h): the plate's face leaves wa by e (column A), arrives at wb by e (column B).
    if (has_corner_cube(an, wa) && face_counts_at(an, f, wa)) {
        oa = a + kCornerCubeColumnA, oua = oa + 1, oda = oa + 2;
    }
    if (has_corner_cube(an, wb) && face_counts_at(an, f, wb)) {
        ob = b + kCornerCubeColumnB, oub = ob + 1, odb = ob + 2;
    }
    // A wall's end on a docked chain (docked_walls.h): its out column is the plate's.
    if (!sides.docked.empty() && sides.docked[4 * f + k][3] >= 0) {
        const std::array<int, 6>& d = sides.docked[4 * f + k];
        oa = d[3];
        oua = d[4];
        oda = d[5];
    }
    if (!sides.docked.empty() && sides.docked[4 * f + (k + 1) % 4][3] >= 0) {
        const std::array<int, 6>& d = sides.docked[4 * f + (k + 1) % 4];
        ob = d[3];
        oub = d[4];
        odb = d[5];
    }
    raw.mesh.hexes[h] = {a, oa, ob, b, ua, oua, oub, ub};
    raw.mesh.hexes[h + 1] = {a, b, ob, oa, da, db, odb, oda};
    raw.hex_edge[h] = raw.hex_edge[h + 1] = e;
}

void write_half_chunks(const SkeletonAnalysis& an, const ConnectionSurfaces& cs, const FanGaps& gaps,
                       const FaceSideIds& sides, const HexSlots& slots, RawMesh& raw) {
    const int ne = static_cast<int>(slots.boundary_slot.size());
    tbb::parallel_for(tbb::blocked_range<int>(0, ne, 1024), [&](const tbb::blocked_range<int>& range) {
        for (int e = range.begin(); e != range.end(); ++e) {
            const int h = slots.boundary_slot[e];
            if (h < 0) continue;
            const auto [f, k] = slots.boundary_side[e];
            write_half_chunk(an, cs, gaps, sides, e, h, f, k, raw);
        }
    });
}

// The 9 ids (centre, 4 points, 4 edge midpoints) of the connection quad of a branch rooted on the plates at
// leaflet vertex v; rooted[v] = 1 for such vertices.
struct RootedPatches {
    std::vector<std::array<int, 9>> ids;
    std::vector<char> rooted;
};

// Inside a leaflet (LeafletPatch): v's up (down) copy, its edge neighbours' and its diagonal neighbours' copies on the
// branch's side.
std::array<int, 9> leaflet_patch_ids(const Skeleton& skeleton, const SkeletonAnalysis& an, const FaceSideIds& sides,
                                     int v, int e) {
    const LeafletPatch patch = leaflet_patch(skeleton, an, v, e);
    const std::vector<std::array<int, 4>>& side = patch.up ? sides.up : sides.dn;
    std::array<int, 9> ids{};
    ids[0] = side[patch.face[0]][patch.corner_centre[0]];
    for (int k = 0; k < 4; ++k) {
        ids[1 + k] = side[patch.face[k]][patch.corner_point[k]];
        ids[5 + k] = side[patch.face[k]][patch.corner_diagonal[k]];
    }
    return ids;
}

// On the border (BorderPatch), read from the half-chunks of v's two boundary edges (written already): Out = v's out
// copy, its border neighbours' out copies and v's out-up / out-down, the neighbours' out-up / out-down; Side = v's up
// (down) copy, the plate copies of face[0] and face[1], v's and the neighbours' out-up (out-down).
std::array<int, 9> border_patch_ids(const Skeleton& skeleton, const SkeletonAnalysis& an, const FaceSideIds& sides,
                                    const HexSlots& slots, const RawMesh& raw, int v, int e) {
    const BorderPatch patch = border_patch(skeleton, an, v, e);
    const int base = raw.vertex_base[v];
    std::array<int, 2> o{}, ou{}, od{};  // per border neighbour: its out, out-up, out-down copies
    for (int i = 0; i < 2; ++i) {
        const int be = patch.border_edge[i], h = slots.boundary_slot[be];
        const auto [f, k] = slots.boundary_side[be];
        const std::array<int, 8>& up = raw.mesh.hexes[h];
        const std::array<int, 8>& dn = raw.mesh.hexes[h + 1];
        const bool leaves = an.face_vertices[f][k] == v;  // the face traverses the edge from v
        o[i] = leaves ? up[2] : up[1];
        ou[i] = leaves ? up[6] : up[5];
        od[i] = leaves ? dn[6] : dn[7];
    }
    const int wu = base + 4, wd = base + 5;
    if (patch.kind == BorderRoot::Out)
        return patch.up_first ? std::array<int, 9>{base + 3, o[0], wu, o[1], wd, ou[0], ou[1], od[1], od[0]}
                              : std::array<int, 9>{base + 3, o[0], wd, o[1], wu, od[0], od[1], ou[1], ou[0]};
    // Side: face[0] = (v, first border neighbour, its diagonal d0, middle), face[1] = (v, middle, d1, the other).
    const int a = patch.first, b = 1 - patch.first;
    const int f0 = patch.face[0], c0 = patch.corner[0], f1 = patch.face[1], c1 = patch.corner[1];
    if (patch.up) {
        const auto& U = sides.up;
        return {base + 1, U[f0][(c0 + 1) & 3], U[f0][(c0 + 3) & 3], U[f1][(c1 + 3) & 3],
                wu,       U[f0][(c0 + 2) & 3], U[f1][(c1 + 2) & 3], ou[b],
                ou[a]};
    }
    const auto& D = sides.dn;
    return {base + 2,
            D[f0][(c0 + 1) & 3],
            wd,
            D[f1][(c1 + 3) & 3],
            D[f0][(c0 + 3) & 3],
            od[a],
            od[b],
            D[f1][(c1 + 2) & 3],
            D[f0][(c0 + 2) & 3]};
}

// One wing of a notch patch (FanBlockChain::notch): the face of the last fan edge (w, l) labelled `label` at w, its
// plate copies on the side of M_j at w's and l's border neighbours ({at w's neighbour, at l's}) and the out copy on
// that side of its border half-chunk at w's neighbour.
struct NotchWing {
    int at_w = -1, at_l = -1, out = -1;
};

NotchWing notch_wing(const SkeletonAnalysis& an, const ConnectionSurfaces& cs, const FaceSideIds& sides,
                     const HexSlots& slots, const RawMesh& raw, int w, int l, int label, int j) {
    const int nf = static_cast<int>(an.face_vertices.size());
    for (int f = 0; f < nf; ++f) {
        const int kw = face_corner(an, f, w), kl = face_corner(an, f, l);
        if (kw < 0 || kl < 0 || cs.fan_blocks.corner_axis[f][kw] != label) continue;
        const bool up = cs.fan_blocks.corner_up[f][kw] == j;  // the side of M_j
        const std::vector<std::array<int, 4>>& side = up ? sides.up : sides.dn;
        const int kx = ((kw + 1) & 3) == kl ? (kw + 3) & 3 : (kw + 1) & 3;  // w's border neighbour x
        const int ky = (kw + 2) & 3;                                        // l's
        const int be = an.face_edges[f][((kw + 1) & 3) == kx ? kw : kx];    // the border side (w, x)
        const int h = slots.boundary_slot[be];
        MESOHEX_CHECK(h >= 0,
                      "fan notch at skeleton vertex " + std::to_string(w) + ": its border side has no half-chunk");
        const bool x_first = an.face_vertices[slots.boundary_side[be][0]][slots.boundary_side[be][1]] ==
                             an.face_vertices[f][kx];  // the half-chunk runs from x
        const std::array<int, 8>& hu = raw.mesh.hexes[h];
        const std::array<int, 8>& hd = raw.mesh.hexes[h + 1];
        return {side[f][kx], side[f][ky], up ? (x_first ? hu[5] : hu[6]) : (x_first ? hd[7] : hd[6])};
    }
    MESOHEX_CHECK(false, "fan notch at skeleton vertex " + std::to_string(w) +
                             ": no face of its last fan edge in leaflet " + std::to_string(label));
    return {};
}

// A branch in the notch at M_j of its chain end v (fan_blocks.h, FanBlockChain::notch): the folded 2 x 2 patch.
std::array<int, 9> notch_patch_ids(const SkeletonAnalysis& an, const ConnectionSurfaces& cs, const FaceSideIds& sides,
                                   const HexSlots& slots, const RawMesh& raw, const FanBlockChain& c, int i) {
    const int n = static_cast<int>(c.vertices.size()), j = c.notch[i == 0 ? 0 : 1];
    const int w = c.vertices[i], l = c.vertices[i == 0 ? 1 : n - 2];
    const NotchWing a = notch_wing(an, cs, sides, slots, raw, w, l, j, j);  // leaflet j (direction A_j)
    const NotchWing b = notch_wing(an, cs, sides, slots, raw, w, l, (j + 1) & 3, j);
    const int mw = raw.vertex_base[w] + 5 + j, mk = mw + kFanSectionIds, ml = raw.vertex_base[l] + 5 + j;
    if (i == 0)  // +t is the L row
        return {mw, b.at_w, ml, a.at_w, mk, b.at_l, a.at_l, a.out, b.out};
    return {mw, b.at_w, mk, a.at_w, ml, b.out, a.out, a.at_l, b.at_l};
}

// Branches rooted on the plates: their connection quad's centre, 4 points and 4 edge midpoints are vertices the
// plates and half-chunks already have; a branch on a fan block's cap: the cap section's (fan_cap_section_ids), on
// its side section: the side's 2 x 2 quads (fan_side_section_ids).
RootedPatches rooted_patch_ids(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                               const FaceSideIds& sides, const HexSlots& slots, const RawMesh& raw) {
    const int nv = static_cast<int>(skeleton.points.size());
    RootedPatches rp{std::vector<std::array<int, 9>>(nv, std::array<int, 9>{}), std::vector<char>(nv, 0)};
    for (int v = 0; v < nv; ++v) {
        if (roots_fan_cap(an, v)) {  // on a fan block's cap: the cap section in the connection quad's order
            const FanBlockChain& c = cs.fan_blocks.chains[fan_block_at(cs, v)];
            const int i = cs.fan_blocks.vertex_index[v];
            rp.rooted[v] = 1;
            if (c.notch[i == 0 ? 0 : 1] >= 0) {  // in the notch between two leaflets at a section corner
                rp.ids[v] = notch_patch_ids(an, cs, sides, slots, raw, c, i);
                continue;
            }
            if (c.side_axis[i == 0 ? 0 : 1] >= 0) {  // on the block's side section (fan_side_section_ids)
                const std::array<std::array<int, 2>, 9> ids = fan_side_section_ids(c, i);
                for (int x = 0; x < 9; ++x) rp.ids[v][x] = raw.vertex_base[c.vertices[ids[x][0]]] + ids[x][1];
                continue;
            }
            const std::array<int, 9> ids = fan_cap_section_ids(c, i);
            for (int x = 0; x < 9; ++x) rp.ids[v][x] = raw.vertex_base[v] + ids[x];
            continue;
        }
        if (!roots_branch(an, v)) continue;
        rp.rooted[v] = 1;
        const int e = first_branch_edge(an, v);
        rp.ids[v] = an.vertex_class[v] == VertexClass::LeafletInterior
                        ? leaflet_patch_ids(skeleton, an, sides, v, e)
                        : border_patch_ids(skeleton, an, sides, slots, raw, v, e);
    }
    return rp;
}

// Blocks: one chunk of 4 hexes per branch edge (reference-notes §8.1, written in VTK order: the kite at the
// first endpoint u, counter-clockwise around the direction u -> v, is the bottom face).
void write_branch_chunks(const Skeleton& skeleton, const ConnectionSurfaces& cs, const BranchFrames& frames,
                         const HexSlots& slots, const RootedPatches& rp, RawMesh& raw) {
    const int ne = static_cast<int>(skeleton.edges.size());
    tbb::parallel_for(tbb::blocked_range<int>(0, ne, 1024), [&](const tbb::blocked_range<int>& range) {
        for (int e = range.begin(); e != range.end(); ++e) {
            const int h0 = slots.edge_slot[e];
            if (h0 < 0) continue;
            const int u = skeleton.edges[e][0], v = skeleton.edges[e][1];
            const int qu = cs.edge_quad[e][0], qv = cs.edge_quad[e][1];
            const int ru = frames.edge_rotation[e][0], rv = frames.edge_rotation[e][1];
            const int bu = raw.vertex_base[u], bv = raw.vertex_base[v];
            const int mu = bu + 1 + (cs.point_begin[u + 1] - cs.point_begin[u]);
            const int mv = bv + 1 + (cs.point_begin[v + 1] - cs.point_begin[v]);
            const std::array<int, 4>& au = cs.quads[qu];
            const std::array<int, 4>& eu = cs.quad_edges[qu];
            const std::array<int, 4>& av = cs.quads[qv];
            const std::array<int, 4>& ev = cs.quad_edges[qv];
            // Ids of the centre, of surface point x and of surface edge j at an end (its own surface vertices, the
            // plate vertices of a rooted branch's patch, or the cube face of a compatible block: quad i's points and
            // edges are 4i..4i+3, Q_k and M_k of its block_section).
            const int blu = block_at(cs, u), blv = block_at(cs, v);
            std::array<int, 9> su{}, sv{};
            if (blu >= 0) su = block_section(cs.blocks[blu].labels[qu - cs.quad_begin[u]]);
            if (blv >= 0) sv = block_section(cs.blocks[blv].labels[qv - cs.quad_begin[v]]);
            auto section = [&](int w) -> const std::array<int, 9>* {
                return w == u ? (blu >= 0 ? &su : nullptr) : (blv >= 0 ? &sv : nullptr);
            };
            auto centre = [&](int w, int b) {
                return rp.rooted[w] ? rp.ids[w][0] : section(w) ? b + (*section(w))[0] : b;
            };
            auto point = [&](int w, int b, int x) {
                return rp.rooted[w] ? rp.ids[w][1 + x] : section(w) ? b + (*section(w))[1 + (x & 3)] : b + 1 + x;
            };
            auto edge = [&](int w, int m, int j) {
                const int b = raw.vertex_base[w];
                return rp.rooted[w] ? rp.ids[w][5 + j] : section(w) ? b + (*section(w))[5 + (j & 3)] : m + j;
            };
            for (int k = 0; k < 4; ++k) {
                // a_k = au[(ru + k) & 3]; matched far vertex a'_k = b_{(2 - k) & 3} = av[(rv + 2 - k) & 3].
                const int a0 = au[(ru + k) & 3], a1 = au[(ru + k + 1) & 3], ea = eu[(ru + k) & 3];
                const int b0 = av[(rv + 2 - k) & 3], b1 = av[(rv + 1 - k) & 3], eb = ev[(rv + 1 - k) & 3];
                raw.mesh.hexes[h0 + k] = {centre(u, bu), point(u, bu, a0), edge(u, mu, ea), point(u, bu, a1),
                                          centre(v, bv), point(v, bv, b0), edge(v, mv, eb), point(v, bv, b1)};
                raw.hex_edge[h0 + k] = e;
            }
        }
    });
}

// Radius of v after the margin limit of the branch edges joining it to branching points: a vertex next to a
// branching point u (edge length L, direction d from u) gets at most L sin(kappa m), m = margin of d inside u's
// quad, so that its cross-section seen from u fits inside that quad: then every hex corner on u's sphere is positive
// (see relax_partition in connection_surfaces.cpp).
double branching_margin_radius(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                               const BranchFrames& frames, const RawMeshOptions& options, int v, double radius) {
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (an.edge_degree[e] != 0) continue;
        const int side_u = skeleton.edges[e][0] == v ? 1 : 0;
        const int u = skeleton.edges[e][side_u];
        if (an.vertex_class[u] != VertexClass::BranchingPoint) continue;
        const Vec3 d = skeleton.points[v] - skeleton.points[u];
        const double L = norm(d);
        const int gq = cs.edge_quad[e][side_u];
        std::array<Vec3, 4> q;
        for (int k = 0; k < 4; ++k) q[k] = frames.directions[cs.point_begin[u] + cs.quads[gq][k]];
        const double m = spherical_quad_margin(q, d / L);
        if (m > 0) radius = margin_limited_radius(radius, L, m, options.margin_fraction);
    }
    return radius;
}

// The unit direction of branching point v's local surface point x (x < np) or edge midpoint (x = np + j).
Vec3 surface_direction(const ConnectionSurfaces& cs, const BranchFrames& frames, int v, int x) {
    const int p0 = cs.point_begin[v], np = cs.point_begin[v + 1] - p0;
    if (x < np) return frames.directions[p0 + x];
    const std::array<int, 2>& ed = cs.edges[cs.edge_begin[v] + x - np];
    return normalized(frames.directions[p0 + ed[0]] + frames.directions[p0 + ed[1]]);
}

// RawMeshOptions::bridge_quad_radius: the radius of each surface point of branching point v (local point x at
// out[x], local surface edge j at out[np + j]). A point on the quad of a bridge (v, u), u a branching point, gets the
// margin limit of that bridge (branching_margin_radius's rule for that edge alone; the smallest over its bridges);
// every other point keeps v's input radius. An edge midpoint gets its edge's bridge limit when the edge is a side of
// a bridge quad, else the mean of its two ends' radii. on_bridge_quad[x]: x is a corner or side midpoint of a bridge
// quad (its radius is that limit).
void bridge_quad_point_radii(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                             const BranchFrames& frames, const RawMeshOptions& options, int v, std::vector<double>& out,
                             std::vector<char>& on_bridge_quad) {
    const int p0 = cs.point_begin[v], np = cs.point_begin[v + 1] - p0;
    const int e0 = cs.edge_begin[v], ne = cs.edge_begin[v + 1] - e0;
    const double r = skeleton.radii[v];
    out.assign(static_cast<std::size_t>(np + ne), r);
    on_bridge_quad.assign(static_cast<std::size_t>(np + ne), 0);
    std::vector<double> side(static_cast<std::size_t>(ne), r);
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (an.edge_degree[e] != 0) continue;
        const int side_v = skeleton.edges[e][0] == v ? 0 : 1;
        const int u = skeleton.edges[e][1 - side_v];
        if (an.vertex_class[u] != VertexClass::BranchingPoint) continue;
        const Vec3 d = skeleton.points[v] - skeleton.points[u];
        const double L = norm(d);
        const int gu = cs.edge_quad[e][1 - side_v], gv = cs.edge_quad[e][side_v];
        if (gu < 0 || gv < 0 || L <= 0) continue;
        std::array<Vec3, 4> q;
        for (int k = 0; k < 4; ++k) q[k] = frames.directions[cs.point_begin[u] + cs.quads[gu][k]];
        const double m = spherical_quad_margin(q, d / L);
        if (m <= 0) continue;
        const double limited = margin_limited_radius(r, L, m, options.margin_fraction);
        for (int k = 0; k < 4; ++k) {
            double& a = out[static_cast<std::size_t>(cs.quads[gv][k])];
            a = std::min(a, limited);
            double& b = side[static_cast<std::size_t>(cs.quad_edges[gv][k])];
            b = std::min(b, limited);
            on_bridge_quad[static_cast<std::size_t>(cs.quads[gv][k])] = 1;
            on_bridge_quad[static_cast<std::size_t>(np + cs.quad_edges[gv][k])] = 1;
        }
    }
    for (int j = 0; j < ne; ++j) {
        const std::array<int, 2>& ed = cs.edges[e0 + j];
        const double mean = 0.5 * (out[static_cast<std::size_t>(ed[0])] + out[static_cast<std::size_t>(ed[1])]);
        out[static_cast<std::size_t>(np + j)] =
            side[static_cast<std::size_t>(j)] < r ? side[static_cast<std::size_t>(j)] : mean;
    }
}

// Sharp turn at a joint v: its cross-section (normal to the bisector) reaches r sin(theta / 2) along each of its
// edges; keep that within turn_fraction of half of each edge so that neighbouring cross-sections cannot cross.
double turn_limited_radius(const Skeleton& skeleton, const SkeletonAnalysis& an, const RawMeshOptions& options, int v,
                           double radius) {
    const int e0 = an.vertex_edges[an.vertex_edge_begin[v]];
    const int e1 = an.vertex_edges[an.vertex_edge_begin[v] + 1];
    const Vec3& p = skeleton.points[v];
    const int w0 = skeleton.edges[e0][0] == v ? skeleton.edges[e0][1] : skeleton.edges[e0][0];
    const int w1 = skeleton.edges[e1][0] == v ? skeleton.edges[e1][1] : skeleton.edges[e1][0];
    const Vec3 a = skeleton.points[w0] - p, b = skeleton.points[w1] - p;
    const double la = norm(a), lb = norm(b);
    // turn angle theta = pi - angle(a, b); sin(theta / 2) = cos(angle(a, b) / 2)
    const double cos_ab = std::clamp(dot(a, b) / (la * lb), -1.0, 1.0);
    const double reach = std::sqrt(0.5 * (1 + cos_ab));
    if (reach > 1e-9) radius = std::min(radius, options.turn_fraction * 0.5 * std::min(la, lb) / reach);
    return radius;
}

// Effective radius per skeleton vertex: the input radius, limited next to branching points and at sharp joints.
std::vector<double> effective_radii(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                                    const BranchFrames& frames, const RawMeshOptions& options) {
    const int nv = static_cast<int>(skeleton.points.size());
    std::vector<double> radius(skeleton.radii);
    tbb::parallel_for(tbb::blocked_range<int>(0, nv, 512), [&](const tbb::blocked_range<int>& range) {
        for (int v = range.begin(); v != range.end(); ++v) {
            radius[v] = branching_margin_radius(skeleton, an, cs, frames, options, v, radius[v]);
            if (an.vertex_class[v] == VertexClass::Joint)
                radius[v] = turn_limited_radius(skeleton, an, options, v, radius[v]);
        }
    });
    return radius;
}

// The distance of fan end v's cap beyond v along its out direction e (unit): reach, or with
// RawMeshOptions::fan_end_cap_to_border the lowest of v's leaflet border neighbours along e when that is farther
// (every border side at v then leans out past v: a retracted fan end).
double fan_end_cap_height(const Skeleton& skeleton, const SkeletonAnalysis& an, const RawMeshOptions& options, int v,
                          const Vec3& e, double reach) {
    if (!options.fan_end_cap_to_border) return reach;
    double lowest = std::numeric_limits<double>::infinity();
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int ed = an.vertex_edges[i];
        if (an.edge_degree[ed] != 1) continue;
        const int x = skeleton.edges[ed][0] == v ? skeleton.edges[ed][1] : skeleton.edges[ed][0];
        lowest = std::min(lowest, dot(skeleton.points[x] - skeleton.points[v], e));
    }
    return std::isfinite(lowest) ? std::max(reach, lowest) : reach;
}

// The half size of the sections at a chain end with a branch in a notch (FanBlockChain::notch) and at its neighbour
// on the chain: min(r, kFanNotchHalf x
// its shortest leaflet border edge), so that the section corner M_j stands where the two plates' faces meet (each
// plate r thick beyond the fan line), the notch a right angle; the half-edge bound of other vertices would pull the
// plates' copies in to M_j and close the notch to a narrow groove (the plate copy at the border neighbour r off the
// leaflet, M_j h off it: docs/blocks.md, "Thick moved roots on the fan block's side section").
double fan_notch_half_size(const Skeleton& skeleton, const SkeletonAnalysis& an, double r, int v) {
    double h = r;
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (an.edge_degree[e] != 1) continue;
        const std::array<int, 2>& ed = skeleton.edges[e];
        h = std::min(h, kFanNotchHalf * distance(skeleton.points[ed[0]], skeleton.points[ed[1]]));
    }
    return h;
}

// A fan-block chain vertex (fan_blocks.h): its section (and cap section) with half size h = min(r, half its shortest
// incident edge), so that the leaflet corners Q_a = v + h a stay inside every incident edge; the cap section
// fan_end_cap_height(h) beyond v.
void place_fan_block_vertex(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                            const RawMeshOptions& options, double r, int v, RawMesh& raw) {
    double h = r;
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const std::array<int, 2>& ed = skeleton.edges[an.vertex_edges[i]];
        h = std::min(h, 0.5 * distance(skeleton.points[ed[0]], skeleton.points[ed[1]]));
    }
    const FanBlockChain& c = cs.fan_blocks.chains[fan_block_at(cs, v)];
    const int i = cs.fan_blocks.vertex_index[v], n = static_cast<int>(c.vertices.size());
    // A notch end and its neighbour on the chain (the fold M_j runs straight over the last fan edge).
    if (!c.closed && ((i <= 1 && c.notch[0] >= 0) || (i >= n - 2 && c.notch[1] >= 0)))
        h = fan_notch_half_size(skeleton, an, r, v);
    double cap = h;
    if (!c.closed && (i == 0 || i == n - 1))
        cap = fan_end_cap_height(skeleton, an, options, v, (i == 0 ? -1.0 : 1.0) * c.tangent[i], h);
    std::vector<Vec3> pts;
    fan_section_points(c, i, skeleton.points[v], h, cap, pts);
    for (std::size_t x = 0; x < pts.size(); ++x) raw.mesh.points[raw.vertex_base[v] + static_cast<int>(x)] = pts[x];
}

// The unit direction of O_w at fan end v whose fan edge continues along -e (unit): e, unless the leaflets' own out
// directions at v (per border edge at v: in its face's plane, normal to the edge, away from the face) are served
// better by their narrowest cone's axis (narrower_cone_axis, kFanDirectionGainDeg); then that axis. Every
// half-chunk at v has O_w as its out vertex there. At a T / X fan end whose leaflet borders leave v across the fan
// line, every such out is e (gain 0). At a flange (the fan chain on part of a plate's border, walls above and below:
// the plate's border runs on along the fan line past v) the plate's out there is normal to e, and O_w = v + r e put
// the plate's border half-chunk's out vertex on its own edge (those half-chunks folded); the axis, 45 degrees
// between the walls' out (e) and the plate's, serves all of them.
Vec3 fan_end_out_direction(const Skeleton& skeleton, const SkeletonAnalysis& an, int v, const Vec3& e) {
    std::vector<Vec3> outs;
    const Vec3& c = skeleton.points[v];
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int k = 0; k < 4; ++k) {
            if (an.face_vertices[f][k] != v) continue;
            Vec3 centroid{};
            for (int w : an.face_vertices[f]) centroid += 0.25 * skeleton.points[w];
            const Vec3 away = c - centroid;
            for (int j : {k, (k + 3) & 3}) {
                if (an.edge_degree[an.face_edges[f][j]] != 1) continue;
                const int o = an.face_vertices[f][j == k ? (k + 1) & 3 : j];
                const Vec3 t = normalized(skeleton.points[o] - c);
                const Vec3 out = away - dot(away, t) * t;
                if (norm(out) > 0) outs.push_back(normalized(out));
            }
        }
    return narrower_cone_axis(outs, e, kFanDirectionGainDeg);
}

// Whether the leaflets around a gap at a fan vertex (`leaflets`: per face corner facing the gap, its face's leaflet)
// have different numbers of faces there (a leaflet running on past a fan end, a fan line turning inside a plate).
// A leaflet twisted or curved around a regular fan vertex has as many as its neighbour: its gap keeps the bisector.
bool unequal_leaflet_faces(std::vector<int> leaflets) {
    std::sort(leaflets.begin(), leaflets.end());
    long fewest = -1, most = -1;
    for (std::size_t i = 0; i < leaflets.size();) {
        std::size_t next = i;
        while (next < leaflets.size() && leaflets[next] == leaflets[i]) ++next;
        const long n = static_cast<long>(next - i);
        fewest = fewest < 0 ? n : std::min(fewest, n);
        most = std::max(most, n);
        i = next;
    }
    return fewest != most;
}

// Fan-edge vertices (reference-notes §10): gap vertex = w + r unit(sum of the normals of the faces around the
// gap, each flipped into the gap), the bisector (or, when one side of the gap has more faces at w than the other
// (unequal_leaflet_faces), the axis of those normals' narrowest cone: narrower_cone_axis); at a fan end
// also O_w = w + H e and gap out-copies = gap + H e, e = unit vector along the fan edge pointing away from it
// (fan_end_out_direction: or the leaflets' own outs' axis), H = r or farther at a retracted fan end
// (fan_end_cap_height). Serial in face order: deterministic.
void place_fan_vertices(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                        const FanGaps& gaps, const RawMeshOptions& options, const std::vector<double>& radius,
                        RawMesh& raw) {
    if (an.counts.fan_edges == 0) return;
    const int nv = static_cast<int>(skeleton.points.size());
    const int nf = static_cast<int>(an.face_vertices.size());
    std::vector<Vec3> gap_sum(raw.mesh.points.size());
    std::vector<std::vector<Vec3>> gap_dirs(raw.mesh.points.size());
    std::vector<std::vector<int>> gap_leaflets(raw.mesh.points.size());
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) {
            const int w = an.face_vertices[f][k];
            if (!is_fan(an.vertex_class[w]) || fan_block_at(cs, w) >= 0) continue;
            for (int side = 0; side < 2; ++side) {
                const int id = raw.vertex_base[w] + 1 + gaps.gap_of[f * 8 + k * 2 + side];
                const Vec3& n = gaps.gap_dir[f * 8 + k * 2 + side];  // unit, or 0 for a degenerate face
                gap_sum[id] += n;
                if (norm(n) > 0) gap_dirs[id].push_back(normalized(n));  // a zero normal bounds no cone
                gap_leaflets[id].push_back(an.face_leaflet[f]);
            }
        }
    for (int v = 0; v < nv; ++v) {
        const VertexClass vc = an.vertex_class[v];
        if (!is_fan(vc)) continue;
        if (fan_block_at(cs, v) >= 0) {
            place_fan_block_vertex(skeleton, an, cs, options, radius[v], v, raw);
            continue;
        }
        const int base = raw.vertex_base[v], g = expected_gaps(an, v);
        const Vec3& c = skeleton.points[v];
        const double r = radius[v];
        raw.mesh.points[base] = c;
        for (int j = 0; j < g; ++j) {
            const Vec3 bisector = normalized(gap_sum[base + 1 + j]);
            const bool uneven = unequal_leaflet_faces(gap_leaflets[base + 1 + j]);
            raw.mesh.points[base + 1 + j] =
                c +
                r * (uneven ? narrower_cone_axis(gap_dirs[base + 1 + j], bisector, kFanDirectionGainDeg) : bisector);
        }
        if (vc != VertexClass::FanEdgeEnd) continue;
        Vec3 e{};
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int fe = an.vertex_edges[i];
            if (an.edge_degree[fe] < 3) continue;
            const int o = skeleton.edges[fe][0] == v ? skeleton.edges[fe][1] : skeleton.edges[fe][0];
            e = normalized(c - skeleton.points[o]);
        }
        e = fan_end_out_direction(skeleton, an, v, e);
        e = fan_end_cap_height(skeleton, an, options, v, e, r) * e;
        raw.mesh.points[base + 1 + g] = c + e;
        for (int j = 0; j < g; ++j) raw.mesh.points[base + 2 + g + j] = raw.mesh.points[base + 1 + j] + e;
    }
}

// A leaflet vertex placed by place_leaflet_vertex (one up / down column for all its faces).
bool leaflet_column_class(VertexClass c) {
    return c == VertexClass::LeafletInterior || c == VertexClass::LeafletBoundary;
}

// RawMeshOptions::leaflet_offset_fraction: per leaflet column vertex the factor (at most 1) on its up and on its down
// offset (with the up / down column's out point) so that, for every two corners v, w of one face (sides and
// diagonals), the two offsets on that side bring v and w closer along the line v -> w by at most fraction x |w - v|
// (the offsets fold over each other where they would pass). A pair past the limit scales both its offsets on that
// side by the same factor; a vertex keeps the smallest factor of its pairs. 1, 1 elsewhere and with fraction <= 0.
std::vector<std::array<double, 2>> leaflet_offset_limits(const Skeleton& skeleton, const SkeletonAnalysis& an,
                                                         const LeafletVertexFrames& leaf,
                                                         const std::vector<double>& radius, double fraction) {
    std::vector<std::array<double, 2>> limit(skeleton.points.size(), {1.0, 1.0});
    if (!(fraction > 0)) return limit;
    for (const std::array<int, 4>& face : an.face_vertices)
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) {
                const int v = face[i], w = face[j];
                if (!leaflet_column_class(an.vertex_class[v]) || !leaflet_column_class(an.vertex_class[w])) continue;
                const Vec3 d = skeleton.points[w] - skeleton.points[v];
                const double e = norm(d);
                if (!(e > 0)) continue;
                const double nv = dot(leaf.normal[v], d) / e * radius[v], nw = dot(leaf.normal[w], d) / e * radius[w];
                // Up: v moves by up_scale r_v n_v, w by up_scale r_w n_w; down: the opposite signs.
                const double shrink[2] = {leaf.up_scale[v] * nv - leaf.up_scale[w] * nw,
                                          leaf.down_scale[w] * nw - leaf.down_scale[v] * nv};
                for (int side = 0; side < 2; ++side) {
                    if (!(shrink[side] > fraction * e)) continue;
                    const double k = fraction * e / shrink[side];
                    limit[v][side] = std::min(limit[v][side], k);
                    limit[w][side] = std::min(limit[w][side], k);
                }
            }
    return limit;
}

// Corner cube vertex v (docked_walls.h) of radius r, plate normal n: its columns A and B stand r straight out of its
// two border edges (in the plate's plane, normal to the edge), K at A + B - v; each with its up / down copies at r n
// (limit: leaflet_offset_limits's factors).
void place_corner_cube(const Skeleton& skeleton, const SkeletonAnalysis& an, const Vec3& n, int v, double r,
                       const std::array<double, 2>& limit, RawMesh& raw) {
    const int f = corner_cube_face(an, v), k = face_corner(an, f, v);  // the plate's one face at v, v's corner in it
    const int base = raw.vertex_base[v];
    const Vec3& c = skeleton.points[v];
    const Vec3 ta = skeleton.points[an.face_vertices[f][(k + 1) & 3]] - c;  // along the edge f leaves v by
    const Vec3 tb = c - skeleton.points[an.face_vertices[f][(k + 3) & 3]];  // along the edge f arrives by
    const Vec3 a = c + r * normalized(cross(ta, n)), b = c + r * normalized(cross(tb, n)), kk = a + b - c;
    const Vec3 up = limit[0] * r * n, dn = limit[1] * r * n;
    const std::array<Vec3, 3> column{kk, a, b};
    for (int j = 0; j < 3; ++j) {
        raw.mesh.points[base + 3 + 3 * j] = column[j];
        raw.mesh.points[base + 4 + 3 * j] = column[j] + up;
        raw.mesh.points[base + 5 + 3 * j] = column[j] - dn;
    }
}

// Leaflet vertex v of radius r: centre, up and down; at a boundary vertex also its out column (out, out-up,
// out-down); limit: leaflet_offset_limits's up / down factors for v.
void place_leaflet_vertex(const Skeleton& skeleton, const SkeletonAnalysis& an, const LeafletVertexFrames& leaf,
                          const RawMeshOptions& options, int v, double r, const std::array<double, 2>& limit,
                          RawMesh& raw) {
    const int base = raw.vertex_base[v];
    const Vec3& c = skeleton.points[v];
    const Vec3 n = r * leaf.normal[v];
    raw.mesh.points[base] = c;
    raw.mesh.points[base + 1] = c + limit[0] * leaf.up_scale[v] * n;
    raw.mesh.points[base + 2] = c - limit[1] * leaf.down_scale[v] * n;
    if (an.vertex_class[v] != VertexClass::LeafletBoundary) return;
    Vec3 o = leaf.out[v], m = n;
    if (an.vertex_border_root[v] == BorderRoot::Out) {
        // The out column of a vertex rooting a branch on its out patch turns in the leaflet's plane
        // towards the branch (border_root_turn), then about the border by the branch's tilt out of
        // that plane (border_root_tilt): the patch then faces the branch.
        const int e = first_branch_edge(an, v);
        const Vec3 b = skeleton.points[skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0]] - c;
        const Vec3 un = leaf.normal[v];
        const Vec3 side = cross(un, o);
        const double psi = options.border_root_turn * std::atan2(dot(b, side), dot(b, o));
        const Vec3 o1 = std::cos(psi) * o + std::sin(psi) * side;
        const double phi = options.border_root_tilt * std::atan2(dot(b, un), dot(b, o1));
        o = std::cos(phi) * o1 + std::sin(phi) * un;
        m = r * (std::cos(phi) * un - std::sin(phi) * o1);
    }
    const Vec3 out = c + leaflet_out_distance(skeleton, an, leaf, v, r) * o;
    raw.mesh.points[base + 3] = out;
    raw.mesh.points[base + 4] = out + limit[0] * m;
    raw.mesh.points[base + 5] = out - limit[1] * m;
    if (has_corner_cube(an, v)) place_corner_cube(skeleton, an, leaf.normal[v], v, r, limit, raw);
}

// Geometry transfer: centre, surface points and surface-edge midpoints on the sphere of local radius; leaflet
// vertices along the leaflet's normal and out directions (shared with the junction surfaces).
void place_vertices(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                    const BranchFrames& frames, const RawMeshOptions& options, const std::vector<double>& radius,
                    RawMesh& raw) {
    const int nv = static_cast<int>(skeleton.points.size());
    const LeafletVertexFrames leaf = leaflet_vertex_frames(skeleton, an);
    const std::vector<std::array<double, 2>> limits =
        leaflet_offset_limits(skeleton, an, leaf, radius, options.leaflet_offset_fraction);
    tbb::parallel_for(tbb::blocked_range<int>(0, nv, 512), [&](const tbb::blocked_range<int>& range) {
        for (int v = range.begin(); v != range.end(); ++v) {
            const int base = raw.vertex_base[v];
            if (base < 0 || is_fan(an.vertex_class[v])) continue;
            const Vec3& c = skeleton.points[v];
            const double r = radius[v];
            const VertexClass vc = an.vertex_class[v];
            if (vc == VertexClass::LeafletInterior || vc == VertexClass::LeafletBoundary) {
                place_leaflet_vertex(skeleton, an, leaf, options, v, r, limits[v], raw);
                continue;
            }
            if (block_at(cs, v) >= 0) {
                // Compatible block: K(i, j, k) = c + h (i F_x + j F_y + k F_z), h = min(r, half the shortest edge).
                double h = r;
                for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
                    const std::array<int, 2>& ed = skeleton.edges[an.vertex_edges[i]];
                    h = std::min(h, 0.5 * distance(skeleton.points[ed[0]], skeleton.points[ed[1]]));
                }
                const CubeBlock& blk = cs.blocks[block_at(cs, v)];
                for (int x = 0; x < kBlockVertices; ++x) raw.mesh.points[base + x] = block_point(blk, c, h, x);
                continue;
            }
            const int p0 = cs.point_begin[v], np = cs.point_begin[v + 1] - p0;
            raw.mesh.points[base] = c;
            for (int x = 0; x < np; ++x) raw.mesh.points[base + 1 + x] = c + r * frames.directions[p0 + x];
            for (int j = 0; j < cs.edge_begin[v + 1] - cs.edge_begin[v]; ++j)
                raw.mesh.points[base + 1 + np + j] = c + r * surface_direction(cs, frames, v, np + j);
        }
    });
}

double min_hex_sj(const HexMesh& mesh, const std::vector<int>& hexes) {
    double worst = 1.0;
    for (int h : hexes) worst = std::min(worst, hex_scaled_jacobian(mesh.points, mesh.hexes[h]));
    return worst;
}

// RawMeshOptions::bridge_quad_inset: with v's points placed at rad (fully raised), each point off v's bridge quads
// stops inset x its shortest raw boundary edge short of that, never below floor_radius (v's limited radius); the
// midpoints of edges that are no bridge quad's side go to the mean of their ends again.
void inset_raised_points(const ConnectionSurfaces& cs, const std::vector<std::vector<int>>& nbrs, int v, int base,
                         double floor_radius, double inset, const std::vector<char>& on_bridge_quad,
                         const std::vector<Vec3>& points, std::vector<double>& rad) {
    const int np = cs.point_begin[v + 1] - cs.point_begin[v];
    for (int x = 0; x < np; ++x) {
        if (on_bridge_quad[static_cast<std::size_t>(x)]) continue;
        const int id = base + 1 + x;
        double shortest = std::numeric_limits<double>::infinity();
        for (int w : nbrs[static_cast<std::size_t>(id)]) shortest = std::min(shortest, distance(points[id], points[w]));
        if (std::isfinite(shortest))
            rad[static_cast<std::size_t>(x)] =
                std::max(floor_radius, rad[static_cast<std::size_t>(x)] - inset * shortest);
    }
    for (int j = 0; j < cs.edge_begin[v + 1] - cs.edge_begin[v]; ++j) {
        if (on_bridge_quad[static_cast<std::size_t>(np + j)]) continue;
        const std::array<int, 2>& ed = cs.edges[cs.edge_begin[v] + j];
        rad[static_cast<std::size_t>(np + j)] =
            0.5 * (rad[static_cast<std::size_t>(ed[0])] + rad[static_cast<std::size_t>(ed[1])]);
    }
}

// RawMeshOptions::bridge_quad_radius, after place_vertices: every branching point whose sphere a bridge's margin
// limit shrank (radius[v] < its input radius) moves its surface points off its bridge quads out to
// bridge_quad_point_radii (with bridge_quad_inset, one padding layer short of them: inset_raised_points), by the
// largest of t = 1, 1/2, 1/4 of the way that leaves no hex at its centre below min(0.3, before); else they stay.
// Serial in vertex order (a junction's hexes reach its neighbours' points, which may move in the same pass): the
// same result for any thread count.
void raise_bridge_junctions(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                            const BranchFrames& frames, const RawMeshOptions& options,
                            const std::vector<double>& radius, RawMesh& raw) {
    if (!options.bridge_quad_radius) return;
    const int nv = static_cast<int>(skeleton.points.size());
    std::vector<int> centre_of(raw.mesh.points.size(), -1);
    for (int v = 0; v < nv; ++v)
        if (an.vertex_class[v] == VertexClass::BranchingPoint && raw.vertex_base[v] >= 0 && block_at(cs, v) < 0 &&
            radius[v] < skeleton.radii[v])
            centre_of[static_cast<std::size_t>(raw.vertex_base[v])] = v;
    std::vector<std::vector<int>> hexes_at(static_cast<std::size_t>(nv));
    for (int h = 0; h < static_cast<int>(raw.mesh.hexes.size()); ++h)
        for (int id : raw.mesh.hexes[h])
            if (centre_of[static_cast<std::size_t>(id)] >= 0)
                hexes_at[static_cast<std::size_t>(centre_of[static_cast<std::size_t>(id)])].push_back(h);
    // The boundary's topology only where a junction is raised (the studio remeshes on every edit).
    const bool any =
        std::any_of(hexes_at.begin(), hexes_at.end(), [](const std::vector<int>& h) { return !h.empty(); });
    if (!any) return;
    const bool inset = options.bridge_quad_inset > 0;
    std::vector<int> inset_points;  // the surface points of the raised junctions (inset_raised_points reads theirs)
    for (int v = 0; v < nv && inset; ++v)
        if (!hexes_at[static_cast<std::size_t>(v)].empty())
            for (int x = 0; x < cs.point_begin[v + 1] - cs.point_begin[v]; ++x)
                inset_points.push_back(raw.vertex_base[v] + 1 + x);
    const std::vector<std::vector<int>> nbrs = boundary_edge_neighbours(raw.mesh, inset_points);
    std::vector<double> rad;
    std::vector<char> on_bridge_quad;
    for (int v = 0; v < nv; ++v) {
        if (hexes_at[static_cast<std::size_t>(v)].empty()) continue;
        const std::vector<int>& hexes = hexes_at[static_cast<std::size_t>(v)];
        bridge_quad_point_radii(skeleton, an, cs, frames, options, v, rad, on_bridge_quad);
        const double before = min_hex_sj(raw.mesh, hexes), floor = std::min(0.3, before);
        const Vec3& c = skeleton.points[v];
        const int base = raw.vertex_base[v], n = static_cast<int>(rad.size());
        const auto place = [&](double t) {
            for (int x = 0; x < n; ++x)
                raw.mesh.points[base + 1 + x] = c + (radius[v] + t * (rad[static_cast<std::size_t>(x)] - radius[v])) *
                                                        surface_direction(cs, frames, v, x);
        };
        if (inset) {
            place(1.0);
            inset_raised_points(cs, nbrs, v, base, radius[v], options.bridge_quad_inset, on_bridge_quad,
                                raw.mesh.points, rad);
        }
        for (double t : {1.0, 0.5, 0.25, 0.0}) {
            place(t);
            if (t == 0.0 || min_hex_sj(raw.mesh, hexes) >= floor) break;
        }
    }
}

// Whether raw id `id` of a border half-chunk's out point can be pulled towards its vertex by limit_out_closing: a
// leaflet column's out (with `columns`) or a junction's point on its sphere (not a fan vertex's, not a block's). Its
// centre's id, or -1.
int movable_out_centre(const SkeletonAnalysis& an, const ConnectionSurfaces& cs, const RawMesh& raw,
                       const std::vector<int>& owner, bool columns, int id) {
    const int w = owner[static_cast<std::size_t>(id)];
    if (w < 0) return -1;
    const int base = raw.vertex_base[w];
    const VertexClass c = an.vertex_class[w];
    if (c == VertexClass::LeafletBoundary) return columns && id == base + 3 ? base : -1;
    const bool sphere = !leaflet_column_class(c) && !is_fan(c) && block_at(cs, w) < 0 && id > base &&
                        id <= base + cs.point_begin[w + 1] - cs.point_begin[w];
    return sphere ? base : -1;
}

// Per leaflet border edge: its two half-chunk hexes' corners as (a, out a, out b, b, out-up a, out-up b, out-down a,
// out-down b), from the up hex (a oa ob b | ua oua oub ub) and the down hex (a b ob oa | da db odb oda); edges whose
// two hexes do not share a, b, oa, ob that way are left out.
std::vector<std::array<int, 8>> border_half_chunk_corners(const SkeletonAnalysis& an, const RawMesh& raw,
                                                          const std::vector<int>& owner) {
    const auto is_centre = [&](int id) {
        const int w = owner[static_cast<std::size_t>(id)];
        return w >= 0 && raw.vertex_base[w] == id;
    };
    std::vector<std::array<int, 2>> hexes(an.edge_degree.size(), {-1, -1});  // up, down
    for (int h = 0; h < static_cast<int>(raw.mesh.hexes.size()); ++h) {
        const int e = raw.hex_edge[h];
        const std::array<int, 8>& hx = raw.mesh.hexes[h];
        if (e >= 0 && an.edge_degree[e] == 1 && is_centre(hx[0])) hexes[e][is_centre(hx[1]) ? 1 : 0] = h;
    }
    std::vector<std::array<int, 8>> out;
    for (const std::array<int, 2>& hs : hexes) {
        if (hs[0] < 0 || hs[1] < 0) continue;
        const std::array<int, 8>&up = raw.mesh.hexes[hs[0]], &dn = raw.mesh.hexes[hs[1]];
        if (dn[0] != up[0] || dn[1] != up[3] || dn[2] != up[2] || dn[3] != up[1]) continue;
        out.push_back({up[0], up[1], up[2], up[3], up[5], up[6], dn[7], dn[6]});
    }
    return out;
}

// One cap on an out point's offset x from its centre (limit_out_closing's lean mode): dot(x, dir) <= cap.
struct LeanCap {
    Vec3 dir;
    double cap = 0;
};

// The offset nearest to x whose every cap holds (x itself when they do): the caps are half-spaces, so the nearest
// point lies on at most three of their planes; with one or two sides per out point this tries x projected onto each
// plane and onto each line where two planes meet and keeps the nearest that keeps every cap. When none does (planes
// that meet nowhere), x projected onto the planes in turn, a few rounds.
Vec3 nearest_within_caps(const Vec3& x, const std::vector<LeanCap>& caps) {
    const auto holds = [&](const Vec3& y) {
        return std::all_of(caps.begin(), caps.end(),
                           [&](const LeanCap& c) { return dot(y, c.dir) <= c.cap + 1e-12 * (1 + std::abs(c.cap)); });
    };
    if (holds(x)) return x;
    const auto onto = [](const Vec3& y, const LeanCap& c) { return y - (dot(y, c.dir) - c.cap) * c.dir; };
    Vec3 best = x;
    double best_d = std::numeric_limits<double>::infinity();
    const auto consider = [&](const Vec3& y) {
        const double d = norm(y - x);
        if (d < best_d && holds(y)) best = y, best_d = d;
    };
    const std::size_t n = caps.size();
    for (std::size_t i = 0; i < n; ++i) consider(onto(x, caps[i]));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            // y = x - p d_i - q d_j with dot(y, d_i) = cap_i, dot(y, d_j) = cap_j (unit d: Gram [[1, g], [g, 1]]).
            const double g = dot(caps[i].dir, caps[j].dir), det = 1 - g * g;
            if (!(det > 1e-12)) continue;
            const double ei = dot(x, caps[i].dir) - caps[i].cap, ej = dot(x, caps[j].dir) - caps[j].cap;
            consider(x - ((ei - g * ej) / det) * caps[i].dir - ((ej - g * ei) / det) * caps[j].dir);
        }
    if (best_d < std::numeric_limits<double>::infinity()) return best;
    Vec3 y = x;
    for (int round = 0; round < 16; ++round)
        for (const LeanCap& c : caps)
            if (dot(y, c.dir) > c.cap) y = onto(y, c);
    return y;
}

// Whether limit_out_closing's lean mode cuts only the lean of vertex w's out point: a plain leaflet border column's.
// A column turned towards a branch rooted on its out patch (BorderRoot::Out) and a junction's sphere point carry a
// branch's first chunk, which stands on the patch they span: moved along the side, the patch no longer faces the
// branch and that chunk folds; they are pulled towards their vertex instead.
bool lean_cut_column(const SkeletonAnalysis& an, int w) {
    return an.vertex_class[w] == VertexClass::LeafletBoundary && an.vertex_border_root[w] != BorderRoot::Out;
}

// RawMeshOptions::leaflet_out_fraction (with leaflet_out_columns and leaflet_out_lean_only), on the placed points: per
// border half-chunk (a, out a, out b, b) of a leaflet border edge of length L, the two out points may come closer
// along a -> b than a and b by at most fraction x L.
// Pull (leaflet_out_lean_only false): past the limit, the movable ones (movable_out_centre) are pulled towards their
// centres by one factor k, so that the movable part of the closing times k plus the fixed part is fraction x L; a
// point keeps the smallest k of its half-chunks. A half-chunk whose fixed part alone exceeds the limit is left.
// Lean (true): past the limit, the positive leans of the movable ones are cut by one factor k >= 0 (0 when the rest
// alone exceeds the limit); for a plain column's out point (lean_cut_column) each cut is a cap on its offset along
// that side, and it moves to the nearest offset within the caps of all its half-chunks (nearest_within_caps): its
// offset across the side and off the sheet stays. The other movable points are pulled by their smallest k as above
// (not with k 0: a point on its centre would flatten the branch's chunk).
// A column's out-up and out-down copies move with its out; a junction's (the midpoints of the sphere's edges from the
// out point to its up and down points, shared with the quads across those edges) go to the mean of their ends' radii,
// (1 + k) / 2 of theirs. Serial in edge order (every limit from the positions before any move): deterministic.
void limit_out_closing(const SkeletonAnalysis& an, const ConnectionSurfaces& cs, const RawMeshOptions& options,
                       RawMesh& raw) {
    const double fraction = options.leaflet_out_fraction;
    if (!(fraction > 0)) return;
    const bool lean_only = options.leaflet_out_lean_only;
    std::vector<Vec3>& pts = raw.mesh.points;
    const std::vector<int> owner = raw_vertex_owner(raw);
    std::vector<double> factor(pts.size(), 1.0);
    std::vector<std::vector<LeanCap>> caps(lean_only ? pts.size() : 0);
    std::vector<int> centre(pts.size(), -1);
    std::vector<std::array<int, 2>> copies(pts.size(), {-1, -1});  // per out point: its out-up and out-down copies
    std::vector<int> moved;
    for (const std::array<int, 8>& q : border_half_chunk_corners(an, raw, owner)) {
        const Vec3 d = pts[q[3]] - pts[q[0]];
        const double L = norm(d);
        if (!(L > 0)) continue;
        const Vec3 u = d / L;
        // How far each out point leans towards the other end, along the side.
        const double lean[2] = {dot(pts[q[1]] - pts[q[0]], u), dot(pts[q[3]] - pts[q[2]], u)};
        const bool cols = options.leaflet_out_columns;
        const int c[2] = {movable_out_centre(an, cs, raw, owner, cols, q[1]),
                          movable_out_centre(an, cs, raw, owner, cols, q[2])};
        double movable = 0, fixed = 0;
        for (int k = 0; k < 2; ++k) (c[k] >= 0 && (!lean_only || lean[k] > 0) ? movable : fixed) += lean[k];
        const double limit = fraction * L;
        if (!(lean[0] + lean[1] > limit) || !(movable > 0)) continue;
        if (!lean_only && !(limit - fixed > 0)) continue;
        const double k_side = std::max(0.0, (limit - fixed) / movable);
        for (int k = 0; k < 2; ++k) {
            const int id = q[1 + k];
            const bool cut = lean_only && lean_cut_column(an, owner[id]);
            if (c[k] < 0 || (lean_only && !(lean[k] > 0)) || (!cut && !(k_side > 0))) continue;
            if (centre[id] < 0) moved.push_back(id);
            centre[id] = c[k];
            copies[id] = {q[4 + k], q[6 + k]};
            if (cut)
                caps[id].push_back({k == 0 ? u : -1.0 * u, k_side * lean[k]});  // (its offset's lean: lean[k])
            else
                factor[id] = std::min(factor[id], k_side);
        }
    }
    for (const int id : moved) {
        const Vec3& c = pts[centre[id]];
        const double k = factor[id];
        const bool column = an.vertex_class[owner[id]] == VertexClass::LeafletBoundary;
        const Vec3 delta = !caps.empty() && !caps[id].empty()
                               ? nearest_within_caps(pts[id] - c, caps[id]) - (pts[id] - c)
                               : (k - 1.0) * (pts[id] - c);
        pts[id] += delta;
        for (const int x : copies[id]) pts[x] = column ? pts[x] + delta : c + 0.5 * (1.0 + k) * (pts[x] - c);
    }
}

}  // namespace

std::vector<int> raw_vertex_owner(const RawMesh& raw) {
    std::vector<int> owner(raw.mesh.points.size(), -1);
    for (int v = static_cast<int>(raw.vertex_base.size()) - 1, next = static_cast<int>(owner.size()); v >= 0; --v) {
        if (raw.vertex_base[v] < 0) continue;
        for (int id = raw.vertex_base[v]; id < next; ++id) owner[static_cast<std::size_t>(id)] = v;
        next = raw.vertex_base[v];
    }
    return owner;
}

std::vector<std::array<int, 2>> close_pair_crease_edges(const Skeleton& skeleton, const SkeletonAnalysis& an,
                                                        const RawMesh& raw, double pair_deg) {
    if (!(pair_deg > 0)) return {};
    const std::vector<int> owner = raw_vertex_owner(raw);
    // (edge, skeleton edge of a chunk hex holding it), for the edges between two surface ids of a branching point.
    std::vector<std::pair<std::array<int, 2>, int>> held;
    for (std::size_t h = 0; h < raw.hex_edge.size(); ++h) {
        const int e = raw.hex_edge[h];
        if (e < 0 || an.edge_degree[e] != 0) continue;
        const std::array<int, 8>& hex = raw.mesh.hexes[h];
        for (const std::array<int, 2>& le : kHexEdges) {
            const int v0 = hex[le[0]], v1 = hex[le[1]], c = owner[v0];
            if (c < 0 || owner[v1] != c || an.vertex_class[c] != VertexClass::BranchingPoint) continue;
            if (v0 == raw.vertex_base[c] || v1 == raw.vertex_base[c]) continue;  // a ray from the centre
            held.push_back({{std::min(v0, v1), std::max(v0, v1)}, e});
        }
    }
    std::sort(held.begin(), held.end());
    const double cos_limit = std::cos(pair_deg * std::numbers::pi / 180);
    std::vector<std::array<int, 2>> out;
    for (std::size_t i = 0; i < held.size();) {
        std::size_t j = i;
        while (j < held.size() && held[j].first == held[i].first) ++j;
        const int e1 = held[i].second, e2 = held[i + 1 < j ? i + 1 : i].second;
        const int c = owner[held[i].first[0]];
        if (j - i == 2 && e1 != e2) {
            const auto away = [&](int e) {
                const int w = skeleton.edges[e][0] == c ? skeleton.edges[e][1] : skeleton.edges[e][0];
                return normalized(skeleton.points[w] - skeleton.points[c]);
            };
            if (dot(away(e1), away(e2)) > cos_limit) out.push_back(held[i].first);
        }
        i = j;
    }
    return out;
}

RawMesh build_raw_mesh(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                       const BranchFrames& frames, const RawMeshOptions& options, const Skeleton* domain) {
    check_raw_mesh_inputs(skeleton, cs, frames);
    RawMesh raw;
    const int n_points = assign_vertex_ids(an, cs, static_cast<int>(skeleton.points.size()), raw.vertex_base);
    const FanGaps gaps = find_fan_gaps(skeleton, an);
    const FaceSideIds sides = face_side_ids(skeleton, an, cs, raw.vertex_base, gaps);
    const HexSlots slots = reserve_hex_slots(an, cs, static_cast<int>(skeleton.edges.size()));
    raw.mesh.points.resize(n_points);
    raw.mesh.hexes.resize(slots.n_hex);
    raw.hex_edge.resize(slots.n_hex);
    write_leaflet_plates(an, sides, slots, raw);
    write_half_chunks(an, cs, gaps, sides, slots, raw);
    // Rooted branches read their patch from the plates and half-chunks written above.
    const RootedPatches rooted = rooted_patch_ids(skeleton, an, cs, sides, slots, raw);
    write_branch_chunks(skeleton, cs, frames, slots, rooted, raw);
    write_block_hexes(cs, slots, raw);
    write_fan_block_hexes(cs, slots, raw);
    write_corner_cubes(an, slots, raw);
    const std::vector<double> radius = effective_radii(skeleton, an, cs, frames, options);
    place_fan_vertices(skeleton, an, cs, gaps, options, radius, raw);
    place_vertices(skeleton, an, cs, frames, options, radius, raw);
    raise_bridge_junctions(skeleton, an, cs, frames, options, radius, raw);
    const bool own = domain == nullptr || domain->radii.size() != domain->points.size();
    cover_junctions(skeleton, own ? skeleton : *domain, an, cs, frames, radius, raw.vertex_base, slots.edge_slot,
                    raw.mesh.hexes, raw.mesh.points, options.cover);
    limit_out_closing(an, cs, options, raw);
    return raw;
}

}  // namespace mesohex
