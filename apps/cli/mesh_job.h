#pragma once
// The meshing job shared by `mesohex mesh` and `mesohex auto`: maps the command-line flags to MeshOptions, runs the
// library's mesh_skeleton, writes the mesh, prints the per-stage lines and writes the JSON report (mesh_report).
// Returns the exit status (0, or 5 when the mesh written has inverted hexes); errors are mesohex::Error.
#include <chrono>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/mesh.h"

namespace mesohex::cli {

struct MeshJob {
    std::string skeleton;  // the skeleton's name in messages and in the report ("input")
    std::string surface;   // the domain's name in messages and in the report (when a domain is given)
    std::string output;
    std::string report;
    std::string refine = "uniform";  // uniform | longitudinal | radial -> options.finishing.refinement
    int threads = 0;                 // 0 = all cores
    bool quiet = false;
    MeshOptions options;  // every meshing option; the flags write into it (library defaults)
};

// Adds the options common to `mesh` and `auto` (from --radius-from-surface to --threads) to `cmd`.
void add_mesh_job_options(CLI::App* cmd, MeshJob* job);

// Runs the job on `skeleton` (and `domain`, when given). `start` is when the caller began reading its inputs: the
// report's "read_skeleton" timing runs from it to the start of the meshing. `report_extra` (an object, may be null):
// its members are added to the report, except "timings_ms" whose members are added to the report's timings; when it
// is given, the timings also get "total" (from `total_start`, or `start` when not given, to the mesh written).
int run_mesh_job(const MeshJob& job, const Skeleton& skeleton, const std::optional<TriangleMesh>& domain,
                 std::chrono::steady_clock::time_point start, const nlohmann::json* report_extra = nullptr,
                 std::optional<std::chrono::steady_clock::time_point> total_start = std::nullopt);

// run_mesh_job in two steps, for a caller that compares runs before writing one (`mesohex auto`): the meshing
// (progress on stderr; errors name job.skeleton), then the writing, printing and report of the run kept (`t_mesh`:
// when its meshing began).
MeshRun mesh_job_run(const MeshJob& job, const Skeleton& skeleton, const std::optional<TriangleMesh>& domain);
int write_mesh_job(const MeshJob& job, const MeshRun& run, std::chrono::steady_clock::time_point start,
                   std::chrono::steady_clock::time_point t_mesh, const nlohmann::json* report_extra = nullptr,
                   std::optional<std::chrono::steady_clock::time_point> total_start = std::nullopt);

}  // namespace mesohex::cli
