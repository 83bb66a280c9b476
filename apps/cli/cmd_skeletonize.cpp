// `mesohex skeletonize SURFACE -o SKELETON.obj`: curve skeleton with radii by mean curvature flow, cleaned for
// meshing (short spurious branches pruned, close branching points merged, extremities extended). docs/skeletons.md.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "mesohex/core/error.h"
#include "mesohex/surface/skeletonize.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex::cli {

namespace {

struct SkeletonizeArgs {
    std::string input;
    std::string output;
    bool no_prune = false, no_merge = false, no_extend = false;
    SkeletonizeOptions options;
};

}  // namespace

void register_skeletonize(CLI::App& app, int* status) {
    auto args = std::make_shared<SkeletonizeArgs>();
    CLI::App* cmd = app.add_subcommand("skeletonize",
                                       "Curve skeleton with radii of a closed surface (CGAL mean "
                                       "curvature flow), cleaned for meshing.");
    cmd->add_option("surface", args->input, "Closed, manifold, single-component triangle surface")->required();
    cmd->add_option("-o,--output", args->output, "Output skeleton file (.obj or .ig)")->required();
    cmd->add_option("--min-edge-length", args->options.min_edge_length,
                    "MCF edge-collapse length (0 = 0.002 x bounding-box diagonal)")
        ->capture_default_str();
    cmd->add_option("--max-iterations", args->options.max_iterations, "MCF iterations at most")->capture_default_str();
    cmd->add_option("--prune-factor", args->options.prune_factor,
                    "Prune terminal branches shorter than this x their mean radius")
        ->capture_default_str();
    cmd->add_option("--merge-factor", args->options.merge_factor,
                    "Merge branching points closer (along the skeleton) than this x the larger radius")
        ->capture_default_str();
    cmd->add_option("--extension-gap", args->options.extension_gap,
                    "Extended extremities stop this x their radius before the surface")
        ->capture_default_str();
    cmd->add_flag("--inscribed-radii", args->options.inscribed_radii,
                  "Radius = distance to the surface (inscribed ball) instead of the median distance to the "
                  "corresponding surface vertices");
    cmd->add_option("--recentre-passes", args->options.recentre_passes,
                    "Passes moving every joint towards the middle of its cross-section (ray pairs in the plane "
                    "normal to the branch; 0 = off)")
        ->capture_default_str()
        ->check(CLI::Range(0, 100));
    cmd->add_flag("--no-prune", args->no_prune, "Keep every terminal branch");
    cmd->add_flag("--no-merge", args->no_merge, "Do not merge close branching points");
    cmd->add_flag("--no-extend", args->no_extend, "Do not extend the extremities towards the surface");
    cmd->footer("Example: mesohex skeletonize cactus.obj -o cactus_skeleton.obj");
    cmd->callback([args, status]() {
        args->options.prune = !args->no_prune;
        args->options.merge_branch_points = !args->no_merge;
        args->options.extend_extremities = !args->no_extend;
        const auto t0 = std::chrono::steady_clock::now();
        const TriangleMesh surface = read_surface(args->input);
        const auto t1 = std::chrono::steady_clock::now();
        const Skeletonization r =
            at_stage("skeletonize", args->input, [&] { return skeletonize_surface(surface, args->options); });
        const auto t2 = std::chrono::steady_clock::now();
        write_skeleton(args->output, r.skeleton);
        const Skeleton& s = r.skeleton;
        std::vector<int> degree(s.points.size(), 0);
        for (const std::array<int, 2>& e : s.edges) {
            ++degree[static_cast<size_t>(e[0])];
            ++degree[static_cast<size_t>(e[1])];
        }
        int extremities = 0, branching = 0;
        for (int d : degree) {
            if (d == 1) ++extremities;
            if (d >= 3) ++branching;
        }
        auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
        std::cout << "skeletonize " << args->input << ": " << surface.points.size() << " vertices, "
                  << surface.triangles.size() << " triangles (read " << ms(t0, t1) << " ms)\n"
                  << "  mean curvature flow skeleton: " << r.mcf_vertices << " vertices; pruned branches "
                  << r.pruned_branches << ", merged branching points " << r.merged_branch_points
                  << ", extended extremities " << r.extended_extremities << ", re-centred joints " << r.recentred_joints
                  << " (largest move " << r.recentre_max_shift << ") (" << ms(t1, t2) << " ms)\n"
                  << "  skeleton: " << s.points.size() << " points, " << s.edges.size() << " edges, " << extremities
                  << " extremities, " << branching << " branching points, "
                  << static_cast<long>(s.edges.size()) - static_cast<long>(s.points.size()) + 1 << " cycles -> "
                  << args->output << "\n";
        *status = 0;
    });
}

}  // namespace mesohex::cli
