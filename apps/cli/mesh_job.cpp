// The meshing job shared by `mesohex mesh` and `mesohex auto` (see mesh_job.h): flags -> MeshOptions ->
// mesh_skeleton -> mesh file, summary lines, report.
#include "mesh_job.h"

#include "commands.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "mesohex/core/error.h"
#include "mesohex/mesh_report.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/hex_io.h"

namespace mesohex::cli {

namespace {

// One progress line on stderr for the finishing stages (a bar for the fit, rounds or sweeps for the others), drawn
// only on a terminal and only once a stage has run for a second.
class ProgressDisplay {
public:
    explicit ProgressDisplay(bool enabled) : enabled_(enabled) {}
    ProgressDisplay(const ProgressDisplay&) = delete;
    ProgressDisplay& operator=(const ProgressDisplay&) = delete;
    ~ProgressDisplay() { end_line(); }

    void update(const MeshProgress& p) {
        if (!enabled_) return;
        if (p.stage != stage_) {
            end_line();
            stage_ = p.stage;
            stage_start_ = std::chrono::steady_clock::now();
        }
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_start_).count();
        if (elapsed < 1.0 || p.stage == "raw" || p.stage == "attempt") return;
        if (p.stage == "fit") {
            const int width = 30;
            const int filled = std::min(width, p.step * width / std::max(1, p.steps));
            std::cerr << "\rfit [" << std::string(static_cast<std::size_t>(filled), '#')
                      << std::string(static_cast<std::size_t>(width - filled), '.') << "] " << p.step << "/" << p.steps
                      << "  SJ min " << p.sj_min << "  inverted " << p.inverted << "   " << std::flush;
        } else {
            const char* unit = p.stage == "smooth" ? "sweep" : "round";
            std::cerr << "\r" << p.stage << " " << unit << " " << p.step << "/" << p.steps;
            if (p.stage != "smooth") std::cerr << "  inverted " << p.inverted;
            std::cerr << "   " << std::flush;
        }
        drawn_ = true;
    }

private:
    void end_line() {
        if (drawn_) std::cerr << "\n";
        drawn_ = false;
    }
    bool enabled_;
    bool drawn_ = false;
    std::string stage_;
    std::chrono::steady_clock::time_point stage_start_ = std::chrono::steady_clock::now();
};

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

MeshOptions options_of(const MeshJob& job) {
    MeshOptions o = job.options;
    if (job.refine == "longitudinal") o.finishing.refinement = FinishOptions::Refinement::Longitudinal;
    if (job.refine == "radial") o.finishing.refinement = FinishOptions::Refinement::Radial;
    return o;
}

void print_summary(const MeshJob& job, const MeshRun& run) {
    const PipelineResult& res = run.pipeline;
    const QualityReport& q = run.raw_quality;
    std::cout << "mesh " << job.skeleton << ": " << res.skeleton.points.size() << " skeleton vertices, "
              << res.skeleton.edges.size() << " edges (" << (run.options.resample ? "resampled" : "input sampling")
              << "), radius " << (run.radius_note.empty() ? res.radius_source : run.radius_note);
    if (res.radius_source != "file") std::cout << " " << res.radius;
    std::cout << "\n" << trimmed_tips_to_text(res);
    std::cout << "raw mesh: " << q.vertices << " vertices, " << q.hexes << " hexes, SJ min " << q.sj_min << " avg "
              << q.sj_avg << ", inverted " << q.inverted << ", " << (q.validation.valid() ? "valid" : "INVALID")
              << ", Euler characteristic " << q.euler_characteristic;
    if (res.predicted.compatible_blocks > 0)
        std::cout << ", " << res.predicted.compatible_blocks << " compatible blocks";
    std::cout << (run.prediction_exact ? ", prediction exact" : ", PREDICTION MISMATCH")
              << (run.finish ? "" : " -> " + job.output) << "\n";
    if (!run.finish) return;
    const FinishResult& fin = *run.finish;
    for (const FinishStage& st : fin.stages) {
        if (st.stage == "input") continue;
        std::cout << st.stage << ": " << st.hexes << " hexes, SJ min " << st.sj_min << " avg " << st.sj_avg
                  << ", inverted " << st.inverted << " (" << st.ms << " ms)\n";
    }
    const QualityReport& f = fin.quality;
    std::cout << "final mesh: " << f.vertices << " vertices, " << f.hexes << " hexes, SJ min " << f.sj_min << " avg "
              << f.sj_avg << ", inverted " << f.inverted << ", " << (f.validation.valid() ? "valid" : "INVALID");
    if (fin.distance_measured)
        std::cout << ", Hausdorff " << fin.distance.max << " (" << 100.0 * fin.distance.relative_max
                  << " % of the bbox diagonal)";
    std::cout << " -> " << job.output << "\n";
    if (const std::optional<DistanceRefinement>& d = run.distance_refinement)
        std::cout << "distance refinement: " << d->stop << " (" << d->reason << "), " << d->levels_kept
                  << " level(s) kept\n";
    if (run.attempts.size() < 2) return;
    for (std::size_t i = 0; i < run.attempts.size(); ++i) {
        const MeshAttempt& a = run.attempts[i];
        std::cout << "attempt " << i + 1 << " (" << a.what << ", first joints at " << a.free_branching_reach
                  << " x the reach at branching points, " << a.levels << " level(s)): " << a.hexes << " hexes, SJ min "
                  << a.sj_min << " avg " << a.sj_avg << ", inverted " << a.inverted;
        if (a.distance_measured) std::cout << ", Hausdorff " << 100.0 * a.hausdorff_relative_max << " %";
        std::cout << (static_cast<int>(i) == run.kept_attempt ? " (kept)" : "") << "\n";
    }
}

// The padding flags of add_mesh_job_options (--no-pad, --pad, the padding directions and thickness, the crease
// wedges before it), in their --help order.
void add_padding_options(CLI::App* cmd, MeshJob* job) {
    cmd->add_flag_callback(
        "--no-pad", [job] { job->options.finishing.pad = false; }, "Skip the padding layer (= --pad none)");
    cmd->add_option_function<std::string>(
           "--pad",
           [job](const std::string& mode) {
               job->options.finishing.pad = mode != "none";
               job->options.finishing.pad_selective = mode == "selective";
           },
           "Padding layer: all (over the whole raw boundary), selective (not over the regions of the raw boundary "
           "whose sharp rims already land on matching sharp rims of the domain: one hex corner on such a rim instead "
           "of two 45-degree hexes; the report's 'padding' says how many boundary quads stayed bare; the default), "
           "none")
        ->check(CLI::IsMember({"all", "selective", "none"}));
    cmd->add_flag(
        "--pad-inward-edges", job->options.finishing.padding.inward_edges,
        "Padding layer thickness from the shortest boundary edge OR edge into the mesh at each vertex (thin sheets: "
        "the sheet's height, not its leaflet edge; docs/sheets.md)");
    cmd->add_option("--pad-corner-guard", job->options.finishing.padding.corner_guard,
                    "Padding directions turned where the mean normal leaves a new hex's corner on the raw boundary "
                    "below this scaled Jacobian, towards the direction that maximises the worst such corner "
                    "(docs/junctions.md, \"The padding layer at junctions\")")
        ->check(finite_range(0.0, 1.0));
    cmd->add_option("--crease-wedge", job->options.finishing.crease_wedge.min_dihedral_deg,
                    "Before padding, a wedge hex fills the gap at every raw boundary edge of two hexes whose interior "
                    "dihedral exceeds this many degrees (folded junction crotches; 0 = off, the default: "
                    "docs/junctions.md, \"Crease wedges\")")
        ->check(finite_range(0.0, 360.0))
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                // CreaseWedgeOptions::min_dihedral_deg: 0 or a reflex angle (at or below 180 degrees every flat
                // boundary edge of two hexes would get a wedge over its neighbours).
                double x = 0;
                try {
                    x = std::stod(text);
                } catch (const std::exception&) {
                    return "'" + text + "' is not a number";
                }
                return x == 0 || x > 180 ? "" : "'" + text + "' is neither 0 (off) nor above 180 degrees";
            },
            "0 or (180, 360]"));
    cmd->add_option("--crease-wedge-pair", job->options.crease_wedge_pair_deg,
                    "With --crease-wedge: wedges only on the crease two branches less than this many degrees apart "
                    "share at a branching point (0 = every folded crease, the default: docs/junctions.md, \"The "
                    "close pair's crease carried by a wedge\")")
        ->check(finite_range(0.0, 180.0));
    cmd->add_option("--crotch-wedge", job->options.crotch_wedge_pair_deg,
                    "Crotch wedges: the crease two branches less than this many degrees apart share at a branching "
                    "point gets a wedge only as long as the domain's crotch, its two chunks cut there (0 = off, the "
                    "default: docs/junctions.md, \"The close pair's wedge only as long as the crotch\")")
        ->check(finite_range(0.0, 180.0));
    cmd->add_flag("--crease-wedge-inside", job->options.finishing.crease_wedge_inside,
                  "With --crease-wedge: only wedges whose new vertices lie inside the domain");
    cmd->add_option("--pad-search-cos", job->options.finishing.padding.search_cos,
                    "Padding directions searched where the direction leaves a quad corner's normal at a cosine below "
                    "this (folded valleys): the best of five towards the narrowest cone's axis for the new hexes "
                    "around the vertex (0 = off, the default: docs/junctions.md, \"Padding directions at folded "
                    "valleys\")")
        ->check(finite_range(0.0, 1.0));
    cmd->add_option("--pad-improve-sj", job->options.finishing.pad_improve_sj,
                    "Quality pass on the padded mesh before subdivision when it has no inverted hex and its min SJ is "
                    "below this (0 = off)")
        ->check(finite_range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_flag("--pad-improve-keep-distance", job->options.finishing.pad_improve_keep_distance,
                  "With --pad-improve-sj: drop the pass's result when it moves the padded boundary farther from the "
                  "domain (docs/sheets.md, \"What pad-improve does to hand.ma\")");
    cmd->add_flag("--pad-improve-hold-outside", job->options.finishing.pad_improve_hold_outside,
                  "With --pad-improve-sj: the pass holds the vertices outside the domain that it would move farther "
                  "out (docs/sheets.md, \"Pad-improve that holds the vertices outside\")");
    cmd->add_option("--pad-overshoot-keep", job->options.finishing.pad_overshoot_keep,
                    "Where the padding layer would reach past the domain surface, pad only to the surface but at "
                    "least this share of the layer's own thickness (1: the full layer)")
        ->check(finite_range(0.01, 1.0));
}

// The skeleton repair's valley trunks (SkeletonRepairOptions::valley_trunk_*), for add_raw_structure_options.
void add_valley_trunk_options(CLI::App* cmd, MeshJob* job) {
    cmd->add_option("--valley-trunks", job->options.pipeline.repair.valley_trunk_degree,
                    "At branching points of at least this degree, give a close pair of fat branches whose tubes "
                    "branch inside the point's ball a trunk all the same, ending where its ball reaches the crotch "
                    "between them (0 = off, the default, or a degree of 4 to 64; docs/junctions.md, \"Valley "
                    "trunks\")")
        ->check(CLI::IsMember({0}) | CLI::Range(4, 64))
        ->capture_default_str();
    cmd->add_option("--valley-trunk-min-radius", job->options.pipeline.repair.valley_trunk_min_radius,
                    "With --valley-trunks: the smallest radius of the trunk's end, as a fraction of the fatter "
                    "branch's radius there (0.6 by default)")
        ->check(finite_range(0.0, 10.0))
        ->capture_default_str();
    cmd->add_option("--valley-trunks-per-point", job->options.pipeline.repair.valley_trunks_per_point,
                    "With --valley-trunks: build a valley trunk at a branching point only while it has fewer than "
                    "this many trunks of either rule (0 = no limit, the default)")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    cmd->add_option("--valley-trunks-apart", job->options.pipeline.repair.valley_trunks_apart,
                    "With --valley-trunks: build a trunk at a branching point only 90 degrees or more from every "
                    "trunk already there when either is a valley trunk (0 or 1, 1 by default)")
        ->check(CLI::IsMember({"0", "1"}))
        ->capture_default_str();
    cmd->add_option("--valley-trunk-fit-across", job->options.pipeline.repair.valley_trunk_fit_across,
                    "With --valley-trunks: cap the trunk end's radius at the pair's tubes' half-width across the "
                    "pair's plane (0 or 1, 0 by default)")
        ->check(CLI::IsMember({"0", "1"}))
        ->capture_default_str();
}

// The raw-mesh structure flags of add_mesh_job_options (junction cover and crease, docked walls, fan-end caps,
// bridge quads), in their --help order.
void add_raw_structure_options(CLI::App* cmd, MeshJob* job) {
    cmd->add_option("--junction-cover", job->options.pipeline.raw_mesh.cover.fraction,
                    "Move the surface points of branching points out along their rays by this fraction of the way to "
                    "where the union of the input's balls ends, guarded so no junction hex gets worse than min(0.3, "
                    "before) (0 = off, the default: docs/junctions.md)")
        ->check(finite_range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--junction-cover-bulge", job->options.pipeline.raw_mesh.cover.bridge_bulge,
                    "With --junction-cover: cover only the two ends of each bridge between branching points along "
                    "which the input's balls reach this many times the ends' interpolated radius (a bulged torso), "
                    "both ends from the union of the bridge's balls (0 = every junction, the default: "
                    "docs/junctions.md, \"Bulged bridges covered from both ends\")")
        ->check(finite_range(0.0, 100.0))
        ->capture_default_str();
    cmd->add_option("--junction-cover-overlap", job->options.pipeline.raw_mesh.cover.bridge_overlap,
                    "With --junction-cover: cover only the two ends of each bridge between branching points whose "
                    "balls overlap by (r_a + r_b) / distance >= this ratio (twin junctions), both ends from the union "
                    "of the input's balls; with --junction-cover-bulge, the ends either selects (0 = off, the default: "
                    "docs/junctions.md, \"Twin junctions: the slit between the two ends' limbs\")")
        ->check(finite_range(0.0, 100.0))
        ->capture_default_str();
    cmd->add_option(
           "--docked-foot-split", job->options.pipeline.repair.docked_foot_split,
           "Split the plate's face strips beside a docked wall's chain (both sides) and beyond its inside ends at this "
           "many x the chain's radius from it, so the wall stands on a foot as wide as itself, not 2 plate "
           "faces (with resampling; 0 = off: docs/blocks.md)")
        ->check(finite_range(0.0, 10.0))
        ->capture_default_str();
    cmd->add_flag("--docked-band-pillow,!--no-docked-band-pillow", job->options.pipeline.repair.docked_band_pillow,
                  "A docked wall whose chain does not match the plate's grid (it turns in the grid, or other than 4 "
                  "plate faces meet at a chain vertex) gets a band of plate faces pillowed along its chain, run on "
                  "to the plate's border (on by default, with resampling; --no-docked-band-pillow refuses it: "
                  "docs/blocks.md)");
    cmd->add_flag("--fan-end-cap-to-border", job->options.pipeline.raw_mesh.fan_end_cap_to_border,
                  "At a fan end retracted from a branch, raise the cap up to the retracted leaflet corners so the "
                  "leaflets' border hexes span the notch (off by default: docs/blocks.md, \"The notch closed by the "
                  "cap\")");
    cmd->add_option(
           "--bridge-quad-radius", job->options.pipeline.raw_mesh.bridge_quad_radius,
           "At a branching point joined to another by a bridge edge, shrink only the surface points of its "
           "quad on the bridge to the bridge's margin limit, the others staying on the input radius (0 or 1, on "
           "by default; 0: the whole sphere at the limit, docs/junctions.md, \"Bridge quads\")")
        ->check(CLI::IsMember({"0", "1"}))
        ->capture_default_str();
    cmd->add_option("--slide-cut-joint", job->options.pipeline.adaptation.slide_cut_joint,
                    "A joint next to a branching point or leaflet vertex that the section criterion would remove "
                    "slides along its branch, away from the junction, to the nearest position where the criterion "
                    "holds; gated: only where the edge replacing the joint would cut a ball by 1 % of its radius or "
                    "more, and never at a junction of degree 4 or more (also one the skeleton repair split or gave a "
                    "trunk, or two points joined by a collapsed short bridge) (0 or 1; docs/junctions.md, \"Cut joints "
                    "slid away from the junction\", \"The cut-joint slide's gate\")")
        ->check(CLI::IsMember({"0", "1"}))
        ->capture_default_str();
    cmd->add_option("--junction-split-five", job->options.pipeline.repair.junction_split_degree_five,
                    "Split branching points of degree 5 too: the closest pair of branches moves to a new point along "
                    "the direction from the others to it, as at degree 4, and the degree-4 point left is split when "
                    "it can (0 or 1, off by default; docs/junctions.md, \"Degree-5 junctions split\")")
        ->check(CLI::IsMember({"0", "1"}))
        ->capture_default_str();
    add_valley_trunk_options(cmd, job);
    cmd->add_option("--pit-branches", job->options.pipeline.virtual_branches.pit_excess,
                    "A one-edge branch into the pit inside a ring of branches at a branching point of degree 4 or "
                    "more, along the direction farthest from its nearest three branches, where the domain reaches "
                    "beyond the branching point's ball by at least this many x its radius (0 = off, the default; "
                    "docs/junctions.md, \"Pit branches\")")
        ->check(finite_range(0.0, 10.0))
        ->capture_default_str();
    cmd->add_option("--bridge-peak-ratio", job->options.pipeline.adaptation.bridge_peak_ratio,
                    "On a branch between two branching points that resampling would leave as one edge, keep a joint "
                    "at the input vertex whose radius exceeds the ends' interpolated radius the most, when by at least "
                    "this ratio, whatever the section criterion says (0 = off, the default; docs/junctions.md, \"A "
                    "radius peak held on its bridge\")")
        ->check(finite_range(0.0, 100.0))
        ->capture_default_str();
    cmd->add_option("--overlap-merge-ratio", job->options.pipeline.adaptation.overlap_merge_ratio,
                    "Merge two branching points joined by a one-edge bridge into one junction when their balls "
                    "overlap by (r_a + r_b) / distance >= this ratio (centred on the union's span along the bridge; 0 "
                    "= off; docs/junctions.md, \"Overlapping junction balls merged\")")
        ->check(finite_range(0.0, 100.0))
        ->capture_default_str();
    cmd->add_option("--overlap-merge-max-degree", job->options.pipeline.adaptation.overlap_merge_max_degree,
                    "With --overlap-merge-ratio: merge only when the merged junction has at most this many branches "
                    "(0 = no limit)")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    cmd->add_option("--keep-cut-joint", job->options.pipeline.adaptation.keep_cut_joint,
                    "Keep a joint next to a branching point or leaflet vertex that the section criterion would remove "
                    "when the edge replacing it misses its ball by at least this fraction of its radius, with its "
                    "radius lowered "
                    "until the criterion holds (0 = off, the default; docs/junctions.md, \"A cut joint kept thinner\")")
        ->check(finite_range(0.0, 10.0))
        ->capture_default_str();
    cmd->add_option("--bridge-quad-inset", job->options.pipeline.raw_mesh.bridge_quad_inset,
                    "With --bridge-quad-radius 1: the raised points stop this many times their shortest raw boundary "
                    "edge short of the input ball (0.25 = one padding layer, the default; 0 = on the ball: "
                    "docs/junctions.md, \"Bridge quads raised one layer short\")")
        ->check(finite_range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--leaflet-out-fraction", job->options.pipeline.raw_mesh.leaflet_out_fraction,
                    "The two out points of a leaflet border side may close in along it by at most this fraction of "
                    "its length (out rays crossing along short sides; 0 = off: docs/sheets.md, \"Out rays crossing "
                    "along short border sides\")")
        ->check(finite_range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_flag("--leaflet-out-lean-only,!--leaflet-out-pull", job->options.pipeline.raw_mesh.leaflet_out_lean_only,
                  "With --leaflet-out-fraction: cut only the out points' lean along the side, keeping their distance "
                  "across it (--leaflet-out-pull: pull them towards their vertex; docs/sheets.md, \"Only the lean "
                  "along the side\")");
    cmd->add_option("--junction-crease", job->options.pipeline.raw_mesh.cover.crease_deg,
                    "Open the raw boundary creases on branching points' spheres sharper than this many degrees "
                    "(interior dihedral through their two hexes): their surface points move out along their rays, "
                    "at most to where the union of the input's balls ends, guarded like --junction-cover (0 = off, "
                    "the default: docs/junctions.md)")
        ->check(finite_range(0.0, 360.0))
        ->capture_default_str();
    cmd->add_flag("--junction-crease-midpoints", job->options.pipeline.raw_mesh.cover.crease_midpoints,
                  "With --junction-crease: move the middle of each folded surface edge out along its own ray "
                  "instead of the edge's end points (docs/junctions.md, \"Dino's hip and knight's v9 traced through "
                  "the stages\")");
    cmd->add_option("--junction-crease-pair", job->options.pipeline.raw_mesh.cover.crease_pair_deg,
                    "With --junction-crease-midpoints: move only the middle of a folded surface edge whose two quads "
                    "belong to branches less than this many degrees apart (a close pair's shared edge; 0 = every "
                    "folded edge, the default: docs/junctions.md, \"The three shared skeletons that miss\")")
        ->check(finite_range(0.0, 180.0))
        ->capture_default_str();
    cmd->add_option("--junction-inset", job->options.pipeline.raw_mesh.cover.inset,
                    "Cap the distance of each branching point's surface points at where the union of the input's "
                    "balls ends minus this many x the point's shortest boundary edge (0.25: one padding layer), so the "
                    "padding layer starts inside the domain; guarded like --junction-cover (0 = off, the default: "
                    "docs/junctions.md)")
        ->check(finite_range(0.0, 1.0))
        ->capture_default_str();
}

}  // namespace

void add_mesh_job_options(CLI::App* cmd, MeshJob* job) {
    cmd->add_flag("--radius-from-surface", job->options.radius_from_surface,
                  "Take every radius from the surface (factor x distance), even when the skeleton file has radii "
                  "(without radii in the file and with --surface, this is what happens)");
    cmd->add_option("--radius-factor", job->options.radius_factor,
                    "Radius from the surface = factor x distance to the surface (room for the padding layer)")
        ->capture_default_str();
    cmd->add_option(
        "--levels", job->options.finishing.levels,
        "1->8 subdivision levels after padding (default: from --size, else 1, or 2 when the padded mesh's mean edge "
        "is longer than 1/16 of the domain's bounding-box diagonal or the raw mesh's mean scaled Jacobian is below "
        "0.5, "
        "within 150000 hexes and if padding inverted nothing)");
    cmd->add_option("--size", job->options.finishing.size, "Target mean edge length; chooses the subdivision levels");
    cmd->add_option("--fit-levels", job->options.finishing.fit_levels,
                    "Fit, untangle and smooth after this many of the levels; the finer levels inherit that shape "
                    "(subdivision, boundary projected onto the surface); -1 = fit at the finest level")
        ->check(CLI::Range(-1, 8))
        ->capture_default_str();
    cmd->add_option("--refine", job->refine,
                    "Subdivision per level: uniform (1->8), longitudinal (only the sheets along the branches: more "
                    "cross-sections), radial (only the cross-sections of the branches)")
        ->check(CLI::IsMember({"uniform", "longitudinal", "radial"}))
        ->capture_default_str();
    cmd->add_flag_callback(
        "--virtual-branches", [job] { job->options.pipeline.virtual_branches.enabled = true; },
        "Virtual branches at branching points whose branches leave an empty cap of more than 100 degrees (all "
        "inside a narrow cone): one extra 4-hex chunk each (off by default, docs/blocks.md)");
    cmd->add_flag_callback(
        "--no-blocks", [job] { job->options.pipeline.connection_surfaces.blocks.enabled = false; },
        "No compatible block: neither the 8-hex blocks at branching points whose branches are near a cube's face "
        "normals nor the fan blocks: the paper's layout (sphere partitions, gap vertices) everywhere");
    cmd->add_flag_callback(
        "--fan-blocks", [job] { job->options.compare_fan_layouts = false; },
        "Keep the 4-hex fan blocks wherever accepted (T and X fan-edge chains whose leaflets meet near 90 / 180 "
        "degrees: no valence-6 or -8 edge on the fan line). By default they are on where accepted, and with "
        "--surface the paper's layout is finished too and kept when better (fewer missed goals, then a higher min "
        "SJ; docs/blocks.md)");
    cmd->add_flag_callback(
        "--no-fan-blocks", [job] { job->options.pipeline.connection_surfaces.blocks.fan_blocks = false; },
        "No fan block: the paper's gap vertices on every fan edge (8-hex blocks stay on; --no-blocks turns both off)");
    cmd->add_flag("--fan-cap-branches,!--no-fan-cap-branches",
                  job->options.pipeline.connection_surfaces.blocks.fan_cap_branches,
                  "A branch on a fan-block chain end within 35 degrees of the fan line's continuation stands on the "
                  "block's cap instead of the fan edge being retracted from it (on by default; --no-fan-cap-branches "
                  "retracts it: docs/blocks.md, \"Branches on the fan block's cap\")");
    cmd->add_flag("--fan-side-branches,!--no-fan-side-branches",
                  job->options.pipeline.connection_surfaces.blocks.fan_side_branches,
                  "Where the fan-end repair refuses a branch across the fan line as too thick for the moved root's "
                  "border, the branch stands on the fan block's side section (a T's empty side) or in its notch "
                  "between two leaflets (on by default; --no-fan-side-branches leaves it refused: docs/blocks.md, "
                  "\"Thick moved roots on the fan block's side section\")");
    add_padding_options(cmd, job);
    add_raw_structure_options(cmd, job);
    cmd->add_flag_callback(
        "--pad-inset", [job] { job->options.finishing.pad_inset = true; },
        "Where the padding layer reaches past the domain surface, move it inward to end at the surface, the raw "
        "hexes beneath giving up that thickness (the report's 'padding.inset_vertices'; off by default: "
        "docs/junctions.md)");
    cmd->add_flag_callback(
        "--pad-inset-concave",
        [job] {
            job->options.finishing.pad_inset = true;
            job->options.finishing.pad_insetting.concave_only = true;
        },
        "--pad-inset at concave raw boundary vertices only (the valleys between a junction's chunks; off by default: "
        "docs/junctions.md, \"Junction inset\")");
    cmd->add_flag_callback(
        "--no-fit",
        [job] {
            job->options.finishing.fit = false;
            job->options.finishing.untangle = false;
        },
        "Skip the surface fitting (and untangling)");
    cmd->add_flag_callback(
        "--no-untangle", [job] { job->options.finishing.untangle = false; },
        "Skip the untangling of inverted hexes after the fit (the report and exit status 5 still say so)");
    cmd->add_flag_callback(
        "--no-smooth", [job] { job->options.finishing.smooth = false; }, "Skip the final smoothing pass");
    cmd->add_flag_callback(
        "--no-trim-tips", [job] { job->options.trim_unheld_tips = false; },
        "With --surface: mesh branch tips whose centres lie outside the domain as given (default: trimmed back to "
        "the last vertex inside)");
    cmd->add_flag_callback(
        "--no-retry",
        [job] {
            job->options.retry = false;
            job->options.structural_retry = false;
        },
        "One attempt only: no second adaptation with the first joints farther from the branching points "
        "and no structural alternative when the mesh misses a goal (inverted hex, SJ min < 0.3, avg < 0.85, "
        "Hausdorff > 1 % of the diagonal); auto's attempt one level finer has its own flag, --no-finer-retry");
    cmd->add_flag_callback(
        "--no-structural-retry", [job] { job->options.structural_retry = false; },
        "No structural alternatives when the mesh kept after the other attempts misses a goal (docs/junctions.md, "
        "\"Structural alternatives when the mesh kept misses\")");
    cmd->add_option_function<std::vector<std::string>>(
           "--structural-alternatives",
           [job](const std::vector<std::string>& names) {
               job->options.structural_alternatives.clear();
               for (const std::string& n : names)
                   for (const StructuralAlternative a : all_structural_alternatives())
                       if (n == structural_alternative_flag(a)) job->options.structural_alternatives.push_back(a);
           },
           "The structural alternatives tried in this order (comma-separated: valley-trunks, slide-cut-joint, "
           "pit-branches, crease-wedge, crotch-wedge, bridge-cover; default valley-trunks, slide-cut-joint, "
           "pit-branches, crotch-wedge, bridge-cover)")
        ->delimiter(',')
        ->check(CLI::IsMember(
            {"valley-trunks", "slide-cut-joint", "pit-branches", "crease-wedge", "crotch-wedge", "bridge-cover"}));
    cmd->add_option("--structural-max-finished", job->options.structural_max_finished,
                    "At most this many structural alternatives finished (0 = no limit)")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    cmd->add_flag("--structural-try-all", job->options.structural_try_all,
                  "Finish every structural alternative even after one meets every goal (measurement; the best kept)");
    cmd->add_flag("--retry-by-shortfall", job->options.retry_by_shortfall,
                  "When every attempt misses the same number of goals, keep the one with the smallest product of "
                  "the factors by which it misses them (default: the smallest Hausdorff distance; docs/junctions.md, "
                  "\"The retry's choice when every attempt misses\")");
    cmd->add_option("--iterations", job->options.finishing.fitting.max_iterations, "Iteration cap of the fitting loop")
        ->capture_default_str();
    cmd->add_option("--fit-weight", job->options.finishing.fitting.lambda,
                    "Weight of the pull of the boundary onto the surface, relative to the shape terms")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--fit-two-sided-floor", job->options.finishing.fitting.two_sided_floor,
                    "From the fit's first two-sided step on, no hex may go below min(its scaled Jacobian then, this): "
                    "the pull towards surface samples the boundary does not reach stops short of crushing hexes "
                    "(0 = off, the default: docs/sheets.md, \"The fit's crush traced\")")
        ->capture_default_str()
        ->check(finite_range(0.0, 1.0));
    cmd->add_option("--improve-below", job->options.finishing.improve_sj,
                    "Quality pass after fitting on the hexes whose scaled Jacobian is below this (0 = off)")
        ->capture_default_str()
        ->check(finite_range(0.0, 0.99));
    cmd->add_flag("-q,--quiet", job->quiet, "No progress bar");
    cmd->add_option("--report", job->report, "Write a JSON report (skeleton, predicted, quality, timings_ms)");
    cmd->add_option("--threads", job->threads, "Worker threads (0 = all cores)");
    cmd->add_option("--partitions", job->options.partitions,
                    "Split the mesh into N parts for MPI solvers (METIS k-way on the face adjacency of the hexes): "
                    "cell data 'partition' in .vtk .vtu .msh, one element block per part in .exo; edge cut and "
                    "imbalance in the report ('partition')")
        ->check(CLI::Range(1, 1 << 30));
}

MeshRun mesh_job_run(const MeshJob& job, const Skeleton& skeleton, const std::optional<TriangleMesh>& domain) {
    MeshOptions options = options_of(job);
    ProgressDisplay display(!job.quiet && isatty(STDERR_FILENO));
    options.progress = [&display, &job](const MeshProgress& p) {
        if (p.stage == "attempt" && p.what == "paper's fan layout, first" && !job.quiet)
            std::cerr
                << "mesohex: the raw mesh has fan blocks; the paper's fan layout is finished too, the better kept\n";
        if (p.stage == "attempt" && p.what.ends_with("fully padded") && !job.quiet)
            std::cerr << "mesohex: the mesh misses a goal; another attempt with every boundary quad padded\n";
        if (p.stage == "attempt" && p.what == "one level finer" && !job.quiet)
            std::cerr << "mesohex: the mesh misses a goal; another attempt one subdivision level finer\n";
        if (p.stage == "attempt" && p.what == "finer for the distance goal" && !job.quiet)
            std::cerr << "mesohex: the mesh misses the Hausdorff goal with its min SJ met; another attempt one "
                         "subdivision level finer\n";
        if (p.stage == "attempt" && p.what.ends_with("cautious joints") && !job.quiet)
            std::cerr << "mesohex: the mesh misses a goal; another attempt with first joints farther from the "
                         "branching points\n";
        for (const StructuralAlternative a : all_structural_alternatives())
            if (p.stage == "attempt" && p.what.ends_with(structural_alternative_name(a)) && !job.quiet)
                std::cerr << "mesohex: the mesh kept misses a goal; another attempt with a structural alternative: "
                          << structural_alternative_name(a) << "\n";
        display.update(p);
    };
    try {
        return mesh_skeleton(skeleton, domain ? &*domain : nullptr, options);
    } catch (const Error& e) {
        throw Error(e.code(), job.skeleton + ": " + e.what(), e.where());  // name the file the element is in
    }
}

int run_mesh_job(const MeshJob& job, const Skeleton& skeleton, const std::optional<TriangleMesh>& domain,
                 std::chrono::steady_clock::time_point start, const nlohmann::json* report_extra,
                 std::optional<std::chrono::steady_clock::time_point> total_start) {
    const auto t_mesh = std::chrono::steady_clock::now();
    const MeshRun run = mesh_job_run(job, skeleton, domain);
    return write_mesh_job(job, run, start, t_mesh, report_extra, total_start);
}

int write_mesh_job(const MeshJob& job, const MeshRun& run, std::chrono::steady_clock::time_point start,
                   std::chrono::steady_clock::time_point t_mesh, const nlohmann::json* report_extra,
                   std::optional<std::chrono::steady_clock::time_point> total_start) {
    const auto t_write = std::chrono::steady_clock::now();
    write_hex_mesh(job.output, run.mesh(), run.quality().sj, run.partition ? run.partition->part : std::vector<int>{});
    const auto t_end = std::chrono::steady_clock::now();
    print_summary(job, run);
    if (run.partition) std::cout << partition_to_text(*run.partition);

    if (!job.report.empty()) {
        ReportContext context{job.skeleton, job.output, job.surface, ms_between(start, t_mesh),
                              ms_between(t_write, t_end)};
        nlohmann::json rep = mesh_report(run, context);
        if (report_extra) {
            for (const auto& [key, value] : report_extra->items())
                if (key != "timings_ms") rep[key] = value;
            if (report_extra->contains("timings_ms"))
                for (const auto& [key, value] : (*report_extra)["timings_ms"].items()) rep["timings_ms"][key] = value;
            rep["timings_ms"]["total"] = ms_between(total_start.value_or(start), t_end);
        }
        write_file_atomically(job.report, rep.dump(2) + "\n");
    }
    const QualityReport& final_quality = run.quality();
    if (run.exit_status() != 0)
        std::cerr << "mesohex: warning: the mesh written to " << job.output << " has " << final_quality.inverted
                  << " inverted hex(es) (scaled Jacobian <= 0)"
                  << (final_quality.validation.valid() ? "" : " and is not a valid hex mesh") << "\n";
    return run.exit_status();
}

}  // namespace mesohex::cli
