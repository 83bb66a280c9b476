// `mesohex analyze SKELETON`: prints the skeleton analysis (paper step 2): counts, vertex classes, predicted hexes,
// the repairs `mesh` makes before meshing (pipeline.h prepare_skeleton: e.g. a fan edge retracted from a branch on its
// end); then the verdict of `mesh` on the same skeleton (the raw pipeline is run, nothing is written), so that a
// skeleton analyze approves is one mesh accepts, with the same exit status when it does not. With --surface, the radii
// and the branch tips trimmed where the domain does not hold them (mesh.h prepare_mesh_skeleton) as `mesh --surface`,
// and the verdict is that of `mesh --surface --raw` (mesh_skeleton without the finishing).
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "mesohex/mesh.h"
#include "mesohex/pipeline.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex::cli {

namespace {

struct AnalyzeArgs {
    std::string path;
    double radius = 0;            // as `mesh --radius`
    bool no_resample = false;     // as `mesh --no-resample`
    bool no_fan_caps = false;     // as `mesh --no-fan-cap-branches`
    bool no_fan_sides = false;    // as `mesh --no-fan-side-branches`
    bool no_band_pillow = false;  // as `mesh --no-docked-band-pillow`
    bool no_verdict = false;
    std::string surface;        // as `mesh --surface`: radii from it when the file has none, tips outside it trimmed
    bool no_trim_tips = false;  // as `mesh --no-trim-tips`
};

}  // namespace

void register_analyze(CLI::App& app, int* status) {
    auto args = std::make_shared<AnalyzeArgs>();
    CLI::App* cmd = app.add_subcommand("analyze",
                                       "Classify a skeleton's vertices, count branches and leaflets, "
                                       "predict the raw hex count, and check that `mesh` accepts it.");
    cmd->add_option("skeleton", args->path, "Skeleton file (.skel, .cg, .cgr, .ig, .obj)")->required();
    cmd->add_option("--radius", args->radius, "As for `mesh`: radius for skeletons without one");
    cmd->add_flag("--no-resample", args->no_resample, "As for `mesh`: keep the input sampling");
    cmd->add_flag("--no-fan-cap-branches", args->no_fan_caps,
                  "As for `mesh`: retract the fan edge from a branch on a fan-block chain end instead of standing the "
                  "branch on the block's cap");
    cmd->add_flag("--no-fan-side-branches", args->no_fan_sides,
                  "As for `mesh`: leave a branch across the fan line too thick for its moved root refused instead of "
                  "standing it on the fan block's side section or notch");
    cmd->add_flag("--no-docked-band-pillow", args->no_band_pillow,
                  "As for `mesh`: refuse a docked wall whose feet do not match its plate's grid instead of pillowing "
                  "its band");
    cmd->add_flag("--no-verdict", args->no_verdict, "Only the analysis: do not run the raw pipeline");
    cmd->add_option("--surface", args->surface,
                    "As for `mesh`: the domain (radii from it when the file has none; branch tips outside it trimmed)");
    cmd->add_flag("--no-trim-tips", args->no_trim_tips, "As for `mesh`: keep branch tips outside the --surface domain");
    cmd->footer(
        "Example: mesohex analyze cactus.skel\n"
        "Exit status: 0 = `mesh` accepts the skeleton (the raw mesh was built and has the predicted counts); "
        "otherwise the status `mesh` gives for it: 2 invalid input, 3 unsupported configuration, 4 file "
        "error, 6 numerical failure (the message names the skeleton element).");
    cmd->callback([args, status]() {
        const Skeleton skeleton = read_skeleton(args->path);
        // The calls `mesh` makes (mesh_job.cpp, pipeline.h) with the same options: the same repairs before the
        // analysis, the same verdict. --no-verdict stops after the repairs and the analysis of their result.
        PipelineOptions options;
        options.radius = args->radius;
        options.resample = !args->no_resample;
        options.connection_surfaces.blocks.fan_cap_branches = !args->no_fan_caps;
        options.connection_surfaces.blocks.fan_side_branches = !args->no_fan_sides;
        options.repair.docked_band_pillow = !args->no_band_pillow;
        std::optional<TriangleMesh> domain;
        if (!args->surface.empty()) domain = read_surface(args->surface);
        MeshOptions mesh_options;  // with --surface: mesh_skeleton's radii and trims, the raw mesh only
        mesh_options.pipeline = options;
        mesh_options.finish = false;
        mesh_options.trim_unheld_tips = !args->no_trim_tips;
        const auto prepare = [&] {
            return domain ? prepare_mesh_skeleton(skeleton, &*domain, nullptr, mesh_options)
                          : prepare_skeleton(skeleton, options);
        };
        const auto run = [&] {
            return domain ? mesh_skeleton(skeleton, &*domain, mesh_options).pipeline : run_pipeline(skeleton, options);
        };
        const PipelineResult res =
            args->no_verdict ? at_stage("analysis", args->path, prepare) : at_stage("mesh", args->path, run);
        std::cout << args->path << "\n" << analysis_to_text(res.input_analysis) << repairs_to_text(res, options);
        *status = 0;
        if (args->no_verdict) return;
        std::cout << "verdict: mesh accepts it: raw mesh of " << res.raw.mesh.hexes.size() << " hexes, "
                  << res.raw.mesh.points.size() << " vertices\n";
    });
}

}  // namespace mesohex::cli
