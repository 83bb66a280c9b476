// finish_mesh on the real skeleton / surface pairs of ../shared/data (label shared_data): raw mesh from run_pipeline
// (default options: resampling on, radii from the file), then pad -> subdivide -> fit -> untangle. Prints the measured
// quality per stage, the Hausdorff distance and the timings; asserts only what was measured to hold (with margins).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "mesohex/finish.h"
#include "mesohex/pipeline.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"
#include "mesohex_io/medial_io.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

using namespace mesohex;

namespace {

std::string data(const std::string& rel) { return std::string(MESOHEX_SHARED_DATA_DIR) + "/" + rel; }

struct Case {
    PipelineResult pipeline;
    double pipeline_ms = 0;
    FinishResult finish;
};

Case run_case(const std::string& label, Skeleton skeleton, const TriangleMesh& domain, const FinishOptions& options,
              const PipelineOptions& pipeline = {}) {
    Case c;
    const auto t0 = std::chrono::steady_clock::now();
    c.pipeline = run_pipeline(skeleton, pipeline);
    c.pipeline_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    c.finish = finish_mesh(c.pipeline.raw.mesh, domain, options);
    const FinishResult& f = c.finish;
    std::printf("[finish_data] %s: skeleton %zu pts -> raw %zu hexes (run_pipeline %.0f ms); domain flipped %d tris\n",
                label.c_str(), c.pipeline.skeleton.points.size(), c.pipeline.raw.mesh.hexes.size(), c.pipeline_ms,
                f.domain_flipped_triangles);
    for (const FinishStage& s : f.stages) {
        std::printf("[finish_data]   %-9s %8ld hexes %8ld verts  SJ min %+.4f avg %.4f  inverted %6ld  %8.0f ms\n",
                    s.stage.c_str(), s.hexes, s.vertices, s.sj_min, s.sj_avg, s.inverted, s.ms);
    }
    std::printf(
        "[finish_data]   fit: %d iterations, converged %d, max boundary-vertex distance %.4g; untangle ran %d"
        " (%d rounds)\n",
        f.fit_iterations, f.fit_converged ? 1 : 0, f.fit_max_distance, f.untangled ? 1 : 0, f.untangle_rounds);
    std::printf("[finish_data]   final: SJ min %+.4f avg %.4f inverted %ld valid %d\n", f.quality.sj_min,
                f.quality.sj_avg, f.quality.inverted, f.quality.validation.valid() ? 1 : 0);
    std::printf(
        "[finish_data]   Hausdorff: %.4g (%.3f %% of bbox diag %.4g); mesh->surface max %.4g, surface->mesh max"
        " %.4g; mean %.4g (%.3f %%); %.0f ms; total finish %.0f ms\n",
        f.distance.max, 100 * f.distance.relative_max, f.distance.diagonal, f.distance.mesh_to_surface_max,
        f.distance.surface_to_mesh_max, f.distance.mean, 100 * f.distance.relative_mean, f.distance_ms, f.total_ms);
    std::fflush(stdout);
    return c;
}

// The defaults of FinishOptions (1 level, 300 fit iterations, per-hex inversion guard, two-sided pull, lambda staged
// 3 -> 30, quality pass), as `mesohex mesh --surface` runs them.
FinishOptions data_options() { return FinishOptions{}; }

const FinishStage* stage_named(const FinishResult& f, const std::string& name) {
    for (const FinishStage& s : f.stages)
        if (s.stage == name) return &s;
    return nullptr;
}

void expect_hex_counts(const FinishResult& f, const PipelineResult& p) {
    ASSERT_GE(f.stages.size(), 4u);
    EXPECT_EQ(f.stages[0].hexes, static_cast<long>(p.raw.mesh.hexes.size()));
    // "pad-improve" (between pad and subdivide) runs only on near-flat padding hexes: stages are looked up by name.
    const FinishStage* padded = stage_named(f, "pad");
    const FinishStage* subdivided = stage_named(f, "subdivide");
    ASSERT_NE(padded, nullptr);
    ASSERT_NE(subdivided, nullptr);
    EXPECT_GT(padded->hexes, f.stages[0].hexes);  // one layer per boundary quad
    long factor = 1;
    for (int i = 0; i < f.subdivision_levels; ++i) factor *= 8;
    EXPECT_EQ(subdivided->hexes, factor * padded->hexes);
    EXPECT_EQ(static_cast<long>(f.mesh.hexes.size()), subdivided->hexes);
}

// Issue 5's targets: valid, no inverted hex, min SJ >= 0.3, avg >= min_avg, Hausdorff <= 1 % of the diagonal.
void expect_targets(const FinishResult& f, double min_avg = 0.85) {
    EXPECT_TRUE(f.quality.validation.valid());
    EXPECT_EQ(f.quality.inverted, 0);
    EXPECT_GE(f.quality.sj_min, 0.3);
    EXPECT_GE(f.quality.sj_avg, min_avg);
    EXPECT_LE(f.distance.relative_max, 0.01);
}

}  // namespace

// Measured: raw 116 hexes -> 2912; final min SJ 0.676, avg 0.930, 0 inverted; Hausdorff 0.52 % of the diagonal
// (0.647 / 0.931 / 0.63 % with the padding layer from the mean boundary edge; raw 104 hexes -> 2624 and
// 0.660 / 0.927 / 0.57 % with AdaptationOptions::free_branching_reach 1; raw 92 hexes -> 2336 and 0.538 / 0.917 /
// 0.65 % while a bridge of 0.8 (r_a + r_b) still collapsed; before the smoothing pass: 0.354 / 0.902 / 0.54 %;
// smoothing without its max-min pass: 0.438 / 0.917 / 0.54 %).
// Issue 5 targets: min SJ >= 0.3, avg >= 0.85, Hausdorff <= 1 %.
TEST(FinishData, Cactus) {
    const Skeleton s = read_skeleton(data("curve-skeletons/cactus.skel"));
    const TriangleMesh domain = read_surface(data("surfaces/cactus.obj"));
    const Case c = run_case("cactus (file radii, 1 level)", s, domain, data_options());
    const FinishResult& f = c.finish;
    expect_hex_counts(f, c.pipeline);
    EXPECT_EQ(f.domain_flipped_triangles, 0);
    expect_targets(f);
}

// The shared medial meshes imported (mesohex import) and finished in their own surfaces: real pairs with leaflets.
// Measured 2026-12-02 (raw hexes / inverted -> finished: min / avg SJ, Hausdorff):
//   cup:       1768 / 0 -> 0.714 / 0.974, 0.38 %  (its handle rooted inside the sheet, 3 strips split around its
//              root by SkeletonRepairOptions::root_patch_factor; without: 1488 / 0 -> 0.690 / 0.971, 0.39 %; with
//              the handle's ends moved to the rim, the former import: 12 raw inverted hexes, 0.050 / 0.961, 7.0 %:
//              the handle ran along the wall outside the domain);
//   hand:      314 / 1 -> 0.580 / 0.928, 0.86 %   (fingers rooted on the palm's border: out patches turned towards
//              the branch; with BL-joint pillows on corners pushed out by the import: 12 raw inverted, 0.094 / 0.901,
//              2.45 %);
//   airplane1: 446 / 0 -> 0.626 / 0.950, 0.48 %   (nose and tail rooted on out / side patches: 14 raw inverted,
//              0.054 / 0.908, 3.17 % with pillows);
//   wrench 0.680 / 0.954, 0.21 % (unchanged).
// dtorus needs the mesh command's second attempt (0.195 / 0.924, 1.41 % at the first: MedialData.FinishedMeshesMeet-
// TheRealPairTargets checks the command). Issue 5 targets for real pairs: no inverted hex, min SJ >= 0.3,
// avg >= 0.85, Hausdorff <= 1 %.
TEST(FinishData, ImportedMedialMeshesMeetTheRealPairTargets) {
    for (const char* name : {"cup", "hand", "airplane1", "wrench"}) {
        SCOPED_TRACE(name);
        const Skeleton s =
            import_medial_mesh(read_medial_mesh(data(std::string("medial-meshes/") + name + ".ma"))).skeleton;
        const TriangleMesh domain = read_surface(data(std::string("surfaces/") + name + ".off"));
        const Case c = run_case(std::string(name) + " (imported medial mesh, 1 level)", s, domain, data_options());
        const FinishResult& f = c.finish;
        expect_hex_counts(f, c.pipeline);
        expect_targets(f);
    }
}

// Same with 2 levels. Measured: 23296 hexes, min SJ 0.601, avg 0.974, 0 inverted, Hausdorff 0.49 %, ~4 s (0.754 /
// 0.978 / 0.56 % with the padding layer from the mean boundary edge; before
// the smoothing pass the min SJ target was missed: 0.215; without its max-min pass: 0.472 / 0.974 / 0.56 %).
TEST(FinishData, CactusTwoLevels) {
    const Skeleton s = read_skeleton(data("curve-skeletons/cactus.skel"));
    const TriangleMesh domain = read_surface(data("surfaces/cactus.obj"));
    FinishOptions o = data_options();
    o.levels = 2;
    const Case c = run_case("cactus (file radii, 2 levels)", s, domain, o);
    const FinishResult& f = c.finish;
    expect_hex_counts(f, c.pipeline);
    expect_targets(f, 0.9);
}

// Radii 0.5 x distance to the surface (the reference's choice: room for the padding layer). Measured: raw 260 hexes
// -> 6368; min SJ 0.601, avg 0.939, Hausdorff 0.54 % (0.591 / 0.939 / 1.13 % with the layer from the shortest edge
// alone, FinishOptions::pad_to_domain 0; 0.88 % from the mean edge; raw 240 -> 5888, 0.611 / 0.939 / 0.59 % with
// free_branching_reach 1; before the smoothing pass: 0.264 / 0.921 / 0.44 %; without its
// max-min pass: 0.591 / 0.939 / 0.55 %).
TEST(FinishData, CactusRadiusFromSurface) {
    Skeleton s = read_skeleton(data("curve-skeletons/cactus.skel"));
    const TriangleMesh domain = read_surface(data("surfaces/cactus.obj"));
    const RadiusFromSurface r = radius_from_surface(s, SurfaceQuery(domain));  // factor 0.5
    ASSERT_TRUE(r.zero_radius_vertices.empty());
    s.radii = r.radii;
    // The paper's layout: with these radii one branching point gets a compatible block (raw 260 -> 268 hexes) and the
    // result misses the Hausdorff target: measured 6528 hexes, 0.546 / 0.939, Hausdorff 1.27 % (docs/blocks.md).
    PipelineOptions no_blocks;
    no_blocks.connection_surfaces.blocks.enabled = false;
    const Case c = run_case("cactus (0.5 x distance radii, 1 level)", s, domain, data_options(), no_blocks);
    const FinishResult& f = c.finish;
    expect_hex_counts(f, c.pipeline);
    EXPECT_TRUE(f.quality.validation.valid());
    EXPECT_EQ(f.quality.inverted, 0);
    EXPECT_GE(f.quality.sj_min, 0.4);
    EXPECT_GE(f.quality.sj_avg, 0.9);
    EXPECT_LE(f.distance.relative_max, 0.01);
}

// Measured: raw 64 hexes -> 1632; min SJ 0.600, avg 0.920, 0 inverted; Hausdorff 0.58 % (0.61 % with the padding
// layer from the mean edge; raw 52 -> 1344, 0.601 / 0.912 / 0.64 % with free_branching_reach 1; padding min SJ 0.052,
// 0.217 after the pad-improve pass; with
// reach 1, without that pass: 0.578 / 0.910 / 0.67 %; without the smoothing's max-min pass: 0.585 / 0.911 / 0.64 %).
// Issue 5 targets met. Since its trunk joint is pinned (SkeletonRepairOptions::pin_trunk_joints, 2026-12-03): raw 68
// hexes -> 1728, min SJ 0.601, avg 0.921, Hausdorff 0.57 %.
TEST(FinishData, Aorta) {
    const Skeleton s = read_skeleton(data("curve-skeletons/aorta.skel"));
    const TriangleMesh domain = read_surface(data("surfaces/aorta.stl"));
    const Case c = run_case("aorta (file radii, 1 level)", s, domain, data_options());
    const FinishResult& f = c.finish;
    expect_hex_counts(f, c.pipeline);
    EXPECT_EQ(f.domain_flipped_triangles, static_cast<int>(domain.triangles.size()));  // aorta.stl faces inward
    expect_targets(f);
}
