// Foldover-free untangling (Garanzha et al. 2021) on hex corners and centre frames, minimized with L-BFGS over the free
// vertices.
// Per-hex corner gradients go to per-hex slots (parallel), then each free vertex gathers its slots in a fixed order:
// results are independent of the thread count.
#include "mesohex/post/untangle.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"
#include "mesohex/post/quality.h"

namespace mesohex {
namespace {

struct UntangleState {
    const HexMesh* mesh = nullptr;
    std::vector<Vec3> x;                        // current positions (all vertices)
    std::vector<Vec3> x0;                       // start positions (attachment)
    std::vector<int> free_vertices;             // ascending
    std::vector<bool> attached;                 // per vertex: boundary vertex moving with the attachment term
    std::vector<int> active_hexes;              // ascending: hexes with at least one free vertex
    std::vector<double> hex_size;               // per hex: h_hex
    std::vector<int> vh_begin, vh_slot;         // per vertex: its (h * 8 + lv) slots
    std::vector<int> vh_active;                 // per slot: (position of h in active_hexes) * 8 + lv, -1 if inactive
    std::vector<std::array<Vec3, 8>> hex_grad;  // per active hex (index in active_hexes)
    double theta = 0.5, eps = 1e-6, attach = 0, attach_scale = 1;
};

struct Sum {
    double value = 0;
};

// Signs of the 8 hex vertices in the centre (principal-axes) frame of the scaled Jacobian (post/quality.cpp):
// xi = (p1 + p2 + p5 + p6) - (p0 + p3 + p4 + p7), eta = (p2 + p3 + p6 + p7) - (p0 + p1 + p4 + p5),
// zeta = (p4 + p5 + p6 + p7) - (p0 + p1 + p2 + p3).
constexpr std::array<std::array<double, 8>, 3> kCentreFrameSign = {{
    {-1, 1, 1, -1, -1, 1, 1, -1},
    {-1, -1, 1, 1, -1, -1, 1, 1},
    {-1, -1, -1, -1, 1, 1, 1, 1},
}};

// The centre frame of corners p, each axis (a sum of 4 edges) x 0.25 inv_s.
std::array<Vec3, 3> centre_frame(const std::array<Vec3, 8>& p, double inv_s) {
    const double q = 0.25 * inv_s;
    std::array<Vec3, 3> f{};
    for (int i = 0; i < 8; ++i)
        for (std::size_t k = 0; k < 3; ++k)
            f[k] += (q * kCentreFrameSign[k][static_cast<std::size_t>(i)]) * p[static_cast<std::size_t>(i)];
    return f;
}

// Energy of one hex and (optionally) its 8 vertex gradients (9 frames: 8 corners and the centre).
double hex_energy(const UntangleState& pb, int h, std::array<Vec3, 8>* grad) {
    const std::array<int, 8>& hex = pb.mesh->hexes[static_cast<std::size_t>(h)];
    const double inv_s = 1.0 / pb.hex_size[static_cast<std::size_t>(h)];
    std::array<Vec3, 8> p;
    for (int i = 0; i < 8; ++i)
        p[static_cast<std::size_t>(i)] = pb.x[static_cast<std::size_t>(hex[static_cast<std::size_t>(i)])];
    if (grad) grad->fill(Vec3{});
    double energy = 0;
    const double eps2 = pb.eps * pb.eps;
    // The 8 corner frames, then the centre frame (c = 8), as in the scaled Jacobian: a hex can have 8 positive
    // corners and a negative centre frame (a twisted hex), and it counts as inverted then.
    for (int c = 0; c < 9; ++c) {
        Vec3 f0, f1, f2;
        if (c < 8) {
            const std::array<Vec3, 3> e = hex_corner_frame(p, static_cast<std::size_t>(c));
            f0 = e[0] * inv_s;
            f1 = e[1] * inv_s;
            f2 = e[2] * inv_s;
        } else {
            const std::array<Vec3, 3> f = centre_frame(p, inv_s);
            f0 = f[0];
            f1 = f[1];
            f2 = f[2];
        }
        const Vec3 c0 = cross(f1, f2), c1 = cross(f2, f0), c2 = cross(f0, f1);
        const double det = dot(f0, c0);
        const double trace = squared_norm(f0) + squared_norm(f1) + squared_norm(f2);
        const double sq = std::sqrt(eps2 + det * det);
        const double chi = 0.5 * (det + sq);
        const double chi23 = std::cbrt(chi * chi);
        energy += (1 - pb.theta) * trace / chi23 + pb.theta * (det * det + 1) / chi;
        if (!grad) continue;
        const double dchi = chi / sq;
        const double d_trace = (1 - pb.theta) / chi23;
        const double d_det = (1 - pb.theta) * trace * (-2.0 / 3.0) / (chi23 * chi) * dchi +
                             pb.theta * (2 * det / chi - (det * det + 1) * dchi / (chi * chi));
        const Vec3 g0 = (2 * d_trace * f0 + d_det * c0) * inv_s;
        const Vec3 g1 = (2 * d_trace * f1 + d_det * c1) * inv_s;
        const Vec3 g2 = (2 * d_trace * f2 + d_det * c2) * inv_s;
        if (c == 8) {
            for (int i = 0; i < 8; ++i)
                (*grad)[static_cast<std::size_t>(i)] += 0.25 * (kCentreFrameSign[0][static_cast<std::size_t>(i)] * g0 +
                                                                kCentreFrameSign[1][static_cast<std::size_t>(i)] * g1 +
                                                                kCentreFrameSign[2][static_cast<std::size_t>(i)] * g2);
            continue;
        }
        const std::array<int, 3>& nb = kHexCornerNeighbors[static_cast<std::size_t>(c)];
        (*grad)[static_cast<std::size_t>(nb[0])] += g0;
        (*grad)[static_cast<std::size_t>(nb[1])] += g1;
        (*grad)[static_cast<std::size_t>(nb[2])] += g2;
        (*grad)[static_cast<std::size_t>(c)] -= g0 + g1 + g2;
    }
    return energy;
}

// Total energy at pb.x; with `grad` (one Vec3 per free vertex) also its gradient.
double evaluate(UntangleState& pb, std::vector<Vec3>* grad) {
    const std::size_t na = pb.active_hexes.size();
    if (grad) pb.hex_grad.resize(na);
    double energy = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, na, 256), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double acc) {
            for (std::size_t i = r.begin(); i < r.end(); ++i)
                acc += hex_energy(pb, pb.active_hexes[i], grad ? &pb.hex_grad[i] : nullptr);
            return acc;
        },
        [](double a, double b) { return a + b; });
    const double k = pb.attach / (pb.attach_scale * pb.attach_scale);
    for (int v : pb.free_vertices)
        if (pb.attached[static_cast<std::size_t>(v)])
            energy += k * squared_norm(pb.x[static_cast<std::size_t>(v)] - pb.x0[static_cast<std::size_t>(v)]);
    if (!grad) return energy;
    // Gather: every hex at a free vertex is active, so each of its slots has an active position (vh_active).
    grad->assign(pb.free_vertices.size(), Vec3{});
    tbb::parallel_for(std::size_t{0}, pb.free_vertices.size(), [&](std::size_t i) {
        const int v = pb.free_vertices[i];
        Vec3 g;
        for (int s = pb.vh_begin[static_cast<std::size_t>(v)]; s < pb.vh_begin[static_cast<std::size_t>(v) + 1]; ++s) {
            const int a = pb.vh_active[static_cast<std::size_t>(s)];
            g += pb.hex_grad[static_cast<std::size_t>(a / 8)][static_cast<std::size_t>(a % 8)];
        }
        if (pb.attached[static_cast<std::size_t>(v)])
            g += (2 * k) * (pb.x[static_cast<std::size_t>(v)] - pb.x0[static_cast<std::size_t>(v)]);
        (*grad)[i] = g;
    });
    return energy;
}

// vh_active from active_hexes (ascending): the gradient gather's slot -> (active position, corner) table, built once
// per round instead of a binary search per slot and evaluation.
void set_active_slots(UntangleState& pb) {
    std::vector<int> position(pb.mesh->hexes.size(), -1);
    for (std::size_t i = 0; i < pb.active_hexes.size(); ++i)
        position[static_cast<std::size_t>(pb.active_hexes[i])] = static_cast<int>(i);
    pb.vh_active.resize(pb.vh_slot.size());
    for (std::size_t s = 0; s < pb.vh_slot.size(); ++s) {
        const int slot = pb.vh_slot[s], i = position[static_cast<std::size_t>(slot / 8)];
        pb.vh_active[s] = i < 0 ? -1 : i * 8 + slot % 8;
    }
}

double min_corner_det(const UntangleState& pb) {
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, pb.active_hexes.size(), 256), std::numeric_limits<double>::infinity(),
        [&](const tbb::blocked_range<std::size_t>& r, double acc) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) {
                const int h = pb.active_hexes[i];
                const std::array<int, 8>& hex = pb.mesh->hexes[static_cast<std::size_t>(h)];
                const double inv_s = 1.0 / pb.hex_size[static_cast<std::size_t>(h)];
                for (int c = 0; c < 8; ++c) {
                    const std::array<int, 3>& nb = kHexCornerNeighbors[static_cast<std::size_t>(c)];
                    const Vec3& xc = pb.x[static_cast<std::size_t>(hex[static_cast<std::size_t>(c)])];
                    const double det =
                        det3((pb.x[static_cast<std::size_t>(hex[static_cast<std::size_t>(nb[0])])] - xc) * inv_s,
                             (pb.x[static_cast<std::size_t>(hex[static_cast<std::size_t>(nb[1])])] - xc) * inv_s,
                             (pb.x[static_cast<std::size_t>(hex[static_cast<std::size_t>(nb[2])])] - xc) * inv_s);
                    acc = std::min(acc, det);
                }
                std::array<Vec3, 8> p;
                for (std::size_t i = 0; i < 8; ++i) p[i] = pb.x[static_cast<std::size_t>(hex[i])];
                const std::array<Vec3, 3> f = centre_frame(p, inv_s);
                acc = std::min(acc, det3(f[0], f[1], f[2]));
            }
            return acc;
        },
        [](double a, double b) { return std::min(a, b); });
}

// L-BFGS (memory 8) with Armijo backtracking on the free vertices of pb. Returns the final energy; adds the
// iterations it ran to `iterations`.
double minimize(UntangleState& pb, int max_iterations, double length_scale, long& iterations) {
    const std::size_t n = pb.free_vertices.size();
    std::vector<Vec3> g, g_new, dir(n), x_start(n);
    double energy = evaluate(pb, &g);
    std::deque<std::pair<std::vector<Vec3>, std::vector<Vec3>>> history;  // (s, y)
    auto vdot = [](const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
        double s = 0;
        for (std::size_t i = 0; i < a.size(); ++i) s += dot(a[i], b[i]);
        return s;
    };
    for (int it = 0; it < max_iterations && std::isfinite(energy); ++it) {
        ++iterations;
        // Two-loop recursion.
        std::vector<Vec3> q = g;
        std::vector<double> alpha(history.size());
        for (std::size_t k = history.size(); k-- > 0;) {
            const double rho = 1.0 / vdot(history[k].second, history[k].first);
            alpha[k] = rho * vdot(history[k].first, q);
            for (std::size_t i = 0; i < n; ++i) q[i] -= alpha[k] * history[k].second[i];
        }
        double gamma = 1;
        if (!history.empty())
            gamma =
                vdot(history.back().first, history.back().second) / vdot(history.back().second, history.back().second);
        for (Vec3& v : q) v *= gamma;
        for (std::size_t k = 0; k < history.size(); ++k) {
            const double rho = 1.0 / vdot(history[k].second, history[k].first);
            const double beta = rho * vdot(history[k].second, q);
            for (std::size_t i = 0; i < n; ++i) q[i] += (alpha[k] - beta) * history[k].first[i];
        }
        for (std::size_t i = 0; i < n; ++i) dir[i] = -q[i];
        double slope = vdot(dir, g);
        if (!(slope < 0)) {  // not a descent direction: restart with steepest descent
            history.clear();
            for (std::size_t i = 0; i < n; ++i) dir[i] = -g[i];
            slope = vdot(dir, g);
            if (!(slope < 0)) break;
        }
        double step = 1;
        if (history.empty()) {  // first step: move at most 0.1 h
            double max_d = 0;
            for (const Vec3& d : dir) max_d = std::max(max_d, norm(d));
            if (max_d > 0) step = std::min(1.0, 0.1 * length_scale / max_d);
        }
        for (std::size_t i = 0; i < n; ++i) x_start[i] = pb.x[static_cast<std::size_t>(pb.free_vertices[i])];
        double e_new = energy;
        bool accepted = false;
        for (int ls = 0; ls < 40; ++ls) {
            for (std::size_t i = 0; i < n; ++i)
                pb.x[static_cast<std::size_t>(pb.free_vertices[i])] = x_start[i] + step * dir[i];
            e_new = evaluate(pb, nullptr);
            if (std::isfinite(e_new) && e_new <= energy + 1e-4 * step * slope) {
                accepted = true;
                break;
            }
            step *= 0.5;
        }
        if (!accepted) {
            for (std::size_t i = 0; i < n; ++i) pb.x[static_cast<std::size_t>(pb.free_vertices[i])] = x_start[i];
            break;
        }
        evaluate(pb, &g_new);
        std::vector<Vec3> s(n), y(n);
        for (std::size_t i = 0; i < n; ++i) {
            s[i] = step * dir[i];
            y[i] = g_new[i] - g[i];
        }
        if (vdot(s, y) > 1e-300) {
            history.emplace_back(std::move(s), std::move(y));
            if (history.size() > 8) history.pop_front();
        }
        g.swap(g_new);
        const double decrease = energy - e_new;
        energy = e_new;
        if (decrease <= 1e-12 * std::abs(energy)) break;
    }
    return energy;
}

struct Inversion {
    long count = 0;     // hexes with SJ <= the threshold (the ones the stage works on)
    long inverted = 0;  // hexes with SJ <= 0
    double sj_min = 1;
    std::vector<int> hexes;
};

Inversion inversion_of(const HexMesh& mesh, const std::vector<Vec3>& x, double threshold) {
    std::vector<double> sj(mesh.hexes.size());
    tbb::parallel_for(std::size_t{0}, mesh.hexes.size(), [&](std::size_t h) {
        std::array<Vec3, 8> c;
        for (int i = 0; i < 8; ++i)
            c[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(mesh.hexes[h][static_cast<std::size_t>(i)])];
        sj[h] = scaled_jacobian(c);
    });
    Inversion inv;
    inv.sj_min = mesh.hexes.empty() ? 1.0 : std::numeric_limits<double>::infinity();
    for (std::size_t h = 0; h < sj.size(); ++h) {
        inv.sj_min = std::min(inv.sj_min, sj[h]);
        if (!(sj[h] > threshold)) inv.hexes.push_back(static_cast<int>(h));
        if (!(sj[h] > 0)) ++inv.inverted;
    }
    inv.count = static_cast<long>(inv.hexes.size());
    return inv;
}

double inversion_sj(const HexMesh& mesh, const std::vector<Vec3>& x, int h) {
    std::array<Vec3, 8> c;
    for (int i = 0; i < 8; ++i)
        c[static_cast<std::size_t>(i)] =
            x[static_cast<std::size_t>(mesh.hexes[static_cast<std::size_t>(h)][static_cast<std::size_t>(i)])];
    return scaled_jacobian(c);
}

// The vertices within `rings` hex rings of the given hexes (rings < 0: every vertex).
std::vector<bool> region_around(const HexMesh& mesh, const std::vector<int>& hexes, int rings) {
    std::vector<bool> seed(mesh.points.size(), rings < 0);
    if (rings < 0) return seed;
    for (int h : hexes)
        for (int v : mesh.hexes[static_cast<std::size_t>(h)]) seed[static_cast<std::size_t>(v)] = true;
    for (int ring = 0; ring < rings; ++ring) {
        std::vector<bool> next = seed;
        for (const std::array<int, 8>& hex : mesh.hexes) {
            bool touches = false;
            for (int v : hex) touches = touches || seed[static_cast<std::size_t>(v)];
            if (touches)
                for (int v : hex) next[static_cast<std::size_t>(v)] = true;
        }
        seed.swap(next);
    }
    return seed;
}

}  // namespace

UntangleResult untangle(const HexMesh& mesh, const UntangleOptions& options) {
    const int nv = static_cast<int>(mesh.points.size());
    check_hex_indices(mesh, "untangle");
    if (!options.frozen.empty() && options.frozen.size() != mesh.points.size())
        throw Error(ErrorCode::InvalidInput, "untangle: frozen must have one entry per vertex");
    if (!(options.volume_weight > 0 && options.volume_weight < 1))
        throw Error(ErrorCode::InvalidInput, "untangle: volume_weight must lie in (0, 1)");

    UntangleResult result;
    result.mesh = mesh;
    if (!(options.target_sj >= 0 && options.target_sj < 1))
        throw Error(ErrorCode::InvalidInput, "untangle: target_sj must lie in [0, 1)");
    Inversion inv = inversion_of(mesh, mesh.points, options.target_sj);
    result.inverted_before = inv.inverted;
    result.sj_min_before = inv.sj_min;
    if (inv.count == 0) {
        result.inverted_after = inv.inverted;
        result.sj_min_after = inv.sj_min;
        return result;
    }

    const HexTopology topo = compute_hex_topology(mesh);
    std::vector<bool> on_boundary(mesh.points.size(), false);
    for (const std::array<int, 4>& q : topo.boundary_quads)
        for (int v : q) on_boundary[static_cast<std::size_t>(v)] = true;

    UntangleState pb;
    pb.mesh = &mesh;
    pb.x = mesh.points;
    pb.x0 = mesh.points;
    pb.theta = options.volume_weight;
    pb.attach = options.fix_boundary ? 0.0 : options.boundary_attach;
    pb.attached.assign(mesh.points.size(), false);
    if (!options.fix_boundary)
        for (std::size_t v = 0; v < mesh.points.size(); ++v) pb.attached[v] = on_boundary[v];
    double size_sum = 0;
    pb.hex_size.resize(mesh.hexes.size());
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
        double s = 0;
        for (const std::array<int, 2>& e : kHexEdges)
            s += distance(mesh.points[static_cast<std::size_t>(mesh.hexes[h][static_cast<std::size_t>(e[0])])],
                          mesh.points[static_cast<std::size_t>(mesh.hexes[h][static_cast<std::size_t>(e[1])])]);
        pb.hex_size[h] = s / 12;
        size_sum += pb.hex_size[h];
    }
    const double mean_size = size_sum / static_cast<double>(mesh.hexes.size());
    for (double& s : pb.hex_size) s = std::max(s, 1e-3 * mean_size);  // collapsed hexes: a sane reference size
    pb.attach_scale = mean_size > 0 ? mean_size : 1.0;
    pb.vh_begin.assign(mesh.points.size() + 1, 0);
    for (const std::array<int, 8>& hex : mesh.hexes)
        for (int v : hex) ++pb.vh_begin[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < mesh.points.size(); ++v) pb.vh_begin[v + 1] += pb.vh_begin[v];
    pb.vh_slot.resize(static_cast<std::size_t>(pb.vh_begin.back()));
    {
        std::vector<int> fill(pb.vh_begin.begin(), pb.vh_begin.end() - 1);
        for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
            for (int lv = 0; lv < 8; ++lv)
                pb.vh_slot[static_cast<std::size_t>(
                    fill[static_cast<std::size_t>(mesh.hexes[h][static_cast<std::size_t>(lv)])]++)] =
                    static_cast<int>(h) * 8 + lv;
    }

    std::vector<bool> in_region(mesh.points.size(), false);
    std::vector<Vec3> best_x = pb.x;  // the best state seen: fewest inverted hexes, then largest min SJ
    Inversion best = inv;
    const double start_min = inv.sj_min;
    bool rose = false;  // a round of a quality pass ended with min SJ above the start's
    int stale = 0;      // rounds since the best state last changed
    double detmin = 0;
    int clean_rounds = 0;
    for (int round = 1; round <= options.max_rounds; ++round) {
        // Grow the region around the hexes inverted now.
        const std::vector<bool> seed = region_around(mesh, inv.hexes, options.region_rings);
        for (std::size_t v = 0; v < seed.size(); ++v) in_region[v] = in_region[v] || seed[v];
        pb.free_vertices.clear();
        for (int v = 0; v < nv; ++v) {
            const std::size_t vu = static_cast<std::size_t>(v);
            if (!in_region[vu]) continue;
            if (options.fix_boundary && on_boundary[vu]) continue;
            if (!options.frozen.empty() && options.frozen[vu]) continue;
            pb.free_vertices.push_back(v);
        }
        std::vector<bool> is_free(mesh.points.size(), false);
        for (int v : pb.free_vertices) is_free[static_cast<std::size_t>(v)] = true;
        pb.active_hexes.clear();
        for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
            bool any = false;
            for (int v : mesh.hexes[h]) any = any || is_free[static_cast<std::size_t>(v)];
            if (any) pb.active_hexes.push_back(static_cast<int>(h));
        }
        set_active_slots(pb);
        if (pb.free_vertices.empty()) break;  // nothing can move

        if (round == 1) {
            detmin = min_corner_det(pb);
            pb.eps = std::sqrt(1e-12 + 0.04 * std::pow(std::min(detmin, 0.0), 2));
        }
        const double e_prev = evaluate(pb, nullptr);
        const double energy = minimize(pb, options.max_inner_iterations, mean_size, result.iterations);
        detmin = min_corner_det(pb);
        inv = inversion_of(mesh, pb.x, options.target_sj);
        result.rounds = round;
        if (inv.inverted < best.inverted ||
            (inv.inverted == best.inverted &&
             (inv.count < best.count || (inv.count == best.count && inv.sj_min > best.sj_min)))) {
            best = inv;
            best_x = pb.x;
            stale = 0;
        } else {
            ++stale;
        }
        rose = rose || inv.sj_min > start_min;
        if (options.progress) {
            UntangleProgress p;
            p.round = round;
            p.epsilon = pb.eps;
            p.energy = energy;
            p.min_det = detmin;
            p.inverted = inv.inverted;
            options.progress(p);
        }
        // Garanzha et al.'s epsilon update.
        const double sigma = std::max(1 - energy / e_prev, 0.1);
        const double chi_min = 0.5 * (detmin + std::sqrt(pb.eps * pb.eps + detmin * detmin));
        const double mu = (1 - sigma) * chi_min;
        pb.eps = detmin < mu ? 2 * std::sqrt(mu * (mu - detmin)) : 1e-10;
        if (options.target_sj > 0 && options.quality_patience > 0 && round >= options.quality_patience && !rose) {
            best_x = mesh.points;  // nothing the finishing would keep: the start is returned
            best = inversion_of(mesh, best_x, options.target_sj);
            break;
        }
        if (options.target_sj > 0 && options.quality_patience > 0 && stale >= options.quality_patience) break;
        if (inv.count == 0 && detmin > 0) {
            if (clean_rounds >= options.extra_rounds) break;
            ++clean_rounds;
        }
    }
    result.mesh.points = best_x;
    result.inverted_after = best.inverted;
    result.sj_min_after = best.sj_min;
    for (int h : best.hexes)
        if (!(inversion_sj(mesh, best_x, h) > 0)) result.inverted_hexes.push_back(h);
    return result;
}

UntangleResult untangle_holding_outside(const HexMesh& mesh, UntangleOptions options,
                                        const SignedDistancesFn& signed_distances, int max_reruns) {
    UntangleResult u = untangle(mesh, options);
    if (u.rounds == 0 || max_reruns <= 0) return u;
    const std::vector<double> start = signed_distances(mesh.points);
    if (start.size() != mesh.points.size())
        throw Error(ErrorCode::InvalidInput, "untangle_holding_outside: one signed distance per vertex expected");
    if (options.frozen.empty()) options.frozen.assign(mesh.points.size(), false);
    long iterations = u.iterations;
    for (int rerun = 0; rerun < max_reruns; ++rerun) {
        std::vector<std::size_t> moved;  // free vertices outside at the start that the pass moved
        std::vector<Vec3> at;
        for (std::size_t v = 0; v < mesh.points.size(); ++v)
            if (!options.frozen[v] && start[v] > 0 && !(u.mesh.points[v] == mesh.points[v])) {
                moved.push_back(v);
                at.push_back(u.mesh.points[v]);
            }
        const std::vector<double> now = signed_distances(at);
        bool held = false;
        for (std::size_t i = 0; i < moved.size(); ++i)
            if (now[i] > start[moved[i]]) {
                options.frozen[moved[i]] = true;
                held = true;
            }
        if (!held) break;
        u = untangle(mesh, options);
        iterations += u.iterations;
    }
    u.iterations = iterations;
    return u;
}

}  // namespace mesohex
