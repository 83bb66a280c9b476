#include "mesohex/incremental.h"

#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "mesohex/core/error.h"
#include "mesohex/core/skeleton_radii.h"

namespace mesohex {

namespace {

// A connection surface reads its vertex's neighbours (directions, radii), the leaflet faces at the vertex and the
// leaflet frames of its neighbours (normals of their faces): everything within three edges.
constexpr int kReach = 3;

// One radius per vertex, each finite and > 0 (the pipeline fills missing radii; incremental remeshing does not).
void check_all_radii(const Skeleton& s) {
    if (s.radii.size() != s.points.size())
        throw Error(ErrorCode::InvalidInput, "incremental remeshing needs one radius per skeleton vertex (" +
                                                 std::to_string(s.radii.size()) + " radii for " +
                                                 std::to_string(s.points.size()) + " vertices)");
    check_radii(s);
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

// read_memo: look the surfaces to compute up in cache.memo first (not in remesh_full, which computes everything).
RemeshStats rebuild(RemeshCache& cache, const Skeleton& skeleton, SkeletonAnalysis analysis,
                    const std::vector<char>* recompute, bool read_memo) {
    RemeshStats stats;
    SurfaceMemo memo;
    const SurfaceMemo* memo_in = read_memo && cache.memo_enabled ? &cache.memo : nullptr;
    ConnectionSurfaces cs =
        recompute ? rebuild_connection_surfaces(skeleton, analysis, &cache.surfaces, *recompute, cache.surface_options,
                                                memo_in, &memo)
                  : rebuild_connection_surfaces(skeleton, analysis, nullptr, {}, cache.surface_options, memo_in, &memo);
    BranchFrames frames = propagate_frames(skeleton, analysis, cs);
    RawMesh raw = build_raw_mesh(skeleton, analysis, cs, frames, cache.raw_options);
    // Everything built: commit (the cache stays unchanged if anything above threw).
    cache.skeleton = skeleton;
    cache.analysis = std::move(analysis);
    cache.surfaces = std::move(cs);
    cache.frames = std::move(frames);
    cache.raw = std::move(raw);
    stats.full = recompute == nullptr;
    stats.memo_surfaces = memo.hits;
    stats.computed_partitions = memo.misses;
    cache.memo = std::move(memo);
    return stats;
}

// Every surface rebuilt (none copied by index); read_memo: as for rebuild.
RemeshStats full_run(RemeshCache& cache, const Skeleton& skeleton, const SkeletonAnalysis* given, bool read_memo) {
    check_all_radii(skeleton);
    SkeletonAnalysis analysis = given ? *given : analyze_skeleton(skeleton, cache.analysis_options);
    RemeshStats stats = rebuild(cache, skeleton, std::move(analysis), nullptr, read_memo);
    stats.changed_vertices = static_cast<int>(skeleton.points.size());
    stats.recomputed_surfaces = static_cast<int>(skeleton.points.size());
    return stats;
}

}  // namespace

RemeshStats remesh_full(RemeshCache& cache, const Skeleton& skeleton, const SkeletonAnalysis* given) {
    return full_run(cache, skeleton, given, false);
}

RemeshStats remesh_incremental(RemeshCache& cache, const Skeleton& skeleton, const SkeletonAnalysis* given) {
    const Skeleton& old = cache.skeleton;
    const int nv = static_cast<int>(skeleton.points.size());
    if (static_cast<int>(old.points.size()) != nv || old.edges != skeleton.edges || old.faces != skeleton.faces ||
        old.radii.size() != old.points.size() || cache.analysis.vertex_class.size() != old.points.size())
        return full_run(cache, skeleton, given, true);
    check_all_radii(skeleton);
    SkeletonAnalysis analysis = given ? *given : analyze_skeleton(skeleton, cache.analysis_options);
    if (analysis.vertex_class != cache.analysis.vertex_class ||
        analysis.vertex_border_root != cache.analysis.vertex_border_root)
        return full_run(cache, skeleton, &analysis, true);

    // Changed vertices, then everything within kReach edges of them (breadth-first over the incidence lists).
    std::vector<int> dist(nv, -1), frontier;
    int changed = 0;
    for (int v = 0; v < nv; ++v)
        if (!same_bits(old.points[v], skeleton.points[v]) ||
            std::memcmp(&old.radii[v], &skeleton.radii[v], sizeof(double)) != 0) {
            dist[v] = 0;
            frontier.push_back(v);
            ++changed;
        }
    for (std::size_t i = 0; i < frontier.size(); ++i) {
        const int v = frontier[i];
        if (dist[v] == kReach) continue;
        for (int j = analysis.vertex_edge_begin[v]; j < analysis.vertex_edge_begin[v + 1]; ++j) {
            const std::array<int, 2>& e = skeleton.edges[analysis.vertex_edges[j]];
            const int w = e[0] == v ? e[1] : e[0];
            if (dist[w] < 0) {
                dist[w] = dist[v] + 1;
                frontier.push_back(w);
            }
        }
    }
    std::vector<char> recompute(nv, 0);
    for (int v : frontier) recompute[v] = 1;
    RemeshStats stats = rebuild(cache, skeleton, std::move(analysis), &recompute, true);
    stats.changed_vertices = changed;
    stats.recomputed_surfaces = static_cast<int>(frontier.size());
    return stats;
}

}  // namespace mesohex
