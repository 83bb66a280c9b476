// Quality report: Verdict's hex scaled Jacobian, Euler characteristics, boundary genus, singular edges.
#include "mesohex/post/quality.h"
#include "mesohex/core/union_find.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <sstream>

#include <tbb/parallel_for.h>
#include <nlohmann/json.hpp>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"

namespace mesohex {
double scaled_jacobian(const std::array<Vec3, 8>& p) { return hex_scaled_jacobian(p); }

std::vector<double> scaled_jacobians(const HexMesh& mesh) {
    std::vector<double> sj(mesh.hexes.size(), -1.0);
    tbb::parallel_for(std::size_t{0}, mesh.hexes.size(), [&](std::size_t h) {
        const std::array<int, 8>& hex = mesh.hexes[h];
        if (!hex_indices_in_range(hex, mesh.points.size())) return;  // stays -1
        std::array<Vec3, 8> corners;
        for (std::size_t lv = 0; lv < 8; ++lv) corners[lv] = mesh.points[static_cast<std::size_t>(hex[lv])];
        sj[h] = scaled_jacobian(corners);
    });
    return sj;
}

namespace {

// sj_min, sj_avg, inverted, the histogram and the worst hexes of r.sj (sequential sum: the same result for any thread
// count).
void sj_statistics(QualityReport& r) {
    r.sj_min = r.sj_avg = 0;
    r.inverted = 0;
    r.sj_histogram.fill(0);
    r.worst_hexes.clear();
    if (!r.sj.empty()) {
        double sum = 0;
        r.sj_min = r.sj[0];
        for (double s : r.sj) {
            sum += s;
            r.sj_min = std::min(r.sj_min, s);
            if (s <= 0) ++r.inverted;
            const int bin = std::clamp(static_cast<int>(std::floor((s + 1.0) / 0.2)), 0, 9);
            ++r.sj_histogram[static_cast<std::size_t>(bin)];
        }
        r.sj_avg = sum / static_cast<double>(r.sj.size());
        std::vector<int> order(r.sj.size());
        std::iota(order.begin(), order.end(), 0);
        const std::size_t k = std::min<std::size_t>(10, order.size());
        std::partial_sort(
            order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(), [&](int a, int b) {
                const double sa = r.sj[static_cast<std::size_t>(a)], sb = r.sj[static_cast<std::size_t>(b)];
                return sa != sb ? sa < sb : a < b;
            });
        r.worst_hexes.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k));
    }
}

}  // namespace

QualityReport compute_quality(const HexMesh& mesh) {
    HexTopology topo;
    return compute_quality(mesh, topo);
}

QualityReport compute_quality(const HexMesh& mesh, HexTopology& topo) { return compute_quality(mesh, topo, {}); }

QualityReport compute_quality(const HexMesh& mesh, HexTopology& topo, std::vector<double> sj) {
    MESOHEX_CHECK(sj.empty() || sj.size() == mesh.hexes.size(), "compute_quality: sj needs one entry per hex");
    topo = HexTopology{};
    QualityReport r;
    r.vertices = static_cast<long>(mesh.points.size());
    r.hexes = static_cast<long>(mesh.hexes.size());
    r.sj = sj.empty() ? scaled_jacobians(mesh) : std::move(sj);

    sj_statistics(r);

    // Topology needs every index in range.
    for (const std::array<int, 8>& hex : mesh.hexes) {
        if (!hex_indices_in_range(hex, mesh.points.size())) {
            r.validation = validate(mesh);
            return r;
        }
    }
    topo = compute_hex_topology(mesh);
    r.validation = validate(mesh, topo);

    std::vector<char> used(mesh.points.size(), 0);
    for (const std::array<int, 8>& hex : mesh.hexes)
        for (int v : hex) used[static_cast<std::size_t>(v)] = 1;
    const long used_vertices = std::count(used.begin(), used.end(), 1);
    r.euler_characteristic = used_vertices - static_cast<long>(topo.edges.size()) +
                             static_cast<long>(topo.faces.size()) - static_cast<long>(mesh.hexes.size());

    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        const int valence = topo.edge_valence[e];
        if (topo.edge_on_boundary[e]) {
            if (valence != 2) ++r.singular_boundary_edges[valence];
        } else if (valence != 4) {
            ++r.singular_interior_edges[valence];
        }
    }

    // Boundary components: union-find over the vertices of boundary quads.
    UnionFind sets(static_cast<int>(mesh.points.size()));
    std::vector<char> on_boundary(mesh.points.size(), 0);
    for (const std::array<int, 4>& q : topo.boundary_quads) {
        for (int i = 0; i < 4; ++i) on_boundary[static_cast<std::size_t>(q[static_cast<std::size_t>(i)])] = 1;
        for (int i = 1; i < 4; ++i) sets.unite(q[0], q[static_cast<std::size_t>(i)]);
    }
    std::vector<int> component_of_root(mesh.points.size(), -1);
    std::vector<long> chi;  // per component, numbered by first appearance in the boundary quads
    auto component = [&](int v) {
        int& c = component_of_root[static_cast<std::size_t>(sets.find(v))];
        if (c < 0) {
            c = static_cast<int>(chi.size());
            chi.push_back(0);
        }
        return static_cast<std::size_t>(c);
    };
    for (const std::array<int, 4>& q : topo.boundary_quads) chi[component(q[0])] += 1;  // faces
    for (std::size_t v = 0; v < mesh.points.size(); ++v)
        if (on_boundary[v]) chi[component(static_cast<int>(v))] += 1;  // vertices
    for (std::size_t e = 0; e < topo.edges.size(); ++e)
        if (topo.edge_on_boundary[e]) chi[component(topo.edges[e][0])] -= 1;  // edges
    r.boundary_components = static_cast<long>(chi.size());
    for (long c : chi) {
        r.boundary_euler_characteristic += c;
        r.boundary_genus += (2.0 - static_cast<double>(c)) / 2.0;
    }
    return r;
}

QualityReport update_quality(const QualityReport& old, const HexMesh& old_mesh, const HexMesh& mesh,
                             const HexTopology& topology) {
    const bool same_cells = old_mesh.points.size() == mesh.points.size() && old_mesh.hexes == mesh.hexes &&
                            old.sj.size() == mesh.hexes.size() && old.validation.valid() &&
                            topology.hex_faces.size() == mesh.hexes.size();
    const bool finite = std::all_of(mesh.points.begin(), mesh.points.end(), [](const Vec3& p) {
        return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    });
    if (!same_cells || !finite) {
        HexTopology fresh;
        return compute_quality(mesh, fresh);
    }
    // Every check of validate() but the finite coordinates reads the cells only, and those passed before: the
    // validation, Euler characteristics, boundary and singular edges stay; only the scaled Jacobians of hexes with a
    // moved corner change.
    std::vector<char> moved(mesh.points.size(), 0);
    for (std::size_t v = 0; v < mesh.points.size(); ++v)
        moved[v] = std::memcmp(&mesh.points[v], &old_mesh.points[v], sizeof(Vec3)) != 0;
    QualityReport r = old;
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
        const std::array<int, 8>& hex = mesh.hexes[h];
        if (std::none_of(hex.begin(), hex.end(), [&](int v) { return moved[static_cast<std::size_t>(v)] != 0; }))
            continue;
        std::array<Vec3, 8> corners;
        for (std::size_t lv = 0; lv < 8; ++lv) corners[lv] = mesh.points[static_cast<std::size_t>(hex[lv])];
        r.sj[h] = scaled_jacobian(corners);
    }
    sj_statistics(r);
    return r;
}

std::string quality_to_json(const QualityReport& r, int indent) {
    nlohmann::ordered_json j;
    j["vertices"] = r.vertices;
    j["hexes"] = r.hexes;
    j["sj_min"] = r.sj_min;
    j["sj_avg"] = r.sj_avg;
    j["inverted"] = r.inverted;
    nlohmann::ordered_json hist = nlohmann::ordered_json::array();
    for (std::size_t b = 0; b < 10; ++b) {
        const double lo = -1.0 + 0.2 * static_cast<double>(b);
        hist.push_back({{"from", lo}, {"to", lo + 0.2}, {"count", r.sj_histogram[b]}});
    }
    j["sj_histogram"] = hist;
    nlohmann::ordered_json worst = nlohmann::ordered_json::array();
    for (int h : r.worst_hexes) {
        const double s = static_cast<std::size_t>(h) < r.sj.size() ? r.sj[static_cast<std::size_t>(h)] : 0.0;
        worst.push_back({{"hex", h}, {"sj", s}});
    }
    j["worst_hexes"] = worst;
    j["euler_characteristic"] = r.euler_characteristic;
    j["boundary_euler_characteristic"] = r.boundary_euler_characteristic;
    j["boundary_components"] = r.boundary_components;
    j["boundary_genus"] = r.boundary_genus;
    nlohmann::ordered_json interior = nlohmann::ordered_json::object(), boundary = nlohmann::ordered_json::object();
    for (const auto& [valence, count] : r.singular_interior_edges) interior[std::to_string(valence)] = count;
    for (const auto& [valence, count] : r.singular_boundary_edges) boundary[std::to_string(valence)] = count;
    j["singular_edges"] = {{"interior", interior}, {"boundary", boundary}};
    j["valid"] = r.validation.valid();
    j["total_problems"] = r.validation.total_problems;
    nlohmann::ordered_json problems = nlohmann::ordered_json::array();
    for (const Problem& p : r.validation.problems)
        problems.push_back(
            {{"kind", p.kind}, {"message", p.message}, {"hex", p.hex}, {"face", p.face}, {"vertex", p.vertex}});
    j["problems"] = problems;
    return j.dump(indent);
}

std::string quality_to_text(const QualityReport& r) {
    std::ostringstream os;
    char buf[256];
    os << "vertices: " << r.vertices << "\nhexes: " << r.hexes << "\n";
    std::snprintf(buf, sizeof buf, "scaled Jacobian: min %.6g  avg %.6g  inverted (<= 0): %ld\n", r.sj_min, r.sj_avg,
                  r.inverted);
    os << buf << "histogram:\n";
    for (std::size_t b = 0; b < 10; ++b) {
        const double lo = -1.0 + 0.2 * static_cast<double>(b);
        std::snprintf(buf, sizeof buf, "  [%+.1f, %+.1f%c %ld\n", lo, lo + 0.2, b == 9 ? ']' : ')', r.sj_histogram[b]);
        os << buf;
    }
    if (!r.worst_hexes.empty()) {
        os << "worst hexes:";
        for (int h : r.worst_hexes) {
            std::snprintf(buf, sizeof buf, " %d (%.4g)", h, r.sj[static_cast<std::size_t>(h)]);
            os << buf;
        }
        os << "\n";
    }
    os << "euler characteristic (V-E+F-C): " << r.euler_characteristic << "\n";
    os << "boundary: " << r.boundary_components << " component(s), euler characteristic "
       << r.boundary_euler_characteristic << ", genus " << r.boundary_genus << "\n";
    auto valences = [&](const std::map<int, long>& m) {
        if (m.empty()) return std::string("none");
        std::string s;
        for (const auto& [valence, count] : m)
            s += (s.empty() ? "" : ", ") + std::string("valence ") + std::to_string(valence) + ": " +
                 std::to_string(count);
        return s;
    };
    os << "singular interior edges (valence != 4): " << valences(r.singular_interior_edges) << "\n";
    os << "singular boundary edges (valence != 2): " << valences(r.singular_boundary_edges) << "\n";
    os << "valid: " << (r.validation.valid() ? "yes" : "no");
    if (!r.validation.valid()) os << " (" << r.validation.total_problems << " problem(s))";
    os << "\n";
    for (const Problem& p : r.validation.problems) os << "  " << p.kind << ": " << p.message << "\n";
    if (r.validation.total_problems > static_cast<long>(r.validation.problems.size()))
        os << "  ... " << (r.validation.total_problems - static_cast<long>(r.validation.problems.size())) << " more\n";
    return os.str();
}

}  // namespace mesohex
