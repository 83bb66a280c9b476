// Property tests of the whole raw pipeline (issue 18): thousands of seeded random skeletons -- trees, cycles, leaflet
// patches (generator plates with branches), stars up to degree 12, near-coincident and opposite directions, tiny and
// huge radii and scales -- each either gives a valid raw mesh whose vertex and hex counts equal the prediction, with
// finite coordinates only, or is refused with a mesohex::Error of a documented code whose message names the element
// (a skeleton vertex, edge or face). Never another exception, a crash or a NaN. Inverted hexes are allowed (random
// directions). Deterministic: fixed seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <random>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/generators.h"

namespace mesohex {
namespace {

using Rng = std::mt19937;

Vec3 random_unit(Rng& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    for (;;) {
        const Vec3 d{g(rng), g(rng), g(rng)};
        if (norm(d) > 1e-3) return normalized(d);
    }
}

// A unit vector at `angle` (radians) from d.
Vec3 rotated_away(const Vec3& d, double angle, Rng& rng) {
    Vec3 t = cross(d, random_unit(rng));
    if (norm(t) < 1e-6) t = cross(d, Vec3{1, 0, 0});
    if (norm(t) < 1e-6) t = cross(d, Vec3{0, 1, 0});
    t = normalized(t);
    return normalized(std::cos(angle) * d + std::sin(angle) * t);
}

// Random tree: each new vertex hangs off a random earlier one, in a random direction.
Skeleton random_tree(Rng& rng) {
    std::uniform_int_distribution<int> size(2, 24);
    std::uniform_real_distribution<double> len(0.5, 2.0);
    Skeleton s;
    const int n = size(rng);
    s.points.push_back({0, 0, 0});
    for (int v = 1; v < n; ++v) {
        std::uniform_int_distribution<int> parent(0, v - 1);
        const int p = parent(rng);
        s.points.push_back(s.points[p] + len(rng) * random_unit(rng));
        s.edges.push_back({p, v});
    }
    return s;
}

// A closed polygon (3 to 12 vertices, jittered circle), sometimes with a tail.
Skeleton random_cycle(Rng& rng) {
    std::uniform_int_distribution<int> size(3, 12);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    const int n = size(rng);
    Skeleton s;
    const double radius = n / 3.0;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        s.points.push_back({radius * std::cos(a) + jitter(rng), radius * std::sin(a) + jitter(rng), jitter(rng)});
        s.edges.push_back({i, (i + 1) % n});
    }
    if (rng() % 2 == 0) {
        s.points.push_back(s.points[0] + Vec3{0, 0, 1.5});
        s.edges.push_back({0, n});
    }
    return s;
}

// A star: a centre with k = 2..12 one-edge branches; some directions nearly coincide (1e-9 .. 1e-2 rad apart) or are
// exactly / nearly opposite.
Skeleton random_star(Rng& rng) {
    std::uniform_int_distribution<int> degree(2, 12);
    std::uniform_real_distribution<double> len(0.5, 2.0);
    const int k = degree(rng);
    std::vector<Vec3> dirs;
    for (int i = 0; i < k; ++i) {
        const int kind = static_cast<int>(rng() % 6);
        if (i > 0 && kind == 0) {
            dirs.push_back(
                rotated_away(dirs[rng() % dirs.size()], std::pow(10.0, -9.0 + 7.0 * (rng() % 1000) / 1000.0), rng));
        } else if (i > 0 && kind == 1) {
            dirs.push_back(-1.0 * dirs[rng() % dirs.size()]);
        } else if (i > 0 && kind == 2) {
            dirs.push_back(rotated_away(-1.0 * dirs[rng() % dirs.size()], 1e-6, rng));
        } else {
            dirs.push_back(random_unit(rng));
        }
    }
    Skeleton s;
    s.points.push_back({0, 0, 0});
    for (int i = 0; i < k; ++i) {
        s.points.push_back(len(rng) * dirs[i]);
        s.edges.push_back({0, i + 1});
    }
    return s;
}

// A generator plate (leaflet patch) with 0..3 two-edge branches at random vertices in random directions.
Skeleton random_patch(Rng& rng) {
    GeneratorOptions o;
    o.n = 1 + static_cast<int>(rng() % 4);
    o.m = 1 + static_cast<int>(rng() % 3);
    Skeleton s = generate_skeleton("plate", o);
    const int branches = static_cast<int>(rng() % 4);
    const double r = s.radii.empty() ? 0.3 : s.radii[0];
    for (int b = 0; b < branches; ++b) {
        const int v = static_cast<int>(rng() % s.points.size());
        const Vec3 d = random_unit(rng);
        const int a = static_cast<int>(s.points.size());
        s.points.push_back(s.points[v] + 0.8 * d);
        s.points.push_back(s.points[v] + 1.6 * d);
        if (!s.radii.empty()) s.radii.insert(s.radii.end(), {r, r});
        s.edges.push_back({v, a});
        s.edges.push_back({a, a + 1});
    }
    return s;
}

// Scales positions by `scale` and sets radii to `radius_factor` x the mean edge length (per-vertex jitter).
void set_scale_and_radii(Skeleton& s, double scale, double radius_factor, Rng& rng) {
    for (Vec3& p : s.points) p = scale * p;
    double total = 0;
    for (const std::array<int, 2>& e : s.edges) total += distance(s.points[e[0]], s.points[e[1]]);
    const double mean = s.edges.empty() ? scale : total / static_cast<double>(s.edges.size());
    std::uniform_real_distribution<double> jitter(0.8, 1.25);
    s.radii.assign(s.points.size(), 0.0);
    for (double& r : s.radii) r = radius_factor * mean * jitter(rng);
}

bool names_an_element(const Error& e) {
    const std::string m = e.what();
    return e.where().kind != ElementRef::Kind::None || m.find("vertex") != std::string::npos ||
           m.find("edge") != std::string::npos || m.find("face") != std::string::npos;
}

struct Tally {
    int built = 0;
    std::map<ErrorCode, int> refused;
};

void check_one(const Skeleton& s, bool resample, Tally& tally, const std::string& what) {
    PipelineOptions options;
    options.resample = resample;
    try {
        const PipelineResult res = run_pipeline(s, options);
        const HexMesh& mesh = res.raw.mesh;
        EXPECT_EQ(static_cast<long>(mesh.points.size()), res.predicted.vertices) << what;
        EXPECT_EQ(static_cast<long>(mesh.hexes.size()), res.predicted.hexes) << what;
        EXPECT_TRUE(std::all_of(mesh.points.begin(), mesh.points.end(), [](const Vec3& p) { return is_finite(p); }))
            << what;
        const QualityReport q = compute_quality(mesh);
        EXPECT_TRUE(q.validation.valid())
            << what << ": " << (q.validation.problems.empty() ? "" : q.validation.problems[0].message);
        EXPECT_FALSE(std::isnan(q.sj_min)) << what;
        ++tally.built;
    } catch (const Error& e) {
        const int code = static_cast<int>(e.code());
        EXPECT_TRUE(code >= 1 && code <= 4) << what << ": " << e.what();
        EXPECT_TRUE(names_an_element(e)) << what << ": " << e.what();
        EXPECT_EQ(std::string(e.what()).find("internal check failed"), std::string::npos) << what << ": " << e.what();
        ++tally.refused[e.code()];
    } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": foreign exception " << e.what();
    }
}

// Scale and radius regimes: ordinary, tiny and huge coordinates, thin and fat radii.
constexpr std::array<std::pair<double, double>, 5> kRegimes{
    {{1.0, 0.2}, {1e-6, 0.2}, {1e6, 0.2}, {1.0, 1e-6}, {1.0, 3.0}}};

void run_family(const char* name, Skeleton (*make)(Rng&), int trials, unsigned seed, int min_built) {
    Rng rng(seed);
    Tally tally;
    for (int t = 0; t < trials; ++t) {
        Skeleton s = make(rng);
        const auto [scale, radius] = kRegimes[static_cast<std::size_t>(t) % kRegimes.size()];
        set_scale_and_radii(s, scale, radius, rng);
        // Resampling (adaptation) with ordinary radii only: with radius 1e-6 x the edge length it samples every edge
        // up to its cap (65536 samples), a large mesh rather than a property.
        const bool resample = t % 8 == 0 && radius >= 0.2;
        check_one(s, resample, tally, std::string(name) + " trial " + std::to_string(t));
    }
    EXPECT_GE(tally.built, min_built) << name;
    std::cout << name << ": " << tally.built << " built, refused";
    for (const auto& [code, n] : tally.refused) std::cout << " code " << static_cast<int>(code) << " x " << n;
    std::cout << "\n";
}

TEST(PipelineProperties, RandomTrees) { run_family("trees", random_tree, 500, 181, 200); }
TEST(PipelineProperties, RandomCycles) { run_family("cycles", random_cycle, 500, 182, 200); }
TEST(PipelineProperties, RandomStars) { run_family("stars", random_star, 700, 183, 150); }
TEST(PipelineProperties, RandomLeafletPatches) { run_family("patches", random_patch, 500, 184, 100); }

}  // namespace
}  // namespace mesohex
