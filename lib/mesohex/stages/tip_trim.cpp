#include "mesohex/stages/tip_trim.h"

#include <algorithm>
#include <array>
#include <cstddef>

namespace mesohex {

namespace {

// Adjacency of the edges: per vertex, its neighbours (an edge repeated counts twice, a loop edge twice at its vertex).
std::vector<std::vector<int>> neighbours(const Skeleton& s) {
    std::vector<std::vector<int>> out(s.points.size());
    for (const std::array<int, 2>& e : s.edges) {
        out[static_cast<std::size_t>(e[0])].push_back(e[1]);
        out[static_cast<std::size_t>(e[1])].push_back(e[0]);
    }
    return out;
}

// The input without the vertices marked in `drop` (and every edge at one of them).
TipTrim compact(const Skeleton& s, const std::vector<char>& drop) {
    TipTrim out;
    out.vertex_map.assign(s.points.size(), -1);
    for (std::size_t v = 0; v < s.points.size(); ++v) {
        if (drop[v]) {
            out.trimmed.push_back(static_cast<int>(v));
            continue;
        }
        out.vertex_map[v] = static_cast<int>(out.skeleton.points.size());
        out.skeleton.points.push_back(s.points[v]);
        if (!s.radii.empty()) out.skeleton.radii.push_back(s.radii[v]);
    }
    for (const std::array<int, 2>& e : s.edges)
        if (!drop[static_cast<std::size_t>(e[0])] && !drop[static_cast<std::size_t>(e[1])])
            out.skeleton.edges.push_back(
                {out.vertex_map[static_cast<std::size_t>(e[0])], out.vertex_map[static_cast<std::size_t>(e[1])]});
    for (const std::vector<int>& f : s.faces) {  // no face vertex is dropped
        std::vector<int> g;
        for (const int v : f) g.push_back(out.vertex_map[static_cast<std::size_t>(v)]);
        out.skeleton.faces.push_back(std::move(g));
    }
    return out;
}

}  // namespace

TipTrim trim_unheld_tips(const Skeleton& s, const std::vector<char>& held) {
    const std::size_t n = s.points.size();
    const std::vector<std::vector<int>> adj = neighbours(s);
    std::vector<char> on_face(n, 0);
    for (const std::vector<int>& f : s.faces)
        for (const int v : f) on_face[static_cast<std::size_t>(v)] = 1;
    const auto joint = [&](int v) {  // a branch vertex with two edges
        const auto u = static_cast<std::size_t>(v);
        return adj[u].size() == 2 && !on_face[u] && adj[u][0] != v && adj[u][1] != v;
    };
    std::vector<char> drop(n, 0);
    std::vector<std::vector<int>> chains;  // each trimmed chain, tip first
    std::vector<int> ends;                 // the vertex each chain stops at
    for (std::size_t t = 0; t < n; ++t) {
        if (adj[t].size() != 1 || on_face[t] || held[t] || adj[t][0] == static_cast<int>(t)) continue;
        std::vector<int> chain{static_cast<int>(t)};
        int prev = static_cast<int>(t);
        int cur = adj[t][0];
        while (joint(cur) && !held[static_cast<std::size_t>(cur)]) {
            chain.push_back(cur);
            const std::vector<int>& a = adj[static_cast<std::size_t>(cur)];
            const int next = a[0] == prev ? a[1] : a[0];
            prev = cur;
            cur = next;
        }
        if (!joint(cur) || !held[static_cast<std::size_t>(cur)]) continue;  // not held up to its root: left whole
        for (const int v : chain) drop[static_cast<std::size_t>(v)] = 1;
        chains.push_back(std::move(chain));
        ends.push_back(cur);
    }
    // A held vertex between two trimmed chains (a single branch not held at either end) would lose both edges: the
    // earlier chain (the lower tip id) stays.
    std::vector<int> new_ends;
    for (std::size_t c = 0; c < chains.size(); ++c) {
        const std::vector<int>& a = adj[static_cast<std::size_t>(ends[c])];
        if (drop[static_cast<std::size_t>(a[0])] && drop[static_cast<std::size_t>(a[1])]) {
            for (const int v : chains[c]) drop[static_cast<std::size_t>(v)] = 0;
            continue;
        }
        new_ends.push_back(ends[c]);
    }
    if (new_ends.empty()) {
        TipTrim same;
        same.skeleton = s;
        same.vertex_map.resize(n);
        for (std::size_t v = 0; v < n; ++v) same.vertex_map[v] = static_cast<int>(v);
        return same;
    }
    TipTrim out = compact(s, drop);
    std::sort(new_ends.begin(), new_ends.end());
    out.new_ends = std::move(new_ends);
    return out;
}

}  // namespace mesohex
