#pragma once
// The raw mesh of a small skeleton (its own sampling, no adaptation), checked against the analysis's prediction:
// shared by the block and docked-wall stage tests.
#include <gtest/gtest.h>

#include <map>

#include "mesohex/core/validate.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/raw_mesh.h"

namespace mesohex::test {

struct RawRun {
    SkeletonAnalysis analysis;
    RawMeshPrediction predicted;
    QualityReport quality;
    long fan_chains = 0;  // fan-block chains accepted by the connection surfaces
    bool valid = false;
};

// Builds the raw mesh of s with options o (analysis options a); hexes, vertices and irregular edges must equal the
// prediction.
inline RawRun checked_raw_mesh(const Skeleton& s, const ConnectionSurfaceOptions& o = {},
                               const AnalysisOptions& a = {}) {
    RawRun r;
    r.analysis = analyze_skeleton(s, a);
    const ConnectionSurfaces cs = build_connection_surfaces(s, r.analysis, o);
    r.predicted = predict_raw_mesh(s, r.analysis, cs);
    r.fan_chains = static_cast<long>(cs.fan_blocks.chains.size());
    const RawMesh raw = build_raw_mesh(s, r.analysis, cs, propagate_frames(s, r.analysis, cs));
    r.quality = compute_quality(raw.mesh);
    r.valid = validate(raw.mesh).valid();
    EXPECT_EQ(r.quality.hexes, r.predicted.hexes);
    EXPECT_EQ(r.quality.vertices, r.predicted.vertices);
    EXPECT_EQ(r.quality.singular_interior_edges, r.predicted.interior_irregular_edges);
    EXPECT_EQ(r.quality.singular_boundary_edges, r.predicted.boundary_irregular_edges);
    return r;
}

// The number of irregular edges over all valences of a valence -> count map.
inline long total(const std::map<int, long>& m) {
    long n = 0;
    for (const auto& [valence, count] : m) n += count;
    return n;
}

}  // namespace mesohex::test
