// Incremental remeshing (mesohex/incremental.h) against a full run on the same skeleton, no adaptation.
//   BM_RemeshMoveOneVertex   one vertex of a 2 600-vertex random tree (about 10 k raw hexes) moved back and forth,
//                            remesh_incremental per iteration; /M: M = 1 with the content-keyed memo of
//                            branching-point surfaces (RemeshCache::memo), 0 without (memo_enabled = false)
//   BM_RemeshFull            remesh_full of the same tree (the figure the incremental run is compared with)
// Counter "hexes" = raw hexes of the tree.
#include <benchmark/benchmark.h>

#include "bench_inputs.h"
#include "mesohex/incremental.h"

using namespace mesohex;

namespace {

const Skeleton& tree10k() {
    static const Skeleton s = bench::random_tree(2600, 5);
    return s;
}

void BM_RemeshMoveOneVertex(benchmark::State& state) {
    Skeleton s = tree10k();
    RemeshCache cache;
    cache.memo_enabled = state.range(0) != 0;
    remesh_full(cache, s);
    // A branching point in the middle of the id range (the worst kind: its partition is recomputed).
    int v = static_cast<int>(s.points.size()) / 2;
    while (cache.analysis.vertex_class[v] != VertexClass::BranchingPoint) ++v;
    const Vec3 home = s.points[v];
    long i = 0;
    for (auto _ : state) {
        s.points[v] = home + Vec3{0.02 * static_cast<double>(i++ % 2), 0.01, 0};
        const RemeshStats stats = remesh_incremental(cache, s);
        benchmark::DoNotOptimize(stats.recomputed_surfaces);
    }
    state.counters["hexes"] = static_cast<double>(cache.raw.mesh.hexes.size());
}

void BM_RemeshFull(benchmark::State& state) {
    RemeshCache cache;
    for (auto _ : state) benchmark::DoNotOptimize(remesh_full(cache, tree10k()).recomputed_surfaces);
    state.counters["hexes"] = static_cast<double>(cache.raw.mesh.hexes.size());
}

}  // namespace

BENCHMARK(BM_RemeshMoveOneVertex)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RemeshFull)->Unit(benchmark::kMillisecond);
