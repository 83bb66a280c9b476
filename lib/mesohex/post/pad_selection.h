#pragma once
// Selective padding: which boundary quads of a raw mesh need no padding layer because the raw boundary there already
// matches the domain (its sharp rims land on sharp feature lines of the domain with the same dihedral angle).
// Padding covers a sharp rim of the domain with two hexes (about 45 degrees each on a 90-degree rim, scaled Jacobian
// near sin 45 = 0.71); a raw mesh whose own boundary has the rim covers it with one hex corner. The reference's
// "pad extremities off" leaves the caps of branch ends bare the same way (reference-notes §12.2).
#include <functional>
#include <vector>

#include "mesohex/core/hex_mesh.h"

namespace mesohex {

struct PadSelectionOptions {
    // Degrees: a boundary edge of the raw mesh, or an edge of the domain's triangles, is sharp when the normals of its
    // two faces are more than this apart. Raw boundary quads form regions separated by the sharp raw edges.
    double sharp_angle = 30;
    // Degrees: a sharp raw edge matches a sharp domain edge when both are convex or both concave and their normal
    // angles differ by at most this.
    double angle_tolerance = 20;
    // Degrees: a region stays bare only if every sharp edge around it has a normal angle of at least this. A rim of
    // interior angle a = 180 - (normal angle) is one hex corner of scaled Jacobian sin a when bare, two of sin(a / 2)
    // each when padded: bare is better when the normal angle exceeds 60 degrees.
    double min_rim_angle = 60;
    // Dimensionless: the midpoint of a sharp raw edge of length len, landed along the mean normal of its two quads,
    // must lie within r = search_radius x len + landing_slack x (the distance travelled to land) of a matching sharp
    // domain edge, and the raw edge's extent across that edge's direction (len x sine of the angle between them) must
    // be at most r (with these values: within 30 degrees for an edge much longer than the landing distance).
    double search_radius = 0.5;
    double landing_slack = 0.5;
    // Degrees: every quad of a bare region, landed along its normal from its centre, must meet the domain where the
    // domain's normal is at most this far from the quad's normal (the region's interior is as flat as the domain's).
    double normal_tolerance = 30;
};

// Where a point of the raw boundary lands on the domain: from p along the unit direction d (the first hit of the ray
// from inside, else the closest point), and the domain's outward unit normal there.
struct Landing {
    Vec3 point;
    Vec3 normal;
};
using LandingFn = std::function<Landing(const Vec3& p, const Vec3& d)>;

struct PadSelection {
    // Per boundary quad of compute_hex_topology(mesh) (same order): 1 = bare (no padding hex), 0 = padded.
    std::vector<char> bare;
    std::vector<std::array<int, 4>> bare_quads;  // the bare boundary quads themselves (PaddingOptions::bare_quads)
    int regions = 0;                             // regions of boundary quads between sharp raw edges
    int bare_regions = 0;                        // of them, left bare
    long sharp_edges = 0;                        // sharp raw boundary edges
    long matched_edges = 0;
    long domain_sharp_edges = 0;  // sharp edges of the domain's triangles (0, not counted, when no raw edge is sharp)
};

// The bare regions: a region of raw boundary quads is bare when (1) it is bounded by at least one sharp raw edge,
// (2) every sharp raw edge around it has a normal angle >= min_rim_angle and matches a sharp edge of `domain` near
// where its midpoint lands (along the mean of its two quad normals) and along its direction (PadSelectionOptions), (3)
// every vertex inside it (on no sharp edge) has 4 boundary quads, or 3 (a leaflet's convex corner), (4) every quad
// lands where the domain's normal is within normal_tolerance of its own. Then, until nothing changes, a bare region
// becomes padded when it meets a padded quad along a concave edge (the padding's side face would lie on the bare
// region) or at a vertex where the padded quads form more than one fan (the new vertex there would pinch the boundary).
// `domain` must be oriented outward. Boundary edges with other than two boundary quads count as sharp and unmatched.
// Deterministic; O(sharp raw edges x sharp domain edges) for the matching.
PadSelection select_bare_regions(const HexMesh& mesh, const TriangleMesh& domain, const LandingFn& land,
                                 const PadSelectionOptions& options = {});

}  // namespace mesohex
