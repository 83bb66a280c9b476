// The whole raw-mesh pipeline on the real curve skeletons of ../shared/data (label shared_data), plus the radius
// rules on an in-memory skeleton.
#include <gtest/gtest.h>

#include <string>

#include "mesohex/core/validate.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/skeleton_io.h"

using namespace mesohex;

namespace {

void expect_exact_valid(const PipelineResult& res, const std::string& name) {
    SCOPED_TRACE(name);
    const QualityReport q = compute_quality(res.raw.mesh);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.euler_characteristic, euler_characteristic(res.skeleton) - res.analysis.counts.isolated);
    // 4 per branch edge, 8 per compatible block (docs/blocks.md; bigbuddy.skel has one when resampled)
    EXPECT_EQ(q.hexes, 4 * static_cast<long>(res.skeleton.edges.size()) + 8 * res.predicted.compatible_blocks);
    EXPECT_EQ(q.hexes, res.predicted.hexes);
    EXPECT_EQ(q.vertices, res.predicted.vertices);
    EXPECT_EQ(q.singular_interior_edges, res.predicted.interior_irregular_edges);
    EXPECT_EQ(q.singular_boundary_edges, res.predicted.boundary_irregular_edges);
    for (const Vec3& p : res.raw.mesh.points) ASSERT_TRUE(is_finite(p));
}

}  // namespace

TEST(PipelineData, RealCurveSkeletons) {
    for (const char* name : {"aorta.skel", "aorta.cg", "armadillo.skel", "bigbuddy.skel", "block.skel", "cactus.skel",
                             "dino.skel", "dinopet.skel", "knight.skel"}) {
        const Skeleton s = read_skeleton(std::string(MESOHEX_SHARED_DATA_DIR) + "/curve-skeletons/" + name);
        PipelineOptions raw_sampling;
        raw_sampling.resample = false;
        const PipelineResult input = run_pipeline(s, raw_sampling);
        expect_exact_valid(input, std::string(name) + " --no-resample");
        EXPECT_EQ(input.raw.mesh.hexes.size(), 4 * s.edges.size() + 8 * input.predicted.compatible_blocks);

        const PipelineResult res = run_pipeline(s);  // resampling on: no inverted hex on the real skeletons
        expect_exact_valid(res, name);
        const QualityReport q = compute_quality(res.raw.mesh);
        EXPECT_EQ(q.inverted, 0) << name;
        EXPECT_GT(q.sj_min, 0.0) << name;
        EXPECT_EQ(res.radius_source, "file");
    }
}

TEST(Pipeline, RadiusRules) {
    Skeleton s;
    s.points = {{0, 0, 0}, {2, 0, 0}, {2, 4, 0}};
    s.edges = {{0, 1}, {1, 2}};
    PipelineOptions o;
    o.resample = false;
    const PipelineResult def = run_pipeline(s, o);
    EXPECT_EQ(def.radius_source, "default");
    EXPECT_DOUBLE_EQ(def.radius, 0.25 * 3.0);  // 0.25 x mean edge length (2 and 4)
    o.radius = 0.4;
    const PipelineResult opt = run_pipeline(s, o);
    EXPECT_EQ(opt.radius_source, "option");
    EXPECT_DOUBLE_EQ(opt.radius, 0.4);
    EXPECT_NEAR(distance(opt.raw.mesh.points[1], s.points[0]), 0.4, 1e-12);
    expect_exact_valid(opt, "polyline");
}
