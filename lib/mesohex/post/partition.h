#pragma once
// Partitioning a hex mesh for MPI solvers: METIS k-way on the dual graph of the hexes (two hexes are adjacent when
// they share a face). METIS stays inside partition.cpp.
#include <string>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct PartitionOptions {
    int parts = 2;                      // number of parts N, 1 <= N <= #hexes
    int seed = 1;                       // METIS random seed: the same seed gives the same partition
    double imbalance_tolerance = 0.03;  // METIS balance target: largest part <= (1 + this) x #hexes / N
                                        // (METIS' own default, 3 %; small meshes may miss it by one hex)
};

struct Partition {
    int parts = 0;
    std::vector<int> part;         // per hex: its part, 0 .. parts - 1
    std::vector<long> part_sizes;  // hexes per part
    long edge_cut = 0;             // interior faces whose two hexes lie in different parts
    double imbalance = 0;          // largest part / (#hexes / parts) - 1 (0 = perfectly balanced)
};

// METIS_PartGraphKway on the dual graph (edge weight = number of faces two hexes share, so METIS' edge cut equals
// `edge_cut`). Faces of more than two hexes (non-manifold) add no adjacency. parts == 1 puts every hex in part 0
// without calling METIS. Deterministic: the graph depends only on the input arrays, METIS runs serially with a fixed
// seed, so the result is the same for any thread count.
// Errors: InvalidInput when parts < 1, parts > #hexes, or an index is out of range; NumericalFailure when METIS
// fails. Complexity: O(#hexes log #hexes) for the graph, plus METIS (about linear in the graph size).
Partition partition_hexes(const HexMesh& mesh, const PartitionOptions& options = {});

// Sizes, edge cut and imbalance of a given assignment `part` (values 0 .. parts - 1, one per hex), computed from the
// faces of the mesh. Used by partition_hexes and to check partitions read back from files.
// Errors: InvalidInput when part has the wrong size or a value out of range. O(#hexes log #hexes).
Partition evaluate_partition(const HexMesh& mesh, std::vector<int> part, int parts);

// The partition quality as one JSON object (serialised text): {"parts", "edge_cut", "imbalance", "part_sizes"} (the
// per-hex ids are not included). Indent as nlohmann's dump (-1 = one line).
std::string partition_to_json(const Partition& partition, int indent = -1);
// One line: "partition: N parts, sizes a..b hexes, imbalance x %, edge cut c faces".
std::string partition_to_text(const Partition& partition);

}  // namespace mesohex
