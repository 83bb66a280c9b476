// `mesohex thicken SKELETON -o SURFACE.off`: the closed surface of the domain a skeleton with radii describes (union
// of spheres, round cones along edges and thickened leaflets), by marching tetrahedra over a signed distance grid.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "mesohex/core/error.h"
#include "mesohex/surface/surface_check.h"
#include "mesohex/surface/thicken.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex::cli {

namespace {

struct ThickenArgs {
    std::string input;
    std::string output;
    double radius = 0;
    ThickenOptions options;
};

}  // namespace

void register_thicken(CLI::App& app, int* status) {
    auto args = std::make_shared<ThickenArgs>();
    CLI::App* cmd = app.add_subcommand("thicken",
                                       "Closed triangle surface of the domain a skeleton with radii describes "
                                       "(spheres + round cones + thickened leaflets).");
    cmd->add_option("skeleton", args->input, "Skeleton file (.ig, .cg, .cgr, .skel, .obj)")->required();
    cmd->add_option("-o,--output", args->output, "Output surface (.off, .obj or .stl)")->required();
    cmd->add_option("--radius", args->radius, "Radius of every point, used only when the skeleton file has none");
    cmd->add_option("--resolution", args->options.cells_per_radius, "Grid cells per smallest radius")
        ->capture_default_str();
    cmd->add_option("--max-grid-points", args->options.max_grid_points,
                    "Upper bound on the grid size (the cell grows to fit)")
        ->capture_default_str();
    cmd->footer("Example: mesohex thicken aorta.skel -o aorta_domain.off");
    cmd->callback([args, status]() {
        const auto t0 = std::chrono::steady_clock::now();
        Skeleton skeleton = read_skeleton(args->input);
        if (!skeleton.radii.empty() && args->radius > 0)
            std::cerr << "mesohex thicken: note: the skeleton has radii; --radius is ignored\n";
        args->options.radius = args->radius;
        if (skeleton.radii.empty() && !(args->radius > 0))
            throw Error(ErrorCode::InvalidInput, args->input + ": the skeleton has no radii; give one with --radius R");
        const auto t1 = std::chrono::steady_clock::now();
        ThickenStats stats;
        const TriangleMesh surface = at_stage(
            "thicken", args->input, [&] { return thicken(skeleton, args->options, &stats); }, false);
        const auto t2 = std::chrono::steady_clock::now();
        const SurfaceCheck check = check_surface(surface);
        write_surface(args->output, surface);
        auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
        std::cout << "thicken " << args->input << ": " << skeleton.points.size() << " points, " << skeleton.edges.size()
                  << " edges, " << skeleton.faces.size() << " faces (read " << ms(t0, t1) << " ms)\n"
                  << "  grid " << stats.nx << " x " << stats.ny << " x " << stats.nz << ", cell " << stats.cell_size
                  << ", " << stats.primitives << " primitives, " << stats.evaluations << " distance evaluations ("
                  << ms(t1, t2) << " ms)\n"
                  << "  surface: " << surface.points.size() << " vertices, " << surface.triangles.size()
                  << " triangles, " << check.components.size() << " component(s), volume " << check.signed_volume
                  << (check.is_closed_manifold() ? ", closed manifold" : ", NOT a closed manifold") << " -> "
                  << args->output << "\n";
        *status = check.is_closed_manifold() && !surface.triangles.empty() ? 0 : 1;
    });
}

}  // namespace mesohex::cli
