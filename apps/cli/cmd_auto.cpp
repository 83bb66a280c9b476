// `mesohex auto SURFACE -o OUT [finishing options] [--report REPORT.json]`: surface -> curve skeleton by mean
// curvature flow (skeletonize_surface) -> the same meshing job as `mesohex mesh SKELETON --surface SURFACE`. The
// skeleton is written beside the mesh (OUT with its extension replaced by .skeleton.obj) so the user can edit it and
// re-run `mesohex mesh`. A surface that cannot be skeletonized is an error and nothing is written.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "commands.h"
#include "mesh_job.h"
#include "mesohex/surface/skeletonize.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex::cli {

namespace {

struct AutoArgs {
    MeshJob job;
    std::string surface;
};

}  // namespace

void register_auto(CLI::App& app, int* status) {
    auto args = std::make_shared<AutoArgs>();
    CLI::App* cmd = app.add_subcommand(
        "auto", "Surface -> hex mesh in one step: skeletonize (mean curvature flow), then mesh with the surface.");
    cmd->add_option("surface", args->surface, "Closed surface (.off .obj .stl .ply), one component, manifold")
        ->required();
    cmd->add_option("-o,--output", args->job.output, "Output hex mesh (.mesh, .vtk, .vtu, .msh, .inp)")->required();
    cmd->add_flag_callback("--no-resample", [args] { args->job.options.pipeline.resample = false; },
                           "Keep the skeleton's sampling (hexes = 4 x edges)");
    cmd->add_flag_callback("--raw", [args] { args->job.options.finish = false; },
                           "Stop after the raw mesh (no padding, subdivision or fitting)");
    add_mesh_job_options(cmd, &args->job);
    cmd->footer("The skeleton used is written beside the mesh (OUT.skeleton.obj, with radii): edit it and re-run\n"
                "  mesohex mesh OUT.skeleton.obj --surface SURFACE -o OUT.mesh\n"
                "Examples:\n  mesohex auto cactus.obj -o cactus.mesh --report cactus.json\n"
                "  mesohex auto aorta.stl -o aorta.vtu --levels 2\n"
                "Exit status: 0 ok; 2 invalid input (e.g. a surface that is open, non-manifold or in several "
                "components); 3 unsupported configuration; 4 file error; 5 the mesh written has inverted hexes.");
    cmd->callback([args, status]() {
        std::optional<tbb::global_control> threads;
        if (args->job.threads > 0)
            threads.emplace(tbb::global_control::max_allowed_parallelism, args->job.threads);
        auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };

        const auto t0 = std::chrono::steady_clock::now();
        std::optional<TriangleMesh> domain = read_surface(args->surface);
        const auto t1 = std::chrono::steady_clock::now();
        Skeletonization sk = skeletonize_surface(*domain);  // throws (nothing written) when it cannot be done
        const auto t2 = std::chrono::steady_clock::now();
        const std::string skeleton_path =
            std::filesystem::path(args->job.output).replace_extension(".skeleton.obj").string();
        write_skeleton(skeleton_path, sk.skeleton);
        const auto t3 = std::chrono::steady_clock::now();

        std::cout << "skeletonize " << args->surface << ": " << sk.skeleton.points.size() << " vertices, "
                  << sk.skeleton.edges.size() << " edges (MCF skeleton " << sk.mcf_vertices << " vertices; pruned "
                  << sk.pruned_branches << " branches, merged " << sk.merged_branch_points
                  << " branching points, extended " << sk.extended_extremities << " extremities) in " << ms(t1, t2)
                  << " ms -> " << skeleton_path << "\n";

        MeshJob job = args->job;
        job.skeleton = skeleton_path;
        job.surface = args->surface;
        const nlohmann::json extra = {
            {"mode", "auto"},
            {"skeleton_used",
             {{"path", skeleton_path},
              {"source", "skeletonize_surface (mean curvature flow)"},
              {"vertices", sk.skeleton.points.size()},
              {"edges", sk.skeleton.edges.size()},
              {"mcf_vertices", sk.mcf_vertices},
              {"pruned_branches", sk.pruned_branches},
              {"merged_branch_points", sk.merged_branch_points},
              {"extended_extremities", sk.extended_extremities}}},
            {"timings_ms",
             {{"read_surface", ms(t0, t1)}, {"skeletonize", ms(t1, t2)}, {"write_skeleton", ms(t2, t3)}}}};
        // The report's "read_skeleton" is the radius step only (the skeleton is in memory); "total" starts at t0.
        *status = run_mesh_job(job, sk.skeleton, domain, t3, &extra, t0);
        std::cout << "auto: total " << ms(t0, std::chrono::steady_clock::now()) << " ms\n";
    });
}

}  // namespace mesohex::cli
