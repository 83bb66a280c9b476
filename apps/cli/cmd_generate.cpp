// `mesohex generate NAME [options] -o SKELETON.obj`: writes a procedural meso-skeleton (with radii).
// `mesohex generate --list`: the generator names, one per line.
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "mesohex/core/error.h"
#include "mesohex/stages/generators.h"
#include "mesohex_io/skeleton_io.h"

namespace mesohex::cli {

namespace {

struct GenerateArgs {
    bool list = false;
    std::string name;
    std::string output;
    GeneratorOptions options;
};

std::string shapes_footer() {
    std::string text = "Shapes (n, m = 0 or omitted: the shape's default):\n";
    for (const std::string& name : generator_names()) text += "  " + name + ": " + generator_help(name) + "\n";
    text += "Example: mesohex generate hand -o hand.obj";
    return text;
}

}  // namespace

void register_generate(CLI::App& app, int* status) {
    auto args = std::make_shared<GenerateArgs>();
    CLI::App* cmd = app.add_subcommand("generate", "Write a procedural meso-skeleton (points with radii, branches, "
                                                   "quad leaflets).");
    cmd->add_flag("--list", args->list, "Print the generator names, one per line, and exit");
    cmd->add_option("name", args->name, "Shape name (see --list)");
    cmd->add_option("-o,--output", args->output, "Output skeleton file (.obj or .ig)");
    cmd->add_option("-n", args->options.n, "Main resolution (meaning per shape, see below)");
    cmd->add_option("-m", args->options.m, "Second resolution (meaning per shape, see below)");
    cmd->add_option("--quarter-turns", args->options.quarter_turns,
                    "twist, torustwist: turn of the section in quarter turns (default 2 = 180 degrees)");
    cmd->add_option("--edge-length", args->options.edge_length, "Scale: typical leaflet edge length")
        ->capture_default_str();
    cmd->add_option("--radius-scale", args->options.radius_scale,
                    "Multiplies every radius (default radii are about 0.3 x the edge length)")
        ->capture_default_str();
    cmd->footer(shapes_footer());
    cmd->callback([args, status]() {
        if (args->list) {
            for (const std::string& name : generator_names()) std::cout << name << "\n";
            *status = 0;
            return;
        }
        if (args->name.empty())
            throw Error(ErrorCode::InvalidInput, "generate: give a shape NAME (mesohex generate --list)");
        if (args->output.empty()) throw Error(ErrorCode::InvalidInput, "generate: give the output file with -o");
        const Skeleton skeleton = generate_skeleton(args->name, args->options);
        write_skeleton(args->output, skeleton);
        std::cout << "generate " << args->name << ": " << skeleton.points.size() << " points, "
                  << skeleton.edges.size() << " edges, " << skeleton.faces.size() << " faces, Euler characteristic "
                  << euler_characteristic(skeleton) << " -> " << args->output << "\n";
        *status = 0;
    });
}

}  // namespace mesohex::cli
