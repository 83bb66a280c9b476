// Quality smoothing: Gauss-Seidel sweeps of per-vertex descent on a scaled-Jacobian penalty; boundary vertices slide
// on the surface (tangential step, then projection). Sequential: the result does not depend on the thread count.
#include "mesohex/post/smoothing.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/topology.h"
#include "mesohex/post/quality.h"

namespace mesohex {
namespace {

// The 9 normalized frame determinants of Verdict's hex scaled Jacobian (centre frame first); -1 for a degenerate one.
std::array<double, 9> frame_values(const std::array<Vec3, 8>& p) {
    std::array<double, 9> q{};
    auto ndet = [](const Vec3& a, const Vec3& b, const Vec3& c) {
        const double la = squared_norm(a), lb = squared_norm(b), lc = squared_norm(c);
        if (!(la > DBL_MIN && lb > DBL_MIN && lc > DBL_MIN)) return -1.0;
        const double d = det3(a, b, c) / std::sqrt(la * lb * lc);
        return std::isfinite(d) ? d : -1.0;
    };
    q[0] = ndet((p[1] + p[2] + p[5] + p[6]) - (p[0] + p[3] + p[4] + p[7]),
                (p[2] + p[3] + p[6] + p[7]) - (p[0] + p[1] + p[4] + p[5]),
                (p[4] + p[5] + p[6] + p[7]) - (p[0] + p[1] + p[2] + p[3]));
    for (std::size_t lv = 0; lv < 8; ++lv) {
        const std::array<int, 3>& nb = kHexCornerNeighbors[lv];
        q[lv + 1] = ndet(p[static_cast<std::size_t>(nb[0])] - p[lv], p[static_cast<std::size_t>(nb[1])] - p[lv],
                         p[static_cast<std::size_t>(nb[2])] - p[lv]);
    }
    return q;
}

struct Local {
    double energy = 0;
    double sj_min = 1;
};

}  // namespace

SmoothResult smooth_quality(const HexMesh& mesh, const std::function<Vec3(const Vec3&)>& project,
                            const SmoothOptions& options) {
    const std::size_t nv = mesh.points.size();
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
        for (int v : mesh.hexes[h])
            if (v < 0 || static_cast<std::size_t>(v) >= nv)
                throw Error(ErrorCode::InvalidInput,
                            "smooth_quality: hex " + std::to_string(h) + " has vertex index " + std::to_string(v) +
                                " out of range",
                            {ElementRef::Kind::Hex, static_cast<int>(h)});
    if (!options.frozen.empty() && options.frozen.size() != nv)
        throw Error(ErrorCode::InvalidInput, "smooth_quality: frozen must have one entry per vertex");

    SmoothResult result;
    result.mesh = mesh;
    std::vector<Vec3>& x = result.mesh.points;
    const std::size_t nh = mesh.hexes.size();
    auto hex_corners = [&](std::size_t h) {
        std::array<Vec3, 8> c;
        for (std::size_t i = 0; i < 8; ++i) c[i] = x[static_cast<std::size_t>(mesh.hexes[h][i])];
        return c;
    };
    std::vector<double> sj(nh);
    auto stats = [&](double& mn, double& avg) {
        mn = nh ? DBL_MAX : 0;
        double sum = 0;
        for (std::size_t h = 0; h < nh; ++h) {
            sj[h] = scaled_jacobian(hex_corners(h));
            mn = std::min(mn, sj[h]);
            sum += sj[h];
        }
        avg = nh ? sum / static_cast<double>(nh) : 0;
    };
    stats(result.sj_min_before, result.sj_avg_before);
    result.sj_min_after = result.sj_min_before;
    result.sj_avg_after = result.sj_avg_before;
    if (nh == 0 || !(result.sj_min_before > 0)) return result;  // only for meshes without inverted hexes

    // Vertex -> hexes (CSR).
    const VertexHexes incident = vertex_hexes(mesh);
    const std::vector<int>& vh_begin = incident.begin;
    const std::vector<int>& vh = incident.hexes;
    // Mean length of the edges at every vertex (each edge seen from its hexes; the mean is what matters).
    std::vector<double> edge_len(nv, 0.0);
    {
        std::vector<int> count(nv, 0);
        for (const std::array<int, 8>& hex : mesh.hexes)
            for (const std::array<int, 2>& e : kHexEdges) {
                const int a = hex[static_cast<std::size_t>(e[0])], b = hex[static_cast<std::size_t>(e[1])];
                const double l =
                    distance(mesh.points[static_cast<std::size_t>(a)], mesh.points[static_cast<std::size_t>(b)]);
                edge_len[static_cast<std::size_t>(a)] += l;
                edge_len[static_cast<std::size_t>(b)] += l;
                ++count[static_cast<std::size_t>(a)];
                ++count[static_cast<std::size_t>(b)];
            }
        for (std::size_t v = 0; v < nv; ++v)
            if (count[v] > 0) edge_len[v] /= count[v];
    }
    // Boundary vertices and their quads.
    const HexTopology topo = compute_hex_topology(mesh);
    std::vector<char> on_boundary(nv, 0);
    std::vector<int> vq_begin(nv + 1, 0), vq;
    for (const std::array<int, 4>& q : topo.boundary_quads)
        for (int v : q) {
            on_boundary[static_cast<std::size_t>(v)] = 1;
            ++vq_begin[static_cast<std::size_t>(v) + 1];
        }
    for (std::size_t v = 0; v < nv; ++v) vq_begin[v + 1] += vq_begin[v];
    vq.resize(static_cast<std::size_t>(vq_begin.back()));
    {
        std::vector<int> fill(vq_begin.begin(), vq_begin.end() - 1);
        for (std::size_t q = 0; q < topo.boundary_quads.size(); ++q)
            for (int v : topo.boundary_quads[q])
                vq[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = static_cast<int>(q);
    }
    const bool slide = options.move_boundary && static_cast<bool>(project);
    const double cos_feature = std::cos(options.feature_angle * 3.14159265358979323846 / 180.0);
    auto quad_normal = [&](int q) {
        const std::array<int, 4>& f = topo.boundary_quads[static_cast<std::size_t>(q)];
        return normalized(cross(x[static_cast<std::size_t>(f[2])] - x[static_cast<std::size_t>(f[0])],
                                x[static_cast<std::size_t>(f[3])] - x[static_cast<std::size_t>(f[1])]));
    };
    // Boundary vertex normal; `feature` when a quad normal deviates more than feature_angle from it.
    auto boundary_normal = [&](std::size_t v, bool& feature) {
        Vec3 n;
        for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i) n += quad_normal(vq[static_cast<std::size_t>(i)]);
        n = normalized(n);
        feature = false;
        for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i)
            if (dot(n, quad_normal(vq[static_cast<std::size_t>(i)])) < cos_feature) feature = true;
        return n;
    };
    // Boundary vertices that start on a feature stay fixed for the whole pass.
    std::vector<char> fixed(nv, 0);
    for (std::size_t v = 0; v < nv; ++v) {
        if (!options.frozen.empty() && options.frozen[v]) fixed[v] = 1;
        if (on_boundary[v]) {
            bool feature = false;
            boundary_normal(v, feature);
            if (!slide || feature) fixed[v] = 1;
        }
    }
    const std::vector<Vec3> start = mesh.points;
    // Chord gap of the boundary around v: largest distance of its boundary quads' centroids and edge midpoints to the
    // surface.
    auto chord_gap = [&](std::size_t v) {
        double gap = 0;
        for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i) {
            const std::array<int, 4>& f =
                topo.boundary_quads[static_cast<std::size_t>(vq[static_cast<std::size_t>(i)])];
            Vec3 c;
            for (int w : f) c += x[static_cast<std::size_t>(w)];
            c *= 0.25;
            gap = std::max(gap, distance(c, project(c)));
            for (std::size_t k = 0; k < 4; ++k)
                if (static_cast<std::size_t>(f[k]) == v) {
                    const Vec3 a = 0.5 * (x[v] + x[static_cast<std::size_t>(f[(k + 1) % 4])]);
                    gap = std::max(gap, distance(a, project(a)));
                }
        }
        return gap;
    };

    auto local = [&](std::size_t v) {
        Local l;
        for (int i = vh_begin[v]; i < vh_begin[v + 1]; ++i) {
            const std::array<Vec3, 8> c = hex_corners(static_cast<std::size_t>(vh[static_cast<std::size_t>(i)]));
            const std::array<double, 9> q = frame_values(c);
            double m = q[0];
            for (double s : q) {
                m = std::min(m, s);
                const double below = std::max(0.0, options.target_sj - s);
                l.energy += (1 - s) * (1 - s) + options.below_weight * below * below;
            }
            l.sj_min = std::min(l.sj_min, m);
        }
        return l;
    };

    // A vertex is tried again only after a vertex of one of its hexes moved (itself included).
    std::vector<char> dirty(nv, 1);
    for (int sweep = 1; sweep <= options.max_sweeps; ++sweep) {
        double total = 0, gain = 0;
        long moves = 0;
        for (std::size_t v = 0; v < nv; ++v) {
            if (fixed[v] || !dirty[v]) continue;
            dirty[v] = 0;
            bool active = false;
            for (int i = vh_begin[v]; i < vh_begin[v + 1] && !active; ++i)
                active = sj[static_cast<std::size_t>(vh[static_cast<std::size_t>(i)])] <= options.skip_above;
            if (!active) continue;
            const Vec3 x0 = x[v];
            const Local before = local(v);
            total += before.energy;
            const double h = edge_len[v];
            const double d = 1e-4 * h;
            Vec3 g;
            for (int k = 0; k < 3; ++k) {
                x[v] = x0;
                x[v][k] += d;
                const double ep = local(v).energy;
                x[v] = x0;
                x[v][k] -= d;
                const double em = local(v).energy;
                g[k] = (ep - em) / (2 * d);
            }
            x[v] = x0;
            Vec3 n;
            if (on_boundary[v]) {
                bool feature = false;
                n = boundary_normal(v, feature);
                if (feature) continue;
                g -= dot(g, n) * n;
            }
            const double gn = norm(g);
            if (!(gn > 0) || !std::isfinite(gn)) continue;
            const Vec3 dir = g / (-gn);
            // The chord-gap limit needs the gap at x0 (a dozen projections): computed only once a candidate passes the
            // other tests, most visits end before that.
            double gap_limit = -1;
            auto gap_ok = [&]() {
                if (!(on_boundary[v] && options.max_gap > 0)) return true;
                if (gap_limit < 0) {
                    const Vec3 cand = x[v];
                    x[v] = x0;
                    gap_limit = std::max(options.max_gap, chord_gap(v));
                    x[v] = cand;
                }
                return chord_gap(v) <= gap_limit;
            };
            double step = 0.2 * h;
            bool accepted = false;
            double energy_after = before.energy;
            for (int ls = 0; ls < 6 && !accepted; ++ls, step *= 0.5) {
                Vec3 cand = x0 + step * dir;
                if (on_boundary[v]) {
                    cand = project(cand);
                    if (!is_finite(cand) || distance(cand, start[v]) > options.max_slide * h) continue;
                }
                x[v] = cand;
                const Local after = local(v);
                if (after.energy < before.energy && after.sj_min >= std::min(before.sj_min, options.target_sj) &&
                    after.sj_min > 0 && gap_ok())
                    accepted = true;
                energy_after = after.energy;
            }
            if (!accepted) {
                x[v] = x0;
                continue;
            }
            ++moves;
            gain += before.energy - energy_after;
            for (int i = vh_begin[v]; i < vh_begin[v + 1]; ++i) {
                const std::size_t hh = static_cast<std::size_t>(vh[static_cast<std::size_t>(i)]);
                sj[hh] = scaled_jacobian(hex_corners(hh));
                for (int w : mesh.hexes[hh]) dirty[static_cast<std::size_t>(w)] = 1;
            }
        }
        result.sweeps = sweep;
        result.moves += moves;
        if (options.progress) options.progress({sweep, moves});
        if (moves == 0 || gain <= options.min_gain * total) break;
    }
    stats(result.sj_min_after, result.sj_avg_after);
    return result;
}

}  // namespace mesohex
