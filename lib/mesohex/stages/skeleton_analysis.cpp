#include "mesohex/core/union_find.h"
#include "mesohex/stages/skeleton_analysis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <sstream>

#include "mesohex/core/error.h"

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
           "(here " + std::to_string(branch_edges) + " branch edge(s), " + std::to_string(faces) +
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
                       int faces) {
    if (angle_between_deg(d1, d2) >= kBorderRootAngleDeg) {
        Vec3 out = cross(normalized(d2 - d1), normal);
        if (norm(out) > 1e-12) {
            if (dot(out, inward) > 0) out = -1.0 * out;
            if (angle_between_deg(out, branch) <= kBorderRootBranchDeg) return BorderRoot::Out;
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
    for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
        const int e = an.vertex_edges[i];
        const int w = s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0];
        const Vec3 d = normalized(s.points[w] - s.points[v]);
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
    return border_root(to_border[0], to_border[1], inward, normal, branch, faces);
}

SkeletonAnalysis analyze_skeleton(const Skeleton& s, const AnalysisOptions& options) {
    validate_input(s, options);
    const int nv = static_cast<int>(s.points.size());
    const int ne = static_cast<int>(s.edges.size());
    const int nf = static_cast<int>(s.faces.size());
    SkeletonAnalysis an;

    // Incidence (CSR, edges in increasing id per vertex).
    an.vertex_edge_begin.assign(nv + 1, 0);
    for (const std::array<int, 2>& ed : s.edges) {
        ++an.vertex_edge_begin[ed[0] + 1];
        ++an.vertex_edge_begin[ed[1] + 1];
    }
    std::partial_sum(an.vertex_edge_begin.begin(), an.vertex_edge_begin.end(), an.vertex_edge_begin.begin());
    an.vertex_edges.resize(an.vertex_edge_begin[nv]);
    {
        std::vector<int> fill(an.vertex_edge_begin.begin(), an.vertex_edge_begin.end() - 1);
        for (int e = 0; e < ne; ++e) {
            an.vertex_edges[fill[s.edges[e][0]]++] = e;
            an.vertex_edges[fill[s.edges[e][1]]++] = e;
        }
    }

    // Faces: sides -> edges, edge degrees.
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
    // Edge -> faces (CSR).
    std::vector<int> edge_face_begin(ne + 1, 0), edge_faces;
    for (int e = 0; e < ne; ++e) edge_face_begin[e + 1] = edge_face_begin[e] + an.edge_degree[e];
    edge_faces.resize(edge_face_begin[ne]);
    {
        std::vector<int> fill(edge_face_begin.begin(), edge_face_begin.end() - 1);
        for (int f = 0; f < nf; ++f)
            for (int k = 0; k < 4; ++k) edge_faces[fill[an.face_edges[f][k]]++] = f;
    }

    // Leaflets: flood across degree-2 edges, orienting each new face against its neighbour.
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
                const int g = edge_faces[edge_face_begin[e]] == f ? edge_faces[edge_face_begin[e] + 1]
                                                                   : edge_faces[edge_face_begin[e]];
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

    // Vertex classification (pseudo-degree, reference-notes §4.1-4.2, plus explicit rejection of the unsupported).
    // Per vertex: does some leaflet have faces at it but no boundary or fan edge at it (the vertex is inside that
    // leaflet)? Serial in face order.
    std::vector<std::vector<std::pair<int, bool>>> leaflet_rim(nv);  // (leaflet, has a rim edge at the vertex)
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 4; ++k) {
            const int w = an.face_vertices[f][k], l = an.face_leaflet[f];
            const bool rim =
                an.edge_degree[an.face_edges[f][k]] != 2 || an.edge_degree[an.face_edges[f][(k + 3) & 3]] != 2;
            auto it = std::find_if(leaflet_rim[w].begin(), leaflet_rim[w].end(),
                                   [&](const std::pair<int, bool>& x) { return x.first == l; });
            if (it == leaflet_rim[w].end()) leaflet_rim[w].push_back({l, rim});
            else it->second = it->second || rim;
        }
    std::vector<int> faces_at(nv, 0);
    for (const std::array<int, 4>& fv : an.face_vertices)
        for (int w : fv) ++faces_at[w];
    an.vertex_class.assign(nv, VertexClass::Isolated);
    an.vertex_border_root.assign(nv, BorderRoot::None);
    an.vertex_branch_edges.assign(nv, 0);
    an.vertex_boundary_edges.assign(nv, 0);
    for (int v = 0; v < nv; ++v) {
        int nb = 0, nbnd = 0, ninner = 0, nfan = 0;
        std::vector<int> fan_degrees;
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int d = an.edge_degree[an.vertex_edges[i]];
            if (d == 0) ++nb;
            else if (d == 1) ++nbnd;
            else if (d == 2) ++ninner;
            else {
                ++nfan;
                fan_degrees.push_back(d);
            }
        }
        bool inside_a_leaflet = false;
        for (const std::pair<int, bool>& x : leaflet_rim[v]) inside_a_leaflet = inside_a_leaflet || !x.second;
        an.vertex_branch_edges[v] = nb;
        an.vertex_boundary_edges[v] = nbnd;
        const std::string vname = "skeleton vertex " + std::to_string(v);
        VertexClass c = VertexClass::Isolated;
        if (nfan > 0) {
            if (nb > 0)
                fail(ErrorCode::UnsupportedConfiguration,
                     vname + ": a branch edge on a fan-edge vertex (on an edge shared by 3 or more faces) is not "
                             "supported (paper limitation 3); edit: start the branch from a vertex where 4 faces of one "
                             "of the leaflets meet, or shorten the fan edge chain so the branch leaves from a leaflet "
                             "corner off the fan edge",
                     ElementRef::Kind::SkeletonVertex, v);
            // A regular fan: at its end every leaflet around the fan edge leaves by one boundary edge; along it,
            // every leaflet goes on across the vertex (paper limitation 2 otherwise: the fan stops inside a leaflet).
            const bool regular = !inside_a_leaflet &&
                                 (nfan == 1 ? nbnd == fan_degrees[0]
                                            : nfan == 2 && fan_degrees[0] == fan_degrees[1] && nbnd == 0);
            if (!regular)
                fail(ErrorCode::UnsupportedConfiguration,
                     vname + ": an irregular fan (a fan edge ending inside a leaflet, paper limitation 2, or " +
                         std::to_string(nfan) + " fan edges of unequal degrees or not in one chain) is not supported; "
                         "edit: let every leaflet around the fan edge end with its own border edge at the chain's end "
                         "(cut the leaflet that continues past it along the chain's line), or extend the fan edge "
                         "chain to that leaflet's border",
                     ElementRef::Kind::SkeletonVertex, v);
            c = nfan == 1 ? VertexClass::FanEdgeEnd : VertexClass::FanEdgeVertex;
        } else if (inside_a_leaflet && nb == 1 && nbnd == 0 && leaflet_rim[v].size() == 1 && ninner == 4 &&
                   faces_at[v] == 4) {
            // Beyond the paper's limitation 1: one branch leaving a regular interior vertex (4 faces of one
            // leaflet). The branch's first chunk stands on the 2 x 2 plate faces around the vertex, on the side the
            // branch leaves to (raw_mesh.cpp).
            c = VertexClass::LeafletInterior;
        } else if (inside_a_leaflet && (nb > 0 || nbnd > 0)) {
            if (nb > 0)
                fail(ErrorCode::UnsupportedConfiguration,
                     vname + ": " + branch_inside_leaflet(nb, faces_at[v]), ElementRef::Kind::SkeletonVertex, v);
            fail(ErrorCode::UnsupportedConfiguration,
                 vname + ": a leaflet touches the interior of another leaflet; not supported; edit: make the touching "
                         "leaflet share a whole edge there (a fan edge, cutting the other leaflet's faces along it), "
                         "or move its vertex off the other leaflet",
                 ElementRef::Kind::SkeletonVertex, v);
        } else {
            if (nbnd % 2 != 0)
                fail(ErrorCode::UnsupportedConfiguration,
                     vname + " has an odd number (" + std::to_string(nbnd) + ") of leaflet boundary edges (a "
                             "leaflet border must pass through it an even number of times); edit: look for a missing "
                             "or extra face, or an edge listed without its face, at it",
                     ElementRef::Kind::SkeletonVertex, v);
            const int nl = nbnd / 2;
            if (nl == 0 && ninner > 0) {
                if (nb > 0)
                    fail(ErrorCode::UnsupportedConfiguration,
                         vname + ": " + branch_inside_leaflet(nb, faces_at[v]), ElementRef::Kind::SkeletonVertex, v);
                c = VertexClass::LeafletInterior;
            } else if (nl + nb > 2) {
                c = VertexClass::BranchingPoint;
            } else if (nl == 0 && nb == 1) {
                c = VertexClass::Extremity;
            } else if (nl == 0 && nb == 2) {
                c = VertexClass::Joint;
            } else if (nl == 1 && nb == 0) {
                c = VertexClass::LeafletBoundary;
            } else if (nl == 1 && nb == 1) {
                an.vertex_border_root[v] = border_root_at(s, an, v);
                c = an.vertex_border_root[v] != BorderRoot::None ? VertexClass::LeafletBoundary : VertexClass::BLJoint;
            } else if (nl == 2 && nb == 0) {
                c = VertexClass::LLJoint;
            }
        }
        an.vertex_class[v] = c;
    }

    // Branches rooted on the plates: no two may stand on the same raw quad (a plate's up / down face, a half-chunk's
    // up / down face, or one of the two half-chunk out faces of a boundary edge). Keys: (kind, face or edge, side).
    {
        std::map<std::array<int, 3>, int> owner;  // key -> rooted vertex
        auto claim = [&](int v, int kind, int id, int side) {
            const auto [it, fresh] = owner.insert({{kind, id, side}, v});
            if (!fresh)
                fail(ErrorCode::UnsupportedConfiguration,
                     "skeleton vertex " + std::to_string(v) + ": its branch would stand on leaflet faces that the "
                         "branch rooted at skeleton vertex " + std::to_string(it->second) +
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
                for (int e : border) {
                    claim(v, 2, e, 0);
                    claim(v, 2, e, 1);
                }
            }
        }
    }

    // Branches: walk from every non-joint vertex along each unvisited branch edge; what is left are closed rings.
    an.edge_branch.assign(ne, -1);
    auto other_end = [&](int e, int v) { return s.edges[e][0] == v ? s.edges[e][1] : s.edges[e][0]; };
    auto next_joint_edge = [&](int v, int e_in) {
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int e = an.vertex_edges[i];
            if (e != e_in && an.edge_degree[e] == 0) return e;
        }
        return -1;
    };
    auto walk = [&](int start, int e0, bool ring) {
        const int b = static_cast<int>(an.branches.size());
        an.branches.push_back({});
        Branch& br = an.branches.back();
        br.ring = ring;
        br.vertices.push_back(start);
        int cur = start, e = e0;
        while (true) {
            an.edge_branch[e] = b;
            br.edges.push_back(e);
            cur = other_end(e, cur);
            br.vertices.push_back(cur);
            if (cur == start || an.vertex_class[cur] != VertexClass::Joint) break;
            e = next_joint_edge(cur, e);
            if (e < 0 || an.edge_branch[e] >= 0) break;  // cannot happen for a joint; defensive against a hang
        }
    };
    for (int v = 0; v < nv; ++v) {
        if (an.vertex_class[v] == VertexClass::Joint) continue;
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int e = an.vertex_edges[i];
            if (an.edge_degree[e] == 0 && an.edge_branch[e] < 0) walk(v, e, false);
        }
    }
    for (int v = 0; v < nv; ++v) {
        if (an.vertex_class[v] != VertexClass::Joint) continue;
        for (int i = an.vertex_edge_begin[v]; i < an.vertex_edge_begin[v + 1]; ++i) {
            const int e = an.vertex_edges[i];
            if (an.edge_degree[e] == 0 && an.edge_branch[e] < 0) walk(v, e, true);
        }
    }

    // Counts.
    AnalysisCounts& c = an.counts;
    c.vertices = nv;
    c.edges = ne;
    c.faces = nf;
    for (int e = 0; e < ne; ++e) {
        const int d = an.edge_degree[e];
        if (d == 0) ++c.branch_edges;
        else if (d == 1) ++c.boundary_edges;
        else if (d >= 3) ++c.fan_edges;
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
    UnionFind sets(nv);
    for (const std::array<int, 2>& ed : s.edges) {
        sets.unite(ed[0], ed[1]);
    }
    for (int v = 0; v < nv; ++v)
        if (an.vertex_class[v] != VertexClass::Isolated && sets.find(v) == v) ++c.components;
    c.cycles = c.components - ((c.vertices - c.isolated) - c.edges + c.faces);
    an.predicted_hexes = 4 * c.branch_edges + 2 * c.faces + 2 * c.boundary_edges;
    return an;
}

std::string analysis_to_text(const SkeletonAnalysis& an) {
    const AnalysisCounts& c = an.counts;
    std::ostringstream os;
    os << "vertices " << c.vertices << ", edges " << c.edges << ", faces " << c.faces << "\n";
    os << "branches " << c.branches << " (rings " << c.rings << "), leaflets " << c.leaflets << ", components "
       << c.components << ", independent cycles " << c.cycles << "\n";
    os << "branch edges " << c.branch_edges << ", leaflet boundary edges " << c.boundary_edges << ", fan edges "
       << c.fan_edges << "\n";
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
