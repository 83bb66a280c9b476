#pragma once
// Untangling: removes inverted hexes (scaled Jacobian <= 0) by minimizing a foldover-free, Winslow-type energy with
// the regularized determinant of Garanzha, Kaporin, Kudryavtseva, Protais, Ray, Sokolov ("Foldover-free maps in 50
// lines of code", 2021).
#include <functional>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct UntangleProgress {
    int round = 0;       // 1-based epsilon round
    double epsilon = 0;  // regularization of that round
    double energy = 0;   // at the end of the round
    double min_det = 0;  // smallest normalized corner determinant at the end of the round
    long inverted = 0;   // hexes with scaled Jacobian <= 0 at the end of the round
};

struct UntangleOptions {
    int max_rounds = 40;             // epsilon rounds (each ends with an L-BFGS minimization)
    int max_inner_iterations = 200;  // L-BFGS iterations per round
    double volume_weight = 0.5;      // theta: f = (1 - theta) tr(J^T J) / chi^(2/3) + theta (det^2 + 1) / chi
    int region_rings = 3;            // vertices moved: those within this many hex rings of an inverted hex; < 0 = all
    bool fix_boundary = true;        // false: boundary vertices move too, softly attached to their start position
    double boundary_attach = 10;     // weight of that attachment (x |x - x0|^2 / h^2, h = mean edge length)
    std::vector<bool> frozen;        // optional, per vertex: never moved
    int extra_rounds = 1;            // rounds run after the last inversion disappeared (improve the margin)
    double target_sj = 0;            // the hexes worked on: SJ <= target_sj (0: the inverted ones). A positive value
                                     // makes this a quality pass: the region grows around the hexes below it, and the
                                     // state kept is the one with the fewest inverted hexes, then fewest below target,
                                     // then the largest min SJ (never more inverted hexes than at the start)
    // Rounds: a quality pass (target_sj > 0) stops when none of its first quality_patience rounds ended with a min SJ
    // above the start's; it then returns the start. (The finishing keeps a quality pass only when the min SJ rose; on
    // 38 inputs of bench/finish_all.sh and 20 random seeds every pass that rose did so by round 2,
    // docs/performance.md.) It also stops, returning its best state, after quality_patience rounds in a row that did
    // not improve that state (fewest inverted, then fewest below target, then largest min SJ). <= 0: never stop early.
    int quality_patience = 5;
    std::function<void(const UntangleProgress&)> progress;  // optional, called after every round
};

struct UntangleResult {
    HexMesh mesh;
    long inverted_before = 0, inverted_after = 0;  // scaled Jacobian <= 0
    double sj_min_before = 0, sj_min_after = 0;
    int rounds = 0;
    long iterations = 0;  // L-BFGS iterations over all rounds (each evaluates the energy on the active hexes only)
    std::vector<int> inverted_hexes;  // the hexes still inverted at the end (ascending ids)
};

// If no hex has scaled Jacobian <= 0, returns the mesh unchanged (rounds = 0). Otherwise minimizes
// sum over the 8 corners and the centre frame of the active hexes of f(J), J = (corner frame) / h_hex (centre frame:
// its three axes, each a sum of 4 edges, / 4 h_hex; h_hex = the hex's mean edge length at the start; ideal = cube of
// that size; the centre frame is the scaled Jacobian's ninth, which can be negative with 8 positive corners), chi(D,
// eps) = (D + sqrt(eps^2 + D^2)) / 2 in place of det J, over the free vertices (interior vertices near inverted hexes),
// decreasing eps as in the paper, until every hex has a positive scaled Jacobian (or max_rounds). The energy is finite
// for every position, so the minimization never needs a feasible start. Reports what
// remains inverted. Deterministic (parallel evaluation with fixed reduction order).
// Preconditions: indices in range (InvalidInput otherwise).
UntangleResult untangle(const HexMesh& mesh, const UntangleOptions& options = {});

// Signed distances of points to a domain (positive outside), one per point.
using SignedDistancesFn = std::function<std::vector<double>(const std::vector<Vec3>& points)>;

// untangle, holding the vertices that lie outside a domain where it would move them farther out: while the result
// moves a vertex whose signed distance at the start is positive to a larger signed distance, those vertices are
// frozen at their start (added to options.frozen) and the pass runs again from `mesh`, at most max_reruns more times
// (the last run's result is returned as it is). Every other vertex moves as in untangle. iterations: over all runs.
// Preconditions: as untangle; signed_distances returns one value per point.
UntangleResult untangle_holding_outside(const HexMesh& mesh, UntangleOptions options,
                                        const SignedDistancesFn& signed_distances, int max_reruns);

}  // namespace mesohex
