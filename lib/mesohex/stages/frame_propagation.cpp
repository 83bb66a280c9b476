#include "mesohex/stages/frame_propagation.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "mesohex/core/error.h"

namespace mesohex {

namespace {

Frame reversed(const Frame& f) { return {f.r, -f.s, -f.t}; }

Frame rotated(const Frame& f, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    const Vec3 r = c * f.r + s * f.s;
    return {r, cross(f.t, r), f.t};
}

// Quad vertex directions (from the start) of the frame: (-s, +r, +s, -r).
std::array<Vec3, 4> quad_directions(const Frame& f) { return {-f.s, f.r, f.s, -f.r}; }

// Frame of a quad a0..a3 (CCW around t): r along a3 -> a1 and along (a2 - a0) x t, orthogonalised against t.
Frame quad_frame(const std::array<Vec3, 4>& a, const Vec3& t) {
    return orthonormal_frame((a[1] - a[3]) + cross(a[2] - a[0], t), t);
}

// Unit tangent at an interior vertex (bisector of the two edge directions); falls back to the incoming direction.
Vec3 joint_tangent(const Vec3& prev, const Vec3& p, const Vec3& next) {
    const Vec3 din = normalized(p - prev), dout = normalized(next - p);
    const Vec3 t = din + dout;
    return norm(t) > 1e-9 ? normalized(t) : (norm(din) > 0 ? din : dout);
}

}  // namespace

BranchFrames propagate_frames(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaces& cs,
                              const FrameOptions& /*options*/) {
    const int ne = static_cast<int>(skeleton.edges.size());
    BranchFrames out;
    out.edge_frames.assign(ne, {});
    out.edge_rotation.assign(ne, {0, 0});
    out.directions = cs.directions;  // branching points keep their partition; the rest is overwritten below
    out.branch_defect.assign(an.branches.size(), 0.0);

    auto side_of = [&](int e, int v) { return skeleton.edges[e][0] == v ? 0 : 1; };
    auto quad_dirs = [&](int v, int gq, int rot, const std::vector<Vec3>& dirs) {
        const int p0 = cs.point_begin[v];
        const std::array<int, 4>& q = cs.quads[gq];
        std::array<Vec3, 4> a;
        for (int k = 0; k < 4; ++k) a[k] = dirs[p0 + q[(rot + k) & 3]];
        return a;
    };
    // Writes the points of a joint/extremity surface at v so that the quad registered on e_out shows frame f.
    auto place_surface = [&](int v, int e_out, const Frame& f) {
        const int gq = cs.edge_quad[e_out][side_of(e_out, v)];
        const std::array<Vec3, 4> d = quad_directions(f);
        const std::array<int, 4>& q = cs.quads[gq];
        for (int k = 0; k < 4; ++k) out.directions[cs.point_begin[v] + q[k]] = d[k];
    };

    const int nb = static_cast<int>(an.branches.size());
    tbb::parallel_for(tbb::blocked_range<int>(0, nb, 64), [&](const tbb::blocked_range<int>& range) {
        std::vector<int> verts, edges;
        std::vector<Frame> F;
        std::vector<double> arc, twist;
        for (int b = range.begin(); b != range.end(); ++b) {
            const Branch& br = an.branches[b];
            verts = br.vertices;
            edges = br.edges;
            auto constrained = [&](int v) {
                return an.vertex_class[v] == VertexClass::BranchingPoint ||
                       an.vertex_class[v] == VertexClass::BLJoint || roots_branch(an, v) || roots_fan_cap(an, v);
            };
            if (!br.ring && !constrained(verts.front()) && constrained(verts.back())) {
                std::reverse(verts.begin(), verts.end());
                std::reverse(edges.begin(), edges.end());
            }
            const int m = static_cast<int>(edges.size());
            const bool start_fixed = !br.ring && constrained(verts.front());
            const bool end_fixed = br.ring || constrained(verts.back());
            auto P = [&](int i) -> const Vec3& { return skeleton.points[verts[i]]; };

            arc.assign(m + 1, 0.0);
            for (int i = 1; i <= m; ++i) arc[i] = arc[i - 1] + distance(P(i - 1), P(i));

            // Start frame.
            F.assign(m, Frame{});
            const Vec3 t_first = normalized(P(1) - P(0));
            if (start_fixed) {
                const int v0 = verts[0];
                const int gq = cs.edge_quad[edges[0]][side_of(edges[0], v0)];
                F[0] = quad_frame(quad_dirs(v0, gq, 0, cs.directions), t_first);
            } else if (br.ring) {
                const Vec3 t0 = joint_tangent(P(m - 1), P(0), P(1));
                F[0] = orthonormal_frame(any_perpendicular(t0), t0);
            } else {
                F[0] = orthonormal_frame(any_perpendicular(t_first), t_first);
            }
            // Forward rotation-minimizing propagation through the joints.
            for (int i = 1; i < m; ++i)
                F[i] = rotation_minimizing_step(F[i - 1], P(i - 1), P(i), joint_tangent(P(i - 1), P(i), P(i + 1)));
            const Vec3 t_end = br.ring ? F[0].t : normalized(P(m) - P(m - 1));
            Frame arrival = rotation_minimizing_step(F[m - 1], P(m - 1), P(m), t_end);

            // The ring's start joint is placed from its free frame before it serves as the far end.
            if (br.ring) place_surface(verts[0], edges[0], F[0]);

            const int vm = verts[m];
            const int side_m = side_of(edges[m - 1], vm);
            if (end_fixed) {
                // Quarter-turn snapping of the far quad, then the residual defect spread by arc length.
                const int gq = cs.edge_quad[edges[m - 1]][side_m];
                const std::vector<Vec3>& dirs = br.ring ? out.directions : cs.directions;
                int best = 0;
                double best_dot = -2;
                Frame g_best{};
                for (int rot = 0; rot < 4; ++rot) {
                    const Frame g = quad_frame(quad_dirs(vm, gq, rot, dirs), -t_end);
                    const double d = dot(arrival.r, g.r);
                    if (d > best_dot) {
                        best_dot = d;
                        best = rot;
                        g_best = g;
                    }
                }
                const double theta = std::atan2(dot(cross(arrival.r, g_best.r), arrival.t), dot(arrival.r, g_best.r));
                out.edge_rotation[edges[m - 1]][side_m] = static_cast<std::uint8_t>(best);
                out.branch_defect[b] = theta;
                // Twist budget per edge: its length, except that an edge ending on a compatible block's face takes
                // none while the branch has other edges (a block face is as wide as the tube and close to the next
                // joint: a twisted first chunk folds; the partition's first chunks start from the centre and do not).
                // The same for an edge standing on a fan block's cap (as wide as the tube, h from its vertex).
                auto on_block = [&](int i) {
                    const auto square = [&](int v) { return cs.vertex_block[v] >= 0 || roots_fan_cap(an, v); };
                    return (i == 0 && !br.ring && square(verts[0])) || (i == m - 1 && !br.ring && square(verts[m]));
                };
                twist.assign(m + 1, 0.0);
                for (int i = 1; i <= m; ++i) twist[i] = twist[i - 1] + (on_block(i - 1) ? 0.0 : arc[i] - arc[i - 1]);
                const std::vector<double>& share = twist[m] > 0 ? twist : arc;
                const double L = share[m];
                if (L > 0)
                    for (int i = 1; i < m; ++i) F[i] = rotated(F[i], theta * share[i] / L);
                arrival = rotated(arrival, theta);
            } else {
                // Free far end: an extremity, placed from the arriving frame.
                place_surface(vm, edges[m - 1], reversed(arrival));
            }
            if (!start_fixed && !br.ring) place_surface(verts[0], edges[0], F[0]);
            for (int i = 1; i < m; ++i) place_surface(verts[i], edges[i], F[i]);
            for (int i = 0; i < m; ++i) {
                const int e = edges[i];
                out.edge_frames[e][side_of(e, verts[i])] = F[i];
                out.edge_frames[e][side_of(e, verts[i + 1])] = reversed(i + 1 < m ? F[i + 1] : arrival);
            }
        }
    });
    return out;
}

}  // namespace mesohex
