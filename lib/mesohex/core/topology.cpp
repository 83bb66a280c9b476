// Derived topology of a hex mesh by sorting: every (hex, local face) slot gets its sorted vertex quadruple as a key,
// slots with equal keys are one face; the same for edges with sorted vertex pairs. Ids are given in order of first
// appearance (hex by hex, local element by local element), so they depend only on the input arrays.
#include "mesohex/core/topology.h"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"

namespace mesohex {
namespace {

// Slot ids sorted by (key, slot): a least-significant-digit radix sort, one stable counting sort per key component
// from the last to the first, each O(#slots + num_buckets). Keys are vertex ids in [0, num_buckets). The order is a
// total order, hence the same for any thread count.
template <std::size_t N>
std::vector<int> sort_slots(const std::vector<std::array<int, N>>& keys, int num_buckets) {
    const std::size_t n = keys.size();
    std::vector<int> order(n), next(n);
    std::vector<int> start(static_cast<std::size_t>(num_buckets) + 1);
    for (std::size_t c = N; c-- > 0;) {
        std::fill(start.begin(), start.end(), 0);
        for (const std::array<int, N>& k : keys) ++start[static_cast<std::size_t>(k[c]) + 1];
        for (std::size_t b = 0; b < static_cast<std::size_t>(num_buckets); ++b) start[b + 1] += start[b];
        if (c == N - 1) {  // first pass: the slots in their own order
            for (std::size_t s = 0; s < n; ++s)
                next[static_cast<std::size_t>(start[static_cast<std::size_t>(keys[s][c])]++)] = static_cast<int>(s);
        } else {
            for (const int s : order)
                next[static_cast<std::size_t>(
                    start[static_cast<std::size_t>(keys[static_cast<std::size_t>(s)][c])]++)] = s;
        }
        order.swap(next);
    }
    return order;
}

// Ascending order of 4 ints: a sorting network of 5 compare-exchanges.
void sort4(std::array<int, 4>& k) {
    const auto exchange = [&k](std::size_t i, std::size_t j) {
        if (k[j] < k[i]) std::swap(k[i], k[j]);
    };
    exchange(0, 1), exchange(2, 3), exchange(0, 2), exchange(1, 3), exchange(1, 2);
}

template <std::size_t N>
bool same_key(const std::array<int, N>& a, const std::array<int, N>& b) {
    for (std::size_t i = 0; i < N; ++i)
        if (a[i] != b[i]) return false;
    return true;
}

// Groups of equal keys in the sorted slot order, numbered by the smallest slot of each group (= first appearance).
// Fills id per slot and `first_slot[id]` (the smallest slot of group id); `group_size[slot of head]` = group size.
template <std::size_t N>
int number_groups(const std::vector<std::array<int, N>>& keys, const std::vector<int>& order,
                  std::vector<int>& id_of_slot, std::vector<int>& first_slot) {
    const std::size_t n = order.size();
    std::vector<int> group_head(n);  // per slot: the smallest slot of its group
    std::size_t i = 0;
    while (i < n) {
        const std::array<int, N>& key = keys[static_cast<std::size_t>(order[i])];
        std::size_t j = i + 1;
        while (j < n && same_key(keys[static_cast<std::size_t>(order[j])], key)) ++j;
        for (std::size_t k = i; k < j; ++k) group_head[static_cast<std::size_t>(order[k])] = order[i];
        i = j;
    }
    id_of_slot.assign(n, -1);
    first_slot.clear();
    for (std::size_t s = 0; s < n; ++s) {
        const int head = group_head[s];
        if (head == static_cast<int>(s)) {
            id_of_slot[s] = static_cast<int>(first_slot.size());
            first_slot.push_back(static_cast<int>(s));
        } else {
            id_of_slot[s] = id_of_slot[static_cast<std::size_t>(head)];  // head < s: already numbered
        }
    }
    return static_cast<int>(first_slot.size());
}

}  // namespace

VertexHexes vertex_hexes(const HexMesh& mesh) {
    const std::size_t nv = mesh.points.size();
    VertexHexes r;
    r.begin.assign(nv + 1, 0);
    for (const std::array<int, 8>& hex : mesh.hexes)
        for (int v : hex) ++r.begin[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < nv; ++v) r.begin[v + 1] += r.begin[v];
    r.hexes.resize(static_cast<std::size_t>(r.begin[nv]));
    std::vector<int> fill(r.begin.begin(), r.begin.end() - 1);
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
        for (int v : mesh.hexes[h])
            r.hexes[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = static_cast<int>(h);
    return r;
}

HexTopology compute_hex_topology(const HexMesh& mesh) {
    HexTopology topo;
    const std::size_t num_hexes = mesh.hexes.size();

    // ---- faces ----
    int num_buckets = 0;
    for (const std::array<int, 8>& hex : mesh.hexes)
        for (int v : hex) {
            MESOHEX_CHECK(v >= 0, "compute_hex_topology needs vertex indices in range");
            num_buckets = std::max(num_buckets, v + 1);
        }
    std::vector<std::array<int, 4>> face_keys(num_hexes * 6);  // sorted vertex quadruple per (hex, local face)
    tbb::parallel_for(std::size_t{0}, num_hexes, [&](std::size_t h) {
        const std::array<int, 8>& hex = mesh.hexes[h];
        for (std::size_t lf = 0; lf < 6; ++lf) {
            std::array<int, 4>& key = face_keys[h * 6 + lf];
            for (std::size_t i = 0; i < 4; ++i) key[i] = hex[static_cast<std::size_t>(kHexFaces[lf][i])];
            sort4(key);
        }
    });
    std::vector<int> face_of_slot, face_first_slot;
    const int num_faces = number_groups(face_keys, sort_slots(face_keys, num_buckets), face_of_slot, face_first_slot);
    face_keys = {};
    topo.faces.resize(static_cast<std::size_t>(num_faces));
    topo.face_hexes.assign(static_cast<std::size_t>(num_faces), {-1, -1});
    topo.face_hex_count.assign(static_cast<std::size_t>(num_faces), 0);
    topo.hex_faces.resize(num_hexes);
    for (std::size_t s = 0; s < face_of_slot.size(); ++s) {  // slot order: face_hexes[f][0] is the first hex
        const int f = face_of_slot[s];
        const int h = static_cast<int>(s / 6);
        const int lf = static_cast<int>(s % 6);
        topo.hex_faces[static_cast<std::size_t>(h)][static_cast<std::size_t>(lf)] = f;
        const std::size_t fu = static_cast<std::size_t>(f);
        int& count = topo.face_hex_count[fu];
        if (count < 2) topo.face_hexes[fu][static_cast<std::size_t>(count)] = h;
        ++count;
    }
    for (int f = 0; f < num_faces; ++f) {
        const int s = face_first_slot[static_cast<std::size_t>(f)];
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(s / 6)];
        for (int i = 0; i < 4; ++i)
            topo.faces[static_cast<std::size_t>(f)][static_cast<std::size_t>(i)] =
                hex[static_cast<std::size_t>(kHexFaces[s % 6][i])];
    }

    // ---- edges ----
    std::vector<std::array<int, 2>> edge_keys(num_hexes * 12);  // (min, max) per (hex, local edge)
    tbb::parallel_for(std::size_t{0}, num_hexes, [&](std::size_t h) {
        const std::array<int, 8>& hex = mesh.hexes[h];
        for (std::size_t le = 0; le < 12; ++le) {
            const int a = hex[static_cast<std::size_t>(kHexEdges[le][0])];
            const int b = hex[static_cast<std::size_t>(kHexEdges[le][1])];
            edge_keys[h * 12 + le] = {std::min(a, b), std::max(a, b)};
        }
    });
    const std::vector<int> edge_order = sort_slots(edge_keys, num_buckets);
    // Valence = number of distinct hexes around the edge (slots of one group are sorted, so equal hexes are adjacent).
    std::vector<int> edge_valence_of_head(num_hexes * 12, 0);
    for (std::size_t i = 0; i < edge_order.size();) {
        const std::array<int, 2>& key = edge_keys[static_cast<std::size_t>(edge_order[i])];
        std::size_t j = i + 1;
        int distinct = 1;
        while (j < edge_order.size() && same_key(edge_keys[static_cast<std::size_t>(edge_order[j])], key)) {
            if (edge_order[j] / 12 != edge_order[j - 1] / 12) ++distinct;
            ++j;
        }
        edge_valence_of_head[static_cast<std::size_t>(edge_order[i])] = distinct;
        i = j;
    }
    std::vector<int> edge_of_slot, edge_first_slot;
    const int num_edges = number_groups(edge_keys, edge_order, edge_of_slot, edge_first_slot);
    edge_keys = {};
    topo.edges.resize(static_cast<std::size_t>(num_edges));
    topo.edge_valence.resize(static_cast<std::size_t>(num_edges));
    for (int e = 0; e < num_edges; ++e) {
        const int s = edge_first_slot[static_cast<std::size_t>(e)];
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(s / 12)];
        const int a = hex[static_cast<std::size_t>(kHexEdges[s % 12][0])];
        const int b = hex[static_cast<std::size_t>(kHexEdges[s % 12][1])];
        topo.edges[static_cast<std::size_t>(e)] = {std::min(a, b), std::max(a, b)};
        topo.edge_valence[static_cast<std::size_t>(e)] = edge_valence_of_head[static_cast<std::size_t>(s)];
    }
    topo.hex_edges.resize(num_hexes);
    for (std::size_t s = 0; s < edge_of_slot.size(); ++s) topo.hex_edges[s / 12][s % 12] = edge_of_slot[s];

    // ---- boundary ----
    topo.edge_on_boundary.assign(static_cast<std::size_t>(num_edges), false);
    for (int f = 0; f < num_faces; ++f) {
        if (topo.face_hex_count[static_cast<std::size_t>(f)] != 1) continue;
        topo.boundary_quads.push_back(topo.faces[static_cast<std::size_t>(f)]);
        topo.boundary_face.push_back(f);
        const int s = face_first_slot[static_cast<std::size_t>(f)];
        const std::size_t h = static_cast<std::size_t>(s / 6);
        for (const int le : kHexFaceSideEdges[static_cast<std::size_t>(s % 6)])
            topo.edge_on_boundary[static_cast<std::size_t>(topo.hex_edges[h][static_cast<std::size_t>(le)])] = true;
    }
    return topo;
}

BoundarySurface extract_boundary(const HexMesh& mesh, const HexTopology& topo) {
    BoundarySurface out;
    std::vector<int> new_id(mesh.points.size(), -1);
    out.surface.quads.reserve(topo.boundary_quads.size());
    for (const std::array<int, 4>& quad : topo.boundary_quads) {
        std::array<int, 4> q;
        for (int i = 0; i < 4; ++i) {
            const int v = quad[static_cast<std::size_t>(i)];
            int& id = new_id[static_cast<std::size_t>(v)];
            if (id < 0) {
                id = static_cast<int>(out.vertex_of.size());
                out.vertex_of.push_back(v);
                out.surface.points.push_back(mesh.points[static_cast<std::size_t>(v)]);
            }
            q[static_cast<std::size_t>(i)] = id;
        }
        out.surface.quads.push_back(q);
    }
    return out;
}

}  // namespace mesohex
