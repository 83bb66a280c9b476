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
    bool keep_fans = false;
    bool no_bl_corners = false;
    bool keep_interior_curves = false;
    bool reattach_interior_curves = false;
    bool no_boundary_smoothing = false;
    MedialImportOptions options;
};

}  // namespace

void add_bl_corner_options(CLI::App* cmd, MedialImportOptions* o, const std::string& help_prefix) {
    cmd->add_flag_callback(
        "--no-bl-notch-corners", [o] { o->bl_joint_reflex_corners = false; },
        help_prefix + "leave curve attachments in sharp notches of a leaflet boundary where they are");
    cmd->add_flag_callback(
        "--no-bl-branch-corners", [o] { o->bl_joint_corners_with_branches = false; },
        help_prefix + "leave leaflet boundary vertices where several curves attach where they are");
    cmd->add_option(
           "--bl-corner-max-push", o->bl_joint_max_push_curve_fraction,
           help_prefix + "notch and several-curve attachments move at most this x their shortest curve's length")
        ->capture_default_str()
        ->check(finite_range(0.0, 1.0));
    cmd->add_option("--bl-corner-reach", o->bl_joint_corner_reach,
                    help_prefix +
                        "a several-curve attachment cut short by --bl-corner-max-push hands its curves to a convex "
                        "boundary corner at most this x its boundary edges away (0 = off)")
        ->capture_default_str()
        ->check(finite_range(0.0, 100.0));
    cmd->add_option("--fill-pinch", o->fill_pinch_max_angle_deg,
                    help_prefix +
                        "two leaflets touching at one vertex get a triangle across the gap between them when it is "
                        "narrower than this (degrees; 0 = off)")
        ->capture_default_str()
        ->check(finite_range(0.0, 180.0));
    cmd->add_option("--min-border-side", o->min_border_side_fraction,
                    help_prefix +
                        "while smoothing, a leaflet border side stays at least this x its length before the smoothing, "
                        "except at notches deeper than 270 degrees (0 = off)")
        ->capture_default_str()
        ->check(finite_range(0.0, 1.0));
}

void register_import(CLI::App& app, int* status) {
    auto args = std::make_shared<ImportArgs>();
    CLI::App* cmd = app.add_subcommand("import",
                                       "Turn a medial mesh (.ma: curves + triangle sheets) into a "
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
    cmd->add_flag("--keep-irregular-fans", args->keep_fans,
                  "Keep fan edges whose triangles are not in distinct leaflets (the mesher rejects them)");
    cmd->add_flag("--keep-interior-curves", args->keep_interior_curves,
                  "Keep curve edges that end inside a sheet exactly there (the mesher roots a branch only where 4 "
                  "quads meet) instead of moving such an end to a regular neighbour");
    cmd->add_flag("--reattach-interior-curves", args->reattach_interior_curves,
                  "Move curve ends that lie inside a sheet to the sheet's nearest boundary vertex (the former way)");
    cmd->add_flag("--no-bl-corners", args->no_bl_corners,
                  "Leave curve attachments on straight leaflet boundaries where they are (no corner made)");
    cmd->add_option("--bl-corner-angle", args->options.bl_joint_max_angle_deg,
                    "A curve attachment whose two leaflet boundary edges make a larger angle (degrees) is moved out")
        ->capture_default_str();
    cmd->add_option("--bl-corner-push", args->options.bl_joint_push,
                    "... by this x the mean length of its two boundary edges")
        ->capture_default_str();
    cmd->add_option("--bl-corner-back-push", args->options.bl_joint_back_push,
                    "... times (1 + this x c) when the curve heads back over the leaflet (c = cosine of its angle to "
                    "the inward direction, > 0)")
        ->capture_default_str()
        ->check(finite_range(0.0, 10.0));
    add_bl_corner_options(cmd, &args->options, "");
    cmd->add_option("--smoothing", args->options.smoothing_iterations,
                    "Smoothing sweeps over the leaflets: Laplacian on interior vertices, along the normal on boundary "
                    "vertices (0 = none)")
        ->capture_default_str();
    cmd->add_flag("--no-boundary-smoothing", args->no_boundary_smoothing,
                  "Smooth the leaflet interior vertices only (boundary vertices stay where they are)");
    cmd->add_option("--reflex-corner-angle", args->options.reflex_corner_deg,
                    "A leaflet boundary vertex whose face angles sum to more (degrees) also moves towards the midpoint "
                    "of its two boundary neighbours while smoothing")
        ->capture_default_str()
        ->check(finite_range(0.0, 360.0));
    cmd->add_option("--max-sheet-offset", args->options.max_sheet_offset,
                    "While smoothing, a leaflet vertex stays within this x its radius of the input sheet (0: on the "
                    "sheet; negative: free)")
        ->capture_default_str()
        ->check(finite_range(-1.0, 100.0));
    cmd->footer("Method: docs/skeletons.md. Example: mesohex import hand.ma -o hand.obj");
    cmd->callback([args, status]() {
        args->options.pair_triangles = !args->no_pairing;
        args->options.resolve_irregular_fans = !args->keep_fans;
        args->options.bl_joint_corners = !args->no_bl_corners;
        args->options.root_interior_curves = !args->keep_interior_curves;
        args->options.reattach_interior_curves = args->reattach_interior_curves;
        args->options.smooth_boundary = !args->no_boundary_smoothing;
        const Skeleton medial = read_medial_mesh(args->input);
        const MedialImport r = at_stage(
            "import", args->input, [&] { return import_medial_mesh(medial, args->options); }, false);
        write_skeleton(args->output, r.skeleton);
        std::cout << "import " << args->input << ": " << medial.points.size() << " vertices, " << medial.edges.size()
                  << " edges, " << medial.faces.size() << " triangles in " << r.sheets << " sheet(s)\n"
                  << "  irregular-fan triangles removed " << r.fan_triangles_removed << ", pinches filled "
                  << r.filled_pinches << ", curve ends moved to a sheet boundary " << r.reattached_curve_ends
                  << ", curve ends moved to a regular leaflet vertex " << r.rooted_curve_ends << ", collapsed sheets "
                  << r.collapsed_sheets << ", leaflets " << r.leaflets << ", fan edges " << r.fan_edges
                  << ", triangle pairs " << r.paired_quads << ", lone triangles " << r.split_triangles
                  << ", BL-joints moved to a corner " << r.moved_bl_joints << " (" << r.notch_corners << " at notches, "
                  << r.branch_corners << " of several curves; " << r.joins_to_corners
                  << " handed their curves to a corner), smoothed vertices " << r.smoothed_vertices
                  << "\n  skeleton: " << r.skeleton.points.size() << " points, " << r.skeleton.edges.size()
                  << " edges, " << r.skeleton.faces.size() << " quads, Euler characteristic "
                  << euler_characteristic(r.skeleton) << " (input " << euler_characteristic(medial) << ") -> "
                  << args->output << "\n";
        *status = 0;
    });
}

}  // namespace mesohex::cli
