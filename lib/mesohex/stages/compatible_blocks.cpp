#include "mesohex/stages/compatible_blocks.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mesohex/core/error.h"
#include "mesohex/stages/connection_surfaces.h"
#include "mesohex/stages/skeleton_analysis.h"

namespace mesohex {

namespace {

constexpr double kDeg = std::numbers::pi / 180;

double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// Eigenvector of the largest eigenvalue of a symmetric 4 x 4 matrix (cyclic Jacobi, fixed sweeps: deterministic).
std::array<double, 4> top_eigenvector(std::array<std::array<double, 4>, 4> a) {
    std::array<std::array<double, 4>, 4> v{};
    for (int i = 0; i < 4; ++i) v[i][i] = 1;
    for (int sweep = 0; sweep < 30; ++sweep) {
        double off = 0;
        for (int p = 0; p < 4; ++p)
            for (int q = p + 1; q < 4; ++q) off += a[p][q] * a[p][q];
        if (off < 1e-30) break;
        for (int p = 0; p < 4; ++p)
            for (int q = p + 1; q < 4; ++q) {
                if (std::abs(a[p][q]) < 1e-300) continue;
                const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 4; ++k) {  // columns p, q
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 4; ++k) {  // rows p, q
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 4; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    int best = 0;
    for (int i = 1; i < 4; ++i)
        if (a[i][i] > a[best][best]) best = i;
    return {v[0][best], v[1][best], v[2][best], v[3][best]};
}

// The rotation F maximising sum_i d_i . F e_i (Horn 1987): columns F e_x, F e_y, F e_z.
std::array<Vec3, 3> fit_rotation(const std::vector<Vec3>& d, const std::vector<Vec3>& e) {
    double S[3][3] = {};  // S[a][b] = sum e_i[a] d_i[b]
    for (std::size_t i = 0; i < d.size(); ++i)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) S[a][b] += e[i][a] * d[i][b];
    const double xx = S[0][0], xy = S[0][1], xz = S[0][2], yx = S[1][0], yy = S[1][1], yz = S[1][2], zx = S[2][0],
                 zy = S[2][1], zz = S[2][2];
    const std::array<std::array<double, 4>, 4> N{{{xx + yy + zz, yz - zy, zx - xz, xy - yx},
                                                  {yz - zy, xx - yy - zz, xy + yx, zx + xz},
                                                  {zx - xz, xy + yx, -xx + yy - zz, yz + zy},
                                                  {xy - yx, zx + xz, yz + zy, -xx - yy + zz}}};
    const std::array<double, 4> q = top_eigenvector(N);
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    const double n2 = w * w + x * x + y * y + z * z;
    const double s = n2 > 0 ? 2 / n2 : 0;
    // Columns of the rotation matrix of the quaternion (w, x, y, z).
    return {Vec3{1 - s * (y * y + z * z), s * (x * y + w * z), s * (x * z - w * y)},
            Vec3{s * (x * y - w * z), 1 - s * (x * x + z * z), s * (y * z + w * x)},
            Vec3{s * (x * z + w * y), s * (y * z - w * x), 1 - s * (x * x + y * y)}};
}

// Nearest signed axis of frame f to unit d (lowest label on ties).
int nearest_label(const std::array<Vec3, 3>& f, const Vec3& d) {
    int best = 0;
    double best_dot = -2;
    for (int l = 0; l < 6; ++l) {
        const double c = dot(d, (l & 1) ? -f[l >> 1] : f[l >> 1]);
        if (c > best_dot + 1e-15) {
            best_dot = c;
            best = l;
        }
    }
    return best;
}

Vec3 frame_axis(const std::array<Vec3, 3>& f, int label) { return (label & 1) ? -f[label >> 1] : f[label >> 1]; }

}  // namespace

Vec3 signed_axis(int label) {
    Vec3 v{};
    v[label >> 1] = (label & 1) ? -1.0 : 1.0;
    return v;
}

CubeFit fit_cube_frame(const std::vector<Vec3>& directions, const CompatibleBlockOptions& options) {
    CubeFit fit;
    const int n = static_cast<int>(directions.size());
    fit.labels.assign(n, -1);
    if (n < 2) return fit;
    std::vector<Vec3> d(n);
    for (int i = 0; i < n; ++i) {
        if (!is_finite(directions[i]) || !(norm(directions[i]) > 0)) return fit;
        d[i] = normalized(directions[i]);
    }
    int j = 1;
    for (int i = 2; i < n; ++i)
        if (std::abs(dot(d[0], d[i])) < std::abs(dot(d[0], d[j])) - 1e-15) j = i;
    const Vec3 b = d[j] - dot(d[j], d[0]) * d[0];
    if (!(norm(b) > 1e-9)) return fit;  // all directions on one line
    std::array<Vec3, 3> f{d[0], normalized(b), cross(d[0], normalized(b))};
    std::vector<Vec3> e(n);
    for (int round = 0; round < 3; ++round) {
        for (int i = 0; i < n; ++i) e[i] = signed_axis(nearest_label(f, d[i]));
        f = fit_rotation(d, e);
        for (Vec3& a : f) a = normalized(a);
    }
    fit.axes = f;
    for (int i = 0; i < n; ++i) {
        fit.labels[i] = nearest_label(f, d[i]);
        fit.max_axis_angle = std::max(fit.max_axis_angle, angle_between(d[i], frame_axis(f, fit.labels[i])));
    }
    bool distinct = true;
    for (int i = 0; i < n; ++i)
        for (int k = i + 1; k < n; ++k) {
            distinct = distinct && fit.labels[i] != fit.labels[k];
            const double want = (fit.labels[i] >> 1) == (fit.labels[k] >> 1) ? std::numbers::pi : std::numbers::pi / 2;
            fit.max_pair_error = std::max(fit.max_pair_error, std::abs(angle_between(d[i], d[k]) - want));
        }
    fit.accepted = distinct && fit.max_axis_angle <= options.axis_tolerance_deg * kDeg &&
                   fit.max_pair_error <= options.pair_tolerance_deg * kDeg;
    return fit;
}

std::array<int, 3> block_coordinates(int x) { return {x / 9 - 1, (x / 3) % 3 - 1, x % 3 - 1}; }

std::array<std::array<int, 8>, 8> block_hexes() {
    std::array<std::array<int, 8>, 8> h{};
    int n = 0;
    for (int i0 = -1; i0 <= 0; ++i0)
        for (int j0 = -1; j0 <= 0; ++j0)
            for (int k0 = -1; k0 <= 0; ++k0) {
                for (int up = 0; up < 2; ++up) {
                    const int k = k0 + up;
                    h[n][4 * up + 0] = block_vertex(i0, j0, k);
                    h[n][4 * up + 1] = block_vertex(i0 + 1, j0, k);
                    h[n][4 * up + 2] = block_vertex(i0 + 1, j0 + 1, k);
                    h[n][4 * up + 3] = block_vertex(i0, j0 + 1, k);
                }
                ++n;
            }
    return h;
}

std::array<int, 9> block_section(int label) {
    const Vec3 t = signed_axis(label);
    const Vec3 r = signed_axis(2 * (((label >> 1) + 1) % 3));
    const Vec3 s = cross(t, r);
    auto id = [](const Vec3& p) {
        return block_vertex(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)),
                            static_cast<int>(std::lround(p.z)));
    };
    const std::array<Vec3, 4> q{t + r, t + s, t - r, t - s};
    std::array<int, 9> sec{};
    sec[0] = id(t);
    for (int k = 0; k < 4; ++k) {
        sec[1 + k] = id(q[k]);
        sec[5 + k] = id(q[k] + q[(k + 1) & 3] - t);
    }
    return sec;
}

Vec3 block_point(const CubeBlock& block, const Vec3& c, double h, int x) {
    const std::array<int, 3> ijk = block_coordinates(x);
    return c + h * (ijk[0] * block.axes[0] + ijk[1] * block.axes[1] + ijk[2] * block.axes[2]);
}

void add_block_irregular_edges(const CubeBlock& block, std::map<int, long>& boundary_irregular_edges) {
    bool labelled[6] = {};
    for (int l : block.labels) labelled[l] = true;
    // A cube edge runs along axis a; its two neighbouring faces are the signed axes of the other two axes.
    for (int a = 0; a < 3; ++a)
        for (int sb = 0; sb < 2; ++sb)
            for (int sc = 0; sc < 2; ++sc) {
                const int b = (a + 1) % 3, c = (a + 2) % 3;
                const int docked = (labelled[2 * b + sb] ? 1 : 0) + (labelled[2 * c + sc] ? 1 : 0);
                if (docked != 1) boundary_irregular_edges[1 + docked] += 2;
            }
}

std::vector<CubeBlock> find_compatible_blocks(const Skeleton& skeleton, const SkeletonAnalysis& an,
                                              const CompatibleBlockOptions& options) {
    std::vector<CubeBlock> blocks;
    if (!options.enabled) return blocks;
    const int nv = static_cast<int>(an.vertex_class.size());
    std::vector<int> inc;
    std::vector<Vec3> dirs;
    for (int v = 0; v < nv; ++v) {
        if (an.vertex_class[v] != VertexClass::BranchingPoint) continue;
        inc.clear();
        bool only_branches = true;
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int e = an.vertex_edges[i];
            if (an.edge_degree[e] == 0)
                inc.push_back(e);
            else
                only_branches = false;
        }
        const int n = static_cast<int>(inc.size());
        if (!only_branches || n < options.min_branches || n > options.max_branches) continue;
        dirs.resize(n);
        bool free_ends = true;  // every neighbour a joint or an extremity
        for (int i = 0; i < n; ++i) {
            const int e = inc[i];
            const int w = skeleton.edges[e][0] == v ? skeleton.edges[e][1] : skeleton.edges[e][0];
            dirs[i] = skeleton.points[w] - skeleton.points[v];
            free_ends =
                free_ends && (an.vertex_class[w] == VertexClass::Joint || an.vertex_class[w] == VertexClass::Extremity);
        }
        if (!free_ends) continue;
        const CubeFit fit = fit_cube_frame(dirs, options);
        if (fit.accepted) blocks.push_back({v, fit.axes, fit.labels});
    }
    return blocks;
}

void set_block_surface(const Skeleton& skeleton, const SkeletonAnalysis& an, const CubeBlock& block,
                       ConnectionSurfaces& cs) {
    const int v = block.vertex, n = static_cast<int>(block.labels.size());
    const int p0 = cs.point_begin[v], q0 = cs.quad_begin[v], e0 = cs.edge_begin[v];
    MESOHEX_CHECK(
        cs.point_begin[v + 1] - p0 == 4 * n && cs.quad_begin[v + 1] - q0 == n && cs.edge_begin[v + 1] - e0 == 4 * n,
        "block surface ranges");
    for (int i = 0; i < n; ++i) {
        const std::array<int, 9> sec = block_section(block.labels[i]);
        for (int k = 0; k < 4; ++k) {
            cs.directions[p0 + 4 * i + k] = normalized(block_point(block, Vec3{}, 1.0, sec[1 + k]));
            cs.point_valence[p0 + 4 * i + k] = 1;
            cs.edges[e0 + 4 * i + k] = {4 * i + k, 4 * i + ((k + 1) & 3)};
            cs.quads[q0 + i][k] = 4 * i + k;
            cs.quad_edges[q0 + i][k] = 4 * i + k;
        }
    }
    int i = 0;
    for (int j = an.vertex_edge_begin[v]; j < an.vertex_edge_begin[v + 1]; ++j) {
        const int e = an.vertex_edges[j];
        if (an.edge_degree[e] != 0) continue;
        cs.edge_quad[e][skeleton.edges[e][0] == v ? 0 : 1] = q0 + i++;
    }
}

}  // namespace mesohex
