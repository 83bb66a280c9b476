// Sheet subdivision on a per-hex 3 x 3 x 3 lattice: lattice coordinate 0 / 2 are the hex's own corners along an axis,
// 1 is the midpoint (present only if that axis is split). A lattice point with m coordinates equal to 1 is a corner
// (m = 0), an edge midpoint (m = 1), a face centroid (m = 2) or the cell centroid (m = 3); its global id comes from the
// topology element it lies on, so neighbouring hexes agree without any sewing.
#include "mesohex/post/subdivision.h"
#include "mesohex/core/union_find.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"

namespace mesohex {
namespace {

// Local corner of the unit-cube position (x, y, z) in {0, 1}^3 (VTK order).
constexpr int corner_at(int x, int y, int z) {
    constexpr std::array<int, 4> base = {0, 1, 3, 2};  // (x, y) -> 0 (0,0), 1 (1,0), 3 (0,1), 2 (1,1)
    return base[static_cast<std::size_t>(x + 2 * y)] + 4 * z;
}

// The three axis directions of a hex: the local edges parallel to 0-1, 0-3, 0-4.
constexpr std::array<std::array<int, 4>, 3> kAxisEdges = {{{0, 2, 4, 6}, {1, 3, 5, 7}, {8, 9, 10, 11}}};

int local_edge(int a, int b) {
    for (int le = 0; le < 12; ++le)
        if ((kHexEdges[le][0] == a && kHexEdges[le][1] == b) || (kHexEdges[le][0] == b && kHexEdges[le][1] == a))
            return le;
    return -1;
}

int local_face(std::array<int, 4> corners) {
    std::sort(corners.begin(), corners.end());
    for (int lf = 0; lf < 6; ++lf) {
        std::array<int, 4> f = kHexFaces[lf];
        std::sort(f.begin(), f.end());
        if (f == corners) return lf;
    }
    return -1;
}

void check_indices(const HexMesh& mesh, const char* who) { check_hex_indices(mesh, who); }

struct LatticeSlot {
    int kind = 0;   // 0 corner, 1 edge midpoint, 2 face centroid, 3 cell centroid
    int local = 0;  // lv, le or lf
};

// Lattice point (i, j, k) in {0, 1, 2}^3 -> the local hex element it lies on; index i + 3 j + 9 k.
std::array<LatticeSlot, 27> lattice_table() {
    std::array<LatticeSlot, 27> table{};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                const std::array<int, 3> c = {i, j, k};
                std::array<int, 4> corners{};
                int count = 0;
                // Corners of the sub-box: coordinate 1 spans {0, 1}, coordinate 0 / 2 is fixed to 0 / 1.
                for (int z = 0; z < 2; ++z)
                    for (int y = 0; y < 2; ++y)
                        for (int x = 0; x < 2; ++x) {
                            const std::array<int, 3> xyz = {x, y, z};
                            bool inside = true;
                            for (std::size_t a = 0; a < 3; ++a)
                                if (c[a] != 1 && xyz[a] != c[a] / 2) inside = false;
                            if (!inside) continue;
                            if (count < 4) corners[static_cast<std::size_t>(count)] = corner_at(x, y, z);
                            ++count;
                        }
                LatticeSlot& slot = table[static_cast<std::size_t>(i + 3 * j + 9 * k)];
                if (count == 1)
                    slot = {0, corners[0]};
                else if (count == 2)
                    slot = {1, local_edge(corners[0], corners[1])};
                else if (count == 4)
                    slot = {2, local_face(corners)};
                else
                    slot = {3, 0};
            }
    return table;
}

// SubdivisionResult::on_boundary of every output point (cell centroids are interior).
void mark_boundary_points(const HexTopology& topo, const std::vector<int>& edge_point,
                          const std::vector<int>& face_point, SubdivisionResult& result) {
    std::vector<char>& on = result.on_boundary;
    on.assign(result.mesh.points.size(), 0);
    for (const std::array<int, 4>& q : topo.boundary_quads)
        for (int v : q) on[static_cast<std::size_t>(v)] = 1;
    for (std::size_t e = 0; e < topo.edges.size(); ++e)
        if (topo.edge_on_boundary[e] && edge_point[e] >= 0) on[static_cast<std::size_t>(edge_point[e])] = 1;
    for (int f : topo.boundary_face)
        if (face_point[static_cast<std::size_t>(f)] >= 0)
            on[static_cast<std::size_t>(face_point[static_cast<std::size_t>(f)])] = 1;
}

SubdivisionResult split(const HexMesh& mesh, const HexTopology& topo, const std::vector<bool>& edge_split) {
    const std::size_t num_hexes = mesh.hexes.size();
    SubdivisionResult result;
    HexMesh& out = result.mesh;
    out.points = mesh.points;

    std::vector<int> edge_point(topo.edges.size(), -1);
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        if (!edge_split[e]) continue;
        edge_point[e] = static_cast<int>(out.points.size());
        out.points.push_back(0.5 * (mesh.points[static_cast<std::size_t>(topo.edges[e][0])] +
                                    mesh.points[static_cast<std::size_t>(topo.edges[e][1])]));
    }
    // A face gets a centroid when all its 4 edges are split (= both of its directions).
    std::vector<bool> face_split(topo.faces.size(), true);
    for (std::size_t h = 0; h < num_hexes; ++h)
        for (int lf = 0; lf < 6; ++lf)
            for (int i = 0; i < 4; ++i) {
                const int le = local_edge(kHexFaces[lf][i], kHexFaces[lf][(i + 1) % 4]);
                if (!edge_split[static_cast<std::size_t>(topo.hex_edges[h][static_cast<std::size_t>(le)])])
                    face_split[static_cast<std::size_t>(topo.hex_faces[h][static_cast<std::size_t>(lf)])] = false;
            }
    std::vector<int> face_point(topo.faces.size(), -1);
    for (std::size_t f = 0; f < topo.faces.size(); ++f) {
        if (!face_split[f]) continue;
        face_point[f] = static_cast<int>(out.points.size());
        Vec3 c;
        for (int v : topo.faces[f]) c += mesh.points[static_cast<std::size_t>(v)];
        out.points.push_back(c / 4.0);
    }

    std::vector<std::array<bool, 3>> axis_split(num_hexes);
    std::vector<int> cell_point(num_hexes, -1);
    for (std::size_t h = 0; h < num_hexes; ++h) {
        for (int a = 0; a < 3; ++a)
            axis_split[h][static_cast<std::size_t>(a)] =
                edge_split[static_cast<std::size_t>(topo.hex_edges[h][static_cast<std::size_t>(kAxisEdges[a][0])])];
        if (axis_split[h][0] && axis_split[h][1] && axis_split[h][2]) {
            cell_point[h] = static_cast<int>(out.points.size());
            Vec3 c;
            for (int v : mesh.hexes[h]) c += mesh.points[static_cast<std::size_t>(v)];
            out.points.push_back(c / 8.0);
        }
    }

    mark_boundary_points(topo, edge_point, face_point, result);
    const std::array<LatticeSlot, 27> table = lattice_table();
    out.hexes.reserve(num_hexes * 8);
    result.parent_hex.reserve(num_hexes * 8);
    for (std::size_t h = 0; h < num_hexes; ++h) {
        const std::array<int, 8>& hex = mesh.hexes[h];
        auto lattice = [&](int i, int j, int k) -> int {
            const LatticeSlot& slot = table[static_cast<std::size_t>(i + 3 * j + 9 * k)];
            switch (slot.kind) {
                case 0: return hex[static_cast<std::size_t>(slot.local)];
                case 1:
                    return edge_point[static_cast<std::size_t>(
                        topo.hex_edges[h][static_cast<std::size_t>(slot.local)])];
                case 2:
                    return face_point[static_cast<std::size_t>(
                        topo.hex_faces[h][static_cast<std::size_t>(slot.local)])];
                default: return cell_point[h];
            }
        };
        std::array<std::array<int, 3>, 3> ranges{};  // per axis: lattice coordinates of the child boundaries
        std::array<int, 3> segments{};
        for (int a = 0; a < 3; ++a) {
            if (axis_split[h][static_cast<std::size_t>(a)]) {
                ranges[static_cast<std::size_t>(a)] = {0, 1, 2};
                segments[static_cast<std::size_t>(a)] = 2;
            } else {
                ranges[static_cast<std::size_t>(a)] = {0, 2, 2};
                segments[static_cast<std::size_t>(a)] = 1;
            }
        }
        for (int sk = 0; sk < segments[2]; ++sk)
            for (int sj = 0; sj < segments[1]; ++sj)
                for (int si = 0; si < segments[0]; ++si) {
                    const std::array<int, 2> ci = {ranges[0][static_cast<std::size_t>(si)],
                                                   ranges[0][static_cast<std::size_t>(si + 1)]};
                    const std::array<int, 2> cj = {ranges[1][static_cast<std::size_t>(sj)],
                                                   ranges[1][static_cast<std::size_t>(sj + 1)]};
                    const std::array<int, 2> ck = {ranges[2][static_cast<std::size_t>(sk)],
                                                   ranges[2][static_cast<std::size_t>(sk + 1)]};
                    std::array<int, 8> child{};
                    for (int z = 0; z < 2; ++z)
                        for (int y = 0; y < 2; ++y)
                            for (int x = 0; x < 2; ++x)
                                child[static_cast<std::size_t>(corner_at(x, y, z))] =
                                    lattice(ci[static_cast<std::size_t>(x)], cj[static_cast<std::size_t>(y)],
                                            ck[static_cast<std::size_t>(z)]);
                    out.hexes.push_back(child);
                    result.parent_hex.push_back(static_cast<int>(h));
                }
    }
    return result;
}

}  // namespace

SubdivisionResult subdivide_sheets(const HexMesh& mesh, const std::vector<bool>& edge_selected) {
    check_indices(mesh, "subdivide_sheets");
    const HexTopology topo = compute_hex_topology(mesh);
    if (edge_selected.size() != topo.edges.size())
        throw Error(ErrorCode::InvalidInput, "subdivide_sheets: edge_selected has " +
                                                 std::to_string(edge_selected.size()) + " entries, the mesh has " +
                                                 std::to_string(topo.edges.size()) + " edges");
    // Sheets: union of the 4 parallel edges per hex axis.
    UnionFind sheets(static_cast<int>(topo.edges.size()));
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
        for (int a = 0; a < 3; ++a)
            for (int i = 1; i < 4; ++i)
                sheets.unite(topo.hex_edges[h][static_cast<std::size_t>(kAxisEdges[a][0])],
                             topo.hex_edges[h][static_cast<std::size_t>(kAxisEdges[a][i])]);
    std::vector<bool> root_split(topo.edges.size(), false);
    for (std::size_t e = 0; e < topo.edges.size(); ++e)
        if (edge_selected[e]) root_split[static_cast<std::size_t>(sheets.find(static_cast<int>(e)))] = true;
    std::vector<bool> edge_split(topo.edges.size(), false);
    for (std::size_t e = 0; e < topo.edges.size(); ++e)
        edge_split[e] = root_split[static_cast<std::size_t>(sheets.find(static_cast<int>(e)))];
    return split(mesh, topo, edge_split);
}

SubdivisionResult subdivide(const HexMesh& mesh) {
    check_indices(mesh, "subdivide");
    const HexTopology topo = compute_hex_topology(mesh);
    return split(mesh, topo, std::vector<bool>(topo.edges.size(), true));
}

double mean_edge_length(const HexMesh& mesh) {
    check_indices(mesh, "mean_edge_length");
    const HexTopology topo = compute_hex_topology(mesh);
    if (topo.edges.empty()) return 0.0;
    double sum = 0;
    for (const std::array<int, 2>& e : topo.edges)
        sum += distance(mesh.points[static_cast<std::size_t>(e[0])], mesh.points[static_cast<std::size_t>(e[1])]);
    return sum / static_cast<double>(topo.edges.size());
}

int levels_for_size(const HexMesh& mesh, double h) {
    if (!(h > 0) || !std::isfinite(h))
        throw Error(ErrorCode::InvalidInput, "levels_for_size: target size must be a positive finite number");
    double len = mean_edge_length(mesh);
    int levels = 0;
    while (levels < 8 && len > h * (1 + 1e-9)) {
        len *= 0.5;
        ++levels;
    }
    return levels;
}

}  // namespace mesohex
