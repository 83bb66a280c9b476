// The finishing stages on a large mesh (issue 19 items 3-5): skeleton + domain -> raw mesh -> finish_mesh with the
// given levels -> optional mesh file, with per stage its wall and CPU time (all threads), CPU microseconds per hex
// (per hex and iteration for the fit), and peak resident memory per hex of the stage's mesh. Not a test, not a Google
// benchmark: a measuring tool (bench/finish_1m.sh runs it on the 1 M-hex cases).
//
//   mesohex_finish_levels SKELETON DOMAIN [--levels L] [--fit-levels F] [--rings R] [--guard SJ] [--inherit-smooth 0|1]
//                         [--smooth-sj SJ] [--smooth-rings R] [-o MESH]
//
// Memory: the peak resident set (VmHWM) is reset (/proc/self/clear_refs) when a stage starts and read when it ends;
// large blocks are mmap-allocated (so freed memory leaves the process and the next stage's peak is its own).
#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex/mesh.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

using namespace mesohex;

namespace {

double cpu_ms() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return 1e3 * static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-3 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// VmHWM / VmRSS of this process in bytes.
long status_bytes(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    const std::string k = std::string(key) + ":";
    while (std::getline(in, line))
        if (line.rfind(k, 0) == 0) return std::atol(line.c_str() + k.size()) * 1024;
    return 0;
}

void reset_peak() { std::ofstream("/proc/self/clear_refs") << "5"; }

struct Clock {
    std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
    double cpu = cpu_ms();
    double wall_ms() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall).count();
    }
};

long overall_peak = 0;  // the largest stage peak

void print_row(const char* stage, long hexes, double wall, double cpu, long peak, long rss_before, double per) {
    overall_peak = std::max(overall_peak, peak);
    std::printf("%-14s %10ld %10.0f %10.0f %9.3f %9.0f %9.0f\n", stage, hexes, wall, cpu, per, peak / 1048576.0,
                hexes > 0 ? static_cast<double>(peak - rss_before) / static_cast<double>(hexes) : 0.0);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(
            stderr,
            "usage: %s SKELETON DOMAIN [--levels L] [--fit-levels F] [--rings R] [--guard SJ] [--inherit-smooth 0|1] "
            "[--smooth-sj SJ] [--smooth-rings R] [-o MESH]\n",
            argv[0]);
        return 2;
    }
    mallopt(M_MMAP_THRESHOLD, 1 << 20);  // fixed: blocks of 1 MB and more are mmap'ed and returned when freed
    mallopt(M_TRIM_THRESHOLD, 1 << 20);
    MeshOptions options;
    options.retry = false;
    std::string out;
    for (int i = 3; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--levels") options.finishing.levels = std::atoi(argv[i + 1]);
        if (a == "--fit-levels") options.finishing.fit_levels = std::atoi(argv[i + 1]);
        if (a == "--rings") options.finishing.inherit_rings = std::atoi(argv[i + 1]);
        if (a == "--guard") options.finishing.inherit_guard_sj = std::atof(argv[i + 1]);
        if (a == "--inherit-smooth") options.finishing.inherit_smooth = std::atoi(argv[i + 1]) != 0;
        if (a == "--smooth-sj") options.finishing.inherit_smooth_sj = std::atof(argv[i + 1]);
        if (a == "--smooth-rings") options.finishing.inherit_smooth_rings = std::atoi(argv[i + 1]);
        if (a == "-o") out = argv[i + 1];
    }
    try {
        Clock all;
        const Skeleton skeleton = read_skeleton(argv[1]);
        const TriangleMesh domain = read_surface(argv[2]);
        std::printf("read: %.0f ms wall, %.0f ms CPU; domain %zu triangles; RSS %.0f MB\n", all.wall_ms(),
                    cpu_ms() - all.cpu, domain.triangles.size(), status_bytes("VmRSS") / 1048576.0);
        std::printf("%-14s %10s %10s %10s %9s %9s %9s\n", "stage", "hexes", "wall_ms", "cpu_ms", "cpu_us/hex",
                    "peak_MB", "B/hex");
        Clock stage;
        long rss_before = status_bytes("VmRSS");
        reset_peak();
        options.finishing.stage_done = [&](const FinishStage& s) {
            const double cpu = cpu_ms() - stage.cpu;
            print_row(s.stage.c_str(), s.hexes, stage.wall_ms(), cpu, status_bytes("VmHWM"), rss_before,
                      s.hexes > 0 ? 1e3 * cpu / static_cast<double>(s.hexes) : 0.0);
            stage = Clock{};
            rss_before = status_bytes("VmRSS");
            reset_peak();
        };
        const MeshRun run = mesh_in_domain(skeleton, domain, options);
        const FinishResult& f = *run.finish;
        const long hexes = static_cast<long>(f.mesh.hexes.size());
        print_row("quality+dist", hexes, stage.wall_ms(), cpu_ms() - stage.cpu, status_bytes("VmHWM"), rss_before,
                  1e3 * (cpu_ms() - stage.cpu) / static_cast<double>(hexes));
        if (f.fit_iterations > 0) std::printf("fit: %d iterations\n", f.fit_iterations);
        if (!out.empty()) {
            stage = Clock{};
            rss_before = status_bytes("VmRSS");
            reset_peak();
            write_hex_mesh(out, f.mesh);
            print_row("write", hexes, stage.wall_ms(), cpu_ms() - stage.cpu, status_bytes("VmHWM"), rss_before,
                      1e3 * (cpu_ms() - stage.cpu) / static_cast<double>(hexes));
        }
        std::printf(
            "final: %ld hexes, SJ min %.4f avg %.4f, inverted %ld, Hausdorff %.4f %% (distance %.0f ms); "
            "levels %d (inherited %d)\n",
            hexes, f.quality.sj_min, f.quality.sj_avg, f.quality.inverted, 100 * f.distance.relative_max, f.distance_ms,
            f.subdivision_levels, f.inherited_levels);
        std::printf("total: %.0f ms wall, %.0f ms CPU, peak RSS %.0f MB (%.0f B per final hex)\n", all.wall_ms(),
                    cpu_ms() - all.cpu, static_cast<double>(overall_peak) / 1048576.0,
                    static_cast<double>(overall_peak) / static_cast<double>(hexes));
    } catch (const Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    return 0;
}
