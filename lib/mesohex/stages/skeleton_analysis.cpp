#include "mesohex/stages/skeleton_analysis.h"
#include "mesohex/core/union_find.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <sstream>

#include "mesohex/core/error.h"
#include "mesohex/stages/docked_walls.h"
#include "mesohex/stages/fan_end_repair.h"

namespace mesohex {

const char* to_string(VertexClass c) {
    switch (c) {
        case VertexClass::Isolated: return "isolated";
        case VertexClass::Extremity: return "extremity";
        case VertexClass::Joint: return "joint";
        case VertexClass::BranchingPoint: return "branching_point";
        case VertexClass::LeafletInterior: return "leaflet_interior";
        case VertexClass::LeafletBoundary: return "leaflet_boundary";
        case VertexClass::BLJoint: return "bl_joint";
        case VertexClass::LLJoint: return "ll_joint";
        case VertexClass::FanEdgeVertex: return "fan_edge_vertex";
        case VertexClass::FanEdgeEnd: return "fan_edge_end";
    }
    return "?";
}

namespace {

[[noreturn]] void fail(ErrorCode code, const std::string& msg, ElementRef::Kind kind, int index) {
    throw Error(code, msg, ElementRef{kind, index});
}

double angle_between_deg(const Vec3& a, const Vec3& b) {
    return std::acos(std::clamp(dot(a, b) / (norm(a) * norm(b)), -1.0, 1.0)) * 180 / std::numbers::pi;
}

std::string branch_inside_leaflet(int branch_edges, int faces) {
    return "a leaflet interior vertex carries a branch only where 4 faces of one leaflet meet and one branch leaves "
           "(here " +
           std::to_string(branch_edges) + " branch edge(s), " + std::to_string(faces) +
           " faces; the paper's limitation 1 otherwise); edit: keep one branch per vertex and re-sample the leaflet so "
           "that 4 of its faces meet there, or start the branch from a vertex on the leaflet's border";
}

// Edge between a and b among a's incident edges (smallest id), or -1.
int edge_between(const SkeletonAnalysis& an, const Skeleton& s, int a, int b) {
    for (int i = an.vertex_edge_begin[a]; i < an.vertex_edge_begin[a + 1]; ++i) {
        const int e = an.vertex_edges[i];
        const std::array<int, 2>& ed = s.edges[e];
        if ((ed[0] == a && ed[1] == b) || (ed[0] == b && ed[1] == a)) return e;
    }
    return -1;
}

void validate_input(const Skeleton& s, const AnalysisOptions& opt) {
    const int nv = static_cast<int>(s.points.size());
    for (int v = 0; v < nv; ++v)
        if (!is_finite(s.points[v]))
            fail(ErrorCode::InvalidInput, "skeleton vertex " + std::to_string(v) + " has a non-finite position",
                 ElementRef::Kind::SkeletonVertex, v);
    if (!s.radii.empty() && s.radii.size() != s.points.size())
        fail(ErrorCode::InvalidInput,
             "skeleton has " + std::to_string(s.radii.size()) + " radii for " + std::to_string(nv) + " vertices",
             ElementRef::Kind::None, -1);
    for (int e = 0; e < static_cast<int>(s.edges.size()); ++e) {
        const std::array<int, 2>& ed = s.edges[e];
        if (ed[0] < 0 || ed[0] >= nv || ed[1] < 0 || ed[1] >= nv)
            fail(ErrorCode::InvalidInput, "skeleton edge " + std::to_string(e) + " names a vertex out of range",
                 ElementRef::Kind::SkeletonEdge, e);
        if (ed[0] == ed[1])
            fail(ErrorCode::InvalidInput,
                 "skeleton edge " + std::to_string(e) + " is a self-loop on vertex " + std::to_string(ed[0]),
                 ElementRef::Kind::SkeletonEdge, e);
        if (!(distance(s.points[ed[0]], s.points[ed[1]]) > opt.min_edge_length))
            fail(ErrorCode::InvalidInput,
                 "skeleton edge " + std::to_string(e) + " (" + std::to_string(ed[0]) + ", " + std::to_string(ed[1]) +
                     ") has zero length",
                 ElementRef::Kind::SkeletonEdge, e);
    }
    for (int f = 0; f < static_cast<int>(s.faces.size()); ++f) {
        const std::vector<int>& face = s.faces[f];
        if (face.size() != 4)
            fail(ErrorCode::InvalidInput,
                 "skeleton face " + std::to_string(f) + " has " + std::to_string(face.size()) +
                     " vertices; leaflets must be made of quads",
                 ElementRef::Kind::SkeletonFace, f);
        for (int k = 0; k < 4; ++k) {
            if (face[k] < 0 || face[k] >= nv)
                fail(ErrorCode::InvalidInput, "skeleton face " + std::to_string(f) + " names a vertex out of range",
                     ElementRef::Kind::SkeletonFace, f);
            for (int j = 0; j < k; ++j)
                if (face[j] == face[k])
                    fail(ErrorCode::InvalidInput,
                         "skeleton face " + std::to_string(f) + " repeats vertex " + std::to_string(face[k]),
                         ElementRef::Kind::SkeletonFace, f);
        }
    }
}

}  // namespace

BorderRoot border_root(const Vec3& d1, const Vec3& d2, const Vec3& inward, const Vec3& normal, const Vec3& branch,
                       int faces, double radius_over_edge) {
    const double border_angle = angle_between_deg(d1, d2);
    if (border_angle >= kBorderRootAngleDeg) {
        Vec3 out = cross(normalized(d2 - d1), normal);
        if (norm(out) > 1e-12) {
            if (dot(out, inward) > 0) out = -1.0 * out;
            const double off = angle_between_deg(out, branch);
            const bool corner = faces == 1 && border_angle < kBorderCornerMaxDeg && off <= kBorderCornerBranchDeg &&
                                radius_over_edge < kBorderCornerMaxRadiusEdge;
            if (corner) return BorderRoot::None;
            if (off <= kBorderRootBranchDeg) return BorderRoot::Out;
        }
    }
    if (faces == 2 && norm(normal) > 0 &&
        std::min(angle_between_deg(normal, branch), angle_between_deg(-1.0 * normal, branch)) <= kBorderRootSideDeg)
        return BorderRoot::Side;
    return BorderRoot::None;
}

BorderRoot border_root_at(const Skeleton& s, const SkeletonAnalysis& an, int v) {
    std::vector<Vec3> to_border;
    Vec3 inward{}, branch{}, normal{};
    int branches = 0;
    double border_edge = 0;  // the shorter border edge at v
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        const int w = s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0];
        const Vec3 d = normalized(s.points[w] - s.points[v]);
        if (an.edge_degree[e] == 1) {
            const double len = distance(s.points[w], s.points[v]);
            border_edge = to_border.empty() ? len : std::min(border_edge, len);
        }
        if (an.edge_degree[e] == 0) {
            branch = d;
            ++branches;
        } else {
            inward += d;
        }
        if (an.edge_degree[e] == 1) to_border.push_back(d);
        if (an.edge_degree[e] >= 3) return BorderRoot::None;
    }
    if (branches != 1 || to_border.size() != 2) return BorderRoot::None;
    int faces = 0;
    for (std::size_t f = 0; f < an.face_vertices.size(); ++f)
        for (int w : an.face_vertices[f])
            if (w == v) {
                normal += an.face_normal[f];
                ++faces;
            }
    const double r = static_cast<std::size_t>(v) < s.radii.size() ? s.radii[v] : 0.0;
    return border_root(to_border[0], to_border[1], inward, normal, branch, faces,
                       border_edge > 0 ? r / border_edge : 0.0);
}

namespace {

// The steps of analyze_skeleton, in the order it calls them: incidence, faces and their edges, leaflets, face
// normals, vertex classes, the rooted-branch check, branches, counts. Each fills its part of the analysis.

// Incidence (CSR, edges in increasing id per vertex).
void build_incidence(const Skeleton& s, SkeletonAnalysis& an) {
    const int nv = static_cast<int>(s.points.size());
    const int ne = static_cast<int>(s.edges.size());
    an.vertex_edge_begin.assign(nv + 1, 0);
    for (const std::array<int, 2>& ed : s.edges) {
        ++an.vertex_edge_begin[ed[0] + 1];
        ++an.vertex_edge_begin[ed[1] + 1];
    }
    std::partial_sum(an.vertex_edge_begin.begin(), an.vertex_edge_begin.end(), an.vertex_edge_begin.begin());
    an.vertex_edges.resize(an.vertex_edge_begin[nv]);
    std::vector<int> fill(an.vertex_edge_begin.begin(), an.vertex_edge_begin.end() - 1);
    for (int e = 0; e < ne; ++e) {
        an.vertex_edges[fill[s.edges[e][0]]++] = e;
        an.vertex_edges[fill[s.edges[e][1]]++] = e;
    }
}

// The faces of each edge (CSR over edges, faces in increasing id).
struct EdgeFaces {
    std::vector<int> begin, faces;
};

// Faces: sides -> edges, edge degrees; returns the faces of each edge. Throws Error(InvalidInput) naming a face whose
// side is not an edge.
EdgeFaces build_faces(const Skeleton& s, SkeletonAnalysis& an) {
    const int ne = static_cast<int>(s.edges.size());
    const int nf = static_cast<int>(s.faces.size());
    an.edge_degree.assign(ne, 0);
    an.face_vertices.resize(nf);
    an.face_edges.resize(nf);
    for (int f = 0; f < nf; ++f) {
        for (int k = 0; k < 4; ++k) an.face_vertices[f][k] = s.faces[f][k];
        for (int k = 0; k < 4; ++k) {
            const int a = s.faces[f][k], b = s.faces[f][(k + 1) % 4];
            const int e = edge_between(an, s, a, b);
            if (e < 0)
                fail(ErrorCode::InvalidInput,
                     "side (" + std::to_string(a) + ", " + std::to_string(b) + ") of skeleton face " +
                         std::to_string(f) + " is not in the edge list",
                     ElementRef::Kind::SkeletonFace, f);
            an.face_edges[f][k] = e;
            ++an.edge_degree[e];
        }
    }
    EdgeFaces ef{std::vector<int>(ne + 1, 0), {}};
    for (int e = 0; e < ne; ++e) ef.begin[e + 1] = ef.begin[e] + an.edge_degree[e];
    ef.faces.resize(ef.begin[ne]);
    std::vector<int> fill(ef.begin.begin(), ef.begin.end() - 1);
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) ef.faces[fill[an.face_edges[f][k]]++] = f;
    return ef;
}

// Leaflets: flood across degree-2 edges, orienting each new face against its neighbour (face_vertices and
// face_edges of a flipped face are reversed in place).
void find_leaflets(const EdgeFaces& ef, SkeletonAnalysis& an) {
    const int nf = static_cast<int>(an.face_vertices.size());
    an.face_leaflet.assign(nf, -1);
    std::vector<int> queue;
    for (int f0 = 0; f0 < nf; ++f0) {
        if (an.face_leaflet[f0] >= 0) continue;
        const int leaf = static_cast<int>(an.leaflets.size());
        an.leaflets.push_back({});
        Leaflet& L = an.leaflets.back();
        queue.assign(1, f0);
        an.face_leaflet[f0] = leaf;
        for (std::size_t qi = 0; qi < queue.size(); ++qi) {
            const int f = queue[qi];
            L.faces.push_back(f);
            for (int k = 0; k < 4; ++k) {
                const int e = an.face_edges[f][k];
                if (an.edge_degree[e] != 2) continue;
                const int a = an.face_vertices[f][k], b = an.face_vertices[f][(k + 1) % 4];
                const int g = ef.faces[ef.begin[e]] == f ? ef.faces[ef.begin[e] + 1] : ef.faces[ef.begin[e]];
                if (g == f) continue;  // a face glued to itself: cannot happen with 4 distinct vertices
                std::array<int, 4>& gv = an.face_vertices[g];
                int ia = 0;
                while (gv[ia] != a) ++ia;
                const bool same_direction = gv[(ia + 1) % 4] == b;  // g also traverses a -> b
                if (an.face_leaflet[g] < 0) {
                    if (same_direction) {
                        std::swap(gv[1], gv[3]);
                        std::array<int, 4>& ge = an.face_edges[g];
                        // sides of (w0,w3,w2,w1): (w0,w3)=old side 3, (w3,w2)=old 2, (w2,w1)=old 1, (w1,w0)=old 0
                        ge = {ge[3], ge[2], ge[1], ge[0]};
                    }
                    an.face_leaflet[g] = leaf;
                    queue.push_back(g);
                } else if (same_direction) {
                    L.orientable = false;
                }
            }
        }
        std::sort(L.faces.begin(), L.faces.end());
    }
}

// Unit normal of every (oriented) face; Error(InvalidInput) naming a face of zero area.
void compute_face_normals(const Skeleton& s, SkeletonAnalysis& an) {
    const int nf = static_cast<int>(an.face_vertices.size());
    an.face_normal.resize(nf);
    for (int f = 0; f < nf; ++f) {
        Vec3 n{};
        for (int k = 0; k < 4; ++k)
            n += cross(s.points[an.face_vertices[f][k]], s.points[an.face_vertices[f][(k + 1) % 4]]);
        if (!(norm(n) > 0))
            fail(ErrorCode::InvalidInput, "skeleton face " + std::to_string(f) + " has zero area",
                 ElementRef::Kind::SkeletonFace, f);
        an.face_normal[f] = normalized(n);
    }
}

// The edges at a vertex by face degree, and what its leaflets look like there.
struct VertexStar {
    int nb = 0, nbnd = 0, ninner = 0, nfan = 0;  // branch, boundary, interior leaflet and fan edges
    std::vector<int> fan_degrees;
    bool inside_a_leaflet = false;  // some leaflet has faces at it but no boundary or fan edge at it
    int leaflets = 0;               // leaflets with faces at it
    int faces = 0;                  // faces at it
};

// Why the fan at a fan-edge vertex with star `st` is irregular (classify_fan_vertex), and the edit, as "WHAT; edit:
// EDIT": fan edges of unequal degrees meeting here (a leaflet along the chain stops here, e.g. a wall on one side of a
// plate shorter than the wall that cuts it), a chain branching here, another leaflet touching an inner chain vertex
// with an interior vertex, a leaflet with border edges at an inner chain vertex, or a fan edge ending inside a
// leaflet.
std::string irregular_fan_reason(const VertexStar& st) {
    std::string what, edit;
    const bool unequal = st.nfan == 2 && st.fan_degrees[0] != st.fan_degrees[1];
    if (unequal) {
        what = "2 fan edges shared by " + std::to_string(std::min(st.fan_degrees[0], st.fan_degrees[1])) + " and " +
               std::to_string(std::max(st.fan_degrees[0], st.fan_degrees[1])) +
               " faces meet here (a leaflet along the fan-edge chain stops at this vertex while the chain goes on)";
        edit =
            "let that leaflet run along the whole chain (every fan edge of the chain shared by as many faces: "
            "for a wall on a plate cut by another wall, as long as the plate)";
    } else if (st.nfan > 2) {
        what = std::to_string(st.nfan) + " fan edges meet here (the fan-edge chain branches)";
        edit =
            "make the fan edges one chain through this vertex (2 fan edges at every inner vertex), or cut the "
            "leaflets so that each chain ends at this vertex with its own border edges";
    } else if (st.nfan == 2 && st.nbnd == 0) {  // regular but for inside_a_leaflet
        what = "another leaflet touches this inner vertex of the fan-edge chain with an interior vertex";
        edit =
            "make the touching leaflet share a whole edge there (a fan edge, cutting the other leaflets' faces "
            "along it), or move its vertex off the chain";
    } else {
        what = st.nfan == 2 ? "a leaflet has border edges at this inner vertex of the fan-edge chain"
                            : "the fan edge (shared by " + std::to_string(st.fan_degrees[0]) +
                                  " faces) ends inside a leaflet or with " + std::to_string(st.nbnd) +
                                  " border edges instead of one per face (the paper's limitation 2, not docked)";
        edit =
            "let every leaflet around the fan edge end with its own border edge at the chain's end (cut the "
            "leaflet that continues past it along the chain's line), or extend the fan edge chain to that "
            "leaflet's border";
    }
    return what + "; edit: " + edit;
}

// Fan-edge vertex: its class, or Error(UnsupportedConfiguration) for a branch edge on it (accepted on a fan-edge end
// with fan_end_branches) or an irregular fan.
VertexClass classify_fan_vertex(const Skeleton& s, const VertexStar& st, const std::string& vname, int v,
                                bool fan_end_branches, bool fan_cap_branches) {
    if (st.nb > 0 && st.nfan == 1 && !fan_end_branches && !(fan_cap_branches && st.nb == 1)) {
        // Why the fan-end repair (fan_end_repair.h) does not take it: the first of its conditions that fails, and
        // the edit; none fails when the repair did not run.
        const int g = st.fan_degrees[0];
        const std::optional<FanEndRefusal> refusal = fan_end_refusal(s, v);
        const std::string why =
            refusal ? refusal->reason
                    : "the skeleton repair that retracts the fan edge from it did not run (it runs with resampling "
                      "only, and when not turned off)";
        const std::string edit = refusal ? refusal->edit
                                         : "mesh with resampling (do not pass --no-resample) and the repair on "
                                           "(SkeletonRepairOptions::fan_end_retraction), or start the branch from a "
                                           "corner of one leaflet off the fan edge";
        fail(ErrorCode::UnsupportedConfiguration,
             vname + ": a branch on a fan-edge end (the end of a fan edge shared by " + std::to_string(g) +
                 " faces; the paper's limitation 3) that the fan-end repair does not take: " + why + "; edit: " + edit,
             ElementRef::Kind::SkeletonVertex, v);
    }
    if (st.nb > 0 && st.nfan != 1)
        fail(ErrorCode::UnsupportedConfiguration,
             vname + ": a branch on a vertex inside a fan-edge chain (on " + std::to_string(st.nfan) +
                 " fan edges, edges shared by 3 or more faces; the paper's limitation 3) is not supported; edit: "
                 "start the branch from a vertex where 4 faces of one of the leaflets meet, or from an end of the "
                 "fan edge chain",
             ElementRef::Kind::SkeletonVertex, v);
    // A regular fan: at its end every leaflet around the fan edge leaves by one boundary edge; along it,
    // every leaflet goes on across the vertex (paper limitation 2 otherwise: the fan stops inside a leaflet).
    const bool regular =
        !st.inside_a_leaflet && (st.nfan == 1 ? st.nbnd == st.fan_degrees[0]
                                              : st.nfan == 2 && st.fan_degrees[0] == st.fan_degrees[1] && st.nbnd == 0);
    if (!regular)
        fail(ErrorCode::UnsupportedConfiguration,
             vname + ": an irregular fan is not supported: " + irregular_fan_reason(st),
             ElementRef::Kind::SkeletonVertex, v);
    return st.nfan == 1 ? VertexClass::FanEdgeEnd : VertexClass::FanEdgeVertex;
}

// The class of vertex v (pseudo-degree, reference-notes §4.1-4.2, plus explicit rejection of the unsupported); sets
// vertex_border_root[v] at a border vertex with one branch.
VertexClass classify_vertex(const Skeleton& s, const VertexStar& st, int v, const AnalysisOptions& options,
                            SkeletonAnalysis& an) {
    const std::string vname = "skeleton vertex " + std::to_string(v);
    if (st.nfan > 0) return classify_fan_vertex(s, st, vname, v, options.fan_end_branches, options.fan_cap_branches);
    if (st.inside_a_leaflet && st.nb == 1 && st.nbnd == 0 && st.leaflets == 1 && st.ninner == 4 && st.faces == 4) {
        // Beyond the paper's limitation 1: one branch leaving a regular interior vertex (4 faces of one
        // leaflet). The branch's first chunk stands on the 2 x 2 plate faces around the vertex, on the side the
        // branch leaves to (raw_mesh.cpp).
        return VertexClass::LeafletInterior;
    }
    if (st.inside_a_leaflet && (st.nb > 0 || st.nbnd > 0)) {
        if (st.nb > 0)
            fail(ErrorCode::UnsupportedConfiguration, vname + ": " + branch_inside_leaflet(st.nb, st.faces),
                 ElementRef::Kind::SkeletonVertex, v);
        fail(ErrorCode::UnsupportedConfiguration,
             vname +
                 ": a leaflet touches the interior of another leaflet; not supported; edit: make the touching "
                 "leaflet share a whole edge there (a fan edge, cutting the other leaflet's faces along it), "
                 "or move its vertex off the other leaflet",
             ElementRef::Kind::SkeletonVertex, v);
    }
    if (st.nbnd % 2 != 0)
        fail(ErrorCode::UnsupportedConfiguration,
             vname + " has an odd number (" + std::to_string(st.nbnd) +
                 ") of leaflet boundary edges (a "
                 "leaflet border must pass through it an even number of times); edit: look for a missing "
                 "or extra face, or an edge listed without its face, at it",
             ElementRef::Kind::SkeletonVertex, v);
    const int nl = st.nbnd / 2, nb = st.nb;
    if (nl == 0 && st.ninner > 0) {
        if (nb > 0)
            fail(ErrorCode::UnsupportedConfiguration, vname + ": " + branch_inside_leaflet(nb, st.faces),
                 ElementRef::Kind::SkeletonVertex, v);
        return VertexClass::LeafletInterior;
    }
    if (nl + nb > 2) return VertexClass::BranchingPoint;
    if (nl == 0 && nb == 1) return VertexClass::Extremity;
    if (nl == 0 && nb == 2) return VertexClass::Joint;
    if (nl == 1 && nb == 0) return VertexClass::LeafletBoundary;
    if (nl == 1 && nb == 1) {
        an.vertex_border_root[v] = border_root_at(s, an, v);
        return an.vertex_border_root[v] != BorderRoot::None ? VertexClass::LeafletBoundary : VertexClass::BLJoint;
    }
    if (nl == 2 && nb == 0) return VertexClass::LLJoint;
    return VertexClass::Isolated;
}

// Vertex classification. Per vertex: does some leaflet have faces at it but no boundary or fan edge at it (the vertex
// is inside that leaflet)? Serial in face order.
void classify_vertices(const Skeleton& s, const AnalysisOptions& options, SkeletonAnalysis& an) {
    const int nv = static_cast<int>(s.points.size());
    const int nf = static_cast<int>(an.face_vertices.size());
    std::vector<std::vector<std::pair<int, bool>>> leaflet_rim(nv);  // (leaflet, has a rim edge at the vertex)
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) {
            const int w = an.face_vertices[f][k], l = an.face_leaflet[f];
            const bool rim =
                an.edge_degree[an.face_edges[f][k]] != 2 || an.edge_degree[an.face_edges[f][(k + 3) & 3]] != 2;
            auto it = std::find_if(leaflet_rim[w].begin(), leaflet_rim[w].end(),
                                   [&](const std::pair<int, bool>& x) { return x.first == l; });
            if (it == leaflet_rim[w].end())
                leaflet_rim[w].push_back({l, rim});
            else
                it->second = it->second || rim;
        }
    std::vector<int> faces_at(nv, 0);
    for (const std::array<int, 4>& fv : an.face_vertices)
        for (int w : fv) ++faces_at[w];
    an.vertex_class.assign(nv, VertexClass::Isolated);
    an.vertex_border_root.assign(nv, BorderRoot::None);
    an.vertex_branch_edges.assign(nv, 0);
    an.vertex_boundary_edges.assign(nv, 0);
    for (int v = 0; v < nv; ++v) {
        if (an.vertex_plate[v] >= 0) {  // a docked chain vertex: a vertex of its plate (docked_walls.h)
            an.vertex_class[v] = docked_vertex_class(an, v, an.vertex_boundary_edges[v]);
            continue;
        }
        VertexStar st;
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int d = an.edge_degree[an.vertex_edges[i]];
            if (d == 0)
                ++st.nb;
            else if (d == 1)
                ++st.nbnd;
            else if (d == 2)
                ++st.ninner;
            else {
                ++st.nfan;
                st.fan_degrees.push_back(d);
            }
        }
        for (const std::pair<int, bool>& x : leaflet_rim[v]) st.inside_a_leaflet = st.inside_a_leaflet || !x.second;
        st.leaflets = static_cast<int>(leaflet_rim[v].size());
        st.faces = faces_at[v];
        an.vertex_branch_edges[v] = st.nb;
        an.vertex_boundary_edges[v] = st.nbnd;
        an.vertex_class[v] = classify_vertex(s, st, v, options, an);
    }
}

// Branches rooted on the plates: no two may stand on the same raw quad (a plate's up / down face, a half-chunk's
// up / down face, or one of the two half-chunk out faces of a boundary edge). Keys: (kind, id, side): kind 0 a plate
// face, 1 a border edge's half-chunk, 2 a corner cube's top (id: the corner vertex; walls' feet only), 3 a border
// edge's out faces.
// Error(UnsupportedConfiguration) naming the second vertex otherwise.
void check_rooted_branches(const Skeleton& s, const SkeletonAnalysis& an) {
    const int nv = static_cast<int>(s.points.size());
    const int nf = static_cast<int>(an.face_vertices.size());
    std::map<std::array<int, 3>, int> owner;  // key -> rooted vertex (a wall's docked vertex: -1 - vertex)
    // A chain left to the band pillow (AnalysisOptions::docked_band_pillow) has no feet yet: the repaired skeleton's
    // analysis checks them.
    const std::vector<FootQuad> feet = an.docked_unmatched.empty() ? docked_foot_quads(s, an) : std::vector<FootQuad>{};
    for (const FootQuad& q : feet) {
        const auto [it, fresh] = owner.insert({{q.kind, q.id, q.up ? 0 : 1}, -1 - q.vertex});
        if (!fresh)
            fail(ErrorCode::UnsupportedConfiguration,
                 "skeleton vertex " + std::to_string(q.vertex) + ": the foot of the wall docked there (leaflet " +
                     std::to_string(q.wall) + ") would stand on plate " +
                     (q.kind == 0   ? "face "
                      : q.kind == 1 ? "border edge "
                                    : "corner cube at vertex ") +
                     std::to_string(q.id) + ", which the wall docked at skeleton vertex " +
                     std::to_string(-1 - it->second) +
                     " stands on too; edit: move the walls at least two plate faces apart, or to opposite sides",
                 ElementRef::Kind::SkeletonVertex, q.vertex);
    }
    auto claim = [&](int v, int kind, int id, int side) {
        const auto [it, fresh] = owner.insert({{kind, id, side}, v});
        if (!fresh && it->second < 0)
            fail(ErrorCode::UnsupportedConfiguration,
                 "skeleton vertex " + std::to_string(v) +
                     ": its branch would stand on plate faces that the foot of the wall docked at skeleton vertex " +
                     std::to_string(-1 - it->second) +
                     " stands on too; edit: start the branch at least one plate face away from the wall's foot",
                 ElementRef::Kind::SkeletonVertex, v);
        if (!fresh)
            fail(ErrorCode::UnsupportedConfiguration,
                 "skeleton vertex " + std::to_string(v) +
                     ": its branch would stand on leaflet faces that the "
                     "branch rooted at skeleton vertex " +
                     std::to_string(it->second) +
                     " stands on too (two branches rooted next to each other on the same side); edit: move one "
                     "of them at least two vertices away, or to the other side",
                 ElementRef::Kind::SkeletonVertex, v);
    };
    for (int v = 0; v < nv; ++v) {
        if (!roots_branch(an, v)) continue;
        const int be = first_branch_edge(an, v);
        const Vec3 branch = s.points[s.edges[be][0] == v ? s.edges[be][1] : s.edges[be][0]] - s.points[v];
        Vec3 normal{};
        std::vector<int> faces, border;
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i)
            if (an.edge_degree[an.vertex_edges[i]] == 1) border.push_back(an.vertex_edges[i]);
        for (int f = 0; f < nf; ++f)
            for (int w : an.face_vertices[f])
                if (w == v) {
                    faces.push_back(f);
                    normal += an.face_normal[f];
                }
        const int side = dot(branch, normal) >= 0 ? 0 : 1;
        if (an.vertex_class[v] == VertexClass::LeafletInterior || an.vertex_border_root[v] == BorderRoot::Side) {
            for (int f : faces) claim(v, 0, f, side);
            for (int e : border) claim(v, 1, e, side);
        } else {
            for (int e : border) {  // kind 3: a border edge's out faces (kind 2 is a corner cube's top, by vertex)
                claim(v, 3, e, 0);
                claim(v, 3, e, 1);
            }
        }
    }
}

// Counts, components and independent cycles, and the predicted hex count.
void count_elements(const Skeleton& s, SkeletonAnalysis& an) {
    AnalysisCounts& c = an.counts;
    c.vertices = static_cast<long>(s.points.size());
    c.edges = static_cast<long>(s.edges.size());
    c.faces = static_cast<long>(s.faces.size());
    for (const int d : an.edge_degree) {
        if (d == 0)
            ++c.branch_edges;
        else if (d == 1)
            ++c.boundary_edges;
    }
    for (std::size_t e = 0; e < an.edge_degree.size(); ++e) {
        if (an.edge_docked[e] == 3)
            ++c.boundary_edges;  // a flange's chain: its plate's border (half-chunks)
        else if (an.edge_degree[e] >= 3)
            ++(an.edge_docked[e] == 1 ? c.docked_edges : c.fan_edges);
    }
    c.branches = static_cast<long>(an.branches.size());
    c.leaflets = static_cast<long>(an.leaflets.size());
    for (const Branch& b : an.branches) c.rings += b.ring ? 1 : 0;
    for (VertexClass vc : an.vertex_class) {
        switch (vc) {
            case VertexClass::Isolated: ++c.isolated; break;
            case VertexClass::Extremity: ++c.extremities; break;
            case VertexClass::Joint: ++c.joints; break;
            case VertexClass::BranchingPoint: ++c.branching_points; break;
            case VertexClass::LeafletInterior: ++c.leaflet_interior; break;
            case VertexClass::LeafletBoundary: ++c.leaflet_boundary; break;
            case VertexClass::BLJoint: ++c.bl_joints; break;
            case VertexClass::LLJoint: ++c.ll_joints; break;
            case VertexClass::FanEdgeVertex: ++c.fan_edge_vertices; break;
            case VertexClass::FanEdgeEnd: ++c.fan_edge_ends; break;
        }
    }
    const int nv = static_cast<int>(s.points.size());
    UnionFind sets(nv);
    for (const std::array<int, 2>& ed : s.edges) sets.unite(ed[0], ed[1]);
    for (int v = 0; v < nv; ++v)
        if (an.vertex_class[v] != VertexClass::Isolated && sets.find(v) == v) ++c.components;
    c.cycles = c.components - ((c.vertices - c.isolated) - c.edges + c.faces);
    const long cubes = std::count(an.corner_cube.begin(), an.corner_cube.end(), char{1});
    an.predicted_hexes = 4 * c.branch_edges + 2 * c.faces + 2 * c.boundary_edges + 2 * cubes;
}

}  // namespace

std::vector<Branch> extract_branches(const Skeleton& s, const std::vector<int>& vertex_edge_begin,
                                     const std::vector<int>& vertex_edges, const std::vector<char>& branch_edge,
                                     const std::vector<char>& joint, std::vector<int>& edge_branch) {
    const int nv = static_cast<int>(s.points.size());
    std::vector<Branch> branches;
    edge_branch.assign(s.edges.size(), -1);
    auto other_end = [&](int e, int v) { return s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0]; };
    auto next_joint_edge = [&](int v, int e_in) {
        for (int i = vertex_edge_begin[v]; i < vertex_edge_begin[v + 1]; ++i) {
            const int e = vertex_edges[i];
            if (e != e_in && branch_edge[e]) return e;
        }
        return -1;
    };
    auto walk = [&](int start, int e0, bool ring) {
        const int b = static_cast<int>(branches.size());
        branches.push_back({});
        Branch& br = branches.back();
        br.ring = ring;
        br.vertices.push_back(start);
        int cur = start, e = e0;
        while (true) {
            edge_branch[e] = b;
            br.edges.push_back(e);
            cur = other_end(e, cur);
            br.vertices.push_back(cur);
            if (cur == start || !joint[cur]) break;
            e = next_joint_edge(cur, e);
            if (e < 0 || edge_branch[e] >= 0) break;  // cannot happen for a joint; defensive against a hang
        }
    };
    for (const bool rings : {false, true})
        for (int v = 0; v < nv; ++v) {
            if ((joint[v] != 0) != rings) continue;
            for (int i = vertex_edge_begin[v]; i < vertex_edge_begin[v + 1]; ++i) {
                const int e = vertex_edges[i];
                if (branch_edge[e] && edge_branch[e] < 0) walk(v, e, rings);
            }
        }
    return branches;
}

SkeletonAnalysis analyze_leaflets(const Skeleton& s) {
    SkeletonAnalysis an;
    build_incidence(s, an);
    const EdgeFaces edge_faces = build_faces(s, an);
    find_leaflets(edge_faces, an);
    compute_face_normals(s, an);
    return an;
}

SkeletonAnalysis analyze_skeleton(const Skeleton& s, const AnalysisOptions& options) {
    validate_input(s, options);
    SkeletonAnalysis an = analyze_leaflets(s);
    find_docked_walls(s, an, options.docked_band_pillow, options.docked_band_pillow_ran);
    classify_vertices(s, options, an);
    check_rooted_branches(s, an);
    std::vector<char> branch_edge(s.edges.size()), joint(s.points.size());
    for (std::size_t e = 0; e < branch_edge.size(); ++e) branch_edge[e] = an.edge_degree[e] == 0;
    for (std::size_t v = 0; v < joint.size(); ++v) joint[v] = an.vertex_class[v] == VertexClass::Joint;
    an.branches = extract_branches(s, an.vertex_edge_begin, an.vertex_edges, branch_edge, joint, an.edge_branch);
    count_elements(s, an);
    return an;
}

std::string analysis_to_text(const SkeletonAnalysis& an) {
    const AnalysisCounts& c = an.counts;
    std::ostringstream os;
    os << "vertices " << c.vertices << ", edges " << c.edges << ", faces " << c.faces << "\n";
    os << "branches " << c.branches << " (rings " << c.rings << "), leaflets " << c.leaflets << ", components "
       << c.components << ", independent cycles " << c.cycles << "\n";
    os << "branch edges " << c.branch_edges << ", leaflet boundary edges " << c.boundary_edges << ", fan edges "
       << c.fan_edges;
    if (c.docked_edges > 0) os << ", docked fan edges (walls on a plate) " << c.docked_edges;
    os << "\n";
    os << "extremities " << c.extremities << ", joints " << c.joints << ", branching points " << c.branching_points
       << ", BL-joints " << c.bl_joints << ", LL-joints " << c.ll_joints << "\n";
    os << "leaflet interior " << c.leaflet_interior << ", leaflet boundary " << c.leaflet_boundary
       << ", fan-edge vertices " << c.fan_edge_vertices << ", fan-edge ends " << c.fan_edge_ends << ", isolated "
       << c.isolated << "\n";
    os << "predicted hexes " << an.predicted_hexes << "\n";
    const int nv = static_cast<int>(an.vertex_class.size());
    for (int v = 0; v < nv; ++v) {
        const VertexClass vc = an.vertex_class[v];
        if (roots_branch(an, v)) {
            const BorderRoot root = an.vertex_border_root[v];
            const char* where = root == BorderRoot::Out    ? "out patch of the border"
                                : root == BorderRoot::Side ? "side patch of the border"
                                                           : "inside the leaflet";
            os << "vertex " << v << ": " << to_string(vc) << ", its branch rooted on the plates (" << where << ")\n";
            continue;
        }
        bool flange = false;  // on a chain docked on its plate's border (edge_docked 3)
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i)
            flange = flange || an.edge_docked[an.vertex_edges[i]] == 3;
        if (flange) {
            os << "vertex " << v << ": " << to_string(vc) << " of leaflet " << an.vertex_plate[v]
               << ", a wall docked on its border (a flange: the chain is the leaflet's border)"
               << (has_corner_cube(an, v) ? ", its corner cube" : "") << "\n";
            continue;
        }
        if (an.vertex_plate[v] >= 0) {
            os << "vertex " << v << ": " << to_string(vc) << " of leaflet " << an.vertex_plate[v]
               << ", a wall docked on it (chain of fan edges ending inside the leaflet, or across it with a leaflet "
                  "stopping on the chain)\n";
            continue;
        }
        if (vc == VertexClass::Joint || vc == VertexClass::LeafletInterior || vc == VertexClass::LeafletBoundary)
            continue;
        os << "vertex " << v << ": " << to_string(vc) << " (degree "
           << an.vertex_edge_begin[v + 1] - an.vertex_edge_begin[v] << ")\n";
    }
    for (std::size_t l = 0; l < an.leaflets.size(); ++l)
        if (!an.leaflets[l].orientable) os << "leaflet " << l << ": not orientable\n";
    return os.str();
}

}  // namespace mesohex
