// Sphere-partition benchmarks (connection surface at a branching point).
//   BM_PartitionSphereRandom/<n>  partition_sphere on 16 fixed pseudo-random direction sets of n directions
//                                 (time per call = reported time / 16)
//   BM_PartitionSpherePlanar/<n>  n directions on a great circle (the orange, no hull)
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "mesohex/stages/sphere_partition.h"

namespace {

std::vector<std::vector<mesohex::Vec3>> random_sets(int n, int count) {
    std::mt19937 rng(12345u + static_cast<unsigned>(n));
    std::uniform_real_distribution<double> uni(-1, 1);
    std::vector<std::vector<mesohex::Vec3>> sets(count);
    for (std::vector<mesohex::Vec3>& d : sets)
        while (static_cast<int>(d.size()) < n) {
            const mesohex::Vec3 v{uni(rng), uni(rng), uni(rng)};
            const double r = mesohex::norm(v);
            if (r > 0.1 && r <= 1) d.push_back(v / r);
        }
    return sets;
}

void BM_PartitionSphereRandom(benchmark::State& state) {
    const std::vector<std::vector<mesohex::Vec3>> sets = random_sets(static_cast<int>(state.range(0)), 16);
    for (auto _ : state)
        for (const std::vector<mesohex::Vec3>& d : sets) benchmark::DoNotOptimize(mesohex::partition_sphere(d));
    state.counters["calls/s"] =
        benchmark::Counter(16.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PartitionSphereRandom)->DenseRange(3, 8)->Arg(12)->Arg(16)->Unit(benchmark::kMillisecond);

void BM_PartitionSpherePlanar(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    std::vector<mesohex::Vec3> d;
    for (int i = 0; i < n; ++i) {
        const double a = 6.283185307179586 * i / n;
        d.push_back({std::cos(a), std::sin(a), 0});
    }
    for (auto _ : state) benchmark::DoNotOptimize(mesohex::partition_sphere(d));
}
BENCHMARK(BM_PartitionSpherePlanar)->Arg(3)->Arg(8)->Unit(benchmark::kMicrosecond);

}  // namespace
