#pragma once
// Padding inset: where the padding layer reaches past the domain surface (a raw mesh that already fills its domain,
// e.g. a skeleton whose radii are the domain's own), the layer is moved inward so that it ends at the surface: the
// raw boundary vertex and its padding vertex move together along the padding direction, the raw hexes beneath give
// up that thickness. The fit then starts with the boundary on the surface instead of pulling a whole layer back in.
#include <functional>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct PadInsetOptions {
    // A hex around a moved vertex may not go below min(guard_sj, its scaled Jacobian before the inset), nor be
    // inverted: the moves of its vertices are halved (up to max_halvings times, then dropped). Scaled Jacobian.
    double guard_sj = 0.2;
    int max_halvings = 6;  // count
    // Only concave raw boundary vertices move: those whose padded quads' centroids lie outwards of them along their
    // padding direction on average (the valleys between a junction's chunks, where the directions converge and the
    // fit crushes the layer it pulls back; the same test as PaddingOptions::concave_scale). A tube's wall and a
    // convex corner keep the layer outside, which the fit pulls back without crushing it. false: every vertex.
    bool concave_only = false;
};

struct PadInsetResult {
    long moved_vertices = 0;  // raw boundary vertices moved (with their padding vertex)
    double max_inset = 0;     // largest move, model units
};

// `mesh`: one padding layer over a raw mesh (pad's result: vertices >= first_new_vertex are the padding vertices,
// origin_vertex[w] the raw boundary vertex that w was pushed from). overshoot(p, u, t): how far the point p + t u
// lies beyond the domain surface along the unit direction u, in [0, t] (0: inside). keep (optional, per raw vertex):
// never moved (vertices of bare quads, which already lie on the domain's rims). Deterministic (vertex order).
PadInsetResult inset_padding(HexMesh& mesh, int first_new_vertex, const std::vector<int>& origin_vertex,
                             const std::function<double(const Vec3& p, const Vec3& u, double t)>& overshoot,
                             const std::vector<char>& keep, const PadInsetOptions& options = {});

}  // namespace mesohex
