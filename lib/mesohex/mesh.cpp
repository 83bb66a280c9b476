#include "mesohex/mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "mesohex/core/error.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex {

namespace {

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Radii from the domain (factor x distance to its surface) when the skeleton has none or the options ask for it.
// Returns the note the report gives as the radius source ("" when the domain was not used).
std::string take_radii_from_domain(Skeleton& skeleton, const TriangleMesh& domain, const SurfaceQuery* domain_query,
                                   const MeshOptions& options) {
    if (!skeleton.radii.empty() && !options.radius_from_surface) return "";
    std::optional<SurfaceQuery> own;
    if (!domain_query) domain_query = &own.emplace(domain);
    RadiusFromSurfaceOptions ro;
    ro.factor = options.radius_factor;
    const RadiusFromSurface rs = radius_from_surface(skeleton, *domain_query, ro);
    for (std::size_t v = 0; v < rs.radii.size(); ++v)
        if (!(rs.radii[v] > 0))
            throw Error(ErrorCode::InvalidInput,
                        "skeleton vertex " + std::to_string(v) +
                            " lies on or outside the domain surface: no radius can be taken from it",
                        {ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
    skeleton.radii = rs.radii;
    return "surface (" + std::to_string(options.radius_factor) + " x distance)";
}

// Per skeleton vertex: 1 when its centre lies inside the domain (the ball is held by it); empty when the options do not
// trim unheld tips (MeshOptions::trim_unheld_tips, resampling) or the skeleton has no branch edge to trim.
std::vector<char> held_vertices(const Skeleton& skeleton, const TriangleMesh& domain, const SurfaceQuery* domain_query,
                                const MeshOptions& options) {
    if (!options.trim_unheld_tips || !options.pipeline.resample || skeleton.edges.empty()) return {};
    std::optional<SurfaceQuery> own;
    if (!domain_query) domain_query = &own.emplace(domain, false);
    return domain_query->inside(skeleton.points);
}

const std::vector<char>* held_of(const MeshRun& run) { return run.held.empty() ? nullptr : &run.held; }

// Per raw hex: 1 when it is a chunk hex of a branch edge (what longitudinal / radial refinement splits).
std::vector<char> branch_chunk_hexes(const PipelineResult& run) {
    std::vector<char> chunk(run.raw.hex_edge.size(), 0);
    for (std::size_t h = 0; h < run.raw.hex_edge.size(); ++h) {
        const int e = run.raw.hex_edge[h];
        chunk[h] = e >= 0 && run.analysis.edge_degree[static_cast<std::size_t>(e)] == 0;
    }
    return chunk;
}

// The finishing options with the stages' progress callbacks forwarded to options.progress.
FinishOptions finishing_options(const MeshOptions& options, const PipelineResult& run) {
    FinishOptions fo = options.finishing;
    if (fo.refinement != FinishOptions::Refinement::Uniform && fo.chunk_hex.empty())
        fo.chunk_hex = branch_chunk_hexes(run);
    if (options.crease_wedge_pair_deg > 0 && fo.crease_wedge.min_dihedral_deg > 0) {
        fo.crease_wedge.listed_only = true;
        fo.crease_wedge.listed =
            close_pair_crease_edges(run.skeleton, run.analysis, run.raw, options.crease_wedge_pair_deg);
    }
    if (options.crotch_wedge_pair_deg > 0) {
        if (!(fo.crease_wedge.min_dihedral_deg > 0))
            fo.crease_wedge.min_dihedral_deg = options.crotch_wedge_dihedral_deg;
        fo.crease_wedge.listed_only = true;
        fo.crease_wedge.listed =
            close_pair_crease_edges(run.skeleton, run.analysis, run.raw, options.crotch_wedge_pair_deg);
        fo.crease_wedge_crotch = true;
    }
    if (!options.progress) return fo;
    const auto& report = options.progress;
    const int fit_cap = fo.fitting.max_iterations;
    fo.fitting.progress = [report, fit_cap](const FitProgress& p) {
        report({"fit", p.iteration, fit_cap, p.sj_min, p.inverted, ""});
    };
    const int untangle_cap = fo.untangling.max_rounds;
    fo.untangling.progress = [report, untangle_cap](const UntangleProgress& p) {
        report({"untangle", p.round, untangle_cap, 0, p.inverted, ""});
    };
    const int improve_cap = fo.improving.max_rounds;
    fo.improving.progress = [report, improve_cap](const UntangleProgress& p) {
        report({"improve", p.round, improve_cap, 0, p.inverted, ""});
    };
    const int smooth_cap = fo.smoothing.max_sweeps + fo.smoothing.resweeps;
    fo.smoothing.progress = [report, smooth_cap](const SmoothProgress& p) {
        report({"smooth", p.sweep, smooth_cap, 0, 0, ""});
    };
    return fo;
}

MeshAttempt attempt_of(const PipelineOptions& pipeline, const PipelineResult& raw, const FinishResult& f,
                       const MeshGoals& goals) {
    MeshAttempt a;
    a.what = f.pad_mode;  // replaced by record_attempt
    a.free_branching_reach = pipeline.adaptation.free_branching_reach;
    a.fan_blocks = raw.predicted.fan_blocks;
    a.levels = f.subdivision_levels;
    a.padding = f.pad_mode;
    a.hexes = f.quality.hexes;
    a.sj_min = f.quality.sj_min;
    a.sj_avg = f.quality.sj_avg;
    a.inverted = f.quality.inverted;
    a.missed_goals = missed_goals(f, goals);
    a.distance_measured = f.distance_measured;
    a.hausdorff_relative_max = f.distance.relative_max;
    return a;
}

bool prediction_matches(const QualityReport& q, const RawMeshPrediction& p) {
    return q.hexes == p.hexes && q.vertices == p.vertices && q.singular_interior_edges == p.interior_irregular_edges &&
           q.singular_boundary_edges == p.boundary_irregular_edges;
}

// The second attempt's pipeline options: the first joints at the cautious reach at branching points.
PipelineOptions cautious_options(const PipelineOptions& options) {
    PipelineOptions cautious = options;
    cautious.adaptation.free_branching_reach = options.adaptation.branching_reach;
    return cautious;
}

// The raw mesh's quality and whether it matches the prediction; its topology kept when asked for.
void set_raw_quality(MeshRun& run, const MeshOptions& options) {
    HexTopology topology;
    run.raw_quality = compute_quality(run.pipeline.raw.mesh, topology);
    run.raw_topology = options.keep_raw_topology ? std::move(topology) : HexTopology{};
    run.prediction_exact = prediction_matches(run.raw_quality, run.pipeline.predicted);
}

// Whether the options allow a second skeleton with the cautious reach (before any result is known).
bool cautious_retry_allowed(const MeshOptions& options) {
    return options.retry && options.finishing.fit && options.pipeline.resample &&
           options.pipeline.adaptation.branching_reach != options.pipeline.adaptation.free_branching_reach;
}

bool retry_applies(const MeshOptions& options, const MeshRun& run) {
    return cautious_retry_allowed(options) && missed_goals(*run.finish, options.goals) > 0 &&
           (options.retry_max_hexes <= 0 || run.finish->quality.hexes <= options.retry_max_hexes);
}

// Whether the run finishes two layouts (compare_fan_layouts): its raw mesh has fan blocks, or it is the paper's
// layout finished after them (its attempts start with theirs).
bool two_layouts(const MeshRun& run, const MeshOptions& options) {
    return (options.compare_fan_layouts && run.pipeline.predicted.fan_blocks > 0) ||
           (!run.attempts.empty() && run.attempts.front().fan_blocks > 0);
}

// The most finishing attempts the options allow: per layout the first, the fully padded one, the cautious skeleton;
// then the one level finer.
int max_attempts(const MeshRun& run, const MeshOptions& options) {
    const bool padded = options.retry && options.finishing.pad && options.finishing.pad_selective;
    const int per_layout = 1 + (padded ? 1 : 0) + (cautious_retry_allowed(options) ? 1 : 0);
    int structural = options.structural_retry ? static_cast<int>(options.structural_alternatives.size()) : 0;
    if (options.structural_max_finished > 0) structural = std::min(structural, options.structural_max_finished);
    return (two_layouts(run, options) ? 2 * per_layout : per_layout) + structural + (options.finer_retry ? 1 : 0) +
           (options.refine_to_distance ? options.distance_max_levels : 0);
}

// What the next attempt, meshed with `pipeline`, is called: `what`, after "paper's fan layout, " in the paper's layout
// after the fan blocks'.
std::string attempt_name(const MeshRun& run, const PipelineOptions& pipeline, const std::string& what) {
    const bool paper_after_blocks =
        !run.attempts.empty() && run.attempts.front().fan_blocks > 0 && !pipeline.connection_surfaces.blocks.fan_blocks;
    return paper_after_blocks ? "paper's fan layout, " + what : what;
}

// Reports the start of the next finishing attempt (numbered from 1 in the order they run, both layouts together),
// meshed with `pipeline`.
void report_attempt(const MeshRun& run, const MeshOptions& options, const PipelineOptions& pipeline,
                    const std::string& what) {
    if (!options.progress) return;
    options.progress({"attempt", static_cast<int>(run.attempts.size()) + 1, max_attempts(run, options), 0, 0,
                      attempt_name(run, pipeline, what)});
}

void report_attempt(const MeshRun& run, const MeshOptions& options, const std::string& what) {
    report_attempt(run, options, options.pipeline, what);
}

std::uint64_t fnv(std::uint64_t h, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ULL;
    return h;
}

// FNV-1a hash of what a finish starts from: the raw mesh (points and hexes, bit for bit), the requested subdivision
// levels, whether the padding is selective and the crease edges listed for wedges. Two attempts with the same hash
// finish the same input (MeshOptions::structural_retry skips the second).
std::uint64_t finish_input_hash(const HexMesh& raw, const FinishOptions& fo) {
    std::uint64_t h = 14695981039346656037ULL;
    for (const Vec3& p : raw.points) h = fnv(h, &p, sizeof p);
    for (const auto& hex : raw.hexes) h = fnv(h, hex.data(), sizeof hex);
    const CreaseWedgeOptions& w = fo.crease_wedge;
    const bool wedges = w.min_dihedral_deg > 0 && !(w.listed_only && w.listed.empty());  // else none can be inserted
    const int flags[] = {fo.levels, fo.pad ? 1 : 0, fo.pad_selective ? 1 : 0, wedges ? 1 : 0};
    h = fnv(h, flags, sizeof flags);
    if (!wedges) return h;
    const int listed_only = w.listed_only ? 1 : 0;
    h = fnv(h, &listed_only, sizeof listed_only);
    if (w.listed_only)
        for (const auto& e : w.listed) h = fnv(h, e.data(), sizeof e);
    return fnv(h, &w.min_dihedral_deg, sizeof(double));
}

// Appends the attempt `what` finished from `raw` with `fo` to run.attempts; returns its index.
int record_attempt(MeshRun& run, const MeshOptions& options, const std::string& what, const PipelineOptions& pipeline,
                   const PipelineResult& raw, const FinishResult& f, const FinishOptions& fo) {
    MeshAttempt a = attempt_of(pipeline, raw, f, options.goals);
    a.what = attempt_name(run, pipeline, what);
    a.finish_input = finish_input_hash(raw.raw.mesh, fo);
    run.attempts.push_back(std::move(a));
    return static_cast<int>(run.attempts.size()) - 1;
}

// The order the attempts are kept in (MeshOptions::retry_by_shortfall).
bool better_attempt(const FinishResult& a, const FinishResult& b, const MeshOptions& options) {
    return options.retry_by_shortfall ? better_finish_by_shortfall(a, b, options.goals)
                                      : better_finish(a, b, options.goals);
}

// The selective padding left regions of the raw boundary bare and the result misses a goal: the same raw mesh is
// finished again with every quad padded, and the better of the two kept. Bare regions are chosen by how the raw
// rims match the domain's, not by how far the fit must then move them; where the raw boundary lies well inside the
// domain (radii from the domain, medial meso-skeletons) the bare hexes can be stretched too far (measurements:
// docs/tuning.md, "Selective padding").
void retry_fully_padded(MeshRun& run, const TriangleMesh& domain, const MeshOptions& options) {
    if (!options.retry || run.finish->pad_bare_quads == 0 || missed_goals(*run.finish, options.goals) == 0) return;
    MeshOptions padded = options;
    padded.finishing.pad_selective = false;
    report_attempt(run, options, "fully padded");
    const FinishOptions fo = finishing_options(padded, run.pipeline);
    FinishResult finished = finish_mesh(run.pipeline.raw.mesh, domain, fo);
    const int index = record_attempt(run, options, "fully padded", run.options, run.pipeline, finished, fo);
    if (!better_attempt(finished, *run.finish, options)) return;
    run.finish = std::move(finished);
    run.kept_attempt = index;
}

// Finishes the raw mesh of `run` in the domain; when the result misses a goal, the same raw mesh fully padded if the
// selective padding left quads bare, then a second skeleton with the cautious reach at branching points, keeping the
// best.
void finish_with_retry(MeshRun& run, const Skeleton& skeleton, const TriangleMesh& domain, const MeshOptions& options) {
    report_attempt(run, options, "first");
    const FinishOptions fo = finishing_options(options, run.pipeline);
    run.finish = finish_mesh(run.pipeline.raw.mesh, domain, fo);
    run.kept_attempt = record_attempt(run, options, "first", run.options, run.pipeline, *run.finish, fo);
    retry_fully_padded(run, domain, options);
    if (!retry_applies(options, run)) return;

    const PipelineOptions cautious = cautious_options(run.options);
    PipelineResult second = run_pipeline(skeleton, cautious, held_of(run));
    if (second.skeleton == run.pipeline.skeleton) return;  // the same skeleton would give the same mesh
    report_attempt(run, options, "cautious joints");
    const FinishOptions second_fo = finishing_options(options, second);
    FinishResult finished = finish_mesh(second.raw.mesh, domain, second_fo);
    const int index = record_attempt(run, options, "cautious joints", cautious, second, finished, second_fo);
    if (!better_attempt(finished, *run.finish, options)) return;
    run.finish = std::move(finished);
    run.kept_attempt = index;
    run.pipeline = std::move(second);
    run.options = cautious;
    set_raw_quality(run, options);
}

// Whether the kept mesh gets the attempt one level finer (MeshOptions::finer_retry): levels chosen by the finishing,
// uniform refinement, a goal missed, and 8 x its hexes within both budgets.
bool finer_retry_applies(const MeshOptions& options, const MeshRun& run) {
    const FinishOptions& fo = options.finishing;
    if (!options.finer_retry || !run.finish || !fo.subdivide || fo.levels >= 0 || fo.size > 0 ||
        fo.refinement != FinishOptions::Refinement::Uniform || missed_goals(*run.finish, options.goals) == 0)
        return false;
    const long finer = 8 * run.finish->quality.hexes;
    return (options.retry_max_hexes <= 0 || finer <= options.retry_max_hexes) &&
           (fo.max_hexes <= 0 || finer <= fo.max_hexes);
}

// The kept mesh's raw mesh finished again with one level more (and the padding mode it was kept with), reported as
// the attempt `why` and recorded in run.attempts.
FinishResult finish_one_level_finer(MeshRun& run, const TriangleMesh& domain, const MeshOptions& options,
                                    const char* why) {
    MeshOptions finer = options;
    finer.finishing.levels = run.finish->subdivision_levels + 1;
    if (run.finish->pad_mode == "all") finer.finishing.pad_selective = false;
    report_attempt(run, options, run.options, why);
    const FinishOptions fo = finishing_options(finer, run.pipeline);
    FinishResult finished = finish_mesh(run.pipeline.raw.mesh, domain, fo);
    record_attempt(run, options, why, run.options, run.pipeline, finished, fo);
    return finished;
}

// The kept mesh misses a goal: its raw mesh finished again with one level more, the better of the two kept.
void retry_finer(MeshRun& run, const TriangleMesh& domain, const MeshOptions& options) {
    if (!finer_retry_applies(options, run)) return;
    FinishResult finished = finish_one_level_finer(run, domain, options, "one level finer");
    if (!better_attempt(finished, *run.finish, options)) return;
    run.finish = std::move(finished);
    run.kept_attempt = static_cast<int>(run.attempts.size()) - 1;
}

// Why MeshOptions::refine_to_distance tries no finer level on the kept mesh after `finished` hexes finished by all
// attempts: the stop code and its reason (DistanceRefinement); both empty when it tries one.
std::pair<std::string, std::string> distance_refinement_stop(const MeshRun& run, const MeshOptions& options,
                                                             long finished) {
    const FinishOptions& fo = options.finishing;
    const FinishResult& f = *run.finish;
    const MeshGoals& goals = options.goals;
    std::ostringstream why;
    if (!fo.subdivide || fo.levels >= 0 || fo.size > 0 || fo.refinement != FinishOptions::Refinement::Uniform)
        return {"levels given", "the subdivision levels are given (levels, size or a directional refinement)"};
    if (!f.distance_measured) return {"not measured", "the distance to the surface was not measured"};
    if (f.distance.relative_max <= goals.hausdorff) {
        why << "Hausdorff " << 100 * f.distance.relative_max << " % within the goal " << 100 * goals.hausdorff << " %";
        return {"distance met", why.str()};
    }
    if (f.quality.inverted > 0 || !f.quality.validation.valid())
        return {"inverted", "the mesh kept is invalid or has inverted hexes: a finer level does not untangle it"};
    if (!(f.quality.sj_min >= goals.sj_min)) {
        why << "min SJ " << f.quality.sj_min << " below the goal " << goals.sj_min
            << ": a subdivision keeps every corner's scaled Jacobian, a finer level does not raise the minimum";
        return {"min SJ missed", why.str()};
    }
    if (f.subdivision_levels + 1 > options.distance_max_levels) {
        why << f.subdivision_levels << " levels, the most allowed (" << options.distance_max_levels << ")";
        return {"max levels", why.str()};
    }
    const long finer = 8 * f.quality.hexes;
    if (fo.max_hexes > 0 && finished + finer > fo.max_hexes) {
        why << finer << " hexes one level finer, after " << finished << " finished, exceed the budget of "
            << fo.max_hexes;
        return {"budget", why.str()};
    }
    return {"", ""};
}

// MeshOptions::refine_to_distance: the kept mesh finished one level finer while it misses only the distance goal
// (and possibly the average), each finer mesh kept when better; what was decided goes to run.distance_refinement.
void refine_to_distance(MeshRun& run, const TriangleMesh& domain, const MeshOptions& options) {
    if (!options.refine_to_distance || !run.finish) return;
    DistanceRefinement& dr = run.distance_refinement.emplace();
    dr.tolerance = options.goals.hausdorff;
    dr.levels_before = run.finish->subdivision_levels;
    long finished = 0;
    for (const MeshAttempt& a : run.attempts) finished += a.hexes;
    for (;;) {
        auto [stop, reason] = distance_refinement_stop(run, options, finished);
        if (!stop.empty()) {
            dr.stop = std::move(stop);
            dr.reason = std::move(reason);
            break;
        }
        FinishResult f = finish_one_level_finer(run, domain, options, "finer for the distance goal");
        finished += f.quality.hexes;
        dr.levels.push_back(f.subdivision_levels);
        dr.hausdorff.push_back(f.distance_measured ? f.distance.relative_max : 0.0);
        dr.hexes.push_back(f.quality.hexes);
        if (!better_attempt(f, *run.finish, options)) {
            std::ostringstream why;
            why << f.subdivision_levels << " levels (" << f.quality.hexes << " hexes) not better than the mesh kept";
            dr.stop = "not better";
            dr.reason = why.str();
            break;
        }
        run.finish = std::move(f);
        run.kept_attempt = static_cast<int>(run.attempts.size()) - 1;
    }
    dr.levels_kept = run.finish->subdivision_levels;
}

// The layout comparison's order (MeshOptions::compare_fan_layouts): fewer inverted hexes (a valid mesh first), fewer
// missed goals, then a higher min scaled Jacobian. Unlike better_finish, not the Hausdorff distance first: within the
// goal, the block's sharp crease and the paper's chamfered one trade a little distance for the worst hex.
bool better_layout(const FinishResult& a, const FinishResult& b, const MeshGoals& goals) {
    if (const int c = compare_inverted_then_goals(a, b, goals); c != 0) return c < 0;
    return a.quality.sj_min > b.quality.sj_min;
}

// The raw mesh kept has fan blocks: the same skeleton meshed and finished (with its own attempts) in the paper's layout
// on the fan edges, kept when better_layout says so. The attempts of both are listed, the fan-block ones first. When
// the paper's layout refuses the skeleton (UnsupportedConfiguration), the fan blocks' is kept.
void compare_fan_layouts(MeshRun& run, const Skeleton& skeleton, const TriangleMesh& domain,
                         const MeshOptions& options) {
    if (!options.compare_fan_layouts || run.pipeline.predicted.fan_blocks == 0 || !run.finish) return;
    if (options.retry_max_hexes > 0 && run.finish->quality.hexes > options.retry_max_hexes) return;  // work budget
    MeshOptions paper = options;
    paper.pipeline.connection_surfaces.blocks.fan_blocks = false;
    MeshRun other;
    other.options = paper.pipeline;
    other.held = run.held;
    try {
        other.pipeline = run_pipeline(skeleton, other.options, held_of(other));
    } catch (const Error& e) {
        // The paper's layout refuses what only a block carries (a branch on a fan block's side section or in its
        // notch, CompatibleBlockOptions::fan_side_branches): the block's layout is the only one.
        if (e.code() == ErrorCode::UnsupportedConfiguration) return;
        throw;
    }
    set_raw_quality(other, paper);
    other.attempts = run.attempts;  // numbers the progress reports on from the fan-block attempts
    finish_with_retry(other, skeleton, domain, paper);
    run.attempts = std::move(other.attempts);
    if (!better_layout(*other.finish, *run.finish, options.goals)) return;
    run.options = std::move(other.options);
    run.pipeline = std::move(other.pipeline);
    run.raw_quality = std::move(other.raw_quality);
    run.raw_topology = std::move(other.raw_topology);
    run.prediction_exact = other.prediction_exact;
    run.finish = std::move(other.finish);
    run.kept_attempt = other.kept_attempt;
}

// `options` with the alternative's mechanism switched on, the pipeline options being `kept` (the mesh kept's).
MeshOptions alternative_options(StructuralAlternative a, const MeshOptions& options, const PipelineOptions& kept) {
    MeshOptions alt = options;
    alt.pipeline = kept;
    switch (a) {
        case StructuralAlternative::ValleyTrunks: alt.pipeline.repair.valley_trunk_degree = 4; break;
        case StructuralAlternative::SlideCutJoint: alt.pipeline.adaptation.slide_cut_joint = true; break;
        case StructuralAlternative::PitBranches: alt.pipeline.virtual_branches.pit_excess = 0.3; break;
        case StructuralAlternative::CloseCreaseWedge:
            alt.finishing.crease_wedge.min_dihedral_deg = 300;
            alt.crease_wedge_pair_deg = 60;
            break;
        case StructuralAlternative::CrotchWedge: alt.crotch_wedge_pair_deg = 60; break;
        case StructuralAlternative::BulgedBridgeCover:
            alt.pipeline.raw_mesh.cover.fraction = 1;
            alt.pipeline.raw_mesh.cover.bridge_bulge = 1.5;
            break;
    }
    return alt;
}

// Whether the alternative leaves the pipeline as the mesh kept's (only its finish input changes).
bool finishing_only(StructuralAlternative a) {
    return a == StructuralAlternative::CloseCreaseWedge || a == StructuralAlternative::CrotchWedge;
}

bool finish_input_tried(const MeshRun& run, std::uint64_t hash) {
    for (const MeshAttempt& a : run.attempts)
        if (a.finish_input == hash) return true;
    return false;
}

// One structural alternative on a run whose mesh kept misses a goal: meshed, finished once unless its finish input
// was finished already (then the reason goes to run.structural->skipped), the better kept.
// The hexes an alternative's finish would give, estimated from the mesh kept: its finished hexes scaled by the ratio
// of the raw hexes (the same levels and padding mode; the padding layer about proportional too).
long estimated_finished_hexes(const MeshRun& run, const PipelineResult& raw) {
    const double kept_raw = static_cast<double>(std::max<std::size_t>(run.pipeline.raw.mesh.hexes.size(), 1));
    return static_cast<long>(std::ceil(static_cast<double>(run.finish->quality.hexes) *
                                       static_cast<double>(raw.raw.mesh.hexes.size()) / kept_raw));
}

// budget_left: the hexes the alternative's finish may still give under finishing.max_hexes (< 0: no limit).
void try_alternative(MeshRun& run, StructuralAlternative a, const Skeleton& skeleton, const TriangleMesh& domain,
                     const MeshOptions& options, long budget_left) {
    StructuralRetry& sr = *run.structural;
    const std::string name = structural_alternative_name(a);
    MeshOptions alt = alternative_options(a, options, run.options);
    if (run.finish->pad_mode == "all") alt.finishing.pad_selective = false;
    std::optional<PipelineResult> own;
    if (!finishing_only(a)) {
        try {
            own = run_pipeline(skeleton, alt.pipeline, held_of(run));
        } catch (const Error& e) {
            sr.skipped.push_back(name + ": refused (" + e.what() + ")");
            return;
        }
    }
    const PipelineResult& raw = own ? *own : run.pipeline;
    const FinishOptions fo = finishing_options(alt, raw);
    if (finish_input_tried(run, finish_input_hash(raw.raw.mesh, fo))) {
        sr.skipped.push_back(name + ": the same finish input as an attempt finished");
        return;
    }
    if (const long estimate = estimated_finished_hexes(run, raw); budget_left >= 0 && estimate > budget_left) {
        sr.skipped.push_back(name + ": over the hex budget (about " + std::to_string(estimate) + " hexes, " +
                             std::to_string(budget_left) + " left)");
        return;
    }
    report_attempt(run, options, alt.pipeline, name);
    std::optional<FinishResult> result;
    try {
        result = finish_mesh(raw.raw.mesh, domain, fo);
    } catch (const Error& e) {
        // The input finished once already: a failure here is the alternative's (e.g. the fit's factorization on its
        // mesh), not the run's.
        sr.skipped.push_back(name + ": failed in the finish (" + e.what() + ")");
        return;
    }
    FinishResult& finished = *result;
    const int index = record_attempt(run, options, name, alt.pipeline, raw, finished, fo);
    sr.finished.push_back(name);
    // Ranked by the goals' shortfall whatever retry_by_shortfall says: another structure trades min SJ for distance
    // freely, and a mesh that misses by less overall is the one to keep (docs/junctions.md, "Structural
    // alternatives when the mesh kept misses").
    if (!better_finish_by_shortfall(finished, *run.finish, options.goals)) return;
    run.finish = std::move(finished);
    run.kept_attempt = index;
    sr.kept = name;
    if (!own) return;
    run.pipeline = std::move(*own);
    run.options = alt.pipeline;
    set_raw_quality(run, options);
}

// MeshOptions::structural_retry: while the mesh kept misses a goal, the next structural alternative, the better kept.
void retry_structural(MeshRun& run, const Skeleton& skeleton, const TriangleMesh& domain, const MeshOptions& options) {
    if (!options.structural_retry || !run.finish || options.structural_alternatives.empty() || !options.finishing.fit ||
        !options.pipeline.resample || missed_goals(*run.finish, options.goals) == 0)
        return;
    StructuralRetry& sr = run.structural.emplace();
    if (options.retry_max_hexes > 0 && run.finish->quality.hexes > options.retry_max_hexes) {
        sr.stop = "budget";
        return;
    }
    sr.stop = "all tried";
    long finished = 0;
    for (const MeshAttempt& a : run.attempts) finished += a.hexes;
    for (const StructuralAlternative a : options.structural_alternatives) {
        // The finishing's time is about proportional to the hexes it finishes: finishing.max_hexes bounds them all.
        if (options.finishing.max_hexes > 0 && finished + run.finish->quality.hexes > options.finishing.max_hexes) {
            sr.stop = "budget";
            return;
        }
        if (options.structural_max_finished > 0 &&
            static_cast<int>(sr.finished.size()) >= options.structural_max_finished) {
            sr.stop = "most finished";
            return;
        }
        const std::size_t before = run.attempts.size();
        const long budget_left = options.finishing.max_hexes > 0 ? options.finishing.max_hexes - finished : -1;
        try_alternative(run, a, skeleton, domain, options, budget_left);
        if (run.attempts.size() > before) finished += run.attempts.back().hexes;
        if (!options.structural_try_all && missed_goals(*run.finish, options.goals) == 0) {
            sr.stop = "goals met";
            return;
        }
    }
}

// The start shared by mesh_skeleton and mesh_skeleton_raw: the skeleton with its radii from the domain (when given,
// timed in run.radius_ms), the pipeline options, and the "raw" progress report.
Skeleton start_run(MeshRun& run, const Skeleton& input, const TriangleMesh* domain, const SurfaceQuery* domain_query,
                   const MeshOptions& options) {
    Skeleton skeleton = input;
    const auto t = std::chrono::steady_clock::now();
    if (domain) run.radius_note = take_radii_from_domain(skeleton, *domain, domain_query, options);
    if (domain) run.held = held_vertices(skeleton, *domain, domain_query, options);
    run.radius_ms = ms_since(t);
    run.options = options.pipeline;
    if (options.progress) options.progress({"raw", 1, 1, 0, 0, ""});
    return skeleton;
}

}  // namespace

const char* structural_alternative_name(StructuralAlternative a) {
    switch (a) {
        case StructuralAlternative::ValleyTrunks: return "valley trunks";
        case StructuralAlternative::SlideCutJoint: return "slid cut joints";
        case StructuralAlternative::PitBranches: return "pit branches";
        case StructuralAlternative::CloseCreaseWedge: return "close-pair crease wedge";
        case StructuralAlternative::CrotchWedge: return "close-pair crotch wedge";
        case StructuralAlternative::BulgedBridgeCover: return "bulged bridges covered";
    }
    return "unknown";
}

const char* structural_alternative_flag(StructuralAlternative a) {
    switch (a) {
        case StructuralAlternative::ValleyTrunks: return "valley-trunks";
        case StructuralAlternative::SlideCutJoint: return "slide-cut-joint";
        case StructuralAlternative::PitBranches: return "pit-branches";
        case StructuralAlternative::CloseCreaseWedge: return "crease-wedge";
        case StructuralAlternative::CrotchWedge: return "crotch-wedge";
        case StructuralAlternative::BulgedBridgeCover: return "bridge-cover";
    }
    return "unknown";
}

std::vector<StructuralAlternative> all_structural_alternatives() {
    return {StructuralAlternative::ValleyTrunks, StructuralAlternative::SlideCutJoint,
            StructuralAlternative::PitBranches,  StructuralAlternative::CloseCreaseWedge,
            StructuralAlternative::CrotchWedge,  StructuralAlternative::BulgedBridgeCover};
}

std::vector<StructuralAlternative> default_structural_alternatives() {
    return {StructuralAlternative::ValleyTrunks, StructuralAlternative::SlideCutJoint,
            StructuralAlternative::PitBranches, StructuralAlternative::CrotchWedge,
            StructuralAlternative::BulgedBridgeCover};
}

int MeshRun::exit_status() const {
    const QualityReport& q = quality();
    return q.inverted > 0 || !q.validation.valid() ? 5 : 0;
}

PipelineResult prepare_mesh_skeleton(const Skeleton& input, const TriangleMesh* domain,
                                     const SurfaceQuery* domain_query, const MeshOptions& options) {
    Skeleton skeleton = input;
    std::vector<char> held;
    if (domain) take_radii_from_domain(skeleton, *domain, domain_query, options);
    if (domain) held = held_vertices(skeleton, *domain, domain_query, options);
    return prepare_skeleton(skeleton, options.pipeline, held.empty() ? nullptr : &held);
}

MeshRun mesh_skeleton(const Skeleton& input, const TriangleMesh* domain, const MeshOptions& options) {
    return mesh_skeleton(input, domain, nullptr, options);
}

MeshRun mesh_skeleton(const Skeleton& input, const TriangleMesh* domain, const SurfaceQuery* domain_query,
                      const MeshOptions& options) {
    MeshRun run;
    const Skeleton skeleton = start_run(run, input, domain, domain_query, options);
    auto t = std::chrono::steady_clock::now();
    run.pipeline = run_pipeline(skeleton, run.options, held_of(run));
    run.pipeline_ms = ms_since(t);
    t = std::chrono::steady_clock::now();
    set_raw_quality(run, options);
    run.raw_quality_ms = ms_since(t);
    // The raw mesh is the output: an inverted hex at a moved root refuses the run (with a domain the fit may untangle).
    if ((!domain || !options.finish) && run.raw_quality.inverted > 0) {
        check_moved_roots(run.pipeline);
        check_border_creases(run.pipeline);
    }
    if (domain && options.finish) {
        t = std::chrono::steady_clock::now();
        finish_with_retry(run, skeleton, *domain, options);
        compare_fan_layouts(run, skeleton, *domain, options);
        retry_structural(run, skeleton, *domain, options);
        retry_finer(run, *domain, options);
        refine_to_distance(run, *domain, options);
        run.finish_ms = ms_since(t);
    }
    if (options.partitions > 0) {
        t = std::chrono::steady_clock::now();
        PartitionOptions po;
        po.parts = options.partitions;
        run.partition = partition_hexes(run.mesh(), po);
        run.partition_ms = ms_since(t);
    }
    return run;
}

MeshRun mesh_skeleton_raw(const Skeleton& input, const TriangleMesh* domain, const SurfaceQuery* domain_query,
                          const MeshOptions& options, RawRunCache& cache) {
    const bool raw_only = (!domain || !options.finish) && options.partitions <= 0 && options.pipeline.resample;
    const bool reuse = cache.valid;
    cache.valid = false;  // until this run succeeds
    if (!raw_only) return mesh_skeleton(input, domain, domain_query, options);
    MeshRun run;
    const Skeleton skeleton = start_run(run, input, domain, domain_query, options);
    auto t = std::chrono::steady_clock::now();
    // run_pipeline with the stages after prepare_skeleton through the remesh cache (the same calls, the same options).
    run.pipeline = prepare_skeleton(skeleton, run.options, held_of(run));
    PipelineResult& res = run.pipeline;
    const auto t_remesh = std::chrono::steady_clock::now();
    RemeshCache& rc = cache.remesh;
    rc.analysis_options = run.options.analysis;
    rc.surface_options = run.options.connection_surfaces;
    rc.raw_options = run.options.raw_mesh;
    const HexMesh old_mesh = reuse ? rc.raw.mesh : HexMesh{};
    cache.last =
        reuse ? remesh_incremental(rc, res.skeleton, &res.analysis) : remesh_full(rc, res.skeleton, &res.analysis);
    res.predicted = predict_raw_mesh(res.skeleton, res.analysis, rc.surfaces);
    res.predicted.virtual_branches = res.virtual_branches;
    res.timings_ms.push_back({"connection_surfaces", ms_since(t_remesh)});
    res.timings_ms.push_back({"frames", 0.0});  // in the remesh above
    res.timings_ms.push_back({"raw_mesh", 0.0});
    res.raw = rc.raw;
    add_fan_side_roots(res, rc.surfaces.fan_blocks, skeleton, run.options.resample);
    run.pipeline_ms = ms_since(t);

    t = std::chrono::steady_clock::now();
    const bool same_cells =
        reuse && old_mesh.points.size() == res.raw.mesh.points.size() && old_mesh.hexes == res.raw.mesh.hexes;
    if (same_cells) {
        // The topology reads the cells only: the cached one is this mesh's.
        run.raw_quality = update_quality(cache.quality, old_mesh, res.raw.mesh, cache.topology);
    } else {
        run.raw_quality = compute_quality(res.raw.mesh, cache.topology);
    }
    run.prediction_exact = prediction_matches(run.raw_quality, res.predicted);
    if (run.raw_quality.inverted > 0) {  // as mesh_skeleton's raw output
        check_moved_roots(res);
        check_border_creases(res);
    }
    cache.quality = run.raw_quality;
    if (options.keep_raw_topology) run.raw_topology = cache.topology;
    run.raw_quality_ms = ms_since(t);
    cache.valid = true;
    return run;
}

}  // namespace mesohex
