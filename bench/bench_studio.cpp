// Studio latency: the raw mesh the page asks for after every edit (POST /api/mesh?stage=raw), at about 10 k hexes.
//   BM_StudioRawServer/E       the server's share of an edit without HTTP: read the skeleton from the OBJ text the
//                              page sends, then mesh_response (run the raw pipeline, build the body). Counters: the
//                              phases of MeshTimings (ms per run, averaged;
//                              parse = reading the body: OBJ text or MHSK bytes).
//   BM_StudioRawRoundTrip/E    the full HTTP round trip over loopback: OBJ text up, body down, through a studio
//                              server started in-process on a free port (httplib::Client; the browser's decoding
//                              and drawing are not included: bench/studio_page_latency.mjs measures those).
//                              Counter server_ms = the server time the body reports.
// E: 0 = OBJ text up, JSON body down (the documented API); 1 = OBJ text up, binary body down (encoding=binary);
//    2 = binary skeleton up (format=mhsk), binary body down: what the page sent before sessions;
//    3 = an editing session: one vertex moved (back and forth) sent as an MHSD delta (format=delta), remeshed
//        incrementally, binary body down (the round trip: a patch answer, since=): what the page sends now after a
//        move.
//    4 = the session of 3 on the tree of BM_StudioRawTree (its branching point moved back and forth; counters hexes
//        and answer_kb, the last answer's size).
// Skeleton: generated torus 128 x 40 quads, 10240 raw hexes (2 per leaflet face, no boundary).
//   BM_StudioRawTree/S         the server's share of an edit on a skeleton with branches, where the repairs and the
//                              adaptation run on every edit: a 2 600-vertex random tree (bench_inputs.h), one
//                              branching point moved back and forth; S = 0 the whole skeleton read (MHSK), 1 an
//                              MHSD delta in a session (incremental remesh when the adapted topology stays; when
//                              the adaptation renumbers it, the content-keyed memo serves the unchanged branching
//                              points), 2 the same session with the memo off (cache.remesh.memo_enabled = false),
//                              3 the session of 1 answering patches of the previous answer (since=, what the page
//                              asks for; row patches when the mesh is renumbered).
//                              Counters: hexes, answer_kb (bytes of the last answer / 1000), incremental (share of runs
//                              that were incremental by index), memo (branching-point surfaces
//                              taken from the memo per run), computed (those computed).
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "bench_inputs.h"
#include "binary_answer.h"
#include "meshing.h"
#include "mesohex/stages/generators.h"
#include "mesohex_io/skeleton_io.h"
#include "server.h"
#include "sessions.h"

using namespace mesohex;

namespace {

Skeleton torus_10k() { return generate_skeleton("torus", {.n = 128, .m = 40}); }

void BM_StudioRawServer(benchmark::State& state) {
    const std::string format = state.range(0) >= 2 ? "mhsk" : "obj";
    const std::string text = format == "mhsk" ? skeleton_binary(torus_10k()) : skeleton_text(torus_10k(), "obj", "t");
    studio::MeshRequest request;
    request.encoding = state.range(0) ? studio::Encoding::Binary : studio::Encoding::Json;
    std::size_t bytes = 0;
    studio::MeshTimings sum;
    long runs = 0;
    // E = 3: the session's skeleton and cache, and the two deltas moving vertex 0 by +-0.02 along x.
    const bool session = state.range(0) == 3;
    const Skeleton base = torus_10k();
    Skeleton moved = base;
    moved.points[0].x += 0.02;
    const std::string deltas[2] = {studio::skeleton_delta_binary(base, moved),
                                   studio::skeleton_delta_binary(moved, base)};
    Skeleton current = base;
    RawRunCache cache;
    if (session) studio::mesh_response(base, nullptr, request, nullptr, &cache);
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const Skeleton s = session ? studio::apply_skeleton_delta(current, deltas[runs % 2])
                                   : read_skeleton_text(text, format, "request body");
        request.parse_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        studio::MeshTimings t;
        const std::string body = studio::mesh_response(s, nullptr, request, &t, session ? &cache : nullptr);
        if (session) current = s;
        bytes = body.size();
        benchmark::DoNotOptimize(body.data());
        sum.parse_ms += t.parse_ms;
        sum.mesh_ms += t.mesh_ms, sum.pipeline_ms += t.pipeline_ms, sum.quality_ms += t.quality_ms;
        sum.report_ms += t.report_ms, sum.topology_ms += t.topology_ms;
        sum.connection_surfaces_ms += t.connection_surfaces_ms, sum.encode_ms += t.encode_ms;
        sum.total_ms += t.total_ms;
        ++runs;
    }
    const double n = runs ? static_cast<double>(runs) : 1.0;
    state.counters["hexes"] = 2.0 * 128 * 40;
    state.counters["body_MB"] = static_cast<double>(bytes) / 1e6;
    state.counters["parse"] = sum.parse_ms / n;
    state.counters["mesh"] = sum.mesh_ms / n;
    state.counters["pipeline"] = sum.pipeline_ms / n;
    state.counters["quality"] = sum.quality_ms / n;
    state.counters["report"] = sum.report_ms / n;
    state.counters["topology"] = sum.topology_ms / n;
    state.counters["conn_surf"] = sum.connection_surfaces_ms / n;
    state.counters["encode"] = sum.encode_ms / n;
    state.counters["total"] = sum.total_ms / n;
}
BENCHMARK(BM_StudioRawServer)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

// The tree of BM_StudioRawTree and the branching point it moves (from the middle vertex on).
Skeleton tree_2600() { return bench::random_tree(2600, 5); }
int tree_moved_vertex(const Skeleton& tree) {
    int v = static_cast<int>(tree.points.size()) / 2;
    const SkeletonAnalysis an = analyze_skeleton(tree);
    while (an.vertex_class[static_cast<std::size_t>(v)] != VertexClass::BranchingPoint) ++v;
    return v;
}

void BM_StudioRawRoundTrip(benchmark::State& state) {
    const bool binary = state.range(0) != 0;
    const bool mhsk = state.range(0) >= 2;
    const bool session = state.range(0) >= 3;
    const bool tree = state.range(0) == 4;
    const Skeleton base = tree ? tree_2600() : torus_10k();
    const std::string text = mhsk ? skeleton_binary(base) : skeleton_text(base, "obj", "torus");
    studio::StudioOptions options;
    options.port = 0;
    studio::StudioServer server({}, {}, options);
    const int port = server.start();
    httplib::Client client("127.0.0.1", port);
    client.set_read_timeout(60, 0);
    const std::string path = mhsk     ? "/api/mesh?stage=raw&encoding=binary&format=mhsk"
                             : binary ? "/api/mesh?stage=raw&encoding=binary"
                                      : "/api/mesh?stage=raw";
    double server_ms = 0;
    long runs = 0;
    // E = 3: the session opened with the full skeleton (revision 0), then deltas moving vertex 0 back and forth.
    Skeleton moved = base;
    if (tree)
        moved.points[static_cast<std::size_t>(tree_moved_vertex(base))] += Vec3{0.02, 0.01, 0};
    else
        moved.points[0].x += 0.02;
    const std::string deltas[2] = {studio::skeleton_delta_binary(base, moved),
                                   studio::skeleton_delta_binary(moved, base)};
    std::size_t answer_bytes = 0;
    // and since = the previous revision: patch answers, decoded against the previous answer.
    studio::DecodedAnswer held;
    if (session) {
        const auto first = client.Post(path + "&session=bench&revision=0", text, "application/octet-stream");
        if (!first || first->status != 200)
            state.SkipWithError("session request failed");
        else
            held = studio::decode_binary_answer(first->body);
    }
    for (auto _ : state) {
        const auto r = session ? client.Post("/api/mesh?stage=raw&encoding=binary&format=delta&session=bench&base=" +
                                                 std::to_string(runs) + "&revision=" + std::to_string(runs + 1) +
                                                 "&since=" + std::to_string(runs),
                                             deltas[runs % 2], "application/octet-stream")
                               : client.Post(path, text, mhsk ? "application/octet-stream" : "text/plain");
        if (!r || r->status != 200) {
            state.SkipWithError("request failed");
            break;
        }
        state.PauseTiming();
        answer_bytes = r->body.size();
        if (session) held = studio::decode_binary_answer(r->body, &held);
        const nlohmann::json j = session  ? held.header
                                 : binary ? studio::decode_binary_answer(r->body).header
                                          : nlohmann::json::parse(r->body);
        server_ms += j["server_ms"].get<double>();
        ++runs;
        state.ResumeTiming();
    }
    state.counters["server_ms"] = runs ? server_ms / static_cast<double>(runs) : 0;
    state.counters["hexes"] = tree ? static_cast<double>(held.ints("mesh.hexes").size() / 8) : 2.0 * 128 * 40;
    state.counters["answer_kb"] = static_cast<double>(answer_bytes) / 1000.0;
    server.stop();
}
BENCHMARK(BM_StudioRawRoundTrip)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_StudioRawTree(benchmark::State& state) {
    const bool session = state.range(0) >= 1;
    const Skeleton base = tree_2600();
    studio::MeshRequest request;
    request.encoding = studio::Encoding::Binary;
    RawRunCache cache;
    cache.remesh.memo_enabled = state.range(0) != 2;
    const std::string first = studio::mesh_response(base, nullptr, request, nullptr, &cache);
    const int v = tree_moved_vertex(base);
    Skeleton moved = base;
    moved.points[static_cast<std::size_t>(v)] += Vec3{0.02, 0.01, 0};
    const std::string deltas[2] = {studio::skeleton_delta_binary(base, moved),
                                   studio::skeleton_delta_binary(moved, base)};
    const std::string whole[2] = {skeleton_binary(moved), skeleton_binary(base)};
    Skeleton current = base;
    long runs = 0, incremental = 0, memo = 0, computed = 0;
    studio::BinaryArrays answers[2];  // S = 3: the previous answer's arrays and this one's
    if (state.range(0) == 3) {
        request.arrays_out = &answers[0];
        studio::mesh_response(base, nullptr, request, nullptr, &cache);
    }
    std::size_t answer_bytes = 0;
    for (auto _ : state) {
        if (state.range(0) == 3) {
            request.patch_base = &answers[runs % 2];
            request.patch_of = runs;
            request.arrays_out = &answers[(runs + 1) % 2];
        }
        const auto t0 = std::chrono::steady_clock::now();
        const Skeleton s = session ? studio::apply_skeleton_delta(current, deltas[runs % 2])
                                   : read_skeleton_text(whole[runs % 2], "mhsk", "request body");
        request.parse_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        const std::string body = studio::mesh_response(s, nullptr, request, nullptr, session ? &cache : nullptr);
        benchmark::DoNotOptimize(body.data());
        answer_bytes = body.size();
        current = s;
        incremental += session && !cache.last.full;
        if (session) {
            memo += cache.last.memo_surfaces;
            computed += cache.last.computed_partitions;
        }
        ++runs;
    }
    const double n = runs ? static_cast<double>(runs) : 1.0;
    state.counters["hexes"] = static_cast<double>(cache.remesh.raw.mesh.hexes.size());
    state.counters["answer_kb"] = static_cast<double>(answer_bytes) / 1000.0;
    state.counters["incremental"] = static_cast<double>(incremental) / n;
    state.counters["memo"] = static_cast<double>(memo) / n;
    state.counters["computed"] = static_cast<double>(computed) / n;
}
BENCHMARK(BM_StudioRawTree)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
