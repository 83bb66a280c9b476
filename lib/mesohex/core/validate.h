#pragma once
// Structural validation of a hex mesh: every problem found, each naming the hex or face it concerns.
#include <string>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct Problem {
    std::string kind;     // short machine-readable tag, e.g. "index_out_of_range", "nonmanifold_face"
    std::string message;  // human-readable, names the element
    int hex = -1;
    int face = -1;  // face id in compute_hex_topology, or -1
    int vertex = -1;
};

struct ValidationReport {
    std::vector<Problem> problems;  // capped at a few hundred entries; total_problems counts all
    long total_problems = 0;
    bool valid() const { return total_problems == 0; }
};

// Checks: indices in range, 8 distinct corners, each face on at most two hexes, interior faces seen with opposite
// orientations from their two hexes, boundary a closed 2-manifold (each boundary edge on exactly two boundary quads),
// no unused vertex, no NaN/Inf coordinate.
ValidationReport validate(const HexMesh& mesh);

// The same checks, reusing `topo` = compute_hex_topology(mesh) when the caller has it already (it is only used when
// every index is in range).
struct HexTopology;
ValidationReport validate(const HexMesh& mesh, const HexTopology& topo);

}  // namespace mesohex
