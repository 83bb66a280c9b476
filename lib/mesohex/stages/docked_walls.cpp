#include "mesohex/stages/docked_walls.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "mesohex/core/error.h"

namespace mesohex {

namespace {

[[noreturn]] void refuse(int v, const std::string& what) {
    throw Error(ErrorCode::UnsupportedConfiguration, "skeleton vertex " + std::to_string(v) + ": " + what,
                ElementRef{ElementRef::Kind::SkeletonVertex, v});
}

int other_end(const Skeleton& s, int e, int v) { return s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0]; }

bool face_has_edge(const SkeletonAnalysis& an, int f, int e) {
    return std::find(an.face_edges[f].begin(), an.face_edges[f].end(), e) != an.face_edges[f].end();
}

// Unit direction from edge e (side k of face f) into f, perpendicular to the edge: from the edge's midpoint to the
// midpoint of the opposite side.
Vec3 into_face(const Skeleton& s, const SkeletonAnalysis& an, int f, int e) {
    int k = 0;
    while (an.face_edges[f][k] != e) ++k;
    const std::array<int, 4>& fv = an.face_vertices[f];
    const Vec3 a = s.points[fv[k]], b = s.points[fv[(k + 1) & 3]];
    const Vec3 t = normalized(b - a);
    Vec3 d = 0.5 * (s.points[fv[(k + 2) & 3]] + s.points[fv[(k + 3) & 3]]) - 0.5 * (a + b);
    d = d - dot(d, t) * t;
    return norm(d) > 0 ? normalized(d) : d;
}

double angle_deg(const Vec3& a, const Vec3& b) {
    return std::acos(std::clamp(dot(a, b), -1.0, 1.0)) * 180 / std::numbers::pi;
}

// Faces per edge (in face order), only for the edges of degree >= 3 and the edges at their vertices.
struct LocalFaces {
    std::vector<std::vector<int>> of_edge;    // per edge (empty unless needed)
    std::vector<std::vector<int>> of_vertex;  // per vertex on a fan edge: its faces, in face order
};

// Also for the edges marked in `more` (when not empty) and the edges at their vertices, and for a flange's chain
// (edge_docked 3).
LocalFaces local_faces(const Skeleton& s, const SkeletonAnalysis& an, const std::vector<char>& more = {}) {
    const int nv = static_cast<int>(s.points.size()), ne = static_cast<int>(s.edges.size());
    std::vector<char> on_fan(nv, 0);
    for (int e = 0; e < ne; ++e)
        if (an.edge_degree[e] >= 3 || (!more.empty() && more[e]) || (!an.edge_docked.empty() && an.edge_docked[e] == 3))
            on_fan[s.edges[e][0]] = on_fan[s.edges[e][1]] = 1;
    LocalFaces lf{std::vector<std::vector<int>>(ne), std::vector<std::vector<int>>(nv)};
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int k = 0; k < 4; ++k) {
            const int w = an.face_vertices[f][k], next = an.face_vertices[f][(k + 1) & 3];
            if (on_fan[w]) lf.of_vertex[w].push_back(f);
            if (on_fan[w] || on_fan[next]) lf.of_edge[an.face_edges[f][k]].push_back(f);
        }
    return lf;
}

// How fan edge e splits into a plate and walls: plate = the leaflet of the one pair of its faces that continue across
// it (in-plane directions >= kDockPlateAngleDeg apart), walls on opposite sides (at most one per side). plate -1 and
// `why` set when it does not.
struct EdgeSplit {
    int plate = -1;
    std::array<int, 2> plate_faces{-1, -1};
    std::vector<int> walls;  // wall faces
    std::string why;
};

EdgeSplit split_fan_edge(const Skeleton& s, const SkeletonAnalysis& an, const std::vector<int>& faces, int e) {
    EdgeSplit sp;
    const int d = static_cast<int>(faces.size());
    const std::string name = "fan edge (" + std::to_string(s.edges[e][0]) + ", " + std::to_string(s.edges[e][1]) + ")";
    if (d > 4) {
        sp.why = name + " has " + std::to_string(d) +
                 " faces: a wall docks on a plate only with 3 (one wall) or 4 (one wall on each side of the plate)";
        return sp;
    }
    std::vector<Vec3> dir(d);
    for (int i = 0; i < d; ++i) dir[i] = into_face(s, an, faces[i], e);
    int pairs = 0;
    for (int i = 0; i < d; ++i)
        for (int j = i + 1; j < d; ++j)
            if (an.face_leaflet[faces[i]] == an.face_leaflet[faces[j]] &&
                angle_deg(dir[i], dir[j]) >= kDockPlateAngleDeg) {
                ++pairs;
                sp.plate_faces = {faces[i], faces[j]};
            }
    if (pairs != 1) {
        sp.why = name + (pairs == 0 ? ": no two faces of one leaflet continue across it (a plate bent by at most " +
                                          std::to_string(static_cast<int>(180 - kDockPlateAngleDeg)) + " degrees)"
                                    : ": two leaflets cross there");
        return sp;
    }
    const int plate = an.face_leaflet[sp.plate_faces[0]];
    const Vec3 n = an.face_normal[sp.plate_faces[0]];
    int sides[2] = {0, 0};
    for (int i = 0; i < d; ++i) {
        const int f = faces[i];
        if (f == sp.plate_faces[0] || f == sp.plate_faces[1]) continue;
        if (an.face_leaflet[f] == plate) {
            sp.why = name + ": a third face of the plate's leaflet stands on it";
            return sp;
        }
        sp.walls.push_back(f);
        ++sides[dot(dir[i], n) > 0 ? 0 : 1];
        const double tilt = angle_deg(dir[i], dot(dir[i], n) > 0 ? n : -1.0 * n);
        if (tilt > kDockWallTiltDeg) {
            sp.why = name + ": its wall leans " + std::to_string(static_cast<int>(std::lround(tilt))) +
                     " degrees from the plate's normal (at most " + std::to_string(static_cast<int>(kDockWallTiltDeg)) +
                     " are docked)";
            return sp;
        }
    }
    if (sides[0] > 1 || sides[1] > 1) {
        sp.why = name + ": two walls stand on the same side of the plate";
        return sp;
    }
    sp.plate = plate;
    return sp;
}

// The edges marked in `member` connected to member edge e0 through shared vertices (its component), in edge order;
// marks them in `seen`.
std::vector<int> edge_component(const Skeleton& s, const SkeletonAnalysis& an, int e0, const std::vector<char>& member,
                                std::vector<char>& seen) {
    std::vector<int> comp{e0};
    seen[e0] = 1;
    for (std::size_t i = 0; i < comp.size(); ++i)
        for (int w : s.edges[comp[i]])
            for (int j = an.vertex_edge_begin[w]; j < an.vertex_edge_begin[w + 1]; ++j) {
                const int e = an.vertex_edges[j];
                if (member[e] && !seen[e]) {
                    seen[e] = 1;
                    comp.push_back(e);
                }
            }
    std::sort(comp.begin(), comp.end());
    return comp;
}

// Edges at v by kind, for a chain vertex of plate P.
struct ChainStar {
    std::vector<int> chain;                       // chain (fan) edges at v
    int plate_faces = 0, plate_border = 0;        // P's faces and boundary edges at v
    std::vector<std::array<int, 3>> wall_counts;  // (wall leaflet, faces at v, boundary edges at v)
};

void count_wall(std::vector<std::array<int, 3>>& wc, int leaflet, int faces, int border) {
    auto it = std::find_if(wc.begin(), wc.end(), [&](const std::array<int, 3>& x) { return x[0] == leaflet; });
    if (it == wc.end()) {
        wc.push_back({leaflet, faces, border});
    } else {
        (*it)[1] += faces;
        (*it)[2] += border;
    }
}

// The star of chain vertex v (plate P): refuses a branch, another leaflet, or a wall face off the chain.
ChainStar chain_star(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf, int v, int P) {
    ChainStar st;
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (an.edge_degree[e] == 0)
            refuse(v,
                   "a branch edge on the chain of a wall docked on a plate is not supported; edit: start the branch "
                   "from a plate vertex at least one face away from the wall, or from a wall vertex off the plate");
        if (an.edge_degree[e] >= 3) {
            st.chain.push_back(e);
            continue;
        }
        const int f = lf.of_edge[e].front();
        if (an.face_leaflet[f] == P) {
            st.plate_border += an.edge_degree[e] == 1 ? 1 : 0;
        } else if (an.edge_degree[e] == 1) {
            if (an.vertex_plate[other_end(s, e, v)] >= 0)
                refuse(v,
                       "a wall's border edge joins two vertices of the chain it stands on; edit: give the wall at "
                       "least one row of faces above the plate");
            count_wall(st.wall_counts, an.face_leaflet[f], 0, 1);
        }
    }
    for (int f : lf.of_vertex[v]) {
        if (an.face_leaflet[f] == P) {
            ++st.plate_faces;
            continue;
        }
        bool on_chain = false;
        for (int c : st.chain) on_chain = on_chain || face_has_edge(an, f, c);
        if (!on_chain)
            refuse(v,
                   "a face of the wall standing on the plate touches the chain only at this vertex (the wall must "
                   "end at the chain with a border edge); edit: cut the wall's faces at the chain's end vertex");
        count_wall(st.wall_counts, an.face_leaflet[f], 1, 0);
    }
    return st;
}

}  // namespace

double band_pillow_max_turn_deg() { return std::acos(kBandPillowMinTurnCos) * 180 / std::numbers::pi; }

bool docked_foot_matches(int chain_edges, int plate_faces, int plate_border, bool straight) {
    if (chain_edges == 2) return plate_faces == 4 && plate_border == 0 && straight;
    return chain_edges == 1 && straight &&
           ((plate_faces == 4 && plate_border == 0) || (plate_faces == 2 && plate_border == 2));
}

namespace {

// What the refusal of a chain whose feet do not match the plate's grid says of the band pillow and the edit: that it
// ran and could not take the chain (ran), or that it is off.
std::string band_pillow_words(bool ran) {
    if (!ran)
        return " (the repair's band pillow, which makes such a grid match, is off: --no-docked-band-pillow or "
               "--no-resample); edit: mesh with the band pillow and resampling on, or re-sample the plate so that its "
               "grid lines follow the wall";
    return " (the repair's band pillow, which makes the grid match, did not take this chain: it needs the chain's path "
           "to run on straight through the plate's grid from each inside end to the plate's border, through vertices "
           "of 4 plate faces, no branch, no other chain, no vertex twice, turns of at most about " +
           std::to_string(std::lround(band_pillow_max_turn_deg())) +
           " degrees); edit: re-sample the plate so that its grid lines follow the wall, or so that the wall's line "
           "runs on through vertices of 4 plate faces to the border";
}

// Checks chain vertex v of a docked chain (plate P); refuses with an edit suggestion. With band_pillow, a plate grid
// that does not match the foot lists v in an.docked_unmatched instead.
void check_chain_vertex(const Skeleton& s, SkeletonAnalysis& an, const LocalFaces& lf, int v, int P, bool band_pillow,
                        bool pillow_ran) {
    const ChainStar st = chain_star(s, an, lf, v, P);
    const int nc = static_cast<int>(st.chain.size());
    bool straight = true;
    for (int f : lf.of_vertex[v]) {
        if (an.face_leaflet[f] != P) continue;
        int on = 0;
        for (int c : st.chain) on += face_has_edge(an, f, c) ? 1 : 0;
        straight = straight && on <= 1 && (nc == 1 || on == 1);
    }
    const bool ok = docked_foot_matches(nc, st.plate_faces, st.plate_border, straight);
    if (!ok && band_pillow)
        an.docked_unmatched.push_back(v);
    else if (!ok)
        refuse(v,
               "a wall docked on a plate needs the chain to run straight through the plate's grid: 4 plate faces at "
               "every chain vertex, 2 on each side of the wall (2 faces and 2 border edges where the chain ends "
               "on the plate's border); here " +
                   std::to_string(st.plate_faces) + " plate faces, " + std::to_string(nc) + " chain edges" +
                   band_pillow_words(pillow_ran));
    std::array<int, 2> side_wall{-1, -1};  // wall leaflet on the plate's up / down side at v
    for (int c : st.chain) {
        int g = -1;
        for (int h : lf.of_edge[c])
            if (an.face_leaflet[h] == P) g = h;
        for (int h : lf.of_edge[c]) {
            if (an.face_leaflet[h] == P) continue;
            int& sw = side_wall[dot(into_face(s, an, h, c), an.face_normal[g]) > 0 ? 0 : 1];
            if (sw >= 0 && sw != an.face_leaflet[h])
                refuse(v,
                       "two walls stand on the same side of the plate at this chain vertex; edit: join them into "
                       "one wall, or move one to the plate's other side or at least two plate faces away");
            sw = an.face_leaflet[h];
        }
    }
    for (const std::array<int, 3>& w : st.wall_counts) {
        int carried = 0;  // chain edges at v with a face of this wall
        for (int c : st.chain)
            for (int f : lf.of_edge[c]) carried += an.face_leaflet[f] == w[0] ? 1 : 0;
        if (w[1] != carried || w[1] + w[2] != 2)
            refuse(v, "the wall (leaflet " + std::to_string(w[0]) +
                          ") standing on the plate must meet the chain vertex with its faces on the chain edges only "
                          "and end there with one border edge; edit: cut the wall along the chain's line");
    }
}

// The end vertices of a path of fan edges (vertices on one of them), or refusal naming a vertex on three or more.
std::vector<int> chain_ends(const Skeleton& s, const std::vector<int>& comp, std::vector<int>& vertices) {
    std::vector<std::pair<int, int>> count;  // (vertex, fan edges)
    for (int e : comp)
        for (int w : s.edges[e]) {
            auto it =
                std::find_if(count.begin(), count.end(), [&](const std::pair<int, int>& x) { return x.first == w; });
            if (it == count.end())
                count.push_back({w, 1});
            else
                ++it->second;
        }
    std::sort(count.begin(), count.end());
    std::vector<int> ends;
    vertices.clear();
    for (const auto& [w, c] : count) {
        vertices.push_back(w);
        if (c == 1) ends.push_back(w);
    }
    return ends;
}

// Does the fan leave a leaflet going on past end vertex v (a leaflet with faces at the fan edge and no boundary edge
// at v: the paper's limitation 2)?
bool ends_inside(const SkeletonAnalysis& an, const LocalFaces& lf, int v, int fan_edge) {
    for (int f : lf.of_edge[fan_edge]) {
        bool border = false;
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int e = an.vertex_edges[i];
            if (an.edge_degree[e] != 1) continue;
            for (int g : lf.of_edge[e]) border = border || an.face_leaflet[g] == an.face_leaflet[f];
        }
        if (!border) return true;
    }
    return false;
}

// The leaflets with faces at fan edge e, sorted, without repeats.
std::vector<int> edge_leaflets(const SkeletonAnalysis& an, const LocalFaces& lf, int e) {
    std::vector<int> l;
    for (int f : lf.of_edge[e]) l.push_back(an.face_leaflet[f]);
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    return l;
}

// Does a leaflet along the chain stop at one of its inner vertices while the chain goes on (the two chain edges there
// carry different leaflets: a wall across a plate with a shorter wall on the other side, fan edges of degree 3 and 4
// in one chain)? Such a fan is irregular (the paper's layout refuses it), but docks like a chain ending inside.
bool leaflet_stops_on_chain(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf,
                            const std::vector<int>& comp, const std::vector<int>& vertices) {
    for (int v : vertices) {
        std::vector<int> at;  // chain edges at v
        for (int e : comp)
            if (s.edges[e][0] == v || s.edges[e][1] == v) at.push_back(e);
        if (at.size() == 2 && edge_leaflets(an, lf, at[0]) != edge_leaflets(an, lf, at[1])) return true;
    }
    return false;
}

// Does face f run through fan edge e from the edge's first vertex to its second?
bool runs_forward(const Skeleton& s, const SkeletonAnalysis& an, int f, int e) {
    int k = 0;
    while (an.face_edges[f][k] != e) ++k;
    return an.face_vertices[f][k] == s.edges[e][0];
}

// The two leaflets that continue across every edge of chain comp (one face each, in-plane directions at least
// kDockPlateAngleDeg apart), lower id first; {-1, -1} when no such pair, or more than one, exists.
std::array<int, 2> plate_halves(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf,
                                const std::vector<int>& comp) {
    std::vector<std::array<int, 2>> common;
    for (std::size_t i = 0; i < comp.size(); ++i) {
        const int e = comp[i];
        const std::vector<int>& faces = lf.of_edge[e];
        std::vector<std::array<int, 2>> pairs;
        for (std::size_t a = 0; a < faces.size(); ++a)
            for (std::size_t b = a + 1; b < faces.size(); ++b) {
                const int la = an.face_leaflet[faces[a]], lb = an.face_leaflet[faces[b]];
                if (la != lb &&
                    angle_deg(into_face(s, an, faces[a], e), into_face(s, an, faces[b], e)) >= kDockPlateAngleDeg)
                    pairs.push_back({std::min(la, lb), std::max(la, lb)});
            }
        if (i == 0) {
            common = pairs;
        } else {
            std::erase_if(common, [&](const std::array<int, 2>& c) {
                return std::find(pairs.begin(), pairs.end(), c) == pairs.end();
            });
        }
    }
    if (common.size() != 1) return {-1, -1};
    for (int e : comp) {  // one face of each half per chain edge
        int count[2] = {0, 0};
        for (int f : lf.of_edge[e])
            for (int h = 0; h < 2; ++h) count[h] += an.face_leaflet[f] == common[0][h] ? 1 : 0;
        if (count[0] != 1 || count[1] != 1) return {-1, -1};
    }
    return common[0];
}

// A chain with all ends on borders cuts its plate into two leaflets, one on each side: joins them into one (the
// second's faces take the first's id and, where needed, its orientation: opposite runs through every chain edge), so
// that the chain docks as on a plate it ends inside. False (nothing changed) when the halves are not found or their
// orientations disagree along the chain.
bool join_plate_halves(const Skeleton& s, SkeletonAnalysis& an, const LocalFaces& lf, const std::vector<int>& comp) {
    const std::array<int, 2> half = plate_halves(s, an, lf, comp);
    if (half[0] < 0) return false;
    int flip = -1;  // 1: the second half's faces run the chain edges the same way as the first's
    for (int e : comp) {
        int dir[2] = {0, 0};
        for (int f : lf.of_edge[e])
            for (int h = 0; h < 2; ++h)
                if (an.face_leaflet[f] == half[h]) dir[h] = runs_forward(s, an, f, e) ? 1 : 0;
        const int same = dir[0] == dir[1] ? 1 : 0;
        if (flip >= 0 && same != flip) return false;
        flip = same;
    }
    Leaflet& first = an.leaflets[half[0]];
    const Leaflet& second = an.leaflets[half[1]];
    for (int f : second.faces) {
        if (flip == 1) {  // as find_leaflets turns a face: (w0, w3, w2, w1), sides 3, 2, 1, 0
            std::array<int, 4>& fv = an.face_vertices[f];
            std::swap(fv[1], fv[3]);
            std::array<int, 4>& fe = an.face_edges[f];
            fe = {fe[3], fe[2], fe[1], fe[0]};
            an.face_normal[f] = -1.0 * an.face_normal[f];
        }
        first.faces.push_back(f);
    }
    std::sort(first.faces.begin(), first.faces.end());
    first.orientable = first.orientable && second.orientable;
    an.leaflets.erase(an.leaflets.begin() + half[1]);
    for (int& l : an.face_leaflet)
        if (l == half[1])
            l = half[0];
        else if (l > half[1])
            --l;
    return true;
}

// Docks component comp if it is a chain with an end inside a leaflet, or a chain across a plate whose halves
// join_across_chain joined; refuses a chain ending inside that cannot be docked. Other chains with all ends on borders
// stay fans (the paper's layout, or the irregular-fan refusal).
// The chain's end vertex inside a leaflet (-1: every end on a border).
int inside_end(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf, const std::vector<int>& comp) {
    std::vector<int> vertices;
    int inside = -1;
    for (int v : chain_ends(s, comp, vertices))
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1] && inside < 0; ++i) {
            const int e = an.vertex_edges[i];
            if (an.edge_degree[e] >= 3 && ends_inside(an, lf, v, e)) inside = v;
        }
    return inside;
}

// A chain with all ends on borders that cuts its plate into two leaflets, with a leaflet stopping on it: joins the
// halves (join_plate_halves) when every chain edge then splits into that one plate and walls. True when joined; else
// the analysis is left exactly as it was (the chain stays a fan). The one test of such a chain: the repair's view of
// docked plates takes it through join_plates_across_chains.
bool join_across_chain(const Skeleton& s, SkeletonAnalysis& an, const LocalFaces& lf, const std::vector<int>& comp) {
    std::vector<int> vertices;
    if (chain_ends(s, comp, vertices).size() != 2 || inside_end(s, an, lf, comp) >= 0 ||
        !leaflet_stops_on_chain(s, an, lf, comp, vertices))
        return false;
    SkeletonAnalysis joined = an;
    if (!join_plate_halves(s, joined, lf, comp)) return false;
    int plate = -1;
    for (int e : comp) {
        const EdgeSplit sp = split_fan_edge(s, joined, lf.of_edge[e], e);
        if (sp.plate < 0 || (plate >= 0 && sp.plate != plate)) return false;
        plate = sp.plate;
    }
    an = std::move(joined);
    return true;
}

// Leaflet candidates for the plate of a border chain at chain edge e (face leaflets `leaf`): a leaflet with exactly one
// face at e whose other faces are other leaflets within kDockWallTiltDeg of its normal, at most one on each side.
std::vector<int> border_plate_candidates(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf,
                                         const std::vector<int>& leaf, int e) {
    std::vector<int> out;
    for (int f : lf.of_edge[e]) {
        const int l = leaf[f];
        if (std::count_if(lf.of_edge[e].begin(), lf.of_edge[e].end(), [&](int g) { return leaf[g] == l; }) != 1)
            continue;
        const Vec3 n = an.face_normal[f];
        int sides[2] = {0, 0};
        bool ok = true;
        for (int g : lf.of_edge[e]) {
            if (g == f) continue;
            const Vec3 d = into_face(s, an, g, e);
            ok = ok && leaf[g] != l && angle_deg(d, dot(d, n) > 0 ? n : -1.0 * n) <= kDockWallTiltDeg;
            ++sides[dot(d, n) > 0 ? 0 : 1];
        }
        if (ok && sides[0] <= 1 && sides[1] <= 1) out.push_back(l);
    }
    return out;
}

// The angle (degrees) between the directions from v to the other ends of edges a and b.
double edge_angle_deg(const Skeleton& s, int v, int a, int b) {
    const Vec3 da = s.points[other_end(s, a, v)] - s.points[v];
    const Vec3 db = s.points[other_end(s, b, v)] - s.points[v];
    return norm(da) > 0 && norm(db) > 0 ? angle_deg(normalized(da), normalized(db)) : 0;
}

// Does chain vertex v (an end or not) meet the border-chain conditions for plate P (see border_chain_plate)? 0 no,
// 1 yes, 2 yes at an end on P's corner (a corner cube: one face of P, its border turning within kCornerCubeMaxSkewDeg
// of a right angle).
int border_chain_vertex(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf,
                        const std::vector<int>& leaf, const std::vector<int>& comp, const std::vector<int>& vertices,
                        int v, bool end, int P) {
    auto in_comp = [&](int e) { return std::find(comp.begin(), comp.end(), e) != comp.end(); };
    int chain_edge = -1, chain_edges = 0, border = -1, plate_faces = 0;
    std::vector<std::array<int, 3>> walls;  // (leaflet, faces, border edges)
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (in_comp(e)) {
            chain_edge = e;
            ++chain_edges;
            continue;
        }
        if (an.edge_degree[e] == 0 || an.edge_degree[e] >= 3) return 0;
        const int l = leaf[lf.of_edge[e].front()];
        if (an.edge_degree[e] == 2) {
            if (leaf[lf.of_edge[e].back()] != l) return 0;
            continue;
        }
        if (l == P) {
            if (border >= 0) return 0;
            border = e;
        } else {
            if (std::find(vertices.begin(), vertices.end(), other_end(s, e, v)) != vertices.end()) return 0;
            count_wall(walls, l, 0, 1);
        }
    }
    if (chain_edges != (end ? 1 : 2)) return 0;
    for (int f : lf.of_vertex[v]) {
        int on = 0;
        for (int e : comp) on += face_has_edge(an, f, e) ? 1 : 0;
        if (leaf[f] == P) {
            if (on > 1 || (!end && on != 1)) return 0;  // the chain runs straight along P's grid
            ++plate_faces;
            continue;
        }
        if (on == 0) return 0;
        count_wall(walls, leaf[f], 1, 0);
    }
    const bool corner = end && plate_faces == 1;
    if ((plate_faces != 2 && !corner) || (end ? border < 0 : border >= 0)) return 0;
    for (const std::array<int, 3>& w : walls)
        if (w[1] != (end ? 1 : 2) || w[2] != (end ? 1 : 0)) return 0;
    if (!end) return 1;
    const double turn = edge_angle_deg(s, v, border, chain_edge);
    if (corner) return std::abs(turn - 90) <= kCornerCubeMaxSkewDeg ? 2 : 0;
    return turn >= kDockPlateAngleDeg ? 1 : 0;
}

// The plate of a wall standing on part of a plate's border (a flange): chain comp (face leaflets `leaf`) is a path
// whose every edge has exactly one face of leaflet P and walls (other leaflets) within kDockWallTiltDeg of P's normal,
// at most one per side; at every inner chain vertex P has 2 faces, each on one chain edge, and no border edge off the
// chain, at each end 2 faces and one border edge off the chain continuing the chain's line (at least
// kDockPlateAngleDeg from the chain edge: P's border runs on past the end), or at one end (not both) P's corner: one
// face, on the chain edge, and a border edge off the chain within kCornerCubeMaxSkewDeg of a right angle to it (its
// vertex returned in `cube`, else -1); no branch edge, no fan edge off the chain and no other leaflet at a chain
// vertex; each wall has only faces on chain edges at a chain vertex, and at an end one face and one border edge not
// joining two chain vertices. The one leaflet passing, or -1 (nothing docked) otherwise.
int border_chain_plate(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf,
                       const std::vector<int>& leaf, const std::vector<int>& comp, int& cube) {
    cube = -1;
    std::vector<int> vertices;
    const std::vector<int> ends = chain_ends(s, comp, vertices);
    if (ends.size() != 2) return -1;
    std::vector<int> candidates;
    for (std::size_t i = 0; i < comp.size(); ++i) {
        const std::vector<int> here = border_plate_candidates(s, an, lf, leaf, comp[i]);
        if (i == 0)
            candidates = here;
        else
            std::erase_if(candidates, [&](int l) { return std::find(here.begin(), here.end(), l) == here.end(); });
    }
    int plate = -1, passing = 0, corner = -1;
    for (int P : candidates) {
        int corners = 0, at = -1;
        bool ok = true;
        for (int v : vertices) {
            const int k = ok ? border_chain_vertex(s, an, lf, leaf, comp, vertices, v,
                                                   std::find(ends.begin(), ends.end(), v) != ends.end(), P)
                             : 0;
            ok = k > 0;
            if (k == 2) ++corners, at = v;
        }
        if (ok && corners <= 1) plate = P, corner = at, ++passing;
    }
    if (passing != 1) return -1;
    cube = corner;
    return plate;
}

// Marks chain comp as docked on plate P's border (edge_docked 3, its vertices' plate P, the walls' border edges at
// them 2) and P's corner `cube` (or -1) as a corner cube.
void dock_on_border(const Skeleton& s, SkeletonAnalysis& an, const LocalFaces& lf, const std::vector<int>& comp, int P,
                    int cube) {
    std::vector<int> vertices;
    (void)chain_ends(s, comp, vertices);
    if (cube >= 0) an.corner_cube[cube] = 1;
    for (int e : comp) an.edge_docked[e] = 3;
    for (int v : vertices) an.vertex_plate[v] = P;
    for (int v : vertices)
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int e = an.vertex_edges[i];
            if (an.edge_degree[e] == 1 && an.face_leaflet[lf.of_edge[e].front()] != P) an.edge_docked[e] = 2;
        }
}

void dock_component(const Skeleton& s, SkeletonAnalysis& an, const LocalFaces& lf, const std::vector<int>& comp,
                    bool across, bool band_pillow, bool pillow_ran) {
    std::vector<int> vertices;
    (void)chain_ends(s, comp, vertices);
    const int inside = across ? -1 : inside_end(s, an, lf, comp);
    if (inside < 0 && !across) {  // a flange: docked on its plate's border, or a fan
        int cube = -1;
        const int P = border_chain_plate(s, an, lf, an.face_leaflet, comp, cube);
        if (P >= 0) dock_on_border(s, an, lf, comp, P, cube);
        return;
    }
    int plate = -1;
    for (int e : comp) {
        const EdgeSplit sp = split_fan_edge(s, an, lf.of_edge[e], e);
        if (sp.plate < 0 || (plate >= 0 && sp.plate != plate))
            refuse(inside,
                   "a fan edge chain ends inside a leaflet here (paper limitation 2) and cannot be docked as "
                   "walls standing on a plate: " +
                       (sp.plate < 0 ? sp.why : std::string("its edges stand on two different plates")) +
                       "; edit: let one leaflet (the plate) continue straight across every chain edge with at "
                       "most one wall on each side, or end every leaflet at the chain's end with its own "
                       "border edge");
        plate = sp.plate;
    }
    for (int v : vertices) {
        int on = 0;
        for (int e : comp) on += s.edges[e][0] == v || s.edges[e][1] == v ? 1 : 0;
        if (on > 2)
            refuse(v,
                   "three or more fan edges of a wall's chain meet here; edit: split the walls so that each stands on "
                   "one straight chain");
    }
    for (int e : comp) an.edge_docked[e] = 1;
    for (int v : vertices) an.vertex_plate[v] = plate;
    for (int v : vertices) check_chain_vertex(s, an, lf, v, plate, band_pillow, pillow_ran);
    for (int v : vertices)
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int e = an.vertex_edges[i];
            if (an.edge_degree[e] == 1 && an.face_leaflet[lf.of_edge[e].front()] != plate) an.edge_docked[e] = 2;
        }
}

}  // namespace

namespace {

// The fan-edge components (chains) of the analysis, each as its edges.
std::vector<std::vector<int>> fan_components(const Skeleton& s, const SkeletonAnalysis& an) {
    const int ne = static_cast<int>(s.edges.size());
    std::vector<char> seen(ne, 0), fan(ne, 0);
    for (int e = 0; e < ne; ++e) fan[e] = an.edge_degree[e] >= 3;
    std::vector<std::vector<int>> comps;
    for (int e = 0; e < ne; ++e)
        if (fan[e] && !seen[e]) comps.push_back(edge_component(s, an, e, fan, seen));
    return comps;
}

// Per component: 1 when join_across_chain joined its plate's halves. Every plate a chain cuts in two is joined before
// any chain docks: a join renumbers the leaflets and turns the second half's faces, which must not happen under a
// chain already docked on them.
std::vector<char> join_across_chains(const Skeleton& s, SkeletonAnalysis& an, const LocalFaces& lf,
                                     const std::vector<std::vector<int>>& comps) {
    std::vector<char> across(comps.size(), 0);
    for (std::size_t i = 0; i < comps.size(); ++i) across[i] = join_across_chain(s, an, lf, comps[i]) ? 1 : 0;
    return across;
}

}  // namespace

namespace {

// Fold edges: degree 2, one face within kDockWallTiltDeg of the other's normal (a crease of at least 45 degrees).
std::vector<char> fold_edges(const Skeleton& s, const SkeletonAnalysis& an) {
    const int ne = static_cast<int>(s.edges.size());
    std::vector<std::array<int, 2>> faces(ne, {-1, -1});
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int e : an.face_edges[f])
            if (an.edge_degree[e] == 2) faces[e][faces[e][0] < 0 ? 0 : 1] = f;
    std::vector<char> fold(ne, 0);
    for (int e = 0; e < ne; ++e) {
        if (an.edge_degree[e] != 2 || faces[e][1] < 0) continue;
        for (int i = 0; i < 2; ++i) {
            const Vec3 n = an.face_normal[faces[e][i]], d = into_face(s, an, faces[e][1 - i], e);
            if (norm(n) > 0 && norm(d) > 0 && angle_deg(d, dot(d, n) > 0 ? n : -1.0 * n) <= kDockWallTiltDeg)
                fold[e] = 1;
        }
    }
    return fold;
}

// The faces reached from face f0 through adjacency adj, marked in `part` (1).
void flood_part(const std::vector<std::vector<int>>& adj, int f0, std::vector<char>& part) {
    std::vector<int> queue{f0};
    part[f0] = 1;
    for (std::size_t i = 0; i < queue.size(); ++i)
        for (int g : adj[queue[i]])
            if (!part[g]) {
                part[g] = 1;
                queue.push_back(g);
            }
}

// A crease chain of one leaflet (fold edges, a path) cutting it in two: the face leaflets with the part not holding
// the first chain edge's first face given a new leaflet id (an.leaflets.size()); empty when the chain does not cut.
std::vector<int> cut_leaflets(const SkeletonAnalysis& an, const LocalFaces& lf, const std::vector<int>& comp) {
    const int l = an.face_leaflet[lf.of_edge[comp[0]].front()];
    for (int e : comp)
        for (int f : lf.of_edge[e])
            if (an.face_leaflet[f] != l) return {};
    const int nf = static_cast<int>(an.face_vertices.size());
    std::vector<std::vector<int>> adj(nf);
    std::vector<int> first(an.edge_degree.size(), -1);  // per edge: the first face of l met on it
    for (int f : an.leaflets[l].faces)
        for (int e : an.face_edges[f]) {
            if (an.edge_degree[e] != 2 || std::find(comp.begin(), comp.end(), e) != comp.end()) continue;
            if (first[e] < 0) {
                first[e] = f;
            } else {
                adj[f].push_back(first[e]);
                adj[first[e]].push_back(f);
            }
        }
    std::vector<char> a(nf, 0), b(nf, 0);
    flood_part(adj, lf.of_edge[comp[0]].front(), a);
    for (int f : an.leaflets[l].faces)
        if (!a[f]) {
            flood_part(adj, f, b);
            break;
        }
    std::vector<int> leaf = an.face_leaflet;
    for (int f : an.leaflets[l].faces) {
        if (a[f] == b[f]) return {};  // in neither part (a third part) or both: not a cut in two
        if (b[f]) leaf[f] = static_cast<int>(an.leaflets.size());
    }
    for (int e : comp)
        if (leaf[lf.of_edge[e].front()] == leaf[lf.of_edge[e].back()]) return {};
    return leaf;
}

// A cheap first test of a fold chain (border_chain_vertex decides): a path, no branch or fan edge at its vertices,
// and 2 border edges at each end (the plate's and the wall's), none at an inner vertex.
bool flange_crease_star(const Skeleton& s, const SkeletonAnalysis& an, const std::vector<int>& comp) {
    std::vector<int> vertices;
    const std::vector<int> ends = chain_ends(s, comp, vertices);
    if (ends.size() != 2) return false;
    for (int v : vertices) {
        int border = 0, on = 0;
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int e = an.vertex_edges[i], d = an.edge_degree[e];
            if (d == 0 || d >= 3) return false;
            border += d == 1 ? 1 : 0;
            on += std::find(comp.begin(), comp.end(), e) != comp.end() ? 1 : 0;
        }
        const bool end = std::find(ends.begin(), ends.end(), v) != ends.end();
        if (on > 2 || border != (end ? 2 : 0)) return false;
    }
    return true;
}

// Flanges on one creased leaflet (a wall standing on part of a plate's border, both one leaflet: `flangeup`): every
// path of fold edges (fold_edges) that cuts its leaflet in two, one part of which is a plate P whose border runs on in
// line past both chain ends (border_chain_plate with the cut leaflets), is cut there (the other part becomes a new
// leaflet, a wall) and docked on P's border. Leaflets and faces are otherwise unchanged.
void cut_border_creases(const Skeleton& s, SkeletonAnalysis& an) {
    const std::vector<char> fold = fold_edges(s, an);
    if (std::none_of(fold.begin(), fold.end(), [](char c) { return c != 0; })) return;
    const int ne = static_cast<int>(s.edges.size());
    std::vector<char> seen(ne, 0);
    for (int e0 = 0; e0 < ne; ++e0) {
        if (!fold[e0] || seen[e0]) continue;
        const std::vector<int> comp = edge_component(s, an, e0, fold, seen);
        if (!flange_crease_star(s, an, comp)) continue;
        std::vector<char> mark(ne, 0);
        for (int e : comp) mark[e] = 1;
        const LocalFaces lf = local_faces(s, an, mark);
        const std::vector<int> leaf = cut_leaflets(an, lf, comp);
        if (leaf.empty()) continue;
        int cube = -1;
        const int P = border_chain_plate(s, an, lf, leaf, comp, cube);
        if (P < 0) continue;
        const int l = an.face_leaflet[lf.of_edge[comp[0]].front()];
        Leaflet wall{{}, an.leaflets[l].orientable};
        std::erase_if(an.leaflets[l].faces, [&](int f) { return leaf[f] != l; });
        for (int f = 0; f < static_cast<int>(leaf.size()); ++f)
            if (leaf[f] != an.face_leaflet[f]) wall.faces.push_back(f);
        an.leaflets.push_back(wall);
        an.face_leaflet = leaf;
        dock_on_border(s, an, lf, comp, P, cube);
    }
}

}  // namespace

std::vector<char> join_plates_across_chains(const Skeleton& s, SkeletonAnalysis& an) {
    std::vector<char> on(s.edges.size(), 0);
    if (std::none_of(an.edge_degree.begin(), an.edge_degree.end(), [](int d) { return d >= 3; })) return on;
    const LocalFaces lf = local_faces(s, an);
    const std::vector<std::vector<int>> comps = fan_components(s, an);
    const std::vector<char> across = join_across_chains(s, an, lf, comps);
    for (std::size_t i = 0; i < comps.size(); ++i)
        for (int e : comps[i]) on[e] = across[i];
    return on;
}

void find_docked_walls(const Skeleton& s, SkeletonAnalysis& an, bool band_pillow, bool pillow_ran) {
    const int nv = static_cast<int>(s.points.size()), ne = static_cast<int>(s.edges.size());
    an.edge_docked.assign(ne, 0);
    an.vertex_plate.assign(nv, -1);
    an.corner_cube.assign(nv, 0);
    an.docked_unmatched.clear();
    cut_border_creases(s, an);
    if (std::none_of(an.edge_degree.begin(), an.edge_degree.end(), [](int d) { return d >= 3; })) return;
    const LocalFaces lf = local_faces(s, an);
    const std::vector<std::vector<int>> comps = fan_components(s, an);
    const std::vector<char> across = join_across_chains(s, an, lf, comps);
    for (std::size_t i = 0; i < comps.size(); ++i)
        dock_component(s, an, lf, comps[i], across[i] != 0, band_pillow, pillow_ran);
}

int corner_cube_column(const SkeletonAnalysis& an, int f, int c, int e) {
    return an.face_edges[f][face_corner(an, f, c)] == e ? kCornerCubeColumnA : kCornerCubeColumnB;
}

VertexClass docked_vertex_class(const SkeletonAnalysis& an, int v, int& plate_boundary_edges) {
    plate_boundary_edges = 0;
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if ((an.edge_degree[e] == 1 && an.edge_docked[e] != 2) || an.edge_docked[e] == 3) ++plate_boundary_edges;
    }
    return plate_boundary_edges == 2 ? VertexClass::LeafletBoundary : VertexClass::LeafletInterior;
}

namespace {

// What a wall's face corner at a docked chain vertex w stands on: the chain edge c of face f at w, the wall's side of
// the plate (up), the plate faces g+ / g- at c on the wall's +n / -n side and sigma+-, and at the wall's end its
// boundary edge and what lies beyond: the plate's border (border) or the faces k+- with x, x+-.
struct WallCorner {
    int c = -1, end_edge = -1;
    bool up = true, border = false;
    bool on_border = false;   // the chain is on the plate's border (edge_docked 3): g- = -1, one side on P's out copy
    bool plate_plus = false;  // on_border: P lies on the wall's +n side (else its -n side)
    int g_plus = -1, g_minus = -1, sigma_plus = -1, sigma_minus = -1;
    int x = -1, x_plus = -1, x_minus = -1;
    std::array<int, 2> beyond{-1, -1};  // kind-0 faces k+ / k- (inside) or kind-1 plate border edges at w (border)
};

// The corner of plate face g adjacent to w other than `not_this`.
int adjacent_corner(const SkeletonAnalysis& an, int g, int w, int not_this) {
    const int k = face_corner(an, g, w);
    const int a = an.face_vertices[g][(k + 1) & 3], b = an.face_vertices[g][(k + 3) & 3];
    return a == not_this ? b : a;
}

// wall_corner for a chain on P's border (edge_docked 3): g+ = P's one face at c whatever the wall's side, sigma+ its
// corner next to w off the chain; up_is_plus says whether P lies on the wall's +n side. At the wall's end: x = P's
// border neighbour of w off the chain, beyond = (P's other face at w, its border edge (w, x)), x+ that face's corner
// opposite w.
WallCorner border_wall_corner(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf, int f, int w,
                              WallCorner wc) {
    const int P = an.vertex_plate[w];
    wc.on_border = true;
    for (int h : lf.of_edge[wc.c])
        if (an.face_leaflet[h] == P) wc.g_plus = h;
    wc.up = dot(into_face(s, an, f, wc.c), an.face_normal[wc.g_plus]) > 0;
    wc.plate_plus = dot(into_face(s, an, wc.g_plus, wc.c), an.face_normal[f]) > 0;
    wc.sigma_plus = adjacent_corner(an, wc.g_plus, w, other_end(s, wc.c, w));
    if (wc.end_edge < 0) return wc;
    for (int i = an.vertex_edge_begin[w]; i < an.vertex_edge_begin[w + 1]; ++i) {
        const int e = an.vertex_edges[i];
        if (an.edge_degree[e] == 1 && an.face_leaflet[lf.of_edge[e].front()] == P) {
            wc.beyond[1] = e;
            wc.x = other_end(s, e, w);
        }
    }
    for (int h : lf.of_vertex[w])
        if (an.face_leaflet[h] == P && h != wc.g_plus) {
            wc.beyond[0] = h;
            wc.x_plus = an.face_vertices[h][(face_corner(an, h, w) + 2) & 3];
        }
    return wc;
}

WallCorner wall_corner(const Skeleton& s, const SkeletonAnalysis& an, const LocalFaces& lf, int f, int k) {
    WallCorner wc;
    const int w = an.face_vertices[f][k], P = an.vertex_plate[w];
    const int e0 = an.face_edges[f][k], e1 = an.face_edges[f][(k + 3) & 3];
    wc.c = an.edge_docked[e0] == 1 || an.edge_docked[e0] == 3 ? e0 : e1;
    const int other = wc.c == e0 ? e1 : e0;
    if (an.edge_docked[other] == 2) wc.end_edge = other;
    if (an.edge_docked[wc.c] == 3) return border_wall_corner(s, an, lf, f, w, wc);
    std::array<int, 2> g{-1, -1};
    int ng = 0;
    for (int h : lf.of_edge[wc.c])
        if (an.face_leaflet[h] == P && ng < 2) g[ng++] = h;
    wc.up = dot(into_face(s, an, f, wc.c), an.face_normal[g[0]]) > 0;
    const bool first_plus = dot(into_face(s, an, g[0], wc.c), an.face_normal[f]) > 0;
    wc.g_plus = first_plus ? g[0] : g[1];
    wc.g_minus = first_plus ? g[1] : g[0];
    const int u = other_end(s, wc.c, w);
    wc.sigma_plus = adjacent_corner(an, wc.g_plus, w, u);
    wc.sigma_minus = adjacent_corner(an, wc.g_minus, w, u);
    if (wc.end_edge < 0) return wc;
    wc.border = an.vertex_class[w] == VertexClass::LeafletBoundary;
    if (wc.border) {  // the plate's two border edges at w, (w, sigma+) first
        for (int i = an.vertex_edge_begin[w]; i < an.vertex_edge_begin[w + 1]; ++i) {
            const int e = an.vertex_edges[i];
            if (an.edge_degree[e] != 1 || an.edge_docked[e] == 2) continue;
            const int o = other_end(s, e, w);
            if (o == wc.sigma_plus || o == wc.sigma_minus) wc.beyond[o == wc.sigma_plus ? 0 : 1] = e;
        }
        return wc;
    }
    // Inside: k+ / k- = the plate faces at w off the chain edge, sharing (w, sigma+) / (w, sigma-); x = their common
    // neighbour of w, x+- their corners opposite w.
    for (int h : lf.of_vertex[w]) {
        if (an.face_leaflet[h] != P || face_has_edge(an, h, wc.c)) continue;
        const int kh = face_corner(an, h, w);
        const int a = an.face_vertices[h][(kh + 1) & 3], b = an.face_vertices[h][(kh + 3) & 3];
        const int i = a == wc.sigma_plus || b == wc.sigma_plus     ? 0
                      : a == wc.sigma_minus || b == wc.sigma_minus ? 1
                                                                   : -1;
        if (i < 0) continue;
        const int sigma = i == 0 ? wc.sigma_plus : wc.sigma_minus;
        wc.beyond[i] = h;
        (i == 0 ? wc.x_plus : wc.x_minus) = an.face_vertices[h][(kh + 2) & 3];
        wc.x = a == sigma ? b : a;
    }
    return wc;
}

// Calls fn(f, k, WallCorner) for every wall face corner at a docked chain vertex, in face order.
template <class Fn>
void for_wall_corners(const Skeleton& s, const SkeletonAnalysis& an, Fn&& fn) {
    if (std::none_of(an.edge_docked.begin(), an.edge_docked.end(), [](char d) { return d == 1 || d == 3; })) return;
    const LocalFaces lf = local_faces(s, an);
    for (int f = 0; f < static_cast<int>(an.face_vertices.size()); ++f)
        for (int k = 0; k < 4; ++k) {
            const int w = an.face_vertices[f][k];
            if (an.vertex_plate[w] < 0 || an.face_leaflet[f] == an.vertex_plate[w]) continue;
            fn(f, k, wall_corner(s, an, lf, f, k));
        }
}

}  // namespace

std::vector<FootQuad> docked_foot_quads(const Skeleton& s, const SkeletonAnalysis& an) {
    std::vector<FootQuad> quads;
    auto check = [&](int v, int w) {
        const VertexClass c = an.vertex_class[w];
        if (c != VertexClass::LeafletInterior && c != VertexClass::LeafletBoundary)
            refuse(v, "the foot of the wall docked here (the plate faces next to the chain) reaches skeleton vertex " +
                          std::to_string(w) + ", a " + to_string(c) +
                          "; edit: keep junctions, fans and branch roots at least one plate face away from the wall");
    };
    for_wall_corners(s, an, [&](int f, int k, const WallCorner& wc) {
        const int w = an.face_vertices[f][k], wall = an.face_leaflet[f];
        if (wc.on_border) {  // on P's border: on g+ and c's half-chunk; the end on (w, x)'s plate and half-chunk
            if (w == std::min(s.edges[wc.c][0], s.edges[wc.c][1])) {
                for (int x : an.face_vertices[wc.g_plus]) check(w, x);
                quads.push_back({0, wc.g_plus, wc.up, wall, w});
                quads.push_back({1, wc.c, wc.up, wall, w});
            }
            if (wc.end_edge < 0) return;
            if (has_corner_cube(an, w)) {  // on the half-chunk of (w, sigma+) and on the corner cube
                check(w, wc.x);
                quads.push_back({1, wc.beyond[1], wc.up, wall, w});
                quads.push_back({2, w, wc.up, wall, w});
                return;
            }
            if (wc.beyond[0] < 0 || wc.beyond[1] < 0) refuse(w, "the plate beyond the wall's end is not 2 faces wide");
            for (int x : an.face_vertices[wc.beyond[0]]) check(w, x);
            quads.push_back({0, wc.beyond[0], wc.up, wall, w});
            quads.push_back({1, wc.beyond[1], wc.up, wall, w});
            return;
        }
        // The wall's two plate hexes on the chain edge c stand on g+ and g-: counted once, at c's first end.
        if (w == std::min(s.edges[wc.c][0], s.edges[wc.c][1]))
            for (int g : {wc.g_plus, wc.g_minus}) {
                for (int x : an.face_vertices[g]) check(w, x);
                quads.push_back({0, g, wc.up, wall, w});
            }
        if (wc.end_edge < 0) return;
        for (int b : wc.beyond) {
            if (b < 0) refuse(w, "the plate beyond the wall's end is not a 2 x 2 patch of faces");
            if (wc.border) {
                for (int x : s.edges[b]) check(w, x);
            } else {
                for (int x : an.face_vertices[b]) check(w, x);
            }
            quads.push_back({wc.border ? 1 : 0, b, wc.up, wall, w});
        }
    });
    return quads;
}

std::vector<std::array<int, 6>> docked_corner_ids(const Skeleton& s, const SkeletonAnalysis& an,
                                                  const std::vector<int>& base) {
    std::vector<std::array<int, 6>> ids;
    for_wall_corners(s, an, [&](int f, int k, const WallCorner& wc) {
        if (ids.empty()) ids.assign(4 * an.face_vertices.size(), std::array<int, 6>{-1, -1, -1, -1, -1, -1});
        const int w = an.face_vertices[f][k];
        const int x = wc.up ? 1 : 2;   // plate copy on the wall's side: up (+1) or down (+2)
        const int xo = wc.up ? 4 : 5;  // out copy on that side: out-up (+4) or out-down (+5)
        std::array<int, 6>& id = ids[4 * f + k];
        id[0] = base[w] + x;
        if (wc.on_border) {  // P's side: its X copies; the other side: P's out copies on the wall's side (XO)
            const int p = wc.plate_plus ? 1 : 2, o = wc.plate_plus ? 2 : 1;
            id[p] = base[wc.sigma_plus] + x;
            id[o] = base[w] + xo;
            if (has_corner_cube(an, w)) {  // the chain's own column at w; the end on (w, x)'s column and K
                const int chain = corner_cube_column(an, wc.g_plus, w, wc.c);
                id[o] = base[w] + chain + x;
                if (wc.end_edge < 0) return;
                id[3] = base[w] + (15 - chain) + x;
                id[3 + p] = base[wc.x] + xo;
                id[3 + o] = base[w] + xo;
                return;
            }
            if (wc.end_edge < 0) return;
            id[3] = base[wc.x] + x;
            id[3 + p] = base[wc.x_plus] + x;
            id[3 + o] = base[wc.x] + xo;
            return;
        }
        id[1] = base[wc.sigma_plus] + x;
        id[2] = base[wc.sigma_minus] + x;
        if (wc.end_edge < 0) return;
        if (wc.border) {
            id[3] = base[w] + xo;
            id[4] = base[wc.sigma_plus] + xo;
            id[5] = base[wc.sigma_minus] + xo;
        } else {
            id[3] = base[wc.x] + x;
            id[4] = base[wc.x_plus] + x;
            id[5] = base[wc.x_minus] + x;
        }
    });
    return ids;
}

}  // namespace mesohex
