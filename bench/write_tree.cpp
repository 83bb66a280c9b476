// Writes bench::random_tree(VERTICES, SEED) (bench/bench_inputs.h, the benchmarks' synthetic tree, radius 0.5) as a
// skeleton file with its radii, for measuring outside the benchmarks, e.g. the studio page on a tree:
//
//   mesohex_write_tree 2600 5 tree.obj      (the tree of BM_StudioRawTree: 12 564 raw hexes)
//   node bench/studio_page_latency.mjs --skeleton tree.obj --vertex 1305
//
// Not a test, not a Google benchmark: a measuring tool.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_inputs.h"
#include "mesohex/core/error.h"
#include "mesohex_io/skeleton_io.h"

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: mesohex_write_tree VERTICES SEED OUT.obj|OUT.ig\n");
        return 2;
    }
    const int vertices = std::atoi(argv[1]);
    const long seed = std::atol(argv[2]);
    if (vertices < 2 || seed < 0) {
        std::fprintf(stderr, "mesohex_write_tree: VERTICES must be >= 2 and SEED >= 0\n");
        return 2;
    }
    try {
        mesohex::write_skeleton(argv[3], mesohex::bench::random_tree(vertices, static_cast<std::uint32_t>(seed)));
    } catch (const mesohex::Error& e) {
        std::fprintf(stderr, "mesohex_write_tree: %s\n", e.what());
        return 1;
    }
    return 0;
}
