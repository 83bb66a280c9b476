#pragma once
// Post-processing chain of a raw mesh: pad -> subdivide -> fit to the domain surface ->
// untangle (only if needed) -> final quality and two-sided Hausdorff distance to the domain. Times every stage and
// records the quality after each one. No geometry of its own; no printing.
#include <functional>
#include <string>
#include <vector>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/post/crease_wedge.h"
#include "mesohex/post/pad_inset.h"
#include "mesohex/post/pad_selection.h"
#include "mesohex/post/padding.h"
#include "mesohex/post/quality.h"
#include "mesohex/post/sheet_selection.h"
#include "mesohex/post/smoothing.h"
#include "mesohex/post/surface_fitting.h"
#include "mesohex/post/untangle.h"
#include "mesohex/surface/surface_distance.h"

namespace mesohex {

inline UntangleOptions improve_defaults() {
    UntangleOptions o;
    o.fix_boundary = false;
    o.boundary_attach = 100;
    o.region_rings = 1;
    return o;
}

inline UntangleOptions pad_improve_defaults() {
    UntangleOptions o = improve_defaults();
    o.boundary_attach = 10;
    return o;
}

struct FinishStage {
    std::string
        stage;  // "input", "pad", "pad-improve", "subdivide", "fit", "untangle", "improve", "untangle-free", "smooth",
                // "refine", "refine-smooth"
    double ms = 0;  // wall time of the stage (0 for "input")
    long vertices = 0, hexes = 0;
    double sj_min = 0, sj_avg = 0;  // scaled Jacobian after the stage
    long inverted = 0;              // hexes with scaled Jacobian <= 0 after the stage
    // The stage's iterations: fit iterations; untangling / quality passes: L-BFGS iterations over all rounds (on the
    // bad region only); smoothing: sweeps + max-min rounds; 0 for the one-pass stages (input, pad, subdivide,
    // refine). Time per hex and iteration: ms / (hexes x iterations).
    long iterations = 0;
};

struct FinishOptions {
    bool pad = true;         // add one padding layer (padding) over the raw boundary first
    PaddingOptions padding;  // default: 1 layer
    // Selective padding (pad, and padding.bare_quads empty): the regions of the raw boundary whose sharp rims already
    // land on matching sharp rims of the domain stay bare (select_bare_regions, pad_selection.h); the rest is padded.
    // On by default: where nothing matches (smooth domains) the output is the full padding's, byte for byte
    // (measurements: docs/tuning.md, "Selective padding").
    bool pad_selective = true;
    PadSelectionOptions pad_selection;  // the criterion (angles in degrees)
    // > 0 (and padding.offset_rule unset, padding.absolute_thickness 0): a boundary vertex inside the domain moves as
    // far as the domain surface along its padding direction, between the padding's own offset (thickness x shortest
    // boundary edge) and pad_to_domain x the mean boundary edge at the vertex. A raw mesh inside its domain (radii
    // 0.5 x the distance to the surface) then starts the fit with its boundary near the surface, while a raw mesh
    // already at the surface keeps a thin layer.
    double pad_to_domain = 0.25;
    // With pad_to_domain: where the layer would reach past the domain surface (a raw boundary vertex outside the
    // domain, or closer to the surface along its padding direction than the padding's own offset), the offset is
    // only as far as the surface, but at least this share of the padding's own offset: the fit then pulls a thinner
    // layer back to the surface instead of crushing a full one. 1: the padding's own offset (as without the rule).
    // Dimensionless, in (0, 1].
    double pad_overshoot_keep = 1.0;
    // Where the padding layer reaches past the domain surface (a raw mesh already at the surface: the skeleton's
    // radii are the domain's own), the layer is moved inward to end at the surface, the raw hexes beneath giving up
    // that thickness (inset_padding, pad_inset.h; one padding layer only; vertices of bare quads stay). The fit then
    // starts with the boundary on the surface instead of pulling the whole layer back through the mesh. Off: on the
    // random set it lowers the Hausdorff distance on most misses but thins poor junction hexes, fewer seeds meet
    // (measurements: docs/junctions.md, "The fit side of the random set's misses").
    bool pad_inset = false;
    PadInsetOptions pad_insetting;  // the inset's guard
    // Crease wedges before the padding (pad): a boundary edge of two hexes whose interior dihedral exceeds
    // crease_wedge.min_dihedral_deg (degrees; 0 = off) gets a wedge hex filling the gap between its two boundary quads
    // (insert_crease_wedges, crease_wedge.h): the crotch between two chunks of a junction then has three hexes instead
    // of two. Off by default (measurements: docs/junctions.md, "Crease wedges").
    CreaseWedgeOptions crease_wedge;
    // With crease_wedge: a wedge is kept only if its new vertices lie inside the domain (the raw crotch touches the
    // domain, so a wedge filling the gap beyond it is outside and the fit crushes it back).
    bool crease_wedge_inside = false;
    // With crease_wedge: the crotch cut (CreaseWedgeOptions::crotch_distance, the distance to the domain along a ray
    // from inside it): the hexes on each wedge's crease are cut, with their sheets, where the domain's crotch ends, so
    // that the wedge is only as long as the crotch (MeshOptions::crotch_wedge_pair_deg sets it).
    bool crease_wedge_crotch = false;
    // Quality pass on the padded mesh (before subdivision) when its min SJ is below pad_improve_sj (near-flat padding
    // hexes where the averaged normals of a concave junction or a high-valence vertex almost cross; the fit keeps
    // every hex near its start quality, so they would stay bad and hold the boundary off the surface): the untangling
    // energy over the hexes below it and one ring around, boundary vertices softly held (attachment 10 / h^2); kept
    // only if min SJ rises and nothing is inverted. Stage "pad-improve" (only when it ran). 0 = off. Scaled Jacobian.
    double pad_improve_sj = 0.2;
    UntangleOptions pad_improving = pad_improve_defaults();  // energy and holds of that pass
    // With pad_improve_sj: the pass's result is also dropped when it moves the boundary farther from the domain
    // (two-sided distance above max(its value before, improve_distance_budget x diagonal), as the quality pass after
    // the fit): relaxed outward where the padding already lies outside, the layer is a thickness the fit has to
    // crush back within its SJ guard (docs/sheets.md, "What pad-improve does to hand.ma"). Off by default.
    bool pad_improve_keep_distance = false;
    // With pad_improve_sj: the pass holds, at their place on the padded mesh, the vertices (boundary or interior) that
    // lie outside the domain and that it would move farther out (signed distance to the domain, from its closest
    // point and inside test, larger after the pass than before): the pass runs, those vertices are frozen, and it runs
    // again from the padded mesh, up to pad_improve_hold_rounds more times while a further one moves out; every other
    // vertex moves as without the rule. Where the padding already overshoots the domain the pass then does not thicken
    // the layer the fit has to pull back. Off by default (measurements: docs/sheets.md, "Pad-improve that holds the
    // vertices outside").
    bool pad_improve_hold_outside = false;
    int pad_improve_hold_rounds = 3;  // reruns of the pass at most (count)
    bool subdivide = true;            // refine (levels / size / min_resolution below, refinement)
    int levels = -1;             // >= 0: this many 1 -> 8 levels; < 0: from `size` when > 0, else from min_resolution
    double size = 0;             // target mean edge length (levels_for_size on the padded mesh), used when levels < 0
    double min_resolution = 16;  // levels < 0, size <= 0: at least 1 level, more (up to max_auto_levels) while the
    int max_auto_levels = 2;     // mean edge length of the padded mesh exceeds the domain's bbox diagonal / this
    // levels < 0, size <= 0: one level more (up to max_auto_levels, if the result stays within max_auto_hexes) when
    // the raw mesh's mean scaled Jacobian is below this. A raw mesh of poor hexes (short, fat branches between
    // crossings) keeps much of that shape after one level and a fit; with one more level the distortion spreads over
    // 8 times more hexes. Not when the padded mesh has inverted hexes: the untangling then has 8 times more to do and
    // a finer mesh does not undo the folds (measurements: docs/tuning.md). 0 = off.
    double poor_raw_sj_avg = 0.5;
    long max_auto_hexes = 150000;  // hexes after the extra level of poor_raw_sj_avg at most
    // > 0, levels < 0: a work budget in hexes. The levels chosen from size / min_resolution are lowered (down to 0)
    // while the subdivided mesh would have more hexes than this: the finishing's stages cost a bounded number of
    // sweeps per hex, so this bounds their time whatever the shape (`mesohex auto`, docs/skeletons.md). 0 = off.
    long max_hexes = 0;
    // Uniform: 1 -> 8 per level. Longitudinal / Radial: per level, split only the sheets of the branch chunks along
    // the branches / across them (select_branch_sheets); needs chunk_hex.
    enum class Refinement { Uniform, Longitudinal, Radial } refinement = Refinement::Uniform;
    std::vector<char> chunk_hex;  // per raw hex: 1 for a chunk hex of a branch edge (RawMesh::hex_edge on a branch)
    // Levels past fit_levels are inherited, not fitted: the fit, untangling, quality passes and smoothing run on the
    // mesh after min(levels, fit_levels) levels, and every further level is a subdivision whose boundary vertices are
    // projected onto the domain (stage "refine"): the move spreads, decreasing linearly, over inherit_rings layers of
    // vertices beneath the boundary, and is halved (up to 6 times, then dropped) at the vertices of a hex it would
    // invert or take below min(inherit_guard_sj, that hex's scaled Jacobian before). A fit from scratch costs about 8x
    // per level and decides no more of the shape (docs/performance.md). < 0: fit at the finest level.
    int fit_levels = 2;
    int inherit_rings = 6;          // layers of vertices (count)
    double inherit_guard_sj = 0.3;  // scaled Jacobian
    bool inherit_smooth = false;    // the smoothing pass (smooth) again after the inherited levels (all vertices)
    // Local smoothing after the inherited levels (unless inherit_smooth; stage "refine-smooth", when some hex is below
    // inherit_smooth_sj): the smoothing pass's sweeps and max-min rounds (smoothing) on the hexes below
    // inherit_smooth_sj and inherit_smooth_rings rings of hexes around them only (smooth_region); every other vertex
    // keeps its coordinates bit for bit. The projection's guard leaves a few hexes near its floor where the boundary
    // moved most; a whole smoothing pass at the finest level sweeps every vertex. 0 = off. Scaled Jacobian.
    double inherit_smooth_sj = 0.8;
    int inherit_smooth_rings = 2;  // rings of hexes around those below inherit_smooth_sj (count)
    bool fit = true;               // fit the boundary to the domain surface (fit_to_surface)
    FitOptions fitting;            // the fit's options (gap_goal from gap_goal_relative when > 0)
    // > 0: fitting.gap_goal (a length) = this fraction of the domain's bbox diagonal: the fit tightens its pull only
    // while the boundary is farther than that from the surface. Dimensionless.
    double gap_goal_relative = 0.005;
    bool untangle = true;                // run only when some hex has scaled Jacobian <= 0 at that point
    UntangleOptions untangling;          // the untangling after the fit (boundary fixed by default)
    bool free_boundary_fallback = true;  // if hexes stay inverted with the boundary fixed, untangle again with the
                                         // boundary vertices softly attached (untangling.boundary_attach)
    // Quality pass: when min SJ is below improve_sj after fitting, the vertices of the hexes below it and of their
    // neighbours are optimized with the untangling energy, boundary vertices softly held where they are (attachment
    // 100 / h^2: they move a small fraction of an edge); kept only if min SJ rises and no hex got inverted. 0 = off.
    double improve_sj = 0.3;
    double improve_distance_budget = 0.01;           // x the domain's diagonal: see quality_pass in finish.cpp
    UntangleOptions improving = improve_defaults();  // energy and holds of the quality pass
    // Smoothing pass (last, after a fit, on a mesh without inverted hexes): per-vertex scaled-Jacobian descent,
    // boundary vertices sliding on the domain surface (smooth_quality); never inverts a hex nor lowers the worst hex
    // at a vertex below the target.
    bool smooth = true;
    SmoothOptions smoothing;  // max_gap from smooth_gap_relative when > 0
    // > 0: smoothing.max_gap (a length) = this fraction of the domain's bbox diagonal: boundary moves keep the
    // boundary that close to the surface, or no farther than before. Dimensionless.
    double smooth_gap_relative = 0.0025;
    bool measure_distance = true;     // two-sided Hausdorff distance of the final boundary to the domain
    SurfaceDistanceOptions distance;  // sampling of the Hausdorff estimate
    // Optional: called after every stage is recorded (FinishResult::stages.back()), from the calling thread; e.g. a
    // benchmark measuring each stage's memory.
    std::function<void(const FinishStage&)> stage_done;
};

struct FinishResult {
    HexMesh mesh;                      // the final mesh
    std::vector<FinishStage> stages;   // "input" first, then every stage that ran, in order
    int domain_flipped_triangles = 0;  // triangles of the domain reversed by orient_outward (inward-facing input)
    int subdivision_levels = 0;        // levels actually applied (fitted and inherited)
    int inherited_levels = 0;          // of them, levels refined after the fit (FinishOptions::fit_levels)
    int fit_iterations = 0;
    bool fit_converged = false;
    double fit_max_distance = 0;  // largest boundary-vertex distance to the surface at the end of the fit
    double fit_uncovered = -1;    // FitResult::uncovered / the domain's bbox diagonal (-1: no two-sided step ran)
    bool untangled = false;       // untangle ran
    int untangle_rounds = 0;
    bool untangled_boundary_moved = false;  // the free-boundary fallback of the untangle stage was kept
    bool pad_improved = false;              // the quality pass on the padded mesh ran and its result was kept
    bool improved = false;                  // the quality pass ran and its result was kept
    bool smoothed = false;                  // the smoothing pass moved some vertex
    QualityReport quality;                  // compute_quality of the final mesh
    bool distance_measured = false;
    SurfaceDistance distance;  // absolute (max, mean) and relative to the domain bbox diagonal
    double distance_ms = 0;
    double total_ms = 0;
    // Selective padding (FinishOptions::pad_selective): boundary quads of the raw mesh, those left bare, regions of
    // them between sharp raw edges and of those the bare ones (PadSelection). 0 when it did not run.
    std::string pad_mode = "none";  // "none", "all" or "selective": FinishOptions::pad and pad_selective
    long pad_boundary_quads = 0, pad_bare_quads = 0;
    int pad_regions = 0, pad_bare_regions = 0;
    // Sharp raw boundary edges, and of them those matched to a sharp edge of the domain.
    long pad_sharp_edges = 0, pad_matched_edges = 0;
    long crease_wedges = 0;       // wedge hexes added before the padding (crease_wedge)
    long crotch_sheets = 0;       // hex sheets cut at the crotch for them (crease_wedge_crotch)
    long pad_inset_vertices = 0;  // raw boundary vertices moved inward with their padding vertex (pad_inset)
};

// What a finished mesh is judged by when the mesh command weighs a second attempt (another adaptation of the same
// skeleton): the acceptance targets for real skeleton/surface pairs. A result misses a goal when some hex is inverted
// or the mesh is invalid, when min scaled Jacobian < sj_min, average < sj_avg, or (distance measured) relative
// Hausdorff distance > hausdorff.
struct MeshGoals {
    double sj_min = 0.3;
    double sj_avg = 0.85;
    double hausdorff = 0.01;  // x the domain's bounding-box diagonal
};
// Number of goals missed (0..4: validity-and-inversion, min, average, distance).
int missed_goals(const FinishResult& r, const MeshGoals& goals = {});
// The first criteria of both comparisons below: < 0 when `a` has fewer inverted hexes (a valid mesh before an invalid
// one), else fewer goals missed; > 0 when `b` has; 0 when they tie on both.
int compare_inverted_then_goals(const FinishResult& a, const FinishResult& b, const MeshGoals& goals = {});
// True when `a` is strictly better than `b`: fewer inverted hexes (a valid mesh before an invalid one), else fewer
// goals missed, else a smaller relative Hausdorff distance (when both measured it), else a higher min scaled Jacobian.
bool better_finish(const FinishResult& a, const FinishResult& b, const MeshGoals& goals = {});
// How far `r` falls short of the goals it misses, as one dimensionless number: the sum over the missed goals of the
// natural log of the factor it misses each by: ln(goal / value) for the min and the average scaled Jacobian,
// ln(value / goal) for the relative Hausdorff distance (when measured); 0 when every goal is met; +infinity when the
// min (or average) scaled Jacobian is not positive. Validity and inverted hexes are compare_inverted_then_goals's.
double goal_shortfall(const FinishResult& r, const MeshGoals& goals = {});
// Like better_finish, with the smaller goal_shortfall deciding between two results that tie on inverted hexes and on
// goals missed (before the Hausdorff distance and the min scaled Jacobian): with both missing min SJ and Hausdorff,
// 0.2 / 2 % (shortfall ln(0.3 / 0.2) + ln(2) = 1.10) is better than 0.1 / 1.9 % (ln 3 + ln 1.9 = 1.74).
bool better_finish_by_shortfall(const FinishResult& a, const FinishResult& b, const MeshGoals& goals = {});

// Preconditions: `raw` has indices in range (the stages throw InvalidInput otherwise); `domain` has a non-degenerate
// triangle (InvalidInput otherwise) and should be a closed surface. The domain is copied and oriented outward first
// (orient_outward) when it faces inward. Errors: whatever the stages throw.
FinishResult finish_mesh(const HexMesh& raw, const TriangleMesh& domain, const FinishOptions& options = {});

}  // namespace mesohex
