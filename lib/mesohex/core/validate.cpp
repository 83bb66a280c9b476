// Structural validation of a hex mesh. Checks run in a fixed order; each problem names its element.
#include "mesohex/core/validate.h"

#include <algorithm>
#include <cstdint>
#include <string>

#include "mesohex/core/hex_convention.h"
#include "mesohex/core/topology.h"

namespace mesohex {
namespace {

constexpr std::size_t kMaxListedProblems = 200;

void add(ValidationReport& report, Problem p) {
    ++report.total_problems;
    if (report.problems.size() < kMaxListedProblems) report.problems.push_back(std::move(p));
}

std::string quad_text(const std::array<int, 4>& q) {
    std::string s = "(";
    for (std::size_t i = 0; i < 4; ++i) {
        s += std::to_string(q[i]);
        s += i < 3 ? ' ' : ')';
    }
    return s;
}

// The quad of hex h at local face lf, outward from h.
std::array<int, 4> local_quad(const HexMesh& mesh, int h, int lf) {
    std::array<int, 4> q;
    for (int i = 0; i < 4; ++i)
        q[static_cast<std::size_t>(i)] =
            mesh.hexes[static_cast<std::size_t>(h)]
                      [static_cast<std::size_t>(kHexFaces[static_cast<std::size_t>(lf)][static_cast<std::size_t>(i)])];
    return q;
}

// +1: b is a cyclic rotation of a; -1: b is a cyclic rotation of a reversed; 0: neither (a twisted face).
int cyclic_relation(const std::array<int, 4>& a, const std::array<int, 4>& b) {
    for (std::size_t k = 0; k < 4; ++k) {
        if (b[k] != a[0]) continue;
        if (b[(k + 1) % 4] == a[1] && b[(k + 2) % 4] == a[2] && b[(k + 3) % 4] == a[3]) return 1;
        if (b[(k + 1) % 4] == a[3] && b[(k + 2) % 4] == a[2] && b[(k + 3) % 4] == a[1]) return -1;
        return 0;
    }
    return 0;
}

ValidationReport validate_impl(const HexMesh& mesh, const HexTopology* given_topo) {
    ValidationReport report;
    const int num_points = static_cast<int>(mesh.points.size());
    const int num_hexes = static_cast<int>(mesh.hexes.size());

    if (num_hexes == 0) add(report, {"empty_mesh", "the mesh has no hexahedra", -1, -1, -1});

    // Coordinates.
    for (int v = 0; v < num_points; ++v) {
        if (!is_finite(mesh.points[static_cast<std::size_t>(v)]))
            add(report, {"non_finite_coordinate", "vertex " + std::to_string(v) + " has a NaN or infinite coordinate",
                         -1, -1, v});
    }

    // Indices, distinct corners, vertex use.
    bool indices_ok = true;
    std::vector<char> used(static_cast<std::size_t>(num_points), 0);
    for (int h = 0; h < num_hexes; ++h) {
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(h)];
        bool hex_ok = true;
        for (int lv = 0; lv < 8; ++lv) {
            const int v = hex[static_cast<std::size_t>(lv)];
            if (v < 0 || v >= num_points) {
                add(report, {"index_out_of_range",
                             "hex " + std::to_string(h) + " corner " + std::to_string(lv) + " refers to vertex " +
                                 std::to_string(v) + ", but there are " + std::to_string(num_points) + " vertices",
                             h, -1, v});
                hex_ok = false;
            } else {
                used[static_cast<std::size_t>(v)] = 1;
            }
        }
        indices_ok = indices_ok && hex_ok;
        std::array<int, 8> sorted = hex;
        std::sort(sorted.begin(), sorted.end());
        bool has_repeat = false;
        int repeated = -1;
        for (std::size_t i = 0; i + 1 < 8; ++i)
            if (sorted[i] == sorted[i + 1]) {
                has_repeat = true;
                repeated = sorted[i];
            }
        if (has_repeat)
            add(report, {"repeated_corner",
                         "hex " + std::to_string(h) + " uses vertex " + std::to_string(repeated) + " more than once", h,
                         -1, repeated});
    }
    for (int v = 0; v < num_points; ++v) {
        if (!used[static_cast<std::size_t>(v)])
            add(report, {"unused_vertex", "vertex " + std::to_string(v) + " is not used by any hex", -1, -1, v});
    }
    if (!indices_ok) return report;  // face and edge checks need every index in range

    // Faces.
    HexTopology computed;
    if (!given_topo) computed = compute_hex_topology(mesh);
    const HexTopology& topo = given_topo ? *given_topo : computed;
    for (int f = 0; f < static_cast<int>(topo.faces.size()); ++f) {
        const std::size_t fu = static_cast<std::size_t>(f);
        const int count = topo.face_hex_count[fu];
        const int h0 = topo.face_hexes[fu][0];
        if (count > 2) {
            add(report, {"nonmanifold_face",
                         "face " + std::to_string(f) + " " + quad_text(topo.faces[fu]) + " is shared by " +
                             std::to_string(count) + " hexes (first: hex " + std::to_string(h0) + ")",
                         h0, f, -1});
            continue;
        }
        if (count != 2) continue;
        const int h1 = topo.face_hexes[fu][1];
        int lf1 = -1;
        for (int lf = 0; lf < 6; ++lf)
            if (topo.hex_faces[static_cast<std::size_t>(h1)][static_cast<std::size_t>(lf)] == f) lf1 = lf;
        const std::array<int, 4> seen_from_h1 = local_quad(mesh, h1, lf1);
        const int relation = cyclic_relation(topo.faces[fu], seen_from_h1);
        if (relation == 1) {
            add(report, {"same_orientation_face",
                         "interior face " + std::to_string(f) + " " + quad_text(topo.faces[fu]) +
                             " has the same orientation in hex " + std::to_string(h0) + " and hex " +
                             std::to_string(h1) + " (one of them is inverted or mis-numbered)",
                         h1, f, -1});
        } else if (relation == 0) {
            add(report, {"twisted_face",
                         "interior face " + std::to_string(f) + " is " + quad_text(topo.faces[fu]) + " in hex " +
                             std::to_string(h0) + " but " + quad_text(seen_from_h1) + " in hex " + std::to_string(h1) +
                             " (different vertex cycles)",
                         h1, f, -1});
        }
    }

    // Boundary: every boundary edge on exactly two boundary quads.
    std::vector<int> boundary_uses(topo.edges.size(), 0);
    std::vector<int> first_face(topo.edges.size(), -1);
    for (std::size_t b = 0; b < topo.boundary_quads.size(); ++b) {
        const int f = topo.boundary_face[b];
        const int h = topo.face_hexes[static_cast<std::size_t>(f)][0];
        int lf0 = -1;
        for (int lf = 0; lf < 6; ++lf)
            if (topo.hex_faces[static_cast<std::size_t>(h)][static_cast<std::size_t>(lf)] == f) lf0 = lf;
        for (const int le : kHexFaceSideEdges[static_cast<std::size_t>(lf0)]) {
            const std::size_t e =
                static_cast<std::size_t>(topo.hex_edges[static_cast<std::size_t>(h)][static_cast<std::size_t>(le)]);
            ++boundary_uses[e];
            if (first_face[e] < 0) first_face[e] = f;
        }
    }
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        if (boundary_uses[e] == 0 || boundary_uses[e] == 2) continue;
        const int f = first_face[e];
        add(report,
            {"nonmanifold_boundary_edge",
             "boundary edge (" + std::to_string(topo.edges[e][0]) + " " + std::to_string(topo.edges[e][1]) +
                 ") lies on " + std::to_string(boundary_uses[e]) + " boundary quads instead of 2 (e.g. boundary face " +
                 std::to_string(f) + " of hex " + std::to_string(topo.face_hexes[static_cast<std::size_t>(f)][0]) + ")",
             topo.face_hexes[static_cast<std::size_t>(f)][0], f, topo.edges[e][0]});
    }
    return report;
}

}  // namespace

ValidationReport validate(const HexMesh& mesh) { return validate_impl(mesh, nullptr); }
ValidationReport validate(const HexMesh& mesh, const HexTopology& topo) { return validate_impl(mesh, &topo); }

}  // namespace mesohex
