#include "mesohex/core/skeleton.h"

#include "mesohex/core/error.h"
#include "mesohex/core/skeleton_radii.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>

namespace mesohex {

int add_face_edges(Skeleton& s) {
    std::set<std::pair<int, int>> known;
    for (const std::array<int, 2>& e : s.edges) known.insert(std::minmax(e[0], e[1]));
    int added = 0;
    for (const std::vector<int>& f : s.faces) {
        for (std::size_t i = 0; i < f.size(); ++i) {
            const int a = f[i], b = f[(i + 1) % f.size()];
            if (known.insert(std::minmax(a, b)).second) {
                s.edges.push_back({a, b});
                ++added;
            }
        }
    }
    return added;
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
