#pragma once
// Disjoint sets over 0..n-1 with path halving. The root of a set is always its smallest element, so component
// numbering derived from roots is deterministic.
#include <algorithm>
#include <numeric>
#include <vector>

namespace mesohex {

struct UnionFind {
    std::vector<int> parent;

    explicit UnionFind(int n = 0) : parent(static_cast<std::size_t>(n)) { std::iota(parent.begin(), parent.end(), 0); }

    int find(int x) {
        while (parent[static_cast<std::size_t>(x)] != x) {
            int& p = parent[static_cast<std::size_t>(x)];
            p = parent[static_cast<std::size_t>(p)];
            x = p;
        }
        return x;
    }
    // Merges the sets of a and b; false when they were already one set.
    bool unite(int a, int b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
        return true;
    }
};

}  // namespace mesohex
