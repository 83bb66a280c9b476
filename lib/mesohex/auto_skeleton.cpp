#include "mesohex/auto_skeleton.h"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "mesohex/core/error.h"
#include "mesohex/finish.h"
#include "mesohex/post/quality.h"
#include "mesohex/surface/radius_from_surface.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex {

const char* skeleton_kind_name(SkeletonKind kind) {
    switch (kind) {
        case SkeletonKind::Auto: return "auto";
        case SkeletonKind::Curve: return "curve";
        case SkeletonKind::Meso: return "meso";
    }
    return "auto";
}

int cap_leaflet_radii(Skeleton& skeleton, double factor) {
    MESOHEX_CHECK(skeleton.radii.size() == skeleton.points.size(), "cap_leaflet_radii: one radius per point");
    if (!(factor > 0)) return 0;
    const size_t n = skeleton.points.size();
    std::set<std::array<int, 2>> sides;
    std::vector<double> shortest(n, std::numeric_limits<double>::infinity());
    std::vector<char> in_face(n, 0), on_curve(n, 0);
    for (const std::vector<int>& f : skeleton.faces)
        for (size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            sides.insert({std::min(a, b), std::max(a, b)});
            const double len =
                distance(skeleton.points[static_cast<size_t>(a)], skeleton.points[static_cast<size_t>(b)]);
            for (const int x : {a, b}) {
                shortest[static_cast<size_t>(x)] = std::min(shortest[static_cast<size_t>(x)], len);
                in_face[static_cast<size_t>(x)] = 1;
            }
        }
    for (const std::array<int, 2>& e : skeleton.edges)
        if (!sides.count({std::min(e[0], e[1]), std::max(e[0], e[1])}))
            on_curve[static_cast<size_t>(e[0])] = on_curve[static_cast<size_t>(e[1])] = 1;
    auto is_join = [&](int x) { return in_face[static_cast<size_t>(x)] && on_curve[static_cast<size_t>(x)]; };
    std::vector<char> near(n, 0);  // a corner, not itself a join, of a face that has a join among its corners
    for (const std::vector<int>& f : skeleton.faces)
        if (std::any_of(f.begin(), f.end(), is_join))
            for (const int x : f) near[static_cast<size_t>(x)] = is_join(x) ? 0 : 1;
    int capped = 0;
    for (size_t v = 0; v < n; ++v)
        if (near[v] && skeleton.radii[v] > factor * shortest[v]) {
            skeleton.radii[v] = factor * shortest[v];
            ++capped;
        }
    return capped;
}

int cap_border_radii(Skeleton& skeleton, double factor) {
    MESOHEX_CHECK(skeleton.radii.size() == skeleton.points.size(), "cap_border_radii: one radius per point");
    if (!(factor > 0)) return 0;
    std::map<std::array<int, 2>, int> side_faces;  // face side (sorted ends) -> faces on it
    for (const std::vector<int>& f : skeleton.faces)
        for (size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            ++side_faces[{std::min(a, b), std::max(a, b)}];
        }
    std::vector<double> shortest(skeleton.points.size(), std::numeric_limits<double>::infinity());
    for (const auto& [side, faces] : side_faces) {
        if (faces != 1) continue;  // not a border side
        const double len =
            distance(skeleton.points[static_cast<size_t>(side[0])], skeleton.points[static_cast<size_t>(side[1])]);
        for (const int x : side) shortest[static_cast<size_t>(x)] = std::min(shortest[static_cast<size_t>(x)], len);
    }
    int capped = 0;
    for (size_t v = 0; v < shortest.size(); ++v)
        if (skeleton.radii[v] > factor * shortest[v]) {
            skeleton.radii[v] = factor * shortest[v];
            ++capped;
        }
    return capped;
}

RawInversionSites locate_raw_inversions(const Skeleton& meshed, const RawMesh& raw) {
    RawInversionSites out;
    std::set<std::array<int, 2>> sides;
    std::vector<char> in_face(meshed.points.size(), 0), on_branch(meshed.points.size(), 0);
    for (const std::vector<int>& f : meshed.faces)
        for (size_t k = 0; k < f.size(); ++k) {
            const int a = f[k], b = f[(k + 1) % f.size()];
            sides.insert({std::min(a, b), std::max(a, b)});
            in_face[static_cast<size_t>(a)] = 1;
        }
    std::vector<char> is_side(meshed.edges.size(), 0);
    for (size_t e = 0; e < meshed.edges.size(); ++e) {
        const int a = meshed.edges[e][0], b = meshed.edges[e][1];
        is_side[e] = sides.count({std::min(a, b), std::max(a, b)}) ? 1 : 0;
        if (!is_side[e]) on_branch[static_cast<size_t>(a)] = on_branch[static_cast<size_t>(b)] = 1;
    }
    auto join = [&](int v) { return in_face[static_cast<size_t>(v)] && on_branch[static_cast<size_t>(v)]; };
    for (size_t v = 0; v < meshed.points.size(); ++v) out.joins += join(static_cast<int>(v)) ? 1 : 0;
    const std::vector<double> sj = scaled_jacobians(raw.mesh);
    for (size_t h = 0; h < sj.size() && h < raw.hex_edge.size(); ++h) {
        if (sj[h] > 0) continue;
        const int e = raw.hex_edge[h];
        if (e >= static_cast<int>(meshed.edges.size())) {
            ++out.chunks;  // not an edge of `meshed` (precondition broken): counted, not placed
            continue;
        }
        if (e < 0) {
            ++out.plates;
            continue;
        }
        ++(is_side[static_cast<size_t>(e)] ? out.half_chunks : out.chunks);
        if (join(meshed.edges[static_cast<size_t>(e)][0]) || join(meshed.edges[static_cast<size_t>(e)][1]))
            ++out.at_joins;
    }
    return out;
}

namespace {

// Largest distance from a surface vertex to the union of the medial mesh's spheres, swept along its edges and
// triangles (points every 1/8 of an edge, a 4 x 4 barycentric grid per triangle, radii interpolated): a part of the
// shape the medial mesh lost (cut off by the angle filter and dropped as a smaller component) shows as a large gap.
double medial_coverage_gap(const TriangleMesh& surface, const Skeleton& medial) {
    std::vector<Vec3> centre;
    std::vector<double> radius;
    for (size_t v = 0; v < medial.points.size(); ++v) {
        centre.push_back(medial.points[v]);
        radius.push_back(medial.radii[v]);
    }
    for (const std::array<int, 2>& e : medial.edges)
        for (int k = 1; k < 8; ++k) {
            const double t = k / 8.0;
            centre.push_back((1 - t) * medial.points[static_cast<size_t>(e[0])] +
                             t * medial.points[static_cast<size_t>(e[1])]);
            radius.push_back((1 - t) * medial.radii[static_cast<size_t>(e[0])] +
                             t * medial.radii[static_cast<size_t>(e[1])]);
        }
    for (const std::vector<int>& f : medial.faces)
        for (int i = 1; i < 4; ++i)
            for (int j = 1; i + j < 4; ++j) {
                const double a = i / 4.0, b = j / 4.0, c = 1 - a - b;
                const size_t f0 = static_cast<size_t>(f[0]), f1 = static_cast<size_t>(f[1]),
                             f2 = static_cast<size_t>(f[2]);
                centre.push_back(a * medial.points[f0] + b * medial.points[f1] + c * medial.points[f2]);
                radius.push_back(a * medial.radii[f0] + b * medial.radii[f1] + c * medial.radii[f2]);
            }
    double gap = 0;
    for (const Vec3& p : surface.points) {
        double best = std::numeric_limits<double>::infinity();
        for (size_t s = 0; s < centre.size(); ++s) best = std::min(best, distance(p, centre[s]) - radius[s]);
        gap = std::max(gap, best);
    }
    return gap;
}

// The raw mesh (no finishing) of a skeleton with radii, in the surface; with `padded`, also the number of inverted
// hexes after the finishing's padding layer alone (the first stage of finish_mesh, with its defaults).
// With `sites`, also where its inverted hexes lie (locate_raw_inversions). The raw mesh with `raw_mesh`'s options.
QualityReport raw_quality_of(const Skeleton& skeleton, const TriangleMesh& surface, const RawMeshOptions& raw_mesh,
                             long* padded_inverted = nullptr, RawInversionSites* sites = nullptr) {
    MeshOptions raw_options;
    raw_options.finish = false;
    raw_options.pipeline.raw_mesh = raw_mesh;
    const MeshRun run = mesh_skeleton(skeleton, &surface, raw_options);
    if (sites) *sites = locate_raw_inversions(run.pipeline.skeleton, run.pipeline.raw);
    if (padded_inverted) {
        FinishOptions pad_only;
        pad_only.pad_improve_sj = 0;
        pad_only.subdivide = pad_only.fit = pad_only.untangle = pad_only.smooth = false;
        pad_only.improve_sj = 0;
        pad_only.measure_distance = false;
        *padded_inverted = finish_mesh(run.pipeline.raw.mesh, surface, pad_only).quality.inverted;
    }
    return run.raw_quality;
}

// The imported meso-skeleton with radii factor x each vertex's distance to the surface (0: the medial radii; a point on
// the surface keeps its own), then capped at joins and borders (cap_leaflet_radii, cap_border_radii).
Skeleton meso_with_radii(const Skeleton& imported, const SurfaceQuery& query, double factor,
                         const AutoSkeletonOptions& options, int* capped_leaflet, int* capped_border) {
    Skeleton s = imported;
    if (factor > 0) {
        RadiusFromSurfaceOptions ro;
        ro.factor = factor;
        const RadiusFromSurface rs = radius_from_surface(s, query, ro);
        for (size_t v = 0; v < rs.radii.size(); ++v)
            if (rs.radii[v] > 0) s.radii[v] = rs.radii[v];
    }
    *capped_leaflet = cap_leaflet_radii(s, options.meso_leaflet_radius_edge_factor);
    *capped_border = cap_border_radii(s, options.meso_border_radius_edge_factor);
    return s;
}

bool meso_raw_passes(const QualityReport& raw, const AutoSkeletonOptions& options) {
    return raw.validation.valid() && raw.inverted <= options.max_raw_inverted && raw.sj_min >= options.min_raw_sj;
}

// The meso-skeleton's radii (out.import.skeleton): meso_full_radius_factor x the distance when the raw mesh there
// passes the check (meso_raw_passes), else meso_radius_factor. Sets the raw numbers of the radii taken (raw_checked,
// raw_sites, meso_radius_*; full_raw_* when the full radii failed) and returns that raw mesh's quality. A raw mesh
// that cannot be built at the full radii (a mesohex::Error) falls back likewise; at the fallback radii it propagates.
QualityReport choose_meso_radii(AutoSkeleton& out, const TriangleMesh& surface, const AutoSkeletonOptions& options) {
    const SurfaceQuery query(surface);
    const Skeleton imported = out.import.skeleton;
    const double full = options.meso_full_radius_factor, half = options.meso_radius_factor;
    std::ostringstream why;
    if (full > 0 && full != half) {
        Skeleton s =
            meso_with_radii(imported, query, full, options, &out.capped_leaflet_radii, &out.capped_border_radii);
        try {
            RawInversionSites sites;
            const QualityReport raw = raw_quality_of(s, surface, options.raw_mesh, nullptr, &sites);
            if (meso_raw_passes(raw, options)) {
                out.import.skeleton = std::move(s);
                out.raw_sites = sites;
                out.meso_radius_factor_used = full;
                why << "full radii (" << full << " x distance): raw mesh passes";
                out.meso_radius_why = why.str();
                return raw;
            }
            out.full_raw_hexes = raw.hexes;
            out.full_raw_inverted = raw.inverted;
            out.full_raw_sj_min = raw.sj_min;
            out.full_raw_valid = raw.validation.valid();
            why << "full radii (" << full << " x distance): raw mesh " << raw.hexes << " hexes, " << raw.inverted
                << " inverted (min SJ " << raw.sj_min << (raw.validation.valid() ? "" : ", invalid") << ")";
        } catch (const Error& e) {
            out.full_raw_error = e.what();
            why << "full radii (" << full << " x distance): raw mesh failed (" << e.what() << ")";
        }
        out.full_raw_failed = true;
        why << ", fails the check; " << half << " x distance instead";
    } else {
        why << half << " x distance";
    }
    out.import.skeleton =
        meso_with_radii(imported, query, half, options, &out.capped_leaflet_radii, &out.capped_border_radii);
    out.meso_radius_factor_used = half;
    out.meso_radius_why = why.str();
    return raw_quality_of(out.import.skeleton, surface, options.raw_mesh, nullptr, &out.raw_sites);
}

void use_curve(AutoSkeleton& out, const TriangleMesh& surface, const AutoSkeletonOptions& options) {
    out.curve = skeletonize_surface(surface, options.skeletonize);
    out.skeleton = out.curve.skeleton;
    out.kind = SkeletonKind::Curve;
    if (options.kind != SkeletonKind::Auto) return;
    QualityReport q = raw_quality_of(out.skeleton, surface, options.raw_mesh, &out.curve_padded_inverted);
    // The re-centring moves joints by up to 0.75 x their radius: where that inverts raw (or padded) hexes that the
    // flow's own curve does not, keep the flow's curve (fewer inverted hexes, raw and padded together, and valid).
    const auto failing = [&](const QualityReport& r, long padded) {
        return !r.validation.valid() || r.inverted > options.max_answer_inverted ||
               padded > options.max_answer_inverted;
    };
    if (out.curve.recentred_joints > 0 && failing(q, out.curve_padded_inverted)) {
        long flow_padded = 0;
        const QualityReport flow = raw_quality_of(out.curve.flow_skeleton, surface, options.raw_mesh, &flow_padded);
        if (flow.validation.valid() &&
            (!q.validation.valid() || flow.inverted + flow_padded < q.inverted + out.curve_padded_inverted)) {
            out.skeleton = out.curve.flow_skeleton;
            out.curve_recentring_dropped = true;
            out.curve_padded_inverted = flow_padded;
            q = flow;
        }
    }
    out.curve_raw_checked = true;
    out.curve_raw_valid = q.validation.valid();
    out.curve_raw_hexes = q.hexes;
    out.curve_raw_inverted = q.inverted;
    out.curve_raw_sj_min = q.sj_min;
}

// Auto with the curve skeleton chosen: the refusal when its raw mesh cannot be finished without untangling.
void judge_curve_answer(AutoSkeleton& out, const AutoSkeletonOptions& options) {
    if (!out.curve_raw_checked) return;
    if (out.curve_raw_valid && out.curve_raw_inverted <= options.max_answer_inverted &&
        out.curve_padded_inverted <= options.max_answer_inverted)
        return;
    std::ostringstream why;
    why << "no skeleton gives a raw mesh without inverted hexes: curve skeleton " << out.curve_raw_hexes
        << " raw hexes, " << out.curve_raw_inverted << " inverted (min SJ " << out.curve_raw_sj_min << "), "
        << out.curve_padded_inverted << " inverted after the padding layer" << (out.curve_raw_valid ? "" : ", invalid");
    if (out.raw_checked)
        why << "; medial meso-skeleton " << out.raw_hexes << " raw hexes, " << out.raw_inverted << " inverted (min SJ "
            << out.raw_sj_min << "; " << out.raw_sites.at_joins << " of them next to the " << out.raw_sites.joins
            << " joins where its curves meet its sheets)";
    else if (out.medial_computed)
        why << "; medial meso-skeleton not tried (" << out.reason << ")";
    out.refusal = why.str();
}

}  // namespace

AutoSkeleton choose_skeleton(const TriangleMesh& surface, const AutoSkeletonOptions& options) {
    check_surface_for_skeleton(surface);  // either skeleton needs a closed solid: refuse a degenerate one first
    AutoSkeleton out;
    if (options.kind == SkeletonKind::Curve) {
        use_curve(out, surface, options);
        out.reason = "curve skeleton forced";
        return out;
    }
    std::ostringstream why;
    try {
        out.medial = compute_medial_axis(surface, options.medial);
        out.medial_computed = true;
        why << "medial axis: sheet fraction " << out.medial.sheet_fraction << " (" << out.medial.sheets << " sheets, "
            << out.medial.curves << " curves)";
        if (options.kind == SkeletonKind::Auto && out.medial.sheet_fraction < options.min_sheet_fraction) {
            why << " < " << options.min_sheet_fraction << ": tubular, curve skeleton";
            out.reason = why.str();
            use_curve(out, surface, options);
            judge_curve_answer(out, options);
            return out;
        }
        if (options.kind == SkeletonKind::Auto) {
            out.coverage_gap = medial_coverage_gap(surface, out.medial.medial) / out.medial.bbox_diagonal;
            why << "; coverage gap " << 100 * out.coverage_gap << " % of the diagonal";
            if (out.coverage_gap > options.max_coverage_gap) {
                why << " > " << 100 * options.max_coverage_gap << " %: the medial mesh misses a part, curve skeleton";
                out.reason = why.str();
                use_curve(out, surface, options);
                judge_curve_answer(out, options);
                return out;
            }
        }
        out.import = import_medial_mesh(out.medial.medial, options.import);
        {
            const QualityReport raw = choose_meso_radii(out, surface, options);
            out.raw_checked = true;
            out.raw_hexes = raw.hexes;
            out.raw_inverted = raw.inverted;
            out.raw_sj_min = raw.sj_min;
            out.raw_valid = raw.validation.valid();
        }
        if (options.kind == SkeletonKind::Auto) {
            why << "; meso radii: " << out.meso_radius_why << "; meso raw mesh " << out.raw_hexes << " hexes, "
                << out.raw_inverted << " inverted (min SJ " << out.raw_sj_min << ", radii "
                << out.meso_radius_factor_used << " x distance";
            if (options.meso_leaflet_radius_edge_factor > 0)
                why << ", " << out.capped_leaflet_radii << " leaflet radii at joins capped at "
                    << options.meso_leaflet_radius_edge_factor << " x their shortest leaflet edge";
            if (options.meso_border_radius_edge_factor > 0)
                why << ", " << out.capped_border_radii << " leaflet border radii capped at "
                    << options.meso_border_radius_edge_factor << " x their shortest border side";
            why << ")";
            if (out.raw_inverted > 0) {
                const RawInversionSites& w = out.raw_sites;
                why << " [inverted: " << w.at_joins << " next to the " << w.joins << " joins where curves meet sheets; "
                    << w.half_chunks << " along leaflet borders, " << w.chunks << " on branches, " << w.plates
                    << " in plates or blocks]";
            }
            if (!out.raw_valid || out.raw_inverted > options.max_raw_inverted || out.raw_sj_min < options.min_raw_sj) {
                why << ": more than " << options.max_raw_inverted << " inverted, min SJ below " << options.min_raw_sj
                    << " or invalid: curve skeleton instead";
                out.reason = why.str();
                use_curve(out, surface, options);
                judge_curve_answer(out, options);
                return out;
            }
        }
        out.skeleton = out.import.skeleton;
        out.kind = SkeletonKind::Meso;
        if (options.kind == SkeletonKind::Meso)
            why << ": meso-skeleton forced (radii: " << out.meso_radius_why << ")";
        else
            why << " >= " << options.min_sheet_fraction << ": flat or thin parts, medial meso-skeleton";
        out.reason = why.str();
        return out;
    } catch (const Error& e) {
        if (options.kind == SkeletonKind::Meso) throw;
        why << (out.medial_computed ? "; import or raw mesh failed: " : "medial axis failed: ") << e.what()
            << "; curve skeleton instead";
        out.reason = why.str();
    }
    use_curve(out, surface, options);
    judge_curve_answer(out, options);
    return out;
}

AutoSkeleton curve_instead(const TriangleMesh& surface, const AutoSkeletonOptions& options, const AutoSkeleton& meso,
                           const std::string& why) {
    AutoSkeleton out = meso;
    out.reason = meso.reason + "; " + why;
    use_curve(out, surface, options);
    judge_curve_answer(out, options);
    return out;
}

}  // namespace mesohex
