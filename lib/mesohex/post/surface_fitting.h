#pragma once
// Surface fitting and geometry optimization: the local-global loop (reference-notes §12.6, paper §4 / [LSVT15]).
// Eigen stays in surface_fitting.cpp behind the SurfaceFitter class.
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

// The domain surface, as a callback: closest[i] = the point of the surface closest to in[i]. The pipeline plugs in
// CGAL's AABB tree; tests use analytic surfaces. May be called from one thread at a time (never concurrently).
struct SurfaceProjector {
    using ClosestPoints = std::function<void(const std::vector<Vec3>& in, std::vector<Vec3>& closest)>;
    SurfaceProjector() = default;
    SurfaceProjector(ClosestPoints f) : closest_points(std::move(f)) {}  // NOLINT: implicit, {lambda} reads well
    ClosestPoints closest_points;
    // Optional, for the two-sided fit: points sampled on the surface, and the closest point of a triangle mesh (the
    // current boundary of the hex mesh) to every sample: hits[i] = {triangle id, point}. When both are set, the
    // fitter also pulls the boundary toward the samples it does not yet reach (creases, tips, rims).
    std::vector<Vec3> samples;
    struct Hit {
        int triangle = -1;
        Vec3 point;
    };
    std::function<void(const TriangleMesh& boundary, std::vector<Hit>& hits)> samples_to_boundary;
    // Optional, for the facing test (FitOptions::facing_limit): the surface's outward unit normal at every point the
    // last closest_points call returned (same order), and at every sample. Leave unset / empty when the surface's
    // orientation is not known: the test is then skipped.
    std::function<void(std::vector<Vec3>& normals)> last_closest_normals;
    std::vector<Vec3> sample_normals;
};

struct FitProgress {
    int iteration = 0;          // 1-based, the step just done
    double energy = 0;          // least-squares residual |A X - b|^2 at the start of the step
    double max_move = 0;        // largest vertex displacement of the step / mean target length
    long inverted = 0;          // hexes with scaled Jacobian <= 0 after the step
    double sj_min = 0;          // after the step
    double step_fraction = 1;   // mean over the vertices of the accepted part of their move: 1 = full global step,
                                // < 1 = some moves damped by the inversion guard, 0 = no vertex could move (stalled)
    long held_vertices = 0;     // vertices whose move the guard damped or cancelled in this step
    int solver_iterations = 0;  // CG iterations of the global step (0 with the direct solver)
};

enum class FitSolver {
    Auto,               // Direct up to 1000 vertices, ConjugateGradient above (faster from a few thousand on)
    Direct,             // sparse LDL^T of A^T A (Eigen SimplicialLDLT), factorized once; exact global step
    ConjugateGradient,  // A^T A assembled once; Jacobi-preconditioned CG warm-started at the current positions
};

struct FitOptions {
    double lambda = 3.0;           // weight of the boundary-to-surface rows, relative to the edge rows (reference: 1),
    double lambda_final = 30.0;    // raised x 3 each time the fit settles while the surface gap (the largest
    double gap_goal = 0;           // vertex-to-surface or sample-to-boundary distance) is above gap_goal
                                   // (fit_to_surface; a looser pull keeps better hexes)
    int max_iterations = 300;      // iteration cap of fit_to_surface
    double move_tolerance = 1e-5;  // stop when the largest move of a step < move_tolerance x mean target length ...
    double energy_tolerance = 1e-3;      // ... or when the energy decreased by less than this relative amount over the
    int energy_window = 10;              //     last energy_window steps
    int refresh_every = 5;               // recompute the edge target lengths from the current geometry every this many
                                         // steps (then one refactorization); 0 = never (the matrix is factorized once)
    FitSolver solver = FitSolver::Auto;  // global step: direct (small meshes) or CG (see below)
    int cg_max_iterations = 100;         // ConjugateGradient: iteration cap per global step ...
    double cg_tolerance = 3e-2;    // ... and residual reduction per step (per coordinate, relative to the residual
                                   // of the warm start; a fixed point has residual 0 and does not move)
    bool guard_inversions = true;  // per hex: damp the moves of the vertices of a hex the step would invert or collapse
    int max_backtracks = 6;        // halvings of a vertex's move before it stays where it was for this step
    double sj_guard = 0.2;         // no step may take a hex below min(floor_fraction x its SJ before the fit,
    double max_sj_drop = 0.1;      // sj_guard - max_sj_drop), nor invert a hex that was not inverted
    double floor_fraction = 0.5;   // (see sj_guard; dimensionless)
    double two_sided_weight = 0.5;  // pull toward the surface samples (SurfaceProjector::samples), 0 = one-sided ...
    int two_sided_start = 50;       // ... from this step on (the boundary first settles on the surface), matching
    int two_sided_every = 2;        // the samples with the boundary again every this many steps
    double reach = 0.5;             // a boundary target is at most reach x Lbar from its vertex (0 = no limit)
    // Scaled Jacobian (dimensionless, 0 = off): from the first two-sided step on, the guard's floor of every hex is
    // raised to min(its SJ at that step, two_sided_floor) where that is above its own floor (sj_guard): the pull
    // towards surface samples the boundary does not reach (corners of the domain far from the raw mesh, the far side of
    // a thin part) may then not take a hex below it, while the one-sided phase before keeps the lower floor.
    double two_sided_floor = 0;
    // Cosine (dimensionless): a closest surface point whose outward normal is more than acos(facing_limit) (120
    // degrees) away from the boundary vertex's outward normal lies on a part of the surface that faces the other
    // way (the other sheet across a sharp fold, the other side of a thin slab): it does not pull the vertex in that
    // step, and a sample whose normal is that far from its boundary triangle's does not pull the triangle. < -1: off
    // (also when the projector gives no normals).
    double facing_limit = -0.5;
    bool fit_boundary = true;  // false: boundary rows pull to the CURRENT boundary positions (optimize inside
                               // the skin; the projector is then not called)
    std::vector<bool> frozen;  // optional, per vertex: never moved (still in the solve)
    std::function<void(const FitProgress&)> progress;  // called after every step, from the calling thread
};

struct FitResult {
    HexMesh mesh;
    int iterations = 0;
    bool converged = false;  // stopped by the progress rule (not by the cap)
    long inverted_before = 0, inverted_after = 0;
    double sj_min_before = 0, sj_min_after = 0;
    double energy = 0;        // last energy
    double max_distance = 0;  // largest distance of a boundary vertex to the surface at the end (0 if !fit_boundary)
    // The largest distance of a surface sample to the boundary at the first two-sided step (model units; -1 when no
    // two-sided step ran): how far the domain reaches past what the one-sided phase covered.
    double uncovered = -1;
};

// The local-global optimizer. Builds the target lengths and the normal matrix A^T A once and factorizes it
// (SimplicialLDLT; symbolic analysis once per connectivity, numeric factorization again only when the targets are
// refreshed, every refresh_every steps), then every step(): local step (parallel over edges, deterministic) computes
// the ideal direction of every oriented edge from the corner normals of its hexes and the surface target of every
// boundary vertex; global step solves A^T A X = A^T b for the 3 coordinates with the stored factorization; then the
// inversion guard. With FitSolver::ConjugateGradient (the default above 1000 vertices: the sparse Cholesky factor of a
// 3D mesh Laplacian grows superlinearly; at 56 k hexes the factorization takes over a minute and one solve ~0.3 s), the
// matrix is assembled once (again per refresh) and each global step runs a warm-started Jacobi-preconditioned CG
// until the residual dropped by cg_tolerance: a fixed point of the exact iteration is one of this iteration too.
// Rows of A: per edge e = (1, 2) and orientation, w_e (x2 - x1) = Lbar d (d = ideal unit direction at the start vertex,
// w_e = Lbar / t_e, t_e = mean length of the edges parallel to e in the hexes around e, Lbar = mean t_e); per boundary
// vertex, lambda x_v = lambda c_v (c_v = closest surface point); per vertex, 1e-8 x_v = 1e-8 x_v^current (keeps the
// system positive definite on any connectivity; does not move a fixed point).
// Preconditions: a valid hex mesh (indices in range; InvalidInput otherwise), lambda > 0.
class SurfaceFitter {
public:
    SurfaceFitter(const HexMesh& mesh, const SurfaceProjector& surface, const FitOptions& options = {});
    ~SurfaceFitter();
    SurfaceFitter(const SurfaceFitter&) = delete;
    SurfaceFitter& operator=(const SurfaceFitter&) = delete;

    // One local-global iteration (with the inversion guard). Returns its progress record.
    FitProgress step();
    const std::vector<Vec3>& points() const;
    const HexMesh& mesh() const;
    long inverted() const;
    double sj_min() const;
    double mean_target_length() const;
    // At the last step's start: the largest distance of a boundary vertex to its closest surface point and (two-sided
    // fit) of a surface sample to the boundary.
    double surface_gap() const;
    // The largest sample-to-boundary distance of the first two-sided matching; -1 before it.
    double first_sample_gap() const;
    // Changes the weight of the boundary rows (refactorizes / reassembles the matrix). lambda > 0.
    void set_lambda(double lambda);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Runs SurfaceFitter::step() until the progress rule holds (max move < move_tolerance x Lbar, or
// E[k - W] - E[k] <= energy_tolerance x E[k - W] with W = energy_window) or max_iterations, or until a step had to be
// given up entirely (stalled: not converged); then measures the distance of the boundary vertices to the surface.
FitResult fit_to_surface(const HexMesh& mesh, const SurfaceProjector& surface, const FitOptions& options = {});

}  // namespace mesohex
