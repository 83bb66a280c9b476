// Quality smoothing: Gauss-Seidel sweeps of per-vertex descent on a scaled-Jacobian penalty; boundary vertices slide
// on the surface (tangential step, then projection). Sequential: the result does not depend on the thread count.
#include "mesohex/post/smoothing.h"

#include <algorithm>
#include <cassert>
#include <cfloat>
#include <cmath>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"
#include "mesohex/post/quality.h"

namespace mesohex {
namespace {

struct Local {
    double energy = 0;
    double sj_min = 1;
};

// The smoothing's state: the mesh being moved (x), per-hex scaled Jacobians, vertex -> hexes and vertex -> boundary
// quads, and the fixed / frozen flags; one member function per step of smooth_quality.
struct Smoother {
    const HexMesh& mesh;
    const std::function<Vec3(const Vec3&)>& project;
    const SmoothOptions& options;
    SmoothResult& result;
    std::vector<Vec3>& x;
    std::size_t nv, nh;
    std::vector<double> sj;
    // Per hex: its 9 frame values (hex_frame_values) at the current positions, kept up to date by moved_hex. A trial
    // move of v changes only the 5 frames that contain v (the centre and the corners at v and at its 3 neighbours);
    // local() takes the other 4 from here, bit for bit what it would recompute.
    std::vector<std::array<double, 9>> frames;
    VertexHexes incident;
    std::vector<double> edge_len;  // mean length of the edges at every vertex (at the start)
    HexTopology topo;
    std::vector<char> on_boundary;
    std::vector<int> vq_begin, vq;  // vertex -> boundary quads (CSR)
    bool slide = false;
    double cos_feature = 1;
    bool domain_normals = false;
    std::vector<Vec3> quad_domain_normal, quad_domain_point;
    std::vector<char> domain_feature, fixed, frozen;
    std::vector<Vec3> start;
    std::vector<double> worst_gap_limit, cover_limit;
    std::vector<Vec3> quad_sample;
    std::vector<char> quad_sampled;
    std::vector<char> dirty;
    std::vector<std::array<int, 2>> crease;  // the two sharp-edge neighbours
    std::vector<char> corner;
    std::vector<int> around;
    std::vector<Vec3> x0, g, best;

    Smoother(const HexMesh& m, const std::function<Vec3(const Vec3&)>& proj, const SmoothOptions& opt, SmoothResult& r)
        : mesh(m),
          project(proj),
          options(opt),
          result(r),
          x(r.mesh.points),
          nv(m.points.size()),
          nh(m.hexes.size()),
          sj(m.hexes.size()) {}

    std::array<Vec3, 8> hex_corners(std::size_t h) const {
        std::array<Vec3, 8> c;
        for (std::size_t i = 0; i < 8; ++i) c[i] = x[static_cast<std::size_t>(mesh.hexes[h][i])];
        return c;
    }
    void stats(double& mn, double& avg) {
        mn = nh ? DBL_MAX : 0;
        double sum = 0;
        for (std::size_t h = 0; h < nh; ++h) {
            sj[h] = scaled_jacobian(hex_corners(h));
            mn = std::min(mn, sj[h]);
            sum += sj[h];
        }
        avg = nh ? sum / static_cast<double>(nh) : 0;
    }

    // Mean length of the edges at every vertex (each edge seen from its hexes; the mean is what matters).
    void compute_edge_lengths() {
        edge_len.assign(nv, 0.0);
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
    void collect_boundary() {
        topo = compute_hex_topology(mesh);
        on_boundary.assign(nv, 0);
        vq_begin.assign(nv + 1, 0);
        for (const std::array<int, 4>& q : topo.boundary_quads)
            for (int v : q) {
                on_boundary[static_cast<std::size_t>(v)] = 1;
                ++vq_begin[static_cast<std::size_t>(v) + 1];
            }
        for (std::size_t v = 0; v < nv; ++v) vq_begin[v + 1] += vq_begin[v];
        vq.resize(static_cast<std::size_t>(vq_begin.back()));
        std::vector<int> fill(vq_begin.begin(), vq_begin.end() - 1);
        for (std::size_t q = 0; q < topo.boundary_quads.size(); ++q)
            for (int v : topo.boundary_quads[q])
                vq[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = static_cast<int>(q);
    }

    Vec3 quad_normal(int q) const {
        const std::array<int, 4>& f = topo.boundary_quads[static_cast<std::size_t>(q)];
        return normalized(cross(x[static_cast<std::size_t>(f[2])] - x[static_cast<std::size_t>(f[0])],
                                x[static_cast<std::size_t>(f[3])] - x[static_cast<std::size_t>(f[1])]));
    }
    // Two quads are a convex-sharp pair of the domain when their domain normals are more than the angle apart and
    // each one's domain point lies below the other's tangent plane.
    bool convex_sharp(std::size_t a, std::size_t b, double cos_angle) const {
        return !(dot(quad_domain_normal[a], quad_domain_normal[b]) >= cos_angle) &&
               dot(quad_domain_point[b] - quad_domain_point[a], quad_domain_normal[a]) +
                       dot(quad_domain_point[a] - quad_domain_point[b], quad_domain_normal[b]) <
                   0;
    }

    // The domain under every boundary quad (its point closest to the quad's start centroid, and its normal there), if
    // its normals are given; a boundary vertex can be a feature only where a pair of its quads is convex-sharp.
    void find_domain_features() {
        domain_normals = static_cast<bool>(options.surface_normal) && static_cast<bool>(project);
        domain_feature.assign(nv, 1);
        if (!domain_normals) return;
        quad_domain_normal.resize(topo.boundary_quads.size());
        quad_domain_point.resize(topo.boundary_quads.size());
        for (std::size_t q = 0; q < topo.boundary_quads.size(); ++q) {
            Vec3 c;
            for (int w : topo.boundary_quads[q]) c += x[static_cast<std::size_t>(w)];
            quad_domain_point[q] = project(0.25 * c);
            quad_domain_normal[q] = options.surface_normal(0.25 * c);
        }
        for (std::size_t v = 0; v < nv; ++v) {
            if (!on_boundary[v]) continue;
            domain_feature[v] = 0;
            for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i)
                for (int j = i + 1; j < vq_begin[v + 1]; ++j)
                    if (convex_sharp(static_cast<std::size_t>(vq[static_cast<std::size_t>(i)]),
                                     static_cast<std::size_t>(vq[static_cast<std::size_t>(j)]), cos_feature))
                        domain_feature[v] = 1;
        }
    }

    // Boundary vertex normal; `feature` when a quad normal deviates more than feature_angle from it (and the domain
    // is sharp there too, when its normals are known).
    Vec3 boundary_normal(std::size_t v, bool& feature) const {
        Vec3 n;
        for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i) n += quad_normal(vq[static_cast<std::size_t>(i)]);
        n = normalized(n);
        feature = false;
        if (!domain_feature[v]) return n;
        for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i)
            if (dot(n, quad_normal(vq[static_cast<std::size_t>(i)])) < cos_feature) feature = true;
        return n;
    }

    // Boundary vertices that start on a feature stay fixed for the whole sweeps (the max-min pass may move them:
    // worst_moves_features); frozen vertices and, without sliding, all boundary vertices never move.
    void fix_vertices() {
        fixed.assign(nv, 0);
        frozen.assign(nv, 0);
        for (std::size_t v = 0; v < nv; ++v) {
            if ((!options.frozen.empty() && options.frozen[v]) || (on_boundary[v] && !slide)) frozen[v] = 1;
            fixed[v] = frozen[v];
            if (on_boundary[v] && !fixed[v]) {
                bool feature = false;
                boundary_normal(v, feature);
                if (feature) fixed[v] = 1;
            }
        }
    }

    // Chord gap of the boundary around v with the vertices at `pos`: largest distance of its boundary quads'
    // centroids and edge midpoints to the surface.
    double chord_gap_at(std::size_t v, const std::vector<Vec3>& pos) const {
        double gap = 0;
        for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i) {
            const std::array<int, 4>& f =
                topo.boundary_quads[static_cast<std::size_t>(vq[static_cast<std::size_t>(i)])];
            Vec3 c;
            for (int w : f) c += pos[static_cast<std::size_t>(w)];
            c *= 0.25;
            gap = std::max(gap, distance(c, project(c)));
            for (std::size_t k = 0; k < 4; ++k)
                if (static_cast<std::size_t>(f[k]) == v) {
                    const Vec3 a = 0.5 * (pos[v] + pos[static_cast<std::size_t>(f[(k + 1) % 4])]);
                    gap = std::max(gap, distance(a, project(a)));
                }
        }
        return gap;
    }
    double chord_gap(std::size_t v) const { return chord_gap_at(v, x); }

    // Distance of p to the boundary quads at v with the vertices at `pos` (each split as the distance measure splits
    // them: (a, b, c), (a, c, d)).
    double patch_distance(std::size_t v, const std::vector<Vec3>& pos, const Vec3& p) const {
        double d = DBL_MAX;
        for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i) {
            const std::array<int, 4>& f =
                topo.boundary_quads[static_cast<std::size_t>(vq[static_cast<std::size_t>(i)])];
            const Vec3& a = pos[static_cast<std::size_t>(f[0])];
            const Vec3& b = pos[static_cast<std::size_t>(f[1])];
            const Vec3& c = pos[static_cast<std::size_t>(f[2])];
            const Vec3& e = pos[static_cast<std::size_t>(f[3])];
            d = std::min({d, distance(p, closest_point_on_triangle(p, a, b, c)),
                          distance(p, closest_point_on_triangle(p, a, c, e))});
        }
        return d;
    }
    // Cover gap at v with the vertices at `pos`: largest distance of the surface points near v (its start position and
    // the surface points closest to the start centroids of its boundary quads) to its boundary quads. Catches the
    // boundary sliding away from a bump or tip of the surface, which the chord gap does not see.
    double cover_gap_at(std::size_t v, const std::vector<Vec3>& pos) {
        double gap = patch_distance(v, pos, start[v]);
        for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i) {
            const std::size_t q = static_cast<std::size_t>(vq[static_cast<std::size_t>(i)]);
            if (!quad_sampled[q]) {
                Vec3 c;
                for (int w : topo.boundary_quads[q]) c += start[static_cast<std::size_t>(w)];
                quad_sample[q] = project(0.25 * c);
                quad_sampled[q] = 1;
            }
            gap = std::max(gap, patch_distance(v, pos, quad_sample[q]));
        }
        return gap;
    }
    // Max-min pass: limits of the chord gap and of the cover gap at v, max(worst_gap_factor x max_gap, the gap at the
    // start), computed when first needed. Relative to the start (not to the position before the move): where the
    // boundary is coarse for the curvature (gap above max_gap from the start), vertices can still slide, never
    // farther from the surface than the fit left them.
    bool worst_gap_ok(std::size_t v) {
        if (!(on_boundary[v] && options.max_gap > 0)) return true;
        if (worst_gap_limit[v] < 0)
            worst_gap_limit[v] = std::max(options.worst_gap_factor * options.max_gap, chord_gap_at(v, start));
        if (cover_limit[v] < 0)
            cover_limit[v] = std::max(options.worst_gap_factor * options.max_gap, cover_gap_at(v, start));
        return cover_gap_at(v, x) <= cover_limit[v] && chord_gap(v) <= worst_gap_limit[v];
    }

    Local local(std::size_t v) const {
        Local l;
        for (int i = incident.begin[v]; i < incident.begin[v + 1]; ++i) {
            const std::size_t hh = static_cast<std::size_t>(incident.hexes[static_cast<std::size_t>(i)]);
            const std::array<double, 9> q = frames_with_moved(hh, v);
            double m = q[0];
            for (double s : q) {
                m = std::min(m, s);
                const double below = std::max(0.0, options.target_sj - s);
                l.energy += (1 - s) * (1 - s) + options.below_weight * below * below;
            }
            l.sj_min = std::min(l.sj_min, m);
        }
        return l;
    }

    // The frame values of hex hh with only vertex v (one of its corners) moved since frames[hh] was set.
    std::array<double, 9> frames_with_moved(std::size_t hh, std::size_t v) const {
        const std::array<Vec3, 8> c = hex_corners(hh);
        std::array<double, 9> q = frames[hh];
        std::size_t lv = 0;
        while (lv < 7 && static_cast<std::size_t>(mesh.hexes[hh][lv]) != v) ++lv;
        assert(static_cast<std::size_t>(mesh.hexes[hh][lv]) == v);  // v is a corner of hh (incident lists only)
        const std::array<Vec3, 3> centre = hex_centre_frame(c);
        q[0] = frame_det_over_lengths(centre[0], centre[1], centre[2]);
        auto corner = [&](std::size_t k) {
            const std::array<Vec3, 3> f = hex_corner_frame(c, k);
            q[k + 1] = frame_det_over_lengths(f[0], f[1], f[2]);
        };
        corner(lv);
        for (int k : kHexCornerNeighbors[lv]) corner(static_cast<std::size_t>(k));
        return q;
    }
    void set_all_frames() {
        frames.resize(nh);
        for (std::size_t hh = 0; hh < nh; ++hh) frames[hh] = hex_frame_values(hex_corners(hh));
    }

    // After a move of v (or of a vertex set): the scaled Jacobians and frame values of the hexes at it, and their
    // vertices to try again.
    void moved_hex(std::size_t hh) {
        sj[hh] = scaled_jacobian(hex_corners(hh));
        frames[hh] = hex_frame_values(hex_corners(hh));
        for (int w : mesh.hexes[hh]) dirty[static_cast<std::size_t>(w)] = 1;
    }

    // One sweep's visit of v: a descent step on local(v) (boundary: tangential, then projected). Adds the energy
    // before to `total` and, when a move is kept, the gain to `gain`; returns whether v moved.
    bool sweep_vertex(std::size_t v, double& total, double& gain) {
        dirty[v] = 0;
        bool active = false;
        for (int i = incident.begin[v]; i < incident.begin[v + 1] && !active; ++i)
            active = sj[static_cast<std::size_t>(incident.hexes[static_cast<std::size_t>(i)])] <= options.skip_above;
        if (!active) return false;
        const Vec3 x0v = x[v];
        const Local before = local(v);
        total += before.energy;
        // A boundary vertex on a feature (at its current position) stays; the others move tangentially.
        Vec3 n;
        if (on_boundary[v]) {
            bool feature = false;
            n = boundary_normal(v, feature);
            if (feature) return false;
        }
        const double h = edge_len[v];
        const double d = 1e-4 * h;
        Vec3 gv;
        for (int k = 0; k < 3; ++k) {
            x[v] = x0v;
            x[v][k] += d;
            const double ep = local(v).energy;
            x[v] = x0v;
            x[v][k] -= d;
            const double em = local(v).energy;
            gv[k] = (ep - em) / (2 * d);
        }
        x[v] = x0v;
        if (on_boundary[v]) gv -= dot(gv, n) * n;
        const double gn = norm(gv);
        if (!(gn > 0) || !std::isfinite(gn)) return false;
        const Vec3 dir = gv / (-gn);
        // The chord-gap limit needs the gap at x0 (a dozen projections): computed only once a candidate passes the
        // other tests, most visits end before that.
        double gap_limit = -1;
        auto gap_ok = [&]() {
            if (!(on_boundary[v] && options.max_gap > 0)) return true;
            if (gap_limit < 0) {
                const Vec3 cand = x[v];
                x[v] = x0v;
                gap_limit = std::max(options.max_gap, chord_gap(v));
                x[v] = cand;
            }
            return chord_gap(v) <= gap_limit;
        };
        double step = 0.2 * h;
        bool accepted = false;
        double energy_after = before.energy;
        for (int ls = 0; ls < 6 && !accepted; ++ls, step *= 0.5) {
            Vec3 cand = x0v + step * dir;
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
            x[v] = x0v;
            return false;
        }
        gain += before.energy - energy_after;
        for (int i = incident.begin[v]; i < incident.begin[v + 1]; ++i)
            moved_hex(static_cast<std::size_t>(incident.hexes[static_cast<std::size_t>(i)]));
        return true;
    }

    // A vertex is tried again only after a vertex of one of its hexes moved (itself included). Sweeps are numbered
    // on from the last one when run again.
    void run_sweeps(int max_sweeps) {
        const int first = result.sweeps + 1, last = result.sweeps + max_sweeps;
        for (int sweep = first; sweep <= last; ++sweep) {
            double total = 0, gain = 0;
            long moves = 0;
            for (std::size_t v = 0; v < nv; ++v) {
                if (fixed[v] || !dirty[v]) continue;
                if (sweep_vertex(v, total, gain)) ++moves;
            }
            result.sweeps = sweep;
            result.moves += moves;
            if (options.progress) options.progress({sweep, moves});
            if (moves == 0 || gain <= options.min_gain * total) break;
        }
    }

    // Sharp boundary edges (their two boundary quads' normals more than worst_crease_angle apart, at the start): a
    // boundary vertex with none slides on the surface, one with two slides along them (along the line through its
    // two sharp-edge neighbours, then projected), any other (a corner, the end of a crease) stays where it is.
    void find_creases() {
        crease.assign(nv, {-1, -1});
        corner.assign(nv, 0);
        if (!(options.worst_below > 0)) return;
        const double cos_crease = std::cos(deg_to_rad(options.worst_crease_angle));
        std::vector<std::pair<int, int>> edges;  // (neighbour, quad) of the boundary edges at v
        for (std::size_t v = 0; v < nv; ++v) {
            if (!on_boundary[v]) continue;
            edges.clear();
            for (int i = vq_begin[v]; i < vq_begin[v + 1]; ++i) {
                const int q = vq[static_cast<std::size_t>(i)];
                const std::array<int, 4>& f = topo.boundary_quads[static_cast<std::size_t>(q)];
                for (std::size_t k = 0; k < 4; ++k)
                    if (static_cast<std::size_t>(f[k]) == v) {
                        edges.emplace_back(f[(k + 1) % 4], q);
                        edges.emplace_back(f[(k + 3) % 4], q);
                    }
            }
            std::sort(edges.begin(), edges.end());
            int sharp = 0;
            for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
                if (edges[i].first != edges[i + 1].first) continue;
                const int qa = edges[i].second, qb = edges[i + 1].second;
                if (dot(quad_normal(qa), quad_normal(qb)) < cos_crease &&
                    (!domain_normals ||
                     convex_sharp(static_cast<std::size_t>(qa), static_cast<std::size_t>(qb), cos_crease))) {
                    if (sharp < 2) crease[v][static_cast<std::size_t>(sharp)] = edges[i].first;
                    ++sharp;
                }
                ++i;
            }
            if (sharp == 1 || sharp > 2) corner[v] = 1;
            if (sharp != 2) crease[v] = {-1, -1};
        }
    }

    bool movable(std::size_t v) const {
        return !frozen[v] && !corner[v] && (!fixed[v] || options.worst_moves_features);
    }
    double hexes_min(const std::vector<int>& hexes) const {
        double m = 1;
        for (int hh : hexes)
            for (double q : hex_frame_values(hex_corners(static_cast<std::size_t>(hh)))) m = std::min(m, q);
        return m;
    }
    double soft_min(std::size_t v, double m0) const {
        double e = 0;
        for (int i = incident.begin[v]; i < incident.begin[v + 1]; ++i)
            for (double q :
                 hex_frame_values(hex_corners(static_cast<std::size_t>(incident.hexes[static_cast<std::size_t>(i)]))))
                e += std::exp(-options.worst_sharpness * (q - m0));
        return e;
    }

    // Gradient g[i] of the soft minimum at set[i] (central differences), along its crease or tangential on the
    // boundary; returns the largest |g[i]| and adds the mean edge lengths to `h`.
    double soft_min_gradient(const std::vector<std::size_t>& set, double m0, double& h) {
        const std::size_t n = set.size();
        x0.assign(n, Vec3{});
        g.assign(n, Vec3{});
        double gmax = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t v = set[i];
            x0[i] = x[v];
            h += edge_len[v];
            const double d = 1e-5 * edge_len[v];
            for (int k = 0; k < 3; ++k) {
                x[v] = x0[i];
                x[v][k] += d;
                const double ep = soft_min(v, m0);
                x[v] = x0[i];
                x[v][k] -= d;
                const double em = soft_min(v, m0);
                g[i][k] = (ep - em) / (2 * d);
            }
            x[v] = x0[i];
            if (crease[v][0] >= 0) {
                const Vec3 t =
                    normalized(x[static_cast<std::size_t>(crease[v][1])] - x[static_cast<std::size_t>(crease[v][0])]);
                g[i] = dot(g[i], t) * t;
            } else if (on_boundary[v]) {
                bool feature = false;
                const Vec3 nrm = boundary_normal(v, feature);
                g[i] -= dot(g[i], nrm) * nrm;
            }
            gmax = std::max(gmax, norm(g[i]));
        }
        return gmax;
    }

    // Moves the vertices `set` (all movable, ascending) together if that raises the smallest frame value of the
    // hexes around them; returns whether it did.
    bool raise_min(const std::vector<std::size_t>& set) {
        around.clear();
        for (std::size_t v : set)
            for (int i = incident.begin[v]; i < incident.begin[v + 1]; ++i)
                around.push_back(incident.hexes[static_cast<std::size_t>(i)]);
        std::sort(around.begin(), around.end());
        around.erase(std::unique(around.begin(), around.end()), around.end());
        const double m0 = hexes_min(around);
        const std::size_t n = set.size();
        double h = 0;
        const double gmax = soft_min_gradient(set, m0, h);
        if (!(gmax > 0) || !std::isfinite(gmax)) return false;
        h /= static_cast<double>(n);
        double best_min = m0 + 1e-5;
        best.clear();
        double step = 0.2 * h;
        for (int ls = 0; ls < 10; ++ls, step *= 0.5) {
            bool ok = true;
            for (std::size_t i = 0; i < n && ok; ++i) {
                const std::size_t v = set[i];
                Vec3 cand = x0[i] - (step / gmax) * g[i];
                if (on_boundary[v]) {
                    cand = project(cand);
                    ok = is_finite(cand) && distance(cand, start[v]) <= options.worst_max_slide * edge_len[v];
                }
                x[v] = cand;
            }
            if (ok) {
                const double m = hexes_min(around);
                if (m > best_min) {
                    for (std::size_t i = 0; i < n && ok; ++i) ok = worst_gap_ok(set[i]);
                    if (ok) {
                        best_min = m;
                        best.resize(n);
                        for (std::size_t i = 0; i < n; ++i) best[i] = x[set[i]];
                    }
                }
            }
            for (std::size_t i = 0; i < n; ++i) x[set[i]] = x0[i];
        }
        if (best.empty()) return false;
        for (std::size_t i = 0; i < n; ++i) x[set[i]] = best[i];
        for (int hh : around) moved_hex(static_cast<std::size_t>(hh));
        return true;
    }

    // Max-min pass: rounds of single moves of every vertex of a hex below worst_below, then joint moves of each such
    // hex's vertices, worst hex first (its SJ after the single moves; ties by id).
    void max_min_pass() {
        std::fill(dirty.begin(), dirty.end(), 0);  // from here on: marked by the max-min moves (for the sweeps after)
        std::vector<char> wanted(nv);
        std::vector<std::size_t> bad, set;
        for (int round = 1; options.worst_below > 0 && round <= options.worst_rounds; ++round) {
            bad.clear();
            for (std::size_t hh = 0; hh < nh; ++hh)
                if (sj[hh] < options.worst_below) bad.push_back(hh);
            if (bad.empty()) break;
            long moves = 0;
            std::fill(wanted.begin(), wanted.end(), 0);
            for (std::size_t hh : bad)
                for (int w : mesh.hexes[hh]) wanted[static_cast<std::size_t>(w)] = 1;
            for (std::size_t v = 0; v < nv; ++v)
                if (wanted[v] && movable(v) && raise_min({v})) ++moves;
            std::stable_sort(bad.begin(), bad.end(), [&](std::size_t a, std::size_t b) { return sj[a] < sj[b]; });
            for (std::size_t hh : bad) {
                if (!(sj[hh] < options.worst_below)) continue;
                set.clear();
                for (int w : mesh.hexes[hh])
                    if (movable(static_cast<std::size_t>(w))) set.push_back(static_cast<std::size_t>(w));
                std::sort(set.begin(), set.end());
                if (!set.empty() && raise_min(set)) ++moves;
            }
            result.worst_rounds = round;
            result.worst_moves += moves;
            if (moves == 0) break;
        }
    }
};

// smooth_region's region: per hex 1 when it is a seed (scaled Jacobian below below_sj) or within `rings` rings of one
// (a ring: the hexes sharing a vertex with the region so far). `seeds`: the number of seeds.
std::vector<char> select_region(const HexMesh& mesh, const std::vector<double>& sj, double below_sj, int rings,
                                long& seeds) {
    std::vector<char> in(mesh.hexes.size(), 0);
    seeds = 0;
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
        if (sj[h] < below_sj) {
            in[h] = 1;
            ++seeds;
        }
    if (seeds == 0) return in;
    std::vector<char> marked(mesh.points.size());
    for (int ring = 0; ring < rings; ++ring) {
        std::fill(marked.begin(), marked.end(), 0);
        for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
            if (in[h])
                for (int v : mesh.hexes[h]) marked[static_cast<std::size_t>(v)] = 1;
        for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
            for (std::size_t lv = 0; lv < 8 && !in[h]; ++lv)
                if (marked[static_cast<std::size_t>(mesh.hexes[h][lv])]) in[h] = 1;
    }
    return in;
}

// The region's hexes as a mesh of their own: its vertices in ascending order of their id in `mesh` (vertex_of), and
// frozen those that a hex outside the region uses (or that `frozen` freezes).
struct Region {
    HexMesh mesh;
    std::vector<int> vertex_of;
    std::vector<bool> frozen;
};

Region extract_region(const HexMesh& mesh, const std::vector<char>& in, const std::vector<bool>& frozen) {
    constexpr char kInside = 1, kOutside = 2;
    std::vector<char> used(mesh.points.size(), 0);
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
        for (int v : mesh.hexes[h]) used[static_cast<std::size_t>(v)] |= in[h] ? kInside : kOutside;
    Region r;
    std::vector<int> local(mesh.points.size(), -1);
    for (std::size_t v = 0; v < mesh.points.size(); ++v) {
        if (!(used[v] & kInside)) continue;
        local[v] = static_cast<int>(r.vertex_of.size());
        r.vertex_of.push_back(static_cast<int>(v));
        r.mesh.points.push_back(mesh.points[v]);
        r.frozen.push_back((used[v] & kOutside) != 0 || (!frozen.empty() && frozen[v]));
    }
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
        if (!in[h]) continue;
        std::array<int, 8> hex;
        for (std::size_t lv = 0; lv < 8; ++lv) hex[lv] = local[static_cast<std::size_t>(mesh.hexes[h][lv])];
        r.mesh.hexes.push_back(hex);
    }
    return r;
}

}  // namespace

SmoothResult smooth_region(const HexMesh& mesh, const std::function<Vec3(const Vec3&)>& project, double below_sj,
                           int rings, const SmoothOptions& options, const std::vector<double>& sj) {
    check_hex_indices(mesh, "smooth_region");
    if (!options.frozen.empty() && options.frozen.size() != mesh.points.size())
        throw Error(ErrorCode::InvalidInput, "smooth_region: frozen must have one entry per vertex");
    if (!sj.empty() && sj.size() != mesh.hexes.size())
        throw Error(ErrorCode::InvalidInput, "smooth_region: sj must have one entry per hex");
    SmoothResult result;
    result.mesh = mesh;
    if (rings < 0) return result;
    long seeds = 0;
    std::vector<double> computed;
    const std::vector<double>& q = sj.empty() ? (computed = scaled_jacobians(mesh)) : sj;
    const std::vector<char> in = select_region(mesh, q, below_sj, rings, seeds);
    if (seeds == 0) return result;
    Region region = extract_region(mesh, in, options.frozen);
    SmoothOptions local = options;
    local.frozen = std::move(region.frozen);
    SmoothResult r = smooth_quality(region.mesh, project, local);
    for (std::size_t i = 0; i < region.vertex_of.size(); ++i)
        result.mesh.points[static_cast<std::size_t>(region.vertex_of[i])] = r.mesh.points[i];
    r.mesh = std::move(result.mesh);
    return r;
}

SmoothResult smooth_quality(const HexMesh& mesh, const std::function<Vec3(const Vec3&)>& project,
                            const SmoothOptions& options) {
    const std::size_t nv = mesh.points.size();
    check_hex_indices(mesh, "smooth_quality");
    if (!options.frozen.empty() && options.frozen.size() != nv)
        throw Error(ErrorCode::InvalidInput, "smooth_quality: frozen must have one entry per vertex");

    SmoothResult result;
    result.mesh = mesh;
    Smoother s(mesh, project, options, result);
    s.stats(result.sj_min_before, result.sj_avg_before);
    result.sj_min_after = result.sj_min_before;
    result.sj_avg_after = result.sj_avg_before;
    if (s.nh == 0 || !(result.sj_min_before > 0)) return result;  // only for meshes without inverted hexes

    s.incident = vertex_hexes(mesh);
    s.compute_edge_lengths();
    s.collect_boundary();
    s.slide = options.move_boundary && static_cast<bool>(project);
    s.cos_feature = std::cos(deg_to_rad(options.feature_angle));
    s.find_domain_features();
    s.fix_vertices();
    s.start = mesh.points;
    s.worst_gap_limit.assign(nv, -1.0);
    s.cover_limit.assign(nv, -1.0);
    s.quad_sample.assign(s.topo.boundary_quads.size(), Vec3{});
    s.quad_sampled.assign(s.topo.boundary_quads.size(), 0);
    s.dirty.assign(nv, 1);
    s.set_all_frames();
    s.run_sweeps(options.max_sweeps);
    s.find_creases();
    s.max_min_pass();
    // The max-min moves may have lowered good hexes around them: a few sweeps from the vertices near them (never
    // below min(their worst hex, target_sj)).
    if (result.worst_moves > 0) s.run_sweeps(options.resweeps);
    s.stats(result.sj_min_after, result.sj_avg_after);
    return result;
}

}  // namespace mesohex
