#include "mesohex/core/skeleton.h"

#include "mesohex/core/error.h"
#include "mesohex/core/skeleton_radii.h"
#include "mesohex/core/unordered_pairs.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace mesohex {

namespace {

using Pairs = std::vector<std::array<int, 2>>;

bool in_range(const Pairs& pairs, int n) {
    for (const std::array<int, 2>& p : pairs)
        if (p[0] < 0 || p[0] >= n || p[1] < 0 || p[1] >= n) return false;
    return true;
}

// Pairs of ids in [0, n) grouped by their smaller id (CSR); inside a bucket sorted by (larger id, index of the pair).
// O(#pairs + n) plus tiny sorts.
struct PairBuckets {
    std::vector<int> begin;                  // n + 1 entries
    std::vector<std::pair<int, int>> items;  // (larger id, index of the pair)
};

PairBuckets bucket_pairs(const Pairs& pairs, int n) {
    PairBuckets b;
    b.begin.assign(static_cast<std::size_t>(n) + 1, 0);
    for (const std::array<int, 2>& p : pairs) ++b.begin[static_cast<std::size_t>(std::min(p[0], p[1])) + 1];
    for (std::size_t v = 0; v < static_cast<std::size_t>(n); ++v) b.begin[v + 1] += b.begin[v];
    std::vector<int> fill(b.begin.begin(), b.begin.end() - 1);
    b.items.resize(pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const std::array<int, 2>& p = pairs[i];
        b.items[static_cast<std::size_t>(fill[static_cast<std::size_t>(std::min(p[0], p[1]))]++)] = {
            std::max(p[0], p[1]), static_cast<int>(i)};
    }
    for (std::size_t v = 0; v < static_cast<std::size_t>(n); ++v)
        std::sort(b.items.begin() + b.begin[v], b.items.begin() + b.begin[v + 1]);
    return b;
}

// Every side of every face, in face order.
Pairs face_sides(const Skeleton& s) {
    Pairs sides;
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i) sides.push_back({f[i], f[(i + 1) % f.size()]});
    return sides;
}

}  // namespace

std::vector<char> first_of_each_pair(const std::vector<std::array<int, 2>>& pairs, int n) {
    std::vector<char> first(pairs.size(), 0);
    if (in_range(pairs, n)) {
        const PairBuckets b = bucket_pairs(pairs, n);
        for (std::size_t v = 0; v < static_cast<std::size_t>(n); ++v)
            for (int j = b.begin[v]; j < b.begin[v + 1]; ++j)
                first[static_cast<std::size_t>(b.items[static_cast<std::size_t>(j)].second)] =
                    j == b.begin[v] ||
                    b.items[static_cast<std::size_t>(j)].first != b.items[static_cast<std::size_t>(j) - 1].first;
        return first;
    }
    std::vector<std::pair<std::pair<int, int>, int>> keyed(pairs.size());  // ((min, max), index)
    for (std::size_t i = 0; i < pairs.size(); ++i)
        keyed[i] = {std::minmax(pairs[i][0], pairs[i][1]), static_cast<int>(i)};
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t i = 0; i < keyed.size(); ++i)
        first[static_cast<std::size_t>(keyed[i].second)] = i == 0 || keyed[i].first != keyed[i - 1].first;
    return first;
}

int add_face_edges(Skeleton& s) {
    // The edges then the face sides: a side is added when it is the first of its pair (no earlier edge or side).
    const std::size_t ne = s.edges.size();
    Pairs all = s.edges;
    const Pairs sides = face_sides(s);
    all.insert(all.end(), sides.begin(), sides.end());
    const std::vector<char> first = first_of_each_pair(all, static_cast<int>(s.points.size()));
    int added = 0;
    for (std::size_t i = 0; i < sides.size(); ++i)
        if (first[ne + i]) s.edges.push_back(sides[i]), ++added;
    return added;
}

bool has_side_of_three_faces(const Skeleton& s) {
    const int n = static_cast<int>(s.points.size());
    const Pairs sides = face_sides(s);
    if (!in_range(sides, n)) return true;  // cannot tell cheaply: no shortcut
    const PairBuckets b = bucket_pairs(sides, n);
    for (std::size_t v = 0; v < static_cast<std::size_t>(n); ++v)
        for (int j = b.begin[v] + 2; j < b.begin[v + 1]; ++j)
            if (b.items[static_cast<std::size_t>(j)].first == b.items[static_cast<std::size_t>(j) - 2].first)
                return true;
    return false;
}

bool has_edge_off_faces(const Skeleton& s) {
    const int n = static_cast<int>(s.points.size());
    const Pairs sides = face_sides(s);
    if (!in_range(sides, n)) return true;  // cannot tell cheaply: no shortcut
    const PairBuckets b = bucket_pairs(sides, n);
    for (const std::array<int, 2>& e : s.edges) {
        if (e[0] < 0 || e[0] >= n || e[1] < 0 || e[1] >= n || e[0] == e[1]) continue;
        const auto lo = b.items.begin() + b.begin[static_cast<std::size_t>(std::min(e[0], e[1]))];
        const auto hi = b.items.begin() + b.begin[static_cast<std::size_t>(std::min(e[0], e[1])) + 1];
        const auto it = std::lower_bound(lo, hi, std::make_pair(std::max(e[0], e[1]), -1));
        if (it == hi || it->first != std::max(e[0], e[1])) return true;
    }
    return false;
}

void check_radii(const Skeleton& s) {
    for (std::size_t v = 0; v < s.radii.size(); ++v)
        if (!(s.radii[v] > 0) || !std::isfinite(s.radii[v]))
            throw Error(ErrorCode::InvalidInput,
                        "skeleton vertex " + std::to_string(v) + " has radius " + std::to_string(s.radii[v]) +
                            " (must be finite and > 0)",
                        ElementRef{ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
}

}  // namespace mesohex
