#include "mesohex/stages/adaptation.h"
#include "mesohex/stages/skeleton_analysis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mesohex/core/error.h"
#include "mesohex/core/union_find.h"

// Section criterion (why AdaptationOptions::turn_safety and branching_reach exist).
// Joints. The cross-section at a joint is the plane through it normal to the bisector of its two edge directions
// (frames stage, reference-notes §7.3); its rim (the connection-surface vertices) lies at distance r from the joint.
// When the branch turns by theta at the joint, that plane is tilted by theta/2 from the plane normal to each adjacent
// edge, so on the inner side of the turn the rim moves along the edge, towards the next section, by r sin(theta/2).
// Two consecutive sections A, B therefore cross (inverted hexes) on the inner side when
//     |AB| < r_A sin(theta_A / 2) + r_B sin(theta_B / 2)
// (worst case: both tilts face each other, as in a planar C-shaped turn). We ask for turn_safety times that.
// Extremities: the section is flat and normal to the edge: reach 0.
// Branching points and leaflet vertices. The section is a quad of the sphere of radius r_c, joined to the centre; its
// vertices lie up to almost r_c ahead along the branch, so the next section must be beyond r_c. Moreover the quad only
// covers a cone of half-angle gamma around the branch (about half the angle beta to the nearest other branch); the
// first hex layer is inverted where the next section's rim, seen from the centre, leaves that cone, i.e. when
// L < r_next cot(gamma). Hence reach = branching_reach * max(r_c, r_next cot(gamma)), with free_branching_reach in
// place of branching_reach at a branching point without a leaflet.
// The same bound with r_a + r_b is the reference's collapse rule for short bridges.
// A joint whose edge violates the bound is removed (the one of the edge's two ends with the larger reach); removing
// it lengthens the edge, and the turn it carried is shared by its neighbours.

namespace mesohex {
namespace {

// The original polyline of a branch, parametrised by arc length.
struct Polyline {
    std::vector<Vec3> x;
    std::vector<double> r;
    std::vector<double> s;  // cumulative arc length, s[0] = 0
    // Arc lengths of its pinned joints (adapt_skeleton_detailed's `pinned`), increasing: samples the resampling keeps.
    std::vector<double> pinned;

    double length() const { return s.back(); }
    // Linear interpolation of position and radius at arc length t (clamped to [0, length]).
    std::pair<Vec3, double> at(double t) const {
        if (!(t > 0)) return {x.front(), r.front()};
        if (t >= s.back()) return {x.back(), r.back()};
        const std::size_t i = static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), t) - s.begin());
        const std::size_t a = i - 1;  // s[a] <= t < s[i]
        const double len = s[i] - s[a];
        const double u = len > 0 ? (t - s[a]) / len : 0.0;
        return {x[a] + u * (x[i] - x[a]), r[a] + u * (r[i] - r[a])};
    }
};

[[noreturn]] void invalid(const std::string& what, ElementRef where = {}) {
    throw Error(ErrorCode::InvalidInput, "adapt_skeleton: " + what, where);
}

void validate(const Skeleton& s, const AdaptationOptions& o) {
    const int n = static_cast<int>(s.points.size());
    if (!(o.density > 0) || !std::isfinite(o.density)) invalid("density must be a positive number");
    if (s.radii.size() != s.points.size())
        invalid("the skeleton (" + std::to_string(n) + " vertices, " + std::to_string(s.edges.size()) + " edges) has " +
                std::to_string(s.radii.size()) + " radii: adaptation needs one radius per vertex (fill radii first)");
    for (int v = 0; v < n; ++v) {
        if (!is_finite(s.points[v]))
            invalid("vertex " + std::to_string(v) + " has a non-finite position",
                    {ElementRef::Kind::SkeletonVertex, v});
        if (!(s.radii[v] > 0) || !std::isfinite(s.radii[v]))
            invalid("vertex " + std::to_string(v) + " has radius " + std::to_string(s.radii[v]) + " (must be > 0)",
                    {ElementRef::Kind::SkeletonVertex, v});
    }
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e) {
        const auto [a, b] = s.edges[e];
        const ElementRef where{ElementRef::Kind::SkeletonEdge, e};
        if (a < 0 || a >= n || b < 0 || b >= n)
            invalid("edge " + std::to_string(e) + " has a vertex out of range", where);
        if (a == b) invalid("edge " + std::to_string(e) + " is a self-loop", where);
    }
    for (int f = 0; f < static_cast<int>(s.faces.size()); ++f)
        for (const int v : s.faces[f])
            if (v < 0 || v >= n)
                invalid("face " + std::to_string(f) + " has a vertex out of range",
                        {ElementRef::Kind::SkeletonFace, f});
}

double sin_half_turn(const Vec3& prev, const Vec3& here, const Vec3& next) {
    const Vec3 u = normalized(here - prev), w = normalized(next - here);
    if (u == Vec3{} || w == Vec3{}) return 1.0;  // degenerate edge: treat as the worst turn
    const double c = std::clamp(dot(u, w), -1.0, 1.0);
    return std::sqrt(std::max(0.0, 0.5 * (1.0 - c)));
}

void bisect(const Polyline& pl, double t0, double t1, int depth, double r_floor, const AdaptationOptions& o,
            std::vector<double>& out) {
    if (depth >= o.max_depth) return;
    const double r0 = std::max(pl.at(t0).second, r_floor);
    const double r1 = std::max(pl.at(t1).second, r_floor);
    if (!(r0 + r1 < o.density * (t1 - t0))) return;
    const double tm = 0.5 * (t0 + t1);
    bisect(pl, t0, tm, depth + 1, r_floor, o, out);
    out.push_back(tm);
    bisect(pl, tm, t1, depth + 1, r_floor, o, out);
}

// Bisection + smoothing of each piece between pinned joints (the pins stay where they are); the pins included, in
// order. Empty when the pieces give fewer than min_edges edges (the caller then samples the branch as a whole).
std::vector<double> sample_pinned(const Polyline& pl, int min_edges, double r_floor, const AdaptationOptions& o) {
    std::vector<double> bounds{0.0};
    for (const double p : pl.pinned)  // strictly inside and increasing: no zero-length piece (coincident vertices)
        if (p > bounds.back() && p < pl.length()) bounds.push_back(p);
    bounds.push_back(pl.length());
    std::vector<double> t;
    for (std::size_t i = 0; i + 1 < bounds.size(); ++i) {
        std::vector<double> piece;
        bisect(pl, bounds[i], bounds[i + 1], 0, r_floor, o, piece);
        for (std::size_t k = 0; k < piece.size() && o.smooth; ++k) {  // Jacobi, as sample_branch
            const double before = k == 0 ? bounds[i] : piece[k - 1];
            const double after = k + 1 == piece.size() ? bounds[i + 1] : piece[k + 1];
            t.push_back(0.5 * (before + after));
        }
        if (!o.smooth) t.insert(t.end(), piece.begin(), piece.end());
        if (i + 2 < bounds.size()) t.push_back(bounds[i + 1]);
    }
    if (static_cast<int>(t.size()) + 1 < min_edges) t.clear();
    return t;
}

// Bisection + minimum edge count + smoothing; returns the joints' arc parameters.
std::vector<double> sample_branch(const Polyline& pl, int min_edges, const AdaptationOptions& o) {
    const double r_max = *std::max_element(pl.r.begin(), pl.r.end());
    if (!pl.pinned.empty()) {
        std::vector<double> t = sample_pinned(pl, min_edges, o.min_radius_fraction * r_max, o);
        if (!t.empty()) return t;
    }
    std::vector<double> t;
    bisect(pl, 0.0, pl.length(), 0, o.min_radius_fraction * r_max, o, t);
    if (static_cast<int>(t.size()) + 1 < min_edges) {
        t.clear();
        for (int i = 1; i < min_edges; ++i) t.push_back(pl.length() * i / min_edges);
        return t;
    }
    if (o.smooth && !t.empty()) {
        std::vector<double> smoothed(t.size());
        for (std::size_t i = 0; i < t.size(); ++i) {
            const double before = i == 0 ? 0.0 : t[i - 1];
            const double after = i + 1 == t.size() ? pl.length() : t[i + 1];
            smoothed[i] = 0.5 * (before + after);
        }
        t = std::move(smoothed);
    }
    return t;
}

// What a branch end demands of the distance to its first joint: sphere * r_end (the end's own section), and
// cot_gamma * r_joint (the joint's disc seen from the end vertex must stay inside the angular extent gamma of the
// end's connection quad). Both 0 at an extremity.
struct EndReach {
    double sphere = 0;
    double cot_gamma = 0;
    double extent = 0;  // absolute: a branch rooted on a leaflet patch clears root_extent x the patch's edges
    double patch = 0;   // absolute: ... and the raw-mesh points of that patch (patch_reach), unless a pin yields
    // A branching point without a leaflet that is, or was made from, a junction of degree >= 4: its own degree >= 4
    // (its sphere partition's pattern, which pairs of branches share a quad side, depends on the branch directions,
    // so moving this branch's first joint may switch it), or a part of such a junction of the input that the repair
    // made degree 3 (a split's halves, a trunk's root and t: adapt_skeleton's junction_degree), whose parts sit
    // closer together than the junction's balls. slide_away_from_end does not slide there. A junction of degree 3
    // has one pattern (3 quads on 5 points).
    bool pattern_may_switch = false;
};

// Where the edge a - b passes the ball (x, rx): how far it misses the ball as a fraction of rx (the distance from x
// to the segment + rx - the segment's interpolated radius at the nearest point), and that interpolated radius.
struct BallMiss {
    double fraction = 0;
    double r_edge = 0;
};

BallMiss ball_miss(const Vec3& xa, double ra, const Vec3& xb, double rb, const Vec3& x, double rx) {
    const Vec3 ab = xb - xa;
    const double len2 = dot(ab, ab);
    const double u = len2 > 0 ? std::clamp(dot(x - xa, ab) / len2, 0.0, 1.0) : 0.0;
    const double r_edge = ra + u * (rb - ra);
    return {(distance(x, xa + u * ab) + rx - r_edge) / rx, r_edge};
}

// How deep the edge a - c that replaces the removed joint v cuts into a ball: the largest BallMiss fraction over v's
// ball (radius rv) and the balls of the input vertices strictly between the arc parameters of a and c (either order).
double replaced_edge_cut(const std::vector<Vec3>& x, const std::vector<double>& r, const std::vector<double>& arc,
                         int a, int v, double rv, int c, const Polyline& input) {
    double cut = ball_miss(x[a], r[a], x[c], r[c], x[v], rv).fraction;
    const double lo = std::min(arc[a], arc[c]), hi = std::max(arc[a], arc[c]);
    for (std::size_t i = 0; i < input.x.size(); ++i)
        if (input.s[i] > lo && input.s[i] < hi)
            cut = std::max(cut, ball_miss(x[a], r[a], x[c], r[c], input.x[i], input.r[i]).fraction);
    return cut;
}

// The largest joint radius r with max(a, c r) + s r <= l (0 when a >= l): an edge of length turn_safety x l from an
// end of reach max(a, c r_joint) to a joint of reach s r meets the criterion (s the joint's sin_half_turn).
double largest_joint_radius(double a, double c, double s, double l) {
    if (!(a < l) || !(c + s > 0)) return 0;
    const double r1 = l / (c + s);
    if (c * r1 >= a) return r1;
    return s > 0 ? (l - a) / s : std::numeric_limits<double>::infinity();
}

// The criterion would remove chain index `victim` from the violated edge j -> j + 1 of a chain (not a ring) whose end
// next to it has a connection quad (cot_gamma > 0: a branching point or a leaflet vertex). With
// AdaptationOptions::slide_cut_joint the victim slides instead, along the input polyline away from that end, to the
// first of kSlideSteps - 1 evenly spaced arc positions before its other neighbour q where both the edge from the end
// and the edge to q meet the criterion (q's reach taken with the slid joint as its neighbour). Only where the slide has
// something to keep and cannot switch the junction's pattern: the edge from the end to q cuts a ball (the victim's or
// an input vertex's between them: replaced_edge_cut >= kSlideMinCut), and the end is no branching point whose
// partition pattern may switch (EndReach::pattern_may_switch). Position, radius and arc parameter are updated in x, r,
// arc; returns false (nothing changed) when the gate fails or no position passes.
bool slide_away_from_end(std::vector<Vec3>& x, std::vector<double>& r, std::vector<double>& arc,
                         const std::vector<int>& keep, std::size_t j, std::size_t victim,
                         const std::array<EndReach, 2>& end_reach, const Polyline& input, const AdaptationOptions& o) {
    const std::size_t last = keep.size() - 1;
    const bool front = j == 0 && victim == 1, back = j + 1 == last && victim + 1 == last;
    if (!o.slide_cut_joint || (!front && !back) || (front && back)) return false;
    const EndReach& er = end_reach[front ? 0 : 1];
    if (!(er.cot_gamma > 0) || er.pattern_may_switch) return false;
    const std::size_t qk = front ? victim + 1 : victim - 1;  // the victim's other neighbour, in keep
    const int e = keep[front ? 0 : last], v = keep[victim], q = keep[qk];
    // kSlideMinCut (x the ball's radius): below it the edge replacing the victim cuts no ball (a straight piece whose
    // radius varies linearly gives 0 up to rounding): removing the victim loses nothing, a slide would only keep a
    // joint (docs/junctions.md, "The cut-joint slide's gate").
    constexpr double kSlideMinCut = 0.01;
    if (!(replaced_edge_cut(x, r, arc, e, v, r[v], q, input) >= kSlideMinCut)) return false;
    const bool q_is_end = qk == 0 || qk == last;
    const EndReach& eq = end_reach[front ? 1 : 0];
    const int q2 = q_is_end ? q : keep[front ? qk + 1 : qk - 1];
    const double a = std::max({er.sphere * r[e], er.extent, er.patch});
    // kSlideSteps: the slid positions tried divide the arc from the victim to q into this many parts (dimensionless;
    // a step is about 3 % of the edge, fine against the criterion's 1.25 safety factor; not tuned).
    constexpr int kSlideSteps = 32;
    for (int k = 1; k < kSlideSteps; ++k) {
        const double t = arc[v] + (arc[q] - arc[v]) * k / kSlideSteps;
        const auto [p, rp] = input.at(t);
        const double sp = rp * sin_half_turn(x[e], p, x[q]);
        const double reach_q = q_is_end ? std::max({eq.sphere * r[q], eq.cot_gamma * rp, eq.extent, eq.patch})
                                        : r[q] * sin_half_turn(p, x[q], x[q2]);
        if (distance(x[e], p) < o.turn_safety * (std::max(a, er.cot_gamma * rp) + sp)) continue;
        if (distance(p, x[q]) < o.turn_safety * (sp + reach_q)) continue;
        x[v] = p;
        r[v] = rp;
        arc[v] = t;
        return true;
    }
    return false;
}

// Removes joints that violate the section criterion. x/r hold the whole sampled chain (ends included); end_reach gives
// the demands of each end (zero at an extremity); ring: x.front() == x.back() is the anchor, a joint that stays.
// Never leaves fewer than min_edges edges, never removes a pinned joint (pinned: per chain index). Returns the kept
// chain indices; a joint next to an end that the criterion would remove but whose ball the edge replacing it misses
// (AdaptationOptions::keep_cut_joint) is kept with a lowered radius in r instead; *stuck (when given) gets the pinned
// chain indices left on an edge that still violates the criterion (their
// neighbours could not be removed: a branch end, another pin, or min_edges).
std::vector<int> apply_turn_criterion(std::vector<Vec3>& x, std::vector<double>& r,
                                      const std::array<EndReach, 2>& end_reach, bool ring, int min_edges,
                                      const std::vector<bool>& pinned, const AdaptationOptions& o,
                                      std::vector<int>* stuck = nullptr, const Polyline* input = nullptr,
                                      std::vector<double>* arc = nullptr) {
    std::vector<int> keep(x.size());
    std::iota(keep.begin(), keep.end(), 0);
    if (!(o.turn_safety > 0)) return keep;
    const auto reach = [&](std::size_t k) -> double {
        const std::size_t last = keep.size() - 1;
        if (k == 0 || k == last) {
            if (ring) {  // the anchor: a joint between the last and the first edge
                if (keep.size() < 3) return r[keep[0]];
                return r[keep[0]] * sin_half_turn(x[keep[last - 1]], x[keep[0]], x[keep[1]]);
            }
            const EndReach& er = end_reach[k == 0 ? 0 : 1];
            const double r_near = r[keep[k == 0 ? 1 : last - 1]];
            return std::max({er.sphere * r[keep[k]], er.cot_gamma * r_near, er.extent, er.patch});
        }
        return r[keep[k]] * sin_half_turn(x[keep[k - 1]], x[keep[k]], x[keep[k + 1]]);
    };
    std::vector<double> r_input = r;  // the input radius at each joint's current position (a slide moves it)
    // The violated edge j -> j + 1 joins an end and the victim joint: keep the victim thinner if its ball is cut.
    const auto kept_thinner = [&](std::size_t j, std::size_t victim) -> bool {
        const std::size_t last = keep.size() - 1;
        const bool front = j == 0 && victim == 1, back = j + 1 == last && victim + 1 == last;
        if (!(o.keep_cut_joint > 0) || ring || (!front && !back)) return false;
        const EndReach& er = end_reach[front ? 0 : 1];
        if (!(er.cot_gamma > 0)) return false;
        const int v = keep[victim], p = keep[victim - 1], q = keep[victim + 1], e = keep[front ? 0 : last];
        const double cut = input && arc ? replaced_edge_cut(x, r, *arc, p, v, r_input[v], q, *input)
                                        : ball_miss(x[p], r[p], x[q], r[q], x[v], r_input[v]).fraction;
        if (cut < o.keep_cut_joint) return false;
        const double a = std::max({er.sphere * r[e], er.extent, er.patch});
        const double s = sin_half_turn(x[p], x[v], x[q]);
        // kKeptMargin (dimensionless): the kept radius just inside the criterion's bound, so that the edge passes it
        // despite rounding; kKeptFloor (x the input radius): a joint thinner than this pinches the tube, so it goes.
        constexpr double kKeptMargin = 0.999, kKeptFloor = 0.5;
        const double r_new =
            kKeptMargin * largest_joint_radius(a, er.cot_gamma, s, distance(x[e], x[v]) / o.turn_safety);
        if (!(r_new >= kKeptFloor * r_input[v]) || !(r_new < r[v])) return false;
        r[v] = r_new;
        return true;
    };
    std::size_t j = 0;  // edge keep[j] -> keep[j+1]
    while (j + 1 < keep.size()) {
        const double chord = distance(x[keep[j]], x[keep[j + 1]]);
        const double ra = reach(j), rb = reach(j + 1);
        const bool violated = chord < o.turn_safety * (ra + rb);
        const bool can_remove = static_cast<int>(keep.size()) - 2 >= min_edges;  // edges after removing one joint
        const bool a_joint = j > 0 && !pinned[keep[j]], b_joint = j + 2 < keep.size() && !pinned[keep[j + 1]];
        if (violated && can_remove && (a_joint || b_joint)) {
            const std::size_t victim = !a_joint ? j + 1 : (!b_joint ? j : (rb > ra ? j + 1 : j));
            if (!ring && input && arc && slide_away_from_end(x, r, *arc, keep, j, victim, end_reach, *input, o)) {
                // The slid joint turns its other neighbour q by a new angle: q's edges are checked again (at the back
                // end the edge before q lies behind j). Finite: a joint slides again only after an erase.
                r_input[keep[victim]] = r[keep[victim]];
                j = victim >= 2 ? victim - 2 : 0;
                continue;
            }
            if (kept_thinner(j, victim)) {
                ++j;
                continue;
            }
            keep.erase(keep.begin() + static_cast<std::ptrdiff_t>(victim));
            j = victim >= 2 ? victim - 2 : 0;  // the turns of the victim's neighbours changed
            continue;
        }
        ++j;
    }
    for (std::size_t k = 0; stuck && k + 1 < keep.size(); ++k)
        if (distance(x[keep[k]], x[keep[k + 1]]) < o.turn_safety * (reach(k) + reach(k + 1)))
            for (const std::size_t m : {k, k + 1})
                if (pinned[keep[m]]) stuck->push_back(keep[m]);
    return keep;
}

// Degenerate branch configurations (AdaptationOptions::merge_distance, coincident_angle): the input after repair, and
// the map from input vertices to repaired ones.
struct Repaired {
    Skeleton s;
    std::vector<int> map;
    int merged_vertices = 0, duplicate_edges = 0, reattached_edges = 0;
};

// Which vertices lie on a leaflet face, and the faces' sides as vertex pairs: per smaller vertex lo, the larger ends
// of its sides in side_hi[side_begin[lo] .. side_begin[lo + 1]) (CSR, built by counting; repeats allowed).
struct FaceMembership {
    std::vector<bool> on_face;
    std::vector<int> side_begin;  // #vertices + 1 entries
    std::vector<int> side_hi;
    bool is_side(int a, int b) const {
        const int lo = std::min(a, b), hi = std::max(a, b);
        for (int k = side_begin[lo]; k < side_begin[lo + 1]; ++k)
            if (side_hi[k] == hi) return true;
        return false;
    }
};

FaceMembership face_membership(const Skeleton& s) {
    FaceMembership m;
    const std::size_t n = s.points.size();
    m.on_face.assign(n, false);
    m.side_begin.assign(n + 1, 0);
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i) {
            m.on_face[static_cast<std::size_t>(f[i])] = true;
            ++m.side_begin[static_cast<std::size_t>(std::min(f[i], f[(i + 1) % f.size()])) + 1];
        }
    for (std::size_t v = 0; v < n; ++v) m.side_begin[v + 1] += m.side_begin[v];
    m.side_hi.resize(static_cast<std::size_t>(m.side_begin[n]));
    std::vector<int> fill(m.side_begin.begin(), m.side_begin.end() - 1);
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i) {
            const int a = f[i], b = f[(i + 1) % f.size()];
            m.side_hi[fill[std::min(a, b)]++] = std::max(a, b);
        }
    return m;
}

// Merges the two ends of every branch edge shorter than merge_distance x the smaller end radius (not both on a
// leaflet face; the merged vertex takes the leaflet vertex's position, else the mean, and the larger radius), then
// drops self-loops and repeated edges. Vertices are renumbered in order; unused vertex ids disappear only by merging.
// inside_branches: also edges between two joints (on the final output, where no resampling follows). Returns whether
// anything was merged or dropped.
bool merge_short_edges(Repaired& r, const AdaptationOptions& o, bool inside_branches = false) {
    const Skeleton& s = r.s;
    const int n = static_cast<int>(s.points.size());
    const FaceMembership faces = face_membership(s);
    const std::vector<bool>& on_face = faces.on_face;
    std::vector<int> degree(n, 0);
    for (const std::array<int, 2>& e : s.edges) ++degree[e[0]], ++degree[e[1]];
    UnionFind uf(n);
    std::vector<bool> class_on_face = on_face;
    int merged = 0;
    for (const std::array<int, 2>& e : s.edges) {
        if (faces.is_side(e[0], e[1])) continue;
        // Inside a branch (two joints) the resampling steps over a zero-length segment: nothing to repair.
        if (!inside_branches && degree[e[0]] == 2 && degree[e[1]] == 2 && !on_face[e[0]] && !on_face[e[1]]) continue;
        const int a = uf.find(e[0]), b = uf.find(e[1]);
        if (a == b || (class_on_face[a] && class_on_face[b])) continue;
        const double limit = std::max(0.0, o.merge_distance) * std::min(s.radii[e[0]], s.radii[e[1]]);
        if (!(distance(s.points[e[0]], s.points[e[1]]) <= limit)) continue;
        uf.unite(a, b);
        class_on_face[uf.find(a)] = class_on_face[a] || class_on_face[b];
        ++merged;
    }
    std::vector<int> id(n, -1);
    Skeleton out;
    std::vector<int> members(n, 0);
    for (int v = 0; v < n; ++v) ++members[uf.find(v)];
    std::vector<Vec3> sum(n);
    std::vector<double> rmax(n, 0.0);
    std::vector<int> face_member(n, -1);
    for (int v = 0; v < n; ++v) {
        const int c = uf.find(v);
        sum[c] += s.points[v];
        rmax[c] = std::max(rmax[c], s.radii[v]);
        if (on_face[v]) face_member[c] = v;
    }
    for (int v = 0; v < n; ++v) {
        if (uf.find(v) != v) continue;
        id[v] = static_cast<int>(out.points.size());
        out.points.push_back(face_member[v] >= 0 ? s.points[face_member[v]] : sum[v] / members[v]);
        out.radii.push_back(rmax[v]);
    }
    // An edge is kept when it is the first (lowest index) of the edges joining its two new ends: edges bucketed by
    // their smaller new end in index order (counting sort), a stamp per larger end marks repeats inside a bucket.
    const std::size_t ne = s.edges.size();
    const std::size_t nn = out.points.size();
    std::vector<int> lo_of(ne), hi_of(ne), bucket(nn + 1, 0);
    for (std::size_t e = 0; e < ne; ++e) {
        const int a = id[uf.find(s.edges[e][0])], b = id[uf.find(s.edges[e][1])];
        lo_of[e] = std::min(a, b);
        hi_of[e] = std::max(a, b);
        ++bucket[static_cast<std::size_t>(lo_of[e]) + 1];
    }
    for (std::size_t v = 0; v < nn; ++v) bucket[v + 1] += bucket[v];
    std::vector<int> by_lo(ne);
    for (std::size_t e = 0; e < ne; ++e) by_lo[bucket[lo_of[e]]++] = static_cast<int>(e);  // bucket[v] -> end of v
    std::vector<bool> repeated(ne, false);
    std::vector<int> stamp(nn, -1);
    for (std::size_t k = 0; k < ne; ++k) {
        const int e = by_lo[k];
        int& st = stamp[hi_of[e]];
        if (st == lo_of[e]) repeated[e] = true;
        st = lo_of[e];
    }
    for (std::size_t e = 0; e < ne; ++e) {
        const int a = id[uf.find(s.edges[e][0])], b = id[uf.find(s.edges[e][1])];
        if (a == b) continue;  // the merged edge itself
        if (repeated[e]) {
            ++r.duplicate_edges;
            continue;
        }
        out.edges.push_back({a, b});
    }
    out.faces = s.faces;
    for (std::vector<int>& f : out.faces)
        for (int& v : f) v = id[uf.find(v)];
    for (int& v : r.map) v = id[uf.find(v)];
    const bool changed = merged > 0 || out.edges.size() != s.edges.size();
    r.s = std::move(out);
    r.merged_vertices += merged;
    return changed;
}

// At a vertex, two branch edges (v, a), (v, b) less than coincident_angle apart, |va| <= |vb|: (v, b) becomes (a, b)
// (dropped if that edge exists), unless a is a leaflet vertex. Repeats until no pair is left (each re-attachment moves
// an edge to a vertex farther along the common direction; bounded by 4 x edges). Returns whether anything changed.
bool reattach_coincident(Repaired& r, const AdaptationOptions& o) {
    Skeleton& s = r.s;
    const int n = static_cast<int>(s.points.size());
    const FaceMembership faces = face_membership(s);
    const std::vector<bool>& on_face = faces.on_face;
    std::set<std::pair<int, int>> links;  // the current edges; built at the first re-attachment (most inputs have none)
    bool links_built = false;
    // Per vertex its branch edges in edge order, first as one array (start[v] .. start[v + 1] in flat).
    std::vector<int> start(static_cast<std::size_t>(n) + 1, 0), flat;
    std::vector<char> branch_edge(s.edges.size(), 0);
    for (std::size_t e = 0; e < s.edges.size(); ++e)
        if (!faces.is_side(s.edges[e][0], s.edges[e][1])) {
            branch_edge[e] = 1;
            ++start[s.edges[e][0] + 1];
            ++start[s.edges[e][1] + 1];
        }
    for (int v = 0; v < n; ++v) start[v + 1] += start[v];
    flat.resize(static_cast<std::size_t>(start[n]));
    {
        std::vector<int> at(start.begin(), start.end() - 1);
        for (std::size_t e = 0; e < s.edges.size(); ++e)
            if (branch_edge[e])
                for (const int v : s.edges[e]) flat[at[v]++] = static_cast<int>(e);
    }
    const double cos_limit = std::cos(o.coincident_angle);
    std::vector<bool> removed(s.edges.size(), false);
    bool changed = false;
    long budget = 4 * static_cast<long>(s.edges.size()) + 4;
    // The pair (inc[i], inc[j]) of v's edges that would be re-attached: {near, far, e_far}, or near = -1.
    const auto pair_at = [&](int v, const int* inc, std::size_t i, std::size_t j) {
        const int ei = inc[i], ej = inc[j];
        const int wi = s.edges[ei][0] == v ? s.edges[ei][1] : s.edges[ei][0];
        const int wj = s.edges[ej][0] == v ? s.edges[ej][1] : s.edges[ej][0];
        const Vec3 di = s.points[wi] - s.points[v], dj = s.points[wj] - s.points[v];
        const double li = norm(di), lj = norm(dj);
        if (!(li > 0 && lj > 0) || !(dot(di, dj) >= cos_limit * li * lj)) return std::array<int, 3>{-1, -1, -1};
        const bool i_near = li < lj || (li == lj && wi < wj);
        const int near = i_near ? wi : wj;
        if (on_face[near]) return std::array<int, 3>{-1, -1, -1};
        return std::array<int, 3>{near, i_near ? wj : wi, i_near ? ej : ei};
    };
    // The vertices with such a pair at the start, found in parallel (most inputs have none: then nothing changes). A
    // vertex's pairs change only when its edges do: as `near` (an edge added) or `far` (an edge's other end moved to
    // near) of a re-attachment, marked in `touched`; the loop below examines only the vertices of either list, which
    // are the ones where the full scan would find a pair, so the result is the scan's.
    std::vector<char> has_pair(n, 0), touched(n, 0);
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 256), [&](const tbb::blocked_range<int>& range) {
        for (int v = range.begin(); v < range.end(); ++v) {
            const std::size_t count = static_cast<std::size_t>(start[v + 1] - start[v]);
            for (std::size_t i = 0; i < count && !has_pair[v]; ++i)
                for (std::size_t j = i + 1; j < count && !has_pair[v]; ++j)
                    has_pair[v] = pair_at(v, flat.data() + start[v], i, j)[0] >= 0;
        }
    });
    if (std::find(has_pair.begin(), has_pair.end(), 1) == has_pair.end()) return false;
    std::vector<std::vector<int>> incident(n);
    for (int v = 0; v < n; ++v) incident[v].assign(flat.begin() + start[v], flat.begin() + start[v + 1]);
    std::vector<int> queue(n);
    std::iota(queue.begin(), queue.end(), 0);
    while (!queue.empty() && budget > 0) {
        const int v = queue.back();
        queue.pop_back();
        if (!has_pair[v] && !touched[v]) continue;
        std::vector<int>& inc = incident[v];
        bool again = true;
        while (again && budget > 0) {
            again = false;
            for (std::size_t i = 0; i < inc.size() && !again; ++i)
                for (std::size_t j = i + 1; j < inc.size() && !again; ++j) {
                    const auto [near, far, e_far] = pair_at(v, inc.data(), i, j);
                    if (near < 0) continue;
                    touched[near] = touched[far] = 1;
                    if (!links_built) {
                        for (const std::array<int, 2>& e : s.edges) links.insert(std::minmax(e[0], e[1]));
                        links_built = true;
                    }
                    --budget;
                    changed = true;
                    ++r.reattached_edges;
                    inc.erase(std::find(inc.begin(), inc.end(), e_far));
                    links.erase(std::minmax(v, far));
                    std::vector<int>& at_far = incident[far];
                    if (links.count(std::minmax(near, far))) {  // (near, far) exists: the edge is a duplicate
                        removed[e_far] = true;
                        ++r.duplicate_edges;
                        at_far.erase(std::find(at_far.begin(), at_far.end(), e_far));
                    } else {
                        s.edges[e_far] = {near, far};
                        links.insert(std::minmax(near, far));
                        incident[near].push_back(e_far);
                        queue.push_back(near);
                    }
                    again = true;
                }
        }
    }
    if (!changed) return false;
    std::vector<std::array<int, 2>> kept;
    for (std::size_t e = 0; e < s.edges.size(); ++e)
        if (!removed[e]) kept.push_back(s.edges[e]);
    s.edges = std::move(kept);
    return true;
}

Repaired repair_degenerate_branches(const Skeleton& in, const AdaptationOptions& o) {
    Repaired r{in, std::vector<int>(in.points.size()), 0, 0, 0};
    std::iota(r.map.begin(), r.map.end(), 0);
    merge_short_edges(r, o);  // also drops repeated edges
    if (o.coincident_angle > 0)
        for (int round = 0; round < 8 && reattach_coincident(r, o); ++round)
            merge_short_edges(r, o);  // a re-attachment may join two coincident points
    return r;
}

}  // namespace

namespace {

// The steps of adapt_skeleton_detailed, in the order it calls them: the branches of the repaired skeleton, their
// polylines and end demands, the short-bridge collapses, the resampled output, the repair of the output.

// The repaired skeleton as the resampling sees it: leaflet membership, incidence, its branches (maximal chains of
// branch edges through joints), and per branch its polyline over the current positions and radii and its ends'
// demands.
struct BranchView {
    const Skeleton& s;
    FaceMembership faces;
    std::vector<std::vector<int>> incident;         // per vertex: its edges, in edge order
    std::vector<bool> branch_edge;                  // per edge: not a side of a leaflet face
    std::map<std::pair<int, int>, int> side_count;  // per face side (sorted vertex pair): number of faces
    std::vector<Branch> branches;                   // in order of each branch's first edge id
    // Vertex positions and radii as the branches see them: the input, then merged bridge ends after collapses.
    std::vector<Vec3> pos;
    std::vector<double> rad;
    std::vector<Polyline> polylines;                 // per branch
    std::vector<bool> pinned;                        // per vertex: a joint the resampling keeps (may be empty)
    std::vector<std::array<EndReach, 2>> end_reach;  // per branch and end
    std::vector<std::vector<int>> vertex_faces;      // per vertex: the leaflet faces on it, in face order
    std::vector<int> junction_degree;                // per vertex: its input junction's degree (may be empty)

    bool is_joint(int v) const { return incident[v].size() == 2 && !faces.on_face[v]; }
    bool is_free_branching_point(int v) const { return incident[v].size() >= 3 && !faces.on_face[v]; }
    int other(int e, int v) const { return s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0]; }
};

// The branches of the analysis's extraction (extract_branches) in the order and direction adaptation resamples and
// numbers them: by their smallest edge id e0, each chain traversing e0 from edges[e0][0] to edges[e0][1]; a closed
// ring starts and ends at its smallest vertex id.
std::vector<Branch> branches_in_resampling_order(const BranchView& view) {
    const Skeleton& s = view.s;
    const int n = static_cast<int>(s.points.size());
    std::vector<int> vertex_edge_begin(n + 1, 0), vertex_edges;
    std::vector<char> branch_edge(view.branch_edge.begin(), view.branch_edge.end()), joint(n);
    for (int v = 0; v < n; ++v) {
        vertex_edge_begin[v + 1] = vertex_edge_begin[v] + static_cast<int>(view.incident[v].size());
        vertex_edges.insert(vertex_edges.end(), view.incident[v].begin(), view.incident[v].end());
        joint[v] = view.is_joint(v);
    }
    std::vector<int> edge_branch;
    std::vector<Branch> branches =
        extract_branches(s, vertex_edge_begin, vertex_edges, branch_edge, joint, edge_branch);
    std::vector<std::pair<int, std::size_t>> order;  // (smallest edge id, branch)
    for (std::size_t bi = 0; bi < branches.size(); ++bi) {
        Branch& b = branches[bi];
        const std::size_t i0 =
            static_cast<std::size_t>(std::min_element(b.edges.begin(), b.edges.end()) - b.edges.begin());
        order.push_back({b.edges[i0], bi});
        if (b.vertices[i0] != s.edges[b.edges[i0]][0]) {  // edge i joins vertices i and i + 1
            std::reverse(b.vertices.begin(), b.vertices.end());
            std::reverse(b.edges.begin(), b.edges.end());
        }
        if (!b.ring) continue;
        b.vertices.pop_back();
        const std::ptrdiff_t k = std::min_element(b.vertices.begin(), b.vertices.end()) - b.vertices.begin();
        std::rotate(b.vertices.begin(), b.vertices.begin() + k, b.vertices.end());
        std::rotate(b.edges.begin(), b.edges.begin() + k, b.edges.end());
        b.vertices.push_back(b.vertices.front());
    }
    std::sort(order.begin(), order.end());
    std::vector<Branch> sorted;
    for (const auto& [e0, bi] : order) sorted.push_back(std::move(branches[bi]));
    return sorted;
}

// Each branch's polyline on its own (in parallel: a branch writes only its polyline).
void build_polylines(BranchView& view) {
    view.polylines.resize(view.branches.size());
    const auto build = [&](std::size_t i) {
        Polyline& pl = view.polylines[i];
        pl = Polyline{};
        const std::size_t m = view.branches[i].vertices.size();
        pl.x.reserve(m);
        pl.r.reserve(m);
        pl.s.reserve(m);
        double acc = 0;
        for (std::size_t k = 0; k < m; ++k) {
            const int v = view.branches[i].vertices[k];
            if (k > 0) acc += distance(pl.x.back(), view.pos[v]);
            pl.x.push_back(view.pos[v]);
            pl.r.push_back(view.rad[v]);
            pl.s.push_back(acc);
            const bool interior = k > 0 && k + 1 < m;
            if (interior && v < static_cast<int>(view.pinned.size()) && view.pinned[v]) pl.pinned.push_back(acc);
        }
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, view.branches.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i < range.end(); ++i) build(i);
                      });
}

// Leaflet membership, incidence, branches and their polylines over the input positions and radii (end_reach is
// left to compute_end_reach); pinned: per vertex of s, or empty.
BranchView make_branch_view(const Skeleton& s, std::vector<bool> pinned) {
    const int n = static_cast<int>(s.points.size());
    const int ne = static_cast<int>(s.edges.size());
    BranchView view{s,
                    face_membership(s),
                    std::vector<std::vector<int>>(n),
                    std::vector<bool>(ne),
                    {},
                    {},
                    s.points,
                    s.radii,
                    {},
                    {},
                    {},
                    std::vector<std::vector<int>>(n),
                    {}};
    for (int f = 0; f < static_cast<int>(s.faces.size()); ++f)
        for (const int v : s.faces[f])
            if (view.vertex_faces[v].empty() || view.vertex_faces[v].back() != f) view.vertex_faces[v].push_back(f);
    for (int e = 0; e < ne; ++e) {
        view.incident[s.edges[e][0]].push_back(e);
        view.incident[s.edges[e][1]].push_back(e);
    }
    for (int e = 0; e < ne; ++e) view.branch_edge[e] = !view.faces.is_side(s.edges[e][0], s.edges[e][1]);
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i) ++view.side_count[std::minmax(f[i], f[(i + 1) % f.size()])];
    view.branches = branches_in_resampling_order(view);
    view.pinned = std::move(pinned);
    build_polylines(view);
    return view;
}

// The outward direction of a leaflet border vertex u in the plane normal to n: from the centroid of the vertices of
// u's faces towards u (unit); zero when u has no border edge (every leaflet edge at u shared by two faces).
Vec3 border_out(const BranchView& view, int u, const Vec3& n) {
    const Skeleton& s = view.s;
    bool border = false;
    for (const int e : view.incident[u]) {
        if (view.branch_edge[e]) continue;
        const auto it = view.side_count.find(std::minmax(s.edges[e][0], s.edges[e][1]));
        border = border || (it != view.side_count.end() && it->second == 1);
    }
    if (!border) return {};
    Vec3 centroid{};
    int count = 0;
    for (const int fi : view.vertex_faces[u]) {
        const std::vector<int>& f = s.faces[fi];
        for (const int w : f) centroid += view.pos[w];
        count += static_cast<int>(f.size());
    }
    if (count == 0) return {};
    Vec3 out = view.pos[u] - (1.0 / count) * centroid;
    out -= dot(out, n) * n;
    return norm(out) > 0 ? normalized(out) : Vec3{};
}

// How far the out vertex of leaflet border vertex u stands from u along its outward direction out (unit): r_u, or, when
// the raw mesh raises fan-end caps (raised), at a fan-edge end (u on a side of 3 or more faces) the raw mesh's cap
// there (RawMeshOptions::fan_end_cap_to_border, raw_mesh.h): at least as far as the lowest of u's border neighbours
// along out (a fan end retracted from a branch, whose carrier corner roots the branch on a patch with u's cap on its
// rim).
double out_reach(const BranchView& view, int u, const Vec3& out, bool raised) {
    if (!raised) return view.rad[u];
    const Skeleton& s = view.s;
    bool fan = false;
    double lowest = std::numeric_limits<double>::infinity();
    for (const int e : view.incident[u]) {
        if (view.branch_edge[e]) continue;
        const auto it = view.side_count.find(std::minmax(s.edges[e][0], s.edges[e][1]));
        if (it == view.side_count.end()) continue;
        fan = fan || it->second > 2;
        if (it->second == 1) lowest = std::min(lowest, dot(view.pos[view.other(e, u)] - view.pos[u], out));
    }
    return fan && std::isfinite(lowest) ? std::max(view.rad[u], lowest) : view.rad[u];
}

// How far ahead along the branch direction dir (unit) the raw-mesh points of the patch a branch rooted at v stands on
// reach, from v: every vertex u of the leaflet faces at v puts its plate vertex at u +- r_u n (n = unit normal of v's
// faces; the side the branch leaves) and, on the border, its out vertices out_reach further along u's outward direction
// (away from the centroid of u's faces, in their plane). The first cross-section must lie beyond the farthest of
// them, or the hexes between the patch and that section fold there: a branch leaving a border 45 degrees off the
// leaflet's plane sees the border's out-up corners sqrt(2) r_u ahead, beyond the r of its own section.
double patch_reach(const BranchView& view, int v, const Vec3& dir, const Vec3& n, bool raised) {
    const Skeleton& s = view.s;
    const double up = std::abs(dot(n, dir));
    double reach = 0;
    for (const int f : view.vertex_faces[v]) {
        for (const int u : s.faces[f]) {
            double ahead = dot(view.pos[u] - view.pos[v], dir) + view.rad[u] * up;
            const Vec3 out = border_out(view, u, n);
            if (!(out == Vec3{})) ahead += out_reach(view, u, out, raised) * std::max(0.0, dot(out, dir));
            reach = std::max(reach, ahead);
        }
    }
    return reach;
}

// A leaflet vertex with one branch edge that the mesher roots on its plates (inside the leaflet, or border_root on
// its border): {o.root_extent x the mean length of its leaflet edges, with o.root_patch_clearance the patch's reach
// along the branch (patch_reach), else 0}; {0, 0} elsewhere (BL-joint pillows, junctions).
std::pair<double, double> root_extent(const BranchView& view, int v, const Vec3& dir, const AdaptationOptions& o) {
    const Skeleton& s = view.s;
    if (!view.faces.on_face[v] || !(o.root_extent > 0)) return {0, 0};
    int branches_at = 0, faces_at = 0;
    double length = 0, border_edge = 0;  // sum of the leaflet edges at v; the shorter border edge
    std::vector<Vec3> to_border;
    Vec3 inward{}, branch{}, normal{};
    for (int e : view.incident[v]) {
        const Vec3 d = view.pos[view.other(e, v)] - view.pos[v];
        if (view.branch_edge[e]) {
            ++branches_at;
            branch = normalized(d);
            continue;
        }
        const int c = view.side_count.at(std::minmax(s.edges[e][0], s.edges[e][1]));
        if (c > 2) return {0, 0};  // a fan edge
        if (c == 1) {
            border_edge = to_border.empty() ? norm(d) : std::min(border_edge, norm(d));
            to_border.push_back(normalized(d));
        }
        inward += normalized(d);
        length += norm(d);
    }
    const int leaflet_edges = static_cast<int>(view.incident[v].size()) - branches_at;
    if (branches_at != 1 || leaflet_edges == 0) return {0, 0};
    for (const int fi : view.vertex_faces[v]) {
        const std::vector<int>& f = s.faces[fi];
        Vec3 fn{};
        for (std::size_t i = 0; i < f.size(); ++i) fn += cross(view.pos[f[i]], view.pos[f[(i + 1) % f.size()]]);
        normal += dot(fn, normal) < 0 ? -1.0 * fn : fn;  // faces need not be oriented consistently yet
        ++faces_at;
    }
    const bool rooted =
        to_border.empty() ||
        (to_border.size() == 2 && border_root(to_border[0], to_border[1], inward, normal, branch, faces_at,
                                              border_edge > 0 ? view.rad[v] / border_edge : 0.0) != BorderRoot::None);
    if (!rooted) return {0, 0};
    const double extent = o.root_extent * length / leaflet_edges;
    if (!o.root_patch_clearance || !(norm(normal) > 0)) return {extent, 0};
    return {extent, patch_reach(view, v, dir, normalized(normal), o.raised_fan_end_caps)};
}

// Per branch end: the direction it leaves its end vertex (towards the point of its original polyline at arc length
// min(2 r, L)), and the smallest angle beta to any other branch end or leaflet edge at that vertex. The end's
// connection quad extends about gamma = beta / 2 from the branch direction (clamped to [15, 60] degrees).
void compute_end_reach(BranchView& view, const AdaptationOptions& o) {
    const Skeleton& s = view.s;
    const std::vector<Branch>& branches = view.branches;
    view.end_reach.assign(branches.size(), {});
    std::vector<std::vector<Vec3>> dirs_at(s.points.size());  // every direction leaving each vertex
    std::vector<std::array<Vec3, 2>> end_dir(branches.size());
    for (std::size_t bi = 0; bi < branches.size(); ++bi) {
        if (branches[bi].ring) continue;
        const Polyline& pl = view.polylines[bi];
        for (int side = 0; side < 2; ++side) {
            const int v = side == 0 ? branches[bi].vertices.front() : branches[bi].vertices.back();
            const double d = std::min(2.0 * view.rad[v], pl.length());
            const Vec3 target = pl.at(side == 0 ? d : pl.length() - d).first;
            end_dir[bi][side] = normalized(target - view.pos[v]);
            dirs_at[v].push_back(end_dir[bi][side]);
        }
    }
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e)
        if (!view.branch_edge[e]) {
            const int a = s.edges[e][0], b = s.edges[e][1];
            dirs_at[a].push_back(normalized(view.pos[b] - view.pos[a]));
            dirs_at[b].push_back(normalized(view.pos[a] - view.pos[b]));
        }
    const double pi = std::numbers::pi;
    // Each branch writes only its own end_reach and reads the view: in parallel, the same values for any thread count.
    const auto reach_of = [&](std::size_t bi) {
        if (branches[bi].ring) return;
        for (int side = 0; side < 2; ++side) {
            const int v = side == 0 ? branches[bi].vertices.front() : branches[bi].vertices.back();
            if (view.incident[v].size() == 1 && !view.faces.on_face[v]) continue;  // extremity: flat, no demand
            double beta = pi;
            bool skipped_self = false;
            for (const Vec3& d : dirs_at[v]) {
                if (!skipped_self && d == end_dir[bi][side]) {
                    skipped_self = true;
                    continue;
                }
                beta = std::min(beta, std::acos(std::clamp(dot(d, end_dir[bi][side]), -1.0, 1.0)));
            }
            const double gamma = std::clamp(0.5 * beta, pi / 24, pi / 3);
            const double br = view.is_free_branching_point(v) ? o.free_branching_reach : o.branching_reach;
            const auto [extent, patch] = root_extent(view, v, end_dir[bi][side], o);
            const int junction = v < static_cast<int>(view.junction_degree.size()) ? view.junction_degree[v] : 0;
            const bool may_switch =
                view.is_free_branching_point(v) && std::max(static_cast<int>(view.incident[v].size()), junction) >= 4;
            view.end_reach[bi][side] = {br, br / std::tan(gamma), extent, patch, may_switch};
        }
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, branches.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t bi = range.begin(); bi < range.end(); ++bi) reach_of(bi);
                      });
}

// AdaptationOptions::bridge_peak_ratio: on a bridge bi (both ends free branching points), the arc length of the
// interior input vertex with the largest ratio of its radius to the end radii's linear interpolation at its arc
// length, when that ratio is at least bridge_peak_ratio; -1 otherwise (off, no interior vertex, a ring or a loop).
double bridge_peak_arc(const BranchView& view, std::size_t bi, const AdaptationOptions& o) {
    const Branch& b = view.branches[bi];
    const Polyline& pl = view.polylines[bi];
    if (!(o.bridge_peak_ratio > 0) || b.ring || b.vertices.front() == b.vertices.back()) return -1;
    if (!view.is_free_branching_point(b.vertices.front()) || !view.is_free_branching_point(b.vertices.back()))
        return -1;
    double best = -1, best_ratio = o.bridge_peak_ratio;
    for (std::size_t k = 1; k + 1 < pl.x.size(); ++k) {
        if (!(pl.s[k] > 0 && pl.s[k] < pl.length())) continue;
        const double r_line = pl.r.front() + (pl.r.back() - pl.r.front()) * pl.s[k] / pl.length();
        if (pl.r[k] >= best_ratio * r_line) best = pl.s[k], best_ratio = pl.r[k] / r_line;
    }
    return best;
}

// Samples branch bi with its ends at positions xa, xb: the joints' arc parameters after bisection, smoothing and the
// turn criterion; adds the joints the criterion removed to *removed when given.
std::vector<double> resample(const BranchView& view, std::size_t bi, int min_edges, const Vec3& xa, const Vec3& xb,
                             const AdaptationOptions& o, int* removed, std::vector<double>* kept_r = nullptr,
                             bool hold_peak = true) {
    const Branch& b = view.branches[bi];
    Polyline pl = view.polylines[bi];
    std::vector<double> t;
    std::vector<Vec3> x;
    std::vector<double> r;
    std::vector<int> keep;
    std::vector<double> arc;  // per chain index: its arc parameter (the ends' included; slid joints move)
    std::array<EndReach, 2> ends = view.end_reach[bi];
    // A held pin (never yields), or -1: the bridge's radius peak, where the resampling would leave one edge.
    double held = hold_peak ? bridge_peak_arc(view, bi, o) : -1;
    if (held > 0 && !resample(view, bi, min_edges, xa, xb, o, nullptr, nullptr, false).empty()) held = -1;
    if (held > 0 && !std::binary_search(pl.pinned.begin(), pl.pinned.end(), held))
        pl.pinned.insert(std::upper_bound(pl.pinned.begin(), pl.pinned.end(), held), held);
    // A pin whose edges cannot meet the section criterion yields: the branch is sampled again without it. The
    // patch clearance yields first: a pin the repair placed (a bend, a moved root's first joint) is kept as long as
    // the rest of the criterion allows it.
    for (;;) {
        t = sample_branch(pl, min_edges, o);
        x = {xa};
        r = {pl.r.front()};
        std::vector<bool> pinned{false};
        for (const double ti : t) {
            const auto [p, ri] = pl.at(ti);
            x.push_back(p);
            r.push_back(ri);
            pinned.push_back(std::binary_search(pl.pinned.begin(), pl.pinned.end(), ti));
        }
        x.push_back(xb);
        r.push_back(pl.r.back());
        pinned.push_back(false);
        std::vector<int> stuck;
        arc = {0.0};
        arc.insert(arc.end(), t.begin(), t.end());
        arc.push_back(pl.length());
        keep = apply_turn_criterion(x, r, ends, b.ring, min_edges, pinned, o, &stuck, &pl, &arc);
        std::erase_if(stuck, [&](int k) { return t[static_cast<std::size_t>(k) - 1] == held; });
        if (stuck.empty()) break;
        if (ends[0].patch > 0 || ends[1].patch > 0) {
            ends[0].patch = ends[1].patch = 0;
            continue;
        }
        std::vector<double> yielded;
        for (const int k : stuck) yielded.push_back(t[static_cast<std::size_t>(k) - 1]);
        std::erase_if(pl.pinned,
                      [&](double p) { return std::find(yielded.begin(), yielded.end(), p) != yielded.end(); });
    }
    if (removed) *removed += static_cast<int>(x.size() - keep.size());
    std::vector<double> kept_t;
    for (std::size_t k = 1; k + 1 < keep.size(); ++k) kept_t.push_back(arc[keep[k]]);  // slid joints moved
    if (kept_r)
        for (std::size_t k = 1; k + 1 < keep.size(); ++k) kept_r->push_back(r[keep[k]]);
    return kept_t;
}

// The short-bridge collapses: classes of merged vertices (smallest id as root) and the collapsed branches.
struct Collapses {
    UnionFind classes;
    std::vector<bool> collapsed;  // per branch
    int count = 0;
    // Per vertex: a member of a pair merged by AdaptationOptions::overlap_merge_ratio (placed by overlap_ball, taking
    // part in no further collapse). Empty when none.
    std::vector<bool> overlap_merged;
};

// Short bridges between two free branching points that resampling would leave as one edge: collapse candidates,
// shortest first, as (chord, branch).
std::vector<std::pair<double, std::size_t>> bridge_candidates(const BranchView& view, const AdaptationOptions& o) {
    const Skeleton& s = view.s;
    std::vector<std::pair<double, std::size_t>> candidates;
    for (std::size_t bi = 0; bi < view.branches.size(); ++bi) {
        const Branch& b = view.branches[bi];
        const int a = b.vertices.front(), c = b.vertices.back();
        if (b.ring || a == c || !view.is_free_branching_point(a) || !view.is_free_branching_point(c)) continue;
        const double chord = distance(s.points[a], s.points[c]);
        if (!(s.radii[a] + s.radii[c] > chord)) continue;
        if (!resample(view, bi, 1, s.points[a], s.points[c], o, nullptr).empty()) continue;
        candidates.push_back({chord, bi});
    }
    std::sort(candidates.begin(), candidates.end());
    return candidates;
}

// Whether the merged vertex of members (their mean position and radius) keeps every member's centre within
// collapse_spread x its radius: a pair only when its chord < collapse_spread (r_a + r_b), and a chain of short
// bridges does not drift away from the balls at its ends.
bool merge_drifts(const Skeleton& s, const std::vector<int>& merged, const AdaptationOptions& o) {
    Vec3 mean;
    double mean_r = 0;
    for (const int v : merged) mean += s.points[v], mean_r += s.radii[v];
    mean *= 1.0 / static_cast<double>(merged.size());
    mean_r /= static_cast<double>(merged.size());
    return std::any_of(merged.begin(), merged.end(),
                       [&](int v) { return !(distance(s.points[v], mean) < o.collapse_spread * mean_r); });
}

// Whether the candidate bridge a - c (both classes single vertices, neither merged) is merged by overlap:
// (r_a + r_c) / |ac| >= overlap_merge_ratio (> 0), the merged degree (deg a + deg c - 2) at most
// overlap_merge_max_degree (unless 0), and neither end made by the skeleton repair from a larger junction (its
// junction_degree above its own degree: a split's half, a trunk's t or root).
bool overlap_merge(const BranchView& view, int a, int c, const AdaptationOptions& o) {
    const Skeleton& s = view.s;
    const double chord = distance(s.points[a], s.points[c]);
    if (!(o.overlap_merge_ratio > 0 && chord > 0 && s.radii[a] + s.radii[c] >= o.overlap_merge_ratio * chord))
        return false;
    const auto degree = [&](int v) { return static_cast<int>(view.incident[v].size()); };
    const auto repaired = [&](int v) {
        return v < static_cast<int>(view.junction_degree.size()) && view.junction_degree[v] > degree(v);
    };
    if (repaired(a) || repaired(c)) return false;
    return o.overlap_merge_max_degree <= 0 || degree(a) + degree(c) - 2 <= o.overlap_merge_max_degree;
}

// Whether the single-vertex classes a and c each have a branch (other than bridge bi and the collapsed ones) to one
// same class: merging a and c would turn that triangle into a cycle of two branches.
bool share_neighbour_class(const std::vector<Branch>& branches, const std::vector<std::vector<int>>& branches_at,
                           const std::vector<bool>& collapsed, UnionFind& classes, int a, int c, std::size_t bi) {
    const auto other_end = [&](int bj, int v) {
        const int x = classes.find(branches[bj].vertices.front()), y = classes.find(branches[bj].vertices.back());
        return x == v ? y : x;
    };
    std::vector<int> around_a;
    for (const int bj : branches_at[a])
        if (bj != static_cast<int>(bi) && !collapsed[bj]) around_a.push_back(other_end(bj, a));
    for (const int bj : branches_at[c])
        if (bj != static_cast<int>(bi) && !collapsed[bj] &&
            std::find(around_a.begin(), around_a.end(), other_end(bj, c)) != around_a.end())
            return true;
    return false;
}

// Collapses candidate bridges, shortest first, unless another branch joins the same two classes (it would become a
// loop) or the merged vertex drifts (merge_drifts). A pair of single vertices whose balls overlap by
// overlap_merge_ratio or more and that share no neighbour class merges without the drift check (placed by
// overlap_ball, also where the drift check would pass); such a pair takes part in no further collapse.
Collapses collapse_short_bridges(const BranchView& view, const AdaptationOptions& o) {
    const int n = static_cast<int>(view.s.points.size());
    const std::vector<Branch>& branches = view.branches;
    Collapses col{UnionFind(n), std::vector<bool>(branches.size(), false), 0, {}};
    if (!o.collapse_short_bridges) return col;
    UnionFind& classes = col.classes;
    const std::vector<std::pair<double, std::size_t>> candidates = bridge_candidates(view, o);
    // Branches at each vertex, and the members of each class, to look only at branches touching a class.
    std::vector<std::vector<int>> branches_at(n), members(n);
    for (std::size_t bj = 0; bj < branches.size(); ++bj)
        if (!branches[bj].ring) {
            branches_at[branches[bj].vertices.front()].push_back(static_cast<int>(bj));
            branches_at[branches[bj].vertices.back()].push_back(static_cast<int>(bj));
        }
    for (const auto& [chord, bi] : candidates) {
        const int ca = classes.find(branches[bi].vertices.front()), cc = classes.find(branches[bi].vertices.back());
        if (ca == cc) continue;
        if (members[ca].empty()) members[ca] = {ca};
        if (members[cc].empty()) members[cc] = {cc};
        bool other_link = false;  // another branch between the two classes would become a loop
        for (const int v : members[ca])
            for (const int bj : branches_at[v]) {
                if (bj == static_cast<int>(bi) || col.collapsed[bj]) continue;
                const int x = classes.find(branches[bj].vertices.front()),
                          y = classes.find(branches[bj].vertices.back());
                other_link = other_link || (x == ca && y == cc) || (x == cc && y == ca);
            }
        if (other_link) continue;
        std::vector<int> merged = members[ca];
        merged.insert(merged.end(), members[cc].begin(), members[cc].end());
        const bool held = !col.overlap_merged.empty() && (col.overlap_merged[ca] || col.overlap_merged[cc]);
        const bool by_overlap = !held && merged.size() == 2 && overlap_merge(view, ca, cc, o) &&
                                !share_neighbour_class(branches, branches_at, col.collapsed, classes, ca, cc, bi);
        if (held || (!by_overlap && merge_drifts(view.s, merged, o))) continue;
        if (by_overlap) {
            col.overlap_merged.resize(static_cast<std::size_t>(n), false);
            col.overlap_merged[ca] = col.overlap_merged[cc] = true;
        }
        const int keep_class = std::min(ca, cc), gone = std::max(ca, cc);
        members[keep_class].insert(members[keep_class].end(), members[gone].begin(), members[gone].end());
        members[gone].clear();
        classes.unite(ca, cc);
        col.collapsed[bi] = true;
        ++col.count;
    }
    return col;
}

// The degree of each merged class's junction (its members' edges less both ends of every collapsed bridge between
// them) is raised into view.junction_degree at every member: two points of degree 3 joined by a collapsed bridge are
// one junction of degree 4 (AdaptationOptions::slide_cut_joint's gate).
void mark_merged_junctions(BranchView& view, Collapses& col) {
    const int n = static_cast<int>(view.s.points.size());
    std::vector<int> degree(static_cast<std::size_t>(n), 0);
    for (int v = 0; v < n; ++v) degree[col.classes.find(v)] += static_cast<int>(view.incident[v].size());
    for (std::size_t bi = 0; bi < view.branches.size(); ++bi)
        if (col.collapsed[bi]) degree[col.classes.find(view.branches[bi].vertices.front())] -= 2;
    view.junction_degree.resize(static_cast<std::size_t>(n), 0);
    for (int v = 0; v < n; ++v)
        view.junction_degree[v] = std::max(view.junction_degree[v], degree[col.classes.find(v)]);
}

// Merged classes: mean position and radius of their members (for a pair: the midpoint); a pair merged by overlap
// (overlap_merge_ratio): overlap_ball. The branches attached to
// them start from the merged vertex: their polylines and end directions are rebuilt.
void move_merged_classes(BranchView& view, Collapses& col, const AdaptationOptions& o) {
    if (col.count == 0) return;
    mark_merged_junctions(view, col);
    const Skeleton& s = view.s;
    const int n = static_cast<int>(s.points.size());
    std::vector<Vec3> sum_x(n);
    std::vector<double> sum_r(n, 0.0);
    std::vector<int> count(n, 0);
    for (int v = 0; v < n; ++v) {
        const int c = col.classes.find(v);
        sum_x[c] += s.points[v], sum_r[c] += s.radii[v], ++count[c];
    }
    std::vector<int> partner(static_cast<std::size_t>(n), -1);  // per vertex of an overlap-merged pair: the other
    for (int v = 0; v < static_cast<int>(col.overlap_merged.size()); ++v)
        if (col.overlap_merged[v] && col.classes.find(v) != v)
            partner[v] = col.classes.find(v), partner[partner[v]] = v;
    for (int v = 0; v < n; ++v) {
        const int c = col.classes.find(v);
        if (count[c] < 2) continue;
        const int w = partner[c];
        const OverlapBall ball = w < 0 ? OverlapBall{sum_x[c] / count[c], sum_r[c] / count[c]}
                                       : overlap_ball(s.points[c], s.radii[c], s.points[w], s.radii[w]);
        view.pos[v] = ball.centre;
        view.rad[v] = ball.radius;
    }
    build_polylines(view);
    compute_end_reach(view, o);
}

// The output skeleton's kept vertices (every non-joint, merged classes once at their smallest id, plus ring
// anchors), its leaflet edges and faces; new_id: per repaired vertex, its output id or -1.
void write_kept_vertices(const BranchView& view, Collapses& col, std::vector<int>& new_id, Skeleton& out) {
    const Skeleton& s = view.s;
    const int n = static_cast<int>(s.points.size());
    std::vector<bool> kept(n, false);
    for (int v = 0; v < n; ++v) kept[v] = !view.is_joint(v) && col.classes.find(v) == v;
    for (const Branch& b : view.branches)
        if (b.ring) kept[b.vertices.front()] = true;
    new_id.assign(n, -1);
    for (int v = 0; v < n; ++v) {
        if (!kept[v]) continue;
        new_id[v] = static_cast<int>(out.points.size());
        out.points.push_back(view.pos[v]);
        out.radii.push_back(view.rad[v]);
    }
    const auto id_of = [&](int v) { return new_id[col.classes.find(v)]; };
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e)
        if (!view.branch_edge[e]) out.edges.push_back({id_of(s.edges[e][0]), id_of(s.edges[e][1])});
    out.faces = s.faces;
    for (std::vector<int>& f : out.faces)
        for (int& v : f) v = id_of(v);
}

// Every branch not collapsed, resampled between its kept ends, appended to out (new joints and edges in branch
// order). Two branches never both become one edge between the same two vertices. The resampling runs in parallel
// with each branch's min_edges as the edges before it decide it (a link that some earlier branch of the loop turns into
// one edge is not known yet); the serial pass that appends them samples again, with the right min_edges, the rare
// branch whose min_edges the earlier ones changed: the same result as sampling one branch after the other.
void write_resampled_branches(const BranchView& view, Collapses& col, const std::vector<int>& new_id,
                              const AdaptationOptions& o, AdaptationResult& result) {
    Skeleton& out = result.skeleton;
    const auto id_of = [&](int v) { return new_id[col.classes.find(v)]; };
    std::set<std::pair<int, int>> single_edge_links;  // to never emit two edges joining the same two vertices
    for (const std::array<int, 2>& e : out.edges) single_edge_links.insert(std::minmax(e[0], e[1]));
    const std::size_t nb = view.branches.size();
    struct Sampled {
        int a = -1, c = -1, min_edges = 1, removed = 0;
        std::vector<double> t, r;
    };
    std::vector<Sampled> sampled(nb);
    const auto min_edges_of = [&](const Sampled& b, bool ring) {
        if (ring || b.a == b.c) return 3;
        return single_edge_links.count(std::minmax(b.a, b.c)) ? 2 : 1;
    };
    for (std::size_t bi = 0; bi < nb; ++bi) {
        if (col.collapsed[bi]) continue;
        sampled[bi].a = id_of(view.branches[bi].vertices.front());
        sampled[bi].c = id_of(view.branches[bi].vertices.back());
        sampled[bi].min_edges = min_edges_of(sampled[bi], view.branches[bi].ring);
    }
    const auto sample = [&](std::size_t bi) {
        Sampled& b = sampled[bi];
        b.removed = 0;
        b.r.clear();
        b.t = resample(view, bi, b.min_edges, out.points[b.a], out.points[b.c], o, &b.removed, &b.r);
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb, 16), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t bi = range.begin(); bi < range.end(); ++bi)
            if (!col.collapsed[bi]) sample(bi);
    });
    for (std::size_t bi = 0; bi < nb; ++bi) {
        if (col.collapsed[bi]) continue;
        Sampled& b = sampled[bi];
        const int min_edges = min_edges_of(b, view.branches[bi].ring);
        if (min_edges != b.min_edges) {
            b.min_edges = min_edges;
            sample(bi);
        }
        result.turn_removed_joints += b.removed;
        if (b.t.empty()) single_edge_links.insert(std::minmax(b.a, b.c));
        int prev = b.a;
        for (std::size_t k = 0; k < b.t.size(); ++k) {
            const Vec3 p = view.polylines[bi].at(b.t[k]).first;
            const int v = static_cast<int>(out.points.size());
            out.points.push_back(p);
            out.radii.push_back(b.r[k]);
            out.edges.push_back({prev, v});
            prev = v;
        }
        out.edges.push_back({prev, b.c});
    }
}

// Resampled first edges can still be coincident (two branches whose first joints lie in one direction): the same
// repair on the output (a re-attachment that joins two coincident points is followed by their merge). Returns the map
// from the resampled output's vertices to the repaired ones (empty when coincident_angle is off) and adds the repair
// counts to `repaired`.
std::vector<int> repair_output(Skeleton& out, Repaired& repaired, const AdaptationOptions& o) {
    if (!(o.coincident_angle > 0)) return {};
    std::vector<int> identity(out.points.size());
    Repaired post{std::move(out), std::move(identity), 0, 0, 0};
    std::iota(post.map.begin(), post.map.end(), 0);
    for (int round = 0; round < 8; ++round) {
        const bool moved = reattach_coincident(post, o);
        if (!merge_short_edges(post, o, true) && !moved) break;
    }
    out = std::move(post.s);
    repaired.reattached_edges += post.reattached_edges;
    repaired.duplicate_edges += post.duplicate_edges;
    repaired.merged_vertices += post.merged_vertices;
    return std::move(post.map);
}

}  // namespace

OverlapBall overlap_ball(const Vec3& a, double ra, const Vec3& b, double rb) {
    const double d = distance(a, b);
    if (!(d > 0)) return {a, std::max(ra, rb)};
    const Vec3 u = (b - a) / d;
    const double lo = std::min(-ra, d - rb), hi = std::max(ra, d + rb);  // the union's span along u, from a
    return {a + (0.5 * (lo + hi)) * u, 0.5 * (0.5 * (hi - lo) + std::max(ra, rb))};
}

Skeleton adapt_skeleton(const Skeleton& s, const AdaptationOptions& o, const std::vector<int>& pinned,
                        const std::vector<int>& junction_degree) {
    return adapt_skeleton_detailed(s, o, pinned, junction_degree).skeleton;
}

AdaptationResult adapt_skeleton_detailed(const Skeleton& input, const AdaptationOptions& o,
                                         const std::vector<int>& pinned, const std::vector<int>& junction_degree) {
    validate(input, o);
    Repaired repaired = repair_degenerate_branches(input, o);
    std::vector<bool> pinned_repaired;  // in the numbering of repaired.s
    for (const int v : pinned) {
        if (v < 0 || v >= static_cast<int>(repaired.map.size()) || repaired.map[v] < 0) continue;
        pinned_repaired.resize(repaired.s.points.size(), false);
        pinned_repaired[repaired.map[v]] = true;
    }
    BranchView view = make_branch_view(repaired.s, std::move(pinned_repaired));
    // A vertex the degenerate repair merged takes the largest junction degree of its members.
    for (std::size_t v = 0; v < junction_degree.size() && v < repaired.map.size(); ++v) {
        const int w = repaired.map[v];
        if (w < 0 || junction_degree[v] <= 0) continue;
        view.junction_degree.resize(repaired.s.points.size(), 0);
        view.junction_degree[w] = std::max(view.junction_degree[w], junction_degree[v]);
    }
    compute_end_reach(view, o);
    Collapses col = collapse_short_bridges(view, o);
    move_merged_classes(view, col, o);

    AdaptationResult result;
    std::vector<int> new_id;
    write_kept_vertices(view, col, new_id, result.skeleton);
    write_resampled_branches(view, col, new_id, o, result);
    const std::vector<int> post_map = repair_output(result.skeleton, repaired, o);
    result.collapsed_bridges = col.count;
    result.merged_vertices = repaired.merged_vertices;
    result.duplicate_edges = repaired.duplicate_edges;
    result.reattached_edges = repaired.reattached_edges;
    result.vertex_map.resize(input.points.size());
    for (std::size_t v = 0; v < input.points.size(); ++v) {
        const int w = new_id[col.classes.find(repaired.map[v])];
        result.vertex_map[v] = w < 0 || post_map.empty() ? w : post_map[w];
    }
    return result;
}

}  // namespace mesohex
