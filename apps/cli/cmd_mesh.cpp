// `mesohex mesh SKELETON -o OUT [--surface SURFACE] [--radius R] [--no-resample] [--raw] [--report REPORT.json] ...`:
// skeleton -> raw all-hex mesh (paper steps 1-7); with a domain surface, then pad -> subdivide -> fit -> untangle
// (finish_mesh). Prints the quality summary; optional JSON report. Exit status 5 when the mesh written has inverted
// hexes (it is still written, and the message says so).
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <tbb/global_control.h>

#include "commands.h"
#include "mesh_job.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex::cli {

void register_mesh(CLI::App& app, int* status) {
    auto args = std::make_shared<MeshJob>();
    CLI::App* cmd = app.add_subcommand("mesh", "Mesh a skeleton: raw all-hex mesh guided by its branches.");
    cmd->add_option("skeleton", args->skeleton, "Skeleton file (.skel, .cg, .cgr, .ig, .obj)")->required();
    cmd->add_option("-o,--output", args->output, "Output hex mesh (.mesh, .vtk, .vtu, .msh, .inp, .exo)")->required();
    cmd->add_option("--radius", args->options.pipeline.radius,
                    "Radius for skeletons without one (default: 0.25 x mean skeleton edge length)");
    cmd->add_flag_callback(
        "--no-resample", [args] { args->options.pipeline.resample = false; },
        "Keep the input sampling (hexes = 4 x edges)");
    cmd->add_option("--surface", args->surface,
                    "Domain surface (.off .obj .stl .ply): pad, subdivide, fit the mesh to it, untangle if needed");
    cmd->add_flag_callback(
        "--raw", [args] { args->options.finish = false; }, "Stop after the raw mesh even when --surface is given");
    add_mesh_job_options(cmd, args.get());
    cmd->footer(
        "Examples:\n  mesohex mesh cactus.skel -o cactus_raw.mesh --report cactus.json\n"
        "  mesohex mesh cactus.skel --surface cactus.obj -o cactus.mesh\n"
        "Exit status: 0 ok; 2 invalid input; 3 unsupported configuration; 4 file error; 5 the mesh written "
        "has inverted hexes (said on stderr).");
    cmd->callback([args, status]() {
        std::optional<tbb::global_control> threads;
        if (args->threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, args->threads);

        const auto t0 = std::chrono::steady_clock::now();
        Skeleton skeleton = read_skeleton(args->skeleton);
        std::optional<TriangleMesh> domain;
        if (!args->surface.empty()) domain = read_surface(args->surface);
        *status = at_stage(
            "mesh", args->skeleton, [&] { return run_mesh_job(*args, std::move(skeleton), domain, t0); }, false);
    });
}

}  // namespace mesohex::cli
