#pragma once
// Small skeletons built in memory for the stage tests.
#include "mesohex/core/skeleton.h"

namespace mesohex::test {

// n x m unit quads in the plane z = 0, vertex (i, j) = j * (n + 1) + i, faces counter-clockwise seen from +z.
inline Skeleton plate(int n, int m) {
    Skeleton s;
    for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= n; ++i) s.points.push_back({double(i), double(j), 0});
    for (int j = 0; j < m; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i;
            s.faces.push_back({a, a + 1, a + n + 2, a + n + 1});
        }
    add_face_edges(s);
    return s;
}

}  // namespace mesohex::test
