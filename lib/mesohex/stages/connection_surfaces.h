#pragma once
// Paper step 3: connection surfaces. One closed quad surface per skeleton vertex that joins branches (one quad at an
// extremity, two quads sharing their four vertices at a joint, a quad partition of the sphere with one quad per
// incident branch at a branching point), stored in flat arrays with one CSR range per skeleton vertex.
//
// Conventions (reference-notes §6.1): every quad is counter-clockwise seen from outside the sphere of its vertex.
// For a quad registered on (edge e, endpoint v), "outside" is the direction from v into e. Points are unit
// directions from the vertex centre; branching-point directions come from partition_sphere, extremity and joint
// directions are left zero here and set by frame propagation (they depend on the frames).
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/core/vec.h"
#include "mesohex/stages/compatible_blocks.h"
#include "mesohex/stages/fan_blocks.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

struct ConnectionSurfaces {
    // CSR ranges per skeleton vertex (size V + 1). A vertex without a surface has empty ranges.
    std::vector<int> point_begin;
    std::vector<int> quad_begin;
    std::vector<int> edge_begin;
    // Flat arrays. Quad and edge entries hold point indices LOCAL to their vertex's surface.
    std::vector<Vec3> directions;                // unit direction per surface point (zero for extremity/joint)
    std::vector<std::array<int, 4>> quads;       // local point indices, CCW seen from outside
    std::vector<std::array<int, 4>> quad_edges;  // local edge index of quad side k = (q_k, q_{k+1})
    std::vector<std::array<int, 2>> edges;       // local point indices of each surface edge
    std::vector<int> point_valence;              // number of quads containing each point
    // Per skeleton edge and side (0: edges[e][0], 1: edges[e][1]): the GLOBAL quad index registered there, or -1.
    std::vector<std::array<int, 2>> edge_quad;
    // Leaflets at LL-joints and branching points (virtual branches, after the branch quads of the vertex): per leaflet
    // face and corner, the LOCAL quad index of that corner's leaflet at the vertex, or -1 elsewhere; per global quad,
    // the registration rotation k of reference-notes §8.5 (up = q_{k+1}, down = q_{k+3}), -1 for branch quads.
    std::vector<std::array<int, 4>> face_corner_quad;
    std::vector<int> quad_rotation;
    // Compatible blocks (compatible_blocks.h): per skeleton vertex its block index or -1, and the blocks in vertex
    // order. A block vertex's surface is one square per branch edge (not a partition of the sphere).
    std::vector<int> vertex_block;
    std::vector<CubeBlock> blocks;
    // Fan blocks (fan_blocks.h): chains of fan edges with a square section per vertex and 4 hexes per edge and per
    // open end (the same options: blocks.enabled = false keeps the paper's gap vertices).
    FanBlocks fan_blocks;
};

struct ConnectionSurfaceOptions {
    double planarity_tolerance = 0.05;  // passed to partition_sphere
    // Move branching-point surface points on the sphere to maximise the angular margin of every direction inside its
    // quad (topology unchanged; re-verified with verify_sphere_partition, else the partition is kept as built).
    bool relax_partitions = true;
    double relax_below_margin = 0.5;  // radians (~29 deg): only partitions with a smaller margin are relaxed
    // Junctions with leaflets (branching points with leaflet sides, BL-joints) are relaxed on a model of their leaflet
    // hexes (half-chunk and plate corners at the junction, scaled-Jacobian-like values, and 0.5 sin(margin) of each
    // branch direction) when the smallest model value is below this (with relax_partitions).
    double relax_junctions_below = 0.5;
    // At a branching point with exactly three branch edges, no leaflet side, and a gap wider than 180 degrees between
    // two of them (seen in the plane through their tips: a parent and two children leaving to one side), take the
    // "orange" around the normal of the branches' best-fit plane (partition_sphere's planar candidate, whatever the
    // planarity): its two valence-3 poles lie as far from every branch as three directions allow, its three equator
    // points in the gaps. Kept unless its lunes are slivers or it is invalid (then partition_sphere's general
    // choice, whose score prefers there an axis tilted into the branches' plane, with a pole next to a branch of the
    // close pair: docs/junctions.md, "Degree-3 partitions").
    bool plane_orange_at_degree_three = true;
    // At a branching point with exactly four branch edges and no leaflet side whose closest pair is unambiguous
    // (SpherePartitionOptions::close_pair_gap_deg) and less than 90 degrees apart: no partition with a valence-2
    // point (two quads at 180 degrees) held by just that pair's quads, i.e. in the pair's crotch, when partition_sphere
    // has a valid candidate without (SpherePartitionOptions::no_flat_point_in_close_pair; the orange has one between
    // every two consecutive branches). Kept only if the junction's first chunks do not get worse: the smallest hex
    // corner value and weighted margin of the junction model (as relax_junction measures it) at least the default
    // partition's. docs/junctions.md, "The shared curve skeletons".
    bool no_flat_point_in_close_pair = true;
    // At every branching point with exactly three branch edges, no leaflet side, and every branch edge ending at a
    // joint or an extremity (see degree_three_chunks_next_to_branching_points), build both the general partition
    // and the orange around the branches' best-fit plane normal, and keep the one whose first chunks (the 4 hexes per
    // branch edge from the junction to the next vertex, modelled with the edges' lengths and the neighbours' radii as
    // the raw mesh builds them) have the larger smallest corner value (ties: the general one). Replaces the gap rule
    // of plane_orange_at_degree_three where on (docs/junctions.md, "Degree-3 partitions chosen by their chunks").
    bool degree_three_partition_by_chunks = true;
    // With degree_three_partition_by_chunks: also choose at a degree-3 point one of whose branch edges ends at another
    // branching point (the chunk model then puts a square cross-section there, where the raw mesh has that point's
    // own partition quad), or at any vertex other than a joint or an extremity. Off: such points keep the gap rule,
    // except those that degree_three_chunks_at_bridges chooses (it models a branching neighbour's quad, with this
    // option on too).
    bool degree_three_chunks_next_to_branching_points = false;
    // With degree_three_partition_by_chunks: also choose at a degree-3 point one of whose branch edges ends at another
    // branching point (a bridge), with that chunk's far end modelled on the neighbour's own partition quad on the
    // bridge instead of a square; every other branch edge must end at a joint or an extremity (else, without
    // degree_three_chunks_next_to_branching_points, the gap rule). A neighbour that is itself such a point is modelled
    // with its own choice made on its neighbours' partitions without this option (two rounds: no result of the same
    // pass is read, the same for any thread count). docs/junctions.md, "Degree-3 points at bridges".
    bool degree_three_chunks_at_bridges = true;
    // Passed to partition_sphere (SpherePartitionOptions::exact_three_orange): the orange of three branch directions
    // around the axis the max-min solver of orange_three.h finds, margins weighted 60 degrees (instead of the pattern
    // search's axis on quality_score).
    bool exact_three_orange = true;
    // Passed to partition_sphere (SpherePartitionOptions::shared_hull_relaxation): hull candidates with one geometry
    // (differing only in where valence-2 points sit on their arcs) share one brief relaxation.
    bool shared_hull_relaxation = true;
    // Passed to partition_sphere (SpherePartitionOptions::gradient_long_relaxation): true, the hull candidates' long
    // relaxations move each real vertex along its local energy gradient (at most 20 sweeps) instead of the
    // 8-direction pattern (at most 100); off by default (the finished random set loses 2 of its 11 changed seeds).
    bool gradient_long_relaxation = false;
    // Passed to partition_sphere (SpherePartitionOptions::coarse_three_scan): the three-direction solver starts from
    // distinct axes of a 60-axis scan instead of the 400-axis scan's 3 best.
    bool coarse_three_scan = true;
    // Passed to partition_sphere (SpherePartitionOptions::tabled_three_start): the three-direction solver starts from a
    // table of maxima (and the pair normals, the tips' plane normal, the mean) instead of a scan.
    bool tabled_three_start = true;
    // Passed to partition_sphere (SpherePartitionOptions::first_improving_long_relaxation): the long relaxations'
    // pattern takes a vertex's first better trial, starting with its last direction; off (measured, raw meshes worse).
    bool first_improving_long_relaxation = false;
    // 8-hex compatible blocks at branching points whose branch directions are near a cube's face normals
    // (find_compatible_blocks) and 4-hex fan blocks along T / X fan chains (find_fan_blocks, same tolerances);
    // blocks.enabled = false keeps the paper's layout (`--no-blocks`).
    CompatibleBlockOptions blocks;
};

// Content-keyed memo of branching-point surfaces (for remeshing after an edit, mesohex/incremental.h). The surface of
// a branching point without leaflet sides and without a compatible block is a pure function of its branch directions
// (unit(w - v) for its branch edges in increasing edge id, in that order) and of the options read by its partition
// (planarity_tolerance, relax_partitions, relax_below_margin, plane_orange_at_degree_three,
// no_flat_point_in_close_pair, degree_three_partition_by_chunks, degree_three_chunks_next_to_branching_points,
// degree_three_chunks_at_bridges, exact_three_orange, shared_hull_relaxation, gradient_long_relaxation,
// coarse_three_scan, tabled_three_start, first_improving_long_relaxation; a point
// whose partition may read its neighbours' positions, radii and partitions, a degree-3 point chosen by its chunks (at
// a bridge too) or a degree-4 point under no_flat_point_in_close_pair, is not memo-able): an entry keyed on the exact
// bits of those directions is reused whatever the vertex's number, so an edit that renumbers the skeleton
// (adaptation re-sampling a branch) recomputes only the branching points whose directions changed. Keys are compared
// in full (no trust in the hash).
struct SurfaceMemo {
    struct Entry {
        std::vector<Vec3> key;  // the branch directions, compared bit for bit
        // The surface, local indices (as store_partition writes it; quad i is on the i-th branch edge).
        std::vector<Vec3> directions;
        std::vector<std::array<int, 4>> quads;
        std::vector<std::array<int, 4>> quad_edges;
        std::vector<std::array<int, 2>> edges;
        std::vector<int> point_valence;
    };
    // The options the entries were computed with (another set: the memo is ignored and replaced).
    double planarity_tolerance = 0;
    bool relax_partitions = false;
    double relax_below_margin = 0;
    bool plane_orange_at_degree_three = false;
    bool no_flat_point_in_close_pair = false;
    bool degree_three_partition_by_chunks = false;
    bool degree_three_chunks_next_to_branching_points = false;
    bool degree_three_chunks_at_bridges = false;
    bool exact_three_orange = false;
    bool shared_hull_relaxation = false;
    bool gradient_long_relaxation = false;
    bool coarse_three_scan = false;
    bool tabled_three_start = false;
    bool first_improving_long_relaxation = false;
    std::vector<Entry> entries;                        // one per distinct key
    std::vector<std::pair<std::uint64_t, int>> index;  // (hash of the key, entry), sorted
    int hits = 0;                                      // surfaces the last rebuild took from the memo it was given
    int misses = 0;                                    // memo-able surfaces it computed
};

// Preconditions: `analysis` is analyze_skeleton(skeleton). Leaflet interior and regular boundary vertices need no
// surface. A BL-joint gets a pillow like a joint: quad A = (0,1,2,3) on its branch edge, quad B = (2,1,0,3) for the
// leaflet (on no edge), placed from a frame (T into the leaflet, R = leaflet normal made orthogonal to T): quad B from
// its start is (-S, R, S, -R), so its q1 is "up". T starts halfway between the leaflet's mean direction and the
// reversed branch, then (T, R) are relaxed on the hex model described below. Right at convex leaflet corners with the
// branch in any direction (in-plane, perpendicular); on a straight leaflet border no pillow can hold the half-chunks
// (both border edges would have to be strictly inside one hemisphere): flat or inverted hexes (reference-notes §8.5).
// Junctions with leaflets (BL-joints, branching points with leaflet sides) whose model value is below
// options.relax_junctions_below are relaxed on a model of their hexes: every half-chunk and plate hex corner at the
// junction (leaflet neighbours placed as regular leaflet vertices), and each branch's margin and first chunk; the
// relaxed partition is re-verified (verify_sphere_partition), else the partition is kept as built.
// Radii: skeleton.radii when present, else 0.25 x the mean incident edge length (the model only).
// An LL-joint gets a pillow too (quad A = (0,1,2,3) for side 0, quad B = (2,1,0,3) for side 1, on no edge), see
// leaflet_rotation. Fan-edge vertices need no surface (their gap vertices are made by build_raw_mesh).
// A branching point with leaflets partitions the sphere with one quad per branch edge and one per leaflet side.
// Not supported yet (Error(UnsupportedConfiguration) naming the vertex or face): non-orientable leaflets.
// Postconditions: every branch edge has a quad on both sides; extremity surfaces have 4 points / 1 quad / 4 edges,
// joints 4 / 2 / 4 (quad A = (0,1,2,3) on the vertex's first incident edge, quad B = (2,1,0,3) on the second), a
// branching point of degree n has n + 2 points, n quads (quad i on its i-th incident edge in increasing edge id) and
// 2n edges, except at an accepted compatible block (options.blocks; 4n points, n squares, 4n edges, see
// set_block_surface). Throws Error(NumericalFailure) naming the vertex if no sphere partition can be built.
// Parallel over vertices (oneTBB), deterministic. Complexity: linear in the skeleton plus the partitions.
ConnectionSurfaces build_connection_surfaces(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                                             const ConnectionSurfaceOptions& options = {});

// Incremental form (for remeshing after an edit, see mesohex/incremental.h): the same result as
// build_connection_surfaces(skeleton, analysis, options), computing the surfaces of the vertices with recompute[v] != 0
// only and copying every other vertex's surface from `previous`. The caller guarantees that a copied vertex's inputs
// did not change since `previous` was built with the same options: its position, its neighbours' positions and
// radii, and the leaflet faces within three edges of it (incremental.cpp marks every vertex within three edges of a
// moved one); a degree-3 point chosen at a bridge (degree_three_chunks_at_bridges) reads its neighbours' surfaces and
// theirs, and is recomputed whenever a vertex within two edges of it is. When `previous` is null, recompute.size() !=
// V, or the CSR layout differs (other topology or vertex classes, or other compatible blocks), everything is
// recomputed. LL-joint pillows (cheap, serial) are always
// recomputed; blocks are always re-decided (cheap), a block vertex's squares copied when it is not recomputed.
// With `memo_out` (may be null): every memo-able branching point (see SurfaceMemo) that is computed is first looked up
// in `memo_in` (may be null) by its exact key, and taken from it when found; memo_out receives the entries of this
// skeleton only (bounded: one per distinct key of its branching points) with hits and misses counted. The result is
// the same, bit for bit.
ConnectionSurfaces rebuild_connection_surfaces(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                                               const ConnectionSurfaces* previous, const std::vector<char>& recompute,
                                               const ConnectionSurfaceOptions& options = {},
                                               const SurfaceMemo* memo_in = nullptr, SurfaceMemo* memo_out = nullptr);

// Test hooks of the partition relaxation's margin evaluations (unit quad corners q, unit direction d, floor >= -1):
// the plain one (stops once the margin is <= floor) and the one that skips asin calls; both return the exact margin
// when it is > floor and some value <= floor otherwise.
namespace detail {
double quad_margin_to_floor(const std::array<Vec3, 4>& q, const Vec3& d, double floor);
double quad_margin_above(const std::array<Vec3, 4>& q, const Vec3& d, double floor);
}  // namespace detail

}  // namespace mesohex
