#pragma once
// The JSON report of a meshing run (what `mesohex mesh --report` writes, what the studio's /api/mesh answers and the
// Python module's report dict holds): input and output names, skeleton counts before and after adaptation, radius
// source, predicted counts and irregular edges, raw and final quality, the finishing stages, the attempts, the
// two-sided Hausdorff distance, and the timings. One builder, so every caller gives the same keys.
#include <map>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "mesohex/auto_skeleton.h"
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

// What `mesohex auto` adds to the report about the skeleton it chose: "mode", "skeleton_kind", "skeleton_decision"
// (requested kind, thresholds, reason, the medial mesh's measures, the meso raw-mesh check) and "skeleton_used" (where
// it was written and how it was made). `medial_path` may be empty (no medial mesh written).
nlohmann::json auto_skeleton_report(const AutoSkeleton& chosen, const AutoSkeletonOptions& options,
                                    const std::string& skeleton_path, const std::string& medial_path);

// Skeleton counts as the report gives them ("skeleton", "meshed_skeleton"), and a valence histogram.
nlohmann::json analysis_counts_json(const AnalysisCounts& counts);
// The report's "repairs" object: the structural repairs prepare_skeleton made (pipeline.h; with resampling only).
nlohmann::json repairs_json(const PipelineResult& res);
nlohmann::json valence_histogram_json(const std::map<int, long>& histogram);
// The report's "predicted" object: hexes, vertices, compatible and fan blocks, virtual branches, irregular edges.
nlohmann::json prediction_json(const RawMeshPrediction& p);

}  // namespace mesohex
