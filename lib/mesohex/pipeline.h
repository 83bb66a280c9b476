#pragma once
// The pipeline: chains the stages (radius -> analysis -> adaptation -> analysis -> connection surfaces -> frames ->
// raw mesh) and times each one. No geometry of its own.
#include <string>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/stages/adaptation.h"
#include "mesohex/stages/raw_mesh.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex/stages/skeleton_repair.h"
#include "mesohex/stages/virtual_branches.h"

namespace mesohex {

struct FanBlocks;

struct PipelineOptions {
    // Radius: the file's per-vertex radii when present; else `radius` when > 0; else the default
    // default_radius_factor x (mean length of all skeleton edges), the same for every vertex.
    double radius = 0;
    double default_radius_factor = 0.25;  // x the mean skeleton edge length (dimensionless)
    bool resample = true;          // paper step 1 (adapt_skeleton); false keeps the input sampling (hexes == 4 x edges)
    SkeletonRepairOptions repair;  // trunks, root patches (before adaptation, with resample)
    AdaptationOptions adaptation;  // resampling against the radii
    AnalysisOptions analysis;      // classification and rejection rules
    ConnectionSurfaceOptions connection_surfaces;  // junction surfaces
    RawMeshOptions raw_mesh;                       // block layout and leaflet offsets
    // One-edge virtual branches at branching points with an empty cap (stages/virtual_branches.h), added to the
    // meshed skeleton after adaptation. Off by default.
    VirtualBranchOptions virtual_branches;
};

struct StageTiming {
    std::string stage;
    double ms = 0;
};

// What stands at a root checked on the raw mesh (check_moved_roots): a root the fan-end repair moved or a corner it
// retracted (fan_end_repair.h), or a fan end whose branch stands on its fan block's side section or in its notch
// between two leaflets (CompatibleBlockOptions::fan_side_branches; FanBlockChain::side_axis, notch).
enum class RootPlaceKind { Repaired, SideSection, Notch };

// A moved root (fan_end_repair.h): the fan-end vertex named in messages (its input id, or its repaired id when the
// repair made it: by_input), the cut point m that carries the branch and the radius r_w there (model units). For a
// side section or a notch: the fan end w itself and r_w.
struct MovedRootPlace {
    int vertex = -1;
    bool by_input = true;
    Vec3 point{};
    double radius = 0;
    bool far = true;  // a branch far from the fan line (moved, or retracted by the fallback); else a retraction
    RootPlaceKind kind = RootPlaceKind::Repaired;
};

struct PipelineResult {
    std::string radius_source;        // "file", "option" or "default"
    double radius = 0;                // the uniform radius used when radius_source != "file" (else 0)
    SkeletonAnalysis input_analysis;  // analysis of the input skeleton (before adaptation)
    int trunks = 0;                   // trunk vertices the repair inserted (SkeletonRepairResult)
    int absorbed_stubs = 0;           // stubs the repair absorbed into a trunk vertex
    int side_stubs = 0;               // stubs the repair kept as side branches of their sibling
    int main_stubs = 0;               // fat stubs the repair kept as the main line (fat_stub_main_line)
    int merged_ends = 0;  // close-pair branches ending at a branching point, absorbed (their children re-attached)
    int unseparated_pairs = 0;             // close branch pairs the repair left (a branch ends inside the other's tube)
    int root_strip_splits = 0;             // leaflet face strips the repair split around rooted branches
    int docked_foot_splits = 0;            // plate face strips split beside and beyond docked chains
    int docked_band_pillows = 0;           // docked chains whose plate band was pillowed
    int junction_splits = 0;               // degree-4 branching points the repair split into two of degree 3
    std::vector<int> fan_end_retractions;  // input vertices (branches on fan-edge ends) the repair made leaflet corners
    // Input vertices whose branch stands on a fan block's cap (CompatibleBlockOptions::fan_cap_branches): not repaired.
    std::vector<int> fan_cap_branches;
    // Of fan_end_retractions: branches far from the fan line whose root the repair moved onto a leaflet border
    // (FanEndRetraction::moved_root), and those retracted with the fan edge instead (FanEndRetraction::far_branch,
    // kFallbackCornerDeg: a notch at the leaflets' corner).
    std::vector<int> fan_end_moved_roots;
    std::vector<int> fan_end_far_retractions;
    // Fan-edge chains cut before their retraction: single fan edges in two, chains of 1-2 edges with branches at both
    // ends into 3-4.
    int fan_edge_splits = 0;
    // Branches far from the fan line whose root the repair moved onto a leaflet border (FanEndRetraction::moved_root),
    // and every retracted corner (far or not); after the connection surfaces, the fan ends whose branch stands on the
    // fan block's side section or in its notch (add_fan_side_roots): checked on the raw mesh (check_moved_roots).
    std::vector<MovedRootPlace> moved_roots;
    // Branch tips the domain does not hold, trimmed before the structural repairs (stages/tip_trim.h; `held` given to
    // prepare_skeleton, with resampling): the input vertices removed, and the input vertices that became branch ends.
    std::vector<int> trimmed_tips;
    std::vector<int> trimmed_tip_ends;
    int virtual_branches = 0;   // virtual branches added to the meshed skeleton (PipelineOptions::virtual_branches)
    Skeleton skeleton;          // the skeleton actually meshed (radii filled, adapted when resampling)
    SkeletonAnalysis analysis;  // analysis of `skeleton`
    RawMeshPrediction predicted;
    RawMesh raw;
    std::vector<StageTiming> timings_ms;  // in pipeline order
};

// The first half of run_pipeline: the input analysis (accepting the configurations the repairs below fix, e.g. a
// branch on a fan-edge end), the radii, and with `resample` the structural repairs (repair_skeleton), adaptation and
// the analysis of the result. Fills everything in PipelineResult up to `analysis` (not predicted, raw). `mesohex
// analyze` and the studio's analyze call it (or run_pipeline), so every subcommand judges the skeleton `mesh`
// meshes, after the same repairs. Errors: as run_pipeline's analyses and repairs.
// held (may be null; else one entry per input vertex): 1 where the domain holds the vertex's ball (mesh.cpp: its
// centre inside the domain). With resampling, branch tips not held are trimmed before the repairs
// (trim_unheld_tips, stages/tip_trim.h; PipelineResult::trimmed_tips); vertices are still named by their input ids.
PipelineResult prepare_skeleton(const Skeleton& input, const PipelineOptions& options = {},
                                const std::vector<char>* held = nullptr);

// Errors: whatever the stages throw (mesohex::Error naming the element), before anything is built. held: as
// prepare_skeleton's.
PipelineResult run_pipeline(const Skeleton& input, const PipelineOptions& options = {},
                            const std::vector<char>* held = nullptr);

// The repairs prepare_skeleton made, one line each ("repairs: none" when there were none; "repairs: not run (no
// resampling)" when `resample` was off), for `mesohex analyze`.
std::string repairs_to_text(const PipelineResult& res, const PipelineOptions& options);
// The line of repairs_to_text on PipelineResult::trimmed_tips ("" when none were trimmed), which `mesh` prints too.
std::string trimmed_tips_to_text(const PipelineResult& res);

// Appends to res.moved_roots the fan ends whose branch stands on a fan block's side section or in its notch
// (blocks: the connection surfaces' fan blocks of res.skeleton), at the fan end w with radius r_w; named by the input
// vertex at w's place among res.fan_cap_branches (resampled), by w itself when res.skeleton is numbered as `input`
// (no resampling: the meshed skeleton is the input, virtual branches appended), else by w's meshed id.
void add_fan_side_roots(PipelineResult& res, const FanBlocks& blocks, const Skeleton& input, bool resampled);

// Refuses a raw mesh with an inverted hex next to a moved root (its centroid within kMovedRootCheckRadii r_w of the
// cut point m): throws UnsupportedConfiguration naming the fan-end vertex, the configuration and an edit. The moved
// roots between two leaflets or near a leaflet's plane give 1 - 2 such hexes at scattered radii (issue 22's sweep,
// docs/blocks.md "Moved roots: first joint and thick radii"), where no measured angle or radius ratio separates them
// from their clean neighbours. Every retracted corner is checked the same way, whether or not its fan neighbour's cap
// reaches up to it (RawMeshOptions::fan_end_cap_to_border, off by default). Each inverted hex counts for the root
// nearest to its centroid (within reach), so that the refusal names the root where the hexes fold (a single fan edge
// has roots at both ends within reach of the same hexes). The fan ends whose branch stands on a fan block's side
// section or in its notch (add_fan_side_roots) are checked the same way around the fan end: their first chunk folds
// when its first section lies less than r past the block's side or the notch's corner (the skeleton meshed as given
// with a close first joint). O(hexes x moved roots) when there is a moved root, else nothing.
void check_moved_roots(const PipelineResult& res);

// Refuses a raw mesh with an inverted half-chunk hex of a leaflet border edge (w, x) whose inverted corner is on the
// out column of w, where w's border creases (its faces' normals more than kCreaseNormalGainDeg apart, a leaflet
// boundary vertex or a fan-edge end): a wall standing on part of a plate's border, at the wall's end (`flange`,
// `flangeup`). There w's one out column serves the plate's border half-chunk (out across the border, up the plate's
// normal) and the wall's end half-chunk (out along the border, up the wall's normal); its face lies in the plane of
// w's out and crease-normal directions, which passes through x's out-up copy at r = L / 2 for a wall at right angles
// (L = |w x|; docs/blocks.md, "Thick flanges: the bound r < L / 2"), and no placement of w's column alone clears it
// (measured: at most 0.14 / 0.08 at r = 0.6 / 0.9 L). Throws UnsupportedConfiguration naming w, the bound and an
// edit, only when w's radius is above L / 2 (an inverted hex there below the bound has another cause: counted only).
// Called, as check_moved_roots, only where the raw mesh is the output. O(hexes) when a half-chunk is inverted.
void check_border_creases(const PipelineResult& res);

// The default uniform radius: factor x mean edge length (1.0 for a skeleton without edges).
double default_radius(const Skeleton& skeleton, double factor);

}  // namespace mesohex
