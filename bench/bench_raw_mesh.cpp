// Raw-mesh benchmarks (paper steps 2-7). Counter "hex/s" = hexes built per second.
//   BM_RawMeshStage/<threads>      build_raw_mesh only (blocks + geometry transfer: the "raw stage"), synthetic tree
//   BM_RawPipeline/<threads>       analysis + connection surfaces + frames + raw mesh, synthetic tree
//   BM_RawPipelineBlock/<threads>  the same on ../shared/data/curve-skeletons/block.skel, input sampling
//                                  (skipped when the file is absent; MESOHEX_SHARED_DATA overrides the directory)
// Threads are limited with tbb::global_control.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <tbb/global_control.h>

#include "mesohex/stages/raw_mesh.h"
#include "mesohex_io/skeleton_io.h"

using namespace mesohex;

namespace {

// Deterministic binary tree of curved branches: every branch has `edges_per_branch` unit edges and splits into two
// children at +-35 degrees in alternating planes; grows breadth-first until about `target_edges` edges.
Skeleton synthetic_tree(long target_edges, int edges_per_branch = 8) {
    Skeleton s;
    s.points.push_back({0, 0, 0});
    struct Tip {
        int vertex;
        Vec3 dir, normal;
    };
    std::vector<Tip> queue{{0, {0, 0, 1}, {1, 0, 0}}};
    for (std::size_t qi = 0; qi < queue.size() && static_cast<long>(s.edges.size()) < target_edges; ++qi) {
        const Tip tip = queue[qi];
        for (int side = -1; side <= 1; side += 2) {
            const double a = side * 0.61;  // 35 degrees
            Vec3 d = normalized(std::cos(a) * tip.dir + std::sin(a) * tip.normal);
            const Vec3 n = normalized(cross(d, tip.normal));  // alternate the splitting plane
            int prev = tip.vertex;
            Vec3 p = s.points[tip.vertex];
            for (int k = 0; k < edges_per_branch; ++k) {
                d = normalized(d + 0.05 * n);  // slight bend
                p = p + d;
                s.points.push_back(p);
                const int cur = static_cast<int>(s.points.size()) - 1;
                s.edges.push_back({prev, cur});
                prev = cur;
            }
            queue.push_back({prev, d, n});
        }
    }
    s.radii.assign(s.points.size(), 0.25);
    return s;
}

struct Prepared {
    Skeleton skeleton;
    SkeletonAnalysis analysis;
    ConnectionSurfaces surfaces;
    BranchFrames frames;
};

Prepared prepare(Skeleton s) {
    Prepared p;
    p.skeleton = std::move(s);
    p.analysis = analyze_skeleton(p.skeleton);
    p.surfaces = build_connection_surfaces(p.skeleton, p.analysis);
    p.frames = propagate_frames(p.skeleton, p.analysis, p.surfaces);
    return p;
}

const Prepared& tree() {
    static const Prepared p = prepare(synthetic_tree(250000));  // about 1 M hexes
    return p;
}

void BM_RawMeshStage(benchmark::State& state) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
    const Prepared& p = tree();
    long hexes = 0;
    for (auto _ : state) {
        RawMesh raw = build_raw_mesh(p.skeleton, p.analysis, p.surfaces, p.frames);
        hexes += static_cast<long>(raw.mesh.hexes.size());
        benchmark::DoNotOptimize(raw.mesh.points.data());
    }
    state.counters["hex/s"] = benchmark::Counter(static_cast<double>(hexes), benchmark::Counter::kIsRate);
    state.counters["hexes"] = static_cast<double>(p.analysis.predicted_hexes);
}

void run_pipeline_bench(benchmark::State& state, const Skeleton& s) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
    long hexes = 0;
    for (auto _ : state) {
        const SkeletonAnalysis an = analyze_skeleton(s);
        const ConnectionSurfaces cs = build_connection_surfaces(s, an);
        const BranchFrames fr = propagate_frames(s, an, cs);
        RawMesh raw = build_raw_mesh(s, an, cs, fr);
        hexes += static_cast<long>(raw.mesh.hexes.size());
        benchmark::DoNotOptimize(raw.mesh.points.data());
    }
    state.counters["hex/s"] = benchmark::Counter(static_cast<double>(hexes), benchmark::Counter::kIsRate);
}

void BM_RawPipeline(benchmark::State& state) { run_pipeline_bench(state, tree().skeleton); }

void BM_RawPipelineBlock(benchmark::State& state) {
    const char* env = std::getenv("MESOHEX_SHARED_DATA");
    const std::string dir = env ? env : std::string(MESOHEX_BENCH_SHARED_DATA_DIR);
    const std::string path = dir + "/curve-skeletons/block.skel";
    if (!std::filesystem::exists(path)) {
        state.SkipWithError(("missing " + path).c_str());
        for (auto _ : state) {
        }
        return;
    }
    static const Skeleton s = read_skeleton(path);
    run_pipeline_bench(state, s);
}

}  // namespace

BENCHMARK(BM_RawMeshStage)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RawPipeline)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RawPipelineBlock)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
