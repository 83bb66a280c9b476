#include "mesohex/mesh_report.h"

#include <map>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

namespace mesohex {

namespace {

nlohmann::json xyz(const Vec3& p) { return nlohmann::json::array({p.x, p.y, p.z}); }

nlohmann::json attempts_json(const std::vector<MeshAttempt>& attempts) {
    nlohmann::json list = nlohmann::json::array();
    for (const MeshAttempt& a : attempts) {
        nlohmann::json j = {{"what", a.what},         {"free_branching_reach", a.free_branching_reach},
                            {"padding", a.padding},   {"fan_blocks", a.fan_blocks},
                            {"levels", a.levels},     {"hexes", a.hexes},
                            {"sj_min", a.sj_min},     {"sj_avg", a.sj_avg},
                            {"inverted", a.inverted}, {"missed_goals", a.missed_goals}};
        if (a.distance_measured) j["hausdorff_relative_max"] = a.hausdorff_relative_max;
        list.push_back(j);
    }
    return list;
}

nlohmann::json distance_refinement_json(const DistanceRefinement& d) {
    return {{"tolerance", d.tolerance}, {"levels_before", d.levels_before},
            {"levels_tried", d.levels}, {"hausdorff_tried", d.hausdorff},
            {"hexes_tried", d.hexes},   {"levels_kept", d.levels_kept},
            {"stop", d.stop},           {"reason", d.reason}};
}

nlohmann::json stages_json(const std::vector<FinishStage>& stages) {
    nlohmann::json list = nlohmann::json::array();
    for (const FinishStage& st : stages)
        list.push_back({{"stage", st.stage},
                        {"ms", st.ms},
                        {"vertices", st.vertices},
                        {"hexes", st.hexes},
                        {"sj_min", st.sj_min},
                        {"sj_avg", st.sj_avg},
                        {"inverted", st.inverted},
                        {"iterations", st.iterations}});
    return list;
}

nlohmann::json hausdorff_json(const SurfaceDistance& d) {
    return {{"max", d.max},
            {"mean", d.mean},
            {"relative_max", d.relative_max},
            {"relative_mean", d.relative_mean},
            {"mesh_to_surface_max", d.mesh_to_surface_max},
            {"surface_to_mesh_max", d.surface_to_mesh_max},
            {"mesh_to_surface_at", xyz(d.mesh_to_surface_at)},
            {"surface_to_mesh_at", xyz(d.surface_to_mesh_at)},
            {"bbox_diagonal", d.diagonal}};
}

nlohmann::json timings_json(const MeshRun& run, const ReportContext& context) {
    nlohmann::json timings = nlohmann::json::object();
    timings["read_skeleton"] = context.read_ms + run.radius_ms;
    for (const StageTiming& t : run.pipeline.timings_ms) timings[t.stage] = t.ms;
    timings["pipeline_total"] = run.pipeline_ms;
    timings["quality"] = run.raw_quality_ms;
    if (run.finish) {
        for (const FinishStage& st : run.finish->stages)
            if (st.stage != "input") timings[st.stage] = st.ms;
        timings["hausdorff"] = run.finish->distance_ms;
        timings["finish_total"] = run.finish->total_ms;
    }
    if (run.partition) timings["partition"] = run.partition_ms;
    timings["write_and_finish"] = run.finish_ms + context.write_ms;
    return timings;
}

}  // namespace

nlohmann::json analysis_counts_json(const AnalysisCounts& c) {
    return {{"vertices", c.vertices},
            {"edges", c.edges},
            {"faces", c.faces},
            {"branches", c.branches},
            {"branching_points", c.branching_points},
            {"joints", c.joints},
            {"extremities", c.extremities},
            {"cycles", c.cycles},
            {"components", c.components},
            {"rings", c.rings},
            {"leaflets", c.leaflets},
            {"bl_joints", c.bl_joints},
            {"ll_joints", c.ll_joints},
            {"fan_edges", c.fan_edges},
            {"docked_edges", c.docked_edges},
            {"boundary_edges", c.boundary_edges},
            {"isolated_vertices", c.isolated},
            {"euler_characteristic", c.vertices - c.edges + c.faces}};
}

nlohmann::json prediction_json(const RawMeshPrediction& p) {
    return {{"hexes", p.hexes},
            {"vertices", p.vertices},
            {"compatible_blocks", p.compatible_blocks},
            {"fan_blocks", {{"edges", p.fan_blocks}, {"caps", p.fan_block_caps}}},
            {"virtual_branches", p.virtual_branches},
            {"irregular_edges",
             {{"interior", valence_histogram_json(p.interior_irregular_edges)},
              {"boundary", valence_histogram_json(p.boundary_irregular_edges)}}}};
}

nlohmann::json valence_histogram_json(const std::map<int, long>& histogram) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [valence, count] : histogram) j[std::to_string(valence)] = count;
    return j;
}

nlohmann::json repairs_json(const PipelineResult& res) {
    return {{"trunks", res.trunks},
            {"absorbed_stubs", res.absorbed_stubs},
            {"side_stubs", res.side_stubs},
            {"merged_ends", res.merged_ends},
            {"unseparated_pairs", res.unseparated_pairs},
            {"root_strip_splits", res.root_strip_splits},
            {"docked_foot_splits", res.docked_foot_splits},
            {"docked_band_pillows", res.docked_band_pillows},
            {"junction_splits", res.junction_splits},
            {"fan_end_retractions", res.fan_end_retractions},
            {"fan_cap_branches", res.fan_cap_branches},
            {"fan_end_moved_roots", res.fan_end_moved_roots},
            {"fan_end_far_retractions", res.fan_end_far_retractions},
            {"fan_edge_splits", res.fan_edge_splits},
            {"trimmed_tips", res.trimmed_tips},
            {"trimmed_tip_ends", res.trimmed_tip_ends}};
}

nlohmann::json mesh_report(const MeshRun& run, const ReportContext& context) {
    const PipelineResult& res = run.pipeline;
    nlohmann::json rep;
    rep["input"] = context.input;
    rep["output"] = context.output;
    rep["skeleton"] = analysis_counts_json(res.input_analysis.counts);
    rep["meshed_skeleton"] = analysis_counts_json(res.analysis.counts);
    rep["resampled"] = run.options.resample;
    if (run.options.resample)  // structural repairs before adaptation (stages/skeleton_repair.h)
        rep["repairs"] = repairs_json(res);
    rep["radius"] = {{"source", res.radius_source}, {"value", res.radius}};
    if (res.radius_source == "default") {
        std::ostringstream rule;
        rule << run.options.default_radius_factor << " x mean skeleton edge length";
        rep["radius"]["rule"] = rule.str();
    }
    rep["predicted"] = prediction_json(res.predicted);
    rep["prediction_matches"] = run.prediction_exact;
    rep["quality"] = nlohmann::json::parse(quality_to_json(run.quality()));
    rep["raw_quality"] = nlohmann::json::parse(quality_to_json(run.raw_quality));
    if (!run.radius_note.empty()) rep["radius"]["source"] = run.radius_note;
    if (run.finish) {
        const FinishResult& fin = *run.finish;
        rep["stages"] = stages_json(fin.stages);
        rep["surface"] = context.surface;
        rep["subdivision_levels"] = fin.subdivision_levels;
        rep["inherited_levels"] = fin.inherited_levels;
        rep["fit"] = {{"iterations", fin.fit_iterations}, {"converged", fin.fit_converged}};
        if (fin.fit_uncovered >= 0) rep["fit"]["uncovered_relative"] = fin.fit_uncovered;
        rep["untangled"] = fin.untangled;
        rep["padding"] = {{"mode", fin.pad_mode},
                          {"boundary_quads", fin.pad_boundary_quads},
                          {"bare_quads", fin.pad_bare_quads},
                          {"regions", fin.pad_regions},
                          {"bare_regions", fin.pad_bare_regions},
                          {"sharp_edges", fin.pad_sharp_edges},
                          {"matched_edges", fin.pad_matched_edges},
                          {"inset_vertices", fin.pad_inset_vertices}};
        if (fin.crease_wedges > 0) rep["padding"]["crease_wedges"] = fin.crease_wedges;
        if (fin.crotch_sheets > 0) rep["padding"]["crotch_sheets"] = fin.crotch_sheets;
        rep["attempts"] = attempts_json(run.attempts);  // in the order they ran
        rep["kept_attempt"] = run.kept_attempt;         // index in attempts of the mesh written
        if (const std::optional<StructuralRetry>& sr = run.structural)
            rep["structural_retry"] = {
                {"finished", sr->finished}, {"skipped", sr->skipped}, {"kept", sr->kept}, {"stop", sr->stop}};
        rep["free_branching_reach"] = run.options.adaptation.free_branching_reach;  // of the mesh written
        if (fin.distance_measured) rep["hausdorff"] = hausdorff_json(fin.distance);
        if (run.distance_refinement) rep["distance_refinement"] = distance_refinement_json(*run.distance_refinement);
    }
    if (run.partition) rep["partition"] = nlohmann::json::parse(partition_to_json(*run.partition));
    rep["timings_ms"] = timings_json(run, context);
    return rep;
}

nlohmann::json auto_skeleton_report(const AutoSkeleton& chosen, const AutoSkeletonOptions& options,
                                    const std::string& skeleton_path, const std::string& medial_path) {
    nlohmann::json used = {{"path", skeleton_path},
                           {"vertices", chosen.skeleton.points.size()},
                           {"edges", chosen.skeleton.edges.size()},
                           {"faces", chosen.skeleton.faces.size()}};
    if (chosen.kind == SkeletonKind::Curve) {
        const Skeletonization& sk = chosen.curve;
        used["source"] = "skeletonize_surface (mean curvature flow)";
        used["mcf_vertices"] = sk.mcf_vertices;
        used["pruned_branches"] = sk.pruned_branches;
        used["merged_branch_points"] = sk.merged_branch_points;
        used["extended_extremities"] = sk.extended_extremities;
        // The skeleton used: the flow's own curve when the re-centred one was dropped (nothing re-centred in it).
        const bool dropped = chosen.curve_recentring_dropped;
        used["recentred_joints"] = dropped ? 0 : sk.recentred_joints;
        used["recentre_max_shift"] = dropped ? 0.0 : sk.recentre_max_shift;
        used["recentring_dropped"] = dropped;
    } else {
        used["source"] = "compute_medial_axis + import_medial_mesh (medial meso-skeleton)";
        used["leaflets"] = chosen.import.leaflets;
    }
    nlohmann::json decision = {{"requested", skeleton_kind_name(options.kind)},
                               {"min_sheet_fraction", options.min_sheet_fraction},
                               {"reason", chosen.reason}};
    if (chosen.medial_computed) {
        const MedialAxis& m = chosen.medial;
        decision["medial"] = {{"path", medial_path},
                              {"samples", m.samples},
                              {"vertices", m.medial.points.size()},
                              {"edges", m.medial.edges.size()},
                              {"triangles", m.medial.faces.size()},
                              {"sheets", m.sheets},
                              {"curves", m.curves},
                              {"euler_characteristic", m.euler},
                              {"sheet_area", m.sheet_area},
                              {"curve_band_area", m.curve_band_area},
                              {"sheet_fraction", m.sheet_fraction},
                              {"covering_parts", m.covering_parts},
                              {"limbs", m.limbs},
                              {"limb_branches", m.limb_branches},
                              {"rim_border_vertices", m.rim_border_vertices},
                              {"rim_moved", m.rim_moved},
                              {"coverage_gap_relative", chosen.coverage_gap}};
    }
    if (chosen.raw_checked) {
        decision["meso_radii"] = {{"radius_factor_used", chosen.meso_radius_factor_used},
                                  {"full_radius_factor", options.meso_full_radius_factor},
                                  {"fallback_radius_factor", options.meso_radius_factor},
                                  {"why", chosen.meso_radius_why}};
        if (chosen.full_raw_failed)
            decision["meso_radii"]["full_raw_mesh"] = {{"hexes", chosen.full_raw_hexes},
                                                       {"inverted", chosen.full_raw_inverted},
                                                       {"sj_min", chosen.full_raw_sj_min},
                                                       {"valid", chosen.full_raw_valid},
                                                       {"error", chosen.full_raw_error}};
        decision["meso_raw_mesh"] = {{"hexes", chosen.raw_hexes},
                                     {"inverted", chosen.raw_inverted},
                                     {"sj_min", chosen.raw_sj_min},
                                     {"max_inverted", options.max_raw_inverted},
                                     {"min_sj", options.min_raw_sj},
                                     {"radius_factor", chosen.meso_radius_factor_used},
                                     {"leaflet_radius_edge_factor", options.meso_leaflet_radius_edge_factor},
                                     {"capped_leaflet_radii", chosen.capped_leaflet_radii},
                                     {"border_radius_edge_factor", options.meso_border_radius_edge_factor},
                                     {"capped_border_radii", chosen.capped_border_radii},
                                     {"inverted_at",
                                      {{"joins", chosen.raw_sites.joins},
                                       {"at_joins", chosen.raw_sites.at_joins},
                                       {"half_chunks", chosen.raw_sites.half_chunks},
                                       {"chunks", chosen.raw_sites.chunks},
                                       {"plates", chosen.raw_sites.plates}}}};
    }
    if (chosen.curve_raw_checked)
        decision["curve_raw_mesh"] = {{"hexes", chosen.curve_raw_hexes},
                                      {"inverted", chosen.curve_raw_inverted},
                                      {"sj_min", chosen.curve_raw_sj_min},
                                      {"valid", chosen.curve_raw_valid},
                                      {"padded_inverted", chosen.curve_padded_inverted},
                                      {"recentring_dropped", chosen.curve_recentring_dropped},
                                      {"max_answer_inverted", options.max_answer_inverted}};
    if (!chosen.refusal.empty()) decision["refusal"] = chosen.refusal;
    return {{"mode", "auto"},
            {"skeleton_kind", skeleton_kind_name(chosen.kind)},
            {"skeleton_decision", decision},
            {"skeleton_used", used}};
}

}  // namespace mesohex
