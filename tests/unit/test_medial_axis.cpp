// compute_medial_axis on closed surfaces whose medial axis is known, generated here (coarse samplings, fast):
// a thick square plate (one sheet), a cylinder (one curve), an L-bracket (two plates meeting along a seam), a torus
// (a closed curve), a disk with a hub (sheet + curve).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/mesh.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/surface/medial_axis.h"
#include "mesohex/surface/surface_check.h"
#include "mesohex_io/medial_io.h"
#include "surface_fixtures.h"

namespace mesohex {
namespace {

constexpr double kPi = std::numbers::pi;

TriangleMesh extrude(const std::vector<std::array<double, 2>>& poly, double z0, double z1) {
    return test::prism_surface(poly, z0, z1);
}

// Surface of revolution about z of a profile (rho, z) that starts and ends on the axis (rho = 0), n segments.
TriangleMesh revolve(const std::vector<std::array<double, 2>>& profile, int n) {
    TriangleMesh m;
    const int k = static_cast<int>(profile.size());
    m.points.push_back({0, 0, profile.front()[1]});
    for (int i = 1; i + 1 < k; ++i)
        for (int s = 0; s < n; ++s) {
            const double a = 2 * kPi * s / n;
            m.points.push_back({profile[static_cast<size_t>(i)][0] * std::cos(a),
                                profile[static_cast<size_t>(i)][0] * std::sin(a), profile[static_cast<size_t>(i)][1]});
        }
    m.points.push_back({0, 0, profile.back()[1]});
    const int last = static_cast<int>(m.points.size()) - 1;
    auto ring = [n](int i, int s) { return 1 + (i - 1) * n + (s % n); };
    for (int s = 0; s < n; ++s) {
        m.triangles.push_back({0, ring(1, s + 1), ring(1, s)});
        for (int i = 1; i + 2 < k; ++i) {
            m.triangles.push_back({ring(i, s), ring(i, s + 1), ring(i + 1, s + 1)});
            m.triangles.push_back({ring(i, s), ring(i + 1, s + 1), ring(i + 1, s)});
        }
        m.triangles.push_back({last, ring(k - 2, s), ring(k - 2, s + 1)});
    }
    return m;
}

TriangleMesh torus(double R, double r, int nu, int nv) { return test::torus_surface(R, r, nu, nv); }

void expect_closed(const TriangleMesh& m) {
    const SurfaceCheck c = check_surface(m);
    ASSERT_TRUE(c.is_closed_manifold());
    ASSERT_EQ(c.components.size(), 1u);
}

// The default options (1.5 % sample spacing: 0.2 to 1.5 s per shape here).
MedialAxisOptions coarse() { return {}; }

// import_medial_mesh + mesh_skeleton (raw mesh, in the surface for the radii check): a valid hex mesh.
QualityReport raw_mesh_of(const MedialAxis& m, const TriangleMesh& surface) {
    const MedialImport imported = import_medial_mesh(m.medial);
    MeshOptions o;
    o.finish = false;
    return mesh_skeleton(imported.skeleton, &surface, o).raw_quality;
}

// Every medial radius is positive and every medial centre lies inside the surface's bounding box.
void expect_sane(const MedialAxis& m, const TriangleMesh& s) {
    ASSERT_EQ(m.medial.radii.size(), m.medial.points.size());
    Vec3 lo = s.points[0], hi = s.points[0];
    for (const Vec3& p : s.points)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], p[k]);
            hi[k] = std::max(hi[k], p[k]);
        }
    for (size_t v = 0; v < m.medial.points.size(); ++v) {
        EXPECT_GT(m.medial.radii[v], 0);
        for (int k = 0; k < 3; ++k) {
            EXPECT_GE(m.medial.points[v][k], lo[k] - 1e-9);
            EXPECT_LE(m.medial.points[v][k], hi[k] + 1e-9);
        }
    }
}

TEST(MedialAxis, ThickSquarePlateIsOneSheet) {
    const TriangleMesh s = extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3);
    expect_closed(s);
    const MedialAxis m = compute_medial_axis(s, coarse());
    expect_sane(m, s);
    EXPECT_EQ(m.sheets, 1);
    EXPECT_EQ(m.curves, 0);
    EXPECT_EQ(m.euler, 1);  // a disk
    // The sheet is the mid-plane z = 0 (radius 0.3 = half the thickness) within the square shrunk by about the
    // half-thickness (trimmed: the wedges going to the 90-degree edges are filtered out).
    for (size_t v = 0; v < m.medial.points.size(); ++v) {
        EXPECT_NEAR(m.medial.points[v].z, 0, 0.05);
        EXPECT_NEAR(m.medial.radii[v], 0.3, 0.06);  // poles of samples 0.085 apart overestimate by up to 20 %
        EXPECT_LE(std::abs(m.medial.points[v].x), 1.8);
        EXPECT_LE(std::abs(m.medial.points[v].y), 1.8);
    }
    EXPECT_GT(m.sheet_fraction, 0.9);
    const QualityReport q = raw_mesh_of(m, s);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.inverted, 0);
    EXPECT_EQ(q.euler_characteristic, 1);
}

TEST(MedialAxis, CylinderIsOneCurve) {
    const TriangleMesh s = revolve({{0, -2}, {0.5, -2}, {0.5, 2}, {0, 2}}, 32);
    expect_closed(s);
    const MedialAxis m = compute_medial_axis(s, coarse());
    expect_sane(m, s);
    EXPECT_EQ(m.sheets, 0);
    EXPECT_EQ(m.curves, 1);
    EXPECT_EQ(m.euler, 1);
    // On the axis, between the cones going to the rims (z in [-1.5, 1.5]), radius 0.5.
    for (size_t v = 0; v < m.medial.points.size(); ++v) {
        EXPECT_LT(std::hypot(m.medial.points[v].x, m.medial.points[v].y), 0.05);
        EXPECT_LE(std::abs(m.medial.points[v].z), 1.55);
        EXPECT_NEAR(m.medial.radii[v], 0.5, 0.05);
    }
    EXPECT_LT(m.sheet_fraction, 0.05);
    EXPECT_TRUE(raw_mesh_of(m, s).validation.valid());
}

// Every medial edge (sheet sides and curve edges) no longer than factor x the smaller radius of its two ends.
void expect_edges_within(const MedialAxis& m, double factor) {
    for (const std::array<int, 2>& e : m.medial.edges) {
        const size_t a = static_cast<size_t>(e[0]), b = static_cast<size_t>(e[1]);
        EXPECT_LE(distance(m.medial.points[a], m.medial.points[b]),
                  factor * std::min(m.medial.radii[a], m.medial.radii[b]) + 1e-9)
            << e[0] << "-" << e[1];
    }
}

// The simplification stopped by resolution (max_edge_radius) instead of a count: the plate's mid-sheet stays one
// sheet (a disk) with every edge at most 2 radii, and a plate twice as wide (four times the sheet area at the same
// radius) keeps more than twice as many spheres (a fixed count keeps 60 on both).
TEST(MedialAxis, ResolutionStopScalesTheSheetWithItsSize) {
    MedialAxisOptions o = coarse();
    o.max_edge_radius = 2;
    const TriangleMesh small = extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3);
    const TriangleMesh large = extrude({{-4, -4}, {4, -4}, {4, 4}, {-4, 4}}, -0.3, 0.3);
    const MedialAxis a = compute_medial_axis(small, o);
    const MedialAxis b = compute_medial_axis(large, o);
    for (const MedialAxis* m : {&a, &b}) {
        EXPECT_EQ(m->sheets, 1);
        EXPECT_EQ(m->curves, 0);
        EXPECT_EQ(m->euler, 1);
        expect_edges_within(*m, 2);
    }
    EXPECT_GT(b.medial.points.size(), 2 * a.medial.points.size());
    const QualityReport q = raw_mesh_of(a, small);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.inverted, 0);
}

// The same stop on the cylinder (radius 0.5, axis from z -1.5 to 1.5 after the trim at the rims): one curve whose
// edges are at most 2 radii (at least 3 of them) and, as every collapse left would make an edge longer, at least one
// radius on average (at most 7: with consecutive edges of length l1 + l2 <= 2 r a collapse would still be allowed).
TEST(MedialAxis, ResolutionStopSamplesTheCylindersAxisByItsRadius) {
    MedialAxisOptions o = coarse();
    o.max_edge_radius = 2;
    const TriangleMesh s = revolve({{0, -2}, {0.5, -2}, {0.5, 2}, {0, 2}}, 32);
    const MedialAxis m = compute_medial_axis(s, o);
    EXPECT_EQ(m.sheets, 0);
    EXPECT_EQ(m.curves, 1);
    EXPECT_EQ(m.euler, 1);
    expect_edges_within(m, 2);
    EXPECT_GE(m.medial.edges.size(), 3u);
    EXPECT_LE(m.medial.edges.size(), 7u) << m.medial.points.size() << " " << m.collapses << " " << m.initial_vertices;
}

// Every medial edge at least factor x the smaller radius of its two ends.
void expect_edges_at_least(const MedialAxis& m, double factor) {
    for (const std::array<int, 2>& e : m.medial.edges) {
        const size_t a = static_cast<size_t>(e[0]), b = static_cast<size_t>(e[1]);
        EXPECT_GE(distance(m.medial.points[a], m.medial.points[b]),
                  factor * std::min(m.medial.radii[a], m.medial.radii[b]) - 1e-9)
            << e[0] << "-" << e[1];
    }
}

// The second stop (min_edge_radius): on the flat plate (mid-sheet 3.4 wide, radius 0.3) the count stop's 60 spheres
// leave sides of about 0.4 to 0.6 = 1.3 to 2 radii; with the bound 2 the collapses go on until no side is shorter than
// 2 radii (a flat sheet neither folds nor thins, so none is refused), the sheet stays one disk with fewer spheres and
// its raw mesh has no inverted hex. On the cylinder (radius 0.5, axis 3 long) the curve's edges become at least 2
// radii = 1.0 long: at most 3 of them.
TEST(MedialAxis, MinEdgeRadiusLeavesNoEdgeShortAgainstItsSpheres) {
    MedialAxisOptions o = coarse();
    o.min_edge_radius = 2;
    const TriangleMesh plate = extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3);
    const MedialAxis m = compute_medial_axis(plate, o);
    EXPECT_EQ(m.sheets, 1);
    EXPECT_EQ(m.curves, 0);
    EXPECT_EQ(m.euler, 1);
    expect_edges_at_least(m, 2);
    EXPECT_LT(m.medial.points.size(), compute_medial_axis(plate, coarse()).medial.points.size());
    const QualityReport q = raw_mesh_of(m, plate);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.inverted, 0);
    const TriangleMesh cylinder = revolve({{0, -2}, {0.5, -2}, {0.5, 2}, {0, 2}}, 32);
    const MedialAxis c = compute_medial_axis(cylinder, o);
    EXPECT_EQ(c.sheets, 0);
    EXPECT_EQ(c.curves, 1);
    EXPECT_EQ(c.euler, 1);
    expect_edges_at_least(c, 2);
    EXPECT_LE(c.medial.edges.size(), 3u);
}

TEST(MedialAxis, TorusIsOneClosedCurve) {
    const TriangleMesh s = torus(2, 0.5, 48, 16);
    expect_closed(s);
    const MedialAxis m = compute_medial_axis(s, coarse());
    expect_sane(m, s);
    EXPECT_EQ(m.sheets, 0);
    EXPECT_EQ(m.curves, 1);
    EXPECT_EQ(m.euler, 0);  // a circle
    for (size_t v = 0; v < m.medial.points.size(); ++v) {
        EXPECT_NEAR(std::hypot(m.medial.points[v].x, m.medial.points[v].y), 2, 0.1);  // core circle R = 2, within 5 %
        EXPECT_NEAR(m.medial.radii[v], 0.5, 0.05);
    }
    const QualityReport q = raw_mesh_of(m, s);
    EXPECT_TRUE(q.validation.valid());
    EXPECT_EQ(q.inverted, 0);
    EXPECT_EQ(q.euler_characteristic, 0);
}

// The disk (0.2 thick) is barely thicker than the base sample spacing (0.088): without the thin-part samples
// (thickness_samples 0) many Voronoi faces between its two sides see them under less than min_angle_deg and are
// dropped, the mid-sheet is punched full of holes (Euler characteristic -181 before simplification; with the erosion
// -4, holes of the sparse inner Voronoi complex itself). With them (local spacing thickness / 4 where the solid is
// thinner than 4 x the spacing) the sheet is whole, and the thin-part criterion (faces whose samples are at least
// 0.85 x the local thickness apart) keeps the ligature inside the hub between the disk's sheet and the hub's axis,
// which the angle filter alone cuts (an annulus: KeepTopologyKeepsTheSolidsEulerCharacteristic).
// Expected: 1 sheet (a disk), 2 curves (the hub's axis above and below), Euler characteristic 1.
TEST(MedialAxis, DiskWithHubIsSheetAndCurves) {
    const TriangleMesh s =
        revolve({{0, -0.8}, {0.3, -0.8}, {0.3, -0.1}, {2, -0.1}, {2, 0.1}, {0.3, 0.1}, {0.3, 0.8}, {0, 0.8}}, 32);
    expect_closed(s);
    const MedialAxis m = compute_medial_axis(s, coarse());
    expect_sane(m, s);
    EXPECT_GT(m.refinement_samples, 0);
    EXPECT_GT(m.thin_faces, 0);
    EXPECT_EQ(m.initial_euler, 1);
    EXPECT_EQ(m.sheets, 1);
    EXPECT_EQ(m.curves, 2);
    EXPECT_EQ(m.euler, 1);
    EXPECT_TRUE(raw_mesh_of(m, s).validation.valid());
    // The same with the erosion (keep_topology).
    MedialAxisOptions o = coarse();
    o.keep_topology = true;
    const MedialAxis k = compute_medial_axis(s, o);
    EXPECT_EQ(k.initial_euler, 1);
    EXPECT_EQ(k.sheets, 1);
    EXPECT_EQ(k.curves, 2);
    EXPECT_EQ(k.euler, 1);
}

// The thin-part samples go only where the solid is thin: the 0.6-thick plate (10 x 0.085 > 4 x the spacing) gets
// none, so its medial mesh is the one without them.
TEST(MedialAxis, ThickPartsGetNoExtraSamples) {
    const TriangleMesh plate = extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3);
    MedialAxisOptions off = coarse();
    off.thickness_samples = 0;
    const MedialAxis a = compute_medial_axis(plate, coarse());
    const MedialAxis b = compute_medial_axis(plate, off);
    EXPECT_EQ(a.refinement_samples, 0);
    EXPECT_EQ(a.samples, b.samples);
    EXPECT_EQ(a.medial, b.medial);
}

// max_samples bounds the samples with the thin-part ones: the spacing grows until both fit.
TEST(MedialAxis, ThinPartSamplesStayWithinMaxSamples) {
    const TriangleMesh s =
        revolve({{0, -0.8}, {0.3, -0.8}, {0.3, -0.1}, {2, -0.1}, {2, 0.1}, {0.3, 0.1}, {0.3, 0.8}, {0, 0.8}}, 32);
    MedialAxisOptions o = coarse();
    o.max_samples = 8000;
    const MedialAxis m = compute_medial_axis(s, o);
    EXPECT_GT(m.refinement_samples, 0);
    EXPECT_LE(m.samples, 8000);
}

TEST(MedialAxis, LBracketIsTwoPlatesMeetingAlongASeam) {
    // Cross-section: an L of two arms 3 long and 1 thick; extruded 3 deep.
    const TriangleMesh s = extrude({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 3);
    expect_closed(s);
    const MedialAxis m = compute_medial_axis(s, coarse());
    expect_sane(m, s);
    EXPECT_EQ(m.curves, 0);
    EXPECT_EQ(m.sheets, 1);  // one component: the two plates' mid-sheets, bent by 90 degrees along the seam
    EXPECT_EQ(m.euler, 1);
    // Both plates are there: triangles whose normal is along y (the arm along x, mid-plane y = 0.5) and along x.
    int along_x_arm = 0, along_y_arm = 0;
    for (const std::vector<int>& f : m.medial.faces) {
        const Vec3& a = m.medial.points[static_cast<size_t>(f[0])];
        const Vec3 n = normalized(
            cross(m.medial.points[static_cast<size_t>(f[1])] - a, m.medial.points[static_cast<size_t>(f[2])] - a));
        if (std::abs(n.y) > 0.95) ++along_x_arm;
        if (std::abs(n.x) > 0.95) ++along_y_arm;
    }
    EXPECT_GT(along_x_arm, 0);
    EXPECT_GT(along_y_arm, 0);
}

// keep_topology: the angle filter erodes the inner Voronoi complex by elementary collapses, so the complex before
// simplification keeps (nearly) the solid's Euler characteristic (a ball: 1; a solid torus: 0), where dropping the
// narrow faces punches holes into thin sheets.
TEST(MedialAxis, KeepTopologyKeepsTheSolidsEulerCharacteristic) {
    MedialAxisOptions o = coarse();
    o.keep_topology = true;
    const TriangleMesh plate = extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3);
    const MedialAxis p = compute_medial_axis(plate, o);
    EXPECT_EQ(p.initial_euler, 1);
    EXPECT_EQ(p.euler, 1);
    const MedialAxis t = compute_medial_axis(torus(2, 0.5, 48, 16), o);
    EXPECT_EQ(t.initial_euler, 0);
    EXPECT_EQ(t.euler, 0);
    // The disk with a hub (a ball: 1), without the thin-part samples (thickness_samples 0): dropping the narrow faces
    // leaves 182 independent cycles (Euler characteristic -181); the erosion keeps all but the few the inner Voronoi
    // complex itself has (measured -4). With the thin-part samples (default) both give the ball's 1.
    const TriangleMesh hub =
        revolve({{0, -0.8}, {0.3, -0.8}, {0.3, -0.1}, {2, -0.1}, {2, 0.1}, {0.3, 0.1}, {0.3, 0.8}, {0, 0.8}}, 32);
    MedialAxisOptions sparse = coarse();
    sparse.thickness_samples = 0;
    EXPECT_LT(compute_medial_axis(hub, sparse).initial_euler, -100);
    sparse.keep_topology = true;
    const MedialAxis d = compute_medial_axis(hub, sparse);
    EXPECT_GE(d.initial_euler, -4);
    EXPECT_LE(d.initial_euler, 1);
    EXPECT_EQ(compute_medial_axis(hub, o).initial_euler, 1);
    // The plain filter with the thin-part samples but without the thin-part criterion (thin_separation 0): no hole in
    // the disk's sheet any more, but the ligature inside the hub (the sheet between the two reflex rims, seen under
    // less than 110 degrees within 0.23 of the axis) is cut: an annulus (0), the hub's axis a separate, smaller part.
    MedialAxisOptions angle_only = coarse();
    angle_only.thin_separation = 0;
    const MedialAxis plain = compute_medial_axis(hub, angle_only);
    EXPECT_GT(plain.refinement_samples, 0);
    EXPECT_EQ(plain.initial_euler, 0);
    EXPECT_EQ(plain.sheets, 1);
    EXPECT_EQ(plain.euler, 0);
}

TEST(MedialAxis, FringeCurvesAlongASheetAreRemoved) {
    // A unit square sheet (0-3, 2 triangles) and a one-triangle sheet (7-9) 0.2 to its right, every radius 0.1 (the
    // limit is 2 x 0.1). Curve chains: 1-4-2 runs along the square's edge x = 1 (4 is 0.112 from it): a fringe; the
    // chord 1-3 lies in the square: a fringe; the handle 0-5-3 rises 1 above it (0.28 from it at a quarter of 0-5):
    // kept; 2-6 ends at a tip: kept; 1-7 is near both sheets all along but is their only link: kept.
    Skeleton m;
    m.points = {{0, 0, 0},      {1, 0, 0},     {1, 1, 0},   {0, 1, 0}, {1.1, 0.5, 0.05},
                {0.5, -0.5, 1}, {1.1, 1.1, 0}, {1.2, 0, 0}, {2, 0, 0}, {1.2, 1, 0}};
    m.radii.assign(m.points.size(), 0.1);
    m.faces = {{0, 1, 2}, {0, 2, 3}, {7, 8, 9}};
    m.edges = {{0, 1}, {1, 2}, {0, 2}, {2, 3}, {0, 3}, {7, 8}, {8, 9}, {7, 9},
               {1, 4}, {4, 2}, {1, 3}, {0, 5}, {5, 3}, {2, 6}, {1, 7}};
    EXPECT_EQ(remove_fringe_curves(m, 2.0), 2);
    ASSERT_EQ(m.points.size(), 9u);  // vertex 4 goes, the others keep their order
    EXPECT_EQ(m.points[4], (Vec3{0.5, -0.5, 1}));
    EXPECT_EQ(m.edges.size(), 12u);
    EXPECT_EQ(m.faces.size(), 3u);
    const auto has = [&](int a, int b) {
        return std::count(m.edges.begin(), m.edges.end(), std::array<int, 2>{a, b}) == 1;
    };
    EXPECT_TRUE(has(0, 4) && has(4, 3) && has(2, 5) && has(1, 6));  // handle, tip, link (ids after vertex 4)
    EXPECT_FALSE(has(1, 3));
    EXPECT_EQ(euler_characteristic(m), 9 - 12 + 3);
    EXPECT_EQ(remove_fringe_curves(m, 2.0), 0);  // nothing left to remove
}

TEST(MedialAxis, FringeChainsEndingAtACurveBranchingPointAreRemovedWithNodeEnds) {
    // A unit square sheet (0-3, 2 triangles), every radius 0.1 (the limit is 3 x 0.1). Node 4 at (1.1, 0.5, 0), 0.1
    // off the square's edge x = 1, branches into 1-4, 2-4 (along that edge) and 4-5 (a limb to the tip 5, 1.4 away).
    // Node 6, 2 above the square's centre, branches into 0-6, 2-6 and 6-7 (a tip). With node ends, 1-4 is a fringe
    // (its samples 0.025 to 0.075 from the sheet; 1 and 4 stay connected through 1-2 and 2-4); 2-4 is then the only
    // link of 4 and stays; 0-6 and 2-6 rise (0.5 above the sheet at a quarter); chains ending at a tip stay.
    Skeleton m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1.1, 0.5, 0}, {2.5, 0.5, 0}, {0.5, 0.5, 2}, {0.5, 0.5, 3}};
    m.radii.assign(m.points.size(), 0.1);
    m.faces = {{0, 1, 2}, {0, 2, 3}};
    m.edges = {{0, 1}, {1, 2}, {0, 2}, {2, 3}, {0, 3}, {1, 4}, {2, 4}, {4, 5}, {0, 6}, {2, 6}, {6, 7}};
    Skeleton without = m;
    EXPECT_EQ(remove_fringe_curves(without, 3.0, false), 0);  // 4 is no sheet vertex: nothing ends on two sheets
    EXPECT_EQ(euler_characteristic(without), 8 - 11 + 2);
    EXPECT_EQ(remove_fringe_curves(m, 3.0, true), 1);
    ASSERT_EQ(m.points.size(), 8u);  // every vertex keeps an edge: none goes
    EXPECT_EQ(m.edges.size(), 10u);
    EXPECT_EQ(std::count(m.edges.begin(), m.edges.end(), std::array<int, 2>{1, 4}), 0);
    for (const std::array<int, 2> e : {std::array<int, 2>{2, 4}, {4, 5}, {0, 6}, {2, 6}, {6, 7}})
        EXPECT_EQ(std::count(m.edges.begin(), m.edges.end(), e), 1) << e[0] << "-" << e[1];
    EXPECT_EQ(euler_characteristic(m), 8 - 10 + 2);    // the cycle 1-2-4 is gone
    EXPECT_EQ(remove_fringe_curves(m, 3.0, true), 0);  // 2-4 is the only link left
}

TEST(MedialAxis, SpursAreTheTerminalBranchesThatBarelyLeaveTheirNodesSphere) {
    // A square sheet of side 2 (0-3, 2 triangles), every radius 0.5 (prune factor 2: length + tip radius < 1).
    // The stub 2-4-5 runs 0.2 + 0.2 = 0.4 out of the sheet's corner 2 through the joint 4 (0.4 + 0.5 < 1: a spur);
    // curve node 6, 3 from corner 0, carries the tip 7, 0.3 away (0.3 + 0.5 < 1: a spur), and the limb 6-8 (3 long).
    // Shortest first: 6-7 goes, then 2-4-5; 0-6-8 is then one branch 6 long and stays. Points 4, 5, 7 go.
    Skeleton m;
    m.points = {{0, 0, 0},   {2, 0, 0},  {2, 2, 0},    {0, 2, 0}, {2.2, 2, 0},
                {2.4, 2, 0}, {-3, 0, 0}, {-3, 0.3, 0}, {-6, 0, 0}};
    m.radii.assign(m.points.size(), 0.5);
    m.faces = {{0, 1, 2}, {0, 2, 3}};
    m.edges = {{0, 1}, {1, 2}, {0, 2}, {2, 3}, {0, 3}, {2, 4}, {4, 5}, {0, 6}, {6, 7}, {6, 8}};
    ASSERT_EQ(euler_characteristic(m), 9 - 10 + 2);
    Skeleton loose = m;
    EXPECT_EQ(prune_spurs(loose, 1.5), 0);  // 0.8 and 0.9 are not below 0.75
    EXPECT_EQ(loose.edges.size(), 10u);
    EXPECT_EQ(prune_spurs(m, 2.0), 2);
    ASSERT_EQ(m.points.size(), 6u);  // 0-3, then 6 -> 4 and 8 -> 5, in their order
    EXPECT_EQ(m.points[4], (Vec3{-3, 0, 0}));
    EXPECT_EQ(m.points[5], (Vec3{-6, 0, 0}));
    EXPECT_EQ(m.edges.size(), 7u);
    EXPECT_EQ(std::count(m.edges.begin(), m.edges.end(), std::array<int, 2>{0, 4}), 1);
    EXPECT_EQ(std::count(m.edges.begin(), m.edges.end(), std::array<int, 2>{4, 5}), 1);
    EXPECT_EQ(m.faces.size(), 2u);
    EXPECT_EQ(euler_characteristic(m), 6 - 7 + 2);  // the same: elementary collapses
    EXPECT_EQ(prune_spurs(m, 2.0), 0);
    Skeleton path;  // a path keeps both its ends
    path.points = {{0, 0, 0}, {0.1, 0, 0}};
    path.radii = {1, 1};
    path.edges = {{0, 1}};
    EXPECT_EQ(prune_spurs(path, 2.0), 0);
}

TEST(MedialAxis, SpursGoShortestFirstAndTheirNodeMayThenBecomeAJoint) {
    // The square sheet of side 2 (0-3, 2 triangles), every radius 0.5 (prune factor 2: length + tip radius < 1), and
    // curve node 4, 3 from corner 0, with two tips: 5 at `up` and 6 at 0.3 below. Both are spurs at first; the shorter
    // goes, node 4 is then a joint and the other tip ends the branch 6-4-0 (3.3 long), which stays. Lengths 0.35 and
    // 0.3: tip 6 goes although tip 5 has the smaller id (shortest first). Equal lengths: tip 5 goes (smaller ids).
    for (const double up : {0.35, 0.3}) {
        SCOPED_TRACE(up);
        Skeleton m;
        m.points = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {-3, 0, 0}, {-3, up, 0}, {-3, -0.3, 0}};
        m.radii.assign(m.points.size(), 0.5);
        m.faces = {{0, 1, 2}, {0, 2, 3}};
        m.edges = {{0, 1}, {1, 2}, {0, 2}, {2, 3}, {0, 3}, {0, 4}, {4, 5}, {4, 6}};
        ASSERT_EQ(euler_characteristic(m), 7 - 8 + 2);
        EXPECT_EQ(prune_spurs(m, 2.0), 1);
        ASSERT_EQ(m.points.size(), 6u);
        EXPECT_EQ(m.points[5], (up == 0.3 ? Vec3{-3, -0.3, 0} : Vec3{-3, up, 0}));  // the tip that stays
        EXPECT_EQ(std::count(m.edges.begin(), m.edges.end(), std::array<int, 2>{4, 5}), 1);
        EXPECT_EQ(euler_characteristic(m), 6 - 7 + 2);
        EXPECT_EQ(prune_spurs(m, 2.0), 0);
    }
    Skeleton alone;  // a lone point (a component of its own) stays when a spur goes
    alone.points = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {2.2, 0, 0}, {9, 9, 9}};
    alone.radii.assign(alone.points.size(), 0.5);
    alone.faces = {{0, 1, 2}};
    alone.edges = {{0, 1}, {1, 2}, {0, 2}, {1, 3}};
    EXPECT_EQ(prune_spurs(alone, 2.0), 1);
    ASSERT_EQ(alone.points.size(), 4u);
    EXPECT_EQ(alone.points[3], (Vec3{9, 9, 9}));
    EXPECT_EQ(euler_characteristic(alone), 4 - 3 + 1);  // 2 components, each contractible
}

// Limbs: a thick disk (radius 2, 1.2 thick) with a rod (radius 0.25) 1.5 long on each face. The angle filter cuts the
// rods' axes off the disk's mid-sheet where they meet (the ligature from the reflex rim is seen under small angles):
// without keep_limbs and cover_fraction only the disk's sheet is left and the rods' ends lie 1.5 from every sphere;
// with keep_limbs both rods come back as one curve each, joined to the sheet (trees: the Euler characteristic stays).
TEST(MedialAxis, RodsTheAngleFilterCutsOffAreKeptAsCurves) {
    const TriangleMesh s =
        revolve({{0, -2.1}, {0.25, -2.1}, {0.25, -0.6}, {2, -0.6}, {2, 0.6}, {0.25, 0.6}, {0.25, 2.1}, {0, 2.1}}, 32);
    expect_closed(s);
    MedialAxisOptions off = coarse();
    off.cover_fraction = 0;  // the limbs alone (the covering parts would keep the rods whole first)
    MedialAxisOptions on = off;
    on.keep_limbs = true;
    const MedialAxis a = compute_medial_axis(s, off);
    const MedialAxis b = compute_medial_axis(s, on);
    auto reach = [](const MedialAxis& m) {  // {lowest, highest} z of a sphere centre
        std::array<double, 2> z = {1e9, -1e9};
        for (const Vec3& p : m.medial.points) z = {std::min(z[0], p.z), std::max(z[1], p.z)};
        return z;
    };
    // Without: the disk's sheet alone, in its mid-plane (the rods' ends lie 1.5 beyond the disk's faces).
    EXPECT_EQ(a.limbs, 0);
    EXPECT_LT(reach(a)[1], 0.05);
    EXPECT_GT(reach(a)[0], -0.05);
    // With: both rods, one path each, as curves reaching beyond 1.2 of the 2.1 (their ends are 0.25 thick).
    EXPECT_EQ(b.limbs, 2);
    EXPECT_EQ(b.limb_branches, 2);
    EXPECT_GT(reach(b)[1], 1.2);
    EXPECT_LT(reach(b)[0], -1.2);
    EXPECT_EQ(b.sheets, a.sheets);
    EXPECT_EQ(b.curves, a.curves + 2);
    EXPECT_EQ(b.initial_euler, a.initial_euler);  // trees joined by one edge each: no cycle added
    EXPECT_EQ(b.euler, a.euler);
    expect_sane(b, s);
}

// keep_limbs with both coverage thresholds 0 (every sample not inside a kept sphere is uncovered, and a sample lies on
// its own sphere only up to rounding): the tree growth ends (each sample picked at most once) and keeps at least the
// two rods of RodsTheAngleFilterCutsOffAreKeptAsCurves.
TEST(MedialAxis, LimbsWithZeroThresholdsEnd) {
    const TriangleMesh s =
        revolve({{0, -2.1}, {0.25, -2.1}, {0.25, -0.6}, {2, -0.6}, {2, 0.6}, {0.25, 0.6}, {0.25, 2.1}, {0, 2.1}}, 32);
    MedialAxisOptions o = coarse();
    o.cover_fraction = 0;
    o.keep_limbs = true;
    o.limb_gap = 0;
    o.limb_radius_factor = 0;
    const MedialAxis m = compute_medial_axis(s, o);
    EXPECT_GE(m.limbs, 2);
    expect_sane(m, s);
}

// Plates have no limbs: the debris the angle filter leaves at their edges and corners is not longer than thick, and
// a 90-degree edge lies within the sheet's radius of it, so keep_limbs changes nothing.
// A 3 x 2 grid of unit squares (12 vertices, 12 triangles; interior vertices 5 = (1, 1) and 6 = (2, 1)), every radius
// 0.1 (limit 2 x 0.1). Two chains run along the sheet: 5-12-6 between the two interior vertices (a handle's two
// roots, 0.1 above the sheet) and 0-13-5 from the border corner 0. Without spare_interior both are fringe; with it the
// chain between interior vertices stays and the one from the border goes.
TEST(MedialAxis, FringeRuleSparesChainsBetweenInteriorSheetVertices) {
    Skeleton m;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) m.points.push_back({static_cast<double>(i), static_cast<double>(j), 0});
    m.points.push_back({1.5, 1, 0.1});     // 12
    m.points.push_back({0.5, 0.45, 0.1});  // 13
    m.radii.assign(m.points.size(), 0.1);
    std::set<std::array<int, 2>> edges;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) {
            const int a = i + 4 * j, b = a + 1, c = a + 5, d = a + 4;
            for (const std::vector<int>& f : {std::vector<int>{a, b, c}, std::vector<int>{a, c, d}}) {
                m.faces.push_back(f);
                for (size_t k = 0; k < 3; ++k)
                    edges.insert({std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])});
            }
        }
    for (const std::array<int, 2>& e : {std::array<int, 2>{5, 12}, {6, 12}, {0, 13}, {5, 13}}) edges.insert(e);
    m.edges.assign(edges.begin(), edges.end());
    Skeleton plain = m;
    EXPECT_EQ(remove_fringe_curves(plain, 2.0, false, false), 2);
    EXPECT_EQ(plain.points.size(), 12u);
    EXPECT_EQ(remove_fringe_curves(m, 2.0, false, true), 1);
    ASSERT_EQ(m.points.size(), 13u);  // 13 goes, 12 stays
    EXPECT_EQ(m.points[12], (Vec3{1.5, 1, 0.1}));
    EXPECT_EQ(m.edges.size(), edges.size() - 2);
    EXPECT_EQ(euler_characteristic(m), 13 - static_cast<long>(edges.size() - 2) + 12);
}

// The disk with two rods (radius 0.25, 1.5 beyond each face): the angle filter cuts the rods off the disk's sheet;
// joined back (join_factor 3) only as substantial parts (extent >= 4 x radius: a rod's axis is 6 radii long), they
// stay, as curves reaching beyond 1.2 of the 2.1. The plates' corner debris is not substantial: nothing joins there.
TEST(MedialAxis, SubstantialPartsTheAngleFilterCutsOffAreJoined) {
    const TriangleMesh s =
        revolve({{0, -2.1}, {0.25, -2.1}, {0.25, -0.6}, {2, -0.6}, {2, 0.6}, {0.25, 0.6}, {0.25, 2.1}, {0, 2.1}}, 32);
    MedialAxisOptions o = coarse();
    o.join_factor = 3;
    o.join_min_extent = 4;
    const MedialAxis m = compute_medial_axis(s, o);
    EXPECT_EQ(m.joined_parts, 2);
    std::array<double, 2> z = {1e9, -1e9};
    for (const Vec3& p : m.medial.points) z = {std::min(z[0], p.z), std::max(z[1], p.z)};
    EXPECT_GT(z[1], 1.2);
    EXPECT_LT(z[0], -1.2);
    EXPECT_EQ(m.sheets, 1);
    expect_sane(m, s);
    for (const TriangleMesh& p : {extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3),
                                  extrude({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 3)}) {
        const MedialAxis q = compute_medial_axis(p, o);
        EXPECT_EQ(q.joined_parts, 0);
        EXPECT_EQ(q.medial, compute_medial_axis(p, coarse()).medial);
    }
}

// Covering parts: the disk with two rods (radius 0.25, 1.5 beyond each face). The angle filter cuts the rods' axes off
// the disk's sheet; the largest part alone leaves the rods' ends 1.5 from every sphere. Each rod's part touches the
// samples of its rod (its side 2 pi 0.25 x 1.5 and its end: about 5 % of the surface's area each), which no sphere of
// the disk covers (gap up to 1.5 - 0.6 > limb_gap x diag): with cover_fraction 0.01 both are kept whole, joined by one
// edge each (no cycle added: the Euler characteristic is the default's), and reach beyond 1.2 of the 2.1. On the
// plates (a square plate, an L-bracket) no cut-off part covers anything: the medial mesh is the default's.
TEST(MedialAxis, PartsCoveringUncoveredSurfaceAreKeptWhole) {
    const TriangleMesh s =
        revolve({{0, -2.1}, {0.25, -2.1}, {0.25, -0.6}, {2, -0.6}, {2, 0.6}, {0.25, 0.6}, {0.25, 2.1}, {0, 2.1}}, 32);
    MedialAxisOptions o = coarse();
    o.cover_fraction = 0.01;
    MedialAxisOptions off = coarse();
    off.cover_fraction = 0;
    const MedialAxis a = compute_medial_axis(s, off);
    const MedialAxis m = compute_medial_axis(s, o);
    EXPECT_EQ(a.covering_parts, 0);
    EXPECT_EQ(m.covering_parts, 2);
    std::array<double, 2> z = {1e9, -1e9};
    for (const Vec3& p : m.medial.points) z = {std::min(z[0], p.z), std::max(z[1], p.z)};
    EXPECT_GT(z[1], 1.2);
    EXPECT_LT(z[0], -1.2);
    EXPECT_EQ(m.sheets, 1);
    EXPECT_EQ(m.curves, a.curves + 2);
    EXPECT_EQ(m.euler, a.euler);
    expect_sane(m, s);
    for (const TriangleMesh& p : {extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3),
                                  extrude({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 3)}) {
        const MedialAxis q = compute_medial_axis(p, o);
        EXPECT_EQ(q.covering_parts, 0);
        EXPECT_EQ(q.medial, compute_medial_axis(p, off).medial);
    }
}

TEST(MedialAxis, PlatesKeepNoLimbs) {
    MedialAxisOptions on = coarse();
    on.keep_limbs = true;
    for (const TriangleMesh& s : {extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3),
                                  extrude({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 3)}) {
        const MedialAxis m = compute_medial_axis(s, on);
        EXPECT_EQ(m.limbs, 0);
        EXPECT_EQ(m.medial, compute_medial_axis(s, coarse()).medial);
    }
}

TEST(MedialAxis, SameSurfaceSameMedialMesh) {
    const TriangleMesh s = extrude({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 3);
    const MedialAxis a = compute_medial_axis(s, coarse());
    const MedialAxis b = compute_medial_axis(s, coarse());
    EXPECT_EQ(a.medial, b.medial);
}

TEST(MedialAxis, WrittenMaReadsBackTheSame) {
    const TriangleMesh s = extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3);
    const MedialAxis m = compute_medial_axis(s, coarse());
    const std::string path = ::testing::TempDir() + "medial_axis_plate.ma";
    write_medial_mesh(path, m.medial);
    const Skeleton back = read_medial_mesh(path);
    EXPECT_EQ(back, m.medial);  // 17 significant digits: doubles round-trip exactly
}

TEST(MedialAxis, OpenSurfaceIsRefused) {
    TriangleMesh s = extrude({{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, -0.3, 0.3);
    s.triangles.pop_back();
    try {
        compute_medial_axis(s, coarse());
        FAIL() << "an open surface was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        EXPECT_NE(std::string(e.what()).find("boundary edges 3"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace mesohex
