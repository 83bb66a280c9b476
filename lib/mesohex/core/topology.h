#pragma once
// Derived topology of a hex mesh, computed by a function (never maintained). Deterministic: element order depends only
// on the input arrays, never on hash-table iteration order.
#include <array>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct HexTopology {
    // Unique quad faces. faces[f] is the quad as seen from its first hex (outward from face_hexes[f][0]).
    std::vector<std::array<int, 4>> faces;
    // The (at most two, in well-formed meshes) hexes of each face; -1 when absent. face_hexes[f][0] is never -1.
    std::vector<std::array<int, 2>> face_hexes;
    // Number of hexes that contain each face (> 2 means non-manifold; kept so validation can report it).
    std::vector<int> face_hex_count;
    // Per hex, its 6 face ids in kHexFaces order.
    std::vector<std::array<int, 6>> hex_faces;
    // Unique edges (v0 < v1), and the number of hexes around each (valence).
    std::vector<std::array<int, 2>> edges;
    std::vector<int> edge_valence;
    std::vector<bool> edge_on_boundary;  // edge belongs to a boundary quad
    // Per hex, its 12 edge ids in kHexEdges order.
    std::vector<std::array<int, 12>> hex_edges;
    // Boundary quads (faces with one hex), oriented outward from the mesh, and the face id each one comes from.
    std::vector<std::array<int, 4>> boundary_quads;
    std::vector<int> boundary_face;
};

// O(#hexes log #hexes). Works on any input with indices in range (validation reports the rest).
HexTopology compute_hex_topology(const HexMesh& mesh);

// Per vertex v, the hexes that use it in ascending order: hexes[begin[v]] .. hexes[begin[v + 1] - 1] (CSR).
// Preconditions: indices in range. O(#hexes).
struct VertexHexes {
    std::vector<int> begin;  // #vertices + 1 entries
    std::vector<int> hexes;
};
VertexHexes vertex_hexes(const HexMesh& mesh);

// The boundary surface as a quad mesh with its own compact vertex numbering; vertex_of[i] is the hex-mesh vertex of
// boundary vertex i.
struct BoundarySurface {
    QuadMesh surface;
    std::vector<int> vertex_of;
};
BoundarySurface extract_boundary(const HexMesh& mesh, const HexTopology& topo);

// Per vertex (num_points of them), the vertices joined to it by a boundary edge (edge_on_boundary), in edge order.
std::vector<std::vector<int>> boundary_edge_neighbours(const HexTopology& topo, std::size_t num_points);

// boundary_edge_neighbours(compute_hex_topology(mesh), mesh.points.size()) for the listed vertices only, without the
// whole mesh's topology: per mesh vertex, empty unless listed in `vertices`; a listed vertex gets the same neighbours
// in
// ascending order without repeats (a degenerate edge from v to itself gives v once). A face with v is on the boundary
// when no other (hex, local face) slot has its vertex set, and every such slot is in a hex with v, so only the hexes
// around v are read. O(#hexes) for the vertex -> hex table plus a few hundred operations per listed vertex (the
// listed vertices in parallel: the same result for any thread count). Preconditions: indices in range.
std::vector<std::vector<int>> boundary_edge_neighbours(const HexMesh& mesh, const std::vector<int>& vertices);

}  // namespace mesohex
