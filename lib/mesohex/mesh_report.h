#pragma once
// The JSON report of a meshing run (what `mesohex mesh --report` writes, what the studio's /api/mesh answers and the
// Python module's report dict holds): input and output names, skeleton counts before and after adaptation, radius
// source, predicted counts and irregular edges, raw and final quality, the finishing stages, the attempts, the
// two-sided Hausdorff distance, and the timings. One builder, so every caller gives the same keys.
#include <map>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "mesohex/mesh.h"

namespace mesohex {

struct ReportContext {
    std::string input;    // the skeleton's name ("input")
    std::string output;   // the mesh file written ("output"), may be empty
    std::string surface;  // the domain's name ("surface", only when the mesh was finished in a domain)
    double read_ms = 0;   // reading the inputs, before mesh_skeleton (added to timings_ms.read_skeleton)
    double write_ms = 0;  // writing the mesh, after mesh_skeleton (added to timings_ms.write_and_finish)
};

nlohmann::json mesh_report(const MeshRun& run, const ReportContext& context);

// Skeleton counts as the report gives them ("skeleton", "meshed_skeleton"), and a valence histogram.
nlohmann::json analysis_counts_json(const AnalysisCounts& counts);
nlohmann::json valence_histogram_json(const std::map<int, long>& histogram);

}  // namespace mesohex
