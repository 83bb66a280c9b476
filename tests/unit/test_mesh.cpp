// mesh_skeleton, the library call behind `mesohex mesh`, and its report: checked on cases small enough to follow by
// hand (a straight segment in a box, the generated shapes without a domain).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesohex/core/error.h"
#include "mesohex/core/topology.h"
#include "mesohex/mesh.h"
#include "mesohex/mesh_report.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex/stages/tip_trim.h"
#include "mesohex/surface/thicken.h"

using namespace mesohex;

namespace {

// The box [0, sx] x [0, sy] x [0, sz] as 12 triangles, counter-clockwise seen from outside.
TriangleMesh box_surface(double sx, double sy, double sz) {
    TriangleMesh s;
    s.points = {{0, 0, 0}, {sx, 0, 0}, {sx, sy, 0}, {0, sy, 0}, {0, 0, sz}, {sx, 0, sz}, {sx, sy, sz}, {0, sy, sz}};
    const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    for (const auto& q : quads) {
        s.triangles.push_back({q[0], q[1], q[2]});
        s.triangles.push_back({q[0], q[2], q[3]});
    }
    return s;
}

// A segment along the box's axis, 0.5 from both ends: every point is 0.5 from the nearest face.
Skeleton axis_segment() {
    Skeleton s;
    s.points = {{0.5, 0.5, 0.5}, {3.5, 0.5, 0.5}};
    s.edges = {{0, 1}};
    return s;
}

std::set<std::string> keys(const nlohmann::json& j) {
    std::set<std::string> k;
    for (const auto& [key, value] : j.items()) k.insert(key);
    return k;
}

}  // namespace

TEST(MeshSkeleton, WithoutADomainItIsTheRawPipeline) {
    for (const char* name : {"tfan", "hand", "pan"}) {
        const Skeleton s = generate_skeleton(name);
        const MeshRun run = mesh_skeleton(s, nullptr);
        const PipelineResult direct = run_pipeline(s);
        EXPECT_EQ(run.mesh(), direct.raw.mesh) << name;
        EXPECT_FALSE(run.finish.has_value());
        EXPECT_TRUE(run.attempts.empty());
        EXPECT_TRUE(run.prediction_exact) << name;
        EXPECT_EQ(run.quality().hexes, direct.predicted.hexes);
        EXPECT_EQ(run.exit_status(), 0);
        EXPECT_TRUE(run.radius_note.empty());
    }
}

// keep_raw_topology: the raw mesh's topology comes with the run (the one its quality was computed from); without
// it, none is kept.
TEST(MeshSkeleton, KeepsTheRawTopologyWhenAsked) {
    const Skeleton s = generate_skeleton("tfan");
    MeshOptions options;
    options.keep_raw_topology = true;
    const MeshRun kept = mesh_skeleton(s, nullptr, options);
    const HexTopology direct = compute_hex_topology(kept.pipeline.raw.mesh);
    EXPECT_EQ(kept.raw_topology.faces, direct.faces);
    EXPECT_EQ(kept.raw_topology.edge_valence, direct.edge_valence);
    EXPECT_EQ(kept.raw_topology.boundary_quads, direct.boundary_quads);
    EXPECT_EQ(kept.raw_topology.hex_faces.size(), kept.pipeline.raw.mesh.hexes.size());
    const MeshRun dropped = mesh_skeleton(s, nullptr);
    EXPECT_TRUE(dropped.raw_topology.faces.empty());
    EXPECT_EQ(dropped.raw_quality.sj, kept.raw_quality.sj);
}

TEST(MeshSkeleton, RadiiComeFromTheDomain) {
    // Both ends 0.5 from the nearest face: radius 0.5 x 0.5 = 0.25 there, and along the resampled segment too.
    MeshOptions o;
    o.finish = false;
    const TriangleMesh box = box_surface(4, 1, 1);
    const MeshRun run = mesh_in_domain(axis_segment(), box, o);
    EXPECT_EQ(run.radius_note, "surface (0.500000 x distance)");
    ASSERT_FALSE(run.pipeline.skeleton.radii.empty());
    for (double r : run.pipeline.skeleton.radii) EXPECT_NEAR(r, 0.25, 1e-12);
    EXPECT_FALSE(run.finish.has_value());
    // A straight segment of E edges: 4 hexes per edge.
    EXPECT_EQ(run.quality().hexes, 4 * static_cast<long>(run.pipeline.skeleton.edges.size()));
}

TEST(MeshSkeleton, AVertexOnTheSurfaceIsNamed) {
    Skeleton s = axis_segment();
    s.points[1] = {4.0, 0.5, 0.5};  // on the face x = 4: distance 0, no radius
    try {
        mesh_in_domain(s, box_surface(4, 1, 1));
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        EXPECT_EQ(e.where().kind, ElementRef::Kind::SkeletonVertex);
        EXPECT_EQ(e.where().index, 1);
    }
}

TEST(MeshSkeleton, FinishedInTheDomainWithItsReport) {
    const TriangleMesh box = box_surface(4, 1, 1);
    MeshOptions o;
    o.finishing.levels = 1;
    o.retry = false;  // the first attempt's counts (the retries: FullyPaddedAttemptWhenTheBareFinishMissesAGoal)
    o.structural_retry = false;  // (StructuralAlternativesSkippedWhenTheyChangeNothing)
    const MeshRun run = mesh_in_domain(axis_segment(), box, o);
    ASSERT_TRUE(run.finish.has_value());
    ASSERT_EQ(run.attempts.size(), 1u);
    EXPECT_EQ(run.attempts.front().hexes, run.finish->quality.hexes);
    EXPECT_EQ(run.attempts.front().padding, "selective");
    // The raw tube's boundary: a chunk's cross-section is a square cut into 4 quadrant squares, so 8 side quads per
    // edge, and 4 quads on each end cap. The end caps are flat squares whose 90-degree rims land on the rims of the
    // box's end faces: the selective padding (the default) leaves them bare (8 quads) and adds one hex per side quad;
    // one level multiplies by 8.
    const long raw = run.raw_quality.hexes;
    const long edges = static_cast<long>(run.pipeline.skeleton.edges.size());
    EXPECT_EQ(run.finish->pad_bare_quads, 8);
    EXPECT_EQ(run.finish->pad_bare_regions, 2);
    EXPECT_EQ(run.quality().hexes, 8 * (raw + 8 * edges));
    EXPECT_EQ(&run.mesh(), &run.finish->mesh);
    EXPECT_EQ(run.exit_status(), run.quality().inverted > 0 ? 5 : 0);

    const nlohmann::json rep = mesh_report(run, {"segment.obj", "segment.mesh", "box.off", 1.0, 2.0});
    const std::set<std::string> expected = {"input",
                                            "output",
                                            "skeleton",
                                            "meshed_skeleton",
                                            "resampled",
                                            "radius",
                                            "predicted",
                                            "prediction_matches",
                                            "quality",
                                            "raw_quality",
                                            "repairs",
                                            "stages",
                                            "surface",
                                            "subdivision_levels",
                                            "fit",
                                            "untangled",
                                            "attempts",
                                            "kept_attempt",
                                            "free_branching_reach",
                                            "hausdorff",
                                            "timings_ms",
                                            "inherited_levels",
                                            "padding"};
    EXPECT_EQ(keys(rep), expected);
    EXPECT_EQ(rep["quality"]["hexes"].get<long>(), run.quality().hexes);
    EXPECT_EQ(rep["raw_quality"]["hexes"].get<long>(), raw);
    EXPECT_EQ(rep["surface"], "box.off");
    EXPECT_EQ(rep["radius"]["source"], "surface (0.500000 x distance)");
    EXPECT_EQ(rep["subdivision_levels"].get<int>(), 1);
    EXPECT_GE(rep["timings_ms"]["read_skeleton"].get<double>(), 1.0);
    EXPECT_GE(rep["timings_ms"]["write_and_finish"].get<double>(), 2.0);
}

// The same tube in its box with the retries on: the selectively padded finish (end caps bare) misses a goal here, so
// the same raw mesh is finished again with every quad padded (one padding hex per raw boundary quad: 8 side quads per
// edge and 4 per end cap), and the better of the two is kept; the attempts say which padding each had.
TEST(MeshSkeleton, FullyPaddedAttemptWhenTheBareFinishMissesAGoal) {
    const TriangleMesh box = box_surface(4, 1, 1);
    MeshOptions o;
    o.finishing.levels = 1;
    std::vector<MeshProgress> attempts;  // the progress reports of the attempts, in order
    o.progress = [&attempts](const MeshProgress& p) {
        if (p.stage == "attempt") attempts.push_back(p);
    };
    const MeshRun run = mesh_in_domain(axis_segment(), box, o);
    ASSERT_TRUE(run.finish.has_value());
    ASSERT_GE(run.attempts.size(), 2u);
    // Every attempt is announced once, numbered in the order they run, out of the 6 the default options allow (first,
    // fully padded, cautious joints, 3 structural alternatives: structural_max_finished).
    ASSERT_EQ(attempts.size(), run.attempts.size());
    for (std::size_t i = 0; i < attempts.size(); ++i) {
        EXPECT_EQ(attempts[i].step, static_cast<int>(i) + 1);
        EXPECT_EQ(attempts[i].steps, 6);  // and 3 of the 5 structural alternatives
    }
    EXPECT_EQ(attempts[0].what, "first");
    EXPECT_EQ(attempts[1].what, "fully padded");
    EXPECT_EQ(run.attempts[0].padding, "selective");
    EXPECT_GT(run.attempts[0].missed_goals, 0);
    EXPECT_EQ(run.attempts[1].padding, "all");
    const long raw = run.raw_quality.hexes;
    const long edges = static_cast<long>(run.pipeline.skeleton.edges.size());
    EXPECT_EQ(run.attempts[0].hexes, 8 * (raw + 8 * edges));
    EXPECT_EQ(run.attempts[1].hexes, 8 * (raw + 8 * edges + 8));
    const MeshAttempt& kept = run.finish->pad_mode == "all" ? run.attempts[1] : run.attempts[0];
    EXPECT_EQ(kept.hexes, run.quality().hexes);
    EXPECT_LE(kept.missed_goals, std::min(run.attempts[0].missed_goals, run.attempts[1].missed_goals));
}

namespace {

// A Y: a trunk of length 3 along -x and two branches of length 3 leaving the origin 15 degrees either side of +x (a
// close pair, 30 degrees apart: the crease their chunks share is folded beyond 300 degrees), every radius 0.5.
Skeleton close_pair_y() {
    const double a = 15.0 * std::acos(-1.0) / 180.0;
    Skeleton s;
    s.points = {{0, 0, 0}, {-3, 0, 0}, {3 * std::cos(a), 3 * std::sin(a), 0}, {3 * std::cos(a), -3 * std::sin(a), 0}};
    s.edges = {{0, 1}, {0, 2}, {0, 3}};
    s.radii = {0.5, 0.5, 0.5, 0.5};
    return s;
}

// The close pair's Y thickened at 3 cells per radius.
TriangleMesh close_pair_y_domain(const Skeleton& y) {
    ThickenOptions t;
    t.cells_per_radius = 3;
    return thicken(y, t);
}

// One attempt at one level, a min SJ goal no mesh meets, and the close-pair crease wedge as the only alternative.
MeshOptions wedge_alternative_only() {
    MeshOptions o;
    o.retry = false;
    o.finishing.levels = 1;
    o.goals.sj_min = 1.0;
    o.structural_alternatives = {StructuralAlternative::CloseCreaseWedge};
    return o;
}

}  // namespace

// MeshOptions::structural_retry on the tube in its box, which misses a goal after its attempts (first, fully padded):
// it has no branching point, so no alternative changes the finish input (no degree-4 point for a valley trunk, no
// joint next to a junction to slide, no ring of branches for a pit branch, no close pair's crease for a wedge, no
// bulged bridge to cover). Each is skipped by its hash, the run keeps
// its two attempts and the progress counts the alternatives among the attempts the options allow (3 + at most 3
// structural ones finished, structural_max_finished).
TEST(MeshSkeleton, StructuralAlternativesSkippedWhenTheyChangeNothing) {
    const TriangleMesh box = box_surface(4, 1, 1);
    MeshOptions o;
    o.finishing.levels = 1;
    std::vector<MeshProgress> attempts;
    o.progress = [&attempts](const MeshProgress& p) {
        if (p.stage == "attempt") attempts.push_back(p);
    };
    const MeshRun run = mesh_in_domain(axis_segment(), box, o);
    ASSERT_EQ(run.attempts.size(), 2u);
    EXPECT_EQ(run.attempts[0].what, "first");
    EXPECT_EQ(run.attempts[1].what, "fully padded");
    for (const MeshProgress& p : attempts) EXPECT_EQ(p.steps, 6);
    ASSERT_TRUE(run.structural.has_value());
    EXPECT_TRUE(run.structural->finished.empty());
    EXPECT_EQ(run.structural->skipped,
              (std::vector<std::string>{"valley trunks: the same finish input as an attempt finished",
                                        "slid cut joints: the same finish input as an attempt finished",
                                        "pit branches: the same finish input as an attempt finished",
                                        "close-pair crotch wedge: the same finish input as an attempt finished",
                                        "bulged bridges covered: the same finish input as an attempt finished"}));
    EXPECT_EQ(run.structural->kept, "");
    EXPECT_EQ(run.structural->stop, "all tried");
    EXPECT_EQ(run.attempts[static_cast<std::size_t>(run.kept_attempt)].hexes, run.quality().hexes);
}

// The close pair's Y in its thickened domain with a min SJ goal no hex can reach (1.0: every finish misses): after
// the first attempt (retries off, one subdivision level) the close-pair crease wedge is finished as a second
// attempt, since the pair is 30 degrees apart (< 60) and shares a crease, and the better of the two
// (better_finish_by_shortfall) is kept. The two results are recomputed apart (the wedges switched on directly) to say
// which. With goals every finish meets, the first attempt is the only one and nothing structural runs.
TEST(MeshSkeleton, StructuralAlternativeFinishedAndTheBetterKept) {
    const Skeleton y = close_pair_y();
    const TriangleMesh domain = close_pair_y_domain(y);
    const MeshOptions o = wedge_alternative_only();
    const MeshRun run = mesh_in_domain(y, domain, o);
    ASSERT_EQ(run.attempts.size(), 2u);
    EXPECT_EQ(run.attempts[0].what, "first");
    EXPECT_EQ(run.attempts[1].what, "close-pair crease wedge");
    ASSERT_TRUE(run.structural.has_value());
    EXPECT_EQ(run.structural->finished, (std::vector<std::string>{"close-pair crease wedge"}));
    EXPECT_TRUE(run.structural->skipped.empty());

    MeshOptions plain = o;
    plain.structural_retry = false;
    const MeshRun first = mesh_in_domain(y, domain, plain);
    MeshOptions wedged = plain;
    wedged.finishing.crease_wedge.min_dihedral_deg = 300;
    wedged.crease_wedge_pair_deg = 60;
    const MeshRun wedge = mesh_in_domain(y, domain, wedged);
    ASSERT_EQ(first.attempts.size(), 1u);
    EXPECT_GT(wedge.finish->crease_wedges, 0);
    EXPECT_EQ(run.attempts[1].hexes, wedge.quality().hexes);
    EXPECT_EQ(run.attempts[1].sj_min, wedge.quality().sj_min);
    const bool wedge_better = better_finish_by_shortfall(*wedge.finish, *first.finish, o.goals);
    EXPECT_EQ(run.kept_attempt, wedge_better ? 1 : 0);
    EXPECT_EQ(run.structural->kept, wedge_better ? "close-pair crease wedge" : "");
    EXPECT_EQ(run.mesh(), wedge_better ? wedge.mesh() : first.mesh());

    MeshOptions easy = o;
    easy.goals = {0.0, 0.0, 1.0};  // any valid mesh with no inverted hex meets them
    const MeshRun met = mesh_in_domain(y, domain, easy);
    ASSERT_EQ(met.attempts.size(), 1u);
    EXPECT_EQ(met.kept_attempt, 0);
    EXPECT_FALSE(met.structural.has_value());
    EXPECT_EQ(met.mesh(), first.mesh());
}

// An alternative whose finish throws a mesohex::Error (here from the progress callback in its finish, as a fit whose
// factorization fails would) is skipped: the run ends with the mesh kept before it, as without the alternative. Any
// other exception (a caller's cancellation) propagates.
TEST(MeshSkeleton, StructuralAlternativeWhoseFinishFailsIsSkipped) {
    const Skeleton y = close_pair_y();
    const TriangleMesh domain = close_pair_y_domain(y);
    MeshOptions o = wedge_alternative_only();
    MeshOptions plain = o;
    plain.structural_retry = false;
    const MeshRun first = mesh_in_domain(y, domain, plain);
    bool in_wedge = false;  // shared by the callback's copies (the run copies its options)
    const auto failing = [&in_wedge](bool mesohex_error) {
        return [mesohex_error, &in_wedge](const MeshProgress& p) {
            if (p.stage == "attempt") in_wedge = p.what == "close-pair crease wedge";
            if (!in_wedge || p.stage == "attempt") return;  // the wedge's first finishing stage that reports
            if (mesohex_error) throw Error(ErrorCode::NumericalFailure, "test: the fit failed");
            throw std::runtime_error("test: cancelled");
        };
    };
    o.progress = failing(true);
    const MeshRun run = mesh_in_domain(y, domain, o);
    ASSERT_EQ(run.attempts.size(), 1u);
    EXPECT_EQ(run.kept_attempt, 0);
    ASSERT_TRUE(run.structural.has_value());
    EXPECT_TRUE(run.structural->finished.empty());
    EXPECT_EQ(run.structural->skipped,
              (std::vector<std::string>{"close-pair crease wedge: failed in the finish (test: the fit failed)"}));
    EXPECT_EQ(run.structural->stop, "all tried");
    EXPECT_EQ(run.mesh(), first.mesh());
    o.progress = failing(false);
    EXPECT_THROW(mesh_in_domain(y, domain, o), std::runtime_error);
}

// MeshOptions::finer_retry: the tube in its box misses a goal after its attempts (first, fully padded) at the level the
// finishing chose; its kept raw mesh is finished once more one level finer (8 x the hexes: uniform subdivision), the
// seventh attempt
// the options allow (after 3 retries and 3 structural alternatives), and the better of the two kept. Not with the
// levels given, nor beyond the budget.
TEST(MeshSkeleton, OneLevelFinerWhenTheKeptMeshMissesAGoal) {
    const TriangleMesh box = box_surface(4, 1, 1);
    MeshOptions o;
    o.finer_retry = true;
    std::vector<MeshProgress> attempts;
    o.progress = [&attempts](const MeshProgress& p) {
        if (p.stage == "attempt") attempts.push_back(p);
    };
    const MeshRun run = mesh_in_domain(axis_segment(), box, o);
    ASSERT_TRUE(run.finish.has_value());
    ASSERT_EQ(run.attempts.size(), 3u);
    ASSERT_EQ(attempts.size(), 3u);
    EXPECT_EQ(attempts[2].what, "one level finer");
    for (const MeshProgress& p : attempts) EXPECT_EQ(p.steps, 7);  // 3 retries, 3 structural, 1 finer
    const MeshAttempt& before =
        run.attempts[0].missed_goals <= run.attempts[1].missed_goals ? run.attempts[0] : run.attempts[1];
    EXPECT_GT(std::min(run.attempts[0].missed_goals, run.attempts[1].missed_goals), 0);
    EXPECT_EQ(run.attempts[2].levels, run.attempts[0].levels + 1);
    EXPECT_EQ(run.attempts[2].hexes, 8 * before.hexes);
    EXPECT_EQ(run.attempts[2].padding, before.padding);
    EXPECT_LE(run.finish->quality.hexes, run.attempts[2].hexes);

    MeshOptions budget = o;
    budget.retry_max_hexes = 8 * before.hexes - 1;  // the finer mesh would exceed it
    attempts.clear();
    EXPECT_EQ(mesh_in_domain(axis_segment(), box, budget).attempts.size(), 2u);
    MeshOptions given = o;
    given.finishing.levels = run.attempts[0].levels;
    attempts.clear();
    EXPECT_EQ(mesh_in_domain(axis_segment(), box, given).attempts.size(), 2u);
}

// The unit sphere as a UV mesh: the poles (-1, 0, 0) and (1, 0, 0), `rings` - 1 rings of `segments` vertices between
// them (ring i at angle pi i / rings from the first pole), counter-clockwise seen from outside.
TriangleMesh uv_sphere(int rings, int segments) {
    TriangleMesh s;
    s.points.push_back({-1, 0, 0});
    for (int i = 1; i < rings; ++i) {
        const double t = M_PI * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double p = 2 * M_PI * j / segments;
            s.points.push_back({-std::cos(t), std::sin(t) * std::cos(p), std::sin(t) * std::sin(p)});
        }
    }
    s.points.push_back({1, 0, 0});
    const auto at = [segments](int i, int j) { return 1 + (i - 1) * segments + j % segments; };
    const int last = static_cast<int>(s.points.size()) - 1;
    for (int j = 0; j < segments; ++j) s.triangles.push_back({0, at(1, j + 1), at(1, j)});
    for (int i = 1; i + 1 < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            s.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            s.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    for (int j = 0; j < segments; ++j) s.triangles.push_back({last, at(rings - 1, j), at(rings - 1, j + 1)});
    return s;
}

// MeshOptions::refine_to_distance on a short segment (x = -0.2 .. 0.2) in the unit sphere (24 x 32 facets), radii
// 0.5 x the distance: the level rule gives 1 level, 160 hexes (a padded raw mesh of 20 hexes, nothing left bare on a
// smooth surface, no branching point for a cautious skeleton), which meets the min SJ (about 0.72) but misses the
// Hausdorff goal (about 1.15 % of the diagonal): too few boundary vertices on a round surface. One level finer
// (8 x 160 = 1 280 hexes, about 0.42 %) meets it and is kept; with a goal of 0.3 % that one still misses and a third
// level (10 240 hexes, about 0.26 %) meets it. The rule stops at the budget, never runs when min SJ is missed (a
// subdivision keeps every corner's scaled Jacobian) nor with the levels given, and the report says so.
TEST(MeshSkeleton, FinerLevelsWhileOnlyTheDistanceGoalIsMissed) {
    const TriangleMesh sphere = uv_sphere(24, 32);
    Skeleton segment;
    segment.points = {{-0.2, 0, 0}, {0.2, 0, 0}};
    segment.edges = {{0, 1}};
    MeshOptions o;
    o.refine_to_distance = true;
    const MeshRun run = mesh_in_domain(segment, sphere, o);
    ASSERT_TRUE(run.finish.has_value());
    ASSERT_TRUE(run.distance_refinement.has_value());
    ASSERT_EQ(run.attempts.size(), 2u);
    EXPECT_EQ(run.attempts[0].levels, 1);
    EXPECT_EQ(run.attempts[0].hexes, 160);
    EXPECT_GE(run.attempts[0].sj_min, 0.3);
    EXPECT_GT(run.attempts[0].hausdorff_relative_max, 0.01);
    const DistanceRefinement& d = *run.distance_refinement;
    EXPECT_EQ(d.levels_before, 1);
    EXPECT_EQ(d.levels, std::vector<int>{2});
    EXPECT_EQ(d.hexes, std::vector<long>{8 * 160});
    EXPECT_EQ(d.levels_kept, 2);
    EXPECT_EQ(d.stop, "distance met");
    EXPECT_LE(run.finish->distance.relative_max, 0.01);
    EXPECT_EQ(run.quality().hexes, 1280);
    EXPECT_EQ(missed_goals(*run.finish, o.goals), 0);
    const nlohmann::json rep = mesh_report(run, {"segment.obj", "segment.mesh", "sphere.off", 0, 0});
    EXPECT_EQ(rep["distance_refinement"]["levels_tried"], nlohmann::json::array({2}));
    EXPECT_EQ(rep["distance_refinement"]["stop"], "distance met");
    EXPECT_EQ(rep["distance_refinement"]["tolerance"].get<double>(), 0.01);

    MeshOptions tight = o;
    tight.goals.hausdorff = 0.003;
    const MeshRun three = mesh_in_domain(segment, sphere, tight);
    ASSERT_TRUE(three.distance_refinement.has_value());
    EXPECT_EQ(three.distance_refinement->levels, (std::vector<int>{2, 3}));
    EXPECT_EQ(three.distance_refinement->hexes, (std::vector<long>{1280, 10240}));
    EXPECT_GT(three.distance_refinement->hausdorff[0], 0.003);
    EXPECT_EQ(three.distance_refinement->stop, "distance met");
    EXPECT_EQ(three.quality().hexes, 10240);

    MeshOptions budget = tight;  // the third level would bring the hexes finished to 160 + 1 280 + 10 240
    budget.finishing.max_hexes = 160 + 1280 + 10240 - 1;
    const MeshRun two = mesh_in_domain(segment, sphere, budget);
    EXPECT_EQ(two.distance_refinement->levels, std::vector<int>{2});
    EXPECT_EQ(two.distance_refinement->stop, "budget");
    EXPECT_EQ(two.quality().hexes, 1280);

    MeshOptions strict = o;
    strict.goals.sj_min = 0.9;  // missed at 1 level: no finer level
    const MeshRun kept = mesh_in_domain(segment, sphere, strict);
    EXPECT_TRUE(kept.distance_refinement->levels.empty());
    EXPECT_EQ(kept.distance_refinement->stop, "min SJ missed");
    EXPECT_EQ(kept.quality().hexes, 160);
    MeshOptions given = o;
    given.finishing.levels = 1;
    EXPECT_EQ(mesh_in_domain(segment, sphere, given).distance_refinement->stop, "levels given");
    o.refine_to_distance = false;
    EXPECT_FALSE(mesh_in_domain(segment, sphere, o).distance_refinement.has_value());
}

// A straight branch along the box [0, 4] x [0, 1] x [0, 1] with file radii 0.25: joints at x = 0.5, 1.5, 2.5, 3.5
// inside, then 4.2 and 4.6 outside (a domain that ends before the skeleton does).
Skeleton branch_leaving_the_box() {
    Skeleton s;
    for (const double x : {0.5, 1.5, 2.5, 3.5, 4.2, 4.6}) s.points.push_back({x, 0.5, 0.5});
    s.radii.assign(s.points.size(), 0.25);
    for (int v = 0; v + 1 < 6; ++v) s.edges.push_back({v, v + 1});
    return s;
}

TEST(TipTrim, TheChainOutsideGoesBackToTheLastHeldJoint) {
    const Skeleton s = branch_leaving_the_box();
    const TipTrim t = trim_unheld_tips(s, {1, 1, 1, 1, 0, 0});
    EXPECT_EQ(t.trimmed, (std::vector<int>{4, 5}));
    EXPECT_EQ(t.new_ends, (std::vector<int>{3}));
    EXPECT_EQ(t.skeleton.points.size(), 4u);
    EXPECT_EQ(t.skeleton.edges.size(), 3u);
    EXPECT_EQ(t.vertex_map, (std::vector<int>{0, 1, 2, 3, -1, -1}));
    // Not held at both ends of a single branch: the held middle keeps
    // one side (the earlier chain, lower tip id), never zero edges.
    const TipTrim both = trim_unheld_tips(s, {0, 0, 1, 0, 0, 0});
    EXPECT_EQ(both.trimmed, (std::vector<int>{3, 4, 5}));
    EXPECT_EQ(both.new_ends, (std::vector<int>{2}));
    // A tip held, or a branch not held up to its other end: nothing trimmed, the skeleton as given.
    EXPECT_TRUE(trim_unheld_tips(s, {1, 1, 1, 1, 1, 1}).trimmed.empty());
    const TipTrim none = trim_unheld_tips(s, {0, 0, 0, 0, 0, 0});
    EXPECT_TRUE(none.trimmed.empty());
    EXPECT_EQ(none.skeleton, s);
}

TEST(MeshSkeleton, BranchTipsOutsideTheDomainAreTrimmed) {
    const TriangleMesh box = box_surface(4, 1, 1);
    MeshOptions o;
    o.finish = false;
    const MeshRun run = mesh_in_domain(branch_leaving_the_box(), box, o);
    EXPECT_EQ(run.pipeline.trimmed_tips, (std::vector<int>{4, 5}));
    EXPECT_EQ(run.pipeline.trimmed_tip_ends, (std::vector<int>{3}));
    // The branch x = 0.5 ... 3.5 (length 3, radius 0.25): adaptation bisects while r + r < length (adaptation.h),
    // 3 -> 1.5 -> 0.75 -> 0.375: 8 edges, 4 hexes each; the same mesh as the skeleton given without the two outside
    // vertices. Untrimmed (x up to 4.6, length 4.1): 4.1 / 8 = 0.51 > 0.5 is cut once more, 16 edges, 64 hexes.
    EXPECT_EQ(run.pipeline.skeleton.edges.size(), 8u);
    EXPECT_EQ(run.quality().hexes, 32);
    Skeleton inside = branch_leaving_the_box();
    inside.points.resize(4);
    inside.radii.resize(4);
    inside.edges.resize(3);
    EXPECT_EQ(run.mesh(), mesh_in_domain(inside, box, o).mesh());
    const nlohmann::json rep = mesh_report(run, {"branch.obj", "branch.mesh", "box.off", 0, 0});
    EXPECT_EQ(rep["repairs"]["trimmed_tips"], nlohmann::json::array({4, 5}));
    EXPECT_NE(repairs_to_text(run.pipeline, run.options)
                  .find("branch tips outside the domain trimmed: input vertices 4 5 removed; the branch now ends at "
                        "input vertices 3"),
              std::string::npos);
    // Off: the whole branch is meshed, out to x = 4.6.
    o.trim_unheld_tips = false;
    const MeshRun off = mesh_in_domain(branch_leaving_the_box(), box, o);
    EXPECT_TRUE(off.pipeline.trimmed_tips.empty());
    EXPECT_EQ(off.quality().hexes, 64);
}

TEST(MeshSkeleton, RawReportSaysWhereTheRadiusCameFrom) {
    const MeshRun run = mesh_skeleton(generate_skeleton("tfan"), nullptr);
    const nlohmann::json rep = mesh_report(run, {"tfan.obj", "tfan.mesh", "", 0, 0});
    EXPECT_EQ(rep.count("stages"), 0u);
    EXPECT_EQ(rep.count("hausdorff"), 0u);
    EXPECT_TRUE(rep["prediction_matches"].get<bool>());
    EXPECT_EQ(rep["predicted"]["hexes"].get<long>(), run.pipeline.predicted.hexes);
    EXPECT_EQ(rep["quality"]["hexes"].get<long>(), run.pipeline.predicted.hexes);
}

TEST(MeshSkeleton, TheProgressCallbackCanCancel) {
    struct Cancelled : std::runtime_error {
        Cancelled() : std::runtime_error("cancelled") {}
    };
    MeshOptions o;
    std::set<std::string> seen;
    o.progress = [&seen](const MeshProgress& p) {
        seen.insert(p.stage);
        if (p.stage == "fit") throw Cancelled();
    };
    EXPECT_THROW(mesh_in_domain(axis_segment(), box_surface(4, 1, 1), o), Cancelled);
    EXPECT_EQ(seen, (std::set<std::string>{"raw", "attempt", "fit"}));
}

// Issue 16 item 3, thin sheets: the generated thin-sheet shapes (sheet radius 0.1 x the leaflet edge) meshed end to end
// in their thickened domains (3 grid cells per smallest radius, as bench/random_set.sh) with the default options: no
// inverted hex, min scaled Jacobian >= 0.4 and Hausdorff <= 1 % of the diagonal (measured 2026-12-02 with the
// padding layer following the edge into the mesh: 0.53 to 0.64, 0.36 to 0.64 %; docs/sheets.md).
TEST(MeshSkeleton, ThinSheetsMeetTheTargetsInTheirThickenedDomains) {
    struct Case {
        const char* name;
        double angle_deg;
    };
    for (const Case c : {Case{"fold", 45}, Case{"vfan", 30}, Case{"airplane", 0}, Case{"wireplate", 0}}) {
        SCOPED_TRACE(std::string(c.name) + " " + std::to_string(c.angle_deg));
        GeneratorOptions g;
        g.angle_deg = c.angle_deg;
        const Skeleton s = generate_skeleton(c.name, g);
        ThickenOptions t;
        t.cells_per_radius = 3;
        const MeshRun run = mesh_in_domain(s, thicken(s, t));
        ASSERT_TRUE(run.finish.has_value());
        EXPECT_TRUE(run.quality().validation.valid());
        EXPECT_EQ(run.quality().inverted, 0);
        EXPECT_GE(run.quality().sj_min, 0.4);
        EXPECT_GE(run.quality().sj_avg, 0.85);
        ASSERT_TRUE(run.finish->distance_measured);
        EXPECT_LE(run.finish->distance.relative_max, 0.01);
    }
}

// Random sheet seeds 23 and 148: a branch at a one-face leaflet corner 101.1 / 103.2 degrees open, 10 / 18 degrees
// off its outward bisector. Rooted on the out patch (the rule before 2026-12-03) they missed on Hausdorff only
// (1.61 / 1.69 %); as BL-joints, measured 0.753 / 0.935 / 0.38 % and 0.604 / 0.929 / 0.46 % (docs/sheets.md, "Leaflet
// corners rooted on the out patch").
TEST(MeshSkeleton, ThinSheetsCornerBranchesAreBLJoints) {
    for (const auto& [seed, bl_joints] : {std::pair{23, 2}, std::pair{148, 1}}) {
        SCOPED_TRACE("random seed " + std::to_string(seed));
        const Skeleton s = generate_random_skeleton(seed);
        const SkeletonAnalysis an = analyze_skeleton(s);
        for (const BorderRoot r : an.vertex_border_root) EXPECT_NE(r, BorderRoot::Out);
        EXPECT_EQ(an.counts.bl_joints, bl_joints);
        ThickenOptions t;
        t.cells_per_radius = 3;
        const MeshRun run = mesh_in_domain(s, thicken(s, t));
        ASSERT_TRUE(run.finish.has_value());
        EXPECT_EQ(run.quality().inverted, 0);
        EXPECT_GE(run.quality().sj_min, 0.5);
        EXPECT_GE(run.quality().sj_avg, 0.85);
        ASSERT_TRUE(run.finish->distance_measured);
        EXPECT_LE(run.finish->distance.relative_max, 0.01);
    }
}

// A thick flange (issue 22 item 1): `flange -n 6 -m 1` (plate of 6 x 6 unit quads, walls of 1 row above and below the
// chain of 2 edges from (-3, -1, 0) to (-3, 1, 0) on its border side x = -3; the border runs on 2 edges past each chain
// end) and `flangeup` (the upper wall only: one leaflet creased along the chain, cut there). The walls dock on the
// plate's border (docked_walls.h, docs/blocks.md "The flange docked on the plate's border"): the chain edges are the
// plate's border edges. Hexes by hand, 2 per face + 2 per border edge (the plate's 24 with the chain, 4 per wall):
// flange 2 x 40 + 2 x (24 + 8) = 144, flangeup 2 x 38 + 2 x (24 + 4) = 132; vertices: the plate's 25 interior x 3 +
// 24 border x 6, 3 off-chain vertices per wall x 6: 255 / 237; a ball (Euler characteristic 1 = the skeleton's). The
// worst hex is the wall's end half-chunk on the plate (one row: its end vertex is the wall's corner, out column on the
// diagonal): scaled Jacobian 0.500 (bench/flange_dock_sj.py) whatever r < L, where the old structure inverted above
// r = L / 2 (SJ (L - 2 r) / ..., refused since session 31): checked at r = 0.45, 0.55 and 0.75 L.
TEST(MeshSkeleton, ThickFlangeIsDockedOnThePlatesBorderAtAnyRadiusBelowTheEdge) {
    for (const char* name : {"flange", "flangeup"}) {
        const bool both = std::string(name) == "flange";
        for (const double r : {0.45, 0.55, 0.75}) {
            SCOPED_TRACE(std::string(name) + " r " + std::to_string(r));
            GeneratorOptions g;
            g.n = 6;
            g.m = 1;
            g.radius_scale = r / 0.3;  // the generators' radius is 0.3 x the edge at scale 1
            const Skeleton s = generate_skeleton(name, g);
            const SkeletonAnalysis an = analyze_skeleton(s);
            EXPECT_EQ(an.counts.fan_edges, 0);
            EXPECT_EQ(an.counts.leaflets, both ? 3 : 2);
            MeshOptions placed;  // the hand placement: leaflet copies where the frames put them
            placed.pipeline.raw_mesh.leaflet_offset_fraction = 0;
            const MeshRun exact = mesh_skeleton(s, nullptr, placed);
            EXPECT_EQ(exact.raw_quality.inverted, 0);
            EXPECT_NEAR(exact.raw_quality.sj_min, 0.5, 1e-9);
            // Defaults: the leaflet offset limit (RawMeshOptions::leaflet_offset_fraction, session 31) pulls the
            // wall's copies at the chain in above r = L / 2; measured 0.473 / 0.316 at r = 0.55 / 0.75, none inverted.
            const MeshRun run = mesh_skeleton(s, nullptr, MeshOptions{});
            EXPECT_EQ(run.raw_quality.hexes, both ? 144 : 132);
            EXPECT_EQ(run.raw_quality.vertices, both ? 255 : 237);
            EXPECT_EQ(run.pipeline.predicted.hexes, run.raw_quality.hexes);
            EXPECT_TRUE(run.prediction_exact);
            EXPECT_TRUE(run.raw_quality.validation.valid());
            EXPECT_EQ(run.raw_quality.euler_characteristic, 1);
            EXPECT_EQ(run.raw_quality.inverted, 0);
            EXPECT_GE(run.raw_quality.sj_min, 0.3);
            if (r < 0.5) {
                EXPECT_NEAR(run.raw_quality.sj_min, 0.5, 1e-9);
            }
        }
    }
}

// A flange from the plate's corner (`flangecorner` / `flangecornerup`: plate 4 x 4 of unit quads, walls of 2 rows on
// the chain (0, 0) -> (0, 2) of the side x = 0 from the corner; docs/blocks.md, "Flanges from the plate's corner: the
// corner cube"): docked on the plate's border with a corner cube at the corner, at any r < L. Counts by hand: hexes
// 2 F + 2 B + 2 (the cube), one wall F 20, B 16 + 6 = 22: 86; walls above and below F 24, B 16 + 12 = 28: 106.
// Vertices: the plate's 9 interior x 3 + 15 border x 6 + 12 at the corner = 129, each wall 5 border x 6 + 1 interior
// x 3 = 33: 162 / 195. With the frames' placement the worst hex is the wall's end half-chunk at the mid-side end (2
// rows: 1 / sqrt 3, the flange's value); the corner's own hexes are at least 0.707 (the +n half of the wall's end
// half-chunk, a frustum; the cubes are boxes).
TEST(MeshSkeleton, FlangeFromThePlatesCornerIsDockedWithACornerCube) {
    for (const char* name : {"flangecorner", "flangecornerup"}) {
        const bool both = std::string(name) == "flangecorner";
        for (const double r : {0.3, 0.45, 0.55, 0.75}) {
            SCOPED_TRACE(std::string(name) + " r " + std::to_string(r));
            GeneratorOptions g;
            g.radius_scale = r / 0.3;
            const Skeleton s = generate_skeleton(name, g);
            const SkeletonAnalysis an = analyze_skeleton(s);
            EXPECT_EQ(an.counts.fan_edges, 0);
            EXPECT_EQ(std::count(an.corner_cube.begin(), an.corner_cube.end(), char{1}), 1);
            MeshOptions placed;
            placed.pipeline.raw_mesh.leaflet_offset_fraction = 0;
            const MeshRun exact = mesh_skeleton(s, nullptr, placed);
            EXPECT_EQ(exact.raw_quality.inverted, 0);
            EXPECT_NEAR(exact.raw_quality.sj_min, 1 / std::sqrt(3.0), 1e-9);
            const MeshRun run = mesh_skeleton(s, nullptr, MeshOptions{});
            EXPECT_EQ(run.raw_quality.hexes, both ? 106 : 86);
            EXPECT_EQ(run.raw_quality.vertices, both ? 195 : 162);
            EXPECT_EQ(run.pipeline.predicted.hexes, run.raw_quality.hexes);
            EXPECT_TRUE(run.prediction_exact);
            EXPECT_TRUE(run.raw_quality.validation.valid());
            EXPECT_EQ(run.raw_quality.euler_characteristic, 1);
            EXPECT_EQ(run.raw_quality.inverted, 0);
        }
    }
}
