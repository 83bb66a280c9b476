// Surface queries through CGAL's AABB tree (one of the two CGAL translation units of mesohex_surface).
#include "mesohex/surface/surface_query.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using Triangle = K::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

constexpr double kPi = std::numbers::pi;

Point to_cgal(const Vec3& p) { return {p.x, p.y, p.z}; }
Vec3 to_vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// Ray directions for the parity test: fixed, far from the axes and from each other.
constexpr Vec3 kDirections[8] = {{0.5773, 0.4817, 0.6596},   {-0.3624, 0.8211, -0.4410}, {0.7071, -0.5123, 0.4877},
                                 {-0.6012, -0.3317, 0.7270}, {0.2231, -0.9012, -0.3716}, {-0.8123, 0.1979, -0.5486},
                                 {0.4349, 0.3201, -0.8416},  {-0.1387, -0.6521, -0.7453}};

enum class Crossing { None, Clean, Ambiguous, OnSurface };

// Ray (o + t d) against triangle (a, b, c), Moeller-Trumbore; reports near-edge and parallel cases as ambiguous.
Crossing ray_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c, double scale,
                      double& t_out) {
    const Vec3 e1 = b - a, e2 = c - a;
    const Vec3 pv = cross(d, e2);
    const double det = dot(e1, pv);
    const double area2 = norm(cross(e1, e2));
    if (std::abs(det) <= 1e-12 * area2) {
        // Parallel: ambiguous only if the ray's line is in the triangle's plane.
        const Vec3 n = cross(e1, e2);
        if (std::abs(dot(o - a, n)) <= 1e-12 * scale * norm(n)) return Crossing::Ambiguous;
        return Crossing::None;
    }
    const double inv = 1.0 / det;
    const Vec3 tv = o - a;
    const double u = dot(tv, pv) * inv;
    const Vec3 qv = cross(tv, e1);
    const double v = dot(d, qv) * inv;
    const double w = 1.0 - u - v;
    const double t = dot(e2, qv) * inv;
    constexpr double eps = 1e-9;
    if (u < -eps || v < -eps || w < -eps) return Crossing::None;
    if (std::abs(t) <= 1e-12 * scale) return Crossing::OnSurface;
    if (t < 0) return Crossing::None;
    t_out = t;
    if (u < eps || v < eps || w < eps) return Crossing::Ambiguous;
    return Crossing::Clean;
}

}  // namespace

struct SurfaceQuery::Impl {
    TriangleMesh mesh;
    std::vector<Triangle> triangles;  // non-degenerate triangles only
    std::vector<int> triangle_id;     // index in mesh.triangles of triangles[i]
    std::vector<int> primitive_of;    // per triangle of mesh: its index in triangles, or -1 (degenerate)
    Tree tree;
    Vec3 lo, hi;
    double diagonal = 0;

    int id_of(const TriangleIterator& it) const {
        return triangle_id[static_cast<std::size_t>(std::distance(triangles.cbegin(), it))];
    }

    // Candidate triangles of a ray.
    std::vector<TriangleIterator> candidates(const Vec3& o, const Vec3& d) const {
        std::vector<TriangleIterator> out;
        tree.all_intersected_primitives(K::Ray_3(to_cgal(o), K::Vector_3(d.x, d.y, d.z)), std::back_inserter(out));
        return out;
    }

    double winding_number(const Vec3& p) const {
        double omega = 0;
        for (const Triangle& t : triangles) {
            const Vec3 a = to_vec(t[0]) - p, b = to_vec(t[1]) - p, c = to_vec(t[2]) - p;
            const double la = norm(a), lb = norm(b), lc = norm(c);
            omega += 2.0 * std::atan2(det3(a, b, c), la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la);
        }
        return omega / (4.0 * kPi);
    }

    bool inside(const Vec3& p) const {
        const double scale = std::max(diagonal, 1e-300);
        // Outside the bounding box: outside.
        for (int i = 0; i < 3; ++i)
            if (p[i] < lo[i] - 1e-12 * scale || p[i] > hi[i] + 1e-12 * scale) return false;
        const double d2 = tree.squared_distance(to_cgal(p));
        if (d2 <= (1e-12 * scale) * (1e-12 * scale)) return true;
        for (const Vec3& d : kDirections) {
            int count = 0;
            bool ambiguous = false;
            for (const TriangleIterator& it : candidates(p, d)) {
                double t = 0;
                const Crossing c = ray_triangle(p, d, to_vec((*it)[0]), to_vec((*it)[1]), to_vec((*it)[2]), scale, t);
                if (c == Crossing::Clean)
                    ++count;
                else if (c == Crossing::OnSurface)
                    return true;
                else if (c == Crossing::Ambiguous) {
                    ambiguous = true;
                    break;
                }
            }
            if (!ambiguous) return count % 2 == 1;
        }
        return std::abs(winding_number(p)) > 0.5;
    }
};

SurfaceQuery::SurfaceQuery(const TriangleMesh& surface, bool accelerate) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.mesh = surface;
    const long nv = static_cast<long>(surface.points.size());
    for (const Vec3& p : surface.points)
        if (!is_finite(p)) throw Error(ErrorCode::InvalidInput, "surface query: a surface vertex is not finite");
    m.triangles.reserve(surface.triangles.size());
    for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
        const std::array<int, 3>& t = surface.triangles[f];
        for (int v : t)
            if (v < 0 || v >= nv)
                throw Error(ErrorCode::InvalidInput, "surface query: triangle " + std::to_string(f) +
                                                         " has vertex index " + std::to_string(v) + " out of range");
        const Vec3& a = surface.points[static_cast<std::size_t>(t[0])];
        const Vec3& b = surface.points[static_cast<std::size_t>(t[1])];
        const Vec3& c = surface.points[static_cast<std::size_t>(t[2])];
        if (squared_norm(cross(b - a, c - a)) == 0) continue;  // degenerate: no area, no closest point of its own
        m.triangles.emplace_back(to_cgal(a), to_cgal(b), to_cgal(c));
        m.triangle_id.push_back(static_cast<int>(f));
    }
    if (m.triangles.empty())
        throw Error(ErrorCode::InvalidInput, "surface query: the surface has no non-degenerate triangle");
    m.lo = m.hi = to_vec(m.triangles[0][0]);
    for (const Triangle& t : m.triangles)
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) {
                m.lo[i] = std::min(m.lo[i], t[k][i]);
                m.hi[i] = std::max(m.hi[i], t[k][i]);
            }
    m.diagonal = norm(m.hi - m.lo);
    m.tree.insert(m.triangles.cbegin(), m.triangles.cend());
    m.tree.build();
    // The search kd-tree is built now or never: later queries are read-only (thread-safe).
    if (accelerate)
        m.tree.accelerate_distance_queries();
    else
        m.tree.do_not_accelerate_distance_queries();
    m.primitive_of.assign(surface.triangles.size(), -1);
    for (std::size_t i = 0; i < m.triangle_id.size(); ++i)
        m.primitive_of[static_cast<std::size_t>(m.triangle_id[i])] = static_cast<int>(i);
}

SurfaceQuery::~SurfaceQuery() = default;
SurfaceQuery::SurfaceQuery(SurfaceQuery&&) noexcept = default;
SurfaceQuery& SurfaceQuery::operator=(SurfaceQuery&&) noexcept = default;

const TriangleMesh& SurfaceQuery::surface() const { return impl_->mesh; }
Vec3 SurfaceQuery::bbox_min() const { return impl_->lo; }
Vec3 SurfaceQuery::bbox_max() const { return impl_->hi; }
double SurfaceQuery::bbox_diagonal() const { return impl_->diagonal; }

ClosestPoint SurfaceQuery::closest(const Vec3& p) const {
    const auto r = impl_->tree.closest_point_and_primitive(to_cgal(p));
    ClosestPoint c;
    c.point = to_vec(r.first);
    c.triangle = impl_->id_of(r.second);
    c.squared_distance = squared_norm(c.point - p);
    return c;
}

ClosestPoint SurfaceQuery::closest(const Vec3& p, int hint_triangle) const {
    const Impl& m = *impl_;
    const int prim = hint_triangle >= 0 && static_cast<std::size_t>(hint_triangle) < m.primitive_of.size()
                         ? m.primitive_of[static_cast<std::size_t>(hint_triangle)]
                         : -1;
    if (prim < 0) return closest(p);
    const TriangleIterator it = m.triangles.cbegin() + prim;
    // The hint's closest point bounds the search from the start: the traversal skips every box farther than it.
    const Point q = to_cgal(p);
    const Point on_hint = K().construct_projected_point_3_object()(*it, q);
    const auto r = m.tree.closest_point_and_primitive(q, std::make_pair(on_hint, it));
    ClosestPoint c;
    c.point = to_vec(r.first);
    c.triangle = m.id_of(r.second);
    c.squared_distance = squared_norm(c.point - p);
    return c;
}

double SurfaceQuery::squared_distance(const Vec3& p) const { return impl_->tree.squared_distance(to_cgal(p)); }

std::optional<RayHit> SurfaceQuery::first_hit(const Vec3& origin, const Vec3& direction, double min_distance) const {
    const Vec3 d = normalized(direction);
    if (squared_norm(d) == 0) return std::nullopt;
    std::optional<RayHit> best;
    const double scale = std::max(impl_->diagonal, 1e-300);
    for (const TriangleIterator& it : impl_->candidates(origin, d)) {
        double t = 0;
        const Crossing c = ray_triangle(origin, d, to_vec((*it)[0]), to_vec((*it)[1]), to_vec((*it)[2]), scale, t);
        if (c == Crossing::OnSurface)
            t = 0;
        else if (c == Crossing::None)
            continue;
        if (t <= min_distance) continue;
        if (!best || t < best->distance)
            best = RayHit{origin + t * d, impl_->id_of(it), t};
        else if (t == best->distance)
            best->triangle = std::min(best->triangle, impl_->id_of(it));  // deterministic
    }
    return best;
}

bool SurfaceQuery::inside(const Vec3& p) const { return impl_->inside(p); }

std::vector<ClosestPoint> SurfaceQuery::closest(const std::vector<Vec3>& points) const {
    std::vector<ClosestPoint> out(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) out[i] = closest(points[i]);
                      });
    return out;
}

std::vector<ClosestPoint> SurfaceQuery::closest(const std::vector<Vec3>& points,
                                                const std::vector<int>& hint_triangles) const {
    if (hint_triangles.size() != points.size())
        throw Error(ErrorCode::InvalidInput, "surface query: " + std::to_string(hint_triangles.size()) + " hints for " +
                                                 std::to_string(points.size()) + " points");
    std::vector<ClosestPoint> out(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i)
                              out[i] = closest(points[i], hint_triangles[i]);
                      });
    return out;
}

std::vector<double> SurfaceQuery::squared_distances(const std::vector<Vec3>& points) const {
    std::vector<double> out(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) out[i] = squared_distance(points[i]);
                      });
    return out;
}

std::vector<char> SurfaceQuery::inside(const std::vector<Vec3>& points) const {
    std::vector<char> out(points.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) out[i] = inside(points[i]) ? 1 : 0;
                      });
    return out;
}

}  // namespace mesohex
