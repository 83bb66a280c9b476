#pragma once
// Quality report: Verdict's hex scaled Jacobian, topology invariants, singular edges.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/topology.h"
#include "mesohex/core/validate.h"

namespace mesohex {

// Verdict hex_scaled_jacobian: min over the 8 corner frames and the centre principal-axes frame of
// det / (product of the three column lengths). Zero-length column or non-finite value -> -1 (inverted, never perfect).
double scaled_jacobian(const std::array<Vec3, 8>& corners);
std::vector<double> scaled_jacobians(const HexMesh& mesh);  // parallel, deterministic

struct QualityReport {
    long vertices = 0, hexes = 0;
    double sj_min = 0, sj_avg = 0;
    long inverted = 0;                    // hexes with scaled Jacobian <= 0
    std::array<long, 10> sj_histogram{};  // 10 bins over [-1, 1]
    std::vector<int> worst_hexes;         // ids of the (up to) 10 worst hexes, worst first
    long euler_characteristic = 0;        // V - E + F - C
    long boundary_euler_characteristic = 0;
    long boundary_components = 0;
    double boundary_genus = 0;                    // per closed boundary: sum over components of (2 - chi_i) / 2
    std::map<int, long> singular_interior_edges;  // valence -> count (valence != 4)
    std::map<int, long> singular_boundary_edges;  // valence -> count (valence != 2)
    ValidationReport validation;
    std::vector<double> sj;  // per hex
};

QualityReport compute_quality(const HexMesh& mesh);
// The same, also handing over the topology it computed (a caller that needs it too, e.g. the studio drawing the
// singular edges and the boundary, does not compute it twice). `topology` is left empty when a hex has an index out
// of range (no topology is computed then).
QualityReport compute_quality(const HexMesh& mesh, HexTopology& topology);
// The same with the scaled Jacobians a caller already has: `sj` is scaled_jacobians(mesh) (moved into the report), or
// empty (then computed).
QualityReport compute_quality(const HexMesh& mesh, HexTopology& topology, std::vector<double> sj);

// compute_quality(mesh) after only vertices moved (the studio's incremental raw mesh): `old` and `topology` are
// compute_quality(old_mesh, topology)'s. When mesh has the hexes and vertex count of old_mesh, old_mesh was valid and
// every coordinate is finite, the topology and everything read from it are reused and only the scaled Jacobians of
// hexes with a moved corner (bit-wise) are recomputed; otherwise this is compute_quality(mesh). Either way the result
// equals compute_quality(mesh) bit for bit (tests/unit/test_quality.cpp). Cost: O(V + H) plus the moved hexes.
QualityReport update_quality(const QualityReport& old, const HexMesh& old_mesh, const HexMesh& mesh,
                             const HexTopology& topology);

// One JSON object (serialised text) with at least: vertices, hexes, sj_min, sj_avg, inverted, euler_characteristic,
// singular_edges {interior: {valence: count}, boundary: {...}}, valid, problems. Implemented without exposing the
// JSON library in this header.
std::string quality_to_json(const QualityReport& report, int indent = 2);
std::string quality_to_text(const QualityReport& report);

}  // namespace mesohex
