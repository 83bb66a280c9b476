#!/usr/bin/env python3
"""Acceptance check of issue 22 from outside the project (docs/blocks.md, "Acceptance audit (session 24)").

Writes hand-style meso-skeletons directly as .obj / .skel files (not through `mesohex generate`), meshes each with
`mesohex mesh SKEL --raw -o X.mesh --report X.json`, and checks the .mesh with its own reader:

  - validity: every hex's scaled Jacobian (8 corners and the centre, as Verdict) > 0, no repeated corner, every quad
    face in at most 2 hexes, every boundary edge in exactly 2 boundary quads, every boundary vertex's link one cycle;
  - Euler characteristic V - E + F - H of the hex mesh = V - E + F of the skeleton file;
  - hex count and irregular edges (interior: valence != 4; boundary: valence != 2, counted here) = the report's
    `predicted`; where this script can derive the count itself it checks that too (plates with docked walls:
    2 per face + 2 per boundary edge of the file; stars: 4 per branch edge of the meshed skeleton + 8 per block;
    a star with a block: no interior irregular edge, boundary valence 1 / 3 edges from the cube's free / docked faces);
  - blocks only where expected: a near-orthogonal star perturbed by at most 10 degrees must get its block; a star
    with a pair angle outside [65, 115] U [155, 180] degrees (120-degree Y, tetrahedral) never; a T / X fan may;
  - where a block (8-hex or fan block) is accepted, `--no-blocks` gives more interior irregular edges;
  - a refusal (exit status 3) must name the skeleton vertex ("vertex N") and suggest an edit.

Kinds: `wall` (n x n plate, n = 2..6, a wall 1-4 edges long ending inside, on the border, or across, one or both
sides, tilted up to 30 degrees), `fanbranch` (T / X fans of 1-3 fan edges, strips 1-2 quads wide, off the right
angles by up to 6 degrees, a 3-edge branch at one or both fan ends at 0-150 degrees off the fan line), `cubestar`
(3- to 6-stars on a cube's axes, rotated at random, each direction perturbed by up to 15 degrees), `ystar` (exact 120
degrees, in a random plane), `tetrastar` (exact tetrahedral, random rotation); arms of 1-3 edges, radii 0.1 - 0.4 of
the edge. Deterministic (seeded).

  bench/issue22_check.py [--mesohex build/bin/mesohex] [--out DIR] [--count N] [--seed S] [--jobs 2]
                         [--kinds wall,fanbranch,cubestar,ystar,tetrastar] [--finish K] [--tsv FILE] [--keep-failing DIR]

--finish K also finishes the first K accepted cases of every kind in their thickened domains (`mesohex thicken`,
`mesh --surface`) and checks the final mesh's validity and Euler characteristic.
"""
import argparse
import concurrent.futures
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# ---------------------------------------------------------------------------------------------------------------------
# Vectors


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(s, a):
    return (s * a[0], s * a[1], s * a[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a):
    n = norm(a)
    return mul(1 / n, a) if n > 0 else (0.0, 0.0, 0.0)


def angle_deg(a, b):
    return math.degrees(math.acos(max(-1.0, min(1.0, dot(unit(a), unit(b))))))


def rotation(axis, ang):
    """3 x 3 rotation matrix (rows) about a unit axis by ang radians (Rodrigues)."""
    x, y, z = unit(axis)
    c, s, t = math.cos(ang), math.sin(ang), 1 - math.cos(ang)
    return ((t * x * x + c, t * x * y - s * z, t * x * z + s * y), (t * x * y + s * z, t * y * y + c, t * y * z - s * x),
            (t * x * z - s * y, t * y * z + s * x, t * z * z + c))


def apply(m, v):
    return (dot(m[0], v), dot(m[1], v), dot(m[2], v))


def random_rotation(rng):
    axis = unit((rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
    return rotation(axis, rng.uniform(0, 2 * math.pi))


def perturb(rng, d, max_deg):
    """d turned by an angle uniform in [0, max_deg] about a random axis normal to d."""
    d = unit(d)
    r = unit((rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
    axis = unit(cross(d, r))
    return apply(rotation(axis, math.radians(rng.uniform(0, max_deg))), d)


# ---------------------------------------------------------------------------------------------------------------------
# Skeletons: points, radii, branch edges, quad faces (0-based), written as .obj (1-based, radius comments) or .skel.


class Skel:
    def __init__(self):
        self.points, self.radii, self.edges, self.faces = [], [], [], []

    def point(self, p, r):
        self.points.append(tuple(float(x) for x in p))
        self.radii.append(r)
        return len(self.points) - 1

    def polyline(self, start, pts, r):
        ids = [start]
        for p in pts:
            ids.append(self.point(p, r))
            self.edges.append((ids[-2], ids[-1]))
        return ids

    def all_edges(self):
        """Branch edges and face sides, each once."""
        seen, out = set(), []
        for a, b in self.edges + [(f[i], f[(i + 1) % len(f)]) for f in self.faces for i in range(len(f))]:
            k = (min(a, b), max(a, b))
            if k not in seen:
                seen.add(k)
                out.append(k)
        return out

    def euler(self):
        return len(self.points) - len(self.all_edges()) + len(self.faces)

    def boundary_edges(self):
        count = {}
        for f in self.faces:
            for i in range(len(f)):
                a, b = f[i], f[(i + 1) % len(f)]
                k = (min(a, b), max(a, b))
                count[k] = count.get(k, 0) + 1
        return sum(1 for c in count.values() if c == 1)

    def write_obj(self, path):
        with open(path, "w") as f:
            f.write("# hand-written meso-skeleton (bench/issue22_check.py)\n")
            for p in self.points:
                f.write("v %.12g %.12g %.12g\n" % p)
            for i, r in enumerate(self.radii):
                f.write("# mesohex radius %d %.12g\n" % (i + 1, r))
            for a, b in self.edges:
                f.write("l %d %d\n" % (a + 1, b + 1))
            for q in self.faces:
                f.write("f " + " ".join(str(i + 1) for i in q) + "\n")

    def write_skel(self, path):
        assert not self.faces
        nb = [[] for _ in self.points]
        for a, b in self.edges:
            nb[a].append(b)
            nb[b].append(a)
        with open(path, "w") as f:
            f.write("ID Cx Cy Cz RADIUS #NEIGHBORS NEIGHBORS_LIST\n%d\n" % len(self.points))
            for i, p in enumerate(self.points):
                f.write("%d %.12g %.12g %.12g %.12g %d %s\n" % (i, *p, self.radii[i], len(nb[i]),
                                                                  " ".join(map(str, nb[i]))))


def lattice_quads(s, lat, nu, nv):
    for i in range(nu):
        for j in range(nv):
            s.faces.append((lat[i][j], lat[i + 1][j], lat[i + 1][j + 1], lat[i][j + 1]))


# ---------------------------------------------------------------------------------------------------------------------
# Case builders. Each returns (Skel, description dict); the dict holds what is expected.


def build_wall(rng, i):
    n = rng.randint(2, 6)
    r = round(rng.uniform(0.1, 0.4), 3)
    c = rng.randint(1, n - 1)  # an inner grid line of the plate (column 0 / n would be a flange on the border)
    mode = rng.choice(["inside", "inside", "border", "border", "across"])
    if mode == "inside" and n < 3:
        mode = "border"
    if mode == "inside":
        length = rng.randint(1, min(4, n - 2))
        j0 = rng.randint(1, n - 1 - length)
    elif mode == "border":
        length = rng.randint(1, min(4, n - 1))
        j0 = 0 if rng.random() < 0.5 else n - length
    else:
        length, j0 = n, 0
    sides = rng.choice([1, 1, 2])
    rows = [rng.randint(1, 3) for _ in range(sides)]
    # The second side's wall over a part of the chain only (degree 3 and 4 on one chain), in a third of the cases.
    sub = (0, length)
    if sides == 2 and length > 1 and rng.random() < 0.33:
        a = rng.randint(0, length - 1)
        sub = (a, rng.randint(a + 1, length))
    rw = r if rng.random() < 0.75 else round(rng.uniform(0.1, 0.4), 3)  # the walls' radius (the plate's: r)
    tilt = [rng.choice([0, 0, 0, 10, 20, 30]) for _ in range(sides)]
    noise = rng.choice([0, 0, 0.05, 0.1])  # hand-drawn: plate vertices off the grid (in the plane), not on the chain
    s = Skel()
    lat = [[s.point((x + (rng.uniform(-noise, noise) if x != c else 0), y + rng.uniform(-noise, noise), 0.0), r)
            for y in range(n + 1)] for x in range(n + 1)]
    lattice_quads(s, lat, n, n)
    for side in range(sides):
        up = 1.0 if side == 0 else -1.0
        t = math.radians(tilt[side])
        lo, hi = (0, length) if side == 0 else sub
        w = [[lat[c][j0 + j]] for j in range(lo, hi + 1)]
        for j in range(lo, hi + 1):
            for k in range(1, rows[side] + 1):
                w[j - lo].append(s.point((c + k * math.sin(t), j0 + j, up * k * math.cos(t)), rw))
        lattice_quads(s, w, hi - lo, rows[side])
    name = f"wall n{n} c{c} {mode} j{j0}+{length} sides{sides} rows{rows} tilt{tilt} noise{noise} sub{sub} r{r}/{rw}"
    # Docked (not across): the raw mesh is the standard formula, 2 per face + 2 per boundary edge (docs/blocks.md).
    own = 2 * len(s.faces) + 2 * s.boundary_edges() if mode != "across" else None
    return s, {"kind": "wall", "name": name, "block": "fan-may" if mode == "across" else "none", "own_hexes": own}


def build_fanbranch(rng, i):
    x = rng.random() < 0.5
    k = rng.randint(1, 3)  # fan edges
    m = rng.randint(1, 2)  # strip width in quads
    r = round(rng.uniform(0.1, 0.4), 3)
    base = [0, 90, 180, 270] if x else [0, 90, 180]
    jitter = rng.choice([0, 0, 3, 6])
    angles = [a + rng.uniform(-jitter, jitter) for a in base]
    s = Skel()
    fan = [s.point((0.0, 0.0, float(j)), r) for j in range(k + 1)]
    for a in angles:
        d = (math.cos(math.radians(a)), math.sin(math.radians(a)), 0.0)
        lat = [[fan[j] if ii == 0 else None for j in range(k + 1)] for ii in range(m + 1)]
        for ii in range(1, m + 1):
            for j in range(k + 1):
                lat[ii][j] = s.point(add(s.points[fan[j]], mul(ii, d)), r)
        lattice_quads(s, lat, m, k)
    ends = rng.choice(["top", "top", "both"])
    thetas = [0, 0, 10, 20, 30, 45, 60, 90, 120, 150]
    phis = [270, 45, 0, 22.5, 135, 315] if not x else [45, 0, 22.5, 135, 10]
    br = []
    for e in (["top"] if ends == "top" else ["top", "bottom"]):
        th, ph = rng.choice(thetas), rng.choice(phis)
        t, p = math.radians(th), math.radians(ph)
        sign = 1.0 if e == "top" else -1.0
        d = (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), sign * math.cos(t))
        w = fan[k] if e == "top" else fan[0]
        s.polyline(w, [add(s.points[w], mul(q, d)) for q in (1, 2, 3)], r)
        br.append(f"{e} {th}/{ph:g}")
    name = f"{'X' if x else 'T'} fan k{k} m{m} jit{jitter} {' '.join(br)} r{r}"
    return s, {"kind": "fanbranch", "name": name, "block": "fan-may", "own_hexes": None}


CUBE_SETS = {3: [(1, 0, 0), (0, 1, 0), (0, 0, 1)],
             4: [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0)],
             "4b": [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, 0, 1)],
             "3t": [(1, 0, 0), (-1, 0, 0), (0, 1, 0)],
             5: [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)],
             6: [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]}


def star(rng, dirs, r):
    s = Skel()
    c = s.point((0.0, 0.0, 0.0), r)
    arms = []
    own = rng.random() < 0.25  # each arm its own radius (0.1 - 0.4 of the edge) in a quarter of the stars
    for d in dirs:
        n = rng.randint(1, 3)
        L = rng.uniform(0.8, 1.2)
        s.polyline(c, [mul(q * L, d) for q in range(1, n + 1)], round(rng.uniform(0.1, 0.4), 3) if own else r)
        arms.append(n)
    return s, arms


def pair_angles(dirs):
    return [angle_deg(dirs[a], dirs[b]) for a in range(len(dirs)) for b in range(a + 1, len(dirs))]


def build_cubestar(rng, i):
    key = rng.choice([3, "3t", 4, "4b", 5, 6])
    axes = CUBE_SETS[key]
    dev = rng.choice([0, 5, 10, 15])
    rot = random_rotation(rng)
    dirs = [perturb(rng, apply(rot, a), dev) for a in axes]
    r = round(rng.uniform(0.1, 0.4), 3)
    s, arms = star(rng, dirs, r)
    pa = pair_angles(dirs)
    # An accepted block has every pair angle in [65, 115] or [155, 180] (docs/blocks.md, "Acceptance"); with every
    # direction at most 10 degrees off its axis the pairs are within 20 of 90 / 180 and the block must be accepted.
    if any(65 > a or 115 < a < 155 for a in pa):
        exp = "never"
    elif dev <= 10:
        exp = "must"
    else:
        exp = "may"
    # Cube faces: docked (an arm) or free; cube edges between two adjacent faces.
    docked = set(axes)
    faces6 = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    dd = ff = 0
    for a in range(6):
        for b in range(a + 1, 6):
            if dot(faces6[a], faces6[b]) == 0:
                da, db = faces6[a] in docked, faces6[b] in docked
                dd += da and db
                ff += (not da) and (not db)
    name = f"cube{key} dev{dev} arms{arms} r{r} pairs {min(pa):.0f}-{max(pa):.0f}"
    return s, {"kind": "cubestar", "name": name, "block": exp, "star": True, "block_val": {"1": 2 * ff, "3": 2 * dd}}


def build_ystar(rng, i):
    rot = random_rotation(rng)
    dirs = [apply(rot, (math.cos(a), math.sin(a), 0.0)) for a in (0, 2 * math.pi / 3, 4 * math.pi / 3)]
    r = round(rng.uniform(0.1, 0.4), 3)
    s, arms = star(rng, dirs, r)
    return s, {"kind": "ystar", "name": f"Y arms{arms} r{r}", "block": "never", "star": True}


def build_tetrastar(rng, i):
    rot = random_rotation(rng)
    dirs = [apply(rot, unit(d)) for d in ((1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1))]
    r = round(rng.uniform(0.1, 0.4), 3)
    s, arms = star(rng, dirs, r)
    return s, {"kind": "tetrastar", "name": f"tetra arms{arms} r{r}", "block": "never", "star": True}


BUILDERS = {"wall": build_wall, "fanbranch": build_fanbranch, "cubestar": build_cubestar, "ystar": build_ystar,
            "tetrastar": build_tetrastar}

# ---------------------------------------------------------------------------------------------------------------------
# The .mesh reader and the checks (independent of the project's code).

# VTK / Medit hex order: bottom 0-1-2-3 counter-clockwise seen from above, 4-7 above them.
CORNER_NEIGHBOURS = ((1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3))
FACES = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
EDGES = ((0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7))


def read_mesh(path):
    tok = open(path).read().split()
    pts, hexes, i = [], [], 0
    while i < len(tok):
        t = tok[i]
        if t == "Vertices":
            n = int(tok[i + 1])
            i += 2
            for _ in range(n):
                pts.append((float(tok[i]), float(tok[i + 1]), float(tok[i + 2])))
                i += 4
        elif t == "Hexahedra":
            n = int(tok[i + 1])
            i += 2
            for _ in range(n):
                hexes.append(tuple(int(tok[i + k]) - 1 for k in range(8)))
                i += 9
        elif t in ("Quadrilaterals", "Triangles", "Edges", "Tetrahedra"):
            n = int(tok[i + 1])
            per = {"Quadrilaterals": 5, "Triangles": 4, "Edges": 3, "Tetrahedra": 5}[t]
            i += 2 + n * per
        else:
            i += 1
    return pts, hexes


def det3(a, b, c):
    return dot(a, cross(b, c))


def scaled_jacobian(p):
    """Verdict's hex scaled Jacobian: min over the 8 corners and the centre of det of the unit edge / axis vectors."""
    best = 1.0
    for c, (a, b, d) in enumerate(CORNER_NEIGHBOURS):
        e1, e2, e3 = sub(p[a], p[c]), sub(p[b], p[c]), sub(p[d], p[c])
        n1, n2, n3 = norm(e1), norm(e2), norm(e3)
        if n1 == 0 or n2 == 0 or n3 == 0:
            return 0.0
        best = min(best, det3(e1, e2, e3) / (n1 * n2 * n3))
    x1 = sub(add(add(p[1], p[2]), add(p[5], p[6])), add(add(p[0], p[3]), add(p[4], p[7])))
    x2 = sub(add(add(p[2], p[3]), add(p[6], p[7])), add(add(p[0], p[1]), add(p[4], p[5])))
    x3 = sub(add(add(p[4], p[5]), add(p[6], p[7])), add(add(p[0], p[1]), add(p[2], p[3])))
    n1, n2, n3 = norm(x1), norm(x2), norm(x3)
    if n1 == 0 or n2 == 0 or n3 == 0:
        return 0.0
    return min(best, det3(x1, x2, x3) / (n1 * n2 * n3))


def check_mesh(pts, hexes):
    """Validity, Euler characteristic and irregular edges of a hex mesh, from its connectivity and points only."""
    out = {"hexes": len(hexes), "problems": []}
    sj = [scaled_jacobian([pts[v] for v in h]) for h in hexes]
    out["sj_min"] = min(sj) if sj else 0.0
    out["inverted"] = sum(1 for x in sj if x <= 0)
    if any(len(set(h)) != 8 for h in hexes):
        out["problems"].append("hex with a repeated corner")
    faces, edges = {}, {}
    for hi, h in enumerate(hexes):
        for f in FACES:
            key = tuple(sorted(h[k] for k in f))
            faces.setdefault(key, []).append((hi, tuple(h[k] for k in f)))
        for a, b in EDGES:
            key = (min(h[a], h[b]), max(h[a], h[b]))
            edges[key] = edges.get(key, 0) + 1
    if any(len(v) > 2 for v in faces.values()):
        out["problems"].append("face in more than 2 hexes")
    bfaces = [v[0][1] for v in faces.values() if len(v) == 1]
    bedge = {}
    for q in bfaces:
        for k in range(4):
            a, b = q[k], q[(k + 1) % 4]
            bedge.setdefault((min(a, b), max(a, b)), []).append(q)
    if any(len(v) != 2 for v in bedge.values()):
        out["problems"].append("boundary edge not in exactly 2 boundary quads")
    # Every boundary vertex's link (its boundary quads, joined through shared boundary edges) is one cycle.
    around = {}
    for e, qs in bedge.items():
        for v in e:
            around.setdefault(v, []).append(e)
    for v, es in around.items():
        # quads at v are joined by the boundary edges at v; a disc link: #quads = #edges and connected
        qs = {}
        for e in es:
            for q in bedge[e]:
                qs.setdefault(tuple(sorted(q)), []).append(e)
        if len(qs) != len(es):
            out["problems"].append(f"boundary vertex {v + 1} not manifold")
            break
        seen, stack = set(), [next(iter(qs))]
        adj = {}
        for e in es:
            ends = [tuple(sorted(q)) for q in bedge[e]]
            if len(ends) == 2:
                adj.setdefault(ends[0], []).append(ends[1])
                adj.setdefault(ends[1], []).append(ends[0])
        while stack:
            q = stack.pop()
            if q in seen:
                continue
            seen.add(q)
            stack.extend(adj.get(q, []))
        if len(seen) != len(qs):
            out["problems"].append(f"boundary vertex {v + 1} not manifold (link of {len(qs)} quads not connected)")
            break
    used = {v for h in hexes for v in h}
    out["euler"] = len(used) - len(edges) + len(faces) - len(hexes)
    bset = set(bedge)
    interior, boundary = {}, {}
    for e, val in edges.items():
        if e in bset:
            if val != 2:
                boundary[str(val)] = boundary.get(str(val), 0) + 1
        elif val != 4:
            interior[str(val)] = interior.get(str(val), 0) + 1
    out["irregular"] = {"boundary": boundary, "interior": interior}
    out["valid"] = not out["problems"] and out["inverted"] == 0
    return out


# ---------------------------------------------------------------------------------------------------------------------
# One case

SUGGESTION = re.compile(r"\b(edit|turn|move|start|make|split|root|shorten|lengthen|remove|add|thin|change|give|"
                        r"straighten|reduce|lower|raise|use|end|run|keep|cut|join|dock|tilt|bend)\b", re.I)


MESH_ARGS = []  # --mesh-args: extra options for every `mesohex mesh` run


def run_mesh(binary, skel, base, extra=()):
    rep = base + ".json"
    for f in (rep, base + ".mesh"):
        if os.path.exists(f):
            os.remove(f)
    m = subprocess.run([binary, "mesh", skel, "--raw", "-o", base + ".mesh", "--report", rep, "-q", "--threads", "1",
                        *MESH_ARGS, *extra], capture_output=True, text=True)
    return m, rep


def run_case(binary, out, idx, case):
    s, d = case
    ext = ".skel" if d.get("star") and idx % 2 == 0 else ".obj"
    base = os.path.join(out, f"{d['kind']}_{idx:04d}")
    skel = base + ext
    (s.write_skel if ext == ".skel" else s.write_obj)(skel)
    res = {"kind": d["kind"], "name": d["name"], "file": skel, "fails": [], "info": "", "euler": s.euler()}
    m, rep = run_mesh(binary, skel, base)
    err = m.stderr.strip()
    if m.returncode == 3:
        last = err.split("\n")[-1]
        ok = re.search(r"vertex \d+", last) and SUGGESTION.search(last.split("vertex", 1)[1])
        res["class"] = "refused" if ok else "refused-bad"
        res["info"] = last[:300]
        if d["block"] == "must":
            res["class"] = "fail"
            res["fails"].append("refused a star that must get a block")
        return res
    if m.returncode not in (0, 5) or not os.path.exists(rep) or not os.path.exists(base + ".mesh"):
        res["class"] = "fail"
        res["fails"].append(f"exit {m.returncode}: {err[-200:]}")
        return res
    r = json.load(open(rep))
    p = r["predicted"]
    pts, hexes = read_mesh(base + ".mesh")
    q = check_mesh(pts, hexes)
    res["hexes"], res["sj_min"], res["irregular"] = q["hexes"], q["sj_min"], q["irregular"]
    if q["problems"]:
        res["fails"].append("invalid: " + "; ".join(q["problems"][:3]))
    if q["inverted"]:
        res["fails"].append(f"{q['inverted']} inverted (SJ min {q['sj_min']:.3f})")
    if q["euler"] != s.euler():
        res["fails"].append(f"Euler {q['euler']} vs skeleton {s.euler()}")
    if q["hexes"] != p["hexes"]:
        res["fails"].append(f"hexes {q['hexes']} vs predicted {p['hexes']}")
    if q["irregular"] != p["irregular_edges"]:
        res["fails"].append(f"irregular {q['irregular']} vs predicted {p['irregular_edges']}")
    blocks8 = p["compatible_blocks"]
    fanb = p["fan_blocks"]["edges"] + p["fan_blocks"]["caps"]
    res["blocks"] = (blocks8, fanb)
    exp = d["block"]
    if exp == "never" and blocks8 + fanb:
        res["fails"].append(f"{blocks8} block(s) on a star that must not get one")
    if exp == "must" and blocks8 != 1:
        res["fails"].append("no block on a near-orthogonal star (directions within 10 degrees of the axes)")
    if exp == "none" and blocks8 + fanb:
        res["fails"].append(f"blocks {blocks8} / fan blocks {fanb} where none was expected")
    if d.get("own_hexes") is not None:
        ms = r["meshed_skeleton"]
        # The file's count, or the meshed skeleton's when a repair split plate strips (--docked-foot-split).
        own = d["own_hexes"] if ms["faces"] == len(s.faces) else 2 * ms["faces"] + 2 * ms["boundary_edges"]
        if own != q["hexes"]:
            res["fails"].append(f"hexes {q['hexes']} vs 2 x faces + 2 x boundary edges {own}")
    if d.get("star"):
        own = 4 * r["meshed_skeleton"]["edges"] + 8 * blocks8
        if own != q["hexes"]:
            res["fails"].append(f"hexes {q['hexes']} vs 4 x meshed edges + 8 x blocks {own}")
        if blocks8:
            if q["irregular"]["interior"]:
                res["fails"].append(f"interior irregular edges {q['irregular']['interior']} at a block")
            # Tubes: 4 corner edges per chunk and 8 at each extremity cap (valence 1); the block's cube edges.
            arms = r["meshed_skeleton"]["extremities"]
            v1 = 4 * r["meshed_skeleton"]["edges"] + 8 * arms + d["block_val"]["1"]
            want = {k: v for k, v in (("1", v1), ("3", d["block_val"]["3"])) if v}
            if q["irregular"]["boundary"] != want:
                res["fails"].append(f"boundary irregular {q['irregular']['boundary']} vs by hand {want}")
    if blocks8 + fanb and exp != "never":
        m2, rep2 = run_mesh(binary, skel, base + "_paper", ["--no-blocks"])
        if m2.returncode in (0, 5) and os.path.exists(rep2):
            q2 = check_mesh(*read_mesh(base + "_paper.mesh"))
            mine = sum(q["irregular"]["interior"].values())
            paper = sum(q2["irregular"]["interior"].values())
            tot = mine + sum(q["irregular"]["boundary"].values())
            tot2 = paper + sum(q2["irregular"]["boundary"].values())
            res["paper"] = (mine, paper, tot, tot2)
            res["info"] += f"interior irregular {mine} vs paper {paper} (all {tot} vs {tot2}); "
            if mine >= paper:
                res["fails"].append(f"interior irregular {mine} with blocks, {paper} in the paper's layout")
        else:
            res["info"] += f"--no-blocks exit {m2.returncode}; "
    res["info"] += f"min SJ {q['sj_min']:.3f}"
    res["class"] = "fail" if res["fails"] else "pass"
    return res


def finish_case(binary, out, res):
    """Thicken the skeleton, mesh in the domain (1 subdivision level), check the final mesh (validity, Euler
    characteristic); where the raw mesh had a block, the same with `--no-blocks`, to compare the finished meshes'
    interior irregular edges (padding turns the raw boundary's valence-1 / 3 edges into interior valence-3 / 5 ones)."""
    skel = res["file"]
    base = os.path.splitext(skel)[0] + "_fin"
    t = subprocess.run([binary, "thicken", skel, "-o", base + ".off"], capture_output=True, text=True)
    if t.returncode != 0:
        return f"thicken exit {t.returncode}"
    text = []
    for tag, extra in (("", []), ("no-blocks ", ["--no-blocks"])):
        if extra and not sum(res.get("blocks", (0, 0))):
            break
        m = subprocess.run([binary, "mesh", skel, "--surface", base + ".off", "-o", base + ".mesh", "--report",
                            base + ".json", "--levels", "1", "-q", "--threads", "1", *MESH_ARGS, *extra],
                           capture_output=True, text=True)
        if m.returncode not in (0, 5):
            text.append(f"{tag}mesh exit {m.returncode}: {m.stderr.strip()[-200:]}")
            continue
        q = check_mesh(*read_mesh(base + ".mesh"))
        h = json.load(open(base + ".json")).get("hausdorff", {}).get("relative_max", float("nan"))
        text.append(f"{tag}{q['hexes']} hexes, SJ min {q['sj_min']:.3f}, inverted {q['inverted']}, Euler {q['euler']}"
                    f"{' (skeleton ' + str(res['euler']) + ')' if q['euler'] != res['euler'] else ''}, "
                    f"problems {len(q['problems'])}, Hausdorff {100 * h:.2f} %, interior irregular "
                    f"{sum(q['irregular']['interior'].values())} {q['irregular']['interior']}")
    return "; ".join(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesohex", default=os.path.join(HERE, "build", "bin", "mesohex"))
    ap.add_argument("--out", default="/tmp/issue22_check")
    ap.add_argument("--count", type=int, default=60, help="cases per kind")
    ap.add_argument("--seed", type=int, default=22)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--kinds", default=",".join(BUILDERS))
    ap.add_argument("--finish", type=int, default=0, help="finish the first K accepted cases of every kind")
    ap.add_argument("--tsv", help="one line per case: kind, name, class, failures / info")
    ap.add_argument("--keep-failing", help="copy the skeleton files of failing cases here")
    ap.add_argument("--mesh-args", default="", help="extra options for every mesh run, e.g. '--docked-foot-split 2'")
    a = ap.parse_args()
    MESH_ARGS.extend(a.mesh_args.split())
    os.makedirs(a.out, exist_ok=True)
    cases = []
    for kind in a.kinds.split(","):
        rng = random.Random(f"{a.seed}-{kind}")
        cases += [BUILDERS[kind](rng, i) for i in range(a.count)]
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as ex:
        results = list(ex.map(lambda ic: run_case(a.mesohex, a.out, *ic), enumerate(cases)))
    kinds = list(dict.fromkeys(r["kind"] for r in results))
    classes = ["pass", "refused", "refused-bad", "fail"]
    print(f"{'kind':10} " + " ".join(f"{c:>11}" for c in classes) + "  blocks accepted")
    for k in kinds + ["all"]:
        rs = [r for r in results if k == "all" or r["kind"] == k]
        row = [sum(1 for r in rs if r["class"] == c) for c in classes]
        nb = sum(1 for r in rs if sum(r.get("blocks", (0, 0))))
        print(f"{k:10} " + " ".join(f"{x:>11}" for x in row) + f"  {nb:>6}")
    if a.tsv:
        with open(a.tsv, "w") as t:
            for r in results:
                t.write(f"{r['kind']}\t{r['name']}\t{r['class']}\t{' | '.join(r['fails']) or r['info']}\n")
    bad = [r for r in results if r["class"] in ("fail", "refused-bad")]
    if bad:
        print("\nfailing cases:")
    for r in bad:
        print(f"  {os.path.basename(r['file'])}  {r['name']}: {' | '.join(r['fails']) or r['info']}")
        if a.keep_failing:
            os.makedirs(a.keep_failing, exist_ok=True)
            shutil.copy(r["file"], a.keep_failing)
    if a.finish:
        print("\nfinished in the thickened domain:")
        for k in kinds:
            for r in [r for r in results if r["kind"] == k and r["class"] == "pass"][:a.finish]:
                print(f"  {os.path.basename(r['file'])}  {r['name']}: {finish_case(a.mesohex, a.out, r)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
