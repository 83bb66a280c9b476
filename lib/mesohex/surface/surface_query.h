#pragma once
// Geometric queries on a triangle surface through CGAL's AABB tree (built once; CGAL only in surface_query.cpp):
// closest point, squared distance, first ray hit, inside / outside. The batch versions run in parallel (oneTBB), each
// query writing its own slot, so results do not depend on the thread count.
#include <memory>
#include <optional>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct ClosestPoint {
    Vec3 point;
    int triangle = -1;  // id in the TriangleMesh the query was built from
    double squared_distance = 0;
};

struct RayHit {
    Vec3 point;
    int triangle = -1;
    double distance = 0;  // from the ray origin, along the (normalized) direction
};

class SurfaceQuery {
public:
    // Builds the tree over the non-degenerate triangles of `surface` (the mesh is copied). Preconditions: at least one
    // non-degenerate triangle, indices in range, finite coordinates (InvalidInput otherwise). O(F log F).
    // `accelerate` builds CGAL's search kd-tree for closest-point queries without a hint; a query object used only
    // with hints (see closest below) can skip it.
    explicit SurfaceQuery(const TriangleMesh& surface, bool accelerate = true);
    ~SurfaceQuery();
    SurfaceQuery(SurfaceQuery&&) noexcept;
    SurfaceQuery& operator=(SurfaceQuery&&) noexcept;
    SurfaceQuery(const SurfaceQuery&) = delete;
    SurfaceQuery& operator=(const SurfaceQuery&) = delete;

    const TriangleMesh& surface() const;
    // Bounding box of the surface vertices and its diagonal length.
    Vec3 bbox_min() const;
    Vec3 bbox_max() const;
    double bbox_diagonal() const;

    ClosestPoint closest(const Vec3& p) const;
    // The same, the search bounded from the start by p's closest point on triangle hint_triangle (-1: no hint). Same
    // closest point (on a tie, the triangle reported may differ).
    ClosestPoint closest(const Vec3& p, int hint_triangle) const;
    double squared_distance(const Vec3& p) const;
    // First intersection of the ray origin + t direction, t > min_distance (use a small positive value to skip the
    // surface the origin lies on). direction need not be unit; a zero direction gives no hit.
    std::optional<RayHit> first_hit(const Vec3& origin, const Vec3& direction, double min_distance = 0) const;
    // Inside test for a closed surface (orientation does not matter): parity of the crossings of a ray, with up to
    // eight fixed ray directions tried while a hit is ambiguous (too close to an edge or vertex, or coplanar); when all
    // are ambiguous, the generalized winding number decides. A point on the surface (distance <= 1e-12 x bbox
    // diagonal) counts as inside. For an open surface the answer is the crossing parity and has no guarantee.
    bool inside(const Vec3& p) const;

    // Parallel batch versions (deterministic: result[i] depends on points[i] only).
    std::vector<ClosestPoint> closest(const std::vector<Vec3>& points) const;
    // The same with a hint per point: a triangle (index in surface().triangles, or -1 for none) whose closest point to
    // the query bounds the search from the start. Points that moved little since their last query pass their last
    // triangle: the traversal then skips most of the tree. The closest point found is the same as without the hint.
    std::vector<ClosestPoint> closest(const std::vector<Vec3>& points, const std::vector<int>& hint_triangles) const;
    std::vector<double> squared_distances(const std::vector<Vec3>& points) const;
    std::vector<char> inside(const std::vector<Vec3>& points) const;  // 1 inside, 0 outside

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mesohex
