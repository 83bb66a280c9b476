#include "mesohex/stages/fan_end_repair.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace mesohex {
namespace {

using Side = std::pair<int, int>;  // (min, max) vertex ids of an edge

// Incidence of the current skeleton: faces per side, edges per vertex.
struct Incidence {
    std::map<Side, std::vector<int>> side_faces;
    std::vector<std::vector<int>> vertex_edges;  // per vertex: incident edges, increasing id
    std::vector<std::vector<int>> vertex_faces;  // per vertex: faces containing it, increasing id
};

bool well_formed(const Skeleton& s) {
    const int n = static_cast<int>(s.points.size());
    if (s.radii.size() != s.points.size()) return false;
    for (const double r : s.radii)
        if (!(r > 0) || !std::isfinite(r)) return false;
    for (const std::array<int, 2>& e : s.edges)
        if (e[0] < 0 || e[0] >= n || e[1] < 0 || e[1] >= n || e[0] == e[1]) return false;
    for (const std::vector<int>& f : s.faces) {
        if (f.size() != 4) return false;
        for (const int v : f)
            if (v < 0 || v >= n) return false;
    }
    return true;
}

Incidence make_incidence(const Skeleton& s) {
    Incidence in;
    in.vertex_edges.assign(s.points.size(), {});
    in.vertex_faces.assign(s.points.size(), {});
    for (int f = 0; f < static_cast<int>(s.faces.size()); ++f)
        for (int k = 0; k < 4; ++k) {
            const int a = s.faces[f][k], b = s.faces[f][(k + 1) % 4];
            in.side_faces[std::minmax(a, b)].push_back(f);
            in.vertex_faces[a].push_back(f);
        }
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e)
        for (const int v : s.edges[e]) in.vertex_edges[v].push_back(e);
    return in;
}

int faces_on(const Incidence& in, int a, int b) {
    const auto it = in.side_faces.find(std::minmax(a, b));
    return it == in.side_faces.end() ? 0 : static_cast<int>(it->second.size());
}

int other_end(const Skeleton& s, int e, int v) { return s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0]; }

// w's neighbour other than u in face f (u and w adjacent in f).
int corner_neighbour(const std::vector<int>& f, int w, int u) {
    const int k = static_cast<int>(std::find(f.begin(), f.end(), w) - f.begin());
    const int next = f[(k + 1) % 4], prev = f[(k + 3) % 4];
    return next == u ? prev : next;
}

// A fan-edge end of the header's configuration: w, u, the faces around (u, w) (increasing id), the unit sum of the
// branch directions.
struct Candidate {
    int w = -1, u = -1;
    std::vector<int> faces;
    Vec3 branch{};
};

// The edit that avoids the fan end altogether.
std::string off_fan() { return "start the branch from a corner of one leaflet off the fan edge"; }

// Sets *why (when given) to the failing condition and its edit; returns false. Called as `why != nullptr && refuse(why,
// ...)` where the repair's own loops call without why: the words are built only for fan_end_refusal.
bool refuse(FanEndRefusal* why, std::string reason, std::string edit) {
    if (why != nullptr) *why = {std::move(reason), std::move(edit)};
    return false;
}

std::string str(int i) { return std::to_string(i); }

int fan_edges_at(const Skeleton& s, const Incidence& in, int v) {
    int fans = 0;
    for (const int e : in.vertex_edges[v]) fans += faces_on(in, v, other_end(s, e, v)) >= 3 ? 1 : 0;
    return fans;
}

bool branch_end(const Skeleton& s, const Incidence& in, int w, Candidate& c, FanEndRefusal* why = nullptr);

// Is v a plain fan-edge end: on one fan edge and no branch, every face at v one of those around the fan edge, each
// leaving v by its own border side? Sets *why to the first condition that fails (worded after "skeleton vertex v").
// Does v carry a branch far from the fan line whose root the repair moves off (move_far_roots)?
bool movable_far_branch(const Skeleton& s, const Incidence& in, int v);

// With movable: a branch on v that the repair moves off later does not count (the fan end is plain after the move).
bool plain_fan_end(const Skeleton& s, const Incidence& in, int v, int other, FanEndRefusal* why = nullptr,
                   bool movable = false) {
    int fans = 0, border = 0, inner = 0, branches = 0;
    for (const int e : in.vertex_edges[v]) {
        const int d = faces_on(in, v, other_end(s, e, v));
        branches += d == 0 ? 1 : 0;
        inner += d == 2 ? 1 : 0;
        border += d == 1 ? 1 : 0;
        fans += d >= 3 ? 1 : 0;
    }
    const char* const edit =
        "end the fan edge there with one corner face per leaflet, each with its own border side, or split the fan "
        "edge and the strips of its faces in two by hand";
    if (branches > 0 && !(movable && movable_far_branch(s, in, v))) {
        if (why == nullptr) return false;
        FanEndRefusal other_why;
        Candidate c;
        const bool taken = branch_end(s, in, v, c, &other_why);
        // Not taken: v's own refusal as the repair gives it at v (a far branch: the moved root's failing condition, and
        // first a tube running into a plate), not only the retraction's angle rule that branch_end names.
        if (!taken)
            if (std::optional<FanEndRefusal> own = fan_end_refusal(s, v)) other_why = std::move(*own);
        return refuse(why,
                      "carries a branch too" +
                          (taken ? std::string() : " that the repair does not take either (" + other_why.reason + ")"),
                      taken ? edit : other_why.edit);
    }
    const std::vector<int>& around = in.side_faces.at(std::minmax(v, other));
    const int g = static_cast<int>(around.size()), faces = static_cast<int>(in.vertex_faces[v].size());
    if (fans != 1) return why != nullptr && refuse(why, "is on " + str(fans) + " fan edges", edit);
    if (inner > 0 || border != g || faces != g)
        return why != nullptr &&
               refuse(why,
                      "is not a plain fan end: the leaflets meet it with " + str(faces) + " faces and " + str(border) +
                          " border edges (one corner face per leaflet needed, " + str(g) +
                          "; edges there inside a leaflet: " + str(inner) + ")",
                      edit);
    for (const int f : around) {
        const int x = corner_neighbour(s.faces[f], v, other), d = faces_on(in, v, x);
        if (d != 1)
            return why != nullptr &&
                   refuse(why,
                          "is not a plain fan end: face " + str(f) + " leaves it by its side to skeleton vertex " +
                              str(x) + ", shared by " + str(d) + " faces (each face needs its own border side there)",
                          edit);
    }
    return true;
}

// Is w a fan-edge end carrying a branch that the retraction can take: on exactly one fan edge (u, w), every face at w
// one of those around (u, w) and leaving w by its own border side, and on branch edges whose mean direction is within
// 45 degrees of the fan line's continuation? Fills c (whatever u is); else sets *why to the first condition that
// fails (fan_end_refusal).
// The configuration of branch_end but for the angle: fills c (c.branch the unit mean branch direction).
bool fan_end_branch(const Skeleton& s, const Incidence& in, int w, Candidate& c, FanEndRefusal* why) {
    int fan_edge = -1, fans = 0, border = 0, inner = 0, branches = 0;
    Vec3 branch{};
    for (const int e : in.vertex_edges[w]) {
        const int x = other_end(s, e, w), d = faces_on(in, w, x);
        if (d == 0) branch += normalized(s.points[x] - s.points[w]), ++branches;
        if (d == 1) ++border;
        if (d == 2) ++inner;
        if (d >= 3) fan_edge = e, ++fans;
    }
    if (fans != 1)
        return why != nullptr &&
               refuse(why, "the vertex is on " + str(fans) + " fan edges (the repair needs exactly one)", off_fan());
    if (branches == 0)
        return why != nullptr && refuse(why, "the vertex has no branch edge", "none needed (no branch to carry)");
    const int u = other_end(s, fan_edge, w);
    const std::vector<int>& around = in.side_faces.at(std::minmax(u, w));
    const int g = static_cast<int>(around.size()), faces = static_cast<int>(in.vertex_faces[w].size());
    if (inner > 0 || border != g || faces != g)
        return why != nullptr &&
               refuse(why,
                      "the leaflets around the fan edge meet the vertex with " + str(faces) + " faces and " +
                          str(border) + " border edges (the repair needs one corner face per leaflet, " + str(g) +
                          (inner > 0 ? "; edges there inside a leaflet (2 faces each): " + str(inner) : "") + ")",
                      "make every leaflet there end with one corner face at this vertex (cut off the faces beyond the "
                      "fan edge's end, or end the fan edge where the leaflets' borders turn), or " +
                          off_fan());
    for (const int f : around) {  // each face leaves w by its own border side (implied by the counts above for quads)
        const int x = corner_neighbour(s.faces[f], w, u), d = faces_on(in, w, x);
        if (d != 1)
            return why != nullptr &&
                   refuse(why,
                          "face " + str(f) + " around the fan edge leaves the vertex by its side to skeleton vertex " +
                              str(x) + ", shared by " + str(d) +
                              " faces (the repair needs each face to leave it by its own border side)",
                          "make that side a border of face " + str(f) + " alone, or " + off_fan());
    }
    if (!(norm(branch) > 1e-9)) {
        std::ostringstream len;
        len << norm(branch);
        return why != nullptr &&
               refuse(why,
                      "the directions of its " + str(branches) + " branches cancel (their unit vectors sum to length " +
                          len.str() + ", no mean direction to compare with the fan line)",
                      "remove one of the opposite branches, or " + off_fan());
    }
    c = {w, u, around, normalized(branch)};
    std::sort(c.faces.begin(), c.faces.end());
    return true;
}

// The straight border run of a leaflet from the fan-edge end w through its border neighbour x: w, x, then the next
// border vertex as long as the last one is a plain straight border vertex (on 2 faces and 3 edges: two border sides and
// one inner edge; no branch, no fan edge) where the border turns by at most kBorderRunTurnDeg, not yet in the run.
std::vector<int> border_run(const Skeleton& s, const Incidence& in, int w, int x) {
    std::vector<int> run{w, x};
    while (true) {
        const int v = run.back(), prev = run[run.size() - 2];
        if (in.vertex_faces[v].size() != 2 || in.vertex_edges[v].size() != 3) return run;
        int next = -1, border = 0, inner = 0;
        for (const int e : in.vertex_edges[v]) {
            const int y = other_end(s, e, v), d = faces_on(in, v, y);
            border += d == 1 ? 1 : 0;
            inner += d == 2 ? 1 : 0;
            if (d == 1 && y != prev) next = y;
        }
        if (border != 2 || inner != 1 || next < 0 || std::find(run.begin(), run.end(), next) != run.end()) return run;
        const double turn = dot(normalized(s.points[v] - s.points[prev]), normalized(s.points[next] - s.points[v]));
        if (turn < std::cos(kBorderRunTurnDeg * std::numbers::pi / 180)) return run;
        run.push_back(next);
    }
}

// The point at arc length a along the polyline pts (a in [0, its length]); zero-length segments (coincident
// vertices) are skipped.
Vec3 at_arc_length(const std::vector<Vec3>& pts, double a) {
    for (std::size_t j = 0; j + 1 < pts.size(); ++j) {
        const double len = distance(pts[j], pts[j + 1]);
        if (!(len > 0)) continue;
        if (a <= len || j + 2 == pts.size()) return pts[j] + std::clamp(a / len, 0.0, 1.0) * (pts[j + 1] - pts[j]);
        a -= len;
    }
    return pts.back();
}

// The border runs of the faces around (c.u, c.w) (c.faces order); a vertex in two runs (a leaflet that comes back to
// the fan edge) ends both before it.
std::vector<std::vector<int>> face_runs(const Skeleton& s, const Incidence& in, const Candidate& c) {
    std::vector<std::vector<int>> whole;
    for (const int f : c.faces) whole.push_back(border_run(s, in, c.w, corner_neighbour(s.faces[f], c.w, c.u)));
    std::vector<std::vector<int>> runs = whole;
    for (std::size_t i = 0; i < runs.size(); ++i)
        for (std::size_t j = 0; j < whole.size(); ++j)
            for (std::size_t a = 1; i != j && a < runs[i].size(); ++a)
                if (std::find(whole[j].begin() + 1, whole[j].end(), runs[i][a]) != whole[j].end()) {
                    runs[i].resize(std::max<std::size_t>(a, 2));
                    break;
                }
    return runs;
}

// The cumulative arc length at every point of a polyline (0 first, its length last).
std::vector<double> arc_lengths(const std::vector<Vec3>& pts) {
    std::vector<double> arc{0};
    for (std::size_t j = 0; j + 1 < pts.size(); ++j) arc.push_back(arc.back() + distance(pts[j], pts[j + 1]));
    return arc;
}

std::vector<Vec3> run_points(const Skeleton& s, const std::vector<int>& run) {
    std::vector<Vec3> pts;
    for (const int v : run) pts.push_back(s.points[v]);
    return pts;
}

// The longest retraction along a border run: kRetractionMaxAtCorner of a single side (the run ends at the side's far
// end, which cannot slide), else kRetractionMax of the run's length.
double retraction_reach(const Skeleton& s, const std::vector<int>& run) {
    const double total = arc_lengths(run_points(s, run)).back();
    return (run.size() == 2 ? kRetractionMaxAtCorner : kRetractionMax) * total;
}

double branch_cos(const Skeleton& s, const Candidate& c);

// Is there room to retract the fan edge from c.w: on every face's border run the longest retraction reaches at least
// kRetractionMinRadii r_w, kRetractionRadii r_w for a branch leaning off the fan line (kRetractionAlignedCos; else
// *why, when given, names the first face short of it, its run and
// the ratio)? A skeleton without one radius per vertex passes.
bool retraction_room(const Skeleton& s, const Incidence& in, const Candidate& c, FanEndRefusal* why) {
    if (s.radii.size() != s.points.size()) return true;  // no radii yet (an analysis before they are set): not judged
    const std::vector<std::vector<int>> runs = face_runs(s, in, c);
    const double rw = s.radii[c.w];
    // A branch leaning off the fan line's continuation needs the full retraction (kRetractionAlignedCos).
    const double need = branch_cos(s, c) >= kRetractionAlignedCos ? kRetractionMinRadii : kRetractionRadii;
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const double reach = retraction_reach(s, runs[i]);
        if (reach >= need * rw) continue;
        if (why == nullptr) return false;
        std::ostringstream words;
        words.precision(3);
        words << "the branch's radius there, " << rw
              << ", is too thick for the leaflets: the retraction can go at most " << reach
              << " along the border of face " << c.faces[i] << " from the vertex (" << reach / rw
              << " radii; the straight border from it, " << runs[i].size() - 1
              << " side(s) long, ends at skeleton vertex " << runs[i].back() << "), at least " << need
              << " radii are needed (the border's hexes at the fan line fold"
              << (need == kRetractionMinRadii ? "" : "; the branch leans off the fan line's continuation") << ")";
        std::ostringstream edit;
        edit.precision(3);
        edit << "thin the branch at the vertex to at most " << reach / need
             << ", or make that leaflet's border from the vertex straight over more faces (at least "
             << need * rw / kRetractionMax << " long), or " << off_fan();
        return refuse(why, words.str(), edit.str());
    }
    return true;
}

// The cosine of the angle between the branches' mean direction and the fan line's continuation at c.w.
double branch_cos(const Skeleton& s, const Candidate& c) {
    return dot(c.branch, normalized(s.points[c.w] - s.points[c.u]));
}

// "the branch leaves N degrees off the fan line's continuation", N from the cosine.
std::string angle_words(double cos) {
    return "the branch leaves " +
           str(static_cast<int>(std::lround(std::acos(std::clamp(cos, -1.0, 1.0)) * 180 / std::numbers::pi))) +
           " degrees off the fan line's continuation";
}

// A branch far from the fan line whose moved root the repair refuses, retracted instead (kFallbackCornerDeg)?
bool fallback_retraction(const Skeleton& s, const Incidence& in, const Candidate& c);

bool branch_end(const Skeleton& s, const Incidence& in, int w, Candidate& c, FanEndRefusal* why) {
    if (!fan_end_branch(s, in, w, c, why)) return false;
    const double cos = branch_cos(s, c);
    if (cos < kFanEndBranchCos && !fallback_retraction(s, in, c))
        return why != nullptr && refuse(why,
                                        angle_words(cos) +
                                            " (the retraction takes branches within 45 degrees of the fan line; one "
                                            "across it has its root moved onto a leaflet border instead)",
                                        "turn the branch's first edge towards the fan line's continuation, or " +
                                            off_fan() + " (e.g. the far corner of the leaflet it leans over)");
    return retraction_room(s, in, c, why);
}

// What the repair does at w.
enum class EndKind { None, Retract, Split };

// Is w a vertex of the header's configuration (Retract), or one on a single fan edge whose other end u is a plain fan
// end (Split)? Fills c.
EndKind end_kind(const Skeleton& s, const Incidence& in, int w, Candidate& c) {
    if (!branch_end(s, in, w, c)) return EndKind::None;
    const int u_fans = fan_edges_at(s, in, c.u);  // the chain must go on past u
    if (u_fans == 2) return EndKind::Retract;
    return u_fans == 1 && plain_fan_end(s, in, c.u, c.w, nullptr, true) ? EndKind::Split : EndKind::None;
}

// The fan-edge chain from the end w through its neighbour u: w, u, ... up to the first vertex not on exactly two fan
// edges (the other end), or empty if it comes back to a vertex already seen.
std::vector<int> chain_from(const Skeleton& s, const Incidence& in, int w, int u) {
    std::vector<int> chain{w, u};
    while (fan_edges_at(s, in, chain.back()) == 2) {
        const int v = chain.back(), prev = chain[chain.size() - 2];
        int next = -1;
        for (const int e : in.vertex_edges[v]) {
            const int x = other_end(s, e, v);
            if (x != prev && faces_on(in, v, x) >= 3) next = x;
        }
        if (next < 0 || std::find(chain.begin(), chain.end(), next) != chain.end()) return {};
        chain.push_back(next);
    }
    return chain;
}

// One face crossed by a strip: the face and the position k of the side it is entered by (f[k], f[k + 1]).
struct Crossing {
    int face = -1, k = 0;
};

// The strips of the faces around the fan edge (u, w), each from its fan-edge side across the leaflet to a border
// side (a side of one face), or empty when one strip meets a side of 3 or more faces, or a face twice (then *why, when
// given, says which).
int side_at(const Skeleton& s, int f, int a, int b) {
    for (int k = 0; k < 4; ++k)
        if (std::minmax(s.faces[f][k], s.faces[f][(k + 1) % 4]) == std::minmax(a, b)) return k;
    return -1;
}

// Appends to out the strip of faces from face f0, entered by its side k0, across its leaflet to a border side (a side
// of one face); false when it meets a side of 3 or more faces, or a face already seen (then *why, when given, says
// which).
bool walk_strip(const Skeleton& s, const Incidence& in, int f0, int k0, std::vector<char>& seen,
                std::vector<Crossing>& out, FanEndRefusal* why) {
    int f = f0, k = k0;
    while (true) {
        if (seen[f]) {
            refuse(why, "the strip of faces from face " + str(f0) + " meets face " + str(f) + " a second time", "");
            return false;
        }
        seen[f] = 1;
        out.push_back({f, k});
        const int a = s.faces[f][(k + 2) % 4], b = s.faces[f][(k + 3) % 4];
        const std::vector<int>& next = in.side_faces.at(std::minmax(a, b));
        if (next.size() == 1) return true;
        if (next.size() != 2) {
            refuse(why,
                   "the strip of faces from face " + str(f0) + " meets the side (" + str(a) + ", " + str(b) +
                       ") of face " + str(f) + ", shared by " + str(static_cast<int>(next.size())) + " faces",
                   "");
            return false;
        }
        f = next[0] == f ? next[1] : next[0];
        k = side_at(s, f, a, b);
    }
}

// The strips of the faces around the fan edge (u, w), each from its fan-edge side across the leaflet to a border
// side (a side of one face), or empty when one strip meets a side of 3 or more faces, or a face twice (then *why, when
// given, says which).
std::vector<Crossing> fan_edge_strips(const Skeleton& s, const Incidence& in, const Candidate& c,
                                      FanEndRefusal* why = nullptr) {
    std::vector<Crossing> out;
    std::vector<char> seen(s.faces.size(), 0);
    for (const int f0 : c.faces)
        if (!walk_strip(s, in, f0, side_at(s, f0, c.u, c.w), seen, out, why)) return {};
    return out;
}

// Splits the fan edge (u, w) at m = u + t (w - u) and every strip crossing it (fan_edge_strips) through the points at
// the same fraction t of the sides it crosses, measured from the side's end on u's side of the strip (t = 1/2: the
// midpoints): each crossed face (a, b, c, d), entered by (a, b), becomes (a, m_ab, m_cd, d) in its place and
// (m_ab, b, c, m_cd) appended; each cut edge [a, b] becomes [a, m_ab] in its place and [m_ab, b] appended, then the
// edge [m_ab, m_cd] is appended. New vertices get the radius interpolated at the same fraction. Returns m.
int split_fan_edge(Skeleton& s, const Candidate& c, const std::vector<Crossing>& strips, double t = 0.5) {
    std::map<Side, int> edge_of;
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e) edge_of[std::minmax(s.edges[e][0], s.edges[e][1])] = e;
    std::map<Side, int> mid;
    const auto cut = [&](int from, int to) {  // the point at t from `from`
        const Side side = std::minmax(from, to);
        const auto it = mid.find(side);
        if (it != mid.end()) return it->second;
        const int m = static_cast<int>(s.points.size());
        s.points.push_back((1 - t) * s.points[from] + t * s.points[to]);
        s.radii.push_back((1 - t) * s.radii[from] + t * s.radii[to]);
        std::array<int, 2>& e = s.edges[edge_of.at(side)];
        const int far = e[1];
        e[1] = m;
        s.edges.push_back({m, far});
        mid[side] = m;
        return m;
    };
    const int m = cut(c.u, c.w);
    int from = c.u;  // the entered side's end on u's side of the strip
    for (const Crossing& x : strips) {
        const std::vector<int> f = s.faces[x.face];
        const int a = f[x.k], b = f[(x.k + 1) % 4], cc = f[(x.k + 2) % 4], d = f[(x.k + 3) % 4];
        if (std::minmax(a, b) == std::minmax(c.u, c.w)) from = c.u;  // a strip's first face
        const int mab = from == a ? cut(a, b) : cut(b, a);
        const int mcd = from == a ? cut(d, cc) : cut(cc, d);
        from = from == a ? d : cc;
        s.faces[x.face] = {a, mab, mcd, d};
        s.faces.push_back({mab, b, cc, mcd});
        s.edges.push_back({mab, mcd});
    }
    return m;
}

// A fan-edge chain with a retractable branch at both ends (branch_end) and fewer than 3 fan edges: retracting both
// ends needs a fan edge left between them (two retractions on a chain of 2 edges would leave its middle vertex a
// leaflet-only branching point, whose raw mesh folds). Each of its k fan edges is cut into ceil(3 / k) equal pieces
// (1 edge: thirds; 2 edges: halves, 4 in all) with the strips of its faces (split_fan_edge), when every fan edge's
// faces start strips that cross their leaflets to a border. Returns, per chain done, its lower end, the first cut
// point and the faces cut.
struct ChainSplit {
    int end = -1, first_cut = -1, faces_cut = 0;
};

// Is v one of the fan ends left to a fan block's cap (sorted)?
bool left_to_cap(const std::vector<int>& fan_caps, int v) {
    return std::binary_search(fan_caps.begin(), fan_caps.end(), v);
}

std::vector<ChainSplit> split_short_chains_with_two_branches(Skeleton& s, const std::vector<int>& fan_caps) {
    std::vector<ChainSplit> done;
    const int n = static_cast<int>(s.points.size());
    Incidence in = make_incidence(s);  // rebuilt after every cut below
    for (int w = 0; w < n; ++w) {
        Candidate c, other;
        if (left_to_cap(fan_caps, w) || !branch_end(s, in, w, c)) continue;
        const std::vector<int> chain = chain_from(s, in, w, c.u);
        const int k = static_cast<int>(chain.size()) - 1;
        if (k < 1 || k >= 3 || chain.back() < w || left_to_cap(fan_caps, chain.back()) ||
            !branch_end(s, in, chain.back(), other))
            continue;
        bool crossable = true;
        for (int i = 0; i < k && crossable; ++i) {
            Candidate edge{chain[i + 1], chain[i], in.side_faces.at(std::minmax(chain[i], chain[i + 1])), {}};
            crossable = !fan_edge_strips(s, in, edge).empty();
        }
        if (!crossable) continue;
        const int pieces = (3 + k - 1) / k;
        ChainSplit cs{w, static_cast<int>(s.points.size()), 0};
        for (int i = 0; i < k; ++i) {
            int a = chain[i];
            for (int j = 0; j + 1 < pieces; ++j) {  // cut the rest (a, chain[i + 1]) at 1 / (pieces - j) from a
                Candidate edge{chain[i + 1], a, in.side_faces.at(std::minmax(a, chain[i + 1])), {}};
                std::sort(edge.faces.begin(), edge.faces.end());
                const std::vector<Crossing> strips = fan_edge_strips(s, in, edge);
                cs.faces_cut += static_cast<int>(strips.size());
                a = split_fan_edge(s, edge, strips, 1.0 / (pieces - j));
                in = make_incidence(s);
            }
        }
        done.push_back(cs);
    }
    return done;
}

// The carrier face: max of d . o_i (ties within 1e-9 to the first in id order).
int carrier(const Skeleton& s, const Candidate& c) {
    const Vec3& pw = s.points[c.w];
    const Vec3 along = normalized(pw - s.points[c.u]);
    int best = -1;
    double best_dot = -2;
    for (const int f : c.faces) {
        const Vec3 x = s.points[corner_neighbour(s.faces[f], c.w, c.u)];
        const double d = dot(c.branch, normalized(along + normalized(pw - x)));
        if (d > best_dot + 1e-9) best = f, best_dot = d;
    }
    return best;
}

// The retraction along one face's border run (w, x, ...) from w: the retracted corner's place, and the run's inner
// vertices slid along it (their new places, run[1] first) when the retraction goes past kRetractionMax of the first
// side.
struct RunRetraction {
    Vec3 corner{};
    std::vector<Vec3> slid;
};

RunRetraction retract_run(const Skeleton& s, const std::vector<int>& run, double rw) {
    const std::vector<Vec3> pts = run_points(s, run);
    const double first = distance(pts[0], pts[1]);
    const double want = kRetractionRadii * rw;                // the retraction length along the border
    if (run.size() == 2 || want <= kRetractionMax * first) {  // within the first side (the rule for thin radii)
        const double t =
            std::clamp(want / first, kRetractionMin, run.size() == 2 ? kRetractionMaxAtCorner : kRetractionMax);
        return {pts[0] + t * (pts[1] - pts[0]), {}};
    }
    // Thick radii: the corner goes `want` along the run (at most kRetractionMax of it), and every inner vertex of the
    // run slides along it, its arc length a mapped to l + a (S - l) / S (S the run's length, l the corner's): the
    // run's far end stays, its sides keep their proportions.
    const std::vector<double> arc = arc_lengths(pts);
    const double total = arc.back();
    const double l = std::min(want, kRetractionMax * total);
    RunRetraction r{at_arc_length(pts, l), {}};
    for (std::size_t j = 1; j + 1 < pts.size(); ++j)
        r.slid.push_back(at_arc_length(pts, l + arc[j] * (total - l) / total));
    return r;
}

FanEndRetraction retract(Skeleton& s, const Candidate& c) {
    FanEndRetraction r{c.w, c.u, carrier(s, c), {}};
    const Vec3 pw = s.points[c.w];
    const double rw = s.radii[c.w];
    // The border runs first (on the skeleton before any move); a vertex in two runs (a leaflet that comes back to the
    // fan edge) ends both before it.
    const std::vector<std::vector<int>> runs = face_runs(s, make_incidence(s), c);
    std::vector<RunRetraction> moves;
    for (const std::vector<int>& run : runs) moves.push_back(retract_run(s, run, rw));
    // u slides along the fan line towards w (its fan-end cap then covers the notch the retraction opens).
    const double len = distance(pw, s.points[c.u]);
    s.points[c.u] = pw + std::clamp(kRetractionRadii * rw / len, 0.5, 1.0) * (s.points[c.u] - pw);
    for (std::size_t i = 0; i < c.faces.size(); ++i) {
        const int f = c.faces[i];
        const int x = runs[i][1];
        for (std::size_t j = 0; j < moves[i].slid.size(); ++j) s.points[runs[i][j + 1]] = moves[i].slid[j];
        r.border_vertices_slid += static_cast<int>(moves[i].slid.size());
        if (f == r.carrier_face) {  // w itself moves along the carrier's border
            s.points[c.w] = moves[i].corner;
            continue;
        }
        const int wi = static_cast<int>(s.points.size());
        s.points.push_back(moves[i].corner);
        s.radii.push_back(rw);
        *std::find(s.faces[f].begin(), s.faces[f].end(), c.w) = wi;
        for (std::array<int, 2>& e : s.edges)
            if (std::minmax(e[0], e[1]) == std::minmax(c.w, x)) (e[0] == c.w ? e[0] : e[1]) = wi;
        s.edges.push_back({c.u, wi});
        r.new_vertices.push_back(wi);
    }
    return r;
}

// A branch far from the fan line at c.w (branch_cos < kFanEndBranchCos), moved onto a leaflet border: the carrier face
// (max d . unit(x_i - w), ties within 1e-9 to the lowest face id), its border neighbour x of w, the cut fraction t on
// (w, x), and the strip of faces from that side across the leaflet to a border (empty when it does not cross: *why,
// when given, says why).
struct RootMove {
    int face = -1, x = -1;
    double t = 0;
    std::vector<Crossing> strip;
    bool bent = false;  // the first edge is bent: a new vertex at `bend` on it (bent_first_edge)
    Vec3 bend{};
    std::vector<int> run;    // thick radii (thick_root_run): the border run from w that slides, else empty
    std::vector<Vec3> slid;  // ... its inner vertices' new places (run[1] first)
};

// Where a branch at the fan end w comes closest to a leaflet's plate: past kPlateOverlapRootRadii r_w of arc length
// from w along the branch (its polyline through plain joints: two edges, no face), the sample whose centre-line
// distance to a face, over the tube's radius there plus the face's mean radius, is least (10 samples per edge, its
// far end included).
struct PlateOverlap {
    double ratio = std::numeric_limits<double>::infinity();  // distance / (r_tube + r_plate); < 1: they overlap
    double distance = 0, arc = 0, need = 0;
    int face = -1;
};

PlateOverlap plate_overlap(const Skeleton& s, const Incidence& in, int w) {
    PlateOverlap best;
    const double from = kPlateOverlapRootRadii * s.radii[w];
    const auto sample = [&](const Vec3& p, double r, double arc) {
        for (int f = 0; f < static_cast<int>(s.faces.size()); ++f) {
            const std::vector<int>& q = s.faces[f];
            const Vec3 &a = s.points[q[0]], &b = s.points[q[1]], &c = s.points[q[2]], &d = s.points[q[3]];
            const double dist = std::min(distance(p, closest_point_on_triangle(p, a, b, c)),
                                         distance(p, closest_point_on_triangle(p, a, c, d)));
            const double need = r + 0.25 * (s.radii[q[0]] + s.radii[q[1]] + s.radii[q[2]] + s.radii[q[3]]);
            if (dist / need < best.ratio) best = {dist / need, dist, arc, need, f};
        }
    };
    for (const int e0 : in.vertex_edges[w]) {
        int prev = w, cur = other_end(s, e0, w);
        if (faces_on(in, w, cur) != 0) continue;
        double arc = 0;
        for (int steps = 0; steps < static_cast<int>(s.points.size()); ++steps) {
            const Vec3 &a = s.points[prev], &b = s.points[cur];
            const double len = distance(a, b);
            for (int k = 1; k <= 10; ++k) {
                const double f = k / 10.0;
                if (arc + f * len >= from)
                    sample(a + f * (b - a), s.radii[prev] + f * (s.radii[cur] - s.radii[prev]), arc + f * len);
            }
            arc += len;
            if (in.vertex_edges[cur].size() != 2 || !in.vertex_faces[cur].empty()) break;
            const int e = in.vertex_edges[cur][0];
            const int next =
                other_end(s, e, cur) == prev ? other_end(s, in.vertex_edges[cur][1], cur) : other_end(s, e, cur);
            prev = cur, cur = next;
        }
    }
    return best;
}

// The fallback retraction's own condition (fallback_retraction without the moved root's): the branch within
// kFallbackCornerDeg of the carrier's outward corner direction and its tube clear of the leaflets' plates (one whose
// tube runs into a plate is refused, naming it).
bool corner_fallback(const Skeleton& s, const Incidence& in, const Candidate& c) {
    const int k = carrier(s, c);
    const Vec3& pw = s.points[c.w];
    const Vec3 x = s.points[corner_neighbour(s.faces[k], c.w, c.u)];
    const Vec3 out = normalized(normalized(pw - s.points[c.u]) + normalized(pw - x));
    return dot(c.branch, out) >= std::cos(kFallbackCornerDeg * std::numbers::pi / 180) &&
           !(plate_overlap(s, in, c.w).ratio < 1);
}

// The moved first edge from the cut point m towards v (unit) in the border's frame: along (the border side, unit),
// out (its outward in-plane direction), normal (the leaflet's). Returns its angles (degrees) off out and off the
// normal (either side).
std::pair<double, double> root_angles(const Vec3& v, const Vec3& out, const Vec3& normal) {
    const double deg = 180 / std::numbers::pi;
    return {std::acos(std::clamp(dot(v, out), -1.0, 1.0)) * deg,
            std::acos(std::clamp(std::abs(dot(v, normal)), 0.0, 1.0)) * deg};
}

bool clean_root(const std::pair<double, double>& off) {
    return off.first <= kMovedOutDeg || (off.first > kMovedSideOffOutDeg && off.second <= kMovedSideDeg);
}

// The direction c of a moved first edge bent at a new vertex (v, unit, no clean root): between the out and side
// limits, the outward direction turned towards v to kBendOutDeg off it; leaning back (more than kMovedSideOffOutDeg
// off out, more than kMovedSideDeg off the normal), the normal on v's side. Returns false when there is none (v along
// out or in the leaflet's plane), or when the branch would turn at the bend by more than kBendMaxTurnDeg.
// *turn_deg gets the turn of v onto c, degrees (-1 when v lies in the leaflet's plane: no side to bend to).
bool bent_first_edge(const Vec3& v, const Vec3& out, const Vec3& normal, Vec3& c, double* turn_deg) {
    *turn_deg = -1;
    const double vn = dot(v, normal);
    if (!(std::abs(vn) > 1e-9)) return false;
    if (root_angles(v, out, normal).first <= kMovedSideOffOutDeg) {
        const double a = kBendOutDeg * std::numbers::pi / 180;
        c = std::cos(a) * out + std::sin(a) * (vn > 0 ? normal : -1.0 * normal);
    } else {
        c = vn > 0 ? normal : -1.0 * normal;
    }
    *turn_deg = std::acos(std::clamp(dot(c, v), -1.0, 1.0)) * 180 / std::numbers::pi;
    return *turn_deg <= kBendMaxTurnDeg;
}

// The distance from the border line (through pw, unit direction along) of a moved branch where it reaches the
// border coordinate a0 (dot(p - pw, along) = a0): its polyline from the moved root m through cur (the branch edge
// (prev, cur) at the fan end), then on through vertices of two edges and no face. Infinite when it never gets that
// far along the border. Measured at that one coordinate only: a branch coming back to the border further on, or
// past a vertex of another degree or with faces, is not checked here.
double run_on_clearance(const Skeleton& s, const Incidence& in, const Vec3& pw, const Vec3& along, double a0,
                        const Vec3& m, int prev, int cur) {
    const auto coord = [&](const Vec3& p) { return dot(p - pw, along); };
    Vec3 a = m;
    for (int steps = 0; steps < static_cast<int>(s.points.size()); ++steps) {
        const Vec3& b = s.points[cur];
        if (coord(b) >= a0) {
            const double ca = coord(a), cb = coord(b);
            const double f = cb > ca ? std::clamp((a0 - ca) / (cb - ca), 0.0, 1.0) : 1.0;
            const Vec3 p = a + f * (b - a);
            return norm((p - pw) - coord(p) * along);
        }
        if (in.vertex_edges[cur].size() != 2 || !in.vertex_faces[cur].empty()) break;
        const int e0 = in.vertex_edges[cur][0];
        const int next =
            other_end(s, e0, cur) == prev ? other_end(s, in.vertex_edges[cur][1], cur) : other_end(s, e0, cur);
        a = b, prev = cur, cur = next;
    }
    return std::numeric_limits<double>::infinity();
}

// The edit for a moved root too thick for its border run: the largest radius the run takes.
std::string thin_to(double rw, const RootMove& mv, double side) {
    std::ostringstream edit;
    edit << std::setprecision(3) << "thin the branch at the vertex (now " << rw << ") to the bound above, or make the "
         << "border of face " << mv.face << " from the vertex straight over more faces, or start the branch from "
         << "skeleton vertex " << mv.x << " (" << side << " away along that border)";
    return edit.str();
}

// The edit for a moved first edge outside the clean-root limits that is not bent (root_move).
std::string angle_edit(int branches, double radius_ratio, double side) {
    std::ostringstream edit;
    edit << std::setprecision(3) << "turn the branch's first edge to within " << kMovedOutDeg
         << " degrees of the border's outward direction (or more than " << kMovedSideOffOutDeg << " off it and within "
         << kMovedSideDeg << " of the leaflet's normal)";
    if (branches == 1 && radius_ratio > kBendMaxRadius)
        edit << ", or thin it at the vertex to at most " << kBendMaxRadius * side << " (" << kBendMaxRadius
             << " x the border side, " << side << ", so that it is bent)";
    return edit.str();
}

// A moved root thicker than the first border side allows (kRootMoveRadii r_w > kRootMoveMax |x - w|): the root goes
// along the straight border run from w through mv.x (border_run) to the arc length a = clamp(proj, kRootMoveRadii r_w,
// min(kRootMoveMax S, S - kRootMoveRunRestRadii r_w)) (S the run's length, proj the branch's first vertex projected on
// it), and the run's inner vertices slide along it, arc length l to a + l (S - a) / S (the run's far end stays, the
// border keeps its line), so that the cut stays on the first side, at mv.t of it. Fills mv.run, mv.slid (the inner
// vertices' new places, mv.x's first) and mv.t; false when the run is a single side (mv.x cannot slide) or too short
// for both bounds (then *why, when given, says so).
bool thick_root_run(const Skeleton& s, const Incidence& in, int w, RootMove& mv, double proj, FanEndRefusal* why) {
    const double rw = s.radii[w];
    const std::vector<int> run = border_run(s, in, w, mv.x);
    const std::vector<Vec3> pts = run_points(s, run);
    const std::vector<double> arc = arc_lengths(pts);
    const double total = arc.back(), lo = kRootMoveRadii * rw;
    const double hi = std::min(kRootMoveMax * total, total - kRootMoveRunRestRadii * rw);
    if (run.size() == 2 || lo > hi) {
        std::ostringstream reason;
        reason << std::fixed << std::setprecision(3) << "its radius there, " << rw
               << ", is too thick for the border of face " << mv.face << ": a moved root needs " << std::defaultfloat
               << kRootMoveRadii << " radii of plate beside the fan line and " << kRootMoveRunRestRadii
               << " radii of border beyond it, along the straight border from the vertex (" << std::fixed << total
               << " long, " << run.size() - 1 << " side(s), ending at skeleton vertex " << run.back()
               << "), that is a radius of at most "
               << (run.size() == 2 ? kRootMoveMax * (arc[1] - arc[0]) / kRootMoveRadii
                                   : std::min(kRootMoveMax * total / kRootMoveRadii,
                                              total / (kRootMoveRadii + kRootMoveRunRestRadii)));
        refuse(why, reason.str(), thin_to(rw, mv, arc[1] - arc[0]));
        if (why != nullptr) why->thick_root = true;
        return false;
    }
    const double a = std::clamp(proj, lo, hi);
    mv.run = run;
    mv.slid.clear();
    for (std::size_t j = 1; j + 1 < pts.size(); ++j)
        mv.slid.push_back(at_arc_length(pts, a + arc[j] * (total - a) / total));
    mv.t = a / distance(pts[0], mv.slid.front());
    return true;
}

RootMove root_move(const Skeleton& s, const Incidence& in, const Candidate& c, FanEndRefusal* why = nullptr) {
    RootMove mv;
    const Vec3& pw = s.points[c.w];
    double best = -2;
    for (const int f : c.faces) {
        const int x = corner_neighbour(s.faces[f], c.w, c.u);
        const double d = dot(c.branch, normalized(s.points[x] - pw));
        if (d > best + 1e-9) best = d, mv.face = f, mv.x = x;
    }
    Vec3 b{};  // the mean of the branches' first vertices
    int n = 0;
    for (const int e : in.vertex_edges[c.w]) {
        const int y = other_end(s, e, c.w);
        if (faces_on(in, c.w, y) == 0) b += s.points[y], ++n;
    }
    const double rw = s.radii[c.w];
    Vec3 side = s.points[mv.x] - pw;
    double along_side = dot(b / static_cast<double>(n) - pw, side) / dot(side, side);  // b projected, 0 at w
    if (kRootMoveRadii * rw > kRootMoveMax * norm(side)) {
        // Thick radii: the border run slides (thick_root_run); the cut stays on the first side, now longer.
        if (!thick_root_run(s, in, c.w, mv, along_side * norm(side), why)) return mv;
        side = mv.slid.front() - pw;
        along_side = dot(b / static_cast<double>(n) - pw, side) / dot(side, side);
    } else {
        const double lo = std::clamp(kRootMoveRadii * rw / norm(side), kRootMoveMin, kRootMoveMax);
        mv.t = std::clamp(along_side, lo, kRootMoveMax);
    }
    // The moved branch's first edge against the border there: within kMovedOutDeg of the outward in-plane direction
    // (an out root), or more than kMovedSideOffOutDeg off it and within kMovedSideDeg of the leaflet's normal (a side
    // root); else (inverted raw hexes in between and beyond, measured) a single branch edge is bent at a new vertex
    // (bent_first_edge), or the move is not made.
    const Vec3 along = normalized(side), into = normalized(s.points[c.u] - pw);
    const Vec3 out = normalized(dot(into, along) * along - into);
    const Vec3 m = pw + mv.t * side, normal = normalized(cross(along, out));
    const Vec3 v = normalized(b / static_cast<double>(n) - m);
    const auto [off_out, off_normal] = root_angles(v, out, normal);
    if (!mv.slid.empty() && off_out > 90 + kThickRootBackDeg) {
        std::ostringstream reason;
        reason << "its radius there, " << std::fixed << std::setprecision(3) << rw << ", needs the border of face "
               << mv.face << " slid, and its first edge leans back " << std::lround(off_out - 90)
               << " degrees below the border's outward direction's plane (a thick moved "
               << "root takes at most " << std::lround(kThickRootBackDeg) << ")";
        refuse(why, reason.str(),
               "turn the branch's first edge out of the leaflets' half-space below the border (at most " +
                   str(static_cast<int>(kThickRootBackDeg)) +
                   " degrees past the plane normal to the outward direction), or thin it");
        return mv;
    }
    // Checked first, for clean and bent roots alike (issue 22: inverted raw hexes otherwise, measured by
    // bench/fanend_sweep.py): the branch's clearance where it runs on past the root.
    const double side_len = norm(side);
    for (const int e : in.vertex_edges[c.w]) {
        int prev = c.w, cur = other_end(s, e, c.w);
        if (faces_on(in, c.w, cur) != 0) continue;
        const double clearance = run_on_clearance(s, in, pw, along, mv.t * side_len + rw, m, prev, cur);
        if (clearance < kRunOnClearanceRadii * rw) {
            std::ostringstream reason;
            reason << std::fixed << std::setprecision(3) << "the branch runs on beside the border of face " << mv.face
                   << " past its moved root: " << rw << " (one radius) beyond the root along the border it is "
                   << clearance << " from the border line, " << clearance / rw << " radii (at least "
                   << std::defaultfloat << kRunOnClearanceRadii << " needed: the branch's tube and the border's own)";
            refuse(why, reason.str(),
                   "turn the branch away from the border of face " + str(mv.face) + " (its centre line " +
                       str(static_cast<int>(kRunOnClearanceRadii)) +
                       " radii off the border line one radius past the root), or start it from the leaflet's far "
                       "corner along that border");
            return mv;
        }
    }
    Vec3 dir{};
    // Bent only when the branch does not run on past the cut along the border (b projected within kRootMoveMax of the
    // side): a branch close to the carrier's plane stays beside its plates after the bend (inverted raw hexes); and
    // only for radii up to kBendMaxRadius x the side. The first condition that fails is named in the refusal.
    if (!clean_root({off_out, off_normal})) {
        const double radius_ratio = s.radii[c.w] / norm(side);
        double turn = -1;
        std::ostringstream no_bend;
        if (n != 1)
            no_bend << "the vertex has " << n << " branch edges (a bend takes a single one)";
        else if (along_side > kRootMoveMax)
            no_bend << "the branch runs on along the border side (its first vertex projects at "
                    << std::lround(100 * along_side) << "% of it, past " << std::lround(100 * kRootMoveMax) << "%)";
        else if (radius_ratio > kBendMaxRadius &&
                 !(off_out > kMovedSideOffOutDeg && plate_overlap(s, in, c.w).ratio >= 1 && !corner_fallback(s, in, c)))
            no_bend << "its radius is " << std::fixed << std::setprecision(2) << radius_ratio
                    << " x the border side (a bend takes at most " << kBendMaxRadius
                    << ", or more leaning back where the branch's tube clears the leaflets' plates)";
        else if (!bent_first_edge(v, out, normal, dir, &turn))
            no_bend << (turn < 0
                            ? std::string("the branch lies in the leaflet's plane (no side to bend it to)")
                            : "the bend would turn it by " + str(static_cast<int>(std::lround(turn))) +
                                  " degrees (at most " + str(static_cast<int>(std::lround(kBendMaxTurnDeg))) + ")");
        if (no_bend.tellp() == 0) {
            mv.bent = true;
            mv.bend = m + std::min(kBendRadii * s.radii[c.w], distance(m, b / static_cast<double>(n))) * dir;
        } else {
            std::ostringstream reason;
            reason << "its first edge, moved onto the border of face " << mv.face << ", would leave it "
                   << std::lround(off_out) << " degrees off the border's outward direction and "
                   << std::lround(off_normal) << " off the leaflet's normal (a moved root takes at most "
                   << kMovedOutDeg << " off the outward direction, or more than " << kMovedSideOffOutDeg
                   << " off it and at most " << kMovedSideDeg
                   << " off the normal), and it is not bent: " << no_bend.str();
            refuse(why, reason.str(), angle_edit(n, radius_ratio, norm(side)));
            return mv;
        }
    }
    std::vector<char> seen(s.faces.size(), 0);
    if (!walk_strip(s, in, mv.face, side_at(s, mv.face, c.w, mv.x), seen, mv.strip, why)) mv.strip.clear();
    return mv;
}

bool movable_far_branch(const Skeleton& s, const Incidence& in, int v) {
    Candidate c;
    return fan_end_branch(s, in, v, c, nullptr) && branch_cos(s, c) < kFanEndBranchCos &&
           !root_move(s, in, c).strip.empty();
}

// The first joint y of a moved root's branch edge e = (m, y), moved to y' = m + kFirstJointRadii r_w unit(y - m) along
// the edge (in or out). Only for a plain joint (two edges, no face) whose next vertex z lies farther than
// kFirstJointRadii r_w from m. Returns y, or -1 when not moved.
int place_first_joint(Skeleton& s, int e, int m, double rw) {
    const int y = other_end(s, e, m);
    int z = -1, degree = 0;
    for (int f = 0; f < static_cast<int>(s.edges.size()); ++f)
        if (s.edges[f][0] == y || s.edges[f][1] == y) {
            ++degree;
            if (f != e) z = other_end(s, f, y);
        }
    for (const std::vector<int>& face : s.faces)
        if (std::find(face.begin(), face.end(), y) != face.end()) return -1;
    const double reach = kFirstJointRadii * rw;
    const double now = distance(s.points[y], s.points[m]);
    if (degree != 2 || z < 0 || !(distance(s.points[z], s.points[m]) > reach) || !(now > 0)) return -1;
    s.points[y] = s.points[m] + reach * normalized(s.points[y] - s.points[m]);
    return y;
}

// Cuts the carrier's strip at mv.t (split_fan_edge from w's side) and moves every branch edge at c.w to the cut point
// on (w, x).
FanEndRetraction move_root(Skeleton& s, const Incidence& in, const Candidate& c, const RootMove& mv) {
    std::vector<int> branches;
    for (const int e : in.vertex_edges[c.w])
        if (faces_on(in, c.w, other_end(s, e, c.w)) == 0) branches.push_back(e);
    for (std::size_t j = 0; j < mv.slid.size(); ++j) s.points[mv.run[j + 1]] = mv.slid[j];
    const int m = split_fan_edge(s, Candidate{mv.x, c.w, {}, {}}, mv.strip, mv.t);
    for (const int e : branches) (s.edges[e][0] == c.w ? s.edges[e][0] : s.edges[e][1]) = m;
    FanEndRetraction r{c.w, c.u, mv.face, {}};
    r.border_vertices_slid = static_cast<int>(mv.slid.size());
    if (mv.bent) {  // one branch edge (m, y): becomes (m, p), (p, y) appended
        const int p = static_cast<int>(s.points.size()), e = branches.front();
        s.points.push_back(mv.bend);
        s.radii.push_back(s.radii[c.w]);
        int& end = s.edges[e][0] == m ? s.edges[e][1] : s.edges[e][0];
        s.edges.push_back({p, end});
        end = p;
        r.bend = p;
    } else if (branches.size() == 1) {
        r.first_joint = place_first_joint(s, branches.front(), m, s.radii[c.w]);
    }
    r.strip_faces_split = static_cast<int>(mv.strip.size());
    r.moved_root = m;
    return r;
}

// Every branch far from the fan line on a fan-edge end whose carrier strip crosses its leaflet, moved (increasing w).
std::vector<FanEndRetraction> move_far_roots(Skeleton& s) {
    std::vector<FanEndRetraction> done;
    const int n = static_cast<int>(s.points.size());
    Incidence in = make_incidence(s);  // rebuilt after every move
    for (int w = 0; w < n; ++w) {
        Candidate c;
        if (!fan_end_branch(s, in, w, c, nullptr) || branch_cos(s, c) >= kFanEndBranchCos) continue;
        RootMove mv = root_move(s, in, c);
        if (mv.strip.empty()) continue;
        // The row under the root: the fan edge (u, w) and the strips of its faces cut at kRootRowRadii r_w from w (at
        // least half the fan edge left below), when every strip crosses its leaflet; the root's patch then reaches
        // that far below the border instead of the whole fan edge.
        int row = -1;
        const double len = distance(s.points[c.w], s.points[c.u]);
        const std::vector<Crossing> rows = fan_edge_strips(s, in, c);
        if (!rows.empty() && kRootRowRadii * s.radii[c.w] < 0.5 * len) {
            row = split_fan_edge(s, c, rows, 1 - kRootRowRadii * s.radii[c.w] / len);
            in = make_incidence(s);
            if (!fan_end_branch(s, in, w, c, nullptr)) break;  // cannot happen: w keeps its configuration
            mv = root_move(s, in, c);
            if (mv.strip.empty()) break;  // cannot happen: the cut strips cross as before
        }
        done.push_back(move_root(s, in, c, mv));
        done.back().fan_edge_split = row;
        in = make_incidence(s);
    }
    return done;
}

bool fallback_retraction(const Skeleton& s, const Incidence& in, const Candidate& c) {
    return branch_cos(s, c) < kFanEndBranchCos && root_move(s, in, c).strip.empty() && corner_fallback(s, in, c);
}

// A refusal at w whose branch's tube meets a leaflet's plate (plate_overlap below 1) names that first: the input's
// domain has the tube run into the plate there, which no root placement meshes; the repair's own condition follows.
FanEndRefusal with_plate_overlap(const Skeleton& s, const Incidence& in, int w, FanEndRefusal why) {
    if (s.radii.size() != s.points.size()) return why;
    const PlateOverlap o = plate_overlap(s, in, w);
    if (!(o.ratio < 1)) return why;
    std::ostringstream words, edit;
    words << std::fixed << std::setprecision(3) << "the branch's tube runs into the plate of face " << o.face << ": "
          << o.arc << " along the branch from the vertex (past " << std::defaultfloat << kPlateOverlapRootRadii
          << std::fixed << " radii, the root's own reach) its centre line is " << o.distance
          << " from that face, where the tube's "
          << "radius and the plate's need " << o.need << " (" << o.ratio
          << " of it); the repair's own condition: " << why.reason;
    edit << std::fixed << std::setprecision(3) << "turn the branch away from face " << o.face
         << "'s leaflet (its centre line at "
         << "least " << o.need << " from it), or thin the branch and that leaflet there to radii adding up to at most "
         << o.distance << ", or " << why.edit;
    return {words.str(), edit.str()};
}

std::optional<FanEndRefusal> repair_conditions(const Skeleton& s, int w);

}  // namespace

std::optional<FanEndRefusal> fan_end_refusal(const Skeleton& s, int w) {
    std::optional<FanEndRefusal> why = repair_conditions(s, w);
    const int n = static_cast<int>(s.points.size());
    if (!why || w < 0 || w >= n || !well_formed(s)) return why;
    const Incidence in = make_incidence(s);
    Candidate c;
    if (!fan_end_branch(s, in, w, c, nullptr)) return why;
    return with_plate_overlap(s, in, w, std::move(*why));
}

namespace {

std::optional<FanEndRefusal> repair_conditions(const Skeleton& s, int w) {
    const int n = static_cast<int>(s.points.size());
    for (const std::array<int, 2>& e : s.edges)
        if (e[0] < 0 || e[0] >= n || e[1] < 0 || e[1] >= n || e[0] == e[1])
            return FanEndRefusal{"the skeleton has an edge with an index out of range or a loop", "fix the edge"};
    for (const std::vector<int>& f : s.faces)
        if (f.size() != 4 || std::any_of(f.begin(), f.end(), [n](int v) { return v < 0 || v >= n; }))
            return FanEndRefusal{"the skeleton has a face that is not a quad of vertices in range", "fix the face"};
    if (w < 0 || w >= n) return FanEndRefusal{"no such vertex", "name a vertex of the skeleton"};
    const Incidence in = make_incidence(s);
    Candidate c, other;
    FanEndRefusal why;
    if (!fan_end_branch(s, in, w, c, &why)) return why;
    if (branch_cos(s, c) < kFanEndBranchCos) {  // moved onto a leaflet border (move_far_roots)
        if (s.radii.size() != s.points.size())  // root_move and fallback_retraction read r_w
            return FanEndRefusal{angle_words(branch_cos(s, c)) +
                                     " and the skeleton has no radius per vertex: the repair's moved root is judged "
                                     "by the branch's radius",
                                 "give every skeleton vertex a radius (the pipeline does before the repair)"};
        const RootMove mv = root_move(s, in, c, &why);
        if (!mv.strip.empty()) return std::nullopt;
        if (!fallback_retraction(s, in, c))
            return FanEndRefusal{
                angle_words(branch_cos(s, c)) +
                    " (not retracted; its root is moved onto the border of the leaflet it leans over only when the "
                    "strip of faces from that border side, from face " +
                    str(mv.face) + ", crosses the leaflet to a border, and " + why.reason + ")",
                (why.edit.empty() ? std::string("make that strip reach a border, or ") : why.edit + ", or ") +
                    "turn the branch's first edge towards the fan line's continuation, or " + off_fan(),
                why.thick_root};
    }
    if (!retraction_room(s, in, c, &why)) return why;
    // u carries a branch far from the fan line that the repair moves off: judge w after that move (the repair's rounds
    // run again after the moves).
    if (movable_far_branch(s, in, c.u)) {
        Skeleton moved = s;
        (void)move_far_roots(moved);
        return repair_conditions(moved, w);
    }
    const std::string u = "skeleton vertex " + str(c.u);
    // A chain of 1 or 2 fan edges with a retractable branch at
    // its other end too (split_short_chains_with_two_branches).
    const std::vector<int> chain = chain_from(s, in, w, c.u);
    const int k = static_cast<int>(chain.size()) - 1;
    if (k >= 1 && k < 3 && branch_end(s, in, chain.back(), other)) {
        for (int i = 0; i < k; ++i) {
            Candidate edge{chain[i + 1], chain[i], in.side_faces.at(std::minmax(chain[i], chain[i + 1])), {}};
            if (!fan_edge_strips(s, in, edge, &why).empty()) continue;
            // Not cut: a chain of 2 is retracted at its lower end as it is (u goes on past it), the other end refused.
            if (k == 2 && w < chain.back()) return std::nullopt;
            return FanEndRefusal{
                "the fan-edge chain from it has " + str(k) + " fan edge" + (k == 1 ? "" : "s") +
                    " and a branch the repair takes at its other end too, skeleton vertex " + str(chain.back()) +
                    "; such a chain is cut into 3 or more fan edges first (both ends retracted) only when the "
                    "strips of faces from each of its fan edges cross the leaflets to a border, and on the fan edge (" +
                    str(chain[i]) + ", " + str(chain[i + 1]) + ") " + why.reason,
                "cut the chain into 3 fan edges by hand (with the strips of their faces), or make that strip reach a "
                "border, or start one of the two branches from a corner of one leaflet off the fan edge"};
        }
        return std::nullopt;
    }
    const int u_fans = fan_edges_at(s, in, c.u);
    if (u_fans == 2) return std::nullopt;  // retracted as it is
    if (u_fans != 1)
        return FanEndRefusal{
            "the fan edge's other end, " + u + ", is on " + str(u_fans) +
                " fan edges (the repair slides it along the fan line: the fan-edge chain must go on past it by one "
                "fan edge, or end there)",
            "start the branch from a corner of one leaflet off the fan edge, or make the fan edges at " + u +
                " one chain"};
    if (!plain_fan_end(s, in, c.u, w, &why))
        return FanEndRefusal{"the fan edge is a single one (its other end, " + u + ", " + why.reason +
                                 "); a single fan edge is split in two first only when every face at its other end "
                                 "is one of the fan edge's faces with its own border side there",
                             why.edit};
    if (fan_edge_strips(s, in, c, &why).empty())
        return FanEndRefusal{"the fan edge is a single one (its other end, " + u +
                                 ", is a fan-edge end); a single fan edge is split in two first only when the strips "
                                 "of its faces cross the leaflets to a border without meeting another fan edge, and " +
                                 why.reason,
                             "split the fan edge and the strips of its faces in two by hand, or make the leaflets' "
                             "strips from the fan edge reach a border"};
    return std::nullopt;  // split, then retracted
}

}  // namespace

std::optional<FanEndRefusalAt> first_fan_end_refusal(const Skeleton& s, const std::vector<int>& fan_caps) {
    if (!well_formed(s)) return std::nullopt;  // the analysis reports the input
    const Incidence in = make_incidence(s);
    for (int v = 0; v < static_cast<int>(s.points.size()); ++v) {
        if (left_to_cap(fan_caps, v)) continue;
        int branches = 0, fans = 0, degree = 0;
        for (const int e : in.vertex_edges[v]) {
            const int f = faces_on(in, v, other_end(s, e, v));
            branches += f == 0 ? 1 : 0;
            if (f >= 3) ++fans, degree = f;
        }
        if (branches == 0 || fans != 1) continue;
        std::optional<FanEndRefusal> why = fan_end_refusal(s, v);
        if (why) return FanEndRefusalAt{v, degree, std::move(*why)};
    }
    return std::nullopt;
}

namespace {

// The retraction rounds: one retraction (or a single fan edge's split and retraction) per round, the lowest vertex
// first, until none is left; appended to done.
void retraction_rounds(Skeleton& s, const std::vector<ChainSplit>& chains, const std::vector<int>& fan_caps,
                       std::vector<FanEndRetraction>& done) {
    const int n = static_cast<int>(s.points.size());
    for (int round = 0; round < n; ++round) {
        const Incidence in = make_incidence(s);
        Candidate c;
        int w = 0, split_at = -1;
        Candidate split;
        std::vector<Crossing> strips;
        for (; w < n; ++w) {
            const EndKind kind = left_to_cap(fan_caps, w) ? EndKind::None : end_kind(s, in, w, c);
            if (kind == EndKind::Retract) break;
            if (kind == EndKind::Split && split_at < 0) {
                strips = fan_edge_strips(s, in, c);
                if (!strips.empty()) split_at = w, split = c;
            }
        }
        if (w < n) {
            const bool far = branch_cos(s, c) < kFanEndBranchCos;
            FanEndRetraction r = retract(s, c);
            r.far_branch = far;
            for (const ChainSplit& cs : chains)
                if (cs.end == w) r.fan_edge_split = cs.first_cut, r.strip_faces_split = cs.faces_cut;
            done.push_back(std::move(r));
            continue;
        }
        if (split_at < 0) break;
        // A single fan edge: split in two (the chain then goes on past its middle), retracted from w in the next round.
        const int m = split_fan_edge(s, split, strips);
        const Incidence again = make_incidence(s);
        if (end_kind(s, again, split_at, c) != EndKind::Retract) break;  // cannot happen: (m, w) continues past m
        const bool far = branch_cos(s, c) < kFanEndBranchCos;
        FanEndRetraction r = retract(s, c);
        r.far_branch = far;
        r.fan_edge_split = m;
        r.strip_faces_split = static_cast<int>(strips.size());
        done.push_back(std::move(r));
    }
}

}  // namespace

std::vector<FanEndRetraction> retract_fan_ends(Skeleton& s, const std::vector<int>& fan_caps) {
    std::vector<FanEndRetraction> done;
    if (s.faces.empty() || !well_formed(s) || !has_side_of_three_faces(s)) return done;  // a candidate needs a fan edge
    const std::vector<ChainSplit> chains = split_short_chains_with_two_branches(s, fan_caps);
    retraction_rounds(s, chains, fan_caps, done);
    // Branches far from the fan line: roots moved; a fan end that carried one is then plain, so the other end of its
    // chain may now be retracted (a single fan edge: split first).
    const std::vector<FanEndRetraction> moved = move_far_roots(s);
    if (moved.empty()) return done;
    done.insert(done.end(), moved.begin(), moved.end());
    retraction_rounds(s, {}, fan_caps, done);
    return done;
}

}  // namespace mesohex
