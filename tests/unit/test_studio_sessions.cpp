// Editing sessions and skeleton deltas (apps/studio/sessions.h, /api/mesh?session=&format=delta): the incremental
// raw run (mesh_skeleton_raw) gives mesh_skeleton's answer byte for byte after random edits; a delta sequence over
// HTTP answers what full uploads of the same skeletons answer; malformed deltas are 400 JSON leaving the session as it
// was; unknown, stale and dropped sessions are 409 "SendFullSkeleton".
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "bench_inputs.h"
#include "binary_answer.h"
#include "meshing.h"
#include "mesohex/core/error.h"
#include "mesohex/mesh.h"
#include "mesohex/stages/generators.h"
#include "mesohex_io/skeleton_io.h"
#include "sessions.h"
#include "studio_fixtures.h"

using nlohmann::json;
using namespace mesohex;
using mesohex::test::body_json;
using mesohex::test::start_studio;

namespace {

// The JSON answer without its wall times (server_ms, server_phases_ms, report.timings_ms): what must not differ.
json without_times(const std::string& answer) {
    json j = json::parse(answer);
    j.erase("server_ms");
    j.erase("server_phases_ms");
    j["report"].erase("timings_ms");
    return j;
}

// Moves 1-3 random vertices by up to 8 % of their radius per axis, sometimes scales a radius by 0.9-1.1.
Skeleton random_edit(const Skeleton& s, std::mt19937& rng) {
    Skeleton next = s;
    const int k = 1 + static_cast<int>(rng() % 3);
    for (int j = 0; j < k; ++j) {
        const int v = static_cast<int>(rng() % next.points.size());
        const double r = next.radii.empty() ? 0.05 : next.radii[v];
        const double step = 0.08 * r;
        next.points[v] += Vec3{step * (2 * bench::unit_draw(rng) - 1), step * (2 * bench::unit_draw(rng) - 1),
                               step * (2 * bench::unit_draw(rng) - 1)};
        if (!next.radii.empty() && rng() % 4 == 0) next.radii[v] *= 0.9 + 0.2 * bench::unit_draw(rng);
    }
    return next;
}

// mesh_response with a session cache after each random edit equals mesh_response without one (every byte of the JSON
// answer but the times); rejected skeletons are rejected by both, and the run after one is still equal. Returns the
// number of runs that were incremental (the adapted skeleton kept its topology).
int random_session(const Skeleton& start, int edits, std::uint32_t seed) {
    std::mt19937 rng(seed);
    studio::MeshRequest request;
    RawRunCache cache;
    Skeleton s = start;
    int equal = 0;
    bool warm = false;  // the cache holds the last skeleton's run
    int incremental_runs = 0;
    for (int i = 0; i <= edits; ++i) {
        const Skeleton next = i == 0 ? start : random_edit(s, rng);
        std::string full;
        try {
            full = studio::mesh_response(next, nullptr, request);
        } catch (const Error&) {
            EXPECT_THROW(studio::mesh_response(next, nullptr, request, nullptr, &cache), Error);
            EXPECT_FALSE(cache.valid);
            warm = false;
            continue;
        }
        const std::string incremental = studio::mesh_response(next, nullptr, request, nullptr, &cache);
        EXPECT_TRUE(cache.valid);
        if (warm && !cache.last.full) ++incremental_runs;
        warm = true;
        EXPECT_EQ(without_times(incremental), without_times(full)) << "edit " << i;
        s = next;
        ++equal;
    }
    EXPECT_GE(equal, edits / 2);
    return incremental_runs;
}

// The decoded arrays of a binary answer made of `arrays` (a patch needs the previous answer's decoded arrays).
studio::DecodedAnswer decoded(const studio::BinaryArrays& arrays, const studio::DecodedAnswer* previous = nullptr) {
    return studio::decode_binary_answer(studio::binary_answer(json::object(), arrays), previous);
}

// Array i of a row patch came as `rows` runs of copied rows and `literal` literal rows.
void expect_row_runs(const studio::BinaryArrays& patch, std::size_t i, int rows, int literal) {
    EXPECT_EQ(patch.list[i]["rows"], rows) << "array " << i;
    EXPECT_EQ(patch.list[i]["literal"], literal) << "array " << i;
}

}  // namespace

TEST(StudioSessions, IncrementalRawRunEqualsFullRunOnRandomEdits) {
    // Moves on a leaflet-only skeleton keep the adapted topology: every run after the first is incremental. On
    // branches the adaptation's resampling may change the topology (then the run is a full one).
    EXPECT_EQ(random_session(generate_skeleton("torus"), 5, 3), 5);
    EXPECT_GE(random_session(bench::random_tree(300, 5), 8, 1), 1);
    for (const char* name : {"hand", "dualocta", "bird", "torustwist", "plate"}) {
        SCOPED_TRACE(name);
        random_session(generate_skeleton(name), 5, 2);
    }
}

// A vertex moved and moved back, then a topology change (one edge removed from a tree): the cache follows.
TEST(StudioSessions, IncrementalRawRunAfterATopologyChange) {
    const Skeleton tree = bench::random_tree(120, 3);
    studio::MeshRequest request;
    RawRunCache cache;
    const std::string first = studio::mesh_response(tree, nullptr, request, nullptr, &cache);
    Skeleton cut = tree;
    cut.edges.pop_back();
    EXPECT_EQ(without_times(studio::mesh_response(cut, nullptr, request, nullptr, &cache)),
              without_times(studio::mesh_response(cut, nullptr, request)));
    EXPECT_EQ(without_times(studio::mesh_response(tree, nullptr, request, nullptr, &cache)), without_times(first));
}

// Branching points of a random tree moved by (0.02, 0.01, 0) one after the other, as the studio's drag sends them:
// whenever the adaptation renumbers the prepared skeleton (the run is no incremental one by index), the memo still
// serves most branching-point surfaces, and the answer equals the sessionless one byte for byte (but the times).
TEST(StudioSessions, BranchingPointMovesThatRenumberTheAdaptedSkeleton) {
    const Skeleton tree = bench::random_tree(600, 5);
    studio::MeshRequest request;
    RawRunCache cache;
    studio::mesh_response(tree, nullptr, request, nullptr, &cache);
    const SkeletonAnalysis an = analyze_skeleton(tree);
    Skeleton s = tree;
    int renumbered = 0, v = 0;
    for (int edit = 0; edit < 5; ++edit) {
        while (an.vertex_class[static_cast<std::size_t>(v)] != VertexClass::BranchingPoint) ++v;
        s.points[static_cast<std::size_t>(v++)] += Vec3{0.02, 0.01, 0};
        const std::size_t before = cache.remesh.skeleton.points.size();
        const std::string incremental = studio::mesh_response(s, nullptr, request, nullptr, &cache);
        EXPECT_EQ(without_times(incremental), without_times(studio::mesh_response(s, nullptr, request))) << edit;
        ASSERT_TRUE(cache.valid);
        if (cache.remesh.skeleton.points.size() != before) {
            ++renumbered;
            EXPECT_TRUE(cache.last.full);
            EXPECT_GT(cache.last.memo_surfaces, cache.last.computed_partitions) << edit;
        }
    }
    EXPECT_GE(renumbered, 1);
}

TEST(StudioSessions, DeltaRoundTripAndMalformedDeltas) {
    Skeleton a = generate_skeleton("torus", {.n = 12, .m = 6});
    Skeleton b = a;
    b.points[3] += Vec3{0.01, 0, 0};
    b.radii[5] *= 1.05;
    const std::string d = studio::skeleton_delta_binary(a, b);
    EXPECT_EQ(d.size(), 20u + 2 * (4 + 24 + 8));  // vertices 3 and 5
    EXPECT_EQ(studio::apply_skeleton_delta(a, d), b);
    EXPECT_EQ(studio::apply_skeleton_delta(a, studio::skeleton_delta_binary(a, a)), a);  // K = 0
    const auto rejects = [&](std::string bytes) { EXPECT_THROW(studio::apply_skeleton_delta(a, bytes), Error); };
    rejects("");
    rejects(d.substr(0, 19));
    rejects(d + "x");
    rejects("MHSK" + d.substr(4));
    std::string bad = d;
    bad[4] = 2;  // version
    rejects(bad);
    bad = d;
    bad[8] = static_cast<char>(bad[8] + 1);  // V
    rejects(bad);
    bad = d;
    bad[16] = 0;  // no radii (the skeleton has them): the length no longer matches either
    rejects(bad);
    bad = d;
    bad[20] = 5, bad[24] = 3;  // indices not increasing
    rejects(bad);
    bad = d;
    bad[24] = static_cast<char>(0xff), bad[25] = static_cast<char>(0xff);  // index out of range
    rejects(bad);
    Skeleton nan = a;
    nan.points[2].y = std::numeric_limits<double>::quiet_NaN();
    rejects(studio::skeleton_delta_binary(a, nan));
    Skeleton zero = a;
    zero.radii[2] = 0;
    rejects(studio::skeleton_delta_binary(a, zero));
    // Random byte flips and truncations: an error or a skeleton with a's topology, never anything else.
    std::mt19937 rng(3);
    int accepted = 0;
    for (int i = 0; i < 2000; ++i) {
        std::string bytes = d;
        for (int k = 1 + static_cast<int>(rng() % 3); k > 0; --k)
            bytes[rng() % bytes.size()] = static_cast<char>(rng() & 0xffu);
        if (rng() % 4 == 0) bytes.resize(rng() % bytes.size());
        try {
            const Skeleton out = studio::apply_skeleton_delta(a, bytes);
            EXPECT_EQ(out.edges, a.edges);
            EXPECT_EQ(out.points.size(), a.points.size());
            ++accepted;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
        }
    }
    EXPECT_GT(accepted, 0);  // flips of coordinate bits give valid deltas too
}

TEST(StudioSessions, SessionIds) {
    EXPECT_TRUE(studio::valid_session_id("page-ab12_x.y"));
    EXPECT_FALSE(studio::valid_session_id(""));
    EXPECT_FALSE(studio::valid_session_id(std::string(65, 'a')));
    EXPECT_FALSE(studio::valid_session_id("a/b"));
    EXPECT_FALSE(studio::valid_session_id("a b"));
}

TEST(StudioSessions, LeastRecentlyUsedSessionIsDropped) {
    studio::MeshSessions sessions(2);
    const auto a = sessions.find_or_create("a");
    sessions.find_or_create("b");
    EXPECT_EQ(sessions.find("a"), a);  // a is now the most recent
    sessions.find_or_create("c");      // drops b
    EXPECT_EQ(sessions.size(), 2u);
    EXPECT_EQ(sessions.find("b"), nullptr);
    EXPECT_EQ(sessions.find("a"), a);
    EXPECT_NE(sessions.find("c"), nullptr);
}

// Over HTTP: a full upload opens the session, deltas follow; each answer equals the sessionless full upload of the
// same skeleton (JSON, without the times); errors are JSON and leave the session usable.
TEST(StudioSessions, DeltaUploadsOverHttp) {
    studio::StudioOptions options;
    options.mesh_sessions = 2;
    auto studio = start_studio({}, {}, options);
    httplib::Client& c = *studio.client;
    const auto post = [&](const std::string& query, const std::string& body) {
        return c.Post(("/api/mesh?stage=raw&" + query).c_str(), body, "application/octet-stream");
    };
    Skeleton s = generate_skeleton("torus", {.n = 24, .m = 8});
    auto r = post("format=mhsk&session=p1&revision=1", skeleton_binary(s));
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_EQ(without_times(r->body), without_times(post("format=mhsk", skeleton_binary(s))->body));
    std::mt19937 rng(7);
    long long revision = 1;
    for (int i = 0; i < 4; ++i) {
        const Skeleton next = random_edit(s, rng);
        r = post(
            "format=delta&session=p1&base=" + std::to_string(revision) + "&revision=" + std::to_string(revision + 1),
            studio::skeleton_delta_binary(s, next));
        ASSERT_TRUE(r);
        ASSERT_EQ(r->status, 200) << r->body;
        EXPECT_EQ(without_times(r->body), without_times(post("format=mhsk", skeleton_binary(next))->body));
        s = next, ++revision;
    }
    // The binary answer of a delta request decodes to the same header as the full one's.
    const Skeleton moved = random_edit(s, rng);
    r = post("format=delta&encoding=binary&session=p1&base=" + std::to_string(revision) + "&revision=99",
             studio::skeleton_delta_binary(s, moved));
    ASSERT_EQ(r->status, 200) << r->body;
    const auto full = post("format=mhsk&encoding=binary", skeleton_binary(moved));
    EXPECT_EQ(studio::decode_binary_answer(r->body).u32, studio::decode_binary_answer(full->body).u32);
    EXPECT_EQ(studio::decode_binary_answer(r->body).f32, studio::decode_binary_answer(full->body).f32);
    s = moved, revision = 99;
    const std::string next = "&revision=100";
    const std::string base = "format=delta&session=p1&base=99";

    const auto expect_error = [&](const httplib::Result& res, int status, const std::string& code) {
        ASSERT_TRUE(res);
        EXPECT_EQ(res->status, status) << res->body;
        EXPECT_EQ(body_json(res)["error"]["code"], code) << res->body;
    };
    // Malformed deltas: 400, the session keeps revision 99.
    expect_error(post(base + next, "MHSD"), 400, "InvalidInput");
    std::string wrong = studio::skeleton_delta_binary(s, s);
    wrong[8] = 1;  // vertex count
    expect_error(post(base + next, wrong), 400, "InvalidInput");
    Skeleton bad = s;
    bad.radii[0] = -1;
    const auto neg = post(base + next, studio::skeleton_delta_binary(s, bad));
    expect_error(neg, 400, "InvalidInput");
    EXPECT_EQ(body_json(neg)["error"]["where"]["kind"], "skeleton_vertex");
    expect_error(post(base, studio::skeleton_delta_binary(s, s)), 400, "BadRequest");  // no revision
    expect_error(post(base + "&revision=-3", studio::skeleton_delta_binary(s, s)), 400, "BadRequest");
    expect_error(post("format=delta&base=99&revision=100", studio::skeleton_delta_binary(s, s)), 400, "BadRequest");
    expect_error(post("format=delta&session=a%2Fb&base=99&revision=100", ""), 400, "BadRequest");
    expect_error(c.Post("/api/mesh?stage=final&format=mhsk&session=p1&revision=5", skeleton_binary(s),
                        "application/octet-stream"),
                 400, "BadRequest");
    // Stale base, unknown session: 409, send the full skeleton.
    expect_error(post("format=delta&session=p1&base=98&revision=100", studio::skeleton_delta_binary(s, s)), 409,
                 "SendFullSkeleton");
    expect_error(post("format=delta&session=nobody&base=1&revision=2", studio::skeleton_delta_binary(s, s)), 409,
                 "SendFullSkeleton");
    // Still at 99 after all that.
    r = post(base + next, studio::skeleton_delta_binary(s, s));
    ASSERT_EQ(r->status, 200) << r->body;
    EXPECT_EQ(without_times(r->body), without_times(post("format=mhsk", skeleton_binary(s))->body));
    // Two newer sessions drop p1 (2 kept).
    ASSERT_EQ(post("format=mhsk&session=p2&revision=1", skeleton_binary(s))->status, 200);
    ASSERT_EQ(post("format=mhsk&session=p3&revision=1", skeleton_binary(s))->status, 200);
    expect_error(post("format=delta&session=p1&base=100&revision=101", studio::skeleton_delta_binary(s, s)), 409,
                 "SendFullSkeleton");
    EXPECT_EQ(post("format=delta&session=p3&base=1&revision=2", studio::skeleton_delta_binary(s, s))->status, 200);
    // The server still answers.
    EXPECT_EQ(c.Get("/api/session")->status, 200);
}

// patch_arrays: unchanged arrays become "patch": 0, one changed value "patch": 1 with its index and value, arrays of
// another length or changed in half their values or more stay whole.
TEST(StudioSessions, PatchArrays) {
    studio::BinaryArrays base, full;
    studio::append_f32(base, "a", std::vector<double>{1, 2, 3, 4});
    studio::append_f32(base, "b", std::vector<double>{1, 2});
    studio::append_f32(base, "c", std::vector<double>{1, 2, 3, 4});
    studio::append_f32(base, "d", std::vector<double>{1, 2, 3, 4});
    studio::append_f32(full, "a", std::vector<double>{1, 2, 3, 4});
    studio::append_f32(full, "b", std::vector<double>{1, 2, 3});
    studio::append_f32(full, "c", std::vector<double>{1, 2, 3.5, 4});
    studio::append_f32(full, "d", std::vector<double>{1, 0, 0, 4});
    const studio::BinaryArrays p = studio::patch_arrays(base, full);
    EXPECT_EQ(p.list[0]["patch"], 0);
    EXPECT_FALSE(p.list[1].contains("patch"));
    EXPECT_EQ(p.list[2]["patch"], 1);
    EXPECT_FALSE(p.list[3].contains("patch"));
    EXPECT_EQ(p.bytes.size(), 3 * 4 + 8 + 4 * 4u);
    const studio::DecodedAnswer previous = decoded(base);
    const studio::DecodedAnswer d = decoded(p, &previous);
    const studio::DecodedAnswer whole = decoded(full);
    EXPECT_EQ(d.f32, whole.f32);
    EXPECT_THROW(decoded(p), std::invalid_argument);
}

// Over HTTP: with since=R (the session's last answer) a binary answer is a patch of it, much smaller, decoding to
// the whole answer; a since that is not the session's last answer gets a whole answer.
TEST(StudioSessions, PatchAnswersOverHttp) {
    auto studio = start_studio({});
    httplib::Client& c = *studio.client;
    const auto post = [&](const std::string& query, const std::string& body) {
        return c.Post(("/api/mesh?stage=raw&encoding=binary&" + query).c_str(), body, "application/octet-stream");
    };
    const auto same = [](const studio::DecodedAnswer& a, const studio::DecodedAnswer& b) {
        EXPECT_EQ(a.names, b.names);
        EXPECT_EQ(a.f32, b.f32);
        EXPECT_EQ(a.u32, b.u32);
        EXPECT_EQ(a.header["analysis"], b.header["analysis"]);
        EXPECT_EQ(a.header["report"]["quality"], b.header["report"]["quality"]);
    };
    Skeleton s = generate_skeleton("torus", {.n = 24, .m = 8});
    auto r = post("format=mhsk&session=q&revision=1", skeleton_binary(s));
    ASSERT_EQ(r->status, 200) << r->body;
    studio::DecodedAnswer held = studio::decode_binary_answer(r->body);
    std::mt19937 rng(11);
    for (int i = 0; i < 3; ++i) {
        const Skeleton next = random_edit(s, rng);
        r = post("format=delta&session=q&base=" + std::to_string(i + 1) + "&revision=" + std::to_string(i + 2) +
                     "&since=" + std::to_string(i + 1),
                 studio::skeleton_delta_binary(s, next));
        ASSERT_EQ(r->status, 200) << r->body;
        const auto whole = post("format=mhsk", skeleton_binary(next));
        EXPECT_LT(4 * r->body.size(), whole->body.size());
        const studio::DecodedAnswer patched = studio::decode_binary_answer(r->body, &held);
        EXPECT_EQ(patched.header["patch_of"], i + 1);
        same(patched, studio::decode_binary_answer(whole->body));
        held = patched;
        s = next;
    }
    // since=2 while the session's last answer is revision 4: a whole answer.
    r = post("format=delta&session=q&base=4&revision=5&since=2", studio::skeleton_delta_binary(s, s));
    ASSERT_EQ(r->status, 200) << r->body;
    const studio::DecodedAnswer whole = studio::decode_binary_answer(r->body);
    EXPECT_FALSE(whole.header.contains("patch_of"));
    same(whole, held);
    // Another skeleton (other counts) in the same session with since=5: arrays of other lengths come whole.
    const Skeleton other = generate_skeleton("torus", {.n = 20, .m = 8});
    r = post("format=mhsk&session=q&revision=6&since=5", skeleton_binary(other));
    ASSERT_EQ(r->status, 200) << r->body;
    same(studio::decode_binary_answer(r->body, &whole),
         studio::decode_binary_answer(post("format=mhsk", skeleton_binary(other))->body));
    EXPECT_EQ(post("format=mhsk&session=q&revision=7&since=x", skeleton_binary(other))->status, 400);
}
// Row patches (an insertion renumbers every later row): vertices A B C D -> A X B C D are a run of base row 0, one
// literal row, a run of base rows 1-3; edges (0 1) (2 3) of the vertices become (0 2) (3 4) in the new numbering: one
// run of both base rows, translated, no literal row. The decoded arrays are the new ones.
TEST(StudioSessions, RowPatchOfAnInsertion) {
    studio::BinaryArrays base, full;
    const std::vector<Vec3> abcd = {{1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}};
    std::vector<Vec3> axbcd = abcd;
    axbcd.insert(axbcd.begin() + 1, Vec3{9, 9, 9});
    studio::append_f32(base, "v", abcd);
    studio::append_u32_cells(base, "e", std::vector<std::array<int, 2>>{{0, 1}, {2, 3}});
    studio::append_f32(full, "v", axbcd);
    studio::append_u32_cells(full, "e", std::vector<std::array<int, 2>>{{0, 2}, {3, 4}});
    const std::vector<studio::RowLayout> layouts = {{"v", 3, "", 0}, {"e", 2, "v", 2}};
    const studio::BinaryArrays p = studio::patch_arrays(base, full, layouts);
    expect_row_runs(p, 0, 3, 1);
    expect_row_runs(p, 1, 1, 0);
    EXPECT_EQ(p.bytes.size(), 4 * (2 * 3 + 3) + 4 * 2u);
    // Without layouts the arrays of other lengths stay whole.
    EXPECT_FALSE(studio::patch_arrays(base, full).list[0].contains("rows"));
    const studio::DecodedAnswer previous = decoded(base);
    const studio::DecodedAnswer d = decoded(p, &previous);
    const studio::DecodedAnswer whole = decoded(full);
    EXPECT_EQ(d.f32, whole.f32);
    EXPECT_EQ(d.u32, whole.u32);
}

// Row b of abcd deleted: the points come as two runs (a; c d resumed after the gap), no literal row; the edges, whose
// vertex numbers all shift past b, as one run translated by the points' row map: 3 runs of 8 bytes. A hostile copy
// of that patch (a source row past the base, a width that wraps 4 x width) is refused with invalid_argument, never
// a crash.
TEST(StudioSessions, RowPatchOfADeletionAndHostileCopies) {
    studio::BinaryArrays base, full;
    studio::append_f32(base, "v", std::vector<Vec3>{{1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}});
    studio::append_u32_cells(base, "e", std::vector<std::array<int, 2>>{{0, 2}, {2, 3}});
    studio::append_f32(full, "v", std::vector<Vec3>{{1, 0, 0}, {3, 0, 0}, {4, 0, 0}});
    studio::append_u32_cells(full, "e", std::vector<std::array<int, 2>>{{0, 1}, {1, 2}});
    const std::vector<studio::RowLayout> layouts = {{"v", 3, "", 0}, {"e", 2, "v", 2}};
    const studio::BinaryArrays p = studio::patch_arrays(base, full, layouts);
    expect_row_runs(p, 0, 2, 0);
    expect_row_runs(p, 1, 1, 0);
    EXPECT_EQ(p.bytes.size(), 8 * 3u);
    const studio::DecodedAnswer previous = decoded(base);
    const studio::DecodedAnswer d = decoded(p, &previous);
    const studio::DecodedAnswer whole = decoded(full);
    EXPECT_EQ(d.f32, whole.f32);
    EXPECT_EQ(d.u32, whole.u32);

    studio::BinaryArrays far = p;  // the points' second run starts at base row 7 (the base has 4)
    far.bytes[12] = 7;
    EXPECT_THROW(decoded(far, &previous), std::invalid_argument);
    studio::BinaryArrays wide = p;  // count 0 passes the layout checks; 4 x 2^62 wraps to 0
    wide.list[0]["count"] = 0;
    wide.list[0]["width"] = std::uint64_t{1} << 62;
    wide.list[0]["literal"] = 1;
    EXPECT_THROW(decoded(wide, &previous), std::invalid_argument);
    // Without the base the patch means nothing: refused too.
    EXPECT_THROW(decoded(p), std::invalid_argument);
}

// A base with two equal rows (a a b) patched into (a b): the first copy of each content is the source, the decoded
// arrays equal the whole ones. And a 100 x 100 grid of points on a dyadic lattice (every coordinate's low bits zero,
// the case that once put every row in one hash slot) with one point inserted in front: one literal row, one run.
TEST(StudioSessions, RowPatchOfRepeatedRowsAndAGrid) {
    studio::BinaryArrays base, full;
    studio::append_f32(base, "v", std::vector<Vec3>{{1, 0, 0}, {1, 0, 0}, {2, 0, 0}});
    studio::append_f32(full, "v", std::vector<Vec3>{{1, 0, 0}, {2, 0, 0}});
    const std::vector<studio::RowLayout> layouts = {{"v", 3, "", 0}};
    const studio::BinaryArrays p = studio::patch_arrays(base, full, layouts);
    ASSERT_TRUE(p.list[0].contains("rows"));
    expect_row_runs(p, 0, 2, 0);
    const studio::DecodedAnswer previous = decoded(base);
    EXPECT_EQ(decoded(p, &previous).f32, decoded(full).f32);

    std::vector<Vec3> grid;
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 100; ++j) grid.push_back({0.5 * i, 0.25 * j, 0});
    std::vector<Vec3> moved = grid;
    moved.insert(moved.begin(), Vec3{-1, -1, -1});
    studio::BinaryArrays gb, gf;
    studio::append_f32(gb, "v", grid);
    studio::append_f32(gf, "v", moved);
    const studio::BinaryArrays gp = studio::patch_arrays(gb, gf, layouts);
    expect_row_runs(gp, 0, 2, 1);
    const studio::DecodedAnswer gprev = decoded(gb);
    EXPECT_EQ(decoded(gp, &gprev).f32, decoded(gf).f32);
}

// A session on a 600-vertex random tree over HTTP: branching points moved one after the other (a drag's edits; some
// change the adapted vertex count, so the raw mesh is renumbered and arrays change length). Every patch answer
// decodes to the arrays of the sessionless whole answer, and stays under 1/10 of its size (1/16 to 1/48 here; on the
// 2 600-vertex tree of BM_StudioRawTree 25 KB of 1.8 MB): the renumbered arrays come
// as row patches.
TEST(StudioSessions, TreePatchAnswersStaySmallWhenTheMeshIsRenumbered) {
    auto studio = start_studio({});
    httplib::Client& c = *studio.client;
    const auto post = [&](const std::string& query, const std::string& body) {
        return c.Post(("/api/mesh?stage=raw&encoding=binary&" + query).c_str(), body, "application/octet-stream");
    };
    const Skeleton tree = bench::random_tree(600, 5);
    auto r = post("format=mhsk&session=t&revision=1", skeleton_binary(tree));
    ASSERT_EQ(r->status, 200) << r->body;
    studio::DecodedAnswer held = studio::decode_binary_answer(r->body);
    const SkeletonAnalysis an = analyze_skeleton(tree);
    Skeleton s = tree;
    int v = 0, renumbered = 0;
    for (int edit = 0; edit < 5; ++edit) {
        while (an.vertex_class[static_cast<std::size_t>(v)] != VertexClass::BranchingPoint) ++v;
        Skeleton next = s;
        next.points[static_cast<std::size_t>(v++)] += Vec3{0.02, 0.01, 0};
        r = post("format=delta&session=t&base=" + std::to_string(edit + 1) + "&revision=" + std::to_string(edit + 2) +
                     "&since=" + std::to_string(edit + 1),
                 studio::skeleton_delta_binary(s, next));
        ASSERT_EQ(r->status, 200) << r->body;
        const auto whole = post("format=mhsk", skeleton_binary(next));
        ASSERT_EQ(whole->status, 200);
        EXPECT_LT(10 * r->body.size(), whole->body.size()) << edit;
        const studio::DecodedAnswer patched = studio::decode_binary_answer(r->body, &held);
        const studio::DecodedAnswer full = studio::decode_binary_answer(whole->body);
        EXPECT_EQ(patched.names, full.names);
        EXPECT_EQ(patched.f32, full.f32) << edit;
        EXPECT_EQ(patched.u32, full.u32) << edit;
        if (patched.ints("mesh.hexes").size() != held.ints("mesh.hexes").size()) {
            ++renumbered;
            bool rows = false;
            for (const json& a : patched.header["arrays"])
                rows = rows || (a["name"] == "mesh.hexes" && a.contains("rows"));
            EXPECT_TRUE(rows) << edit;
        }
        held = patched;
        s = next;
    }
    EXPECT_GE(renumbered, 1);
}
