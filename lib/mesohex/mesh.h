#pragma once
// The one library call that meshes like `mesohex mesh`: radii (from the file, the domain, an option or the default)
// -> run_pipeline (raw mesh) -> finish_mesh in the domain -> further attempts while the mesh kept misses a goal (every
// quad padded, the cautious reach at branching points, the other fan layout, structural alternatives, finer levels),
// the best kept. `mesohex mesh`, `mesohex auto`, the studio and the
// Python module all call mesh_skeleton; they only map their flags to MeshOptions and print or serialize MeshRun.
// No printing; progress through MeshOptions::progress (which may throw to cancel a run).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/finish.h"
#include "mesohex/incremental.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/partition.h"
#include "mesohex/post/quality.h"

namespace mesohex {

// Where a run is, for a progress display (and a point where a caller can cancel by throwing from the callback).
struct MeshProgress {
    std::string stage;  // "raw", "fit", "untangle", "improve", "smooth", "attempt"
    int step = 0;       // iteration / round / sweep within the stage (attempt: its number, from 1)
    int steps = 0;      // the stage's cap on `step` (0 when unknown; attempt: the most attempts the options allow)
    double sj_min = 0;  // fit only: current min scaled Jacobian
    long inverted = 0;  // fit, untangle, improve: hexes with scaled Jacobian <= 0
    std::string what;   // attempt only: "first", "fully padded" (same raw mesh, every quad padded), "cautious
                        // joints" (a second skeleton, first joints farther from the branching points), a structural
                        // alternative's name (MeshOptions::structural_retry) or "one level finer"
                        // (MeshOptions::finer_retry)
};

// A structural alternative (MeshOptions::structural_retry): one mechanism that is off by default, switched on for one
// more attempt on the skeleton of the mesh kept. Each changes the block structure or the finish input where its case
// occurs (docs/junctions.md, "Structural alternatives when the mesh kept misses").
enum class StructuralAlternative {
    ValleyTrunks,       // SkeletonRepairOptions::valley_trunk_degree 4: trunks for close fat pairs at degree >= 4
    SlideCutJoint,      // AdaptationOptions::slide_cut_joint: cut joints slid away from the junction
    PitBranches,        // VirtualBranchOptions::pit_excess 0.3: a branch into the pit inside a ring of branches
    CloseCreaseWedge,   // crease wedges (300 degrees) on a close pair's crease only (crease_wedge_pair_deg 60)
    CrotchWedge,        // the close pair's wedge only as long as the crotch (crotch_wedge_pair_deg 60)
    BulgedBridgeCover,  // JunctionCoverOptions fraction 1 with bridge_bulge 1.5: bulged bridges covered from both ends
};

// The name the report, the progress and the CLI give an alternative ("valley trunks", "slid cut joints", ...).
const char* structural_alternative_name(StructuralAlternative a);
// Its command-line name ("valley-trunks", "slide-cut-joint", "pit-branches", "crease-wedge", "crotch-wedge",
// "bridge-cover").
const char* structural_alternative_flag(StructuralAlternative a);
// Every alternative, in the enum's order.
std::vector<StructuralAlternative> all_structural_alternatives();
// The alternatives tried by default, in their order: valley trunks, slid cut joints, pit branches, crotch wedge,
// bulged bridges covered (the crotch wedge in place of the crease wedge it contains: where the uncut wedge fits in the
// domain it is the same wedge; docs/junctions.md, "Structural alternatives when the mesh kept misses").
std::vector<StructuralAlternative> default_structural_alternatives();

struct MeshOptions {
    // Radius when the skeleton file has none (in skeleton units). With a domain: radius_factor x the distance of each
    // skeleton vertex to the domain surface (radius_from_surface also replaces the file's radii). Without a domain:
    // pipeline.radius when > 0, else pipeline.default_radius_factor x the mean skeleton edge length.
    bool radius_from_surface = false;
    double radius_factor = 0.5;  // x distance to the surface (dimensionless); < 1 leaves room for the padding layer
    PipelineOptions pipeline;    // radius, resampling, adaptation, analysis, connection surfaces, raw mesh
    // With a domain and resampling: a branch end whose centre lies outside the domain, with the chain of such vertices
    // leading to it, is trimmed back to the last vertex inside (which becomes the end) before the repairs
    // (stages/tip_trim.h; the report's repairs.trimmed_tips). A `thicken` grid coarser than a thin tip's radii ends
    // the domain before the skeleton, and the fit crushes the hexes left outside (docs/junctions.md, "The
    // armadillo's claw"). false: the skeleton is meshed as given.
    bool trim_unheld_tips = true;
    // With a domain: pad, subdivide, fit, untangle, improve, smooth (finish_mesh). false = the raw mesh only.
    bool finish = true;
    FinishOptions finishing;  // finishing.chunk_hex is filled by mesh_skeleton for longitudinal / radial refinement
    // > 0, with finishing.crease_wedge on (min_dihedral_deg > 0): the wedges go only on the crease a close pair of
    // branches shares at a branching point, i.e. on the raw boundary edges between two of its surface ids held by the
    // chunks of two branch edges less than this many degrees apart (close_pair_crease_edges, raw_mesh.h; the other
    // folded creases keep two hexes). Degrees; 0 = every crease sharper than min_dihedral_deg (docs/junctions.md,
    // "The close pair's crease carried by a wedge").
    double crease_wedge_pair_deg = 0;
    // > 0: crotch wedges, one switch for the whole mechanism (docs/junctions.md, "The close pair's wedge only as long
    // as the crotch"): the close pairs' creases (close_pair_crease_edges at this many degrees, as
    // crease_wedge_pair_deg) get a crease wedge (at dihedrals above finishing.crease_wedge.min_dihedral_deg when set,
    // else crotch_wedge_dihedral_deg) after the two chunks on each crease are cut where the domain's crotch ends
    // (FinishOptions::crease_wedge_crotch). Degrees; 0 = off.
    double crotch_wedge_pair_deg = 0;
    // With crotch_wedge_pair_deg and finishing.crease_wedge off: the dihedral above which a listed crease gets its
    // wedge (degrees, in (180, 360)).
    double crotch_wedge_dihedral_deg = 300;
    // Further attempts when the finished mesh misses one of `goals`, keeping the best (better_finish): first, if the
    // selective padding left quads bare, the same raw mesh with every quad padded; then adapt again with the first
    // joints at adaptation.branching_reach (instead of free_branching_reach), only with resampling, a fit, and when
    // that adaptation gives another skeleton.
    bool retry = true;
    // > 0: a work budget for the second attempt: it runs only when the first attempt's finished mesh has at most this
    // many hexes (with finishing.max_hexes = 2 x this, both attempts together finish at most that many; `mesohex
    // auto`). 0 = no limit.
    long retry_max_hexes = 0;
    // With a domain, levels chosen by the finishing (finishing.levels < 0, no finishing.size, uniform refinement): when
    // the mesh kept after the attempts above misses a goal, its raw mesh is finished once more with one subdivision
    // level more and the better kept (better_finish). A coarse finished mesh (a few hundred hexes: short curve
    // skeletons of round solids) cannot follow the surface, however well its raw mesh is laid out; 8 x the hexes
    // can (docs/sheets.md, "One level finer"). Only when the finer mesh stays within retry_max_hexes and
    // finishing.max_hexes (when > 0). Off by default; `mesohex auto` turns it on.
    bool finer_retry = false;
    // With a domain, levels chosen by the finishing (as finer_retry), after finer_retry: while the mesh kept misses the
    // Hausdorff goal (goals.hausdorff) but meets the min scaled Jacobian with no inverted hex, its raw mesh is finished
    // again one level finer than the kept mesh (with the padding mode it was kept with) and the better kept
    // (better_finish). It stops when the distance goal is met, when the finer mesh is not kept, at
    // distance_max_levels, or when the hexes finished by all attempts, the finer one included, would exceed
    // finishing.max_hexes (when > 0: the finishing's time is about proportional to them). Not when min SJ is missed: a
    // subdivision keeps every corner's scaled Jacobian (the child hex at a parent's corner has that corner's edge
    // directions), so finer levels do not raise the minimum. What it decided and why: MeshRun::distance_refinement.
    // Off by default; `mesohex auto` turns it on (docs/sheets.md, "Refined until the distance goal is met").
    bool refine_to_distance = false;
    int distance_max_levels = 4;  // refine_to_distance: subdivision levels at most (count)
    // After the attempts above (both fan layouts, before finer_retry): while the mesh kept misses a goal, the next of
    // structural_alternatives is meshed (the kept attempt's pipeline options with that mechanism on) and finished once
    // (with the padding mode the mesh kept has), the better kept by better_finish_by_shortfall (whatever
    // retry_by_shortfall says: the mesh that misses the goals by less overall; one that meets every goal always
    // wins). Each alternative starts from the mesh kept so far. One whose raw mesh and finish input equal an attempt's
    // already finished (compared by hash) is skipped without a finish; one the pipeline refuses or whose finish fails
    // (a mesohex::Error) is skipped. It stops at the first mesh kept that meets every goal (unless structural_try_all),
    // and does not run when the mesh kept has more than retry_max_hexes hexes, nor without a fit, nor without
    // resampling; with finishing.max_hexes > 0 it stops before an alternative when the hexes finished by all attempts
    // plus the mesh kept's would exceed it, and skips one whose finish would (estimated: the mesh kept's hexes x the
    // ratio of the raw hexes). A mesh that meets every goal after the attempts above is untouched (no
    // attempt added). What ran and why: MeshRun::structural (docs/junctions.md, "Structural alternatives when the mesh
    // kept misses").
    bool structural_retry = true;
    // structural_retry: the alternatives in the order they are tried (by default every one but the crease wedge,
    // whose place the crotch wedge takes, in the enum's order: the order measured, docs/junctions.md).
    std::vector<StructuralAlternative> structural_alternatives = default_structural_alternatives();
    // structural_retry: at most this many alternatives finished (count; those skipped by their hash do not count;
    // 0 = no limit). Each costs about one finish of the mesh kept.
    int structural_max_finished = 3;
    // structural_retry: every alternative is finished even after one meets every goal (measurement; the best kept).
    bool structural_try_all = false;
    MeshGoals goals;  // the goals a finished mesh must meet (else the second attempt)
    // How the attempts above are ranked when they tie on inverted hexes and on the number of goals missed. false:
    // the smaller relative Hausdorff distance, then the higher min scaled Jacobian (better_finish). true: the smaller
    // goal_shortfall first (the product of the factors by which each missed goal is missed, so a 30 % lower min SJ is
    // not traded for a 3 % smaller Hausdorff distance, nor the reverse), then better_finish's order
    // (better_finish_by_shortfall; docs/junctions.md, "The retry's choice when every attempt misses").
    bool retry_by_shortfall = false;
    // With a domain, when the raw mesh has fan blocks (pipeline.connection_surfaces.blocks.fan_blocks): the skeleton
    // is meshed and finished again (with the same attempts) in the paper's layout on the fan edges, and that result
    // kept only when it is better (better_layout: valid and not inverted, fewer missed goals, then a higher min SJ).
    // Neither layout finishes better on every domain: the block's concave crease (raw boundary valence 3) stays sharp
    // where the domain's rims are sharp and takes two 45-degree padding hexes where they are round (docs/blocks.md).
    // false (`--fan-blocks`): fan blocks kept wherever accepted. Costs a second finish on skeletons with a fan block
    // (skipped, like the second attempt, when the first finished mesh has more than retry_max_hexes hexes).
    bool compare_fan_layouts = true;
    // Parts for MPI solvers: METIS k-way on the face adjacency of the hexes of the mesh kept (partition_hexes);
    // 0 = no partition. More parts than hexes is an InvalidInput error.
    int partitions = 0;
    // Keep the raw mesh's topology (computed for its quality anyway) in MeshRun::raw_topology: for a caller that
    // draws its singular edges and boundary (the studio). false = dropped after the quality (memory).
    bool keep_raw_topology = false;
    // May be empty; may throw to cancel (the exception propagates), with anything but a mesohex::Error: one thrown
    // during a structural alternative's finish is that alternative's failure, a skip (structural_retry).
    std::function<void(const MeshProgress&)> progress;
};

// One finished attempt, as the report lists it.
struct MeshAttempt {
    // What was tried: MeshProgress::what of the attempt ("first", "fully padded", "cautious joints", "one level
    // finer", "finer for the distance goal", a structural alternative's name), with "paper's fan layout, " before it
    // when finished in the paper's layout after the fan blocks'.
    std::string what;
    double free_branching_reach = 0;  // AdaptationOptions::free_branching_reach used for this attempt
    std::string padding;              // FinishResult::pad_mode of this attempt ("none", "all" or "selective")
    long fan_blocks = 0;              // fan edges with a fan block in this attempt's raw mesh (0: the paper's layout)
    int levels = 0;                   // subdivision levels applied (FinishResult::subdivision_levels)
    long hexes = 0;
    double sj_min = 0, sj_avg = 0;
    long inverted = 0;
    int missed_goals = 0;
    bool distance_measured = false;
    double hausdorff_relative_max = 0;  // x the domain's bbox diagonal (when distance_measured)
    // FNV-1a hash of the finish input (raw mesh, requested levels, padding mode, listed crease edges): two attempts
    // with the same hash finished the same input. Not in the report.
    std::uint64_t finish_input = 0;
};

// What MeshOptions::structural_retry did on a finished run whose mesh kept missed a goal after the other attempts.
struct StructuralRetry {
    std::vector<std::string> finished;  // the alternatives finished, in order (each one attempt in MeshRun::attempts)
    std::vector<std::string> skipped;   // the alternatives not finished, each "NAME: why"
    std::string kept;                   // the name of the alternative kept, "" when none was better than the mesh kept
    // "goals met", "all tried", "budget" (retry_max_hexes or finishing.max_hexes), "most finished"
    // (structural_max_finished)
    std::string stop;
};

// What MeshOptions::refine_to_distance decided on a finished run.
struct DistanceRefinement {
    double tolerance = 0;           // goals.hausdorff (x the domain's bbox diagonal)
    int levels_before = 0;          // subdivision levels of the mesh kept before the rule
    std::vector<int> levels;        // the levels of each finer finish it ran, in order (empty: none ran)
    std::vector<double> hausdorff;  // their relative Hausdorff distances
    std::vector<long> hexes;        // their hex counts
    int levels_kept = 0;            // subdivision levels of the mesh kept after the rule
    // Why it stopped (or never ran): "distance met", "min SJ missed", "inverted", "not measured", "levels given",
    // "not better", "budget", "max levels".
    std::string stop;
    std::string reason;  // the same with its numbers, for a reader
};

struct MeshRun {
    std::string radius_note;             // "" (radii as run_pipeline chose them) or "surface (F x distance)"
    PipelineOptions options;             // the pipeline options of the kept attempt
    PipelineResult pipeline;             // skeleton, analyses, prediction and raw mesh of the kept attempt
    QualityReport raw_quality;           // compute_quality(pipeline.raw.mesh)
    HexTopology raw_topology;            // of pipeline.raw.mesh when MeshOptions::keep_raw_topology, else empty
    bool prediction_exact = false;       // raw counts and irregular edges equal the prediction
    std::optional<FinishResult> finish;  // set when a domain was given and options.finish
    std::vector<MeshAttempt> attempts;   // finished attempts, first the default adaptation
    int kept_attempt = -1;               // index in attempts of the mesh kept (-1 without a finish)
    // Set when MeshOptions::structural_retry considered alternatives (the mesh kept missed a goal).
    std::optional<StructuralRetry> structural;
    std::optional<Partition> partition;  // of mesh(), set when options.partitions > 0
    // Set when MeshOptions::refine_to_distance asked for it on a finished run.
    std::optional<DistanceRefinement> distance_refinement;
    // Wall times (ms): radii from the domain, run_pipeline (the kept attempt's), raw-mesh quality, and everything
    // after it (finishing of every attempt, the second attempt's pipeline).
    double radius_ms = 0, pipeline_ms = 0, raw_quality_ms = 0, finish_ms = 0;
    double partition_ms = 0;  // partition_hexes on the mesh kept
    // Per input skeleton vertex: 1 when its centre lies inside the domain (MeshOptions::trim_unheld_tips); empty
    // without a domain or with the option off. Every attempt's run_pipeline trims the same tips.
    std::vector<char> held;

    const HexMesh& mesh() const { return finish ? finish->mesh : pipeline.raw.mesh; }
    const QualityReport& quality() const { return finish ? finish->quality : raw_quality; }
    // 0 when the mesh is valid with no inverted hex; else 5 (the CLI's exit status for such a mesh).
    int exit_status() const;
};

class SurfaceQuery;

// Preconditions: none beyond the stages' (every error is a mesohex::Error naming the element: InvalidInput for a
// skeleton vertex on or outside the domain when radii come from it). `domain` may be null (raw mesh only).
MeshRun mesh_skeleton(const Skeleton& skeleton, const TriangleMesh* domain, const MeshOptions& options = {});

// The same with the domain's closest-point structure built by the caller (`domain_query` built on `*domain`, may be
// null): a caller meshing many skeletons in one domain (the studio, one query per session) builds it once.
MeshRun mesh_skeleton(const Skeleton& skeleton, const TriangleMesh* domain, const SurfaceQuery* domain_query,
                      const MeshOptions& options);

// What mesh_skeleton does before the raw mesh, and nothing after: radii from the domain (when it would take them), then
// prepare_skeleton (pipeline.h: input analysis, repairs, adaptation, analysis) with options.pipeline. The studio's
// analyze calls it, so it judges the skeleton mesh_skeleton meshes, after the same repairs. Errors: as mesh_skeleton's
// up to the analysis.
PipelineResult prepare_mesh_skeleton(const Skeleton& skeleton, const TriangleMesh* domain,
                                     const SurfaceQuery* domain_query, const MeshOptions& options);

// What a raw run leaves for the next one on a similar skeleton (the studio keeps one per editing session).
struct RawRunCache {
    bool valid = false;     // the members below belong to the last successful mesh_skeleton_raw
    RemeshCache remesh;     // the prepared skeleton with its analysis, connection surfaces, frames and raw mesh
    QualityReport quality;  // compute_quality(remesh.raw.mesh)
    HexTopology topology;   // its topology
    RemeshStats last;       // what the last run recomputed (full = everything)
};

// mesh_skeleton(skeleton, domain, domain_query, options) for a run that stops at the raw mesh (options.finish false
// or no domain, no partitions; else, and without resampling, this is mesh_skeleton and the cache is emptied), reusing
// `cache`: the radii and prepare_skeleton (repairs, adaptation, analyses) run whole, then, when the prepared skeleton
// has the edges and faces of the cached one, only the connection surfaces near moved vertices are rebuilt
// (remesh_incremental) and only the scaled Jacobians of moved hexes recomputed (update_quality). The result equals
// mesh_skeleton's bit for bit (tests/unit/test_mesh_incremental.cpp) except the stage times: the remesh is timed as
// "connection_surfaces" ("frames" and "raw_mesh" 0). Use one cache with one set of options. On error the cache is
// emptied and the error propagates as from mesh_skeleton.
MeshRun mesh_skeleton_raw(const Skeleton& skeleton, const TriangleMesh* domain, const SurfaceQuery* domain_query,
                          const MeshOptions& options, RawRunCache& cache);

// The same, with the domain required: raw mesh, then finish in it.
inline MeshRun mesh_in_domain(const Skeleton& skeleton, const TriangleMesh& domain, const MeshOptions& options = {}) {
    return mesh_skeleton(skeleton, &domain, options);
}

}  // namespace mesohex
