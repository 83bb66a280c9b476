// The studio server started in-process on a free loopback port, driven with httplib::Client: every endpoint, the
// static table, errors as 4xx JSON with the server still answering, the body limit, the raw and final meshes equal
// to the pipeline's and the CLI's, and jobs.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "binary_answer.h"
#include "cli_run.h"
#include "meshing.h"
#include "mesohex/core/error.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/generators.h"
#include "mesohex_io/medial_io.h"
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

fs::path temp_dir() {
    const fs::path dir = fs::path(testing::TempDir()) / "mesohex_test_studio_server";
    fs::create_directories(dir);
    return dir;
}

std::string tripod_path() { return std::string(MESOHEX_PROJECT_DIR) + "/data/tiny/tripod.obj"; }

std::string obj_text(const Skeleton& s) { return skeleton_text(s, "obj", "test"); }

httplib::Result post(httplib::Client& c, const std::string& path, const std::string& body,
                     const char* type = "text/plain") {
    return c.Post(path.c_str(), body, type);
}

int raw_request_status(int port, const std::string& request);

// The raw bytes of a request sent as-is on a socket (no client-side path normalization); the status line's code.
int raw_get_status(int port, const std::string& target) {
    return raw_request_status(port, "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
}

int raw_request_status(int port, const std::string& req) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        ::close(fd);
        return -1;
    }
    if (::send(fd, req.data(), req.size(), 0) != static_cast<ssize_t>(req.size())) {
        ::close(fd);
        return -1;
    }
    std::string reply;
    char buf[4096];
    ssize_t n;
    while ((n = ::recv(fd, buf, sizeof buf, 0)) > 0) reply.append(buf, static_cast<std::size_t>(n));
    ::close(fd);
    if (reply.size() < 12) return -1;
    return std::stoi(reply.substr(9, 3));
}

// An axis-aligned closed box [-1, 1]^3 as 12 outward triangles.
TriangleMesh unit_box() {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i) m.points.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

long sum_counts(const std::map<int, long>& m) {
    long n = 0;
    for (const auto& [valence, count] : m) n += count;
    return n;
}

}  // namespace

TEST(StudioServer, SessionGivesTheCommandLineSkeletonAndNoDomain) {
    studio::StudioSession session;
    session.skeleton = read_skeleton(tripod_path());
    session.skeleton_name = "tripod.obj";
    auto s = start_studio(session);
    const auto r = s.client->Get("/api/session");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/json");
    const json j = body_json(r);
    ASSERT_TRUE(j["skeleton"].is_object()) << r->body;
    EXPECT_EQ(j["skeleton"]["points"].size(), 17u);  // data/tiny/tripod.obj: 17 vertices, 16 edges, no face
    EXPECT_EQ(j["skeleton"]["edges"].size(), 16u);
    EXPECT_EQ(j["skeleton"]["faces"].size(), 0u);
    EXPECT_EQ(j["skeleton"]["edges"][0], json::array({0, 1}));
    EXPECT_EQ(j["skeleton_name"], "tripod.obj");
    EXPECT_TRUE(j["domain"].is_null());
    EXPECT_TRUE(j["save_target"].is_null());
    EXPECT_TRUE(j["medial"].is_null());
}

// Only what the table holds is served; no request path reaches the file system.
TEST(StudioServer, StaticFilesComeFromTheInMemoryTableOnly) {
    studio::StaticFiles files;
    files.by_url["/"] = {"text/html; charset=utf-8", "<!doctype html><title>studio</title>"};
    files.by_url["/app/main.js"] = {"text/javascript; charset=utf-8", "export const x = 1;"};
    auto s = start_studio({}, files);
    const auto index = s.client->Get("/");
    ASSERT_TRUE(index);
    EXPECT_EQ(index->status, 200);
    EXPECT_EQ(index->body, "<!doctype html><title>studio</title>");
    EXPECT_EQ(index->get_header_value("Content-Type"), "text/html; charset=utf-8");
    const auto js = s.client->Get("/app/main.js");
    ASSERT_TRUE(js);
    EXPECT_EQ(js->body, "export const x = 1;");
    EXPECT_EQ(js->get_header_value("Content-Type"), "text/javascript; charset=utf-8");
    for (const std::string target : {"/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/app/../../../etc/passwd",
                                     "/app/..%2f..%2f..%2fetc%2fpasswd", "/etc/passwd", "//etc/passwd",
                                     "/app/main.js/../../../../etc/hostname", "/index.html"}) {
        EXPECT_EQ(raw_get_status(s.port, target), 404) << target;
        const auto r = s.client->Get(target.c_str());
        ASSERT_TRUE(r) << target;
        EXPECT_EQ(r->status, 404) << target;
        EXPECT_EQ(body_json(r)["error"]["code"], "NotFound") << target << ": " << r->body;
        EXPECT_EQ(r->body.find("root:"), std::string::npos);
    }
}

// A web directory made here: the fixed files, the top-level modules (not test/, not odd names), node_modules' three.
TEST(StudioServer, LoadsTheFixedFilesAndTheTopLevelModules) {
    const fs::path web = temp_dir() / "web";
    fs::remove_all(web);
    fs::create_directories(web / "test");
    fs::create_directories(web / "node_modules/three/build");
    const auto write = [](const fs::path& p, const std::string& text) { std::ofstream(p) << text; };
    write(web / "index.html", "<html>");
    write(web / "main.js", "m");
    write(web / "edit-ops.js", "e");
    write(web / "odd.name.js", "o");
    write(web / "test/edit.test.js", "t");
    write(web / "node_modules/three/build/three.module.js", "three");
    const studio::StaticFiles f = studio::load_static_files(web.string());
    std::set<std::string> urls;
    for (const auto& [url, file] : f.by_url) urls.insert(url);
    EXPECT_EQ(urls, (std::set<std::string>{"/", "/index.html", "/app/edit-ops.js", "/app/main.js",
                                           "/vendor/three.module.js"}));
    EXPECT_EQ(f.by_url.at("/vendor/three.module.js").body, "three");
    EXPECT_EQ(f.by_url.at("/app/main.js").content_type, "text/javascript; charset=utf-8");
    EXPECT_EQ(f.missing,
              (std::vector<std::string>{"studio.css", "node_modules/three/examples/jsm/controls/OrbitControls.js",
                                        "node_modules/three/examples/jsm/controls/TransformControls.js"}));
}

// Every generated shape: /api/mesh?stage=raw answers the raw mesh run_pipeline builds (same hexes, same points to the
// last bit through the shortest round-trip decimal text, same quality).
TEST(StudioServer, RawMeshEqualsThePipelineOnGeneratedSkeletons) {
    auto s = start_studio({});
    for (const std::string& name : generator_names()) {
        const Skeleton skeleton = generate_skeleton(name);
        const PipelineResult res = run_pipeline(skeleton);
        const QualityReport q = compute_quality(res.raw.mesh);
        const auto r = post(*s.client, "/api/mesh?stage=raw&format=obj", obj_text(skeleton));
        ASSERT_TRUE(r) << name;
        ASSERT_EQ(r->status, 200) << name << ": " << r->body.substr(0, 300);
        const json j = body_json(r);
        EXPECT_EQ(j["report"]["quality"]["hexes"].get<long>(), q.hexes) << name;
        EXPECT_EQ(j["report"]["quality"]["sj_min"].get<double>(), q.sj_min) << name;
        EXPECT_EQ(j["report"]["quality"]["sj_avg"].get<double>(), q.sj_avg) << name;
        EXPECT_EQ(j["report"]["quality"]["inverted"].get<long>(), q.inverted) << name;
        const json& mesh = j["mesh"];
        ASSERT_EQ(mesh["hexes"].size(), 8 * res.raw.mesh.hexes.size()) << name;
        ASSERT_EQ(mesh["vertices"].size(), 3 * res.raw.mesh.points.size()) << name;
        for (std::size_t h = 0; h < res.raw.mesh.hexes.size(); ++h)
            for (int lv = 0; lv < 8; ++lv) ASSERT_EQ(mesh["hexes"][8 * h + lv].get<int>(), res.raw.mesh.hexes[h][lv]);
        for (std::size_t v = 0; v < res.raw.mesh.points.size(); ++v) {
            ASSERT_EQ(mesh["vertices"][3 * v].get<double>(), res.raw.mesh.points[v].x);
            ASSERT_EQ(mesh["vertices"][3 * v + 2].get<double>(), res.raw.mesh.points[v].z);
        }
        ASSERT_EQ(mesh["sj"].size(), q.sj.size()) << name;
        // One triple per irregular edge: the quality report's interior (valence != 4) and boundary (!= 2) counts.
        EXPECT_EQ(mesh["singular_edges"].size(), 3 * static_cast<std::size_t>(sum_counts(q.singular_interior_edges) +
                                                                              sum_counts(q.singular_boundary_edges)))
            << name;
        EXPECT_EQ(mesh["boundary_quads"].size() % 4, 0u);
        // One hex per boundary quad, and the quad's corners are corners of that hex.
        ASSERT_EQ(4 * mesh["boundary_hexes"].size(), mesh["boundary_quads"].size()) << name;
        for (std::size_t q = 0; q < mesh["boundary_hexes"].size(); ++q) {
            const std::array<int, 8>& hex = res.raw.mesh.hexes[mesh["boundary_hexes"][q].get<std::size_t>()];
            for (int k = 0; k < 4; ++k)
                ASSERT_NE(std::find(hex.begin(), hex.end(), mesh["boundary_quads"][4 * q + k].get<int>()), hex.end())
                    << name << " quad " << q;
        }
        EXPECT_FALSE(mesh.contains("boundary_distance"));
        EXPECT_EQ(j["analysis"]["predicted"]["hexes"].get<long>(), res.predicted.hexes) << name;
        EXPECT_EQ(j["analysis"]["vertex_class"].size(), skeleton.points.size()) << name;
        EXPECT_EQ(j["analysis"]["edge_kind"].size(), skeleton.edges.size()) << name;
        EXPECT_EQ(j["meshed_skeleton"]["points"].size(), res.skeleton.points.size()) << name;
        ASSERT_TRUE(j["connection_surfaces"].is_object()) << name;
        EXPECT_EQ(j["connection_surfaces"]["quads"].size() % 4, 0u);
        EXPECT_GE(j["server_ms"].get<double>(), 0.0);
    }
}

// encoding=binary: the same answer as the JSON one, arrays as uint32 (exact) and float32 (each value the JSON double
// rounded to float), without meshed_skeleton; the report, analysis and phases in the header.
TEST(StudioServer, BinaryMeshIsTheJsonMeshInFloat32) {
    auto s = start_studio({});
    for (const char* name : {"torus", "hand", "tfan"}) {
        const std::string text = obj_text(generate_skeleton(name));
        const auto rj = post(*s.client, "/api/mesh?stage=raw", text);
        const auto rb = post(*s.client, "/api/mesh?stage=raw&encoding=binary", text);
        ASSERT_TRUE(rj && rb) << name;
        ASSERT_EQ(rj->status, 200) << name;
        ASSERT_EQ(rb->status, 200) << name << ": " << rb->body.substr(0, 300);
        EXPECT_EQ(rb->get_header_value("Content-Type"), "application/octet-stream");
        const json j = body_json(rj);
        const studio::DecodedAnswer b = studio::decode_binary_answer(rb->body);
        EXPECT_EQ(b.header["report"]["quality"], j["report"]["quality"]) << name;
        EXPECT_EQ(b.header["report"]["predicted"], j["report"]["predicted"]) << name;
        EXPECT_EQ(b.header["analysis"], j["analysis"]) << name;
        EXPECT_FALSE(b.header.contains("meshed_skeleton"));
        EXPECT_GE(b.header["server_ms"].get<double>(), 0.0);
        EXPECT_TRUE(b.header["server_phases_ms"].contains("pipeline"));
        EXPECT_TRUE(j["server_phases_ms"].contains("encode"));
        const auto same_ints = [&](const char* key, const json& expected) {
            const std::vector<std::uint32_t>& got = b.ints(key);
            ASSERT_EQ(got.size(), expected.size()) << name << " " << key;
            for (std::size_t i = 0; i < got.size(); ++i)
                ASSERT_EQ(static_cast<long long>(got[i]), expected[i].get<long long>())
                    << name << " " << key << " " << i;
        };
        const auto same_floats = [&](const char* key, const json& expected) {
            const std::vector<double>& got = b.reals(key);
            ASSERT_EQ(got.size(), expected.size()) << name << " " << key;
            for (std::size_t i = 0; i < got.size(); ++i)
                ASSERT_EQ(got[i], static_cast<double>(static_cast<float>(expected[i].get<double>())))
                    << name << " " << key << " " << i;
        };
        same_floats("mesh.vertices", j["mesh"]["vertices"]);
        same_ints("mesh.hexes", j["mesh"]["hexes"]);
        same_floats("mesh.sj", j["mesh"]["sj"]);
        same_ints("mesh.singular_edges", j["mesh"]["singular_edges"]);
        same_ints("mesh.boundary_quads", j["mesh"]["boundary_quads"]);
        same_ints("mesh.boundary_hexes", j["mesh"]["boundary_hexes"]);
        same_floats("connection_surfaces.vertices", j["connection_surfaces"]["vertices"]);
        same_ints("connection_surfaces.quads", j["connection_surfaces"]["quads"]);
        EXPECT_FALSE(b.has("mesh.boundary_distance"));
        // 8 mesh / connection-surface arrays and the analysis' classes and kinds as enum arrays (restored into the
        // header above, so that its "analysis" equals the JSON answer's).
        EXPECT_EQ(b.names.size(), 10u);
        EXPECT_EQ(b.ints("analysis.vertex_class").size(), j["analysis"]["vertex_class"].size()) << name;
        EXPECT_EQ(b.ints("analysis.edge_kind").size(), j["analysis"]["edge_kind"].size()) << name;
    }
    // The default torus, a closed leaflet of 24 x 8 quads: one hex on each side of each quad (384 hexes), the mesh a
    // thick torus shell whose boundary is its two skins, one quad per hex (2 x 192).
    const auto rb = post(*s.client, "/api/mesh?stage=raw&encoding=binary", obj_text(generate_skeleton("torus")));
    const studio::DecodedAnswer b = studio::decode_binary_answer(rb->body);
    EXPECT_EQ(b.ints("mesh.hexes").size(), 8u * 384);
    EXPECT_EQ(b.ints("mesh.boundary_quads").size(), 4u * 2 * 192);
    // A bad encoding is a 400 and a rejected skeleton answers JSON whatever the encoding.
    const auto bad = post(*s.client, "/api/mesh?stage=raw&encoding=xml", obj_text(generate_skeleton("tfan")));
    ASSERT_TRUE(bad);
    EXPECT_EQ(bad->status, 400);
    EXPECT_EQ(body_json(bad)["error"]["code"], "BadRequest");
    const auto rejected = post(*s.client, "/api/mesh?stage=raw&encoding=binary", "v 0 0 0\nv 0 0 0\nl 1 2\n");
    ASSERT_TRUE(rejected);
    EXPECT_EQ(rejected->status, 422);
    EXPECT_EQ(body_json(rejected)["error"]["where"]["kind"], "skeleton_edge");
}

// The page uploads its skeleton as MHSK bytes (format=mhsk): the answer is the one the OBJ text of the same skeleton
// gets, byte for byte apart from the timings; a malformed upload is a 400 naming the element, and the server goes on.
TEST(StudioServer, BinarySkeletonUploadAnswersAsTheObjText) {
    auto s = start_studio({});
    for (const char* name : {"torus", "hand", "tfan", "chair"}) {
        const Skeleton sk = read_skeleton_text(obj_text(generate_skeleton(name)), "obj", name);
        const auto rt = post(*s.client, "/api/mesh?stage=raw", obj_text(sk));
        const auto rb =
            post(*s.client, "/api/mesh?stage=raw&format=mhsk", skeleton_binary(sk), "application/octet-stream");
        ASSERT_TRUE(rt && rb) << name;
        ASSERT_EQ(rb->status, 200) << name << ": " << rb->body.substr(0, 300);
        json jt = body_json(rt), jb = body_json(rb);
        for (json* j : {&jt, &jb})
            j->erase("server_ms"), j->erase("server_phases_ms"), (*j)["report"].erase("timings_ms");
        EXPECT_EQ(jb, jt) << name << ": " << json::diff(jt, jb).dump().substr(0, 600);
    }
    std::string bad = skeleton_binary(generate_skeleton("tfan"));
    bad.replace(32 + 24 * 3, 8, std::string("\x00\x00\x00\x00\x00\x00\xf8\x7f", 8));  // vertex 3's x = NaN
    const auto r = post(*s.client, "/api/mesh?stage=raw&format=mhsk", bad, "application/octet-stream");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400);
    EXPECT_EQ(body_json(r)["error"]["where"]["kind"], "skeleton_vertex");
    EXPECT_EQ(body_json(r)["error"]["where"]["index"], 3);
    const auto cut = post(*s.client, "/api/mesh?stage=raw&format=mhsk", bad.substr(0, 40), "application/octet-stream");
    ASSERT_TRUE(cut);
    EXPECT_EQ(cut->status, 400);
    const auto ok = post(*s.client, "/api/mesh?stage=raw", obj_text(generate_skeleton("tfan")));
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->status, 200);
}

// The binary reader refuses what is not a whole answer.
TEST(StudioServer, BinaryAnswerReaderRejectsTruncatedBodies) {
    studio::BinaryArrays arrays;
    studio::append_f32(arrays, "a", std::vector<double>{1.5, -2.0});
    studio::append_u32_cells(arrays, "b", std::vector<std::array<int, 2>>{{3, 4}});
    const std::string full = studio::binary_answer({{"x", 1}}, arrays);
    const studio::DecodedAnswer d = studio::decode_binary_answer(full);
    EXPECT_EQ(d.reals("a"), (std::vector<double>{1.5, -2.0}));
    EXPECT_EQ(d.ints("b"), (std::vector<std::uint32_t>{3, 4}));
    EXPECT_EQ(d.header["x"], 1);
    EXPECT_EQ(full.size() % 4, 0u);
    EXPECT_THROW(studio::decode_binary_answer(full.substr(0, full.size() - 4)), std::invalid_argument);
    EXPECT_THROW(studio::decode_binary_answer(full + "zzzz"), std::invalid_argument);
    EXPECT_THROW(studio::decode_binary_answer("MHXA" + full.substr(4)), std::invalid_argument);
    EXPECT_THROW(studio::decode_binary_answer(""), std::invalid_argument);
    // A header written as text: "arrays" appended as its last member, also to an empty object.
    EXPECT_EQ(studio::decode_binary_answer(studio::binary_answer_text("{\"x\": 1}", arrays)).header["x"], 1);
    const studio::DecodedAnswer e = studio::decode_binary_answer(studio::binary_answer_text("{}", arrays));
    EXPECT_EQ(e.header.size(), 1u);
    EXPECT_EQ(e.reals("a").size(), 2u);
    EXPECT_THROW(studio::binary_answer_text("[1]", arrays), std::invalid_argument);
}

// The bundled example: the same report keys and quality as `mesohex mesh --report` (raw mesh, no domain).
TEST(StudioServer, RawMeshReportEqualsTheCli) {
    const fs::path out = temp_dir() / "tripod_raw.vtu", report = temp_dir() / "tripod_raw.json";
    const auto cli = run_cli("mesh " + tripod_path() + " -o " + out.string() + " --report " + report.string());
    ASSERT_EQ(cli.status, 0) << cli.output;
    json expected;
    std::ifstream(report) >> expected;
    auto s = start_studio({});
    std::ifstream in(tripod_path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto r = post(*s.client, "/api/mesh?stage=raw", text);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
    const json rep = body_json(r)["report"];
    std::set<std::string> keys, cli_keys;
    for (const auto& [k, v] : rep.items()) keys.insert(k);
    for (const auto& [k, v] : expected.items()) cli_keys.insert(k);
    EXPECT_EQ(keys, cli_keys);
    EXPECT_EQ(rep["quality"]["hexes"], expected["quality"]["hexes"]);
    EXPECT_EQ(rep["quality"]["hexes"], 176);  // 44 adapted branch edges x 4
    EXPECT_EQ(rep["quality"]["sj_min"], expected["quality"]["sj_min"]);
    EXPECT_EQ(rep["quality"]["sj_avg"], expected["quality"]["sj_avg"]);
    EXPECT_EQ(rep["predicted"], expected["predicted"]);
    EXPECT_EQ(rep["skeleton"], expected["skeleton"]);
}

// Classes of data/tiny/tripod.obj by hand: vertex 4 has four branch edges (BranchingPoint), vertices 0, 8, 12, 16
// one (Extremity), the others two (Joint). Prediction = the raw mesh's count.
TEST(StudioServer, AnalyzeGivesTheClassesAndThePrediction) {
    auto s = start_studio({});
    std::ifstream in(tripod_path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto r = post(*s.client, "/api/analyze", text);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const json j = body_json(r);
    ASSERT_EQ(j["vertex_class"].size(), 17u);
    for (int v = 0; v < 17; ++v) {
        const std::string expected = v == 4                                     ? "BranchingPoint"
                                     : (v == 0 || v == 8 || v == 12 || v == 16) ? "Extremity"
                                                                                : "Joint";
        EXPECT_EQ(j["vertex_class"][v], expected) << v;
    }
    EXPECT_EQ(j["edge_kind"], json(std::vector<std::string>(16, "branch")));
    EXPECT_EQ(j["counts"]["branching_points"], 1);
    EXPECT_EQ(j["counts"]["extremities"], 4);
    EXPECT_EQ(j["predicted"]["hexes"], 176);
}

// A branch on a fan-edge end continuing the fan line (generator fanend): /api/mesh meshes it standing on the fan
// block's cap, so /api/analyze accepts it too and lists it (the input vertex of the branch, a fan-edge end); with a
// thick branch leaning
// back from the fan line (135 degrees, radius 0.39 x the border side: too thick to be bent) both refuse it, naming the
// same vertex.
TEST(StudioServer, AnalyzeAcceptsWhatMeshRepairs) {
    auto s = start_studio({});
    GeneratorOptions o;
    o.m = 1;
    const std::string continuing = obj_text(generate_skeleton("fanend", o));
    const auto a = post(*s.client, "/api/analyze", continuing);
    ASSERT_TRUE(a);
    ASSERT_EQ(a->status, 200) << a->body;
    const json j = body_json(a);
    // The branch continues the fan line: it stands on the fan block's cap (no retraction; design note C1).
    EXPECT_TRUE(j["repairs"]["fan_end_retractions"].empty()) << a->body;
    ASSERT_EQ(j["repairs"]["fan_cap_branches"].size(), 1u) << a->body;
    const int v = j["repairs"]["fan_cap_branches"][0];
    EXPECT_EQ(j["vertex_class"][v], "FanEdgeEnd") << a->body;
    const auto m = post(*s.client, "/api/mesh?stage=raw", continuing);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->status, 200) << m->body.substr(0, 300);
    EXPECT_EQ(body_json(m)["report"]["predicted"]["hexes"], j["predicted"]["hexes"]);
    // The X leaning back 135 degrees between two leaflets: bent at the default radius, refused when thick (a bend takes
    // r <= 0.3 x side there: its tube runs into the +x strip's plate; the T leaning back over its empty side is bent).
    o.n = 4;
    o.m = 5;
    o.radius_scale = 1.3;
    const std::string perpendicular = obj_text(generate_skeleton("fanend", o));
    json where[2];
    int k = 0;
    for (const char* endpoint : {"/api/analyze", "/api/mesh?stage=raw"}) {
        const auto r = post(*s.client, endpoint, perpendicular);
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 422) << endpoint << ": " << r->body;
        EXPECT_EQ(body_json(r)["error"]["code"], "UnsupportedConfiguration") << r->body;
        where[k++] = body_json(r)["error"]["where"];
    }
    EXPECT_EQ(where[0], where[1]);
    EXPECT_EQ(where[0]["kind"], "skeleton_vertex");
}

// A plate (3 x 3 quads) with two branch edges on one interior vertex: analysis rejects it (paper limitation 1) and
// names the vertex; the page gets 422 with where = that vertex. A zero-length edge is named as an edge.
TEST(StudioServer, RejectedSkeletonsNameTheElement) {
    auto s = start_studio({});
    Skeleton plate = generate_skeleton("plate");
    // Interior vertex: in 4 faces.
    std::vector<int> faces_at(plate.points.size(), 0);
    for (const auto& f : plate.faces)
        for (const int v : f) ++faces_at[v];
    int interior = -1;
    for (std::size_t v = 0; v < faces_at.size(); ++v)
        if (faces_at[v] == 4) interior = static_cast<int>(v);
    ASSERT_GE(interior, 0);
    for (const Vec3 d : {Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
        plate.points.push_back(plate.points[interior] + d);
        plate.radii.push_back(plate.radii[interior]);
        plate.edges.push_back({interior, static_cast<int>(plate.points.size()) - 1});
    }
    for (const char* endpoint : {"/api/analyze", "/api/mesh?stage=raw"}) {
        const auto r = post(*s.client, endpoint, obj_text(plate));
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 422) << endpoint << ": " << r->body;
        const json e = body_json(r)["error"];
        EXPECT_EQ(e["code"], "UnsupportedConfiguration") << r->body;
        EXPECT_EQ(e["where"]["kind"], "skeleton_vertex") << r->body;
        EXPECT_EQ(e["where"]["index"], interior) << r->body;
    }
    const auto r = post(*s.client, "/api/mesh", "v 0 0 0\nv 0 0 0\nv 1 0 0\nl 1 2\nl 2 3\n");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 422) << r->body;
    EXPECT_EQ(body_json(r)["error"]["where"]["kind"], "skeleton_edge") << r->body;
    EXPECT_EQ(body_json(r)["error"]["where"]["index"], 0) << r->body;
}

// Bad requests of every kind get a 4xx JSON error, and the server keeps answering.
// A POST without Content-Length (and not chunked) has no body (`curl -X POST`): read as empty instead of waiting for
// the connection to close and failing with 400 "could not read the request body".
TEST(StudioServer, PostWithoutContentLengthHasAnEmptyBody) {
    auto s = start_studio({});
    const std::string head = " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
    EXPECT_EQ(raw_request_status(s.port, "POST /api/auto-skeleton" + head), 409);  // needs a domain
    EXPECT_EQ(raw_request_status(s.port, "POST /api/save" + head), 403);           // no --save target
}

TEST(StudioServer, MalformedRequestsGet4xxJsonAndTheServerKeepsAnswering) {
    auto s = start_studio({});
    struct Case {
        std::string method, path, body;
        int status;
        std::string code;
    };
    const std::vector<Case> cases = {
        {"POST", "/api/mesh", "v 1 2\n", 400, "InvalidInput"},
        {"POST", "/api/mesh", std::string("v 0 0 0\0v 1 1 1\n", 16), 400, "InvalidInput"},
        {"POST", "/api/mesh", "v 0 0 0\nv 1 0 0\nl 1 7\n", 400, "InvalidInput"},
        {"POST", "/api/mesh", "v 0 0 \xff\xfe\n", 400, "InvalidInput"},  // invalid UTF-8 quoted in the message
        {"POST", "/api/mesh?format=stl", "v 0 0 0\n", 400, "InvalidInput"},
        {"POST", "/api/mesh?stage=cooked", "v 0 0 0\n", 400, "BadRequest"},
        {"POST", "/api/mesh?stage=final", "v 0 0 0\n", 409, "BadRequest"},
        {"POST", "/api/mesh", "", 400, ""},
        {"POST", "/api/mesh?format=ig", "IG\n99999999999 0 0\n", 400, "InvalidInput"},
        {"POST", "/api/analyze", "f 1 2 3 4\n", 400, "InvalidInput"},
        {"POST", "/api/parse?format=skel", "garbage\n", 400, "InvalidInput"},
        {"POST", "/api/serialize", "{not json", 400, "BadRequest"},
        {"POST", "/api/serialize", "[1,2]", 400, "BadRequest"},
        {"POST", "/api/serialize", R"({"points": [[0,0,"x"]]})", 400, "BadRequest"},
        {"POST", "/api/serialize", R"({"points": [[0,0,0]], "edges": [[0,5]]})", 400, "InvalidInput"},
        {"POST", "/api/serialize?format=vtk", R"({"points": []})", 400, "BadRequest"},
        {"POST", "/api/import?format=ma", "3 2\n", 400, ""},
        {"POST", "/api/import?format=ma", "1 0 0\nv 0 0 0 -1\n", 400, ""},
        {"POST", "/api/import?format=obj", "", 400, "BadRequest"},
        {"POST", "/api/save", "v 0 0 0\n", 403, "Forbidden"},
        {"POST", "/api/auto-skeleton", "", 409, "BadRequest"},
        {"POST", "/api/radius-from-domain", "v 0 0 0\n", 409, "BadRequest"},
        {"POST", "/api/snap-medial", R"({"points": [[0,0,0]]})", 409, "BadRequest"},
        {"POST", "/api/jobs", "v 0 0 0\n", 409, "BadRequest"},
        {"GET", "/api/jobs/77", "", 404, "NotFound"},
        {"DELETE", "/api/jobs/77", "", 404, "NotFound"},
        {"GET", "/api/jobs/77/events", "", 404, "NotFound"},
        {"GET", "/api/nothing", "", 404, "NotFound"},
        {"POST", "/api/nothing", "x", 404, "NotFound"},
        {"PUT", "/api/mesh", "x", 404, "NotFound"},
    };
    for (const Case& c : cases) {
        httplib::Result r = c.method == "GET"      ? s.client->Get(c.path.c_str())
                            : c.method == "DELETE" ? s.client->Delete(c.path.c_str())
                            : c.method == "PUT"    ? s.client->Put(c.path.c_str(), c.body, "text/plain")
                                                   : post(*s.client, c.path, c.body);
        ASSERT_TRUE(r) << c.method << " " << c.path;
        EXPECT_EQ(r->status, c.status) << c.method << " " << c.path << ": " << r->body;
        const json j = body_json(r);
        ASSERT_TRUE(j.contains("error")) << c.method << " " << c.path << ": " << r->body;
        EXPECT_TRUE(j["error"]["message"].is_string());
        EXPECT_TRUE(j["error"]["where"].is_object());
        if (!c.code.empty()) {
            EXPECT_EQ(j["error"]["code"], c.code) << c.method << " " << c.path << ": " << r->body;
        }
        const auto alive = s.client->Get("/api/session");
        ASSERT_TRUE(alive);
        EXPECT_EQ(alive->status, 200);
    }
    // The line of a parse error is named.
    const auto r = post(*s.client, "/api/mesh", "v 0 0 0\nv 1 0 0\nl 1 2\nv 1 x 0\n");
    ASSERT_TRUE(r);
    EXPECT_EQ(body_json(r)["error"]["where"], json({{"kind", "line"}, {"index", 4}})) << r->body;
}

TEST(StudioServer, OversizedBodyGets413AndTheServerKeepsAnswering) {
    studio::StudioOptions options;
    options.max_body_bytes = 1000;
    auto s = start_studio({}, {}, options);
    const auto big = post(*s.client, "/api/mesh", std::string(5000, '#'));
    ASSERT_TRUE(big);
    EXPECT_EQ(big->status, 413);
    EXPECT_EQ(body_json(big)["error"]["code"], "PayloadTooLarge") << big->body;
    // Without a Content-Length (chunked), the limit holds too (counted while reading).
    const auto chunked = s.client->Post(
        "/api/mesh",
        [](std::size_t offset, httplib::DataSink& sink) {
            const std::string chunk(500, '#');
            if (offset < 5000)
                sink.write(chunk.data(), chunk.size());
            else
                sink.done();
            return true;
        },
        "text/plain");
    // (The server answers 413 and stops reading; the client may see that, or only the connection closed while it
    // was still sending. Accepted, the '#' comment lines would have given 400: no skeleton.)
    if (chunked) {
        EXPECT_EQ(chunked->status, 413) << chunked->body;
        EXPECT_EQ(body_json(chunked)["error"]["code"], "PayloadTooLarge") << chunked->body;
    }
    const auto small = post(*s.client, "/api/parse", "v 0 0 0\nv 1 0 0\nl 1 2\n");
    ASSERT_TRUE(small);
    EXPECT_EQ(small->status, 200) << small->body;
    EXPECT_EQ(body_json(small)["skeleton"]["edges"], json::array({json::array({0, 1})}));
}

// `curl --data-binary @file` sends application/x-www-form-urlencoded: the body is still the file's text (no form
// decoding, no 8 KiB form limit); a body parameter named format does not override the query.
TEST(StudioServer, FormEncodedContentTypeIsReadAsPlainText) {
    auto s = start_studio({});
    const Skeleton torus = generate_skeleton("torus");  // 24 x 8 quads: 192 faces, 384 raw hexes
    const std::string text = obj_text(torus) + "# format=ig&stage=final\n";
    ASSERT_GT(text.size(), 8192u);
    const auto r = post(*s.client, "/api/mesh?stage=raw", text, "application/x-www-form-urlencoded");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
    EXPECT_EQ(body_json(r)["report"]["quality"]["hexes"], 384);
}

// Answers are never compressed (loopback), whatever the client accepts: the JSON and the static files alike.
TEST(StudioServer, AnswersAreNotCompressed) {
    studio::StaticFiles files;
    files.by_url["/app/main.js"] = {"text/javascript; charset=utf-8", std::string(20000, ' ') + "export {};"};
    auto s = start_studio({}, files);
    s.client->set_decompress(false);
    const httplib::Headers accept{{"Accept-Encoding", "gzip, deflate, br"}};
    const auto r = s.client->Post("/api/mesh?stage=raw", accept, obj_text(generate_skeleton("plate")), "text/plain");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200);
    EXPECT_FALSE(r->has_header("Content-Encoding")) << r->get_header_value("Content-Encoding");
    EXPECT_EQ(body_json(r)["report"]["quality"]["hexes"], 42);  // plate 3 x 3: 2 x 9 plate + 2 x 12 half-chunk hexes
    const auto js = s.client->Get("/app/main.js", accept);
    ASSERT_TRUE(js);
    EXPECT_FALSE(js->has_header("Content-Encoding")) << js->get_header_value("Content-Encoding");
    EXPECT_EQ(js->body.size(), 20010u);
}

// Skeleton JSON -> OBJ / IG text -> parse: the same skeleton, radii included.
TEST(StudioServer, SerializeAndParseRoundTrip) {
    auto s = start_studio({});
    const Skeleton plate = generate_skeleton("plate", {.n = 2, .m = 1});
    const json sj = studio::skeleton_json(plate);
    for (const std::string format : {"obj", "ig"}) {
        const auto text = post(*s.client, "/api/serialize?format=" + format, sj.dump(), "application/json");
        ASSERT_TRUE(text);
        ASSERT_EQ(text->status, 200) << text->body;
        EXPECT_EQ(text->body, skeleton_text(plate, format, "x"));
        const auto parsed = post(*s.client, "/api/parse?format=" + format, text->body);
        ASSERT_TRUE(parsed);
        ASSERT_EQ(parsed->status, 200) << parsed->body;
        EXPECT_EQ(studio::skeleton_from_json(body_json(parsed)["skeleton"]), plate) << format;
    }
}

TEST(StudioServer, SaveWritesTheTargetFile) {
    const fs::path target = temp_dir() / "saved.ig";
    fs::remove(target);
    studio::StudioSession session;
    session.save_target = target.string();
    auto s = start_studio(session);
    EXPECT_EQ(body_json(s.client->Get("/api/session"))["save_target"], target.string());
    std::ifstream in(tripod_path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto r = post(*s.client, "/api/save?format=obj", text);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_EQ(body_json(r)["saved"], target.string());
    EXPECT_EQ(read_skeleton(target.string()), read_skeleton(tripod_path()));
}

// In the box [-1, 1]^3: radius = 0.5 x distance to the nearest face; the medial position of (0.5, 0.2, 0) (inside)
// and of (2, 0.2, 0) (outside) is (0, 0.2, 0), midway between the faces x = 1 and x = -1.
TEST(StudioServer, RadiusFromDomainAndSnapToTheMedialPosition) {
    studio::StudioSession session;
    session.domain = unit_box();
    session.domain_name = "box";
    auto s = start_studio(session);
    const json sess = body_json(s.client->Get("/api/session"));
    EXPECT_EQ(sess["domain"]["name"], "box");
    EXPECT_EQ(sess["domain"]["vertices"].size(), 24u);
    EXPECT_EQ(sess["domain"]["triangles"].size(), 36u);
    EXPECT_NEAR(sess["domain"]["bbox_diagonal"].get<double>(), std::sqrt(12.0), 1e-12);
    const auto r = post(*s.client, "/api/radius-from-domain", "v 0 0 0\nv 0.5 0 0\nv 0 0.9 0\nl 1 2\nl 1 3\n");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const json radii = body_json(r)["radii"];
    ASSERT_EQ(radii.size(), 3u);
    EXPECT_NEAR(radii[0].get<double>(), 0.5, 1e-12);
    EXPECT_NEAR(radii[1].get<double>(), 0.25, 1e-12);
    EXPECT_NEAR(radii[2].get<double>(), 0.05, 1e-12);
    const auto m =
        post(*s.client, "/api/snap-medial", R"({"points": [[0.5, 0.2, 0], [2, 0.2, 0]]})", "application/json");
    ASSERT_TRUE(m);
    ASSERT_EQ(m->status, 200) << m->body;
    const json pts = body_json(m)["points"];
    ASSERT_EQ(pts.size(), 2u);
    for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(pts[i][0].get<double>(), 0.0, 1e-9) << i;
        EXPECT_NEAR(pts[i][1].get<double>(), 0.2, 1e-9) << i;
        EXPECT_NEAR(pts[i][2].get<double>(), 0.0, 1e-9) << i;
    }
}

// A .ma with a curve only (3 vertices, 2 edges): imported as one branch, radii kept.
TEST(StudioServer, ImportsAMedialMeshFromTheBody) {
    auto s = start_studio({});
    const auto r =
        post(*s.client, "/api/import?format=ma", "3 2 0\nv 0 0 0 0.1\nv 1 0 0 0.2\nv 2 0 0 0.3\ne 0 1\ne 1 2\n");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const json j = body_json(r);
    EXPECT_EQ(j["skeleton"]["points"].size(), 3u);
    EXPECT_EQ(j["skeleton"]["edges"].size(), 2u);
    EXPECT_EQ(j["skeleton"]["radii"], json::array({0.1, 0.2, 0.3}));
    EXPECT_EQ(read_skeleton_text(j["obj"].get<std::string>(), "obj", "x").points.size(), 3u);
}

// The readers on text (what the server uses) give what the file readers give, and name the text's stand-in name.
TEST(StudioServer, TextReadersMatchTheFileReaders) {
    std::ifstream in(tripod_path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(read_skeleton_text(text, "OBJ", "body"), read_skeleton(tripod_path()));
    std::string message = "accepted";
    try {
        read_skeleton_text("v 0 0 0\nl 1 2\n", "obj", "body");  // an edge to a missing vertex
    } catch (const std::exception& e) {
        message = e.what();
    }
    EXPECT_EQ(message.rfind("body:2:", 0), 0u) << message;
    EXPECT_THROW(read_skeleton_text(text, "stl", "body"), mesohex::Error);
    const fs::path ma = temp_dir() / "curve.ma";
    const std::string ma_text = "3 2 0\nv 0 0 0 0.1\nv 1 0 0 0.2\nv 2 0 0 0.3\ne 0 1\ne 1 2\n";
    std::ofstream(ma) << ma_text;
    EXPECT_EQ(read_medial_mesh_text(ma_text, "body"), read_medial_mesh(ma.string()));
    EXPECT_EQ(skeleton_text(read_skeleton(tripod_path()), "ig", "x").rfind("IG\n17 16 0\n", 0), 0u);
}
