#include "mesohex/core/skeleton.h"

#include "mesohex/core/error.h"
#include "mesohex/core/skeleton_radii.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace mesohex {

int add_face_edges(Skeleton& s) {
    using Key = std::pair<int, int>;  // (min, max) vertex of an edge or a face side
    std::vector<Key> known(s.edges.size());
    for (std::size_t e = 0; e < s.edges.size(); ++e) known[e] = std::minmax(s.edges[e][0], s.edges[e][1]);
    std::sort(known.begin(), known.end());
    // The face sides that are no edge, in face order, then the first side of each key among them (sorting by key
    // and order): the same edges, in the same order, as adding every side not seen before one by one.
    std::vector<std::array<int, 2>> sides;
    std::vector<std::pair<Key, int>> keyed;  // (key, index in sides)
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i) {
            const int a = f[i], b = f[(i + 1) % f.size()];
            const Key key = std::minmax(a, b);
            if (std::binary_search(known.begin(), known.end(), key)) continue;
            keyed.push_back({key, static_cast<int>(sides.size())});
            sides.push_back({a, b});
        }
    std::sort(keyed.begin(), keyed.end());
    std::vector<char> first(sides.size(), 0);
    for (std::size_t i = 0; i < keyed.size(); ++i)
        first[static_cast<std::size_t>(keyed[i].second)] = i == 0 || keyed[i].first != keyed[i - 1].first;
    int added = 0;
    for (std::size_t i = 0; i < sides.size(); ++i)
        if (first[i]) s.edges.push_back(sides[i]), ++added;
    return added;
}

namespace {
// Every side of every face as (min, max) vertex ids, sorted.
std::vector<std::pair<int, int>> sorted_face_sides(const Skeleton& s) {
    std::vector<std::pair<int, int>> sides;
    for (const std::vector<int>& f : s.faces)
        for (std::size_t i = 0; i < f.size(); ++i) sides.push_back(std::minmax(f[i], f[(i + 1) % f.size()]));
    std::sort(sides.begin(), sides.end());
    return sides;
}
}  // namespace

bool has_side_of_three_faces(const Skeleton& s) {
    const std::vector<std::pair<int, int>> sides = sorted_face_sides(s);
    for (std::size_t i = 2; i < sides.size(); ++i)
        if (sides[i] == sides[i - 2]) return true;
    return false;
}

bool has_edge_off_faces(const Skeleton& s) {
    const std::vector<std::pair<int, int>> sides = sorted_face_sides(s);
    const int n = static_cast<int>(s.points.size());
    for (const std::array<int, 2>& e : s.edges) {
        if (e[0] < 0 || e[0] >= n || e[1] < 0 || e[1] >= n || e[0] == e[1]) continue;
        const std::pair<int, int> key = std::minmax(e[0], e[1]);
        if (!std::binary_search(sides.begin(), sides.end(), key)) return true;
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
