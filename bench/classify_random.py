#!/usr/bin/env python3
"""Where the seeds of the random evaluation set miss (issue 16): for every seed run by bench/random_set.sh, the
targets it misses, and the skeleton element nearest to its worst hex (final mesh, and raw mesh when OUT/SEED/raw.mesh
exists) and to its Hausdorff maximum.

    bench/classify_random.py OUT [FIRST LAST]     (OUT as given to random_set.sh; needs build/bin/mesohex)

The nearest element is the input skeleton vertex whose ball (distance / radius) is nearest to the point, named by its
kind: extremity, joint (with its turn angle), branching point (with the smallest angle between its edges and its
largest radius over its shortest edge), leaflet vertex (interior, border, BL-joint = border with a branch edge, root =
interior with a branch edge). Also per seed: the min SJ after every finishing stage of the kept attempt (raw, pad,
pad-improve, fit, improve, smooth), whether the worst final hex descends from a padding hex or a raw hex (uniform
refinement: hex h of the final mesh descends from padded hex h / 8^levels), and where the Hausdorff maximum is: the
domain uncovered (a domain point far from the mesh), the mesh bulging out of the domain, or a dent (a point of the
mesh's boundary far from the surface but inside the domain: the mesh does not fill it; ray parity on domain.off).
One line per seed, then counts per kind. Pure Python (no numpy).
"""
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MESOHEX = os.environ.get("MESOHEX", os.path.join(HERE, "build", "bin", "mesohex"))


def read_skeleton(path):
    pts, rad, edges, faces = [], {}, [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                pts.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == "l":
                edges.append((int(t[1]) - 1, int(t[2]) - 1))
            elif t[0] == "f":
                faces.append([int(x.split("/")[0]) - 1 for x in t[1:]])
            elif t[:3] == ["#", "mesohex", "radius"]:
                rad[int(t[3]) - 1] = float(t[4])
    return pts, [rad.get(i, 0.0) for i in range(len(pts))], edges, faces


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def angle(a, b):
    na, nb = norm(a), norm(b)
    if na == 0 or nb == 0:
        return 0.0
    return math.degrees(math.acos(max(-1.0, min(1.0, dot(a, b) / (na * nb)))))


class Skel:
    def __init__(self, path):
        self.p, self.r, self.e, self.f = read_skeleton(path)
        n = len(self.p)
        self.adj = [[] for _ in range(n)]
        for a, b in self.e:
            self.adj[a].append(b)
            self.adj[b].append(a)
        self.on_face = [False] * n
        side_count = {}
        for f in self.f:
            for i, v in enumerate(f):
                self.on_face[v] = True
                s = tuple(sorted((v, f[(i + 1) % len(f)])))
                side_count[s] = side_count.get(s, 0) + 1
        self.side_count = side_count

    def kind(self, v):
        adj = self.adj[v]
        if self.on_face[v]:
            branch = [w for w in adj if tuple(sorted((v, w))) not in self.side_count]
            border = any(self.side_count.get(tuple(sorted((v, w))), 0) == 1 for w in adj)
            if branch:
                return "BL-joint" if border else "leaflet root"
            return "leaflet border" if border else "leaflet interior"
        if len(adj) == 1:
            return "extremity"
        if len(adj) == 2:
            return "joint"
        return "branching point"

    def detail(self, v):
        k = self.kind(v)
        adj = self.adj[v]
        if k == "joint":
            a, b = adj
            turn = 180 - angle(sub(self.p[a], self.p[v]), sub(self.p[b], self.p[v]))
            return "turn %.0f" % turn
        if k == "branching point":
            dirs = [sub(self.p[w], self.p[v]) for w in adj]
            amin = min(angle(dirs[i], dirs[j]) for i in range(len(dirs)) for j in range(i + 1, len(dirs)))
            rmax = max([self.r[v]] + [self.r[w] for w in adj])
            lmin = min(norm(d) for d in dirs)
            return "deg %d, min angle %.0f, r/edge %.2f" % (len(adj), amin, rmax / lmin)
        if k == "extremity":
            w = adj[0]
            return "edge %.1f r" % (norm(sub(self.p[w], self.p[v])) / self.r[v])
        if self.on_face[v]:
            lens = [norm(sub(self.p[w], self.p[v])) for w in adj
                    if tuple(sorted((v, w))) in self.side_count]
            return "r/edge %.2f" % (self.r[v] / (sum(lens) / len(lens)))
        return ""

    def nearest(self, x):
        """The vertex of the nearest skeleton edge end (or face corner) to x, by distance / radius."""
        best, bv = None, -1
        for a, b in self.e:
            d = sub(self.p[b], self.p[a])
            L2 = dot(d, d)
            t = 0.0 if L2 == 0 else max(0.0, min(1.0, dot(sub(x, self.p[a]), d) / L2))
            q = (self.p[a][0] + t * d[0], self.p[a][1] + t * d[1], self.p[a][2] + t * d[2])
            dist = norm(sub(x, q)) / (self.r[a] + t * (self.r[b] - self.r[a]))
            v = a if t < 0.5 else b
            if best is None or dist < best - 1e-12:
                best, bv = dist, v
        # Prefer a branching point or leaflet vertex within 2.5 of its radii over a joint of the same edge: the junction
        # reaches into the first chunks.
        for v in range(len(self.p)):
            if self.kind(v) in ("branching point", "BL-joint", "leaflet root") and \
                    norm(sub(x, self.p[v])) < 2.5 * self.r[v]:
                if self.kind(bv) in ("joint", "extremity"):
                    bv = v
        return bv, best


def read_medit(path):
    verts, hexes = [], []
    with open(path) as f:
        toks = f.read().split()
    i = 0
    while i < len(toks):
        t = toks[i]
        if t == "Vertices":
            n = int(toks[i + 1])
            i += 2
            for _ in range(n):
                verts.append((float(toks[i]), float(toks[i + 1]), float(toks[i + 2])))
                i += 4
            continue
        if t == "Hexahedra":
            n = int(toks[i + 1])
            i += 2
            for _ in range(n):
                hexes.append([int(x) - 1 for x in toks[i:i + 8]])
                i += 9
            continue
        i += 1
    return verts, hexes


class Domain:
    """Point inside a closed triangle surface (OFF): parity of the crossings of a ray along +x, triangles bucketed on
    a y-z grid."""

    def __init__(self, path, cells=64):
        t = open(path).read().split()
        nv, nf = int(t[1]), int(t[2])
        i = 4
        self.p = [tuple(float(x) for x in t[i + 3 * k:i + 3 * k + 3]) for k in range(nv)]
        i += 3 * nv
        self.f = []
        for _ in range(nf):
            n = int(t[i])
            self.f.append(tuple(int(x) for x in t[i + 1:i + 1 + n]))
            i += 1 + n
        ys, zs = [q[1] for q in self.p], [q[2] for q in self.p]
        self.y0, self.z0 = min(ys), min(zs)
        self.hy, self.hz = (max(ys) - self.y0) / cells + 1e-12, (max(zs) - self.z0) / cells + 1e-12
        self.grid = {}
        for fi, f in enumerate(self.f):
            a = [self.p[v] for v in f]
            for iy in range(self.cell(min(q[1] for q in a), 1), self.cell(max(q[1] for q in a), 1) + 1):
                for iz in range(self.cell(min(q[2] for q in a), 2), self.cell(max(q[2] for q in a), 2) + 1):
                    self.grid.setdefault((iy, iz), []).append(fi)

    def cell(self, x, axis):
        return int((x - self.y0) / self.hy) if axis == 1 else int((x - self.z0) / self.hz)

    def inside(self, x):
        y, z = x[1] + 1.234567e-9, x[2] + 2.345678e-9  # off the triangles' edges
        crossings = 0
        for fi in self.grid.get((self.cell(x[1], 1), self.cell(x[2], 2)), []):
            a, b, d = (self.p[v] for v in self.f[fi][:3])
            det = (b[1] - a[1]) * (d[2] - a[2]) - (d[1] - a[1]) * (b[2] - a[2])
            if det == 0:
                continue
            u = ((y - a[1]) * (d[2] - a[2]) - (d[1] - a[1]) * (z - a[2])) / det
            v = ((b[1] - a[1]) * (z - a[2]) - (y - a[1]) * (b[2] - a[2])) / det
            if u >= 0 and v >= 0 and u + v <= 1 and a[0] + u * (b[0] - a[0]) + v * (d[0] - a[0]) > x[0]:
                crossings += 1
        return crossings % 2 == 1


def stage_chain(rep):
    """The min SJ after each finishing stage of the kept attempt, and the origin of final hex h (padding or raw)."""
    st = {s["stage"]: s for s in rep["stages"]}
    names = [("input", "raw"), ("pad", "pad"), ("pad-improve", "padimp"), ("fit", "fit"), ("improve", "imp"),
             ("untangle", "untangle"), ("smooth", "smooth")]
    chain = " ".join("%s %.3f" % (short, st[n]["sj_min"]) for n, short in names if n in st)
    raw_n = st["input"]["hexes"]
    padded_n = st["pad"]["hexes"] if "pad" in st else raw_n
    per = rep["stages"][-1]["hexes"] // padded_n

    def origin(h):
        return "pad" if h // per >= raw_n else "raw"
    return chain, origin


def worst_hex_centroid(mesh):
    q = json.loads(subprocess.run([MESOHEX, "quality", mesh, "--json"], capture_output=True, text=True).stdout)
    h = q["worst_hexes"][0]["hex"]
    verts, hexes = read_medit(mesh)
    c = [0.0, 0.0, 0.0]
    for v in hexes[h]:
        for k in range(3):
            c[k] += verts[v][k] / 8
    return tuple(c), q["sj_min"], h


def main():
    out = sys.argv[1]
    seeds = sorted(int(d) for d in os.listdir(out) if d.isdigit())
    if len(sys.argv) >= 4:
        seeds = [s for s in seeds if int(sys.argv[2]) <= s <= int(sys.argv[3])]
    counts = {}
    for seed in seeds:
        d = os.path.join(out, str(seed))
        rp = os.path.join(d, "report.json")
        if not os.path.exists(rp):
            print("%d: no report" % seed)
            continue
        rep = json.load(open(rp))
        q = rep["quality"]
        h = rep.get("hausdorff", {})
        hd = 100 * h.get("relative_max", 1)
        miss = []
        if q["sj_min"] < 0.3:
            miss.append("min")
        if q["sj_avg"] < 0.85:
            miss.append("avg")
        if hd > 1:
            miss.append("H")
        if q["inverted"] > 0:
            miss.append("inv")
        if not miss:
            continue
        sk = Skel(os.path.join(d, "skel.obj"))
        gen = open(os.path.join(d, "generate.log")).read()
        kind = "sheet" if "(sheet)" in gen else "character" if "(character)" in gen else "tree"
        c, sj, worst = worst_hex_centroid(os.path.join(d, "mesh.mesh"))
        chain, origin = stage_chain(rep)
        v, dist = sk.nearest(c)
        wk = sk.kind(v)
        at = h["mesh_to_surface_at"] if h["mesh_to_surface_max"] >= h["surface_to_mesh_max"] else h["surface_to_mesh_at"]
        side = "uncovered"
        if h["mesh_to_surface_max"] >= h["surface_to_mesh_max"]:
            side = "dent" if Domain(os.path.join(d, "domain.off")).inside(at) else "bulge"
        hv, hdist = sk.nearest(tuple(at))
        raw = ""
        rawp = os.path.join(d, "raw.mesh")
        if os.path.exists(rawp):
            rc, rsj, _ = worst_hex_centroid(rawp)
            rv, _ = sk.nearest(rc)
            raw = " | raw %.3f at v%d %s" % (rsj, rv, sk.kind(rv))
        print("%3d %-5s miss %-10s minSJ %.3f avg %.3f H %.2f%% | worst (%s hex) at v%d %s (%s) %.1fr | H %s at v%d %s "
              "(%s)%s | %s" % (seed, kind, ",".join(miss), q["sj_min"], q["sj_avg"], hd, origin(worst), v, wk,
                               sk.detail(v), dist, side, hv, sk.kind(hv), sk.detail(hv), raw, chain))
        key = ("minSJ" if "min" in miss or "inv" in miss else "H only", wk)
        counts[key] = counts.get(key, 0) + 1
        hkey = ("H", sk.kind(hv), side)
        if "H" in miss:
            counts[hkey] = counts.get(hkey, 0) + 1
    print()
    for k in sorted(counts, key=lambda k: (k[0], -counts[k])):
        print("%-6s %-45s %d" % (k[0], " / ".join(k[1:]), counts[k]))


if __name__ == "__main__":
    main()
