#pragma once
// Medial mesh (curve edges + triangle sheets, e.g. read from a .ma file) -> meso-skeleton (curve branches + quad
// leaflets). Method (docs/skeletons.md):
//   1. sheets = triangles connected through shared edges; a sheet with fewer than min_sheet_triangles triangles or an
//      area below min_sheet_area_factor x (its mean radius)^2 collapses to a curve: a new vertex at its centroid,
//      joined to each sheet vertex that has an attachment (a curve edge or another sheet); unattached sheet vertices
//      are dropped;
//   2. leaflets = triangles connected through manifold edges (edges in exactly two triangles); edges in three or more
//      triangles are fan edges between leaflets; each leaflet is oriented consistently (breadth-first flips);
//   3. adjacent triangles of a leaflet are paired greedily into quads, best shape first (corner angles closest to
//      90 degrees, small fold); every face (pair quad or lone triangle) is then split at its centroid and its edge
//      midpoints into 4 or 3 quads that share the midpoints: an all-quad, conforming subdivision of every sheet;
//   4. curve edges (in no triangle) stay branch edges. Radii are kept at input vertices, averaged at new ones.
// The Euler characteristic V - E + F is preserved by pairing, splitting and by collapsing a sheet whose vertices are
// all attached.
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex {

struct MedialImportOptions {
    int min_sheet_triangles = 2;          // sheets with fewer triangles collapse to a curve
    double min_sheet_area_factor = 1.0;   // sheets with area < factor x (mean vertex radius)^2 collapse to a curve
    bool pair_triangles = true;           // pair triangles into quads before splitting (fewer irregular vertices)
    double max_pair_corner_deviation_deg = 60;  // a pair quad is accepted if every corner is within this of 90 deg
    double max_pair_fold_deg = 45;        // ... and the two triangle normals differ by at most this angle
};

struct MedialImport {
    Skeleton skeleton;                // all faces are quads; every face side is in edges; radii one per point
    std::vector<int> face_leaflet;    // per output face, its leaflet id (0..leaflets-1); faces of one leaflet are
                                      // consistently oriented
    int sheets = 0;                   // triangle sheets in the input (components through shared edges)
    int collapsed_sheets = 0;
    int leaflets = 0;
    int paired_quads = 0;             // triangle pairs merged into a quad before splitting
    int split_triangles = 0;          // triangles left unpaired (each split into 3 quads)
    int fan_edges = 0;                // input edges in 3 or more triangles (each becomes 2 fan edges when split)
};

// Preconditions (checked, InvalidInput naming the element): radii present (one per point, > 0), every face a
// triangle with 3 distinct in-range vertices, edges in range with distinct ends and no duplicate, every triangle
// side in edges. UnsupportedConfiguration if a leaflet is not orientable (a Moebius band).
// Complexity: O((V + E + F) log(V + E + F)).
MedialImport import_medial_mesh(const Skeleton& medial, const MedialImportOptions& options = {});

}  // namespace mesohex
