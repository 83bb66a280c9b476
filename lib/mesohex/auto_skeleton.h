#pragma once
// The skeleton `mesohex auto` meshes a surface with: the mean-curvature-flow curve skeleton for tubular
// shapes, the medial meso-skeleton (compute_medial_axis -> import_medial_mesh: curve branches + quad leaflets) where
// the shape has flat or thin parts. The choice is made from measured geometry: the medial axis's sheet fraction
// (MedialAxis::sheet_fraction: the share of its measure that is sheet-like triangles rather than curves), then the
// raw mesh of the imported meso-skeleton (mesh_skeleton without finishing, about 0.1 s): Auto keeps the meso-skeleton
// only when that raw mesh is valid, has at most max_raw_inverted inverted hexes and a minimum scaled Jacobian of at
// least min_raw_sj (the finishing repairs a few, not many, and spends its whole time budget trying).
#include <string>

#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/skeleton.h"
#include "mesohex/mesh.h"
#include "mesohex/stages/medial_import.h"
#include "mesohex/stages/raw_mesh.h"
#include "mesohex/surface/medial_axis.h"
#include "mesohex/surface/skeletonize.h"

namespace mesohex {

enum class SkeletonKind { Auto, Curve, Meso };

// Where the inverted hexes (scaled Jacobian <= 0) of a raw mesh lie, by the skeleton element that made each one
// (RawMesh::hex_edge). A join is a skeleton vertex with both a leaflet face and a branch edge (a curve meeting a
// sheet: BL-joint, branch rooted on a leaflet, branching point with leaflets).
struct RawInversionSites {
    long plates = 0;       // hex_edge -1: leaflet plates (and 8-hex or fan blocks)
    long half_chunks = 0;  // on a leaflet edge (a face side): the half-chunks along a leaflet border
    long chunks = 0;       // on a branch edge
    long at_joins = 0;     // of the half-chunks and chunks, those whose edge has an end at a join
    long joins = 0;        // joins in the skeleton
};

// Caps the radius of every corner of a face that has a join among its corners (a join: a vertex with both a face and
// an edge that is no face side), except the joins themselves, at factor x the corner's shortest face side; returns how
// many radii were lowered. Other vertices keep theirs. Preconditions: radii has one entry per point. Deterministic.
int cap_leaflet_radii(Skeleton& skeleton, double factor);

// Caps the radius of every leaflet border vertex (an end of a face side that lies on exactly one face), joins
// included, at factor x its shortest border side; returns how many radii were lowered. The mesher puts a half-chunk
// of two hexes on every border side, between the two ends' columns (centre, up, down at +-r along the normal) and
// their out columns (at about r along the border's outward bisector); where a border side is short against r next
// to a corner of the border or a crease of the sheet, the two out columns cross within r and the half-chunk and its
// plate fold (docs/sheets.md, "Short border sides").
// Preconditions: radii has one entry per point. Deterministic.
int cap_border_radii(Skeleton& skeleton, double factor);

// Preconditions: raw was built from `meshed` (hex_edge indexes meshed.edges, one entry per hex). Deterministic.
RawInversionSites locate_raw_inversions(const Skeleton& meshed, const RawMesh& raw);

// The import options `auto` uses for the medial meshes it computes: the defaults, with the leaflet smoothing kept
// within 0.25 x the radius of the medial sheet (MedialImportOptions::max_sheet_offset): compute_medial_axis fits its
// spheres to the surface, and smoothing them off the sheet leaves the hexes short of it (docs/sheets.md).
inline MedialImportOptions meso_import_options() {
    MedialImportOptions o;
    o.max_sheet_offset = 0.25;
    return o;
}

struct AutoSkeletonOptions {
    SkeletonKind kind = SkeletonKind::Auto;  // Curve / Meso force one; Auto decides
    // Auto: the meso-skeleton when the medial axis's sheet fraction is at least this (dimensionless, 0..1). Tubes
    // give 0 to 0.1 (thin bundles become curves), plates and disks 0.9 and more.
    double min_sheet_fraction = 0.3;
    // Auto: the meso-skeleton only when every surface vertex is within this x diagonal of the medial mesh's swept
    // spheres (dimensionless, x diagonal): a part the angle filter lost leaves a larger gap (docs/tuning.md).
    double max_coverage_gap = 0.2;
    long max_raw_inverted = 0;  // Auto: the meso-skeleton's raw mesh may have at most this many inverted hexes
    // Auto: ... and its minimum scaled Jacobian must be at least this (dimensionless): the lowest raw minimum the
    // finishing was measured to lift above 0.3 (docs/sheets.md, "Smoothing on the medial sheet").
    double min_raw_sj = 0.05;
    // The meso-skeleton's radii: meso_radius_factor x each vertex's distance to the surface (dimensionless; 0 keeps
    // the medial radii, which are the full distance). The raw mesh then fills about half of the inscribed ball, as
    // with `mesh --surface` on a skeleton without radii: room for the padding layer, and a leaflet's hex layers
    // stay clear of the fold where a bent sheet's offset at the full radius meets itself (docs/tuning.md).
    double meso_radius_factor = 0.5;
    // The meso-skeleton's radii tried first: meso_full_radius_factor x each vertex's distance to the surface
    // (dimensionless; 0 = off: meso_radius_factor only). A good medial mesh meets the goals at its full radii (the
    // shared medial meshes do, and miss at half: docs/sheets.md, "The shared medial meshes on auto's path"); a folded
    // one inverts raw hexes there. So the raw mesh (mesh_skeleton without finishing, about 0.5 s) is built at this
    // factor first, and the meso-skeleton takes meso_radius_factor instead when that raw mesh is invalid, has more
    // than max_raw_inverted inverted hexes, a minimum scaled Jacobian below min_raw_sj, or cannot be built; the
    // report says which factor was used and why (AutoSkeleton::meso_radius_factor_used, meso_radius_why).
    double meso_full_radius_factor = 1.0;
    // The meso-skeleton's leaflet vertices next to a join (the corners of every face that has a join, a vertex with
    // both faces and curve edges, among its corners; the join itself keeps its radius, which its branch's first chunk
    // needs): radius at most this x the vertex's shortest leaflet edge (a side of one of its faces; dimensionless; 0:
    // no cap). Where a sheet meets a curve the medial sheet can be thick against its simplified triangles (border
    // edges at the BL-joints shorter than the radius): the plate hexes there are taller than wide and the half-chunks
    // at the leaflet corner fold whatever the joint's frame. Elsewhere the radii stay (capping every leaflet vertex
    // makes the fit stretch the padding across the thickness). Measurements per surface: docs/sheets.md ("Thick
    // leaflets at joins") and docs/tuning.md.
    double meso_leaflet_radius_edge_factor = 0.35;
    // The meso-skeleton's leaflet border vertices (cap_border_radii): radius at most this x the vertex's shortest
    // border side (dimensionless; 0: no cap). Off by default: it removes raw inversions at short border sides but
    // can make `auto` take a meso-skeleton that finishes worse than the curve answer (measurements: docs/sheets.md,
    // "Short border sides", and docs/tuning.md).
    double meso_border_radius_edge_factor = 0;
    // Auto: the answer. When the raw mesh of the curve skeleton Auto falls back to is invalid or has more than
    // max_answer_inverted inverted hexes, raw or after the finishing's padding layer, `refusal` says so (a
    // meso-skeleton is only chosen with a raw mesh that passed its own, stricter check): the finishing would have to
    // untangle it, which spends its round caps (the slow part of `auto` on the shared plates with holes, and the
    // result then misses the targets anyway; docs/skeletons.md). The CLI refuses such a surface unless --best-effort.
    long max_answer_inverted = 0;
    // The raw meshes of the checks above (meso and curve) are built with these options (the CLI passes the mesh job's,
    // so the check judges the raw mesh the answer is finished from).
    RawMeshOptions raw_mesh;
    MedialAxisOptions medial;
    MedialImportOptions import = meso_import_options();  // max_sheet_offset 0.25 (see meso_import_options)
    SkeletonizeOptions skeletonize;
};

struct AutoSkeleton {
    Skeleton skeleton;                        // with radii, one per point
    SkeletonKind kind = SkeletonKind::Curve;  // Curve or Meso: the one returned
    std::string reason;                       // why this kind, in words, with the numbers
    bool medial_computed = false;             // the medial axis was computed (Auto or Meso)
    MedialAxis medial;                        // when medial_computed: the medial mesh and its measures
    MedialImport import;                      // when kind == Meso
    Skeletonization curve;                    // when kind == Curve
    double coverage_gap = 0;                  // Auto: largest surface-to-medial-spheres gap, x bbox diagonal
    bool raw_checked = false;                 // the meso-skeleton's raw mesh was built (Auto or Meso)
    long raw_hexes = 0, raw_inverted = 0;
    double raw_sj_min = 0;
    bool raw_valid = false;
    int capped_leaflet_radii = 0;  // meso-skeleton radii lowered by meso_leaflet_radius_edge_factor
    int capped_border_radii = 0;   // meso-skeleton radii lowered by meso_border_radius_edge_factor
    RawInversionSites raw_sites;   // where the meso raw mesh's inverted hexes lie (when raw_checked)
    // The meso-skeleton's radius factor (x distance to the surface; 0: the medial radii) and why: the full factor
    // (meso_full_radius_factor) when its raw mesh passed the check, else meso_radius_factor (kind Meso or raw_checked).
    double meso_radius_factor_used = 0;
    std::string meso_radius_why;
    // The raw mesh at meso_full_radius_factor when it failed the check and the meso-skeleton fell back to
    // meso_radius_factor (the numbers above are then the fallback's): hexes, inverted, min SJ, valid, and the error
    // when it could not be built (empty otherwise).
    bool full_raw_failed = false;
    long full_raw_hexes = 0, full_raw_inverted = 0;
    double full_raw_sj_min = 0;
    bool full_raw_valid = false;
    std::string full_raw_error;
    // Auto, curve skeleton chosen: its raw mesh (mesh_skeleton without finishing, radii of the skeleton file).
    bool curve_raw_checked = false;
    bool curve_raw_valid = false;
    long curve_raw_hexes = 0, curve_raw_inverted = 0;
    double curve_raw_sj_min = 0;
    long curve_padded_inverted = 0;  // inverted hexes after the finishing's padding layer on that raw mesh
    // The re-centred curve skeleton (SkeletonizeOptions::recentre_passes) failed that check and the flow's own curve
    // (Skeletonization::flow_skeleton) inverted fewer hexes: the skeleton (and the numbers above) are the flow's.
    bool curve_recentring_dropped = false;
    // Auto: non-empty when the chosen skeleton's raw mesh is invalid or has more than max_answer_inverted inverted
    // hexes; says why, with both skeletons' raw numbers (the skeleton is still returned, for editing).
    std::string refusal;
};

// "curve" / "meso" (Auto: "auto").
const char* skeleton_kind_name(SkeletonKind kind);

// Chooses and computes the skeleton of a closed, manifold surface. Auto: computes the medial axis; when its sheet
// fraction is >= min_sheet_fraction, imports it (meso-skeleton), else skeletonizes (curve). If the medial axis cannot
// be computed or imported (a mesohex::Error), Auto falls back to the curve skeleton and says why in `reason`; a forced
// kind lets the error propagate. Preconditions: those of skeletonize_surface / compute_medial_axis (InvalidInput
// naming the element otherwise). Deterministic.
AutoSkeleton choose_skeleton(const TriangleMesh& surface, const AutoSkeletonOptions& options = {});

// Auto chose the meso-skeleton (`meso`) and its finished mesh missed a goal (`why`, in words): the curve skeleton of
// the same surface, with meso's medial measures and raw numbers kept and `why` added to its reason, judged like Auto's
// own curve answer (`refusal` set when its raw mesh is invalid or inverted). The caller finishes it and keeps the
// better of the two finished meshes (`mesohex auto`: better_finish). Deterministic.
AutoSkeleton curve_instead(const TriangleMesh& surface, const AutoSkeletonOptions& options, const AutoSkeleton& meso,
                           const std::string& why);

}  // namespace mesohex
