#!/usr/bin/env python3
"""Where the seeds of the random evaluation set miss (issue 16): for every seed run by bench/random_set.sh, the
targets it misses, and the skeleton element nearest to its worst hex (final mesh, and raw mesh when OUT/SEED/raw.mesh
exists) and to its Hausdorff maximum.

    bench/classify_random.py OUT [FIRST LAST]     (OUT as given to random_set.sh; needs build/bin/mesohex)

The nearest element is the input skeleton vertex whose ball (distance / radius) is nearest to the point, named by its
kind: extremity, joint (with its turn angle), branching point (with the smallest angle between its edges and its
largest radius over its shortest edge), leaflet vertex (interior, border, BL-joint = border with a branch edge, root =
interior with a branch edge). One line per seed, then counts per kind. Pure Python (no numpy)."""
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


def worst_hex_centroid(mesh):
    q = json.loads(subprocess.run([MESOHEX, "quality", mesh, "--json"], capture_output=True, text=True).stdout)
    h = q["worst_hexes"][0]["hex"]
    verts, hexes = read_medit(mesh)
    c = [0.0, 0.0, 0.0]
    for v in hexes[h]:
        for k in range(3):
            c[k] += verts[v][k] / 8
    return tuple(c), q["sj_min"]


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
        kind = "sheet" if "(sheet)" in gen else "tree"
        c, sj = worst_hex_centroid(os.path.join(d, "mesh.mesh"))
        v, dist = sk.nearest(c)
        wk = sk.kind(v)
        at = h["mesh_to_surface_at"] if h["mesh_to_surface_max"] >= h["surface_to_mesh_max"] else h["surface_to_mesh_at"]
        side = "outside" if h["mesh_to_surface_max"] >= h["surface_to_mesh_max"] else "uncovered"
        hv, hdist = sk.nearest(tuple(at))
        raw = ""
        rawp = os.path.join(d, "raw.mesh")
        if os.path.exists(rawp):
            rc, rsj = worst_hex_centroid(rawp)
            rv, _ = sk.nearest(rc)
            raw = " | raw %.3f at v%d %s" % (rsj, rv, sk.kind(rv))
        print("%3d %-5s miss %-10s minSJ %.3f avg %.3f H %.2f%% | worst at v%d %s (%s) %.1fr | H %s at v%d %s (%s)%s"
              % (seed, kind, ",".join(miss), q["sj_min"], q["sj_avg"], hd, v, wk, sk.detail(v), dist, side, hv,
                 sk.kind(hv), sk.detail(hv), raw))
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
