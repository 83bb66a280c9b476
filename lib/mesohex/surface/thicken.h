#pragma once
// Thickening: the domain that a skeleton with radii describes, as a closed triangle surface.
// The domain is the union of
//   - a sphere at every skeleton point that no edge or face uses,
//   - a round cone along every edge (convex hull of its two end spheres),
//   - a slab over every face: each quad is split along its shorter diagonal (other polygons into a fan) and every
//     triangle is thickened into the convex hull of its three vertex spheres, which is also the union of the spheres
//     swept over the triangle with the linearly interpolated radius.
// Method: the signed distance of the union (min over primitives, each exact outside and sign-correct inside) is
// sampled on a uniform grid, only inside each primitive's bounding box (+2 cells), in parallel over z-slices; the zero
// level set is extracted by marching tetrahedra (6 Kuhn tetrahedra per cube, a consistent triangulation of the grid),
// which gives a closed, edge- and vertex-manifold surface whose triangles face outward (toward positive values) by
// construction. No CGAL is needed here.
#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"

namespace mesohex {

struct ThickenOptions {
    double radius = 0;                // radius of every point when the skeleton has none (must then be > 0)
    double cells_per_radius = 4;      // grid step = smallest radius / cells_per_radius (4: volume within ~1 %) ...
    long max_grid_points = 1L << 24;  // ... enlarged until the grid has at most this many points (memory: 4 bytes each)
};

struct ThickenStats {
    double cell_size = 0;        // grid step h actually used
    int nx = 0, ny = 0, nz = 0;  // grid points per axis
    int primitives = 0;          // spheres + round cones + triangle slabs
    long evaluations = 0;        // primitive distance evaluations
};

// Preconditions (InvalidInput naming the element otherwise): at least one point; finite points; radii either absent
// (then options.radius > 0) or one per point and > 0; edge / face indices in range; faces with >= 3 vertices.
// Postconditions: a closed, edge- and vertex-manifold, outward-oriented triangle surface (one component per connected
// part of the domain that is thicker than about one grid cell; thinner parts may vanish or break up). The volume
// converges to the union's volume as O(h^2); with the default 4 cells per radius a sphere comes within about 1 %.
// Parallel (oneTBB), deterministic. Time O(sum of primitive box volumes / h^3 + grid points).
TriangleMesh thicken(const Skeleton& skeleton, const ThickenOptions& options = {}, ThickenStats* stats = nullptr);

}  // namespace mesohex
