#pragma once
// Quality smoothing: local, per-vertex optimization of the scaled Jacobian (Gauss-Seidel sweeps), with the boundary
// vertices sliding on the domain surface. Runs after the fit on a mesh without inverted hexes; never inverts a hex.
#include <functional>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct SmoothProgress {
    int sweep = 0;   // sweeps done
    long moves = 0;  // vertex moves accepted in that sweep
};

struct SmoothOptions {
    int max_sweeps = 20;        // Gauss-Seidel sweeps over the vertices (ascending ids; a vertex is tried again only
    double min_gain = 1e-4;     // after a vertex of its hexes moved); stops earlier when the moves of a sweep lower
                                // the energy of the vertices tried by less than this relative amount
    double target_sj = 0.6;     // frame values below this are penalized strongly (weight below_weight)
    double below_weight = 20;   // weight of max(0, target_sj - q)^2 against (1 - q)^2 (dimensionless)
    double skip_above = 0.97;   // vertices whose hexes all have scaled Jacobian above this are not moved
    bool move_boundary = true;  // boundary vertices slide on the surface (needs `project`); false: fixed
    double feature_angle = 35;  // degrees: a boundary vertex whose boundary quad normals deviate more than this from
                                // their mean (crease, corner, rim) stays fixed
    double max_slide = 0.5;     // a boundary vertex moves at most this x its mean edge length from its start
    double max_gap = 0;         // > 0: a boundary move is kept only if the chord gap at the vertex (the largest
                                // distance to the surface of the centroids and edge midpoints of its boundary quads)
                                // stays <= max(this, before)
    // Max-min pass, after the sweeps: the sweeps lower a sum over all frames and stall where the worst hex needs a
    // move that lowers some other frame first (the fan of quads at a high-valence boundary vertex: its ring has to
    // turn as a whole). While a round raises something: every vertex of a hex below worst_below, then the 8 vertices
    // of every such hex together (worst hex first), move along the descent direction of the soft minimum
    // sum exp(-worst_sharpness (q - m)) over the frames q of the hexes around them (m = their smallest frame value),
    // boundary vertices tangentially and projected; the best of 10 step lengths is kept if it raises m by more than
    // 1e-5 and passes the slide and gap limits (worst_max_slide, worst_gap_factor). 0 = off.
    double worst_below = 0.6;
    int worst_rounds = 100;            // at most this many rounds of the max-min pass
    double worst_sharpness = 40;       // k of the soft minimum sum exp(-k (q - m)) (dimensionless)
    bool worst_moves_features = true;  // feature boundary vertices (fixed in the sweeps) may slide in that pass too:
    double worst_crease_angle = 70;    // degrees: that pass moves a boundary vertex with two sharp boundary edges
                                       // (normals of their quads more than this apart) only along them, and never one
                                       // with one or more than two (corner); the gap limits hold the others
    int resweeps = 5;                  // after that pass, at most this many sweeps more from the vertices near its
                                       // moves (they may have lowered good hexes there)
    double worst_max_slide = 1.0;      // that pass's max_slide
    double worst_gap_factor = 2;       // that pass's limit at a vertex of the chord gap and of the cover gap (the
                                       // distance of the surface points around it at the start to its boundary quads:
                                       // the boundary must not slide off a bump or tip): max(this x max_gap, the gap
                                       // there at the start of the smoothing). The few vertices it moves may slide
                                       // where the boundary is coarse for the curvature, never farther than the fit
                                       // left them
    // Optional: the domain's unit outward normal at the surface point closest to a point. With it (and `project`),
    // sharpness must be a convex feature of the domain too: take, for every boundary quad, the domain's point closest
    // to its centroid at the start and the normal there; two quads are a convex-sharp pair when those normals are more
    // than the angle apart and each point lies below the other's tangent plane. A boundary vertex is a feature in the
    // sweeps only if some pair of its quads is (feature_angle), and a boundary edge is sharp for the max-min pass only
    // if its two quads are (worst_crease_angle). Why: a fit can leave the boundary folded where the domain is smooth,
    // and along a concave crease of the domain the boundary folds back and forth; with every such vertex fixed the
    // worst hexes there cannot be raised (docs/tuning.md). A concave crease is then rounded off within the gap limits
    // instead; convex ones (a CAD edge, a cube's corner) stay. Without it, the quads' own normals alone decide.
    std::function<Vec3(const Vec3&)> surface_normal;
    std::vector<bool> frozen;                             // optional, per vertex: never moved
    std::function<void(const SmoothProgress&)> progress;  // optional, called after every sweep
};

struct SmoothResult {
    HexMesh mesh;
    int sweeps = 0;        // sweeps done, both runs (before and after the max-min pass)
    long moves = 0;        // accepted vertex moves over all sweeps
    int worst_rounds = 0;  // rounds of the max-min pass
    long worst_moves = 0;  // accepted moves of the max-min pass (a joint move of a hex's vertices counts once)
    double sj_min_before = 0, sj_min_after = 0, sj_avg_before = 0, sj_avg_after = 0;
};

// Per vertex v (not frozen, not a feature boundary vertex, in a hex with scaled Jacobian <= skip_above): minimizes
// E(v) = sum over the hexes h at v and over their 9 Verdict frames (8 corners + centre) of
// (1 - q)^2 + below_weight * max(0, target_sj - q)^2 (q = normalized frame determinant) along its negative gradient
// (central differences; boundary vertices: tangential to the boundary, then projected onto the surface by `project`),
// trying steps of 0.2, 0.1, ... x its mean edge length. A move is kept when E(v) decreases and the smallest scaled
// Jacobian m of the hexes at v stays >= min(m before, target_sj): no hex is inverted, the worst hex at v never gets
// worse unless it stays above target_sj. Then the max-min pass (worst_below): its moves only raise the smallest
// scaled Jacobian of the hexes they touch. Sequential sweeps in ascending vertex order: deterministic.
// `project` may be empty when move_boundary is false (or then boundary vertices stay fixed).
// Preconditions: indices in range, frozen empty or one entry per vertex (InvalidInput otherwise).
SmoothResult smooth_quality(const HexMesh& mesh, const std::function<Vec3(const Vec3&)>& project,
                            const SmoothOptions& options = {});

// smooth_quality on the bad region only: the hexes with scaled Jacobian below `below_sj` (the seeds) and `rings` rings
// of hexes around them (a ring: every hex sharing a vertex with the region). The region is smoothed as a mesh of its
// own (vertices in ascending id order, so deterministic) with every vertex that a hex outside the region uses frozen:
// the vertices of hexes outside the region keep their coordinates bit for bit, and a hex outside changes in nothing.
// rings 0: only the vertices all of whose hexes are seeds can move; each ring more frees the vertices of the ring
// before. `sj`: the scaled Jacobians of `mesh` per hex (scaled_jacobians), or empty (then computed).
// Result: the whole mesh with the region's vertices moved; sweeps, moves and rounds those of the region's smoothing,
// sj_min/avg before/after those of the region's hexes. No seed (or rings < 0): the mesh unchanged, sweeps 0.
// Cost: O(#hexes x (rings + 1)) for the selection, smooth_quality's on the region. Preconditions as smooth_quality's
// (options.frozen must be empty or have one entry per vertex of `mesh`; sj empty or one entry per hex).
SmoothResult smooth_region(const HexMesh& mesh, const std::function<Vec3(const Vec3&)>& project, double below_sj,
                           int rings, const SmoothOptions& options = {}, const std::vector<double>& sj = {});

}  // namespace mesohex
