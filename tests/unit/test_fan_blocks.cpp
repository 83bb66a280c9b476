// Fan blocks (issue 22 item 3, second half; ../shared/design/beyond-the-paper.md D2): the 2D acceptance by measured
// angles, and raw meshes of T and X fans with and without blocks: exact hex / vertex / irregular-edge counts derived by
// hand, validity, Euler characteristic, no inverted hex, fewer interior irregular edges than the paper's layout; Y
// fans and wider stars never get a block.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/core/validate.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/fan_blocks.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/raw_mesh.h"
#include "raw_run.h"
#include "skeleton_fixtures.h"

using namespace mesohex;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180;

using test::RawRun;
using test::total;

RawRun mesh_raw(const Skeleton& s, bool blocks) {
    ConnectionSurfaceOptions o;
    o.blocks.enabled = blocks;
    o.blocks.fan_blocks = true;
    return test::checked_raw_mesh(s, o);
}

using test::apply;
using test::random_rotation;

// Strips of m x 1 quads (edge 1, radius 0.3) on a fan line of n edges along z, strip k leaving at angle angles[k] about
// z (plus twist[j] at line vertex j when given); the whole skeleton rotated by f.
Skeleton fan(const std::vector<double>& angles, int n, int m, const std::array<Vec3, 3>& f,
             const std::vector<double>& twist = {}) {
    Skeleton s;
    auto add = [&](const Vec3& p) {
        s.points.push_back(apply(f, p));
        s.radii.push_back(0.3);
        return static_cast<int>(s.points.size()) - 1;
    };
    std::vector<int> line;
    for (int j = 0; j <= n; ++j) line.push_back(add({0, 0, static_cast<double>(j)}));
    for (int j = 0; j < n; ++j) s.edges.push_back({line[j], line[j + 1]});
    for (const double a : angles) {
        std::vector<std::vector<int>> id(m + 1, std::vector<int>(n + 1));
        for (int j = 0; j <= n; ++j) id[0][j] = line[j];
        for (int i = 1; i <= m; ++i)
            for (int j = 0; j <= n; ++j) {
                const double b = a + (twist.empty() ? 0.0 : twist[j]);
                id[i][j] = add({i * std::cos(b), i * std::sin(b), static_cast<double>(j)});
            }
        for (int i = 1; i <= m; ++i)
            for (int j = 0; j <= n; ++j) {
                s.edges.push_back({id[i - 1][j], id[i][j]});
                if (j < n) s.edges.push_back({id[i][j], id[i][j + 1]});
            }
        for (int i = 0; i < m; ++i)
            for (int j = 0; j < n; ++j) s.faces.push_back({id[i][j], id[i + 1][j], id[i + 1][j + 1], id[i][j + 1]});
    }
    return s;
}

const std::array<Vec3, 3> kIdentity{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};

long chains_found(const Skeleton& s) {
    const SkeletonAnalysis an = analyze_skeleton(s);
    CompatibleBlockOptions o;
    o.fan_blocks = true;
    return static_cast<long>(find_fan_blocks(s, an, o).chains.size());
}

}  // namespace

TEST(FanBlocks, SquareFitAcceptsTAndXRejectsY) {
    const Vec3 t{0, 0, 1};
    CompatibleBlockOptions o;
    auto dirs = [](const std::vector<double>& angles, double turn) {
        std::vector<Vec3> d;
        for (const double a : angles) d.push_back({std::cos(a + turn), std::sin(a + turn), 0.3});  // off-plane: ignored
        return d;
    };
    const SquareFit T = fit_square_frame(t, dirs({0, 0.5 * kPi, kPi}, 0.4), {}, o);
    ASSERT_TRUE(T.accepted);
    EXPECT_NEAR(T.max_axis_angle, 0, 1e-9);
    EXPECT_NEAR(T.max_pair_error, 0, 1e-9);
    EXPECT_EQ((T.labels[2] - T.labels[0]) & 3, 2);  // the straight plate: opposite axes
    EXPECT_TRUE(fit_square_frame(t, dirs({0, 0.5 * kPi, kPi, 1.5 * kPi}, 1.0), {}, o).accepted);
    EXPECT_FALSE(fit_square_frame(t, dirs({0, 2 * kPi / 3, 4 * kPi / 3}, 0.2), {}, o).accepted);     // Y
    EXPECT_FALSE(fit_square_frame(t, dirs({0, 0.25 * kPi, kPi + 0.125 * kPi}, 0), {}, o).accepted);  // vfan 45
    // The seed decides the labels' rotation: seeded with -u, the T's first strip gets axis 2.
    const SquareFit seeded = fit_square_frame(t, dirs({0, 0.5 * kPi, kPi}, 0), {-1, 0, 0}, o);
    ASSERT_TRUE(seeded.accepted);
    EXPECT_EQ(seeded.labels[0], 2);
    EXPECT_FALSE(fit_square_frame(t, {Vec3{0, 0, 1}, Vec3{1, 0, 0}}, {}, o).accepted);  // along t: rejected
    // Jitter: every direction within 10 degrees of a T / X is accepted; a Y with 15 degrees per direction never is
    // (3 distinct labels contain an opposite pair, which needs >= 155 degrees; the Y's pairs are <= 150).
    std::mt19937 rng(22);
    std::uniform_real_distribution<double> u(-1, 1), turn(0, 2 * kPi);
    auto jittered = [&](const std::vector<double>& angles, double max) {
        std::vector<double> a;
        for (const double x : angles) a.push_back(x + max * u(rng));
        return dirs(a, turn(rng));
    };
    for (int trial = 0; trial < 1000; ++trial) {
        EXPECT_TRUE(fit_square_frame(t, jittered({0, 0.5 * kPi, kPi}, 10 * kDeg), {}, o).accepted);
        EXPECT_TRUE(fit_square_frame(t, jittered({0, 0.5 * kPi, kPi, 1.5 * kPi}, 10 * kDeg), {}, o).accepted);
        EXPECT_FALSE(fit_square_frame(t, jittered({0, 2 * kPi / 3, 4 * kPi / 3}, 15 * kDeg), {}, o).accepted);
    }
}

// T (g = 3) and X (g = 4) fans of strips of m x n quads on a fan line of n edges, by hand:
//   faces g n m, border edges g (n + 2 m): hexes 2 g n m + 2 g (n + 2 m) (paper), + 4 n + 4 x 2 caps (block);
//   leaflet vertices per strip (n + 1) m, (n - 1)(m - 1) of them inside (3 ids), the others on the border (6 ids);
//   fan line: paper 1 + g ids inside, 2 + 2 g at the ends; block 9 inside, 18 at the ends;
//   interior irregular: the strips' 2 outer corners have 2 valence-3 edges each (both layouts); the paper's fan edges
//   and end extension edges valence 2 g (n + 2 of them), the block none;
//   boundary valence 1: 2 per border edge; the block adds per row (n fan edges + 2 caps) a valence-3 crease between
//   two labelled axes (T: 2, X: 4) and, for the T's free axis, 2 valence-1 rim edges on each cap.
TEST(FanBlocks, TAndXFansWithAndWithoutBlocksByHand) {
    for (const int g : {3, 4})
        for (const auto& [n, m] : {std::pair{2, 2}, std::pair{3, 1}, std::pair{1, 2}}) {
            SCOPED_TRACE(testing::Message() << "g " << g << " n " << n << " m " << m);
            const std::vector<double> angles =
                g == 3 ? std::vector<double>{0, 0.5 * kPi, kPi} : std::vector<double>{0, 0.5 * kPi, kPi, 1.5 * kPi};
            const Skeleton s = fan(angles, n, m, kIdentity);
            const RawRun paper = mesh_raw(s, false), block = mesh_raw(s, true);
            EXPECT_EQ(paper.fan_chains, 0);
            EXPECT_EQ(block.fan_chains, 1);
            EXPECT_EQ(block.predicted.compatible_blocks, n);
            EXPECT_EQ(block.predicted.fan_blocks, n);
            EXPECT_EQ(block.predicted.fan_block_caps, 2);
            const long hexes = 2L * g * n * m + 2L * g * (n + 2 * m);
            EXPECT_EQ(paper.quality.hexes, hexes);
            EXPECT_EQ(block.quality.hexes, hexes + 4L * n + 8);
            const long inside = (n - 1L) * (m - 1L), leaflet = g * (3 * inside + 6 * ((n + 1L) * m - inside));
            EXPECT_EQ(paper.quality.vertices, leaflet + (n - 1L) * (1 + g) + 2 * (2 + 2 * g));
            EXPECT_EQ(block.quality.vertices, leaflet + 9 * (n - 1L) + 36);
            EXPECT_EQ(paper.quality.singular_interior_edges, (std::map<int, long>{{3, 4L * g}, {2 * g, n + 2L}}));
            EXPECT_EQ(block.quality.singular_interior_edges, (std::map<int, long>{{3, 4L * g}}));
            EXPECT_LT(total(block.quality.singular_interior_edges), total(paper.quality.singular_interior_edges));
            const long border = 2L * g * (n + 2 * m);
            EXPECT_EQ(paper.quality.singular_boundary_edges, (std::map<int, long>{{1, border}}));
            EXPECT_EQ(block.quality.singular_boundary_edges,
                      g == 3 ? (std::map<int, long>{{1, border + 4}, {3, 2 * (n + 2L)}})
                             : (std::map<int, long>{{1, border}, {3, 4 * (n + 2L)}}));
            for (const RawRun* r : {&paper, &block}) {
                EXPECT_TRUE(r->valid);
                EXPECT_EQ(r->quality.euler_characteristic, 1);
                EXPECT_EQ(r->quality.inverted, 0);
            }
            // Every block hex is a cuboid; the worst raw hex is then a strip's outer corner half-chunk, whose out
            // column leaves along the corner's diagonal: sin 45 degrees (tolerance 1e-6).
            EXPECT_NEAR(block.quality.sj_min, std::sqrt(0.5), 1e-6);
            EXPECT_GT(block.quality.sj_avg, paper.quality.sj_avg);
        }
}

TEST(FanBlocks, RotatedJitteredTAndXAcceptedYAndStarsNever) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    auto jittered = [&](const std::vector<double>& angles, double max) {
        std::vector<double> a;
        for (const double x : angles) a.push_back(x + max * u(rng));
        return a;
    };
    for (int trial = 0; trial < 100; ++trial) {
        const std::array<Vec3, 3> f = random_rotation(rng);
        EXPECT_EQ(chains_found(fan(jittered({0, 0.5 * kPi, kPi}, 10 * kDeg), 2, 1, f)), 1);
        EXPECT_EQ(chains_found(fan(jittered({0, 0.5 * kPi, kPi, 1.5 * kPi}, 10 * kDeg), 2, 1, f)), 1);
        EXPECT_EQ(chains_found(fan(jittered({0, 2 * kPi / 3, 4 * kPi / 3}, 15 * kDeg), 2, 1, f)), 0);  // Y
        EXPECT_EQ(chains_found(fan(jittered({0, 0.4 * kPi, 0.8 * kPi, 1.2 * kPi, 1.6 * kPi}, 5 * kDeg), 2, 1, f)), 0);
        EXPECT_EQ(
            chains_found(fan(jittered({0, kPi / 3, 2 * kPi / 3, kPi, 4 * kPi / 3, 5 * kPi / 3}, 5 * kDeg), 2, 1, f)),
            0);
        // An X squashed to 60 / 120 degrees between neighbours.
        EXPECT_EQ(chains_found(fan(jittered({0, kPi / 3, kPi, 4 * kPi / 3}, 5 * kDeg), 2, 1, f)), 0);
    }
    // The generated Y-star, tetrahedral star and the 45-degree vfan: no fan block.
    for (const char* name : {"ystar", "tetrastar", "vfan"}) EXPECT_EQ(chains_found(generate_skeleton(name)), 0) << name;
}

// A closed degree-4 fan line (torustwist): accepted when the X comes back to itself with the same labels (0 or 4
// quarter turns: every leaflet keeps its axis), refused at 1, 2, 3 quarter turns (the labels arrive rotated). The
// closed chain has n fan edges and no cap: 4 n hexes more, no valence-8 interior edge.
TEST(FanBlocks, ClosedChainsKeepTheirLabels) {
    for (const int q : {0, 1, 2, 3, 4}) {
        SCOPED_TRACE(q);
        GeneratorOptions o;
        o.quarter_turns = q;
        o.n = 16;
        const Skeleton s = generate_skeleton("torustwist", o);
        const bool accepted = q % 4 == 0;
        EXPECT_EQ(chains_found(s), accepted ? 1 : 0);
        if (!accepted) continue;
        const RawRun paper = mesh_raw(s, false), block = mesh_raw(s, true);
        EXPECT_EQ(block.predicted.fan_block_caps, 0);
        EXPECT_EQ(block.quality.hexes, paper.quality.hexes + 4 * 16);
        EXPECT_EQ(paper.quality.singular_interior_edges.at(8), 16);
        EXPECT_EQ(block.quality.singular_interior_edges.count(8), 0u);
        EXPECT_TRUE(block.valid);
        EXPECT_EQ(block.quality.euler_characteristic, paper.quality.euler_characteristic);
        EXPECT_EQ(block.quality.inverted, 0);
    }
}

// Chain conditions: a fan line whose T turns by 90 degrees from one fan edge to the next (each fan edge alone an exact
// T, but every leaflet changes its axis) gets no block; the same T turning by 20 degrees does.
TEST(FanBlocks, ConditionsAlongTheChain) {
    // Strip vertices at angle a, a + 45, a + 135 degrees (j = 0, 1, 2): face directions a + 22.5 and a + 90.
    EXPECT_EQ(chains_found(fan({0, 0.5 * kPi, kPi}, 2, 1, kIdentity, {0, 0.25 * kPi, 0.75 * kPi})), 0);
    EXPECT_EQ(chains_found(fan({0, 0.5 * kPi, kPi}, 2, 1, kIdentity, {0, 10 * kDeg, 30 * kDeg})), 1);
    EXPECT_EQ(chains_found(fan({0, 0.5 * kPi, kPi}, 2, 1, kIdentity)), 1);
    // --no-blocks: nothing.
    const Skeleton t = fan({0, 0.5 * kPi, kPi}, 2, 1, kIdentity);
    CompatibleBlockOptions off;
    off.fan_blocks = true;
    off.enabled = false;
    EXPECT_TRUE(find_fan_blocks(t, analyze_skeleton(t), off).chains.empty());
    // The default: on where accepted (test_fan_layouts: with a domain, the better finished layout is kept);
    // fan_blocks = false (`--no-fan-blocks`): nothing.
    EXPECT_EQ(find_fan_blocks(t, analyze_skeleton(t), CompatibleBlockOptions{}).chains.size(), 1u);
    CompatibleBlockOptions no_fan;
    no_fan.fan_blocks = false;
    EXPECT_TRUE(find_fan_blocks(t, analyze_skeleton(t), no_fan).chains.empty());
}

namespace {

// The fan of `fan` with a branch of 3 unit edges (radius 0.3) from chain end `from` (the line vertex at z = 0 or z =
// n) along `dir` (unit).
void add_branch(Skeleton& s, int from, const Vec3& dir) {
    for (int k = 1; k <= 3; ++k) {
        s.points.push_back(s.points[from] + static_cast<double>(k) * dir);
        s.radii.push_back(0.3);
        s.edges.push_back(
            {k == 1 ? from : static_cast<int>(s.points.size()) - 2, static_cast<int>(s.points.size()) - 1});
    }
}

// The raw stages with branches on fan-block caps accepted (AnalysisOptions / CompatibleBlockOptions::
// fan_cap_branches), checked against the prediction (test::checked_raw_mesh).
RawRun mesh_raw_with_caps(const Skeleton& s) {
    AnalysisOptions ao;
    ao.fan_cap_branches = true;
    ConnectionSurfaceOptions o;
    o.blocks.fan_cap_branches = true;
    return test::checked_raw_mesh(s, o, ao);
}

}  // namespace

// Design note C1: a branch of 3 unit edges on the T / X fan of 2 x 2 strips (n = 2 fan edges, m = 2) continuing the
// fan line, at its top end (z = 2, the chain's last vertex: cap axes in the block's order), its bottom end (z = 0, the
// first: reversed order) or both. By hand, from the block's counts (TAndXFansWithAndWithoutBlocksByHand: T 76 hexes,
// 144 vertices, boundary {1: 40, 3: 8}; X 96, 177, {1: 48, 3: 16}): per branch 12 hexes (3 chunks; no hex of its own
// at the cap, the branch shortened by h) and 27 vertices (2 joints and the extremity, 9 each; the fan end keeps its 18
// section ids); boundary: the branch's 12 longitudinal edges and the extremity's 8 rim edges of valence 1, and the
// cap's 8 rim edges get the first chunk's hex: at a labelled axis 2 -> 3 (T 6, X 8), at the T's free axis 1 -> 2 (2
// fewer of valence 1); interior irregular edges unchanged ({3: 4 g}, the strips' outer corners). The T with one branch:
// the design note's 88 hexes. The worst raw hex is the first chunk's, at the round section's edge point M (first joint
// at z = 3 (1 from the end), the cap section h = 0.3 beyond the end: the chunk 0.7 long): its two section edges meet at
// 135 degrees (M at 0.3 on the circle between Q = (0.3, 0) and (0, 0.3)), the edge down to the cap's corner (0.3, 0.3)
// goes a = 0.3 (1 - 1 / sqrt 2) along each axis and 0.7 along the branch: SJ = sin 135 x 0.7 / sqrt(2 a^2 + 0.49)
// = 0.69622 (below the strips' corners' sin 45 degrees; tolerance 1e-6).
TEST(FanBlocks, BranchOnTheCapByHand) {
    for (const int g : {3, 4})
        for (const int ends : {1, 2, 3}) {  // 1: top, 2: bottom, 3: both
            SCOPED_TRACE(testing::Message() << "g " << g << " ends " << ends);
            const std::vector<double> angles =
                g == 3 ? std::vector<double>{0, 0.5 * kPi, kPi} : std::vector<double>{0, 0.5 * kPi, kPi, 1.5 * kPi};
            Skeleton s = fan(angles, 2, 2, kIdentity);
            if (ends & 1) add_branch(s, 2, {0, 0, 1});
            if (ends & 2) add_branch(s, 0, {0, 0, -1});
            const long branches = ends == 3 ? 2 : 1;
            const RawRun r = mesh_raw_with_caps(s);
            EXPECT_EQ(r.fan_chains, 1);
            EXPECT_EQ(r.predicted.fan_block_caps, 2);
            EXPECT_EQ(r.quality.hexes, (g == 3 ? 76 : 96) + 12 * branches);
            if (g == 3 && ends == 1) {
                EXPECT_EQ(r.quality.hexes, 88);
            }
            EXPECT_EQ(r.quality.vertices, (g == 3 ? 144 : 177) + 27 * branches);
            EXPECT_EQ(r.quality.singular_interior_edges, (std::map<int, long>{{3, 4L * g}}));
            EXPECT_EQ(r.quality.singular_boundary_edges,
                      g == 3 ? (std::map<int, long>{{1, 40 + 18 * branches}, {3, 8 + 6 * branches}})
                             : (std::map<int, long>{{1, 48 + 20 * branches}, {3, 16 + 8 * branches}}));
            EXPECT_TRUE(r.valid);
            EXPECT_EQ(r.quality.euler_characteristic, 1);
            EXPECT_EQ(r.quality.inverted, 0);
            const double a = 0.3 * (1 - std::sqrt(0.5));
            EXPECT_NEAR(r.quality.sj_min, std::sqrt(0.5) * 0.7 / std::sqrt(2 * a * a + 0.49), 1e-6);
        }
}

// The side section and the notch (CompatibleBlockOptions::fan_side_branches, on by default): a branch of 3 unit edges
// from the top end w = (0, 0, 2) of the T / X fan of 2 x 2 strips (n = 2 fan edges, m = 2, radius 0.3) across the fan
// line: the T's along -y (its free axis), the X's along (1, 1, 0) / sqrt 2 (between the +x and +y leaflets). Counts by
// hand from the block's (T 76 hexes, 144 vertices, boundary {1: 40, 3: 8}, interior {3: 12}; X 96, 177, {1: 48, 3:
// 16}, {3: 16}): per branch 12 hexes and 27 vertices as on the cap (no hex of its own at the root, the fan end keeps
// its 18 section ids); the branch's 12 longitudinal edges and its extremity's 8 rim edges of valence 1 (+20). T, side
// section s = -y: the patch M_2 Q_3 M_3 over the fan edge (1, 2) and the cap; its 4 rim edges through M_2 and M_3
// (block hex + the +x or -x plate, 2) and its 2 rim edges at z = 1 (the chunks below and above, 2) get the first
// chunk's hex: 6 of valence 3; its 2 rim edges on the cap's end face (1, the cap's hex) 2: {1: 40 + 20 - 2, 3: 8 + 6},
// interior unchanged (the patch's 4 inner edges 2 + 2 = 4). X, notch M_j between +x and +y: the 2 fold edges on M_j's
// column (block hex + 2 plates or half-chunks, boundary 3) get 2 chunk hexes each: interior valence 5; the 6 rim edges
// on the plates' and half-chunks' sides 2 -> 3, the 2 on the half-chunks' outer edges 1 -> 2: {1: 48 + 20 - 2, 3: 16 -
// 2 + 6}, interior {3: 16, 5: 2}. The sections at the X's notch
// end and its chain neighbour keep h = min(0.3, 0.8 x 1) = 0.3.
TEST(FanBlocks, BranchOnTheSideSectionAndInTheNotchByHand) {
    for (const int g : {3, 4}) {
        SCOPED_TRACE(g);
        const std::vector<double> angles =
            g == 3 ? std::vector<double>{0, 0.5 * kPi, kPi} : std::vector<double>{0, 0.5 * kPi, kPi, 1.5 * kPi};
        Skeleton s = fan(angles, 2, 2, kIdentity);
        add_branch(s, 2, g == 3 ? Vec3{0, -1, 0} : Vec3{2.5 * std::sqrt(0.5), 2.5 * std::sqrt(0.5), 0});
        s.radii.assign(s.points.size(), 0.75);
        AnalysisOptions ao;
        ao.fan_cap_branches = true;
        CompatibleBlockOptions on;
        const FanBlocks fb = find_fan_blocks(s, analyze_skeleton(s, ao), on);
        ASSERT_EQ(fb.chains.size(), 1u);
        EXPECT_EQ(fb.chains[0].side_axis[1] >= 0, g == 3);
        EXPECT_EQ(fb.chains[0].notch[1] >= 0, g == 4);
        on.fan_side_branches = false;
        EXPECT_TRUE(find_fan_blocks(s, analyze_skeleton(s, ao), on).chains.empty());
        const RawRun r = mesh_raw_with_caps(s);
        EXPECT_EQ(r.fan_chains, 1);
        EXPECT_EQ(r.quality.hexes, g == 3 ? 88 : 108);
        EXPECT_EQ(r.quality.vertices, g == 3 ? 171 : 204);
        EXPECT_EQ(r.quality.singular_interior_edges,
                  g == 3 ? (std::map<int, long>{{3, 12}}) : (std::map<int, long>{{3, 16}, {5, 2}}));
        EXPECT_EQ(r.quality.singular_boundary_edges,
                  g == 3 ? (std::map<int, long>{{1, 58}, {3, 14}}) : (std::map<int, long>{{1, 66}, {3, 20}}));
        EXPECT_TRUE(r.valid);
        EXPECT_EQ(r.quality.euler_characteristic, 1);
        EXPECT_EQ(r.quality.inverted, 0);
        EXPECT_GT(r.quality.sj_min, 0.2);
    }
}

// The cap takes a branch within 35 degrees of the fan line's continuation (kFanCapBranchCos: the pipeline's decision
// on the input) or, in the connection surfaces, 45 (kFanCapKeepCos, after the resampling): 30 degrees off it (towards
// +x) both, 40 only the second, 50 neither (the connection surfaces refuse the vertex, naming it; the pipeline retracts
// it instead, fan_end_repair.h); nor a Y fan's (no block), nor without the option.
TEST(FanBlocks, BranchOnTheCapOnlyNearTheFanLine) {
    const std::vector<double> t{0, 0.5 * kPi, kPi};
    for (const double deg : {0.0, 30.0, 40.0, 50.0}) {
        SCOPED_TRACE(deg);
        Skeleton s = fan(t, 2, 2, kIdentity);
        add_branch(s, 2, {std::sin(deg * kDeg), 0, std::cos(deg * kDeg)});
        AnalysisOptions ao;
        ao.fan_cap_branches = true;
        const SkeletonAnalysis an = analyze_skeleton(s, ao);
        CompatibleBlockOptions on;
        on.fan_cap_branches = true;
        EXPECT_EQ(fan_cap_roots(find_fan_blocks(s, an, on)), deg < 35 ? std::vector<int>{2} : std::vector<int>{});
        EXPECT_EQ(fan_cap_roots(find_fan_blocks(s, an, on, kFanCapKeepCos)),
                  deg < 45 ? std::vector<int>{2} : std::vector<int>{});
        CompatibleBlockOptions off;
        off.fan_cap_branches = false;
        EXPECT_TRUE(find_fan_blocks(s, an, off).chains.empty());  // option off: end refused
        if (deg < 45) {
            const RawRun r = mesh_raw_with_caps(s);
            EXPECT_TRUE(r.valid);
            EXPECT_EQ(r.quality.inverted, 0);
            EXPECT_EQ(r.quality.hexes, 88);
            continue;
        }
        ConnectionSurfaceOptions o;
        o.blocks.fan_cap_branches = true;
        try {
            (void)build_connection_surfaces(s, an, o);
            ADD_FAILURE() << "no refusal";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::UnsupportedConfiguration);
            EXPECT_NE(std::string(e.what()).find("skeleton vertex 2:"), std::string::npos) << e.what();
        }
    }
    Skeleton y = fan({0, 2 * kPi / 3, 4 * kPi / 3}, 2, 2, kIdentity);
    add_branch(y, 2, {0, 0, 1});
    AnalysisOptions ao;
    ao.fan_cap_branches = true;
    CompatibleBlockOptions on;
    on.fan_cap_branches = true;
    EXPECT_TRUE(fan_cap_roots(find_fan_blocks(y, analyze_skeleton(y, ao), on)).empty());
}
