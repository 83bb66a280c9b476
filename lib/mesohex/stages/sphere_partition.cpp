// Quad partition of the unit sphere, one quad per direction (paper step 3 at a branching point).
//
// Candidates, each checked by verify_sphere_partition; the one with the best quality_score is returned:
//   1. planar directions (within options.planarity_tolerance of a great circle) and n = 2: the "orange" around the
//      best-fit plane normal (lunes between two poles; equator vertices on the bisectors of consecutive directions),
//      returned at once unless its lunes are slivers (a tight cluster is "planar" too);
//   2. the VKB21 construction made robust: convex hull of the directions as a polygon map (coplanar corners give one
//      polygon; a hull that does not contain the centre gets one "complement" face), a bounded branch-and-bound
//      choosing edge removals / doublings (digons) / diagonals so that every direction has degree 4, the dual
//      (a face of the 4-regular map = a partition vertex at its vector-area direction, i.e. the Voronoi vertex for a
//      hull triangle), then a relaxation of the partition vertices maximising a smooth minimum of the quality
//      measures without ever leaving the valid set;
//   3. oranges around the best axes of a fixed candidate set (grid, pair normals, circle centres), refined by local
//      search: valid whenever the directions have distinct azimuths about the axis, so this is the fallback.
// Ties go to the earlier candidate in this order. The oranges are computed before the hull path, whose candidates
// are not relaxed when their topology caps their score below the best orange (quality_cap): same result, less work.
// Every loop is bounded (search nodes, sweeps, iterations); no randomness; no unordered containers.
#include "mesohex/stages/sphere_partition.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/stages/orange_three.h"

namespace mesohex {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMinSeparation = 1e-7;         // rad; closer directions are rejected as duplicates
constexpr double kUnitTolerance = 1e-9;         // | |p| - 1 | allowed for partition points
constexpr double kAngleTolerance = 1e-8;        // rad; slack on "angle <= 180°" and "angle > 0"
constexpr double kSumTolerance = 1e-6;          // rad / sr; slack on vertex angle sums and the total area
constexpr double kMinMargin = 1e-10;            // sin of the angular distance of a direction to its quad boundary
constexpr double kGoodOrange = 15 * kPi / 180;  // a planar set's orange is used at once when its quality_score >= this
constexpr std::size_t kScreenMaxQuads = 500;    // quads around a vertex up to which the relaxation screens its terms

double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// Per direction, the largest possible distance to its quad's boundary: half the angle to the nearest other direction.
std::vector<double> margin_bounds(const std::vector<Vec3>& directions) {
    const int n = static_cast<int>(directions.size());
    std::vector<double> bound(n, kPi / 2);
    // Each pair once: angle_between(a, b) and angle_between(b, a) are the same bits (cross(b, a) = -cross(a, b)
    // component by component, the dot product is commutative term by term), and min() does not depend on the order.
    // This needs cross's products rounded before the subtraction: a build that contracts them into fused
    // multiply-adds (GCC with -march=haswell; aarch64 compilers by default) breaks the symmetry in the last bit for
    // about 8 % of random pairs (Vec3.CrossIsAntisymmetricBitForBit checks it).
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            const double half = 0.5 * angle_between(directions[i], directions[j]);
            bound[i] = std::min(bound[i], half);
            bound[j] = std::min(bound[j], half);
        }
    for (double& b : bound) b = std::max(b, 1e-12);
    return bound;
}

// Larger is better; only meaningful for verified partitions. An angle's quality is its distance to 0 or 180°; a
// margin ratio of 1 (the direction as far from its quad's edges as its nearest neighbour allows) counts as 90°.
double quality_score(const SpherePartition& p, const std::vector<Vec3>& d) {
    const SpherePartitionStats s = sphere_partition_stats(p, d);
    return std::min({s.min_angle, kPi - s.max_angle, kPi / 2 * s.min_margin_ratio});
}

// Interior angle at b of a spherical polygon ... a, b, c ... listed counter-clockwise seen from outside; in [0, 2π).
// Returns -1 when an adjacent vertex coincides with b or is antipodal to it (no tangent direction).
double corner_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 to_prev = a - dot(a, b) * b;
    const Vec3 to_next = c - dot(c, b) * b;
    if (norm(to_prev) < 1e-12 || norm(to_next) < 1e-12) return -1;
    double angle = std::atan2(dot(b, cross(to_next, to_prev)), dot(to_next, to_prev));
    if (angle < 0) angle += 2 * kPi;
    return angle;
}

// cos and sin of the 8 pattern-search directions phi = k x 45° (tables computed once with std::cos / std::sin).
const std::array<double, 8>& trial_cos() {
    static const std::array<double, 8> table = [] {
        std::array<double, 8> t;
        for (int k = 0; k < 8; ++k) t[k] = std::cos(kPi * k / 4);
        return t;
    }();
    return table;
}
const std::array<double, 8>& trial_sin() {
    static const std::array<double, 8> table = [] {
        std::array<double, 8> t;
        for (int k = 0; k < 8; ++k) t[k] = std::sin(kPi * k / 4);
        return t;
    }();
    return table;
}

// Eigenvector of the smallest eigenvalue of the symmetric 3x3 matrix m (cyclic Jacobi, bounded sweeps).
Vec3 smallest_eigenvector(double m[3][3]) {
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
        if (off < 1e-30) break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                if (std::abs(m[p][q]) < 1e-300) continue;
                const double theta = (m[q][q] - m[p][p]) / (2 * m[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; ++k) {  // m <- m J (columns p, q)
                    const double mkp = m[k][p], mkq = m[k][q];
                    m[k][p] = c * mkp - s * mkq;
                    m[k][q] = s * mkp + c * mkq;
                }
                for (int k = 0; k < 3; ++k) {  // m <- J^T m (rows p, q)
                    const double mpk = m[p][k], mqk = m[q][k];
                    m[p][k] = c * mpk - s * mqk;
                    m[q][k] = s * mpk + c * mqk;
                }
                for (int k = 0; k < 3; ++k) {  // v <- v J
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    int best = 0;
    for (int k = 1; k < 3; ++k)
        if (m[k][k] < m[best][best]) best = k;
    return normalized(Vec3{v[0][best], v[1][best], v[2][best]});
}

// Normal of the great circle that best fits the directions (least-squares, through the centre).
Vec3 best_fit_plane_normal(const std::vector<Vec3>& d) {
    double m[3][3] = {};
    for (const Vec3& p : d)
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] += p[r] * p[c];
    return smallest_eigenvector(m);
}

// ---------------------------------------------------------------------------------------------------------------
// Orange: lunes between the poles +axis and -axis, one per direction, split at the bisectors of consecutive azimuths.

struct OrangeFrame {
    Vec3 axis, u, w;                // right-handed: u x w = axis
    std::vector<double> azimuth;    // per direction, in (-π, π]
    std::vector<double> elevation;  // per direction, asin(d . axis)
    std::vector<int> order;         // directions sorted by azimuth
};

OrangeFrame orange_frame(const std::vector<Vec3>& d, const Vec3& axis) {
    OrangeFrame f;
    f.axis = axis;
    f.u = any_perpendicular(axis);
    f.w = cross(axis, f.u);
    const int n = static_cast<int>(d.size());
    f.azimuth.resize(n);
    f.elevation.resize(n);
    for (int i = 0; i < n; ++i) {
        f.azimuth[i] = std::atan2(dot(d[i], f.w), dot(d[i], f.u));
        f.elevation[i] = std::asin(std::clamp(dot(d[i], axis), -1.0, 1.0));
    }
    f.order.resize(n);
    std::iota(f.order.begin(), f.order.end(), 0);
    std::sort(f.order.begin(), f.order.end(),
              [&](int a, int b) { return f.azimuth[a] != f.azimuth[b] ? f.azimuth[a] < f.azimuth[b] : a < b; });
    return f;
}

// Gap (CCW azimuth difference) from sorted position k to k + 1, in (0, 2π]; one direction alone gets 2π.
double orange_gap(const OrangeFrame& f, int k) {
    const int n = static_cast<int>(f.order.size());
    double gap = f.azimuth[f.order[(k + 1) % n]] - f.azimuth[f.order[k]];
    if (k + 1 >= n) gap += 2 * kPi;
    return gap;
}

// Smallest sin of the angular distance of a direction to its lune's boundary (<= 0: orange impossible on this axis).
double orange_margin(const OrangeFrame& f) {
    const int n = static_cast<int>(f.order.size());
    double margin = 1;
    for (int k = 0; k < n; ++k) {
        const int i = f.order[k];
        const double half_before = 0.5 * orange_gap(f, (k + n - 1) % n);
        const double half_after = 0.5 * orange_gap(f, k);
        const double side = std::sin(std::min({half_before, half_after, kPi / 2}));
        margin = std::min(margin, std::cos(f.elevation[i]) * side);
    }
    return margin;
}

// quality_score of the orange around an axis (n >= 3), computed directly: lune width w at both poles, margin ratio.
// Evaluated on hundreds of axes per partition, so without allocating (the arrays are reused), and the elevations
// (asin) and margins only while the quality can still exceed a threshold (callers only ask "is it above t?" or "which
// are the top three"). The exact value, when returned, is the same for any threshold: min() does not depend on the
// order of its arguments. Before the exact evaluation, certainly_at_most rejects most axes without libm calls.
struct OrangeEvaluator {
    const std::vector<Vec3>& d;
    const std::vector<double>& bound;
    std::vector<double> azimuth;
    std::vector<int> order;
    std::vector<double> gap;  // gap[k] = orange_gap(frame, k)
    // certainly_at_most's scratch: unit projections, and its thresholds for `thresholds_for` (NaN: none yet).
    std::vector<double> px, py, half_sin2;  // half_sin2[k] = sin(min(gap_k / 2, pi / 2))^2
    double thresholds_for = std::numeric_limits<double>::quiet_NaN();
    double cos_two_t = 0;
    std::vector<double> side2_threshold;  // per direction: (sin(2 t bound / pi) - slack)^2, 2 = any side passes
    std::array<double, 3> pair_dot{};     // three directions: d_a . d_b for b = a + 1 (mod 3)

    OrangeEvaluator(const std::vector<Vec3>& dirs, const std::vector<double>& bounds)
        : d(dirs),
          bound(bounds),
          azimuth(dirs.size()),
          order(dirs.size()),
          gap(dirs.size()),
          px(dirs.size()),
          py(dirs.size()),
          half_sin2(dirs.size()),
          side2_threshold(dirs.size()) {
        if (d.size() == 3)
            for (int a = 0; a < 3; ++a) pair_dot[a] = dot(d[a], d[a == 2 ? 0 : a + 1]);
    }

    // Returns the exact quality and sets `valid` (orange_margin > 0) when the quality is > threshold; otherwise some
    // value <= threshold (valid unset).
    double quality(const Vec3& axis, double threshold, bool& valid) {
        if (three_certainly_at_most(axis, threshold)) return threshold;
        const Vec3 u = any_perpendicular(axis);
        return quality(axis, u, cross(axis, u), threshold, valid);
    }
    // Same with the frame (u = any_perpendicular(axis), w = axis x u) given.
    double quality(const Vec3& axis, const Vec3& u, const Vec3& w, double threshold, bool& valid) {
        if (certainly_at_most(axis, u, w, threshold)) return threshold;
        const int n = static_cast<int>(d.size());
        for (int i = 0; i < n; ++i) azimuth[i] = std::atan2(dot(d[i], w), dot(d[i], u));
        // The same order as orange_frame's std::sort: (azimuth, index) is a strict total order.
        for (int i = 0; i < n; ++i) {
            int k = i;
            while (k > 0 &&
                   (azimuth[order[k - 1]] > azimuth[i] || (azimuth[order[k - 1]] == azimuth[i] && order[k - 1] > i))) {
                order[k] = order[k - 1];
                --k;
            }
            order[k] = i;
        }
        for (int k = 0; k < n; ++k) {
            double g = azimuth[order[k + 1 < n ? k + 1 : 0]] - azimuth[order[k]];
            if (k + 1 >= n) g += 2 * kPi;
            gap[k] = g;
        }
        double q = kPi;
        for (int k = 0; k < n; ++k) {
            const double width = 0.5 * (gap[k > 0 ? k - 1 : n - 1] + gap[k]);
            q = std::min({q, width, kPi - width});
        }
        if (q <= threshold) return q;
        valid = true;
        for (int k = 0; k < n; ++k) {
            const int i = order[k];
            const double before = gap[k > 0 ? k - 1 : n - 1], after = gap[k];
            const double elevation = std::asin(std::clamp(dot(d[i], axis), -1.0, 1.0));
            const double side = std::cos(elevation) * std::sin(std::min({0.5 * before, 0.5 * after, kPi / 2}));
            if (!(side > 0)) valid = false;
            const double margin = std::asin(std::clamp(side, -1.0, 1.0));
            q = std::min(q, kPi / 2 * margin / bound[i]);
            if (q <= threshold) return q;
        }
        return q;
    }

    // True only when the exact quality above is <= threshold, decided without libm calls: most trial axes of the scan
    // and of the refinement are rejected here (issue 19). Works on the directions' projections p_i = (d_i . u,
    // d_i . w) (the very doubles the exact evaluation gives atan2), sorted by angle with the half-plane and cross
    // product tests, and compares cosines and squared sines with thresholds computed once per `threshold`, each test
    // widened by 1e-12 against the roundings of both evaluations (theirs and the exact one's are below 1e-14):
    //   - a lune width w (half the angle theta from the previous direction to the next) is <= t or >= pi - t iff
    //     cos theta >= cos 2t (for 0 < t < pi/2);
    //   - a margin term pi/2 asin(side) / bound_i is <= t iff side <= sin(2 t bound_i / pi) (asin increases; when the
    //     argument is >= pi/2 the term is always <= t), with side = cos(elevation) sin(min(g_before / 2, g_after / 2,
    //     pi/2)), sin(g / 2)^2 = (1 - cos g) / 2 for a gap g <= pi (cross product >= 0), 1 above, and
    //     cos(elevation)^2 = 1 - (d_i . axis)^2.
    // False means "cannot tell" and the exact evaluation runs: thresholds outside (1e-6, pi/2 - 1e-6), a direction
    // (nearly) on the axis or on the azimuth cut py = 0 (where atan2's sign of zero decides the order), or two
    // consecutive directions less than ~1e-9 rad apart in azimuth (their exact order might differ from ours).
    bool certainly_at_most(const Vec3& axis, const Vec3& u, const Vec3& w, double threshold) {
        constexpr double kSlack = 1e-12;
        const int n = static_cast<int>(d.size());
        if (n < 3 || !(threshold > 1e-6 && threshold < kPi / 2 - 1e-6)) return false;
        set_threshold(threshold);
        if (three_certainly_at_most(axis, threshold)) return true;
        for (int i = 0; i < n; ++i) {
            const double x = dot(d[i], u), y = dot(d[i], w);
            const double r2 = x * x + y * y;
            if (!(r2 > 1e-12) || y == 0) return false;
            const double inv = 1 / std::sqrt(r2);
            px[i] = x * inv;
            py[i] = y * inv;
        }
        // Three directions: the lune of each lies between the other two whatever the order (the width of one is half
        // the angle between the other two, or pi minus it), so the width test needs no sort. It runs before the
        // nearly-equal-azimuths bail-out below: it reads only pairwise dot products, which that ordering ambiguity
        // does not touch, and kSlack covers their rounding, so a rejection here is as certain as the sorted test's.
        if (n == 3)
            for (int a = 0; a < 3; ++a) {
                const int b = a == 2 ? 0 : a + 1;
                if (px[a] * px[b] + py[a] * py[b] >= cos_two_t + kSlack) return true;
            }
        // Angle order in (-pi, pi] as atan2 gives it: lower half-plane (y < 0) first, then by cross product.
        const auto before = [&](int a, int b) {
            const bool lower_a = py[a] < 0, lower_b = py[b] < 0;
            if (lower_a != lower_b) return lower_a;
            return px[a] * py[b] - py[a] * px[b] > 0;
        };
        for (int i = 0; i < n; ++i) {
            int k = i;
            while (k > 0 && before(i, order[k - 1])) {
                order[k] = order[k - 1];
                --k;
            }
            order[k] = i;
        }
        // Per sorted position k, the gap to k + 1: its cosine and sin(min(gap / 2, pi / 2))^2.
        for (int k = 0; k < n; ++k) {
            const int a = order[k], b = order[k + 1 < n ? k + 1 : 0];
            const double c = px[a] * px[b] + py[a] * py[b], s = px[a] * py[b] - py[a] * px[b];
            if (c > 0 && s < 1e-9) return false;  // nearly equal azimuths (or a wrong order): cannot tell
            half_sin2[k] = s >= 0 ? 0.5 * (1 - c) : 1.0;
        }
        for (int k = 0; k < n; ++k) {
            const int prev = order[k > 0 ? k - 1 : n - 1], next = order[k + 1 < n ? k + 1 : 0];
            if (px[prev] * px[next] + py[prev] * py[next] >= cos_two_t + kSlack) return true;
        }
        for (int k = 0; k < n; ++k) {
            const int i = order[k];
            if (side2_threshold[i] > 1) continue;
            const double x = std::clamp(dot(d[i], axis), -1.0, 1.0);
            const double side2 = (1 - x) * (1 + x) * std::min(half_sin2[k > 0 ? k - 1 : n - 1], half_sin2[k]);
            if (side2 + kSlack <= side2_threshold[i]) return true;
        }
        return false;
    }

    // The constants of certainly_at_most's tests for `threshold`, computed once per threshold.
    void set_threshold(double threshold) {
        if (threshold == thresholds_for) return;
        thresholds_for = threshold;
        cos_two_t = std::cos(2 * threshold);
        for (int i = 0; i < static_cast<int>(d.size()); ++i) {
            const double arg = 2 * threshold * (1 - 1e-12) * bound[i] / kPi;
            const double side = arg >= kPi / 2 ? 2.0 : std::sin(arg) - 1e-15 - 1e-13;  // 2: every side passes
            side2_threshold[i] = side > 0 ? side * side : -1.0;                        // -1: no side passes
        }
    }

    // certainly_at_most's width test for three directions without the axis's frame: the cosine of the angle between
    // the projections of d_a and d_b on the plane normal to the axis is (d_a . d_b - z_a z_b) / sqrt((1 - z_a^2)
    // (1 - z_b^2)) with z = d . axis. Only for directions at least ~0.6 degrees off the axis (1 - z^2 > 1e-4), where
    // the roundings of this form stay below 1e-10, and with a slack of 1e-8 on the cosine: a rejection here is as
    // certain as the frame's test (the lune of each direction lies between the other two whatever the order).
    bool three_certainly_at_most(const Vec3& axis, double threshold) {
        if (d.size() != 3 || !(threshold > 1e-6 && threshold < kPi / 2 - 1e-6)) return false;
        set_threshold(threshold);
        const double limit = cos_two_t + 1e-8;
        if (!(limit < 1)) return false;
        std::array<double, 3> z, s;
        for (int i = 0; i < 3; ++i) {
            z[i] = dot(d[i], axis);
            s[i] = 1 - z[i] * z[i];
            if (!(s[i] > 1e-4)) return false;
        }
        for (int a = 0; a < 3; ++a) {
            const int b = a == 2 ? 0 : a + 1;
            if (pair_dot[a] - z[a] * z[b] >= limit * std::sqrt(s[a] * s[b])) return true;
        }
        return false;
    }
};

// Local search on the axis (8 tangent directions, halving steps, bounded) maximising orange_quality.
Vec3 refine_orange_axis(OrangeEvaluator& eval, Vec3 axis) {
    bool valid = false;
    double best = eval.quality(axis, -1e300, valid);
    double step = 0.05;
    for (int iteration = 0; iteration < 100 && step > 1e-4; ++iteration) {
        const Vec3 t1 = any_perpendicular(axis), t2 = cross(axis, t1);
        Vec3 best_axis = axis;
        for (int k = 0; k < 8; ++k) {
            const Vec3 trial = normalized(axis + step * (trial_cos()[k] * t1 + trial_sin()[k] * t2));
            const double q = eval.quality(trial, best + 1e-12, valid);
            if (q > best + 1e-12) {
                best = q;
                best_axis = trial;
            }
        }
        if (best_axis == axis) step *= 0.5;
        axis = best_axis;
    }
    return axis;
}

SpherePartition build_orange(const OrangeFrame& f) {
    const int n = static_cast<int>(f.order.size());
    SpherePartition p;
    p.points.push_back(f.axis);    // 0: north pole
    p.points.push_back(-f.axis);   // 1: south pole
    for (int k = 0; k < n; ++k) {  // 2 + k: equator vertex between sorted directions k and k + 1
        const double phi = f.azimuth[f.order[k]] + 0.5 * orange_gap(f, k);
        p.points.push_back(normalized(std::cos(phi) * f.u + std::sin(phi) * f.w));
    }
    p.quads.resize(n);
    for (int k = 0; k < n; ++k) {
        const int east = 2 + k, west = 2 + (k + n - 1) % n;
        p.quads[f.order[k]] = {east, 0, west, 1};  // east, north, west, south: CCW seen from outside
    }
    return p;
}

// An axis to try with its orange frame (u = any_perpendicular(axis), w = axis x u).
struct ScanAxis {
    Vec3 axis, u, w;
};

ScanAxis scan_axis(const Vec3& axis) {
    const Vec3 u = any_perpendicular(axis);
    return {axis, u, cross(axis, u)};
}

// `count` roughly uniform axes (Fibonacci points on the upper hemisphere; -axis is the same orange) with their frames.
std::vector<ScanAxis> make_fibonacci_axes(int count) {
    std::vector<ScanAxis> axes;
    const double golden = kPi * (3 - std::sqrt(5.0));
    for (int k = 0; k < count; ++k) {
        const double z = 1 - (k + 0.5) / count;
        const double r = std::sqrt(std::max(0.0, 1 - z * z));
        axes.push_back(scan_axis(Vec3{r * std::cos(golden * k), r * std::sin(golden * k), z}));
    }
    return axes;
}

// The scan's 400 Fibonacci axes: the same for every partition, so computed once (an immutable table; thread-safe
// initialisation).
const std::vector<ScanAxis>& fibonacci_axes() {
    static const std::vector<ScanAxis> table = make_fibonacci_axes(400);
    return table;
}

// The coarse scan of three directions (SpherePartitionOptions::coarse_three_scan): 60 Fibonacci axes, about 0.3 rad
// apart (the hemisphere's 2 pi sr / 60 is a cell of 0.32 rad), once.
const std::vector<ScanAxis>& coarse_fibonacci_axes() {
    static const std::vector<ScanAxis> table = make_fibonacci_axes(60);
    return table;
}

// Deterministic axis candidates besides the Fibonacci axes: the best-fit plane normal (candidate 0), then, after the
// Fibonacci axes, pair normals, circle centres and the mean. Candidate a of the scan is extra[0] for a = 0, Fibonacci
// axis a - 1 for a <= 400, else extra[a - 400] (the table is not copied per partition).
std::vector<ScanAxis> extra_candidate_axes(const std::vector<Vec3>& d) {
    std::vector<ScanAxis> axes;
    axes.push_back(scan_axis(best_fit_plane_normal(d)));
    const int n = static_cast<int>(d.size());
    for (int i = 0; i < n && i < 40; ++i)
        for (int j = i + 1; j < n && j < 40; ++j) {
            const Vec3 c = cross(d[i], d[j]);
            if (norm(c) > 1e-6) axes.push_back(scan_axis(normalized(c)));
            // Centres of circles through three directions (hull face normals: for a cluster, the axis through it).
            for (int k = j + 1; k < n && k < 16; ++k) {
                const Vec3 t = cross(d[j] - d[i], d[k] - d[i]);
                if (norm(t) > 1e-12) axes.push_back(scan_axis(normalized(t)));
            }
        }
    Vec3 mean{};
    for (const Vec3& v : d) mean += v;
    if (norm(mean) > 1e-9) axes.push_back(scan_axis(normalized(mean)));
    return axes;
}

// The `keep` (at most 8) best candidate axes by (quality, index), best first, as a sort of every valid axis would rank
// them (fewer when fewer are valid); the candidates are the extra axes and the Fibonacci table `fib`.
std::vector<Vec3> best_scan_axes(const std::vector<Vec3>& d, OrangeEvaluator& eval,
                                 const std::vector<ScanAxis>& fib = fibonacci_axes(), int keep = 3) {
    const std::vector<ScanAxis> extra = extra_candidate_axes(d);
    const int nf = static_cast<int>(fib.size());
    const auto axis_at = [&](int a) -> const ScanAxis& {
        return a == 0 ? extra[0] : a <= nf ? fib[a - 1] : extra[a - nf];
    };
    std::array<std::pair<double, int>, 8> top;  // (-quality, axis), ascending
    keep = std::clamp(keep, 1, 8);
    int top_count = 0;
    const int count = nf + static_cast<int>(extra.size());
    for (int a = 0; a < count; ++a) {
        const ScanAxis& axis = axis_at(a);
        const double threshold = top_count == keep ? -top[keep - 1].first : -1e300;
        bool valid = false;
        const double q = eval.quality(axis.axis, axis.u, axis.w, threshold, valid);
        if (!(q > threshold) || !valid) continue;
        int k = top_count < keep ? top_count++ : keep - 1;
        top[k] = {-q, a};
        for (; k > 0 && top[k] < top[k - 1]; --k) std::swap(top[k], top[k - 1]);
    }
    std::vector<Vec3> best;
    for (int r = 0; r < top_count; ++r) best.push_back(axis_at(top[r].second).axis);
    return best;
}

// The coarse scan's solver starts: of the ranked axes, each one more than 0.5 rad (as lines: an axis and its negative
// are one orange) from every better-ranked start, at most 3. Axes closer than that lie in one cell or neighbouring
// cells of the 60-axis scan, where the solver climbs to the same maximum; distinct starts reach more maxima.
std::vector<Vec3> distinct_starts(const std::vector<Vec3>& ranked) {
    const double cos_min = std::cos(0.5);
    std::vector<Vec3> starts;
    for (const Vec3& a : ranked) {
        bool near = false;
        for (const Vec3& s : starts) near = near || std::abs(dot(a, s)) > cos_min;
        if (!near) starts.push_back(a);
        if (starts.size() == 3) break;
    }
    return starts;
}

// The margin weight of the three-direction orange's axis (orange_three.h): a margin ratio of 1 counts as 60 degrees,
// the most a width term can be for three directions, instead of quality_score's 90 degrees (with which the maximum
// trades margins for width: docs/performance.md, "Seventh pass").
constexpr double kThreeMarginWeight = kPi / 3;

// The three-direction solver's axis (orange_three.h) from the best scan axes; its score <= 0 when no start is valid.
// With `coarse` (SpherePartitionOptions::coarse_three_scan) the starts are distinct_starts of the coarse scan's 8 best.
// With `tabled` (SpherePartitionOptions::tabled_three_start) the starts come from the table, the scan only when none
// gives a valid orange.
OrangeAxisThree exact_three_axis(const std::vector<Vec3>& d, const std::vector<double>& bound, OrangeEvaluator& eval,
                                 bool coarse, bool tabled = false) {
    if (tabled) {
        const std::array<Vec3, 3> t = {d[0], d[1], d[2]};
        const std::array<double, 3> b = {bound[0], bound[1], bound[2]};
        const OrangeAxisThree best =
            best_orange_axis_three(t, b, kThreeMarginWeight, tabled_orange_starts_three(t, b, kThreeMarginWeight));
        if (best.score > 0) return best;
    }
    return best_orange_axis_three(
        {d[0], d[1], d[2]}, {bound[0], bound[1], bound[2]}, kThreeMarginWeight,
        coarse ? distinct_starts(best_scan_axes(d, eval, coarse_fibonacci_axes(), 8)) : best_scan_axes(d, eval));
}

// Oranges around the best axes: for three directions with exact_three, the one around the solver's axis (its starts
// from the coarse scan with coarse_three); else around the three best candidate axes, each refined by local search.
std::vector<SpherePartition> axis_oranges(const std::vector<Vec3>& d, bool exact_three, bool coarse_three,
                                          bool tabled_three) {
    const std::vector<double> bound = margin_bounds(d);
    OrangeEvaluator eval(d, bound);
    std::vector<SpherePartition> oranges;
    if (exact_three && d.size() == 3) {
        const OrangeAxisThree best = exact_three_axis(d, bound, eval, coarse_three, tabled_three);
        if (best.score > 0) {
            const OrangeFrame frame = orange_frame(d, best.axis);
            if (orange_margin(frame) > 0) oranges.push_back(build_orange(frame));
        }
        return oranges;
    }
    for (const Vec3& start : best_scan_axes(d, eval)) {
        const OrangeFrame frame = orange_frame(d, refine_orange_axis(eval, start));
        if (orange_margin(frame) > 0) oranges.push_back(build_orange(frame));
    }
    return oranges;
}

// ---------------------------------------------------------------------------------------------------------------
// Convex hull of the directions as a polygon map on the sphere ("base map").
//
// Brute force over triples (O(n^4), n is a junction degree): a triple spans a hull face when no other direction is
// more than `eps` in front of its plane; the face is every direction within `eps` of the plane, ordered around the
// normal (directions on one plane lie on one circle, so all of them are polygon corners). Faces whose plane passes
// behind the centre (offset < -kNearOffset: all directions lie in an open hemisphere and the centre is outside the
// hull) do not project to the sphere one-to-one; together they stand for the empty rest of the sphere and are merged
// into one "complement" face bounded by the spherical hull of the directions.

constexpr double kNearOffset = 1e-9;

struct BaseMap {
    std::vector<std::vector<int>> faces;  // vertex cycles, counter-clockwise seen from outside
    // Per face: >= 4 corners, so diagonals may split it. The map is only combinatorial (partition geometry comes from
    // the face centres and the relaxation), so a diagonal of the complement face need not be a short arc.
    std::vector<char> allow_diagonals;
};

// True if the faces (vertex cycles) form a closed, oriented 2-manifold map of the sphere on vertices 0..nv-1: every
// directed edge once with its reverse, no repeated vertex in a face, every vertex used with one cycle of faces
// around it, V - E + F = 2.
bool is_sphere_map(const std::vector<std::vector<int>>& faces, int nv) {
    std::map<std::pair<int, int>, int> directed;
    int half_edges = 0;
    std::vector<int> out_degree(nv, 0);
    for (const std::vector<int>& f : faces) {
        if (f.size() < 2) return false;
        for (std::size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            if (a == b || !directed.insert({{a, b}, 1}).second) return false;
            ++out_degree[a];
            ++half_edges;
        }
        std::vector<int> sorted = f;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
    }
    for (const auto& [edge, count] : directed)
        if (!directed.count({edge.second, edge.first})) return false;
    for (int v = 0; v < nv; ++v)
        if (out_degree[v] == 0) return false;
    const int ne = half_edges / 2, nf = static_cast<int>(faces.size());
    if (nv - ne + nf != 2) return false;
    // Vertex links are single cycles: walk succ(v->w) = v->pred_F(v) where F holds v->w.
    std::map<std::pair<int, int>, int> pred;  // directed edge v->w -> predecessor of v in its face
    for (const std::vector<int>& f : faces)
        for (std::size_t k = 0; k < f.size(); ++k)
            pred[{f[k], f[(k + 1) % f.size()]}] = f[(k + f.size() - 1) % f.size()];
    for (int v = 0; v < nv; ++v) {
        const auto first = directed.lower_bound({v, -1});
        const int w0 = first->first.second;
        int w = w0, steps = 0;
        do {
            w = pred.at({v, w});
            ++steps;
        } while (w != w0 && steps <= out_degree[v]);
        if (steps != out_degree[v]) return false;
    }
    return true;
}

std::optional<BaseMap> hull_base_map(const std::vector<Vec3>& d, double eps) {
    const int n = static_cast<int>(d.size());
    struct Face {
        std::vector<int> members;  // sorted
        Vec3 normal;
        double offset;
    };
    std::vector<Face> found;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            for (int k = j + 1; k < n; ++k) {
                const Vec3 c = cross(d[j] - d[i], d[k] - d[i]);
                if (norm(c) < 1e-14) continue;
                const Vec3 nrm = normalized(c);
                const double h = dot(nrm, d[i]);
                bool front = false, back = false;
                std::vector<int> members;
                for (int m = 0; m < n; ++m) {
                    const double s = dot(nrm, d[m]) - h;
                    if (s > eps)
                        front = true;
                    else if (s < -eps)
                        back = true;
                    else
                        members.push_back(m);
                }
                for (int side = 0; side < 2; ++side) {
                    if (side == 0 ? front : back) continue;
                    const Vec3 normal = side == 0 ? nrm : -nrm;
                    bool duplicate = false;
                    for (const Face& f : found)
                        duplicate = duplicate || (f.members == members && dot(f.normal, normal) > 0);
                    if (!duplicate) found.push_back({members, normal, side == 0 ? h : -h});
                }
            }
    // Order each face around its normal; split into proper faces and near faces (centre behind the plane).
    std::vector<std::vector<int>> proper, near;
    std::vector<char> proper_diag;
    for (const Face& f : found) {
        Vec3 centroid{};
        for (int m : f.members) centroid += d[m];
        centroid /= static_cast<double>(f.members.size());
        const Vec3 u = any_perpendicular(f.normal), w = cross(f.normal, u);
        std::vector<std::pair<double, int>> by_angle;
        for (int m : f.members) by_angle.push_back({std::atan2(dot(d[m] - centroid, w), dot(d[m] - centroid, u)), m});
        std::sort(by_angle.begin(), by_angle.end());
        std::vector<int> cycle;
        for (const auto& [angle, m] : by_angle) cycle.push_back(m);
        if (f.offset < -kNearOffset) {
            near.push_back(cycle);
        } else {
            proper.push_back(cycle);
            proper_diag.push_back(cycle.size() >= 4);
        }
    }
    std::vector<std::vector<int>> all = proper;
    all.insert(all.end(), near.begin(), near.end());
    if (!is_sphere_map(all, n)) return std::nullopt;
    BaseMap base{proper, proper_diag};
    if (!near.empty()) {  // merge the near faces: boundary edges are those whose reverse lies in a proper face
        std::set<std::pair<int, int>> in_near;
        for (const std::vector<int>& f : near)
            for (std::size_t k = 0; k < f.size(); ++k) in_near.insert({f[k], f[(k + 1) % f.size()]});
        std::map<int, int> next;  // boundary: a -> b
        for (const auto& [a, b] : in_near)
            if (!in_near.count({b, a}) && !next.insert({a, b}).second) return std::nullopt;
        if (next.empty()) return std::nullopt;
        std::vector<int> cycle = {next.begin()->first};
        while (static_cast<int>(cycle.size()) <= static_cast<int>(next.size())) {
            const auto it = next.find(cycle.back());
            if (it == next.end()) return std::nullopt;
            if (it->second == cycle.front()) break;
            cycle.push_back(it->second);
        }
        if (cycle.size() != next.size()) return std::nullopt;
        base.faces.push_back(cycle);
        base.allow_diagonals.push_back(cycle.size() >= 4);
        // Directions strictly inside the near region would be lost: they must all be on its boundary.
        if (!is_sphere_map(base.faces, n)) return std::nullopt;
    }
    return base;
}

// ---------------------------------------------------------------------------------------------------------------
// Making the map 4-regular. Every base edge gets a multiplicity (0: removed, i.e. its two faces merge; 1: kept; 2:
// doubled, i.e. a digon = a valence-2 partition vertex on the Voronoi edge) and convex faces may get diagonals. A
// bounded branch-and-bound collects the cheapest assignments with every vertex degree exactly 4. Costs: removing an
// edge costs the length of its Voronoi edge (the partition edge that collapses), doubling or a diagonal a small
// constant (no geometric change / a zero-length edge the relaxation opens).

struct Item {
    int a = -1, b = -1;          // endpoints
    int face = -1;               // diagonal: its face; base edge: -1
    int pos_a = -1, pos_b = -1;  // diagonal: corner positions in the face cycle
    double remove_cost = 0;      // base edge: cost of multiplicity 0
    int left = -1, right = -1;   // base edge: the faces left of a->b and of b->a
};

struct Assignment {
    std::vector<int> value;  // per item: base edge multiplicity 0..2, diagonal 0/1
    double cost = 0;
};

constexpr double kDoubleCost = 0.05;
constexpr double kDiagonalCost = 0.05;

Vec3 face_centre(const std::vector<int>& cycle, const std::vector<Vec3>& d) {
    if (cycle.size() == 2) return normalized(d[cycle[0]] + d[cycle[1]]);
    Vec3 area{};
    for (std::size_t k = 0; k < cycle.size(); ++k) area += cross(d[cycle[k]], d[cycle[(k + 1) % cycle.size()]]);
    if (norm(area) > 1e-12) return normalized(area);
    Vec3 sum{};
    for (int v : cycle) sum += d[v];
    return normalized(sum);
}

std::vector<Item> factor_items(const BaseMap& base, const std::vector<Vec3>& d) {
    std::vector<Item> items;
    std::map<std::pair<int, int>, int> left_face;  // directed edge -> face on its left
    for (int f = 0; f < static_cast<int>(base.faces.size()); ++f) {
        const std::vector<int>& c = base.faces[f];
        for (std::size_t k = 0; k < c.size(); ++k) left_face[{c[k], c[(k + 1) % c.size()]}] = f;
    }
    for (const auto& [edge, f] : left_face) {
        if (edge.first > edge.second) continue;
        const int g = left_face.at({edge.second, edge.first});
        Item it;
        it.a = edge.first;
        it.b = edge.second;
        it.left = f;
        it.right = g;
        it.remove_cost = 1e-3 + angle_between(face_centre(base.faces[f], d), face_centre(base.faces[g], d));
        // Merging two faces into a non-convex one makes a poor partition vertex: check the corners at a and b.
        const std::vector<int>& cf = base.faces[f];
        const std::vector<int>& cg = base.faces[g];
        const auto at = [](const std::vector<int>& c, int v, int shift) {
            const int sz = static_cast<int>(c.size());
            const int k = static_cast<int>(std::find(c.begin(), c.end(), v) - c.begin());
            return c[(k + shift + sz) % sz];
        };
        // f holds a->b, g holds b->a; the merged cycle runs b .. pred_f(a) a succ_g(a) .. pred_g(b) b, so its corners
        // are pred_f(a) -> a -> succ_g(a) and pred_g(b) -> b -> succ_f(b).
        const double corner_a = corner_angle(d[at(cf, it.a, -1)], d[it.a], d[at(cg, it.a, 1)]);
        const double corner_b = corner_angle(d[at(cg, it.b, -1)], d[it.b], d[at(cf, it.b, 1)]);
        if (corner_a < 0 || corner_a > kPi - 1e-3 || corner_b < 0 || corner_b > kPi - 1e-3) it.remove_cost += 1;
        items.push_back(it);
    }
    for (int f = 0; f < static_cast<int>(base.faces.size()); ++f) {
        if (!base.allow_diagonals[f]) continue;
        const int k = static_cast<int>(base.faces[f].size());
        for (int i = 0; i < k; ++i)
            for (int j = i + 2; j < k; ++j) {
                if (i == 0 && j == k - 1) continue;
                Item it;
                it.a = base.faces[f][i];
                it.b = base.faces[f][j];
                it.face = f;
                it.pos_a = i;
                it.pos_b = j;
                items.push_back(it);
            }
    }
    return items;
}

// Extra cost of a merged face with about s sides (a partition vertex of valence s): 5 is tolerable, more is not.
double face_size_penalty(int s) {
    if (s <= 4) return 0;
    if (s == 5) return 0.3;
    if (s == 6) return 1.3;
    return 3.3 + 3.0 * (s - 7);
}

// The `max_results` cheapest degree-4 assignments found within `node_budget` search nodes (cheapest first).
// Removing an edge also charges the growth of its two faces (size + removed edges, approximating the merged size).
std::vector<Assignment> cheapest_factors(const std::vector<Item>& items, const BaseMap& base, int nv, int max_results,
                                         long node_budget, int root) {
    const int ni = static_cast<int>(items.size());
    std::vector<int> face_size(base.faces.size());
    for (std::size_t f = 0; f < base.faces.size(); ++f) face_size[f] = static_cast<int>(base.faces[f].size());
    // Visit items so that vertices are completed in breadth-first order over the map (a small frontier of partly
    // assigned vertices keeps the degree pruning effective): item order = (later endpoint rank, earlier rank).
    std::vector<std::vector<int>> adjacent(nv);
    for (const Item& it : items) {
        adjacent[it.a].push_back(it.b);
        adjacent[it.b].push_back(it.a);
    }
    std::vector<int> vertex_rank(nv, -1), queue;
    for (int k = 0; k < nv; ++k) {
        const int start = (root + k) % nv;
        if (vertex_rank[start] >= 0) continue;
        vertex_rank[start] = static_cast<int>(queue.size());
        queue.push_back(start);
        for (std::size_t head = queue.size() - 1; head < queue.size(); ++head) {
            std::vector<int> next = adjacent[queue[head]];
            std::sort(next.begin(), next.end());
            for (int w : next)
                if (vertex_rank[w] < 0) {
                    vertex_rank[w] = static_cast<int>(queue.size());
                    queue.push_back(w);
                }
        }
    }
    std::vector<int> order(ni);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int x, int y) {
        const int kx = std::max(vertex_rank[items[x].a], vertex_rank[items[x].b]);
        const int ky = std::max(vertex_rank[items[y].a], vertex_rank[items[y].b]);
        if (kx != ky) return kx < ky;
        const int lx = std::min(vertex_rank[items[x].a], vertex_rank[items[x].b]);
        const int ly = std::min(vertex_rank[items[y].a], vertex_rank[items[y].b]);
        return lx != ly ? lx < ly : x < y;
    });
    std::vector<int> degree(nv, 0), capacity(nv, 0);  // capacity = most the unassigned items can still add
    for (const Item& it : items) {
        const int most = it.face < 0 ? 2 : 1;
        capacity[it.a] += most;
        capacity[it.b] += most;
    }
    // A direction with two doubled edges would get a lune (its two real corners antipodal): only for a flat hull.
    const int max_doubles = base.faces.size() == 2 ? 2 : 1;
    std::vector<int> doubles(nv, 0);
    std::vector<int> value(ni, 0);
    std::vector<Assignment> best;
    long nodes = 0;
    auto crosses = [&](int item) {
        const Item& x = items[item];
        for (int o = 0; o < ni; ++o) {
            if (o == item || items[o].face != x.face || value[o] == 0) continue;
            const Item& y = items[o];
            const auto inside = [&](int p) { return p > x.pos_a && p < x.pos_b; };
            const bool shares = y.pos_a == x.pos_a || y.pos_a == x.pos_b || y.pos_b == x.pos_a || y.pos_b == x.pos_b;
            if (!shares && inside(y.pos_a) != inside(y.pos_b)) return true;
        }
        return false;
    };
    // Depth-first branch and bound (recursion depth = number of items, a few hundred at most).
    std::function<void(int, double)> search = [&](int depth, double cost) {
        if (++nodes > node_budget) return;
        if (static_cast<int>(best.size()) == max_results && cost >= best.back().cost) return;
        if (depth == ni) {
            for (int v = 0; v < nv; ++v)
                if (degree[v] != 4) return;
            Assignment a{value, cost};
            best.insert(std::upper_bound(best.begin(), best.end(), a,
                                         [](const Assignment& x, const Assignment& y) { return x.cost < y.cost; }),
                        a);
            if (static_cast<int>(best.size()) > max_results) best.pop_back();
            return;
        }
        const int item = order[depth];
        const Item& it = items[item];
        const int most = it.face < 0 ? 2 : 1;
        capacity[it.a] -= most;
        capacity[it.b] -= most;
        // Values cheapest first: edge 1 (free), 2 (double), 0 (remove: Voronoi length); diagonal 0, 1.
        std::array<int, 3> values = {1, 2, 0};
        double growth = 0;
        if (it.face < 0)
            for (int f : {it.left, it.right})
                growth += face_size_penalty(face_size[f] + 1) - face_size_penalty(face_size[f]);
        std::array<double, 3> costs = {0, kDoubleCost, it.remove_cost + growth};
        int count = 3;
        if (it.face >= 0) {
            values = {0, 1, 0};
            costs = {0, kDiagonalCost, 0};
            count = 2;
        } else if (costs[2] < kDoubleCost) {
            std::swap(values[1], values[2]);
            std::swap(costs[1], costs[2]);
        }
        for (int c = 0; c < count; ++c) {
            const int x = values[c];
            degree[it.a] += x;
            degree[it.b] += x;
            value[item] = x;
            if (it.face < 0 && x == 0) {
                ++face_size[it.left];
                ++face_size[it.right];
            }
            if (it.face < 0 && x == 2) {
                ++doubles[it.a];
                ++doubles[it.b];
            }
            const bool feasible = doubles[it.a] <= max_doubles && doubles[it.b] <= max_doubles && degree[it.a] <= 4 &&
                                  degree[it.b] <= 4 && degree[it.a] + capacity[it.a] >= 4 &&
                                  degree[it.b] + capacity[it.b] >= 4 && !(it.face >= 0 && x == 1 && crosses(item));
            if (feasible) search(depth + 1, cost + costs[c]);
            degree[it.a] -= x;
            degree[it.b] -= x;
            value[item] = 0;
            if (it.face < 0 && x == 0) {
                --face_size[it.left];
                --face_size[it.right];
            }
            if (it.face < 0 && x == 2) {
                --doubles[it.a];
                --doubles[it.b];
            }
        }
        capacity[it.a] += most;
        capacity[it.b] += most;
    };
    search(0, 0);
    return best;
}

// ---------------------------------------------------------------------------------------------------------------
// From an assignment to a partition: build the rotation system of the 4-regular map (arcs = kept/doubled base edges
// and diagonals), trace its faces, and take the dual. Dual vertex of a face = its vector-area direction (the
// circumcentre for a hull triangle, i.e. the Voronoi vertex), or the arc midpoint for a digon.

std::optional<SpherePartition> dual_partition(const BaseMap& base, const std::vector<Item>& items,
                                              const Assignment& assignment, const std::vector<Vec3>& d) {
    const int nv = static_cast<int>(d.size());
    std::map<std::pair<int, int>, std::pair<int, int>> left;  // directed base edge -> (face, corner)
    for (int f = 0; f < static_cast<int>(base.faces.size()); ++f) {
        const std::vector<int>& c = base.faces[f];
        for (int k = 0; k < static_cast<int>(c.size()); ++k) left[{c[k], c[(k + 1) % c.size()]}] = {f, k};
    }
    std::map<std::pair<int, int>, int> edge_item;  // undirected base edge (a < b) -> item
    for (int i = 0; i < static_cast<int>(items.size()); ++i)
        if (items[i].face < 0) edge_item[{items[i].a, items[i].b}] = i;
    // Arcs: per base edge item, `value` copies (copy 0 borders the face left of a->b, a < b); per chosen diagonal one.
    std::vector<std::array<int, 2>> arc_ends;
    std::map<std::pair<int, int>, int> first_arc;  // item -> first arc id (key (item, 0))
    for (int i = 0; i < static_cast<int>(items.size()); ++i) {
        first_arc[{i, 0}] = static_cast<int>(arc_ends.size());
        for (int c = 0; c < assignment.value[i]; ++c) arc_ends.push_back({items[i].a, items[i].b});
    }
    // Half-edge h = 2*arc + (0: a->b, 1: b->a).
    std::vector<std::vector<int>> rot(nv);
    for (int v = 0; v < nv; ++v) {
        // Base outgoing edges of v in CCW order: succ(v->w) = v->pred_F(v), F = face left of v->w.
        const auto first = left.lower_bound({v, -1});
        if (first == left.end() || first->first.first != v) return std::nullopt;
        int w = first->first.second;
        const int w0 = w;
        int guard = 0;
        do {
            const auto [f, k] = left.at({v, w});
            const std::vector<int>& cyc = base.faces[f];
            const int sz = static_cast<int>(cyc.size());
            // Copies of v->w: the one bordering the face on the right first, then the one bordering f.
            const int item = edge_item.at(std::minmax(v, w));
            const int arc0 = first_arc.at({item, 0});
            const int copies = assignment.value[item];
            const int half = v == items[item].a ? 0 : 1;
            if (copies == 1) rot[v].push_back(2 * arc0 + half);
            if (copies == 2) {
                const bool v_is_min = v == items[item].a;  // copy 0 borders the face left of min->max
                rot[v].push_back(2 * (arc0 + (v_is_min ? 1 : 0)) + half);
                rot[v].push_back(2 * (arc0 + (v_is_min ? 0 : 1)) + half);
            }
            // Diagonals of f at v, in the order of their other corner along the cycle after v.
            std::vector<std::pair<int, int>> diags;  // (steps from v, half-edge)
            for (int i = 0; i < static_cast<int>(items.size()); ++i) {
                const Item& it = items[i];
                if (it.face != f || assignment.value[i] == 0 || (it.a != v && it.b != v)) continue;
                const int other_pos = it.a == v ? it.pos_b : it.pos_a;
                diags.push_back({(other_pos - k + sz) % sz, 2 * first_arc.at({i, 0}) + (it.a == v ? 0 : 1)});
            }
            std::sort(diags.begin(), diags.end());
            for (const auto& [steps, h] : diags) rot[v].push_back(h);
            w = cyc[(k + sz - 1) % sz];
        } while (w != w0 && ++guard <= nv * 4);
        if (rot[v].size() != 4) return std::nullopt;
    }
    const int nh = 2 * static_cast<int>(arc_ends.size());
    std::vector<int> slot(nh, -1);
    for (int v = 0; v < nv; ++v)
        for (int k = 0; k < 4; ++k) slot[rot[v][k]] = k;
    for (int h = 0; h < nh; ++h)
        if (slot[h] < 0) return std::nullopt;
    const auto tail = [&](int h) { return arc_ends[h / 2][h % 2]; };
    const auto head = [&](int h) { return arc_ends[h / 2][1 - h % 2]; };
    // Faces: next(u->v) = the outgoing half-edge at v just clockwise of v->u.
    std::vector<int> face_of(nh, -1);
    std::vector<std::vector<int>> faces;
    for (int h0 = 0; h0 < nh; ++h0) {
        if (face_of[h0] >= 0) continue;
        const int f = static_cast<int>(faces.size());
        faces.emplace_back();
        int h = h0;
        do {
            face_of[h] = f;
            faces[f].push_back(tail(h));
            const int v = head(h);
            h = rot[v][(slot[h ^ 1] + 3) % 4];
        } while (h != h0 && static_cast<int>(faces[f].size()) <= nh);
        std::vector<int> sorted = faces[f];
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return std::nullopt;
    }
    if (nv - nh / 2 + static_cast<int>(faces.size()) != 2) return std::nullopt;
    std::set<std::pair<int, int>> face_pairs;  // two faces sharing two arcs would give a doubled partition edge
    for (int h = 0; h < nh; h += 2)
        if (!face_pairs.insert(std::minmax(face_of[h], face_of[h + 1])).second) return std::nullopt;
    SpherePartition p;
    for (const std::vector<int>& f : faces) p.points.push_back(face_centre(f, d));
    p.quads.resize(nv);
    for (int v = 0; v < nv; ++v)
        for (int k = 0; k < 4; ++k) p.quads[v][k] = face_of[rot[v][k]];
    return p;
}

// ---------------------------------------------------------------------------------------------------------------
// Relaxation: coordinate descent on the vertices of valence >= 3 (valence-2 vertices stay evenly spread on the arc
// between their two nearest real vertices, so their angles stay 180°). Energy per quad: squared deviation of each
// real corner angle from 360°/valence, plus a barrier keeping the direction away from the quad's edges. Phase 1
// removes constraint violations (if the start is invalid), phase 2 lowers the energy without ever leaving the valid
// set. Bounded sweeps, step halving.

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Relaxer {
    const std::vector<Vec3>& d;
    SpherePartition& p;
    std::vector<int> valence;
    std::vector<int> quad_start, quad_list;     // the quads of point v, in quad order: quad_list[quad_start[v] ..]
    std::vector<std::vector<int>> chains;       // per chain: real start, valence-2 vertices..., real end
    static constexpr double kMinCorner = 2e-3;  // rad, kept from 0 and 180° at real corners
    static constexpr double kMinSide = 1e-3;    // sin-distance of a direction to its quad's edges
    // Energy = sum of exp(-kSharpness * q) over the quality measures q of quality_score: every real corner angle, its
    // supplement, and 90° x (distance of the direction to each quad edge / its bound): a smooth "maximise the minimum".
    static constexpr double kSharpness = 14;
    std::vector<double> bound;
    std::vector<double> trial_energy, best_energy;  // scratch of descend (per quad around the moved vertex)
    bool gradient_steps = false;  // energy phase: moves along the local gradient (gradient_move), not 8 directions
    // Energy phase (pattern): the 8 trials of a vertex start at the direction it moved in last and stop at the first
    // accepted one (SpherePartitionOptions::first_improving_long_relaxation), not the best of 8.
    bool first_improving = false;
    std::vector<int> last_dir;  // per vertex: the trial direction accepted last (first_improving)
    // The terms of the quads around the vertex being moved that a move of it cannot change (fix_terms): per quad of
    // quads_of(v) and corner k, its corner term and the term of its side k -> k + 1, with whether each is kept
    // (fixed_corner_kept / fixed_side_kept; a corner of valence 2 has no term and is never kept).
    int fixed_for = -1;  // the vertex they are for (-1: none)
    std::vector<std::array<double, 4>> fixed_corner, fixed_side;
    std::vector<std::array<char, 4>> fixed_corner_kept, fixed_side_kept;
    bool fixed_violated = false;  // some fixed term is violated: every trial of the vertex is rejected
    std::vector<char> moving;     // per point: moves with fixed_for (itself and its chains' valence-2 points)
    // The screening of a trial (screen_terms). A quad's 8 terms are numbered by slot: corner k at 2k, side k at 2k + 1.
    // term_cache: per quad, its terms at the last accepted points (kept by descend; only an order, never a result);
    // term_order: the moving terms of fixed_for's quads (8 j + slot, j the position in quads_of) by falling
    // term_cache; moving_terms: per position j the trial's moving terms, computed once and then summed in
    // local_energy_below's order; screened: the last local_energy_below filled moving_terms; best_moving: the
    // moving_terms of the best trial so far (empty when not screened).
    std::vector<std::array<double, 8>> term_cache;
    // cache_exact: per quad, term_cache holds exactly quad_term_values at the current points (set by descend,
    // cleared for a moved vertex's quads when update_term_cache cannot update them); fix_terms then reads the fixed
    // terms there.
    std::vector<char> cache_exact;
    std::vector<int> term_order;
    std::vector<std::pair<double, int>> order_keys;  // scratch of order_terms
    std::vector<std::array<double, 8>> moving_terms, best_moving;
    double fixed_sum = 0;  // the sum of fixed_for's fixed terms (order_terms)
    bool screened = false;

    Relaxer(const std::vector<Vec3>& dirs, SpherePartition& part) : d(dirs), p(part), bound(margin_bounds(dirs)) {
        const int nv = static_cast<int>(p.points.size());
        valence.assign(nv, 0);
        for (const std::array<int, 4>& quad : p.quads)
            for (int v : quad) ++valence[v];
        quad_start.assign(static_cast<std::size_t>(nv) + 1, 0);
        for (int v = 0; v < nv; ++v) quad_start[v + 1] = quad_start[v] + valence[v];
        quad_list.resize(static_cast<std::size_t>(quad_start[nv]));
        std::vector<int> at(quad_start.begin(), quad_start.end() - 1);
        for (int q = 0; q < static_cast<int>(p.quads.size()); ++q)
            for (int v : p.quads[q]) quad_list[at[v]++] = q;
    }

    std::span<const int> quads_of(int v) const {
        return {quad_list.data() + quad_start[v], static_cast<std::size_t>(quad_start[v + 1] - quad_start[v])};
    }

    // Chains of valence-2 vertices between two real vertices; false if some chain has no usable real ends.
    bool find_chains() {
        const int nv = static_cast<int>(p.points.size());
        // Per vertex its distinct neighbours in first-seen order: nbr(v)[0 .. count[v]), room for 2 x valence.
        std::vector<int> nbr_list(2 * static_cast<std::size_t>(quad_start[nv])), count(nv, 0);
        const auto nbr = [&](int v) { return nbr_list.data() + 2 * quad_start[v]; };
        const auto add = [&](int a, int b) {
            if (std::find(nbr(a), nbr(a) + count[a], b) == nbr(a) + count[a]) nbr(a)[count[a]++] = b;
        };
        for (const std::array<int, 4>& quad : p.quads)
            for (int k = 0; k < 4; ++k) {
                const int a = quad[k], b = quad[(k + 1) % 4];
                add(a, b);
                add(b, a);
            }
        std::vector<char> done(nv, 0);
        for (int v = 0; v < nv; ++v) {
            if (valence[v] != 2 || done[v]) continue;
            if (count[v] != 2) return false;
            std::vector<int> left = {v}, right;
            for (int side = 0; side < 2; ++side) {  // walk both ways until a real vertex
                int prev = v, at = nbr(v)[side];
                std::vector<int>& path = side == 0 ? left : right;
                int guard = 0;
                while (valence[at] == 2 && ++guard <= nv) {
                    if (at == v) return false;  // a cycle of valence-2 vertices (pillow)
                    path.push_back(at);
                    const int next = nbr(at)[0] == prev ? nbr(at)[1] : nbr(at)[0];
                    prev = at;
                    at = next;
                }
                if (guard > nv) return false;
                path.push_back(at);
            }
            std::vector<int> chain(left.rbegin(), left.rend());  // real end ... v
            chain.insert(chain.end(), right.begin(), right.end());
            for (int x : chain) done[x] = 1;
            for (const std::vector<int>& c : chains)  // two chains between the same ends would coincide
                if (std::minmax(c.front(), c.back()) == std::minmax(chain.front(), chain.back())) return false;
            chains.push_back(chain);
        }
        return true;
    }

    // Places the valence-2 vertices of every chain (all chains), or only of the chains ending at real vertex `v`:
    // the others keep their (already valid) positions, which depend on their ends only.
    bool place_chains(int v = -1) {
        for (const std::vector<int>& c : chains) {
            if (v >= 0 && c.front() != v && c.back() != v) continue;
            const Vec3& a = p.points[c.front()];
            const Vec3& b = p.points[c.back()];
            const double angle = angle_between(a, b);
            if (angle < 1e-9 || angle > kPi - 1e-6) return false;
            const int m = static_cast<int>(c.size()) - 1;
            for (int k = 1; k < m; ++k) {
                const double t = static_cast<double>(k) / m;
                // The middle point of a chain of two edges (t = 1 - t = 0.5) has two equal arguments: one sin call.
                const double from = (1 - t) * angle, to = t * angle;
                const double sin_from = std::sin(from), sin_to = to == from ? sin_from : std::sin(to);
                p.points[c[k]] = normalized(sin_from * a + sin_to * b);
            }
        }
        return true;
    }

    // A real corner's energy term exp(-kSharpness angle) + exp(-kSharpness (pi - angle)), the second computed as
    // exp(-kSharpness pi) / the first: one exp call instead of two, the same value up to a few ulps (the partitions of
    // every measured input are the same bits as with two calls: docs/performance.md, "Twelfth pass").
    double corner_energy(double angle) const {
        static const double far = std::exp(-kSharpness * kPi);
        const double e = std::exp(-kSharpness * angle);
        return e + far / e;
    }

    // violation >= 0 (0 when the quad is valid with the margins above) and energy of quad q (0 unless `energy_too`:
    // the repair phase and total_violation need the violation only, and the exp / asin of the energy are most of
    // the cost).
    std::pair<double, double> quad_terms(int q, bool energy_too = true) const {
        const std::array<int, 4>& quad = p.quads[q];
        double violation = 0, energy = 0;
        for (int k = 0; k < 4; ++k) {
            const int v = quad[k];
            const Vec3& b = p.points[v];
            const Vec3& c = p.points[quad[(k + 1) % 4]];
            if (valence[v] >= 3) {
                double angle = corner_angle(p.points[quad[(k + 3) % 4]], b, c);
                if (angle < 0) angle = 0;
                violation += std::max(0.0, kMinCorner - angle) + std::max(0.0, angle - (kPi - kMinCorner));
                if (energy_too) energy += corner_energy(angle);
            }
            const Vec3 nrm = cross(b, c);
            const double len = norm(nrm);
            const double side = len > 1e-15 ? dot(d[q], nrm) / len : -1;
            violation += std::max(0.0, kMinSide - side);
            if (energy_too)
                energy += std::exp(-kSharpness * kPi / 2 * std::asin(std::clamp(side, -1.0, 1.0)) / bound[q]);
        }
        return {violation, energy};
    }

    std::pair<double, double> local_terms(int v, bool energy_too = true) const {
        double violation = 0, energy = 0;
        for (int q : quads_of(v)) {
            const auto [x, e] = quad_terms(q, energy_too);
            violation += x;
            energy += e;
        }
        return {violation, energy};
    }

    // The energy term of the corner of quad q at its position k (a vertex of valence >= 3); false when violated.
    bool corner_term(int q, int k, double& term) const {
        const std::array<int, 4>& quad = p.quads[q];
        double angle = corner_angle(p.points[quad[(k + 3) % 4]], p.points[quad[k]], p.points[quad[(k + 1) % 4]]);
        if (angle < 0) angle = 0;
        if (kMinCorner - angle > 0 || angle - (kPi - kMinCorner) > 0) return false;
        term = corner_energy(angle);
        return true;
    }

    // The energy term of quad q's side from its position k to k + 1 (the margin of d[q]); false when violated.
    bool side_term(int q, int k, double& term) const {
        const std::array<int, 4>& quad = p.quads[q];
        const Vec3 nrm = cross(p.points[quad[k]], p.points[quad[(k + 1) % 4]]);
        const double len = norm(nrm);
        const double side = len > 1e-15 ? dot(d[q], nrm) / len : -1;
        if (kMinSide - side > 0) return false;
        term = std::exp(-kSharpness * kPi / 2 * std::asin(std::clamp(side, -1.0, 1.0)) / bound[q]);
        return true;
    }

    // For the moves of real vertex v: computes the terms of the quads around v that do not read a point moving with
    // v (neither v nor a valence-2 point of a chain ending at v: place_chains(v) moves only those), at the current
    // points. local_energy_below then takes them as they are: the same values (same inputs, same code) added in the
    // same order, so its result is bit for bit the one it computes without them.
    void fix_terms(int v) {
        moving.assign(p.points.size(), 0);
        moving[v] = 1;
        for (const std::vector<int>& c : chains)
            if (c.front() == v || c.back() == v)
                for (std::size_t k = 1; k + 1 < c.size(); ++k) moving[c[k]] = 1;
        fixed_for = v;
        fixed_violated = false;
        const std::size_t nq = quads_of(v).size();
        fixed_corner.resize(nq);
        fixed_side.resize(nq);
        fixed_corner_kept.resize(nq);
        fixed_side_kept.resize(nq);
        const bool cached = term_cache.size() == p.quads.size() && cache_exact.size() == p.quads.size();
        for (std::size_t j = 0; j < nq; ++j) {
            const int q = quads_of(v)[j];
            const std::array<int, 4>& quad = p.quads[q];
            const bool exact = cached && cache_exact[q];
            for (int k = 0; k < 4; ++k) {
                const int prev = quad[(k + 3) % 4], u = quad[k], next = quad[(k + 1) % 4];
                fixed_corner_kept[j][k] = valence[u] >= 3 && !moving[prev] && !moving[u] && !moving[next];
                if (fixed_corner_kept[j][k] &&
                    !(exact ? cached_term(q, 2 * k, fixed_corner[j][k]) : corner_term(q, k, fixed_corner[j][k])))
                    fixed_violated = true;
                fixed_side_kept[j][k] = !moving[u] && !moving[next];
                if (fixed_side_kept[j][k] &&
                    !(exact ? cached_term(q, 2 * k + 1, fixed_side[j][k]) : side_term(q, k, fixed_side[j][k])))
                    fixed_violated = true;
            }
        }
    }

    // corner_term / side_term of quad q's slot (corner k at 2k, side k at 2k + 1) from an exact term_cache: the value
    // it stored from them at the same points, a violated term as infinity (no valid term is: every one is an exp of a
    // finite non-positive argument, or NaN).
    bool cached_term(int q, int slot, double& term) const {
        const double t = term_cache[q][static_cast<std::size_t>(slot)];
        if (std::isinf(t)) return false;
        term = t;
        return true;
    }

    // The terms of quad q at the current points by slot (a violated term: infinity), for term_cache.
    std::array<double, 8> quad_term_values(int q) const {
        std::array<double, 8> t;
        for (int k = 0; k < 4; ++k) {
            constexpr double violated = kInfinity;
            if (valence[p.quads[q][k]] < 3)
                t[2 * k] = 0;
            else if (!corner_term(q, k, t[2 * k]))
                t[2 * k] = violated;
            if (!side_term(q, k, t[2 * k + 1])) t[2 * k + 1] = violated;
        }
        return t;
    }

    // Lists the terms of v's quads that move with v (fix_terms(v) called) in term_order by falling term_cache (equal
    // ones in list order; NaN as infinity) and sums the fixed ones into fixed_sum: the terms that hold most of the
    // energy before the move mostly hold most of it after a trial step, so screen_terms finds a rejected trial after
    // few terms.
    void order_terms(int v) {
        order_keys.clear();
        fixed_sum = 0;
        for (std::size_t j = 0; j < quads_of(v).size(); ++j) {
            const int q = quads_of(v)[j];
            for (int slot = 0; slot < 8; ++slot) {
                const int k = slot / 2;
                const bool moves =
                    slot % 2 == 0 ? !fixed_corner_kept[j][k] && valence[p.quads[q][k]] >= 3 : !fixed_side_kept[j][k];
                const double t = term_cache[q][slot];
                if (slot % 2 == 0 ? fixed_corner_kept[j][k] : fixed_side_kept[j][k])
                    fixed_sum += slot % 2 == 0 ? fixed_corner[j][k] : fixed_side[j][k];
                if (moves) order_keys.push_back({std::isnan(t) ? kInfinity : t, static_cast<int>(8 * j) + slot});
            }
        }
        std::sort(order_keys.begin(), order_keys.end(), [](const auto& a, const auto& b) {
            return a.first > b.first || (a.first == b.first && a.second < b.second);
        });
        term_order.resize(order_keys.size());
        for (std::size_t i = 0; i < order_keys.size(); ++i) term_order[i] = order_keys[i].second;
    }

    // Computes the terms of the trial that move with v (fix_terms(v) and order_terms(v) called) into moving_terms, in
    // term_order; false when one is violated or when the fixed terms and the terms so far sum (in this order) to at
    // least threshold x (1 + 1e-12), threshold > 0. The rejection is exact: every term is >= 0 and any floating-point
    // sum of n such terms lies within a relative (n - 1) x 2^-53 of their exact sum, so local_energy_below's own sum of
    // all of them, in its order, reaches threshold too while (n - 1) x 2^-53 < 1e-12, n < 4500: the screen runs only at
    // vertices of at most kScreenMaxQuads quads (8 terms each).
    bool screen_terms(int v, double threshold) {
        const double limit = threshold * (1 + 1e-12);
        const std::size_t nq = quads_of(v).size();
        moving_terms.resize(nq);
        double sum = fixed_sum;
        if (sum >= limit) return false;
        for (const int code : term_order) {
            const std::size_t j = static_cast<std::size_t>(code / 8);
            const int q = quads_of(v)[j], slot = code % 8;
            double& term = moving_terms[j][static_cast<std::size_t>(slot)];
            if (!(slot % 2 == 0 ? corner_term(q, slot / 2, term) : side_term(q, slot / 2, term))) return false;
            sum += term;
            if (sum >= limit) return false;
        }
        return true;
    }

    // For a trial move in the energy phase: true when the local violation is 0 and the local energy is < threshold
    // (then `energy` is local_terms(v).second, bit for bit). Stops at the first violated constraint or as soon as the
    // partial energy reaches the threshold: the terms are >= 0 and floating-point sums only grow when adding them.
    // `per_quad` gets the energy of each quad around v (in quads_of(v) order) when the result is true. Terms that
    // cannot move with v come from fix_terms(v) when it was called for v (fixed_for).
    //
    // With fix_terms(v) and order_terms(v) called, the terms that move with v are first computed by screen_terms (the
    // highest terms at v's origin first), which rejects the trial as soon as their partial sum with
    // the fixed terms provably reaches the threshold; the sums below then read those terms (the same values: same
    // inputs, same code), so the result is the same as without the screening.
    bool local_energy_below(int v, double threshold, double& energy, std::vector<double>& per_quad) {
        const bool fixed = fixed_for == v;
        if (fixed && fixed_violated) return false;
        screened =
            fixed && threshold > 0 && term_cache.size() == p.quads.size() && quads_of(v).size() <= kScreenMaxQuads;
        if (screened && !screen_terms(v, threshold)) return false;
        energy = 0;
        per_quad.clear();
        for (std::size_t j = 0; j < quads_of(v).size(); ++j) {
            const int q = quads_of(v)[j];
            double e = 0, term = 0;
            for (int k = 0; k < 4; ++k) {
                if (fixed && fixed_corner_kept[j][k]) {
                    e += fixed_corner[j][k];
                } else if (valence[p.quads[q][k]] >= 3) {
                    if (screened)
                        term = moving_terms[j][2 * k];
                    else if (!corner_term(q, k, term))
                        return false;
                    e += term;
                }
                if (fixed && fixed_side_kept[j][k]) {
                    e += fixed_side[j][k];
                } else {
                    if (screened)
                        term = moving_terms[j][2 * k + 1];
                    else if (!side_term(q, k, term))
                        return false;
                    e += term;
                }
                if (energy + e >= threshold) return false;
            }
            energy += e;
            per_quad.push_back(e);
        }
        return true;
    }

    double total_violation() const {
        double x = 0;
        for (int q = 0; q < static_cast<int>(p.quads.size()); ++q) x += quad_terms(q, false).first;
        return x;
    }

    // The unit tangent direction of steepest descent of the local energy at real vertex v (at `origin`, energy e0,
    // tangent frame t1, t2), from forward differences of length h = min(1e-6, step / 16) (a backward one where the
    // forward point is invalid); nullopt when neither difference is usable or the gradient is 0. Leaves v moved.
    std::optional<Vec3> gradient_direction(int v, const Vec3& origin, const Vec3& t1, const Vec3& t2, double e0,
                                           double step) {
        const double h = std::min(1e-6, step / 16);
        double g[2] = {0, 0};
        for (int axis = 0; axis < 2; ++axis) {
            const Vec3& t = axis == 0 ? t1 : t2;
            bool done = false;
            for (double sign : {1.0, -1.0}) {
                p.points[v] = normalized(origin + sign * h * t);
                if (!place_chains(v)) continue;
                const auto [x, e] = local_terms(v);
                if (x > 0) continue;
                g[axis] = sign * (e - e0) / h;
                done = true;
                break;
            }
            if (!done) return std::nullopt;
        }
        const double len = std::hypot(g[0], g[1]);
        if (!(len > 0)) return std::nullopt;
        return (-g[0] / len) * t1 + (-g[1] / len) * t2;
    }

    // The energy phase's move of real vertex v with gradient_steps (instead of the 8 trial directions): along
    // gradient_direction, a trial at the vertex's step, else at its half and its quarter; after an accepted trial at
    // the full step one at twice its length, again while accepted (5 trials at most). An accepted halved trial ends
    // the search: its double was tried and rejected, and the threshold has only dropped since. Trials are accepted
    // like the pattern's (the local energy below best_score by the same relative margin, no violation), best_score /
    // best_pos / best_energy updated; `step` is set so that descend's growth by 1.25 gives the longest accepted length.
    void gradient_move(int v, const Vec3& origin, const Vec3& t1, const Vec3& t2, double e0, double& step,
                       double& best_score, Vec3& best_pos) {
        const std::optional<Vec3> to = gradient_direction(v, origin, t1, t2, e0, step);
        double length = step;
        for (int trial = 0; to && trial < 5; ++trial) {
            p.points[v] = normalized(origin + length * *to);
            const double threshold = best_score - 1e-6 * best_score - 1e-12;
            double e = 0;
            if (place_chains(v) && local_energy_below(v, threshold, e, trial_energy)) {
                best_score = e;
                best_pos = p.points[v];
                best_energy.assign(trial_energy.begin(), trial_energy.end());
                keep_best_terms();
                length *= 2;
                if (length <= step) break;  // halved before: length is a rejected trial's
            } else if (best_pos == origin && trial < 2) {
                length *= 0.5;
            } else {
                break;
            }
        }
        if (!(best_pos == origin)) step = std::max(step, 0.5 * length / 1.25);
    }

    // After a trial of fixed_for was accepted: its moving terms become the best trial's (for update_term_cache).
    void keep_best_terms() {
        if (screened)
            best_moving.assign(moving_terms.begin(), moving_terms.end());
        else
            best_moving.clear();
    }

    // term_cache of v's quads after v moved to its best trial (fix_terms(v) still in place): the fixed terms and the
    // best trial's moving ones; left as it was when the best trial was not screened.
    void update_term_cache(int v) {
        if (best_moving.size() != quads_of(v).size() || term_cache.size() != p.quads.size()) {
            if (cache_exact.size() == p.quads.size())
                for (const int q : quads_of(v)) cache_exact[q] = 0;
            return;
        }
        for (std::size_t j = 0; j < quads_of(v).size(); ++j) {
            std::array<double, 8>& t = term_cache[quads_of(v)[j]];
            for (int k = 0; k < 4; ++k) {
                const bool corner = valence[p.quads[quads_of(v)[j]][k]] >= 3;
                t[2 * k] = !corner ? 0 : fixed_corner_kept[j][k] ? fixed_corner[j][k] : best_moving[j][2 * k];
                t[2 * k + 1] = fixed_side_kept[j][k] ? fixed_side[j][k] : best_moving[j][2 * k + 1];
            }
        }
    }

    // One phase of coordinate descent with a step per vertex (grown on success, halved on failure); `repair`:
    // minimise the violation, else the energy while the violation stays 0. Stops after max_sweeps sweeps, when every
    // step is tiny, or when a sweep lowers the energy by less than 0.1 %.
    // In the energy phase the energy of every quad is kept (quad_energy, = quad_terms(q).second at the current
    // points): a move of v changes only the quads around v (its chains' points lie in them too), whose energies the
    // accepted trial has just computed. The sums below add the same values in the same order as local_terms and
    // total_energy, so the result is bit for bit the same as recomputing them.
    void descend(bool repair, int max_sweeps) {
        const int nv = static_cast<int>(p.points.size());
        const int nq = static_cast<int>(p.quads.size());
        std::vector<double> step(nv, 0.05);
        std::vector<double> quad_energy(repair ? 0 : nq);
        for (int q = 0; q < nq && !repair; ++q) quad_energy[q] = quad_terms(q).second;
        term_cache.clear();
        for (int q = 0; q < nq && !repair; ++q) term_cache.push_back(quad_term_values(q));
        cache_exact.assign(repair ? 0 : nq, 1);
        const auto cached_total = [&] {
            double e = 0;
            for (int q = 0; q < nq; ++q) e += quad_energy[q];
            return e;
        };
        double energy = repair ? 0 : cached_total();
        for (int sweep = 0; sweep < max_sweeps; ++sweep) {
            bool active = false;
            for (int v = 0; v < nv; ++v) {
                if (valence[v] < 3 || step[v] < 1e-4) continue;
                active = true;
                const Vec3 origin = p.points[v];
                double x0 = 0, e0 = 0;
                if (repair) {
                    x0 = local_terms(v, false).first;
                } else {
                    for (int q : quads_of(v)) e0 += quad_energy[q];
                }
                if (repair && x0 == 0) continue;
                const Vec3 t1 = any_perpendicular(origin), t2 = cross(origin, t1);
                if (!repair) {
                    fix_terms(v);
                    order_terms(v);
                    best_moving.clear();
                }
                double best_score = repair ? x0 : e0;
                Vec3 best_pos = origin;
                const bool first = first_improving && !repair;
                if (first && last_dir.empty()) last_dir.assign(nv, 0);
                for (int j = 0; j < (gradient_steps && !repair ? 0 : 8); ++j) {
                    const int k = first ? (last_dir[v] + j) % 8 : j;
                    if (first && !(best_pos == origin)) break;
                    p.points[v] = normalized(origin + step[v] * (trial_cos()[k] * t1 + trial_sin()[k] * t2));
                    if (!place_chains(v)) continue;
                    const double threshold = best_score - 1e-6 * best_score - 1e-12;
                    if (repair) {
                        const double x = local_terms(v, false).first;
                        if (x < threshold) {
                            best_score = x;
                            best_pos = p.points[v];
                        }
                    } else {
                        double e = 0;
                        if (local_energy_below(v, threshold, e, trial_energy)) {
                            best_score = e;
                            best_pos = p.points[v];
                            best_energy.assign(trial_energy.begin(), trial_energy.end());
                            keep_best_terms();
                            if (first) last_dir[v] = k;
                        }
                    }
                }
                if (gradient_steps && !repair) gradient_move(v, origin, t1, t2, e0, step[v], best_score, best_pos);
                if (!repair && !(best_pos == origin)) update_term_cache(v);
                fixed_for = -1;  // the move changes them
                p.points[v] = best_pos;
                place_chains(v);
                if (!repair && !(best_pos == origin))
                    for (std::size_t j = 0; j < quads_of(v).size(); ++j) quad_energy[quads_of(v)[j]] = best_energy[j];
                step[v] = best_pos == origin ? 0.5 * step[v] : std::min(0.2, 1.25 * step[v]);
            }
            if (!active || (repair && total_violation() == 0)) return;
            if (!repair) {
                const double now = cached_total();
                if (now > energy * (1 - 1e-3)) return;
                energy = now;
            }
        }
    }
};

// Candidates from the hull path (possibly invalid: the caller verifies). Successive halving: up to 8 duals of the
// cheapest assignments get a short relaxation, the 2 best (by quality_score) a long one.
// The highest quality_score any verified partition with p's topology can have: at a vertex of valence k >= 3 the k
// angles sum to 360° (verify allows kSumTolerance), so its largest angle is >= 360°/k and its smallest <= 360°/k.
double quality_cap(const SpherePartition& p) {
    std::vector<int> valence(p.points.size(), 0);
    for (const std::array<int, 4>& quad : p.quads)
        for (int v : quad) ++valence[v];
    double cap = kPi;
    for (int k : valence)
        if (k >= 3) cap = std::min(cap, std::min(2 * kPi / k, kPi - 2 * kPi / k) + kSumTolerance);
    return cap;
}

// The hull path's candidates before relaxation (possibly none).
std::vector<SpherePartition> hull_base_candidates(const std::vector<Vec3>& d) {
    std::vector<SpherePartition> out;
    const int n = static_cast<int>(d.size());
    if (n < 3 || n > 64) return out;
    for (double eps : {1e-10, 1e-7, 1e-4}) {
        const std::optional<BaseMap> base = hull_base_map(d, eps);
        if (!base) continue;
        const std::vector<Item> items = factor_items(*base, d);
        // The search order grows from a root vertex; when a budget runs out without a result, try other roots.
        for (int attempt = 0; attempt < 4 && out.empty(); ++attempt) {
            for (const Assignment& a : cheapest_factors(items, *base, n, 24, 400000, attempt * n / 4)) {
                std::optional<SpherePartition> p = dual_partition(*base, items, a, d);
                if (p) out.push_back(std::move(*p));
                if (out.size() == 8) break;
            }
        }
        break;
    }
    return out;
}

// Hull candidates with one geometry (SpherePartitionOptions::shared_hull_relaxation). Two candidates of one base map
// often differ only in where their valence-2 points sit on the arcs between real vertices (n = 4: the three ways to
// double two opposite edges of the tetrahedron put a valence-2 point on two opposite Voronoi edges; n = 5 mostly
// pairs): their real vertices (valence >= 3) start at the same points, joined by the same arcs, so the quads are the
// same spherical polygons, and their quality_score agrees at any placement of the real vertices (a valence-2 point
// lies on its arc: no angle term, the same margins). Their brief relaxations only rank them, so the first candidate
// of a geometry is relaxed briefly and the others take its real vertices' positions; the long relaxations then run
// each on its own candidate's energy (which weighs a split arc's margin twice, so they end at different points).

// Per quad, its real vertices (valence >= 3) in quad order.
std::vector<std::vector<int>> real_corners(const SpherePartition& p) {
    std::vector<int> valence(p.points.size(), 0);
    for (const std::array<int, 4>& quad : p.quads)
        for (int v : quad) ++valence[v];
    std::vector<std::vector<int>> corners(p.quads.size());
    for (std::size_t q = 0; q < p.quads.size(); ++q)
        for (int v : p.quads[q])
            if (valence[v] >= 3) corners[q].push_back(v);
    return corners;
}

// Candidate b's vertex map onto candidate a (per point of b, a's point at the same place; -1 at valence 2) when they
// have the same geometry: each real vertex of b within 1e-9 of exactly one of a's (the duals' vertices are face centres
// summed in another order: equal up to rounding), and every quad the same cyclic sequence of real vertices. Else empty.
std::vector<int> same_geometry(const SpherePartition& a, const std::vector<std::vector<int>>& ca,
                               const SpherePartition& b, const std::vector<std::vector<int>>& cb) {
    if (ca.size() != cb.size()) return {};
    std::vector<int> map(b.points.size(), -1);
    for (std::size_t q = 0; q < cb.size(); ++q) {
        const std::size_t k = ca[q].size();
        if (cb[q].size() != k || k == 0) return {};
        for (int v : cb[q]) {
            if (map[v] >= 0) continue;
            for (int u = 0; u < static_cast<int>(a.points.size()); ++u)
                if (norm(a.points[u] - b.points[v]) < 1e-9) {
                    if (map[v] >= 0) return {};  // two of a's points at one place
                    map[v] = u;
                }
            if (map[v] < 0) return {};
        }
        const std::size_t shift = std::find(ca[q].begin(), ca[q].end(), map[cb[q][0]]) - ca[q].begin();
        if (shift == k) return {};
        for (std::size_t j = 0; j < k; ++j)
            if (ca[q][(shift + j) % k] != map[cb[q][j]]) return {};
    }
    return map;
}

// Gives candidate p the real-vertex positions of `from` (the first candidate of its geometry) through `map`, its
// valence-2 points placed on their arcs; false (p unchanged) when that placement fails.
bool take_geometry(const std::vector<Vec3>& d, const SpherePartition& from, const std::vector<int>& map,
                   SpherePartition& p) {
    SpherePartition moved = p;
    for (std::size_t v = 0; v < map.size(); ++v)
        if (map[v] >= 0) moved.points[v] = from.points[map[v]];
    Relaxer r(d, moved);
    if (!r.find_chains() || !r.place_chains()) return false;
    p = std::move(moved);
    return true;
}

// The brief relaxation of one hull candidate (in place; restored when it has no usable chains); whether it relaxed.
bool relax_hull_candidate_briefly(const std::vector<Vec3>& d, SpherePartition& p) {
    Relaxer r(d, p);
    const SpherePartition original = p;
    if (!r.find_chains() || !r.place_chains()) {
        p = original;
        return false;
    }
    if (r.total_violation() > 0) r.descend(true, 40);
    if (r.total_violation() == 0) r.descend(false, 5);
    return true;
}

// The 2 best candidates of `ranked` ((-score, candidate) sorted; score 1: invalid) that get a long relaxation. Without
// shared groups (rep[c] == c): among the first two, the relaxable valid ones. With them: the best candidate of each of
// the 2 best geometries, and with a single geometry (n = 4) its 2 best candidates (each relaxed on its own energy).
std::vector<char> long_relaxations(const std::vector<std::pair<double, int>>& ranked,
                                   const std::vector<char>& relaxable, const std::vector<int>& rep, bool shared) {
    std::vector<char> pending(rep.size(), 0);
    if (!shared) {
        for (int k = 0; k < static_cast<int>(ranked.size()) && k < 2; ++k)
            if (relaxable[ranked[k].second] && ranked[k].first <= 0) pending[ranked[k].second] = 1;
        return pending;
    }
    int chosen = 0;
    for (int pass = 0; pass < 2; ++pass)
        for (const auto& [score, c] : ranked) {
            if (chosen == 2 || !relaxable[c] || score > 0 || pending[c]) continue;
            bool taken = false;  // (first pass) its geometry has a long relaxation already
            for (std::size_t o = 0; o < rep.size() && pass == 0; ++o) taken = taken || (pending[o] && rep[o] == rep[c]);
            if (taken) continue;
            pending[c] = 1;
            ++chosen;
        }
    return pending;
}

// Relaxes the hull candidates `out` in place, each briefly (with `shared`, once per geometry: the first candidate of a
// geometry, the others take its positions); returns per candidate whether it gets a long relaxation
// (relax_hull_candidate_long; long_relaxations).
std::vector<char> relax_hull_candidates_briefly(const std::vector<Vec3>& d, std::vector<SpherePartition>& out,
                                                bool shared) {
    const int nc = static_cast<int>(out.size());
    std::vector<std::pair<double, int>> ranked;  // (-score, candidate)
    std::vector<char> relaxable(nc, 0);
    std::vector<int> rep(nc, -1);  // per candidate: the first candidate of its geometry (-1: none yet)
    std::vector<std::vector<std::vector<int>>> corners(nc);
    const std::vector<SpherePartition> initial = shared ? out : std::vector<SpherePartition>{};
    for (int c = 0; c < nc; ++c) {
        if (shared) corners[c] = real_corners(out[c]);
        for (int r = 0; r < c && shared && rep[c] < 0; ++r) {
            if (rep[r] != r) continue;
            const std::vector<int> map = same_geometry(initial[r], corners[r], initial[c], corners[c]);
            if (!map.empty() && take_geometry(d, out[r], map, out[c])) {
                rep[c] = r;
                relaxable[c] = 1;
            }
        }
        if (rep[c] < 0) {
            relaxable[c] = relax_hull_candidate_briefly(d, out[c]);
            rep[c] = relaxable[c] ? c : -2;  // only a relaxed candidate gives its positions to others
        }
        const bool valid = verify_sphere_partition(out[c], d).empty();
        const int r = rep[c] >= 0 ? rep[c] : c;
        // a candidate of an earlier geometry ranks with its score (equal up to rounding), so ties go by index
        ranked.push_back(
            {valid ? (r != c && ranked[r].first <= 0 ? ranked[r].first : -quality_score(out[c], d)) : 1.0, c});
    }
    for (int c = 0; c < nc; ++c)
        if (rep[c] < 0) rep[c] = c;
    std::sort(ranked.begin(), ranked.end());
    return long_relaxations(ranked, relaxable, rep, shared);
}

// The long relaxation of a briefly relaxed hull candidate: it reads only the candidate itself. With
// SpherePartitionOptions::gradient_long_relaxation at most 20 sweeps of gradient moves, else at most 100 sweeps of
// the 8-direction pattern (first_improving_long_relaxation: the first better trial taken).
void relax_hull_candidate_long(const std::vector<Vec3>& d, SpherePartition& p, const SpherePartitionOptions& options) {
    Relaxer r(d, p);
    r.gradient_steps = options.gradient_long_relaxation;
    r.first_improving = options.first_improving_long_relaxation;
    if (r.find_chains() && r.place_chains()) r.descend(false, r.gradient_steps ? 20 : 100);
}

// What partition_sphere computes that does not depend on no_flat_point_in_close_pair, kept for a second call with the
// other value (partition_sphere_close_pair_pair): the axis oranges with their scores, the hull candidates.
struct PartitionWork {
    bool have_oranges = false;
    std::vector<SpherePartition> oranges;
    std::vector<double> orange_scores;
    enum class Hull { None, Base, Relaxed } hull = Hull::None;  // hull_base_candidates, then briefly relaxed
    std::vector<SpherePartition> hull_candidates;
    std::vector<char> long_pending;  // per candidate: its long relaxation is due and not done yet
};

// Makes work.hull_candidates the hull candidates, briefly relaxed (the long relaxations are left to the caller); false
// when no candidate can reach `beat` (quality_cap: the winner needs a strictly higher score or an earlier place, so
// the result is the same without them). A map lookup (.at) that finds an inconsistent structure cannot happen for a
// verified base map; if it does, the hull path simply contributes nothing.
bool hull_candidates(const std::vector<Vec3>& d, double beat, bool shared, PartitionWork& work) {
    try {
        if (work.hull == PartitionWork::Hull::None) {
            work.hull_candidates = hull_base_candidates(d);
            work.hull = PartitionWork::Hull::Base;
        }
        if (work.hull == PartitionWork::Hull::Base) {
            bool may_win = false;
            for (const SpherePartition& p : work.hull_candidates) may_win = may_win || quality_cap(p) >= beat;
            if (!may_win) return false;
            work.long_pending = relax_hull_candidates_briefly(d, work.hull_candidates, shared);
            work.hull = PartitionWork::Hull::Relaxed;
        }
    } catch (const std::out_of_range&) {
        work.hull_candidates.clear();
        work.long_pending.clear();
        work.hull = PartitionWork::Hull::Relaxed;
    }
    return true;
}

// Three directions: whether the hull path's candidate certainly scores below `beat`. That path has one candidate
// there (the plane through the tips is the hull, both its faces triangles; degree 4 needs every edge doubled), never
// relaxed (its three valence-2 chains join the same two poles): the poles are the triangles' vector-area directions
// +-n, n = (d1 - d0) x (d2 - d0) normalised, the other points the digon centres normalised(d_a + d_b) (bit for bit:
// the sum of two terms does not depend on their order). It is built here directly, verified and scored. The vector
// area's sum rounds differently here (~1e-16 absolute), so only tips with |n| > 1e-6 are decided (the poles then agree
// within ~1e-10 rad); the score's minimum is never a margin term near 90 degrees (the poles' angle terms are <= 60),
// so its terms move by at most a few times that, and a score 1e-6 rad below `beat` is certainly below it. An invalid
// direct build, or near-collinear tips, decide nothing (the hull path runs).
bool three_hull_below(const std::vector<Vec3>& d, double beat) {
    const Vec3 c = cross(d[1] - d[0], d[2] - d[0]);
    if (!(norm(c) > 1e-6)) return false;
    const Vec3 axis = normalized(c);
    const OrangeFrame f = orange_frame(d, axis);
    SpherePartition p;
    p.points = {axis, -axis};
    for (int k = 0; k < 3; ++k) p.points.push_back(normalized(d[f.order[k]] + d[f.order[(k + 1) % 3]]));
    p.quads.resize(3);
    for (int k = 0; k < 3; ++k) p.quads[f.order[k]] = {2 + k, 0, 2 + (k + 2) % 3, 1};  // east, north, west, south
    return verify_sphere_partition(p, d).empty() && quality_score(p, d) + 1e-6 < beat;
}

// ---------------------------------------------------------------------------------------------------------------

std::vector<Vec3> validated_directions(const std::vector<Vec3>& directions) {
    const int n = static_cast<int>(directions.size());
    if (n < 2)
        throw Error(ErrorCode::InvalidInput, "sphere partition: need at least 2 directions, got " + std::to_string(n));
    std::vector<Vec3> d(n);
    for (int i = 0; i < n; ++i) {
        if (!is_finite(directions[i]) || norm(directions[i]) < 1e-300)
            throw Error(ErrorCode::InvalidInput,
                        "sphere partition: direction " + std::to_string(i) + " is zero or not finite");
        d[i] = normalized(directions[i]);
    }
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            if (angle_between(d[i], d[j]) < kMinSeparation)
                throw Error(ErrorCode::InvalidInput, "sphere partition: directions " + std::to_string(i) + " and " +
                                                         std::to_string(j) + " coincide");
    return d;
}

}  // namespace

std::string verify_sphere_partition(const SpherePartition& p, const std::vector<Vec3>& directions) {
    const int n = static_cast<int>(directions.size());
    const int nv = static_cast<int>(p.points.size());
    if (static_cast<int>(p.quads.size()) != n)
        return "expected " + std::to_string(n) + " quads, got " + std::to_string(p.quads.size());
    for (int v = 0; v < nv; ++v)
        if (!is_finite(p.points[v]) || std::abs(norm(p.points[v]) - 1) > kUnitTolerance)
            return "point " + std::to_string(v) + " is not a finite unit vector";
    // Topology: every directed edge once, its reverse once; each vertex link one cycle; connected; Euler = 2.
    // The directed edges a -> b, in quad order: the heads of a's are out[a * n + j], j < valence[a] (a vertex is at
    // most once in a quad, so in at most n edges as their tail).
    std::vector<int> out(static_cast<std::size_t>(nv) * static_cast<std::size_t>(n)), valence(nv, 0);
    const auto head = [&](int a, int j) { return out[static_cast<std::size_t>(a) * n + j]; };
    for (int q = 0; q < n; ++q) {
        const std::array<int, 4>& quad = p.quads[q];
        for (int k = 0; k < 4; ++k) {
            if (quad[k] < 0 || quad[k] >= nv) return "quad " + std::to_string(q) + " has an invalid vertex id";
            for (int l = 0; l < k; ++l)
                if (quad[k] == quad[l]) return "quad " + std::to_string(q) + " repeats a vertex";
        }
        for (int k = 0; k < 4; ++k) {
            const int a = quad[k], b = quad[(k + 1) % 4];
            for (int j = 0; j < valence[a]; ++j)
                if (head(a, j) == b) return "directed edge " + std::to_string(a) + "->" + std::to_string(b) + " twice";
            out[static_cast<std::size_t>(a) * n + valence[a]++] = b;
        }
    }
    int edges2 = 0;
    for (int a = 0; a < nv; ++a) {
        if (valence[a] == 0) return "point " + std::to_string(a) + " is in no quad";
        for (int j = 0; j < valence[a]; ++j) {
            const int b = head(a, j);
            bool reverse = false;
            for (int i = 0; i < valence[b]; ++i) reverse = reverse || head(b, i) == a;
            if (!reverse) return "edge " + std::to_string(a) + "-" + std::to_string(b) + " is on the border";
            ++edges2;
        }
    }
    const int ne = edges2 / 2;
    if (nv - ne + n != 2) return "Euler characteristic " + std::to_string(nv - ne + n) + " != 2";
    // Per vertex v, (previous vertex, next vertex) in each quad at v, in quad order: links[start[v] .. start[v + 1]),
    // start[v] = the valences before v (a vertex is at most once in a quad, so in valence[v] quads).
    std::vector<int> start(static_cast<std::size_t>(nv) + 1, 0);
    for (int v = 0; v < nv; ++v) start[v + 1] = start[v] + valence[v];
    std::vector<std::pair<int, int>> links(static_cast<std::size_t>(start[nv]));
    {
        std::vector<int> at(start.begin(), start.end() - 1);
        for (int q = 0; q < n; ++q)
            for (int k = 0; k < 4; ++k) links[at[p.quads[q][k]]++] = {p.quads[q][(k + 3) % 4], p.quads[q][(k + 1) % 4]};
    }
    for (int v = 0; v < nv; ++v) {  // the quads around v form one cycle (prev-neighbour -> next-neighbour)
        const auto first = links.begin() + start[v], last = links.begin() + start[v + 1];
        const int count = start[v + 1] - start[v];
        int steps = 0, at = first->second;
        do {
            const auto it = std::find_if(first, last, [&](const auto& l) { return l.first == at; });
            if (it == last) return "vertex " + std::to_string(v) + " is not manifold";
            at = it->second;
            ++steps;
        } while (at != first->second && steps <= count);
        if (steps != count) return "vertex " + std::to_string(v) + " is not manifold";
    }
    {  // connected
        std::vector<char> seen(nv, 0);
        std::vector<int> stack = {0};
        seen[0] = 1;
        int count = 1;
        while (!stack.empty()) {
            const int a = stack.back();
            stack.pop_back();
            for (int j = 0; j < valence[a]; ++j)
                if (const int b = head(a, j); !seen[b]) {
                    seen[b] = 1;
                    ++count;
                    stack.push_back(b);
                }
        }
        if (count != nv) return "the quads are not connected";
    }
    // Geometry: convex quads with positive area, containing their direction; angle sums 2π, total area 4π.
    std::vector<double> angle_sum(nv, 0);
    double area_sum = 0;
    for (int q = 0; q < n; ++q) {
        const std::array<int, 4>& quad = p.quads[q];
        const Vec3 dir = normalized(directions[q]);
        double quad_angles = 0;
        for (int k = 0; k < 4; ++k) {
            const Vec3& a = p.points[quad[(k + 3) % 4]];
            const Vec3& b = p.points[quad[k]];
            const Vec3& c = p.points[quad[(k + 1) % 4]];
            const double angle = corner_angle(a, b, c);
            if (angle < kAngleTolerance || angle > kPi + kAngleTolerance)
                return "quad " + std::to_string(q) + " is not convex at corner " + std::to_string(k) + " (angle " +
                       std::to_string(angle * 180 / kPi) + " deg)";
            angle_sum[quad[k]] += angle;
            quad_angles += angle;
            const Vec3 edge_normal = cross(b, c);
            if (norm(edge_normal) < 1e-12) return "quad " + std::to_string(q) + " has a degenerate edge";
            if (dot(dir, edge_normal) / norm(edge_normal) <= kMinMargin)
                return "direction " + std::to_string(q) + " is not inside its quad";
        }
        const double area = quad_angles - 2 * kPi;
        if (area <= 0) return "quad " + std::to_string(q) + " has no positive area";
        area_sum += area;
    }
    for (int v = 0; v < nv; ++v)
        if (std::abs(angle_sum[v] - 2 * kPi) > kSumTolerance)
            return "angles around vertex " + std::to_string(v) + " do not sum to 360 deg (fold)";
    if (std::abs(area_sum - 4 * kPi) > kSumTolerance) return "quad areas do not sum to 4 pi (overlap)";
    return "";
}

SpherePartitionStats sphere_partition_stats(const SpherePartition& p, const std::vector<Vec3>& directions) {
    SpherePartitionStats s;
    s.min_angle = 2 * kPi;
    s.min_margin = kPi;
    std::vector<int> valence(p.points.size(), 0);
    for (const std::array<int, 4>& quad : p.quads)
        for (int v : quad) ++valence[v];
    for (int v : valence) s.max_valence = std::max(s.max_valence, v);
    s.min_margin_ratio = 1e300;
    const std::vector<double> bound = margin_bounds(directions);
    for (std::size_t q = 0; q < p.quads.size() && q < directions.size(); ++q) {
        const std::array<int, 4>& quad = p.quads[q];
        const Vec3 dir = normalized(directions[q]);
        double margin = kPi;
        for (int k = 0; k < 4; ++k) {
            const Vec3& b = p.points[quad[k]];
            const Vec3& c = p.points[quad[(k + 1) % 4]];
            if (valence[quad[k]] >= 3) {
                const double angle = corner_angle(p.points[quad[(k + 3) % 4]], b, c);
                s.min_angle = std::min(s.min_angle, angle);
                s.max_angle = std::max(s.max_angle, angle);
            }
            const Vec3 edge_normal = normalized(cross(b, c));
            margin = std::min(margin, std::asin(std::clamp(dot(dir, edge_normal), -1.0, 1.0)));
        }
        s.min_margin = std::min(s.min_margin, margin);
        s.min_margin_ratio = std::min(s.min_margin_ratio, margin / bound[q]);
    }
    if (s.max_angle == 0) s.min_angle = s.max_angle = kPi;  // no vertex of valence >= 3 (n = 2): all angles 180°
    return s;
}

std::array<int, 2> close_pair_of_four(const std::vector<Vec3>& d, double gap_deg) {
    if (d.size() != 4) return {-1, -1};
    int ci = -1, cj = -1;
    double best_cos = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
            if (dot(d[i], d[j]) > best_cos) best_cos = dot(d[i], d[j]), ci = i, cj = j;
    if (ci < 0) return {-1, -1};
    const double a = angle_between(d[ci], d[cj]);
    for (int k = 0; k < 4; ++k)
        if (k != ci && k != cj &&
            std::min(angle_between(d[ci], d[k]), angle_between(d[cj], d[k])) - a < gap_deg * kPi / 180)
            return {-1, -1};
    return {ci, cj};
}

namespace {

// Whether p has a point held by exactly two quads, pair[0]'s and pair[1]'s (false when pair[0] < 0).
bool flat_point_between(const SpherePartition& p, const std::array<int, 2>& pair) {
    if (pair[0] < 0) return false;
    for (int x = 0; x < static_cast<int>(p.points.size()); ++x) {
        int count = 0;
        bool other = false;
        for (int q = 0; q < static_cast<int>(p.quads.size()); ++q)
            if (std::find(p.quads[q].begin(), p.quads[q].end(), x) != p.quads[q].end()) {
                ++count;
                other = other || (q != pair[0] && q != pair[1]);
            }
        if (count == 2 && !other) return true;
    }
    return false;
}

}  // namespace

namespace {

// The long relaxations of the hull candidates that this call can choose (each runs once, in place, for the first call
// that needs it; it reads only its candidate): without a close pair, a candidate whose quality_cap is below `beat`
// cannot win; with one, a candidate with a flat point in the pair's crotch cannot once some candidate without one is
// valid (known after the long relaxations of those).
void finish_hull_candidates(const std::vector<Vec3>& d, double beat, const std::array<int, 2>& pair,
                            const std::vector<SpherePartition>& planar, const std::vector<double>& planar_scores,
                            const std::vector<SpherePartition>& oranges, const std::vector<double>& orange_scores,
                            const SpherePartitionOptions& options, PartitionWork& work) {
    std::vector<SpherePartition>& hull = work.hull_candidates;
    const auto finish = [&](std::size_t c) {
        relax_hull_candidate_long(d, hull[c], options);
        work.long_pending[c] = 0;
    };
    for (std::size_t c = 0; c < hull.size(); ++c)
        if (work.long_pending[c] && (pair[0] < 0 ? quality_cap(hull[c]) >= beat : !flat_point_between(hull[c], pair)))
            finish(c);
    if (pair[0] < 0) return;
    bool clear = false;
    for (std::size_t c = 0; c < planar.size(); ++c)
        clear = clear || (planar_scores[c] != -1e300 && !flat_point_between(planar[c], pair));
    for (std::size_t c = 0; c < oranges.size(); ++c)
        clear = clear || (orange_scores[c] != -1e300 && !flat_point_between(oranges[c], pair));
    for (std::size_t c = 0; c < hull.size() && !clear; ++c)
        clear = !flat_point_between(hull[c], pair) && verify_sphere_partition(hull[c], d).empty();
    if (!clear)
        for (std::size_t c = 0; c < hull.size(); ++c)
            if (work.long_pending[c]) finish(c);
}

// partition_sphere for validated directions d, with what a call with the same directions computed in `work`.
SpherePartition choose_partition(const std::vector<Vec3>& d, const SpherePartitionOptions& options,
                                 PartitionWork& work) {
    const int n = static_cast<int>(d.size());

    // 1. Planar (always for n = 2): the orange around the best-fit plane normal.
    Vec3 normal = best_fit_plane_normal(d);
    if (n == 2) {
        const Vec3 c = cross(d[0], d[1]);
        normal = norm(c) > 1e-9 ? normalized(c) : any_perpendicular(d[0]);
    }
    double planarity = 0;
    for (const Vec3& p : d) planarity = std::max(planarity, std::abs(dot(p, normal)));
    // Candidates in the order that breaks ties (the first of the best wins): planar orange, hull, axis oranges.
    std::vector<SpherePartition> planar, hull;
    const std::array<int, 2> pair = options.no_flat_point_in_close_pair
                                        ? close_pair_of_four(d, options.close_pair_gap_deg)
                                        : std::array<int, 2>{-1, -1};
    const auto flat_in_pair = [&](const SpherePartition& p) { return flat_point_between(p, pair); };
    if (n == 2 || planarity <= options.planarity_tolerance) {
        const OrangeFrame frame = orange_frame(d, normal);
        if (orange_margin(frame) > 0) {
            SpherePartition p = build_orange(frame);
            // A tight cluster is "planar" too, but its lunes are slivers: then let the general path compete.
            if (verify_sphere_partition(p, d).empty() && (n == 2 || quality_score(p, d) >= kGoodOrange) &&
                !flat_in_pair(p))
                return p;
            planar.push_back(std::move(p));
        }
    }

    // Scores of the verified candidates (-1e300: not valid).
    const auto scores_of = [&](const std::vector<SpherePartition>& list) {
        std::vector<double> scores;
        for (const SpherePartition& p : list)
            scores.push_back(verify_sphere_partition(p, d).empty() ? quality_score(p, d) : -1e300);
        return scores;
    };
    // 2. Oranges around the best axes.
    if (!work.have_oranges) {
        work.oranges =
            axis_oranges(d, options.exact_three_orange, options.coarse_three_scan, options.tabled_three_start);
        work.orange_scores = scores_of(work.oranges);
        work.have_oranges = true;
    }
    std::vector<SpherePartition> oranges = work.oranges;
    const std::vector<double> planar_scores = scores_of(planar), &orange_scores = work.orange_scores;
    double beat = -1e300;
    for (double x : planar_scores) beat = std::max(beat, x);
    for (double x : orange_scores) beat = std::max(beat, x);

    // 3. Hull -> 4-regular map -> dual -> relaxation (skipped when its topologies cannot beat the oranges).
    if (!(n == 3 && three_hull_below(d, beat)) &&
        hull_candidates(d, pair[0] >= 0 ? -1e300 : beat, options.shared_hull_relaxation, work)) {
        finish_hull_candidates(d, beat, pair, planar, planar_scores, oranges, orange_scores, options, work);
        hull = work.hull_candidates;
    }
    const std::vector<double> hull_scores = scores_of(hull);
    std::optional<SpherePartition> best;
    double best_score = -1;
    // With a close pair (no_flat_point_in_close_pair): candidates with a flat point in its crotch only if all have one.
    bool any_clear = false;
    for (const auto& [list, scores] :
         {std::pair{&planar, &planar_scores}, std::pair{&hull, &hull_scores}, std::pair{&oranges, &orange_scores}})
        for (std::size_t c = 0; c < list->size(); ++c)
            any_clear = any_clear || ((*scores)[c] != -1e300 && !flat_in_pair((*list)[c]));
    for (const auto& [list, scores] :
         {std::pair{&planar, &planar_scores}, std::pair{&hull, &hull_scores}, std::pair{&oranges, &orange_scores}})
        for (std::size_t c = 0; c < list->size(); ++c) {
            if ((*scores)[c] == -1e300 || (any_clear && flat_in_pair((*list)[c]))) continue;
            if (!best || (*scores)[c] > best_score) {
                best = std::move((*list)[c]);
                best_score = (*scores)[c];
            }
        }
    if (best) return *best;
    throw Error(ErrorCode::NumericalFailure,
                "sphere partition: no valid quad partition found for " + std::to_string(n) + " directions");
}

}  // namespace

SpherePartition partition_sphere(const std::vector<Vec3>& directions, const SpherePartitionOptions& options) {
    PartitionWork work;
    return choose_partition(validated_directions(directions), options, work);
}

std::array<SpherePartition, 2> partition_sphere_close_pair_pair(const std::vector<Vec3>& directions,
                                                                SpherePartitionOptions options) {
    const std::vector<Vec3> d = validated_directions(directions);
    PartitionWork work;
    options.no_flat_point_in_close_pair = false;
    SpherePartition without = choose_partition(d, options, work);
    // A first choice W without a flat point in the pair's crotch is the second call's choice too: W is valid and
    // clear, so the second call chooses among the clear candidates, where W was the first of the best. Between the
    // calls only hull candidates change (relaxed further), and only those the first call could skip: all of them when
    // no hull topology could reach `beat` (the best planar or orange score, <= W's), else the long relaxations of
    // candidates whose quality_cap is below `beat`; either way their scores stay <= quality_cap < beat <= W's score.
    // (The candidates a first call relaxes keep their state, so W, when it is one, is the same bits.)
    if (!flat_point_between(without, close_pair_of_four(d, options.close_pair_gap_deg))) return {without, without};
    options.no_flat_point_in_close_pair = true;
    return {std::move(without), choose_partition(d, options, work)};
}

std::optional<SpherePartition> plane_orange_alternative(const std::vector<Vec3>& directions,
                                                        const SpherePartition& chosen,
                                                        const SpherePartitionOptions& options) {
    const std::vector<Vec3> d = validated_directions(directions);
    if (d.size() < 3 || options.no_flat_point_in_close_pair) return std::nullopt;
    const Vec3 normal = best_fit_plane_normal(d);
    double planarity = 0;
    for (const Vec3& p : d) planarity = std::max(planarity, std::abs(dot(p, normal)));
    // Planar within the tolerance: partition_sphere weighed this orange itself (same result at any tolerance above).
    if (planarity <= options.planarity_tolerance) return std::nullopt;
    const OrangeFrame frame = orange_frame(d, normal);
    if (!(orange_margin(frame) > 0)) return std::nullopt;  // no planar candidate: the search is the chosen one's
    SpherePartition p = build_orange(frame);
    if (!verify_sphere_partition(p, d).empty()) return std::nullopt;
    // Returned at once (a good orange), or first among the best of the candidates; else the search's winner, `chosen`.
    const double score = quality_score(p, d);
    if (score >= kGoodOrange || score >= quality_score(chosen, d)) return p;
    return std::nullopt;
}

namespace detail {

double orange_quality_exact(const std::vector<Vec3>& directions, const Vec3& axis) {
    const std::vector<double> bound = margin_bounds(directions);
    OrangeEvaluator eval(directions, bound);
    bool valid = false;
    return eval.quality(axis, -1e300, valid);
}

std::vector<Vec3> searched_orange_axes(const std::vector<Vec3>& directions) {
    const std::vector<double> bound = margin_bounds(directions);
    OrangeEvaluator eval(directions, bound);
    std::vector<Vec3> out;
    for (const Vec3& start : best_scan_axes(directions, eval)) out.push_back(refine_orange_axis(eval, start));
    return out;
}

std::vector<Vec3> scanned_orange_axes(const std::vector<Vec3>& directions) {
    const std::vector<double> bound = margin_bounds(directions);
    OrangeEvaluator eval(directions, bound);
    return best_scan_axes(directions, eval);
}

Vec3 exact_three_orange_axis(const std::vector<Vec3>& directions, bool coarse_scan, bool tabled) {
    const std::vector<double> bound = margin_bounds(directions);
    OrangeEvaluator eval(directions, bound);
    return exact_three_axis(directions, bound, eval, coarse_scan, tabled).axis;
}

bool orange_certainly_at_most(const std::vector<Vec3>& directions, const Vec3& axis, double threshold) {
    const std::vector<double> bound = margin_bounds(directions);
    OrangeEvaluator eval(directions, bound);
    const Vec3 u = any_perpendicular(axis);
    return eval.certainly_at_most(axis, u, cross(axis, u), threshold);
}

}  // namespace detail

}  // namespace mesohex
