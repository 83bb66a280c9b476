// remesh_incremental gives the same bits as a full run after random edits (moves of 1-3 vertices, radius changes),
// falls back to a full run when the topology changes, and recomputes exactly the vertices within three edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <string>

#include "bench_inputs.h"
#include "mesohex/core/error.h"
#include "mesohex/incremental.h"
#include "mesohex/pipeline.h"
#include "mesohex/stages/adaptation.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex/stages/skeleton_repair.h"

using namespace mesohex;

namespace {

void expect_same_mesh(const RemeshCache& a, const RemeshCache& b) {
    ASSERT_EQ(a.raw.mesh.hexes, b.raw.mesh.hexes);
    ASSERT_EQ(a.raw.mesh.points.size(), b.raw.mesh.points.size());
    EXPECT_EQ(0,
              std::memcmp(a.raw.mesh.points.data(), b.raw.mesh.points.data(), a.raw.mesh.points.size() * sizeof(Vec3)));
    ASSERT_EQ(a.surfaces.directions.size(), b.surfaces.directions.size());
    EXPECT_EQ(0, std::memcmp(a.surfaces.directions.data(), b.surfaces.directions.data(),
                             a.surfaces.directions.size() * sizeof(Vec3)));
    EXPECT_EQ(a.surfaces.quads, b.surfaces.quads);
    EXPECT_EQ(a.surfaces.quad_edges, b.surfaces.quad_edges);
    EXPECT_EQ(a.surfaces.edges, b.surfaces.edges);
    EXPECT_EQ(a.surfaces.point_valence, b.surfaces.point_valence);
    EXPECT_EQ(a.surfaces.point_begin, b.surfaces.point_begin);
    EXPECT_EQ(a.surfaces.edge_quad, b.surfaces.edge_quad);
    EXPECT_EQ(a.surfaces.quad_rotation, b.surfaces.quad_rotation);
    EXPECT_EQ(a.raw.hex_edge, b.raw.hex_edge);
}

// s with its vertices numbered in reverse (edges mapped, in the same order).
Skeleton reversed_numbering(const Skeleton& s) {
    const int nv = static_cast<int>(s.points.size());
    Skeleton r = s;
    for (int v = 0; v < nv; ++v) {
        r.points[static_cast<std::size_t>(nv - 1 - v)] = s.points[static_cast<std::size_t>(v)];
        r.radii[static_cast<std::size_t>(nv - 1 - v)] = s.radii[static_cast<std::size_t>(v)];
    }
    for (std::array<int, 2>& e : r.edges) e = {nv - 1 - e[0], nv - 1 - e[1]};
    return r;
}

// Moves 1-3 random vertices by up to 8 % of their radius per axis (and sometimes scales a radius by 0.9-1.1), then
// checks the incremental result against a full run; edits the full run rejects are skipped (and must be rejected
// by the incremental run too, leaving the cache unchanged).
void random_edits(const Skeleton& start, int edits, std::uint32_t seed) {
    std::mt19937 rng(seed);
    RemeshCache cache;
    remesh_full(cache, start);
    Skeleton s = start;
    int checked = 0;
    for (int i = 0; i < edits; ++i) {
        Skeleton next = s;
        const int k = 1 + static_cast<int>(rng() % 3);
        for (int j = 0; j < k; ++j) {
            const int v = static_cast<int>(rng() % next.points.size());
            const double step = 0.08 * next.radii[v];
            next.points[v] += Vec3{step * (2 * bench::unit_draw(rng) - 1), step * (2 * bench::unit_draw(rng) - 1),
                                   step * (2 * bench::unit_draw(rng) - 1)};
            if (rng() % 4 == 0) next.radii[v] *= 0.9 + 0.2 * bench::unit_draw(rng);
        }
        RemeshCache full;
        try {
            remesh_full(full, next);
        } catch (const Error&) {
            const Skeleton before = cache.skeleton;
            EXPECT_THROW(remesh_incremental(cache, next), Error);
            EXPECT_EQ(cache.skeleton, before);
            continue;
        }
        const RemeshStats stats = remesh_incremental(cache, next);
        EXPECT_FALSE(stats.full);
        EXPECT_GE(stats.changed_vertices, 1);
        EXPECT_LE(stats.changed_vertices, k);
        expect_same_mesh(cache, full);
        s = next;
        ++checked;
    }
    EXPECT_GE(checked, edits / 2);
}

}  // namespace

TEST(Incremental, RandomEditsOnARandomTree) { random_edits(bench::random_tree(600, 11), 12, 1); }

// Degree-3 points at bridges (ConnectionSurfaceOptions::degree_three_chunks_at_bridges) read their neighbours'
// partitions: the meshed skeletons of random seeds 4 and 14 (their degree-3 points next to other branching points
// change partition with the option), edited at random, equal full runs.
TEST(Incremental, RandomEditsNextToBridges) {
    for (const std::uint32_t seed : {4u, 14u}) {
        SCOPED_TRACE(seed);
        random_edits(run_pipeline(generate_random_skeleton(seed)).skeleton, 12, seed);
    }
}

// A degree-3 point chosen at a bridge (three branch edges, one neighbour or more a branching point, the others joints
// or extremities): -1 when there is none.
namespace {
int first_bridge_point(const Skeleton& s, const SkeletonAnalysis& an) {
    const int nv = static_cast<int>(an.vertex_class.size());
    for (int v = 0; v < nv; ++v) {
        if (an.vertex_class[v] != VertexClass::BranchingPoint ||
            an.vertex_edge_begin[v + 1] - an.vertex_edge_begin[v] != 3)
            continue;
        int bridges = 0;
        bool others_plain = true;
        for (int j = an.vertex_edge_begin[v]; j < an.vertex_edge_begin[v + 1]; ++j) {
            const int e = an.vertex_edges[j];
            if (an.edge_degree[e] != 0) others_plain = false;
            const int w = s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0];
            const VertexClass c = an.vertex_class[w];
            if (c == VertexClass::BranchingPoint)
                ++bridges;
            else if (c != VertexClass::Joint && c != VertexClass::Extremity)
                others_plain = false;
        }
        if (bridges > 0 && others_plain) return v;
    }
    return -1;
}
}  // namespace

// The same skeletons, each edited at one vertex 1, 2, ..., 5 edges from a bridge point (the lowest-numbered vertex at
// that distance, moved by 5 % of its radius): the bridge point reads its neighbours' partitions, so it is recomputed
// when a vertex within two edges of it is (whose surfaces are recomputed within three edges of the edit); each
// incremental result equals a full run.
TEST(Incremental, EditsAtEachDistanceFromABridgePoint) {
    for (const std::uint32_t seed : {4u, 14u}) {
        SCOPED_TRACE(seed);
        const Skeleton start = run_pipeline(generate_random_skeleton(seed)).skeleton;
        RemeshCache cache;
        remesh_full(cache, start);
        const int b = first_bridge_point(cache.skeleton, cache.analysis);
        ASSERT_GE(b, 0);
        std::vector<int> dist(start.points.size(), -1);
        std::vector<int> queue = {b};
        dist[b] = 0;
        for (std::size_t q = 0; q < queue.size(); ++q)
            for (const std::array<int, 2>& e : start.edges)
                for (int k = 0; k < 2; ++k)
                    if (e[k] == queue[q] && dist[e[1 - k]] < 0) {
                        dist[e[1 - k]] = dist[e[k]] + 1;
                        queue.push_back(e[1 - k]);
                    }
        Skeleton s = start;
        for (int d = 1; d <= 5; ++d) {
            SCOPED_TRACE(d);
            const auto it = std::find(dist.begin(), dist.end(), d);
            ASSERT_NE(it, dist.end());
            const std::size_t v = static_cast<std::size_t>(it - dist.begin());
            s.points[v] += Vec3{0.05, -0.03, 0.02} * s.radii[v];
            RemeshCache full;
            remesh_full(full, s);
            EXPECT_FALSE(remesh_incremental(cache, s).full);
            expect_same_mesh(cache, full);
        }
    }
}

TEST(Incremental, RandomEditsOnGeneratedShapesWithLeaflets) {
    for (const char* name : {"hand", "dualocta", "turbine", "bird", "pan", "torustwist"}) {
        SCOPED_TRACE(name);
        random_edits(generate_skeleton(name), 6, 2);
    }
}

// A chain 0-1-...-9 with a branching point at 5 (an extra vertex 10 on it): moving vertex 5 recomputes the vertices
// within three edges: 2, 3, 4, 5, 6, 7, 8 and 10 = 8 vertices.
TEST(Incremental, RecomputesTheVerticesWithinThreeEdges) {
    Skeleton s;
    for (int v = 0; v < 10; ++v) s.points.push_back({static_cast<double>(v), 0, 0});
    s.points.push_back({5, 1, 0.3});
    for (int v = 0; v + 1 < 10; ++v) s.edges.push_back({v, v + 1});
    s.edges.push_back({5, 10});
    s.radii.assign(s.points.size(), 0.3);
    RemeshCache cache;
    const RemeshStats first = remesh_full(cache, s);
    EXPECT_TRUE(first.full);
    // 4 hexes per branch edge, 8 for the compatible block at the T (vertex 5: its branch 17 degrees off the normal)
    EXPECT_EQ(cache.raw.mesh.hexes.size(), 4u * 10u + 8u);
    s.points[5].z += 0.05;
    const RemeshStats stats = remesh_incremental(cache, s);
    EXPECT_FALSE(stats.full);
    EXPECT_EQ(stats.changed_vertices, 1);
    EXPECT_EQ(stats.recomputed_surfaces, 8);
    RemeshCache full;
    remesh_full(full, s);
    expect_same_mesh(cache, full);
}

TEST(Incremental, OtherTopologyIsAFullRun) {
    Skeleton s = bench::three_branch_star(31);
    RemeshCache cache;
    remesh_full(cache, s);
    s.points.push_back(s.points.back() + Vec3{1, 0, 0});
    s.edges.push_back({static_cast<int>(s.points.size()) - 2, static_cast<int>(s.points.size()) - 1});
    s.radii.push_back(0.5);
    const RemeshStats stats = remesh_incremental(cache, s);
    EXPECT_TRUE(stats.full);
    EXPECT_EQ(cache.raw.mesh.hexes.size(), 4u * s.edges.size());
}

// Moving a branching point of a random tree by (0.02, 0.01, 0) before the adaptation can change the adapted vertex
// count (adaptation re-samples whole branches): the remesh is then no incremental one by index (stats.full), but the
// content-keyed memo serves every branching point whose branch directions kept their bits. Each result equals a
// fresh remesh_full bit for bit; over the edits at least one renumbers the skeleton, and there the memo serves more
// branching points than are computed (a 600-vertex tree has dozens; an edit changes a few branches).
TEST(Incremental, MemoServesBranchingPointsAfterARenumberingEdit) {
    const Skeleton base = bench::random_tree(600, 5);
    const SkeletonAnalysis an = analyze_skeleton(base);
    PipelineResult prepared = prepare_skeleton(base);
    RemeshCache cache;
    remesh_full(cache, prepared.skeleton, &prepared.analysis);
    int renumbered = 0, v = 0;
    for (int edit = 0; edit < 6; ++edit) {
        while (an.vertex_class[static_cast<std::size_t>(v)] != VertexClass::BranchingPoint) ++v;
        Skeleton moved = base;
        moved.points[static_cast<std::size_t>(v)] += Vec3{0.02, 0.01, 0};
        ++v;
        const std::size_t before = cache.skeleton.points.size();
        prepared = prepare_skeleton(moved);
        const RemeshStats stats = remesh_incremental(cache, prepared.skeleton, &prepared.analysis);
        RemeshCache full;
        const RemeshStats fs = remesh_full(full, prepared.skeleton, &prepared.analysis);
        EXPECT_EQ(fs.memo_surfaces, 0);
        SCOPED_TRACE(edit);
        expect_same_mesh(cache, full);
        if (prepared.skeleton.points.size() != before) {
            ++renumbered;
            EXPECT_TRUE(stats.full);
            EXPECT_EQ(stats.memo_surfaces + stats.computed_partitions, fs.computed_partitions);
            EXPECT_GT(stats.memo_surfaces, stats.computed_partitions);
        }
    }
    EXPECT_GE(renumbered, 1);
}

// Random moves (1-2 vertices of the input, up to 0.03 per axis, before adaptation; 8 per tree) on three random trees:
// every remesh equals a fresh remesh_full bit for bit, renumbering edits included, and those reuse memo surfaces.
TEST(Incremental, MemoOnRandomMovesBeforeAdaptation) {
    int renumbered = 0, checked = 0;
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
        SCOPED_TRACE(seed);
        std::mt19937 rng(seed);
        Skeleton s = bench::random_tree(400, seed + 20);
        PipelineResult prepared = prepare_skeleton(s);
        RemeshCache cache;
        remesh_full(cache, prepared.skeleton, &prepared.analysis);
        for (int edit = 0; edit < 8; ++edit) {
            Skeleton next = s;
            for (int k = 0; k <= static_cast<int>(rng() % 2); ++k)
                next.points[rng() % next.points.size()] +=
                    Vec3{0.06 * bench::unit_draw(rng) - 0.03, 0.06 * bench::unit_draw(rng) - 0.03,
                         0.06 * bench::unit_draw(rng) - 0.03};
            try {
                prepared = prepare_skeleton(next);
            } catch (const Error&) {
                continue;
            }
            const std::size_t before = cache.skeleton.points.size();
            RemeshCache full;
            try {
                remesh_full(full, prepared.skeleton, &prepared.analysis);
            } catch (const Error&) {
                EXPECT_THROW(remesh_incremental(cache, prepared.skeleton, &prepared.analysis), Error);
                continue;
            }
            const RemeshStats stats = remesh_incremental(cache, prepared.skeleton, &prepared.analysis);
            expect_same_mesh(cache, full);
            ++checked;
            if (prepared.skeleton.points.size() != before) {
                ++renumbered;
                EXPECT_GT(stats.memo_surfaces, 0);
            }
            s = next;
        }
    }
    EXPECT_GE(checked, 16);
    EXPECT_GE(renumbered, 3);  // 24 checked, 6 renumbered when written
}

// The memo is keyed on content, not on vertex numbers: the same tree with its vertices numbered in reverse (edges
// mapped, in the same order) is remeshed with every branching-point surface from the memo, nothing computed, and
// equals a fresh run bit for bit. Then other partition options: the memo is not read.
TEST(Incremental, MemoIgnoresVertexNumbers) {
    const Skeleton s = bench::random_tree(300, 7);
    RemeshCache cache;
    const RemeshStats first = remesh_full(cache, s);
    EXPECT_GT(first.computed_partitions, 0);
    const Skeleton r = reversed_numbering(s);
    const RemeshStats stats = remesh_incremental(cache, r);
    EXPECT_TRUE(stats.full);
    EXPECT_EQ(stats.computed_partitions, 0);
    EXPECT_EQ(stats.memo_surfaces, first.computed_partitions);
    RemeshCache full;
    remesh_full(full, r);
    expect_same_mesh(cache, full);
    // Other partition options: the memo (built with the old ones) is not read, everything is computed.
    cache.surface_options.relax_below_margin = 0.3;
    const RemeshStats other = remesh_incremental(cache, s);
    EXPECT_EQ(other.memo_surfaces, 0);
    EXPECT_EQ(other.computed_partitions, first.computed_partitions);
    RemeshCache full_other;
    full_other.surface_options.relax_below_margin = 0.3;
    remesh_full(full_other, s);
    expect_same_mesh(cache, full_other);
}

TEST(Incremental, MissingRadiiAreAnError) {
    Skeleton s = bench::three_branch_star(10);
    s.radii.clear();
    RemeshCache cache;
    EXPECT_THROW(remesh_full(cache, s), Error);
}

// prepare_skeleton skips the repairs and the adaptation of a skeleton without a branch edge (pipeline.cpp,
// curve_work): on every generated shape without one, before and after random moves, running the two gives the
// skeleton back unchanged, and prepare_skeleton gives the same skeleton and analysis as with them.
TEST(Incremental, BranchFreeSkeletonsAreTheirOwnAdaptation) {
    std::mt19937 rng(5);
    int shapes = 0;
    for (const std::string& name : generator_names()) {
        Skeleton s = generate_skeleton(name);
        AnalysisOptions accept_fan_ends;  // as prepare_skeleton analyses its input (fanend has a branch on one)
        accept_fan_ends.fan_end_branches = true;
        const SkeletonAnalysis an = analyze_skeleton(s, accept_fan_ends);
        if (std::find(an.edge_degree.begin(), an.edge_degree.end(), 0) != an.edge_degree.end()) continue;
        // Docked walls get their feet split (SkeletonRepairOptions::docked_foot_split; test
        // SkeletonRepair.DockedWallFeetSplitTheirPlateStrips): repaired although branch-free.
        if (an.counts.docked_edges > 0) continue;
        SCOPED_TRACE(name);
        ++shapes;
        for (int edit = 0; edit < 3; ++edit) {
            if (edit > 0)
                for (int k = 0; k < 3; ++k) {
                    const std::size_t v = rng() % s.points.size();
                    s.points[v] += Vec3{0.05 * s.radii[v], -0.03 * s.radii[v], 0.02 * s.radii[v]};
                }
            const SkeletonRepairResult repaired = repair_skeleton(s);
            EXPECT_EQ(adapt_skeleton(repaired.skeleton, {}, repaired.absorbed_balls), s);
            const PipelineResult res = prepare_skeleton(s, {});
            EXPECT_EQ(res.skeleton, s);
            EXPECT_EQ(res.analysis.vertex_class, analyze_skeleton(s).vertex_class);
            EXPECT_EQ(res.analysis.edge_degree, analyze_skeleton(s).edge_degree);
            EXPECT_EQ(res.analysis.counts, analyze_skeleton(s).counts);
        }
    }
    EXPECT_GE(shapes, 5);
}

// Renumbered in reverse (a full run that reads the memo), a star's centre is served by the memo only when its
// partition depends on its branch directions alone (the memo's key). Not so for a partition chosen by the junction's
// chunks, which read the neighbours' positions and radii: the fat Y of test_raw_mesh's
// DegreeThreePartitionChosenByItsChunks (degree_three_partition_by_chunks) and dino's hip of
// CloseDegreeFourPairGetsNoFlatPointInItsCrotch (no_flat_point_in_close_pair, a close pair); a tetrahedral star (no
// pair closer than 90 degrees) is. Every run equals a fresh one bit for bit.
namespace {

int memo_surfaces_after_reversal(const Skeleton& s, const ConnectionSurfaceOptions& options = {}) {
    RemeshCache cache;
    cache.surface_options = options;
    remesh_full(cache, s);
    const Skeleton r = reversed_numbering(s);
    const RemeshStats stats = remesh_incremental(cache, r);
    EXPECT_TRUE(stats.full);
    RemeshCache full;
    full.surface_options = options;
    remesh_full(full, r);
    expect_same_mesh(cache, full);
    return stats.memo_surfaces;
}

}  // namespace

TEST(Incremental, PartitionsReadingTheirNeighboursAreNotServedByTheMemo) {
    const double e = 10 * std::numbers::pi / 180;
    Skeleton y;
    y.points.push_back({0, 0, 0});
    for (const double az : {0.0, 100.0, 220.0}) {
        const double a = az * std::numbers::pi / 180;
        y.points.push_back(
            {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), az == 100.0 ? -std::sin(e) : std::sin(e)});
    }
    y.edges = {{0, 1}, {0, 2}, {0, 3}};
    y.radii = {0.4, 0.25, 0.25, 0.25};
    EXPECT_EQ(memo_surfaces_after_reversal(y), 0);
    // The same Y with a branching point at the end of its first arm: each of the two reads the other's partition
    // (degree_three_chunks_at_bridges; both keep the gap rule and are memo-able with it off).
    Skeleton bridged = y;
    bridged.points.push_back(y.points[1] + Vec3{0.5, 0.8, 0});
    bridged.points.push_back(y.points[1] + Vec3{0.5, -0.8, 0});
    bridged.edges.push_back({1, 4});
    bridged.edges.push_back({1, 5});
    bridged.radii = {0.4, 0.25, 0.25, 0.25, 0.2, 0.2};
    EXPECT_EQ(memo_surfaces_after_reversal(bridged), 0);
    ConnectionSurfaceOptions gap_rule;
    gap_rule.degree_three_chunks_at_bridges = false;
    EXPECT_EQ(memo_surfaces_after_reversal(bridged, gap_rule), 2);
    Skeleton hip;
    hip.points = {
        {0, 0, 0}, {0.219, 0.193, -0.035}, {0.212, -0.144, 0.149}, {-0.138, -0.305, 0.024}, {-0.002, -0.266, -0.197}};
    hip.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
    hip.radii = {0.223, 0.221, 0.112, 0.100, 0.105};
    EXPECT_EQ(memo_surfaces_after_reversal(hip), 0);
    Skeleton tetra;
    tetra.points = {{0, 0, 0}, {1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    tetra.edges = {{0, 1}, {0, 2}, {0, 3}, {0, 4}};
    tetra.radii = {0.5, 0.3, 0.3, 0.3, 0.3};
    EXPECT_EQ(memo_surfaces_after_reversal(tetra), 1);
}
