#pragma once
// Virtual branches at branching points whose branch directions leave a large empty cap (the paper's §4 suggestion,
// design note ../shared/design/beyond-the-paper.md section E). At a branching point c (branch edges only, degree 3 to
// 5) the covering radius alpha = max over the unit sphere of the angle to the nearest branch direction is measured on a
// Fibonacci grid; while alpha > max_cap_deg (a partition quad would reach past 90 degrees from its own direction, e.g.
// every direction inside a cone of half-angle < 80 degrees) and the degree is below max_degree, a one-edge virtual
// branch is added along v = the grid point realising alpha: a new extremity vertex at c + length_factor x r_c x v
// with radius r_c and the edge (c, it). The raw mesh then gives it its quad in c's sphere partition and one chunk (4
// hexes) to a cap section at c + r v whose faces are extremity faces (padding covers them like any extremity cap).
// A skeleton edit made after adaptation (adaptation would collapse the short edge), before the analysis of the
// meshed skeleton; predicted counts follow from the standard formula (+4 hexes per virtual branch).
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/stages/compatible_blocks.h"

namespace mesohex {

struct VirtualBranchOptions {
    bool enabled = false;        // off by default: measured in docs/blocks.md ("Virtual branches")
    double max_cap_deg = 100;    // covering radius (degrees) above which a virtual branch is added
    int max_degree = 6;          // no virtual branch once the degree (real + virtual) reaches this
    double length_factor = 1.0;  // virtual edge length, x the branching point's radius (dimensionless)
    int grid_points = 512;       // Fibonacci grid on the sphere for the covering radius (deterministic)
    // Pit branches (issue 16 item 1), independent of `enabled`: at a branching point c of degree >= pit_min_degree
    // whose branches stand in a ring (e.g. four limbs in a cone around a torso's end), the directions farthest from
    // their nearest branches inside the ring are the Voronoi vertices of the branch directions on the sphere (a
    // direction equidistant from three branches, none nearer). The sphere partition puts a point of valence 3 or 4
    // there (6 or 8 hexes around its interior edge to c) on c's sphere, while the union of the branches' tubes (the
    // domain) reaches on to their crotch: a pit the padding and the fit fill by folding the layer. Where the ray
    // c + t v along such a vertex v (at most pit_max_deg from its branches) leaves the union of the domain
    // skeleton's balls at t >= (1 + pit_excess) r_c, a one-edge branch along v gets the pit: its quad takes the
    // partition point's place and its chunk (4 hexes) reaches a cap section at c + (t - pit_inset r_c) v, radius
    // r_c (the raw mesh's margins narrow it to the quad). One per branching point (the vertex with the farthest
    // exit). Dimensionless; pit_excess 0 = off (the default: docs/junctions.md, "Pit branches").
    double pit_excess = 0;
    int pit_min_degree = 4;   // only branching points with at least this many branch edges
    double pit_max_deg = 70;  // degrees
    double pit_inset = 0.25;  // x r_c: the cap stays this far inside the exit (one padding layer)
};

struct VirtualBranches {
    std::vector<int> at;  // per virtual branch: its branching point (vertex of the skeleton given)
};

// Covering radius (degrees) of unit directions `dirs` on a Fibonacci grid of `grid_points` points, and the grid point
// realising it (`far`; the first in grid order on ties). Empty dirs: 180 and the first grid point.
double covering_radius_deg(const std::vector<Vec3>& dirs, int grid_points, Vec3* far);

// Adds virtual branches to `s` in place (new vertices and edges appended, in vertex order of the branching points).
// Preconditions: radii filled (one > 0 per vertex). Vertices with a leaflet face or a non-branch edge are skipped, and
// with `blocks` (may be null) those whose directions fit_cube_frame accepts (a compatible block has no empty-cap
// problem: its free cube faces stay boundary, and a virtual branch would break the cube fit).
// V - E + F unchanged (one vertex and one edge each). Deterministic. O(V x grid_points x degree).
// domain (may be null: no pit branch): the skeleton whose balls make the domain (the input), one radius per point.
VirtualBranches add_virtual_branches(Skeleton& s, const VirtualBranchOptions& options,
                                     const CompatibleBlockOptions* blocks = nullptr, const Skeleton* domain = nullptr);

}  // namespace mesohex
