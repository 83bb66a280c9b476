#pragma once
// The meshing job shared by `mesohex mesh` and `mesohex auto`: (radii from the surface) -> run_pipeline ->
// finish_mesh -> write the mesh, print the per-stage lines, write the JSON report. Returns the exit status
// (0, or 5 when the mesh written has inverted hexes); errors are mesohex::Error.
#include <chrono>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"

namespace mesohex::cli {

struct MeshJob {
    std::string skeleton;  // the skeleton's name in messages and in the report ("input")
    std::string surface;   // the domain's name in messages and in the report (when a domain is given)
    std::string output;
    double radius = 0;
    bool no_resample = false;
    bool raw = false;
    std::string report;
    int threads = 0;
    bool radius_from_surface = false;
    double radius_factor = 0.5;
    int levels = -1;
    double size = 0;
    std::string refine = "uniform";  // uniform | longitudinal | radial
    bool no_pad = false;
    bool no_fit = false;
    bool no_untangle = false;
    bool no_smooth = false;
    bool no_retry = false;  // no second attempt with the cautious reach at branching points
    int iterations = 300;
    double fit_weight = 3.0;
    double improve_sj = 0.3;
    bool quiet = false;
};

// Adds the options common to `mesh` and `auto` (from --radius-from-surface to --threads) to `cmd`.
void add_mesh_job_options(CLI::App* cmd, MeshJob* job);

// Runs the job on `skeleton` (and `domain`, when given). `start` is when the caller began reading its inputs: the
// report's "read_skeleton" timing runs from it to the start of the pipeline. `report_extra` (an object, may be null):
// its members are added to the report, except "timings_ms" whose members are added to the report's timings; when it
// is given, the timings also get "total" (from `total_start`, or `start` when not given, to the mesh written).
int run_mesh_job(const MeshJob& job, Skeleton skeleton, const std::optional<TriangleMesh>& domain,
                 std::chrono::steady_clock::time_point start, const nlohmann::json* report_extra = nullptr,
                 std::optional<std::chrono::steady_clock::time_point> total_start = std::nullopt);

}  // namespace mesohex::cli
