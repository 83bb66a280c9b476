#pragma once
// Walls docked on a plate: a fan edge chain ending inside another leaflet (beyond the paper's limitation 2; design
// note ../shared/design/beyond-the-paper.md section B, docs/blocks.md "Docked walls").
//
// Configuration: a chain of fan edges u_0 ... u_m where two faces of one leaflet P (the plate) continue across every
// chain edge (their in-plane directions at least kDockPlateAngleDeg apart) and the other faces are walls: one wall
// (degree 3) or one on each side of the plate (degree 4); at least one chain end lies inside P (P has no boundary
// edge there); every wall within kDockWallTiltDeg of P's normal. A chain whose ends are all on P's border is a regular
// fan and stays one (the paper's layout), unless a leaflet stops on it (a wall across P with a shorter wall on the
// other side: fan edges of degrees 3 and 4 in one chain, an irregular fan otherwise): then P's two halves, which the
// chain cuts into two leaflets, are joined into one and the chain docks (find_docked_walls).
//
// Scheme: the chain edges are ordinary interior edges of P (its vertices get P's ids only: centre, up, down, and at a
// border end the out column). A wall has no vertex of its own on the chain: with X = P's up copies for a wall on P's
// up side (down copies otherwise), and sigma+ / sigma- the plate neighbours of u across the chain on the wall's +n /
// -n side, its copies at a chain vertex u are
//   centre -> X(u),  up -> X(sigma+),  down -> X(sigma-);
// at the wall's end u_e (a wall boundary edge at u_e) its out column is
//   inside P:       out -> X(x), out-up -> X(x+), out-down -> X(x-)   (x: P's neighbour continuing the chain beyond
//                   u_e, x+- the diagonal corners of P's faces (u_e, sigma+-, x+-, x));
//   on P's border:  out -> XO(u_e), out-up -> XO(sigma+), out-down -> XO(sigma-)   (XO: P's out-up / out-down copy).
// The wall's first plate hexes then stand on the X faces of P's plates along the chain, its end half-chunks on the
// plates (or half-chunks) beyond the end: the foot is a band two faces wide, one face longer than the chain at an end
// inside P. Hexes: 2 per face + 2 per boundary edge (the standard count, so predicted_hexes is unchanged); no
// interior irregular edge along the chain (a fan block has one of valence 2 x degree per fan edge); the foot's
// outline edges become boundary edges with one more hex (valence 3 on P's plates).
//
// Flanges (docs/blocks.md, "The flange docked on the plate's border"): a chain on part of P's border (every chain
// edge has one face of P and walls within kDockWallTiltDeg of P's normal, at most one per side; P's border runs on in
// line past both ends; edge degree 3 or 4, or 2 when P and the wall are one leaflet creased along the chain, which the
// analysis then cuts into two) is docked on P's border: its edges are P's border edges (edge_docked 3: half-chunks,
// counted as boundary edges), its vertices P's border vertices (6 ids, P's normal and out alone), and a wall's copies
// at a chain vertex u are centre -> X(u), on P's side -> X(sigma(u)), on the other side -> XO(u); at its end w
// out -> X(x), out on P's side -> X(x+), out on the other side -> XO(x) (x: P's border neighbour of w past the chain,
// x+ the corner of P's face (w, sigma, x+, x) opposite w). The walls' first hexes stand on P's plates and on the
// chain's half-chunks, their end half-chunks on the plate and the half-chunk of (w, x); the standard count holds. A
// chain that does not meet these stays a fan.
//
// Corner cubes (docs/blocks.md, "Flanges from the plate's corner: the corner cube"): a flange chain may start at P's
// corner c (one face of P there, P's border turning within kCornerCubeMaxSkewDeg of a right angle; at most one end of
// a chain: a chain from corner to corner stays a fan). c then has three out columns instead of one: A and B, straight
// out of each of its two border edges (the half-chunk of the border edge that P's face leaves c by uses A, the other
// B), and K = A + B - c (the usual out column, ids +3 .. +5), each with its up and down copies: 12 ids (centre, up,
// down, K, KU, KD, A, AU, AD, B, BU, BD), and 2 corner hexes (c, B, K, A | up copies) and its mirror below (2 more
// hexes than the standard count). A wall's copies at c: on P's side X(sigma(c)) as above, on the other side X of
// the chain edge's column (AU / AD or BU / BD); at its end out -> X of the other border edge's column, out on P's side
// -> XO(sigma(c)), out on the other side -> X(K): the wall's end half-chunk stands on the half-chunk of (c, sigma(c))
// and on the corner cube.
// Conditions (else Error(UnsupportedConfiguration) naming the vertex, with an edit suggestion): the chain is a path;
// at every chain vertex P has 4 faces, each containing a chain edge (the chain runs straight through P's grid), or at
// an end 4 faces and no border (inside) or 2 faces and 2 border edges (on the border); no branch edge at a chain
// vertex; each wall has only the faces on its chain edges at a chain vertex and ends there with one boundary edge; at
// most one wall per side of the plate; every vertex of a foot is an ordinary leaflet vertex (interior or border); no
// two feet (or a foot and a branch rooted on the plates) on the same plate face (checked by the analysis' rooted-patch
// check, see docked_foot_quads).
#include <array>
#include <vector>

#include "mesohex/core/skeleton.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

// Smallest angle (degrees) between the in-plane directions of the two plate faces at a chain edge (from the edge to
// the opposite side of each face): 150 = a plate bent by at most 30 degrees across the chain.
inline constexpr double kDockPlateAngleDeg = 150;

// A flange chain's end at its plate's corner gets a corner cube (see "Corner cubes" above) when the plate's two border
// edges there are within this many degrees of a right angle (the cube's corner hexes then have a scaled Jacobian of
// at least cos(kCornerCubeMaxSkewDeg) at c); other corners leave the chain a fan.
inline constexpr double kCornerCubeMaxSkewDeg = 30;

// Offset from a corner cube vertex c's first raw id of the out column (out, out-up, out-down) that the half-chunk of
// border edge e of c's plate uses there: 6 (A) when the plate's face f at c leaves c by e, else 9 (B: f arrives at c
// by e).
inline constexpr int kCornerCubeColumnA = 6, kCornerCubeColumnB = 9;
int corner_cube_column(const SkeletonAnalysis& analysis, int f, int c, int e);

// Largest angle (degrees) between a wall's direction from the chain (in-plane for the wall, perpendicular to the chain)
// and the plate's normal on its side: the first wall hexes on the acute side are wedges of about that opening.
// The raw minimum scaled Jacobian falls as the wall leans (measurements: docs/blocks.md, "Docked walls").
inline constexpr double kDockWallTiltDeg = 45;

// The band pillow (skeleton_repair.cpp, SkeletonRepairOptions::docked_band_pillow) puts a path vertex's copy on the
// miter of the path's two sides' directions into their faces (on one side), only where the cosine of the angle between
// them, i.e. of the path's turn there, exceeds kBandPillowMinTurnCos (dimensionless): turns of at most
// acos(-0.25) = 104.5 degrees (the miter then at most 1 / cos(52.2 degrees) = 1.63 band widths long). The analysis'
// refusal of a chain the pillow did not take states the limit in degrees (band_pillow_max_turn_deg).
inline constexpr double kBandPillowMinTurnCos = -0.25;
// acos(kBandPillowMinTurnCos) in degrees: the sharpest turn of a band path the pillow takes.
double band_pillow_max_turn_deg();

// Analysis step (after leaflets and face normals, before vertex classes): fills analysis.edge_docked and
// analysis.vertex_plate; first cuts a creased leaflet along a flange's chain (a new leaflet for the wall's part, face
// orientations kept). A fan chain with an end inside a leaflet that cannot be docked is refused here, naming the
// vertex and why; with band_pillow, a chain vertex whose plate grid does not match the foot (the straight-through
// condition below) is listed in analysis.docked_unmatched instead (AnalysisOptions::docked_band_pillow); pillow_ran
// (AnalysisOptions::docked_band_pillow_ran) only words that refusal otherwise. A chain with all ends on the plate's
// border whose plate the chain cuts into two leaflets docks too when a leaflet stops on the chain (a wall across the
// plate with a shorter wall on the other side): the two halves are joined into one leaflet first (the second's faces
// take the first's id, turned to its orientation), then the chain docks as above. Serial, O(E + F) plus the faces of
// the chain vertices.
void find_docked_walls(const Skeleton& skeleton, SkeletonAnalysis& analysis, bool band_pillow = false,
                       bool pillow_ran = false);

// The first step of find_docked_walls, also the repair's view of docked plates (skeleton_repair.cpp: the foot split
// and the band pillow take the chains the analysis docks): every fan-edge chain (a path, 2 ends) with all ends on
// borders, cutting its plate into two leaflets, on which a leaflet stops (the two chain edges at an inner vertex carry
// different leaflets: a wall across a plate with a shorter wall on the other side) has its plate's halves joined into
// one leaflet (the second's faces take the first's id, turned to its orientation) when the halves are the one pair of
// leaflets continuing across every chain edge (one face each, in-plane directions at least kDockPlateAngleDeg apart),
// they run the chain edges with one relative orientation, and every chain edge then splits into that plate and walls
// (at most 4 faces, one wall per side, each within kDockWallTiltDeg of the plate's normal). Needs the analysis'
// incidence, edge degrees, faces, leaflets and face normals (analyze_leaflets); changes face_leaflet, leaflets and the
// turned faces' face_vertices, face_edges, face_normal. Returns per edge 1 on a chain whose halves were joined.
std::vector<char> join_plates_across_chains(const Skeleton& skeleton, SkeletonAnalysis& analysis);

// The foot condition at a chain vertex with chain_edges chain edges (1 at an end, 2 inside), plate_faces faces of the
// plate and plate_border plate border edges there, straight when each plate face holds at most one chain edge (exactly
// one inside the chain): 4 faces and no border, or at an end on the border 2 faces and 2 border edges. Shared by the
// analysis (find_docked_walls) and the band pillow repair (skeleton_repair.cpp).
bool docked_foot_matches(int chain_edges, int plate_faces, int plate_border, bool straight);

// The class of docked chain vertex v by its plate alone (LeafletInterior, or LeafletBoundary at a border end), and its
// plate's boundary edges there (0 or 2).
VertexClass docked_vertex_class(const SkeletonAnalysis& analysis, int v, int& plate_boundary_edges);

// A quad of a plate's outer surface that a wall hex stands on: the X-side face of plate face `id` (kind 0), of the
// half-chunk of plate boundary edge `id` (kind 1), or of the corner cube at vertex `id` (kind 2); up = P's up side.
// wall = the wall's leaflet, vertex = the chain vertex it is docked at (for messages).
struct FootQuad {
    int kind = 0, id = -1;
    bool up = true;
    int wall = -1, vertex = -1;
};
// Every foot quad, once per wall hex standing on it, in face order of the walls. Needs the full analysis (classes).
// Throws Error(UnsupportedConfiguration) naming the chain vertex if a foot vertex is not an ordinary leaflet vertex.
std::vector<FootQuad> docked_foot_quads(const Skeleton& skeleton, const SkeletonAnalysis& analysis);

// Raw-mesh ids of a wall's face corner at a docked chain vertex: centre, up, down, and at the wall's end (a wall
// boundary edge at the corner) out, out-up, out-down (-1 otherwise). vertex_base: the raw mesh's per skeleton vertex
// first id (a leaflet vertex: centre, up, down, out, out-up, out-down). Per face corner f * 4 + k; all -1 except at
// wall corners on docked chain vertices; empty when nothing is docked.
std::vector<std::array<int, 6>> docked_corner_ids(const Skeleton& skeleton, const SkeletonAnalysis& analysis,
                                                  const std::vector<int>& vertex_base);

}  // namespace mesohex
