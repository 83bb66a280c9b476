#pragma once
// Procedural meso-skeletons: small parametric shapes (plates, shells, fans, a hand, a chair, a bird, twisted strips,
// a frame, a turbine) used as test inputs and README examples. Each one is a configuration the paper supports, except
// wall, wallboth and walledge (walls docked on a plate, beyond the paper's limitation 2) and fanend (a branch on a
// fan-edge end, the paper's limitation 3, meshed after the skeleton repair retracts the fan edge):
//   - no branch on a leaflet interior vertex, no fan edge ending inside a leaflet, no branch at a fan-edge vertex;
//   - BL-joints only at convex (~90°) leaflet corners, the branch leaving roughly along the outward corner diagonal;
//   - leaflet edges about 2-4x the local radius (default radii are about 0.3 x the leaflet edge length).
// Postconditions of generate_skeleton(): radii set (> 0, one per point); faces are quads (4 distinct vertices),
// consistently oriented within each leaflet (every edge shared by exactly two faces is traversed in opposite
// directions by them); every face side is in `edges`; no duplicate edge; no unused vertex. The output depends only on
// the name and the options (deterministic).
#include <cstdint>
#include <string>
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex {

struct GeneratorOptions {
    int n = 0;                  // main resolution (meaning per shape, see generator_help()); 0 = the shape's default
    int m = 0;                  // second resolution (meaning per shape); 0 = the shape's default
    int quarter_turns = -1;     // twist, torustwist: rotation of the cross-section over the shape, in quarter turns
                                // (90°); -1 = the shape's default (2, i.e. 180°)
    double edge_length = 1.0;   // overall scale: the typical leaflet edge length
    double radius_scale = 1.0;  // multiplies every radius
    double angle_deg = 0;       // fold, vfan: the angle between the two sheets, degrees in [10, 170]; 0 = 45
};

// The valid shape names, in a fixed order: plate, box, torus, tfan, xfan, fanend, hand, chair, bird, twist, torustwist,
// dualocta, cubestar, ystar, tetrastar, turbine, wall, wallboth, walledge, walledgeboth, flange, flangeup,
// flangecorner, flangecornerup, pan, fold, vfan, airplane, wireplate, fanblock, yfan. fold, vfan, airplane and
// wireplate are thin sheets (issue 16 item 3): their sheet radius is
// 0.1 x the edge length (x radius_scale), not the 0.3 stated above.
std::vector<std::string> generator_names();

// One line describing the shape and what n, m (and quarter_turns) mean for it, with their defaults.
// Unknown name -> Error(InvalidInput) listing the valid names.
std::string generator_help(const std::string& name);

// Builds the named skeleton. Unknown name or out-of-range options -> Error(InvalidInput) (the message lists the valid
// names, or the valid range of the option). O(size of the output).
Skeleton generate_skeleton(const std::string& name, const GeneratorOptions& options = {});

// A plate with walls standing on it (docked_walls.h, beyond the paper's limitation 2): `plate` x `plate` quads of
// edge_length in the z = 0 plane (normal +z, centred on the origin); a chain of `length` edges on the grid line
// x-index `column` (default plate / 2; 0 = on the plate's border, a regular fan: the flange) from y-index `start`
// (default: centred, both ends inside; 0 = from the border); a wall of `length` x `rows` quads standing on it at +z,
// and with sides = 2 a second one at -z. Radius `radius` everywhere. Error(InvalidInput) unless the chain lies on a
// grid line x-index 0 .. plate - 1 of the plate.
struct WallPlate {
    int plate = 6, length = 2, rows = 2, column = -1, start = -1, sides = 1;
};
Skeleton make_wall_plate(const WallPlate& wall, double edge_length, double radius);

// A random skeleton of the evaluation set (`mesohex generate --random SEED`, bench/random_set.sh), deterministic in
// the seed (own 64-bit generator, no std:: distribution, so every platform gives the same skeleton). Two kinds:
//   - tree (seeds with seed % 5 != 0 and != 3): a curve tree of 1-3 branching levels, branches of 2-3 segments of
//     2.5..4.5 radii turning by up to a per-seed maximum of 20..75 degrees, branching points of degree 3-4 whose
//     children are sometimes only 20-40 degrees apart, radius 0.15..0.45 x edge_length at the root, children
//     0.55..1 x their parent, never below a third of the root's (fat, close branches);
//   - sheet (seed % 5 == 0 or 3): one quad leaflet of 2..4 x 2..4 faces, jittered, bent, and folded with probability
//     1/2 by 0..120 degrees along an interior row (sheets meeting at a sharp angle), radius 0.1..0.3 x edge_length
//     (thin), with branches: BL-joints at convex corners leaving within 15 degrees of the outward corner diagonal
//     (each corner with probability 0.4) and a branch rooted at an interior vertex within 30 degrees of the normal
//     (probability 0.5), radius 1..1.7 x the sheet's, at most 0.5 x edge_length, segments of 2.5..4.5 radii.
// Segments keep 1.1 x the sum of their radii from every segment that does not share a vertex with them or their
// branching point (else another direction is drawn, up to 12 times, then the branch ends), so distinct branches do
// not merge in the thickened domain. Only supported configurations. Postconditions as generate_skeleton(); at least
// one edge. edge_length and radius_scale as for the named shapes; n, m, quarter_turns unused. O(output^2) (tiny).
Skeleton generate_random_skeleton(std::uint64_t seed, const GeneratorOptions& options = {});

// The character family of the evaluation set (`mesohex generate --random SEED --family character`,
// `GEN_ARGS="--family character" bench/random_set.sh`), deterministic in the seed (the same generator as above, its
// own sequence of draws; generate_random_skeleton is unchanged). What real character skeletons have and the tree
// kind never makes (the armadillo's torso and neck, docs/junctions.md "A radius peak held on its bridge"): a curve
// tree with exactly two branching points A and B joined by a torso bridge whose radius bulges between them, and 2-4
// limbs leaving each end close together, fat near the torso. Ranges (lengths in edge_length units, radii also x
// radius_scale, angles in degrees):
//   - torso: end radii r_A = 0.12..0.25, r_B = 0.7..1.4 x r_A; 1-3 interior vertices, one of them the peak at
//     parameter 0.35..0.65 along the torso, radius r_P = 1.5..2.5 x max(r_A, r_B) (so the peak is 1.5..2.5 x each
//     end and x the ends' interpolation there); the others on a sine bump between ends and peak, below r_P; length
//     (chord A -> B) 1.6..3.0 x r_P; arched sideways by up to 0.15 x the length;
//   - limbs: 2-4 per end (A and B get degree 3-5), leaving 20..80 degrees off the torso's outward direction at that
//     end, at least 30 degrees apart, azimuths spread over 0.35..1 of the full turn (close together when small);
//     first-joint radius 0.6..1.1 x the end's radius, x 0.6..0.9 per further joint, never below min(r_A, r_B) / 4;
//     2-4 segments of 2.5..4.5 x the current radius, later segments turning by up to a per-seed 15..45 degrees;
//   - clearance as above (1.1 x the radii sum from non-adjacent segments), except that a limb's first segment is
//     not checked against the torso (it leaves from inside the bulge's envelope) and is always placed; a later
//     segment blocked after 12 draws ends its limb (so a limb has 1-4 segments).
// Postconditions as generate_random_skeleton; no face. O(output^2) (tiny).
Skeleton generate_character_skeleton(std::uint64_t seed, const GeneratorOptions& options = {});

// The twin-junction family of the evaluation set (`mesohex generate --random SEED --family twinjunction`,
// `GEN_ARGS="--family twinjunction" bench/random_set.sh`), deterministic in the seed (the same generator, its own
// sequence of draws). Two branching points A (vertex 0) and B closer than their radii: the balls overlap, (r_A + r_B)
// / |AB| = 1.05..1.43 (a curve skeleton's torso and shoulders, docs/junctions.md "The three shared skeletons that
// miss"), each with a pair of fat legs leaving across the bridge and leaning back. Ranges (lengths in edge_length
// units, radii also x radius_scale, angles in degrees):
//   - bridge: r_A = 0.2..0.35, r_B = 0.55..0.9 x r_A; straight, |AB| = 0.7..0.95 x (r_A + r_B), 0-2 interior vertices
//     evenly spaced with the end radii interpolated (no bulge);
//   - legs: 2 per end, at azimuths psi and psi + 180 +- 35 around the bridge axis (B's psi within 30 of A's), each
//     leaning from the plane across the bridge towards that end's outward direction (A: away from B, B: away from
//     A) by -5..20 at the root, then bending back by 25..50 more over its later segments (probability 0.7; else
//     0..10); 2-3 segments, the first 0.8..1.5 x the first-joint radius long (inside or at the junction's ball), the
//     others 2.5..4 x the current radius; first-joint radius 0.8..1.0 x the end's, x 0.7..0.9 per further joint;
//   - tail: with probability 0.6 at A and 0.5 at B, a limb leaving within 30 of the outward direction, first-joint
//     radius 0.6..0.9 x the end's, as a character limb (2-4 segments of 2.5..4.5 x the radius, turning by up to a
//     per-seed 15..40); so A and B have degree 3 or 4;
//   - clearance as the character family (1.1 x the radii sum from non-adjacent segments; a limb's first segment is
//     always placed, unchecked against the bridge; a later segment blocked after 12 draws ends its limb); radii never
//     below r_B / 4.
// Postconditions as generate_random_skeleton; no face. O(output^2) (tiny).
Skeleton generate_twin_junction_skeleton(std::uint64_t seed, const GeneratorOptions& options = {});

// "tree" or "sheet": the kind generate_random_skeleton(seed) builds.
const char* random_skeleton_kind(std::uint64_t seed);

}  // namespace mesohex
