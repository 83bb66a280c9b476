#include "mesohex/stages/connection_surfaces.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <utility>

#include <tbb/parallel_for.h>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/stages/junction_geometry.h"
#include "mesohex/stages/leaflet_geometry.h"
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

// The sine of the angle from side k of the spherical quad q (a great-circle arc) to direction d, in `v`; false when
// the side is degenerate or the quad is not convex there (its margin is then -1).
bool quad_side_sine(const std::array<Vec3, 4>& q, int k, const Vec3& d, double& v) {
    const Vec3 n = cross(q[k], q[(k + 1) % 4]);
    const double nn = norm(n);
    if (!(nn > 1e-12) || dot(n, q[(k + 2) % 4]) < -1e-12 * nn) return false;
    v = std::clamp(dot(n, d) / nn, -1.0, 1.0);
    return true;
}

// The margin of d in quad q (the smallest asin of its side sines, -1 for a degenerate or non-convex quad), for
// floor >= -1: it may stop early with some value <= floor once the margin cannot exceed floor.
double quad_margin_to_floor(const std::array<Vec3, 4>& q, const Vec3& d, double floor) {
    double m = 10, v = 0;
    for (int k = 0; k < 4; ++k) {
        if (!quad_side_sine(q, k, d, v)) return -1.0;
        m = std::min(m, std::asin(v));
        if (m <= floor) return m;
    }
    return m;
}

// quad_margin_to_floor with fewer asin calls (the same value when it is > floor, else some value <= floor; the same
// quads stop early): a side whose sine v is <= sin(floor) - 1e-14 has asin(v) <= floor (asin's slope is >= 1, libm's
// asin and sin are within an ulp), so it stops the quad without asin; a side above sin(floor) + 1e-14 cannot stop it
// and its asin is only needed when no side stops the quad. |floor| >= 1.5: no shortcut. The sines are kept for the
// last floor (a relaxation trial's floor is the vertex's best so far).
struct QuadMarginAbove {
    double sine_floor_for = std::numeric_limits<double>::quiet_NaN(), sine_lo = -2, sine_hi = 2;
    double operator()(const std::array<Vec3, 4>& q, const Vec3& d, double floor) {
        if (floor != sine_floor_for) {
            sine_floor_for = floor;
            const double s = std::abs(floor) < 1.5 ? std::sin(floor) : 0;
            sine_lo = std::abs(floor) < 1.5 ? s - 1e-14 : -2;
            sine_hi = std::abs(floor) < 1.5 ? s + 1e-14 : 2;
        }
        double m = 10, v = 0;
        std::array<double, 4> deferred;  // sines whose asin is > floor
        int count = 0;
        for (int k = 0; k < 4; ++k) {
            if (!quad_side_sine(q, k, d, v)) return -1.0;
            if (v <= sine_lo) return floor;
            if (v > sine_hi) {
                deferred[count++] = v;
                continue;
            }
            m = std::min(m, std::asin(v));
            if (m <= floor) return m;
        }
        for (int k = 0; k < count; ++k) m = std::min(m, std::asin(deferred[k]));
        return m;
    }
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
    // The quads around each point, in quad order: flat[start[x] .. start[x + 1]).
    std::vector<int> start(static_cast<std::size_t>(np) + 1, 0), flat(4 * static_cast<std::size_t>(nq));
    for (int i = 0; i < nq; ++i)
        for (int x : part.quads[i]) ++start[x + 1];
    for (int x = 0; x < np; ++x) start[x + 1] += start[x];
    {
        std::vector<int> at(start.begin(), start.end() - 1);
        for (int i = 0; i < nq; ++i)
            for (int x : part.quads[i]) flat[at[x]++] = i;
    }
    const auto incident = [&](int x) {
        return std::span<const int>(flat.data() + start[x], static_cast<std::size_t>(start[x + 1] - start[x]));
    };
    SpherePartition cur = part;
    for (Vec3& p : cur.points) p = normalized(p);
    auto quad_of = [&](int i) {
        std::array<Vec3, 4> q;
        for (int k = 0; k < 4; ++k) q[k] = cur.points[part.quads[i][k]];
        return q;
    };
    // spherical_quad_margin of quad i at the current points, kept until one of its points moves.
    std::vector<double> exact(nq, 0);
    std::vector<char> known(nq, 0);
    auto margin_of = [&](int i) {
        if (!known[i]) {
            exact[i] = spherical_quad_margin(quad_of(i), dirs[i]);
            known[i] = 1;
        }
        return exact[i];
    };
    // A trial's margin of quad i: the same value when it is > floor, else some value <= floor (QuadMarginAbove).
    QuadMarginAbove above;
    auto margin_above = [&](int i, double floor) { return above(quad_of(i), dirs[i], floor); };
    // The smallest margin of the quads around x (the same value in any order); stops once it is <= `floor` (a trial
    // that cannot win), starting with the quad that stopped the previous trial at x.
    std::vector<int> first(np, 0);
    auto local_min = [&](int x, double floor = -1e300) {
        double m = 10;
        const int count = static_cast<int>(incident(x).size());
        for (int j = 0; j < count; ++j) {
            const int at = (first[x] + j) % count;
            const int i = incident(x)[static_cast<std::size_t>(at)];
            m = std::min(m, floor < -1 ? margin_of(i) : margin_above(i, floor));
            if (m <= floor) {
                first[x] = at;
                break;
            }
        }
        return m;
    };
    // Whether some side of a quad around x that reads neither x nor a point moving with it (its ends and the point
    // after them, which quad_side_sine's convexity test reads) bounds the margin of every trial of x by `floor`:
    // then no trial can beat floor (local_min returns a value <= floor for each), and they need not run. floor >= -1
    // (such trials read no margin_of, whose cache they would otherwise change).
    auto capped = [&](int x, double floor) {
        if (!(floor >= -1)) return false;
        for (const int i : incident(x)) {
            const std::array<int, 4>& quad = part.quads[i];
            for (int k = 0; k < 4; ++k) {
                if (quad[k] == x || quad[(k + 1) % 4] == x || quad[(k + 2) % 4] == x) continue;
                double v = 0;
                if (!quad_side_sine(quad_of(i), k, dirs[i], v) || std::asin(v) <= floor) return true;
            }
        }
        return false;
    };
    double worst = 10;
    for (int i = 0; i < nq; ++i) worst = std::min(worst, margin_of(i));
    if (worst >= good_margin) return part;  // already comfortable: most junctions of degree <= 6 stop here
    std::array<double, 8> cos_a, sin_a;     // the 8 trial directions (a = k x 45 deg)
    for (int k = 0; k < 8; ++k) {
        const double a = k * 0.7853981633974483;
        cos_a[k] = std::cos(a);
        sin_a[k] = std::sin(a);
    }
    double step = 0.25;
    for (int round = 0; round < 64 && step > 2e-3; ++round) {
        bool improved = false;
        const double cos_step = std::cos(step), sin_step = std::sin(step);
        for (int x = 0; x < np; ++x) {
            const Vec3 p = cur.points[x];
            Vec3 u = cross(p, Vec3{1, 0, 0});
            if (norm(u) < 0.5) u = cross(p, Vec3{0, 1, 0});
            u = normalized(u);
            const Vec3 w = cross(p, u);
            double best = local_min(x);
            Vec3 best_p = p;
            for (int k = capped(x, best + 1e-9) ? 8 : 0; k < 8; ++k) {
                const Vec3 dir = cos_a[k] * u + sin_a[k] * w;
                cur.points[x] = normalized(cos_step * p + sin_step * dir);
                const double m = local_min(x, best + 1e-9);
                if (m > best + 1e-9) {
                    best = m;
                    best_p = cur.points[x];
                }
            }
            cur.points[x] = best_p;
            if (!(best_p == p))
                for (const int i : incident(x)) known[i] = 0;  // its quads' margins change
            improved = improved || !(best_p == p);
        }
        if (!improved) step *= 0.5;
    }
    return verify_sphere_partition(cur, dirs).empty() ? cur : part;
}

// ---------------------------------------------------------------------------------------------------------------
// Junctions with leaflets (branching points mixing branches and leaflets, BL-joints). The sphere partition alone only
// sees one mean direction per leaflet, but the leaflet's hexes at the junction are four half-chunks and its plates,
// whose shape depends on where its quad's up / down / out vertices are relative to the leaflet's two boundary edges
// and its normal: e.g. a leaflet corner of 90 degrees between two branches 90 degrees away gets a lune whose sides
// run exactly along its boundary edges (flat half-chunks), and a leaflet whose normal points along a branch gets an
// up vertex tilted towards the leaflet (folded half-chunks). So the junction surface is relaxed on a model of those
// hexes: every corner of a half-chunk or plate hex that lies on the junction's sphere, built with the raw-mesh
// layout (reference-notes §8.2, §8.3, §8.5) and the leaflet neighbours placed as regular leaflet vertices
// (centre, centre + r n, centre + r out, ...; leaflet_vertex_frames), plus, per branch, its angular margin inside
// its quad and every corner of its first chunk (the neighbour's cross-section transported as propagate_frames and
// shrunk as build_raw_mesh do). The objective is a smooth minimum of all these sine-like values.

// One hex vertex of the model: a fixed point (relative to the junction centre), the centre, r x a surface point, or
// r x the unit mean of two surface points (a surface-edge midpoint).
struct ModelVertex {
    enum Kind : std::uint8_t { Fixed, Centre, Point, Mid } kind = Fixed;
    int a = -1, b = -1;
    Vec3 p{};
};
struct ModelHex {
    std::array<ModelVertex, 8> v;
    std::array<bool, 8> on_sphere{};  // corners evaluated (the ones at the junction)
};
struct JunctionModel {
    double r = 1;
    std::vector<std::array<int, 4>> quads;  // the partition quads (local point ids)
    std::vector<Vec3> dirs;                 // per quad: the direction it must contain
    int branch_quads = 0;                   // quads [0, branch_quads) are branches: their margin counts
    std::vector<ModelHex> hexes;
    // Per branch quad: the first chunk of the branch, to the neighbour w at distance length along the quad's
    // direction; w's cross-section (radius w_radius, reduced as build_raw_mesh does next to a branching point) is
    // placed from the rotation-minimising transport of the quad's frame to w (tangent w_tangent), as
    // propagate_frames does. Empty when the model has no chunks.
    struct Chunk {
        double length = 1, w_radius = 1;
        Vec3 w_tangent{};
        // When w is a branching point whose quad on this edge is known (degree_three_chunks_at_bridges): that quad's
        // unit directions from w in its stored order, matched to the branch quad by the quarter turn that
        // propagate_frames snaps to; else the transported square above.
        bool far_quad = false;
        std::array<Vec3, 4> w_quad{};
    };
    std::vector<Chunk> chunks;
    // Whether sin(margin) of each branch quad is a term of its own (relaxation: yes); the choice between two
    // partitions of a degree-3 point (first_chunk_min, degree_three_partition_by_chunks) compares the chunk corners
    // alone.
    bool margin_terms = true;
};

// Weight of sin(branch margin) against the hex corner values: makes narrow branch quads bind earlier than the chunk
// model alone would (measured on the generated shapes: 0.5 gives the best minimum scaled Jacobian of 0.25 / 0.5 / 1).
constexpr double kBranchMarginWeight = 0.5;

// The far quad Q of a chunk that ends at a branching point (unit directions from it, in its stored order), in the
// order of the transported square (-s, r, s, -r) of the arriving frame f: fd[k] = Q[(rot + 2 - k) & 3], where the
// quarter turn rot is the one propagate_frames snaps to (the frame of Q rotated by rot, seen along -f.t, closest to
// f.r) and the pairing is write_branch_chunks' (a_k with b_{(2 - k) & 3}).
std::array<Vec3, 4> matched_far_quad(const Frame& f, const std::array<Vec3, 4>& q) {
    int best = 0;
    double best_dot = -2;
    for (int rot = 0; rot < 4; ++rot) {
        const std::array<Vec3, 4> a{q[rot], q[(rot + 1) & 3], q[(rot + 2) & 3], q[(rot + 3) & 3]};
        const Vec3 t = -1.0 * f.t;
        const double x = dot(f.r, orthonormal_frame((a[1] - a[3]) + cross(a[2] - a[0], t), t).r);
        if (x > best_dot) {
            best_dot = x;
            best = rot;
        }
    }
    std::array<Vec3, 4> fd;
    for (int k = 0; k < 4; ++k) fd[k] = q[(best + 2 - k) & 3];
    return fd;
}

// The terms of the junction objective (each roughly the sine of an angle; all must be positive): sin(margin) of
// every direction in its quad (-1 for a non-convex quad; leaflet directions only need to stay inside), and the
// corner values of the model hexes.
void junction_terms(const JunctionModel& m, const std::vector<Vec3>& pts, std::vector<double>& terms) {
    terms.clear();
    terms.reserve(34 * m.quads.size() + 8 * m.hexes.size());  // the most it pushes: one allocation, not one per growth
    for (std::size_t i = 0; i < m.quads.size(); ++i) {
        std::array<Vec3, 4> q;
        for (int k = 0; k < 4; ++k) q[k] = pts[m.quads[i][k]];
        double mg = spherical_quad_margin(q, m.dirs[i]);
        Vec3 area{};  // a quad turned inside out (e.g. a lune whose sides crossed) can look convex: check its side
        for (int k = 0; k < 4; ++k) area += cross(q[k], q[(k + 1) & 3]);
        if (!(dot(area, m.dirs[i]) > 0)) mg = -1;
        if (static_cast<int>(i) >= m.branch_quads || m.chunks.empty()) {
            const double w = static_cast<int>(i) < m.branch_quads ? kBranchMarginWeight : 1.0;
            // leaflets: inside (by ~6 deg) is enough; branches without a chunk model: the margin itself
            terms.push_back(mg <= -1                               ? -1.0
                            : static_cast<int>(i) < m.branch_quads ? w * std::sin(mg)
                                                                   : std::min(1.0, 10 * std::sin(mg)));
            continue;
        }
        // Branch: its weighted margin, and the 8 corners of its first chunk's 4 hexes.
        if (m.margin_terms || mg <= -1) terms.push_back(mg <= -1 ? -1.0 : kBranchMarginWeight * std::sin(mg));
        if (!(mg > 0)) {  // no chunk: as bad as a folded one (keeps the objective from jumping up here)
            terms.push_back(-1);
            continue;
        }
        const JunctionModel::Chunk& c = m.chunks[i];
        const Vec3& d = m.dirs[i];
        // quad_frame of frame_propagation.cpp: r along (a1 - a3) + (a2 - a0) x t, orthogonalised against t
        Vec3 fr = (q[1] - q[3]) + cross(q[2] - q[0], d);
        fr = fr - dot(fr, d) * d;
        if (!(norm(fr) > 1e-12)) {
            terms.push_back(-1);
            continue;
        }
        fr = normalized(fr);
        const Frame f0{fr, cross(d, fr), d};
        const Frame f1 = rotation_minimizing_step(f0, Vec3{}, c.length * d, c.w_tangent);
        const std::array<Vec3, 4> fd =
            c.far_quad ? matched_far_quad(f1, c.w_quad) : std::array<Vec3, 4>{-1.0 * f1.s, f1.r, f1.s, -1.0 * f1.r};
        // the radius reduction of the raw mesh with its default RawMeshOptions::margin_fraction
        const double rw = margin_limited_radius(c.w_radius, c.length, mg, kBranchMarginFraction);
        const Vec3 w = c.length * d;
        for (int k = 0; k < 4; ++k) {
            const int k1 = (k + 1) & 3;
            const std::array<Vec3, 8> x{Vec3{}, m.r * q[k],     m.r * normalized(q[k] + q[k1]),      m.r * q[k1],
                                        w,      w + rw * fd[k], w + rw * normalized(fd[k] + fd[k1]), w + rw * fd[k1]};
            for (std::size_t corner = 0; corner < 8; ++corner) terms.push_back(hex_corner_value(x, corner));
        }
    }
    for (const ModelHex& h : m.hexes) {
        std::array<Vec3, 8> x;
        for (int k = 0; k < 8; ++k) {
            const ModelVertex& mv = h.v[k];
            switch (mv.kind) {
                case ModelVertex::Fixed: x[k] = mv.p; break;
                case ModelVertex::Centre: x[k] = Vec3{}; break;
                case ModelVertex::Point: x[k] = m.r * pts[mv.a]; break;
                case ModelVertex::Mid: {
                    const Vec3 s = pts[mv.a] + pts[mv.b];
                    x[k] = norm(s) > 1e-12 ? m.r * normalized(s) : Vec3{};
                    break;
                }
            }
        }
        for (int k = 0; k < 8; ++k)
            if (h.on_sphere[k]) terms.push_back(hex_corner_value(x, static_cast<std::size_t>(k)));
    }
}

// Smooth minimum of the terms (log-sum-exp, sharpness 40): raising it raises every nearly binding term.
double soft_min(const std::vector<double>& t) {
    double lo = 1e300;
    for (double x : t) lo = std::min(lo, x);
    double s = 0;
    for (double x : t) s += std::exp(-40.0 * (x - lo));
    return lo - std::log(s) / 40.0;
}

double hard_min(const JunctionModel& m, const std::vector<Vec3>& pts) {
    std::vector<double> t;
    junction_terms(m, pts, t);
    double lo = 1e300;
    for (double x : t) lo = std::min(lo, x);
    return lo;
}

// Pattern search on the partition points maximising soft_min(junction_terms). A point of valence 2 (a lune
// equator point or a digon midpoint) must keep its 180-degree angle: it stays on the great circle through its two
// neighbours unless these are antipodal (then every position keeps it). Deterministic; bounded.
SpherePartition relax_junction(const SpherePartition& part, const JunctionModel& m, double good) {
    if (m.quads.empty() || hard_min(m, part.points) >= good) return part;
    const int np = static_cast<int>(part.points.size());
    std::vector<std::vector<int>> nbrs(np);
    for (const std::array<int, 4>& q : part.quads)
        for (int k = 0; k < 4; ++k) {
            std::vector<int>& l = nbrs[q[k]];
            for (int o : {q[(k + 1) & 3], q[(k + 3) & 3]})
                if (std::find(l.begin(), l.end(), o) == l.end()) l.push_back(o);
        }
    std::vector<Vec3> cur(part.points.begin(), part.points.end());
    for (Vec3& p : cur) p = normalized(p);
    // Keeps every valence-2 point on the great circle of its two neighbours.
    auto project = [&](std::vector<Vec3>& pts) {
        for (int x = 0; x < np; ++x) {
            if (nbrs[x].size() != 2) continue;
            const Vec3 n = cross(pts[nbrs[x][0]], pts[nbrs[x][1]]);
            if (norm(n) < 1e-9) continue;  // antipodal neighbours: free
            const Vec3 a = normalized(n);
            const Vec3 q = pts[x] - dot(pts[x], a) * a;
            if (norm(q) > 1e-12) pts[x] = normalized(q);
        }
    };
    std::vector<double> terms;
    auto score = [&](const std::vector<Vec3>& pts) {
        junction_terms(m, pts, terms);
        return soft_min(terms);
    };
    double best = score(cur);
    const double start = best;
    double step = 0.3;
    std::vector<Vec3> trial;
    for (int round = 0; round < 200 && step > 1e-3; ++round) {
        bool improved = false;
        for (int x = 0; x < np; ++x) {
            const Vec3 p = cur[x];
            Vec3 u = cross(p, Vec3{1, 0, 0});
            if (norm(u) < 0.5) u = cross(p, Vec3{0, 1, 0});
            u = normalized(u);
            const Vec3 w = cross(p, u);
            for (int k = 0; k < 8; ++k) {
                const double a = k * 0.7853981633974483;
                trial = cur;
                trial[x] = normalized(std::cos(step) * p + std::sin(step) * (std::cos(a) * u + std::sin(a) * w));
                project(trial);
                const double sc = score(trial);
                if (sc > best + 1e-12) {
                    best = sc;
                    cur = trial;
                    improved = true;
                }
            }
        }
        if (!improved) step *= 0.5;
    }
    if (!(best > start)) return part;
    SpherePartition out = part;
    out.points = cur;
    return verify_sphere_partition(out, m.dirs).empty() ? out : part;
}

// Registration rotation k of a leaflet quad q (unit points from its start) for a leaflet leaving along unit t with
// normal (sum) nor: with T = t, R = unit((q2 - q0) x T), S = T x R, the quad vertex nearest to the normal is its up
// vertex q_{k+1} (q1 ~ R, q2 ~ S, q3 ~ -R, q0 ~ -S). -1 when the quad is degenerate.
int leaflet_quad_rotation(const std::array<Vec3, 4>& q, const Vec3& t, const Vec3& nor) {
    Vec3 r = cross(q[2] - q[0], t);
    if (!(norm(r) > 1e-12)) return -1;
    r = normalized(r);
    const Vec3 sv = cross(t, r);
    const double psi = std::atan2(dot(nor, sv), dot(nor, r));
    return ((static_cast<int>(std::lround(psi / (std::numbers::pi / 2))) % 4) + 4) % 4;
}

// The pillow of a BL-joint from its frame (T into the leaflet, R = the leaflet's up): points (S, R, -S, -R).
std::vector<Vec3> pillow_points(const Vec3& t, const Vec3& r) {
    const Vec3 sv = cross(t, r);
    return {sv, r, -1.0 * sv, -1.0 * r};
}

// Pattern search on the frame of a BL-joint pillow (T in 8 tangent directions, R turned about T), maximising
// soft_min(junction_terms); keeps the frame when nothing improves. Deterministic; bounded.
void relax_pillow_frame(const JunctionModel& m, Vec3& t, Vec3& r, double good) {
    if (m.quads.empty() || hard_min(m, pillow_points(t, r)) >= good) return;
    std::vector<double> terms;
    auto score = [&](const Vec3& tt, const Vec3& rr) {
        const std::vector<Vec3> pts = pillow_points(tt, rr);
        for (std::size_t i = 0; i < m.quads.size(); ++i) {  // the branch and the leaflet stay in their hemispheres
            std::array<Vec3, 4> q;
            for (int k = 0; k < 4; ++k) q[k] = pts[m.quads[i][k]];
            if (!(spherical_quad_margin(q, m.dirs[i]) > 1e-6)) return -1e300;
        }
        junction_terms(m, pts, terms);
        return soft_min(terms);
    };
    double best = score(t, r);
    double step = 0.1;
    for (int round = 0; round < 200 && step > 1e-3; ++round) {
        bool improved = false;
        Vec3 u = cross(t, Vec3{1, 0, 0});
        if (norm(u) < 0.5) u = cross(t, Vec3{0, 1, 0});
        u = normalized(u);
        const Vec3 w = cross(t, u);
        for (int k = 0; k < 10; ++k) {
            Vec3 tt = t, rr = r;
            if (k < 8) {
                const double a = k * 0.7853981633974483;
                tt = normalized(std::cos(step) * t + std::sin(step) * (std::cos(a) * u + std::sin(a) * w));
                rr = r - dot(r, tt) * tt;
                if (!(norm(rr) > 1e-9)) continue;
                rr = normalized(rr);
            } else {
                const double a = k == 8 ? step : -step;
                rr = normalized(std::cos(a) * r + std::sin(a) * cross(t, r));
            }
            const double sc = score(tt, rr);
            if (sc > best + 1e-12) {
                best = sc;
                t = tt;
                r = rr;
                improved = true;
            }
        }
        if (!improved) step *= 0.5;
    }
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

namespace {

// The steps of rebuild_connection_surfaces, in the order it calls them: checks, the CSR layout, the leaflet sides at
// junctions, the hex model of a junction (for the relaxations), one surface per vertex (parallel), then the LL-joint
// pillows and the leaflet quad rotations (serial).

// Throws Error(UnsupportedConfiguration) naming the first vertex of a class without a surface rule, or the first
// non-orientable leaflet.
void check_surface_support(const SkeletonAnalysis& an) {
    const int nv = static_cast<int>(an.vertex_class.size());
    for (int v = 0; v < nv; ++v) {
        const VertexClass c = an.vertex_class[v];
        if (c != VertexClass::Isolated && c != VertexClass::Extremity && c != VertexClass::Joint &&
            c != VertexClass::BranchingPoint && c != VertexClass::LeafletInterior && c != VertexClass::BLJoint &&
            c != VertexClass::LeafletBoundary && c != VertexClass::FanEdgeVertex && c != VertexClass::FanEdgeEnd &&
            c != VertexClass::LLJoint)
            throw Error(ErrorCode::UnsupportedConfiguration,
                        "skeleton vertex " + std::to_string(v) + " is a " + to_string(c) +
                            ": branching points with leaflets are not meshed yet; edit: attach the branches to "
                            "vertices of the leaflets (inside or on the border) instead of to the junction",
                        ElementRef{ElementRef::Kind::SkeletonVertex, v});
    }
    for (int l = 0; l < static_cast<int>(an.leaflets.size()); ++l)
        if (!an.leaflets[l].orientable)
            throw Error(ErrorCode::UnsupportedConfiguration,
                        "leaflet " + std::to_string(l) + " (face " + std::to_string(an.leaflets[l].faces.front()) +
                            ") is not orientable (Moebius-like): not supported; edit: cut the leaflet along a "
                            "row of edges across its twist (two borders instead of one)",
                        ElementRef{ElementRef::Kind::SkeletonFace, an.leaflets[l].faces.front()});
}

// The CSR layout (sizes from surface_size; a compatible block's vertex: one square per branch edge, see
// set_block_surface) and every array sized, filled with zeros / -1.
ConnectionSurfaces allocate_surfaces(const SkeletonAnalysis& an, int nv, int ne, std::vector<CubeBlock> blocks) {
    ConnectionSurfaces cs;
    cs.point_begin.assign(nv + 1, 0);
    cs.quad_begin.assign(nv + 1, 0);
    cs.edge_begin.assign(nv + 1, 0);
    cs.blocks = std::move(blocks);
    cs.vertex_block.assign(nv, -1);
    for (int b = 0; b < static_cast<int>(cs.blocks.size()); ++b) cs.vertex_block[cs.blocks[b].vertex] = b;
    for (int v = 0; v < nv; ++v) {
        const int nbr = an.vertex_branch_edges[v];
        const SurfaceSize sz = roots_branch(an, v) || roots_fan_cap(an, v) ? SurfaceSize{4, 1, 4}
                               : cs.vertex_block[v] >= 0
                                   ? SurfaceSize{4 * nbr, nbr, 4 * nbr}
                                   : surface_size(an.vertex_class[v], nbr + an.vertex_boundary_edges[v] / 2);
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
    cs.face_corner_quad.assign(an.face_vertices.size(), {-1, -1, -1, -1});
    cs.quad_rotation.assign(cs.quad_begin[nv], -1);
    return cs;
}

bool is_junction(const SkeletonAnalysis& an, int v) {
    return an.vertex_class[v] == VertexClass::LLJoint ||
           (an.vertex_class[v] == VertexClass::BranchingPoint && an.vertex_boundary_edges[v] > 0);
}

// The leaflet sides at every junction (LL-joint or branching point with leaflets) and the faces at every junction
// and BL-joint.
struct LeafletSides {
    std::vector<std::vector<Vec3>> dir, nor;                      // per vertex and side: mean direction, normal sum
    std::vector<std::vector<std::array<int, 3>>> junction_faces;  // per vertex: (face, corner, side)
};

// The side of each face (fl: (face, corner) at v, in face order) at junction v with nl leaflet sides: faces joined
// through interior edges at v share a side, numbered by lowest face id. Throws Error(UnsupportedConfiguration) naming
// v unless they form exactly nl sides.
std::vector<int> group_leaflet_sides(const SkeletonAnalysis& an, const std::vector<std::pair<int, int>>& fl, int nl,
                                     int v) {
    const int n = static_cast<int>(fl.size());
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
                    "skeleton vertex " + std::to_string(v) + ": its leaflet faces do not form " + std::to_string(nl) +
                        " leaflet sides; edit: check the faces at it for a missing face or a leaflet that "
                        "touches itself there",
                    ElementRef{ElementRef::Kind::SkeletonVertex, v});
    return side;
}

// Side s of junction v: the unit mean of the unit vectors to the neighbours across its faces' edges at v, and the sum
// of its face normals.
void side_direction_and_normal(const Skeleton& skeleton, const SkeletonAnalysis& an,
                               const std::vector<std::pair<int, int>>& fl, const std::vector<int>& side, int v, int s,
                               Vec3& dir, Vec3& nor) {
    std::vector<int> es;
    for (int i = 0; i < static_cast<int>(fl.size()); ++i) {
        if (side[i] != s) continue;
        const auto [f, k] = fl[i];
        nor += an.face_normal[f];
        for (int e : {an.face_edges[f][k], an.face_edges[f][(k + 3) & 3]}) es.push_back(e);
    }
    std::sort(es.begin(), es.end());
    es.erase(std::unique(es.begin(), es.end()), es.end());
    for (int e : es) {
        const int w = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
        dir += normalized(skeleton.points[w] - skeleton.points[v]);
    }
    if (!(norm(dir) > 1e-9))
        throw Error(ErrorCode::UnsupportedConfiguration,
                    "skeleton vertex " + std::to_string(v) +
                        ": a leaflet at it has no mean direction (its edges "
                        "there cancel out); edit: move the vertex or its leaflet neighbours",
                    ElementRef{ElementRef::Kind::SkeletonVertex, v});
    dir = normalized(dir);
}

// Leaflet sides at LL-joints and branching points (reference-notes §6.3, §6.8): the faces at v connected through
// interior edges at v form one side, numbered by lowest face id; side s is the vertex's local quad
// (branch edges first), written to cs.face_corner_quad. Each side's direction is the unit mean of the unit vectors to
// its neighbours, its normal the sum of its face normals. BL-joints: every face at the joint is on the leaflet's side
// (quad 1). Serial in face order.
LeafletSides find_leaflet_sides(const Skeleton& skeleton, const SkeletonAnalysis& an, ConnectionSurfaces& cs) {
    const int nv = static_cast<int>(skeleton.points.size());
    const int nf = static_cast<int>(an.face_vertices.size());
    LeafletSides ls;
    ls.dir.resize(nv);
    ls.nor.resize(nv);
    ls.junction_faces.resize(nv);
    if (an.counts.ll_joints > 0 || an.counts.branching_points > 0) {
        std::vector<std::vector<std::pair<int, int>>> vfaces(nv);  // (face, corner), in face order
        for (int f = 0; f < nf; ++f)
            for (int k = 0; k < 4; ++k)
                if (is_junction(an, an.face_vertices[f][k])) vfaces[an.face_vertices[f][k]].push_back({f, k});
        for (int v = 0; v < nv; ++v) {
            if (!is_junction(an, v)) continue;
            const std::vector<std::pair<int, int>>& fl = vfaces[v];
            const int nl = an.vertex_boundary_edges[v] / 2;
            const std::vector<int> side = group_leaflet_sides(an, fl, nl, v);
            ls.dir[v].assign(nl, Vec3{});
            ls.nor[v].assign(nl, Vec3{});
            for (int s = 0; s < nl; ++s)
                side_direction_and_normal(skeleton, an, fl, side, v, s, ls.dir[v][s], ls.nor[v][s]);
            const int nb = an.vertex_branch_edges[v];
            for (int i = 0; i < static_cast<int>(fl.size()); ++i) {
                cs.face_corner_quad[fl[i].first][fl[i].second] = nb + side[i];
                ls.junction_faces[v].push_back({fl[i].first, fl[i].second, side[i]});
            }
        }
    }
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k)
            if (an.vertex_class[an.face_vertices[f][k]] == VertexClass::BLJoint)
                ls.junction_faces[an.face_vertices[f][k]].push_back({f, k, 0});
    return ls;
}

// What the junction models read besides the skeleton and analysis.
struct ModelInputs {
    const Skeleton& skeleton;
    const SkeletonAnalysis& an;
    const LeafletSides& sides;
    const LeafletVertexFrames& leaf;
};

// Radius of skeleton vertex w for the junction model: skeleton.radii when present, else a quarter of the mean
// incident edge length, as the pipeline's default.
double model_radius(const Skeleton& skeleton, const SkeletonAnalysis& an, int w) {
    if (!skeleton.radii.empty()) return skeleton.radii[w];
    double sum = 0;
    const int deg = an.vertex_edge_begin[w + 1] - an.vertex_edge_begin[w];
    for (int i = an.vertex_edge_begin[w]; i < an.vertex_edge_begin[w + 1]; ++i) {
        const std::array<int, 2>& ed = skeleton.edges[an.vertex_edges[i]];
        sum += distance(skeleton.points[ed[0]], skeleton.points[ed[1]]);
    }
    return deg > 0 ? 0.25 * sum / deg : 1.0;
}

// Chunks: the i-th branch quad is on the i-th incident branch edge of v (in increasing edge id); empty unless there
// are nb of them.
std::vector<JunctionModel::Chunk> model_chunks(const Skeleton& skeleton, const SkeletonAnalysis& an, int v,
                                               const std::vector<Vec3>& dirs, int nb) {
    std::vector<JunctionModel::Chunk> chunks;
    const Vec3& c = skeleton.points[v];
    int i = 0;
    for (int j = an.vertex_edge_begin[v]; j < an.vertex_edge_begin[v + 1] && i < nb; ++j) {
        const int e = an.vertex_edges[j];
        if (an.edge_degree[e] != 0) continue;
        const int w = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
        JunctionModel::Chunk ch;
        ch.length = distance(skeleton.points[w], c);
        ch.w_radius = model_radius(skeleton, an, w);
        ch.w_tangent = dirs[i];
        if (an.vertex_class[w] == VertexClass::Joint)
            for (int jj = an.vertex_edge_begin[w]; jj < an.vertex_edge_begin[w + 1]; ++jj) {
                const int e2 = an.vertex_edges[jj];
                if (e2 == e || an.edge_degree[e2] != 0) continue;
                const int x = skeleton.edges[e2][0] == w ? skeleton.edges[e2][1] : skeleton.edges[e2][0];
                const Vec3 t = dirs[i] + normalized(skeleton.points[x] - skeleton.points[w]);
                if (norm(t) > 1e-9) ch.w_tangent = normalized(t);
            }
        chunks.push_back(ch);
        ++i;
    }
    if (i != nb) chunks.clear();
    return chunks;
}

ModelVertex model_point(int a) { return ModelVertex{ModelVertex::Point, a, -1, {}}; }
ModelVertex model_mid(int a, int b) { return ModelVertex{ModelVertex::Mid, a, b, {}}; }
constexpr ModelVertex kModelCentre{ModelVertex::Centre, -1, -1, {}};

// The two plate hexes of face f (corner kv at the junction v, quad q with rotation r): UP = (c0 c1 c2 c3 | up0..up3),
// DOWN = (c0 c3 c2 c1 | dn0 dn3 dn2 dn1), the face's other corners placed as regular leaflet vertices.
void add_plate_model_hexes(const ModelInputs& in, int v, int f, int kv, const std::array<int, 4>& q, int r,
                           JunctionModel& m) {
    const Vec3& c = in.skeleton.points[v];
    auto fixed = [&](const Vec3& p) { return ModelVertex{ModelVertex::Fixed, -1, -1, p - c}; };
    const std::array<int, 4>& fw = in.an.face_vertices[f];
    ModelHex up, dn;
    for (int j = 0; j < 4; ++j) {
        const int w = fw[j], iu = j, id = (4 - j) & 3;
        if (j == kv) {
            up.v[iu] = dn.v[id] = kModelCentre;
            up.v[iu + 4] = model_point(q[(r + 1) & 3]);
            dn.v[id + 4] = model_point(q[(r + 3) & 3]);
            up.on_sphere[iu] = up.on_sphere[iu + 4] = dn.on_sphere[id] = dn.on_sphere[id + 4] = true;
        } else {
            const Vec3& p = in.skeleton.points[w];
            const Vec3 nn = model_radius(in.skeleton, in.an, w) * in.leaf.normal[w];
            up.v[iu] = dn.v[id] = fixed(p);
            up.v[iu + 4] = fixed(p + nn);
            dn.v[id + 4] = fixed(p - nn);
        }
    }
    m.hexes.push_back(up);
    m.hexes.push_back(dn);
}

// The two half-chunk hexes of side ke of face f, a boundary edge at the junction v (reference-notes §8.3, §8.5):
// UP = (a oa ob b | ua oua oub ub), DOWN = (a b ob oa | da db odb oda), the face traversing a -> b.
void add_half_chunk_model_hexes(const ModelInputs& in, int v, int f, int ke, const std::array<int, 4>& q, int r,
                                JunctionModel& m) {
    const Skeleton& skeleton = in.skeleton;
    const Vec3& c = skeleton.points[v];
    auto fixed = [&](const Vec3& p) { return ModelVertex{ModelVertex::Fixed, -1, -1, p - c}; };
    const std::array<int, 4>& fw = in.an.face_vertices[f];
    const int wa = fw[ke], wb = fw[(ke + 1) & 3];
    const bool at_a = wa == v;
    const int w = at_a ? wb : wa;
    const Vec3& p = skeleton.points[w];
    const double rw = model_radius(skeleton, in.an, w);
    const Vec3 nn = rw * in.leaf.normal[w];
    Vec3 o = in.leaf.out[w];
    double ow = rw;
    if (!(norm(o) > 0.5))
        o = cross(normalized(skeleton.points[wb] - skeleton.points[wa]), in.leaf.normal[w]);
    else
        ow = leaflet_out_distance(skeleton, in.an, in.leaf, w, rw);
    o = ow * o;
    // far end: centre, out, out-up, out-down, up, down
    const std::array<ModelVertex, 6> far{fixed(p),          fixed(p + o),  fixed(p + o + nn),
                                         fixed(p + o - nn), fixed(p + nn), fixed(p - nn)};
    std::array<ModelVertex, 6> near;
    if (at_a)  // e leaves v: out q_{k+2}, out-up mid(q_{k+1}, q_{k+2}), out-down mid(q_{k+2}, q_{k+3})
        near = {kModelCentre,
                model_point(q[(r + 2) & 3]),
                model_mid(q[(r + 1) & 3], q[(r + 2) & 3]),
                model_mid(q[(r + 2) & 3], q[(r + 3) & 3]),
                model_point(q[(r + 1) & 3]),
                model_point(q[(r + 3) & 3])};
    else  // e arrives at v: out q_k, out-up mid(q_k, q_{k+1}), out-down mid(q_{k+3}, q_k)
        near = {kModelCentre,
                model_point(q[r & 3]),
                model_mid(q[r & 3], q[(r + 1) & 3]),
                model_mid(q[(r + 3) & 3], q[r & 3]),
                model_point(q[(r + 1) & 3]),
                model_point(q[(r + 3) & 3])};
    const std::array<ModelVertex, 6>& A = at_a ? near : far;
    const std::array<ModelVertex, 6>& B = at_a ? far : near;
    ModelHex hu, hd;
    hu.v = {A[0], A[1], B[1], B[0], A[4], A[2], B[2], B[4]};
    hd.v = {A[0], B[0], B[1], A[1], A[5], B[5], B[3], A[3]};
    using Corners = std::array<int, 4>;  // the corners at v
    const Corners near_u = at_a ? Corners{0, 1, 4, 5} : Corners{2, 3, 6, 7};
    const Corners near_d = at_a ? Corners{0, 3, 4, 7} : Corners{1, 2, 5, 6};
    for (int i : near_u) hu.on_sphere[i] = true;
    for (int i : near_d) hd.on_sphere[i] = true;
    m.hexes.push_back(hu);
    m.hexes.push_back(hd);
}

// The hex model of a junction with leaflets (see relax_junction), for the partition `part` of vertex v whose
// quads [nb, n) are its leaflet sides; rot: per quad, the registration rotation of a leaflet quad (-1 for a branch
// quad).
JunctionModel junction_model(const ModelInputs& in, int v, const SpherePartition& part, const std::vector<Vec3>& dirs,
                             int nb, const std::vector<int>& rot) {
    JunctionModel m;
    m.r = model_radius(in.skeleton, in.an, v);
    m.quads = part.quads;
    m.dirs = dirs;
    m.branch_quads = nb;
    if (nb > 0 && static_cast<int>(part.quads.size()) > nb) m.chunks = model_chunks(in.skeleton, in.an, v, dirs, nb);
    for (const std::array<int, 3>& fks : in.sides.junction_faces[v]) {
        const int f = fks[0], kv = fks[1], qi = nb + fks[2], r = rot[qi];
        const std::array<int, 4>& q = part.quads[qi];
        add_plate_model_hexes(in, v, f, kv, q, r, m);
        for (const int ke : {kv, (kv + 3) & 3})
            if (in.an.edge_degree[in.an.face_edges[f][ke]] == 1) add_half_chunk_model_hexes(in, v, f, ke, q, r, m);
    }
    return m;
}

// The inputs of the per-vertex surface steps.
struct SurfaceInputs {
    const Skeleton& skeleton;
    const SkeletonAnalysis& an;
    const ConnectionSurfaceOptions& options;
    const ModelInputs& model;
    const std::vector<Vec3>& vertex_normal_sum;  // per vertex (when there are BL-joints): sum of its face normals
};

void copy_previous_surface(const SurfaceInputs& in, const ConnectionSurfaces& previous, int v, ConnectionSurfaces& cs) {
    const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
    std::copy(previous.directions.begin() + p0, previous.directions.begin() + cs.point_begin[v + 1],
              cs.directions.begin() + p0);
    std::copy(previous.point_valence.begin() + p0, previous.point_valence.begin() + cs.point_begin[v + 1],
              cs.point_valence.begin() + p0);
    std::copy(previous.quads.begin() + q0, previous.quads.begin() + cs.quad_begin[v + 1], cs.quads.begin() + q0);
    std::copy(previous.quad_edges.begin() + q0, previous.quad_edges.begin() + cs.quad_begin[v + 1],
              cs.quad_edges.begin() + q0);
    std::copy(previous.quad_rotation.begin() + q0, previous.quad_rotation.begin() + cs.quad_begin[v + 1],
              cs.quad_rotation.begin() + q0);
    std::copy(previous.edges.begin() + e0, previous.edges.begin() + cs.edge_begin[v + 1], cs.edges.begin() + e0);
    for (int i = in.an.vertex_edge_begin[v]; i < in.an.vertex_edge_begin[v + 1]; ++i) {
        const int e = in.an.vertex_edges[i];
        const int side = in.skeleton.edges[e][0] == v ? 0 : 1;
        cs.edge_quad[e][side] = previous.edge_quad[e][side];
    }
}

int edge_side(const Skeleton& skeleton, int e, int v) { return skeleton.edges[e][0] == v ? 0 : 1; }

// Branch rooted on the plates: one quad on the branch edge e, its points in the order of the patch (LeafletPatch
// inside the leaflet, BorderPatch on its border), each pointing towards the skeleton vertex whose copy it is (the
// frames start from it; raw_mesh.cpp takes the ids from the patch).
void build_rooted_surface(const SurfaceInputs& in, int v, int e, ConnectionSurfaces& cs) {
    const Skeleton& skeleton = in.skeleton;
    const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
    set_square(cs, e0, q0);
    cs.edge_quad[e][edge_side(skeleton, e, v)] = q0;
    for (int k = 0; k < 4; ++k) cs.point_valence[p0 + k] = 1;
    if (in.an.vertex_class[v] == VertexClass::LeafletInterior) {
        const LeafletPatch patch = leaflet_patch(skeleton, in.an, v, e);
        for (int k = 0; k < 4; ++k)
            cs.directions[p0 + k] = normalized(skeleton.points[patch.neighbour[k]] - skeleton.points[v]);
        return;
    }
    const BorderPatch patch = border_patch(skeleton, in.an, v, e);
    auto to = [&](int x) { return normalized(skeleton.points[x] - skeleton.points[v]); };
    if (patch.kind == BorderRoot::Out) {
        const Vec3 n = normalized(leaflet_normal_sum(in.an, v));
        const Vec3 side = patch.up_first ? n : -1.0 * n;
        cs.directions[p0 + 0] = to(patch.border[0]);
        cs.directions[p0 + 1] = side;
        cs.directions[p0 + 2] = to(patch.border[1]);
        cs.directions[p0 + 3] = -1.0 * side;
    } else {
        // Side: the out vertex lies opposite the middle neighbour.
        const std::array<Vec3, 4> up{to(patch.border[patch.first]), to(patch.middle), to(patch.border[1 - patch.first]),
                                     -1.0 * to(patch.middle)};
        for (int k = 0; k < 4; ++k) cs.directions[p0 + k] = patch.up ? up[k] : up[(4 - k) & 3];
    }
}

// Branches standing on a fan block's cap (fan_blocks.h, CompatibleBlockOptions::fan_cap_branches): one quad on the
// branch edge, its points the cap section's axes in fan_cap_directions' order (raw_mesh.cpp takes the ids from the cap
// section). Throws Error(UnsupportedConfiguration) naming a fan-edge end with a branch that no accepted chain's cap
// carries. Serial, in vertex order.
void build_fan_cap_surfaces(const Skeleton& skeleton, const SkeletonAnalysis& an, ConnectionSurfaces& cs) {
    const int nv = static_cast<int>(an.vertex_class.size());
    for (int v = 0; v < nv; ++v) {
        if (!roots_fan_cap(an, v)) continue;
        const int e = fan_cap_branch_at(cs.fan_blocks, v);
        if (e < 0)
            throw Error(ErrorCode::UnsupportedConfiguration,
                        "skeleton vertex " + std::to_string(v) +
                            ": a branch on a fan-edge end that no fan block's cap, side section or notch carries "
                            "(the chain is not a T or X fan block, or the branch leaves more than 45 degrees off the "
                            "fan line's continuation, off a T's empty side and off the diagonal between two "
                            "leaflets); edit: turn the branch's first edge towards the fan line's continuation, or "
                            "start the branch from a corner of one leaflet off the fan edge",
                        ElementRef{ElementRef::Kind::SkeletonVertex, v});
        const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
        set_square(cs, e0, q0);
        cs.edge_quad[e][edge_side(skeleton, e, v)] = q0;
        const FanBlockChain& c = cs.fan_blocks.chains[cs.fan_blocks.vertex_chain[v]];
        const std::array<Vec3, 4> d = fan_cap_directions(c, cs.fan_blocks.vertex_index[v]);
        for (int k = 0; k < 4; ++k) {
            cs.point_valence[p0 + k] = 1;
            cs.directions[p0 + k] = d[k];
        }
    }
}

// Pillow: quad A = (0,1,2,3) on the branch edge e, quad B = (2,1,0,3) for the leaflet (registered on no edge).
// Geometry from the leaflet frame (reference-notes §7.2): T into the leaflet (mean of the unit vectors to its
// neighbours), R = leaflet normal made orthogonal to T, S = T x R; quad B shows (-S, R, S, -R) from its start, so its
// q1 is "up" (the rotation k = 0 of §8.5).
void build_bl_joint_surface(const SurfaceInputs& in, int v, int e, ConnectionSurfaces& cs) {
    const Skeleton& skeleton = in.skeleton;
    const SkeletonAnalysis& an = in.an;
    const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
    set_square(cs, e0, q0);
    cs.quads[q0 + 1] = {2, 1, 0, 3};
    cs.quad_edges[q0 + 1] = {1, 0, 3, 2};
    cs.edge_quad[e][edge_side(skeleton, e, v)] = q0;
    for (int k = 0; k < 4; ++k) cs.point_valence[p0 + k] = 2;
    const Vec3 leaf_dir = normalized(leaflet_neighbour_direction_sum(skeleton, an, v));
    const int wb = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
    const Vec3 branch_dir = normalized(skeleton.points[wb] - skeleton.points[v]);
    // The hemispheres split the leaflet from the branch: T starts halfway between the leaflet direction
    // and the reversed branch (T = the leaflet direction for a branch along its outward diagonal).
    Vec3 t = leaf_dir - branch_dir;
    t = norm(t) > 1e-6 ? normalized(t) : leaf_dir;
    Vec3 r = in.vertex_normal_sum[v] - dot(in.vertex_normal_sum[v], t) * t;
    if (!(norm(r) > 1e-12))
        throw Error(ErrorCode::UnsupportedConfiguration,
                    "BL-joint at skeleton vertex " + std::to_string(v) +
                        ": the leaflet direction is along its normal (degenerate corner); edit: move the corner "
                        "vertex so that its two border edges make an angle below 180 degrees",
                    ElementRef{ElementRef::Kind::SkeletonVertex, v});
    r = normalized(r);
    if (in.options.relax_partitions) {
        SpherePartition pillow;
        pillow.quads = {{0, 1, 2, 3}, {2, 1, 0, 3}};
        const std::vector<Vec3> pd{branch_dir, leaf_dir};
        const JunctionModel m = junction_model(in.model, v, pillow, pd, 1, {-1, 0});
        relax_pillow_frame(m, t, r, in.options.relax_junctions_below);
    }
    const Vec3 sv = cross(t, r);
    cs.directions[p0 + 2] = -sv;
    cs.directions[p0 + 1] = r;
    cs.directions[p0 + 0] = sv;
    cs.directions[p0 + 3] = -r;
}

// Extremity: one quad on its edge; joint: quad A on its first edge, quad B = (2,1,0,3) on its second. Directions are
// left zero (set by frame propagation).
void build_curve_surface(const Skeleton& skeleton, int v, bool joint, const std::vector<int>& inc,
                         ConnectionSurfaces& cs) {
    const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
    set_square(cs, e0, q0);
    cs.edge_quad[inc[0]][edge_side(skeleton, inc[0], v)] = q0;
    for (int k = 0; k < 4; ++k) cs.point_valence[p0 + k] = 1;
    if (!joint) return;
    cs.quads[q0 + 1] = {2, 1, 0, 3};
    cs.quad_edges[q0 + 1] = {1, 0, 3, 2};
    cs.edge_quad[inc[1]][edge_side(skeleton, inc[1], v)] = q0 + 1;
    for (int k = 0; k < 4; ++k) cs.point_valence[p0 + k] = 2;
}

// Three unit directions whose projections on the plane through their tips leave a gap wider than 180 degrees between
// two consecutive ones (a fat parent and two children leaving to one side): the configuration whose general
// partition tilts its axis into that plane (ConnectionSurfaceOptions::plane_orange_at_degree_three).
bool has_gap_over_half_turn(const std::vector<Vec3>& d) {
    const Vec3 c = cross(d[1] - d[0], d[2] - d[0]);
    if (norm(c) < 1e-12) return false;
    const Vec3 m = normalized(c);
    const Vec3 e1 = normalized(d[0] - dot(d[0], m) * m), e2 = cross(m, e1);
    std::array<double, 3> az{};
    for (int i = 0; i < 3; ++i) az[i] = std::atan2(dot(d[i], e2), dot(d[i], e1));
    std::sort(az.begin(), az.end());
    const double two_pi = 2 * std::numbers::pi;
    const double gap = std::max({az[1] - az[0], az[2] - az[1], az[0] + two_pi - az[2]});
    return gap > std::numbers::pi;
}

// The hex model of branching point v's first chunks (nb branch edges, directions dirs), without quads yet: shared by
// the two partition choices that read the neighbours (degree_three_partition_by_chunks, no_flat_point_in_close_pair).
JunctionModel first_chunk_model(const ModelInputs& in, int v, const std::vector<Vec3>& dirs, int nb) {
    JunctionModel m;
    m.r = model_radius(in.skeleton, in.an, v);
    m.dirs = dirs;
    m.branch_quads = nb;
    m.chunks = model_chunks(in.skeleton, in.an, v, dirs, nb);
    return m;
}

// Per branch edge of a degree-3 point chosen at a bridge (degree_three_chunks_at_bridges): the partition quad of the
// neighbour on that edge when it is a branching point (unit directions from it, in its stored order), else none.
using BridgeEnds = std::array<std::optional<std::array<Vec3, 4>>, 3>;

// The smallest corner value (hex_corner_value, a scaled-Jacobian-like sine) of the 4n hexes of the first chunks at
// branching point v (n branch edges, no leaflet side) for partition part, built as junction_terms models them
// (actual first-edge lengths and neighbour radii); -1 without a chunk model. With ends (n = 3): a chunk ending at a
// branching point ends on that point's quad, and v's radius is reduced as build_raw_mesh reduces it next to those
// points (the margin of the bridge inside their quads).
double first_chunk_min(const ModelInputs& in, int v, const SpherePartition& part, const std::vector<Vec3>& dirs,
                       const BridgeEnds* ends = nullptr) {
    JunctionModel m = first_chunk_model(in, v, dirs, static_cast<int>(dirs.size()));
    m.quads = part.quads;
    m.margin_terms = false;
    if (m.chunks.empty()) return -1;
    if (ends)
        for (std::size_t i = 0; i < ends->size(); ++i) {
            const std::optional<std::array<Vec3, 4>>& q = (*ends)[i];
            if (!q) continue;
            JunctionModel::Chunk& c = m.chunks[i];
            c.far_quad = true;
            c.w_quad = *q;
            const double mw = spherical_quad_margin(*q, -1.0 * dirs[i]);
            if (mw > 0) m.r = margin_limited_radius(m.r, c.length, mw, kBranchMarginFraction);
        }
    return hard_min(m, part.points);
}

// The number of v's neighbours of class BranchingPoint, or -1 when some neighbour is neither that nor a joint or an
// extremity. A joint's or an extremity's cross-section is the square the chunk model of first_chunk_min places; a
// branching point's is its own partition quad (degree_three_chunks_at_bridges).
int branching_neighbours(const Skeleton& skeleton, const SkeletonAnalysis& an, int v) {
    int count = 0;
    for (int j = an.vertex_edge_begin[v]; j < an.vertex_edge_begin[v + 1]; ++j) {
        const int e = an.vertex_edges[j];
        const int w = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
        const VertexClass c = an.vertex_class[w];
        if (c == VertexClass::BranchingPoint)
            ++count;
        else if (c != VertexClass::Joint && c != VertexClass::Extremity)
            return -1;
    }
    return count;
}

// Whether v has exactly k edges, all branch edges (no leaflet side).
bool only_branch_edges(const SkeletonAnalysis& an, int v, int k) {
    if (an.vertex_edge_begin[v + 1] - an.vertex_edge_begin[v] != k) return false;
    for (int j = an.vertex_edge_begin[v]; j < an.vertex_edge_begin[v + 1]; ++j)
        if (an.edge_degree[an.vertex_edges[j]] != 0) return false;
    return true;
}

// Whether branching point v's partition is chosen by its first chunks (degree_three_partition_by_chunks): then it
// depends on its neighbours' positions and radii, not on its branch directions alone (no memo entry).
bool chosen_by_chunks(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaceOptions& options,
                      int v) {
    if (!options.degree_three_partition_by_chunks || !only_branch_edges(an, v, 3)) return false;
    if (options.degree_three_chunks_next_to_branching_points) return true;
    const int bp = branching_neighbours(skeleton, an, v);
    return bp == 0 || (bp > 0 && options.degree_three_chunks_at_bridges);
}

// Whether v is chosen by its chunks with a bridge's far end modelled on the neighbour's quad
// (degree_three_chunks_at_bridges): its partition waits for its neighbours' (the second pass of
// rebuild_connection_surfaces).
bool chosen_at_bridge(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaceOptions& options,
                      int v) {
    return options.degree_three_chunks_at_bridges && chosen_by_chunks(skeleton, an, options, v) &&
           branching_neighbours(skeleton, an, v) > 0;
}

void branch_edges(const SkeletonAnalysis& an, int v, std::vector<int>& inc);
void branch_directions(const Skeleton& skeleton, int v, const std::vector<int>& inc, std::vector<Vec3>& dirs);

// Whether branching point v's partition may read more than its branch directions: chosen by its chunks (above), or
// a degree-4 point without leaflet sides with a close pair under no_flat_point_in_close_pair (its candidate is kept by
// the junction model, which reads the neighbours' positions and radii). Such points get no memo entry.
bool reads_neighbours(const Skeleton& skeleton, const SkeletonAnalysis& an, const ConnectionSurfaceOptions& options,
                      int v) {
    if (chosen_by_chunks(skeleton, an, options, v)) return true;
    if (!options.no_flat_point_in_close_pair || !only_branch_edges(an, v, 4)) return false;
    std::vector<int> inc;
    branch_edges(an, v, inc);
    std::vector<Vec3> dirs;
    branch_directions(skeleton, v, inc, dirs);
    return close_pair_of_four(dirs, SpherePartitionOptions{}.close_pair_gap_deg)[0] >= 0;
}

// The two candidates of a degree-3 point chosen by its chunks, each relaxed as it would be kept: the general choice
// of partition_sphere and the orange around the branches' best-fit plane normal (none when that orange is the general
// choice itself). Neither reads a bridge's far end: a point chosen at a bridge computes them once for all its rounds.
struct ChunkCandidates {
    SpherePartition general;
    std::optional<SpherePartition> orange;
};

ChunkCandidates chunk_candidates(const ConnectionSurfaceOptions& options, const std::vector<Vec3>& dirs,
                                 const SpherePartitionOptions& po) {
    ChunkCandidates c;
    c.general = partition_sphere(dirs, po);
    c.orange = plane_orange_alternative(dirs, c.general, po);
    if (options.relax_partitions) {
        c.general = relax_partition(c.general, dirs, options.relax_below_margin);
        if (c.orange) *c.orange = relax_partition(*c.orange, dirs, options.relax_below_margin);
    }
    return c;
}

// Of the candidates, the one whose first chunks have the better worst hex corner (the general one on a tie).
const SpherePartition& chunk_choice(const ModelInputs& model, int v, const ChunkCandidates& c,
                                    const std::vector<Vec3>& dirs, const BridgeEnds* ends) {
    if (c.orange && first_chunk_min(model, v, *c.orange, dirs, ends) > first_chunk_min(model, v, c.general, dirs, ends))
        return *c.orange;
    return c.general;
}

// The error of a failed partition at branching point v (degree n), naming v.
Error partition_failure(int v, int n, const Error& err) {
    return Error(ErrorCode::NumericalFailure,
                 "no connection surface at skeleton vertex " + std::to_string(v) + " (degree " + std::to_string(n) +
                     "): " + err.what() +
                     "; edit: let its branches and leaflets leave it in distinct directions (no two parallel), or "
                     "move some of them to a neighbouring vertex",
                 ElementRef{ElementRef::Kind::SkeletonVertex, v});
}

// Whether branching point v (directions dirs, nb of them branch edges) is chosen by its chunks (both candidates of
// chunk_candidates), with its bridges' far ends when `with_ends`.
bool by_chunks_at(const SurfaceInputs& in, int v, const std::vector<Vec3>& dirs, int nb, bool with_ends) {
    const int n = static_cast<int>(dirs.size());
    const bool at_bridge = n == 3 && nb == 3 && chosen_at_bridge(in.skeleton, in.an, in.options, v);
    return at_bridge ? with_ends || in.options.degree_three_chunks_next_to_branching_points
                     : n == 3 && nb == 3 && chosen_by_chunks(in.skeleton, in.an, in.options, v);
}

// Whether round 0 of a point chosen at a bridge (directions dirs) is one of its chunk candidates: chosen by its chunks
// without the bridges' ends, or the general partition (not the plane orange of the gap rule).
bool round_zero_reads_candidates(const SurfaceInputs& in, int v, const std::vector<Vec3>& dirs) {
    return by_chunks_at(in, v, dirs, 3, false) ||
           !(in.options.plane_orange_at_degree_three && has_gap_over_half_turn(dirs));
}

// The sphere partition of branching point v for directions dirs (nb branch edges, then its leaflet sides), relaxed
// (relax_partition, then relax_junction on the junction's hex model, whose leaflet quad rotations are stored in
// cs.quad_rotation). Any partition error becomes Error(NumericalFailure) naming v.
// At a point chosen at a bridge (chosen_at_bridge), `ends` holds its neighbours' quads; without them such a point
// gets the partition it would have without degree_three_chunks_at_bridges (what its neighbours model it with).
// `candidates`: v's chunk_candidates when already computed (the second pass's points chosen at a bridge).
SpherePartition partition_branching_point(const SurfaceInputs& in, int v, const std::vector<Vec3>& dirs, int nb,
                                          ConnectionSurfaces& cs, const BridgeEnds* ends = nullptr,
                                          const ChunkCandidates* candidates = nullptr) {
    const ConnectionSurfaceOptions& options = in.options;
    const int n = static_cast<int>(dirs.size()), q0 = cs.quad_begin[v];
    const LeafletSides& sides = in.model.sides;
    SpherePartition part;
    try {
        SpherePartitionOptions po;
        po.exact_three_orange = options.exact_three_orange;
        po.shared_hull_relaxation = options.shared_hull_relaxation;
        po.gradient_long_relaxation = options.gradient_long_relaxation;
        po.coarse_three_scan = options.coarse_three_scan;
        po.tabled_three_start = options.tabled_three_start;
        po.first_improving_long_relaxation = options.first_improving_long_relaxation;
        // Three branch edges, no leaflet side: with degree_three_partition_by_chunks both candidates below; else, at a
        // gap over 180 degrees, the orange around the best-fit plane's normal (a tolerance of 1 takes
        // partition_sphere's planar path for any three directions), see plane_orange_at_degree_three.
        const bool by_chunks = by_chunks_at(in, v, dirs, nb, ends != nullptr);
        const bool plane_orange =
            !by_chunks && options.plane_orange_at_degree_three && n == 3 && nb == 3 && has_gap_over_half_turn(dirs);
        po.planarity_tolerance = plane_orange ? 1.0 : options.planarity_tolerance;
        if (by_chunks) {
            // Both candidates, each relaxed as it would be kept: the general choice and the orange around the
            // branches' best-fit plane normal; the one whose first chunks have the better worst hex corner.
            if (candidates)
                part = chunk_choice(in.model, v, *candidates, dirs, ends);
            else
                part = chunk_choice(in.model, v, chunk_candidates(options, dirs, po), dirs, ends);
        } else if (candidates && !plane_orange) {
            part = candidates->general;  // the same partition_sphere call, relaxed the same way (n = nb = 3)
        } else if (options.no_flat_point_in_close_pair && n == 4 && nb == 4 &&
                   close_pair_of_four(dirs, po.close_pair_gap_deg)[0] >= 0) {
            // The partition without a flat point in the close pair's crotch, kept only if the junction's hexes do not
            // get worse: the smallest value of the first chunks' corners and the weighted margins (junction_terms,
            // the raw mesh's layout and radius reduction), the same measure relax_junction raises. Both partitions
            // come from one call that shares their search; equal ones stay equal after the (deterministic) relaxation.
            std::array<SpherePartition, 2> both = partition_sphere_close_pair_pair(dirs, po);
            const bool same = both[1].points == both[0].points && both[1].quads == both[0].quads;
            part = std::move(both[0]);
            if (options.relax_partitions) part = relax_partition(part, dirs, options.relax_below_margin);
            SpherePartition other = std::move(both[1]);
            if (options.relax_partitions && !same) other = relax_partition(other, dirs, options.relax_below_margin);
            if (!same && (other.points != part.points || other.quads != part.quads)) {
                JunctionModel m = first_chunk_model(in.model, v, dirs, nb);
                const auto value = [&](const SpherePartition& p) {
                    m.quads = p.quads;
                    std::vector<Vec3> pts(p.points.size());
                    for (std::size_t k = 0; k < pts.size(); ++k) pts[k] = normalized(p.points[k]);
                    return hard_min(m, pts);
                };
                if (value(other) >= value(part)) part = std::move(other);
            }
        } else {
            part = partition_sphere(dirs, po);
            if (options.relax_partitions) part = relax_partition(part, dirs, options.relax_below_margin);
        }
        if (options.relax_partitions && n > nb) {
            std::vector<int> rot(n, -1);
            bool ok = true;
            for (int i = nb; i < n; ++i) {
                std::array<Vec3, 4> qd;
                for (int k = 0; k < 4; ++k) qd[k] = normalized(part.points[part.quads[i][k]]);
                rot[i] = leaflet_quad_rotation(qd, sides.dir[v][i - nb], sides.nor[v][i - nb]);
                ok = ok && rot[i] >= 0;
            }
            if (ok) {
                part = relax_junction(part, junction_model(in.model, v, part, dirs, nb, rot),
                                      options.relax_junctions_below);
                // the rotations the model was relaxed with (the nearest vertex to the normal may change)
                for (int i = nb; i < n; ++i) cs.quad_rotation[q0 + i] = rot[i];
            }
        }
    } catch (const Error& err) {
        throw partition_failure(v, n, err);
    }
    return part;
}

// Stores partition `part` (n quads) as v's surface: directions, quads, their edges (numbered by first appearance),
// valences, and quad i < nb on branch edge inc[i]. Throws Error(NumericalFailure) naming v unless it is a closed quad
// surface with n + 2 points and 2n edges.
void store_partition(const Skeleton& skeleton, int v, const SpherePartition& part, int n, const std::vector<int>& inc,
                     ConnectionSurfaces& cs) {
    const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
    const int nb = static_cast<int>(inc.size());
    auto not_closed = [&]() {
        return Error(ErrorCode::NumericalFailure,
                     "sphere partition at skeleton vertex " + std::to_string(v) + " is not a closed quad surface",
                     ElementRef{ElementRef::Kind::SkeletonVertex, v});
    };
    if (static_cast<int>(part.quads.size()) != n || static_cast<int>(part.points.size()) != n + 2)
        throw Error(ErrorCode::NumericalFailure,
                    "sphere partition at skeleton vertex " + std::to_string(v) + " has " +
                        std::to_string(part.quads.size()) + " quads and " + std::to_string(part.points.size()) +
                        " points for degree " + std::to_string(n),
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
                if (n_edges == 2 * n) throw not_closed();
                found = n_edges;
                cs.edges[e0 + n_edges++] = {a, b};
            }
            cs.quad_edges[q0 + i][k] = found;
        }
        if (i < nb) cs.edge_quad[inc[i]][edge_side(skeleton, inc[i], v)] = q0 + i;
    }
    if (n_edges != 2 * n) throw not_closed();
}

// Branching point: partition of the sphere with one quad per incident branch direction (inc: the branch edges, in
// increasing id). Leaflets count as virtual branches after the branch edges (reference-notes §6.8).
// v's branch edges (edge degree 0) in increasing id.
void branch_edges(const SkeletonAnalysis& an, int v, std::vector<int>& inc) {
    inc.clear();
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i)
        if (an.edge_degree[an.vertex_edges[i]] == 0) inc.push_back(an.vertex_edges[i]);
}

// dirs[i] = unit direction from v to the other end of branch edge inc[i] (dirs resized to inc.size()).
void branch_directions(const Skeleton& skeleton, int v, const std::vector<int>& inc, std::vector<Vec3>& dirs) {
    const int nb = static_cast<int>(inc.size());
    dirs.resize(nb);
    const Vec3& center = skeleton.points[v];
    for (int i = 0; i < nb; ++i) {
        const int e = inc[i];
        const int w = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
        dirs[i] = normalized(skeleton.points[w] - center);
    }
}

void build_branching_surface(const SurfaceInputs& in, int v, const std::vector<int>& inc, std::vector<Vec3>& dirs,
                             ConnectionSurfaces& cs) {
    const Skeleton& skeleton = in.skeleton;
    const std::vector<Vec3>& side_dir = in.model.sides.dir[v];
    const int nb = static_cast<int>(inc.size());
    const int n = nb + static_cast<int>(side_dir.size());
    branch_directions(skeleton, v, inc, dirs);
    dirs.resize(n);
    for (int i = nb; i < n; ++i) dirs[i] = side_dir[i - nb];
    const SpherePartition part = partition_branching_point(in, v, dirs, nb, cs);
    store_partition(skeleton, v, part, n, inc, cs);
}

// Rounds of the choice at bridges: in round r a point models each bridge on its neighbour's partition of round r - 1
// (round 0: without degree_three_chunks_at_bridges). Two rounds let two such points next to each other see each
// other's choice (measured: docs/junctions.md, "Degree-3 points at bridges").
constexpr int kBridgeRounds = 2;

// A point chosen at a bridge that the second pass reads: its branch edges, their directions, its chunk candidates
// (computed once for all rounds) and its partition of each round that some point reads.
struct BridgePoint {
    int vertex = -1;
    std::vector<int> inc;
    std::vector<Vec3> dirs;
    ChunkCandidates candidates;
    std::array<SpherePartition, kBridgeRounds + 1> round;
};

// The neighbour across branch edge e of point v whose quad a round of v reads from its partition of the previous
// round (a branching point without compatible block chosen at a bridge), or -1.
int bridge_neighbour(const SurfaceInputs& in, const ConnectionSurfaces& cs, int v, int e) {
    const int w = in.skeleton.edges[e][0] == v ? in.skeleton.edges[e][1] : in.skeleton.edges[e][0];
    const bool read = in.an.vertex_class[w] == VertexClass::BranchingPoint && cs.vertex_block[w] < 0 &&
                      chosen_at_bridge(in.skeleton, in.an, in.options, w);
    return read ? w : -1;
}

// The ends of point v's bridges in round `round` > 0: per branch edge ending at a branching point w, w's quad on it
// (unit directions in its stored order): from cs when w is not chosen at a bridge (computed in the first pass, or
// copied), else from w's partition of round `round` - 1 (computed in this pass, whether w is computed or copied in this
// rebuild: the same result either way); none at a compatible block (its chunk is modelled with a square).
BridgeEnds bridge_ends(const SurfaceInputs& in, const ConnectionSurfaces& cs, int v, int round,
                       const std::vector<BridgePoint>& points, const std::vector<int>& slot) {
    BridgeEnds ends;
    const std::vector<int>& inc = points[slot[v]].inc;
    for (int i = 0; i < 3; ++i) {
        const int e = inc[i];
        const int w = in.skeleton.edges[e][0] == v ? in.skeleton.edges[e][1] : in.skeleton.edges[e][0];
        if (in.an.vertex_class[w] != VertexClass::BranchingPoint || cs.vertex_block[w] >= 0) continue;
        std::array<Vec3, 4> q;
        if (bridge_neighbour(in, cs, v, e) < 0) {
            const int gq = cs.edge_quad[e][edge_side(in.skeleton, e, w)];
            for (int k = 0; k < 4; ++k) q[k] = cs.directions[cs.point_begin[w] + cs.quads[gq][k]];
        } else {
            const BridgePoint& bw = points[slot[w]];
            const int j = static_cast<int>(std::find(bw.inc.begin(), bw.inc.end(), e) - bw.inc.begin());
            MESOHEX_CHECK(j < static_cast<int>(bw.inc.size()), "bridge edge not a branch edge of its end");
            const SpherePartition& part = bw.round[round - 1];
            for (int k = 0; k < 4; ++k) q[k] = normalized(part.points[part.quads[j][k]]);
        }
        ends[i] = q;
    }
    return ends;
}

// The second pass: the points with at_bridge[v] != 0. Round r of a point chosen at a bridge models each bridge on the
// neighbour's partition of round r - 1 (round 0: the partition without degree_three_chunks_at_bridges); the points
// computed here need round kBridgeRounds, which reads round kBridgeRounds - 1 of their neighbours chosen at a bridge,
// and so on. Each point's candidates are computed once (in parallel), then each round in parallel from the previous
// one: every task writes only its point's slot (and, in the last round, its vertex's ranges and slots).
void build_bridge_surfaces(const SurfaceInputs& in, const std::vector<char>& at_bridge, ConnectionSurfaces& cs) {
    const int nv = static_cast<int>(at_bridge.size());
    std::array<std::vector<int>, kBridgeRounds + 1> need;  // per round, the points whose partition of it is read
    for (int v = 0; v < nv; ++v)
        if (at_bridge[v]) need[kBridgeRounds].push_back(v);
    if (need[kBridgeRounds].empty()) return;
    std::vector<int> slot(nv, -1);
    std::vector<BridgePoint> points;
    const auto add = [&](int v) {
        if (slot[v] >= 0) return;
        slot[v] = static_cast<int>(points.size());
        BridgePoint& p = points.emplace_back();
        p.vertex = v;
        branch_edges(in.an, v, p.inc);
        branch_directions(in.skeleton, v, p.inc, p.dirs);
    };
    for (const int v : need[kBridgeRounds]) add(v);
    for (int r = kBridgeRounds; r > 0; --r) {
        std::vector<char> marked(nv, 0);
        for (const int v : need[r])
            for (const int e : points[slot[v]].inc)
                if (const int w = bridge_neighbour(in, cs, v, e); w >= 0) marked[w] = 1;
        for (int w = 0; w < nv; ++w)
            if (marked[w]) {
                need[r - 1].push_back(w);
                add(w);
            }
    }
    // The candidates of every point some round reads them at: the rounds after 0, and round 0 unless it takes the
    // plane orange of the gap rule (then partition_branching_point computes that one alone, as before).
    std::vector<char> wanted(points.size(), 0);
    for (int r = 1; r <= kBridgeRounds; ++r)
        for (const int v : need[r]) wanted[slot[v]] = 1;
    const SpherePartitionOptions po{.planarity_tolerance = in.options.planarity_tolerance,
                                    .exact_three_orange = in.options.exact_three_orange,
                                    .shared_hull_relaxation = in.options.shared_hull_relaxation,
                                    .gradient_long_relaxation = in.options.gradient_long_relaxation,
                                    .coarse_three_scan = in.options.coarse_three_scan,
                                    .tabled_three_start = in.options.tabled_three_start,
                                    .first_improving_long_relaxation = in.options.first_improving_long_relaxation};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              BridgePoint& p = points[i];
                              const int v = p.vertex;
                              if (!wanted[i] && !round_zero_reads_candidates(in, v, p.dirs)) continue;
                              wanted[i] = 1;
                              try {
                                  p.candidates = chunk_candidates(in.options, p.dirs, po);
                              } catch (const Error& err) {
                                  throw partition_failure(v, 3, err);
                              }
                          }
                      });
    for (int r = 0; r <= kBridgeRounds; ++r)
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, need[r].size(), 8), [&](const tbb::blocked_range<std::size_t>& range) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    const int v = need[r][i];
                    BridgePoint& p = points[slot[v]];
                    const BridgeEnds ends = r > 0 ? bridge_ends(in, cs, v, r, points, slot) : BridgeEnds{};
                    p.round[r] = partition_branching_point(in, v, p.dirs, 3, cs, r > 0 ? &ends : nullptr,
                                                           wanted[slot[v]] ? &p.candidates : nullptr);
                    if (r == kBridgeRounds) store_partition(in.skeleton, v, p.round[r], 3, p.inc, cs);
                }
            });
}

// Whether a vertex within kBridgeRounds edges of v is marked in recompute: a point chosen at a bridge reads the
// surfaces of its neighbours (round kBridgeRounds - 1 of those chosen at a bridge, which read their own neighbours'),
// so it is recomputed with them.
bool recompute_near(const Skeleton& skeleton, const SkeletonAnalysis& an, const std::vector<char>& recompute, int v) {
    std::vector<int> ring{v};
    for (int round = 0; round <= kBridgeRounds; ++round) {
        std::vector<int> next;
        for (const int x : ring) {
            if (recompute[x]) return true;
            if (round == kBridgeRounds) continue;
            for (int j = an.vertex_edge_begin[x]; j < an.vertex_edge_begin[x + 1]; ++j) {
                const std::array<int, 2>& e = skeleton.edges[an.vertex_edges[j]];
                next.push_back(e[0] == x ? e[1] : e[0]);
            }
        }
        ring = std::move(next);
    }
    return false;
}

// ---- Content-keyed memo of branching-point surfaces (SurfaceMemo) ----

// A branching point without leaflet sides and without a compatible block: its surface reads its branch directions and
// the partition options only (partition_branching_point without a junction model, store_partition).
bool memoable(const SkeletonAnalysis& an, const LeafletSides& sides, const ConnectionSurfaces& cs, int v) {
    return an.vertex_class[v] == VertexClass::BranchingPoint && !roots_branch(an, v) && sides.dir[v].empty() &&
           cs.vertex_block[v] < 0;
}

bool memo_options_match(const SurfaceMemo& m, const ConnectionSurfaceOptions& o) {
    return std::memcmp(&m.planarity_tolerance, &o.planarity_tolerance, sizeof(double)) == 0 &&
           m.relax_partitions == o.relax_partitions &&
           std::memcmp(&m.relax_below_margin, &o.relax_below_margin, sizeof(double)) == 0 &&
           m.plane_orange_at_degree_three == o.plane_orange_at_degree_three &&
           m.no_flat_point_in_close_pair == o.no_flat_point_in_close_pair &&
           m.degree_three_partition_by_chunks == o.degree_three_partition_by_chunks &&
           m.degree_three_chunks_next_to_branching_points == o.degree_three_chunks_next_to_branching_points &&
           m.degree_three_chunks_at_bridges == o.degree_three_chunks_at_bridges &&
           m.exact_three_orange == o.exact_three_orange && m.shared_hull_relaxation == o.shared_hull_relaxation &&
           m.gradient_long_relaxation == o.gradient_long_relaxation && m.coarse_three_scan == o.coarse_three_scan &&
           m.tabled_three_start == o.tabled_three_start &&
           m.first_improving_long_relaxation == o.first_improving_long_relaxation;
}

// FNV-1a (64 bits) of the key's bytes.
std::uint64_t memo_hash(const std::vector<Vec3>& key) {
    std::uint64_t h = 14695981039346656037ULL;
    const auto* p = reinterpret_cast<const unsigned char*>(key.data());
    for (std::size_t i = 0; i < key.size() * sizeof(Vec3); ++i) h = (h ^ p[i]) * 1099511628211ULL;
    return h;
}

bool same_key(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

// The entry whose key equals `key` bit for bit, or null.
const SurfaceMemo::Entry* find_memo_entry(const SurfaceMemo& m, const std::vector<Vec3>& key, std::uint64_t h) {
    auto it = std::lower_bound(m.index.begin(), m.index.end(), std::pair<std::uint64_t, int>{h, -1});
    for (; it != m.index.end() && it->first == h; ++it)
        if (same_key(m.entries[it->second].key, key)) return &m.entries[it->second];
    return nullptr;
}

// Writes a memo entry as v's surface (the sizes are those of v's CSR ranges: n + 2 points, n quads, 2n edges) and
// registers quad i on branch edge inc[i], as store_partition does.
void store_memo_entry(const Skeleton& skeleton, const SurfaceMemo::Entry& en, int v, const std::vector<int>& inc,
                      ConnectionSurfaces& cs) {
    const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
    MESOHEX_CHECK(static_cast<int>(en.directions.size()) == cs.point_begin[v + 1] - p0 &&
                      static_cast<int>(en.quads.size()) == cs.quad_begin[v + 1] - q0 &&
                      static_cast<int>(en.edges.size()) == cs.edge_begin[v + 1] - e0 && en.quads.size() == inc.size(),
                  "memo entry does not fit the vertex's surface");
    std::copy(en.directions.begin(), en.directions.end(), cs.directions.begin() + p0);
    std::copy(en.point_valence.begin(), en.point_valence.end(), cs.point_valence.begin() + p0);
    std::copy(en.quads.begin(), en.quads.end(), cs.quads.begin() + q0);
    std::copy(en.quad_edges.begin(), en.quad_edges.end(), cs.quad_edges.begin() + q0);
    std::copy(en.edges.begin(), en.edges.end(), cs.edges.begin() + e0);
    for (int i = 0; i < static_cast<int>(inc.size()); ++i)
        cs.edge_quad[inc[i]][edge_side(skeleton, inc[i], v)] = q0 + i;
}

SurfaceMemo::Entry memo_entry_of(const ConnectionSurfaces& cs, int v, const std::vector<Vec3>& key) {
    SurfaceMemo::Entry en;
    en.key = key;
    en.directions.assign(cs.directions.begin() + cs.point_begin[v], cs.directions.begin() + cs.point_begin[v + 1]);
    en.point_valence.assign(cs.point_valence.begin() + cs.point_begin[v],
                            cs.point_valence.begin() + cs.point_begin[v + 1]);
    en.quads.assign(cs.quads.begin() + cs.quad_begin[v], cs.quads.begin() + cs.quad_begin[v + 1]);
    en.quad_edges.assign(cs.quad_edges.begin() + cs.quad_begin[v], cs.quad_edges.begin() + cs.quad_begin[v + 1]);
    en.edges.assign(cs.edges.begin() + cs.edge_begin[v], cs.edges.begin() + cs.edge_begin[v + 1]);
    return en;
}

// The memo of this skeleton: one entry per distinct key of its memo-able vertices (keys[v] non-empty), from cs.
// Serial, in hash then vertex order.
SurfaceMemo collect_memo(const ConnectionSurfaces& cs, const std::vector<std::vector<Vec3>>& keys,
                         const ConnectionSurfaceOptions& options) {
    SurfaceMemo m;
    m.planarity_tolerance = options.planarity_tolerance;
    m.relax_partitions = options.relax_partitions;
    m.relax_below_margin = options.relax_below_margin;
    m.plane_orange_at_degree_three = options.plane_orange_at_degree_three;
    m.no_flat_point_in_close_pair = options.no_flat_point_in_close_pair;
    m.degree_three_partition_by_chunks = options.degree_three_partition_by_chunks;
    m.degree_three_chunks_next_to_branching_points = options.degree_three_chunks_next_to_branching_points;
    m.degree_three_chunks_at_bridges = options.degree_three_chunks_at_bridges;
    m.exact_three_orange = options.exact_three_orange;
    m.shared_hull_relaxation = options.shared_hull_relaxation;
    m.gradient_long_relaxation = options.gradient_long_relaxation;
    m.coarse_three_scan = options.coarse_three_scan;
    m.tabled_three_start = options.tabled_three_start;
    m.first_improving_long_relaxation = options.first_improving_long_relaxation;
    std::vector<std::pair<std::uint64_t, int>> order;
    for (int v = 0; v < static_cast<int>(keys.size()); ++v)
        if (!keys[v].empty()) order.push_back({memo_hash(keys[v]), v});
    std::sort(order.begin(), order.end());
    std::size_t run = 0;  // first index entry with the current hash
    for (const auto& [h, v] : order) {
        if (m.index.empty() || m.index.back().first != h) run = m.index.size();
        bool known = false;
        for (std::size_t i = run; i < m.index.size() && !known; ++i)
            known = same_key(m.entries[m.index[i].second].key, keys[v]);
        if (known) continue;
        m.index.push_back({h, static_cast<int>(m.entries.size())});
        m.entries.push_back(memo_entry_of(cs, v, keys[v]));
    }
    return m;
}

// The surface of one vertex (dirs, inc: scratch of the calling task). Writes only v's ranges and the (edge, side)
// slots of v's own incident edges.
void build_vertex_surface(const SurfaceInputs& in, int v, std::vector<Vec3>& dirs, std::vector<int>& inc,
                          ConnectionSurfaces& cs) {
    const SkeletonAnalysis& an = in.an;
    const VertexClass c = an.vertex_class[v];
    branch_edges(an, v, inc);
    if (roots_branch(an, v))
        build_rooted_surface(in, v, inc[0], cs);
    else if (c == VertexClass::BLJoint)
        build_bl_joint_surface(in, v, inc[0], cs);
    else if (c == VertexClass::Extremity || c == VertexClass::Joint)
        build_curve_surface(in.skeleton, v, c == VertexClass::Joint, inc, cs);
    else
        build_branching_surface(in, v, inc, dirs, cs);
}

// LL-joint pillow (reference-notes §6.3, §7.2, §8.5 with the flaw fixed): quad A = (0,1,2,3) for side 0, quad B =
// (2,1,0,3) for side 1. T = unit(dir_0 - dir_1); R = the side-0 normal made orthogonal to T, turned about T by half
// the residual angle between the two projected normals and the nearest multiple of 90 degrees, S = T x R; points
// (-S, R, S, -R).
void build_ll_joint_pillow(const LeafletSides& sides, int v, ConnectionSurfaces& cs) {
    const double quarter = std::numbers::pi / 2;
    const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
    const auto fail = [&](const std::string& what) {
        throw Error(ErrorCode::UnsupportedConfiguration,
                    "leaflet junction at skeleton vertex " + std::to_string(v) + ": " + what +
                        "; edit: move the vertex so that the leaflets leave it in different directions, off each "
                        "other's planes",
                    ElementRef{ElementRef::Kind::SkeletonVertex, v});
    };
    const std::vector<Vec3>& dir = sides.dir[v];
    const std::vector<Vec3>& nor = sides.nor[v];
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

// LL-joint pillows, then every leaflet quad (LL-joint or branching point) not fixed by the junction relaxation picks
// its own rotation k (§8.5): with its frame T = its direction, R = unit((q2 - q0) x T), S = T x R, the quad vertex
// nearest to the side's own normal is its up vertex q_{k+1} (q1 ~ R, q2 ~ S, q3 ~ -R, q0 ~ -S). Serial.
void finish_leaflet_junctions(const SkeletonAnalysis& an, const LeafletSides& sides, ConnectionSurfaces& cs) {
    const int nv = static_cast<int>(an.vertex_class.size());
    for (int v = 0; v < nv; ++v) {
        if (!is_junction(an, v)) continue;
        if (an.vertex_class[v] == VertexClass::LLJoint) build_ll_joint_pillow(sides, v, cs);
        const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v];
        const int nb = an.vertex_branch_edges[v];
        for (int s = 0; s < static_cast<int>(sides.dir[v].size()); ++s) {
            const int q = q0 + nb + s;
            std::array<Vec3, 4> qd;
            for (int k = 0; k < 4; ++k) qd[k] = cs.directions[p0 + cs.quads[q][k]];
            if (cs.quad_rotation[q] < 0)  // not already fixed by the junction relaxation
                cs.quad_rotation[q] = leaflet_quad_rotation(qd, sides.dir[v][s], sides.nor[v][s]);
            if (cs.quad_rotation[q] < 0)
                throw Error(ErrorCode::UnsupportedConfiguration,
                            "leaflet junction at skeleton vertex " + std::to_string(v) +
                                ": degenerate leaflet quad; edit: move the vertex off its leaflets' planes",
                            ElementRef{ElementRef::Kind::SkeletonVertex, v});
        }
    }
}

}  // namespace

ConnectionSurfaces build_connection_surfaces(const Skeleton& skeleton, const SkeletonAnalysis& an,
                                             const ConnectionSurfaceOptions& options) {
    return rebuild_connection_surfaces(skeleton, an, nullptr, {}, options);
}

ConnectionSurfaces rebuild_connection_surfaces(const Skeleton& skeleton, const SkeletonAnalysis& an,
                                               const ConnectionSurfaces* previous, const std::vector<char>& recompute,
                                               const ConnectionSurfaceOptions& options, const SurfaceMemo* memo_in,
                                               SurfaceMemo* memo_out) {
    const int nv = static_cast<int>(skeleton.points.size());
    const int ne = static_cast<int>(skeleton.edges.size());
    MESOHEX_CHECK(static_cast<int>(an.vertex_class.size()) == nv, "analysis does not match the skeleton");
    check_surface_support(an);
    ConnectionSurfaces cs = allocate_surfaces(an, nv, ne, find_compatible_blocks(skeleton, an, options.blocks));
    cs.fan_blocks = find_fan_blocks(skeleton, an, options.blocks, kFanCapKeepCos);
    // Reuse needs the same CSR layout (same topology and vertex classes); else everything is recomputed.
    const bool reuse = previous != nullptr && static_cast<int>(recompute.size()) == nv &&
                       previous->point_begin == cs.point_begin && previous->quad_begin == cs.quad_begin &&
                       previous->edge_begin == cs.edge_begin && static_cast<int>(previous->edge_quad.size()) == ne;

    // Sum of the normals of the faces around each vertex (for BL-joint frames); serial, in face order.
    std::vector<Vec3> vertex_normal_sum(an.counts.bl_joints > 0 ? nv : 0);
    if (an.counts.bl_joints > 0)
        for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
            for (int w : an.face_vertices[f]) vertex_normal_sum[w] += an.face_normal[f];
    const LeafletSides sides = find_leaflet_sides(skeleton, an, cs);
    const LeafletVertexFrames leaf = leaflet_vertex_frames(skeleton, an);
    const ModelInputs model{skeleton, an, sides, leaf};
    const SurfaceInputs in{skeleton, an, options, model, vertex_normal_sum};

    // Memo keys (the branch directions of each memo-able vertex) and which vertices the memo served.
    const SurfaceMemo* memo = memo_in && memo_out && memo_options_match(*memo_in, options) ? memo_in : nullptr;
    std::vector<std::vector<Vec3>> keys(memo_out ? nv : 0);
    std::vector<char> served(memo_out ? nv : 0, 0);
    std::vector<char> at_bridge(nv, 0);  // computed in the second pass (chosen_at_bridge)

    // Each task writes only its vertex's ranges and the (edge, side) slots of its own incident edges. Ranges of 16
    // vertices at least: a vertex costs from nothing (a joint) to ~10 M instructions (a degree-5 point); with ranges
    // of 256 one of 2 threads did 62 % of this loop on the 5 120-vertex random tree, with 16 it does 51 %
    // (docs/performance.md, "Eleventh pass").
    tbb::parallel_for(tbb::blocked_range<int>(0, nv, 16), [&](const tbb::blocked_range<int>& range) {
        std::vector<Vec3> dirs;
        std::vector<int> inc;
        for (int v = range.begin(); v != range.end(); ++v) {
            const VertexClass c = an.vertex_class[v];
            if (c != VertexClass::Extremity && c != VertexClass::Joint && c != VertexClass::BranchingPoint &&
                c != VertexClass::BLJoint && !roots_branch(an, v))
                continue;
            const bool keyed = memo_out && memoable(an, sides, cs, v) && !reads_neighbours(skeleton, an, options, v);
            if (keyed) {
                branch_edges(an, v, inc);
                branch_directions(skeleton, v, inc, keys[v]);
            }
            const bool bridge = c == VertexClass::BranchingPoint && chosen_at_bridge(skeleton, an, options, v);
            if (reuse && !(bridge ? recompute_near(skeleton, an, recompute, v) : recompute[v])) {
                // copy the vertex's previous surface (its inputs did not change)
                copy_previous_surface(in, *previous, v, cs);
            } else if (cs.vertex_block[v] >= 0) {
                set_block_surface(skeleton, an, cs.blocks[cs.vertex_block[v]], cs);
            } else if (bridge) {
                at_bridge[v] = 1;
            } else if (keyed) {
                const SurfaceMemo::Entry* hit = memo ? find_memo_entry(*memo, keys[v], memo_hash(keys[v])) : nullptr;
                if (hit) {
                    store_memo_entry(skeleton, *hit, v, inc, cs);
                    served[v] = 1;
                } else {  // the key itself is the partition's input (build_branching_surface without leaflet sides)
                    dirs = keys[v];
                    const SpherePartition part =
                        partition_branching_point(in, v, dirs, static_cast<int>(inc.size()), cs);
                    store_partition(skeleton, v, part, static_cast<int>(inc.size()), inc, cs);
                    served[v] = 2;
                }
            } else {
                build_vertex_surface(in, v, dirs, inc, cs);
            }
        }
    });
    build_bridge_surfaces(in, at_bridge, cs);
    build_fan_cap_surfaces(skeleton, an, cs);
    finish_leaflet_junctions(an, sides, cs);
    if (memo_out) {
        *memo_out = collect_memo(cs, keys, options);
        memo_out->hits = static_cast<int>(std::count(served.begin(), served.end(), 1));
        memo_out->misses = static_cast<int>(std::count(served.begin(), served.end(), 2));
    }
    return cs;
}

namespace detail {

double quad_margin_to_floor(const std::array<Vec3, 4>& q, const Vec3& d, double floor) {
    return mesohex::quad_margin_to_floor(q, d, floor);
}

double quad_margin_above(const std::array<Vec3, 4>& q, const Vec3& d, double floor) {
    QuadMarginAbove above;
    return above(q, d, floor);
}

}  // namespace detail

}  // namespace mesohex
