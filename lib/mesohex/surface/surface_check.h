#pragma once
// Checks and repairs of a triangle surface (the domain surface, or a thickened skeleton): closedness, edge and vertex
// manifoldness, orientation, connected components, genus, signed volume. Pure combinatorics + doubles, no CGAL.
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct SurfaceComponent {
    int vertices = 0, edges = 0, triangles = 0;
    bool closed = false;       // every edge of the component in exactly two triangles
    bool manifold = false;     // edge- and vertex-manifold
    bool oriented = false;     // every two-triangle edge traversed in opposite directions
    int genus = -1;            // (2 - V + E - F) / 2 when closed, manifold and oriented; -1 otherwise
    double signed_volume = 0;  // > 0: normals point outward (triangles counter-clockwise seen from outside)
};

struct SurfaceCheck {
    int vertices = 0, edges = 0, triangles = 0;
    int unreferenced_vertices = 0;  // vertices that no triangle uses (tolerated)
    int degenerate_triangles = 0;   // a vertex index repeated in one triangle (ignored by every other count)
    int boundary_edges = 0;         // edges in exactly one triangle
    int non_manifold_edges = 0;     // edges in three or more triangles
    int non_manifold_vertices = 0;  // referenced vertices whose triangles form more than one fan
    int inconsistent_edges = 0;     // two-triangle edges traversed twice in the same direction
    bool closed = false, edge_manifold = false, vertex_manifold = false, consistently_oriented = false;
    double signed_volume = 0;                  // sum over the components
    std::vector<SurfaceComponent> components;  // vertex-connected components, ordered by their smallest triangle id
    std::vector<int> triangle_component;       // per triangle (-1 for degenerate triangles)

    // Closed, edge- and vertex-manifold, consistently oriented, no degenerate triangle.
    bool is_closed_manifold() const {
        return closed && edge_manifold && vertex_manifold && consistently_oriented && degenerate_triangles == 0;
    }
};

// Checks `mesh`. Indices out of range throw InvalidInput naming the triangle. O(F log F).
SurfaceCheck check_surface(const TriangleMesh& mesh);

struct OrientResult {
    int flipped_triangles = 0;        // total triangles whose orientation was reversed
    int reoriented_components = 0;    // components made consistently oriented (some triangles flipped)
    int inverted_components = 0;      // closed components flipped as a whole because they faced the wrong way
    int unorientable_components = 0;  // non-manifold edges or a Moebius-like component: left as they were
};

// Makes every edge-manifold component consistently oriented (propagation from its first triangle), then flips every
// closed component that faces the wrong way: a closed component nested inside an even number of other closed
// components must have a positive signed volume (it bounds the domain from outside), one nested inside an odd
// number (a cavity) a negative one. Nesting is decided with the generalized winding number. Open components are
// only made consistent. aorta.stl (inward-facing) gets all its triangles flipped. O(F log F + C x F).
OrientResult orient_outward(TriangleMesh& mesh);

// Removes the vertices that no triangle uses; returns old_to_new (-1 for removed vertices). Order is kept.
std::vector<int> remove_unreferenced_vertices(TriangleMesh& mesh);

}  // namespace mesohex
