// METIS k-way partition of the dual graph of a hex mesh. The graph comes from compute_hex_topology (faces numbered
// in order of first appearance), each hex's neighbour list is sorted, so the CSR arrays depend only on the input.
#include "mesohex/post/partition.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <metis.h>
#include <nlohmann/json.hpp>

#include "mesohex/core/error.h"
#include "mesohex/core/topology.h"

namespace mesohex {
namespace {

void check_indices(const HexMesh& mesh) {
    const long n = static_cast<long>(mesh.points.size());
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
        for (int v : mesh.hexes[h])
            if (v < 0 || v >= n)
                throw Error(ErrorCode::InvalidInput,
                            "partition: hex " + std::to_string(h) + " refers to vertex " + std::to_string(v) +
                                " (there are " + std::to_string(n) + " vertices)",
                            {ElementRef::Kind::Hex, static_cast<int>(h)});
}

// The dual graph in METIS' CSR form: neighbours of hex h are adjncy[xadj[h] .. xadj[h + 1]), ascending, each with
// the number of faces the two hexes share as its weight.
struct DualGraph {
    std::vector<idx_t> xadj, adjncy, adjwgt;
};

DualGraph dual_graph(const HexMesh& mesh, const HexTopology& topo) {
    const std::size_t nh = mesh.hexes.size();
    std::vector<std::pair<int, int>> arcs;  // (hex, neighbour), both directions of every shared face
    for (std::size_t f = 0; f < topo.faces.size(); ++f) {
        if (topo.face_hex_count[f] != 2) continue;  // boundary or non-manifold face
        const int a = topo.face_hexes[f][0], b = topo.face_hexes[f][1];
        if (a < 0 || b < 0 || a == b) continue;
        arcs.emplace_back(a, b);
        arcs.emplace_back(b, a);
    }
    std::sort(arcs.begin(), arcs.end());
    DualGraph g;
    g.xadj.assign(nh + 1, 0);
    for (std::size_t i = 0; i < arcs.size();) {
        std::size_t j = i + 1;
        while (j < arcs.size() && arcs[j] == arcs[i]) ++j;
        g.adjncy.push_back(static_cast<idx_t>(arcs[i].second));
        g.adjwgt.push_back(static_cast<idx_t>(j - i));
        ++g.xadj[static_cast<std::size_t>(arcs[i].first) + 1];
        i = j;
    }
    for (std::size_t h = 0; h < nh; ++h) g.xadj[h + 1] += g.xadj[h];
    return g;
}

std::vector<int> run_metis(DualGraph& g, int parts, const PartitionOptions& options) {
    idx_t nvtxs = static_cast<idx_t>(g.xadj.size() - 1), ncon = 1, nparts = parts, objval = 0;
    std::array<idx_t, METIS_NOPTIONS> metis_options{};
    METIS_SetDefaultOptions(metis_options.data());
    metis_options[METIS_OPTION_SEED] = options.seed;
    metis_options[METIS_OPTION_NUMBERING] = 0;
    // METIS' tolerance is in thousandths: 1 + ufactor / 1000 is the allowed largest part over the average one.
    metis_options[METIS_OPTION_UFACTOR] = static_cast<idx_t>(std::lround(options.imbalance_tolerance * 1000.0));
    std::vector<idx_t> part(static_cast<std::size_t>(nvtxs), 0);
    // An empty adjacency (hexes that share no face) still needs a valid pointer.
    if (g.adjncy.empty()) {
        g.adjncy.push_back(0);
        g.adjwgt.push_back(0);
    }
    const int status =
        METIS_PartGraphKway(&nvtxs, &ncon, g.xadj.data(), g.adjncy.data(), nullptr, nullptr, g.adjwgt.data(), &nparts,
                            nullptr, nullptr, metis_options.data(), &objval, part.data());
    if (status != METIS_OK)
        throw Error(ErrorCode::NumericalFailure, "partition: METIS_PartGraphKway failed (status " +
                                                     std::to_string(status) + ") for " + std::to_string(nvtxs) +
                                                     " hexes into " + std::to_string(parts) + " parts");
    return std::vector<int>(part.begin(), part.end());
}

Partition evaluate(const HexTopology& topo, std::size_t num_hexes, std::vector<int> part, int parts) {
    if (parts < 1) throw Error(ErrorCode::InvalidInput, "partition: " + std::to_string(parts) + " parts (need >= 1)");
    if (part.size() != num_hexes)
        throw Error(ErrorCode::InvalidInput, "partition: " + std::to_string(part.size()) + " part ids for " +
                                                 std::to_string(num_hexes) + " hexes");
    Partition r;
    r.parts = parts;
    r.part_sizes.assign(static_cast<std::size_t>(parts), 0);
    for (std::size_t h = 0; h < part.size(); ++h) {
        if (part[h] < 0 || part[h] >= parts)
            throw Error(ErrorCode::InvalidInput,
                        "partition: hex " + std::to_string(h) + " has part " + std::to_string(part[h]) +
                            " (parts are 0.." + std::to_string(parts - 1) + ")",
                        {ElementRef::Kind::Hex, static_cast<int>(h)});
        ++r.part_sizes[static_cast<std::size_t>(part[h])];
    }
    for (std::size_t f = 0; f < topo.faces.size(); ++f) {
        if (topo.face_hex_count[f] != 2) continue;
        const int a = topo.face_hexes[f][0], b = topo.face_hexes[f][1];
        if (a >= 0 && b >= 0 && part[static_cast<std::size_t>(a)] != part[static_cast<std::size_t>(b)]) ++r.edge_cut;
    }
    if (num_hexes > 0) {
        const long largest = *std::max_element(r.part_sizes.begin(), r.part_sizes.end());
        r.imbalance = static_cast<double>(largest) * parts / static_cast<double>(num_hexes) - 1.0;
    }
    r.part = std::move(part);
    return r;
}

}  // namespace

Partition evaluate_partition(const HexMesh& mesh, std::vector<int> part, int parts) {
    check_indices(mesh);
    return evaluate(compute_hex_topology(mesh), mesh.hexes.size(), std::move(part), parts);
}

Partition partition_hexes(const HexMesh& mesh, const PartitionOptions& options) {
    const int parts = options.parts;
    const long nh = static_cast<long>(mesh.hexes.size());
    if (parts < 1) throw Error(ErrorCode::InvalidInput, "partition: " + std::to_string(parts) + " parts (need >= 1)");
    if (parts > nh)
        throw Error(ErrorCode::InvalidInput, "partition: cannot split " + std::to_string(nh) + " hexes into " +
                                                 std::to_string(parts) + " non-empty parts");
    if (!(options.imbalance_tolerance >= 0.001 && options.imbalance_tolerance <= 10.0))
        throw Error(ErrorCode::InvalidInput, "partition: imbalance tolerance " +
                                                 std::to_string(options.imbalance_tolerance) + " outside [0.001, 10]");
    check_indices(mesh);
    const HexTopology topo = compute_hex_topology(mesh);
    std::vector<int> part(mesh.hexes.size(), 0);
    if (parts > 1) {
        DualGraph g = dual_graph(mesh, topo);
        part = run_metis(g, parts, options);
    }
    return evaluate(topo, mesh.hexes.size(), std::move(part), parts);
}

std::string partition_to_json(const Partition& partition, int indent) {
    nlohmann::json j;
    j["parts"] = partition.parts;
    j["edge_cut"] = partition.edge_cut;
    j["imbalance"] = partition.imbalance;
    j["part_sizes"] = partition.part_sizes;
    return j.dump(indent);
}

std::string partition_to_text(const Partition& partition) {
    long smallest = 0, largest = 0;
    if (!partition.part_sizes.empty()) {
        smallest = *std::min_element(partition.part_sizes.begin(), partition.part_sizes.end());
        largest = *std::max_element(partition.part_sizes.begin(), partition.part_sizes.end());
    }
    char buf[200];
    std::snprintf(buf, sizeof buf, "partition: %d parts, sizes %ld..%ld hexes, imbalance %.2f %%, edge cut %ld faces\n",
                  partition.parts, smallest, largest, 100.0 * partition.imbalance, partition.edge_cut);
    return buf;
}

}  // namespace mesohex
