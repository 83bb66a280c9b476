#pragma once
// The studio's one meshing call (what /api/mesh and the jobs run) and the JSON it answers: the same library call and
// report as `mesohex mesh`, plus the arrays the page draws.
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "binary_answer.h"
#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/mesh.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex::studio {

// For json::dump: invalid UTF-8 in a string (a request's bytes quoted in an error message) becomes U+FFFD instead of
// an exception.
inline constexpr nlohmann::json::error_handler_t kUtf8Replace = nlohmann::json::error_handler_t::replace;

// The domain of a session: the surface, its name, and the query structure built once.
struct Domain {
    std::string name;
    TriangleMesh surface;
    std::optional<SurfaceQuery> query;  // built from surface
};

// How the /api/mesh body is written: JSON text, or the binary answer of binary_answer.h (the same content with the
// arrays as float32 / uint32 and without "meshed_skeleton").
enum class Encoding { Json, Binary };

struct MeshRequest {
    std::string skeleton_name = "request";  // "input" in the report
    bool finish = false;                    // stage=final (needs a domain)
    Encoding encoding = Encoding::Json;
    double parse_ms = 0;  // the caller's time reading the skeleton from the request body (counted in "server_ms")
    // Progress of the run (MeshOptions::progress: "raw", "attempt", "fit", "untangle", "improve", "smooth"); may
    // throw to cancel it.
    std::function<void(const MeshProgress&)> progress;
    // Binary answers in an editing session: when patch_base is set, the answer patches those arrays (the previous
    // answer's, which the reader holds; binary_answer.h, patch_arrays) and its header says "patch_of": patch_of.
    // arrays_out (may be null) receives this answer's arrays, whole (the base of the next patch).
    const BinaryArrays* patch_base = nullptr;
    long long patch_of = -1;
    BinaryArrays* arrays_out = nullptr;
};

// Where the server's time goes (wall ms), answered as "server_phases_ms".
struct MeshTimings {
    double parse_ms = 0;                // reading the request body (MeshRequest::parse_ms)
    double mesh_ms = 0;                 // mesh_skeleton: radii, pipeline, raw quality and (final) finishing
    double pipeline_ms = 0;             //   of which run_pipeline (analysis, adaptation, connection surfaces, raw mesh)
    double quality_ms = 0;              //   of which compute_quality of the raw mesh
    double report_ms = 0;               // mesh_report and the analysis JSON
    double topology_ms = 0;             // singular edges and boundary quads of the mesh (compute_hex_topology)
    double connection_surfaces_ms = 0;  // raw only: the connection surfaces drawn with the raw mesh's vertices
    double distance_ms = 0;             // final only: distance of the boundary vertices to the domain
    double encode_ms = 0;               // writing the body (JSON text or binary)
    double total_ms = 0;                // = "server_ms": parse_ms and everything after
};

// Meshes `skeleton` (in `domain` when given) and answers the /api/mesh body: {"report", "mesh", "analysis",
// "meshed_skeleton", "connection_surfaces" (raw only), "server_ms", "server_phases_ms"} as JSON text, or as a binary
// answer (request.encoding). `timings` (may be null) receives the phases. `cache` (may be null; raw meshes only):
// what the previous raw mesh of an editing session left (mesh_skeleton_raw), for an answer built faster and equal
// byte for byte but for the times. Errors: mesohex::Error from the library (naming the element), or whatever
// `progress` throws.
std::string mesh_response(const Skeleton& skeleton, const Domain* domain, const MeshRequest& request,
                          MeshTimings* timings = nullptr, RawRunCache* cache = nullptr);

// The /api/analyze body for `skeleton`: {"vertex_class", "edge_kind", "counts", "repairs", "predicted"} (the input
// analysis, the repairs /api/mesh makes before meshing, and the prediction of the raw mesh /api/mesh?stage=raw builds,
// with the same radii). Errors: mesohex::Error.
nlohmann::json analyze_response(const Skeleton& skeleton, const Domain* domain);

// The input analysis /api/mesh makes (after the radii from the domain; accepting what its repairs fix, e.g. a branch
// on a fan-edge end) and its repairs: mesohex::prepare_mesh_skeleton with the defaults of /api/mesh. Errors: the
// mesohex::Error /api/mesh gives for the skeleton up to its analysis.
PipelineResult prepare_for_mesh(const Skeleton& skeleton, const Domain* domain);

// Per-vertex classes and per-edge kinds of an analysis, with the counts (no prediction).
nlohmann::json analysis_json(const SkeletonAnalysis& analysis);

// Skeleton JSON {"points", "radii", "edges", "faces"} and back. skeleton_from_json throws
// std::invalid_argument naming the offending member on anything malformed.
nlohmann::json skeleton_json(const Skeleton& skeleton);
Skeleton skeleton_from_json(const nlohmann::json& j);

}  // namespace mesohex::studio
