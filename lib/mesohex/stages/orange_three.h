#pragma once
// The best orange axis of three directions (sphere_partition's degree-3 case, issue 19 item 1).
//
// An orange around a unit axis a has one lune per direction between the poles +a and -a, split at the bisectors of
// consecutive azimuths (sphere_partition.cpp, build_orange). Its score here is the minimum of 12 smooth pieces, 4 per
// direction i (gaps g_before and g_after to its neighbours in azimuth, which sum with the third gap to 2 pi):
//   - the lune width w = (g_before + g_after) / 2 (the angle at both poles) and pi - w, in radians;
//   - the margin term W asin(cos(e_i) sin(min(g / 2, pi / 2))) / bound_i for g = g_before and g = g_after, e_i the
//     elevation asin(d_i . a), bound_i half the angle from d_i to its nearest other direction, W the margin weight:
//     the value of a margin ratio of 1 (the direction as far from its lune's sides as that neighbour allows).
// With W = pi / 2 this is partition_sphere's quality_score of the built orange (the score the pattern search of
// sphere_partition.cpp maximises). For three directions the smallest width term never exceeds pi / 3 (the widths sum
// to 2 pi), so with W = pi / 2 the maximum never asks a margin ratio above 2/3 and trades margins for width; W = pi / 3
// (the default of partition_sphere's three-direction orange) counts a margin ratio of 1 as the best width term.
// The solver is local: it converges to a maximum of the max-min from each start (to ~1e-9 rad), and the starts decide
// which (partition_sphere gives it the scan's three best axes).
// The score is a max-min over a 2-DOF axis: at a maximum two or three pieces are equal (a ridge where two meet with
// opposite slopes, or a vertex where three meet). A sequential linear program with a trust region solves the pieces'
// linearisation exactly (a 3-variable simplex), and a second-order correction brings steps along a ridge back onto
// it, so it converges there (quadratically at a vertex) where a pattern search stops on the first ridge it meets.
#include <array>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex {

struct OrangeAxisThree {
    Vec3 axis;              // unit
    double score = -1e300;  // the score around `axis` (radians; <= 0: no valid orange there)
};

// The score above of the orange of three unit directions `d` around the unit `axis`, with `bound` and the margin
// weight as above (radians, > 0). With margin_weight pi / 2, partition_sphere's exact orange evaluation up to
// rounding (~1e-15).
double orange_score_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound, double margin_weight,
                          const Vec3& axis);

// Maximises orange_score_three from each of `starts` (unit axes; a start whose score is <= 0 is still followed) and
// returns the best end point (the first of equal scores). Each run is bounded (100 linear programs); the steps stop
// when the trust region falls below 1e-9 rad or the linearisation promises less than 1e-13. Deterministic, no
// allocation beyond the result. Cost: about 10-30 score evaluations per start.
OrangeAxisThree best_orange_axis_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound,
                                       double margin_weight, const std::vector<Vec3>& starts);

// The tabulated maxima of three directions (SpherePartitionOptions::tabled_three_start). Three unit directions are
// determined up to a rotation and a reflection (neither changes the score) by their pairwise angles: in the canonical
// frame of a pair (i, j), d_i = (1, 0, 0), d_j = (cos alpha, sin alpha, 0) and d_k above the xy-plane, with alpha the
// angle (i, j), beta (i, k), gamma (j, k). The table holds, at kOrangeTableNodes^3 nodes of (alpha, beta, gamma), each
// in [0, pi] (steps denser near 0 and pi: orange_table_angle), the axis of the best maximum found from many starts
// (orange_three_table_axis), in the canonical frame and rounded to 1/127 per coordinate; the zero vector where the node
// is no triple (the angles break the triangle inequality), two
// directions are closer than 0.02 rad, or no orange there is valid.
constexpr int kOrangeTableNodes = 13;
// The table's node angles: node a of n at orange_table_angle(a / (n - 1)) = pi (1 - cos(pi u)) / 2 (radians), denser
// near 0 and pi, where the maxima move fastest with the angles (close pairs, near-opposite pairs); its inverse.
double orange_table_angle(double u);
double orange_table_coordinate(double angle);

// The canonical-frame axis of one table node (the triple of the angles above, radians; alpha in (0, pi)) at
// `margin_weight`: the best end of best_orange_axis_three from the distinct 8 best of 400 Fibonacci axes (more than
// 0.3 rad apart as lines), with z >= 0 (an axis and its negative are one orange); the zero vector as above. What
// bench/orange_table.cpp writes into orange_three_table.inc.
Vec3 orange_three_table_axis(double alpha, double beta, double gamma, double margin_weight);

// The solver's 2 starts for `d` (unit, pairwise distinct; `bound` and `margin_weight` as above) from a table of
// `nodes`^3 axes (`table`: per node x, y, z in units of 1/127, node (a, b, c) at index (a nodes + b) nodes + c): the
// frame pair is the pair of directions whose angle has the largest sine (no table axes when it is below 0.2); the axes
// of the 8 nodes around the triple's angles, nearest node first, mapped back from the canonical frame, each kept when
// more than 0.3 rad (as a line) from every kept one; then the three pair normals, the normal of the tips' plane and
// the mean direction. Of these, the two best by score more than 0.3 rad apart (as lines); fewer when fewer have a
// valid orange (score > 0), none when none has: the caller then scans.
std::vector<Vec3> tabled_orange_starts_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound,
                                             double margin_weight, const signed char* table, int nodes);

// The committed table (orange_three_table.inc: kOrangeTableNodes^3 nodes, margin weight pi / 3), 3 values per node.
const signed char* orange_three_table();

// The same with the committed table.
std::vector<Vec3> tabled_orange_starts_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound,
                                             double margin_weight);
}  // namespace mesohex
