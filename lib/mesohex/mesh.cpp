#include "mesohex/mesh.h"

#include <chrono>
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
    return (two_layouts(run, options) ? 2 * per_layout : per_layout) + (options.finer_retry ? 1 : 0) +
           (options.refine_to_distance ? options.distance_max_levels : 0);
}

// Reports the start of the next finishing attempt (numbered from 1 in the order they run, both layouts together).
void report_attempt(const MeshRun& run, const MeshOptions& options, const std::string& what) {
    if (!options.progress) return;
    const bool paper_after_blocks = !run.attempts.empty() && run.attempts.front().fan_blocks > 0 &&
                                    !options.pipeline.connection_surfaces.blocks.fan_blocks;
    options.progress({"attempt", static_cast<int>(run.attempts.size()) + 1, max_attempts(run, options), 0, 0,
                      paper_after_blocks ? "paper's fan layout, " + what : what});
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
    FinishResult finished = finish_mesh(run.pipeline.raw.mesh, domain, finishing_options(padded, run.pipeline));
    run.attempts.push_back(attempt_of(run.options, run.pipeline, finished, options.goals));
    if (better_attempt(finished, *run.finish, options)) run.finish = std::move(finished);
}

// Finishes the raw mesh of `run` in the domain; when the result misses a goal, the same raw mesh fully padded if the
// selective padding left quads bare, then a second skeleton with the cautious reach at branching points, keeping the
// best.
void finish_with_retry(MeshRun& run, const Skeleton& skeleton, const TriangleMesh& domain, const MeshOptions& options) {
    report_attempt(run, options, "first");
    run.finish = finish_mesh(run.pipeline.raw.mesh, domain, finishing_options(options, run.pipeline));
    run.attempts.push_back(attempt_of(run.options, run.pipeline, *run.finish, options.goals));
    retry_fully_padded(run, domain, options);
    if (!retry_applies(options, run)) return;

    const PipelineOptions cautious = cautious_options(run.options);
    PipelineResult second = run_pipeline(skeleton, cautious, held_of(run));
    if (second.skeleton == run.pipeline.skeleton) return;  // the same skeleton would give the same mesh
    report_attempt(run, options, "cautious joints");
    FinishResult finished = finish_mesh(second.raw.mesh, domain, finishing_options(options, second));
    run.attempts.push_back(attempt_of(cautious, second, finished, options.goals));
    if (!better_attempt(finished, *run.finish, options)) return;
    run.finish = std::move(finished);
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
    report_attempt(run, options, why);
    FinishResult finished = finish_mesh(run.pipeline.raw.mesh, domain, finishing_options(finer, run.pipeline));
    run.attempts.push_back(attempt_of(run.options, run.pipeline, finished, options.goals));
    return finished;
}

// The kept mesh misses a goal: its raw mesh finished again with one level more, the better of the two kept.
void retry_finer(MeshRun& run, const TriangleMesh& domain, const MeshOptions& options) {
    if (!finer_retry_applies(options, run)) return;
    FinishResult finished = finish_one_level_finer(run, domain, options, "one level finer");
    if (better_attempt(finished, *run.finish, options)) run.finish = std::move(finished);
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
