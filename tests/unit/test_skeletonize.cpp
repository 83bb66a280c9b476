// Mean-curvature skeletons of shapes made here: a capsule, a torus, an L-shaped (bent) tube; and rejected surfaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/surface/skeletonize.h"
#include "surface_fixtures.h"

namespace mesohex {
namespace {

constexpr double kPi = std::numbers::pi;

double signed_volume(const TriangleMesh& m) {
    double v = 0;
    for (const std::array<int, 3>& t : m.triangles)
        v += det3(m.points[static_cast<size_t>(t[0])], m.points[static_cast<size_t>(t[1])],
                  m.points[static_cast<size_t>(t[2])]);
    return v / 6;
}

void orient_outward(TriangleMesh& m) {
    if (signed_volume(m) < 0)
        for (std::array<int, 3>& t : m.triangles) std::swap(t[1], t[2]);
}

// A tube of radius r around a polyline path (with per-point tangents), closed by hemispherical caps.
TriangleMesh capped_tube(const std::vector<Vec3>& path, const std::vector<Vec3>& tangents, double r, int around) {
    struct Ring {
        Vec3 centre, tangent;
        double radius;
    };
    std::vector<Ring> rings;
    const int cap_rings = 6;
    for (int k = 1; k < cap_rings; ++k) {  // start cap, from near the pole to the equator
        const double a = 0.5 * kPi * k / cap_rings;
        rings.push_back({path.front() - tangents.front() * (r * std::cos(a)), tangents.front(), r * std::sin(a)});
    }
    for (size_t i = 0; i < path.size(); ++i) rings.push_back({path[i], tangents[i], r});
    for (int k = cap_rings - 1; k >= 1; --k) {
        const double a = 0.5 * kPi * k / cap_rings;
        rings.push_back({path.back() + tangents.back() * (r * std::cos(a)), tangents.back(), r * std::sin(a)});
    }
    TriangleMesh m;
    m.points.push_back(path.front() - tangents.front() * r);  // start pole
    for (const Ring& ring : rings) {
        const Vec3 n1{0, 0, 1};
        Vec3 u = normalized(cross(ring.tangent, n1));
        if (squared_norm(u) == 0) u = {1, 0, 0};
        const Vec3 w = normalized(cross(ring.tangent, u));
        for (int j = 0; j < around; ++j) {
            const double phi = 2 * kPi * j / around;
            m.points.push_back(ring.centre + (u * std::cos(phi) + w * std::sin(phi)) * ring.radius);
        }
    }
    m.points.push_back(path.back() + tangents.back() * r);  // end pole
    const int nr = static_cast<int>(rings.size());
    auto id = [&](int ring, int j) { return 1 + ring * around + (j % around); };
    for (int j = 0; j < around; ++j) m.triangles.push_back({0, id(0, j + 1), id(0, j)});
    for (int i = 0; i + 1 < nr; ++i)
        for (int j = 0; j < around; ++j) {
            m.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
        }
    const int end_pole = static_cast<int>(m.points.size()) - 1;
    for (int j = 0; j < around; ++j) m.triangles.push_back({end_pole, id(nr - 1, j), id(nr - 1, j + 1)});
    orient_outward(m);
    return m;
}

// Capsule along z: cylinder from z = -h to h, radius r.
TriangleMesh capsule(double h, double r) {
    const int around = 24;
    const double step = 2 * kPi * r / around;
    const int n = static_cast<int>(std::ceil(2 * h / step));
    std::vector<Vec3> path, tangents;
    for (int i = 0; i <= n; ++i) {
        path.push_back({0, 0, -h + 2 * h * i / n});
        tangents.push_back({0, 0, 1});
    }
    return capped_tube(path, tangents, r, around);
}

// L: leg from (0, L, 0) down to (0, b, 0), quarter circle of radius b centred at (b, b, 0), leg to (L, 0, 0).
TriangleMesh bent_tube(double L, double b, double r) {
    const int around = 24;
    const double step = 2 * kPi * r / around;
    std::vector<Vec3> path, tangents;
    const int n_leg = static_cast<int>(std::ceil((L - b) / step));
    for (int i = 0; i < n_leg; ++i) {
        path.push_back({0, L - (L - b) * i / n_leg, 0});
        tangents.push_back({0, -1, 0});
    }
    const int n_arc = static_cast<int>(std::ceil(0.5 * kPi * b / step));
    for (int i = 0; i < n_arc; ++i) {
        const double a = kPi + 0.5 * kPi * i / n_arc;  // from (0, b) around the centre (b, b) to (b, 0)
        path.push_back({b + b * std::cos(a), b + b * std::sin(a), 0});
        tangents.push_back({-std::sin(a), std::cos(a), 0});
    }
    for (int i = 0; i <= n_leg; ++i) {
        path.push_back({b + (L - b) * i / n_leg, 0, 0});
        tangents.push_back({1, 0, 0});
    }
    return capped_tube(path, tangents, r, around);
}

TriangleMesh torus(double R, double r, int nu, int nv) {
    TriangleMesh m = test::torus_surface(R, r, nu, nv);
    orient_outward(m);
    return m;
}

std::vector<int> degrees(const Skeleton& s) {
    std::vector<int> d(s.points.size(), 0);
    for (const std::array<int, 2>& e : s.edges) {
        ++d[static_cast<size_t>(e[0])];
        ++d[static_cast<size_t>(e[1])];
    }
    return d;
}

int count_degree(const Skeleton& s, int k, bool at_least = false) {
    int n = 0;
    for (int d : degrees(s))
        if (d == k || (at_least && d > k)) ++n;
    return n;
}

bool connected(const Skeleton& s) {
    std::vector<std::vector<int>> adj(s.points.size());
    for (const std::array<int, 2>& e : s.edges) {
        adj[static_cast<size_t>(e[0])].push_back(e[1]);
        adj[static_cast<size_t>(e[1])].push_back(e[0]);
    }
    std::vector<bool> seen(s.points.size(), false);
    std::vector<int> stack{0};
    seen[0] = true;
    size_t count = 1;
    while (!stack.empty()) {
        const int v = stack.back();
        stack.pop_back();
        for (int u : adj[static_cast<size_t>(v)])
            if (!seen[static_cast<size_t>(u)]) {
                seen[static_cast<size_t>(u)] = true;
                ++count;
                stack.push_back(u);
            }
    }
    return count == s.points.size();
}

TEST(Skeletonize, CapsuleGivesOneBranchWithTrueRadius) {
    const double h = 2.0, r = 0.5;
    const Skeletonization sk = skeletonize_surface(capsule(h, r));
    const Skeleton& s = sk.skeleton;
    ASSERT_GE(s.points.size(), 3u);
    ASSERT_EQ(s.radii.size(), s.points.size());
    EXPECT_TRUE(s.faces.empty());
    EXPECT_TRUE(connected(s));
    EXPECT_EQ(count_degree(s, 1), 2);        // two extremities
    EXPECT_EQ(count_degree(s, 3, true), 0);  // no branching point
    EXPECT_EQ(euler_characteristic(s), 1);   // a tree (path)
    int checked = 0;
    double zmax = -1e9, zmin = 1e9;
    for (size_t v = 0; v < s.points.size(); ++v) {
        const Vec3& p = s.points[v];
        zmax = std::max(zmax, p.z);
        zmin = std::min(zmin, p.z);
        EXPECT_LT(std::hypot(p.x, p.y), 0.1 * r) << "vertex " << v << " off the axis";
        if (std::abs(p.z) <= h - r) {  // along the cylinder, away from the caps
            EXPECT_NEAR(s.radii[v], r, 0.1 * r) << "vertex " << v << " at z = " << p.z;
            ++checked;
        }
    }
    EXPECT_GE(checked, 3);
    // Extremities extended towards the tips (z = +-(h + r)), stopping half a radius short, give or take.
    EXPECT_GT(zmax, h + 0.25 * r);
    EXPECT_LT(zmax, h + r);
    EXPECT_LT(zmin, -h - 0.25 * r);
    EXPECT_GT(zmin, -h - r);
}

TEST(Skeletonize, TorusGivesOneCycle) {
    const double R = 1.0, r = 0.3;
    const Skeletonization sk = skeletonize_surface(torus(R, r, 64, 16));
    const Skeleton& s = sk.skeleton;
    EXPECT_TRUE(connected(s));
    EXPECT_EQ(euler_characteristic(s), 0);                             // V - E = 0: exactly one independent cycle
    EXPECT_EQ(count_degree(s, 2), static_cast<int>(s.points.size()));  // a plain cycle: no spur left
    for (size_t v = 0; v < s.points.size(); ++v) {
        EXPECT_NEAR(std::hypot(s.points[v].x, s.points[v].y), R, 0.1 * r);
        EXPECT_NEAR(s.radii[v], r, 0.1 * r) << "vertex " << v;
    }
}

TEST(Skeletonize, BentTubeGivesAPathWithTrueRadii) {
    const double L = 3.0, b = 0.8, r = 0.4;
    const Skeletonization sk = skeletonize_surface(bent_tube(L, b, r));
    const Skeleton& s = sk.skeleton;
    EXPECT_TRUE(connected(s));
    EXPECT_EQ(euler_characteristic(s), 1);
    const int branch_points = count_degree(s, 3, true);
    EXPECT_LE(branch_points, 1);
    EXPECT_EQ(count_degree(s, 1), 2 + branch_points);  // a path, or a 3-branch if MCF keeps a corner branch
    int checked = 0;
    for (size_t v = 0; v < s.points.size(); ++v) {
        const Vec3& p = s.points[v];
        // Along the straight legs, away from the bend and the caps, the radius is the tube's.
        const bool leg1 = p.x < 0.1 * r && p.y > b + r && p.y < L - r;
        const bool leg2 = p.y < 0.1 * r && p.x > b + r && p.x < L - r;
        if (leg1 || leg2) {
            EXPECT_NEAR(s.radii[v], r, 0.1 * r) << "vertex " << v;
            ++checked;
        }
    }
    EXPECT_GE(checked, 4);
}

// A tube along z from -h to h, closed by flat ends, whose one side bulges: the cross-section at height z is the circle
// of radius r + b(z) / 2 around (b(z) / 2, 0, z), b(z) = a exp(-(z / w)^2): its side at x = -r stays straight, the
// other side moves out to r + b(z) (a knob's lobe). The middle of the section at z is x = b(z) / 2.
TriangleMesh one_sided_bulge(double h, double r, double a, double w) {
    const int around = 32, n = 80;
    TriangleMesh m;
    m.points.push_back({0, 0, -h});
    for (int i = 0; i <= n; ++i) {
        const double z = -h + 2 * h * i / n;
        const double b = a * std::exp(-(z / w) * (z / w));
        for (int j = 0; j < around; ++j) {
            const double phi = 2 * kPi * j / around;
            m.points.push_back({0.5 * b + (r + 0.5 * b) * std::cos(phi), (r + 0.5 * b) * std::sin(phi), z});
        }
    }
    m.points.push_back({0, 0, h});
    auto id = [&](int ring, int j) { return 1 + ring * around + (j % around); };
    for (int j = 0; j < around; ++j) m.triangles.push_back({0, id(0, j + 1), id(0, j)});
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < around; ++j) {
            m.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
        }
    const int top = static_cast<int>(m.points.size()) - 1;
    for (int j = 0; j < around; ++j) m.triangles.push_back({top, id(n, j), id(n, j + 1)});
    orient_outward(m);
    return m;
}

// The flow's curve cuts a one-sided bulge short (mean curvature smooths it), the re-centring puts the joints back in
// the middle of their cross-sections. A bulge of a = 2 r over w = 2 r on a tube of radius r = 0.5: at the top of the
// bulge (|z| <= w / 4, where the section normal to the curve is within 14 degrees of the z plane and its middle within
// 0.03 r of x = b(z) / 2) every joint lies within 0.1 r of that middle, less than half as far as the flow's own curve
// (measured: 0.06 r against 0.17 r); the same number of points and edges (the extension may differ). With 0 passes
// nothing moves.
TEST(Skeletonize, JointsAreRecentredInTheirCrossSections) {
    const double h = 3.0, r = 0.5, a = 1.0, w = 1.0;
    const TriangleMesh surface = one_sided_bulge(h, r, a, w);
    SkeletonizeOptions off;
    off.recentre_passes = 0;
    const Skeletonization flow = skeletonize_surface(surface, off);
    EXPECT_EQ(flow.recentred_joints, 0);
    EXPECT_EQ(flow.recentre_max_shift, 0.0);
    const Skeletonization centred = skeletonize_surface(surface);
    ASSERT_EQ(centred.skeleton.points.size(), flow.skeleton.points.size());  // moves only: the same graph
    EXPECT_EQ(centred.skeleton.edges.size(), flow.skeleton.edges.size());
    EXPECT_GT(centred.recentred_joints, 0);
    EXPECT_EQ(centred.flow_skeleton.points, flow.skeleton.points);  // the fallback is the flow's curve, bit for bit
    EXPECT_EQ(centred.flow_skeleton.edges, flow.skeleton.edges);
    EXPECT_EQ(flow.flow_skeleton.points, flow.skeleton.points);
    auto off_middle = [&](const Skeleton& s) {
        double worst = 0;
        int counted = 0;
        for (const Vec3& p : s.points) {
            if (std::abs(p.z) > 0.25 * w) continue;
            const double middle = 0.5 * a * std::exp(-(p.z / w) * (p.z / w));
            worst = std::max(worst, std::hypot(p.x - middle, p.y));
            ++counted;
        }
        EXPECT_GE(counted, 2);
        return worst;
    };
    const double flow_off = off_middle(flow.skeleton), centred_off = off_middle(centred.skeleton);
    EXPECT_LT(centred_off, 0.1 * r) << "flow's curve: " << flow_off;
    EXPECT_LT(centred_off, 0.5 * flow_off);
}

// Same input, same output bits, whatever the heap looks like: CGAL's MCF used to collapse edges in address order.
// Between runs, the heap is churned (many small blocks allocated, every other one freed) so that the flow's internal
// mesh elements land at other addresses and in another relative order.
TEST(Skeletonize, SameSurfaceSameSkeletonWhateverTheHeap) {
    for (const TriangleMesh& surface : {bent_tube(3.0, 0.8, 0.4), torus(1.0, 0.3, 48, 12)}) {
        const Skeletonization first = skeletonize_surface(surface);
        std::vector<std::vector<char>> churn;
        for (int run = 1; run <= 3; ++run) {
            for (int k = 0; k < 4000 * run; ++k) churn.emplace_back(static_cast<size_t>(8 + (k * 37) % 300));
            for (size_t k = 0; k < churn.size(); k += 2) std::vector<char>().swap(churn[k]);
            const TriangleMesh copy = surface;  // a copy at another address
            const Skeletonization again = skeletonize_surface(copy);
            EXPECT_EQ(again.mcf_vertices, first.mcf_vertices) << "run " << run;
            ASSERT_EQ(again.skeleton.points.size(), first.skeleton.points.size()) << "run " << run;
            for (size_t v = 0; v < first.skeleton.points.size(); ++v) {
                // Exact equality on purpose: the same bits are required.
                EXPECT_EQ(again.skeleton.points[v].x, first.skeleton.points[v].x) << "run " << run << " vertex " << v;
                EXPECT_EQ(again.skeleton.points[v].y, first.skeleton.points[v].y) << "run " << run << " vertex " << v;
                EXPECT_EQ(again.skeleton.points[v].z, first.skeleton.points[v].z) << "run " << run << " vertex " << v;
            }
            EXPECT_EQ(again.skeleton.radii, first.skeleton.radii) << "run " << run;
            EXPECT_EQ(again.skeleton.edges, first.skeleton.edges) << "run " << run;
        }
    }
}

TEST(Skeletonize, OutputOrderIsCanonical) {
    const Skeleton s = skeletonize_surface(bent_tube(3.0, 0.8, 0.4)).skeleton;
    ASSERT_GE(s.points.size(), 2u);
    for (size_t v = 1; v < s.points.size(); ++v) {
        const Vec3 &a = s.points[v - 1], &b = s.points[v];
        EXPECT_TRUE(std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z)) << "vertices " << v - 1 << ", " << v;
    }
    for (size_t e = 0; e < s.edges.size(); ++e) {
        EXPECT_LT(s.edges[e][0], s.edges[e][1]) << "edge " << e;
        if (e > 0) {
            EXPECT_LT(s.edges[e - 1], s.edges[e]) << "edge " << e;
        }
    }
}

std::string error_of(const TriangleMesh& m) {
    try {
        skeletonize_surface(m);
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        return e.what();
    }
    return "";
}

TriangleMesh tetrahedron(Vec3 o) {
    TriangleMesh m;
    m.points = {o, o + Vec3{1, 0, 0}, o + Vec3{0, 1, 0}, o + Vec3{0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

TriangleMesh merged(TriangleMesh a, const TriangleMesh& b, int shared_vertices) {
    // b's first `shared_vertices` vertices are a's first ones.
    const int offset = static_cast<int>(a.points.size()) - shared_vertices;
    for (size_t v = static_cast<size_t>(shared_vertices); v < b.points.size(); ++v) a.points.push_back(b.points[v]);
    for (std::array<int, 3> t : b.triangles) {
        for (int& x : t)
            if (x >= shared_vertices) x += offset;
        a.triangles.push_back(t);
    }
    return a;
}

TEST(Skeletonize, RejectsSurfacesThatCannotBeSkeletonized) {
    TriangleMesh open = capsule(1.0, 0.5);
    open.triangles.pop_back();
    EXPECT_NE(error_of(open).find("the surface is open"), std::string::npos);
    open.triangles.resize(3);
    EXPECT_NE(error_of(open).find("3 triangles"), std::string::npos);

    EXPECT_NE(error_of(merged(tetrahedron({0, 0, 0}), tetrahedron({5, 0, 0}), 0)).find("2 connected components"),
              std::string::npos);

    // Two tetrahedra sharing vertex 0 only: edge-manifold, not vertex-manifold.
    TriangleMesh pinch = merged(tetrahedron({0, 0, 0}), tetrahedron({0, 0, 0}), 1);
    for (size_t v = 4; v < pinch.points.size(); ++v) pinch.points[v] = -1.0 * pinch.points[v];
    EXPECT_NE(error_of(pinch).find("not manifold at vertex 0"), std::string::npos);

    // Two tetrahedra sharing edge 0-1: that edge is in 4 triangles.
    EXPECT_NE(error_of(merged(tetrahedron({0, 0, 0}), tetrahedron({0, 0, 0}), 2)).find("not manifold"),
              std::string::npos);

    TriangleMesh flipped = tetrahedron({0, 0, 0});
    std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
    EXPECT_NE(error_of(flipped).find("not consistently oriented"), std::string::npos);

    TriangleMesh out_of_range = tetrahedron({0, 0, 0});
    out_of_range.triangles[0][0] = 7;
    EXPECT_NE(error_of(out_of_range).find("out of range"), std::string::npos);
}

TEST(Skeletonize, UnreferencedVerticesAreIgnored) {
    TriangleMesh m = capsule(1.0, 0.5);
    m.points.insert(m.points.begin(), Vec3{100, 100, 100});  // like chair1.off's stray vertex 0
    for (std::array<int, 3>& t : m.triangles)
        for (int& x : t) ++x;
    const Skeletonization sk = skeletonize_surface(m);
    EXPECT_EQ(count_degree(sk.skeleton, 1), 2);
    for (const Vec3& p : sk.skeleton.points) EXPECT_LT(norm(p), 2.0);
}

}  // namespace
}  // namespace mesohex
