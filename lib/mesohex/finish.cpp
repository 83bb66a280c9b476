#include "mesohex/finish.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>

#include "mesohex/core/topology.h"
#include "mesohex/post/boundary_projection.h"
#include "mesohex/post/pad_inset.h"
#include "mesohex/post/subdivision.h"
#include "mesohex/surface/surface_check.h"
#include "mesohex/surface/surface_query.h"

namespace mesohex {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// `sj`: scaled_jacobians(mesh).
FinishStage measure(const std::string& name, double ms, const HexMesh& mesh, const std::vector<double>& sj) {
    FinishStage s;
    s.stage = name;
    s.ms = ms;
    s.vertices = static_cast<long>(mesh.points.size());
    s.hexes = static_cast<long>(mesh.hexes.size());
    double sum = 0;
    s.sj_min = sj.empty() ? 0 : sj.front();
    for (double v : sj) {
        sum += v;
        if (v < s.sj_min) s.sj_min = v;
        if (v <= 0) ++s.inverted;
    }
    s.sj_avg = sj.empty() ? 0 : sum / static_cast<double>(sj.size());
    return s;
}

FinishStage measure(const std::string& name, double ms, const HexMesh& mesh) {
    return measure(name, ms, mesh, scaled_jacobians(mesh));
}

FinishStage with_iterations(FinishStage stage, long iterations) {
    stage.iterations = iterations;
    return stage;
}

std::size_t count_boundary_vertices(const HexMesh& mesh) {
    std::vector<char> seen(mesh.points.size(), 0);
    std::size_t n = 0;
    for (const std::array<int, 4>& q : compute_hex_topology(mesh).boundary_quads)
        for (int v : q)
            if (!seen[static_cast<std::size_t>(v)]) {
                seen[static_cast<std::size_t>(v)] = 1;
                ++n;
            }
    return n;
}

// The domain, oriented outward, with its query structure (the surface outlives the query that refers to it).
struct Domain {
    int flipped = 0;  // declared (and so initialised) before `surface`, whose initialiser sets it
    TriangleMesh surface;
    SurfaceQuery query;
    static TriangleMesh oriented(const TriangleMesh& domain, int& flipped) {
        TriangleMesh surface = domain;
        if (check_surface(surface).signed_volume < 0) flipped = orient_outward(surface).flipped_triangles;
        return surface;
    }
    // Outward unit normals (the fit's facing test), per triangle and per vertex (area-weighted); both empty when the
    // oriented domain is still not consistently oriented (then the test is off).
    std::vector<Vec3> triangle_normals, vertex_normals;
    explicit Domain(const TriangleMesh& domain) : surface(oriented(domain, flipped)), query(surface) {
        if (!check_surface(surface).consistently_oriented) return;
        triangle_normals.reserve(surface.triangles.size());
        vertex_normals.assign(surface.points.size(), Vec3{});
        for (const std::array<int, 3>& t : surface.triangles) {
            const Vec3& a = surface.points[static_cast<std::size_t>(t[0])];
            const Vec3 n = cross(surface.points[static_cast<std::size_t>(t[1])] - a,
                                 surface.points[static_cast<std::size_t>(t[2])] - a);
            triangle_normals.push_back(normalized(n));
            for (int v : t) vertex_normals[static_cast<std::size_t>(v)] += n;
        }
        for (Vec3& n : vertex_normals) n = normalized(n);
    }
};

// finish_mesh's state: the mesh as it goes through the stages, and the result that records them; one member function
// per stage.
struct Finisher {
    const FinishOptions& options;
    const TriangleMesh& surface;
    const SurfaceQuery& query;
    const std::vector<Vec3>& triangle_normals;  // Domain's (empty: no facing test)
    const std::vector<Vec3>& vertex_normals;
    FinishResult& result;
    HexMesh mesh;
    std::vector<char> chunk;  // per hex of `mesh`: FinishOptions::chunk_hex, inherited by the children
    // Per hex of `mesh`: its scaled Jacobians as the inherited levels (refine, refine-smooth) leave it, for the
    // quality report; empty when another stage moved it since.
    std::vector<double> sj;

    void record(const FinishStage& stage) {
        result.stages.push_back(stage);
        if (options.stage_done) options.stage_done(result.stages.back());
    }

    // Two-sided distance between the boundary of m and the domain.
    double distance_to_domain(const HexMesh& m) const {
        const BoundarySurface boundary = extract_boundary(m, compute_hex_topology(m));
        return surface_distance(boundary.surface, query, options.distance).max;
    }

    // Quality pass (the untangling energy with a target scaled Jacobian) on the current mesh, recorded as stage
    // `name`; its result is kept (and `kept` set) only if it inverts no more hexes and raises the minimum.
    // on_surface (after the fit, no hex inverted): the energy holds boundary vertices only softly and can pull them
    // into the domain or along it, away from the surface they covered; its result is then also dropped if the
    // two-sided distance to the domain grows beyond max(its value before, improve_distance_budget x diagonal). The
    // smoothing, which keeps the boundary on the surface, is left to raise those hexes (docs/tuning.md).
    // hold_outside: the pass holds the vertices outside the domain that it would move farther out
    // (untangle_holding_outside, FinishOptions::pad_improve_hold_outside).
    void quality_pass(const char* name, double target_sj, const UntangleOptions& base, bool on_surface, bool& kept,
                      bool hold_outside = false) {
        const Clock::time_point t = Clock::now();
        const FinishStage& before = result.stages.back();
        UntangleOptions uo = base;
        uo.target_sj = target_sj;
        UntangleResult u = hold_outside
                               ? untangle_holding_outside(
                                     mesh, uo, [this](const std::vector<Vec3>& p) { return signed_distances(p); },
                                     options.pad_improve_hold_rounds)
                               : untangle(mesh, uo);
        const FinishStage after = measure(name, 0, u.mesh);
        bool keep = after.inverted <= before.inverted && after.sj_min > before.sj_min;
        if (keep && on_surface && !uo.fix_boundary && before.inverted == 0)
            keep = distance_to_domain(u.mesh) <=
                   std::max(distance_to_domain(mesh), options.improve_distance_budget * query.bbox_diagonal());
        // The stage's measures: those of the pass's result if kept, else those of the unchanged mesh.
        FinishStage stage = keep ? after : before;
        if (keep) {
            mesh = std::move(u.mesh);
            kept = true;
        }
        stage.stage = name;
        stage.ms = ms_since(t);
        stage.iterations = u.iterations;
        record(stage);
    }

    // Signed distance of each point to the domain (positive outside).
    std::vector<double> signed_distances(const std::vector<Vec3>& points) const {
        const std::vector<ClosestPoint> closest = query.closest(points);
        const std::vector<char> inside = query.inside(points);
        std::vector<double> d(points.size());
        for (std::size_t i = 0; i < points.size(); ++i)
            d[i] = (inside[i] ? -1.0 : 1.0) * std::sqrt(closest[i].squared_distance);
        return d;
    }

    // Where a point lands on the domain along d: the first hit from inside, else the closest point; with the normal
    // of the triangle it lands on (the domain is oriented outward).
    Landing land(const Vec3& p, const Vec3& d) const {
        std::optional<RayHit> hit;
        if (query.inside(p)) hit = query.first_hit(p, d);
        Landing l;
        int triangle = 0;
        if (hit) {
            l.point = hit->point;
            triangle = hit->triangle;
        } else {
            const ClosestPoint c = query.closest(p);
            l.point = c.point;
            triangle = c.triangle;
        }
        const std::array<int, 3>& tr = surface.triangles[static_cast<std::size_t>(triangle)];
        const Vec3& a = surface.points[static_cast<std::size_t>(tr[0])];
        l.normal = normalized(cross(surface.points[static_cast<std::size_t>(tr[1])] - a,
                                    surface.points[static_cast<std::size_t>(tr[2])] - a));
        return l;
    }

    // Selective padding: the bare regions of the raw boundary (FinishOptions::pad_selective).
    void select_bare(PaddingOptions& padding) {
        const PadSelection sel = select_bare_regions(
            mesh, surface, [this](const Vec3& p, const Vec3& d) { return land(p, d); }, options.pad_selection);
        padding.bare_quads = sel.bare_quads;
        result.pad_boundary_quads = static_cast<long>(sel.bare.size());
        result.pad_bare_quads = static_cast<long>(sel.bare_quads.size());
        result.pad_regions = sel.regions;
        result.pad_bare_regions = sel.bare_regions;
        result.pad_sharp_edges = sel.sharp_edges;
        result.pad_matched_edges = sel.matched_edges;
    }

    // The padding layer moved inward where it reaches past the domain (FinishOptions::pad_inset); the vertices of
    // bare quads stay.
    void inset_step(PaddingResult& padded, const std::vector<std::array<int, 4>>& bare_quads) {
        std::vector<char> keep(static_cast<std::size_t>(padded.first_new_vertex), 0);
        for (const std::array<int, 4>& q : bare_quads)
            for (int v : q) keep[static_cast<std::size_t>(v)] = 1;
        const PadInsetResult r = inset_padding(
            padded.mesh, padded.first_new_vertex, padded.origin_vertex,
            [this](const Vec3& p, const Vec3& u, double t) {
                if (!query.inside(p)) return t;
                const std::optional<RayHit> hit = query.first_hit(p, u);
                return hit && hit->distance < t ? t - hit->distance : 0.0;
            },
            keep, options.pad_insetting);
        result.pad_inset_vertices = r.moved_vertices;
    }

    void pad_step() {
        const Clock::time_point t = Clock::now();
        PaddingOptions padding = options.padding;
        if (options.pad_to_domain > 0 && !padding.offset_rule && padding.absolute_thickness == 0)
            padding.offset_rule = [this](const Vec3& p, const Vec3& d, double th, double th_scaled, double mean_edge) {
                // Towards the domain: as far as the surface along d (from inside), at least th, at most
                // pad_to_domain x the mean boundary edge at the vertex or th_scaled (a concave vertex's convex
                // scale, taken only up to the surface: PaddingOptions::concave_scale).
                const double cap = std::max({th, th_scaled, options.pad_to_domain * mean_edge});
                const double keep = options.pad_overshoot_keep;
                if (!(cap > th) && !(keep < 1)) return th;
                if (!query.inside(p)) return keep * th;
                const std::optional<RayHit> hit = query.first_hit(p, d);
                if (!hit) return th;
                if (hit->distance < th) return std::max(hit->distance, keep * th);
                return std::clamp(hit->distance, th, std::max(cap, th));
            };
        if (options.crease_wedge.min_dihedral_deg > 0) {
            CreaseWedgeOptions wo = options.crease_wedge;
            if (options.crease_wedge_inside && !wo.keep_vertex)
                wo.keep_vertex = [this](const Vec3& p) { return query.inside(p); };
            if (options.crease_wedge_crotch && !wo.crotch_distance)
                wo.crotch_distance = [this](const Vec3& p, const Vec3& d) {
                    if (!query.inside(p)) return 0.0;
                    const std::optional<RayHit> hit = query.first_hit(p, d);
                    return hit ? hit->distance : std::numeric_limits<double>::infinity();
                };
            CreaseWedgeResult wedged = insert_crease_wedges(mesh, wo);
            result.crease_wedges = static_cast<long>(wedged.wedge_edges.size());
            result.crotch_sheets = wedged.crotch_sheets;
            mesh = std::move(wedged.mesh);
        }
        if (options.pad_selective && padding.bare_quads.empty()) select_bare(padding);
        PaddingResult padded = pad(mesh, padding);
        if (options.pad_inset && padding.layers == 1) inset_step(padded, padding.bare_quads);
        mesh = std::move(padded.mesh);
        record(measure("pad", ms_since(t), mesh));
        // Near-flat padding hexes: relax them on the coarse padded mesh (FinishOptions::pad_improve_sj).
        if (options.pad_improve_sj > 0 && result.stages.back().inverted == 0 &&
            result.stages.back().sj_min < options.pad_improve_sj)
            quality_pass("pad-improve", options.pad_improve_sj, options.pad_improving,
                         options.pad_improve_keep_distance, result.pad_improved, options.pad_improve_hold_outside);
    }

    // Subdivision levels: given, from a target size, or from the domain size (one more for a poor raw mesh).
    int subdivision_levels() const {
        int levels = 1;
        if (options.levels >= 0) {
            levels = options.levels;
        } else if (options.size > 0) {
            levels = levels_for_size(mesh, options.size);
        } else if (options.min_resolution > 0) {
            const int needed = levels_for_size(mesh, query.bbox_diagonal() / options.min_resolution);
            levels = std::max(1, std::min(needed, options.max_auto_levels));
            const long hexes_after = static_cast<long>(mesh.hexes.size()) << (3 * (levels + 1));
            if (result.stages.front().sj_avg < options.poor_raw_sj_avg && result.stages.back().inverted == 0 &&
                levels < options.max_auto_levels && hexes_after <= options.max_auto_hexes)
                ++levels;
        }
        if (options.levels < 0 && options.max_hexes > 0)
            while (levels > 0 && (static_cast<long>(mesh.hexes.size()) << (3 * levels)) > options.max_hexes) --levels;
        return levels;
    }

    // One level of subdivision (uniform, or the branch sheets of FinishOptions::refinement); returns which points of
    // the new mesh lie on its boundary.
    std::vector<char> subdivide_level() {
        if (options.refinement == FinishOptions::Refinement::Uniform) {
            SubdivisionResult sub = subdivide(mesh);
            mesh = std::move(sub.mesh);
            return std::move(sub.on_boundary);
        }
        const SheetDirection dir = options.refinement == FinishOptions::Refinement::Longitudinal
                                       ? SheetDirection::Longitudinal
                                       : SheetDirection::Radial;
        SubdivisionResult sub =
            subdivide_sheets(mesh, select_branch_sheets(mesh, compute_hex_topology(mesh), chunk, dir));
        std::vector<char> child_chunk(sub.mesh.hexes.size(), 0);
        for (std::size_t h = 0; h < child_chunk.size(); ++h) {
            const std::size_t parent = static_cast<std::size_t>(sub.parent_hex[h]);
            child_chunk[h] = parent < chunk.size() ? chunk[parent] : 0;
        }
        mesh = std::move(sub.mesh);
        chunk = std::move(child_chunk);
        return std::move(sub.on_boundary);
    }

    // The levels fitted (all of them when the fit does not run); the others are inherited (refine_step).
    int fitted_levels(int levels) const {
        if (!options.fit || options.fit_levels < 0) return levels;
        return std::min(levels, options.fit_levels);
    }

    void subdivide_step(int levels) {
        const Clock::time_point t = Clock::now();
        // Padding keeps the raw hexes first, so chunk_hex stays valid; children inherit their parent's flag.
        chunk = options.chunk_hex;
        for (int i = 0; i < levels; ++i) subdivide_level();
        record(measure("subdivide", ms_since(t), mesh));
    }

    // The inherited levels: subdivide, then project the new boundary onto the domain (project_boundary).
    void refine_step(int levels) {
        const Clock::time_point t = Clock::now();
        ProjectionOptions po;
        po.rings = options.inherit_rings;
        po.guard_sj = options.inherit_guard_sj;
        const SurfaceQuery& q = query;
        const ClosestPointsFn closest = [&q](const std::vector<Vec3>& in, std::vector<Vec3>& out) {
            const std::vector<ClosestPoint> hits = q.closest(in);
            out.resize(hits.size());
            for (std::size_t i = 0; i < hits.size(); ++i) out[i] = hits[i].point;
        };
        for (int i = 0; i < levels; ++i) {
            const std::vector<char> on_boundary = subdivide_level();
            project_boundary(mesh, on_boundary, closest, po);
        }
        result.inherited_levels = levels;
        sj = scaled_jacobians(mesh);
        record(measure("refine", ms_since(t), mesh, sj));
    }

    // Two-sided fit: the domain's vertices and triangle centroids, matched with the current mesh boundary; on a
    // surface much denser than the mesh boundary, every k-th of them (k from the count, deterministic). With their
    // outward normals when the domain has them.
    void domain_samples(std::vector<Vec3>& samples, std::vector<Vec3>& normals) const {
        std::vector<Vec3> all = surface.points, all_normals = vertex_normals;
        for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
            const std::array<int, 3>& tri = surface.triangles[t];
            all.push_back((surface.points[static_cast<std::size_t>(tri[0])] +
                           surface.points[static_cast<std::size_t>(tri[1])] +
                           surface.points[static_cast<std::size_t>(tri[2])]) *
                          (1.0 / 3.0));
            if (!triangle_normals.empty()) all_normals.push_back(triangle_normals[t]);
        }
        const std::size_t wanted = std::max<std::size_t>(20000, 4 * count_boundary_vertices(mesh));
        const std::size_t stride = std::max<std::size_t>(1, all.size() / wanted);
        samples.clear();
        normals.clear();
        for (std::size_t i = 0; i < all.size(); i += stride) {
            samples.push_back(all[i]);
            if (all_normals.size() == all.size()) normals.push_back(all_normals[i]);
        }
    }

    void fit_step() {
        const Clock::time_point t = Clock::now();
        SurfaceProjector projector;
        // The fit queries the same boundary vertices (and the same domain samples) step after step, each a little
        // moved: each query starts from the triangle it found last time (the results do not depend on the hints).
        std::vector<int> vertex_hints, sample_hints;
        const SurfaceQuery& q = query;
        projector.closest_points = [&q, &vertex_hints](const std::vector<Vec3>& in, std::vector<Vec3>& closest) {
            const std::vector<ClosestPoint> hits =
                vertex_hints.size() == in.size() ? q.closest(in, vertex_hints) : q.closest(in);
            closest.resize(hits.size());
            vertex_hints.resize(hits.size());
            for (std::size_t i = 0; i < hits.size(); ++i) {
                closest[i] = hits[i].point;
                vertex_hints[i] = hits[i].triangle;
            }
        };
        if (!triangle_normals.empty())
            projector.last_closest_normals = [this, &vertex_hints](std::vector<Vec3>& normals) {
                normals.resize(vertex_hints.size());
                for (std::size_t i = 0; i < vertex_hints.size(); ++i)
                    normals[i] =
                        vertex_hints[i] >= 0 ? triangle_normals[static_cast<std::size_t>(vertex_hints[i])] : Vec3{};
            };
        domain_samples(projector.samples, projector.sample_normals);
        projector.samples_to_boundary = [&projector, &sample_hints](const TriangleMesh& boundary,
                                                                    std::vector<SurfaceProjector::Hit>& hits) {
            // The boundary's triangles keep their indices from call to call (only their corners move).
            const bool hinted = sample_hints.size() == projector.samples.size();
            const SurfaceQuery on_boundary(boundary, /*accelerate=*/!hinted);
            const std::vector<ClosestPoint> found =
                hinted ? on_boundary.closest(projector.samples, sample_hints) : on_boundary.closest(projector.samples);
            hits.resize(found.size());
            sample_hints.resize(found.size());
            for (std::size_t i = 0; i < found.size(); ++i) {
                hits[i] = {found[i].triangle, found[i].point};
                sample_hints[i] = found[i].triangle;
            }
        };
        FitOptions fitting = options.fitting;
        if (options.gap_goal_relative > 0) fitting.gap_goal = options.gap_goal_relative * query.bbox_diagonal();
        FitResult fit = fit_to_surface(mesh, projector, fitting);
        mesh = std::move(fit.mesh);
        result.fit_iterations = fit.iterations;
        result.fit_converged = fit.converged;
        result.fit_max_distance = fit.max_distance;
        result.fit_uncovered = fit.uncovered >= 0 ? fit.uncovered / query.bbox_diagonal() : -1.0;
        record(with_iterations(measure("fit", ms_since(t), mesh), fit.iterations));
    }

    void untangle_step() {
        const Clock::time_point t = Clock::now();
        UntangleResult u = untangle(mesh, options.untangling);
        mesh = std::move(u.mesh);
        result.untangled = true;
        result.untangle_rounds = u.rounds;
        record(with_iterations(measure("untangle", ms_since(t), mesh), u.iterations));
    }

    void improve() {
        if (options.improve_sj > 0 && result.stages.back().sj_min < options.improve_sj)
            quality_pass("improve", options.improve_sj, options.improving, true, result.improved);
    }

    // Some folds need the boundary to move: untangle again with boundary vertices softly attached where they are.
    void untangle_free_step() {
        const Clock::time_point t = Clock::now();
        UntangleOptions free = options.untangling;
        free.fix_boundary = false;
        UntangleResult u = untangle(mesh, free);
        const bool kept = u.inverted_after < result.stages.back().inverted;
        if (kept) {
            mesh = std::move(u.mesh);
            result.untangled_boundary_moved = true;
        }
        record(with_iterations(measure("untangle-free", ms_since(t), mesh), u.iterations));
        if (kept) improve();
    }

    // The smoothing's options (max_gap, the domain's normals) and its projection onto the domain, handed to `run`
    // (which calls smooth_quality or smooth_region with them).
    SmoothResult smoothing(
        const std::function<SmoothResult(const std::function<Vec3(const Vec3&)>&, const SmoothOptions&)>& run) const {
        SmoothOptions so = options.smoothing;
        if (options.smooth_gap_relative > 0) so.max_gap = options.smooth_gap_relative * query.bbox_diagonal();
        // Features are where the domain has a convex crease or corner, not wherever the fit left the boundary folded
        // (SmoothOptions::surface_normal): the domain's normal, its closest triangle's (the surface faces outward).
        const SurfaceQuery& q = query;
        const TriangleMesh& surf = surface;
        if (!so.surface_normal)
            so.surface_normal = [&q, &surf](const Vec3& p) {
                const std::array<int, 3>& tr = surf.triangles[static_cast<std::size_t>(q.closest(p).triangle)];
                const Vec3& a = surf.points[static_cast<std::size_t>(tr[0])];
                return normalized(cross(surf.points[static_cast<std::size_t>(tr[1])] - a,
                                        surf.points[static_cast<std::size_t>(tr[2])] - a));
            };
        // Smoothing projects points one after the other (sequentially), many times near the same places: each query
        // starts from the triangle found last in its cell of a grid (cells of 0.5 % of the diagonal), else from the
        // triangle the last query found (the closest point does not depend on the hint).
        int last_triangle = -1;
        std::unordered_map<std::uint64_t, int> cell_triangle;
        const double cell = 0.005 * query.bbox_diagonal();
        auto cell_of = [cell](const Vec3& p) {
            auto c = [cell](double v) {  // 21 bits per axis
                return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / cell)) & 0x1fffff);
            };
            return (c(p.x) << 42) | (c(p.y) << 21) | c(p.z);
        };
        const std::function<Vec3(const Vec3&)> project = [&](const Vec3& p) {
            const std::uint64_t key = cell_of(p);
            const auto it = cell_triangle.find(key);
            const ClosestPoint c = q.closest(p, it != cell_triangle.end() ? it->second : last_triangle);
            last_triangle = c.triangle;
            cell_triangle[key] = c.triangle;
            return c.point;
        };
        return run(project, so);
    }

    void smooth_step() {
        const Clock::time_point t = Clock::now();
        SmoothResult sm = smoothing([this](const std::function<Vec3(const Vec3&)>& project, const SmoothOptions& so) {
            return smooth_quality(mesh, project, so);
        });
        mesh = std::move(sm.mesh);
        sj.clear();
        result.smoothed = sm.moves > 0;
        record(with_iterations(measure("smooth", ms_since(t), mesh), sm.sweeps + sm.worst_rounds));
    }

    // After the inherited levels: the smoothing on the hexes below inherit_smooth_sj and the rings around them.
    void refine_smooth_step() {
        const Clock::time_point t = Clock::now();
        SmoothResult sm = smoothing([this](const std::function<Vec3(const Vec3&)>& project, const SmoothOptions& so) {
            return smooth_region(mesh, project, options.inherit_smooth_sj, options.inherit_smooth_rings, so, sj);
        });
        mesh = std::move(sm.mesh);
        if (sm.moves > 0 || sm.worst_moves > 0) {
            result.smoothed = true;
            sj = scaled_jacobians(mesh);
        }
        record(with_iterations(measure("refine-smooth", ms_since(t), mesh, sj), sm.sweeps + sm.worst_rounds));
    }

    // `topo`: the final mesh's topology (computed once, for the quality report too).
    void measure_distance(const HexTopology& topo) {
        const Clock::time_point t = Clock::now();
        const BoundarySurface boundary = extract_boundary(mesh, topo);
        result.distance = surface_distance(boundary.surface, query, options.distance);
        result.distance_measured = true;
        result.distance_ms = ms_since(t);
    }
};

}  // namespace

FinishResult finish_mesh(const HexMesh& raw, const TriangleMesh& domain, const FinishOptions& options) {
    const Clock::time_point start_all = Clock::now();
    FinishResult result;
    const Domain dom(domain);
    result.domain_flipped_triangles = dom.flipped;
    Finisher f{options, dom.surface, dom.query, dom.triangle_normals, dom.vertex_normals, result, raw, {}, {}};
    f.record(measure("input", 0, f.mesh));
    if (options.pad) {
        result.pad_mode = options.pad_selective ? "selective" : "all";
        f.pad_step();
    }
    const int levels = options.subdivide ? f.subdivision_levels() : 0;
    const int fitted = f.fitted_levels(levels);
    result.subdivision_levels = levels;
    if (options.subdivide) f.subdivide_step(fitted);
    if (options.fit) f.fit_step();
    if (options.untangle && result.stages.back().inverted > 0) f.untangle_step();
    f.improve();
    if (options.untangle && options.free_boundary_fallback && options.untangling.fix_boundary &&
        result.stages.back().inverted > 0)
        f.untangle_free_step();
    if (options.fit && options.smooth && result.stages.back().inverted == 0) f.smooth_step();
    if (levels > fitted) {
        f.refine_step(levels - fitted);
        if (options.fit && options.smooth && result.stages.back().inverted == 0) {
            if (options.inherit_smooth)
                f.smooth_step();
            else if (options.inherit_smooth_sj > 0 && result.stages.back().sj_min < options.inherit_smooth_sj)
                f.refine_smooth_step();
        }
    }
    {
        HexTopology topo;
        result.quality = compute_quality(f.mesh, topo, std::move(f.sj));
        if (topo.hex_faces.size() != f.mesh.hexes.size()) topo = compute_hex_topology(f.mesh);  // (bad indices)
        if (options.measure_distance) f.measure_distance(topo);
    }
    result.mesh = std::move(f.mesh);
    result.total_ms = ms_since(start_all);
    return result;
}

int missed_goals(const FinishResult& r, const MeshGoals& goals) {
    const QualityReport& q = r.quality;
    int missed = 0;
    if (q.inverted > 0 || !q.validation.valid()) ++missed;
    if (!(q.sj_min >= goals.sj_min)) ++missed;
    if (!(q.sj_avg >= goals.sj_avg)) ++missed;
    if (r.distance_measured && !(r.distance.relative_max <= goals.hausdorff)) ++missed;
    return missed;
}

int compare_inverted_then_goals(const FinishResult& a, const FinishResult& b, const MeshGoals& goals) {
    const auto badness = [](const FinishResult& r) {
        return r.quality.validation.valid() ? r.quality.inverted : std::numeric_limits<long>::max();
    };
    if (badness(a) != badness(b)) return badness(a) < badness(b) ? -1 : 1;
    const int ma = missed_goals(a, goals), mb = missed_goals(b, goals);
    if (ma != mb) return ma < mb ? -1 : 1;
    return 0;
}

bool better_finish(const FinishResult& a, const FinishResult& b, const MeshGoals& goals) {
    if (const int c = compare_inverted_then_goals(a, b, goals); c != 0) return c < 0;
    if (a.distance_measured && b.distance_measured && a.distance.relative_max != b.distance.relative_max)
        return a.distance.relative_max < b.distance.relative_max;
    return a.quality.sj_min > b.quality.sj_min;
}

double goal_shortfall(const FinishResult& r, const MeshGoals& goals) {
    const QualityReport& q = r.quality;
    const auto below = [](double value, double goal) {
        if (!(value < goal)) return 0.0;
        return value > 0 ? std::log(goal / value) : std::numeric_limits<double>::infinity();
    };
    double sum = below(q.sj_min, goals.sj_min) + below(q.sj_avg, goals.sj_avg);
    if (r.distance_measured && r.distance.relative_max > goals.hausdorff && goals.hausdorff > 0)
        sum += std::log(r.distance.relative_max / goals.hausdorff);
    return sum;
}

bool better_finish_by_shortfall(const FinishResult& a, const FinishResult& b, const MeshGoals& goals) {
    if (const int c = compare_inverted_then_goals(a, b, goals); c != 0) return c < 0;
    const double sa = goal_shortfall(a, goals), sb = goal_shortfall(b, goals);
    if (sa != sb) return sa < sb;
    return better_finish(a, b, goals);
}

}  // namespace mesohex
