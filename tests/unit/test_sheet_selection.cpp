// Directional refinement along branches: which sheets are split, with counts derived on paper for a straight tube.
#include <gtest/gtest.h>

#include "mesohex/core/topology.h"
#include "mesohex/core/validate.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/padding.h"
#include "mesohex/post/quality.h"
#include "mesohex/post/sheet_selection.h"
#include "mesohex/post/subdivision.h"

using namespace mesohex;

namespace {

// A straight branch of 3 unit edges along x, radius 0.25, meshed with its own sampling: 3 chunks of 4 hexes.
RawMesh straight_tube() {
    Skeleton s;
    for (int i = 0; i < 4; ++i) s.points.push_back({double(i), 0, 0});
    s.radii.assign(4, 0.25);
    s.edges = {{0, 1}, {1, 2}, {2, 3}};
    PipelineOptions o;
    o.resample = false;
    return run_pipeline(s, o).raw;
}

std::vector<char> chunk_hexes(const RawMesh& raw) {
    std::vector<char> chunk(raw.hex_edge.size());
    for (std::size_t h = 0; h < chunk.size(); ++h) chunk[h] = raw.hex_edge[h] >= 0;
    return chunk;
}

SubdivisionResult refine(const HexMesh& mesh, const std::vector<char>& chunk, SheetDirection d) {
    const HexTopology topo = compute_hex_topology(mesh);
    return subdivide_sheets(mesh, select_branch_sheets(mesh, topo, chunk, d));
}

}  // namespace

TEST(SheetSelection, LongitudinalEdgesRunAlongTheBranch) {
    const RawMesh raw = straight_tube();
    ASSERT_EQ(raw.mesh.hexes.size(), 12u);
    const HexTopology topo = compute_hex_topology(raw.mesh);
    const std::vector<bool> sel = select_branch_sheets(raw.mesh, topo, chunk_hexes(raw), SheetDirection::Longitudinal);
    int count = 0;
    for (std::size_t e = 0; e < sel.size(); ++e) {
        if (!sel[e]) continue;
        ++count;
        const Vec3 d = raw.mesh.points[topo.edges[e][1]] - raw.mesh.points[topo.edges[e][0]];
        EXPECT_NEAR(std::abs(d.x), norm(d), 1e-9) << "edge " << e << " is not parallel to the branch";
    }
    // Per segment: the axis C-C' and the 8 sphere points joined to their copies at the next section.
    EXPECT_EQ(count, 3 * 9);
}

// Longitudinal: each of the 3 segment sheets is split in two: 6 segments x 4 hexes. Radial: the cross-section sheet
// of the tube holds every chunk hex twice (two directions per hex), each hex becomes 4: 48. Both: 8 per hex, 96.
TEST(SheetSelection, StraightTubeCountsDerivedOnPaper) {
    const RawMesh raw = straight_tube();
    const std::vector<char> chunk = chunk_hexes(raw);
    const SubdivisionResult lon = refine(raw.mesh, chunk, SheetDirection::Longitudinal);
    const SubdivisionResult rad = refine(raw.mesh, chunk, SheetDirection::Radial);
    EXPECT_EQ(lon.mesh.hexes.size(), 24u);
    EXPECT_EQ(rad.mesh.hexes.size(), 48u);
    std::vector<char> chunk_lon(lon.mesh.hexes.size(), 1);
    EXPECT_EQ(refine(lon.mesh, chunk_lon, SheetDirection::Radial).mesh.hexes.size(), 96u);
    for (const HexMesh* m : {&lon.mesh, &rad.mesh}) {
        const QualityReport q = compute_quality(*m);
        EXPECT_TRUE(q.validation.valid());
        EXPECT_EQ(q.euler_characteristic, 1);
        EXPECT_EQ(q.inverted, 0);
    }
}

// After padding (12 + 32 boundary quads = 44 hexes: 8 side faces per segment and 4 kites per end cap), a segment's
// longitudinal sheet holds its 4 chunk hexes and its 8 side padding hexes; the cap padding hexes are not in it.
// Splitting the 3 sheets adds 3 x 12 hexes: 80.
TEST(SheetSelection, LongitudinalSheetsRunThroughThePaddingLayer) {
    const RawMesh raw = straight_tube();
    const PaddingResult padded = pad(raw.mesh);
    ASSERT_EQ(padded.mesh.hexes.size(), 44u);
    const SubdivisionResult lon = refine(padded.mesh, chunk_hexes(raw), SheetDirection::Longitudinal);
    EXPECT_EQ(lon.mesh.hexes.size(), 80u);
    EXPECT_TRUE(validate(lon.mesh).valid());
}
