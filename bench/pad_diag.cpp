// The padding layer's worst hexes (issue 16; docs/junctions.md, "The padding layer at junctions"): pads a raw mesh as
// finish_mesh does (selective padding, pad_to_domain, the given options) without the later stages and prints, for
// the worst padding hexes, which frame of the hex is the worst (the centre, a bottom corner on the raw boundary or a
// top corner on the new boundary) and why: at a bottom corner the value is sin(the raw quad's corner angle) x
// cos(the padding direction, that corner's normal); at a top corner, how much the top edges shrank against the
// bottom ones (converging directions) and how the offsets of the hex's four vertices differ.
//   mesohex_pad_diag RAW.mesh DOMAIN.off [COUNT] [--no-pad-to-domain] [--guard SJ] [--search COS]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "mesohex/core/hex_convention.h"
#include "mesohex/core/hex_kernels.h"
#include "mesohex/core/topology.h"
#include "mesohex/finish.h"
#include "mesohex/post/padding.h"
#include "mesohex/post/quality.h"
#include "mesohex_io/hex_io.h"
#include "mesohex_io/surface_io.h"

namespace {

using namespace mesohex;

struct Args {
    std::string raw, domain;
    int count = 8;
    FinishOptions options;
};

Args parse(int argc, char** argv) {
    Args a;
    a.raw = argv[1];
    a.domain = argv[2];
    for (int i = 3; i < argc; ++i) {
        const std::string s = argv[i];
        if (s == "--no-pad-to-domain")
            a.options.pad_to_domain = 0;
        else if (s == "--guard" && i + 1 < argc)
            a.options.padding.corner_guard = std::atof(argv[++i]);
        else if (s == "--search" && i + 1 < argc)
            a.options.padding.search_cos = std::atof(argv[++i]);
        else
            a.count = std::atoi(argv[i]);
    }
    a.options.pad_improve_sj = 0;
    a.options.subdivide = false;
    a.options.fit = false;
    a.options.untangle = false;
    a.options.smooth = false;
    a.options.improve_sj = 0;
    a.options.measure_distance = false;
    return a;
}

std::array<Vec3, 8> corners(const HexMesh& m, const std::array<int, 8>& h) {
    std::array<Vec3, 8> c;
    for (std::size_t i = 0; i < 8; ++i) c[i] = m.points[static_cast<std::size_t>(h[i])];
    return c;
}

// The corner normals (sin-weighted: the raw quad's corner frame) of the boundary quads at boundary vertex v.
void vertex_report(const HexMesh& m, const std::vector<std::array<int, 4>>& quads, int v, const Vec3& dir) {
    std::vector<Vec3> n;
    Vec3 mean;
    double worst_sin = 1;
    for (const std::array<int, 4>& q : quads)
        for (std::size_t i = 0; i < 4; ++i) {
            if (q[i] != v) continue;
            const Vec3 p = m.points[static_cast<std::size_t>(v)];
            const Vec3 a = m.points[static_cast<std::size_t>(q[(i + 1) % 4])] - p;
            const Vec3 b = m.points[static_cast<std::size_t>(q[(i + 3) % 4])] - p;
            const Vec3 c = cross(a, b);
            worst_sin = std::min(worst_sin, norm(c) / (norm(a) * norm(b)));
            n.push_back(normalized(c));
            mean += quad_normal(m, q);
        }
    double lo_dir = 2, lo_mean = 2, best = 0;
    mean = normalized(mean);
    for (const Vec3& x : n) {
        lo_dir = std::min(lo_dir, dot(x, dir));
        lo_mean = std::min(lo_mean, dot(x, mean));
    }
    best = lowest_corner(n, maximin_direction(n, mean));
    std::printf("    vertex %d: %zu quads, worst sin %.3f, min cos: direction %.3f mean normal %.3f maximin %.3f\n", v,
                n.size(), worst_sin, lo_dir, lo_mean, best);
}

void report_hex(const HexMesh& m, std::size_t h, double sj) {
    const std::array<Vec3, 8> c = corners(m, m.hexes[h]);
    const std::array<double, 9> f = hex_frame_values(c);
    const std::size_t worst = static_cast<std::size_t>(std::min_element(f.begin(), f.end()) - f.begin());
    std::printf("hex %zu sj %.4f worst frame %s", h, sj, worst == 0 ? "centre" : (worst <= 4 ? "bottom" : "top"));
    double off[4];
    for (std::size_t i = 0; i < 4; ++i) off[i] = distance(c[i], c[i + 4]);
    double bottom_len = 0, top_len = 0;
    for (std::size_t i = 0; i < 4; ++i) {
        bottom_len += distance(c[i], c[(i + 1) % 4]);
        top_len += distance(c[i + 4], c[(i + 1) % 4 + 4]);
    }
    std::printf(" | top/bottom perimeter %.3f | offsets / mean bottom edge %.3f %.3f %.3f %.3f", top_len / bottom_len,
                4 * off[0] / bottom_len, 4 * off[1] / bottom_len, 4 * off[2] / bottom_len, 4 * off[3] / bottom_len);
    if (worst >= 1 && worst <= 4) {
        const std::size_t lv = worst - 1;
        const std::array<Vec3, 3> fr = hex_corner_frame(c, lv);
        const Vec3 n = cross(fr[0], fr[1]);
        const double sin_angle = norm(n) / (norm(fr[0]) * norm(fr[1]));
        const double cos_dir = dot(normalized(n), normalized(fr[2]));
        std::printf(" | corner %zu sin %.3f cos(dir, n) %.3f", lv, sin_angle, cos_dir);
    }
    std::printf(" | frames");
    for (double v : f) std::printf(" %.3f", v);
    std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: mesohex_pad_diag RAW.mesh DOMAIN.off [COUNT] [--no-pad-to-domain]\n");
        return 2;
    }
    try {
        const Args a = parse(argc, argv);
        const HexMesh raw = read_hex_mesh(a.raw);
        const TriangleMesh domain = read_surface(a.domain);
        const FinishResult r = finish_mesh(raw, domain, a.options);
        const std::vector<double> sj = scaled_jacobians(r.mesh);
        std::vector<std::size_t> order;
        for (std::size_t h = raw.hexes.size(); h < r.mesh.hexes.size(); ++h) order.push_back(h);
        std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return sj[x] < sj[y]; });
        double raw_min = 1;
        for (std::size_t h = 0; h < raw.hexes.size(); ++h) raw_min = std::min(raw_min, sj[h]);
        const int below =
            static_cast<int>(std::count_if(order.begin(), order.end(), [&](std::size_t h) { return sj[h] < 0.2; }));
        double checksum = 0;  // tells two paddings of the same raw mesh apart (e.g. with and without an option)
        for (std::size_t v = 0; v < r.mesh.points.size(); ++v)
            checksum += static_cast<double>(v % 97 + 1) *
                        (r.mesh.points[v].x + 2 * r.mesh.points[v].y + 3 * r.mesh.points[v].z);
        std::printf("raw min %.4f padded min %.4f (padding hexes %zu, below 0.2: %d) checksum %.12g\n", raw_min,
                    order.empty() ? 1.0 : sj[order.front()], order.size(), below, checksum);
        const std::vector<std::array<int, 4>> quads = compute_hex_topology(raw).boundary_quads;
        for (int i = 0; i < a.count && i < static_cast<int>(order.size()); ++i) {
            const std::size_t h = order[static_cast<std::size_t>(i)];
            report_hex(r.mesh, h, sj[h]);
            const std::array<double, 9> f = hex_frame_values(corners(r.mesh, r.mesh.hexes[h]));
            const std::size_t worst =
                static_cast<std::size_t>(std::min_element(f.begin() + 1, f.end()) - f.begin()) - 1;
            const int v = r.mesh.hexes[h][worst % 4];
            vertex_report(raw, quads, v,
                          normalized(r.mesh.points[static_cast<std::size_t>(r.mesh.hexes[h][worst % 4 + 4])] -
                                     raw.points[static_cast<std::size_t>(v)]));
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mesohex_pad_diag: %s\n", e.what());
        return 1;
    }
    return 0;
}
