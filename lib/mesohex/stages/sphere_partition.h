#pragma once
// Quad partition of the unit sphere with one quad per given direction (paper step 3, the "connection surface" at a
// branching point; VKB21's convex hull + valence-4 remeshing + dual, made robust).
#include <array>
#include <string>
#include <vector>

#include "mesohex/core/vec.h"

namespace mesohex {

struct SpherePartition {
    std::vector<Vec3> points;                // unit vectors (the connection-surface vertices, centre at the origin)
    std::vector<std::array<int, 4>> quads;   // quads[i] belongs to direction i; counter-clockwise seen from outside
};

struct SpherePartitionOptions {
    // Directions closer than this to a common great circle (max |dot(d, n)| for the best-fit plane normal n) are
    // treated as planar and get the "orange" partition (lunes between two poles).
    double planarity_tolerance = 0.05;
};

// Preconditions: n >= 2 unit directions (not necessarily distinct in general position; antipodal pairs, clustered
// and coplanar sets allowed). Postconditions (checked by verify_sphere_partition before returning):
//   - quads.size() == n, the quads form a closed genus-0 2-manifold (V - E + F == 2), every edge in two quads with
//     opposite orientations, no repeated vertex in a quad;
//   - each quad i is a convex spherical quad that contains direction i in its interior;
// Throws mesohex::Error(NumericalFailure) if no valid partition could be built (never crashes, never hangs).
SpherePartition partition_sphere(const std::vector<Vec3>& directions, const SpherePartitionOptions& options = {});

// Returns an empty string when `p` satisfies every postcondition above for `directions`, else what is wrong.
std::string verify_sphere_partition(const SpherePartition& p, const std::vector<Vec3>& directions);

}  // namespace mesohex
