// The raw meshes of the random evaluation set (issue 16), fast (no fit): per seed, the adapted skeleton's size, how
// far the input's joints lie off it (corner cutting), the raw mesh's min / mean scaled Jacobian and inverted count,
// and the skeleton element of the worst raw hex. Not a test, not a Google benchmark: a measuring tool.
//
//   mesohex_random_raw FIRST LAST [free_branching_reach [trunks [stubs [keep_joints [merge [joint [wide]]]]]]]   (the
//   others 0/1: SkeletonRepairOptions trunks, absorb_stubs, keep_sibling_joints, merge_branching_ends, joint_trunks,
//   wide_junction_trunks); SIDE_STUB_REACH=K in the environment sets SkeletonRepairOptions::side_stub_reach (0: every
//   stub absorbed), SIDE_STUB_MIN_LENGTH=K its side_stub_min_length, SIDE_STUB_ROOT_EXIT=K its side_stub_root_exit,
//   FAT_STUB_MAIN=0|1 its fat_stub_main_line,
//   KEEP_CUT_JOINT=F AdaptationOptions::keep_cut_joint, SLIDE_CUT_JOINT=0|1 its slide_cut_joint, BRIDGE_PEAK=F its
//   bridge_peak_ratio, OVERLAP_MERGE=F its overlap_merge_ratio (OVERLAP_MERGE_MAX_DEGREE=K its
//   overlap_merge_max_degree), LEAFLET_OUT_FRACTION=F
//   RawMeshOptions::leaflet_out_fraction, LEAFLET_OUT_LEAN_ONLY=0|1 its leaflet_out_lean_only,
//   JUNCTION_SPLIT=H SkeletonRepairOptions::junction_split (0: off), JUNCTION_SPLIT_GAP and JUNCTION_SPLIT_CLEARANCE
//   its junction_split_gap_deg and junction_split_clearance, JUNCTION_SPLIT_FIVE=1 its junction_split_degree_five,
//   VALLEY_TRUNKS=N its valley_trunk_degree (VALLEY_TRUNK_MIN_RADIUS=F its valley_trunk_min_radius,
//   VALLEY_TRUNKS_PER_POINT=N its valley_trunks_per_point, VALLEY_TRUNKS_APART=0|1 its valley_trunks_apart,
//   VALLEY_FIT_ACROSS=0|1 its valley_trunk_fit_across), PIT_BRANCHES=F and PIT_MIN_DEGREE=N
//   VirtualBranchOptions::pit_excess and pit_min_degree, PIN_TRUNK_JOINTS=0 turns
//   SkeletonRepairOptions::pin_trunk_joints off, NO_FLAT_CROTCH=0|1 sets
//   ConnectionSurfaceOptions::no_flat_point_in_close_pair, D3_BY_CHUNKS=0|1 its degree_three_partition_by_chunks,
//   D3_NEXT_TO_BP=0|1 its degree_three_chunks_next_to_branching_points, D3_AT_BRIDGES=0|1 its
//   degree_three_chunks_at_bridges, EXACT_THREE=0|1 its exact_three_orange, SHARED_HULL=0|1 its shared_hull_relaxation,
//   GRADIENT_LONG=0|1 its gradient_long_relaxation, COARSE_THREE=0|1 its coarse_three_scan, TABLED_THREE=0|1 its
//   tabled_three_start, FIRST_IMPROVING=0|1 its first_improving_long_relaxation, JUNCTION_COVER=F RawMeshOptions::
//   cover.fraction (JUNCTION_INSET=F cover.inset, JUNCTION_CREASE=DEG cover.crease_deg, JUNCTION_CREASE_MID=0|1 its
//   crease_midpoints, JUNCTION_CREASE_PAIR=DEG its crease_pair_deg, JUNCTION_COVER_MIN_DEGREE and JUNCTION_COVER_FLOOR
//   its min_degree and sj_floor, JUNCTION_COVER_BULGE its bridge_bulge, JUNCTION_COVER_OVERLAP its bridge_overlap),
//   BRIDGE_QUAD=0|1 RawMeshOptions::bridge_quad_radius (BRIDGE_QUAD_INSET=F its bridge_quad_inset),
//   FAN_CAP_BRANCHES=0|1 CompatibleBlockOptions::fan_cap_branches. CREASE_WEDGE=DEG lists, before the seed's line, the
//   wedges finish_mesh would insert with FinishOptions::crease_wedge at DEG (one line "  wedge SEED edge A B at vC
//   degree D" each; CREASE_WEDGE_PAIR=DEG2 restricts them as MeshOptions::crease_wedge_pair_deg does); the raw mesh and
//   its hash are unchanged. The last three columns: stubs kept as side branches, degree-4 branching points split, and a
//   hash of the raw mesh (compare two builds or option sets seed by seed to find the seeds a change touches).
//
// FAMILY=character takes the character family's skeletons (generate_character_skeleton) instead of the mixed
// tree / sheet ones; the kind column then reads "character". FAMILY=twinjunction: the twin-junction family
// (generate_twin_junction_skeleton), kind "twinjunction".
//
// SKEL=path meshes that skeleton file instead (FIRST = LAST, e.g. `SKEL=curve-skeletons/dino.skel
// mesohex_random_raw 0 0`; the 3rd argument 1.0 gives the second attempt's adaptation). DUMP=1 also lists the meshed
// skeleton (vertex, radius, the radius the raw mesh used: smaller next to branching points, see
// RawMeshOptions::margin_fraction; neighbours), every branching point's partition points (raw hexes using each: 8 at a
// valence-4 pole, 4 at a valence-2 point with its 180-degree corner; angle to each branch edge) and the 10 worst raw
// hexes with their skeleton edge (docs/junctions.md, "The shared curve skeletons").
//
// One line per seed, then the distribution. The worst raw hex is named by the adapted skeleton edge of its chunk
// (a plate hex: "plate"), and by the kind of that edge's ends: bp = branching point without leaflet, lf = leaflet
// vertex, ex = extremity, jt = joint (with its turn in degrees).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/pipeline.h"
#include "mesohex/post/crease_wedge.h"
#include "mesohex/post/quality.h"
#include "mesohex/stages/generators.h"
#include "mesohex/stages/skeleton_repair.h"
#include "mesohex_io/skeleton_io.h"
#include "raw_hash.h"

using namespace mesohex;

namespace {

using bench::raw_hash;

double segment_point_distance(const Vec3& a, const Vec3& b, const Vec3& p) {
    const Vec3 d = b - a;
    const double l2 = dot(d, d);
    const double t = l2 > 0 ? std::clamp(dot(p - a, d) / l2, 0.0, 1.0) : 0.0;
    return distance(a + t * d, p);
}

std::string vertex_kind(const Skeleton& s, const std::vector<std::vector<int>>& adj, const std::vector<bool>& on_face,
                        int v) {
    if (on_face[v]) return "lf";
    if (adj[v].size() == 1) return "ex";
    if (adj[v].size() >= 3) return "bp" + std::to_string(adj[v].size());
    const Vec3 u = normalized(s.points[v] - s.points[adj[v][0]]), w = normalized(s.points[adj[v][1]] - s.points[v]);
    const double turn = std::acos(std::clamp(dot(u, w), -1.0, 1.0)) * 180 / 3.141592653589793;
    return "jt" + std::to_string(static_cast<int>(std::lround(turn)));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: mesohex_random_raw FIRST LAST [free_branching_reach [trunks [stubs [keep_joints "
                     "[merge [joint [wide]]]]]]] (0/1)\n");
        return 2;
    }
    const long first = std::atol(argv[1]), last = std::atol(argv[2]);
    PipelineOptions po;
    if (argc > 3) po.adaptation.free_branching_reach = std::atof(argv[3]);
    if (argc > 4) po.repair.trunks = std::atoi(argv[4]) != 0;
    if (argc > 5) po.repair.absorb_stubs = std::atoi(argv[5]) != 0;
    if (argc > 6) po.repair.keep_sibling_joints = std::atoi(argv[6]) != 0;
    if (argc > 7) po.repair.merge_branching_ends = std::atoi(argv[7]) != 0;
    if (argc > 8) po.repair.joint_trunks = std::atoi(argv[8]) != 0;
    if (argc > 9) po.repair.wide_junction_trunks = std::atoi(argv[9]) != 0;
    if (const char* k = std::getenv("LEAFLET_OUT_FRACTION")) po.raw_mesh.leaflet_out_fraction = std::atof(k);
    if (const char* k = std::getenv("LEAFLET_OUT_LEAN_ONLY")) po.raw_mesh.leaflet_out_lean_only = std::atoi(k) != 0;
    if (const char* k = std::getenv("KEEP_CUT_JOINT")) po.adaptation.keep_cut_joint = std::atof(k);
    if (const char* k = std::getenv("SLIDE_CUT_JOINT")) po.adaptation.slide_cut_joint = std::atoi(k) != 0;
    if (const char* k = std::getenv("BRIDGE_PEAK")) po.adaptation.bridge_peak_ratio = std::atof(k);
    if (const char* k = std::getenv("OVERLAP_MERGE")) po.adaptation.overlap_merge_ratio = std::atof(k);
    if (const char* k = std::getenv("OVERLAP_MERGE_MAX_DEGREE")) po.adaptation.overlap_merge_max_degree = std::atoi(k);
    if (const char* k = std::getenv("SIDE_STUB_REACH")) po.repair.side_stub_reach = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_SPLIT")) po.repair.junction_split = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_SPLIT_GAP")) po.repair.junction_split_gap_deg = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_SPLIT_CLEARANCE")) po.repair.junction_split_clearance = std::atof(k);
    if (const char* k = std::getenv("PIT_BRANCHES")) po.virtual_branches.pit_excess = std::atof(k);
    if (const char* k = std::getenv("PIT_MIN_DEGREE")) po.virtual_branches.pit_min_degree = std::atoi(k);
    if (const char* k = std::getenv("VALLEY_TRUNKS")) po.repair.valley_trunk_degree = std::atoi(k);
    if (const char* k = std::getenv("VALLEY_TRUNKS_PER_POINT")) po.repair.valley_trunks_per_point = std::atoi(k);
    if (const char* k = std::getenv("VALLEY_TRUNKS_APART")) po.repair.valley_trunks_apart = std::atoi(k) != 0;
    if (const char* k = std::getenv("VALLEY_FIT_ACROSS")) po.repair.valley_trunk_fit_across = std::atoi(k) != 0;
    if (const char* k = std::getenv("VALLEY_TRUNK_MIN_RADIUS")) po.repair.valley_trunk_min_radius = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_SPLIT_FIVE")) po.repair.junction_split_degree_five = std::atoi(k) != 0;
    if (const char* k = std::getenv("SIDE_STUB_MIN_LENGTH")) po.repair.side_stub_min_length = std::atof(k);
    if (const char* k = std::getenv("SIDE_STUB_ROOT_EXIT")) po.repair.side_stub_root_exit = std::atof(k);
    if (const char* k = std::getenv("FAT_STUB_MAIN")) po.repair.fat_stub_main_line = std::atoi(k) != 0;
    if (const char* k = std::getenv("JUNCTION_COVER")) po.raw_mesh.cover.fraction = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_COVER_MIN_DEGREE")) po.raw_mesh.cover.min_degree = std::atoi(k);
    if (const char* k = std::getenv("JUNCTION_COVER_FLOOR")) po.raw_mesh.cover.sj_floor = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_COVER_BULGE")) po.raw_mesh.cover.bridge_bulge = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_COVER_OVERLAP")) po.raw_mesh.cover.bridge_overlap = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_INSET")) po.raw_mesh.cover.inset = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_CREASE")) po.raw_mesh.cover.crease_deg = std::atof(k);
    if (const char* k = std::getenv("JUNCTION_CREASE_MID")) po.raw_mesh.cover.crease_midpoints = std::atoi(k) != 0;
    if (const char* k = std::getenv("JUNCTION_CREASE_PAIR")) po.raw_mesh.cover.crease_pair_deg = std::atof(k);
    if (const char* k = std::getenv("BRIDGE_QUAD")) po.raw_mesh.bridge_quad_radius = std::atoi(k) != 0;
    if (const char* k = std::getenv("BRIDGE_QUAD_INSET")) po.raw_mesh.bridge_quad_inset = std::atof(k);
    if (const char* k = std::getenv("PIN_TRUNK_JOINTS")) po.repair.pin_trunk_joints = std::atoi(k) != 0;
    if (const char* k = std::getenv("NO_FLAT_CROTCH"))
        po.connection_surfaces.no_flat_point_in_close_pair = std::atoi(k) != 0;
    if (const char* k = std::getenv("D3_BY_CHUNKS"))
        po.connection_surfaces.degree_three_partition_by_chunks = std::atoi(k) != 0;
    if (const char* k = std::getenv("D3_NEXT_TO_BP"))
        po.connection_surfaces.degree_three_chunks_next_to_branching_points = std::atoi(k) != 0;
    if (const char* k = std::getenv("D3_AT_BRIDGES"))
        po.connection_surfaces.degree_three_chunks_at_bridges = std::atoi(k) != 0;
    if (const char* k = std::getenv("EXACT_THREE")) po.connection_surfaces.exact_three_orange = std::atoi(k) != 0;
    if (const char* k = std::getenv("SHARED_HULL")) po.connection_surfaces.shared_hull_relaxation = std::atoi(k) != 0;
    if (const char* k = std::getenv("GRADIENT_LONG"))
        po.connection_surfaces.gradient_long_relaxation = std::atoi(k) != 0;
    if (const char* k = std::getenv("COARSE_THREE")) po.connection_surfaces.coarse_three_scan = std::atoi(k) != 0;
    if (const char* k = std::getenv("TABLED_THREE")) po.connection_surfaces.tabled_three_start = std::atoi(k) != 0;
    if (const char* k = std::getenv("FIRST_IMPROVING"))
        po.connection_surfaces.first_improving_long_relaxation = std::atoi(k) != 0;
    if (const char* k = std::getenv("FAN_CAP_BRANCHES"))
        po.connection_surfaces.blocks.fan_cap_branches = std::atoi(k) != 0;
    std::vector<double> mins, offs;
    int inverted_seeds = 0;
    std::printf(
        "seed kind V E raw_hexes minSJ avgSJ inv corner_off/r repair_off/r worst_at trunks stubs merged unseparated "
        "side_stubs "
        "junction_splits raw_hash\n");
    for (long seed = first; seed <= last; ++seed) {
        // SKEL=path in the environment: that skeleton file instead of the seeds (FIRST = LAST; e.g. the shared curve
        // skeletons, which bring their radii).
        const char* skel_path = std::getenv("SKEL");
        const char* family = std::getenv("FAMILY");
        const bool character = family != nullptr && std::string(family) == "character";
        const bool twin = family != nullptr && std::string(family) == "twinjunction";
        const auto useed = static_cast<std::uint64_t>(seed);
        const Skeleton in = skel_path   ? read_skeleton(skel_path)
                            : character ? generate_character_skeleton(useed)
                            : twin      ? generate_twin_junction_skeleton(useed)
                                        : generate_random_skeleton(useed);
        const char* kind = character ? "character" : twin ? "twinjunction" : random_skeleton_kind(useed);
        try {
            const PipelineResult res = run_pipeline(in, po);
            const Skeleton& s = res.skeleton;
            // Corner cutting: every input vertex off every face, distance to the nearest adapted branch edge / r.
            std::vector<bool> in_face(in.points.size(), false);
            for (const auto& f : in.faces)
                for (int v : f) in_face[v] = true;
            const auto corner_offset = [&](const Skeleton& m) {
                double o = 0;
                for (std::size_t v = 0; v < in.points.size(); ++v) {
                    if (in_face[v]) continue;
                    double best = 1e300;
                    for (const auto& e : m.edges)
                        best = std::min(best, segment_point_distance(m.points[e[0]], m.points[e[1]], in.points[v]));
                    o = std::max(o, best / in.radii[v]);
                }
                return o;
            };
            const double off = corner_offset(s);
            // The same against the repaired skeleton (before adaptation): the part of the offset the repairs make.
            const Skeleton repaired = repair_skeleton(in, po.repair, &po.connection_surfaces.blocks).skeleton;
            const double repair_off = corner_offset(repaired);
            if (std::getenv("DUMP_REPAIRED"))  // the repaired skeleton (before adaptation): vertex, radius, neighbours
                for (std::size_t v = 0; v < repaired.points.size(); ++v) {
                    std::printf("  r%zu (%.3f %.3f %.3f) r %.3f:", v, repaired.points[v].x, repaired.points[v].y,
                                repaired.points[v].z, repaired.radii[v]);
                    for (const auto& e : repaired.edges)
                        if (e[0] == static_cast<int>(v) || e[1] == static_cast<int>(v))
                            std::printf(" %d", e[0] == static_cast<int>(v) ? e[1] : e[0]);
                    std::printf("\n");
                }
            const QualityReport q = compute_quality(res.raw.mesh);
            if (std::getenv("DUMP")) {  // the meshed skeleton: vertex, radius, neighbours
                for (std::size_t v = 0; v < s.points.size(); ++v) {
                    // raw r: the distance of the vertex's first raw surface point from its centre (the effective
                    // radius the raw mesh used: limited next to branching points and at sharp joints)
                    const int b = res.raw.vertex_base[v];
                    const double rr = b >= 0 && b + 1 < static_cast<int>(res.raw.mesh.points.size())
                                          ? distance(res.raw.mesh.points[b + 1], res.raw.mesh.points[b])
                                          : 0.0;
                    std::printf("  v%zu (%.3f %.3f %.3f) r %.3f raw r %.3f:", v, s.points[v].x, s.points[v].y,
                                s.points[v].z, s.radii[v], rr);
                    for (const auto& e : s.edges)
                        if (e[0] == static_cast<int>(v) || e[1] == static_cast<int>(v))
                            std::printf(" %d", e[0] == static_cast<int>(v) ? e[1] : e[0]);
                    std::printf("\n");
                }
                // Per branching point (a sphere partition: d quads on d + 2 points, ids after its centre): each
                // surface point's raw hex count (2 per quad holding it) and its angle to each branch edge (degrees).
                {
                    std::vector<int> uses(res.raw.mesh.points.size(), 0);
                    for (const auto& hx : res.raw.mesh.hexes)
                        for (int x : hx) ++uses[static_cast<std::size_t>(x)];
                    for (std::size_t v = 0; v < s.points.size(); ++v) {
                        std::vector<int> nb;
                        for (const auto& e : s.edges)
                            if (e[0] == static_cast<int>(v) || e[1] == static_cast<int>(v))
                                nb.push_back(e[0] == static_cast<int>(v) ? e[1] : e[0]);
                        const int b = res.raw.vertex_base[v];
                        if (nb.size() < 3 || b < 0) continue;
                        for (std::size_t x = 1; x <= nb.size() + 2; ++x) {
                            const Vec3 d = normalized(res.raw.mesh.points[b + x] - res.raw.mesh.points[b]);
                            std::printf("  point v%zu.%zu hexes %d dir (%.3f %.3f %.3f) angles", v, x, uses[b + x], d.x,
                                        d.y, d.z);
                            for (int w : nb)
                                std::printf(
                                    " v%d:%.0f", w,
                                    std::acos(std::clamp(dot(d, normalized(s.points[w] - s.points[v])), -1.0, 1.0)) *
                                        180 / 3.141592653589793);
                            std::printf("\n");
                        }
                    }
                }
                for (int k = 0; k < 10 && k < static_cast<int>(q.worst_hexes.size()); ++k) {
                    const int h = q.worst_hexes[k], e = res.raw.hex_edge[h];
                    std::printf("  worst hex %d sj %.3f edge %d (%d %d)\n", h, q.sj[h], e, e < 0 ? -1 : s.edges[e][0],
                                e < 0 ? -1 : s.edges[e][1]);
                }
            }
            if (const char* cw = std::getenv("CREASE_WEDGE")) {
                // The wedges finish_mesh would insert before the padding (FinishOptions::crease_wedge at CREASE_WEDGE
                // degrees; with CREASE_WEDGE_PAIR=DEG only on close pairs' creases, MeshOptions::
                // crease_wedge_pair_deg): one line per wedge, its
                // crease edge's branching point and that point's degree.
                CreaseWedgeOptions wo;
                wo.min_dihedral_deg = std::atof(cw);
                if (const char* pd = std::getenv("CREASE_WEDGE_PAIR")) {
                    wo.listed_only = true;
                    wo.listed = close_pair_crease_edges(s, res.analysis, res.raw, std::atof(pd));
                }
                const CreaseWedgeResult wr = insert_crease_wedges(res.raw.mesh, wo);
                const std::vector<int> owner = raw_vertex_owner(res.raw);
                for (const std::array<int, 2>& we : wr.wedge_edges) {
                    const int c = owner[static_cast<std::size_t>(we[0])];
                    std::printf("  wedge %ld edge %d %d at v%d degree %d\n", seed, we[0], we[1], c,
                                c < 0 ? 0 : res.analysis.vertex_edge_begin[c + 1] - res.analysis.vertex_edge_begin[c]);
                }
            }
            std::vector<std::vector<int>> adj(s.points.size());
            for (const auto& e : s.edges) adj[e[0]].push_back(e[1]), adj[e[1]].push_back(e[0]);
            std::vector<bool> on_face(s.points.size(), false);
            for (const auto& f : s.faces)
                for (int v : f) on_face[v] = true;
            std::string where = "none";
            if (!q.worst_hexes.empty()) {
                const int e = res.raw.hex_edge[q.worst_hexes[0]];
                where = e < 0 ? "plate"
                              : vertex_kind(s, adj, on_face, s.edges[e][0]) + "-" +
                                    vertex_kind(s, adj, on_face, s.edges[e][1]);
            }
            std::printf("%ld %s %zu %zu %zu %.3f %.3f %ld %.2f %.2f %s %d %d %d %d %d %d %016llx\n", seed, kind,
                        s.points.size(), s.edges.size(), res.raw.mesh.hexes.size(), q.sj_min, q.sj_avg, q.inverted, off,
                        repair_off, where.c_str(), res.trunks, res.absorbed_stubs, res.merged_ends,
                        res.unseparated_pairs, res.side_stubs, res.junction_splits,
                        static_cast<unsigned long long>(raw_hash(res.raw)));
            mins.push_back(q.sj_min);
            offs.push_back(off);
            inverted_seeds += q.inverted > 0;
        } catch (const Error& e) {
            std::printf("%ld %s error %s\n", seed, kind, e.what());
        }
    }
    if (mins.empty()) return 1;
    std::sort(mins.begin(), mins.end());
    std::sort(offs.begin(), offs.end());
    const auto pick = [](const std::vector<double>& a, double q) {
        return a[static_cast<std::size_t>(q * (a.size() - 1))];
    };
    std::printf(
        "raw min SJ worst %.3f p5 %.3f median %.3f; seeds with inverted raw hexes %d; corner offset / r "
        "median %.2f p95 %.2f max %.2f; seeds with offset >= 0.3 r: %ld\n",
        mins.front(), pick(mins, 0.05), pick(mins, 0.5), inverted_seeds, pick(offs, 0.5), pick(offs, 0.95), offs.back(),
        static_cast<long>(std::count_if(offs.begin(), offs.end(), [](double x) { return x >= 0.3; })));
    return 0;
}
