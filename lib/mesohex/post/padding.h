#pragma once
// Padding: one layer of hexes over every boundary component of a hex mesh (the reference pads only one component).
#include <array>
#include <functional>
#include <vector>

#include "mesohex/core/cone.h"
#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct PaddingOptions {
    int layers = 1;  // number of layers added, one after the other (each over the whole new boundary)
    // Offset of the new outer vertices, x the SHORTEST boundary edge at the vertex (dimensionless): on a tube of long
    // hexes (edges of 3 radii along the branch) the mean edge gave a layer as thick as the tube, which reached into the
    // concave corners between branches and across the gap to a neighbouring tube, and the fit then left webs of hexes
    // there (measurements: docs/tuning.md).
    double thickness = 0.25;
    // The shortest edge above also counts the edges from the vertex into the mesh (one end on the boundary, the other
    // not): on a thin sheet (plate hexes of edge L and height r << L) the layer is then thickness x r, not
    // thickness x L, which on a sheet of thickness 2r reached past the opposite side of a sharp crease and across the
    // gap between two sheets, where the fit could not pull it back (docs/sheets.md). false: boundary edges only.
    // Off by default until it is measured on the whole random set (docs/sheets.md: it changes every leaflet model).
    bool inward_edges = false;
    // The largest scale of the offset (1 / mean cos, see pad below) at a concave boundary vertex: one whose quads'
    // centroids lie outwards of it along its direction m on average (concave_vertices below: the valley
    // between two branches' chunks, the pit among three). The scale carries a convex corner to the
    // offset cube's corner; at a concave one (the crotch between branches of a junction, whose raw boundary already
    // touches the domain there) it carried the layer up to 3 x its thickness out into the crotch, outside the domain,
    // where the fit could not pull it back (docs/junctions.md, "The shared curve skeletons: the padding in the
    // crotch"). Dimensionless, > 0; 1: the layer's own thickness there; 3 or more: the same scale as at convex
    // vertices, byte-identical to no rule (the default: 1 was mixed on the shared skeletons, docs/junctions.md).
    double concave_scale = 3.0;
    // > 0: a guard on the new hexes' scaled Jacobians (a value in (0, 1]). Directions: at a boundary vertex where the
    // mean normal leaves the bottom corner of some new hex below the guard (that corner's value is sin of the quad's
    // corner angle x cos of the direction to the corner's normal: a valley or ridge whose quads turn steeply, a
    // vertex whose quads lie mostly on one side), the direction turns towards the one that maximises the worst of
    // those corners, as little as reaches min(guard, that maximum); the bottom corners are then at least
    // min(guard, the best any direction allows there). Thickness: a new hex below half of min(guard, its worst bottom
    // corner) (directions converging past each other's rays in a valley, a steeply turned direction sliding its top
    // vertex sideways, unequal offsets tilting the top face) gets the offsets of its four vertices scaled by 0.7, up
    // to 10 rounds: as a neighbourhood's offsets shrink together, its top corners tend to its bottom ones. Vertices of
    // bare quads keep their direction. 0: neither (the mean normal, offsets as above).
    double corner_guard = 0;
    // > 0: a direction search at folded vertices (a cosine in (0, 1]). At a boundary vertex (not of a bare quad) where
    // the direction leaves the unit normal of one of its quads' corners at a cosine below this (a valley whose quads
    // fold past 270 degrees: the crotch between a junction's chunks), the direction is the best of five on the great
    // circle from it to the axis of the narrowest cone around those corner normals (maximin_direction; a quarter of
    // the way per step, the first candidate being the direction itself): the one whose new hexes around the vertex
    // have the largest smallest scaled Jacobian, at the vertex's offset, the other new vertices where they are. Two
    // sweeps in vertex order, before the inverted hexes are repaired. Unlike corner_guard the offsets stay and a
    // direction turns only where its own hexes get better. 0: off (the mean normal).
    double search_cos = 0;
    double absolute_thickness = 0;  // > 0: use this offset (model units) everywhere instead of `thickness`
    // Optional: the offset of a boundary vertex at p moving along the unit direction d, given the offset t from the
    // rules above, the offset t_scaled with the convex scale even at a concave vertex (= t elsewhere; a rule that
    // knows the layer stays inside the domain may go that far) and the mean boundary edge length at the vertex (called
    // once per boundary vertex and layer, serially, in vertex order). finish_mesh uses it to reach the domain surface
    // (FinishOptions::pad_to_domain).
    std::function<double(const Vec3& p, const Vec3& d, double t, double t_scaled, double mean_edge)> offset_rule;
    // Selective padding (pad_selection.h): boundary quads, matched by their vertex set (any order), that get no
    // padding hex, in every layer. The layer then ends on the boundary around them: the side face of a padding hex on
    // a padded quad next to a bare one becomes boundary. At a vertex of both, the new vertex moves along the padded
    // quads' mean normal projected onto the bare quads' tangent plane (the side face continues the bare face), with
    // the offset scaled as elsewhere. Empty: every boundary quad is padded.
    std::vector<std::array<int, 4>> bare_quads;
};

struct PaddingResult {
    long bare_quads = 0;  // boundary quads left without a padding hex (PaddingOptions::bare_quads), summed over layers
    HexMesh mesh;  // old vertices keep their ids, new vertices are appended; old hexes first, then the new layer(s)
    // Per vertex of `mesh`: the vertex of the INPUT mesh it stems from (itself for old vertices, the boundary vertex it
    // was pushed from for new ones; for layers > 1, followed through the previous layers).
    std::vector<int> origin_vertex;
    // Per hex of `mesh`: 0 for the input hexes, k for hexes of the k-th padding layer.
    std::vector<int> layer_of_hex;
    int first_new_vertex = 0;  // = input vertex count
    int first_new_hex = 0;     // = input hex count
};

// For every boundary quad (a, b, c, d) (outward) adds the hex (a, b, c, d, a', b', c', d'), where v' is a new vertex
// per boundary vertex v, at p_v + t_v * m_v: m_v is the unit mean of the unit normals of the boundary quads at v,
// scaled by 1 / (mean over those quads of m_v . n_q) (clamped to at most 3, at a concave vertex to concave_scale) so
// that a planar face moves by t_v and a convex cube corner moves to the corner of the offset cube; t_v = thickness x
// (shortest boundary edge at v, or edge into the mesh with inward_edges) or absolute_thickness. A new hex that would be
// inverted gets the offsets of its outer vertices halved (up to 6 times); if it stays inverted, the directions of its
// vertices are tilted toward their worst-facing quad normal and the offsets restored, then halved again (up to 20
// times). Every boundary component is padded; new vertices are numbered in order of first
// appearance in the boundary quads of compute_hex_topology, the new hexes in boundary-quad order.
// Postconditions: hex count = old + number of boundary quads (per layer); every boundary hex of the result exposes
// exactly one face to the boundary when the input boundary is a closed 2-manifold; old boundary edges of valence 1
// (convex feature lines) become interior edges of valence 3. Euler characteristic is preserved.
// Preconditions: indices in range (InvalidInput otherwise); layers >= 0; thickness > 0.
// Complexity: O(#hexes log #hexes) per layer.
PaddingResult pad(const HexMesh& mesh, const PaddingOptions& options = {});

// lowest_corner, maximin_direction: mesohex/core/cone.h (the corner guard of PaddingOptions).

// Per boundary vertex (by local index: local[v] for every vertex v of `quads`; unit_normal has one entry per local
// index): 1 when the boundary is concave there in the mean: the mean of the centroids of its quads lies outwards of
// it along its unit direction unit_normal (sum over its quads of m . (centroid_q - p) above 1e-9 x the sum of
// |centroid_q - p|; 0 on a flat patch, and the tolerance keeps flat vertices out whatever the rounding). A valley
// between two branches' chunks, the pit among three, count; a tube's wall and a convex corner do not; a vertex in no
// quad does not. (PaddingOptions::concave_scale; PadInsetOptions::concave_only.) O(quads).
std::vector<char> concave_vertices(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                                   const std::vector<Vec3>& unit_normal, const std::vector<int>& local);

// For every vertex v with local[v] >= 0 (local: per vertex of `mesh`, its index among the boundary vertices, -1 if
// none): shortest[local[v]] = min(itself, the length of every hex edge from v to a vertex with local = -1).
// O(hexes). (PaddingOptions::inward_edges)
void shorten_to_inward_edges(const HexMesh& mesh, const std::vector<int>& local, std::vector<double>& shortest);

}  // namespace mesohex
