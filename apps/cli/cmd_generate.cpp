// `mesohex generate NAME [options] -o SKELETON.obj`: writes a procedural meso-skeleton (with radii).
// `mesohex generate --list`: the generator names, one per line.
#include <cstdint>
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
    long long random_seed = 0;  // with --random: generate_random_skeleton(seed) instead of a named shape
    std::string family;         // with --random: "" or "mixed" (tree or sheet by the seed), "character"
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
    CLI::App* cmd = app.add_subcommand("generate",
                                       "Write a procedural meso-skeleton (points with radii, branches, "
                                       "quad leaflets).");
    cmd->add_flag("--list", args->list, "Print the generator names, one per line, and exit");
    cmd->add_option("name", args->name, "Shape name (see --list)");
    CLI::Option* random_option = cmd->add_option(
        "--random", args->random_seed,
        "Random skeleton of the evaluation set (tree or sheet, chosen by the seed; bench/random_set.sh) "
        "instead of a named shape; SEED >= 0");
    CLI::Option* family_option = cmd->add_option(
        "--family", args->family,
        "With --random: mixed (default; tree or sheet, chosen by the seed), character (a torso bulging between two "
        "branching points with 2-4 limbs at each end; generate_character_skeleton) or twinjunction (two branching "
        "points whose balls overlap, each with two fat legs leaning back; generate_twin_junction_skeleton)");
    cmd->add_option("-o,--output", args->output, "Output skeleton file (.obj or .ig)");
    cmd->add_option("-n", args->options.n, "Main resolution (meaning per shape, see below)");
    cmd->add_option("-m", args->options.m, "Second resolution (meaning per shape, see below)");
    cmd->add_option("--quarter-turns", args->options.quarter_turns,
                    "twist, torustwist: turn of the section in quarter turns (default 2 = 180 degrees)");
    cmd->add_option("--angle", args->options.angle_deg,
                    "fold, vfan: angle between the two sheets in degrees, 10 to 170 (default 45)");
    cmd->add_option("--edge-length", args->options.edge_length, "Scale: typical leaflet edge length")
        ->capture_default_str();
    cmd->add_option("--radius-scale", args->options.radius_scale,
                    "Multiplies every radius (default radii are about 0.3 x the edge length)")
        ->capture_default_str();
    cmd->footer(shapes_footer());
    cmd->callback([args, status, random_option, family_option]() {
        if (args->list) {
            for (const std::string& name : generator_names()) std::cout << name << "\n";
            *status = 0;
            return;
        }
        const bool random = random_option->count() > 0;
        if (random && args->random_seed < 0)
            throw Error(ErrorCode::InvalidInput, "generate: --random SEED must be >= 0");
        if (random && !args->name.empty())
            throw Error(ErrorCode::InvalidInput, "generate: give either a shape NAME or --random SEED, not both");
        if (!random && args->name.empty())
            throw Error(ErrorCode::InvalidInput,
                        "generate: give a shape NAME (mesohex generate --list) or --random SEED");
        if (family_option->count() > 0 && !random)
            throw Error(ErrorCode::InvalidInput, "generate: --family needs --random SEED");
        const bool character = args->family == "character", twin = args->family == "twinjunction";
        if (!character && !twin && !args->family.empty() && args->family != "mixed")
            throw Error(ErrorCode::InvalidInput,
                        "generate: unknown --family '" + args->family + "' (valid: mixed, character, twinjunction)");
        if (args->output.empty()) throw Error(ErrorCode::InvalidInput, "generate: give the output file with -o");
        const auto seed = static_cast<std::uint64_t>(args->random_seed);
        const Skeleton skeleton = !random     ? generate_skeleton(args->name, args->options)
                                  : character ? generate_character_skeleton(seed, args->options)
                                  : twin      ? generate_twin_junction_skeleton(seed, args->options)
                                              : generate_random_skeleton(seed, args->options);
        write_skeleton(args->output, skeleton);
        const std::string title = random ? "--random " + std::to_string(seed) + " (" +
                                               (character ? "character"
                                                : twin    ? "twinjunction"
                                                          : random_skeleton_kind(seed)) +
                                               ")"
                                         : args->name;
        std::cout << "generate " << title << ": " << skeleton.points.size() << " points, " << skeleton.edges.size()
                  << " edges, " << skeleton.faces.size() << " faces, Euler characteristic "
                  << euler_characteristic(skeleton) << " -> " << args->output << "\n";
        *status = 0;
    });
}

}  // namespace mesohex::cli
