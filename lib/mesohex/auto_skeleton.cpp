#include "mesohex/auto_skeleton.h"

#include <sstream>
#include <utility>

#include "mesohex/core/error.h"

namespace mesohex {

const char* skeleton_kind_name(SkeletonKind kind) {
    switch (kind) {
        case SkeletonKind::Auto: return "auto";
        case SkeletonKind::Curve: return "curve";
        case SkeletonKind::Meso: return "meso";
    }
    return "auto";
}

namespace {

void use_curve(AutoSkeleton& out, const TriangleMesh& surface, const AutoSkeletonOptions& options) {
    out.curve = skeletonize_surface(surface, options.skeletonize);
    out.skeleton = out.curve.skeleton;
    out.kind = SkeletonKind::Curve;
}

}  // namespace

AutoSkeleton choose_skeleton(const TriangleMesh& surface, const AutoSkeletonOptions& options) {
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
            return out;
        }
        out.import = import_medial_mesh(out.medial.medial, options.import);
        if (options.kind == SkeletonKind::Auto) {
            MeshOptions raw_options;
            raw_options.finish = false;
            const MeshRun raw = mesh_skeleton(out.import.skeleton, &surface, raw_options);
            out.raw_checked = true;
            out.raw_hexes = raw.raw_quality.hexes;
            out.raw_inverted = raw.raw_quality.inverted;
            out.raw_sj_min = raw.raw_quality.sj_min;
            why << "; meso raw mesh " << out.raw_hexes << " hexes, " << out.raw_inverted << " inverted (min SJ "
                << out.raw_sj_min << ")";
            if (!raw.raw_quality.validation.valid() || out.raw_inverted > options.max_raw_inverted) {
                why << " > " << options.max_raw_inverted << " inverted or invalid: curve skeleton instead";
                out.reason = why.str();
                use_curve(out, surface, options);
                return out;
            }
        }
        out.skeleton = out.import.skeleton;
        out.kind = SkeletonKind::Meso;
        if (options.kind == SkeletonKind::Meso)
            why << ": meso-skeleton forced";
        else
            why << " >= " << options.min_sheet_fraction << ": flat or thin parts, medial meso-skeleton";
        out.reason = why.str();
        return out;
    } catch (const Error& e) {
        if (options.kind == SkeletonKind::Meso) throw;
        why << (out.medial_computed ? "; import failed: " : "medial axis failed: ") << e.what()
            << "; curve skeleton instead";
        out.reason = why.str();
    }
    use_curve(out, surface, options);
    return out;
}

}  // namespace mesohex
