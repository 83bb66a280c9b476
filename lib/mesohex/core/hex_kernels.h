#pragma once
// The small numerical kernels several stages share, in one place: the check of a hex mesh's vertex indices, the nine
// frames of Verdict's hex scaled Jacobian, the normalized frame determinant (and the two other forms in use: over the
// product of squared lengths, for the smoothing; over the product of lengths, for the junction model of the
// connection surfaces), and degrees -> radians.
// (post/surface_fitting.cpp evaluates the same scaled Jacobian vectorised, on blocks of hexes; test_hex_kernels checks
// it against hex_scaled_jacobian here on random hexes.)
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>

#include "mesohex/core/error.h"
#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_mesh.h"
#include "mesohex/core/vec.h"

namespace mesohex {

// deg x pi / 180 (in this order: the same bits as the expression written out).
inline double deg_to_rad(double deg) { return deg * std::numbers::pi / 180.0; }

// Whether every vertex id of `hex` is in [0, vertices).
inline bool hex_indices_in_range(const std::array<int, 8>& hex, std::size_t vertices) {
    for (int v : hex)
        if (v < 0 || static_cast<std::size_t>(v) >= vertices) return false;
    return true;
}

// Throws Error(InvalidInput, "<who>: hex H has vertex index V out of range", the hex) for the first hex with a vertex
// id outside [0, #points).
inline void check_hex_indices(const HexMesh& mesh, const std::string& who) {
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
        for (int v : mesh.hexes[h])
            if (v < 0 || static_cast<std::size_t>(v) >= mesh.points.size())
                throw Error(
                    ErrorCode::InvalidInput,
                    who + ": hex " + std::to_string(h) + " has vertex index " + std::to_string(v) + " out of range",
                    {ElementRef::Kind::Hex, static_cast<int>(h)});
}

// The centre (principal-axes) frame of a hex, as Verdict's calc_hex_efg(1..3): differences of the sums of opposite
// faces' corners (xi, eta, zeta).
inline std::array<Vec3, 3> hex_centre_frame(const std::array<Vec3, 8>& p) {
    return {(p[1] + p[2] + p[5] + p[6]) - (p[0] + p[3] + p[4] + p[7]),
            (p[2] + p[3] + p[6] + p[7]) - (p[0] + p[1] + p[4] + p[5]),
            (p[4] + p[5] + p[6] + p[7]) - (p[0] + p[1] + p[2] + p[3])};
}

// The frame at corner lv (0-7): the edges to its three neighbours (kHexCornerNeighbors, right-handed on a positive
// hex).
inline std::array<Vec3, 3> hex_corner_frame(const std::array<Vec3, 8>& p, std::size_t lv) {
    const std::array<int, 3>& nb = kHexCornerNeighbors[lv];
    return {p[static_cast<std::size_t>(nb[0])] - p[lv], p[static_cast<std::size_t>(nb[1])] - p[lv],
            p[static_cast<std::size_t>(nb[2])] - p[lv]};
}

// Determinant of the column-normalized frame (a, b, c), in [-1, 1]. false when a column's squared length is not finite
// or <= DBL_MIN, or the result is not finite (the frame is then degenerate).
inline bool normalized_frame_det(const Vec3& a, const Vec3& b, const Vec3& c, double& out) {
    const double la = squared_norm(a), lb = squared_norm(b), lc = squared_norm(c);
    if (!(std::isfinite(la) && std::isfinite(lb) && std::isfinite(lc))) return false;
    if (la <= DBL_MIN || lb <= DBL_MIN || lc <= DBL_MIN) return false;
    out = det3(a / std::sqrt(la), b / std::sqrt(lb), c / std::sqrt(lc));
    return std::isfinite(out);
}

// The same value computed as det(a, b, c) / sqrt(|a|^2 |b|^2 |c|^2) (one division instead of three normalizations:
// the smoothing's energy, evaluated many times per vertex; equal to normalized_frame_det up to rounding), -1 for a
// degenerate frame.
inline double frame_det_over_lengths(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double la = squared_norm(a), lb = squared_norm(b), lc = squared_norm(c);
    if (!(la > DBL_MIN && lb > DBL_MIN && lc > DBL_MIN)) return -1.0;
    const double d = det3(a, b, c) / std::sqrt(la * lb * lc);
    return std::isfinite(d) ? d : -1.0;
}

// The 9 normalized frame determinants of Verdict's hex scaled Jacobian in the frame_det_over_lengths form (centre
// frame first, then corners 0-7); -1 for a degenerate frame. Their minimum is hex_scaled_jacobian up to rounding (the
// smoothing's energy and its max-min pass use every value).
inline std::array<double, 9> hex_frame_values(const std::array<Vec3, 8>& p) {
    std::array<double, 9> q{};
    const std::array<Vec3, 3> c = hex_centre_frame(p);
    q[0] = frame_det_over_lengths(c[0], c[1], c[2]);
    for (std::size_t lv = 0; lv < 8; ++lv) {
        const std::array<Vec3, 3> f = hex_corner_frame(p, lv);
        q[lv + 1] = frame_det_over_lengths(f[0], f[1], f[2]);
    }
    return q;
}

// The determinant of the frame at corner lv divided by the product of its three edge lengths (each length from its
// own square root): the connection surfaces' junction model evaluates its hex corners in this form. -1 when the
// product is not > 1e-300. Equal to normalized_frame_det up to rounding.
inline double hex_corner_value(const std::array<Vec3, 8>& p, std::size_t lv) {
    const std::array<Vec3, 3> f = hex_corner_frame(p, lv);
    const double l = norm(f[0]) * norm(f[1]) * norm(f[2]);
    if (!(l > 1e-300)) return -1;
    return det3(f[0], f[1], f[2]) / l;
}

// Unit normal of a quad of the mesh from its diagonals (robust for non-planar quads); its orientation follows the
// vertex order.
inline Vec3 quad_normal(const HexMesh& mesh, const std::array<int, 4>& q) {
    const auto p = [&](int k) { return mesh.points[static_cast<std::size_t>(q[static_cast<std::size_t>(k)])]; };
    return normalized(cross(p(2) - p(0), p(3) - p(1)));
}

// Verdict's hex scaled Jacobian: the smallest normalized determinant of the centre frame and the 8 corner frames;
// -1 when a frame is degenerate. 1 for a unit cube, -1 for its mirror image.
inline double hex_scaled_jacobian(const std::array<Vec3, 8>& p) {
    double min_det = DBL_MAX, d = 0;
    const std::array<Vec3, 3> c = hex_centre_frame(p);
    if (!normalized_frame_det(c[0], c[1], c[2], d)) return -1.0;
    min_det = std::min(min_det, d);
    for (std::size_t lv = 0; lv < 8; ++lv) {
        const std::array<Vec3, 3> f = hex_corner_frame(p, lv);
        if (!normalized_frame_det(f[0], f[1], f[2], d)) return -1.0;
        min_det = std::min(min_det, d);
    }
    return min_det;
}

// The same for hex h (8 indices into points).
inline double hex_scaled_jacobian(const std::vector<Vec3>& points, const std::array<int, 8>& h) {
    std::array<Vec3, 8> p;
    for (std::size_t k = 0; k < 8; ++k) p[k] = points[static_cast<std::size_t>(h[k])];
    return hex_scaled_jacobian(p);
}

}  // namespace mesohex
