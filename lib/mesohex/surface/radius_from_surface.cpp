// Skeleton radii from the distance to the domain surface. See radius_from_surface.h.
#include "mesohex/surface/radius_from_surface.h"

#include <cmath>

#include "mesohex/core/error.h"

namespace mesohex {

RadiusFromSurface radius_from_surface(const Skeleton& skeleton, const SurfaceQuery& surface,
                                      const RadiusFromSurfaceOptions& options) {
    if (!(options.factor > 0) || !std::isfinite(options.factor))
        throw Error(ErrorCode::InvalidInput,
                    "radius from surface: the factor must be > 0, got " + std::to_string(options.factor));
    for (std::size_t v = 0; v < skeleton.points.size(); ++v)
        if (!is_finite(skeleton.points[v]))
            throw Error(ErrorCode::InvalidInput,
                        "radius from surface: skeleton point " + std::to_string(v) + " is not finite",
                        ElementRef{ElementRef::Kind::SkeletonVertex, static_cast<int>(v)});
    RadiusFromSurface r;
    const std::vector<double> d2 = surface.squared_distances(skeleton.points);
    const std::vector<char> in = surface.inside(skeleton.points);
    r.radii.resize(d2.size());
    r.distance.resize(d2.size());
    for (std::size_t v = 0; v < d2.size(); ++v) {
        r.distance[v] = std::sqrt(d2[v]);
        r.radii[v] = options.factor * r.distance[v];
        if (!in[v]) r.outside_vertices.push_back(static_cast<int>(v));
        if (r.distance[v] == 0) r.zero_radius_vertices.push_back(static_cast<int>(v));
    }
    return r;
}

}  // namespace mesohex
