// Foundation benchmarks on an n x n x n block of unit cubes (n^3 hexes):
//   BM_HexTopology/<n>    compute_hex_topology (target: about 1 s for 10^6 hexes, n = 100)
//   BM_ScaledJacobians/<n> scaled_jacobians (parallel)
//   BM_ComputeQuality/<n>  the whole quality report (validation + topology + statistics)
//   BM_WriteReadMedit/<n>  write + read a .mesh file in the temporary directory
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "mesohex/core/topology.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/hex_io.h"

namespace {

mesohex::HexMesh block(int n) {
    mesohex::HexMesh m;
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) m.points.push_back({double(i), double(j), double(k)});
    auto vid = [&](int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); };
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                m.hexes.push_back({vid(i, j, k), vid(i + 1, j, k), vid(i + 1, j + 1, k), vid(i, j + 1, k),
                                   vid(i, j, k + 1), vid(i + 1, j, k + 1), vid(i + 1, j + 1, k + 1),
                                   vid(i, j + 1, k + 1)});
    return m;
}

void BM_HexTopology(benchmark::State& state) {
    const mesohex::HexMesh m = block(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(mesohex::compute_hex_topology(m));
    state.SetItemsProcessed(static_cast<long>(state.iterations()) * static_cast<long>(m.hexes.size()));
}
BENCHMARK(BM_HexTopology)->Arg(20)->Arg(100)->Unit(benchmark::kMillisecond);

void BM_ScaledJacobians(benchmark::State& state) {
    const mesohex::HexMesh m = block(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(mesohex::scaled_jacobians(m));
}
BENCHMARK(BM_ScaledJacobians)->Arg(100)->Unit(benchmark::kMillisecond);

void BM_ComputeQuality(benchmark::State& state) {
    const mesohex::HexMesh m = block(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(mesohex::compute_quality(m));
}
BENCHMARK(BM_ComputeQuality)->Arg(100)->Unit(benchmark::kMillisecond);

void BM_WriteReadMedit(benchmark::State& state) {
    const mesohex::HexMesh m = block(static_cast<int>(state.range(0)));
    const std::string path = (std::filesystem::temp_directory_path() / "mesohex_bench_foundation.mesh").string();
    for (auto _ : state) {
        mesohex::write_hex_mesh(path, m);
        benchmark::DoNotOptimize(mesohex::read_hex_mesh(path));
    }
    std::filesystem::remove(path);
}
BENCHMARK(BM_WriteReadMedit)->Arg(50)->Unit(benchmark::kMillisecond);

}  // namespace
