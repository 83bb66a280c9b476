#pragma once
// Procedural meso-skeletons: small parametric shapes (plates, shells, fans, a hand, a chair, a bird, twisted strips,
// a frame, a turbine) used as test inputs and README examples. Each one is a configuration the paper supports:
//   - no branch on a leaflet interior vertex, no fan edge ending inside a leaflet, no branch at a fan-edge vertex;
//   - BL-joints only at convex (~90°) leaflet corners, the branch leaving roughly along the outward corner diagonal;
//   - leaflet edges about 2-4x the local radius (default radii are about 0.3 x the leaflet edge length).
// Postconditions of generate_skeleton(): radii set (> 0, one per point); faces are quads (4 distinct vertices),
// consistently oriented within each leaflet (every edge shared by exactly two faces is traversed in opposite
// directions by them); every face side is in `edges`; no duplicate edge; no unused vertex. The output depends only on
// the name and the options (deterministic).
#include <string>
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex {

struct GeneratorOptions {
    int n = 0;                  // main resolution (meaning per shape, see generator_help()); 0 = the shape's default
    int m = 0;                  // second resolution (meaning per shape); 0 = the shape's default
    int quarter_turns = -1;     // twist, torustwist: rotation of the cross-section over the shape, in quarter turns
                                // (90°); -1 = the shape's default (2, i.e. 180°)
    double edge_length = 1.0;   // overall scale: the typical leaflet edge length
    double radius_scale = 1.0;  // multiplies every radius
};

// The valid shape names, in a fixed order: plate, box, torus, tfan, xfan, hand, chair, bird, twist, torustwist,
// dualocta, turbine.
std::vector<std::string> generator_names();

// One line describing the shape and what n, m (and quarter_turns) mean for it, with their defaults.
// Unknown name -> Error(InvalidInput) listing the valid names.
std::string generator_help(const std::string& name);

// Builds the named skeleton. Unknown name or out-of-range options -> Error(InvalidInput) (the message lists the valid
// names, or the valid range of the option). O(size of the output).
Skeleton generate_skeleton(const std::string& name, const GeneratorOptions& options = {});

}  // namespace mesohex
