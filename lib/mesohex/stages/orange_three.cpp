// The best orange axis of three directions: trust-region sequential linear programming on the score's pieces.
#include "mesohex/stages/orange_three.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kPieces = 12;  // per direction: width, pi - width, margin with the gap before, with the gap after

// The pieces at one axis: values and gradients with respect to a tangent step (s1, s2) of the axis, a -> normalised
// a + s1 t1 + s2 t2 (t1, t2 the frame below).
struct Pieces {
    Vec3 axis, t1, t2;
    std::array<double, kPieces> value{};
    std::array<std::array<double, 2>, kPieces> grad{};
    double score = 0;  // min of value
};

// A unit vector orthogonal to the unit vector a, and a x it: the tangent frame of the steps.
void tangent_frame(const Vec3& a, Vec3& t1, Vec3& t2) {
    t1 = any_perpendicular(a);
    t2 = cross(a, t1);
}

// The directions seen from an axis with the tangent frame (t1, t2): projections (x, y) = (d . t1, d . t2), heights
// z = d . a, azimuths phi = atan2(y, x), projection lengths r, and (with grads) the gradients of phi and r with respect
// to a tangent step. With the frame moved along the step (t_k -> t_k - s_k a, first order), a direction's projection
// moves by -z (s1, s2), so phi has the gradient z (y, -x) / (x^2 + y^2) and r the gradient -z (x, y) / r.
struct Projections {
    std::array<double, 3> x, y, z, phi, r;
    std::array<std::array<double, 2>, 3> dphi{}, dr{};
};

Projections project(const std::array<Vec3, 3>& d, const Pieces& p, bool grads) {
    Projections pr;
    for (int i = 0; i < 3; ++i) {
        pr.x[i] = dot(d[i], p.t1);
        pr.y[i] = dot(d[i], p.t2);
        pr.z[i] = dot(d[i], p.axis);
        pr.phi[i] = std::atan2(pr.y[i], pr.x[i]);
        const double r2 = pr.x[i] * pr.x[i] + pr.y[i] * pr.y[i];
        pr.r[i] = std::sqrt(r2);
        if (grads && r2 > 1e-300) {
            pr.dphi[i] = {pr.z[i] * pr.y[i] / r2, -pr.z[i] * pr.x[i] / r2};
            pr.dr[i] = {-pr.z[i] * pr.x[i] / pr.r[i], -pr.z[i] * pr.y[i] / pr.r[i]};
        }
    }
    return pr;
}

// The azimuth gaps: order sorts the directions by (azimuth, index), as partition_sphere's orange frame does; gap[k]
// runs from sorted position k to k + 1 (with its gradient dgap[k]); sin and cos of min(gap / 2, pi / 2) from the
// cosine of the gap (the half-angle formulas; the gap is below pi where the margin reads it).
struct Gaps {
    std::array<int, 3> order{0, 1, 2};
    std::array<double, 3> gap, sin_half, cos_half;
    std::array<std::array<double, 2>, 3> dgap;
};

Gaps azimuth_gaps(const Projections& pr) {
    Gaps g;
    const auto before = [&](int a, int b) { return pr.phi[a] != pr.phi[b] ? pr.phi[a] < pr.phi[b] : a < b; };
    if (before(g.order[1], g.order[0])) std::swap(g.order[0], g.order[1]);
    if (before(g.order[2], g.order[1])) std::swap(g.order[1], g.order[2]);
    if (before(g.order[1], g.order[0])) std::swap(g.order[0], g.order[1]);
    for (int k = 0; k < 3; ++k) {
        const int a = g.order[k], b = g.order[k < 2 ? k + 1 : 0];
        g.gap[k] = pr.phi[b] - pr.phi[a] + (k == 2 ? 2 * kPi : 0);
        g.dgap[k] = {pr.dphi[b][0] - pr.dphi[a][0], pr.dphi[b][1] - pr.dphi[a][1]};
        if (g.gap[k] < kPi && pr.r[a] * pr.r[b] > 0) {
            const double c = std::clamp((pr.x[a] * pr.x[b] + pr.y[a] * pr.y[b]) / (pr.r[a] * pr.r[b]), -1.0, 1.0);
            g.sin_half[k] = std::sqrt(0.5 * (1 - c));
            g.cos_half[k] = std::sqrt(0.5 * (1 + c));
        } else if (g.gap[k] < kPi) {  // a direction on the axis (no projection): the gap of atan2's azimuths
            g.sin_half[k] = std::sin(0.5 * g.gap[k]);
            g.cos_half[k] = std::cos(0.5 * g.gap[k]);
        } else {
            g.sin_half[k] = 1;
            g.cos_half[k] = 0;
        }
    }
    return g;
}

// Values only (grads == false) or values and gradients of the pieces at `axis`.
void evaluate(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound, double margin_weight, const Vec3& axis,
              bool grads, Pieces& p) {
    p.axis = axis;
    tangent_frame(axis, p.t1, p.t2);
    const Projections pr = project(d, p, grads);
    const Gaps g = azimuth_gaps(pr);
    // Pieces by direction (4 i + 0..3), not by sorted position: the position of a direction moves with the frame's
    // azimuth origin, its before / after neighbours do not (while no two azimuths cross), so a piece keeps its index
    // from one axis to the next (the second-order correction reads it at two axes).
    p.score = kPi;
    int piece = 0;
    const auto add = [&](double v, double g1, double g2) {
        p.value[piece] = v;
        p.grad[piece] = {g1, g2};
        p.score = std::min(p.score, v);
        ++piece;
    };
    for (int i = 0; i < 3; ++i) {
        const int k = g.order[0] == i ? 0 : (g.order[1] == i ? 1 : 2), kb = k > 0 ? k - 1 : 2;
        const double w = 0.5 * (g.gap[kb] + g.gap[k]);
        const double w1 = 0.5 * (g.dgap[kb][0] + g.dgap[k][0]), w2 = 0.5 * (g.dgap[kb][1] + g.dgap[k][1]);
        add(w, w1, w2);
        add(kPi - w, -w1, -w2);
        const double scale = margin_weight / bound[i];
        for (const int kg : {kb, k}) {
            const double sin_h = g.sin_half[kg], cos_h = g.cos_half[kg];
            const double s = std::clamp(pr.r[i] * sin_h, -1.0, 1.0);
            double g1 = 0, g2 = 0;
            const double c2 = 1 - s * s;
            if (grads && c2 > 1e-12) {
                const double k1 = scale / std::sqrt(c2);
                g1 = k1 * (pr.dr[i][0] * sin_h + pr.r[i] * cos_h * 0.5 * g.dgap[kg][0]);
                g2 = k1 * (pr.dr[i][1] * sin_h + pr.r[i] * cos_h * 0.5 * g.dgap[kg][1]);
            }
            add(scale * std::asin(s), g1, g2);
        }
    }
}

// A simplex dictionary over 3 nonbasic columns and up to kPieces + 2 rows: basic_i = b_i - sum_j a_ij nonbasic_j,
// objective = const + sum_j c_j nonbasic_j; variable ids 0 u1, 1 u2, 2 v, 3 + i the slack of row i.
struct Dictionary {
    static constexpr int kCols = 3;
    int rows = 0;
    std::array<std::array<double, kCols>, kPieces + 2> a{};
    std::array<double, kPieces + 2> b{};
    std::array<int, kPieces + 2> basic{};
    std::array<int, kCols> nonbasic{0, 1, 2};
    std::array<double, kCols> c{0, 0, 1};
};

// One pivot by Bland's rule (the entering variable of smallest id with a positive objective coefficient, the leaving
// row by the ratio test, ties by smallest basic id). False at the optimum, or when no row bounds the entering variable
// (cannot happen in best_linear_step: every piece row bounds v).
bool pivot(Dictionary& t) {
    constexpr int kCols = Dictionary::kCols;
    int e = -1;
    for (int j = 0; j < kCols; ++j)
        if (t.c[j] > 1e-15 && (e < 0 || t.nonbasic[j] < t.nonbasic[e])) e = j;
    if (e < 0) return false;
    int r = -1;
    double ratio = 0;
    for (int i = 0; i < t.rows; ++i) {
        if (!(t.a[i][e] > 1e-12)) continue;
        const double q = t.b[i] / t.a[i][e];
        if (r < 0 || q < ratio || (q == ratio && t.basic[i] < t.basic[r])) {
            r = i;
            ratio = q;
        }
    }
    if (r < 0) return false;
    const double inv = 1 / t.a[r][e];
    t.b[r] *= inv;
    for (int j = 0; j < kCols; ++j) t.a[r][j] = j == e ? inv : t.a[r][j] * inv;
    for (int i = 0; i < t.rows; ++i) {
        if (i == r || t.a[i][e] == 0) continue;
        const double f = t.a[i][e];
        t.b[i] = std::max(0.0, t.b[i] - f * t.b[r]);
        for (int j = 0; j < kCols; ++j) t.a[i][j] = j == e ? -f * t.a[r][e] : t.a[i][j] - f * t.a[r][j];
    }
    const double ce = t.c[e];
    for (int j = 0; j < kCols; ++j) t.c[j] = j == e ? -ce * t.a[r][e] : t.c[j] - ce * t.a[r][j];
    std::swap(t.basic[r], t.nonbasic[e]);
    return true;
}

// The step (s1, s2) in the box |s1|, |s2| <= radius that maximises the linearised score min_k (value_k + grad_k . s),
// and that maximum: a linear program in (s1, s2, t) (max t, t <= value_k + grad_k . s), solved by the simplex method
// in dictionary form with Bland's rule (no cycling; at most 50 pivots, 3-6 in practice). Shifted so that the origin
// is a vertex: u = s + radius in [0, 2 radius], v = t - t0 >= 0 with t0 the model's lowest value at s = (-r, -r).
double best_linear_step(const Pieces& p, double radius, double& s1, double& s2, std::array<int, 3>& tight,
                        int& tight_count) {
    // Live pieces: those that can be the minimum somewhere in the box (lowest value there <= the model's upper bound).
    double upper = 1e300, t0 = 1e300;
    for (int k = 0; k < kPieces; ++k)
        upper = std::min(upper, p.value[k] + radius * (std::abs(p.grad[k][0]) + std::abs(p.grad[k][1])));
    std::array<int, kPieces> live;
    int pieces = 0;
    for (int k = 0; k < kPieces; ++k)
        if (p.value[k] - radius * (std::abs(p.grad[k][0]) + std::abs(p.grad[k][1])) <= upper) {
            live[pieces++] = k;
            t0 = std::min(t0, p.value[k] - radius * (p.grad[k][0] + p.grad[k][1]));
        }
    Dictionary t;  // rows: the live pieces, then u1, u2 <= 2 radius
    t.rows = pieces + 2;
    for (int i = 0; i < pieces; ++i) {
        const int k = live[i];
        t.a[i] = {-p.grad[k][0], -p.grad[k][1], 1};
        t.b[i] = std::max(0.0, p.value[k] - radius * (p.grad[k][0] + p.grad[k][1]) - t0);
        t.basic[i] = 3 + i;
    }
    for (int j = 0; j < 2; ++j) {
        t.a[pieces + j][j] = 1;
        t.b[pieces + j] = 2 * radius;
        t.basic[pieces + j] = 3 + pieces + j;
    }
    for (int k = 0; k < 50; ++k)  // at most 50 pivots
        if (!pivot(t)) break;
    double u[2] = {0, 0};
    for (int i = 0; i < t.rows; ++i)
        if (t.basic[i] < 2) u[t.basic[i]] = t.b[i];
    s1 = std::clamp(u[0] - radius, -radius, radius);
    s2 = std::clamp(u[1] - radius, -radius, radius);
    std::array<double, kPieces> at{};
    double model = 1e300;
    for (int i = 0; i < pieces; ++i) {
        const int k = live[i];
        at[i] = p.value[k] + p.grad[k][0] * s1 + p.grad[k][1] * s2;
        model = std::min(model, at[i]);
    }
    // The pieces equal to the minimum there (within 1e-12 rad), at most 3, by index.
    tight_count = 0;
    for (int i = 0; i < pieces && tight_count < 3; ++i)
        if (at[i] <= model + 1e-12) tight[tight_count++] = live[i];
    return model;
}

// The second-order correction of a step that ends at `p`: the smallest tangent move that makes the `tight` pieces of
// the step's linear program equal again in their linearisation at `p` (a step along a ridge of two pieces leaves it
// by its curvature; this brings it back, so that the trust region need not shrink to the ridge's curvature). Returns
// false when there is nothing to correct (one piece) or the pieces' gradients are (nearly) dependent.
bool ridge_correction(const Pieces& p, const std::array<int, 3>& tight, int tight_count, double& c1, double& c2) {
    if (tight_count < 2) return false;
    const int a = tight[0], b = tight[1];
    const double u1 = p.grad[a][0] - p.grad[b][0], u2 = p.grad[a][1] - p.grad[b][1], h = p.value[a] - p.value[b];
    if (tight_count == 2) {
        const double uu = u1 * u1 + u2 * u2;
        if (!(uu > 1e-20)) return false;
        c1 = -h * u1 / uu;
        c2 = -h * u2 / uu;
        return true;
    }
    const int c = tight[2];
    const double v1 = p.grad[a][0] - p.grad[c][0], v2 = p.grad[a][1] - p.grad[c][1], e = p.value[a] - p.value[c];
    const double det = u1 * v2 - u2 * v1;
    if (!(std::abs(det) > 1e-20)) return false;
    c1 = (-h * v2 + u2 * e) / det;
    c2 = (-u1 * e + v1 * h) / det;
    return true;
}

// One trust-region run from `start`.
OrangeAxisThree climb(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound, double margin_weight,
                      const Vec3& start) {
    Pieces here, trial, corrected;
    evaluate(d, bound, margin_weight, start, true, here);
    double radius = 0.1;  // rad
    for (int iteration = 0; iteration < 100 && radius > 1e-9; ++iteration) {
        double s1 = 0, s2 = 0;
        std::array<int, 3> tight{};
        int tight_count = 0;
        const double predicted = best_linear_step(here, radius, s1, s2, tight, tight_count) - here.score;
        if (!(predicted > 1e-13)) break;
        evaluate(d, bound, margin_weight, normalized(here.axis + s1 * here.t1 + s2 * here.t2), true, trial);
        double c1 = 0, c2 = 0;
        if (ridge_correction(trial, tight, tight_count, c1, c2) && std::max(std::abs(c1), std::abs(c2)) <= radius) {
            evaluate(d, bound, margin_weight, normalized(trial.axis + c1 * trial.t1 + c2 * trial.t2), true, corrected);
            if (corrected.score > trial.score) std::swap(trial, corrected);
        }
        const double ratio = (trial.score - here.score) / predicted;
        if (trial.score > here.score && ratio > 0.1) {
            here = trial;
            if (ratio > 0.75 && std::max(std::abs(s1), std::abs(s2)) >= radius * (1 - 1e-9))
                radius = std::min(2 * radius, 0.5);
        } else {
            radius *= 0.25;
        }
    }
    return {here.axis, here.score};
}

}  // namespace

double orange_score_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound, double margin_weight,
                          const Vec3& axis) {
    Pieces p;
    evaluate(d, bound, margin_weight, axis, false, p);
    return p.score;
}

OrangeAxisThree best_orange_axis_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound,
                                       double margin_weight, const std::vector<Vec3>& starts) {
    OrangeAxisThree best;
    for (const Vec3& start : starts) {
        const OrangeAxisThree end = climb(d, bound, margin_weight, start);
        if (end.score > best.score) best = end;
    }
    return best;
}

double orange_table_angle(double u) { return 0.5 * kPi * (1 - std::cos(kPi * u)); }
double orange_table_coordinate(double angle) { return std::acos(std::clamp(1 - 2 * angle / kPi, -1.0, 1.0)) / kPi; }

namespace {

double angle_of(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// Whether the axis a lies within `radius` rad of an axis in `kept`, as lines (a and -a are one orange).
bool near_any(const Vec3& a, const std::vector<Vec3>& kept, double radius) {
    const double c = std::cos(radius);
    for (const Vec3& k : kept)
        if (std::abs(dot(a, k)) > c) return true;
    return false;
}

// The table's reference starts: 400 Fibonacci axes on the upper hemisphere.
std::vector<Vec3> reference_axes() {
    std::vector<Vec3> axes;
    const double golden = kPi * (3 - std::sqrt(5.0));
    for (int k = 0; k < 400; ++k) {
        const double z = 1 - (k + 0.5) / 400;
        const double r = std::sqrt(std::max(0.0, 1 - z * z));
        axes.push_back(Vec3{r * std::cos(golden * k), r * std::sin(golden * k), z});
    }
    return axes;
}

#include "mesohex/stages/orange_three_table.inc"

// The axes of the 8 table nodes around d's pairwise angles (tabled_orange_starts_three), nearest node first, in d's
// frame, each more than 0.3 rad (as a line) from the ones before; none when the frame is ill-conditioned.
std::vector<Vec3> table_corner_axes(const std::array<Vec3, 3>& d, const signed char* table, int nodes) {
    static constexpr std::array<std::array<int, 3>, 3> kPairs = {{{0, 1, 2}, {0, 2, 1}, {1, 2, 0}}};
    int pick = 0;
    double best_sine = -1;
    for (int p = 0; p < 3; ++p) {
        const double s = norm(cross(d[kPairs[p][0]], d[kPairs[p][1]]));
        if (s > best_sine) best_sine = s, pick = p;
    }
    if (!(best_sine >= 0.2)) return {};
    const auto [i, j, k] = kPairs[pick];
    const Vec3 e1 = d[i], e2 = normalized(d[j] - dot(d[j], e1) * e1), e3 = cross(e1, e2);
    const double side = dot(d[k], e3) < 0 ? -1 : 1;
    const std::array<double, 3> angle = {angle_of(d[i], d[j]), angle_of(d[i], d[k]), angle_of(d[j], d[k])};
    std::array<int, 3> base{};
    std::array<double, 3> t{};
    for (int m = 0; m < 3; ++m) {
        const double f = orange_table_coordinate(angle[m]) * (nodes - 1);
        base[m] = std::clamp(static_cast<int>(std::floor(f)), 0, nodes - 2);
        t[m] = std::clamp(f - base[m], 0.0, 1.0);
    }
    std::array<std::pair<double, int>, 8> corners;  // (-weight, corner), nearest first
    for (int c = 0; c < 8; ++c) {
        double w = 1;
        for (int m = 0; m < 3; ++m) w *= (c >> m & 1) ? t[m] : 1 - t[m];
        corners[c] = {-w, c};
    }
    std::sort(corners.begin(), corners.end());
    std::vector<Vec3> axes;
    for (const auto& [w, c] : corners) {
        const int index = ((base[0] + (c & 1)) * nodes + base[1] + (c >> 1 & 1)) * nodes + base[2] + (c >> 2 & 1);
        const signed char* a = table + 3 * index;
        if (a[0] == 0 && a[1] == 0 && a[2] == 0) continue;
        const Vec3 axis = normalized(double(a[0]) * e1 + double(a[1]) * e2 + side * double(a[2]) * e3);
        if (!near_any(axis, axes, 0.3)) axes.push_back(axis);
    }
    return axes;
}

}  // namespace

Vec3 orange_three_table_axis(double alpha, double beta, double gamma, double margin_weight) {
    const double sa = std::sin(alpha);
    if (!(sa > 1e-6)) return {};
    const double y = (std::cos(gamma) - std::cos(alpha) * std::cos(beta)) / sa;
    const double z2 = 1 - std::cos(beta) * std::cos(beta) - y * y;
    if (z2 < -1e-9) return {};  // not a triple: the angles break the triangle inequality
    const std::array<Vec3, 3> d = {Vec3{1, 0, 0}, Vec3{std::cos(alpha), sa, 0},
                                   normalized(Vec3{std::cos(beta), y, std::sqrt(std::max(0.0, z2))})};
    std::array<double, 3> bound{kPi, kPi, kPi};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (i != j) bound[i] = std::min(bound[i], 0.5 * angle_of(d[i], d[j]));
    if (std::min({bound[0], bound[1], bound[2]}) < 0.01) return {};
    std::vector<std::pair<double, int>> ranked;  // (-score, axis)
    const std::vector<Vec3> axes = reference_axes();
    for (int a = 0; a < static_cast<int>(axes.size()); ++a)
        ranked.push_back({-orange_score_three(d, bound, margin_weight, axes[a]), a});
    std::sort(ranked.begin(), ranked.end());
    std::vector<Vec3> starts;
    for (int r = 0; r < 8 && r < static_cast<int>(ranked.size()); ++r)
        if (!near_any(axes[ranked[r].second], starts, 0.3)) starts.push_back(axes[ranked[r].second]);
    const OrangeAxisThree best = best_orange_axis_three(d, bound, margin_weight, starts);
    if (!(best.score > 0)) return {};
    return best.axis.z < 0 ? -1.0 * best.axis : best.axis;
}

std::vector<Vec3> tabled_orange_starts_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound,
                                             double margin_weight, const signed char* table, int nodes) {
    MESOHEX_CHECK(table != nullptr && nodes >= 2, "tabled_orange_starts_three needs a table of at least 2^3 nodes");
    std::vector<Vec3> candidates = table_corner_axes(d, table, nodes);
    for (int a = 0; a < 3; ++a) {
        const Vec3 c = cross(d[a], d[(a + 1) % 3]);
        if (norm(c) > 1e-6) candidates.push_back(normalized(c));
    }
    const Vec3 centre = cross(d[1] - d[0], d[2] - d[0]), mean = d[0] + d[1] + d[2];
    if (norm(centre) > 1e-12) candidates.push_back(normalized(centre));
    if (norm(mean) > 1e-9) candidates.push_back(normalized(mean));
    std::vector<std::pair<double, int>> ranked;  // (-score, candidate)
    for (int c = 0; c < static_cast<int>(candidates.size()); ++c)
        ranked.push_back({-orange_score_three(d, bound, margin_weight, candidates[c]), c});
    std::stable_sort(ranked.begin(), ranked.end());
    std::vector<Vec3> starts;
    for (const auto& [score, c] : ranked) {
        if (!(score < 0)) break;  // no valid orange around it, nor around the rest
        if (!near_any(candidates[c], starts, 0.3)) starts.push_back(candidates[c]);
        if (starts.size() == 2) break;
    }
    return starts;
}

const signed char* orange_three_table() { return kOrangeTable.data(); }

std::vector<Vec3> tabled_orange_starts_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound,
                                             double margin_weight) {
    return tabled_orange_starts_three(d, bound, margin_weight, kOrangeTable.data(), kOrangeTableNodes);
}

}  // namespace mesohex
