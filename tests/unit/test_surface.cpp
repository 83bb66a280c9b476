// Surface checks, orientation repair, AABB queries, Hausdorff distance and radius from surface, on cubes.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_check.h"
#include "mesohex/surface/surface_distance.h"
#include "mesohex/surface/surface_query.h"

using namespace mesohex;

namespace {

// Axis-aligned cube [lo, lo + size]^3 as 12 outward triangles (8 vertices).
TriangleMesh make_cube(double size = 1.0, Vec3 lo = {0, 0, 0}) {
    TriangleMesh m;
    for (int c = 0; c < 8; ++c)
        m.points.push_back(lo + size * Vec3{double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)});
    // Faces as outward quads (corner codes x + 2y + 4z), split in two.
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

void flip(TriangleMesh& m) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
}

TriangleMesh append(TriangleMesh a, const TriangleMesh& b) {
    const int off = static_cast<int>(a.points.size());
    a.points.insert(a.points.end(), b.points.begin(), b.points.end());
    for (auto t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
    return a;
}

}  // namespace

TEST(SurfaceCheck, UnitCube) {
    const SurfaceCheck c = check_surface(make_cube());
    EXPECT_EQ(c.vertices, 8);
    EXPECT_EQ(c.edges, 18);
    EXPECT_EQ(c.triangles, 12);
    EXPECT_TRUE(c.is_closed_manifold());
    ASSERT_EQ(c.components.size(), 1u);
    EXPECT_EQ(c.components[0].genus, 0);
    EXPECT_NEAR(c.signed_volume, 1.0, 1e-12);
    EXPECT_NEAR(check_surface(make_cube(2.0, {100, -50, 7})).signed_volume, 8.0, 1e-9);
}

TEST(SurfaceCheck, OpenNonManifoldAndInconsistent) {
    TriangleMesh open = make_cube();
    open.triangles.pop_back();
    const SurfaceCheck c = check_surface(open);
    EXPECT_FALSE(c.closed);
    EXPECT_EQ(c.boundary_edges, 3);
    EXPECT_EQ(c.components[0].genus, -1);

    TriangleMesh bad = make_cube();
    std::swap(bad.triangles[0][1], bad.triangles[0][2]);  // one triangle flipped: its 3 edges are inconsistent
    const SurfaceCheck b = check_surface(bad);
    EXPECT_EQ(b.inconsistent_edges, 3);
    EXPECT_FALSE(b.consistently_oriented);

    TriangleMesh fin = make_cube();
    fin.points.push_back({0.5, 0.5, 2});
    fin.triangles.push_back({4, 5, 8});  // a third triangle on edge 4-5
    const SurfaceCheck f = check_surface(fin);
    EXPECT_EQ(f.non_manifold_edges, 1);
    EXPECT_FALSE(f.edge_manifold);

    // Two cubes sharing one corner: the shared vertex is not manifold.
    TriangleMesh two = make_cube();
    const TriangleMesh other = make_cube(1.0, {1, 1, 1});
    for (const Vec3& p : other.points) two.points.push_back(p);
    for (auto t : other.triangles) {
        std::array<int, 3> u;
        for (int k = 0; k < 3; ++k)
            u[static_cast<std::size_t>(k)] =
                t[static_cast<std::size_t>(k)] == 0 ? 7 : t[static_cast<std::size_t>(k)] + 8;
        two.triangles.push_back(u);
    }
    const SurfaceCheck tw = check_surface(two);
    EXPECT_EQ(tw.non_manifold_vertices, 1);
    EXPECT_EQ(tw.components.size(), 1u);
    EXPECT_EQ(tw.unreferenced_vertices, 1);  // vertex 8 (the other cube's corner 0) is replaced by 7

    TriangleMesh bad_index = make_cube();
    bad_index.triangles[3][1] = 99;
    EXPECT_THROW(check_surface(bad_index), Error);
}

TEST(SurfaceCheck, OrientOutwardFlipsInwardCube) {
    TriangleMesh m = make_cube();
    flip(m);
    EXPECT_LT(check_surface(m).signed_volume, 0);
    const OrientResult r = orient_outward(m);
    EXPECT_EQ(r.flipped_triangles, 12);
    EXPECT_EQ(r.inverted_components, 1);
    EXPECT_EQ(m, make_cube());
    // Already outward: nothing changes.
    const OrientResult again = orient_outward(m);
    EXPECT_EQ(again.flipped_triangles, 0);
}

TEST(SurfaceCheck, OrientOutwardMakesConsistentAndKeepsCavityInward) {
    // Outer cube [0,3]^3 with a cavity cube [1,2]^3: the cavity's normals must point into the cavity (negative volume).
    TriangleMesh outer = make_cube(3.0);
    TriangleMesh cavity = make_cube(1.0, {1, 1, 1});
    TriangleMesh m = append(outer, cavity);           // cavity wrongly outward
    std::swap(m.triangles[2][1], m.triangles[2][2]);  // and one outer triangle inconsistent
    const OrientResult r = orient_outward(m);
    EXPECT_EQ(r.reoriented_components, 1);
    EXPECT_EQ(r.inverted_components, 1);
    const SurfaceCheck c = check_surface(m);
    EXPECT_TRUE(c.is_closed_manifold());
    ASSERT_EQ(c.components.size(), 2u);
    EXPECT_NEAR(c.components[0].signed_volume, 27.0, 1e-9);
    EXPECT_NEAR(c.components[1].signed_volume, -1.0, 1e-9);
    EXPECT_NEAR(c.signed_volume, 26.0, 1e-9);
}

TEST(SurfaceCheck, RemoveUnreferencedVertices) {
    TriangleMesh m = make_cube();
    m.points.insert(m.points.begin(), Vec3{9, 9, 9});
    for (auto& t : m.triangles)
        for (int& v : t) ++v;
    EXPECT_EQ(check_surface(m).unreferenced_vertices, 1);
    const std::vector<int> map = remove_unreferenced_vertices(m);
    ASSERT_EQ(map.size(), 9u);
    EXPECT_EQ(map[0], -1);
    for (int v = 1; v < 9; ++v) EXPECT_EQ(map[static_cast<std::size_t>(v)], v - 1);
    EXPECT_EQ(m, make_cube());
}

TEST(SurfaceQuery, ClosestPointOnUnitCube) {
    const SurfaceQuery q(make_cube());
    const ClosestPoint a = q.closest({2, 0.5, 0.25});
    EXPECT_NEAR(distance(a.point, Vec3{1, 0.5, 0.25}), 0, 1e-12);
    EXPECT_NEAR(a.squared_distance, 1.0, 1e-12);
    // Face x = 1 is quad {1, 3, 7, 5}: triangles 10 and 11.
    EXPECT_TRUE(a.triangle == 10 || a.triangle == 11);
    const ClosestPoint b = q.closest({2, 3, -1});  // nearest: corner (1, 1, 0)
    EXPECT_NEAR(distance(b.point, Vec3{1, 1, 0}), 0, 1e-12);
    EXPECT_NEAR(b.squared_distance, 1 + 4 + 1, 1e-12);
    const ClosestPoint c = q.closest({0.5, 0.5, 0.4});  // inside: nearest face z = 0 at distance 0.4
    EXPECT_NEAR(c.squared_distance, 0.16, 1e-12);
    EXPECT_NEAR(q.squared_distance({0.5, 0.5, 0.4}), 0.16, 1e-12);
    EXPECT_NEAR(q.bbox_diagonal(), std::sqrt(3.0), 1e-12);
    const std::vector<ClosestPoint> batch = q.closest(std::vector<Vec3>{{2, 0.5, 0.25}, {2, 3, -1}});
    ASSERT_EQ(batch.size(), 2u);
    EXPECT_EQ(batch[0].point, a.point);
    EXPECT_EQ(batch[1].point, b.point);
}

// A hint only bounds the search: with any hint (the right triangle, a far one, none, a degenerate one) the closest
// point is the one found without hints; an unaccelerated tree gives it too.
TEST(SurfaceQuery, HintsDoNotChangeTheClosestPoint) {
    TriangleMesh cube = make_cube();
    cube.triangles.push_back({0, 0, 1});  // degenerate (index 12): not in the tree
    const SurfaceQuery q(cube);
    const SurfaceQuery plain(cube, /*accelerate=*/false);
    std::vector<Vec3> points;
    for (int i = 0; i < 200; ++i)  // a deterministic cloud around the cube, inside and outside
        points.push_back({-0.7 + 2.4 * std::fmod(0.618034 * i, 1.0), -0.7 + 2.4 * std::fmod(0.414214 * i + 0.1, 1.0),
                          -0.7 + 2.4 * std::fmod(0.732051 * i + 0.3, 1.0)});
    const std::vector<ClosestPoint> expected = q.closest(points);
    std::vector<std::vector<int>> hint_sets(4, std::vector<int>(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i) {
        hint_sets[0][i] = expected[i].triangle;      // last answer
        hint_sets[1][i] = static_cast<int>(i % 12);  // any triangle
        hint_sets[2][i] = -1;                        // none
        hint_sets[3][i] = i % 2 == 0 ? 12 : 99;      // degenerate, out of range: ignored
    }
    for (const std::vector<int>& hints : hint_sets)
        for (const SurfaceQuery* query : {&q, &plain}) {
            const std::vector<ClosestPoint> got = query->closest(points, hints);
            ASSERT_EQ(got.size(), points.size());
            for (std::size_t i = 0; i < points.size(); ++i) {
                EXPECT_NEAR(distance(got[i].point, expected[i].point), 0, 1e-12) << i;
                EXPECT_NEAR(got[i].squared_distance, expected[i].squared_distance, 1e-12) << i;
            }
        }
    EXPECT_THROW(q.closest(points, std::vector<int>(3, 0)), Error);
}

TEST(SurfaceQuery, InsideOutside) {
    TriangleMesh cube = make_cube();
    const SurfaceQuery q(cube);
    EXPECT_TRUE(q.inside({0.5, 0.5, 0.5}));
    EXPECT_TRUE(q.inside({0.01, 0.99, 0.5}));
    EXPECT_FALSE(q.inside({1.5, 0.5, 0.5}));
    EXPECT_FALSE(q.inside({-0.01, 0.5, 0.5}));
    EXPECT_FALSE(q.inside({0.5, 0.5, 7}));
    EXPECT_TRUE(q.inside({1.0, 0.5, 0.5}));  // on the surface counts as inside
    // Orientation does not matter.
    flip(cube);
    const SurfaceQuery f(cube);
    EXPECT_TRUE(f.inside({0.5, 0.5, 0.5}));
    EXPECT_FALSE(f.inside({2, 2, 2}));
    // Batch on a grid of points: inside iff strictly within the cube (no grid point on the surface).
    std::vector<Vec3> pts;
    for (int i = -2; i <= 6; ++i)
        for (int j = -2; j <= 6; ++j)
            for (int k = -2; k <= 6; ++k) pts.push_back({0.2 * i + 0.1, 0.2 * j + 0.1, 0.2 * k + 0.1});
    const std::vector<char> in = q.inside(pts);
    int count = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const Vec3& p = pts[i];
        const bool expected = p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1 && p.z > 0 && p.z < 1;
        EXPECT_EQ(in[i] != 0, expected) << p.x << " " << p.y << " " << p.z;
        count += in[i];
    }
    EXPECT_EQ(count, 125);
}

TEST(SurfaceQuery, FirstRayHit) {
    const SurfaceQuery q(make_cube());
    const std::optional<RayHit> h = q.first_hit({0.5, 0.5, 0.5}, {3, 0, 0});
    ASSERT_TRUE(h.has_value());
    EXPECT_NEAR(h->distance, 0.5, 1e-12);
    EXPECT_NEAR(distance(h->point, Vec3{1, 0.5, 0.5}), 0, 1e-12);
    const std::optional<RayHit> outside = q.first_hit({-1, 0.3, 0.6}, {1, 0, 0});
    ASSERT_TRUE(outside.has_value());
    EXPECT_NEAR(outside->distance, 1.0, 1e-12);
    // Starting on the surface, skip it with min_distance.
    const std::optional<RayHit> through = q.first_hit({0, 0.3, 0.6}, {1, 0, 0}, 1e-9);
    ASSERT_TRUE(through.has_value());
    EXPECT_NEAR(through->distance, 1.0, 1e-12);
    EXPECT_FALSE(q.first_hit({2, 0.5, 0.5}, {1, 0, 0}).has_value());
    EXPECT_FALSE(q.first_hit({0.5, 0.5, 0.5}, {0, 0, 0}).has_value());
}

TEST(SurfaceDistance, CubeAgainstScaledCube) {
    // Cube [0,1]^3 against the cube of side 1.1 with the same centre: the faces are 0.05 apart, and the big cube's
    // corners are 0.05 sqrt(3) from the small cube's corners: two-sided Hausdorff distance = 0.05 sqrt(3).
    const SurfaceQuery domain(make_cube());
    const TriangleMesh big = make_cube(1.1, {-0.05, -0.05, -0.05});
    const SurfaceDistance d = surface_distance(big, domain);
    EXPECT_NEAR(d.mesh_to_surface_max, 0.05 * std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(d.surface_to_mesh_max, 0.05, 1e-12);
    EXPECT_NEAR(d.max, 0.05 * std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(d.relative_max, 0.05, 1e-12);          // diagonal of the unit cube is sqrt(3)
    EXPECT_NEAR(d.surface_to_mesh_mean, 0.05, 1e-12);  // every point of the small cube is 0.05 from a big face
    EXPECT_NEAR(d.mesh_to_surface_mean, 0.05 * std::sqrt(3.0), 1e-12);  // the mean is over vertices: all corners
    // Same surface given as quads: the small cube against itself is at distance 0.
    QuadMesh quads;
    quads.points = make_cube().points;
    quads.quads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const SurfaceDistance z = surface_distance(quads, domain);
    EXPECT_NEAR(z.max, 0.0, 1e-12);
    EXPECT_GT(z.mesh_samples, 8);
}

// Where the maxima are: the unit cube with corner 7 pulled out to (1.2, 1.2, 1.2), against the unit cube. The mesh
// sample farthest from the surface is that corner (0.2 sqrt(3) away); the surface sample farthest from the mesh lies on
// the cube and is surface_to_mesh_max from the mesh.
TEST(SurfaceDistance, ReportsWhereTheMaximaAre) {
    const SurfaceQuery domain(make_cube());
    TriangleMesh pulled = make_cube();
    pulled.points[7] = {1.2, 1.2, 1.2};
    const SurfaceDistance d = surface_distance(pulled, domain);
    EXPECT_NEAR(d.mesh_to_surface_max, 0.2 * std::sqrt(3.0), 1e-12);
    EXPECT_EQ(d.mesh_to_surface_at, (Vec3{1.2, 1.2, 1.2}));
    EXPECT_NEAR(domain.closest(d.surface_to_mesh_at).squared_distance, 0.0, 1e-20);
    EXPECT_NEAR(std::sqrt(SurfaceQuery(pulled).closest(d.surface_to_mesh_at).squared_distance), d.surface_to_mesh_max,
                1e-12);
    EXPECT_GT(d.surface_to_mesh_max, 0.0);
}

// The maxima skip samples the vertex distances rule out (1-Lipschitz bound): they must equal the maxima over every
// sample (vertices and the barycentric grid of step 1/3 on every triangle), computed here query by query.
TEST(SurfaceDistance, PrunedMaximaEqualEverySample) {
    auto brute = [](const TriangleMesh& from, const SurfaceQuery& to) {
        double mx = 0;
        for (const Vec3& p : from.points) mx = std::max(mx, std::sqrt(to.closest(p).squared_distance));
        for (const std::array<int, 3>& t : from.triangles)
            for (int i = 0; i <= 3; ++i)
                for (int j = 0; i + j <= 3; ++j) {
                    const Vec3 s = (static_cast<double>(i) * from.points[static_cast<std::size_t>(t[0])] +
                                    static_cast<double>(j) * from.points[static_cast<std::size_t>(t[1])] +
                                    static_cast<double>(3 - i - j) * from.points[static_cast<std::size_t>(t[2])]) /
                                   3.0;
                    mx = std::max(mx, std::sqrt(to.closest(s).squared_distance));
                }
        return mx;
    };
    const TriangleMesh cube = make_cube();
    TriangleMesh bent = make_cube(1.1, {-0.05, -0.05, -0.05});
    bent.points[7] = {1.3, 1.2, 1.25};
    bent.points[0] = {0.1, 0.05, -0.2};
    const SurfaceQuery domain(cube), mesh(bent);
    const SurfaceDistance d = surface_distance(bent, domain);
    // Equal up to the rounding of closest points found from different triangles (a pruning error would be ~0.01).
    EXPECT_NEAR(d.mesh_to_surface_max, brute(bent, domain), 1e-14);
    EXPECT_NEAR(d.surface_to_mesh_max, brute(cube, mesh), 1e-14);
    EXPECT_EQ(d.mesh_samples, 8 + 12 * 7);  // vertices + 7 grid points per triangle (10 minus its corners)
}

TEST(RadiusFromSurface, HalfTheDistanceAndOutsideCheck) {
    const SurfaceQuery q(make_cube(2.0));
    Skeleton s;
    s.points = {{1, 1, 1}, {1, 1, 0.5}, {3, 1, 1}};
    const RadiusFromSurface r = radius_from_surface(s, q);
    ASSERT_EQ(r.radii.size(), 3u);
    EXPECT_NEAR(r.radii[0], 0.5, 1e-12);
    EXPECT_NEAR(r.radii[1], 0.25, 1e-12);
    EXPECT_NEAR(r.distance[2], 1.0, 1e-12);
    EXPECT_EQ(r.outside_vertices, std::vector<int>{2});
    RadiusFromSurfaceOptions o;
    o.factor = 1.0;
    EXPECT_NEAR(radius_from_surface(s, q, o).radii[0], 1.0, 1e-12);
    o.factor = 0;
    EXPECT_THROW(radius_from_surface(s, q, o), Error);
}
