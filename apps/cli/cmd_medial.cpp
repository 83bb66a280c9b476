// `mesohex medial SURFACE -o OUT.ma`: simplified medial mesh (spheres, curve edges, triangle sheets) of a closed
// surface from the inner Voronoi poles of dense samples (compute_medial_axis, docs/skeletons.md). `mesohex import`
// turns the result into a meso-skeleton.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "mesohex/surface/medial_axis.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex::cli {

namespace {

struct MedialArgs {
    std::string input;
    std::string output;
    MedialAxisOptions options;
};

}  // namespace

// The options `medial` shares with `auto` (which passes them to compute_medial_axis); `prefix` starts every help text.
void add_medial_axis_options(CLI::App* cmd, MedialAxisOptions& o, const std::string& prefix) {
    cmd->add_option("--thickness-samples", o.thickness_samples,
                    prefix +
                        "Thin parts: where the solid is thinner than this x the sample spacing, extra samples "
                        "bring the local spacing down to thickness / this (0 = off)")
        ->check(finite_range(0, 64))
        ->capture_default_str();
    cmd->add_flag(
        "--keep-topology", o.keep_topology,
        prefix +
            "Angle filter as an erosion that keeps the inner Voronoi complex's topology (no holes, no cut-off "
            "parts)");
    cmd->add_flag("--limbs", o.keep_limbs,
                  prefix +
                      "Keep the parts the angle filter cut off that are longer than thick and reach surface the "
                      "rest leaves uncovered (a finger cut off the palm), as trees of curves joined by one edge "
                      "each");
    cmd->add_option("--cover-fraction", o.cover_fraction,
                    prefix +
                        "Keep whole every part the angle filter cut off whose spheres cover at least this fraction "
                        "of the surface samples the kept parts leave uncovered, joined by one curve edge (0 = off)")
        ->check(finite_range(0, 1))
        ->capture_default_str();
    cmd->add_option("--join-factor", o.join_factor,
                    prefix +
                        "Join the parts the angle filter cut off to the main part by one curve edge when their "
                        "closest spheres are at most this x the larger radius apart (0 = off: only the largest "
                        "part is kept)")
        ->check(finite_range(0, 100))
        ->capture_default_str();
    cmd->add_option("--join-min-extent", o.join_min_extent,
                    prefix + "... only parts whose extent is at least this x their largest radius (0 = every part)")
        ->check(finite_range(0, 100))
        ->capture_default_str();
    cmd->add_flag("!--no-fringe-spare-interior", o.fringe_spare_interior,
                  prefix + "Remove fringe chains between interior sheet vertices too (by default such a handle stays)");
    cmd->add_option("--max-relative-error", o.max_relative_error,
                    prefix +
                        "Simplify by fit: refuse a collapse whose sphere's RMS distance to its tangent planes "
                        "exceeds this x its radius (0 = off)")
        ->check(finite_range(0, 100))
        ->capture_default_str();
    cmd->add_option("--max-edge-radius", o.max_edge_radius,
                    prefix +
                        "Simplify by resolution instead of a count: refuse a collapse that makes an edge longer "
                        "than this x the smaller radius of its ends, and collapse until every collapse left is "
                        "refused (0 = off: --target-vertices)")
        ->check(finite_range(0, 100))
        ->capture_default_str();
    cmd->add_option("--min-edge-radius", o.min_edge_radius,
                    prefix +
                        "After the count (or resolution) stop, go on collapsing the edges shorter than this x the "
                        "smaller radius of their ends, cheapest first (0 = off)")
        ->check(finite_range(0, 100))
        ->capture_default_str();
    cmd->add_flag("--extend-rims", o.extend_rims,
                  prefix +
                      "Carry each sheet border vertex out along its sheet to a rounded rim ahead (where the "
                      "angle filter trimmed the sheet short of it)");
}

void register_medial(CLI::App& app, int* status) {
    auto args = std::make_shared<MedialArgs>();
    CLI::App* cmd = app.add_subcommand(
        "medial",
        "Medial mesh (.ma: spheres, curves, sheets) of a closed surface: inner Voronoi poles, angle filter, "
        "sphere-quadric edge collapse.");
    cmd->add_option("surface", args->input, "Closed, manifold triangle surface (.off .obj .stl .ply)")->required();
    cmd->add_option("-o,--output", args->output, "Output medial mesh (.ma)")->required();
    MedialAxisOptions& o = args->options;
    add_medial_axis_options(cmd, o, "");
    cmd->add_option("--sample-spacing", o.sample_spacing, "Largest gap between surface samples (x bbox diagonal)")
        ->capture_default_str();
    cmd->add_option("--max-samples", o.max_samples, "Surface samples at most (the spacing grows to fit)")
        ->capture_default_str();
    cmd->add_option("--max-refinement", o.max_refinement,
                    "Thin parts: the local spacing never goes below the sample spacing / this")
        ->check(finite_range(1, 64))
        ->capture_default_str();
    cmd->add_option("--thin-separation", o.thin_separation,
                    "Thin parts: a Voronoi face whose two samples lie in thin parts is also kept when they are at "
                    "least this x the local thickness apart (0 = angle filter only)")
        ->check(finite_range(0, 10))
        ->capture_default_str();
    cmd->add_option("--min-angle", o.min_angle_deg,
                    "Angle filter: a Voronoi face is medial when it sees its two "
                    "samples under at least this angle (degrees)")
        ->capture_default_str();
    cmd->add_option("--target-vertices", o.target_vertices, "Simplify down to this many medial vertices")
        ->capture_default_str();
    cmd->add_option("--error-tolerance", o.error_tolerance,
                    "... or stop earlier when a collapse costs more than (tolerance x diag)^2")
        ->capture_default_str();
    cmd->add_option("--max-vertices", o.max_vertices, "Never stop above this many vertices")->capture_default_str();
    cmd->add_option("--sheet-width", o.sheet_width_factor,
                    "A triangle is a sheet when its smallest height >= this x its mean radius; thinner ones become "
                    "curves")
        ->capture_default_str();
    cmd->add_option("--fringe-factor", o.fringe_factor,
                    "Curve chains within this x their radius of a sheet all along are removed when their ends stay "
                    "connected (0 = off)")
        ->capture_default_str();
    cmd->add_flag("--fringe-node-ends", args->options.fringe_node_ends,
                  "Also remove the fringe chains that end where curves branch (not only those between sheet vertices)");
    cmd->add_flag("!--no-prune-after-fringe", o.prune_after_fringe,
                  "Keep the spurs the fringe removal leaves (short curves from a sheet's border that end in a tip)");
    cmd->add_option("--rim-reach", o.rim_reach_factor,
                    "Rims: a border vertex has reached the rim when the surface straight ahead is within this x its "
                    "ball's radius")
        ->check(finite_range(1, 4))
        ->capture_default_str();
    cmd->footer("Example: mesohex medial plate1.obj -o plate1.ma && mesohex import plate1.ma -o plate1_skel.obj");
    cmd->callback([args, status]() {
        auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
        const auto t0 = std::chrono::steady_clock::now();
        const TriangleMesh surface = read_surface(args->input);
        const auto t1 = std::chrono::steady_clock::now();
        const MedialAxis m = compute_medial_axis(surface, args->options);
        const auto t2 = std::chrono::steady_clock::now();
        write_medial_mesh(args->output, m.medial);
        std::cout << "medial " << args->input << ": " << m.samples << " samples (" << m.refinement_samples
                  << " in thin parts, " << m.thin_faces << " thin-part faces"
                  << "), " << m.inner_poles << " inner poles, " << m.voronoi_faces << " Voronoi faces kept -> "
                  << m.initial_vertices << " vertices, " << m.initial_triangles << " triangles (Euler characteristic "
                  << m.initial_euler << "); " << m.joined_parts << " parts joined, " << m.covering_parts
                  << " covering parts kept, " << m.limbs << " limbs kept (" << m.limb_branches << " branches), "
                  << m.collapses << " collapses, " << m.thin_triangles_removed << " thin triangles to curves, "
                  << m.pruned_tips << " tips pruned, " << m.fringe_curves << " fringe chains removed, "
                  << m.pruned_spurs << " spurs after them, " << m.rim_moved << " of " << m.rim_border_vertices
                  << " border vertices out to a rim (" << m.rim_sharp << " at sharp edges) (read " << ms(t0, t1)
                  << " ms, medial " << ms(t1, t2) << " ms)\n"
                  << "  medial mesh: " << m.medial.points.size() << " vertices, " << m.medial.edges.size() << " edges, "
                  << m.medial.faces.size() << " triangles; " << m.sheets << " sheets, " << m.curves
                  << " curves, Euler characteristic " << m.euler << ", sheet fraction " << m.sheet_fraction << " -> "
                  << args->output << "\n";
        *status = 0;
    });
}

}  // namespace mesohex::cli
