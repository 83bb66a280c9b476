// Every surface in ../shared/data/surfaces: reads, and has the counts and topology listed in ../shared/data/README.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>

#include "mesohex/surface/surface_check.h"
#include "mesohex/surface/surface_query.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"

using namespace mesohex;
namespace fs = std::filesystem;

namespace {

struct Facts {
    int vertices, triangles, genus;
    int unreferenced = 0;
    bool inward = false;
};

// From the "Files" table of ../shared/data/README.md (V, F, genus; all closed, manifold, oriented, 1 component).
const std::map<std::string, Facts>& facts() {
    static const std::map<std::string, Facts> f = {
        {"cactus.obj", {700, 1396, 0}},         {"aorta.stl", {6468, 12932, 0, 0, true}},
        {"hand.off", {3497, 6990, 0}},          {"airplane1.off", {5400, 10796, 0}},
        {"dtorus.off", {2521, 5046, 2}},        {"wrench.off", {12997, 25994, 1}},
        {"cup.off", {10495, 20994, 2}},         {"plate1.obj", {1612, 3220, 0}},
        {"plate3.obj", {2467, 4930, 0}},        {"bearing_plate.obj", {4907, 9830, 5}},
        {"cylinder_plate.obj", {920, 1836, 0}}, {"bracket_inches.obj", {8301, 16622, 6}},
        {"deckel.obj", {5000, 10012, 4}},       {"knob.obj", {6899, 13798, 1}},
        {"pinion.ply", {21439, 42878, 1}},      {"torque.obj", {1652, 3300, 0}},
        {"holes2.ply", {2922, 5848, 2}},        {"hand_loopycuts.obj", {2474, 4944, 0}},
        {"sculpt.ply", {3669, 7342, 2}},        {"chair1.off", {11422, 22854, 4, 1}},
        {"armchair.off", {12973, 25940, 0, 1}}, {"dualocta.off", {4930, 9856, 0}},
    };
    return f;
}

const std::string kDir = std::string(MESOHEX_SHARED_DATA_DIR) + "/surfaces";

}  // namespace

TEST(SharedSurfaces, EveryFileHasItsListedFacts) {
    ASSERT_TRUE(fs::is_directory(kDir)) << kDir;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(kDir))
        if (e.is_regular_file()) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    int checked = 0;
    for (const std::string& name : names) {
        SCOPED_TRACE(name);
        const auto it = facts().find(name);
        ASSERT_NE(it, facts().end()) << "no facts listed for " << name;
        const Facts& f = it->second;
        TriangleMesh m = read_surface(kDir + "/" + name);
        EXPECT_EQ(static_cast<int>(m.points.size()), f.vertices);
        EXPECT_EQ(static_cast<int>(m.triangles.size()), f.triangles);
        const SurfaceCheck c = check_surface(m);
        EXPECT_TRUE(c.is_closed_manifold());
        EXPECT_EQ(c.edges, (3 * f.triangles) / 2);
        EXPECT_EQ(c.unreferenced_vertices, f.unreferenced);
        ASSERT_EQ(c.components.size(), 1u);
        EXPECT_EQ(c.components[0].genus, f.genus);
        EXPECT_EQ(c.signed_volume < 0, f.inward);
        const OrientResult r = orient_outward(m);
        EXPECT_EQ(r.flipped_triangles, f.inward ? f.triangles : 0);
        EXPECT_GT(check_surface(m).signed_volume, 0);
        if (f.unreferenced > 0) {
            const std::vector<int> map = remove_unreferenced_vertices(m);
            EXPECT_EQ(map[0], -1);  // README: the unreferenced vertex is vertex 0
            EXPECT_EQ(static_cast<int>(m.points.size()), f.vertices - f.unreferenced);
            EXPECT_EQ(check_surface(m).unreferenced_vertices, 0);
        }
        ++checked;
    }
    EXPECT_EQ(checked, static_cast<int>(facts().size()));
}

TEST(SharedSurfaces, PairedSkeletonNodesAreInside) {
    // README: cactus 180/180 and aorta 350/350 skeleton nodes inside their surface, with radius ~ distance to the
    // surface (aorta: inscribed-sphere radii; nearest-vertex distance / radius has median 1.00).
    for (const auto& [skel, surf, nodes] : {std::tuple<std::string, std::string, int>{"cactus.skel", "cactus.obj", 180},
                                            {"aorta.skel", "aorta.stl", 350}}) {
        SCOPED_TRACE(surf);
        const Skeleton s = read_skeleton(std::string(MESOHEX_SHARED_DATA_DIR) + "/curve-skeletons/" + skel);
        ASSERT_EQ(static_cast<int>(s.points.size()), nodes);
        const SurfaceQuery q(read_surface(kDir + "/" + surf));
        const std::vector<char> in = q.inside(s.points);
        EXPECT_EQ(std::count(in.begin(), in.end(), 1), nodes);
        if (surf == "aorta.stl") {
            std::vector<double> ratio;
            const std::vector<double> d2 = q.squared_distances(s.points);
            for (std::size_t v = 0; v < d2.size(); ++v) ratio.push_back(std::sqrt(d2[v]) / s.radii[v]);
            std::sort(ratio.begin(), ratio.end());
            const double median = ratio[ratio.size() / 2];
            EXPECT_GT(median, 0.9);
            EXPECT_LE(median, 1.0 + 1e-3);  // closest point is at most the nearest vertex distance
        }
    }
}
