#pragma once
// The meso-skeleton: curve branches (edges) plus quad leaflets (faces), each vertex with an optional radius.
#include <array>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex {

struct Skeleton {
    std::vector<Vec3> points;
    std::vector<double> radii;  // empty (no radius known) or one per point, > 0
    // Every edge of the skeleton, branch edges and leaflet-face edges alike, each once (i < j not required).
    // Readers guarantee that every side of every face is in this list (formats that omit leaflet edges, like OBJ
    // 'f' lines, get them added by the reader through add_face_edges()).
    std::vector<std::array<int, 2>> edges;
    // Leaflet faces as vertex cycles (quads expected by the mesher; others are rejected at analysis).
    std::vector<std::vector<int>> faces;
    friend bool operator==(const Skeleton&, const Skeleton&) = default;
};

// Appends to s.edges every side of every face that is not already listed (in face order). Returns how many were added.
int add_face_edges(Skeleton& s);

// Cheap exact tests for the repairs that need a configuration (a stage can skip its incidence maps without one).
// A side of k faces counts k times (a face repeating a vertex can count twice on one side).
bool has_side_of_three_faces(const Skeleton& s);  // some face side lies on >= 3 faces (a fan edge)
bool has_edge_off_faces(const Skeleton& s);  // some edge (ends in range, distinct) is the side of no face (a branch)

// Euler characteristic V - E + F of the skeleton as a cell complex (assumes edges are unique).
inline long euler_characteristic(const Skeleton& s) {
    return static_cast<long>(s.points.size()) - static_cast<long>(s.edges.size()) + static_cast<long>(s.faces.size());
}

}  // namespace mesohex
