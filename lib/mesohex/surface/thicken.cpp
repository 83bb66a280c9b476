// Thickening a skeleton into a closed surface: grid signed distance + marching tetrahedra. See thicken.h.
#include "mesohex/surface/thicken.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <string>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

// ------------------------------------------------------------------------------------------------ primitives

struct Box {
    Vec3 lo, hi;
};

Box sphere_box(const Vec3& c, double r) { return {c - Vec3{r, r, r}, c + Vec3{r, r, r}}; }
Box merge(const Box& a, const Box& b) {
    Box m = a;
    for (int i = 0; i < 3; ++i) {
        m.lo[i] = std::min(a.lo[i], b.lo[i]);
        m.hi[i] = std::max(a.hi[i], b.hi[i]);
    }
    return m;
}

// Convex hull of the spheres (a, ra) and (b, rb).
struct RoundCone {
    Vec3 a, b, u;
    double ra = 0, rb = 0, length = 0, s = 0, c = 1;
    bool nested = false;  // one sphere contains the other (or a == b): the hull is the larger sphere

    RoundCone() = default;
    RoundCone(const Vec3& a_, double ra_, const Vec3& b_, double rb_) : a(a_), b(b_), ra(ra_), rb(rb_) {
        length = distance(a, b);
        nested = length <= std::abs(ra - rb) || length == 0;
        if (!nested) {
            u = (b - a) / length;
            s = (ra - rb) / length;
            c = std::sqrt(std::max(0.0, 1.0 - s * s));
        }
    }
    double sdf(const Vec3& p) const {
        if (nested) return std::min(distance(p, a) - ra, distance(p, b) - rb);
        const Vec3 d = p - a;
        const double x = dot(d, u);
        const double y = std::sqrt(std::max(0.0, squared_norm(d) - x * x));
        const double k = x * c - y * s;  // coordinate along the tangent line
        if (k < 0) return norm(d) - ra;
        if (k > length * c) return distance(p, b) - rb;
        return x * s + y * c - ra;
    }
    Box box() const { return merge(sphere_box(a, ra), sphere_box(b, rb)); }
};

// Convex hull of three spheres = union of the spheres swept over the triangle with the linear radius.
struct Slab {
    Vec3 a, e1, e2, n, g;  // n unit normal, g in-plane gradient of the radius
    double ra = 0, g2 = 0;
    double d11 = 0, d12 = 0, d22 = 0, inv_den = 0;
    bool flat = true;  // degenerate triangle, or |g| >= 1: the minimum is on the edges
    RoundCone edges[3];

    Slab(const Vec3& pa, double r0, const Vec3& pb, double r1, const Vec3& pc, double r2) {
        a = pa;
        ra = r0;
        e1 = pb - pa;
        e2 = pc - pa;
        edges[0] = RoundCone(pa, r0, pb, r1);
        edges[1] = RoundCone(pb, r1, pc, r2);
        edges[2] = RoundCone(pc, r2, pa, r0);
        const Vec3 cr = cross(e1, e2);
        const double area2 = norm(cr);
        d11 = dot(e1, e1);
        d12 = dot(e1, e2);
        d22 = dot(e2, e2);
        const double den = d11 * d22 - d12 * d12;
        if (area2 <= 1e-12 * (d11 + d22) || den <= 0) return;
        n = cr / area2;
        inv_den = 1.0 / den;
        // g = alpha e1 + beta e2 with g.e1 = r1 - r0, g.e2 = r2 - r0.
        const double alpha = ((r1 - r0) * d22 - (r2 - r0) * d12) * inv_den;
        const double beta = ((r2 - r0) * d11 - (r1 - r0) * d12) * inv_den;
        g = alpha * e1 + beta * e2;
        g2 = squared_norm(g);
        flat = g2 >= 1.0 - 1e-12;
    }
    double sdf(const Vec3& p) const {
        const double edge = std::min({edges[0].sdf(p), edges[1].sdf(p), edges[2].sdf(p)});
        if (flat) return edge;
        const double h = dot(p - a, n);
        const double ah = std::abs(h);
        const Vec3 p0 = p - h * n;
        const double q = std::sqrt(1.0 - g2);
        const Vec3 w = g * (ah / q);
        const Vec3 x = p0 + w - a;  // minimizer relative to a, in the plane
        const double bx1 = dot(x, e1), bx2 = dot(x, e2);
        const double v = (d22 * bx1 - d12 * bx2) * inv_den;
        const double t = (d11 * bx2 - d12 * bx1) * inv_den;
        if (v < 0 || t < 0 || v + t > 1) return edge;
        const double r0 = ra + dot(g, p0 - a);
        return std::min(edge, ah * q - r0);
    }
    Box box() const { return merge(edges[0].box(), edges[1].box()); }
};

struct Primitive {
    enum class Kind { Sphere, Cone, Slab } kind;
    int index;  // into the matching array
};

// ------------------------------------------------------------------------------------------------ input

std::vector<double> radii_of(const Skeleton& s, const ThickenOptions& o) {
    const std::size_t nv = s.points.size();
    if (nv == 0) throw Error(ErrorCode::InvalidInput, "thicken: the skeleton has no point");
    for (std::size_t v = 0; v < nv; ++v)
        if (!is_finite(s.points[v]))
            throw Error(ErrorCode::InvalidInput, "thicken: skeleton point " + std::to_string(v) + " is not finite",
                        ElementRef{ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
    std::vector<double> r;
    if (!s.radii.empty()) {
        if (s.radii.size() != nv)
            throw Error(ErrorCode::InvalidInput,
                        "thicken: " + std::to_string(s.radii.size()) + " radii for " + std::to_string(nv) + " points");
        r = s.radii;
    } else {
        if (!(o.radius > 0) || !std::isfinite(o.radius))
            throw Error(ErrorCode::InvalidInput, "thicken: the skeleton has no radii; give a radius (--radius R)");
        r.assign(nv, o.radius);
    }
    for (std::size_t v = 0; v < nv; ++v)
        if (!(r[v] > 0) || !std::isfinite(r[v]))
            throw Error(ErrorCode::InvalidInput,
                        "thicken: skeleton point " + std::to_string(v) + " has radius " + std::to_string(r[v]) +
                            " (must be > 0)",
                        ElementRef{ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
    for (std::size_t e = 0; e < s.edges.size(); ++e)
        for (int v : s.edges[e])
            if (v < 0 || static_cast<std::size_t>(v) >= nv)
                throw Error(
                    ErrorCode::InvalidInput,
                    "thicken: edge " + std::to_string(e) + " has point index " + std::to_string(v) + " out of range",
                    ElementRef{ElementRef::Kind::SkeletonEdge, static_cast<int>(e)});
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
        if (s.faces[f].size() < 3)
            throw Error(ErrorCode::InvalidInput, "thicken: face " + std::to_string(f) + " has fewer than 3 points",
                        ElementRef{ElementRef::Kind::SkeletonFace, static_cast<int>(f)});
        for (int v : s.faces[f])
            if (v < 0 || static_cast<std::size_t>(v) >= nv)
                throw Error(
                    ErrorCode::InvalidInput,
                    "thicken: face " + std::to_string(f) + " has point index " + std::to_string(v) + " out of range",
                    ElementRef{ElementRef::Kind::SkeletonFace, static_cast<int>(f)});
    }
    return r;
}

// ------------------------------------------------------------------------------------------------ marching tets

// The 6 Kuhn tetrahedra of the unit cube (all share the diagonal 000-111), as corner codes dx + 2 dy + 4 dz, each
// reordered to positive orientation.
struct TetTable {
    int tet[6][4];
    TetTable() {
        const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
        for (int t = 0; t < 6; ++t) {
            int code = 0;
            tet[t][0] = 0;
            for (int k = 0; k < 3; ++k) {
                code |= 1 << axes[t][k];
                tet[t][k + 1] = code;
            }
            auto corner = [](int c) { return Vec3{double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)}; };
            const Vec3 o = corner(tet[t][0]);
            if (det3(corner(tet[t][1]) - o, corner(tet[t][2]) - o, corner(tet[t][3]) - o) < 0)
                std::swap(tet[t][2], tet[t][3]);
        }
    }
};

int inversions(const int s[4]) {
    int n = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
            if (s[i] > s[j]) ++n;
    return n;
}

struct Crossing {
    std::uint64_t key;
    Vec3 point;
};

// The union of the primitives (spheres at unused points, round cones on edges, slabs on face triangles).
struct Primitives {
    std::vector<Vec3> sphere_c;
    std::vector<double> sphere_r;
    std::vector<RoundCone> cones;
    std::vector<Slab> slabs;
    std::vector<Primitive> prims;
    std::vector<Box> boxes;

    double sdf(std::size_t i, const Vec3& p) const {
        const Primitive& pr = prims[i];
        const std::size_t k = static_cast<std::size_t>(pr.index);
        switch (pr.kind) {
            case Primitive::Kind::Sphere: return distance(p, sphere_c[k]) - sphere_r[k];
            case Primitive::Kind::Cone: return cones[k].sdf(p);
            case Primitive::Kind::Slab: return slabs[k].sdf(p);
        }
        return 0.0;
    }
};

Primitives build_primitives(const Skeleton& skeleton, const std::vector<double>& radius) {
    const std::vector<Vec3>& P = skeleton.points;
    auto R = [&](int v) { return radius[static_cast<std::size_t>(v)]; };
    auto X = [&](int v) { return P[static_cast<std::size_t>(v)]; };
    Primitives u;
    std::vector<char> used(P.size(), 0);
    for (const std::array<int, 2>& e : skeleton.edges) {
        used[static_cast<std::size_t>(e[0])] = used[static_cast<std::size_t>(e[1])] = 1;
        u.cones.emplace_back(X(e[0]), R(e[0]), X(e[1]), R(e[1]));
    }
    for (const std::vector<int>& f : skeleton.faces) {
        for (int v : f) used[static_cast<std::size_t>(v)] = 1;
        if (f.size() == 4) {
            // Split along the shorter diagonal.
            const bool d02 = distance(X(f[0]), X(f[2])) <= distance(X(f[1]), X(f[3]));
            const int o = d02 ? 0 : 1;
            const int a = f[static_cast<std::size_t>(o)], b = f[static_cast<std::size_t>(o + 1)],
                      c = f[static_cast<std::size_t>(o + 2)], d = f[static_cast<std::size_t>((o + 3) % 4)];
            u.slabs.emplace_back(X(a), R(a), X(b), R(b), X(c), R(c));
            u.slabs.emplace_back(X(a), R(a), X(c), R(c), X(d), R(d));
        } else {
            for (std::size_t i = 1; i + 1 < f.size(); ++i)
                u.slabs.emplace_back(X(f[0]), R(f[0]), X(f[i]), R(f[i]), X(f[i + 1]), R(f[i + 1]));
        }
    }
    for (std::size_t v = 0; v < P.size(); ++v)
        if (!used[v]) {
            u.sphere_c.push_back(P[v]);
            u.sphere_r.push_back(radius[v]);
        }
    for (std::size_t i = 0; i < u.sphere_c.size(); ++i) {
        u.prims.push_back({Primitive::Kind::Sphere, static_cast<int>(i)});
        u.boxes.push_back(sphere_box(u.sphere_c[i], u.sphere_r[i]));
    }
    for (std::size_t i = 0; i < u.cones.size(); ++i) {
        u.prims.push_back({Primitive::Kind::Cone, static_cast<int>(i)});
        u.boxes.push_back(u.cones[i].box());
    }
    for (std::size_t i = 0; i < u.slabs.size(); ++i) {
        u.prims.push_back({Primitive::Kind::Slab, static_cast<int>(i)});
        u.boxes.push_back(u.slabs[i].box());
    }
    return u;
}

// The sampled distance grid and the marching-tetrahedra passes over it.
struct Grid {
    const Primitives& u;
    double h = 0;
    int dims[3] = {0, 0, 0};
    int nx = 0, ny = 0, nz = 0;
    Vec3 origin;
    std::size_t slice = 0;
    std::vector<float> value;
    std::vector<std::array<int, 6>> range;      // index ranges of every primitive (box + 2 cells)
    std::vector<std::vector<int>> slice_prims;  // the primitives of every z-slice
    std::vector<long> slice_evals;
    std::vector<std::vector<Crossing>> crossings;
    std::vector<int> first_id;
    std::vector<std::vector<std::array<int, 3>>> tris;

    explicit Grid(const Primitives& prims) : u(prims) {}

    Vec3 grid_point(int i, int j, int k) const {
        return origin + Vec3{static_cast<double>(i) * h, static_cast<double>(j) * h, static_cast<double>(k) * h};
    }
    float val(int i, int j, int k) const {
        return value[static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * static_cast<std::size_t>(j) +
                     slice * static_cast<std::size_t>(k)];
    }
    static bool inside(float f) { return f < 0; }

    // Grid step r_min / cells_per_radius, coarsened until the grid has at most max_grid_points points.
    void size(double r_min, const ThickenOptions& options) {
        Box all = u.boxes[0];
        for (const Box& b : u.boxes) all = merge(all, b);
        h = r_min / options.cells_per_radius;
        for (int iter = 0;; ++iter) {
            double count = 1;
            for (int i = 0; i < 3; ++i) {
                dims[i] = static_cast<int>(std::ceil((all.hi[i] - all.lo[i]) / h)) + 7;  // 3 cells of margin each side
                count *= dims[i];
            }
            if (count <= static_cast<double>(options.max_grid_points)) break;
            h *= std::max(1.01, std::cbrt(count / static_cast<double>(options.max_grid_points)));
            MESOHEX_CHECK(iter < 100, "grid sizing did not converge");
        }
        nx = dims[0];
        ny = dims[1];
        nz = dims[2];
        origin = all.lo - Vec3{3 * h, 3 * h, 3 * h};
        slice = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    }

    // Distance of the union at every grid point near a primitive (FLT_MAX elsewhere), z-slices in parallel.
    void sample() {
        value.assign(slice * static_cast<std::size_t>(nz), FLT_MAX);
        range.resize(u.prims.size());
        slice_prims.assign(static_cast<std::size_t>(nz), {});
        for (std::size_t i = 0; i < u.prims.size(); ++i) {
            for (int a = 0; a < 3; ++a) {
                range[i][2 * a] = std::max(0, static_cast<int>(std::floor((u.boxes[i].lo[a] - origin[a]) / h)) - 2);
                range[i][2 * a + 1] =
                    std::min(dims[a] - 1, static_cast<int>(std::ceil((u.boxes[i].hi[a] - origin[a]) / h)) + 2);
            }
            for (int k = range[i][4]; k <= range[i][5]; ++k)
                slice_prims[static_cast<std::size_t>(k)].push_back(static_cast<int>(i));
        }
        slice_evals.assign(static_cast<std::size_t>(nz), 0);
        tbb::parallel_for(tbb::blocked_range<int>(0, nz), [&](const tbb::blocked_range<int>& rk) {
            for (int k = rk.begin(); k != rk.end(); ++k) {
                float* vals = value.data() + slice * static_cast<std::size_t>(k);
                long evals = 0;
                for (int pi : slice_prims[static_cast<std::size_t>(k)]) {
                    const std::array<int, 6>& rg = range[static_cast<std::size_t>(pi)];
                    for (int j = rg[2]; j <= rg[3]; ++j)
                        for (int i = rg[0]; i <= rg[1]; ++i) {
                            const double d = u.sdf(static_cast<std::size_t>(pi), grid_point(i, j, k));
                            float& slot = vals[static_cast<std::size_t>(i) +
                                               static_cast<std::size_t>(nx) * static_cast<std::size_t>(j)];
                            slot = std::min(slot, static_cast<float>(d));
                            ++evals;
                        }
                }
                slice_evals[static_cast<std::size_t>(k)] = evals;
            }
        });
    }

    // The crossing on grid edge a-b: the linear-interpolation estimate t0 refined on the exact distance of the union
    // (Illinois regula falsi), so that surface vertices lie on the union's surface and not inside it (linear
    // interpolation of a convex distance is biased inward: -3 % of a sphere's volume at 4 cells per radius). The
    // primitives that can matter are those of the lower end's slice whose index box contains the lower end (the
    // boxes are expanded by 2 cells). Falls back to t0 when the exact values do not bracket a root.
    double refine_root(int k, int i, int j, const Vec3& a, const Vec3& b, double t0) const {
        int local[64];
        int nl = 0;
        for (int pi : slice_prims[static_cast<std::size_t>(k)]) {
            const std::array<int, 6>& rg = range[static_cast<std::size_t>(pi)];
            if (i < rg[0] || i > rg[1] || j < rg[2] || j > rg[3]) continue;
            if (nl == 64) return t0;  // pathological overlap: keep the estimate
            local[nl++] = pi;
        }
        auto g = [&](double t) {
            const Vec3 p = a + t * (b - a);
            double d = DBL_MAX;
            for (int q = 0; q < nl; ++q) d = std::min(d, u.sdf(static_cast<std::size_t>(local[q]), p));
            return d;
        };
        double lo = 0, hi = 1, glo = g(0), ghi = g(1);
        if (!((glo < 0) != (ghi < 0)) || glo == DBL_MAX || ghi == DBL_MAX) return t0;
        int side = 0;
        double t = t0;
        for (int it = 0; it < 8; ++it) {
            t = lo + glo / (glo - ghi) * (hi - lo);
            const double gt = g(t);
            if (std::abs(gt) <= 1e-9 * h) break;
            if ((gt < 0) == (glo < 0)) {
                lo = t;
                glo = gt;
                if (side == -1) ghi *= 0.5;
                side = -1;
            } else {
                hi = t;
                ghi = gt;
                if (side == 1) glo *= 0.5;
                side = 1;
            }
        }
        return t;
    }

    // Pass A: crossing points, one per grid edge with a sign change, owned by the slice of its lower end.
    // Edge key = 7 x (linear index of the lower end) + direction code (dx + 2 dy + 4 dz - 1).
    void find_crossings() {
        crossings.assign(static_cast<std::size_t>(nz), {});
        tbb::parallel_for(tbb::blocked_range<int>(0, nz), [&](const tbb::blocked_range<int>& rk) {
            for (int k = rk.begin(); k != rk.end(); ++k) {
                std::vector<Crossing>& out = crossings[static_cast<std::size_t>(k)];
                for (int j = 0; j < ny; ++j)
                    for (int i = 0; i < nx; ++i) {
                        const float f0 = val(i, j, k);
                        for (int code = 1; code < 8; ++code) {
                            const int i1 = i + (code & 1), j1 = j + ((code >> 1) & 1), k1 = k + ((code >> 2) & 1);
                            if (i1 >= nx || j1 >= ny || k1 >= nz) continue;
                            const float f1 = val(i1, j1, k1);
                            if (inside(f0) == inside(f1)) continue;
                            const Vec3 a = grid_point(i, j, k), b = grid_point(i1, j1, k1);
                            double t = static_cast<double>(f0) / (static_cast<double>(f0) - static_cast<double>(f1));
                            t = refine_root(k, i, j, a, b, t);
                            t = std::clamp(t, 0.01,
                                           0.99);  // keeps surface vertices apart (at most 1 % of a cell moved)
                            const std::uint64_t lin =
                                static_cast<std::uint64_t>(i) +
                                static_cast<std::uint64_t>(nx) *
                                    (static_cast<std::uint64_t>(j) +
                                     static_cast<std::uint64_t>(ny) * static_cast<std::uint64_t>(k));
                            out.push_back({7 * lin + static_cast<std::uint64_t>(code - 1), a + t * (b - a)});
                        }
                    }
            }
        });
        first_id.assign(static_cast<std::size_t>(nz) + 1, 0);
        for (int k = 0; k < nz; ++k)
            first_id[static_cast<std::size_t>(k) + 1] =
                first_id[static_cast<std::size_t>(k)] + static_cast<int>(crossings[static_cast<std::size_t>(k)].size());
    }

    int find_vertex(int i, int j, int k, int code) const {
        const std::uint64_t lin =
            static_cast<std::uint64_t>(i) +
            static_cast<std::uint64_t>(nx) *
                (static_cast<std::uint64_t>(j) + static_cast<std::uint64_t>(ny) * static_cast<std::uint64_t>(k));
        const std::uint64_t key = 7 * lin + static_cast<std::uint64_t>(code - 1);
        const std::vector<Crossing>& c = crossings[static_cast<std::size_t>(k)];
        const auto it =
            std::lower_bound(c.begin(), c.end(), key, [](const Crossing& x, std::uint64_t kk) { return x.key < kk; });
        MESOHEX_CHECK(it != c.end() && it->key == key, "marching tetrahedra: crossing not found");
        return first_id[static_cast<std::size_t>(k)] + static_cast<int>(it - c.begin());
    }

    const Vec3& point_of(int id) const {
        const std::size_t k =
            static_cast<std::size_t>(std::upper_bound(first_id.begin(), first_id.end(), id) - first_id.begin()) - 1;
        return crossings[k][static_cast<std::size_t>(id - first_id[k])].point;
    }

    // The triangles of one Kuhn tetrahedron `tet` of cell (i, j, k) with corner values cf.
    void tet_triangles(int i, int j, int k, const int* tet, const float* cf,
                       std::vector<std::array<int, 3>>& out) const {
        // Surface vertex on the tet edge between corners ca and cb (codes; one of them is <= the other componentwise
        // since all Kuhn tet edges are monotone).
        auto edge_vertex = [&](int ca, int cb) {
            if ((ca & cb) != ca) std::swap(ca, cb);  // ca = lower end
            return find_vertex(i + (ca & 1), j + ((ca >> 1) & 1), k + ((ca >> 2) & 1), cb - ca);
        };
        int neg[4], pos[4], nn = 0, np = 0;
        for (int q = 0; q < 4; ++q) {
            if (inside(cf[tet[q]]))
                neg[nn++] = q;
            else
                pos[np++] = q;
        }
        if (nn == 0 || nn == 4) return;
        if (nn == 1 || nn == 3) {
            const int lone = nn == 1 ? neg[0] : pos[0];
            int seq[4] = {lone, 0, 0, 0};
            for (int q = 0, m = 1; q < 4; ++q)
                if (q != lone) seq[m++] = q;
            if (inversions(seq) % 2 == 1) std::swap(seq[2], seq[3]);
            // (e_l1, e_l2, e_l3) faces away from `lone`: right for a lone inside corner.
            if (nn == 3) std::swap(seq[2], seq[3]);
            out.push_back({edge_vertex(tet[seq[0]], tet[seq[1]]), edge_vertex(tet[seq[0]], tet[seq[2]]),
                           edge_vertex(tet[seq[0]], tet[seq[3]])});
            return;
        }
        int seq[4] = {neg[0], neg[1], pos[0], pos[1]};
        if (inversions(seq) % 2 == 1) std::swap(seq[2], seq[3]);
        const int I = tet[seq[0]], J = tet[seq[1]], Kc = tet[seq[2]], L = tet[seq[3]];
        const int q0 = edge_vertex(I, Kc), q1 = edge_vertex(I, L), q2 = edge_vertex(J, L), q3 = edge_vertex(J, Kc);
        // Split the quad along its shorter diagonal.
        if (squared_norm(point_of(q0) - point_of(q2)) <= squared_norm(point_of(q1) - point_of(q3))) {
            out.push_back({q0, q1, q2});
            out.push_back({q0, q2, q3});
        } else {
            out.push_back({q0, q1, q3});
            out.push_back({q1, q2, q3});
        }
    }

    // Pass B: triangles, per cell slice.
    void triangulate() {
        static const TetTable table;
        tris.assign(static_cast<std::size_t>(std::max(0, nz - 1)), {});
        tbb::parallel_for(tbb::blocked_range<int>(0, std::max(0, nz - 1)), [&](const tbb::blocked_range<int>& rk) {
            for (int k = rk.begin(); k != rk.end(); ++k) {
                std::vector<std::array<int, 3>>& out = tris[static_cast<std::size_t>(k)];
                for (int j = 0; j + 1 < ny; ++j)
                    for (int i = 0; i + 1 < nx; ++i) {
                        float cf[8];
                        int nin = 0;
                        for (int c = 0; c < 8; ++c) {
                            cf[c] = val(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                            nin += inside(cf[c]) ? 1 : 0;
                        }
                        if (nin == 0 || nin == 8) continue;
                        for (const auto& tet : table.tet) tet_triangles(i, j, k, tet, cf, out);
                    }
            }
        });
    }

    TriangleMesh assemble() const {
        TriangleMesh mesh;
        mesh.points.reserve(static_cast<std::size_t>(first_id.back()));
        for (const std::vector<Crossing>& c : crossings)
            for (const Crossing& x : c) mesh.points.push_back(x.point);
        std::size_t nt = 0;
        for (const auto& t : tris) nt += t.size();
        mesh.triangles.reserve(nt);
        for (const auto& t : tris) mesh.triangles.insert(mesh.triangles.end(), t.begin(), t.end());
        return mesh;
    }
};

}  // namespace

TriangleMesh thicken(const Skeleton& skeleton, const ThickenOptions& options, ThickenStats* stats) {
    const std::vector<double> radius = radii_of(skeleton, options);
    if (!(options.cells_per_radius > 0)) throw Error(ErrorCode::InvalidInput, "thicken: cells_per_radius must be > 0");
    if (options.max_grid_points < 1000)
        throw Error(ErrorCode::InvalidInput, "thicken: max_grid_points must be >= 1000");
    const Primitives prims = build_primitives(skeleton, radius);
    Grid grid(prims);
    grid.size(*std::min_element(radius.begin(), radius.end()), options);
    grid.sample();
    grid.find_crossings();
    grid.triangulate();
    TriangleMesh mesh = grid.assemble();
    if (stats) {
        stats->cell_size = grid.h;
        stats->nx = grid.nx;
        stats->ny = grid.ny;
        stats->nz = grid.nz;
        stats->primitives = static_cast<int>(prims.prims.size());
        stats->evaluations = 0;
        for (long e : grid.slice_evals) stats->evaluations += e;
    }
    return mesh;
}

}  // namespace mesohex
