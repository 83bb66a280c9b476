// `mesohex mesh SKELETON -o OUT [--radius R] [--no-resample] [--raw] [--report REPORT.json] [--threads N]`:
// skeleton -> raw all-hex mesh (paper steps 1-7); prints the quality summary; optional JSON report.
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "commands.h"
#include "mesohex/core/error.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/skeleton_io.h"

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
    cmd->add_flag("--raw", args->raw, "Stop after the raw mesh (currently always the case)");
    cmd->add_option("--report", args->report, "Write a JSON report (skeleton, predicted, quality, timings_ms)");
    cmd->add_option("--threads", args->threads, "Worker threads (0 = all cores)");
    cmd->footer("Example: mesohex mesh cactus.skel -o cactus.mesh --report cactus.json");
    cmd->callback([args, status]() {
        std::optional<tbb::global_control> threads;
        if (args->threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, args->threads);

        const auto t0 = std::chrono::steady_clock::now();
        const Skeleton skeleton = read_skeleton(args->skeleton);
        const auto t1 = std::chrono::steady_clock::now();
        PipelineOptions options;
        options.radius = args->radius;
        options.resample = !args->no_resample;
        const PipelineResult res = run_pipeline(skeleton, options);
        const auto t2 = std::chrono::steady_clock::now();
        const QualityReport q = compute_quality(res.raw.mesh);
        const auto t3 = std::chrono::steady_clock::now();
        write_hex_mesh(args->output, res.raw.mesh, q.sj);
        const auto t4 = std::chrono::steady_clock::now();
        auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };

        const bool prediction_ok = q.hexes == res.predicted.hexes && q.vertices == res.predicted.vertices &&
                                   q.singular_interior_edges == res.predicted.interior_irregular_edges &&
                                   q.singular_boundary_edges == res.predicted.boundary_irregular_edges;
        std::cout << "mesh " << args->skeleton << ": " << res.skeleton.points.size() << " skeleton vertices, "
                  << res.skeleton.edges.size() << " edges (" << (options.resample ? "resampled" : "input sampling")
                  << "), radius " << res.radius_source;
        if (res.radius_source != "file") std::cout << " " << res.radius;
        std::cout << "\n";
        std::cout << "raw mesh: " << q.vertices << " vertices, " << q.hexes << " hexes, SJ min " << q.sj_min
                  << " avg " << q.sj_avg << ", inverted " << q.inverted << ", "
                  << (q.validation.valid() ? "valid" : "INVALID") << ", Euler characteristic "
                  << q.euler_characteristic << (prediction_ok ? ", prediction exact" : ", PREDICTION MISMATCH")
                  << " -> " << args->output << "\n";

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
            rep["quality"] = nlohmann::json::parse(quality_to_json(q));
            nlohmann::json timings = nlohmann::json::object();
            timings["read_skeleton"] = ms(t0, t1);
            for (const StageTiming& t : res.timings_ms) timings[t.stage] = t.ms;
            timings["pipeline_total"] = ms(t1, t2);
            timings["quality"] = ms(t2, t3);
            timings["write_mesh"] = ms(t3, t4);
            rep["timings_ms"] = timings;
            write_file_atomically(args->report, rep.dump(2) + "\n");
        }
        *status = 0;
    });
}

}  // namespace mesohex::cli
