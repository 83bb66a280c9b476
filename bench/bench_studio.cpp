// Studio latency: the raw mesh the page asks for after every edit (POST /api/mesh?stage=raw), at about 10 k hexes.
//   BM_StudioRawServer       mesh_response alone: parse nothing, run the raw pipeline, build the JSON body (the
//                            server's share of an edit)
//   BM_StudioRawRoundTrip    the full HTTP round trip over loopback: OBJ text up, JSON body down, through a studio
//                            server started in-process on a free port (httplib::Client; the browser's JSON.parse
//                            and drawing are not included). Counter server_ms = the server time the body reports.
// Skeleton: generated torus 128 x 40 quads, 10240 raw hexes (2 per leaflet face, no boundary).
#include <benchmark/benchmark.h>

#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "meshing.h"
#include "mesohex/stages/generators.h"
#include "mesohex_io/skeleton_io.h"
#include "server.h"

using namespace mesohex;

namespace {

Skeleton torus_10k() { return generate_skeleton("torus", {.n = 128, .m = 40}); }

void BM_StudioRawServer(benchmark::State& state) {
    const Skeleton s = torus_10k();
    studio::MeshRequest request;
    std::size_t bytes = 0;
    for (auto _ : state) {
        const std::string body = studio::mesh_response(s, nullptr, request);
        bytes = body.size();
        benchmark::DoNotOptimize(body.data());
    }
    state.counters["hexes"] = 2.0 * 128 * 40;
    state.counters["body_MB"] = static_cast<double>(bytes) / 1e6;
}
BENCHMARK(BM_StudioRawServer)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_StudioRawRoundTrip(benchmark::State& state) {
    const std::string text = skeleton_text(torus_10k(), "obj", "torus");
    studio::StudioOptions options;
    options.port = 0;
    studio::StudioServer server({}, {}, options);
    const int port = server.start();
    httplib::Client client("127.0.0.1", port);
    client.set_read_timeout(60, 0);
    double server_ms = 0;
    long runs = 0;
    for (auto _ : state) {
        const auto r = client.Post("/api/mesh?stage=raw", text, "text/plain");
        if (!r || r->status != 200) {
            state.SkipWithError("request failed");
            break;
        }
        state.PauseTiming();
        server_ms += nlohmann::json::parse(r->body)["server_ms"].get<double>();
        ++runs;
        state.ResumeTiming();
    }
    state.counters["server_ms"] = runs ? server_ms / static_cast<double>(runs) : 0;
    state.counters["hexes"] = 2.0 * 128 * 40;
    server.stop();
}
BENCHMARK(BM_StudioRawRoundTrip)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
