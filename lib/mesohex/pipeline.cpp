#include "mesohex/pipeline.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/skeleton_radii.h"
#include "mesohex/stages/connection_surfaces.h"
#include "mesohex/stages/fan_blocks.h"
#include "mesohex/stages/fan_end_repair.h"
#include "mesohex/stages/frame_propagation.h"
#include "mesohex/stages/leaflet_geometry.h"
#include "mesohex/stages/tip_trim.h"

namespace mesohex {

namespace {

class StageClock {
public:
    explicit StageClock(std::vector<StageTiming>& out) : out_(out), start_(std::chrono::steady_clock::now()) {}
    void lap(const char* stage) {
        const auto now = std::chrono::steady_clock::now();
        out_.push_back({stage, std::chrono::duration<double, std::milli>(now - start_).count()});
        start_ = now;
    }

private:
    std::vector<StageTiming>& out_;
    std::chrono::steady_clock::time_point start_;
};

// Whether repair_skeleton or adapt_skeleton may change `s` (analysed as `an`): it has a branch edge (an edge on no
// face) or two edges joining the same two vertices.
bool curve_work(const Skeleton& s, const SkeletonAnalysis& an) {
    if (std::find(an.edge_degree.begin(), an.edge_degree.end(), 0) != an.edge_degree.end()) return true;
    for (std::size_t v = 0; v + 1 < an.vertex_edge_begin.size(); ++v)
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i)
            for (int j = an.vertex_edge_begin[v]; j < i; ++j) {
                const std::array<int, 2>& a = s.edges[static_cast<std::size_t>(an.vertex_edges[i])];
                const std::array<int, 2>& b = s.edges[static_cast<std::size_t>(an.vertex_edges[j])];
                if (a[0] + a[1] == b[0] + b[1]) return true;  // both at v: the same other end
            }
    return false;
}

// The input's analysis `a` (input_options: options.analysis with fan_end_branches possibly set) is what
// options.analysis gives on the same skeleton when the flag is the same or no vertex has a branch on a fan-edge end
// (the one case the flag decides: FanEdgeEnd with branch edges is accepted with it, an error without it).
bool same_analysis(const SkeletonAnalysis& a, const AnalysisOptions& input_options, const AnalysisOptions& options) {
    if (!a.docked_unmatched.empty()) return false;  // accepted only for the band pillow
    if (input_options.fan_end_branches == options.fan_end_branches) return true;
    for (std::size_t v = 0; v < a.vertex_class.size(); ++v)
        if (a.vertex_class[v] == VertexClass::FanEdgeEnd && a.vertex_branch_edges[v] > 0) return false;
    return true;
}

// A repaired skeleton's vertex as messages name it: its input id when it has one (the repair renumbers when it drops
// trunk joints), else its repaired id; and whether it is an input id.
std::pair<int, bool> named_vertex(const std::vector<int>& vertex_map, int v) {
    const auto input_id = std::ranges::find(vertex_map, v);
    if (input_id == vertex_map.end()) return {v, false};
    return {static_cast<int>(input_id - vertex_map.begin()), true};
}

// The fan ends whose branch a fan block carries (sorted input ids): on the cap (design note C1) where accepted; on the
// side section or in a notch (CompatibleBlockOptions::fan_side_branches) only where the fan-end repair alone refuses
// a fan end they carry for the moved root's border budget, the branch's tube clear of the plates
// (FanEndRefusal::thick_root; a trial repair on a copy: every fan end the repair takes keeps the repair, every other
// refusal stays).
std::vector<int> block_carried_ends(const Skeleton& s, const SkeletonAnalysis& an, const PipelineOptions& options) {
    const CompatibleBlockOptions& blocks = options.connection_surfaces.blocks;
    CompatibleBlockOptions caps_only = blocks;
    caps_only.fan_side_branches = false;
    std::vector<int> caps = fan_cap_roots(find_fan_blocks(s, an, caps_only));
    if (!blocks.fan_side_branches || !options.repair.fan_end_retraction || options.analysis.fan_end_branches)
        return caps;
    std::vector<int> sides = fan_cap_roots(find_fan_blocks(s, an, blocks));
    if (sides == caps) return caps;
    const SkeletonRepairResult repaired = repair_skeleton(s, options.repair, &blocks, caps);
    std::vector<int> repaired_caps;
    for (const int v : caps)
        if (repaired.vertex_map[v] >= 0) repaired_caps.push_back(repaired.vertex_map[v]);
    std::sort(repaired_caps.begin(), repaired_caps.end());
    const std::optional<FanEndRefusalAt> left = first_fan_end_refusal(repaired.skeleton, repaired_caps);
    if (!left || !left->why.thick_root) return caps;
    const auto [vertex, is_input] = named_vertex(repaired.vertex_map, left->vertex);
    return is_input && std::ranges::binary_search(sides, vertex) ? sides : caps;
}

// Trims the branch tips `held` says the domain does not hold from `s` (numbered as the input; trim_unheld_tips) and
// records them in `res`. Returns the map input vertex -> trimmed id (-1: trimmed), or empty when nothing was trimmed.
std::vector<int> trim_tips(Skeleton& s, const std::vector<char>& held, PipelineResult& res) {
    if (held.size() != s.points.size())
        throw Error(ErrorCode::InvalidInput, "held: " + std::to_string(held.size()) + " entries for " +
                                                 std::to_string(s.points.size()) + " skeleton vertices");
    TipTrim trim = trim_unheld_tips(s, held);
    if (trim.trimmed.empty()) return {};
    res.trimmed_tips = std::move(trim.trimmed);
    res.trimmed_tip_ends = std::move(trim.new_ends);
    s = std::move(trim.skeleton);
    return std::move(trim.vertex_map);
}

// `second` after `first` (first[v] < 0 stays < 0): the repair's map composed with the trim's, input -> repaired.
std::vector<int> compose(const std::vector<int>& first, const std::vector<int>& second) {
    std::vector<int> out(first.size(), -1);
    for (std::size_t v = 0; v < first.size(); ++v)
        if (first[v] >= 0) out[v] = second[static_cast<std::size_t>(first[v])];
    return out;
}

// The refusal of a root the fan-end repair moved (or a corner it retracted) with `inverted` raw hexes in reach.
std::string moved_root_refusal(const MovedRootPlace& root, long inverted) {
    std::ostringstream why;
    why << (root.by_input ? "skeleton vertex " : "repaired skeleton vertex ") << root.vertex
        << ": a branch on a fan-edge end" << (root.far ? " far from the fan line" : "")
        << ", its root moved onto a leaflet border (or the fan edge retracted from it) by the fan-end repair "
           "(issue 22), gives "
        << inverted << " inverted raw hex(es) within " << kMovedRootCheckRadii << " radii of the moved root (radius "
        << root.radius
        << "; such roots between two leaflets or near a leaflet's plane fold the branch's first chunk); edit: "
           "turn the branch into one leaflet's plane or along the fan line, or root it on the leaflet's border "
           "yourself (a vertex on the border side next to the fan edge), or change its radius there";
    return why.str();
}

// The refusal of a fan end whose branch stands on its fan block's side section or in its notch, with `inverted` raw
// hexes in reach. The first chunk folds when its first section lies inside the block (a side section: closer to the
// fan end than the block's side, h = half the section) or less than r past a notch's corner M_j (sqrt 2 r off the fan
// end): hence the edit's r (above h wherever the repair refuses the moved root) and (1 + sqrt 2) r (docs/blocks.md,
// "Thick moved roots on the fan block's side section").
std::string fan_side_refusal(const MovedRootPlace& root, long inverted) {
    const bool notch = root.kind == RootPlaceKind::Notch;
    std::ostringstream why;
    why << (root.by_input ? "skeleton vertex " : "repaired skeleton vertex ") << root.vertex
        << ": a thick branch on a fan-edge end standing "
        << (notch ? "in the fan block's notch between two leaflets"
                  : "on the fan block's side section (a T's empty side)")
        << " (CompatibleBlockOptions::fan_side_branches, issue 22) gives " << inverted
        << " inverted raw hex(es) within " << kMovedRootCheckRadii << " radii of the fan end (radius " << root.radius
        << (notch ? "; the branch's first chunk folds against the two leaflets' plates when its first joint lies less "
                    "than r past the notch's corner"
                  : "; the branch's first chunk folds into the block when its first joint lies inside the block's side")
        << "); edit: move the branch's first joint at least " << (notch ? "(1 + sqrt 2) r = " : "r = ")
        << (notch ? 1 + std::numbers::sqrt2 : 1.0) * root.radius
        << " from the fan end (or mesh with the resampling, which places it), or mesh with --no-fan-side-branches "
           "(the fan-end repair then moves the root, or refuses it naming its bound)";
    return why.str();
}

}  // namespace

void check_moved_roots(const PipelineResult& res) {
    if (res.moved_roots.empty()) return;
    const HexMesh& mesh = res.raw.mesh;
    // Each inverted hex counts for the root nearest to its centroid among those within reach (a single fan edge with
    // roots at both ends has both within reach of the same hexes): the refusal names the root where the hexes fold.
    std::vector<long> count(res.moved_roots.size(), 0);
    for (const std::array<int, 8>& h : mesh.hexes) {
        std::array<Vec3, 8> p;
        Vec3 centroid{};
        for (std::size_t k = 0; k < 8; ++k) {
            p[k] = mesh.points[static_cast<std::size_t>(h[k])];
            centroid = centroid + p[k] / 8.0;
        }
        std::size_t nearest = res.moved_roots.size();
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < res.moved_roots.size(); ++i) {
            const MovedRootPlace& root = res.moved_roots[i];
            const double d = distance(centroid, root.point);
            if (d <= kMovedRootCheckRadii * root.radius && d < best) nearest = i, best = d;
        }
        if (nearest < res.moved_roots.size() && hex_scaled_jacobian(p) <= 0) ++count[nearest];
    }
    for (std::size_t i = 0; i < res.moved_roots.size(); ++i) {
        const MovedRootPlace& root = res.moved_roots[i];
        if (count[i] == 0) continue;
        const std::string why = root.kind == RootPlaceKind::Repaired ? moved_root_refusal(root, count[i])
                                                                     : fan_side_refusal(root, count[i]);
        throw Error(ErrorCode::UnsupportedConfiguration, why,
                    ElementRef{ElementRef::Kind::SkeletonVertex, root.vertex});
    }
}

void add_fan_side_roots(PipelineResult& res, const FanBlocks& blocks, const Skeleton& input, bool resampled) {
    for (const FanBlockChain& chain : blocks.chains)
        for (std::size_t end = 0; end < 2; ++end) {
            if (chain.closed || (chain.side_axis[end] < 0 && chain.notch[end] < 0)) continue;
            const int w = end == 0 ? chain.vertices.front() : chain.vertices.back();
            const Vec3 p = res.skeleton.points[static_cast<std::size_t>(w)];
            MovedRootPlace root{w,    !resampled,
                                p,    res.skeleton.radii[static_cast<std::size_t>(w)],
                                true, chain.notch[end] >= 0 ? RootPlaceKind::Notch : RootPlaceKind::SideSection};
            if (resampled)  // named by the input vertex at w's place (the repair and the resampling keep fan ends)
                for (const int v : res.fan_cap_branches)
                    if (distance(input.points[static_cast<std::size_t>(v)], p) < 1e-9)
                        root.vertex = v, root.by_input = true;
            res.moved_roots.push_back(root);
        }
}

namespace {

// Whether the faces at leaflet vertex w fold: two of their normals more than kCreaseNormalGainDeg apart (the angle
// leaflet_vertex_frames takes for a crease).
bool creased_at(const SkeletonAnalysis& an, int w) {
    std::vector<Vec3> normals;
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int x : an.face_vertices[f])
            if (x == w && face_counts_at(an, f, w) && norm(an.face_normal[f]) > 0)
                normals.push_back(normalized(an.face_normal[f]));
    const double lim = std::cos(kCreaseNormalGainDeg * std::numbers::pi / 180);
    for (std::size_t i = 0; i < normals.size(); ++i)
        for (std::size_t j = i + 1; j < normals.size(); ++j)
            if (dot(normals[i], normals[j]) < lim) return true;
    return false;
}

}  // namespace

void check_border_creases(const PipelineResult& res) {
    const SkeletonAnalysis& an = res.analysis;
    const RawMesh& raw = res.raw;
    if (an.face_vertices.empty()) return;
    std::vector<int> owner;
    for (std::size_t h = 0; h < raw.mesh.hexes.size(); ++h) {
        const int e = raw.hex_edge[h];
        if (e < 0 || an.edge_degree[e] != 1) continue;  // the half-chunks of leaflet border edges only
        const std::array<int, 8>& hex = raw.mesh.hexes[h];
        std::array<Vec3, 8> p;
        for (std::size_t k = 0; k < 8; ++k) p[k] = raw.mesh.points[static_cast<std::size_t>(hex[k])];
        if (hex_scaled_jacobian(p) > 0) continue;
        if (owner.empty()) owner = raw_vertex_owner(raw);
        for (int lv = 0; lv < 8; ++lv) {
            const int w = owner[static_cast<std::size_t>(hex[static_cast<std::size_t>(lv)])];
            const std::array<int, 2>& ed = res.skeleton.edges[e];
            if (hex_corner_value(p, static_cast<std::size_t>(lv)) > 0 || (w != ed[0] && w != ed[1])) continue;
            const VertexClass c = an.vertex_class[w];
            if ((c != VertexClass::LeafletBoundary && c != VertexClass::FanEdgeEnd) || !creased_at(an, w)) continue;
            const int x = ed[0] == w ? ed[1] : ed[0];
            const double L = distance(res.skeleton.points[w], res.skeleton.points[x]);
            const double r = res.skeleton.radii[w];
            // Only the fold this check explains (the out column's plane past the neighbour's out-up copy, r > L / 2);
            // an inverted hex at a creased border vertex below the bound has another cause and is counted, not refused.
            if (!(r > 0.5 * L)) continue;
            const bool input = w < static_cast<int>(res.input_analysis.vertex_class.size());
            std::ostringstream why;
            why << (input ? "skeleton vertex " : "repaired skeleton vertex ") << w
                << ": a leaflet border that creases there and runs on (a wall standing on part of a plate's border, "
                   "at the wall's end) folds the half-chunk of border edge ("
                << w << ", " << x << ") at its out column: an inverted raw hex, radius " << r
                << " above the bound L / 2 = " << 0.5 * L << " (L = " << L
                << " the border edge; exact for a wall at right angles to the plate, where the plane of the out "
                   "column at the crease reaches the neighbour's out-up copy at r = L / 2); edit: lower the radius "
                   "there below L / 2, end the wall at the plate's corner or run it over the whole border side, or "
                   "mesh with the domain surface (the fit untangles the half-chunk)";
            throw Error(ErrorCode::UnsupportedConfiguration, why.str(),
                        ElementRef{ElementRef::Kind::SkeletonVertex, w});
        }
    }
}

double default_radius(const Skeleton& s, double factor) {
    double total = 0;
    for (const std::array<int, 2>& e : s.edges) total += distance(s.points[e[0]], s.points[e[1]]);
    return s.edges.empty() || !(total > 0) ? 1.0 : factor * total / static_cast<double>(s.edges.size());
}

PipelineResult prepare_skeleton(const Skeleton& input, const PipelineOptions& options, const std::vector<char>* held) {
    PipelineResult res;
    StageClock clock(res.timings_ms);

    // Validates indices and geometry before anything else (the default radius reads edge lengths).
    // A branch on a fan-edge end is accepted here when the repair below retracts the fan edge from it (the analysis
    // after the repair refuses what is left).
    // A branch standing on a fan block's cap (CompatibleBlockOptions::fan_cap_branches) is accepted by both analyses;
    // the connection surfaces refuse one that no accepted chain's cap carries.
    const CompatibleBlockOptions& blocks = options.connection_surfaces.blocks;
    const bool fan_caps_on = blocks.enabled && blocks.fan_blocks && blocks.fan_cap_branches;
    AnalysisOptions meshed_options = options.analysis;
    meshed_options.fan_cap_branches = meshed_options.fan_cap_branches || fan_caps_on;
    AnalysisOptions input_options = meshed_options;
    input_options.fan_end_branches = options.resample && options.repair.fan_end_retraction;
    input_options.docked_band_pillow = options.resample && options.repair.docked_band_pillow;
    meshed_options.docked_band_pillow_ran = input_options.docked_band_pillow;
    res.input_analysis = analyze_skeleton(input, input_options);
    clock.lap("analysis_input");
    if (input.edges.empty() && input.faces.empty())
        throw Error(ErrorCode::InvalidInput, "the skeleton has no edge and no face: nothing to mesh");

    Skeleton s = input;
    if (!s.radii.empty()) {
        res.radius_source = "file";
    } else {
        res.radius_source = options.radius > 0 ? "option" : "default";
        res.radius = options.radius > 0 ? options.radius : default_radius(s, options.default_radius_factor);
        s.radii.assign(s.points.size(), res.radius);
    }
    check_radii(s);

    const bool docked_work = (options.repair.docked_foot_split > 0 && res.input_analysis.counts.docked_edges > 0) ||
                             !res.input_analysis.docked_unmatched.empty();
    if (options.resample && !curve_work(input, res.input_analysis) && !docked_work) {
        // Repairs and adaptation change curve branches only (skeleton_repair.h, adaptation.h: leaflet vertices, edges
        // and faces are kept, in their order): without a branch edge (and a repeated edge, which the adaptation would
        // drop) the skeleton is its own repaired and adapted form. Checked against the two calls in test_incremental.
        clock.lap("adaptation");
    } else if (options.resample) {
        // Fan ends whose branch the fan block's cap carries (design note C1) are left to it, not retracted.
        const std::vector<int> fan_caps =
            fan_caps_on ? block_carried_ends(s, res.input_analysis, options) : std::vector<int>{};
        // Tips the domain does not hold go first; their vertices are on branches only, so every fan cap stays.
        const std::vector<int> to_trimmed = held ? trim_tips(s, *held, res) : std::vector<int>{};
        std::vector<int> trimmed_caps = fan_caps;
        if (!to_trimmed.empty())
            for (int& v : trimmed_caps) v = to_trimmed[static_cast<std::size_t>(v)];
        SkeletonRepairResult repaired = repair_skeleton(s, options.repair, &blocks, trimmed_caps);
        if (!to_trimmed.empty()) repaired.vertex_map = compose(to_trimmed, repaired.vertex_map);  // named by input ids
        res.fan_cap_branches = fan_caps;
        clock.lap("skeleton_repair");
        std::vector<int> repaired_caps;  // the same vertices in the repaired numbering
        for (const int v : fan_caps)
            if (repaired.vertex_map[v] >= 0) repaired_caps.push_back(repaired.vertex_map[v]);
        std::sort(repaired_caps.begin(), repaired_caps.end());
        // A branch on a fan-edge end that the repair left (the analysis refuses it after the resampling): named here,
        // with the reason measured on the sampling the repair judged (fan_end_repair.h, first_fan_end_refusal).
        // The vertex is named by its input id (the repair renumbers when it drops trunk joints); a vertex the repair
        // made is named in the repaired numbering.
        if (options.repair.fan_end_retraction && !options.analysis.fan_end_branches)
            if (const std::optional<FanEndRefusalAt> left = first_fan_end_refusal(repaired.skeleton, repaired_caps)) {
                const auto [vertex, is_input] = named_vertex(repaired.vertex_map, left->vertex);
                throw Error(ErrorCode::UnsupportedConfiguration,
                            (is_input ? "skeleton vertex " : "repaired skeleton vertex ") + std::to_string(vertex) +
                                ": a branch on a fan-edge end (the end of a fan edge shared by " +
                                std::to_string(left->fan_degree) +
                                " faces; the paper's limitation 3) that the fan-end repair does not take: " +
                                left->why.reason + "; edit: " + left->why.edit,
                            ElementRef{ElementRef::Kind::SkeletonVertex, vertex});
            }
        res.trunks = repaired.trunks;
        res.absorbed_stubs = repaired.absorbed_stubs;
        res.side_stubs = repaired.side_stubs;
        res.main_stubs = repaired.main_stubs;
        res.merged_ends = repaired.merged_ends;
        res.unseparated_pairs = repaired.unseparated;
        res.root_strip_splits = repaired.root_strip_splits;
        res.docked_foot_splits = repaired.docked_foot_splits;
        res.docked_band_pillows = repaired.docked_band_pillows;
        res.junction_splits = repaired.junction_splits;
        for (const FanEndRetraction& r : repaired.fan_end_retractions) {
            // Named by input id (the tip trim and the repair renumber); a vertex the repair made by its repaired id.
            const auto [vertex, is_input] = named_vertex(repaired.vertex_map, r.vertex);
            res.fan_end_retractions.push_back(vertex);
            res.fan_edge_splits += r.fan_edge_split >= 0 ? 1 : 0;
            if (r.moved_root >= 0) res.fan_end_moved_roots.push_back(vertex);
            if (r.moved_root < 0 && r.far_branch) res.fan_end_far_retractions.push_back(vertex);
            // Every retracted corner is checked too, with RawMeshOptions::fan_end_cap_to_border off as well (off,
            // main's raw meshes have no inverted hex there: docs/blocks.md, "The notch closed by the cap"); with it on,
            // u's cap reaches up to that corner.
            const int root = r.moved_root >= 0 ? r.moved_root : r.vertex;  // a retraction: its corner w
            res.moved_roots.push_back({vertex, is_input, repaired.skeleton.points[root],
                                       repaired.skeleton.radii[r.vertex], r.moved_root >= 0 || r.far_branch});
        }
        std::vector<int> pinned;
        if (options.repair.pin_absorbed_balls) pinned = repaired.absorbed_balls;
        if (options.repair.pin_trunk_joints)
            pinned.insert(pinned.end(), repaired.trunk_joints.begin(), repaired.trunk_joints.end());
        pinned.insert(pinned.end(), repaired.fan_end_pins.begin(), repaired.fan_end_pins.end());
        AdaptationOptions adaptation = options.adaptation;
        adaptation.raised_fan_end_caps = options.raw_mesh.fan_end_cap_to_border;
        s = adapt_skeleton(repaired.skeleton, adaptation, pinned, repaired.junction_degree);
        clock.lap("adaptation");
    }
    // After adaptation, which would collapse their short edges; new vertices and edges are appended.
    res.virtual_branches = static_cast<int>(
        add_virtual_branches(s, options.virtual_branches, &options.connection_surfaces.blocks, &input).at.size());
    if (res.virtual_branches == 0 && options.resample && !input.radii.empty() && s == input &&
        same_analysis(res.input_analysis, input_options, meshed_options)) {
        // Nothing repaired or resampled (e.g. no curve branch): the analysis of the skeleton meshed is the input's.
        res.analysis = res.input_analysis;
        clock.lap("analysis");
    } else if (options.resample || res.virtual_branches > 0) {
        res.analysis = analyze_skeleton(s, meshed_options);
        clock.lap("analysis");
    } else {
        res.analysis = res.input_analysis;
    }
    res.skeleton = std::move(s);
    return res;
}

PipelineResult run_pipeline(const Skeleton& input, const PipelineOptions& options, const std::vector<char>* held) {
    PipelineResult res = prepare_skeleton(input, options, held);
    StageClock clock(res.timings_ms);
    const ConnectionSurfaces cs = build_connection_surfaces(res.skeleton, res.analysis, options.connection_surfaces);
    res.predicted = predict_raw_mesh(res.skeleton, res.analysis, cs);
    res.predicted.virtual_branches = res.virtual_branches;  // their 4 hexes each are branch chunks, in hexes
    clock.lap("connection_surfaces");
    const BranchFrames frames = propagate_frames(res.skeleton, res.analysis, cs);
    clock.lap("frames");
    res.raw = build_raw_mesh(res.skeleton, res.analysis, cs, frames, options.raw_mesh, &input);
    clock.lap("raw_mesh");
    add_fan_side_roots(res, cs.fan_blocks, input, options.resample);
    return res;
}

std::string trimmed_tips_to_text(const PipelineResult& res) {
    if (res.trimmed_tips.empty()) return "";
    std::ostringstream out;
    out << "repairs: branch tips outside the domain trimmed: input vertices";
    for (const int v : res.trimmed_tips) out << " " << v;
    out << " removed; the branch now ends at input vertices";
    for (const int v : res.trimmed_tip_ends) out << " " << v;
    out << "\n";
    return out.str();
}

std::string repairs_to_text(const PipelineResult& res, const PipelineOptions& options) {
    if (!options.resample) return "repairs: not run (no resampling)\n";
    std::ostringstream out;
    const auto line = [&out](const char* what, long n) {
        if (n > 0) out << "repairs: " << what << ": " << n << "\n";
    };
    line("trunks for close branch pairs", res.trunks);
    line("absorbed stubs", res.absorbed_stubs);
    line("stubs kept as side branches", res.side_stubs);
    line("fat stubs kept as the main line", res.main_stubs);
    line("merged branching ends", res.merged_ends);
    line("close pairs left unseparated", res.unseparated_pairs);
    line("leaflet strips split around rooted branches", res.root_strip_splits);
    line("plate strips split beside and beyond docked walls' chains", res.docked_foot_splits);
    line("docked walls' chains whose plate band was pillowed", res.docked_band_pillows);
    line("degree-4 branching points split in two", res.junction_splits);
    out << trimmed_tips_to_text(res);
    // "repairs: <what> v0 v1 ..." when vs is not empty.
    const auto vertices = [&out](const char* what, const std::vector<int>& vs) {
        if (vs.empty()) return;
        out << "repairs: " << what;
        for (const int v : vs) out << " " << v;
        out << "\n";
    };
    vertices("fan edges retracted from branches on fan-edge ends: at input vertices", res.fan_end_retractions);
    vertices("of these, branches far from the fan line moved onto a leaflet border at input vertices:",
             res.fan_end_moved_roots);
    vertices(
        "of these, branches far from the fan line (their moved root refused) retracted with the fan edge, a notch "
        "at the leaflets' corner, at input vertices:",
        res.fan_end_far_retractions);
    line(
        "fan-edge chains split (with their leaflets' face strips) to be retracted: single fan edges in two, chains "
        "of 1 or 2 fan edges with branches at both ends into 3 or 4, the row under a branch moved off the fan end",
        res.fan_edge_splits);
    std::string text = out.str();
    if (text.empty()) text = "repairs: none\n";
    if (!res.fan_cap_branches.empty()) {  // not a repair: the skeleton is meshed as given there
        std::ostringstream caps;
        caps << "branches standing on fan blocks' caps (not retracted): at input vertices";
        for (const int v : res.fan_cap_branches) caps << " " << v;
        text += caps.str() + "\n";
    }
    return text;
}

}  // namespace mesohex
