#pragma once
// Fidelity of a mesh boundary to the domain surface: two-sided Hausdorff distance estimated by sampling. Uses
// SurfaceQuery (CGAL AABB tree) for the closest-point queries in both directions.
#include "mesohex/core/hex_mesh.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex {

struct SurfaceDistanceOptions {
    int face_subdivision = 3;  // samples per face: the barycentric grid of step 1/n on every triangle (quads are
                               // split in two): vertices, edge points and interior points; n = 1 samples the
                               // vertices only (plus one centre per face)
};

struct SurfaceDistance {
    double mesh_to_surface_max = 0, mesh_to_surface_mean = 0;  // max over the samples of the mesh boundary, mean
    double surface_to_mesh_max = 0, surface_to_mesh_mean = 0;  // over its vertices; the same for the domain surface
    Vec3 mesh_to_surface_at{};                                 // the mesh boundary sample farthest from the surface
    Vec3 surface_to_mesh_at{};                                 // the surface sample farthest from the mesh boundary
    double max = 0;                                            // two-sided Hausdorff distance: max of both maxima
    double mean = 0;                             // average of the two means (each unweighted over its samples)
    double diagonal = 0;                         // bounding-box diagonal of the domain surface
    double relative_max = 0;                     // max / diagonal
    double relative_mean = 0;                    // mean / diagonal
    long mesh_samples = 0, surface_samples = 0;  // samples the maxima stand for (not all of them are queried)
};

// Two-sided distance between `boundary` (e.g. the boundary quads of a hex mesh; quad (a, b, c, d) is split into
// (a, b, c) and (a, c, d)) and the surface of `domain`. Every sample's distance to the other side is exact (closest
// point on the triangles); the maxima are lower bounds of the true Hausdorff distance that converge as
// face_subdivision grows. The vertices are measured first; a triangle sample is measured only when the vertex
// distances and the 1-Lipschitz bound do not already rule it out as the largest (the maxima are those of all samples,
// at a fraction of the queries: O(vertices + samples near the farthest places) queries, each starting from the
// triangle its predecessor found). Preconditions: both surfaces have a non-degenerate triangle (InvalidInput
// otherwise). Parallel, deterministic. O((S_mesh + S_surface) log F).
SurfaceDistance surface_distance(const QuadMesh& boundary, const SurfaceQuery& domain,
                                 const SurfaceDistanceOptions& options = {});
SurfaceDistance surface_distance(const TriangleMesh& boundary, const SurfaceQuery& domain,
                                 const SurfaceDistanceOptions& options = {});

}  // namespace mesohex
