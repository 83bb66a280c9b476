// Local-global fitting throughput: hex x iterations per second of SurfaceFitter::step() on structured blocks of
// n^3 hexes (n = 19, 38, 80: 6 859, 54 872, 512 000 hexes), smoothly deformed, fitted to the unit sphere.
// Items/s in the output = hex x iterations per second. Setup (targets + factorization / assembly) is timed apart.
#include <benchmark/benchmark.h>

#include <cmath>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/post/surface_fitting.h"

namespace {

using namespace mesohex;

// [-0.55, 0.55]^3 split in n^3 cubes, then x += 0.04 sin(5 y) etc. (smooth, no inversion).
HexMesh deformed_block(int n) {
    HexMesh m;
    auto vid = [n](int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); };
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const Vec3 p = Vec3{-0.55, -0.55, -0.55} + (1.1 / n) * Vec3{double(i), double(j), double(k)};
                m.points.push_back(p + 0.04 * Vec3{std::sin(5 * p.y), std::sin(5 * p.z), std::sin(5 * p.x)});
            }
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                m.hexes.push_back({vid(i, j, k), vid(i + 1, j, k), vid(i + 1, j + 1, k), vid(i, j + 1, k),
                                   vid(i, j, k + 1), vid(i + 1, j, k + 1), vid(i + 1, j + 1, k + 1),
                                   vid(i, j + 1, k + 1)});
    return m;
}

SurfaceProjector unit_sphere() {
    return {[](const std::vector<Vec3>& in, std::vector<Vec3>& out) {
        out.resize(in.size());
        for (std::size_t i = 0; i < in.size(); ++i) out[i] = normalized(in[i]);
    }};
}

FitOptions options_for(int solver) {
    FitOptions o;
    o.refresh_every = 0;  // one factorization / assembly for the whole run
    o.solver = solver == 0 ? FitSolver::Direct : FitSolver::ConjugateGradient;
    return o;
}

// Arguments: n, solver (0 = Direct, 1 = ConjugateGradient).
void BM_FitStep(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    const HexMesh mesh = deformed_block(n);
    SurfaceFitter fitter(mesh, unit_sphere(), options_for(static_cast<int>(state.range(1))));
    for (int i = 0; i < 10; ++i) fitter.step();  // past the first large moves towards the sphere
    long solver_iterations = 0, damped = 0;
    for (auto _ : state) {
        const FitProgress p = fitter.step();
        solver_iterations += p.solver_iterations;
        damped += p.step_fraction < 1 ? 1 : 0;
    }
    state.SetItemsProcessed(state.iterations() * static_cast<long>(mesh.hexes.size()));
    state.counters["hexes"] = static_cast<double>(mesh.hexes.size());
    state.counters["cg_iters_per_step"] =
        static_cast<double>(solver_iterations) / static_cast<double>(state.iterations());
    state.counters["damped_steps"] = static_cast<double>(damped);
    state.counters["inverted"] = static_cast<double>(fitter.inverted());
    state.counters["sj_min"] = fitter.sj_min();
}
BENCHMARK(BM_FitStep)
    ->Args({19, 0})
    ->Args({19, 1})
    ->Args({38, 1})
    ->Args({80, 1})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();  // items/s from wall-clock time (CPU time of the main thread would overstate a parallel step)

void BM_FitSetup(benchmark::State& state) {
    const HexMesh mesh = deformed_block(static_cast<int>(state.range(0)));
    for (auto _ : state) {
        SurfaceFitter fitter(mesh, unit_sphere(), options_for(static_cast<int>(state.range(1))));
        benchmark::DoNotOptimize(fitter.mean_target_length());
    }
    state.counters["hexes"] = static_cast<double>(mesh.hexes.size());
}
BENCHMARK(BM_FitSetup)
    ->Args({19, 0})
    ->Args({19, 1})
    ->Args({38, 1})
    ->Args({80, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// Time to convergence (fit_to_surface with its progress rule) at 7k hexes, both solvers: throughput alone would favour
// cheap inexact steps.
void BM_FitToConvergence(benchmark::State& state) {
    const HexMesh mesh = deformed_block(static_cast<int>(state.range(0)));
    FitOptions o = options_for(static_cast<int>(state.range(1)));
    o.max_iterations = 500;
    int iterations = 0;
    double sj_min = 0;
    for (auto _ : state) {
        const FitResult r = fit_to_surface(mesh, unit_sphere(), o);
        iterations = r.iterations;
        sj_min = r.sj_min_after;
    }
    state.counters["iterations"] = iterations;
    state.counters["sj_min"] = sj_min;
}
BENCHMARK(BM_FitToConvergence)->Args({19, 0})->Args({19, 1})->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
