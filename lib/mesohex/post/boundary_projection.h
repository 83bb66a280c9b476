#pragma once
// Boundary projection of a subdivided mesh (the inherited levels of finish_mesh): the boundary vertices move onto the
// domain surface, the layers beneath follow, and a guard keeps every hex near its quality before the move.
#include <functional>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct ProjectionOptions {
    int rings = 3;           // layers of vertices beneath the boundary that follow its move (count, >= 0)
    double guard_sj = 0.3;   // no hex may fall below min(this, its scaled Jacobian before), nor invert
    int max_backtracks = 6;  // halvings of a vertex's move before it is dropped
};

struct ProjectionResult {
    long boundary_vertices = 0;  // vertices projected
    long moved_vertices = 0;     // boundary and layer vertices that moved (by a non-zero amount)
    long damped_vertices = 0;    // of them, vertices whose move the guard halved or dropped
    double max_move = 0;         // largest boundary move before the guard (length)
};

// The closest surface point closest[i] of every in[i] (same contract as SurfaceProjector::closest_points).
using ClosestPointsFn = std::function<void(const std::vector<Vec3>& in, std::vector<Vec3>& closest)>;

// Moves every vertex v with on_boundary[v] to its closest surface point (move m_v). The vertices r = 1..rings hex edges
// beneath the boundary (ring = shortest edge path to a boundary vertex) move by
// (1 - r / (rings + 1)) / (1 - (r - 1) / (rings + 1)) x the mean move of their neighbours in ring r - 1: a boundary
// move fades linearly over the layers under it. Then the guard: a hex that the moves invert or take below
// min(guard_sj, its scaled Jacobian before) halves the move of its 8 vertices, up to max_backtracks times (then they
// stay where they were); only hexes around changed vertices are checked again, in ascending order (deterministic).
// Cost O(moved vertices + their hexes) after one O(#hexes) vertex -> hex table.
// Preconditions: indices in range, on_boundary has one entry per vertex (InvalidInput otherwise).
ProjectionResult project_boundary(HexMesh& mesh, const std::vector<char>& on_boundary,
                                  const ClosestPointsFn& closest_points, const ProjectionOptions& options = {});

}  // namespace mesohex
