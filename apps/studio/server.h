#pragma once
// The studio's local web server (cpp-httplib): the page's static files from an in-memory table, and the JSON API of
// docs/studio.md. Binds 127.0.0.1 unless told otherwise. No request path is ever passed to the file system; the only
// files touched are the ones given on the command line (read before the server starts) and the --save target.
// httplib stays out of this header.
#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"
#include "static_files.h"

namespace mesohex::studio {

// What the studio was started with (files read by the caller).
struct StudioSession {
    std::optional<Skeleton> skeleton;  // SKELETON
    std::string skeleton_name;
    std::optional<TriangleMesh> domain;  // --surface
    std::string domain_name;
    std::optional<Skeleton> medial;  // --medial: the meso-skeleton imported from the .ma file
    std::string save_target;         // --save ("" = none: /api/save answers 403); .obj or .ig
};

struct StudioOptions {
    std::string host = "127.0.0.1";
    int port = 8080;                         // 0 = any free port
    std::size_t max_body_bytes = 64u << 20;  // larger request bodies get 413
    int kept_jobs_per_client = 8;            // finished jobs kept for polling, per client
    // Editing sessions kept for delta uploads (/api/mesh?session=; sessions.h), the least recently used dropped
    // first. Each holds a skeleton, its raw mesh with topology and its last answer: about 16 MB at 10 k hexes.
    int mesh_sessions = 4;
};

class StudioServer {
public:
    StudioServer(StudioSession session, StaticFiles files, StudioOptions options = {});
    ~StudioServer();  // stop()
    StudioServer(const StudioServer&) = delete;
    StudioServer& operator=(const StudioServer&) = delete;

    // Binds host:port. Returns the port (the one chosen when options.port is 0). Error(IoError) when it cannot bind.
    int bind();
    // Serves until stop() (binds first if bind() was not called). Returns false if the server could not run.
    bool listen();
    // bind() and listen() on a background thread (for tests and benchmarks); returns the port once it accepts.
    int start();
    // Cancels the jobs, stops listening and joins the background thread (if start() made one). Idempotent; callable
    // from any thread.
    void stop();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mesohex::studio
