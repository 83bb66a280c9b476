#include "mesohex/stages/connection_surfaces.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>

#include "mesohex/core/error.h"
#include "mesohex/stages/sphere_partition.h"

namespace mesohex {

namespace {

// Quad q0 = (0, 1, 2, 3) with its edges e0..e0+3 = 01, 12, 23, 30 (local point ids): the first quad of an extremity,
// joint or BL-joint surface.
void set_square(ConnectionSurfaces& cs, int e0, int q0) {
    for (int k = 0; k < 4; ++k) cs.edges[e0 + k] = {k, (k + 1) % 4};
    cs.quads[q0] = {0, 1, 2, 3};
    cs.quad_edges[q0] = {0, 1, 2, 3};
}

struct SurfaceSize {
    int points = 0, quads = 0, edges = 0;
};

// Moves the partition points on the sphere (topology unchanged) to increase, vertex by vertex, the smallest margin of
// the quads around it: a deterministic pattern search with a halving step. Why: a raw hex of the first chunk of a
// branch is positive at its sphere corners exactly when the first joint's cross-section, seen from the centre (a cap
// of angular radius atan(r / L)), lies inside the quad; a direction close to a side or corner of its quad gives flat
// or inverted hexes. The result is re-verified (verify_sphere_partition); if it fails, the input is returned.
// Partitions whose smallest margin is already >= good_margin are returned as they are.
SpherePartition relax_partition(const SpherePartition& part, const std::vector<Vec3>& dirs, double good_margin) {
    const int np = static_cast<int>(part.points.size());
    const int nq = static_cast<int>(part.quads.size());
    std::vector<std::vector<int>> incident(np);
    for (int i = 0; i < nq; ++i)
        for (int x : part.quads[i]) incident[x].push_back(i);
    SpherePartition cur = part;
    for (Vec3& p : cur.points) p = normalized(p);
    auto margin_of = [&](int i) {
        std::array<Vec3, 4> q;
        for (int k = 0; k < 4; ++k) q[k] = cur.points[part.quads[i][k]];
        return spherical_quad_margin(q, dirs[i]);
    };
    auto local_min = [&](int x) {
        double m = 10;
        for (int i : incident[x]) m = std::min(m, margin_of(i));
        return m;
    };
    double worst = 10;
    for (int i = 0; i < nq; ++i) worst = std::min(worst, margin_of(i));
    if (worst >= good_margin) return part;  // already comfortable: most junctions of degree <= 6 stop here
    double step = 0.25;
    for (int round = 0; round < 64 && step > 2e-3; ++round) {
        bool improved = false;
        for (int x = 0; x < np; ++x) {
            const Vec3 p = cur.points[x];
            Vec3 u = cross(p, Vec3{1, 0, 0});
            if (norm(u) < 0.5) u = cross(p, Vec3{0, 1, 0});
            u = normalized(u);
            const Vec3 w = cross(p, u);
            double best = local_min(x);
            Vec3 best_p = p;
            for (int k = 0; k < 8; ++k) {
                const double a = k * 0.7853981633974483;
                const Vec3 dir = std::cos(a) * u + std::sin(a) * w;
                cur.points[x] = normalized(std::cos(step) * p + std::sin(step) * dir);
                const double m = local_min(x);
                if (m > best + 1e-9) {
                    best = m;
                    best_p = cur.points[x];
                }
            }
            cur.points[x] = best_p;
            improved = improved || !(best_p == p);
        }
        if (!improved) step *= 0.5;
    }
    return verify_sphere_partition(cur, dirs).empty() ? cur : part;
}

SurfaceSize surface_size(VertexClass c, int branch_degree) {
    switch (c) {
        case VertexClass::Extremity: return {4, 1, 4};
        case VertexClass::Joint: return {4, 2, 4};
        case VertexClass::BLJoint: return {4, 2, 4};
        case VertexClass::LLJoint: return {4, 2, 4};
        case VertexClass::BranchingPoint: return {branch_degree + 2, branch_degree, 2 * branch_degree};
        default: return {};
    }
}

}  // namespace

double spherical_quad_margin(const std::array<Vec3, 4>& q, const Vec3& d) {
    double m = 10;
    for (int k = 0; k < 4; ++k) {
        const Vec3 n = cross(q[k], q[(k + 1) % 4]);
        const double nn = norm(n);
        if (!(nn > 1e-12)) return -1;
        if (dot(n, q[(k + 2) % 4]) < -1e-12 * nn) return -1;  // corner at q[k+1] reflex (flat is allowed: lunes)
        m = std::min(m, std::asin(std::clamp(dot(n, d) / nn, -1.0, 1.0)));
    }
    return m;
}

ConnectionSurfaces build_connection_surfaces(const Skeleton& skeleton, const SkeletonAnalysis& an,
                                             const ConnectionSurfaceOptions& options) {
    const int nv = static_cast<int>(skeleton.points.size());
    const int ne = static_cast<int>(skeleton.edges.size());
    MESOHEX_CHECK(static_cast<int>(an.vertex_class.size()) == nv, "analysis does not match the skeleton");
    for (int v = 0; v < nv; ++v) {
        const VertexClass c = an.vertex_class[v];
        if (c != VertexClass::Isolated && c != VertexClass::Extremity && c != VertexClass::Joint &&
            c != VertexClass::BranchingPoint && c != VertexClass::LeafletInterior && c != VertexClass::BLJoint &&
            c != VertexClass::LeafletBoundary && c != VertexClass::FanEdgeVertex && c != VertexClass::FanEdgeEnd &&
            c != VertexClass::LLJoint)
            throw Error(ErrorCode::UnsupportedConfiguration,
                        "skeleton vertex " + std::to_string(v) + " is a " + to_string(c) +
                            ": branching points with leaflets are not meshed yet",
                        ElementRef{ElementRef::Kind::SkeletonVertex, v});
    }

    for (int l = 0; l < static_cast<int>(an.leaflets.size()); ++l)
        if (!an.leaflets[l].orientable)
            throw Error(ErrorCode::UnsupportedConfiguration,
                        "leaflet " + std::to_string(l) + " (face " + std::to_string(an.leaflets[l].faces.front()) +
                            ") is not orientable (Moebius-like): not supported",
                        ElementRef{ElementRef::Kind::SkeletonFace, an.leaflets[l].faces.front()});

    ConnectionSurfaces cs;
    cs.point_begin.assign(nv + 1, 0);
    cs.quad_begin.assign(nv + 1, 0);
    cs.edge_begin.assign(nv + 1, 0);
    for (int v = 0; v < nv; ++v) {
        const SurfaceSize sz =
            surface_size(an.vertex_class[v], an.vertex_branch_edges[v] + an.vertex_boundary_edges[v] / 2);
        cs.point_begin[v + 1] = cs.point_begin[v] + sz.points;
        cs.quad_begin[v + 1] = cs.quad_begin[v] + sz.quads;
        cs.edge_begin[v + 1] = cs.edge_begin[v] + sz.edges;
    }
    cs.directions.assign(cs.point_begin[nv], Vec3{});
    cs.point_valence.assign(cs.point_begin[nv], 0);
    cs.quads.resize(cs.quad_begin[nv]);
    cs.quad_edges.resize(cs.quad_begin[nv]);
    cs.edges.resize(cs.edge_begin[nv]);
    cs.edge_quad.assign(ne, {-1, -1});

    // Sum of the normals of the faces around each vertex (for BL-joint frames); serial, in face order.
    std::vector<Vec3> vertex_normal_sum(an.counts.bl_joints > 0 ? nv : 0);
    if (an.counts.bl_joints > 0)
        for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
            for (int w : an.face_vertices[f]) vertex_normal_sum[w] += an.face_normal[f];

    // Leaflet sides at LL-joints and branching points (reference-notes §6.3, §6.8): the faces at v connected through
    // interior edges at v form one side, numbered by lowest face id; side s is the vertex's local quad
    // (branch edges first). Each side's direction is the unit mean of the unit vectors to its neighbours, its normal
    // the sum of its face normals. Serial in face order.
    const int nf = static_cast<int>(an.face_vertices.size());
    cs.face_corner_quad.assign(nf, {-1, -1, -1, -1});
    std::vector<std::vector<Vec3>> side_dir(nv), side_nor(nv);
    auto junction = [&](int v) {
        return an.vertex_class[v] == VertexClass::LLJoint ||
               (an.vertex_class[v] == VertexClass::BranchingPoint && an.vertex_boundary_edges[v] > 0);
    };
    if (an.counts.ll_joints > 0 || an.counts.branching_points > 0) {
        std::vector<std::vector<std::pair<int, int>>> vfaces(nv);  // (face, corner), in face order
        for (int f = 0; f < nf; ++f)
            for (int k = 0; k < 4; ++k)
                if (junction(an.face_vertices[f][k])) vfaces[an.face_vertices[f][k]].push_back({f, k});
        for (int v = 0; v < nv; ++v) {
            if (!junction(v)) continue;
            const auto& fl = vfaces[v];
            const int n = static_cast<int>(fl.size());
            const int nl = an.vertex_boundary_edges[v] / 2;
            auto edges_at = [&](int i) {
                const auto [f, k] = fl[i];
                return std::array<int, 2>{an.face_edges[f][k], an.face_edges[f][(k + 3) & 3]};
            };
            auto share = [&](int i, int j) {
                for (int a : edges_at(i))
                    for (int b : edges_at(j))
                        if (a == b && an.edge_degree[a] == 2) return true;
                return false;
            };
            std::vector<int> side(n, -1);
            for (int s = 0; s < nl; ++s) {
                int seed = -1;
                for (int i = 0; i < n && seed < 0; ++i)
                    if (side[i] < 0) seed = i;
                if (seed < 0) break;
                side[seed] = s;
                for (bool changed = true; changed;) {
                    changed = false;
                    for (int i = 0; i < n; ++i)
                        for (int j = 0; j < n; ++j)
                            if (side[i] == s && side[j] < 0 && share(i, j)) {
                                side[j] = s;
                                changed = true;
                            }
                }
            }
            if (std::find(side.begin(), side.end(), -1) != side.end() ||
                std::find(side.begin(), side.end(), nl - 1) == side.end())
                throw Error(ErrorCode::UnsupportedConfiguration,
                            "skeleton vertex " + std::to_string(v) + ": its leaflet faces do not form " +
                                std::to_string(nl) + " leaflet sides",
                            ElementRef{ElementRef::Kind::SkeletonVertex, v});
            side_dir[v].assign(nl, Vec3{});
            side_nor[v].assign(nl, Vec3{});
            const int nb = an.vertex_branch_edges[v];
            for (int s = 0; s < nl; ++s) {
                std::vector<int> es;
                for (int i = 0; i < n; ++i) {
                    if (side[i] != s) continue;
                    side_nor[v][s] += an.face_normal[fl[i].first];
                    for (int e : edges_at(i)) es.push_back(e);
                }
                std::sort(es.begin(), es.end());
                es.erase(std::unique(es.begin(), es.end()), es.end());
                for (int e : es) {
                    const int w = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
                    side_dir[v][s] += normalized(skeleton.points[w] - skeleton.points[v]);
                }
                if (!(norm(side_dir[v][s]) > 1e-9))
                    throw Error(ErrorCode::UnsupportedConfiguration,
                                "skeleton vertex " + std::to_string(v) + ": a leaflet at it has no mean direction",
                                ElementRef{ElementRef::Kind::SkeletonVertex, v});
                side_dir[v][s] = normalized(side_dir[v][s]);
            }
            for (int i = 0; i < n; ++i) cs.face_corner_quad[fl[i].first][fl[i].second] = nb + side[i];
        }
    }

    // Each task writes only its vertex's ranges and the (edge, side) slots of its own incident edges.
    tbb::parallel_for(tbb::blocked_range<int>(0, nv, 256), [&](const tbb::blocked_range<int>& range) {
        std::vector<Vec3> dirs;
        std::vector<int> inc;
        for (int v = range.begin(); v != range.end(); ++v) {
            const VertexClass c = an.vertex_class[v];
            if (c != VertexClass::Extremity && c != VertexClass::Joint && c != VertexClass::BranchingPoint &&
                c != VertexClass::BLJoint)
                continue;
            const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
            inc.clear();
            for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i)
                if (an.edge_degree[an.vertex_edges[i]] == 0) inc.push_back(an.vertex_edges[i]);
            auto side_of = [&](int e) { return skeleton.edges[e][0] == v ? 0 : 1; };
            if (c == VertexClass::BLJoint) {
                // Pillow: quad A = (0,1,2,3) on the branch edge, quad B = (2,1,0,3) for the leaflet (registered on
                // no edge). Geometry from the leaflet frame (reference-notes §7.2): T into the leaflet (mean of the
                // unit vectors to its neighbours), R = leaflet normal made orthogonal to T, S = T x R; quad B shows
                // (-S, R, S, -R) from its start, so its q1 is "up" (the rotation k = 0 of §8.5).
                set_square(cs, e0, q0);
                cs.quads[q0 + 1] = {2, 1, 0, 3};
                cs.quad_edges[q0 + 1] = {1, 0, 3, 2};
                cs.edge_quad[inc[0]][side_of(inc[0])] = q0;
                for (int k = 0; k < 4; ++k) cs.point_valence[p0 + k] = 2;
                Vec3 t{};
                for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
                    const int e = an.vertex_edges[i];
                    if (an.edge_degree[e] == 0) continue;
                    const int w = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
                    t += normalized(skeleton.points[w] - skeleton.points[v]);
                }
                t = normalized(t);
                Vec3 r = vertex_normal_sum[v] - dot(vertex_normal_sum[v], t) * t;
                if (!(norm(r) > 1e-12))
                    throw Error(ErrorCode::UnsupportedConfiguration,
                                "BL-joint at skeleton vertex " + std::to_string(v) +
                                    ": the leaflet direction is along its normal (degenerate corner)",
                                ElementRef{ElementRef::Kind::SkeletonVertex, v});
                r = normalized(r);
                const Vec3 sv = cross(t, r);
                cs.directions[p0 + 2] = -sv;
                cs.directions[p0 + 1] = r;
                cs.directions[p0 + 0] = sv;
                cs.directions[p0 + 3] = -r;
                continue;
            }
            if (c == VertexClass::Extremity || c == VertexClass::Joint) {
                set_square(cs, e0, q0);
                cs.edge_quad[inc[0]][side_of(inc[0])] = q0;
                for (int k = 0; k < 4; ++k) cs.point_valence[p0 + k] = 1;
                if (c == VertexClass::Joint) {
                    cs.quads[q0 + 1] = {2, 1, 0, 3};
                    cs.quad_edges[q0 + 1] = {1, 0, 3, 2};
                    cs.edge_quad[inc[1]][side_of(inc[1])] = q0 + 1;
                    for (int k = 0; k < 4; ++k) cs.point_valence[p0 + k] = 2;
                }
                continue;
            }
            // Branching point: partition of the sphere with one quad per incident branch direction.
            // Leaflets count as virtual branches after the branch edges (reference-notes §6.8).
            const int nb = static_cast<int>(inc.size());
            const int n = nb + static_cast<int>(side_dir[v].size());
            dirs.resize(n);
            const Vec3& center = skeleton.points[v];
            for (int i = 0; i < nb; ++i) {
                const int e = inc[i];
                const int w = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
                dirs[i] = normalized(skeleton.points[w] - center);
            }
            for (int i = nb; i < n; ++i) dirs[i] = side_dir[v][i - nb];
            SpherePartition part;
            try {
                SpherePartitionOptions po;
                po.planarity_tolerance = options.planarity_tolerance;
                part = partition_sphere(dirs, po);
                if (options.relax_partitions) part = relax_partition(part, dirs, options.relax_below_margin);
            } catch (const Error& err) {
                throw Error(ErrorCode::NumericalFailure,
                            "no connection surface at skeleton vertex " + std::to_string(v) + " (degree " +
                                std::to_string(n) + "): " + err.what(),
                            ElementRef{ElementRef::Kind::SkeletonVertex, v});
            }
            if (static_cast<int>(part.quads.size()) != n || static_cast<int>(part.points.size()) != n + 2)
                throw Error(ErrorCode::NumericalFailure,
                            "sphere partition at skeleton vertex " + std::to_string(v) + " has " +
                                std::to_string(part.quads.size()) + " quads and " +
                                std::to_string(part.points.size()) + " points for degree " + std::to_string(n),
                            ElementRef{ElementRef::Kind::SkeletonVertex, v});
            for (int k = 0; k < n + 2; ++k) cs.directions[p0 + k] = normalized(part.points[k]);
            int n_edges = 0;
            for (int i = 0; i < n; ++i) {
                const std::array<int, 4>& q = part.quads[i];
                cs.quads[q0 + i] = q;
                for (int k = 0; k < 4; ++k) {
                    ++cs.point_valence[p0 + q[k]];
                    const int a = q[k], b = q[(k + 1) % 4];
                    int found = -1;
                    for (int j = 0; j < n_edges; ++j) {
                        const std::array<int, 2>& ed = cs.edges[e0 + j];
                        if ((ed[0] == a && ed[1] == b) || (ed[0] == b && ed[1] == a)) {
                            found = j;
                            break;
                        }
                    }
                    if (found < 0) {
                        if (n_edges == 2 * n)
                            throw Error(ErrorCode::NumericalFailure,
                                        "sphere partition at skeleton vertex " + std::to_string(v) +
                                            " is not a closed quad surface",
                                        ElementRef{ElementRef::Kind::SkeletonVertex, v});
                        found = n_edges;
                        cs.edges[e0 + n_edges++] = {a, b};
                    }
                    cs.quad_edges[q0 + i][k] = found;
                }
                if (i < nb) cs.edge_quad[inc[i]][side_of(inc[i])] = q0 + i;
            }
            if (n_edges != 2 * n)
                throw Error(ErrorCode::NumericalFailure,
                            "sphere partition at skeleton vertex " + std::to_string(v) +
                                " is not a closed quad surface",
                            ElementRef{ElementRef::Kind::SkeletonVertex, v});
        }
    });

    // LL-joints (reference-notes §6.3, §7.2, §8.5 with the flaw fixed): a pillow, quad A = (0,1,2,3) for side 0,
    // quad B = (2,1,0,3) for side 1. T = unit(dir_0 - dir_1); R = the side-0 normal made orthogonal to T, turned about
    // T by half the residual angle between the two projected normals and the nearest multiple of 90 degrees,
    // S = T x R; points (-S, R, S, -R). Then every leaflet quad (LL-joint or branching point) picks its own rotation
    // k (§8.5): with its frame T = its direction, R = unit((q2 - q0) x T), S = T x R, the quad vertex nearest to the
    // side's own normal is its up vertex q_{k+1} (q1 ~ R, q2 ~ S, q3 ~ -R, q0 ~ -S). Serial.
    cs.quad_rotation.assign(cs.quad_begin[nv], -1);
    const double quarter = std::numbers::pi / 2;
    for (int v = 0; v < nv; ++v) {
        if (!junction(v)) continue;
        const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
        const auto fail = [&](const std::string& what) {
            throw Error(ErrorCode::UnsupportedConfiguration, "leaflet junction at skeleton vertex " +
                                                                 std::to_string(v) + ": " + what,
                        ElementRef{ElementRef::Kind::SkeletonVertex, v});
        };
        if (an.vertex_class[v] == VertexClass::LLJoint) {
            const std::vector<Vec3>& dir = side_dir[v];
            const std::vector<Vec3>& nor = side_nor[v];
            Vec3 t = dir[0] - dir[1];
            if (!(norm(t) > 1e-9)) fail("both leaflets leave in the same direction");
            t = normalized(t);
            Vec3 a = nor[0] - dot(nor[0], t) * t, b = nor[1] - dot(nor[1], t) * t;
            if (!(norm(a) > 1e-9) || !(norm(b) > 1e-9)) fail("a leaflet normal is along the joint direction");
            a = normalized(a);
            const Vec3 ta = cross(t, a);
            const double phi = std::atan2(dot(b, ta), dot(b, a));
            const double delta = phi - std::round(phi / quarter) * quarter;
            const Vec3 r = normalized(std::cos(0.5 * delta) * a + std::sin(0.5 * delta) * ta);
            const Vec3 sv = cross(t, r);
            for (int k = 0; k < 4; ++k) {
                cs.edges[e0 + k] = {k, (k + 1) & 3};
                cs.point_valence[p0 + k] = 2;
            }
            cs.quads[q0] = {0, 1, 2, 3};
            cs.quad_edges[q0] = {0, 1, 2, 3};
            cs.quads[q0 + 1] = {2, 1, 0, 3};
            cs.quad_edges[q0 + 1] = {1, 0, 3, 2};
            cs.directions[p0 + 0] = -sv;
            cs.directions[p0 + 1] = r;
            cs.directions[p0 + 2] = sv;
            cs.directions[p0 + 3] = -r;
        }
        const int nb = an.vertex_branch_edges[v];
        for (int s = 0; s < static_cast<int>(side_dir[v].size()); ++s) {
            const int q = q0 + nb + s;
            const Vec3 t = side_dir[v][s];
            Vec3 r = cross(cs.directions[p0 + cs.quads[q][2]] - cs.directions[p0 + cs.quads[q][0]], t);
            if (!(norm(r) > 1e-12)) fail("degenerate leaflet quad");
            r = normalized(r);
            const Vec3 sv = cross(t, r);
            const double psi = std::atan2(dot(side_nor[v][s], sv), dot(side_nor[v][s], r));
            cs.quad_rotation[q] = ((static_cast<int>(std::lround(psi / quarter)) % 4) + 4) % 4;
        }
    }
    return cs;
}

}  // namespace mesohex
