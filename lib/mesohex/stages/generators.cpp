#include "mesohex/stages/generators.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numbers>
#include <utility>

#include "mesohex/core/error.h"

namespace mesohex {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxResolution = 1000;  // bounds every n and m so a typo cannot ask for gigabytes

// ---------------------------------------------------------------------------------------------------------------
// Small building blocks. Points are appended with their radius; branch edges are added explicitly; leaflet edges are
// added once at the end by add_face_edges(), so every face side is present exactly once.

int add_point(Skeleton& s, const Vec3& p, double radius) {
    s.points.push_back(p);
    s.radii.push_back(radius);
    return static_cast<int>(s.points.size()) - 1;
}

// Appends a branch (polyline) that starts at the existing point `start` and visits `points` in order; one branch
// edge per consecutive pair. Returns the ids of the whole polyline, `start` included.
std::vector<int> add_polyline(Skeleton& s, int start, const std::vector<Vec3>& points,
                              const std::vector<double>& radii) {
    std::vector<int> ids{start};
    for (std::size_t k = 0; k < points.size(); ++k) {
        const int v = add_point(s, points[k], radii[k]);
        s.edges.push_back({ids.back(), v});
        ids.push_back(v);
    }
    return ids;
}

// Same, but joins two existing points `a` and `b` through the interior `points`.
void add_polyline_between(Skeleton& s, int a, int b, const std::vector<Vec3>& points,
                          const std::vector<double>& radii) {
    const std::vector<int> ids = add_polyline(s, a, points, radii);
    s.edges.push_back({ids.back(), b});
}

// The point ids of a (nu + 1) x (nv + 1) lattice of a quad grid; -1 = not created yet (so that rows can be shared
// with other grids or branches before the grid is filled).
struct Lattice {
    int nu = 0, nv = 0;
    std::vector<int> ids;
    Lattice(int nu_, int nv_) : nu(nu_), nv(nv_), ids(static_cast<std::size_t>((nu_ + 1) * (nv_ + 1)), -1) {}
    int& at(int i, int j) { return ids[static_cast<std::size_t>(i * (nv + 1) + j)]; }
    int at(int i, int j) const { return ids[static_cast<std::size_t>(i * (nv + 1) + j)]; }
};

// Creates every lattice point that is still -1, at position(i, j) with the given radius.
void fill_lattice(Skeleton& s, Lattice& lat, const std::function<Vec3(int, int)>& position, double radius) {
    for (int i = 0; i <= lat.nu; ++i)
        for (int j = 0; j <= lat.nv; ++j)
            if (lat.at(i, j) < 0) lat.at(i, j) = add_point(s, position(i, j), radius);
}

// Adds the nu x nv quads of the lattice, each as (i,j) (i+1,j) (i+1,j+1) (i,j+1): all faces of one lattice are
// consistently oriented, with normal along (d/di) x (d/dj). Only cells with keep(i, j) are added.
void add_lattice_quads(Skeleton& s, const Lattice& lat, const std::function<bool(int, int)>& keep = {}) {
    for (int i = 0; i < lat.nu; ++i)
        for (int j = 0; j < lat.nv; ++j)
            if (!keep || keep(i, j))
                s.faces.push_back({lat.at(i, j), lat.at(i + 1, j), lat.at(i + 1, j + 1), lat.at(i, j + 1)});
}

Vec3 rotate_z(const Vec3& d, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {c * d.x - s * d.y, s * d.x + c * d.y, d.z};
}

// ---------------------------------------------------------------------------------------------------------------
// Options

struct Params {
    int n = 0, m = 0, quarter_turns = 0;
    double angle = 0;  // radians (fold, vfan)
    double L = 1.0;    // leaflet edge length
    double r = 0.3;    // default radius: 0.3 x L x radius_scale
};

int resolution(const std::string& shape, const char* what, int value, int fallback, int min_value) {
    const int v = value == 0 ? fallback : value;
    if (v < min_value || v > kMaxResolution)
        throw Error(ErrorCode::InvalidInput, "generate " + shape + ": " + what + " = " + std::to_string(v) +
                                                 " is out of range [" + std::to_string(min_value) + ", " +
                                                 std::to_string(kMaxResolution) + "]");
    return v;
}

Params make_params(const std::string& shape, const GeneratorOptions& o, std::array<int, 2> default_nm,
                   std::array<int, 2> min_nm) {
    if (!(o.edge_length > 0) || !std::isfinite(o.edge_length))
        throw Error(ErrorCode::InvalidInput, "generate " + shape + ": edge length must be > 0");
    if (!(o.radius_scale > 0) || !std::isfinite(o.radius_scale))
        throw Error(ErrorCode::InvalidInput, "generate " + shape + ": radius scale must be > 0");
    Params p;
    p.n = resolution(shape, "n", o.n, default_nm[0], min_nm[0]);
    p.m = resolution(shape, "m", o.m, default_nm[1], min_nm[1]);
    p.quarter_turns = o.quarter_turns == -1 ? 2 : o.quarter_turns;
    if (p.quarter_turns < 0 || p.quarter_turns > 64)
        throw Error(ErrorCode::InvalidInput, "generate " + shape + ": quarter turns = " +
                                                 std::to_string(p.quarter_turns) + " is out of range [0, 64]");
    const double angle_deg = o.angle_deg == 0 ? 45 : o.angle_deg;
    if (!(angle_deg >= 10 && angle_deg <= 170))
        throw Error(ErrorCode::InvalidInput, "generate " + shape + ": angle = " + std::to_string(angle_deg) +
                                                 " degrees is out of range [10, 170]");
    p.angle = angle_deg * kPi / 180;
    p.L = o.edge_length;
    p.r = 0.3 * o.edge_length * o.radius_scale;
    return p;
}

// ---------------------------------------------------------------------------------------------------------------
// The shapes. Each builds points, branch edges and faces; generate_skeleton() adds the face edges.

// n x m quads in the z = 0 plane, centred on the origin, normal +z.
Skeleton make_plate(const Params& p) {
    Skeleton s;
    Lattice lat(p.n, p.m);
    fill_lattice(
        s, lat,
        [&](int i, int j) {
            return Vec3{(i - 0.5 * p.n) * p.L, (j - 0.5 * p.m) * p.L, 0.0};
        },
        p.r);
    add_lattice_quads(s, lat);
    return s;
}

// The closed surface of a cube, n x n quads per side, normals outward. Points are shared between sides through
// their integer lattice coordinates.
Skeleton make_box(const Params& p) {
    Skeleton s;
    const int k = p.n;
    std::map<std::array<int, 3>, int> id_of;
    struct Side {
        std::array<int, 3> origin, u, v;  // u x v is the outward normal
    };
    const std::array<Side, 6> sides{{
        {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},  // z = 0
        {{0, 0, k}, {1, 0, 0}, {0, 1, 0}},  // z = k
        {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},  // y = 0
        {{0, k, 0}, {0, 0, 1}, {1, 0, 0}},  // y = k
        {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}},  // x = 0
        {{k, 0, 0}, {0, 1, 0}, {0, 0, 1}},  // x = k
    }};
    for (const Side& side : sides) {
        Lattice lat(k, k);
        for (int i = 0; i <= k; ++i) {
            for (int j = 0; j <= k; ++j) {
                std::array<int, 3> c{};
                for (int a = 0; a < 3; ++a) c[a] = side.origin[a] + i * side.u[a] + j * side.v[a];
                auto it = id_of.find(c);
                if (it == id_of.end()) {
                    const Vec3 pos{(c[0] - 0.5 * k) * p.L, (c[1] - 0.5 * k) * p.L, (c[2] - 0.5 * k) * p.L};
                    it = id_of.emplace(c, add_point(s, pos, p.r)).first;
                }
                lat.at(i, j) = it->second;
            }
        }
        add_lattice_quads(s, lat);
    }
    return s;
}

// A closed quad torus: n quads around the z axis, m around the tube. Sizes make the edges at the middle of the tube
// have length L. Radius = 0.3 x the mean local edge length (edges are shorter on the inner side).
Skeleton make_torus(const Params& p) {
    if (p.n < p.m + 4)
        throw Error(ErrorCode::InvalidInput,
                    "generate torus: n (around the axis) must be at least m + 4 so that "
                    "the hole stays open");
    Skeleton s;
    const double big = p.n * p.L / (2 * kPi), small = p.m * p.L / (2 * kPi);
    std::vector<int> id(static_cast<std::size_t>(p.n * p.m));
    for (int i = 0; i < p.n; ++i) {
        const double theta = 2 * kPi * i / p.n;
        for (int j = 0; j < p.m; ++j) {
            const double phi = 2 * kPi * j / p.m;
            const double rho = big + small * std::cos(phi);
            const double around = 2 * kPi * rho / p.n;  // local edge length around the axis
            id[static_cast<std::size_t>(i * p.m + j)] =
                add_point(s, {rho * std::cos(theta), rho * std::sin(theta), small * std::sin(phi)},
                          p.r * 0.5 * (around + p.L) / p.L);
        }
    }
    auto at = [&](int i, int j) { return id[static_cast<std::size_t>((i % p.n) * p.m + (j % p.m))]; };
    for (int i = 0; i < p.n; ++i)
        for (int j = 0; j < p.m; ++j) s.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    return s;
}

// Strips of m x n quads sharing one fan edge of n edges along z; strip k leaves in the horizontal direction at
// angle angles[k]. The fan ends are corners of every strip.
Skeleton make_fan(const Params& p, const std::vector<double>& angles) {
    Skeleton s;
    std::vector<int> fan;
    for (int j = 0; j <= p.n; ++j) fan.push_back(add_point(s, {0, 0, (j - 0.5 * p.n) * p.L}, p.r));
    for (const double angle : angles) {
        const Vec3 d{std::cos(angle), std::sin(angle), 0};
        Lattice lat(p.m, p.n);
        for (int j = 0; j <= p.n; ++j) lat.at(0, j) = fan[static_cast<std::size_t>(j)];
        fill_lattice(
            s, lat, [&](int i, int j) { return s.points[fan[static_cast<std::size_t>(j)]] + i * p.L * d; }, p.r);
        add_lattice_quads(s, lat);
    }
    return s;
}

// Fan-block test shapes (fan_blocks.h): strips of 2 quads on a straight fan line of m edges along z, strip k leaving
// at angles[k] + offset[k] about z and turning by twist[k] radians per fan-line vertex (its quads slightly warped).
Skeleton make_turned_fan(const Params& p, const std::vector<double>& angles, const std::vector<double>& offset,
                         const std::vector<double>& twist) {
    Skeleton s;
    std::vector<int> fan;
    for (int j = 0; j <= p.m; ++j) fan.push_back(add_point(s, {0, 0, (j - 0.5 * p.m) * p.L}, p.r));
    for (std::size_t k = 0; k < angles.size(); ++k) {
        Lattice lat(2, p.m);
        for (int j = 0; j <= p.m; ++j) lat.at(0, j) = fan[static_cast<std::size_t>(j)];
        fill_lattice(
            s, lat,
            [&](int i, int j) {
                const double a = angles[k] + offset[k] + twist[k] * j;
                return s.points[fan[static_cast<std::size_t>(j)]] + i * p.L * Vec3{std::cos(a), std::sin(a), 0};
            },
            p.r);
        add_lattice_quads(s, lat);
    }
    return s;
}

// T (n = 3) or X (n = 4) whose strips are off the right angles by 4 to 9 degrees and turn by up to 3 degrees per
// fan-line vertex (m fan edges): accepted by the fan-block test everywhere.
Skeleton make_fan_block(const Params& p) {
    if (p.n > 4) throw Error(ErrorCode::InvalidInput, "generate fanblock: n (strips) must be 3 or 4");
    const std::vector<double> angles =
        p.n == 3 ? std::vector<double>{0.0, 0.5 * kPi, kPi} : std::vector<double>{0.0, 0.5 * kPi, kPi, 1.5 * kPi};
    const double deg = kPi / 180;
    return make_turned_fan(p, angles, {7 * deg, -4 * deg, 9 * deg, -6 * deg}, {3 * deg, 2 * deg, 3 * deg, 1 * deg});
}

// Y: three strips 120 degrees apart (never a fan block: 3 distinct axes contain an opposite pair).
Skeleton make_y_fan(const Params& p) {
    return make_turned_fan(p, {0.0, 2 * kPi / 3, 4 * kPi / 3}, {0, 0, 0}, {0, 0, 0});
}

// A T (n = 3) or X (n = 4) fan (2 x 2-quad strips on a fan edge of 2 edges, as tfan / xfan) with a 3-edge branch on
// the fan's upper end w = (0, 0, L): continuing the fan line (+z, m = 1) or perpendicular to it (m = 2), horizontal,
// into the middle of the widest gap between strips (T: -y; X: 45 degrees, between the +x and +y strips). Branch
// edges of length L, radius that of the fan. The configuration of the paper's limitation 3: the analysis refuses it,
// the skeleton repair retracts the fan edge when the branch continues the fan line (stages/fan_end_repair.h).
// m = 3: continuing at both ends (a second branch from the lower end (0, 0, -L) along -z; the repair cuts the chain
// into 4 fan edges, then retracts both ends). m = 4: perpendicular at the upper end (as m = 2) and continuing at the
// lower end (the repair retracts the lower end, then moves the upper branch's root onto a leaflet border). m = 5:
// leaning back, 135 degrees off the fan line's continuation, in the
// plane of m = 2's direction and the fan line (refused: no repair).
Skeleton make_fan_end(const Params& p) {
    if (p.n > 4) throw Error(ErrorCode::InvalidInput, "generate fanend: n (strips) must be 3 or 4");
    if (p.m > 5) throw Error(ErrorCode::InvalidInput, "generate fanend: m (branch direction) must be 1 to 5");
    Params fan = p;
    fan.n = 2;
    fan.m = 2;
    const std::vector<double> angles =
        p.n == 3 ? std::vector<double>{0.0, 0.5 * kPi, kPi} : std::vector<double>{0.0, 0.5 * kPi, kPi, 1.5 * kPi};
    Skeleton s = make_fan(fan, angles);
    const int w = 2;  // the fan line's points come first, bottom to top
    const Vec3 across = rotate_z({1, 0, 0}, p.n == 3 ? 1.5 * kPi : 0.25 * kPi);
    const Vec3 d = p.m == 2 || p.m == 4 ? across : p.m == 5 ? std::sqrt(0.5) * (across - Vec3{0, 0, 1}) : Vec3{0, 0, 1};
    std::vector<Vec3> pts;
    for (int k = 1; k <= 3; ++k) pts.push_back(s.points[w] + k * p.L * d);
    add_polyline(s, w, pts, std::vector<double>(3, p.r));
    if (p.m == 3 || p.m == 4) {  // a second branch from the lower end (0, 0, -L) along -z
        pts.clear();
        for (int k = 1; k <= 3; ++k) pts.push_back(s.points[0] - k * p.L * Vec3{0, 0, 1});
        add_polyline(s, 0, pts, std::vector<double>(3, p.r));
    }
    return s;
}

// A finger (or thumb): n branch edges leaving `start` along `first`, then turning by `turn` radians per edge
// (in the z = 0 plane); the radius tapers linearly from the joint's to 0.7 of it.
void add_finger(Skeleton& s, int start, Vec3 first, double turn, double edge, int n) {
    std::vector<Vec3> pts;
    std::vector<double> radii;
    Vec3 pos = s.points[static_cast<std::size_t>(start)];
    Vec3 dir = normalized(first);
    const double r0 = s.radii[static_cast<std::size_t>(start)];
    for (int k = 1; k <= n; ++k) {
        pos += edge * dir;
        pts.push_back(pos);
        radii.push_back(r0 * (1.0 - 0.3 * k / n));
        dir = rotate_z(dir, turn);
    }
    add_polyline(s, start, pts, radii);
}

// Palm: an 8 x m grid (x spacing a = 0.75 L, y spacing L). In the top row, points at odd x index are raised by a/2
// and the others lowered by a/2, so each raised point is a convex 90° boundary vertex whose outward diagonal is +y:
// the four fingers leave from them. The thumb leaves from the palm's lower-left corner (a 90° corner) along its
// outward diagonal (-x-y), then turns towards -x and +y. Fingers and thumb are branches of n edges.
Skeleton make_hand(const Params& p) {
    Skeleton s;
    const int cols = 8, rows = p.m;
    const double a = 0.75 * p.L;
    Lattice lat(cols, rows);
    fill_lattice(
        s, lat,
        [&](int i, int j) {
            Vec3 pos{i * a, j * p.L, 0};
            if (j == rows) pos.y += (i % 2 == 1 ? 0.5 : -0.5) * a;
            return pos;
        },
        p.r);
    add_lattice_quads(s, lat);
    const std::array<double, 4> spread{0.12, 0.04, -0.04, -0.12};  // fingers fan out slightly (radians / edge)
    const std::array<double, 4> length{0.6, 0.75, 0.8, 0.7};       // edge length of each finger, x L
    for (int f = 0; f < 4; ++f) add_finger(s, lat.at(2 * f + 1, rows), {0, 1, 0}, spread[f], length[f] * p.L, p.n);
    add_finger(s, lat.at(0, 0), {-1, -1, 0}, -0.6, 0.7 * p.L, p.n);  // thumb
    return s;
}

// Seat: n x n quads at height h, split by a fan edge (the row of points at y = n - 1) into a front leaflet and a
// one-quad rear lip; the back (n x n quads) rises from the fan edge, which thus has degree 3 and ends on the seat's
// side borders, one row away from the rear corners. Four legs (m edges each) leave the seat's four convex corners,
// the first edge 45° below the outward corner diagonal, then straight down.
Skeleton make_chair(const Params& p) {
    Skeleton s;
    const int n = p.n;
    const double leg_edge = 0.75 * p.L;
    const double height = leg_edge * (p.m - 1) + leg_edge * std::sqrt(0.5);
    Lattice seat(n, n);
    fill_lattice(
        s, seat,
        [&](int i, int j) {
            return Vec3{i * p.L, j * p.L, height};
        },
        p.r);
    add_lattice_quads(s, seat);
    Lattice back(n, n);
    for (int i = 0; i <= n; ++i) back.at(i, 0) = seat.at(i, n - 1);
    fill_lattice(
        s, back,
        [&](int i, int k) {
            return Vec3{i * p.L, (n - 1) * p.L, height + k * p.L};
        },
        p.r);
    add_lattice_quads(s, back);
    const std::array<std::array<int, 2>, 4> corners{{{0, 0}, {n, 0}, {n, n}, {0, n}}};
    for (const std::array<int, 2>& c : corners) {
        const Vec3 out = normalized(Vec3{c[0] == 0 ? -1.0 : 1.0, c[1] == 0 ? -1.0 : 1.0, 0});
        const int start = seat.at(c[0], c[1]);
        std::vector<Vec3> pts;
        std::vector<double> radii;
        Vec3 pos = s.points[static_cast<std::size_t>(start)] + leg_edge * normalized(out + Vec3{0, 0, -1});
        for (int k = 1; k <= p.m; ++k) {
            pts.push_back(pos);
            radii.push_back(p.r * (1.0 - 0.2 * k / p.m));
            pos.z -= leg_edge;
        }
        add_polyline(s, start, pts, radii);
    }
    return s;
}

// Body along x: a neck of 3 edges forward and a body of 3 edges backward from the branching point B (origin). The
// two wings (n quads of span x m quads of chord, swept back) touch B by one corner each (B is a branching point
// with 2 branches + 2 leaflets); a 2 x 2 tail leaflet hangs by its corner at the rear end of the body (a BL-joint,
// the body arriving along the tail's outward corner diagonal).
Skeleton make_bird(const Params& p) {
    Skeleton s;
    const double body_r = 1.2 * p.r, edge = 0.8 * p.L;
    const int b = add_point(s, {0, 0, 0}, body_r);
    add_polyline(s, b, {{edge, 0, 0.1 * edge}, {2 * edge, 0, 0.3 * edge}, {3 * edge, 0, 0.6 * edge}},
                 {body_r, 0.9 * body_r, 0.8 * body_r});
    const std::vector<int> body =
        add_polyline(s, b, {{-edge, 0, 0}, {-2 * edge, 0, 0}, {-3 * edge, 0, 0}}, {body_r, 0.9 * body_r, p.r});
    const double h = std::sqrt(0.5);
    // Left wing: i along the chord (+x+y), j along the span (-x+y): normal +z. Right wing: mirrored.
    for (const double side : {1.0, -1.0}) {
        const Vec3 chord{h, side * h, 0}, span{-h, side * h, 0};
        const bool left = side > 0;
        Lattice lat(left ? p.m : p.n, left ? p.n : p.m);
        lat.at(0, 0) = b;
        fill_lattice(
            s, lat,
            [&](int i, int j) {
                const int c = left ? i : j, w = left ? j : i;
                return (c * p.L) * chord + (w * p.L) * span + Vec3{0, 0, 0.1 * w * p.L};
            },
            p.r);
        add_lattice_quads(s, lat);
    }
    const int tail_corner = body.back();
    const Vec3 t0 = s.points[static_cast<std::size_t>(tail_corner)];
    Lattice tail(2, 2);
    tail.at(0, 0) = tail_corner;
    fill_lattice(
        s, tail,
        [&](int i, int j) {
            return t0 + (i * p.L) * Vec3{-h, h, 0} + (j * p.L) * Vec3{-h, -h, 0};
        },
        p.r);
    add_lattice_quads(s, tail);
    return s;
}

// An open strip of n x m quads along x (width m L, centred on the x axis), its cross-section rotating by
// quarter_turns x 90° from one end to the other.
Skeleton make_twist(const Params& p) {
    Skeleton s;
    const double total = p.quarter_turns * 0.5 * kPi;
    Lattice lat(p.n, p.m);
    fill_lattice(
        s, lat,
        [&](int i, int j) {
            const double angle = total * i / p.n, w = (j - 0.5 * p.m) * p.L;
            return Vec3{i * p.L, w * std::cos(angle), w * std::sin(angle)};
        },
        p.r);
    add_lattice_quads(s, lat);
    return s;
}

// A ring of n segments whose cross-section is an X (four arms of m quads from the core) rotating by
// quarter_turns x 90° once around. The core circle is a closed fan edge of degree 4. With 2 quarter turns each pair
// of opposite arms is a Möbius strip; cut along its centre line by the fan edge it is one orientable annulus, so
// every leaflet is orientable (2 leaflets for 2 quarter turns, 1 for odd, 4 for multiples of 4).
Skeleton make_torustwist(const Params& p) {
    const double big = p.n * p.L / (2 * kPi);
    if (big < (p.m + 0.5) * p.L)
        throw Error(ErrorCode::InvalidInput,
                    "generate torustwist: n must be at least 2 pi (m + 0.5) so that the "
                    "arms do not reach the axis");
    Skeleton s;
    std::vector<int> core;
    for (int i = 0; i < p.n; ++i) {
        const double theta = 2 * kPi * i / p.n;
        core.push_back(add_point(s, {big * std::cos(theta), big * std::sin(theta), 0}, p.r));
    }
    // arm[(i * 4 + a) * m + (j - 1)] = point j (1..m) of arm a at ring position i.
    std::vector<int> arm(static_cast<std::size_t>(p.n * 4 * p.m));
    for (int i = 0; i < p.n; ++i) {
        const double theta = 2 * kPi * i / p.n;
        const Vec3 radial{std::cos(theta), std::sin(theta), 0};
        for (int a = 0; a < 4; ++a) {
            const double phi = 0.5 * kPi * (a + p.quarter_turns * static_cast<double>(i) / p.n);
            const Vec3 d = std::cos(phi) * radial + Vec3{0, 0, std::sin(phi)};
            for (int j = 1; j <= p.m; ++j)
                arm[static_cast<std::size_t>((i * 4 + a) * p.m + j - 1)] = add_point(
                    s, s.points[static_cast<std::size_t>(core[static_cast<std::size_t>(i)])] + j * p.L * d, p.r);
        }
    }
    // Point j of arm a at ring position i, for i in [0, n]: position n is position 0 with the arms shifted.
    auto at = [&](int i, int a, int j) {
        if (i == p.n) {
            i = 0;
            a = (a + p.quarter_turns) % 4;
        }
        if (j == 0) return core[static_cast<std::size_t>(i)];
        return arm[static_cast<std::size_t>((i * 4 + a) * p.m + j - 1)];
    };
    for (int a = 0; a < 4; ++a)
        for (int i = 0; i < p.n; ++i)
            for (int j = 0; j < p.m; ++j)
                s.faces.push_back({at(i, a, j), at(i + 1, a, j), at(i + 1, a, j + 1), at(i, a, j + 1)});
    return s;
}

// The compound of an octahedron (vertices at +-2c on the axes) and its dual cube (vertices at (+-c, +-c, +-c)):
// every octahedron edge crosses one cube edge at right angles at their common midpoint. Branching points: 6
// octahedron vertices (4 branches), 8 cube vertices (3 branches), 12 crossings (4 branches); each of the 48
// half-edges is a branch of n edges. Curve-only.
// A star: arms of p.m edges of length L from the origin along `dirs` (unit vectors).
Skeleton make_star(const Params& p, const std::vector<Vec3>& dirs) {
    Skeleton s;
    const int c = add_point(s, {0, 0, 0}, p.r);
    for (const Vec3& d : dirs) {
        std::vector<Vec3> pts;
        for (int k = 1; k <= p.m; ++k) pts.push_back((k * p.L) * normalized(d));
        add_polyline(s, c, pts, std::vector<double>(pts.size(), p.r));
    }
    return s;
}

// Near-orthogonal stars (compatible blocks, compatible_blocks.h): 3 = the corner (x, y, z), 4 = the planar cross
// (+-x, +-y), 5 = the cross and +z, 6 = +-x, +-y, +-z.
Skeleton make_cubestar(const Params& p) {
    if (p.n > 6)
        throw Error(ErrorCode::InvalidInput,
                    "generate cubestar: n = " + std::to_string(p.n) + " is out of range [3, 6]");
    const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    const std::vector<std::vector<Vec3>> stars{{x, y, z}, {x, -x, y, -y}, {x, -x, y, -y, z}, {x, -x, y, -y, z, -z}};
    return make_star(p, stars[static_cast<std::size_t>(p.n - 3)]);
}

Skeleton make_dualocta(const Params& p) {
    Skeleton s;
    const double c = 0.6 * p.n * p.L;  // cube half-edges have n edges of 0.6 L; octahedron half-edges 0.85 L
    const double r = p.r;
    std::vector<int> octa, cube;
    for (int axis = 0; axis < 3; ++axis)
        for (const double sign : {1.0, -1.0}) {
            Vec3 v{};
            v[axis] = 2 * c * sign;
            octa.push_back(add_point(s, v, r));
        }
    for (int k = 0; k < 8; ++k) cube.push_back(add_point(s, {(k & 1) ? c : -c, (k & 2) ? c : -c, (k & 4) ? c : -c}, r));
    auto half_edge = [&](int from, int to) {  // n edges from point `from` to point `to`
        std::vector<Vec3> pts;
        std::vector<double> radii;
        const Vec3 a = s.points[static_cast<std::size_t>(from)], b = s.points[static_cast<std::size_t>(to)];
        for (int k = 1; k < p.n; ++k) {
            pts.push_back(a + (static_cast<double>(k) / p.n) * (b - a));
            radii.push_back(r);
        }
        add_polyline_between(s, from, to, pts, radii);
    };
    // Cube edges: pairs of corners differing in one bit. Each one's midpoint is a crossing with the octahedron edge
    // joining the two octahedron vertices on the axes in which the cube edge's corners agree.
    for (int k = 0; k < 8; ++k) {
        for (int bit = 0; bit < 3; ++bit) {
            const int other = k ^ (1 << bit);
            if (other < k) continue;
            const Vec3 mid = 0.5 * (s.points[static_cast<std::size_t>(cube[static_cast<std::size_t>(k)])] +
                                    s.points[static_cast<std::size_t>(cube[static_cast<std::size_t>(other)])]);
            const int x = add_point(s, mid, r);
            half_edge(cube[static_cast<std::size_t>(k)], x);
            half_edge(x, cube[static_cast<std::size_t>(other)]);
            for (int axis = 0; axis < 3; ++axis) {
                if (axis == bit) continue;
                const int o = octa[static_cast<std::size_t>(2 * axis + ((k >> axis) & 1 ? 0 : 1))];
                half_edge(o, x);
            }
        }
    }
    return s;
}

// A two- or three-bladed Darrieus turbine on a vertical shaft. The shaft is a branch through two branching points
// S (z = 0) and T (z = H) with 3 edges below S and one above T. Each blade is a strip of n quads along a bow in a
// vertical half-plane (from S out to radius R and back to T) and one quad of chord in the tangential direction; the
// blade touches the shaft only at its two inner corners S and T (each a convex 90° corner: the bow starts
// horizontally in its half-plane, the chord edge is horizontal and tangential). S and T are branching points with 2
// shaft branches + m blade leaflets; no leaflet edge lies along the shaft.
Skeleton make_turbine(const Params& p) {
    if (p.m > 3)
        throw Error(ErrorCode::InvalidInput,
                    "generate turbine: m (blades) must be 2 or 3 (more would make the blade "
                    "roots overlap at the shaft)");
    Skeleton s;
    const double radius_out = 2 * p.L, height = 5 * p.L, shaft_edge = 0.6 * p.L;
    const int below = 3, middle = 8, above = 1;
    const int bottom = add_point(s, {0, 0, -below * shaft_edge}, 0.8 * p.r);
    std::vector<Vec3> pts;
    std::vector<double> radii;
    for (int k = 1; k <= below; ++k) pts.push_back({0, 0, (k - below) * shaft_edge});
    radii.assign(pts.size(), p.r);
    const int low = add_polyline(s, bottom, pts, radii).back();
    pts.clear();
    for (int k = 1; k <= middle; ++k) pts.push_back({0, 0, height * k / middle});
    radii.assign(pts.size(), p.r);
    const int high = add_polyline(s, low, pts, radii).back();
    add_polyline(s, high, {{0, 0, height + above * shaft_edge}}, {0.8 * p.r});
    for (int blade = 0; blade < p.m; ++blade) {
        const double alpha = 2 * kPi * blade / p.m;
        const Vec3 radial{std::cos(alpha), std::sin(alpha), 0}, tangent{-std::sin(alpha), std::cos(alpha), 0};
        Lattice lat(p.n, 1);
        lat.at(0, 0) = low;
        lat.at(p.n, 0) = high;
        fill_lattice(
            s, lat,
            [&](int i, int j) {
                const double t = kPi * i / p.n;
                return (radius_out * std::sin(t)) * radial + Vec3{0, 0, 0.5 * height * (1 - std::cos(t))} +
                       (j * p.L) * tangent;
            },
            p.r);
        add_lattice_quads(s, lat);
    }
    return s;
}

// ---------------------------------------------------------------------------------------------------------------

// A pan: n x m quads (n >= 6, m >= 2) in the z = 0 plane; both branches are rooted on the plates, beyond the paper's
// BL-joints: a handle of 3 edges leaving the middle of the short side x = min outward, 20 degrees above the plane (out
// patch), and a bucket arch of 6 edges over the middle row, from the interior vertex 1 quad in from each short side
// (plates inside the leaflet; 2 quads in, the arch's tighter bend gave min SJ 0.504). Branch radius 5/3 x the
// plate's: half a leaflet edge, as wide as the patches they stand on allow (thinner branches leave a funnel of hexes
// outside the domain around the root; thicker ones, 0.6 or more, are too fat for the arch's bend). A leg straight
// down from a border vertex of 2 faces (side patch) was tried: its patch, centred inside the border, shears the
// funnel towards a tube centred on it, and the fit leaves the plate's underside uncovered there (1.34 %).
Skeleton make_pan(const Params& p) {
    Skeleton s;
    Lattice lat(p.n, p.m);
    const double x0 = -0.5 * p.n * p.L, y0 = -0.5 * p.m * p.L;
    fill_lattice(
        s, lat,
        [&](int i, int j) {
            return Vec3{x0 + i * p.L, y0 + j * p.L, 0.0};
        },
        p.r);
    add_lattice_quads(s, lat);
    const int mid = p.m / 2;
    const double y_mid = y0 + mid * p.L;
    const double tilt = 20 * kPi / 180;
    std::vector<Vec3> handle;
    for (int k = 1; k <= 3; ++k) handle.push_back({x0 - k * p.L * std::cos(tilt), y_mid, k * p.L * std::sin(tilt)});
    const double rb = p.r * 5 / 3;  // half a leaflet edge: the patches the branches stand on are 2 edges wide
    add_polyline(s, lat.at(0, mid), handle, std::vector<double>(3, rb));
    // Arch: a half circle from vertex (1, mid) to (n - 1, mid) (half their distance wide, at least 1.5 edges high).
    const double xa = x0 + 1 * p.L, xb = x0 + (p.n - 1) * p.L, rc = 0.5 * (xb - xa), xc = 0.5 * (xa + xb);
    std::vector<Vec3> arch;
    for (int k = 1; k <= 5; ++k) {
        const double a = kPi * (1 - k / 6.0);
        arch.push_back({xc + rc * std::cos(a), y_mid, std::max(rc, 1.5 * p.L) * std::sin(a)});
    }
    add_polyline_between(s, lat.at(1, mid), lat.at(p.n - 1, mid), arch, std::vector<double>(5, rb));
    return s;
}

}  // namespace

Skeleton make_wall_plate(const WallPlate& w, double edge_length, double radius) {
    const int n = w.plate, c = w.column < 0 ? n / 2 : w.column, j0 = w.start < 0 ? (n - w.length) / 2 : w.start;
    if (n < 2 || w.length < 1 || w.rows < 1 || c < 0 || c > n - 1 || j0 < 0 || j0 + w.length > n ||
        (w.start < 0 && j0 == 0) || w.sides < 1 || w.sides > 2 || !(edge_length > 0) || !(radius > 0))
        throw Error(ErrorCode::InvalidInput, "wall plate: the chain (column " + std::to_string(c) + ", rows " +
                                                 std::to_string(j0) + " to " + std::to_string(j0 + w.length) +
                                                 ") must lie on a grid line of the " + std::to_string(n) + " x " +
                                                 std::to_string(n) + " plate (column 0 .. plate - 1), 1 or 2 sides");
    Skeleton s;
    Lattice lat(n, n);
    const double h = 0.5 * n * edge_length;
    fill_lattice(
        s, lat,
        [&](int i, int j) {
            return Vec3{i * edge_length - h, j * edge_length - h, 0.0};
        },
        radius);
    add_lattice_quads(s, lat);
    for (int side = 0; side < w.sides; ++side) {
        const double z = side == 0 ? edge_length : -edge_length;
        Lattice wall(w.length, w.rows);  // (along the chain, up the wall)
        for (int j = 0; j <= w.length; ++j) wall.at(j, 0) = lat.at(c, j0 + j);
        fill_lattice(
            s, wall,
            [&](int j, int k) {
                return Vec3{c * edge_length - h, (j0 + j) * edge_length - h, k * z};
            },
            radius);
        add_lattice_quads(s, wall);
    }
    add_face_edges(s);
    return s;
}

namespace {

// ---------------------------------------------------------------------------------------------------------------
// Thin sheets (issue 16 item 3): sheet radius 1/3 of the default (0.1 x the edge length at radius_scale 1), sharp
// angles. The sheet radius of these shapes is p.r / 3.

// One leaflet of 2n x m quads (n across the crease on each side, m along it) folded along its middle row: the two
// halves make the angle `angle` (radians) between them (a sharp crease for small angles).
Skeleton make_fold(const Params& p) {
    Skeleton s;
    Lattice lat(2 * p.n, p.m);
    const double turn = kPi - p.angle;  // the second half turns about the crease (the y axis) by this
    fill_lattice(
        s, lat,
        [&](int i, int j) {
            const double u = (i - p.n) * p.L, y = j * p.L;
            if (u <= 0) return Vec3{u, y, 0.0};
            return Vec3{u * std::cos(turn), y, u * std::sin(turn)};
        },
        p.r / 3);
    add_lattice_quads(s, lat);
    return s;
}

// Three strips of m quads on one fan edge of n edges along z: two `angle` apart (a sharp wedge), the third opposite
// their bisector.
Skeleton make_vfan(const Params& p) {
    Params thin = p;
    thin.r = p.r / 3;
    return make_fan(thin, {0.0, p.angle, kPi + 0.5 * p.angle});
}

// A plane: one leaflet of m chord quads (along x) x 2n span quads (along y), swept back by 0.3 x the span and with a
// dihedral of 0.05; the fuselage is its middle row (y = 0) with the default radius p.r, the wings have the thin
// radius p.r / 3. A nose (3 edges, -x) and a tail boom (3 edges, +x) are rooted on the border at the middle row's
// ends (out patches).
Skeleton make_airplane(const Params& p) {
    Skeleton s;
    Lattice lat(p.m, 2 * p.n);
    for (int i = 0; i <= p.m; ++i)
        for (int j = 0; j <= 2 * p.n; ++j) {
            const double y = (j - p.n) * p.L;
            lat.at(i, j) = add_point(s, {i * p.L + 0.3 * std::abs(y), y, 0.05 * std::abs(y)}, j == p.n ? p.r : p.r / 3);
        }
    add_lattice_quads(s, lat);
    const double edge = 0.8 * p.L;
    std::vector<Vec3> nose, tail;
    std::vector<double> nose_r, tail_r;
    for (int k = 1; k <= 3; ++k) {
        nose.push_back({-k * edge, 0, 0});
        nose_r.push_back(p.r * (1 - 0.1 * k));
        tail.push_back({p.m * p.L + k * edge, 0, 0.05 * k * edge});
        tail_r.push_back(p.r * (1 - 0.15 * k));
    }
    add_polyline(s, lat.at(0, p.n), nose, nose_r);
    add_polyline(s, lat.at(p.m, p.n), tail, tail_r);
    return s;
}

// A thin plate of n x m quads (n >= 4, m >= 2) with wires of its own radius: an arch over the middle row rooted
// inside the plate one quad in from each short side, and a wire of 3 edges leaving the corner (0, 0) along its
// outward diagonal (a BL-joint).
Skeleton make_wireplate(const Params& p) {
    Skeleton s;
    const double r = p.r / 3;
    Lattice lat(p.n, p.m);
    const double x0 = -0.5 * p.n * p.L, y0 = -0.5 * p.m * p.L;
    fill_lattice(
        s, lat,
        [&](int i, int j) {
            return Vec3{x0 + i * p.L, y0 + j * p.L, 0.0};
        },
        r);
    add_lattice_quads(s, lat);
    const int mid = p.m / 2;
    const double xa = x0 + p.L, xb = x0 + (p.n - 1) * p.L, rc = 0.5 * (xb - xa), xc = 0.5 * (xa + xb);
    std::vector<Vec3> arch;
    const int pieces = 2 * (p.n - 2);  // arch edges about 0.8 L long
    for (int k = 1; k < pieces; ++k) {
        const double a = kPi * (1 - static_cast<double>(k) / pieces);
        arch.push_back({xc + rc * std::cos(a), y0 + mid * p.L, rc * std::sin(a)});
    }
    add_polyline_between(s, lat.at(1, mid), lat.at(p.n - 1, mid), arch, std::vector<double>(arch.size(), r));
    const double h = std::sqrt(0.5);
    std::vector<Vec3> wire;
    for (int k = 1; k <= 3; ++k) wire.push_back(Vec3{x0, y0, 0} + (k * 0.8 * p.L) * Vec3{-h, -h, 0});
    add_polyline(s, lat.at(0, 0), wire, std::vector<double>(3, r));
    return s;
}

// ---------------------------------------------------------------------------------------------------------------
// Random skeletons (evaluation set).

// splitmix64: a tiny deterministic generator; uniform() uses the top 53 bits, so results are the same everywhere.
class Random {
public:
    explicit Random(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform(double a, double b) { return a + (b - a) * static_cast<double>(next() >> 11) * 0x1.0p-53; }
    int integer(int a, int b) { return a + static_cast<int>(next() % static_cast<std::uint64_t>(b - a + 1)); }
    bool chance(double p) { return uniform(0, 1) < p; }
    Vec3 unit() {  // uniform on the sphere
        const double z = uniform(-1, 1), phi = uniform(0, 2 * kPi), s = std::sqrt(std::max(0.0, 1 - z * z));
        return {s * std::cos(phi), s * std::sin(phi), z};
    }

private:
    std::uint64_t state_;
};

// Any unit vector orthogonal to d.
Vec3 orthogonal_unit(const Vec3& d) {
    const Vec3 a = std::abs(d.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    return normalized(cross(d, a));
}

// d turned by `angle` towards the direction at `azimuth` around it.
Vec3 turned(const Vec3& d, double angle, double azimuth) {
    const Vec3 u = orthogonal_unit(d), v = cross(d, u);
    return normalized(std::cos(angle) * d + std::sin(angle) * (std::cos(azimuth) * u + std::sin(azimuth) * v));
}

double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
    // Sampled (segments are short and this only guards the generator): min over 9 x 9 point pairs.
    double best = distance(p0, q0);
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j)
            best = std::min(best, distance(p0 + (i / 8.0) * (p1 - p0), q0 + (j / 8.0) * (q1 - q0)));
    return best;
}

// A point at p (radius r) grown from point `from` by a new edge; parent (per point: the point it grew from, -1: none)
// follows. Returns the new point's index.
int grow_point(Skeleton& s, std::vector<int>& parent, int from, const Vec3& p, double r) {
    const int v = add_point(s, p, r);
    parent.resize(s.points.size(), -1);
    parent[v] = from;
    s.edges.push_back({from, v});
    return v;
}

struct RandomTree {
    Skeleton& s;
    Random& rng;
    double L;
    double max_turn;          // radians, per seed
    double min_radius;        // radii never below this
    std::vector<int> parent;  // per point: the point it grew from (-1: none)
    bool branched = false;    // the first branch that can branch always does (a tree has a branching point)

    // True if the segment a -> (p, rp) keeps 1.1 x the radii sum from every segment not touching a, a's parent or a
    // sibling start (children of a).
    bool clear(int a, const Vec3& p, double rp) const {
        const auto near_a = [&](int v) {
            return v == a || (a < static_cast<int>(parent.size()) && v == parent[a]) ||
                   (v < static_cast<int>(parent.size()) && parent[v] == a);
        };
        for (const std::array<int, 2>& e : s.edges) {
            if (near_a(e[0]) || near_a(e[1])) continue;
            const double need = 1.1 * (std::max(rp, s.radii[a]) + std::max(s.radii[e[0]], s.radii[e[1]]));
            if (segment_distance(s.points[a], p, s.points[e[0]], s.points[e[1]]) < need) return false;
        }
        return true;
    }

    int add(int from, const Vec3& p, double r) { return grow_point(s, parent, from, p, r); }

    // A branch from `start` leaving along `dir`, radius r at its first joint; ends in a branching point (2 or 3
    // children) while depth > 0 and the dice say so.
    void grow(int start, Vec3 dir, double r, int depth) {
        const int segments = rng.integer(2, 3);
        int cur = start;
        for (int k = 0; k < segments; ++k) {
            const double len = r * rng.uniform(2.5, 4.5);  // 1-2 resampled edges (about 2 r each)
            bool placed = false;
            for (int attempt = 0; attempt < 12 && !placed; ++attempt) {
                const Vec3 d =
                    k == 0 && attempt == 0 ? dir : turned(dir, rng.uniform(0, max_turn), rng.uniform(0, 2 * kPi));
                const Vec3 p = s.points[cur] + len * d;
                if (!clear(cur, p, r)) continue;
                cur = add(cur, p, r);
                dir = d;
                placed = true;
            }
            if (!placed) return;  // blocked: the branch ends here (an extremity)
            r = std::max(min_radius, r * rng.uniform(0.85, 1.0));
        }
        if (depth <= 0 || (branched && !rng.chance(0.75))) return;
        branched = true;
        const int children = rng.chance(0.7) ? 2 : 3;
        // Children: the first turns off by 20..70 degrees; the others at 20..40 degrees from it (close pair) or
        // 60..140 degrees (spread), around random azimuths.
        const bool close_pair = rng.chance(0.35);
        const Vec3 first = turned(dir, rng.uniform(20, 70) * kPi / 180, rng.uniform(0, 2 * kPi));
        std::vector<Vec3> dirs{first};
        for (int c = 1; c < children; ++c) {
            const double apart = (close_pair && c == 1 ? rng.uniform(20, 40) : rng.uniform(60, 140)) * kPi / 180;
            Vec3 d = turned(first, apart, rng.uniform(0, 2 * kPi));
            if (dot(d, dir) < -0.3) d = turned(first, apart, rng.uniform(0, 2 * kPi));  // avoid folding back
            dirs.push_back(d);
        }
        for (const Vec3& d : dirs) grow(cur, d, std::max(min_radius, r * rng.uniform(0.55, 1.0)), depth - 1);
    }
};

Skeleton make_random_tree(Random& rng, double L, double scale) {
    Skeleton s;
    const double r0 = L * scale * rng.uniform(0.15, 0.45);
    RandomTree t{s, rng, L, rng.uniform(20, 75) * kPi / 180, r0 / 3, {}};
    const int root = add_point(s, {0, 0, 0}, r0);
    t.parent.assign(1, -1);
    t.grow(root, rng.unit(), r0, rng.chance(0.2) ? 3 : rng.integer(1, 2));
    return s;
}

Skeleton make_random_sheet(Random& rng, double L, double scale) {
    Skeleton s;
    const int nu = rng.integer(2, 4), nv = rng.integer(2, 4);
    const double r = L * scale * rng.uniform(0.1, 0.3);
    const double bend = rng.uniform(-0.25, 0.25) * L;  // height of a sine bump across u
    const bool fold = nu >= 2 && rng.chance(0.5);
    const int fold_row = rng.integer(1, nu - 1);  // rows i > fold_row are turned about x = fold_row
    const double fold_angle = rng.uniform(0, 120) * kPi / 180;
    std::vector<Vec3> jitter(static_cast<std::size_t>((nu + 1) * (nv + 1)));
    for (Vec3& j : jitter) j = Vec3{rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), rng.uniform(-0.05, 0.05)} * L;
    Lattice lat(nu, nv);
    fill_lattice(
        s, lat,
        [&](int i, int j) {
            const double x = i * L, y = j * L;
            Vec3 p{x, y, bend * std::sin(kPi * j / nv)};
            if (fold && i > fold_row) {  // rotate about the line x = fold_row L (direction y) by fold_angle
                const double dx = x - fold_row * L;
                p = {fold_row * L + dx * std::cos(fold_angle), y, p.z + dx * std::sin(fold_angle)};
            }
            return p + jitter[static_cast<std::size_t>(i * (nv + 1) + j)];
        },
        r);
    add_lattice_quads(s, lat);
    add_face_edges(s);
    RandomTree t{s, rng, L, rng.uniform(15, 45) * kPi / 180, r / 2, std::vector<int>(s.points.size(), -1), true};
    const double rb_max = 0.5 * L * scale;
    // BL-joints at the four corners, along the outward corner diagonal (in the corner face's plane, +-15 degrees).
    const std::array<std::array<int, 4>, 4> corners{{{0, 0, 1, 1}, {nu, 0, -1, 1}, {nu, nv, -1, -1}, {0, nv, 1, -1}}};
    for (const std::array<int, 4>& c : corners) {
        if (!rng.chance(0.4)) continue;
        const int v = lat.at(c[0], c[1]);
        const Vec3 out = normalized((s.points[v] - s.points[lat.at(c[0] + c[2], c[1])]) +
                                    (s.points[v] - s.points[lat.at(c[0], c[1] + c[3])]));
        const Vec3 d = turned(out, rng.uniform(0, 15) * kPi / 180, rng.uniform(0, 2 * kPi));
        t.grow(v, d, std::min(rb_max, r * rng.uniform(1.0, 1.5)), rng.integer(0, 1));
    }
    // A branch rooted inside the leaflet (4 faces meet at every interior lattice vertex), off the fold row.
    if (rng.chance(0.5)) {
        const int i = rng.integer(1, nu - 1), j = rng.integer(1, nv - 1);
        if (!(fold && i == fold_row)) {
            const int v = lat.at(i, j);
            Vec3 n = normalized(cross(s.points[lat.at(i + 1, j)] - s.points[lat.at(i - 1, j)],
                                      s.points[lat.at(i, j + 1)] - s.points[lat.at(i, j - 1)]));
            if (rng.chance(0.5)) n = -n;
            const Vec3 d = turned(n, rng.uniform(0, 30) * kPi / 180, rng.uniform(0, 2 * kPi));
            t.grow(v, d, std::min(rb_max, r * rng.uniform(1.2, 1.7)), 0);
        }
    }
    return s;
}

// The character family: a torso bridge bulging between two branching points, 2-4 limbs leaving each end (ranges in
// generators.h, generate_character_skeleton).
struct Character {
    Skeleton& s;
    Random& rng;
    int torso_edges = 0;      // s.edges[0 .. torso_edges) are the torso's
    double max_turn = 0;      // radians, per seed
    double min_radius = 0;    // limb radii never below this
    std::vector<int> parent;  // per point: the point it grew from (-1: none)

    // True if the segment a -> (p, rp) keeps 1.1 x the radii sum from every segment not touching a, a's parent or a
    // child of a, and (first limb segment, from a torso end) from every non-torso segment only.
    bool clear(int a, const Vec3& p, double rp, bool skip_torso) const {
        for (std::size_t e = 0; e < s.edges.size(); ++e) {
            if (skip_torso && static_cast<int>(e) < torso_edges) continue;
            const std::array<int, 2>& ed = s.edges[e];
            const bool near = ed[0] == a || ed[1] == a || ed[0] == parent[a] || ed[1] == parent[a] ||
                              parent[ed[0]] == a || parent[ed[1]] == a;
            if (near) continue;
            const double need = 1.1 * (std::max(rp, s.radii[a]) + std::max(s.radii[ed[0]], s.radii[ed[1]]));
            if (segment_distance(s.points[a], p, s.points[ed[0]], s.points[ed[1]]) < need) return false;
        }
        return true;
    }

    int add(int from, const Vec3& p, double r) { return grow_point(s, parent, from, p, r); }

    // A limb from the torso end `end` along `dir`: 2-4 segments of 2.5..4.5 x the current radius, radius r at its
    // first joint, x 0.6..0.9 per further joint. The first segment is always placed (the end's degree is fixed);
    // a later one blocked after 12 draws ends the limb.
    void limb(int end, Vec3 dir, double r) {
        const int segments = rng.integer(2, 4);
        int cur = end;
        for (int k = 0; k < segments; ++k) {
            const double len = r * rng.uniform(2.5, 4.5);
            Vec3 chosen = dir;
            bool placed = false;
            for (int attempt = 0; attempt < 12 && !placed; ++attempt) {
                const Vec3 d =
                    attempt == 0 && k == 0 ? dir : turned(dir, rng.uniform(0, max_turn), rng.uniform(0, 2 * kPi));
                if (attempt == 0) chosen = d;
                if (!clear(cur, s.points[cur] + len * d, r, k == 0)) continue;
                chosen = d;
                placed = true;
            }
            if (!placed && k > 0) return;
            cur = add(cur, s.points[cur] + len * chosen, r);
            dir = chosen;
            r = std::max(min_radius, r * rng.uniform(0.6, 0.9));
        }
    }

    // 2-4 limbs at `end`, leaving 20..80 degrees off the torso's outward direction `out`, azimuths spread over a
    // fraction 0.35..1 of the full turn, at least 30 degrees apart (else redrawn, up to 12 times, then spread
    // evenly at 60 degrees off `out`); first-joint radius 0.6..1.1 x the end's radius.
    void limbs(int end, const Vec3& out) {
        const int count = rng.integer(2, 4);
        const double phi0 = rng.uniform(0, 2 * kPi), spread = rng.uniform(0.35, 1.0);
        std::vector<Vec3> dirs;
        for (int i = 0; i < count; ++i) {
            Vec3 d{};
            bool ok = false;
            for (int attempt = 0; attempt < 12 && !ok; ++attempt) {
                const double phi = phi0 + i * spread * 2 * kPi / count + rng.uniform(-0.3, 0.3);
                d = turned(out, rng.uniform(20, 80) * kPi / 180, phi);
                ok = std::all_of(dirs.begin(), dirs.end(),
                                 [&](const Vec3& e) { return dot(d, e) <= std::cos(30 * kPi / 180); });
            }
            if (!ok) d = turned(out, 60 * kPi / 180, phi0 + i * 2 * kPi / count);
            dirs.push_back(d);
        }
        for (const Vec3& d : dirs) limb(end, d, s.radii[end] * rng.uniform(0.6, 1.1));
    }
};

// Torso radius at parameter t in [0, 1]: the end radii interpolated, raised to the peak r_p at t_p by a sine bump
// (never above r_p).
double torso_radius(double t, double ra, double rb, double rp, double tp) {
    const double base = ra + t * (rb - ra), base_p = ra + tp * (rb - ra);
    const double f = t <= tp ? std::sin(0.5 * kPi * t / tp) : std::sin(0.5 * kPi * (1 - t) / (1 - tp));
    return std::min(rp, base + (rp - base_p) * f);
}

Skeleton make_random_character(Random& rng, double L, double scale) {
    Skeleton s;
    const double ra = L * scale * rng.uniform(0.12, 0.25), rb = ra * rng.uniform(0.7, 1.4);
    const double rp = rng.uniform(1.5, 2.5) * std::max(ra, rb);
    const double length = rp * rng.uniform(1.6, 3.0);
    const int inner = rng.integer(1, 3), peak = rng.integer(0, inner - 1);
    const double tp = rng.uniform(0.35, 0.65);
    const double arch = rng.uniform(-0.15, 0.15) * length;
    const Vec3 axis = rng.unit(), bend = turned(axis, 0.5 * kPi, rng.uniform(0, 2 * kPi));  // bend is orthogonal
    Character c{s, rng, 0, rng.uniform(15, 45) * kPi / 180, std::min(ra, rb) / 4, {}};
    const auto at = [&](double t) { return length * t * axis + arch * std::sin(kPi * t) * bend; };
    std::vector<double> ts{0};
    for (int i = 0; i < inner; ++i)
        ts.push_back(i < peak    ? tp * (i + 1) / (peak + 1)
                     : i == peak ? tp
                                 : tp + (1 - tp) * (i - peak) / static_cast<double>(inner - peak));
    ts.push_back(1);
    int cur = add_point(s, at(0), ra);
    c.parent.assign(1, -1);
    for (std::size_t k = 1; k < ts.size(); ++k)
        cur = c.add(cur, at(ts[k]), k + 1 == ts.size() ? rb : torso_radius(ts[k], ra, rb, rp, tp));
    c.torso_edges = static_cast<int>(s.edges.size());
    const int a = 0, b = cur;
    c.limbs(a, normalized(s.points[a] - s.points[1]));
    c.limbs(b, normalized(s.points[b] - s.points[c.parent[b]]));
    return s;
}

// The twin-junction family: two branching points whose balls overlap, joined by a straight bridge, each with a pair
// of fat legs leaving across the bridge and bending back, and sometimes a tail (ranges in generators.h,
// generate_twin_junction_skeleton).

// Whether the outer half of the segment a -> (p, rp) keeps 1.1 x the radii sum from every segment that is not the
// bridge's and touches neither a junction (A or B: the bridge and every limb's first segment lie in the overlapping
// balls by design), nor a, a's parent or a child of a.
bool twin_clear(const Character& c, int a, const Vec3& p, double rp, int ja, int jb) {
    const Vec3 q = 0.5 * (c.s.points[a] + p);
    for (std::size_t e = static_cast<std::size_t>(c.torso_edges); e < c.s.edges.size(); ++e) {
        const std::array<int, 2>& ed = c.s.edges[e];
        const auto near = [&](int v) { return v == ja || v == jb || v == a || v == c.parent[a] || c.parent[v] == a; };
        if (near(ed[0]) || near(ed[1])) continue;
        const double need = 1.1 * (std::max(rp, c.s.radii[a]) + std::max(c.s.radii[ed[0]], c.s.radii[ed[1]]));
        if (segment_distance(q, p, c.s.points[ed[0]], c.s.points[ed[1]]) < need) return false;
    }
    return true;
}

// A leg from `end` (the other junction: `other`): 2-3 segments, radius r at its first joint (x 0.7..0.9 per further
// joint). Segment k leaves in the plane of `across` and `out`, leaning from `across` towards `out` by lean0 + k /
// (segments - 1) x bend (radians). The first segment (0.8..1.5 x r long, from inside the junction's ball) is placed
// as planned; a later one (2.5..4 x r) blocked (twin_clear) is redrawn leaning 7.5 degrees further back each time
// (turned by up to 15 degrees about that), and after 12 draws ends the leg.
void twin_leg(Character& c, int end, int other, const Vec3& across, const Vec3& out, double r, double lean0,
              double bend) {
    const int segments = c.rng.integer(2, 3);
    int cur = end;
    for (int k = 0; k < segments; ++k) {
        const double lean = lean0 + bend * k / (segments - 1);
        const Vec3 base = normalized(std::cos(lean) * across + std::sin(lean) * out);
        const double len = r * (k == 0 ? c.rng.uniform(0.8, 1.5) : c.rng.uniform(2.5, 4.0));
        bool placed = k == 0;
        Vec3 chosen = base;
        for (int attempt = 0; attempt < 12 && !placed; ++attempt) {
            const double back = lean + attempt * 7.5 * kPi / 180;
            chosen = normalized(std::cos(back) * across + std::sin(back) * out);
            if (attempt > 0) chosen = turned(chosen, c.rng.uniform(0, 15) * kPi / 180, c.rng.uniform(0, 2 * kPi));
            placed = twin_clear(c, cur, c.s.points[cur] + len * chosen, r, end, other);
        }
        if (!placed) return;
        cur = c.add(cur, c.s.points[cur] + len * chosen, r);
        r = std::max(c.min_radius, r * c.rng.uniform(0.7, 0.9));
    }
}

// The legs (and, with probability tail_chance, a tail) of one end: legs at azimuths psi and psi + 180 +- 35 degrees
// around the bridge axis (u1, u2 span the plane across it), leaning towards `out` by -5..20 degrees at the root and
// bending back by 25..50 degrees more (probability 0.7) or 0..10; first-joint radius 0.8..1.0 x the end's. The tail
// leaves within 30 degrees of `out`, first-joint radius 0.6..0.9 x the end's (Character::limb).
void twin_end(Character& c, int end, int other, const Vec3& out, const Vec3& u1, const Vec3& u2, double psi,
              double tail_chance) {
    const double rx = c.s.radii[end];
    const std::array<double, 2> azimuths{psi, psi + kPi + c.rng.uniform(-35, 35) * kPi / 180};
    for (const double phi : azimuths) {
        const Vec3 across = std::cos(phi) * u1 + std::sin(phi) * u2;
        const double lean0 = c.rng.uniform(-5, 20) * kPi / 180;
        const double bend = (c.rng.chance(0.7) ? c.rng.uniform(25, 50) : c.rng.uniform(0, 10)) * kPi / 180;
        twin_leg(c, end, other, across, out, rx * c.rng.uniform(0.8, 1.0), lean0, bend);
    }
    if (c.rng.chance(tail_chance))
        c.limb(end, turned(out, c.rng.uniform(0, 30) * kPi / 180, c.rng.uniform(0, 2 * kPi)),
               rx * c.rng.uniform(0.6, 0.9));
}

Skeleton make_random_twin_junction(Random& rng, double L, double scale) {
    Skeleton s;
    const double ra = L * scale * rng.uniform(0.2, 0.35), rb = ra * rng.uniform(0.55, 0.9);
    const double length = (ra + rb) * rng.uniform(0.7, 0.95);  // (r_A + r_B) / |AB| in [1.05, 1.43]
    const int inner = rng.integer(0, 2);
    const Vec3 axis = rng.unit(), u1 = turned(axis, 0.5 * kPi, rng.uniform(0, 2 * kPi)), u2 = cross(axis, u1);
    Character c{s, rng, 0, rng.uniform(15, 40) * kPi / 180, rb / 4, {}};
    int cur = add_point(s, {0, 0, 0}, ra);
    c.parent.assign(1, -1);
    for (int k = 1; k <= inner + 1; ++k) {
        const double t = static_cast<double>(k) / (inner + 1);
        cur = c.add(cur, length * t * axis, ra + t * (rb - ra));
    }
    c.torso_edges = static_cast<int>(s.edges.size());
    const double psi = rng.uniform(0, 2 * kPi);
    twin_end(c, 0, cur, -axis, u1, u2, psi, 0.6);
    twin_end(c, cur, 0, axis, u1, u2, psi + rng.uniform(-30, 30) * kPi / 180, 0.5);
    return s;
}

struct Shape {
    const char* name;
    std::array<int, 2> default_nm;
    std::array<int, 2> min_nm;
    const char* help;
    std::function<Skeleton(const Params&)> make;
};

// The fan-block shapes (issue 22 item 3, design note D2), after the thin sheets.
std::vector<Shape> fan_block_shapes() {
    return {
        {"fanblock",
         {3, 3},
         {3, 1},
         "T (n = 3, default) or X (n = 4) of 2-quad strips on a fan line of m edges (default 3), each strip 4 to 9 "
         "degrees off the right angles and turning by up to 3 degrees per fan edge (a fan block with --fan-blocks)",
         make_fan_block},
        {"yfan",
         {3, 3},
         {1, 1},
         "Y: three 2-quad strips 120 degrees apart on a fan line of m edges (default 3; never a fan block); n unused",
         make_y_fan},
    };
}

// The thin-sheet shapes (issue 16 item 3), last in the table.
std::vector<Shape> thin_sheet_shapes() {
    return {
        {"fold",
         {3, 3},
         {1, 1},
         "thin leaflet (radius 0.1 x edge) of 2n x m quads (default n 3, m 3) folded along its middle row so that "
         "its halves meet at --angle degrees (default 45)",
         make_fold},
        {"vfan",
         {2, 2},
         {1, 1},
         "thin strips (radius 0.1 x edge) of m quads on a fan edge of n edges (default 2, 2): two --angle degrees "
         "apart (default 45), the third opposite",
         make_vfan},
        {"airplane",
         {4, 3},
         {1, 1},
         "one swept leaflet of m chord x 2n span quads (default 3 x 8): fuselage row of radius 0.3 x edge, thin wings "
         "(0.1 x edge), nose and tail booms rooted on its border",
         make_airplane},
        {"wireplate",
         {5, 3},
         {4, 2},
         "thin plate (radius 0.1 x edge) of n x m quads (default 5 x 3) with wires of its radius: an arch rooted "
         "inside, one wire from a corner",
         make_wireplate},
    };
}

// The walls on a plate (docked_walls.h, issue 22 item 1) and the flanges (a fan chain on part of a plate's border),
// after the turbine.
std::vector<Shape> wall_shapes() {
    return {
        {"wall",
         {6, 2},
         {2, 1},
         "plate of n x n quads (default 6) with a wall of m rows (default 2) standing on a chain of 2 fan edges "
         "that ends inside the plate at both ends (docked on the plates)",
         [](const Params& p) {
             return make_wall_plate({p.n, 2, p.m, -1, -1, 1}, p.L, p.r);
         }},
        {"wallboth",
         {6, 2},
         {2, 1},
         "as wall, with a second wall of m rows below the plate on the same chain (fan edges of degree 4)",
         [](const Params& p) {
             return make_wall_plate({p.n, 2, p.m, -1, -1, 2}, p.L, p.r);
         }},
        {"walledge",
         {6, 2},
         {2, 1},
         "as wall, the chain of 2 fan edges running from the plate's border to an interior vertex",
         [](const Params& p) {
             return make_wall_plate({p.n, 2, p.m, -1, 0, 1}, p.L, p.r);
         }},
        {"walledgeboth",
         {6, 2},
         {2, 1},
         "as walledge, with a second wall of m rows below the plate on the same chain (fan edges of degree 4)",
         [](const Params& p) {
             return make_wall_plate({p.n, 2, p.m, -1, 0, 2}, p.L, p.r);
         }},
        {"flange",
         {6, 2},
         {2, 1},
         "plate of n x n quads (default 6) with walls of m rows (default 2) above and below on a chain of 2 fan "
         "edges along the middle of one border side (a flange: fan ends where the plate's border runs on)",
         [](const Params& p) {
             return make_wall_plate({p.n, 2, p.m, 0, -1, 2}, p.L, p.r);
         }},
        {"flangeup",
         {6, 2},
         {2, 1},
         "as flange, with the wall above the plate only",
         [](const Params& p) {
             return make_wall_plate({p.n, 2, p.m, 0, -1, 1}, p.L, p.r);
         }},
        {"flangecorner",
         {4, 2},
         {2, 1},
         "plate of n x n quads (default 4) with walls of m rows (default 2) above and below on a chain of 2 fan "
         "edges along one border side from the plate's corner (a flange with a corner cube at that end)",
         [](const Params& p) {
             return make_wall_plate({p.n, 2, p.m, 0, 0, 2}, p.L, p.r);
         }},
        {"flangecornerup",
         {4, 2},
         {2, 1},
         "as flangecorner, with the wall above the plate only",
         [](const Params& p) {
             return make_wall_plate({p.n, 2, p.m, 0, 0, 1}, p.L, p.r);
         }},
    };
}

const std::vector<Shape>& shapes() {
    static const std::vector<Shape> table = [] {
        std::vector<Shape> t{
            {"plate", {3, 3}, {1, 1}, "flat leaflet of n x m quads (default 3 x 3)", make_plate},
            {"box", {2, 1}, {1, 1}, "closed cube surface, n x n quads per side (default 2); m unused", make_box},
            {"torus",
             {24, 8},
             {7, 3},
             "hollow torus surface, n quads around the axis x m around the tube "
             "(default 24 x 8, n >= m + 4)",
             make_torus},
            {"tfan",
             {2, 2},
             {1, 1},
             "T: three strips of m quads on one fan edge of n edges (default n 2, m 2)",
             [](const Params& p) {
                 return make_fan(p, {0.0, 0.5 * kPi, kPi});
             }},
            {"xfan",
             {2, 2},
             {1, 1},
             "X: four strips of m quads on one fan edge of n edges (default n 2, m 2)",
             [](const Params& p) {
                 return make_fan(p, {0.0, 0.5 * kPi, kPi, 1.5 * kPi});
             }},
            {"fanend",
             {3, 1},
             {3, 1},
             "T (n = 3, default) or X (n = 4) fan of 2 x 2-quad strips with a 3-edge branch on a fan-edge end, "
             "continuing the fan line (m = 1, default: meshed after the skeleton repair retracts the fan edge from the "
             "branch), perpendicular to it (m = 2: meshed after the repair moves the branch's root onto a leaflet "
             "border), continuing it at both ends (m = 3: the chain is cut into 4 fan edges, then retracted at both "
             "ends), perpendicular at the upper end and continuing at the lower (m = 4), or leaning back 135 degrees "
             "(m = 5: the root moved, its first edge bent onto the leaflet's normal)",
             make_fan_end},
            {"hand",
             {3, 4},
             {1, 2},
             "palm leaflet (8 x m quads, default m 4) with four fingers and a thumb of n edges "
             "(default 3) at convex 90-degree border vertices (BL-joints)",
             make_hand},
            {"chair",
             {4, 4},
             {2, 1},
             "seat (n x n quads, default 4) and back meeting at a degree-3 fan edge, four legs "
             "of m edges (default 4) from the seat corners",
             make_chair},
            {"bird",
             {4, 2},
             {1, 1},
             "two wings (n span x m chord quads, default 4 x 2) touching the body's branching "
             "point by a corner, neck and body branches, a 2 x 2 tail leaflet (BL-joint)",
             make_bird},
            {"twist",
             {12, 2},
             {1, 1},
             "open strip of n x m quads (default 12 x 2) whose section turns by "
             "quarter-turns x 90 degrees (default 2 = 180)",
             make_twist},
            {"torustwist",
             {24, 1},
             {4, 1},
             "ring of n segments with an X section (arms of m quads, default 24 x 1) "
             "turning by quarter-turns x 90 degrees (default 2: two intersecting "
             "Moebius strips); the core is a closed degree-4 fan edge, so every leaflet "
             "is an orientable annulus",
             make_torustwist},
            {"dualocta",
             {2, 1},
             {1, 1},
             "curve frame: octahedron + dual cube edges crossing at their midpoints, n "
             "edges per half-edge (default 2); m unused",
             make_dualocta},
            {"cubestar",
             {3, 2},
             {3, 1},
             "branching point whose n branches (3 to 6, default 3) leave along cube face "
             "normals (3: x, y, z; 4: +-x, +-y; 5: and +z; 6: +-x, +-y, +-z), m edges each "
             "(default 2): one compatible block",
             make_cubestar},
            {"ystar",
             {1, 2},
             {1, 1},
             "planar Y: three branches of m edges (default 2) at 120 degrees (never a compatible "
             "block); n unused",
             [](const Params& p) {
                 return make_star(p, {{1, 0, 0}, {-0.5, 0.5 * std::sqrt(3.0), 0}, {-0.5, -0.5 * std::sqrt(3.0), 0}});
             }},
            {"tetrastar",
             {1, 2},
             {1, 1},
             "tetrahedral star: four branches of m edges (default 2) to the corners of a "
             "regular tetrahedron (never a compatible block); n unused",
             [](const Params& p) {
                 return make_star(p, {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}});
             }},
            {"turbine",
             {8, 2},
             {2, 2},
             "Darrieus turbine: shaft branch, m blades (2 or 3, default 2) of n quads "
             "(default 8) touching the shaft at two branching points by their corners",
             make_turbine},
        };
        for (Shape& shape : wall_shapes()) t.push_back(std::move(shape));
        t.push_back({"pan",
                     {6, 4},
                     {6, 2},
                     "plate of n x m quads (default 6 x 4) with its branches rooted on its plates: a "
                     "handle leaving a straight border outward, a bucket arch rooted inside",
                     make_pan});
        for (Shape& shape : thin_sheet_shapes()) t.push_back(std::move(shape));
        for (Shape& shape : fan_block_shapes()) t.push_back(std::move(shape));
        return t;
    }();
    return table;
}

const Shape& find_shape(const std::string& name) {
    for (const Shape& shape : shapes())
        if (name == shape.name) return shape;
    std::string valid;
    for (const Shape& shape : shapes()) valid += (valid.empty() ? "" : ", ") + std::string(shape.name);
    throw Error(ErrorCode::InvalidInput, "unknown skeleton generator '" + name + "' (valid names: " + valid + ")");
}

}  // namespace

std::vector<std::string> generator_names() {
    std::vector<std::string> names;
    for (const Shape& shape : shapes()) names.emplace_back(shape.name);
    return names;
}

std::string generator_help(const std::string& name) { return find_shape(name).help; }

Skeleton generate_skeleton(const std::string& name, const GeneratorOptions& options) {
    const Shape& shape = find_shape(name);
    Skeleton s = shape.make(make_params(name, options, shape.default_nm, shape.min_nm));
    add_face_edges(s);
    return s;
}

Skeleton generate_character_skeleton(std::uint64_t seed, const GeneratorOptions& options) {
    const Params p = make_params("--random --family character", options, {1, 1}, {1, 1});
    Random rng(seed);
    Skeleton s = make_random_character(rng, p.L, options.radius_scale);
    add_face_edges(s);
    return s;
}

Skeleton generate_twin_junction_skeleton(std::uint64_t seed, const GeneratorOptions& options) {
    const Params p = make_params("--random --family twinjunction", options, {1, 1}, {1, 1});
    Random rng(seed);
    Skeleton s = make_random_twin_junction(rng, p.L, options.radius_scale);
    add_face_edges(s);
    return s;
}

const char* random_skeleton_kind(std::uint64_t seed) { return seed % 5 == 0 || seed % 5 == 3 ? "sheet" : "tree"; }

Skeleton generate_random_skeleton(std::uint64_t seed, const GeneratorOptions& options) {
    const Params p = make_params("--random", options, {1, 1}, {1, 1});
    Random rng(seed);
    Skeleton s = std::string(random_skeleton_kind(seed)) == "sheet" ? make_random_sheet(rng, p.L, options.radius_scale)
                                                                    : make_random_tree(rng, p.L, options.radius_scale);
    add_face_edges(s);
    return s;
}

}  // namespace mesohex
