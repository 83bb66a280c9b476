// `mesohex import MEDIAL.ma -o SKELETON.obj`: medial mesh (curves + triangle sheets) -> meso-skeleton (branches +
// quad leaflets). Method: docs/skeletons.md.
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "mesohex/core/error.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"

namespace mesohex::cli {

namespace {

struct ImportArgs {
    std::string input;
    std::string output;
    bool no_pairing = false;
    MedialImportOptions options;
};

}  // namespace

void register_import(CLI::App& app, int* status) {
    auto args = std::make_shared<ImportArgs>();
    CLI::App* cmd = app.add_subcommand("import", "Turn a medial mesh (.ma: curves + triangle sheets) into a "
                                                 "meso-skeleton (branches + quad leaflets).");
    cmd->add_option("input", args->input, "Medial mesh (.ma)")->required();
    cmd->add_option("-o,--output", args->output, "Output skeleton file (.obj or .ig)")->required();
    cmd->add_option("--min-sheet-triangles", args->options.min_sheet_triangles,
                    "Sheets with fewer triangles collapse to a curve")
        ->capture_default_str();
    cmd->add_option("--min-sheet-area", args->options.min_sheet_area_factor,
                    "Sheets with area below this x (mean radius)^2 collapse to a curve")
        ->capture_default_str();
    cmd->add_flag("--no-pairing", args->no_pairing,
                  "Split every triangle into 3 quads (no pairing of triangles into quads first)");
    cmd->footer("Example: mesohex import hand.ma -o hand.obj");
    cmd->callback([args, status]() {
        args->options.pair_triangles = !args->no_pairing;
        const Skeleton medial = read_medial_mesh(args->input);
        const MedialImport r = import_medial_mesh(medial, args->options);
        write_skeleton(args->output, r.skeleton);
        std::cout << "import " << args->input << ": " << medial.points.size() << " vertices, " << medial.edges.size()
                  << " edges, " << medial.faces.size() << " triangles in " << r.sheets << " sheet(s)\n"
                  << "  collapsed sheets " << r.collapsed_sheets << ", leaflets " << r.leaflets << ", fan edges "
                  << r.fan_edges << ", triangle pairs " << r.paired_quads << ", lone triangles " << r.split_triangles
                  << "\n  skeleton: " << r.skeleton.points.size() << " points, " << r.skeleton.edges.size()
                  << " edges, " << r.skeleton.faces.size() << " quads, Euler characteristic "
                  << euler_characteristic(r.skeleton) << " (input " << euler_characteristic(medial) << ") -> "
                  << args->output << "\n";
        *status = 0;
    });
}

}  // namespace mesohex::cli
