// METIS partitions of hex meshes: parts, balance, edge cut, determinism, errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include <tbb/global_control.h>

#include "hex_fixtures.h"
#include "mesohex/core/error.h"
#include "mesohex/post/partition.h"

using namespace mesohex;

TEST(Partition, GridIntoFourBalancedParts) {
    const HexMesh m = mesohex::test::make_block(4, 4, 4);  // 64 hexes
    const Partition p = partition_hexes(m, {.parts = 4});
    EXPECT_EQ(p.parts, 4);
    ASSERT_EQ(p.part.size(), 64u);
    for (int part : p.part) {
        EXPECT_GE(part, 0);
        EXPECT_LT(part, 4);
    }
    ASSERT_EQ(p.part_sizes.size(), 4u);
    long total = 0;
    for (long size : p.part_sizes) {
        EXPECT_GT(size, 0);
        total += size;
    }
    EXPECT_EQ(total, 64);
    EXPECT_LE(p.imbalance, 0.05);
    // The cut of the best 4-way split of a 4 x 4 x 4 block is two planes of 16 faces = 32 (slabs cost 3 x 16 = 48).
    // METIS need not find the optimum; it must lie between the optimum and the slabs.
    EXPECT_GE(p.edge_cut, 32);
    EXPECT_LE(p.edge_cut, 48);
    // The reported figures are those of the assignment.
    const Partition again = evaluate_partition(m, p.part, 4);
    EXPECT_EQ(again.edge_cut, p.edge_cut);
    EXPECT_EQ(again.part_sizes, p.part_sizes);
    EXPECT_DOUBLE_EQ(again.imbalance, p.imbalance);
}

TEST(Partition, EvaluateCountsByHand) {
    // 2 x 1 x 1 block split in its two hexes: one shared face cut, sizes 1 + 1, imbalance 0.
    const HexMesh two = mesohex::test::make_block(2, 1, 1);
    Partition p = evaluate_partition(two, {0, 1}, 2);
    EXPECT_EQ(p.edge_cut, 1);
    EXPECT_EQ(p.part_sizes, (std::vector<long>{1, 1}));
    EXPECT_DOUBLE_EQ(p.imbalance, 0.0);
    // 4 x 1 x 1 with parts {0, 0, 0, 1}: one cut face, largest part 3 of average 2 -> imbalance 0.5.
    const HexMesh row = mesohex::test::make_block(4, 1, 1);
    p = evaluate_partition(row, {0, 0, 0, 1}, 2);
    EXPECT_EQ(p.edge_cut, 1);
    EXPECT_DOUBLE_EQ(p.imbalance, 0.5);
    // {0, 1, 0, 1}: three cut faces.
    EXPECT_EQ(evaluate_partition(row, {0, 1, 0, 1}, 2).edge_cut, 3);
}

TEST(Partition, RowSplitsIntoContiguousHalves) {
    // A row of 8 hexes into 2 parts: the only cut of 1 face with balanced parts is the middle.
    const HexMesh row = mesohex::test::make_block(8, 1, 1);
    const Partition p = partition_hexes(row, {.parts = 2});
    EXPECT_EQ(p.edge_cut, 1);
    EXPECT_EQ(p.part_sizes, (std::vector<long>{4, 4}));
    for (int h = 1; h < 4; ++h) EXPECT_EQ(p.part[static_cast<std::size_t>(h)], p.part[0]);
    for (int h = 5; h < 8; ++h) EXPECT_EQ(p.part[static_cast<std::size_t>(h)], p.part[4]);
}

TEST(Partition, OnePartNeedsNoMetis) {
    const HexMesh m = mesohex::test::make_ring8();
    const Partition p = partition_hexes(m, {.parts = 1});
    EXPECT_EQ(p.part, std::vector<int>(8, 0));
    EXPECT_EQ(p.edge_cut, 0);
    EXPECT_DOUBLE_EQ(p.imbalance, 0.0);
}

TEST(Partition, DisconnectedHexesStillGetParts) {
    // Two unit cubes that share no vertex: the dual graph has no edge.
    HexMesh m = mesohex::test::make_unit_cube();
    const HexMesh other = mesohex::test::make_unit_cube();
    for (Vec3 q : other.points) m.points.push_back({q.x + 5, q.y, q.z});
    std::array<int, 8> hex = other.hexes[0];
    for (int& v : hex) v += 8;
    m.hexes.push_back(hex);
    const Partition p = partition_hexes(m, {.parts = 2});
    EXPECT_EQ(p.part_sizes, (std::vector<long>{1, 1}));
    EXPECT_EQ(p.edge_cut, 0);
}

TEST(Partition, SameResultForAnyThreadCountAndRun) {
    const HexMesh m = mesohex::test::make_block(6, 5, 4);
    std::vector<int> reference;
    for (int threads : {1, 2, 4}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        for (int run = 0; run < 2; ++run) {
            const Partition p = partition_hexes(m, {.parts = 3});
            if (reference.empty()) reference = p.part;
            EXPECT_EQ(p.part, reference) << threads << " threads, run " << run;
        }
    }
}

TEST(Partition, BadRequestsAreErrors) {
    const HexMesh m = mesohex::test::make_block(2, 1, 1);
    auto code_of = [](auto fn) {
        try {
            fn();
        } catch (const Error& e) {
            return e.code();
        }
        return ErrorCode::NumericalFailure;  // "no error" is never what these cases expect
    };
    EXPECT_EQ(code_of([&] { partition_hexes(m, {.parts = 0}); }), ErrorCode::InvalidInput);
    EXPECT_EQ(code_of([&] { partition_hexes(m, {.parts = 3}); }), ErrorCode::InvalidInput);
    EXPECT_EQ(code_of([&] { partition_hexes(HexMesh{}, {.parts = 1}); }), ErrorCode::InvalidInput);
    HexMesh bad = m;
    bad.hexes[1][3] = 99;
    EXPECT_EQ(code_of([&] { partition_hexes(bad, {.parts = 2}); }), ErrorCode::InvalidInput);
    EXPECT_EQ(code_of([&] { evaluate_partition(m, {0, 2}, 2); }), ErrorCode::InvalidInput);
    EXPECT_EQ(code_of([&] { evaluate_partition(m, {0}, 2); }), ErrorCode::InvalidInput);
}
