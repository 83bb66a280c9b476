// Skeleton -> raw mesh (run_pipeline defaults, no file IO in the timed part): a measuring and checking tool for issue
// 19 target 1, not a Google benchmark. Per input one line: name, raw hex count, FNV-1a hash of the raw mesh (the
// points' bits and the hexes' vertex ids), the skeleton repair's counts (trunks / absorbed stubs / merged ends /
// unseparated pairs), CPU ms per run of this thread (min over the reps), then wall ms per run (min and median), the
// process's CPU ms per run (all threads, TBB's waiting workers included; min over the reps) and, with --stages, each
// stage's wall ms (min over the reps; run_pipeline's timings_ms). Two builds print the same hashes
// when their raw meshes are identical bit for bit; one build prints the same hashes for any --threads.
//
//   mesohex_raw_chain [--threads T] [--reps R] [--stages] INPUT...
//     INPUT: tree:VERTICES:SEED (bench::random_tree), star:VERTICES, gen:NAME (generate_skeleton), random:SEED
//            (generate_random_skeleton), or a skeleton file path; gen:all = every generator, random:A-B = seeds A..B
//   Run under valgrind --tool=callgrind for instruction counts (one rep). EXACT_THREE=0|1 in the environment sets
//   ConnectionSurfaceOptions::exact_three_orange, SHARED_HULL=0|1 its shared_hull_relaxation, GRADIENT_LONG=0|1 its
//   gradient_long_relaxation, COARSE_THREE=0|1 its coarse_three_scan, TABLED_THREE=0|1 its tabled_three_start,
//   FIRST_IMPROVING=0|1 its first_improving_long_relaxation, BRIDGE_QUAD=0|1 RawMeshOptions::bridge_quad_radius,
//   BRIDGE_QUAD_INSET=F its bridge_quad_inset.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "bench_inputs.h"
#include "mesohex/core/error.h"
#include "mesohex/pipeline.h"
#include "mesohex/stages/generators.h"
#include "mesohex_io/skeleton_io.h"
#include "raw_hash.h"

using namespace mesohex;

namespace {

using bench::raw_hash;

Skeleton make_input(const std::string& spec) {
    auto field = [&](int k) {
        std::size_t start = 0;
        for (int i = 0; i < k; ++i) start = spec.find(':', start) + 1;
        return spec.substr(start, spec.find(':', start) - start);
    };
    if (spec.rfind("tree:", 0) == 0)
        return bench::random_tree(std::atoi(field(1).c_str()), static_cast<std::uint32_t>(std::atol(field(2).c_str())));
    if (spec.rfind("star:", 0) == 0) return bench::three_branch_star(std::atoi(field(1).c_str()));
    if (spec.rfind("gen:", 0) == 0) return generate_skeleton(field(1));
    if (spec.rfind("random:", 0) == 0) return generate_random_skeleton(std::strtoull(field(1).c_str(), nullptr, 10));
    return read_skeleton(spec);
}

double cpu_ms(clockid_t clock = CLOCK_THREAD_CPUTIME_ID) {
    timespec t{};
    clock_gettime(clock, &t);
    return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
    int threads = 1, reps = 1;
    bool stages = false;
    std::vector<std::string> inputs;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--threads") && i + 1 < argc)
            threads = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--reps") && i + 1 < argc)
            reps = std::max(1, std::atoi(argv[++i]));  // at least one run (the min / median need one)
        else if (!std::strcmp(argv[i], "--stages"))
            stages = true;
        else if (!std::strcmp(argv[i], "gen:all"))
            for (const std::string& name : generator_names()) inputs.push_back("gen:" + name);
        else if (!std::strncmp(argv[i], "random:", 7) && std::strchr(argv[i], '-')) {
            const long first = std::atol(argv[i] + 7), last = std::atol(std::strchr(argv[i], '-') + 1);
            for (long seed = first; seed <= last; ++seed) inputs.push_back("random:" + std::to_string(seed));
        } else
            inputs.emplace_back(argv[i]);
    }
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    for (const std::string& spec : inputs) {
        try {
            const Skeleton s = make_input(spec);
            double best = 1e300, best_process = 1e300;
            std::vector<double> walls;
            std::vector<std::string> stage_order;
            std::map<std::string, double> stage_best;  // stage -> min wall ms over the reps
            PipelineResult res;
            PipelineOptions po;
            if (const char* k = std::getenv("EXACT_THREE"))  // ConnectionSurfaceOptions::exact_three_orange
                po.connection_surfaces.exact_three_orange = std::atoi(k) != 0;
            if (const char* k = std::getenv("SHARED_HULL"))  // ConnectionSurfaceOptions::shared_hull_relaxation
                po.connection_surfaces.shared_hull_relaxation = std::atoi(k) != 0;
            if (const char* k = std::getenv("GRADIENT_LONG"))  // ConnectionSurfaceOptions::gradient_long_relaxation
                po.connection_surfaces.gradient_long_relaxation = std::atoi(k) != 0;
            if (const char* k = std::getenv("COARSE_THREE"))  // ConnectionSurfaceOptions::coarse_three_scan
                po.connection_surfaces.coarse_three_scan = std::atoi(k) != 0;
            if (const char* k = std::getenv("TABLED_THREE"))  // ConnectionSurfaceOptions::tabled_three_start
                po.connection_surfaces.tabled_three_start = std::atoi(k) != 0;
            // ConnectionSurfaceOptions::first_improving_long_relaxation
            if (const char* k = std::getenv("FIRST_IMPROVING"))
                po.connection_surfaces.first_improving_long_relaxation = std::atoi(k) != 0;
            if (const char* k = std::getenv("BRIDGE_QUAD"))  // RawMeshOptions::bridge_quad_radius
                po.raw_mesh.bridge_quad_radius = std::atoi(k) != 0;
            if (const char* k = std::getenv("BRIDGE_QUAD_INSET"))  // RawMeshOptions::bridge_quad_inset
                po.raw_mesh.bridge_quad_inset = std::atof(k);
            for (int r = 0; r < reps; ++r) {
                const double t0 = cpu_ms(), p0 = cpu_ms(CLOCK_PROCESS_CPUTIME_ID);
                const auto w0 = std::chrono::steady_clock::now();
                res = run_pipeline(s, po);
                walls.push_back(
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0).count());
                const double t = cpu_ms() - t0, tp = cpu_ms(CLOCK_PROCESS_CPUTIME_ID) - p0;
                best = t < best ? t : best;
                best_process = tp < best_process ? tp : best_process;
                for (const StageTiming& st : res.timings_ms) {
                    if (!stage_best.count(st.stage)) {
                        stage_order.push_back(st.stage);
                        stage_best[st.stage] = st.ms;
                    }
                    stage_best[st.stage] = std::min(stage_best[st.stage], st.ms);
                }
            }
            std::sort(walls.begin(), walls.end());
            std::printf("%s %zu %016llx repairs %d/%d/%d/%d %.2f wall %.2f/%.2f", spec.c_str(),
                        res.raw.mesh.hexes.size(), static_cast<unsigned long long>(raw_hash(res.raw)), res.trunks,
                        res.absorbed_stubs, res.merged_ends, res.unseparated_pairs, best, walls.front(),
                        walls[walls.size() / 2]);
            std::printf(" process %.2f", best_process);
            if (stages)
                for (const std::string& name : stage_order) std::printf(" %s=%.3f", name.c_str(), stage_best[name]);
            std::printf("\n");
        } catch (const Error& e) {
            std::printf("%s error: %s\n", spec.c_str(), e.what());
        }
    }
    return 0;
}
