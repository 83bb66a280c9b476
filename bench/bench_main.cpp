// Benchmark driver. MESOHEX_BENCH_THREADS=N caps the worker threads (tbb::global_control), so that the per-thread
// cost of a stage can be measured apart from its parallel speed-up (and on a busy machine).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cstdlib>
#include <memory>

int main(int argc, char** argv) {
    std::unique_ptr<tbb::global_control> threads;
    if (const char* env = std::getenv("MESOHEX_BENCH_THREADS"); env != nullptr && std::atoi(env) > 0)
        threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                        static_cast<std::size_t>(std::atoi(env)));
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
