#!/usr/bin/env python3
# Experiment for issue 16 (sheets): the branch rooted inside a leaflet stands on the 4 faces around its root (about
# 2 leaflet edges wide), while its tube is 1-1.7 sheet radii (0.2-0.5 x the edge) wide, so its first chunk is a
# frustum about 3 times wider at the bottom than the tube: it sticks out above the plate and, once fitted, leaves the
# plate's top around the root uncovered. This script splits the 4 face strips crossing the leaflet edges at every
# rooted interior vertex (4 faces, one branch) so the root's neighbours lie K x the branch radius from it (at most
# halfway along the edge); the patch is then about the tube's size. Radii are interpolated, the rest is unchanged.
#
#   bench/root_patch_split.py SKEL.obj OUT.obj [K=1.2]
#
# A measuring tool; the library does the same now (stages/skeleton_repair, SkeletonRepairOptions::root_patch_factor),
# so run it on a skeleton with that step off to reproduce the measurement.
import math
import sys


def load(p):
    P, R, E, F = [], {}, [], []
    for line in open(p):
        t = line.split()
        if not t:
            continue
        if t[0] == 'v':
            P.append(tuple(map(float, t[1:4])))
        elif t[0] == 'l':
            E.append((int(t[1]) - 1, int(t[2]) - 1))
        elif t[0] == 'f':
            F.append([int(x) - 1 for x in t[1:]])
        elif line.startswith('# mesohex radius'):
            R[int(t[3]) - 1] = float(t[4])
    return P, R, E, F


def dist(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def main():
    src, dst = sys.argv[1], sys.argv[2]
    k = float(sys.argv[3]) if len(sys.argv) > 3 else 1.2
    P, R, E, F = load(src)
    fe = set(frozenset((f[i], f[(i + 1) % len(f)])) for f in F for i in range(len(f)))
    roots = []
    for v in sorted(set(x for f in F for x in f)):
        br = [e for e in E if v in e and frozenset(e) not in fe]
        if len(br) == 1 and sum(1 for g in F if v in g) == 4:
            w = br[0][0] if br[0][1] == v else br[0][1]
            roots.append((v, max(R[v], R[w])))
    cut = {}

    def point_on(p, q, t):  # the new point on edge (p, q), t from p (shared by the strip's faces)
        if (q, p) in cut:
            return cut[(q, p)]
        if (p, q) not in cut:
            P.append(tuple(x + (y - x) * t for x, y in zip(P[p], P[q])))
            R[len(P) - 1] = R[p] + (R[q] - R[p]) * t
            cut[(p, q)] = len(P) - 1
            E.remove((p, q) if (p, q) in E else (q, p))
            E.extend([(p, len(P) - 1), (len(P) - 1, q)])
        return cut[(p, q)]

    def faces_with(p, q):
        return [i for i, f in enumerate(F)
                if p in f and q in f and abs(f.index(p) - f.index(q)) in (1, len(f) - 1)]

    def split_strip(p, q, t):  # every face of the strip crossing edge (p, q) in two
        todo = [(p, q, i) for i in faces_with(p, q)]
        done = set()
        while todo:
            p, q, i = todo.pop()
            if i in done:
                continue
            done.add(i)
            f = F[i]
            n = len(f)
            ip, iq = f.index(p), f.index(q)
            step = 1 if (ip + 1) % n == iq else -1
            p2, q2 = f[(ip - step) % n], f[(iq + step) % n]
            a, b = point_on(p, q, t), point_on(p2, q2, t)
            if step == 1:
                F[i] = [p, a, b, p2]
                F.append([a, q, q2, b])
            else:
                F[i] = [p2, b, a, p]
                F.append([b, q2, q, a])
            done.add(len(F) - 1)
            E.append((a, b))
            todo += [(p2, q2, j) for j in faces_with(p2, q2) if j not in done]

    for v, rb in roots:
        nb = set()
        for f in F:
            if v in f:
                i = f.index(v)
                nb |= {f[(i + 1) % 4], f[(i - 1) % 4]}
        for u in sorted(nb):
            split_strip(v, u, min(0.5, k * rb / dist(P[u], P[v])))
        print("root vertex %d: branch radius %.3f, patch split at %.2f x r" % (v + 1, rb, k), file=sys.stderr)
    with open(dst, 'w') as o:
        for p in P:
            o.write("v %.17g %.17g %.17g\n" % p)
        for i in range(len(P)):
            o.write("# mesohex radius %d %.17g\n" % (i + 1, R[i]))
        for a, b in E:
            o.write("l %d %d\n" % (a + 1, b + 1))
        for f in F:
            o.write("f " + " ".join(str(x + 1) for x in f) + "\n")


if __name__ == "__main__":
    main()
