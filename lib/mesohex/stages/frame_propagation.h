#pragma once
// Paper step 4: geometry propagation. Rotation-minimizing frames (double reflection, Wang et al. 2008) along every
// branch from its constrained end(s) (branching points, BL-joints, leaflet vertices rooting a branch); at a
// second constrained end the far quad is relabelled by quarter turns to the closest match and the remaining angular
// defect (|defect| <= 45 degrees) is distributed over all joints of the branch in proportion to arc length (an edge
// ending on a compatible block takes no share while the branch has other edges). Branches
// without a constrained end (isolated polylines, closed rings) start from a free frame. The frames place the
// extremity and joint connection surfaces.
#include <array>
#include <cstdint>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/core/vec.h"
#include "mesohex/stages/connection_surfaces.h"
#include "mesohex/stages/junction_geometry.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

struct BranchFrames {
    // Per skeleton edge and side (0: edges[e][0], 1: edges[e][1]): the frame at that endpoint (t into the edge).
    std::vector<std::array<Frame, 2>> edge_frames;
    // Per skeleton edge and side: start rotation of the registered quad: the quad's vertex k "from its start" is
    // quads[q][(rotation + k) % 4]. Chosen so that the quads at both ends of an edge correspond as
    // b_j = a_{(2 - j) mod 4} (reference-notes §8.1).
    std::vector<std::array<std::uint8_t, 2>> edge_rotation;
    // Unit direction of every connection-surface point (same indexing as ConnectionSurfaces::directions), complete:
    // branching points copied, extremities and joints set from the frames.
    std::vector<Vec3> directions;
    // Per branch: the angular defect (radians, in [-pi/4, pi/4]) distributed along it; 0 for one-way branches.
    std::vector<double> branch_defect;
};

struct FrameOptions {};

// Preconditions: analysis and surfaces built from `skeleton`. Postconditions: every frame is orthonormal and finite
// (degenerate tangents fall back to the incoming direction, never NaN); at a joint the frames on its two edges are
// reversed copies (r, -s, -t) of each other, except at a ring's artificial start joint, where the closing edge gets
// the quarter-turn-snapped frame of the start quad. Parallel over branches (oneTBB), deterministic. O(branch edges).
BranchFrames propagate_frames(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                              const ConnectionSurfaces& surfaces, const FrameOptions& options = {});

}  // namespace mesohex
