#pragma once
// Incremental remeshing for the studio: after an edit that moves k skeleton vertices (or changes their
// radii) without changing the topology, only the connection surfaces within reach of those vertices are recomputed;
// the analysis (O(V + E + F), cheap), the frames and the raw mesh are rebuilt whole (the raw stage runs at > 10 M
// hex/s). The result is byte-identical to a full run on the new skeleton (tests/unit/test_incremental.cpp checks this
// on random edits).
//
// What is incremental: the skeleton that is meshed as given, without adaptation (PipelineOptions::resample = false;
// adaptation re-samples whole branches, so one moved vertex can change the topology of everything downstream). The
// studio remeshes its (already adapted, or hand-drawn) skeleton with this; a full `mesohex mesh` run still adapts.
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/stages/connection_surfaces.h"
#include "mesohex/stages/frame_propagation.h"
#include "mesohex/stages/raw_mesh.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

struct RemeshCache {
    Skeleton skeleton;  // the skeleton last meshed (one radius per vertex)
    SkeletonAnalysis analysis;
    ConnectionSurfaces surfaces;
    BranchFrames frames;
    RawMesh raw;
    AnalysisOptions analysis_options;
    ConnectionSurfaceOptions surface_options;
    RawMeshOptions raw_options;
    // Content-keyed memo of the branching-point surfaces of `skeleton` (connection_surfaces.h): consulted for every
    // surface that is not copied by index, so an edit that renumbers the skeleton (adaptation) still reuses the
    // partitions of the branching points whose branch directions kept their bits. Holds this skeleton's entries only.
    SurfaceMemo memo;
    bool memo_enabled = true;  // false: the memo is filled but never read (to measure what it saves)
};

struct RemeshStats {
    bool full = true;          // everything was recomputed (first call, other topology, or options changed)
    int changed_vertices = 0;  // vertices whose position or radius changed
    // Vertices whose connection surface was recomputed (all when full): those within three edges of a change; the
    // degree-3 points at bridges recomputed because a neighbour within two edges is (degree_three_chunks_at_bridges)
    // are not counted.
    int recomputed_surfaces = 0;
    int memo_surfaces = 0;        // of those, branching-point surfaces taken from the memo (bit-identical inputs)
    int computed_partitions = 0;  // memo-able branching-point surfaces that were computed (memo misses)
};

// Meshes `skeleton` (radii required: one per vertex, finite and > 0) from scratch (cache.memo is not read) and fills
// the cache.
// Errors: whatever analyze_skeleton and the stages throw, plus Error(InvalidInput) for missing or bad radii.
// `analysis` (may be null): analyze_skeleton(skeleton, cache.analysis_options) when the caller has it already.
RemeshStats remesh_full(RemeshCache& cache, const Skeleton& skeleton, const SkeletonAnalysis* analysis = nullptr);

// Brings the cache to `skeleton`: when it has the same edges, faces and number of vertices as cache.skeleton, the
// connection surfaces of the vertices within three edges of a changed vertex are recomputed and the others reused;
// otherwise (or when the vertex classes change) this is remesh_full. Either way the branching-point surfaces to
// compute are first looked up in cache.memo by content (their branch directions' bits), whatever their numbering.
// Afterwards cache.raw equals (bit for bit) what remesh_full(skeleton) gives. On error the cache is left unchanged.
// Cost: O(V + E + F) plus the recomputed surfaces. `analysis` (may be null): as for remesh_full.
RemeshStats remesh_incremental(RemeshCache& cache, const Skeleton& skeleton,
                               const SkeletonAnalysis* analysis = nullptr);

}  // namespace mesohex
