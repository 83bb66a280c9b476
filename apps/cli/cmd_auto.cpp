// `mesohex auto SURFACE -o OUT [--skeleton auto|curve|meso] [finishing options] [--report REPORT.json]`: surface ->
// skeleton chosen by choose_skeleton (curve skeleton by mean curvature flow for tubes, medial meso-skeleton where the
// medial axis has sheets) -> the same meshing job as `mesohex mesh SKELETON --surface SURFACE`. The
// skeleton is written beside the mesh (OUT with its extension replaced by .skeleton.obj) so the user can edit it and
// re-run `mesohex mesh`. A surface that cannot be skeletonized is an error and nothing is written.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "mesh_job.h"
#include "mesohex/auto_skeleton.h"
#include "mesohex/core/error.h"
#include "mesohex/mesh_report.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

namespace mesohex::cli {

namespace {

struct AutoArgs {
    MeshJob job;
    std::string surface;
    std::string skeleton_kind = "auto";
    bool best_effort = false;
    // Work budget in hexes (deterministic, unlike a time limit): the finished mesh has at most this many hexes (the
    // subdivision levels are lowered until it fits), and the second attempt runs only when the first finished at most
    // half of it, so the finishing handles at most max_hexes hexes in all. The finishing's stages cost a bounded number
    // of sweeps per hex: about 2 ms of CPU per hex per attempt on this machine (docs/skeletons.md).
    long max_hexes = 24000;
    // MeshOptions::finer_retry: the mesh kept is finished once more one level finer when it misses a goal (within
    // half of max_hexes, like the second attempt).
    bool finer_retry = true;
    // MeshOptions::refine_to_distance: finer levels while the mesh kept misses only the distance goal (and possibly the
    // average SJ), within max_hexes finished over all attempts.
    bool refine_to_distance = true;
    // MeshOptions::structural_retry: off in auto until measured on its surfaces (its budget is 60 s of CPU per
    // surface; docs/junctions.md, "Structural alternatives when the mesh kept misses").
    bool structural_retry = false;
    AutoSkeletonOptions skeleton;
};

// The refusal of --skeleton auto (AutoSkeleton::refusal): the skeleton and medial mesh stay written for editing, the
// report (if asked for) says why, and the command fails with exit status 3 before any finishing.
void refuse(const AutoArgs& args, const AutoSkeleton& chosen, nlohmann::json extra) {
    if (!args.job.report.empty()) {
        extra["refused"] = chosen.refusal;
        write_file_atomically(args.job.report, extra.dump(2) + "\n");
    }
    throw Error(ErrorCode::UnsupportedConfiguration,
                args.surface + ": auto refuses this surface: " + chosen.refusal +
                    " (the finishing would have to untangle them and would miss the quality targets; --best-effort "
                    "meshes it anyway, or edit the skeleton written beside the output)");
}

// The numbers of a finished mesh in a reason: min / avg SJ, Hausdorff (% of the diagonal), goals missed.
std::string finish_numbers(const FinishResult& f, const MeshGoals& goals) {
    std::ostringstream out;
    out << "min / avg SJ " << f.quality.sj_min << " / " << f.quality.sj_avg;
    if (f.distance_measured) out << ", Hausdorff " << 100 * f.distance.relative_max << " %";
    out << ", " << missed_goals(f, goals) << " goal(s) missed";
    return out.str();
}

// Auto chose the meso-skeleton: when its finished mesh misses a goal, the curve skeleton is finished too and the
// better of the two kept (better_finish: fewer inverted hexes, fewer goals missed, a smaller Hausdorff distance, a
// higher min SJ); the skeleton file then holds the curve skeleton. The reason says what was compared.
void keep_better_of_both(const MeshJob& job, const TriangleMesh& domain, const AutoSkeletonOptions& so,
                         const std::string& skeleton_path, AutoSkeleton& chosen, MeshRun& run) {
    const MeshGoals& goals = job.options.goals;
    if (!run.finish || missed_goals(*run.finish, goals) == 0) return;
    const std::string meso = finish_numbers(*run.finish, goals);
    const auto keep_meso = [&](const std::string& why) {
        chosen.reason += "; its finished mesh (" + meso + ") misses a goal; " + why + ": meso-skeleton kept";
    };
    // The comparison must not cost the meso answer: a curve skeleton that cannot be computed or meshed is noted.
    AutoSkeleton curve;
    MeshRun other;
    try {
        curve =
            curve_instead(domain, so, chosen, "its finished mesh (" + meso + ") misses a goal: curve skeleton tried");
        if (!curve.refusal.empty()) return keep_meso("the curve skeleton is refused (" + curve.refusal + ")");
        other = mesh_job_run(job, curve.skeleton, domain);
    } catch (const Error& e) {
        return keep_meso(std::string("the curve skeleton failed (") + e.what() + ")");
    }
    const std::string alt = other.finish ? finish_numbers(*other.finish, goals) : "not finished";
    if (!other.finish || !better_finish(*other.finish, *run.finish, goals))
        return keep_meso("the curve skeleton's (" + alt + ") is not better");
    curve.reason += " (" + alt + "): better, curve skeleton kept";
    chosen = std::move(curve);
    run = std::move(other);
    write_skeleton(skeleton_path, chosen.skeleton);
    std::cout << "auto: the meso-skeleton's mesh (" << meso << ") misses a goal; the curve skeleton's (" << alt
              << ") is better: kept, its skeleton -> " << skeleton_path << "\n";
}

}  // namespace

void register_auto(CLI::App& app, int* status) {
    auto args = std::make_shared<AutoArgs>();
    CLI::App* cmd = app.add_subcommand(
        "auto",
        "Surface -> hex mesh in one step: a skeleton (curve skeleton for tubes, medial meso-skeleton for flat "
        "or thin parts), then mesh with the surface.");
    cmd->add_option("surface", args->surface, "Closed surface (.off .obj .stl .ply), one component, manifold")
        ->required();
    cmd->add_option("-o,--output", args->job.output, "Output hex mesh (.mesh, .vtk, .vtu, .msh, .inp, .exo)")
        ->required();
    cmd->add_flag_callback(
        "--no-resample", [args] { args->job.options.pipeline.resample = false; },
        "Keep the skeleton's sampling (hexes = 4 x edges)");
    cmd->add_flag_callback(
        "--raw", [args] { args->job.options.finish = false; },
        "Stop after the raw mesh (no padding, subdivision or fitting)");
    cmd->add_option("--skeleton", args->skeleton_kind,
                    "auto: decide from the medial axis's sheet fraction; curve: mean-curvature-flow skeleton; meso: "
                    "medial axis imported as branches + leaflets")
        ->check(CLI::IsMember({"auto", "curve", "meso"}))
        ->capture_default_str();
    cmd->add_flag("--best-effort", args->best_effort,
                  "auto: mesh even when no skeleton gives a raw mesh without inverted hexes (otherwise refused, exit "
                  "status 3, with the skeleton still written)");
    cmd->add_flag_callback(
        "--no-finer-retry", [args] { args->finer_retry = false; },
        "No attempt one subdivision level finer when the mesh kept misses a goal (by default it runs when 8 x its "
        "hexes stay within half of --max-hexes)");
    cmd->add_flag_callback(
        "--no-distance-refinement", [args] { args->refine_to_distance = false; },
        "No finer levels when the mesh kept misses the Hausdorff goal with its min SJ met (by default one level finer "
        "at a time while the goal is missed, each kept when better, within --max-hexes finished over all attempts; "
        "the report's distance_refinement says what was decided)");
    cmd->add_flag("--structural-retry", args->structural_retry,
                  "Structural alternatives when the mesh kept misses a goal, as `mesh` tries them (off in auto by "
                  "default: docs/junctions.md, \"Structural alternatives when the mesh kept misses\")");
    cmd->add_option("--max-hexes", args->max_hexes,
                    "Work budget: at most this many finished hexes over both attempts (fewer subdivision levels, no "
                    "second attempt beyond half of it); 0 = no budget")
        ->check(CLI::Range(0L, 1L << 40))
        ->capture_default_str();
    cmd->add_option("--min-sheet-fraction", args->skeleton.min_sheet_fraction,
                    "auto: the meso-skeleton when the medial axis's sheet fraction is at least this")
        ->capture_default_str();
    add_medial_axis_options(cmd, args->skeleton.medial, "medial axis: ");
    cmd->add_option("--curve-recentre-passes", args->skeleton.skeletonize.recentre_passes,
                    "curve skeleton: passes moving every joint towards the middle of its cross-section (see mesohex "
                    "skeletonize --recentre-passes; 0 = off)")
        ->check(CLI::Range(0, 100))
        ->capture_default_str();
    cmd->add_option(
           "--meso-radius-factor", args->skeleton.meso_radius_factor,
           "meso-skeleton radii = this x the distance to the surface when the full radii's raw mesh inverts (0: "
           "keep the medial radii)")
        ->check(finite_range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--meso-full-radius-factor", args->skeleton.meso_full_radius_factor,
                    "meso-skeleton radii tried first = this x the distance to the surface; when their raw mesh "
                    "inverts, --meso-radius-factor instead (0: --meso-radius-factor only)")
        ->check(finite_range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--meso-leaflet-radius-factor", args->skeleton.meso_leaflet_radius_edge_factor,
                    "meso-skeleton leaflet vertices: radius at most this x their shortest leaflet edge (0: no cap)")
        ->check(finite_range(0.0, 10.0))
        ->capture_default_str();
    cmd->add_option("--meso-border-radius-factor", args->skeleton.meso_border_radius_edge_factor,
                    "meso-skeleton leaflet border vertices: radius at most this x their shortest border side (0: no "
                    "cap)")
        ->check(finite_range(0.0, 10.0))
        ->capture_default_str();
    cmd->add_option("--meso-sheet-offset", args->skeleton.import.max_sheet_offset,
                    "meso-skeleton import: while smoothing, a leaflet vertex stays within this x its radius of the "
                    "medial sheet (0: on the sheet; negative: free)")
        ->check(finite_range(-1.0, 100.0))
        ->capture_default_str();
    add_bl_corner_options(cmd, &args->skeleton.import, "meso-skeleton import: ");
    add_mesh_job_options(cmd, &args->job);
    cmd->footer(
        "The skeleton used is written beside the mesh (OUT.skeleton.obj, with radii): edit it and re-run\n"
        "  mesohex mesh OUT.skeleton.obj --surface SURFACE -o OUT.mesh\n"
        "Examples:\n  mesohex auto cactus.obj -o cactus.mesh --report cactus.json\n"
        "  mesohex auto aorta.stl -o aorta.vtu --levels 2\n"
        "Exit status: 0 ok; 2 invalid input (e.g. a surface that is open, non-manifold or in several "
        "components); 3 unsupported configuration (also: auto refuses the surface, see --best-effort); 4 file error; 5 "
        "the mesh written has inverted hexes.");
    cmd->callback([args, status]() {
        std::optional<tbb::global_control> threads;
        if (args->job.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, args->job.threads);
        auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };

        const auto t0 = std::chrono::steady_clock::now();
        std::optional<TriangleMesh> domain = read_surface(args->surface);
        const auto t1 = std::chrono::steady_clock::now();
        AutoSkeletonOptions so = args->skeleton;
        so.kind = args->skeleton_kind == "curve"  ? SkeletonKind::Curve
                  : args->skeleton_kind == "meso" ? SkeletonKind::Meso
                                                  : SkeletonKind::Auto;
        so.raw_mesh = args->job.options.pipeline.raw_mesh;
        // Throws (nothing written) when it cannot be done, naming the surface file.
        AutoSkeleton chosen = at_stage("skeleton", args->surface, [&] { return choose_skeleton(*domain, so); });
        const auto t2 = std::chrono::steady_clock::now();
        const std::string skeleton_path =
            std::filesystem::path(args->job.output).replace_extension(".skeleton.obj").string();
        write_skeleton(skeleton_path, chosen.skeleton);
        std::string medial_path;
        if (chosen.medial_computed) {
            medial_path = std::filesystem::path(args->job.output).replace_extension(".medial.ma").string();
            write_medial_mesh(medial_path, chosen.medial.medial);
        }
        const auto t3 = std::chrono::steady_clock::now();

        const char* kind = skeleton_kind_name(chosen.kind);
        std::cout << "skeleton (" << kind << ") of " << args->surface << ": " << chosen.skeleton.points.size()
                  << " vertices, " << chosen.skeleton.edges.size() << " edges, " << chosen.skeleton.faces.size()
                  << " faces in " << ms(t1, t2) << " ms -> " << skeleton_path << "\n  " << chosen.reason << "\n";

        MeshJob job = args->job;
        job.options.finer_retry = args->finer_retry;
        job.options.refine_to_distance = args->refine_to_distance;
        job.options.structural_retry = job.options.structural_retry && args->structural_retry;
        if (args->max_hexes > 0) {
            job.options.finishing.max_hexes = args->max_hexes;
            job.options.retry_max_hexes = args->max_hexes / 2;
        }
        job.skeleton = skeleton_path;
        job.surface = args->surface;
        const auto timings = [&] {
            return nlohmann::json{
                {"read_surface", ms(t0, t1)}, {"skeletonize", ms(t1, t2)}, {"write_skeleton", ms(t2, t3)}};
        };
        if (!chosen.refusal.empty() && !args->best_effort) {
            nlohmann::json extra = auto_skeleton_report(chosen, so, skeleton_path, medial_path);
            extra["timings_ms"] = timings();
            refuse(*args, chosen, extra);
        }
        const auto t_mesh = std::chrono::steady_clock::now();
        MeshRun run = at_stage(
            "mesh", skeleton_path, [&] { return mesh_job_run(job, chosen.skeleton, domain); }, false);
        if (so.kind == SkeletonKind::Auto && chosen.kind == SkeletonKind::Meso)
            keep_better_of_both(job, *domain, so, skeleton_path, chosen, run);
        nlohmann::json extra = auto_skeleton_report(chosen, so, skeleton_path, medial_path);
        extra["timings_ms"] = timings();
        // The report's "read_skeleton" is the radius step only (the skeleton is in memory); "total" starts at t0.
        *status = write_mesh_job(job, run, t3, t_mesh, &extra, t0);
        std::cout << "auto: total " << ms(t0, std::chrono::steady_clock::now()) << " ms\n";
    });
}

}  // namespace mesohex::cli
