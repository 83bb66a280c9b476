#pragma once
// Radius of every skeleton vertex from its distance to the domain surface (paper §3.1; reference-notes §5.1),
// used when `mesh --surface` is given, plus a check of the skeleton vertices that lie outside the domain.
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex {

struct RadiusFromSurfaceOptions {
    // r(v) = factor x distance(v, surface). 0.5 as in the reference: the raw mesh then fills about half of the
    // inscribed ball, which leaves room for the padding layer that is pushed outward afterwards and for the fitting
    // to reach the surface without inverting boundary hexes. 1 gives the inscribed-ball radius.
    double factor = 0.5;
};

struct RadiusFromSurface {
    std::vector<double> radii;              // one per skeleton point: factor x distance (0 for a point on the surface)
    std::vector<double> distance;           // distance of each skeleton point to the surface
    std::vector<int> outside_vertices;      // skeleton points outside the closed surface, ascending
    std::vector<int> zero_radius_vertices;  // points on the surface (radius 0), ascending
};

// Preconditions: factor > 0 (InvalidInput otherwise); `surface` should be closed for the outside test to mean
// anything. Does not modify the skeleton: the caller decides what to do with outside points (the pipeline reports
// them). Parallel, deterministic. O(V log F).
RadiusFromSurface radius_from_surface(const Skeleton& skeleton, const SurfaceQuery& surface,
                                      const RadiusFromSurfaceOptions& options = {});

}  // namespace mesohex
