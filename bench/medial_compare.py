#!/usr/bin/env python3
"""Structural measures of a medial mesh (.ma) against its surface (.off / .obj), to compare `mesohex medial`'s
output with the shared medial meshes (issue 17; docs/sheets.md, "Shared medial meshes against ours").

    python3 bench/medial_compare.py MEDIAL.ma SURFACE.off [MEDIAL2.ma ...]

Prints per medial mesh: counts (vertices, curve edges = edges in no triangle, triangles, border and non-manifold
edges, Euler characteristic); radii (x bbox diagonal) and radius / true distance of the centre to the surface;
edge length / mean radius of its two ends (sheet edges and curve edges apart); triangle smallest angle and smallest
height / mean radius; the fold between adjacent triangles (angle of their planes); where curves join sheets (border
or interior vertices), curve branching points and tips; the surface's gap to the swept spheres (sampled along edges
and triangles, radii interpolated; x diagonal: a part the medial mesh misses shows as a large gap); balls crossing the
surface (r > 1.05 x the distance); sheet sides (border and interior apart) over the smaller distance of their ends
to the surface (auto's radii); how centred each centre is (far-side / near-side distance along the ray away from its
nearest surface point, 1 = centred); the surface vertices farther than 3 % of the diagonal from the spheres and their
bounding box (where the missing part is). Quantiles as min p10 median p90 max unless said. Brute force (numpy,
python3-numpy): seconds per medial mesh on the shared surfaces."""
import sys
import numpy as np
from collections import defaultdict


def read_ma(path):
    V, R, E, F = [], [], [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == 'v':
                V.append([float(x) for x in t[1:4]]); R.append(float(t[4]))
            elif t[0] == 'e':
                E.append(tuple(sorted((int(t[1]), int(t[2])))))
            elif t[0] == 'f':
                F.append([int(x) for x in t[1:4]])
    return np.array(V), np.array(R), E, F


def read_surface(path):
    if path.endswith('.off'):
        toks = open(path).read().split()
        i = 1 if toks[0] == 'OFF' else 0
        nv, nf = int(toks[i]), int(toks[i + 1]); i += 3
        P = np.array(toks[i:i + 3 * nv], dtype=float).reshape(nv, 3); i += 3 * nv
        T = []
        for _ in range(nf):
            k = int(toks[i]); T.append([int(x) for x in toks[i + 1:i + 1 + k]]); i += 1 + k
        return P, np.array(T)
    P, T = [], []
    for line in open(path):
        t = line.split()
        if not t:
            continue
        if t[0] == 'v':
            P.append([float(x) for x in t[1:4]])
        elif t[0] == 'f':
            T.append([int(x.split('/')[0]) - 1 for x in t[1:4]])
    return np.array(P), np.array(T)


def point_tri_dist(pts, A, B, C):
    """Unsigned distance from each point to the set of triangles (brute force, chunked)."""
    out = np.full(len(pts), np.inf)
    AB, AC = B - A, C - A
    for s in range(0, len(pts), 64):
        p = pts[s:s + 64][:, None, :]
        AP = p - A
        d1 = (AB * AP).sum(-1); d2 = (AC * AP).sum(-1)
        BP = p - B
        d3 = (AB * BP).sum(-1); d4 = (AC * BP).sum(-1)
        CP = p - C
        d5 = (AB * CP).sum(-1); d6 = (AC * CP).sum(-1)
        va = d3 * d6 - d5 * d4; vb = d5 * d2 - d1 * d6; vc = d1 * d4 - d3 * d2
        den = va + vb + vc
        den = np.where(np.abs(den) < 1e-300, 1e-300, den)
        v = vb / den; w = vc / den
        q = A + v[..., None] * AB + w[..., None] * AC
        # regions
        q = np.where(((d1 <= 0) & (d2 <= 0))[..., None], A, q)
        q = np.where(((d3 >= 0) & (d4 <= d3))[..., None], B, q)
        q = np.where(((d6 >= 0) & (d5 <= d6))[..., None], C, q)
        m = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
        t = d1 / np.where(d1 - d3 == 0, 1, d1 - d3)
        q = np.where(m[..., None], A + t[..., None] * AB, q)
        m = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
        t = d2 / np.where(d2 - d6 == 0, 1, d2 - d6)
        q = np.where(m[..., None], A + t[..., None] * AC, q)
        m = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)
        t = (d4 - d3) / np.where((d4 - d3) + (d5 - d6) == 0, 1, (d4 - d3) + (d5 - d6))
        q = np.where(m[..., None], B + t[..., None] * (C - B), q)
        d = np.linalg.norm(p - q, axis=-1).min(1)
        out[s:s + 64] = d
    return out


def nearest_point(p, A, B, C):
    """Nearest point to p on the triangles (projection onto each plane, barycentrics clamped; brute force)."""
    ab, ac = B - A, C - A
    n = np.cross(ab, ac)
    pp = p - (((p - A) * n).sum(1) / ((n * n).sum(1) + 1e-300))[:, None] * n
    v2 = pp - A
    d00, d01, d11 = (ab * ab).sum(1), (ab * ac).sum(1), (ac * ac).sum(1)
    d20, d21 = (v2 * ab).sum(1), (v2 * ac).sum(1)
    den = d00 * d11 - d01 * d01 + 1e-300
    v = np.clip((d11 * d20 - d01 * d21) / den, 0, 1)
    w = np.clip((d00 * d21 - d01 * d20) / den, 0, 1)
    s = v + w
    v, w = np.where(s > 1, v / s, v), np.where(s > 1, w / s, w)
    cp = A + v[:, None] * ab + w[:, None] * ac
    return cp[np.argmin(np.linalg.norm(cp - p, axis=1))]


def ray_hit(o, u, A, B, C):
    """Distance along the ray o + t u to the first triangle it crosses (Moller-Trumbore, brute force; inf if none)."""
    e1, e2 = B - A, C - A
    h = np.cross(u, e2)
    a = (e1 * h).sum(1)
    ok = np.abs(a) > 1e-14
    f = np.where(ok, 1 / np.where(ok, a, 1), 0)
    s = o - A
    bu = f * (s * h).sum(1)
    qv = np.cross(s, e1)
    bv = f * (qv * u).sum(1)
    t = f * (e2 * qv).sum(1)
    hit = ok & (bu >= 0) & (bv >= 0) & (bu + bv <= 1) & (t > 1e-12)
    return t[hit].min() if hit.any() else np.inf


def centred(V, A, B, C, d):
    out = []
    for c, dc in zip(V, d):
        u = c - nearest_point(c, A, B, C)
        out.append(ray_hit(c, u / max(np.linalg.norm(u), 1e-300), A, B, C) / max(dc, 1e-300))
    return np.array(out)


def q(a, ps=(0, 10, 50, 90, 100)):
    if len(a) == 0:
        return '-'
    return ' '.join('%.3g' % np.percentile(a, p) for p in ps)


def main(ma, surf):
    V, R, E, F = read_ma(ma)
    P, T = read_surface(surf)
    diag = np.linalg.norm(P.max(0) - P.min(0))
    A, B, C = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    tri_edges = defaultdict(list)
    for fi, f in enumerate(F):
        for k in range(3):
            tri_edges[tuple(sorted((f[k], f[(k + 1) % 3])))].append(fi)
    curve = [e for e in E if e not in tri_edges]
    border = [e for e, l in tri_edges.items() if len(l) == 1]
    nonman = [e for e, l in tri_edges.items() if len(l) > 2]
    inF = np.zeros(len(V), bool)
    for f in F:
        inF[f] = True
    bverts = set(v for e in border for v in e)
    cdeg = np.zeros(len(V), int)
    for a, b in curve:
        cdeg[a] += 1; cdeg[b] += 1
    print('== %s  (diag %.4g)' % (ma, diag))
    print('V %d  curve edges %d  triangles %d  border edges %d  nonmanifold edges %d  chi %d' %
          (len(V), len(curve), len(F), len(border), len(nonman), len(V) - len(E) + len(F)))
    d = point_tri_dist(V, A, B, C)
    print('radius/diag   min p10 med p90 max:', q(R / diag))
    print('r / true dist (centre to surface):', q(R / d))
    # spacing
    def elen(es):
        return np.array([np.linalg.norm(V[a] - V[b]) / (0.5 * (R[a] + R[b])) for a, b in es])
    sheet_e = list(tri_edges.keys())
    print('sheet edge len / mean r:', q(elen(sheet_e)))
    print('curve edge len / mean r:', q(elen(curve)))
    # triangle shapes
    mins, hts = [], []
    for f in F:
        p = V[f]
        ang = []
        for k in range(3):
            u = p[(k + 1) % 3] - p[k]; w = p[(k + 2) % 3] - p[k]
            ang.append(np.degrees(np.arccos(np.clip(u @ w / np.linalg.norm(u) / np.linalg.norm(w), -1, 1))))
        mins.append(min(ang))
        area = 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
        lmax = max(np.linalg.norm(p[(k + 1) % 3] - p[k]) for k in range(3))
        hts.append(2 * area / lmax / R[f].mean())
    print('tri min angle deg:', q(mins), ' (<15: %d, <25: %d)' % (sum(m < 15 for m in mins), sum(m < 25 for m in mins)))
    print('tri min height / mean r:', q(hts))
    # folds between adjacent triangles
    nrm = []
    for f in F:
        p = V[f]; n = np.cross(p[1] - p[0], p[2] - p[0]); nrm.append(n / (np.linalg.norm(n) + 1e-300))
    folds = []
    for e, l in tri_edges.items():
        if len(l) == 2:
            folds.append(np.degrees(np.arccos(np.clip(abs(nrm[l[0]] @ nrm[l[1]]), -1, 1))))
    print('fold deg between adjacent tris:', q(folds), ' (>30: %d, >60: %d)' % (sum(x > 30 for x in folds), sum(x > 60 for x in folds)))
    # border: distance to surface relative to radius
    bv = sorted(bverts)
    if bv:
        print('border verts %d: r/diag' % len(bv), q(R[bv] / diag))
    # joins
    joins_border = sum(1 for v in range(len(V)) if cdeg[v] > 0 and inF[v] and v in bverts)
    joins_inner = sum(1 for v in range(len(V)) if cdeg[v] > 0 and inF[v] and v not in bverts)
    print('curve-sheet joins: at border verts %d, at interior verts %d; curve vertices %d; curve branch pts %d, tips %d' %
          (joins_border, joins_inner, int((cdeg > 0).sum()), int(((cdeg >= 3) & ~inF).sum()), int(((cdeg == 1) & ~inF).sum())))
    # coverage of the surface by swept spheres (sampled on edges and triangles)
    cs, rs = [V], [R]
    for a, b in E:
        for t in np.linspace(0.1, 0.9, 9):
            cs.append(((1 - t) * V[a] + t * V[b])[None]); rs.append(np.array([(1 - t) * R[a] + t * R[b]]))
    for f in F:
        for u in np.linspace(0, 1, 6):
            for w in np.linspace(0, 1 - u, 6):
                bc = np.array([1 - u - w, u, w])
                cs.append((bc @ V[f])[None]); rs.append(np.array([bc @ R[f]]))
    cs = np.vstack(cs); rs = np.concatenate(rs)
    gaps = np.empty(len(P))
    for s in range(0, len(P), 256):
        dd = np.linalg.norm(P[s:s + 256, None, :] - cs[None], axis=-1) - rs[None]
        gaps[s:s + 256] = dd.min(1)
    print('surface gap to swept spheres / diag:', q(gaps / diag, (50, 90, 99, 100)))
    far = gaps > 0.03 * diag
    print('surface vertices farther than 3 %% diag: %d of %d%s' %
          (int(far.sum()), len(P), ', bbox %s - %s' % (P[far].min(0).round(2), P[far].max(0).round(2)) if far.any() else ''))
    # sides against the distance of their ends to the surface (auto's radii): border and interior sheet edges apart
    def dlen(es):
        return np.array([np.linalg.norm(V[a] - V[b]) / min(d[a], d[b]) for a, b in es])
    inner = [e for e, l in tri_edges.items() if len(l) == 2]
    print('border side / smaller distance:', q(dlen(border)) if border else '-',
          ' interior sheet edge / smaller distance:', q(dlen(inner)) if inner else '-')
    # centred: far-side over near-side distance along the ray from the centre away from its nearest surface point
    print('far side / near side distance (1 = centred):', q(centred(V, A, B, C, d)))
    # spheres poking out: centre dist < r?  (r / d > 1 means ball crosses surface)
    print('balls crossing surface (r > 1.05 d): %d of %d' % (int((R > 1.05 * d).sum()), len(V)))


if __name__ == '__main__':
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    for medial in [sys.argv[1]] + sys.argv[3:]:
        main(medial, sys.argv[2])

