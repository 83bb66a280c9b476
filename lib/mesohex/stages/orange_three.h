#pragma once
// The best orange axis of three directions (sphere_partition's degree-3 case, issue 19 item 1).
//
// An orange around a unit axis a has one lune per direction between the poles +a and -a, split at the bisectors of
// consecutive azimuths (sphere_partition.cpp, build_orange). Its score, as partition_sphere's quality_score gives it
// for the built orange, is the minimum of 12 smooth pieces, 4 per direction i (sorted position k, gaps g_before and
// g_after to its neighbours in azimuth, which sum with the third gap to 2 pi):
//   - the lune width w = (g_before + g_after) / 2 (the angle at both poles) and pi - w, in radians;
//   - the margin term (pi / 2) asin(cos(e_i) sin(min(g / 2, pi / 2))) / bound_i for g = g_before and g = g_after,
//     e_i the elevation asin(d_i . a), bound_i half the angle from d_i to its nearest other direction (the margin
//     ratio counts as 90 degrees when the direction is as far from its lune's sides as that neighbour allows).
// The score is a max-min over a 2-DOF axis: at a maximum two or three pieces are equal (a ridge where two meet with
// opposite slopes, or a vertex where three meet), so a sequential linear program with a trust region, which solves
// the pieces' linearisation exactly, converges there (quadratically at a vertex) where a pattern search stops on the
// first ridge it meets.
#include <array>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex {

struct OrangeAxisThree {
    Vec3 axis;              // unit
    double score = -1e300;  // the orange's score around `axis` (radians; <= 0: no valid orange there)
};

// The score above of the orange of three unit directions `d` around the unit `axis`, with `bound` as above (radians,
// > 0). Equal to partition_sphere's exact orange evaluation up to rounding (~1e-15).
double orange_score_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound, const Vec3& axis);

// Maximises orange_score_three from each of `starts` (unit axes; a start whose score is <= 0 is still followed) and
// returns the best end point (the first of equal scores). Each run is bounded (100 linear programs); the steps stop
// when the trust region falls below 1e-9 rad or the linearisation promises less than 1e-13. Deterministic, no
// allocation beyond the result. Cost: about 20-60 score evaluations per start.
OrangeAxisThree best_orange_axis_three(const std::array<Vec3, 3>& d, const std::array<double, 3>& bound,
                                       const std::vector<Vec3>& starts);

}  // namespace mesohex
