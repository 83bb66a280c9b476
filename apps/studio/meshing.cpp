#include "meshing.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "binary_answer.h"
#include "mesohex/core/error.h"
#include "mesohex/core/topology.h"
#include "mesohex/mesh.h"
#include "mesohex/mesh_report.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/connection_surfaces.h"
#include "mesohex/surface/radius_from_surface.h"

namespace mesohex::studio {

namespace {

// ------------------------------------------------------------------------------------------- JSON text helpers

void put(std::string& out, double x) {
    if (!std::isfinite(x)) {  // JSON has no NaN / inf
        out += "null";
        return;
    }
    char buf[32];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, r.ptr);
}

void put(std::string& out, long long x) {
    char buf[24];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, r.ptr);
}

void put_key(std::string& out, const char* key) {
    out += '"';
    out += key;
    out += "\":";
}

void put_points(std::string& out, const std::vector<Vec3>& points) {
    out += '[';
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (i) out += ',';
        put(out, points[i].x), out += ',', put(out, points[i].y), out += ',', put(out, points[i].z);
    }
    out += ']';
}

template <typename Range>
void put_ints(std::string& out, const Range& cells) {
    out += '[';
    bool first = true;
    for (const auto& cell : cells)
        for (const int v : cell) {
            if (!first) out += ',';
            first = false;
            put(out, static_cast<long long>(v));
        }
    out += ']';
}

void put_doubles(std::string& out, const std::vector<double>& values) {
    out += '[';
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i) out += ',';
        put(out, values[i]);
    }
    out += ']';
}

// Skeleton JSON written directly (the meshed skeleton of a 10 k-hex mesh has thousands of points).
void put_skeleton(std::string& out, const Skeleton& s) {
    out += '{';
    put_key(out, "points");
    out += '[';
    for (std::size_t i = 0; i < s.points.size(); ++i) {
        if (i) out += ',';
        out += '[', put(out, s.points[i].x), out += ',', put(out, s.points[i].y), out += ',', put(out, s.points[i].z);
        out += ']';
    }
    out += "],";
    put_key(out, "radii"), put_doubles(out, s.radii), out += ',';
    const auto put_cells = [&out](const auto& cells) {
        out += '[';
        for (std::size_t i = 0; i < cells.size(); ++i) {
            if (i) out += ',';
            out += '[';
            for (std::size_t k = 0; k < cells[i].size(); ++k) {
                if (k) out += ',';
                put(out, static_cast<long long>(cells[i][k]));
            }
            out += ']';
        }
        out += ']';
    };
    put_key(out, "edges"), put_cells(s.edges), out += ',';
    put_key(out, "faces"), put_cells(s.faces);
    out += '}';
}

const char* class_name(VertexClass c) {
    switch (c) {
        case VertexClass::Isolated: return "Isolated";
        case VertexClass::Extremity: return "Extremity";
        case VertexClass::Joint: return "Joint";
        case VertexClass::BranchingPoint: return "BranchingPoint";
        case VertexClass::LeafletInterior: return "LeafletInterior";
        case VertexClass::LeafletBoundary: return "LeafletBoundary";
        case VertexClass::BLJoint: return "BLJoint";
        case VertexClass::LLJoint: return "LLJoint";
        case VertexClass::FanEdgeVertex: return "FanEdgeVertex";
        case VertexClass::FanEdgeEnd: return "FanEdgeEnd";
    }
    return "Isolated";
}

const char* edge_kind(int degree) {
    if (degree == 0) return "branch";
    if (degree == 1) return "leaflet_boundary";
    if (degree == 2) return "leaflet_interior";
    return "fan";
}

// The "analysis" of the mesh answer: analysis_json(an) with "predicted", written directly, byte for byte what
// nlohmann's dump of that object gives (keys in sorted order; the class and kind names need no escaping). A 10 k-hex
// skeleton has thousands of vertices and edges: building the JSON object cost more than meshing the raw hexes.
// with_names = false leaves out "edge_kind" and "vertex_class" (the binary answer sends them as enum arrays).
void put_analysis(std::string& out, const SkeletonAnalysis& an, const RawMeshPrediction& predicted,
                  bool with_names = true) {
    const auto put_names = [&out](const auto& items, const auto& name_of) {
        out += '[';
        for (std::size_t i = 0; i < items.size(); ++i) {
            if (i) out += ',';
            out += '"';
            out += name_of(items[i]);
            out += '"';
        }
        out += ']';
    };
    out += "{\"counts\":";
    out += analysis_counts_json(an.counts).dump(-1, ' ', false, kUtf8Replace);
    if (with_names) out += ",\"edge_kind\":", put_names(an.edge_degree, edge_kind);
    out += ",\"predicted\":";
    out += prediction_json(predicted).dump(-1, ' ', false, kUtf8Replace);
    if (with_names) out += ",\"vertex_class\":", put_names(an.vertex_class, class_name);
    out += '}';
}

// ------------------------------------------------------------------------------------------- the meshing run

// The library's run (the same call and report as `mesohex mesh`) and its report.
struct Run {
    MeshRun run;
    nlohmann::json report;
    const ConnectionSurfaces* surfaces = nullptr;  // of run.pipeline.skeleton when a raw-run cache holds them
    const HexTopology* topology = nullptr;         // of the raw mesh when a raw-run cache holds it
    const HexMesh& mesh() const { return run.mesh(); }
    const QualityReport& quality() const { return run.quality(); }
};

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

Run run_mesh(const Skeleton& input, const Domain* domain, const MeshRequest& request, MeshTimings& tm,
             RawRunCache* cache = nullptr) {
    MeshOptions options;  // the defaults of `mesohex mesh`
    options.finish = request.finish;
    options.progress = request.progress;
    options.keep_raw_topology = !request.finish;  // drawn from (singular edges, boundary quads)
    Run r;
    // The session's surface query, built once, instead of one per request (about 100 ms on a 27 k-triangle domain;
    // an edit must take less than 50 ms).
    auto t = std::chrono::steady_clock::now();
    const TriangleMesh* surface = domain ? &domain->surface : nullptr;
    const SurfaceQuery* query = domain && domain->query ? &*domain->query : nullptr;
    if (cache && !request.finish) {
        options.keep_raw_topology = false;  // the cache holds it: no copy
        r.run = mesh_skeleton_raw(input, surface, query, options, *cache);
        if (cache->valid) r.surfaces = &cache->remesh.surfaces, r.topology = &cache->topology;
    } else {
        r.run = mesh_skeleton(input, surface, query, options);
    }
    tm.mesh_ms = ms_since(t);
    tm.pipeline_ms = r.run.pipeline_ms;
    tm.quality_ms = r.run.raw_quality_ms;
    t = std::chrono::steady_clock::now();
    ReportContext context;
    context.input = request.skeleton_name;
    if (r.run.finish && domain) context.surface = domain->name;
    r.report = mesh_report(r.run, context);
    tm.report_ms = ms_since(t);
    return r;
}

// The arrays the page draws, computed once and then written as JSON or binary.
struct DrawArrays {
    std::vector<std::array<int, 3>> singular_edges;  // a, b, valence
    std::vector<std::array<int, 4>> boundary_quads;
    std::vector<std::array<int, 1>> boundary_hexes;  // the hex of each boundary quad
    bool has_distance = false;
    std::vector<double> boundary_distance;  // per mesh vertex (final meshes in a domain)
    bool has_connection_surfaces = false;
    std::vector<Vec3> cs_points;
    std::vector<std::array<int, 4>> cs_quads;
};

nlohmann::json timings_json(const MeshTimings& t) {
    return {{"parse", t.parse_ms},
            {"mesh", t.mesh_ms},
            {"pipeline", t.pipeline_ms},
            {"quality", t.quality_ms},
            {"report", t.report_ms},
            {"topology", t.topology_ms},
            {"connection_surfaces", t.connection_surfaces_ms},
            {"distance", t.distance_ms},
            {"encode", t.encode_ms},
            {"total", t.total_ms}};
}

// Connection surfaces of the meshed skeleton, drawn with the raw mesh's own vertices: the point x of the surface of
// skeleton vertex v is raw vertex vertex_base[v] + 1 + x (raw_mesh.h).
void connection_surface_arrays(const Run& run, DrawArrays& out) {
    const PipelineResult& res = run.run.pipeline;
    ConnectionSurfaces built;
    if (!run.surfaces)
        built = build_connection_surfaces(res.skeleton, res.analysis, run.run.options.connection_surfaces);
    const ConnectionSurfaces& cs = run.surfaces ? *run.surfaces : built;
    const int nv = static_cast<int>(res.skeleton.points.size());
    const auto& mesh_points = res.raw.mesh.points;
    out.has_connection_surfaces = true;
    for (int v = 0; v < nv; ++v) {
        const int p0 = cs.point_begin[v], p1 = cs.point_begin[v + 1];
        const int base = res.raw.vertex_base[v];
        if (p1 == p0 || base < 0 || base + 1 + (p1 - p0) > static_cast<int>(mesh_points.size())) continue;
        const int first = static_cast<int>(out.cs_points.size());
        for (int x = 0; x < p1 - p0; ++x) out.cs_points.push_back(mesh_points[base + 1 + x]);
        for (int q = cs.quad_begin[v]; q < cs.quad_begin[v + 1]; ++q) {
            const std::array<int, 4>& local = cs.quads[q];
            out.cs_quads.push_back({first + local[0], first + local[1], first + local[2], first + local[3]});
        }
    }
}

DrawArrays draw_arrays(const Run& run, const Domain* domain, MeshTimings& timings) {
    auto t = std::chrono::steady_clock::now();
    const HexMesh& mesh = run.mesh();
    // The raw mesh's topology comes with its quality (MeshOptions::keep_raw_topology); a final mesh's is computed.
    const bool raw = !run.run.finish;
    const HexTopology* kept = !raw ? nullptr : run.topology ? run.topology : &run.run.raw_topology;
    if (kept && kept->hex_faces.size() != mesh.hexes.size()) kept = nullptr;
    HexTopology computed;
    if (!kept) computed = compute_hex_topology(mesh);
    const HexTopology& topo = kept ? *kept : computed;
    DrawArrays out;
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        const int regular = topo.edge_on_boundary[e] ? 2 : 4;
        if (topo.edge_valence[e] != regular)
            out.singular_edges.push_back({topo.edges[e][0], topo.edges[e][1], topo.edge_valence[e]});
    }
    out.boundary_quads = topo.boundary_quads;
    out.boundary_hexes.reserve(topo.boundary_face.size());
    for (const int f : topo.boundary_face) out.boundary_hexes.push_back({topo.face_hexes[f][0]});
    timings.topology_ms = ms_since(t);
    if (run.run.finish && domain) {
        t = std::chrono::steady_clock::now();
        std::vector<char> on_boundary(mesh.points.size(), 0);
        for (const std::array<int, 4>& q : topo.boundary_quads)
            for (const int v : q) on_boundary[v] = 1;
        std::vector<Vec3> boundary_points;
        std::vector<int> boundary_ids;
        for (std::size_t v = 0; v < mesh.points.size(); ++v)
            if (on_boundary[v]) boundary_points.push_back(mesh.points[v]), boundary_ids.push_back(static_cast<int>(v));
        const std::vector<double> d2 = domain->query->squared_distances(boundary_points);
        out.has_distance = true;
        out.boundary_distance.assign(mesh.points.size(), 0.0);
        for (std::size_t i = 0; i < boundary_ids.size(); ++i) out.boundary_distance[boundary_ids[i]] = std::sqrt(d2[i]);
        timings.distance_ms = ms_since(t);
    }
    if (!run.run.finish) {
        t = std::chrono::steady_clock::now();
        connection_surface_arrays(run, out);
        timings.connection_surfaces_ms = ms_since(t);
    }
    return out;
}

void put_mesh(std::string& out, const Run& run, const DrawArrays& arrays) {
    const HexMesh& mesh = run.mesh();
    out += '{';
    put_key(out, "vertices"), put_points(out, mesh.points), out += ',';
    put_key(out, "hexes"), put_ints(out, mesh.hexes), out += ',';
    put_key(out, "sj"), put_doubles(out, run.quality().sj), out += ',';
    put_key(out, "singular_edges"), put_ints(out, arrays.singular_edges), out += ',';
    put_key(out, "boundary_quads"), put_ints(out, arrays.boundary_quads), out += ',';
    put_key(out, "boundary_hexes"), put_ints(out, arrays.boundary_hexes);
    if (arrays.has_distance) out += ',', put_key(out, "boundary_distance"), put_doubles(out, arrays.boundary_distance);
    out += '}';
}

void put_connection_surfaces(std::string& out, const DrawArrays& arrays) {
    out += '{';
    put_key(out, "vertices"), put_points(out, arrays.cs_points), out += ',';
    put_key(out, "quads"), put_ints(out, arrays.cs_quads);
    out += '}';
}

}  // namespace

nlohmann::json skeleton_json(const Skeleton& s) {
    nlohmann::json points = nlohmann::json::array();
    for (const Vec3& p : s.points) points.push_back({p.x, p.y, p.z});
    nlohmann::json edges = nlohmann::json::array();
    for (const std::array<int, 2>& e : s.edges) edges.push_back({e[0], e[1]});
    nlohmann::json faces = nlohmann::json::array();
    for (const std::vector<int>& f : s.faces) faces.push_back(f);
    return {{"points", points}, {"radii", s.radii}, {"edges", edges}, {"faces", faces}};
}

Skeleton skeleton_from_json(const nlohmann::json& j) {
    const auto fail = [](const std::string& what) { throw std::invalid_argument("skeleton JSON: " + what); };
    if (!j.is_object()) fail("expected an object {\"points\", \"radii\", \"edges\", \"faces\"}");
    const auto member = [&](const char* key, bool required) -> const nlohmann::json* {
        const auto it = j.find(key);
        if (it == j.end() || it->is_null()) {
            if (required) fail(std::string("missing \"") + key + "\"");
            return nullptr;
        }
        if (!it->is_array()) fail(std::string("\"") + key + "\" must be an array");
        return &*it;
    };
    const auto number = [&](const nlohmann::json& x, const std::string& where) {
        if (!x.is_number()) fail(where + " must be a number");
        const double value = x.get<double>();
        if (!std::isfinite(value)) fail(where + " must be finite");
        return value;
    };
    const auto index = [&](const nlohmann::json& x, const std::string& where) {
        if (!x.is_number_integer()) fail(where + " must be an integer");
        const long long value = x.get<long long>();
        if (value < 0 || value > 2147483647LL) fail(where + " out of range");
        return static_cast<int>(value);
    };
    Skeleton s;
    const nlohmann::json& points = *member("points", true);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::string where = "points[" + std::to_string(i) + "]";
        if (!points[i].is_array() || points[i].size() != 3) fail(where + " must be [x, y, z]");
        s.points.push_back({number(points[i][0], where), number(points[i][1], where), number(points[i][2], where)});
    }
    if (const nlohmann::json* radii = member("radii", false))
        for (std::size_t i = 0; i < radii->size(); ++i)
            s.radii.push_back(number((*radii)[i], "radii[" + std::to_string(i) + "]"));
    if (const nlohmann::json* edges = member("edges", false))
        for (std::size_t i = 0; i < edges->size(); ++i) {
            const std::string where = "edges[" + std::to_string(i) + "]";
            if (!(*edges)[i].is_array() || (*edges)[i].size() != 2) fail(where + " must be [a, b]");
            s.edges.push_back({index((*edges)[i][0], where), index((*edges)[i][1], where)});
        }
    if (const nlohmann::json* faces = member("faces", false))
        for (std::size_t i = 0; i < faces->size(); ++i) {
            const std::string where = "faces[" + std::to_string(i) + "]";
            if (!(*faces)[i].is_array() || (*faces)[i].size() < 3 || (*faces)[i].size() > 4)
                fail(where + " must be [a, b, c, d] (or a triangle)");
            std::vector<int> f;
            for (const nlohmann::json& v : (*faces)[i]) f.push_back(index(v, where));
            s.faces.push_back(std::move(f));
        }
    return s;
}

nlohmann::json analysis_json(const SkeletonAnalysis& an) {
    nlohmann::json classes = nlohmann::json::array();
    for (const VertexClass c : an.vertex_class) classes.push_back(class_name(c));
    nlohmann::json kinds = nlohmann::json::array();
    for (const int d : an.edge_degree) kinds.push_back(edge_kind(d));
    return {{"vertex_class", classes}, {"edge_kind", kinds}, {"counts", analysis_counts_json(an.counts)}};
}

nlohmann::json analyze_response(const Skeleton& skeleton, const Domain* domain) {
    MeshRequest request;
    MeshTimings tm;
    const Run run = run_mesh(skeleton, domain, request, tm);
    nlohmann::json j = analysis_json(run.run.pipeline.input_analysis);
    j["repairs"] = repairs_json(run.run.pipeline);
    j["predicted"] = prediction_json(run.run.pipeline.predicted);
    return j;
}

PipelineResult prepare_for_mesh(const Skeleton& skeleton, const Domain* domain) {
    const MeshOptions options;  // the defaults of `mesohex mesh`, as run_mesh
    return prepare_mesh_skeleton(skeleton, domain ? &domain->surface : nullptr,
                                 domain && domain->query ? &*domain->query : nullptr, options);
}

std::string mesh_response(const Skeleton& skeleton, const Domain* domain, const MeshRequest& request,
                          MeshTimings* timings_out, RawRunCache* cache) {
    const auto t0 = std::chrono::steady_clock::now();
    if (request.finish && !domain)
        throw std::logic_error("mesh_response: stage=final needs a domain");  // the server answers 409 before
    MeshTimings tm;
    tm.parse_ms = request.parse_ms;
    const Run run = run_mesh(skeleton, domain, request, tm, cache);
    auto t = std::chrono::steady_clock::now();
    std::string analysis;
    const SkeletonAnalysis& an = run.run.pipeline.input_analysis;
    put_analysis(analysis, an, run.run.pipeline.predicted, request.encoding != Encoding::Binary);
    tm.report_ms += ms_since(t);
    const DrawArrays arrays = draw_arrays(run, domain, tm);
    t = std::chrono::steady_clock::now();
    std::string out;
    if (request.encoding == Encoding::Binary) {
        BinaryArrays bin;
        const HexMesh& mesh = run.mesh();
        append_f32(bin, "mesh.vertices", mesh.points);
        append_u32_cells(bin, "mesh.hexes", mesh.hexes);
        append_f32(bin, "mesh.sj", run.quality().sj);
        append_u32_cells(bin, "mesh.singular_edges", arrays.singular_edges);
        append_u32_cells(bin, "mesh.boundary_quads", arrays.boundary_quads);
        append_u32_cells(bin, "mesh.boundary_hexes", arrays.boundary_hexes);
        if (arrays.has_distance) append_f32(bin, "mesh.boundary_distance", arrays.boundary_distance);
        if (arrays.has_connection_surfaces) {
            append_f32(bin, "connection_surfaces.vertices", arrays.cs_points);
            append_u32_cells(bin, "connection_surfaces.quads", arrays.cs_quads);
        }
        std::vector<const char*> names(an.vertex_class.size());
        std::transform(an.vertex_class.begin(), an.vertex_class.end(), names.begin(), class_name);
        append_enum(bin, "analysis.vertex_class", names);
        names.resize(an.edge_degree.size());
        std::transform(an.edge_degree.begin(), an.edge_degree.end(), names.begin(), edge_kind);
        append_enum(bin, "analysis.edge_kind", names);
        std::string header = "{\"report\":" + run.report.dump(-1, ' ', false, kUtf8Replace);
        header += ",\"analysis\":" + analysis;
        BinaryArrays patched;
        if (request.patch_base) {
            header += ",\"patch_of\":", put(header, static_cast<long long>(request.patch_of));
            patched = patch_arrays(*request.patch_base, bin, mesh_answer_row_layouts());
        }
        tm.encode_ms = ms_since(t);
        tm.total_ms = tm.parse_ms + ms_since(t0);
        header += ",\"server_ms\":", put(header, tm.total_ms);
        header += ",\"server_phases_ms\":" + timings_json(tm).dump() + '}';
        out = binary_answer_text(std::move(header), request.patch_base ? patched : bin);
        if (request.arrays_out) *request.arrays_out = std::move(bin);
    } else {
        out.reserve(64 * run.mesh().hexes.size() + 4096);
        out += '{';
        put_key(out, "report"), out += run.report.dump(-1, ' ', false, kUtf8Replace), out += ',';
        put_key(out, "mesh"), put_mesh(out, run, arrays), out += ',';
        put_key(out, "analysis"), out += analysis, out += ',';
        put_key(out, "meshed_skeleton"), put_skeleton(out, run.run.pipeline.skeleton), out += ',';
        if (arrays.has_connection_surfaces)
            put_key(out, "connection_surfaces"), put_connection_surfaces(out, arrays), out += ',';
        tm.encode_ms = ms_since(t);
        tm.total_ms = tm.parse_ms + ms_since(t0);
        put_key(out, "server_ms"), put(out, tm.total_ms), out += ',';
        put_key(out, "server_phases_ms"), out += timings_json(tm).dump(), out += '}';
    }
    if (timings_out) *timings_out = tm;
    return out;
}

}  // namespace mesohex::studio
