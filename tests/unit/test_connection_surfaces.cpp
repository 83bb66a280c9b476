// Connection surfaces (paper step 3): counts, registration and orientation on tiny skeletons.
#include <gtest/gtest.h>

#include "skeleton_fixtures.h"

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "mesohex/core/error.h"
#include "mesohex/stages/connection_surfaces.h"

using namespace mesohex;

namespace {

Skeleton star(const std::vector<Vec3>& dirs) {
    Skeleton s;
    s.points.push_back({0, 0, 0});
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        s.points.push_back(dirs[i]);
        s.edges.push_back({0, static_cast<int>(i) + 1});
    }
    return s;
}

// Checks the closed-surface invariants of vertex v's surface: every edge in two quads with opposite orientation,
// V - E + F == 2, quad_edges consistent with edges.
void expect_closed_surface(const ConnectionSurfaces& cs, int v) {
    std::map<std::pair<int, int>, int> directed;
    for (int q = cs.quad_begin[v]; q < cs.quad_begin[v + 1]; ++q)
        for (int k = 0; k < 4; ++k) {
            const int a = cs.quads[q][k], b = cs.quads[q][(k + 1) % 4];
            ++directed[{a, b}];
            const std::array<int, 2>& ed = cs.edges[cs.edge_begin[v] + cs.quad_edges[q][k]];
            EXPECT_TRUE((ed[0] == a && ed[1] == b) || (ed[0] == b && ed[1] == a));
        }
    for (const auto& [key, count] : directed) {
        EXPECT_EQ(count, 1);
        EXPECT_EQ(directed.count({key.second, key.first}), 1u) << "edge without an opposite half-edge";
    }
    const int np = cs.point_begin[v + 1] - cs.point_begin[v];
    const int nq = cs.quad_begin[v + 1] - cs.quad_begin[v];
    const int ne = cs.edge_begin[v + 1] - cs.edge_begin[v];
    EXPECT_EQ(np - ne + nq, 2);
}

// Directions at least 0.35 rad (about 20 degrees) apart.
std::vector<Vec3> random_directions(int n, unsigned seed) { return mesohex::test::random_directions(n, seed, 0.35); }
}  // namespace

TEST(ConnectionSurfaces, OneEdgeHasTwoExtremityQuads) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}};
    s.edges = {{0, 1}};
    const ConnectionSurfaces cs = build_connection_surfaces(s, analyze_skeleton(s));
    for (int v = 0; v < 2; ++v) {
        EXPECT_EQ(cs.point_begin[v + 1] - cs.point_begin[v], 4);
        EXPECT_EQ(cs.quad_begin[v + 1] - cs.quad_begin[v], 1);
        EXPECT_EQ(cs.edge_begin[v + 1] - cs.edge_begin[v], 4);
    }
    EXPECT_EQ(cs.edge_quad[0][0], 0);
    EXPECT_EQ(cs.edge_quad[0][1], 1);
}

TEST(ConnectionSurfaces, JointIsAPillowOfTwoQuads) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    s.edges = {{0, 1}, {1, 2}};
    const ConnectionSurfaces cs = build_connection_surfaces(s, analyze_skeleton(s));
    EXPECT_EQ(cs.quad_begin[2] - cs.quad_begin[1], 2);
    expect_closed_surface(cs, 1);
    for (int x = cs.point_begin[1]; x < cs.point_begin[2]; ++x) EXPECT_EQ(cs.point_valence[x], 2);
    // Quad A on the first incident edge (edge 0, side 1), quad B on edge 1 (side 0).
    EXPECT_EQ(cs.edge_quad[0][1], cs.quad_begin[1]);
    EXPECT_EQ(cs.edge_quad[1][0], cs.quad_begin[1] + 1);
}

TEST(ConnectionSurfaces, BranchingPointsOfDegree3To12) {
    for (int n = 3; n <= 12; ++n) {
        for (unsigned seed = 1; seed <= 3; ++seed) {
            const std::vector<Vec3> dirs = random_directions(n, seed * 100 + n);
            const Skeleton s = star(dirs);
            const ConnectionSurfaces cs = build_connection_surfaces(s, analyze_skeleton(s));
            SCOPED_TRACE("degree " + std::to_string(n) + " seed " + std::to_string(seed));
            EXPECT_EQ(cs.point_begin[1] - cs.point_begin[0], n + 2);
            EXPECT_EQ(cs.quad_begin[1] - cs.quad_begin[0], n);
            EXPECT_EQ(cs.edge_begin[1] - cs.edge_begin[0], 2 * n);
            expect_closed_surface(cs, 0);
            int valence_sum = 0;
            for (int x = cs.point_begin[0]; x < cs.point_begin[1]; ++x) valence_sum += cs.point_valence[x];
            EXPECT_EQ(valence_sum, 4 * n);
            for (int i = 0; i < n; ++i) {
                // Quad registered on edge i at the centre contains direction i: left of every side seen from outside.
                const int q = cs.edge_quad[i][0];
                ASSERT_GE(q, 0);
                for (int k = 0; k < 4; ++k) {
                    const Vec3& a = cs.directions[cs.quads[q][k]];
                    const Vec3& b = cs.directions[cs.quads[q][(k + 1) % 4]];
                    EXPECT_GT(dot(cross(a, b), dirs[i]), 0.0);
                }
            }
        }
    }
}

TEST(ConnectionSurfaces, LeafletVerticesAndBLJoints) {
    Skeleton s;
    s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.faces = {{0, 1, 2, 3}};
    add_face_edges(s);
    const ConnectionSurfaces cs = build_connection_surfaces(s, analyze_skeleton(s));
    EXPECT_EQ(cs.point_begin.back(), 0);
    EXPECT_TRUE(cs.quads.empty());
    s.points.push_back({-1, -1, 0});
    s.edges.push_back({0, 4});  // BL-joint: a pillow, quad A on the branch edge, directions from the leaflet frame
    const ConnectionSurfaces bl = build_connection_surfaces(s, analyze_skeleton(s));
    EXPECT_EQ(bl.quad_begin[1] - bl.quad_begin[0], 2);
    EXPECT_EQ(bl.edge_quad[4][0], bl.quad_begin[0]);
    // quad B = (2, 1, 0, 3): its q1 (point 1) is the leaflet normal +z ("up").
    EXPECT_NEAR(bl.directions[bl.point_begin[0] + 1].z, 1.0, 1e-12);
    s.points.push_back({1, -1, 0});
    s.edges.push_back({0, 5});  // now a branching point with two branches and a leaflet (a virtual third branch)
    const ConnectionSurfaces bp = build_connection_surfaces(s, analyze_skeleton(s));
    EXPECT_EQ(bp.quad_begin[1] - bp.quad_begin[0], 3);
    EXPECT_EQ(bp.point_begin[1] - bp.point_begin[0], 5);
    EXPECT_EQ(bp.edge_quad[4][0], bp.quad_begin[0]);
    EXPECT_EQ(bp.edge_quad[5][0], bp.quad_begin[0] + 1);
    EXPECT_EQ(bp.face_corner_quad[0][0], 2);  // the leaflet quad comes after the two branch quads
    const int r = bp.quad_rotation[bp.quad_begin[0] + 2];
    ASSERT_GE(r, 0);
    // its up vertex q_{r+1} is the quad vertex nearest to the leaflet normal +z (an in-plane configuration:
    // the up vertex lies in the upper hemisphere)
    EXPECT_GT(bp.directions[bp.point_begin[0] + bp.quads[bp.quad_begin[0] + 2][(r + 1) & 3]].z, 0.5);
}

TEST(ConnectionSurfaces, NonOrientableLeafletIsRejected) {
    Skeleton s;
    s.points = {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}, {0, 0, 0}, {1, 0, 0}, {2, 0.5, 0}};
    s.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}, {2, 3, 0, 5}};
    add_face_edges(s);
    try {
        build_connection_surfaces(s, analyze_skeleton(s));
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::UnsupportedConfiguration);
        EXPECT_EQ(e.where().kind, ElementRef::Kind::SkeletonFace);
    }
}

// The relaxation's asin-skipping margin (quad_margin_above) against the plain one (quad_margin_to_floor), on random
// convex spherical quads (4 points around a random centre, 20-60 degrees out) and directions near them, with floors at
// the exact margin m times (1 +- 10^-k), k = 1..15, and at m: both give the exact margin (the same bits) when it is
// above the floor, both give a value <= floor otherwise.
TEST(ConnectionSurfaces, RelaxationMarginSkipsAsinOnlyWhereItCannotMatter) {
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const auto unit = [](const mesohex::Vec3& v) { return v / mesohex::norm(v); };
    long above = 0, below = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const mesohex::Vec3 c = unit({u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5});
        const mesohex::Vec3 t1 =
            unit(mesohex::cross(c, std::abs(c[0]) < 0.9 ? mesohex::Vec3{1, 0, 0} : mesohex::Vec3{0, 1, 0}));
        const mesohex::Vec3 t2 = mesohex::cross(c, t1);
        std::array<mesohex::Vec3, 4> q;
        for (int k = 0; k < 4; ++k) {
            const double a = (k + 0.3 * (u01(rng) - 0.5)) * 1.5707963267948966;
            const double r = std::tan((20 + 40 * u01(rng)) * 0.017453292519943295);
            q[static_cast<std::size_t>(k)] = unit(c + r * (std::cos(a) * t1 + std::sin(a) * t2));
        }
        const mesohex::Vec3 d = unit(c + 0.3 * (u01(rng) - 0.5) * t1 + 0.3 * (u01(rng) - 0.5) * t2);
        const double m = mesohex::detail::quad_margin_to_floor(q, d, -1.0);
        if (!(m > -1 && std::abs(m) > 1e-6)) continue;
        std::vector<double> floors{m};
        for (int k = 1; k <= 15; ++k) {
            floors.push_back(m * (1 + std::pow(10.0, -k)));
            floors.push_back(m * (1 - std::pow(10.0, -k)));
        }
        for (double f : floors) {
            const double plain = mesohex::detail::quad_margin_to_floor(q, d, f);
            const double fast = mesohex::detail::quad_margin_above(q, d, f);
            if (plain > f) {
                ASSERT_EQ(fast, plain) << "trial " << trial << " floor " << f;
                ++above;
            } else {
                ASSERT_LE(fast, f) << "trial " << trial << " floor " << f;
                ++below;
            }
        }
    }
    EXPECT_GT(above, 10000);
    EXPECT_GT(below, 10000);
}
