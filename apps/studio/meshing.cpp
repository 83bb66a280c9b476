#include "meshing.h"

#include <charconv>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

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

nlohmann::json predicted_json(const RawMeshPrediction& p) {
    return {{"hexes", p.hexes},
            {"vertices", p.vertices},
            {"compatible_blocks", p.compatible_blocks},
            {"irregular_edges",
             {{"interior", valence_histogram_json(p.interior_irregular_edges)},
              {"boundary", valence_histogram_json(p.boundary_irregular_edges)}}}};
}

// ------------------------------------------------------------------------------------------- the meshing run

// The library's run (the same call and report as `mesohex mesh`) and its report.
struct Run {
    MeshRun run;
    nlohmann::json report;
    const HexMesh& mesh() const { return run.mesh(); }
    const QualityReport& quality() const { return run.quality(); }
};

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

Run run_mesh(const Skeleton& input, const Domain* domain, const MeshRequest& request) {
    MeshOptions options;  // the defaults of `mesohex mesh`
    options.finish = request.finish;
    options.progress = request.progress;
    Run r;
    // The session's surface query, built once, instead of one per request (about 100 ms on a 27 k-triangle domain;
    // an edit must take less than 50 ms).
    r.run = mesh_skeleton(input, domain ? &domain->surface : nullptr,
                          domain && domain->query ? &*domain->query : nullptr, options);
    ReportContext context;
    context.input = request.skeleton_name;
    if (r.run.finish && domain) context.surface = domain->name;
    r.report = mesh_report(r.run, context);
    return r;
}

// Connection surfaces of the meshed skeleton, drawn with the raw mesh's own vertices: the point x of the surface of
// skeleton vertex v is raw vertex vertex_base[v] + 1 + x (raw_mesh.h).
void put_connection_surfaces(std::string& out, const Run& run) {
    const PipelineResult& res = run.run.pipeline;
    const ConnectionSurfaces cs =
        build_connection_surfaces(res.skeleton, res.analysis, run.run.options.connection_surfaces);
    std::vector<Vec3> points;
    std::vector<std::array<int, 4>> quads;
    const int nv = static_cast<int>(res.skeleton.points.size());
    const auto& mesh_points = res.raw.mesh.points;
    for (int v = 0; v < nv; ++v) {
        const int p0 = cs.point_begin[v], p1 = cs.point_begin[v + 1];
        const int base = res.raw.vertex_base[v];
        if (p1 == p0 || base < 0 || base + 1 + (p1 - p0) > static_cast<int>(mesh_points.size())) continue;
        const int first = static_cast<int>(points.size());
        for (int x = 0; x < p1 - p0; ++x) points.push_back(mesh_points[base + 1 + x]);
        for (int q = cs.quad_begin[v]; q < cs.quad_begin[v + 1]; ++q) {
            const std::array<int, 4>& local = cs.quads[q];
            quads.push_back({first + local[0], first + local[1], first + local[2], first + local[3]});
        }
    }
    out += '{';
    put_key(out, "vertices"), put_points(out, points), out += ',';
    put_key(out, "quads"), put_ints(out, quads);
    out += '}';
}

void put_mesh(std::string& out, const Run& run, const Domain* domain) {
    const HexMesh& mesh = run.mesh();
    const HexTopology topo = compute_hex_topology(mesh);
    std::vector<std::array<int, 3>> singular;
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        const int regular = topo.edge_on_boundary[e] ? 2 : 4;
        if (topo.edge_valence[e] != regular)
            singular.push_back({topo.edges[e][0], topo.edges[e][1], topo.edge_valence[e]});
    }
    out += '{';
    put_key(out, "vertices"), put_points(out, mesh.points), out += ',';
    put_key(out, "hexes"), put_ints(out, mesh.hexes), out += ',';
    put_key(out, "sj"), put_doubles(out, run.quality().sj), out += ',';
    put_key(out, "singular_edges"), put_ints(out, singular), out += ',';
    put_key(out, "boundary_quads"), put_ints(out, topo.boundary_quads);
    if (run.run.finish && domain) {
        std::vector<char> on_boundary(mesh.points.size(), 0);
        for (const std::array<int, 4>& q : topo.boundary_quads)
            for (const int v : q) on_boundary[v] = 1;
        std::vector<Vec3> boundary_points;
        std::vector<int> boundary_ids;
        for (std::size_t v = 0; v < mesh.points.size(); ++v)
            if (on_boundary[v]) boundary_points.push_back(mesh.points[v]), boundary_ids.push_back(static_cast<int>(v));
        const std::vector<double> d2 = domain->query->squared_distances(boundary_points);
        std::vector<double> distance(mesh.points.size(), 0.0);
        for (std::size_t i = 0; i < boundary_ids.size(); ++i) distance[boundary_ids[i]] = std::sqrt(d2[i]);
        out += ',';
        put_key(out, "boundary_distance"), put_doubles(out, distance);
    }
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
    const Run run = run_mesh(skeleton, domain, request);
    nlohmann::json j = analysis_json(run.run.pipeline.input_analysis);
    j["predicted"] = predicted_json(run.run.pipeline.predicted);
    return j;
}

std::string mesh_response(const Skeleton& skeleton, const Domain* domain, const MeshRequest& request) {
    const auto t0 = std::chrono::steady_clock::now();
    if (request.finish && !domain)
        throw std::logic_error("mesh_response: stage=final needs a domain");  // the server answers 409 before
    const Run run = run_mesh(skeleton, domain, request);
    nlohmann::json analysis = analysis_json(run.run.pipeline.input_analysis);
    analysis["predicted"] = predicted_json(run.run.pipeline.predicted);
    std::string out;
    out.reserve(64 * run.mesh().hexes.size() + 4096);
    out += '{';
    put_key(out, "report"), out += run.report.dump(-1, ' ', false, kUtf8Replace), out += ',';
    put_key(out, "mesh"), put_mesh(out, run, domain), out += ',';
    put_key(out, "analysis"), out += analysis.dump(-1, ' ', false, kUtf8Replace), out += ',';
    put_key(out, "meshed_skeleton"), put_skeleton(out, run.run.pipeline.skeleton), out += ',';
    if (!run.run.finish) put_key(out, "connection_surfaces"), put_connection_surfaces(out, run), out += ',';
    put_key(out, "server_ms"), put(out, ms_since(t0));
    out += '}';
    return out;
}

}  // namespace mesohex::studio
