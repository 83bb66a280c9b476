// `mesohex mesh SKELETON -o OUT [--surface SURFACE] [--radius R] [--no-resample] [--raw] [--report REPORT.json] ...`:
// skeleton -> raw all-hex mesh (paper steps 1-7); with a domain surface, then pad -> subdivide -> fit -> untangle
// (finish_mesh). Prints the quality summary; optional JSON report. Exit status 5 when the mesh written has inverted
// hexes (it is still written, and the message says so).
#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "commands.h"
#include "mesohex/core/error.h"
#include "mesohex/finish.h"
#include "mesohex/pipeline.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex::cli {

namespace {

struct MeshArgs {
    std::string skeleton;
    std::string output;
    double radius = 0;
    bool no_resample = false;
    bool raw = false;
    std::string report;
    int threads = 0;
    std::string surface;
    bool radius_from_surface = false;
    double radius_factor = 0.5;
    int levels = -1;
    double size = 0;
    bool no_pad = false;
    bool no_fit = false;
    int iterations = 300;
    bool quiet = false;
};

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

nlohmann::json valence_json(const std::map<int, long>& m) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [valence, count] : m) j[std::to_string(valence)] = count;
    return j;
}

}  // namespace

void register_mesh(CLI::App& app, int* status) {
    auto args = std::make_shared<MeshArgs>();
    CLI::App* cmd = app.add_subcommand("mesh", "Mesh a skeleton: raw all-hex mesh guided by its branches.");
    cmd->add_option("skeleton", args->skeleton, "Skeleton file (.skel, .cg, .cgr, .ig, .obj)")->required();
    cmd->add_option("-o,--output", args->output, "Output hex mesh (.mesh, .vtk, .vtu, .msh, .inp)")->required();
    cmd->add_option("--radius", args->radius,
                    "Radius for skeletons without one (default: 0.25 x mean skeleton edge length)");
    cmd->add_flag("--no-resample", args->no_resample, "Keep the input sampling (hexes = 4 x edges)");
    cmd->add_option("--surface", args->surface,
                    "Domain surface (.off .obj .stl .ply): pad, subdivide, fit the mesh to it, untangle if needed");
    cmd->add_flag("--raw", args->raw, "Stop after the raw mesh even when --surface is given");
    cmd->add_flag("--radius-from-surface", args->radius_from_surface,
                  "Take every radius from the surface (factor x distance), even when the skeleton file has radii "
                  "(without radii in the file and with --surface, this is what happens)");
    cmd->add_option("--radius-factor", args->radius_factor,
                    "Radius from the surface = factor x distance to the surface (room for the padding layer)")
        ->capture_default_str();
    cmd->add_option("--levels", args->levels, "1->8 subdivision levels after padding (default 1, or from --size)");
    cmd->add_option("--size", args->size, "Target mean edge length; chooses the subdivision levels");
    cmd->add_flag("--no-pad", args->no_pad, "Skip the padding layer");
    cmd->add_flag("--no-fit", args->no_fit, "Skip the surface fitting (and untangling)");
    cmd->add_option("--iterations", args->iterations, "Iteration cap of the fitting loop")->capture_default_str();
    cmd->add_flag("-q,--quiet", args->quiet, "No progress bar");
    cmd->add_option("--report", args->report, "Write a JSON report (skeleton, predicted, quality, timings_ms)");
    cmd->add_option("--threads", args->threads, "Worker threads (0 = all cores)");
    cmd->footer("Examples:\n  mesohex mesh cactus.skel -o cactus_raw.mesh --report cactus.json\n"
                "  mesohex mesh cactus.skel --surface cactus.obj -o cactus.mesh\n"
                "Exit status: 0 ok; 2 invalid input; 3 unsupported configuration; 4 file error; 5 the mesh written "
                "has inverted hexes (said on stderr).");
    cmd->callback([args, status]() {
        std::optional<tbb::global_control> threads;
        if (args->threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, args->threads);

        const auto t0 = std::chrono::steady_clock::now();
        Skeleton skeleton = read_skeleton(args->skeleton);
        std::optional<TriangleMesh> domain;
        std::string radius_note;
        if (!args->surface.empty()) {
            domain = read_surface(args->surface);
            if (skeleton.radii.empty() || args->radius_from_surface) {
                const SurfaceQuery query(*domain);
                RadiusFromSurfaceOptions ro;
                ro.factor = args->radius_factor;
                const RadiusFromSurface rs = radius_from_surface(skeleton, query, ro);
                for (std::size_t v = 0; v < rs.radii.size(); ++v)
                    if (!(rs.radii[v] > 0))
                        throw Error(ErrorCode::InvalidInput,
                                    args->skeleton + ": skeleton vertex " + std::to_string(v) +
                                        " lies on or outside the surface " + args->surface +
                                        ": no radius can be taken from it",
                                    {ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
                skeleton.radii = rs.radii;
                radius_note = "surface (" + std::to_string(args->radius_factor) + " x distance)";
            }
        }
        const auto t1 = std::chrono::steady_clock::now();
        PipelineOptions options;
        options.radius = args->radius;
        options.resample = !args->no_resample;
        const PipelineResult res = run_pipeline(skeleton, options);
        const auto t2 = std::chrono::steady_clock::now();
        const QualityReport q = compute_quality(res.raw.mesh);
        const auto t3 = std::chrono::steady_clock::now();

        const bool finishing = domain.has_value() && !args->raw;
        std::optional<FinishResult> fin;
        if (finishing) {
            FinishOptions fo;
            fo.pad = !args->no_pad;
            fo.levels = args->levels;
            fo.size = args->size;
            fo.fit = !args->no_fit;
            fo.untangle = !args->no_fit;
            fo.fitting.max_iterations = args->iterations;
            FitProgressBar bar(args->iterations, !args->quiet && isatty(STDERR_FILENO));
            fo.fitting.progress = [&bar](const FitProgress& p) { bar.update(p); };
            fin = finish_mesh(res.raw.mesh, *domain, fo);
        }
        const QualityReport& final_quality = fin ? fin->quality : q;
        write_hex_mesh(args->output, fin ? fin->mesh : res.raw.mesh, final_quality.sj);
        const auto t4 = std::chrono::steady_clock::now();
        auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };

        const bool prediction_ok = q.hexes == res.predicted.hexes && q.vertices == res.predicted.vertices &&
                                   q.singular_interior_edges == res.predicted.interior_irregular_edges &&
                                   q.singular_boundary_edges == res.predicted.boundary_irregular_edges;
        std::cout << "mesh " << args->skeleton << ": " << res.skeleton.points.size() << " skeleton vertices, "
                  << res.skeleton.edges.size() << " edges (" << (options.resample ? "resampled" : "input sampling")
                  << "), radius " << (radius_note.empty() ? res.radius_source : radius_note);
        if (res.radius_source != "file") std::cout << " " << res.radius;
        std::cout << "\n";
        std::cout << "raw mesh: " << q.vertices << " vertices, " << q.hexes << " hexes, SJ min " << q.sj_min
                  << " avg " << q.sj_avg << ", inverted " << q.inverted << ", "
                  << (q.validation.valid() ? "valid" : "INVALID") << ", Euler characteristic "
                  << q.euler_characteristic << (prediction_ok ? ", prediction exact" : ", PREDICTION MISMATCH")
                  << (finishing ? "" : " -> " + args->output) << "\n";
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
            std::cout << " -> " << args->output << "\n";
        }

        if (!args->report.empty()) {
            nlohmann::json rep;
            rep["input"] = args->skeleton;
            rep["output"] = args->output;
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
                rep["surface"] = args->surface;
                rep["subdivision_levels"] = fin->subdivision_levels;
                rep["fit"] = {{"iterations", fin->fit_iterations}, {"converged", fin->fit_converged}};
                rep["untangled"] = fin->untangled;
                if (fin->distance_measured)
                    rep["hausdorff"] = {{"max", fin->distance.max},
                                        {"mean", fin->distance.mean},
                                        {"relative_max", fin->distance.relative_max},
                                        {"relative_mean", fin->distance.relative_mean},
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
            rep["timings_ms"] = timings;
            write_file_atomically(args->report, rep.dump(2) + "\n");
        }
        if (final_quality.inverted > 0 || !final_quality.validation.valid()) {
            std::cerr << "mesohex: warning: the mesh written to " << args->output << " has " << final_quality.inverted
                      << " inverted hex(es) (scaled Jacobian <= 0)"
                      << (final_quality.validation.valid() ? "" : " and is not a valid hex mesh") << "\n";
            *status = 5;
        } else {
            *status = 0;
        }
    });
}

}  // namespace mesohex::cli
