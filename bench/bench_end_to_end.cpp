// Skeleton -> raw mesh end to end (analysis, adaptation, analysis, connection surfaces, frames, raw stage; no file
// IO): run_pipeline with its defaults (resampling on). Counter "hex/s" = raw hexes per second.
//   BM_EndToEndRandomTree/<threads>  a 5 120-vertex random tree (branchy: about a quarter of its vertices branch,
//                                    degrees 3-6), about 20 k raw hexes
//   BM_EndToEndStar/<threads>        a 256-vertex three-branch star (one branching point, three bent chains)
//   BM_SkeletonRepairRandomTree      repair_skeleton alone on the 5 120-vertex tree (106 repairs, serial rounds)
// Threads are limited with tbb::global_control. The inputs are generated here (random_tree, three_branch_star).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <tbb/global_control.h>

#include "bench_inputs.h"
#include "mesohex/pipeline.h"
#include "mesohex/stages/skeleton_repair.h"

using namespace mesohex;

namespace {

void run_end_to_end(benchmark::State& state, const Skeleton& s) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
    long hexes = 0;
    for (auto _ : state) {
        PipelineResult res = run_pipeline(s);
        hexes += static_cast<long>(res.raw.mesh.hexes.size());
        benchmark::DoNotOptimize(res.raw.mesh.points.data());
    }
    state.counters["hex/s"] = benchmark::Counter(static_cast<double>(hexes), benchmark::Counter::kIsRate);
    state.counters["hexes"] = static_cast<double>(hexes) / static_cast<double>(state.iterations());
}

void BM_EndToEndRandomTree(benchmark::State& state) {
    static const Skeleton s = bench::random_tree(5120, 1);
    run_end_to_end(state, s);
}

void BM_EndToEndStar(benchmark::State& state) {
    static const Skeleton s = bench::three_branch_star(256);
    run_end_to_end(state, s);
}

void BM_SkeletonRepairRandomTree(benchmark::State& state) {
    static const Skeleton s = bench::random_tree(5120, 1);  // radii 0.5 (as run_pipeline takes them from the input)
    for (auto _ : state) {
        SkeletonRepairResult res = repair_skeleton(s, {});
        benchmark::DoNotOptimize(res.skeleton.points.data());
    }
}

}  // namespace

BENCHMARK(BM_SkeletonRepairRandomTree)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EndToEndRandomTree)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_EndToEndStar)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
