// The skeleton -> raw mesh pipeline gives the same bits for any thread count (STYLE.md rule 8): meshes built with
// 1 and 2 threads (tbb::global_control) are compared byte for byte, on a random tree (many branching points of
// degree 3-6, so the connection surfaces are split over tasks) and on generated shapes with leaflets.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include <tbb/global_control.h>

#include "bench_inputs.h"
#include "mesohex/pipeline.h"
#include "mesohex/stages/generators.h"

using namespace mesohex;

namespace {

PipelineResult run_with_threads(const Skeleton& s, int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    return run_pipeline(s);
}

// Byte-for-byte equality of everything the raw stage outputs (points compared as bits, not as doubles).
void expect_same_bits(const PipelineResult& a, const PipelineResult& b) {
    ASSERT_EQ(a.skeleton, b.skeleton);
    ASSERT_EQ(a.raw.mesh.points.size(), b.raw.mesh.points.size());
    ASSERT_EQ(a.raw.mesh.hexes, b.raw.mesh.hexes);
    EXPECT_EQ(0, std::memcmp(a.raw.mesh.points.data(), b.raw.mesh.points.data(),
                             a.raw.mesh.points.size() * sizeof(Vec3)));
    EXPECT_EQ(a.raw.hex_edge, b.raw.hex_edge);
    EXPECT_EQ(a.raw.vertex_base, b.raw.vertex_base);
}

}  // namespace

TEST(ParallelDeterminism, RandomTreeOneVersusTwoThreads) {
    const Skeleton s = bench::random_tree(1500, 7);
    const PipelineResult one = run_with_threads(s, 1);
    const PipelineResult two = run_with_threads(s, 2);
    // The tree branches: at least a tenth of its vertices are branching points (degree >= 3), so the connection
    // surfaces are spread over several 256-vertex tasks.
    int branching = 0;
    for (VertexClass c : one.analysis.vertex_class) branching += c == VertexClass::BranchingPoint ? 1 : 0;
    EXPECT_GE(branching, 150);
    EXPECT_EQ(static_cast<long>(one.raw.mesh.hexes.size()), one.predicted.hexes);
    expect_same_bits(one, two);
}

TEST(ParallelDeterminism, GeneratedShapesOneVersusTwoThreads) {
    for (const char* name : {"hand", "dualocta", "turbine"}) {
        SCOPED_TRACE(name);
        const Skeleton s = generate_skeleton(name);
        expect_same_bits(run_with_threads(s, 1), run_with_threads(s, 2));
    }
}
