#pragma once
// Paper step 2: skeleton analysis. Classifies every vertex, extracts branches (ordered vertex chains) and leaflets
// (consistently oriented face sets), and counts everything the raw mesh needs, so that every raw-mesh vertex and hex
// can be given its id up front (design choice 1).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/core/vec.h"

namespace mesohex {

// Vertex classes of the paper (figure 4) from the pseudo-degree (nl leaflets through the boundary, nb branch edges)
// of reference-notes §4.1-4.2. Fan-edge vertices are vertices on an edge with >= 3 faces.
enum class VertexClass : std::uint8_t {
    Isolated,         // no edge, no face: produces nothing
    Extremity,        // (0,1): one branch edge
    Joint,            // (0,2): two branch edges
    BranchingPoint,   // nl + nb > 2
    LeafletInterior,  // (0,0) with faces: only interior leaflet edges (plus at most one branch edge where 4 faces of
                      // one leaflet meet: vertex_branch_edges == 1)
    LeafletBoundary,  // (1,0): two leaflet boundary edges, no branch (or one rooted on the border's plates:
                      // border_root, vertex_branch_edges == 1)
    BLJoint,          // (1,1): one leaflet (through its boundary) and one branch edge (border_root None)
    LLJoint,          // (2,0): two leaflets through their boundaries
    FanEdgeVertex,    // on two or more fan edges (inside a fan-edge chain)
    FanEdgeEnd,       // on exactly one fan edge
};
const char* to_string(VertexClass c);

// A branch: the ordered chain vertices[0], edges[0], vertices[1], ..., edges[m-1], vertices[m] (m >= 1) through
// Joint vertices only. vertices.front() == vertices.back() for a loop at a branching point and for a closed ring.
struct Branch {
    std::vector<int> vertices;
    std::vector<int> edges;
    bool ring = false;  // closed ring without any non-joint vertex: vertices[0] is an artificial start (free frame)
    friend bool operator==(const Branch&, const Branch&) = default;
};

// A leaflet: faces connected through edges with exactly two incident faces, oriented consistently.
struct Leaflet {
    std::vector<int> faces;
    bool orientable = true;  // false: a Möbius-like leaflet (some interior edge is traversed twice the same way)
    friend bool operator==(const Leaflet&, const Leaflet&) = default;
};

struct AnalysisCounts {
    long vertices = 0, edges = 0, faces = 0;
    long branch_edges = 0;    // edges of degree 0
    long boundary_edges = 0;  // leaflet edges of degree 1
    long fan_edges = 0;       // degree >= 3, not docked
    long docked_edges = 0;    // degree >= 3, docked: walls standing on a plate (docked_walls.h)
    long branches = 0, leaflets = 0;
    long extremities = 0, joints = 0, branching_points = 0, bl_joints = 0, ll_joints = 0;
    long leaflet_interior = 0, leaflet_boundary = 0, fan_edge_vertices = 0, fan_edge_ends = 0, isolated = 0;
    long rings = 0;  // branches that are closed rings without a branching point
    // components - (V - E + F), isolated vertices excluded: the number of independent cycles (first Betti number)
    // for curve skeletons and leaflets without closed surfaces.
    long cycles = 0;
    long components = 0;  // connected components (isolated vertices excluded)
    friend bool operator==(const AnalysisCounts&, const AnalysisCounts&) = default;
};

// Branches rooted on a leaflet border vertex w (boundary neighbours in unit directions d1, d2; `faces` faces at w;
// `branch` the unit direction the branch leaves to; `normal` the sum of the oriented face normals at w; `inward` the
// mean unit vector to w's leaflet neighbours). Such a w is classified LeafletBoundary with vertex_branch_edges 1
// instead of a BL-joint, whose pillow cannot hold the half-chunks on a straight border:
//   Out:  the border is nearly straight (d1, d2 at least kBorderRootAngleDeg apart) and the branch leaves within
//         kBorderRootBranchDeg of the outward in-plane direction cross(unit(d2 - d1), normal) (turned away from
//         inward): the branch stands on the 4 half-chunk out faces around w's out vertex;
//   Side: 2 faces meet at w and the branch leaves within kBorderRootSideDeg of the normal (either side): it stands on
//         the 2 plate and 2 half-chunk faces around w's up (down) vertex.
// Except a leaflet corner: w has one face, d1, d2 are less than kBorderCornerMaxDeg apart, the branch leaves within
// kBorderCornerBranchDeg of that outward direction (the corner's outward bisector) and w's radius over its shorter
// border edge (`radius_over_edge`, 0 when unknown) is below kBorderCornerMaxRadiusEdge: None (a BL-joint), whose
// pillow wraps the corner, where the out patch would fold by 180 degrees minus the corner angle (docs/sheets.md,
// "Leaflet corners rooted on the out patch").
enum class BorderRoot : std::uint8_t { None, Out, Side };
inline constexpr double kBorderRootAngleDeg = 100;       // degrees between the two border edges
inline constexpr double kBorderRootBranchDeg = 60;       // degrees between the branch and the outward direction
inline constexpr double kBorderRootSideDeg = 45;         // degrees between the branch and the normal
inline constexpr double kBorderCornerMaxDeg = 120;       // degrees between the two border edges of a one-face corner
inline constexpr double kBorderCornerBranchDeg = 30;     // degrees between the branch and the corner's outward bisector
inline constexpr double kBorderCornerMaxRadiusEdge = 1;  // radius / shorter border edge (dimensionless)
BorderRoot border_root(const Vec3& d1, const Vec3& d2, const Vec3& inward, const Vec3& normal, const Vec3& branch,
                       int faces, double radius_over_edge = 0);
struct SkeletonAnalysis;
// The same for vertex v of an analysed skeleton (None unless v has exactly one branch edge, two boundary edges and no
// fan edge). Needs only the analysis' incidence, edge degrees, faces and face normals.
BorderRoot border_root_at(const Skeleton& skeleton, const SkeletonAnalysis& analysis, int v);

struct SkeletonAnalysis {
    // Vertex -> incident edges, CSR, each list in increasing edge id: vertex_edges[vertex_edge_begin[v] ...].
    std::vector<int> vertex_edge_begin;  // size V + 1
    std::vector<int> vertex_edges;
    std::vector<VertexClass> vertex_class;       // per vertex
    std::vector<int> vertex_branch_edges;        // per vertex: number of incident branch (degree-0) edges
    std::vector<int> vertex_boundary_edges;      // per vertex: number of incident degree-1 edges
    std::vector<BorderRoot> vertex_border_root;  // per vertex: how a branch is rooted on its leaflet border (None
                                                 // unless a LeafletBoundary vertex with a branch edge)
    std::vector<int> edge_degree;                // per edge: number of incident faces (0 = branch edge)
    std::vector<int> edge_branch;                // per edge: its branch, or -1
    // Walls docked on a plate (docked_walls.h). edge_docked: 1 = a fan edge of a docked chain (no fan block; its plate
    // continues across it, walls stand on the plate's faces), 2 = a wall's boundary edge ending on a docked chain (its
    // half-chunk stands on the plate), 3 = a flange's chain edge (the plate's border edge: walls on its half-chunk), 0.
    // vertex_plate per vertex: the plate leaflet of a docked chain vertex, else -1; such a vertex is classified,
    // and its vertex_boundary_edges counted, by its plate alone (LeafletInterior or LeafletBoundary).
    std::vector<char> edge_docked;
    std::vector<int> vertex_plate;
    // Per vertex: 1 at a corner cube (docked_walls.h, "Corner cubes"): a flange's chain end at its plate's corner,
    // whose two border edges get out columns of their own (12 raw ids instead of 6) and 2 corner hexes; else 0 (empty
    // when nothing is docked).
    std::vector<char> corner_cube;
    // Docked chain vertices whose plate grid does not match the wall's foot (a turn in the grid, other than 4 plate
    // faces, ...), accepted only with AnalysisOptions::docked_band_pillow (left to the repair's band pillow), chain
    // by chain; empty otherwise. With any, the feet are not built nor checked (docked_foot_quads is skipped).
    std::vector<int> docked_unmatched;
    std::vector<Branch> branches;
    // Leaflets. face_vertices is the face re-oriented consistently within its leaflet (the first face of each leaflet,
    // in face-id order, keeps the input orientation). face_normal: Newell normal of the oriented face, unit length.
    std::vector<Leaflet> leaflets;
    std::vector<int> face_leaflet;
    std::vector<std::array<int, 4>> face_vertices;
    std::vector<std::array<int, 4>> face_edges;  // edge of side (face_vertices[k], face_vertices[k+1])
    std::vector<Vec3> face_normal;
    AnalysisCounts counts;
    // Raw-mesh hex count known from the analysis alone: 4 per branch edge + 2 per leaflet face + 2 per boundary edge
    // + 2 per corner cube.
    long predicted_hexes = 0;
};

struct AnalysisOptions {
    // Edges shorter than this (absolute) are rejected as degenerate.
    double min_edge_length = 1e-12;
    // Accept branch edges on a fan-edge end (classified FanEdgeEnd; the raw mesh cannot build them): for the analysis
    // of an input that repair_skeleton's fan-end retraction turns into a leaflet corner (pipeline.cpp).
    bool fan_end_branches = false;
    // Accept one branch edge on a fan-edge end (classified FanEdgeEnd, vertex_branch_edges 1): a branch standing on
    // the fan block's cap there (CompatibleBlockOptions::fan_cap_branches, fan_blocks.h); the connection surfaces
    // refuse it, naming the vertex, when no fan-block chain ends there with that branch accepted. Set by the pipeline.
    bool fan_cap_branches = false;
    // Accept a docked wall's chain whose feet do not match its plate's grid (a chain turning in the grid, a chain
    // vertex where other than 4 plate faces meet; listed in SkeletonAnalysis::docked_unmatched, not refused): for the
    // analysis of an input that repair_skeleton's band pillow (SkeletonRepairOptions::docked_band_pillow) makes
    // match. Set by the pipeline.
    bool docked_band_pillow = false;
    // The band pillow ran on this skeleton before the analysis (the analysis of repair_skeleton's output with
    // SkeletonRepairOptions::docked_band_pillow on): a chain vertex whose feet still do not match is refused saying
    // that the pillow could not take its path; false (the pillow off, or no resampling) the refusal says to turn it on.
    // Only words change. Set by the pipeline.
    bool docked_band_pillow_ran = false;
};

// Preconditions (checked, Error(InvalidInput) naming the element otherwise): indices in range, no self-loop edge,
// no zero-length edge, finite positions, every face a quad whose sides are all listed in skeleton.edges.
// Rejected with Error(UnsupportedConfiguration) naming the vertex (the paper's section 5 limitations, so that they
// never reach the later stages): a branch edge on a vertex inside a leaflet (limitation 1), except one branch where
// 4 faces of one leaflet meet (rooted on the plates, LeafletPatch), or on a fan-edge vertex
// (limitation 3); an irregular fan (limitation 2): a fan edge ending inside a leaflet, i.e. a fan-edge end where not
// every face around the fan edge leaves by its own boundary edge, unless its chain is docked (walls standing on a
// plate, docked_walls.h; refused there with a named vertex when the docking does not apply), a fan-edge chain vertex
// with a boundary edge, with fan edges of unequal degrees or with more than two fan edges, or any fan-edge vertex
// inside a leaflet; a leaflet touching the interior of another
// leaflet; a vertex with an odd number of leaflet boundary edges.
// Postconditions: every branch edge is in exactly one branch; every face in exactly one leaflet.
// Complexity: O(V + E log E + F).
SkeletonAnalysis analyze_skeleton(const Skeleton& skeleton, const AnalysisOptions& options = {});

// The first steps of analyze_skeleton only: incidence, faces with their edges and the edge degrees, leaflets
// (consistently oriented) and face normals; no input validation beyond those steps' own (Error(InvalidInput) naming a
// face whose side is not an edge, or of zero area), nothing classified, docked or counted. For a stage that needs the
// analysis' leaflets on a skeleton it is changing (skeleton_repair.cpp's view of docked plates, which takes the
// analysis' joins across chains: join_plates_across_chains, docked_walls.h). Preconditions: indices in range, faces
// of 4 distinct vertices (validate_input is not run; the leaflet walk relies on it).
// O(V + E log E + F).
SkeletonAnalysis analyze_leaflets(const Skeleton& skeleton);

// The branch extraction of analyze_skeleton over plain data, also for a skeleton the analysis would refuse
// (adaptation resamples the branches of skeletons before they are meshable). vertex_edge_begin / vertex_edges: the
// incidence (CSR, edges in increasing id per vertex); branch_edge[e] != 0: e is a branch edge; joint[v] != 0: v has
// exactly two incident edges, both branch edges (a walk goes on through it). Branches are walked from every non-joint
// vertex, in vertex order, along each of its branch edges not taken yet, in edge order; the edges left form closed
// rings (ring = true), each walked from its smallest vertex along its smaller edge id. edge_branch: per edge, its
// branch or -1. O(V + E).
std::vector<Branch> extract_branches(const Skeleton& skeleton, const std::vector<int>& vertex_edge_begin,
                                     const std::vector<int>& vertex_edges, const std::vector<char>& branch_edge,
                                     const std::vector<char>& joint, std::vector<int>& edge_branch);

// The corner (0-3) of quad face f at vertex w, -1 when w is not one of its corners.
inline int face_corner(const SkeletonAnalysis& an, int f, int w) {
    for (int k = 0; k < 4; ++k)
        if (an.face_vertices[f][k] == w) return k;
    return -1;
}

// Does face f count at its corner w as a leaflet face of w (false only for a wall's face at a docked chain vertex)?
inline bool face_counts_at(const SkeletonAnalysis& an, int f, int w) {
    return an.vertex_plate.empty() || an.vertex_plate[w] < 0 || an.face_leaflet[f] == an.vertex_plate[w];
}

// Is v a corner cube's vertex (SkeletonAnalysis::corner_cube)?
inline bool has_corner_cube(const SkeletonAnalysis& an, int v) { return !an.corner_cube.empty() && an.corner_cube[v]; }

// Does v root a branch on the plates (a leaflet interior or boundary vertex with exactly one branch edge)?
inline bool roots_branch(const SkeletonAnalysis& an, int v) {
    return (an.vertex_class[v] == VertexClass::LeafletInterior || an.vertex_class[v] == VertexClass::LeafletBoundary) &&
           an.vertex_branch_edges[v] == 1;
}
// Does v carry a branch on a fan-edge end (accepted with AnalysisOptions::fan_cap_branches: the branch stands on the
// fan block's cap, fan_blocks.h)?
inline bool roots_fan_cap(const SkeletonAnalysis& an, int v) {
    return an.vertex_class[v] == VertexClass::FanEdgeEnd && an.vertex_branch_edges[v] == 1;
}
// The first branch edge (no face) incident to v in edge id order, or -1.
inline int first_branch_edge(const SkeletonAnalysis& an, int v) {
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i)
        if (an.edge_degree[an.vertex_edges[i]] == 0) return an.vertex_edges[i];
    return -1;
}

// Human-readable classification (one line of counts, then one line per non-trivial class), for `mesohex analyze`.
std::string analysis_to_text(const SkeletonAnalysis& analysis);

}  // namespace mesohex
