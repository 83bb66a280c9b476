#pragma once
// Quad partition of the unit sphere with one quad per given direction (paper step 3, the "connection surface" at a
// branching point; VKB21's convex hull + valence-4 remeshing + dual, made robust).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex {

struct SpherePartition {
    std::vector<Vec3> points;               // unit vectors (the connection-surface vertices, centre at the origin)
    std::vector<std::array<int, 4>> quads;  // quads[i] belongs to direction i; counter-clockwise seen from outside
};

struct SpherePartitionOptions {
    // Directions closer than this to a common great circle (max |dot(d, n)| for the best-fit plane normal n) are
    // treated as planar and get the "orange" partition (lunes between two poles).
    double planarity_tolerance = 0.05;
    // Four directions with a close pair (less than 90 degrees apart, every angle from one of its two directions to
    // one of the other two larger by at least close_pair_gap_deg): no candidate with a valence-2 point (two quads
    // meeting at 180 degrees) held by exactly the pair's two quads, when a valid candidate without one exists (the
    // hull path's candidates are then all built and relaxed, whatever the oranges score). An orange puts such a point
    // in the gap between every two consecutive directions, so in the crotch of the pair; the hull path's partitions
    // there have a valence-3 point instead (docs/junctions.md, "The shared curve skeletons"). false: the best score.
    bool no_flat_point_in_close_pair = false;
    double close_pair_gap_deg = 10;  // degrees (see no_flat_point_in_close_pair)
    // Three directions: the orange candidate is the one around the axis that maximises min(width terms, 60 degrees x
    // margin ratio), found by the solver of orange_three.h from the scan's three best axes: the margins count against
    // the most a width term can be for three directions (quality_score's 90 degrees would trade margins for width).
    // Measured in docs/performance.md, "Seventh pass". false: the pattern search on quality_score from the same axes
    // (three refined oranges compete), as for n >= 4.
    bool exact_three_orange = true;
    // Hull candidates with the same geometry (real vertices at the same points joined by the same arcs; they differ
    // only in where valence-2 points sit on those arcs, e.g. the three ways to double two opposite edges of the
    // tetrahedron at n = 4) share one brief relaxation, the one that ranks them (the first of them is relaxed, the
    // others take its vertex positions); the 2 long relaxations go to the best candidate of each of the 2 best
    // geometries (of the one geometry at n = 4, its 2 best candidates). Measured in docs/performance.md, "Ninth pass".
    // false: every candidate relaxed briefly on its own, the 2 best candidates long.
    bool shared_hull_relaxation = true;
    // true: the long relaxations of the hull candidates (the 2 chosen after the brief ones) move each real vertex along
    // its local energy gradient (forward differences; a line search: the vertex's step, its half and quarter, then
    // twice the step while better), at most 20 sweeps: a quarter fewer energy evaluations than the 8-direction
    // pattern (at most 100 sweeps) and higher quality_score on average at degrees 4 and 5 and in close-pair pairs,
    // but the finished random set loses 2 of the 11 seeds whose raw meshes change (docs/performance.md, "Tenth
    // pass"), so off by default. false: the 8-direction pattern, as in the brief relaxations.
    bool gradient_long_relaxation = false;
    // Three directions with exact_three_orange: the solver starts from up to 3 of the 8 best axes of a coarse scan (60
    // Fibonacci axes, about 0.3 rad apart, and the same extra axes), each more than 0.5 rad from every better one
    // (so in distinct basins), instead of the 3 best of 400 axes (often neighbours in one basin): the scan costs about
    // half, and the starts reach a higher maximum about as often as a lower one (docs/performance.md, "Twelfth pass").
    // false: the 400-axis scan's 3 best axes.
    bool coarse_three_scan = true;
    // Three directions with exact_three_orange: the solver climbs from 2 starts taken from a table instead of a scan
    // (orange_three.h, tabled_orange_starts_three: the tabulated maxima at the 8 nodes of pairwise angles around the
    // triple's, the pair normals, the tips' plane normal and the mean, the 2 best more than 0.3 rad apart), the scan
    // only when none of them gives a valid orange. Measured in docs/performance.md, "Thirteenth pass". false: the
    // scan's starts (coarse_three_scan).
    bool tabled_three_start = true;
    // true: in the long relaxations' pattern moves (gradient_long_relaxation off) each real vertex tries the 8
    // directions starting with the one it moved in last and takes the first trial that lowers the energy (not the
    // best of the 8): a third fewer instructions on branchy trees, but the raw meshes of the random set lose more than
    // they gain (docs/performance.md, "Twelfth pass"), so off. false: the best of the 8 trials.
    bool first_improving_long_relaxation = false;
};

// Preconditions: n >= 2 pairwise distinct directions, in any configuration (antipodal pairs, clusters, coplanar or
// nearly coplanar sets, all in one hemisphere). Postconditions (checked by verify_sphere_partition before returning):
//   - quads.size() == n, points.size() == n + 2, 2n edges; the quads form a closed genus-0 2-manifold
//     (V - E + F == 2), every edge in two quads with opposite orientations, no repeated vertex in a quad;
//   - each quad i is a convex spherical quad that contains direction i in its interior: every interior angle is in
//     (0, 180°] (verify accepts 180° anywhere; partition_sphere makes 180° only where it must, at vertices shared by
//     two quads: the equator vertices of the orange, the four vertices of the n = 2 "pillow" = two hemispheres,
//     digon midpoints); angles around every vertex sum to 360° and the quad areas sum to 4π (no folds, overlaps).
// Among the valid candidates (planar orange; hull -> 4-regular map -> dual -> relaxation; oranges around the best
// axes) the one maximising min(smallest angle, 180° - largest angle, 90° x min_margin_ratio) is returned; a planar
// set's orange is returned at once unless its lunes are slivers (< 15°).
// Directions need not be unit length (they are normalised); n < 2, zero, non-finite or (nearly, < 1e-7 rad)
// identical directions throw Error(InvalidInput). Deterministic: same input, same output bits; thread-safe.
// Cost: O(n^4) hull plus bounded searches; about 0.1-5 ms for n = 3..8 on our machine (1 M instructions at n = 3,
// 4 M at n = 4, 25-30 M at n = 5-6). The hull path reliably
// finds a partition up to n ~ 20; beyond (and for n > 64) the valid but poorer orange fallback may be used.
// Throws mesohex::Error(NumericalFailure) if no valid partition could be built (never crashes, never hangs).
SpherePartition partition_sphere(const std::vector<Vec3>& directions, const SpherePartitionOptions& options = {});

// {partition_sphere(directions, options with no_flat_point_in_close_pair false), the same with it true}, bit for bit,
// sharing the work both calls do (the axis oranges, the hull candidates and their relaxation).
std::array<SpherePartition, 2> partition_sphere_close_pair_pair(const std::vector<Vec3>& directions,
                                                                SpherePartitionOptions options);

// SpherePartitionOptions::no_flat_point_in_close_pair's pair: for four unit directions, the closest pair (i, j), i < j,
// when it is less than 90 degrees apart and every angle from i or j to one of the other two exceeds its angle by
// gap_deg (degrees); else {-1, -1} (also for another count of directions). Without a pair the option changes nothing.
std::array<int, 2> close_pair_of_four(const std::vector<Vec3>& d, double gap_deg);

// What partition_sphere(directions, options with planarity_tolerance 1) returns, the orange around the directions'
// best-fit plane normal, when it differs from `chosen` = partition_sphere(directions, options) (n >= 3, no close-pair
// option); std::nullopt when both calls give `chosen`. Without the second call's candidate search: the orange is
// built and scored, and compared with `chosen`'s score. Same preconditions and errors as partition_sphere.
std::optional<SpherePartition> plane_orange_alternative(const std::vector<Vec3>& directions,
                                                        const SpherePartition& chosen,
                                                        const SpherePartitionOptions& options);

// Returns an empty string when `p` satisfies every postcondition above for `directions`, else what is wrong.
std::string verify_sphere_partition(const SpherePartition& p, const std::vector<Vec3>& directions);

// Shape measures of a (verified) partition, in radians. Angles at valence-2 vertices (always 180°) are left out
// (n = 2, no such vertex: min_angle = max_angle = 180°).
struct SpherePartitionStats {
    double min_angle = 0;   // smallest interior quad angle at a vertex of valence >= 3
    double max_angle = 0;   // largest such angle
    double min_margin = 0;  // smallest angular distance from a direction to the boundary of its quad
    // Smallest ratio margin / (half the angle to the nearest other direction): 1 is the best possible, ~0.5 is good.
    double min_margin_ratio = 0;
    int max_valence = 0;  // largest number of quads around one vertex
};
SpherePartitionStats sphere_partition_stats(const SpherePartition& p, const std::vector<Vec3>& directions);

// Test hooks of the orange axis search (partition_sphere's fallback and candidates): the exact orange quality of
// `directions` (unit, n >= 3) around the unit `axis`, and whether the search's libm-free filter declares it certainly
// <= threshold (it must never do so when the exact quality is above the threshold).
namespace detail {
double orange_quality_exact(const std::vector<Vec3>& directions, const Vec3& axis);
bool orange_certainly_at_most(const std::vector<Vec3>& directions, const Vec3& axis, double threshold);
// For `directions` (n >= 3): the three best scan axes (the searches' starts), the pattern search's axes (each of
// them refined), and (n = 3) the axis of the three-direction solver that exact_three_orange uses with coarse_scan
// (SpherePartitionOptions::coarse_three_scan) (unit; the zero vector when no scan axis gives a valid orange, so the
// solver has no start).
std::vector<Vec3> scanned_orange_axes(const std::vector<Vec3>& directions);
std::vector<Vec3> searched_orange_axes(const std::vector<Vec3>& directions);
Vec3 exact_three_orange_axis(const std::vector<Vec3>& directions,
                             bool coarse_scan = SpherePartitionOptions{}.coarse_three_scan,
                             bool tabled = SpherePartitionOptions{}.tabled_three_start);
}  // namespace detail

}  // namespace mesohex
