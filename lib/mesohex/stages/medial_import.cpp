#include "mesohex/stages/medial_import.h"
#include "mesohex/core/union_find.h"
#include "mesohex/stages/skeleton_analysis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <queue>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include "mesohex/core/error.h"

namespace mesohex {
namespace {

Error bad(const std::string& what, ElementRef where = {}) {
    return Error(ErrorCode::InvalidInput, "medial import: " + what, where);
}

ElementRef vertex_ref(int v) { return {ElementRef::Kind::SkeletonVertex, v}; }
ElementRef edge_ref(int e) { return {ElementRef::Kind::SkeletonEdge, e}; }
ElementRef face_ref(int f) { return {ElementRef::Kind::SkeletonFace, f}; }

// Angle at p between the directions to a and b, in degrees (0 for a degenerate side).
double angle_deg(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 u = normalized(a - p), w = normalized(b - p);
    if (squared_norm(u) == 0 || squared_norm(w) == 0) return 0;
    return std::acos(std::clamp(dot(u, w), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// True if the cyclic triangle t traverses a -> b.
bool has_directed(const std::array<int, 3>& t, int a, int b) {
    for (int i = 0; i < 3; ++i)
        if (t[i] == a && t[(i + 1) % 3] == b) return true;
    return false;
}

int third_vertex(const std::array<int, 3>& t, int a, int b) {
    for (int x : t)
        if (x != a && x != b) return x;
    return -1;
}

// (min, max) of an edge's ends, by value (std::minmax returns references).
std::pair<int, int> side_key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// Angle at the axis a-b between the half-planes towards c and d, in degrees (0..180).
double wing_angle_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const Vec3 axis = normalized(b - a);
    Vec3 u = c - a, w = d - a;
    u = normalized(u - axis * dot(u, axis));
    w = normalized(w - axis * dot(w, axis));
    if (squared_norm(u) == 0 || squared_norm(w) == 0) return 0;
    return std::acos(std::clamp(dot(u, w), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// Per triangle side (sorted vertex pair): the triangles that have it, ascending.
std::map<std::pair<int, int>, std::vector<int>> triangles_by_side(const Skeleton& m) {
    std::map<std::pair<int, int>, std::vector<int>> side_tris;
    for (size_t t = 0; t < m.faces.size(); ++t)
        for (size_t i = 0; i < 3; ++i)
            side_tris[side_key(m.faces[t][i], m.faces[t][(i + 1) % 3])].push_back(static_cast<int>(t));
    return side_tris;
}

// One step of fan resolution on a validated medial mesh (triangle sides all in m.edges). An edge in three or more
// triangles is an IRREGULAR fan when two of its triangles belong to the same leaflet (components through edges in
// exactly two triangles): the mesher needs the leaflets around a fan edge to be distinct (hand.ma's palm/wrist
// junction is one leaflet folding onto itself). Such a fan loses one triangle whose removal keeps the Euler
// characteristic and the connectivity: a triangle with exactly one side in no other triangle (removed with that
// side), or with both other sides free and its third vertex in nothing else (removed with both sides and the
// vertex). Among the candidates, the one leaving the flattest fan (largest angle between the remaining wings) goes,
// ties to the lower triangle index. Returns false when no irregular fan has a removable triangle.
bool remove_irregular_fan_triangle(Skeleton& m) {
    const int nv = static_cast<int>(m.points.size());
    const int nt = static_cast<int>(m.faces.size());
    std::map<std::pair<int, int>, std::vector<int>> side_tris = triangles_by_side(m);
    UnionFind leaf(nt);
    for (const auto& [side, tris] : side_tris)
        if (tris.size() == 2) leaf.unite(tris[0], tris[1]);
    std::vector<int> vertex_uses(static_cast<size_t>(nv), 0);  // triangles + curve edges at each vertex
    for (const std::vector<int>& f : m.faces)
        for (int x : f) ++vertex_uses[static_cast<size_t>(x)];
    for (const std::array<int, 2>& e : m.edges)
        if (side_tris.find(side_key(e[0], e[1])) == side_tris.end())
            for (int x : e) ++vertex_uses[static_cast<size_t>(x)];
    struct Removal {
        double score = -1;
        int tri = -1, drop_vertex = -1;
        std::vector<std::pair<int, int>> drop_sides;
    } best;
    for (const auto& [side, tris] : side_tris) {
        if (tris.size() < 3) continue;
        std::vector<int> roots;
        for (int t : tris) roots.push_back(leaf.find(t));
        std::sort(roots.begin(), roots.end());
        if (std::adjacent_find(roots.begin(), roots.end()) == roots.end()) continue;  // regular: distinct leaflets
        const int a = side.first, b = side.second;  // plain variables: clang 14 cannot capture structured bindings
        for (int t : tris) {
            const int o = third_vertex({m.faces[static_cast<size_t>(t)][0], m.faces[static_cast<size_t>(t)][1],
                                        m.faces[static_cast<size_t>(t)][2]},
                                       a, b);
            std::vector<std::pair<int, int>> free_sides;
            for (const std::pair<int, int>& other : {side_key(a, o), side_key(b, o)})
                if (side_tris[other].size() == 1) free_sides.push_back(other);
            Removal r;
            r.tri = t;
            r.drop_sides = free_sides;
            if (free_sides.size() == 2) {
                if (vertex_uses[static_cast<size_t>(o)] != 1) continue;  // o would be left behind, disconnected
                r.drop_vertex = o;
            } else if (free_sides.size() != 1) {
                continue;  // removing it would open a hole
            }
            for (size_t i = 0; i < tris.size(); ++i)
                for (size_t j = i + 1; j < tris.size(); ++j) {
                    if (tris[i] == t || tris[j] == t) continue;
                    auto opp = [&](int u) {
                        const std::vector<int>& f = m.faces[static_cast<size_t>(u)];
                        return m.points[static_cast<size_t>(third_vertex({f[0], f[1], f[2]}, a, b))];
                    };
                    r.score =
                        std::max(r.score, wing_angle_deg(m.points[static_cast<size_t>(a)],
                                                         m.points[static_cast<size_t>(b)], opp(tris[i]), opp(tris[j])));
                }
            if (r.score > best.score || (r.score == best.score && best.tri >= 0 && r.tri < best.tri)) best = r;
        }
    }
    if (best.tri < 0) return false;
    m.faces.erase(m.faces.begin() + best.tri);
    std::erase_if(m.edges, [&](const std::array<int, 2>& e) {
        return std::find(best.drop_sides.begin(), best.drop_sides.end(), side_key(e[0], e[1])) != best.drop_sides.end();
    });
    if (best.drop_vertex >= 0) {
        const int d = best.drop_vertex;
        m.points.erase(m.points.begin() + d);
        m.radii.erase(m.radii.begin() + d);
        for (std::array<int, 2>& e : m.edges)
            for (int& x : e) x -= x > d ? 1 : 0;
        for (std::vector<int>& f : m.faces)
            for (int& x : f) x -= x > d ? 1 : 0;
    }
    return true;
}

// One pinch of a medial mesh closed (see MedialImportOptions::fill_pinch_max_angle_deg): a vertex v with no curve
// edge, no side in three or more triangles and four border sides (in one triangle each), two of them in each of two
// components through manifold sides (two leaflets touching at v, not one touching itself, so the joined leaflet
// stays orientable). The narrowest pair of border sides (v, a), (v, b) of different components, if their angle is
// below max_angle_deg and a-b is no edge yet, gets the triangle (v, a, b) and the edge a-b: V same, E + 1, F + 1
// (Euler characteristic kept), one leaflet through v instead of two touching at it. The first such vertex by index;
// returns false when there is none.
bool fill_pinch_gap(Skeleton& m, double max_angle_deg) {
    const int nt = static_cast<int>(m.faces.size());
    const std::map<std::pair<int, int>, std::vector<int>> side_tris = triangles_by_side(m);
    UnionFind comp(nt);
    for (const auto& [side, tris] : side_tris)
        if (tris.size() == 2) comp.unite(tris[0], tris[1]);
    std::set<std::pair<int, int>> edges;
    std::vector<char> curve_end(m.points.size(), 0);
    for (const std::array<int, 2>& e : m.edges) {
        edges.insert(side_key(e[0], e[1]));
        if (side_tris.find(side_key(e[0], e[1])) == side_tris.end()) curve_end[e[0]] = curve_end[e[1]] = 1;
    }
    std::vector<std::vector<std::pair<int, int>>> sides_at(m.points.size());  // (other end, triangles on the side)
    for (const auto& [side, tris] : side_tris) {
        sides_at[side.first].push_back({side.second, static_cast<int>(tris.size())});
        sides_at[side.second].push_back({side.first, static_cast<int>(tris.size())});
    }
    for (int v = 0; v < static_cast<int>(m.points.size()); ++v) {
        if (curve_end[v]) continue;
        std::vector<int> border;  // border neighbours of v
        bool regular = true;
        for (const auto& [w, n] : sides_at[v]) {
            if (n == 1) border.push_back(w);
            regular = regular && n <= 2;
        }
        if (!regular || border.size() != 4) continue;
        std::array<int, 4> root{};  // the component of each border side's triangle
        for (size_t i = 0; i < 4; ++i) root[i] = comp.find(side_tris.at(side_key(v, border[i]))[0]);
        std::array<int, 4> sorted = root;
        std::sort(sorted.begin(), sorted.end());
        if (sorted[0] != sorted[1] || sorted[2] != sorted[3] || sorted[1] == sorted[2]) continue;  // not 2 + 2
        const Vec3& p = m.points[v];
        double best = max_angle_deg;
        std::array<int, 2> pair{-1, -1};
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) {
                const double angle = angle_deg(p, m.points[border[i]], m.points[border[j]]);
                if (root[i] != root[j] && angle < best && !edges.contains(side_key(border[i], border[j]))) {
                    best = angle;
                    pair = {border[i], border[j]};
                }
            }
        if (pair[0] < 0) continue;
        m.faces.push_back({v, pair[0], pair[1]});
        m.edges.push_back({pair[0], pair[1]});
        return true;
    }
    return false;
}

// The leaflet border around each vertex of a quad skeleton, for the BL-joint corners: curve neighbours, leaflet
// neighbours, border neighbours (-1 for a fan edge), oriented face-normal sums and face-angle sums (degrees).
struct JoinStars {
    std::vector<std::vector<int>> curve, leaflet, border;
    std::vector<Vec3> normal_sum;
    std::vector<double> angle_sum;
};

JoinStars join_stars(const Skeleton& s) {
    const size_t nv = s.points.size();
    JoinStars st{std::vector<std::vector<int>>(nv), std::vector<std::vector<int>>(nv),
                 std::vector<std::vector<int>>(nv), std::vector<Vec3>(nv), std::vector<double>(nv, 0.0)};
    std::map<std::pair<int, int>, int> side_faces;
    for (const std::vector<int>& f : s.faces)
        for (size_t i = 0; i < f.size(); ++i) ++side_faces[side_key(f[i], f[(i + 1) % f.size()])];
    for (const std::array<int, 2>& e : s.edges) {
        const auto it = side_faces.find(side_key(e[0], e[1]));
        for (int k = 0; k < 2; ++k) {
            const size_t x = static_cast<size_t>(e[k]);
            if (it == side_faces.end()) {
                st.curve[x].push_back(e[1 - k]);
                continue;
            }
            st.leaflet[x].push_back(e[1 - k]);
            if (it->second == 1) st.border[x].push_back(e[1 - k]);
            if (it->second >= 3) st.border[x].push_back(-1);  // fan: not a BL-joint
        }
    }
    for (const std::vector<int>& f : s.faces) {
        Vec3 n{};  // Newell
        for (size_t i = 0; i < f.size(); ++i)
            n += cross(s.points[static_cast<size_t>(f[i])], s.points[static_cast<size_t>(f[(i + 1) % f.size()])]);
        for (int w : f) st.normal_sum[static_cast<size_t>(w)] += n;
    }
    st.angle_sum = face_angle_sums(s.points, s.faces);
    return st;
}

// Length of the curve that leaves v towards its curve neighbour u: curve edges followed through vertices with
// exactly two curve edges and no leaflet edge, up to the next other vertex (or back to v on a loop).
double curve_length(const std::vector<Vec3>& points, const JoinStars& st, int v, int u) {
    double length = distance(points[static_cast<size_t>(v)], points[static_cast<size_t>(u)]);
    int prev = v, cur = u;
    while (cur != v && st.curve[static_cast<size_t>(cur)].size() == 2 && st.leaflet[static_cast<size_t>(cur)].empty()) {
        const std::vector<int>& c = st.curve[static_cast<size_t>(cur)];
        const int next = c[0] == prev ? c[1] : c[0];
        length += distance(points[static_cast<size_t>(cur)], points[static_cast<size_t>(next)]);
        prev = cur;
        cur = next;
    }
    return length;
}

// A border vertex of several curves whose faces' angles sum to less than this (degrees) is a leaflet corner already
// (a straight border: 180): bl_joint_corners_with_branches leaves it.
constexpr double kBranchCornerMinAngleSumDeg = 150;

// The nearest convex leaflet corner along the border from v (a border vertex without curves, faces' angles below
// kBranchCornerMinAngleSumDeg) at most `reach` away along the border, through plain border vertices; -1: none.
int corner_within_reach(const std::vector<Vec3>& points, const JoinStars& st, int v, double reach) {
    int best = -1;
    double best_dist = reach;
    for (int start : st.border[static_cast<size_t>(v)]) {
        int prev = v, cur = start;
        double dist = 0;
        while (cur >= 0 && cur != v) {
            const size_t c = static_cast<size_t>(cur);
            dist += distance(points[static_cast<size_t>(prev)], points[c]);
            const std::vector<int>& bn = st.border[c];
            if (dist > best_dist || bn.size() != 2 || bn[0] < 0 || bn[1] < 0) break;
            if (st.angle_sum[c] < kBranchCornerMinAngleSumDeg) {
                best = cur;
                best_dist = dist;
                break;
            }
            if (!st.curve[c].empty()) break;
            const int next = bn[0] == prev ? bn[1] : bn[0];
            prev = cur;
            cur = next;
        }
    }
    return best;
}

// Moves the curve edges of v (to its curve neighbours `curves`) onto vertex c; an edge whose twin from c exists
// already is dropped (the two curves merge). False (nothing changed) when c is one of the curve neighbours.
bool move_curves(Skeleton& s, int v, const std::vector<int>& curves, int c) {
    const auto has_edge = [&](int x, int y) {
        return std::any_of(s.edges.begin(), s.edges.end(), [&](const std::array<int, 2>& e) {
            return (e[0] == x && e[1] == y) || (e[0] == y && e[1] == x);
        });
    };
    for (int u : curves)
        if (u == c || !has_edge(v, u)) return false;
    std::vector<std::array<int, 2>> edges;
    for (const std::array<int, 2>& e : s.edges) {
        const int k = e[0] == v ? 0 : e[1] == v ? 1 : -1;
        const bool curve = k >= 0 && std::find(curves.begin(), curves.end(), e[1 - k]) != curves.end();
        if (!curve) {
            edges.push_back(e);
            continue;
        }
        if (has_edge(c, e[1 - k])) continue;  // merged with c's curve
        std::array<int, 2> moved = e;
        moved[static_cast<size_t>(k)] = c;
        edges.push_back(moved);
    }
    s.edges = std::move(edges);
    return true;
}

// Moves the curves of the several-curve join v onto the nearest convex corner within `reach` along the border
// (corner_within_reach), unless v, the corner or a curve neighbour took part in an earlier such move or the corner
// was moved; marks them in `touched`. Returns 1 when moved, else 0.
int join_to_corner(Skeleton& s, const std::vector<Vec3>& before, const JoinStars& st, int v, double reach,
                   std::vector<bool>& touched) {
    const int c = corner_within_reach(before, st, v, reach);
    if (c < 0 || touched[static_cast<size_t>(v)] || touched[static_cast<size_t>(c)] ||
        s.points[static_cast<size_t>(c)] != before[static_cast<size_t>(c)])
        return 0;
    const std::vector<int>& curves = st.curve[static_cast<size_t>(v)];
    for (int u : curves)
        if (touched[static_cast<size_t>(u)]) return 0;
    if (!move_curves(s, v, curves, c)) return 0;
    touched[static_cast<size_t>(v)] = touched[static_cast<size_t>(c)] = true;
    for (int u : curves) touched[static_cast<size_t>(u)] = true;
    return 1;
}

// BL-joints (a leaflet boundary vertex with curve edges) are pushed out of the leaflet so that the boundary makes a
// corner there (see MedialImportOptions::bl_joint_corners and bl_joint_reflex_corners). Decisions use the positions
// before any move (each joint is judged on the unmoved skeleton). Counts the moves in `result`.
void make_bl_joint_corners(Skeleton& s, const MedialImportOptions& opt, MedialImport& result) {
    const JoinStars st = join_stars(s);
    const std::vector<Vec3> before = s.points;
    std::vector<bool> touched(before.size(), false);  // corners and curve ends of moved joins: left alone after
    for (size_t v = 0; v < before.size(); ++v) {
        const std::vector<int>& bn = st.border[v];
        const std::vector<int>& curves = st.curve[v];
        if (curves.empty() || bn.size() != 2 || bn[0] < 0 || bn[1] < 0) continue;
        const bool several = curves.size() > 1;
        if (several && !opt.bl_joint_corners_with_branches) continue;
        const Vec3& p = before[v];
        const Vec3 &a = before[static_cast<size_t>(bn[0])], &b = before[static_cast<size_t>(bn[1])];
        // A sharp notch: the border turns by more than a straight stretch but the leaflet wraps around p (faces'
        // angles above 180 degrees); a straight stretch: the border turns little.
        const bool straight = angle_deg(p, a, b) > opt.bl_joint_max_angle_deg;
        const bool notch = !straight && opt.bl_joint_reflex_corners && st.angle_sum[v] > 180;
        if (!straight && !notch) continue;
        if (several && !notch && st.angle_sum[v] < kBranchCornerMinAngleSumDeg) continue;  // a corner already
        // Into the leaflet: the mean direction to the leaflet neighbours; at a notch, against the bisector of the two
        // border edges (which points into the notch's gap).
        Vec3 inward{};
        for (int u : st.leaflet[v]) inward += normalized(before[static_cast<size_t>(u)] - p);
        if (notch) inward = -1.0 * (normalized(a - p) + normalized(b - p));
        inward = normalized(inward);
        if (squared_norm(inward) == 0) continue;
        const double length = 0.5 * (distance(p, a) + distance(p, b));
        const Vec3 branch = normalized(before[static_cast<size_t>(curves[0])] - p);
        // The mesher roots this branch on the border's plates (border_root: Out or Side): no corner needed.
        if (!several && opt.keep_rooted_bl_joints &&
            border_root(normalized(a - p), normalized(b - p), inward, st.normal_sum[v], branch,
                        static_cast<int>(st.leaflet[v].size()) - 1,
                        v < s.radii.size() ? s.radii[v] / std::min(distance(p, a), distance(p, b)) : 0.0) !=
                BorderRoot::None)
            continue;
        // A branch heading back over the leaflet (positive cosine of its angle to the inward direction) gets a
        // sharper corner: bl_joint_back_push x that cosine more.
        double back = 0;
        for (int u : curves)
            back = std::max(back, opt.bl_joint_back_push * dot(normalized(before[static_cast<size_t>(u)] - p), inward));
        double push = opt.bl_joint_push * (1 + back) * length;
        const Vec3 out = -1.0 * inward;
        if (several || notch) {
            // Past the chord of the two border neighbours first, then as far as on a straight border; at most
            // bl_joint_max_push_curve_fraction x the shortest curve leaving p.
            const double chord = std::max(0.0, dot(0.5 * (a + b) - p, out));
            push += chord;
            double shortest = std::numeric_limits<double>::infinity();
            for (int u : curves) shortest = std::min(shortest, curve_length(before, st, static_cast<int>(v), u));
            const double cap = opt.bl_joint_max_push_curve_fraction * shortest;
            // Capped short of the wanted push: the curves move onto a convex corner nearby if there is one; p still
            // goes out as far as the cap allows (a shallower notch for the leaflet).
            if (several && cap < push && opt.bl_joint_corner_reach > 0)
                result.joins_to_corners +=
                    join_to_corner(s, before, st, static_cast<int>(v), opt.bl_joint_corner_reach * length, touched);
            push = std::min(push, cap);
        }
        if (push <= 0) continue;  // capped to nothing (bl_joint_max_push_curve_fraction 0)
        s.points[v] = p + out * push;
        ++result.moved_bl_joints;
        if (several)
            ++result.branch_corners;
        else if (notch)
            ++result.notch_corners;
    }
}

// The input triangles of the leaflets (positions of the medial mesh), each with its leaflet id (-1: collapsed).
struct LeafletSheets {
    std::vector<std::array<Vec3, 3>> triangles;
    std::vector<int> leaflet;
};

// A leaflet notch deeper than this (sum of the face angles at a border vertex, degrees) must open: its border sides
// are less than 90 degrees apart, the out columns of its half-chunks lean below 45 degrees to them and fold unless the
// smoothing's reflex move straightens the corner, which shortens its sides (keep_border_sides leaves them free).
constexpr double kDeepNotchDeg = 270;

// After a smoothing sweep from `prev` to `points`: every border side (ends `sides[k]`, length `length0[k]` before the
// smoothing) shorter than fraction x length0[k] has the sweep's move of both its ends halved, at most 4 times per end,
// then undone (back to `prev`), until no side is short (the positions before the sweep are not: by induction), except
// sides at a deep notch (`angle_sum`, the faces' angles at each vertex before the sweep, above kDeepNotchDeg). The
// smoothing then cannot slide a border vertex along the sheet onto its neighbour where it rounds a crease of the
// sheet (a border side a few times shorter than the radius: the half-chunks and plates there fold).
// Deterministic (sides in key order). O(sweeps x sides) per call.
void keep_border_sides(std::vector<Vec3>& points, const std::vector<Vec3>& prev,
                       const std::vector<std::array<int, 2>>& sides, const std::vector<double>& length0,
                       const std::vector<double>& angle_sum, double fraction) {
    std::vector<int> halvings(points.size(), 0);
    for (bool moved = true; moved;) {
        moved = false;
        for (size_t k = 0; k < sides.size(); ++k) {
            const size_t a = static_cast<size_t>(sides[k][0]), b = static_cast<size_t>(sides[k][1]);
            if (distance(points[a], points[b]) >= fraction * length0[k] || angle_sum[a] > kDeepNotchDeg ||
                angle_sum[b] > kDeepNotchDeg)
                continue;
            for (const size_t x : {a, b}) {
                if (points[x] == prev[x]) continue;
                points[x] = halvings[x] < 4 ? 0.5 * (points[x] + prev[x]) : prev[x];
                ++halvings[x];
                moved = true;
            }
        }
    }
}

// Jacobi smoothing of the leaflets (see MedialImportOptions::smoothing_iterations), all vertices from the same
// previous positions (order-independent): interior vertices (every incident edge in exactly two faces, no curve
// edge) p <- p + factor x (m - p), m = mean of the neighbours; with opt.smooth_boundary, regular boundary vertices
// (exactly two boundary edges, every other edge in two faces, no curve or fan edge) p <- p + factor x ((m - p).n) n,
// n = unit sum of the face normals at p (the sheet's fold flattens, its outline stays), and, at a reflex corner (sum
// of the face angles at p above opt.reflex_corner_deg), also p <- p + factor x (midpoint of the two boundary
// neighbours - p). With opt.max_sheet_offset >= 0 and `sheet` given, every smoothed vertex then has its offset from
// its leaflet's input triangles (sheet->triangles whose sheet->leaflet is the `face_leaflet` of a face at the vertex;
// along the normal of the closest one) limited to opt.max_sheet_offset x its radius. Returns the number of vertices
// smoothed.
int smooth_leaflets(Skeleton& s, const MedialImportOptions& opt, const LeafletSheets* sheet = nullptr,
                    const std::vector<int>* face_leaflet = nullptr) {
    const int nv = static_cast<int>(s.points.size());
    const int iterations = opt.smoothing_iterations;
    const double factor = opt.smoothing_factor;
    std::map<std::pair<int, int>, int> side_faces;
    for (const std::vector<int>& f : s.faces)
        for (size_t i = 0; i < f.size(); ++i) ++side_faces[side_key(f[i], f[(i + 1) % f.size()])];
    std::vector<bool> interior(static_cast<size_t>(nv), false), blocked(static_cast<size_t>(nv), false),
        other(static_cast<size_t>(nv), false);  // other: a curve or fan edge
    std::vector<std::vector<int>> neighbours(static_cast<size_t>(nv)), boundary(static_cast<size_t>(nv));
    for (const std::array<int, 2>& e : s.edges) {
        const auto it = side_faces.find(side_key(e[0], e[1]));
        const int faces = it == side_faces.end() ? 0 : it->second;
        for (int k = 0; k < 2; ++k) {
            const size_t x = static_cast<size_t>(e[k]);
            if (faces == 2)
                interior[x] = true;
            else
                blocked[x] = true;
            if (faces == 1) boundary[x].push_back(e[1 - k]);
            if (faces == 0 || faces >= 3) other[x] = true;
            neighbours[x].push_back(e[1 - k]);
        }
    }
    std::vector<int> movable, rim;
    for (int v = 0; v < nv; ++v) {
        const size_t x = static_cast<size_t>(v);
        if (interior[x] && !blocked[x]) movable.push_back(v);
        if (opt.smooth_boundary && !other[x] && boundary[x].size() == 2) rim.push_back(v);
    }
    auto mean_of_neighbours = [&](const std::vector<Vec3>& prev, int v) {
        Vec3 mean{};
        for (int u : neighbours[static_cast<size_t>(v)]) mean += prev[static_cast<size_t>(u)];
        return mean / static_cast<double>(neighbours[static_cast<size_t>(v)].size());
    };
    // The leaflet of every vertex in a face (interior and regular boundary vertices are in one leaflet only).
    const bool on_sheet = opt.max_sheet_offset >= 0 && sheet != nullptr && face_leaflet != nullptr &&
                          face_leaflet->size() == s.faces.size() && !sheet->triangles.empty();
    std::vector<int> vertex_leaflet(static_cast<size_t>(nv), -1);
    std::vector<std::vector<int>> leaflet_triangles;
    if (on_sheet) {
        for (size_t f = 0; f < s.faces.size(); ++f)
            for (int x : s.faces[f]) vertex_leaflet[static_cast<size_t>(x)] = (*face_leaflet)[f];
        for (size_t t = 0; t < sheet->triangles.size(); ++t) {
            const int leaf = sheet->leaflet[t];
            if (leaf < 0) continue;
            if (static_cast<size_t>(leaf) >= leaflet_triangles.size())
                leaflet_triangles.resize(static_cast<size_t>(leaf) + 1);
            leaflet_triangles[static_cast<size_t>(leaf)].push_back(static_cast<int>(t));
        }
    }
    // Back onto the leaflet's input triangles: the medial sheet, where the spheres touch the surface (the smoothing
    // alone flattens a curved sheet and pulls its border in, off the medial axis: the hexes then no longer reach
    // the surface; docs/sheets.md, "Smoothing on the medial sheet").
    auto project = [&](int v) {
        const int leaf = vertex_leaflet[static_cast<size_t>(v)];
        if (leaf < 0 || static_cast<size_t>(leaf) >= leaflet_triangles.size()) return;
        const Vec3 p = s.points[static_cast<size_t>(v)];
        int best = -1;
        double best_d = std::numeric_limits<double>::infinity();
        for (int t : leaflet_triangles[static_cast<size_t>(leaf)]) {
            const std::array<Vec3, 3>& tr = sheet->triangles[static_cast<size_t>(t)];
            const double d = squared_norm(p - closest_point_on_triangle(p, tr[0], tr[1], tr[2]));
            if (d < best_d) {
                best_d = d;
                best = t;
            }
        }
        if (best < 0) return;
        // Only the offset along the closest triangle's normal is limited (to max_sheet_offset x the vertex's
        // radius): moves within the sheet's plane stay, also past its border (a reflex corner's vertex moving
        // towards the midpoint of its border neighbours leaves the triangles sideways).
        const std::array<Vec3, 3>& tr = sheet->triangles[static_cast<size_t>(best)];
        const Vec3 n = normalized(cross(tr[1] - tr[0], tr[2] - tr[0]));
        const double off = dot(p - tr[0], n);
        const double limit = opt.max_sheet_offset * s.radii[static_cast<size_t>(v)];
        if (std::abs(off) > limit) s.points[static_cast<size_t>(v)] = p - n * (off - std::copysign(limit, off));
    };
    // The border sides with their lengths before the smoothing (MedialImportOptions::min_border_side_fraction).
    std::vector<std::array<int, 2>> border_sides;
    std::vector<double> border_length0;
    for (const auto& [side, faces] : side_faces)
        if (faces == 1) {
            border_sides.push_back({side.first, side.second});
            border_length0.push_back(
                distance(s.points[static_cast<size_t>(side.first)], s.points[static_cast<size_t>(side.second)]));
        }
    for (int it = 0; it < iterations; ++it) {
        const std::vector<Vec3> prev = s.points;
        for (int v : movable)
            s.points[static_cast<size_t>(v)] =
                prev[static_cast<size_t>(v)] + (mean_of_neighbours(prev, v) - prev[static_cast<size_t>(v)]) * factor;
        if (rim.empty()) continue;
        std::vector<Vec3> normal(static_cast<size_t>(nv), Vec3{});
        for (const std::vector<int>& f : s.faces) {
            const size_t k = f.size();
            const Vec3 n = cross(prev[static_cast<size_t>(f[2])] - prev[static_cast<size_t>(f[0])],
                                 prev[static_cast<size_t>(f[3 % k])] - prev[static_cast<size_t>(f[1])]);
            for (int w : f) normal[static_cast<size_t>(w)] += n;
        }
        const std::vector<double> angle_sum = face_angle_sums(prev, s.faces);
        for (int v : rim) {
            const size_t x = static_cast<size_t>(v);
            const Vec3 n = normalized(normal[x]);
            Vec3 move = n * dot(mean_of_neighbours(prev, v) - prev[x], n);
            if (angle_sum[x] > opt.reflex_corner_deg)
                move += 0.5 * (prev[static_cast<size_t>(boundary[x][0])] + prev[static_cast<size_t>(boundary[x][1])]) -
                        prev[x];
            s.points[x] = prev[x] + move * factor;
        }
        if (on_sheet) {
            for (int v : movable) project(v);
            for (int v : rim) project(v);
        }
        if (opt.min_border_side_fraction > 0)
            keep_border_sides(s.points, prev, border_sides, border_length0, angle_sum, opt.min_border_side_fraction);
    }
    return iterations > 0 ? static_cast<int>(movable.size() + rim.size()) : 0;
}

// Curve ends on a sheet's interior (paper limitation 1: the mesher cannot attach a branch there) move to the nearest
// boundary vertex of the same sheet that is on no fan edge (Euclidean distance, ties to the lower index): every curve
// edge (x, v) with v inside a sheet (in a triangle, no side at v in one triangle only or in three or more) becomes
// (x, b). An edge that
// would become a loop or duplicate an existing edge is left as it is. Vertex, edge and face counts, hence the Euler
// characteristic, do not change. Returns the number of curve-edge ends moved.
int reattach_interior_curve_ends(Skeleton& m) {
    const int nv = static_cast<int>(m.points.size());
    const int nt = static_cast<int>(m.faces.size());
    std::map<std::pair<int, int>, std::vector<int>> side_tris = triangles_by_side(m);
    UnionFind sheet(nt);
    for (const auto& [side, tris] : side_tris)
        for (size_t k = 1; k < tris.size(); ++k) sheet.unite(tris[0], tris[k]);
    std::vector<int> vertex_sheet(static_cast<size_t>(nv), -1);
    std::vector<bool> rim(static_cast<size_t>(nv), false), fan(static_cast<size_t>(nv), false);
    for (int t = 0; t < nt; ++t)
        for (int x : m.faces[static_cast<size_t>(t)]) vertex_sheet[static_cast<size_t>(x)] = sheet.find(t);
    for (const auto& [side, tris] : side_tris) {
        std::vector<bool>& flag = tris.size() == 1 ? rim : fan;
        if (tris.size() != 2) flag[static_cast<size_t>(side.first)] = flag[static_cast<size_t>(side.second)] = true;
    }
    std::vector<std::pair<int, int>> existing;
    for (const std::array<int, 2>& e : m.edges) existing.push_back(side_key(e[0], e[1]));
    std::sort(existing.begin(), existing.end());
    int moved = 0;
    for (std::array<int, 2>& e : m.edges) {
        if (side_tris.count(side_key(e[0], e[1])) > 0) continue;  // a triangle side, not a curve edge
        for (int k = 0; k < 2; ++k) {
            const int v = e[k], x = e[1 - k];
            const int sv = vertex_sheet[static_cast<size_t>(v)];
            if (sv < 0 || rim[static_cast<size_t>(v)] || fan[static_cast<size_t>(v)]) continue;
            int best = -1;
            double best_d = std::numeric_limits<double>::infinity();
            for (int b = 0; b < nv; ++b) {
                if (!rim[static_cast<size_t>(b)] || fan[static_cast<size_t>(b)] ||
                    vertex_sheet[static_cast<size_t>(b)] != sv)
                    continue;  // a boundary vertex of the same sheet, not on a fan edge (paper limitation 3)
                const double d = distance(m.points[static_cast<size_t>(v)], m.points[static_cast<size_t>(b)]);
                if (d < best_d) {
                    best_d = d;
                    best = b;
                }
            }
            if (best < 0 || best == x || std::binary_search(existing.begin(), existing.end(), side_key(best, x)))
                continue;
            e[static_cast<size_t>(k)] = best;
            existing.insert(std::lower_bound(existing.begin(), existing.end(), side_key(best, x)), side_key(best, x));
            ++moved;
        }
    }
    return moved;
}

// After the quad split: a curve edge ending at a leaflet interior vertex that is not regular (4 faces) moves that end
// to the regular interior neighbour (through a leaflet edge) without a curve edge of its own that lies most in the
// curve's direction (ties: lowest id). The mesher roots a branch only where 4 faces meet. Returns the ends moved.
int root_interior_curve_ends(Skeleton& s) {
    const int nv = static_cast<int>(s.points.size());
    std::map<std::pair<int, int>, int> side_faces;
    std::vector<int> faces_at(static_cast<size_t>(nv), 0);
    for (const std::vector<int>& f : s.faces)
        for (size_t i = 0; i < f.size(); ++i) {
            ++side_faces[side_key(f[i], f[(i + 1) % f.size()])];
            ++faces_at[static_cast<size_t>(f[i])];
        }
    std::vector<bool> rim(static_cast<size_t>(nv), false);
    std::vector<int> curve_edges(static_cast<size_t>(nv), 0);
    std::vector<std::vector<int>> leaflet_nbrs(static_cast<size_t>(nv));
    for (const std::array<int, 2>& e : s.edges) {
        const auto it = side_faces.find(side_key(e[0], e[1]));
        const int n = it == side_faces.end() ? 0 : it->second;
        if (n == 0) {
            ++curve_edges[static_cast<size_t>(e[0])];
            ++curve_edges[static_cast<size_t>(e[1])];
        } else {
            leaflet_nbrs[static_cast<size_t>(e[0])].push_back(e[1]);
            leaflet_nbrs[static_cast<size_t>(e[1])].push_back(e[0]);
        }
        if (n != 0 && n != 2) rim[static_cast<size_t>(e[0])] = rim[static_cast<size_t>(e[1])] = true;
    }
    auto interior = [&](int v) { return faces_at[static_cast<size_t>(v)] > 0 && !rim[static_cast<size_t>(v)]; };
    std::vector<std::pair<int, int>> existing;
    for (const std::array<int, 2>& e : s.edges) existing.push_back(side_key(e[0], e[1]));
    std::sort(existing.begin(), existing.end());
    int moved = 0;
    for (std::array<int, 2>& e : s.edges) {
        if (side_faces.count(side_key(e[0], e[1])) > 0) continue;
        for (int k = 0; k < 2; ++k) {
            const int v = e[static_cast<size_t>(k)], x = e[static_cast<size_t>(1 - k)];
            if (!interior(v) || (faces_at[static_cast<size_t>(v)] == 4 && curve_edges[static_cast<size_t>(v)] == 1))
                continue;
            const Vec3 d = normalized(s.points[static_cast<size_t>(x)] - s.points[static_cast<size_t>(v)]);
            int best = -1;
            double best_dot = -2;
            for (int b : leaflet_nbrs[static_cast<size_t>(v)]) {
                if (!interior(b) || faces_at[static_cast<size_t>(b)] != 4 || curve_edges[static_cast<size_t>(b)] != 0 ||
                    b == x || std::binary_search(existing.begin(), existing.end(), side_key(b, x)))
                    continue;
                const Vec3 to_b = s.points[static_cast<size_t>(b)] - s.points[static_cast<size_t>(v)];
                const double c = dot(normalized(to_b), d);
                if (c > best_dot || (c == best_dot && b < best)) {
                    best_dot = c;
                    best = b;
                }
            }
            if (best < 0) continue;  // left as it is: the mesher names the vertex
            e[static_cast<size_t>(k)] = best;
            --curve_edges[static_cast<size_t>(v)];
            ++curve_edges[static_cast<size_t>(best)];
            existing.insert(std::lower_bound(existing.begin(), existing.end(), side_key(best, x)), side_key(best, x));
            ++moved;
        }
    }
    return moved;
}
}  // namespace

namespace {

// import_medial_mesh's state: the validated input (triangles, their sides' edge ids), its sheets and leaflets, and
// the output skeleton being written; one member function per step (see medial_import.h, steps 1-3).
struct MedialImporter {
    const Skeleton& m;
    const MedialImportOptions& opt;
    MedialImport& result;
    Skeleton& out;
    int nv, ne, nt;
    std::vector<std::pair<std::pair<int, int>, int>> keys;  // (min, max) -> edge id, sorted
    std::vector<std::array<int, 3>> tri;
    std::vector<std::array<int, 3>> tri_edge;  // side i = (tri[i], tri[i+1])
    std::vector<std::vector<int>> edge_tris;
    std::vector<int> tri_sheet;
    int ns = 0;
    std::vector<std::vector<int>> sheet_vertices;
    std::vector<bool> collapsed;
    std::vector<bool> keep;
    std::vector<std::vector<int>> star;  // vertices joined to each collapsed sheet's centroid
    std::vector<int> new_id;
    std::vector<int> tri_leaflet;
    std::vector<int> partner;
    std::vector<std::array<int, 4>> pair_quad;

    MedialImporter(const Skeleton& medial, const MedialImportOptions& options, MedialImport& r)
        : m(medial),
          opt(options),
          result(r),
          out(r.skeleton),
          nv(static_cast<int>(medial.points.size())),
          ne(static_cast<int>(medial.edges.size())),
          nt(static_cast<int>(medial.faces.size())) {}

    int edge_id(int a, int b) const {
        const std::pair<int, int> k = std::minmax(a, b);
        auto it = std::lower_bound(keys.begin(), keys.end(), std::make_pair(k, -1));
        return (it != keys.end() && it->first == k) ? it->second : -1;
    }
    int add_point(const Vec3& p, double r) {
        out.points.push_back(p);
        out.radii.push_back(r);
        return static_cast<int>(out.points.size()) - 1;
    }
    bool live(int t) const { return !collapsed[static_cast<size_t>(tri_sheet[static_cast<size_t>(t)])]; }

    // ---- Validation (before anything is allocated for the output).
    void validate() {
        if (m.radii.size() != m.points.size())
            throw bad("the medial mesh needs one radius per vertex (" + std::to_string(m.radii.size()) + " radii for " +
                      std::to_string(nv) + " vertices)");
        for (int v = 0; v < nv; ++v)
            if (!is_finite(m.points[static_cast<size_t>(v)]) || !std::isfinite(m.radii[static_cast<size_t>(v)]) ||
                !(m.radii[static_cast<size_t>(v)] > 0))
                throw bad("vertex " + std::to_string(v) + " has a non-finite coordinate or a radius that is not > 0",
                          vertex_ref(v));
        keys.reserve(static_cast<size_t>(ne));
        for (int e = 0; e < ne; ++e) {
            const std::array<int, 2>& ed = m.edges[static_cast<size_t>(e)];
            if (ed[0] < 0 || ed[0] >= nv || ed[1] < 0 || ed[1] >= nv || ed[0] == ed[1])
                throw bad("edge " + std::to_string(e) + " has an out-of-range or repeated vertex", edge_ref(e));
            keys.push_back({std::minmax(ed[0], ed[1]), e});
        }
        std::sort(keys.begin(), keys.end());
        for (size_t i = 1; i < keys.size(); ++i)
            if (keys[i].first == keys[i - 1].first)
                throw bad(
                    "edge " + std::to_string(keys[i].second) + " duplicates edge " + std::to_string(keys[i - 1].second),
                    edge_ref(keys[i].second));
        tri.resize(static_cast<size_t>(nt));
        tri_edge.resize(static_cast<size_t>(nt));
        for (int t = 0; t < nt; ++t) {
            const std::vector<int>& f = m.faces[static_cast<size_t>(t)];
            if (f.size() != 3)
                throw bad("face " + std::to_string(t) + " has " + std::to_string(f.size()) +
                              " vertices (medial sheets are triangles)",
                          face_ref(t));
            for (int x : f)
                if (x < 0 || x >= nv)
                    throw bad("face " + std::to_string(t) + " has a vertex out of range", face_ref(t));
            if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
                throw bad("face " + std::to_string(t) + " has a repeated vertex", face_ref(t));
            tri[static_cast<size_t>(t)] = {f[0], f[1], f[2]};
            for (int i = 0; i < 3; ++i) {
                const int e = edge_id(f[static_cast<size_t>(i)], f[static_cast<size_t>((i + 1) % 3)]);
                if (e < 0)
                    throw bad(
                        "side " + std::to_string(i) + " of face " + std::to_string(t) + " is not in the edge list",
                        face_ref(t));
                tri_edge[static_cast<size_t>(t)][static_cast<size_t>(i)] = e;
            }
        }
    }

    // ---- Edge -> triangles; sheets (components through any shared edge); small sheets collapse.
    void find_sheets() {
        edge_tris.resize(static_cast<size_t>(ne));
        for (int t = 0; t < nt; ++t)
            for (int e : tri_edge[static_cast<size_t>(t)]) edge_tris[static_cast<size_t>(e)].push_back(t);
        UnionFind sheet_uf(nt);
        for (int e = 0; e < ne; ++e)
            for (size_t k = 1; k < edge_tris[static_cast<size_t>(e)].size(); ++k)
                sheet_uf.unite(edge_tris[static_cast<size_t>(e)][0], edge_tris[static_cast<size_t>(e)][k]);
        tri_sheet.assign(static_cast<size_t>(nt), -1);
        std::vector<int> sheet_root_id(static_cast<size_t>(nt), -1);
        for (int t = 0; t < nt; ++t) {
            const int root = sheet_uf.find(t);
            if (sheet_root_id[static_cast<size_t>(root)] < 0)
                sheet_root_id[static_cast<size_t>(root)] = result.sheets++;
            tri_sheet[static_cast<size_t>(t)] = sheet_root_id[static_cast<size_t>(root)];
        }
        ns = result.sheets;
        sheet_vertices.resize(static_cast<size_t>(ns));
        std::vector<int> sheet_tri_count(static_cast<size_t>(ns), 0);
        std::vector<double> sheet_area(static_cast<size_t>(ns), 0.0);
        for (int t = 0; t < nt; ++t) {
            const int s = tri_sheet[static_cast<size_t>(t)];
            const std::array<int, 3>& T = tri[static_cast<size_t>(t)];
            ++sheet_tri_count[static_cast<size_t>(s)];
            const Vec3& a = m.points[static_cast<size_t>(T[0])];
            sheet_area[static_cast<size_t>(s)] +=
                0.5 * norm(cross(m.points[static_cast<size_t>(T[1])] - a, m.points[static_cast<size_t>(T[2])] - a));
            for (int x : T) sheet_vertices[static_cast<size_t>(s)].push_back(x);
        }
        collapsed.assign(static_cast<size_t>(ns), false);
        for (int s = 0; s < ns; ++s) {
            std::vector<int>& sv = sheet_vertices[static_cast<size_t>(s)];
            std::sort(sv.begin(), sv.end());
            sv.erase(std::unique(sv.begin(), sv.end()), sv.end());
            double mean_r = 0;
            for (int v : sv) mean_r += m.radii[static_cast<size_t>(v)];
            mean_r /= static_cast<double>(sv.size());
            collapsed[static_cast<size_t>(s)] =
                sheet_tri_count[static_cast<size_t>(s)] < opt.min_sheet_triangles ||
                sheet_area[static_cast<size_t>(s)] < opt.min_sheet_area_factor * mean_r * mean_r;
            if (collapsed[static_cast<size_t>(s)]) ++result.collapsed_sheets;
        }
    }

    // ---- Which vertices survive. A vertex is attached to sheet s if it has a curve edge or lies in another sheet.
    void select_vertices() {
        std::vector<bool> has_curve_edge(static_cast<size_t>(nv), false);
        for (int e = 0; e < ne; ++e)
            if (edge_tris[static_cast<size_t>(e)].empty())
                for (int x : m.edges[static_cast<size_t>(e)]) has_curve_edge[static_cast<size_t>(x)] = true;
        std::vector<std::vector<int>> vertex_sheets(static_cast<size_t>(nv));
        for (int s = 0; s < ns; ++s)
            for (int v : sheet_vertices[static_cast<size_t>(s)]) vertex_sheets[static_cast<size_t>(v)].push_back(s);
        auto attached = [&](int v) {
            return has_curve_edge[static_cast<size_t>(v)] || vertex_sheets[static_cast<size_t>(v)].size() > 1;
        };
        keep.assign(static_cast<size_t>(nv), true);
        star.resize(static_cast<size_t>(ns));
        for (int s = 0; s < ns; ++s) {
            if (!collapsed[static_cast<size_t>(s)]) continue;
            const std::vector<int>& sv = sheet_vertices[static_cast<size_t>(s)];
            for (int v : sv)
                if (attached(v)) star[static_cast<size_t>(s)].push_back(v);
            if (star[static_cast<size_t>(s)].empty())
                star[static_cast<size_t>(s)] = sv;  // an isolated tiny sheet: keep its corners so something remains
            for (int v : sv)
                if (!std::binary_search(star[static_cast<size_t>(s)].begin(), star[static_cast<size_t>(s)].end(), v))
                    keep[static_cast<size_t>(v)] = false;
        }
    }

    // Kept vertices, curve edges, collapsed sheets' centroids and star edges.
    void emit_vertices_and_curves() {
        new_id.assign(static_cast<size_t>(nv), -1);
        for (int v = 0; v < nv; ++v) {
            if (!keep[static_cast<size_t>(v)]) continue;
            new_id[static_cast<size_t>(v)] = static_cast<int>(out.points.size());
            out.points.push_back(m.points[static_cast<size_t>(v)]);
            out.radii.push_back(m.radii[static_cast<size_t>(v)]);
        }
        // Curve edges, in input order.
        for (int e = 0; e < ne; ++e)
            if (edge_tris[static_cast<size_t>(e)].empty())
                out.edges.push_back({new_id[static_cast<size_t>(m.edges[static_cast<size_t>(e)][0])],
                                     new_id[static_cast<size_t>(m.edges[static_cast<size_t>(e)][1])]});
        // Collapsed sheets: centroid + star edges.
        for (int s = 0; s < ns; ++s) {
            if (!collapsed[static_cast<size_t>(s)]) continue;
            const std::vector<int>& sv = sheet_vertices[static_cast<size_t>(s)];
            Vec3 c{};
            double r = 0;
            for (int v : sv) {
                c += m.points[static_cast<size_t>(v)];
                r += m.radii[static_cast<size_t>(v)];
            }
            const int cv = add_point(c / static_cast<double>(sv.size()), r / static_cast<double>(sv.size()));
            for (int v : star[static_cast<size_t>(s)]) out.edges.push_back({cv, new_id[static_cast<size_t>(v)]});
        }
    }

    // ---- Leaflets: components of kept triangles through manifold edges, oriented by breadth-first flips.
    void orient_leaflets() {
        for (int e = 0; e < ne; ++e)
            if (edge_tris[static_cast<size_t>(e)].size() >= 3 && live(edge_tris[static_cast<size_t>(e)][0]))
                ++result.fan_edges;
        tri_leaflet.assign(static_cast<size_t>(nt), -1);
        for (int t0 = 0; t0 < nt; ++t0) {
            if (!live(t0) || tri_leaflet[static_cast<size_t>(t0)] >= 0) continue;
            const int leaf = result.leaflets++;
            std::queue<int> queue;
            tri_leaflet[static_cast<size_t>(t0)] = leaf;
            queue.push(t0);
            while (!queue.empty()) {
                const int u = queue.front();
                queue.pop();
                for (int e : tri_edge[static_cast<size_t>(u)]) {
                    const std::vector<int>& et = edge_tris[static_cast<size_t>(e)];
                    if (et.size() != 2) continue;
                    const int w = et[0] == u ? et[1] : et[0];
                    const int a = m.edges[static_cast<size_t>(e)][0], b = m.edges[static_cast<size_t>(e)][1];
                    const bool u_ab = has_directed(tri[static_cast<size_t>(u)], a, b);
                    if (tri_leaflet[static_cast<size_t>(w)] < 0) {
                        if (has_directed(tri[static_cast<size_t>(w)], a, b) == u_ab)
                            std::swap(tri[static_cast<size_t>(w)][1], tri[static_cast<size_t>(w)][2]);
                        tri_leaflet[static_cast<size_t>(w)] = leaf;
                        queue.push(w);
                    } else if (has_directed(tri[static_cast<size_t>(w)], a, b) == u_ab) {
                        throw Error(ErrorCode::UnsupportedConfiguration,
                                    "medial import: the sheet containing face " + std::to_string(w) +
                                        " is not orientable (a Moebius band); cut it first",
                                    face_ref(w));
                    }
                }
            }
        }
    }

    // ---- Greedy pairing of adjacent triangles into quads, best shape first.
    void pair_triangles() {
        partner.assign(static_cast<size_t>(nt), -1);
        pair_quad.resize(static_cast<size_t>(nt));
        if (!opt.pair_triangles) return;
        struct Candidate {
            double score;
            int e;
        };
        std::vector<Candidate> candidates;
        for (int e = 0; e < ne; ++e) {
            const std::vector<int>& et = edge_tris[static_cast<size_t>(e)];
            if (et.size() != 2 || !live(et[0])) continue;
            int t1 = et[0], t2 = et[1];
            int a = m.edges[static_cast<size_t>(e)][0], b = m.edges[static_cast<size_t>(e)][1];
            if (!has_directed(tri[static_cast<size_t>(t1)], a, b)) std::swap(a, b);
            const int c = third_vertex(tri[static_cast<size_t>(t1)], a, b);
            const int d = third_vertex(tri[static_cast<size_t>(t2)], a, b);
            if (c == d) continue;
            const Vec3 &pa = m.points[static_cast<size_t>(a)], &pb = m.points[static_cast<size_t>(b)],
                       &pc = m.points[static_cast<size_t>(c)], &pd = m.points[static_cast<size_t>(d)];
            // Quad (b, c, a, d); corners at a and b are the sums of the two triangle angles.
            const std::array<double, 4> corners = {angle_deg(pb, pc, pa) + angle_deg(pb, pa, pd), angle_deg(pc, pa, pb),
                                                   angle_deg(pa, pb, pc) + angle_deg(pa, pd, pb),
                                                   angle_deg(pd, pb, pa)};
            double deviation = 0;
            for (double x : corners) deviation = std::max(deviation, std::abs(x - 90.0));
            const Vec3 n1 = normalized(cross(pb - pa, pc - pa)), n2 = normalized(cross(pa - pb, pd - pb));
            if (squared_norm(n1) == 0 || squared_norm(n2) == 0) continue;
            const double fold = std::acos(std::clamp(dot(n1, n2), -1.0, 1.0)) * 180.0 / std::numbers::pi;
            if (deviation <= opt.max_pair_corner_deviation_deg && fold <= opt.max_pair_fold_deg)
                candidates.push_back({deviation + fold, e});
        }
        std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
            return std::tie(x.score, x.e) < std::tie(y.score, y.e);
        });
        for (const Candidate& cand : candidates) {
            const std::vector<int>& et = edge_tris[static_cast<size_t>(cand.e)];
            int t1 = et[0], t2 = et[1];
            if (partner[static_cast<size_t>(t1)] >= 0 || partner[static_cast<size_t>(t2)] >= 0) continue;
            int a = m.edges[static_cast<size_t>(cand.e)][0], b = m.edges[static_cast<size_t>(cand.e)][1];
            if (!has_directed(tri[static_cast<size_t>(t1)], a, b)) std::swap(a, b);
            const std::array<int, 4> q = {b, third_vertex(tri[static_cast<size_t>(t1)], a, b), a,
                                          third_vertex(tri[static_cast<size_t>(t2)], a, b)};
            partner[static_cast<size_t>(t1)] = t2;
            partner[static_cast<size_t>(t2)] = t1;
            pair_quad[static_cast<size_t>(std::min(t1, t2))] = q;
            ++result.paired_quads;
        }
    }

    // The live input triangles with their leaflets (for smoothing on the sheet).
    LeafletSheets leaflet_sheets() const {
        LeafletSheets sh;
        for (int t = 0; t < nt; ++t) {
            if (!live(t)) continue;
            const std::array<int, 3>& tr = tri[static_cast<size_t>(t)];
            sh.triangles.push_back({m.points[static_cast<size_t>(tr[0])], m.points[static_cast<size_t>(tr[1])],
                                    m.points[static_cast<size_t>(tr[2])]});
            sh.leaflet.push_back(tri_leaflet[static_cast<size_t>(t)]);
        }
        return sh;
    }

    // ---- Split every face (pair quad or lone triangle) at its centroid and edge midpoints into quads.
    void split_faces() {
        std::vector<int> midpoint(static_cast<size_t>(ne), -1);
        for (int t = 0; t < nt; ++t) {
            if (!live(t)) continue;
            const int p = partner[static_cast<size_t>(t)];
            if (p >= 0 && p < t) continue;  // emitted with its partner
            std::vector<int> poly;
            if (p >= 0)
                poly.assign(pair_quad[static_cast<size_t>(t)].begin(), pair_quad[static_cast<size_t>(t)].end());
            else {
                poly.assign(tri[static_cast<size_t>(t)].begin(), tri[static_cast<size_t>(t)].end());
                ++result.split_triangles;
            }
            const size_t k = poly.size();
            std::vector<int> mids(k);
            Vec3 centre{};
            double centre_r = 0;
            for (size_t i = 0; i < k; ++i) {
                const int a = poly[i], b = poly[(i + 1) % k];
                const int e = edge_id(a, b);
                if (midpoint[static_cast<size_t>(e)] < 0)
                    midpoint[static_cast<size_t>(e)] =
                        add_point(0.5 * (m.points[static_cast<size_t>(a)] + m.points[static_cast<size_t>(b)]),
                                  0.5 * (m.radii[static_cast<size_t>(a)] + m.radii[static_cast<size_t>(b)]));
                mids[i] = midpoint[static_cast<size_t>(e)];
                centre += m.points[static_cast<size_t>(a)];
                centre_r += m.radii[static_cast<size_t>(a)];
            }
            const int c = add_point(centre / static_cast<double>(k), centre_r / static_cast<double>(k));
            for (size_t i = 0; i < k; ++i) {
                out.faces.push_back({new_id[static_cast<size_t>(poly[i])], mids[i], c, mids[(i + k - 1) % k]});
                result.face_leaflet.push_back(tri_leaflet[static_cast<size_t>(t)]);
            }
        }
    }
};

}  // namespace

MedialImport import_medial_mesh(const Skeleton& m, const MedialImportOptions& opt) {
    MedialImport result;
    MedialImporter im(m, opt, result);
    im.validate();
    if (opt.resolve_irregular_fans || opt.reattach_interior_curves || opt.fill_pinch_max_angle_deg > 0) {
        Skeleton reduced = m;
        int removed = 0, reattached = 0, filled = 0;
        if (opt.resolve_irregular_fans)
            while (remove_irregular_fan_triangle(reduced)) ++removed;
        if (opt.fill_pinch_max_angle_deg > 0)
            while (fill_pinch_gap(reduced, opt.fill_pinch_max_angle_deg)) ++filled;
        if (opt.reattach_interior_curves) reattached = reattach_interior_curve_ends(reduced);
        if (removed > 0 || reattached > 0 || filled > 0) {
            MedialImportOptions rest = opt;
            rest.resolve_irregular_fans = false;
            rest.reattach_interior_curves = false;
            rest.fill_pinch_max_angle_deg = 0;
            MedialImport r = import_medial_mesh(reduced, rest);
            r.fan_triangles_removed = removed;
            r.reattached_curve_ends = reattached;
            r.filled_pinches = filled;
            return r;
        }
    }

    im.find_sheets();
    im.select_vertices();
    im.emit_vertices_and_curves();
    im.orient_leaflets();
    im.pair_triangles();
    im.split_faces();
    Skeleton& out = result.skeleton;
    add_face_edges(out);
    if (opt.root_interior_curves) result.rooted_curve_ends = root_interior_curve_ends(out);
    if (opt.bl_joint_corners) make_bl_joint_corners(out, opt, result);
    const LeafletSheets sheet = im.leaflet_sheets();
    result.smoothed_vertices = smooth_leaflets(out, opt, &sheet, &result.face_leaflet);
    return result;
}

std::vector<double> face_angle_sums(const std::vector<Vec3>& points, const std::vector<std::vector<int>>& faces) {
    std::vector<double> sum(points.size(), 0.0);
    for (const std::vector<int>& f : faces)
        for (size_t i = 0, k = f.size(); i < k; ++i)
            sum[static_cast<size_t>(f[i])] +=
                angle_deg(points[static_cast<size_t>(f[i])], points[static_cast<size_t>(f[(i + 1) % k])],
                          points[static_cast<size_t>(f[(i + k - 1) % k])]);
    return sum;
}

}  // namespace mesohex
