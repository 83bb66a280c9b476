// Derived topology of a hex mesh by sorting: every (hex, local face) slot gets its sorted vertex quadruple as a key,
// slots with equal keys are one face; the same for edges with sorted vertex pairs. Ids are given in order of first
// appearance (hex by hex, local element by local element), so they depend only on the input arrays.
#include "mesohex/core/topology.h"

#include <algorithm>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"

namespace mesohex {
namespace {

// Ascending order of 4 ints: a sorting network of 5 compare-exchanges.
void sort4(std::array<int, 4>& k) {
    const auto exchange = [&k](std::size_t i, std::size_t j) {
        if (k[j] < k[i]) std::swap(k[i], k[j]);
    };
    exchange(0, 1), exchange(2, 3), exchange(0, 2), exchange(1, 3), exchange(1, 2);
}

// Buckets up to this many slots are sorted by insertion (a vertex of a regular mesh has up to 24 face slots and 24
// edge slots with it as their smallest vertex); larger ones by std::sort.
constexpr int kInsertionSortMax = 64;

// Order and equality of two keys of one bucket (their first vertex is the bucket's): the other components only.
template <std::size_t N>
bool rest_less(const std::array<int, N>& a, const std::array<int, N>& b) {
    for (std::size_t i = 1; i < N; ++i)
        if (a[i] != b[i]) return a[i] < b[i];
    return false;
}
template <std::size_t N>
bool rest_equal(const std::array<int, N>& a, const std::array<int, N>& b) {
    for (std::size_t i = 1; i < N; ++i)
        if (a[i] != b[i]) return false;
    return true;
}

// One bucket of number_groups: the slots order[begin, end) (ascending) sorted stably by key in `bucket`, and the
// first slot of every run of equal keys written to id_of_slot of each slot of the run.
template <class KeyOf, class Key>
void heads_of_bucket(const std::vector<int>& order, int begin, int end, const KeyOf& key_of,
                     std::vector<std::pair<Key, int>>& bucket, std::vector<int>& id_of_slot) {
    bucket.clear();
    if (end - begin > kInsertionSortMax) {  // a vertex of very many hexes (degenerate input): no quadratic sort
        for (int i = begin; i < end; ++i) {
            const int s = order[static_cast<std::size_t>(i)];
            bucket.emplace_back(key_of(static_cast<std::size_t>(s)), s);
        }
        std::sort(bucket.begin(), bucket.end(), [](const std::pair<Key, int>& a, const std::pair<Key, int>& b) {
            return rest_less(a.first, b.first) || (rest_equal(a.first, b.first) && a.second < b.second);
        });  // by (key, slot): the stable order by key
    } else {
        for (int i = begin; i < end; ++i) {
            const int s = order[static_cast<std::size_t>(i)];
            const Key key = key_of(static_cast<std::size_t>(s));
            std::size_t k = bucket.size();
            bucket.emplace_back();
            for (; k > 0 && rest_less(key, bucket[k - 1].first); --k) bucket[k] = bucket[k - 1];
            bucket[k] = {key, s};
        }
    }
    for (std::size_t i = 0; i < bucket.size();) {
        std::size_t j = i + 1;
        while (j < bucket.size() && rest_equal(bucket[j].first, bucket[i].first)) ++j;
        for (std::size_t k = i; k < j; ++k) id_of_slot[static_cast<std::size_t>(bucket[k].second)] = bucket[i].second;
        i = j;
    }
}

// Groups of slots with equal keys, numbered by the smallest slot of each group (= first appearance): fills the group
// id of every slot and `first_slot[id]` (the smallest slot of group id); returns the number of groups. Keys (sorted
// vertex ids in [0, num_buckets)) are computed on the fly by key_of(slot), their first (smallest) vertex by
// first_of(slot). No array of keys: a counting sort of the slots by their first vertex (in slot order), then each
// vertex's bucket (a few dozen slots) sorted by key, stably (insertion sort: slot order within equal keys), and every
// slot's group head (its group's first slot there) written to id_of_slot, the buckets in parallel (disjoint slots);
// then, in ascending slot order (heads before the rest of their group), each head slot replaced by its group's id.
// The same for any thread count.
template <class FirstOf, class KeyOf>
int number_groups(std::size_t n, int num_buckets, const FirstOf& first_of, const KeyOf& key_of,
                  std::vector<int>& id_of_slot, std::vector<int>& first_slot) {
    using Key = decltype(key_of(std::size_t{0}));
    std::vector<int> start(static_cast<std::size_t>(num_buckets) + 1, 0);
    for (std::size_t s = 0; s < n; ++s) ++start[static_cast<std::size_t>(first_of(s)) + 1];
    for (std::size_t b = 0; b < static_cast<std::size_t>(num_buckets); ++b) start[b + 1] += start[b];
    id_of_slot.assign(n, -1);
    {
        std::vector<int> order(n);
        std::vector<int> fill(start.begin(), start.end() - 1);
        for (std::size_t s = 0; s < n; ++s)
            order[static_cast<std::size_t>(fill[static_cast<std::size_t>(first_of(s))]++)] = static_cast<int>(s);
        fill = {};
        // Ranges of at least 4096 buckets: one buffer (allocated once) per range.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, static_cast<std::size_t>(num_buckets), 4096),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              std::vector<std::pair<Key, int>> bucket;
                              bucket.reserve(2 * kInsertionSortMax);
                              for (std::size_t b = range.begin(); b != range.end(); ++b)
                                  heads_of_bucket(order, start[b], start[b + 1], key_of, bucket, id_of_slot);
                          });
    }
    std::size_t groups = 0;
    for (std::size_t s = 0; s < n; ++s) groups += id_of_slot[s] == static_cast<int>(s) ? 1 : 0;
    first_slot.clear();
    first_slot.reserve(groups);
    for (std::size_t s = 0; s < n; ++s) {
        const int head = id_of_slot[s];
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
    // Sorted vertex quadruple of a (hex, local face) slot.
    const auto face_key = [&mesh](std::size_t s) {
        const std::array<int, 8>& hex = mesh.hexes[s / 6];
        std::array<int, 4> key;
        for (std::size_t i = 0; i < 4; ++i) key[i] = hex[static_cast<std::size_t>(kHexFaces[s % 6][i])];
        sort4(key);
        return key;
    };
    const auto face_first = [&mesh](std::size_t s) {
        const std::array<int, 8>& hex = mesh.hexes[s / 6];
        const std::array<int, 4>& lf = kHexFaces[s % 6];
        return std::min(std::min(hex[static_cast<std::size_t>(lf[0])], hex[static_cast<std::size_t>(lf[1])]),
                        std::min(hex[static_cast<std::size_t>(lf[2])], hex[static_cast<std::size_t>(lf[3])]));
    };
    std::vector<int> face_of_slot, face_first_slot;
    const int num_faces =
        number_groups(num_hexes * 6, num_buckets, face_first, face_key, face_of_slot, face_first_slot);
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
    face_of_slot = {};
    for (int f = 0; f < num_faces; ++f) {
        const int s = face_first_slot[static_cast<std::size_t>(f)];
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(s / 6)];
        for (int i = 0; i < 4; ++i)
            topo.faces[static_cast<std::size_t>(f)][static_cast<std::size_t>(i)] =
                hex[static_cast<std::size_t>(kHexFaces[s % 6][i])];
    }

    // ---- edges ----
    // (min, max) vertex of a (hex, local edge) slot.
    const auto edge_key = [&mesh](std::size_t s) {
        const std::array<int, 8>& hex = mesh.hexes[s / 12];
        const int a = hex[static_cast<std::size_t>(kHexEdges[s % 12][0])];
        const int b = hex[static_cast<std::size_t>(kHexEdges[s % 12][1])];
        return std::array<int, 2>{std::min(a, b), std::max(a, b)};
    };
    const auto edge_first = [&edge_key](std::size_t s) { return edge_key(s)[0]; };
    std::vector<int> edge_of_slot, edge_first_slot;
    const int num_edges =
        number_groups(num_hexes * 12, num_buckets, edge_first, edge_key, edge_of_slot, edge_first_slot);
    // Valence = number of distinct hexes around the edge: slots in ascending order visit the hexes in ascending order,
    // so a hex is new for an edge when it differs from the last one counted there.
    topo.edge_valence.assign(static_cast<std::size_t>(num_edges), 0);
    {
        std::vector<int> last_hex(static_cast<std::size_t>(num_edges), -1);
        for (std::size_t s = 0; s < edge_of_slot.size(); ++s) {
            const std::size_t e = static_cast<std::size_t>(edge_of_slot[s]);
            const int h = static_cast<int>(s / 12);
            if (last_hex[e] != h) {
                last_hex[e] = h;
                ++topo.edge_valence[e];
            }
        }
    }
    topo.edges.resize(static_cast<std::size_t>(num_edges));
    for (int e = 0; e < num_edges; ++e) {
        const int s = edge_first_slot[static_cast<std::size_t>(e)];
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(s / 12)];
        const int a = hex[static_cast<std::size_t>(kHexEdges[s % 12][0])];
        const int b = hex[static_cast<std::size_t>(kHexEdges[s % 12][1])];
        topo.edges[static_cast<std::size_t>(e)] = {std::min(a, b), std::max(a, b)};
    }
    edge_first_slot = {};
    topo.hex_edges.resize(num_hexes);
    for (std::size_t s = 0; s < edge_of_slot.size(); ++s) topo.hex_edges[s / 12][s % 12] = edge_of_slot[s];
    edge_of_slot = {};

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

std::vector<std::vector<int>> boundary_edge_neighbours(const HexTopology& topo, std::size_t num_points) {
    std::vector<std::vector<int>> nbrs(num_points);
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
        if (!topo.edge_on_boundary[e]) continue;
        const auto [a, b] = topo.edges[e];
        nbrs[static_cast<std::size_t>(a)].push_back(b);
        nbrs[static_cast<std::size_t>(b)].push_back(a);
    }
    return nbrs;
}

namespace {

// The boundary edge neighbours of vertex v (sorted, once each), from the faces of its hexes (vh) that no other hex
// shares; `slots` is scratch.
std::vector<int> boundary_neighbours_of(const HexMesh& mesh, const VertexHexes& vh, int v,
                                        std::vector<std::pair<std::array<int, 4>, std::array<int, 2>>>& slots) {
    const std::size_t vu = static_cast<std::size_t>(v);
    slots.clear();  // (sorted key, (hex, local face)) with v
    for (int k = vh.begin[vu]; k < vh.begin[vu + 1]; ++k) {
        const int h = vh.hexes[static_cast<std::size_t>(k)];
        if (k > vh.begin[vu] && vh.hexes[static_cast<std::size_t>(k - 1)] == h) continue;  // v twice in h
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(h)];
        for (std::size_t lf = 0; lf < 6; ++lf) {
            std::array<int, 4> key;
            for (std::size_t i = 0; i < 4; ++i) key[i] = hex[static_cast<std::size_t>(kHexFaces[lf][i])];
            if (std::find(key.begin(), key.end(), v) == key.end()) continue;
            sort4(key);
            slots.push_back({key, {h, static_cast<int>(lf)}});
        }
    }
    std::sort(slots.begin(), slots.end());  // equal keys (one face) next to each other
    std::vector<int> out;
    for (std::size_t s = 0; s < slots.size(); ++s) {
        if ((s > 0 && slots[s - 1].first == slots[s].first) ||
            (s + 1 < slots.size() && slots[s + 1].first == slots[s].first))
            continue;  // a face of two or more slots: not on the boundary
        const std::array<int, 8>& hex = mesh.hexes[static_cast<std::size_t>(slots[s].second[0])];
        const std::array<int, 4>& face = kHexFaces[static_cast<std::size_t>(slots[s].second[1])];
        for (std::size_t i = 0; i < 4; ++i) {
            const int a = hex[static_cast<std::size_t>(face[i])];
            const int b = hex[static_cast<std::size_t>(face[(i + 1) % 4])];
            if (a == v) out.push_back(b);
            if (b == v) out.push_back(a);
        }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace

// The listed vertices in parallel (each writes only its own list; a vertex listed twice gets the same list once).
std::vector<std::vector<int>> boundary_edge_neighbours(const HexMesh& mesh, const std::vector<int>& vertices) {
    std::vector<std::vector<int>> nbrs(mesh.points.size());
    if (vertices.empty()) return nbrs;
    const VertexHexes vh = vertex_hexes(mesh);
    std::vector<int> listed = vertices;
    std::sort(listed.begin(), listed.end());
    listed.erase(std::unique(listed.begin(), listed.end()), listed.end());
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, listed.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
            std::vector<std::pair<std::array<int, 4>, std::array<int, 2>>> slots;
            for (std::size_t i = r.begin(); i < r.end(); ++i)
                nbrs[static_cast<std::size_t>(listed[i])] = boundary_neighbours_of(mesh, vh, listed[i], slots);
        });
    return nbrs;
}

}  // namespace mesohex
