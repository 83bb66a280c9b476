// The studio's final mesh (pad, subdivide, fit, smooth) on a small generated plate in its own thickened domain: the
// synchronous /api/mesh?stage=final and the background job give what `mesohex mesh --surface` gives; jobs are
// cancelled by the next job of the same client and by DELETE; progress events stream.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "cli_run.h"
#include "mesohex/stages/generators.h"
#include "mesohex_io/skeleton_io.h"
#include "mesohex_io/surface_io.h"
#include "studio_fixtures.h"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace mesohex;
using mesohex::test::body_json;
using mesohex::test::run_cli;
using mesohex::test::start_studio;

namespace {

class StudioFinal : public testing::Test {
protected:
    // A 2 x 1 plate, thickened (--resolution 2), meshed once by the CLI: the reference report.
    static void SetUpTestSuite() {
        const fs::path dir = fs::path(testing::TempDir()) / "mesohex_test_studio_final";
        fs::create_directories(dir);
        skeleton_file = new std::string((dir / "plate.obj").string());
        domain_file = new std::string((dir / "plate.off").string());
        write_skeleton(*skeleton_file, generate_skeleton("plate", {.n = 2, .m = 1}));
        const auto t = run_cli("thicken " + *skeleton_file + " -o " + *domain_file + " --resolution 2");
        ASSERT_EQ(t.status, 0) << t.output;
        const fs::path report = dir / "plate.json";
        const auto m = run_cli("mesh " + *skeleton_file + " --surface " + *domain_file + " -o " +
                               (dir / "plate.vtu").string() + " --report " + report.string() + " --quiet");
        ASSERT_EQ(m.status, 0) << m.output;
        cli_report = new json();
        std::ifstream(report) >> *cli_report;
    }
    static void TearDownTestSuite() {
        delete skeleton_file;
        delete domain_file;
        delete cli_report;
    }
    static test::RunningStudio studio() {
        studio::StudioSession session;
        session.domain = read_surface(*domain_file);
        session.domain_name = *domain_file;
        return start_studio(session);
    }
    static std::string skeleton_text() {
        std::ifstream in(*skeleton_file);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }
    // Polls GET /api/jobs/ID until the job is finished (at most 5 minutes); its last body.
    static json wait_job(httplib::Client& c, long id) {
        const std::string path = "/api/jobs/" + std::to_string(id);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
        for (;;) {
            const auto r = c.Get(path.c_str());
            if (!r || r->status != 200) return json::object();
            const json j = body_json(r);
            const std::string state = j.value("state", "");
            if (state == "done" || state == "failed" || state == "cancelled") return j;
            if (std::chrono::steady_clock::now() > deadline) return j;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
    static std::string* skeleton_file;
    static std::string* domain_file;
    static json* cli_report;
};
std::string* StudioFinal::skeleton_file = nullptr;
std::string* StudioFinal::domain_file = nullptr;
json* StudioFinal::cli_report = nullptr;

void expect_same_final(const json& result, const json& cli) {
    const json& rep = result["report"];
    EXPECT_EQ(rep["quality"]["hexes"], cli["quality"]["hexes"]);
    EXPECT_EQ(rep["quality"]["vertices"], cli["quality"]["vertices"]);
    EXPECT_EQ(rep["raw_quality"]["hexes"], cli["raw_quality"]["hexes"]);
    EXPECT_NEAR(rep["quality"]["sj_min"].get<double>(), cli["quality"]["sj_min"].get<double>(), 1e-9);
    EXPECT_NEAR(rep["quality"]["sj_avg"].get<double>(), cli["quality"]["sj_avg"].get<double>(), 1e-9);
    EXPECT_EQ(rep["quality"]["inverted"], 0);
    const json& mesh = result["mesh"];
    const std::size_t nv = mesh["vertices"].size() / 3;
    EXPECT_EQ(static_cast<long>(nv), cli["quality"]["vertices"].get<long>());
    EXPECT_EQ(static_cast<long>(mesh["hexes"].size() / 8), cli["quality"]["hexes"].get<long>());
    EXPECT_FALSE(result.contains("connection_surfaces"));
    // Distance to the domain on the boundary vertices (0 inside): within the 1 % goal of the bbox diagonal.
    ASSERT_EQ(mesh["boundary_distance"].size(), nv);
    std::vector<char> on_boundary(nv, 0);
    for (const json& v : mesh["boundary_quads"]) on_boundary[v.get<std::size_t>()] = 1;
    const double diagonal = cli["hausdorff"]["bbox_diagonal"].get<double>();
    for (std::size_t v = 0; v < nv; ++v) {
        const double d = mesh["boundary_distance"][v].get<double>();
        if (!on_boundary[v]) {
            ASSERT_EQ(d, 0.0) << v;
        }
        ASSERT_GE(d, 0.0);
        ASSERT_LE(d, 0.01 * diagonal) << v;
    }
}

}  // namespace

TEST_F(StudioFinal, SynchronousFinalMeshEqualsTheCli) {
    auto s = studio();
    const auto r = s.client->Post("/api/mesh?stage=final", skeleton_text(), "text/plain");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
    expect_same_final(body_json(r), *cli_report);
}

// Job 1 is cancelled by job 2 of the same client; job 2 finishes like the CLI; its events end with "done"; job 3 is
// cancelled by DELETE.
TEST_F(StudioFinal, JobsRunTheFinalMeshAndAreCancelled) {
    auto s = studio();
    httplib::Headers client{{"X-Studio-Client", "page-1"}};
    const auto r1 = s.client->Post("/api/jobs", client, skeleton_text(), "text/plain");
    ASSERT_TRUE(r1);
    ASSERT_EQ(r1->status, 202) << r1->body;
    const long id1 = body_json(r1)["job"];
    const auto r2 = s.client->Post("/api/jobs", client, skeleton_text(), "text/plain");
    ASSERT_TRUE(r2);
    ASSERT_EQ(r2->status, 202) << r2->body;
    const long id2 = body_json(r2)["job"];
    EXPECT_NE(id1, id2);
    EXPECT_EQ(wait_job(*s.client, id1)["state"], "cancelled");
    const json done = wait_job(*s.client, id2);
    ASSERT_EQ(done["state"], "done") << done.dump().substr(0, 300);
    expect_same_final(done["result"], *cli_report);

    const auto events = s.client->Get(("/api/jobs/" + std::to_string(id2) + "/events").c_str());
    ASSERT_TRUE(events);
    EXPECT_EQ(events->status, 200);
    EXPECT_EQ(events->get_header_value("Content-Type"), "text/event-stream");
    ASSERT_EQ(events->body.rfind("data: ", 0), 0u) << events->body;
    EXPECT_NE(events->body.find("\"state\":\"done\""), std::string::npos) << events->body;
    // The progress carries the attempt's description field (set for "attempt" reports, empty otherwise).
    ASSERT_TRUE(done["progress"].contains("what")) << done["progress"].dump();
    EXPECT_EQ(done["progress"]["what"].is_string(), true);
    EXPECT_EQ(done["progress"]["what"] == "", done["progress"]["stage"] != "attempt") << done["progress"].dump();

    const auto r3 = s.client->Post("/api/jobs", skeleton_text(), "text/plain");  // client "default"
    ASSERT_TRUE(r3);
    const long id3 = body_json(r3)["job"];
    const auto del = s.client->Delete(("/api/jobs/" + std::to_string(id3)).c_str());
    ASSERT_TRUE(del);
    EXPECT_EQ(del->status, 200) << del->body;
    EXPECT_EQ(wait_job(*s.client, id3)["state"], "cancelled");
    // The finished job is still there.
    EXPECT_EQ(body_json(s.client->Get(("/api/jobs/" + std::to_string(id2)).c_str()))["state"], "done");
}

// A skeleton without radii in a domain: the raw mesh takes them from the domain (0.5 x distance), as `mesohex mesh
// --surface --raw` does: same report radius source, hexes and quality.
TEST_F(StudioFinal, RawMeshInTheDomainTakesRadiiFromItLikeTheCli) {
    const fs::path dir = fs::path(*skeleton_file).parent_path();
    Skeleton plate = generate_skeleton("plate", {.n = 2, .m = 1});
    plate.radii.clear();
    const fs::path bare = dir / "plate_no_radii.obj", report = dir / "plate_raw.json";
    write_skeleton(bare.string(), plate);
    const auto m = run_cli("mesh " + bare.string() + " --surface " + *domain_file + " --raw -o " +
                           (dir / "plate_raw.vtu").string() + " --report " + report.string() + " --quiet");
    ASSERT_EQ(m.status, 0) << m.output;
    json cli;
    std::ifstream(report) >> cli;
    auto s = studio();
    const auto r = s.client->Post("/api/mesh?stage=raw", mesohex::skeleton_text(plate, "obj", "x"), "text/plain");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
    const json rep = body_json(r)["report"];
    EXPECT_EQ(rep["radius"], cli["radius"]);
    EXPECT_EQ(rep["radius"]["source"], "surface (0.500000 x distance)");
    EXPECT_EQ(rep["quality"]["hexes"], cli["quality"]["hexes"]);
    EXPECT_EQ(rep["quality"]["sj_min"], cli["quality"]["sj_min"]);
    EXPECT_EQ(rep["quality"]["sj_avg"], cli["quality"]["sj_avg"]);
}
