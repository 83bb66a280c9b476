#pragma once
// Branch tips the domain does not hold: a branch end whose ball centre lies outside the domain (a `thicken` grid
// coarser than the tip's radii ends the domain before the skeleton), and the chain of such vertices leading to it, is
// trimmed back to the last vertex the domain still holds, which becomes the branch's end. The fit would otherwise pull
// the part outside back onto the nearest surface and crush its hexes (docs/junctions.md, "The armadillo's claw").
// Pure topology on a per-vertex flag: the caller decides what "held" means (mesh.cpp: the centre inside the domain).
#include <vector>

#include "mesohex/core/skeleton.h"

namespace mesohex {

struct TipTrim {
    Skeleton skeleton;            // the input without the trimmed vertices and their edges; the others in input order
    std::vector<int> vertex_map;  // input vertex -> its id in `skeleton`, -1 for a trimmed vertex
    std::vector<int> trimmed;     // input ids of the trimmed vertices, ascending
    std::vector<int> new_ends;    // input ids of the vertices that became branch ends, ascending
};

// held[v] != 0: the domain holds vertex v. A chain is trimmed from a branch end t (degree 1, on no face, not held)
// through the vertices of degree 2 on no face that are not held, when it stops at a held vertex of degree 2 on no face
// (that vertex becomes the end; the branch keeps at least one edge and every branching point and leaflet vertex stays).
// A branch not held up to its branching point or leaflet is left whole (trimming it would change the skeleton's
// topology). Without any trim, `skeleton` is the input and vertex_map the identity. Preconditions: held has one entry
// per point, edges in range (the input analysis checked them). Deterministic. O(V + E + sum of face sizes).
TipTrim trim_unheld_tips(const Skeleton& s, const std::vector<char>& held);

}  // namespace mesohex
