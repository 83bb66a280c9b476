// The table of three-direction orange maxima (orange_three.h, SpherePartitionOptions::tabled_three_start): writes
// lib/mesohex/stages/orange_three_table.inc, or compares the table's starts with the coarse scan's on random triples.
//
//   mesohex_orange_table [NODES]                  the table source for NODES^3 nodes (default kOrangeTableNodes)
//   mesohex_orange_table --check NODES COUNT      COUNT random triples (the five kinds of test_orange_three.cpp): the
//                                                 table's starts (a table of NODES^3 computed here) against the coarse
//                                                 scan's (SpherePartitionOptions::coarse_three_scan): triples ending
//                                                 higher / lower (by more than 1e-9 rad), the largest loss, the mean
//                                                 change, starts per triple, CPU microseconds per triple of both
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "direction_fixtures.h"
#include "mesohex/stages/orange_three.h"
#include "mesohex/stages/sphere_partition.h"

using namespace mesohex;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kWeight = kPi / 3;

std::vector<signed char> make_table(int nodes) {
    std::vector<signed char> table(3 * nodes * nodes * nodes, 0);
    const auto at = [&](int a) { return orange_table_angle(static_cast<double>(a) / (nodes - 1)); };
    for (int a = 0; a < nodes; ++a)
        for (int b = 0; b < nodes; ++b)
            for (int c = 0; c < nodes; ++c) {
                const Vec3 axis = orange_three_table_axis(at(a), at(b), at(c), kWeight);
                const int index = (a * nodes + b) * nodes + c;
                table[3 * index] = static_cast<signed char>(std::lround(127 * axis.x));
                table[3 * index + 1] = static_cast<signed char>(std::lround(127 * axis.y));
                table[3 * index + 2] = static_cast<signed char>(std::lround(127 * axis.z));
            }
    return table;
}

int check(int nodes, int count) {
    const std::vector<signed char> table = make_table(nodes);
    std::mt19937_64 rng(20261207);
    std::vector<std::array<Vec3, 3>> triples;
    for (int k = 0; k < count; ++k) {
        const std::vector<Vec3> d = test::random_direction_triple(rng, k % 5);
        triples.push_back({d[0], d[1], d[2]});
    }
    int higher = 0, lower = 0, fallback = 0, lower_1deg = 0;
    double loss = 0, sum = 0, starts = 0;
    std::vector<double> coarse_score(count), table_score(count);
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < count; ++k) {
        const std::vector<Vec3> v(triples[k].begin(), triples[k].end());
        coarse_score[k] = orange_score_three(triples[k], test::orange_bounds(triples[k]), kWeight,
                                             detail::exact_three_orange_axis(v, true));
    }
    const auto t1 = std::chrono::steady_clock::now();
    for (int k = 0; k < count; ++k) {
        const std::vector<Vec3> s =
            tabled_orange_starts_three(triples[k], test::orange_bounds(triples[k]), kWeight, table.data(), nodes);
        starts += static_cast<double>(s.size());
        const OrangeAxisThree best = best_orange_axis_three(triples[k], test::orange_bounds(triples[k]), kWeight, s);
        table_score[k] = best.score;
        if (s.empty() || !(best.score > 0)) {
            ++fallback;
            const std::vector<Vec3> v(triples[k].begin(), triples[k].end());
            table_score[k] = orange_score_three(triples[k], test::orange_bounds(triples[k]), kWeight,
                                                detail::exact_three_orange_axis(v, true));
        }
    }
    const auto t2 = std::chrono::steady_clock::now();
    for (int k = 0; k < count; ++k) {
        const double delta = table_score[k] - coarse_score[k];
        sum += delta;
        if (delta > 1e-9) ++higher;
        if (delta < -1e-9) {
            ++lower;
            if (delta < -kPi / 180) ++lower_1deg;
            loss = std::max(loss, -delta);
        }
    }
    const double us = 1e6 / count;
    std::printf(
        "nodes %d, %d triples: table higher %d, lower %d (%d by > 1 degree; largest loss %.4f degrees), "
        "mean %+.5f degrees, starts %.2f per triple, scan fallbacks %d; microseconds per triple: coarse scan "
        "%.1f, table %.1f\n",
        nodes, count, higher, lower, lower_1deg, loss * 180 / kPi, sum / count * 180 / kPi, starts / count, fallback,
        std::chrono::duration<double>(t1 - t0).count() * us, std::chrono::duration<double>(t2 - t1).count() * us);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 4 && !std::strcmp(argv[1], "--check")) {
        const int nodes = std::atoi(argv[2]), count = std::atoi(argv[3]);
        if (nodes < 2 || count < 1) {
            std::fprintf(stderr, "mesohex_orange_table: --check needs NODES >= 2 and COUNT >= 1\n");
            return 2;
        }
        return check(nodes, count);
    }
    const int nodes = argc >= 2 ? std::atoi(argv[1]) : kOrangeTableNodes;
    if (nodes < 2) {
        std::fprintf(stderr, "mesohex_orange_table: NODES must be >= 2\n");
        return 2;
    }
    const std::vector<signed char> table = make_table(nodes);
    std::printf(
        "// Generated by bench/orange_table.cpp (mesohex_orange_table %d): orange_three_table_axis at %d^3 nodes\n"
        "// (alpha, beta, gamma) = orange_table_angle((a, b, c) / %d), margin weight pi / 3; x, y, z in units "
        "of 1/127.\n// Node (a, b, c) at index (a n + b) n + c, n = %d.\n",
        nodes, nodes, nodes - 1, nodes);
    std::printf("constexpr std::array<signed char, %zu> kOrangeTable = {", table.size());
    for (std::size_t k = 0; k < table.size(); ++k) std::printf("%s%d,", k % 36 == 0 ? "\n    " : "", table[k]);
    std::printf("\n};\n");
    return 0;
}
