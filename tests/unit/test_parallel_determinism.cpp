// The skeleton -> raw mesh pipeline gives the same bits for any thread count (STYLE.md rule 8): meshes built with
// 1 and 2 threads (tbb::global_control) are compared byte for byte, on a random tree (many branching points of
// degree 3-6, so the connection surfaces are split over tasks) and on generated shapes with leaflets; sphere
// partitions computed concurrently are compared with serial ones.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "bench_inputs.h"
#include "mesohex/pipeline.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/sphere_partition.h"

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
    EXPECT_EQ(0,
              std::memcmp(a.raw.mesh.points.data(), b.raw.mesh.points.data(), a.raw.mesh.points.size() * sizeof(Vec3)));
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

// partition_sphere called concurrently (as build_connection_surfaces does, one branching point per task) gives the
// same bits as serial calls: no shared mutable state, the scan tables are initialised once and thread-safely.
TEST(ParallelDeterminism, ConcurrentSpherePartitionsGiveTheSameBits) {
    std::mt19937 rng(11);
    std::vector<std::vector<Vec3>> sets;
    for (int k = 0; k < 48; ++k) {
        std::vector<Vec3> d;
        for (int i = 0; i < 3 + k % 4; ++i) d.push_back(bench::random_direction(rng));
        sets.push_back(d);
    }
    std::vector<SpherePartition> serial, parallel(sets.size());
    for (const std::vector<Vec3>& d : sets) serial.push_back(partition_sphere(d));
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
        tbb::parallel_for(0, static_cast<int>(sets.size()), [&](int k) { parallel[k] = partition_sphere(sets[k]); });
    }
    for (std::size_t k = 0; k < sets.size(); ++k) {
        ASSERT_EQ(serial[k].quads, parallel[k].quads);
        ASSERT_EQ(serial[k].points.size(), parallel[k].points.size());
        EXPECT_EQ(
            0, std::memcmp(serial[k].points.data(), parallel[k].points.data(), serial[k].points.size() * sizeof(Vec3)))
            << "set " << k;
    }
}
