#include "mesohex/stages/fan_end_repair.h"

#include <algorithm>
#include <cmath>
#include <map>
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

// Is w such a vertex? Fills c.
bool is_candidate(const Skeleton& s, const Incidence& in, int w, Candidate& c) {
    int fan_edge = -1, fans = 0, border = 0;
    Vec3 branch{};
    for (const int e : in.vertex_edges[w]) {
        const int x = other_end(s, e, w), d = faces_on(in, w, x);
        if (d == 0) branch += normalized(s.points[x] - s.points[w]);
        if (d == 1) ++border;
        if (d == 2) return false;
        if (d >= 3) fan_edge = e, ++fans;
    }
    if (fans != 1 || !(norm(branch) > 1e-9)) return false;
    const int u = other_end(s, fan_edge, w);
    if (dot(normalized(branch), normalized(s.points[w] - s.points[u])) < kFanEndBranchCos) return false;
    int u_fans = 0;  // the chain must go on past u
    for (const int e : in.vertex_edges[u]) u_fans += faces_on(in, u, other_end(s, e, u)) >= 3 ? 1 : 0;
    if (u_fans != 2) return false;
    const std::vector<int>& around = in.side_faces.at(std::minmax(u, w));
    const int g = static_cast<int>(around.size());
    if (border != g || static_cast<int>(in.vertex_faces[w].size()) != g) return false;
    for (const int f : around)  // each face leaves w by its own border side
        if (faces_on(in, w, corner_neighbour(s.faces[f], w, u)) != 1) return false;
    c = {w, u, around, normalized(branch)};
    std::sort(c.faces.begin(), c.faces.end());
    return true;
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

FanEndRetraction retract(Skeleton& s, const Candidate& c) {
    FanEndRetraction r{c.w, c.u, carrier(s, c), {}};
    const Vec3 pw = s.points[c.w];
    const double rw = s.radii[c.w];
    // u slides along the fan line towards w (its fan-end cap then covers the notch the retraction opens).
    const double len = distance(pw, s.points[c.u]);
    s.points[c.u] = pw + std::clamp(kRetractionRadii * rw / len, 0.5, 1.0) * (s.points[c.u] - pw);
    for (const int f : c.faces) {
        const int x = corner_neighbour(s.faces[f], c.w, c.u);
        const double t = std::clamp(kRetractionRadii * rw / distance(s.points[x], pw), 0.3, 0.7);
        if (f == r.carrier_face) {  // w itself moves along the carrier's border
            s.points[c.w] = pw + t * (s.points[x] - pw);
            continue;
        }
        const int wi = static_cast<int>(s.points.size());
        s.points.push_back(pw + t * (s.points[x] - pw));
        s.radii.push_back(rw);
        *std::find(s.faces[f].begin(), s.faces[f].end(), c.w) = wi;
        for (std::array<int, 2>& e : s.edges)
            if (std::minmax(e[0], e[1]) == std::minmax(c.w, x)) (e[0] == c.w ? e[0] : e[1]) = wi;
        s.edges.push_back({c.u, wi});
        r.new_vertices.push_back(wi);
    }
    return r;
}

}  // namespace

std::vector<FanEndRetraction> retract_fan_ends(Skeleton& s) {
    std::vector<FanEndRetraction> done;
    if (s.faces.empty() || !well_formed(s) || !has_side_of_three_faces(s)) return done;  // a candidate needs a fan edge
    const int n = static_cast<int>(s.points.size());
    for (int round = 0; round < n; ++round) {
        const Incidence in = make_incidence(s);
        Candidate c;
        int w = 0;
        while (w < n && !is_candidate(s, in, w, c)) ++w;
        if (w == n) break;
        done.push_back(retract(s, c));
    }
    return done;
}

}  // namespace mesohex
