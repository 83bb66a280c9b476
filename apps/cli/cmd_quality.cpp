// `mesohex quality MESH [--json]` and `mesohex convert IN OUT [--partitions N]`: the hex-mesh inspector and converter.
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "mesohex/core/error.h"
#include "mesohex/post/partition.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/hex_io.h"

namespace mesohex::cli {
namespace {

// Exit status of `quality` when the mesh is readable but has inverted hexes or fails validation.
constexpr int kBadMeshStatus = 5;

struct QualityOptions {
    std::string mesh;
    bool json = false;
};

struct ConvertOptions {
    std::string input, output;
    bool json = false;
    int partitions = 0;  // 0 = no partition
};

}  // namespace

void register_quality(CLI::App& app, int* status) {
    auto opts = std::make_shared<QualityOptions>();
    CLI::App* sub = app.add_subcommand(
        "quality",
        "Print the quality report of a hex mesh: scaled Jacobian (Verdict definition: min, average, histogram, worst "
        "hexes), Euler characteristic of the cell complex and of its boundary, boundary genus, singular edges by "
        "valence, and structural validation problems.");
    sub->add_option("mesh", opts->mesh, "hex mesh file (.mesh, .vtk, .vtu or .msh)")->required();
    sub->add_flag("--json", opts->json, "print one JSON object instead of text");
    sub->footer(
        "Exit status: 0 = valid mesh without inverted hexes; 5 = the mesh was read but has inverted hexes (scaled "
        "Jacobian <= 0) or fails validation; 2 = unreadable or malformed file (message names file:line); 3 = unknown "
        "extension; 4 = file cannot be opened.\n"
        "Example: mesohex quality out.mesh --json");
    sub->callback([opts, status] {
        const HexMesh mesh = read_hex_mesh(opts->mesh);
        const QualityReport report = compute_quality(mesh);
        if (opts->json)
            std::cout << quality_to_json(report) << "\n";
        else
            std::cout << quality_to_text(report);
        *status = (report.validation.valid() && report.inverted == 0) ? 0 : kBadMeshStatus;
    });
}

void register_convert(CLI::App& app, int* status) {
    auto opts = std::make_shared<ConvertOptions>();
    CLI::App* sub = app.add_subcommand(
        "convert",
        "Convert a hex mesh between formats, chosen by extension: reads .mesh (MEDIT), .vtk (legacy VTK), .vtu (VTK "
        "XML, ASCII) and .msh (Gmsh 4.1 ASCII); writes those, .inp (Abaqus C3D8) and .exo / .e (Exodus II, HEX8 "
        "block, boundary side set 'boundary'). The per-hex scaled Jacobian is written as cell data 'scaled_jacobian' "
        "to .vtk, .vtu and .msh (an element variable in .exo). Prints the quality summary of the mesh.");
    sub->add_option("input", opts->input, "input hex mesh file")->required();
    sub->add_option("output", opts->output, "output file; written to a temporary file and renamed")->required();
    sub->add_flag("--json", opts->json,
                  "print the quality summary as JSON (with a 'partition' object when partitioned)");
    sub->add_option("--partitions", opts->partitions,
                    "split the hexes into N parts for MPI solvers (METIS k-way on the face adjacency of the hexes): "
                    "cell data 'partition' in .vtk .vtu .msh, one element block per part in .exo, the reference "
                    "part + 1 in .mesh, element sets PART_<p> in .inp")
        ->check(CLI::Range(1, 1 << 30));
    sub->footer(
        "Exit status (the verdict of `quality` on the same mesh): 0 = converted, valid and without inverted hexes; "
        "5 = converted, but the mesh has inverted hexes or fails validation (said on stderr, as `quality` "
        "reports it); 2 = malformed input (message names file:line); 3 = unknown extension; 4 = file cannot be "
        "read or written.\n"
        "Example: mesohex convert model.mesh model.exo --partitions 4");
    sub->callback([opts, status] {
        const HexMesh mesh = read_hex_mesh(opts->input);
        const QualityReport report = compute_quality(mesh);
        std::optional<Partition> partition;
        if (opts->partitions > 0) partition = partition_hexes(mesh, {.parts = opts->partitions});
        write_hex_mesh(opts->output, mesh, report.sj, partition ? partition->part : std::vector<int>{});
        if (opts->json) {
            nlohmann::json j = nlohmann::json::parse(quality_to_json(report));
            if (partition) j["partition"] = nlohmann::json::parse(partition_to_json(*partition));
            std::cout << j.dump(2) << "\n";
        } else {
            std::cout << "wrote " << opts->output << " (" << mesh.points.size() << " vertices, " << mesh.hexes.size()
                      << " hexes)\n";
            if (partition) std::cout << partition_to_text(*partition);
            std::cout << quality_to_text(report);
        }
        // Same input, same verdict as `quality`.
        const bool good = report.validation.valid() && report.inverted == 0;
        if (!good)
            std::cerr << "mesohex: warning: " << opts->input << ": "
                      << (report.validation.valid()
                              ? "the mesh has " + std::to_string(report.inverted) + " inverted hexes"
                              : std::string("the mesh fails validation (see the report)"))
                      << " (written anyway; exit status 5, as `quality` gives)\n";
        *status = good ? 0 : kBadMeshStatus;
    });
}

}  // namespace mesohex::cli
