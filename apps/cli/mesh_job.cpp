// The meshing job shared by `mesohex mesh` and `mesohex auto` (see mesh_job.h).
#include "mesh_job.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <optional>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "mesohex/core/error.h"
#include "mesohex/finish.h"
#include "mesohex/pipeline.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/hex_io.h"

namespace mesohex::cli {

namespace {

// A one-line progress bar on stderr for the fitting loop, drawn only on a terminal and only after the first second.
class FitProgressBar {
public:
    FitProgressBar(int max_iterations, bool enabled) : max_(max_iterations), enabled_(enabled) {}
    void update(const FitProgress& p) {
        if (!enabled_) return;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        if (elapsed < 1.0) return;
        const int width = 30;
        const int filled = std::min(width, p.iteration * width / std::max(1, max_));
        std::cerr << "\rfit [" << std::string(static_cast<std::size_t>(filled), '#')
                  << std::string(static_cast<std::size_t>(width - filled), '.') << "] " << p.iteration << "/" << max_
                  << "  SJ min " << p.sj_min << "  inverted " << p.inverted << "   " << std::flush;
        drawn_ = true;
    }
    ~FitProgressBar() {
        if (drawn_) std::cerr << "\n";
    }

private:
    int max_;
    bool enabled_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// The same for the untangling, quality and smoothing passes (one line per stage, rounds or sweeps instead of
// iterations).
class StageProgressLine {
public:
    StageProgressLine(const char* label, const char* unit, int max_rounds, bool enabled)
        : label_(label), unit_(unit), max_(max_rounds), enabled_(enabled) {}
    void update(int round, const std::string& detail) {
        if (!enabled_) return;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        if (elapsed < 1.0) return;
        std::cerr << "\r" << label_ << " " << unit_ << " " << round << "/" << max_ << "  " << detail << "   "
                  << std::flush;
        drawn_ = true;
    }
    ~StageProgressLine() {
        if (drawn_) std::cerr << "\n";
    }

private:
    const char* label_;
    const char* unit_;
    int max_;
    bool enabled_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

nlohmann::json counts_json(const AnalysisCounts& c) {
    return {{"vertices", c.vertices},
            {"edges", c.edges},
            {"faces", c.faces},
            {"branches", c.branches},
            {"branching_points", c.branching_points},
            {"joints", c.joints},
            {"extremities", c.extremities},
            {"cycles", c.cycles},
            {"components", c.components},
            {"rings", c.rings},
            {"leaflets", c.leaflets},
            {"bl_joints", c.bl_joints},
            {"ll_joints", c.ll_joints},
            {"fan_edges", c.fan_edges},
            {"boundary_edges", c.boundary_edges},
            {"isolated_vertices", c.isolated},
            {"euler_characteristic", c.vertices - c.edges + c.faces}};
}

nlohmann::json xyz(const Vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); }

nlohmann::json valence_json(const std::map<int, long>& m) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [valence, count] : m) j[std::to_string(valence)] = count;
    return j;
}

}  // namespace

void add_mesh_job_options(CLI::App* cmd, MeshJob* job) {
    cmd->add_flag("--radius-from-surface", job->radius_from_surface,
                  "Take every radius from the surface (factor x distance), even when the skeleton file has radii "
                  "(without radii in the file and with --surface, this is what happens)");
    cmd->add_option("--radius-factor", job->radius_factor,
                    "Radius from the surface = factor x distance to the surface (room for the padding layer)")
        ->capture_default_str();
    cmd->add_option("--levels", job->levels, "1->8 subdivision levels after padding (default: from --size, else 1, or 2 when the padded mesh's mean edge "
                    "is longer than 1/16 of the domain's bounding-box diagonal or the raw mesh's mean scaled Jacobian is below 0.5, "
                    "within 150000 hexes and if padding inverted nothing)");
    cmd->add_option("--size", job->size, "Target mean edge length; chooses the subdivision levels");
    cmd->add_option("--refine", job->refine,
                    "Subdivision per level: uniform (1->8), longitudinal (only the sheets along the branches: more "
                    "cross-sections), radial (only the cross-sections of the branches)")
        ->check(CLI::IsMember({"uniform", "longitudinal", "radial"}))
        ->capture_default_str();
    cmd->add_flag("--no-pad", job->no_pad, "Skip the padding layer");
    cmd->add_flag("--no-fit", job->no_fit, "Skip the surface fitting (and untangling)");
    cmd->add_flag("--no-untangle", job->no_untangle,
                  "Skip the untangling of inverted hexes after the fit (the report and exit status 5 still say so)");
    cmd->add_flag("--no-smooth", job->no_smooth, "Skip the final smoothing pass");
    cmd->add_flag("--no-retry", job->no_retry,
                  "One attempt only: no second adaptation with the first joints farther from the branching points "
                  "when the mesh misses a goal (inverted hex, SJ min < 0.3, avg < 0.85, Hausdorff > 1 % of the "
                  "diagonal)");
    cmd->add_option("--iterations", job->iterations, "Iteration cap of the fitting loop")->capture_default_str();
    cmd->add_option("--fit-weight", job->fit_weight,
                    "Weight of the pull of the boundary onto the surface, relative to the shape terms")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--improve-below", job->improve_sj,
                    "Quality pass after fitting on the hexes whose scaled Jacobian is below this (0 = off)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 0.99));
    cmd->add_flag("-q,--quiet", job->quiet, "No progress bar");
    cmd->add_option("--report", job->report, "Write a JSON report (skeleton, predicted, quality, timings_ms)");
    cmd->add_option("--threads", job->threads, "Worker threads (0 = all cores)");
}

int run_mesh_job(const MeshJob& job, Skeleton skeleton, const std::optional<TriangleMesh>& domain,
                 std::chrono::steady_clock::time_point start, const nlohmann::json* report_extra,
                 std::optional<std::chrono::steady_clock::time_point> total_start) {
    std::string radius_note;
    if (domain) {
        if (skeleton.radii.empty() || job.radius_from_surface) {
            const SurfaceQuery query(*domain);
            RadiusFromSurfaceOptions ro;
            ro.factor = job.radius_factor;
            const RadiusFromSurface rs = radius_from_surface(skeleton, query, ro);
            for (std::size_t v = 0; v < rs.radii.size(); ++v)
                if (!(rs.radii[v] > 0))
                    throw Error(ErrorCode::InvalidInput,
                                job.skeleton + ": skeleton vertex " + std::to_string(v) +
                                    " lies on or outside the surface " + job.surface +
                                    ": no radius can be taken from it",
                                {ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
            skeleton.radii = rs.radii;
            radius_note = "surface (" + std::to_string(job.radius_factor) + " x distance)";
        }
    }
    const auto t0 = start;
    const auto t1 = std::chrono::steady_clock::now();
    PipelineOptions options;
    options.radius = job.radius;
    options.resample = !job.no_resample;
    PipelineResult res = run_pipeline(skeleton, options);
    const auto t2 = std::chrono::steady_clock::now();
    QualityReport q = compute_quality(res.raw.mesh);
    const auto t3 = std::chrono::steady_clock::now();

    const bool finishing = domain.has_value() && !job.raw;
    const auto finish = [&](const PipelineResult& run) {
        FinishOptions fo;
        fo.pad = !job.no_pad;
        fo.levels = job.levels;
        fo.size = job.size;
        if (job.refine != "uniform") {
            fo.refinement = job.refine == "longitudinal" ? FinishOptions::Refinement::Longitudinal
                                                         : FinishOptions::Refinement::Radial;
            fo.chunk_hex.assign(run.raw.hex_edge.size(), 0);
            for (std::size_t h = 0; h < run.raw.hex_edge.size(); ++h) {
                const int e = run.raw.hex_edge[h];
                fo.chunk_hex[h] = e >= 0 && run.analysis.edge_degree[static_cast<std::size_t>(e)] == 0;
            }
        }
        fo.fit = !job.no_fit;
        fo.untangle = !job.no_fit && !job.no_untangle;
        fo.smooth = !job.no_smooth;
        fo.fitting.max_iterations = job.iterations;
        fo.fitting.lambda = job.fit_weight;
        fo.improve_sj = job.improve_sj;
        FitProgressBar bar(job.iterations, !job.quiet && isatty(STDERR_FILENO));
        fo.fitting.progress = [&bar](const FitProgress& p) { bar.update(p); };
        const bool show = !job.quiet && isatty(STDERR_FILENO);
        StageProgressLine untangle_line("untangle", "round", fo.untangling.max_rounds, show);
        StageProgressLine improve_line("improve", "round", fo.improving.max_rounds, show);
        StageProgressLine smooth_line("smooth", "sweep", fo.smoothing.max_sweeps + fo.smoothing.resweeps, show);
        fo.untangling.progress = [&untangle_line](const UntangleProgress& p) {
            untangle_line.update(p.round, "inverted " + std::to_string(p.inverted));
        };
        fo.improving.progress = [&improve_line](const UntangleProgress& p) {
            improve_line.update(p.round, "inverted " + std::to_string(p.inverted));
        };
        fo.smoothing.progress = [&smooth_line](const SmoothProgress& p) {
            smooth_line.update(p.sweep, "moves " + std::to_string(p.moves));
        };
        return finish_mesh(run.raw.mesh, *domain, fo);
    };
    std::optional<FinishResult> fin;
    nlohmann::json attempts = nlohmann::json::array();
    const auto attempt_json = [](const AdaptationOptions& a, const FinishResult& f) {
        nlohmann::json j = {{"free_branching_reach", a.free_branching_reach},
                            {"hexes", f.quality.hexes},
                            {"sj_min", f.quality.sj_min},
                            {"sj_avg", f.quality.sj_avg},
                            {"inverted", f.quality.inverted},
                            {"missed_goals", missed_goals(f)}};
        if (f.distance_measured) j["hausdorff_relative_max"] = f.distance.relative_max;
        return j;
    };
    if (finishing) {
        fin = finish(res);
        attempts.push_back(attempt_json(options.adaptation, *fin));
        // Second attempt: when the mesh misses its goals (MeshGoals), adapt again with the cautious reach at branching
        // points (AdaptationOptions::free_branching_reach) and keep the better result (better_finish).
        PipelineOptions cautious = options;
        cautious.adaptation.free_branching_reach = options.adaptation.branching_reach;
        if (!job.no_retry && !job.no_fit && options.resample && missed_goals(*fin) > 0 &&
            cautious.adaptation.free_branching_reach != options.adaptation.free_branching_reach) {
            PipelineResult res2 = run_pipeline(skeleton, cautious);
            if (!(res2.skeleton == res.skeleton)) {
                if (!job.quiet)
                    std::cerr << "mesohex: the mesh misses " << missed_goals(*fin)
                              << " goal(s); second attempt with first joints farther from the branching points\n";
                FinishResult fin2 = finish(res2);
                attempts.push_back(attempt_json(cautious.adaptation, fin2));
                if (better_finish(fin2, *fin)) {
                    fin = std::move(fin2);
                    res = std::move(res2);
                    q = compute_quality(res.raw.mesh);
                    options = cautious;
                }
            }
        }
    }
    const QualityReport& final_quality = fin ? fin->quality : q;
    write_hex_mesh(job.output, fin ? fin->mesh : res.raw.mesh, final_quality.sj);
    const auto t4 = std::chrono::steady_clock::now();
    auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };

    const bool prediction_ok = q.hexes == res.predicted.hexes && q.vertices == res.predicted.vertices &&
                               q.singular_interior_edges == res.predicted.interior_irregular_edges &&
                               q.singular_boundary_edges == res.predicted.boundary_irregular_edges;
    std::cout << "mesh " << job.skeleton << ": " << res.skeleton.points.size() << " skeleton vertices, "
              << res.skeleton.edges.size() << " edges (" << (options.resample ? "resampled" : "input sampling")
              << "), radius " << (radius_note.empty() ? res.radius_source : radius_note);
    if (res.radius_source != "file") std::cout << " " << res.radius;
    std::cout << "\n";
    std::cout << "raw mesh: " << q.vertices << " vertices, " << q.hexes << " hexes, SJ min " << q.sj_min
              << " avg " << q.sj_avg << ", inverted " << q.inverted << ", "
              << (q.validation.valid() ? "valid" : "INVALID") << ", Euler characteristic "
              << q.euler_characteristic << (prediction_ok ? ", prediction exact" : ", PREDICTION MISMATCH")
              << (finishing ? "" : " -> " + job.output) << "\n";
    if (fin) {
        for (const FinishStage& st : fin->stages) {
            if (st.stage == "input") continue;
            std::cout << st.stage << ": " << st.hexes << " hexes, SJ min " << st.sj_min << " avg " << st.sj_avg
                      << ", inverted " << st.inverted << " (" << st.ms << " ms)\n";
        }
        const QualityReport& f = fin->quality;
        std::cout << "final mesh: " << f.vertices << " vertices, " << f.hexes << " hexes, SJ min " << f.sj_min
                  << " avg " << f.sj_avg << ", inverted " << f.inverted << ", "
                  << (f.validation.valid() ? "valid" : "INVALID");
        if (fin->distance_measured)
            std::cout << ", Hausdorff " << fin->distance.max << " (" << 100.0 * fin->distance.relative_max
                      << " % of the bbox diagonal)";
        std::cout << " -> " << job.output << "\n";
        if (attempts.size() > 1)
            for (std::size_t i = 0; i < attempts.size(); ++i) {
                const nlohmann::json& a = attempts[i];
                std::cout << "attempt " << i + 1 << " (first joints at " << a["free_branching_reach"].get<double>()
                          << " x the reach at branching points): SJ min " << a["sj_min"].get<double>() << " avg "
                          << a["sj_avg"].get<double>() << ", inverted " << a["inverted"].get<long>();
                if (a.contains("hausdorff_relative_max"))
                    std::cout << ", Hausdorff " << 100.0 * a["hausdorff_relative_max"].get<double>() << " %";
                std::cout << (a["free_branching_reach"].get<double>() == options.adaptation.free_branching_reach
                                  ? " (kept)"
                                  : "")
                          << "\n";
            }
    }

    if (!job.report.empty()) {
        nlohmann::json rep;
        rep["input"] = job.skeleton;
        rep["output"] = job.output;
        rep["skeleton"] = counts_json(res.input_analysis.counts);
        rep["meshed_skeleton"] = counts_json(res.analysis.counts);
        rep["resampled"] = options.resample;
        rep["radius"] = {{"source", res.radius_source}, {"value", res.radius}};
        if (res.radius_source == "default") rep["radius"]["rule"] = "0.25 x mean skeleton edge length";
        rep["predicted"] = {{"hexes", res.predicted.hexes},
                            {"vertices", res.predicted.vertices},
                            {"irregular_edges",
                             {{"interior", valence_json(res.predicted.interior_irregular_edges)},
                              {"boundary", valence_json(res.predicted.boundary_irregular_edges)}}}};
        rep["prediction_matches"] = prediction_ok;
        rep["quality"] = nlohmann::json::parse(quality_to_json(final_quality));
        rep["raw_quality"] = nlohmann::json::parse(quality_to_json(q));
        if (!radius_note.empty()) rep["radius"]["source"] = radius_note;
        if (fin) {
            nlohmann::json stages = nlohmann::json::array();
            for (const FinishStage& st : fin->stages)
                stages.push_back({{"stage", st.stage},
                                  {"ms", st.ms},
                                  {"vertices", st.vertices},
                                  {"hexes", st.hexes},
                                  {"sj_min", st.sj_min},
                                  {"sj_avg", st.sj_avg},
                                  {"inverted", st.inverted}});
            rep["stages"] = stages;
            rep["surface"] = job.surface;
            rep["subdivision_levels"] = fin->subdivision_levels;
            rep["fit"] = {{"iterations", fin->fit_iterations}, {"converged", fin->fit_converged}};
            rep["untangled"] = fin->untangled;
            rep["attempts"] = attempts;  // first the default adaptation, then the cautious one when it was tried
            rep["free_branching_reach"] = options.adaptation.free_branching_reach;  // of the mesh written
            if (fin->distance_measured)
                rep["hausdorff"] = {{"max", fin->distance.max},
                                    {"mean", fin->distance.mean},
                                    {"relative_max", fin->distance.relative_max},
                                    {"relative_mean", fin->distance.relative_mean},
                                    {"mesh_to_surface_max", fin->distance.mesh_to_surface_max},
                                    {"surface_to_mesh_max", fin->distance.surface_to_mesh_max},
                                    {"mesh_to_surface_at", xyz(fin->distance.mesh_to_surface_at)},
                                    {"surface_to_mesh_at", xyz(fin->distance.surface_to_mesh_at)},
                                    {"bbox_diagonal", fin->distance.diagonal}};
        }
        nlohmann::json timings = nlohmann::json::object();
        timings["read_skeleton"] = ms(t0, t1);
        for (const StageTiming& t : res.timings_ms) timings[t.stage] = t.ms;
        timings["pipeline_total"] = ms(t1, t2);
        timings["quality"] = ms(t2, t3);
        if (fin) {
            for (const FinishStage& st : fin->stages)
                if (st.stage != "input") timings[st.stage] = st.ms;
            timings["hausdorff"] = fin->distance_ms;
            timings["finish_total"] = fin->total_ms;
        }
        timings["write_and_finish"] = ms(t3, t4);
        if (report_extra) {
            for (const auto& [key, value] : report_extra->items())
                if (key != "timings_ms") rep[key] = value;
            if (report_extra->contains("timings_ms"))
                for (const auto& [key, value] : (*report_extra)["timings_ms"].items()) timings[key] = value;
            timings["total"] = ms(total_start.value_or(t0), t4);
        }
        rep["timings_ms"] = timings;
        write_file_atomically(job.report, rep.dump(2) + "\n");
    }
    if (final_quality.inverted > 0 || !final_quality.validation.valid()) {
        std::cerr << "mesohex: warning: the mesh written to " << job.output << " has " << final_quality.inverted
                  << " inverted hex(es) (scaled Jacobian <= 0)"
                  << (final_quality.validation.valid() ? "" : " and is not a valid hex mesh") << "\n";
        return 5;
    }
    return 0;
}

}  // namespace mesohex::cli
