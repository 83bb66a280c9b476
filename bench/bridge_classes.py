#!/usr/bin/env python3
"""Bridges between branching points of input skeletons, and the two kinds the shared curve skeletons miss at
(issue 16 item 5; docs/junctions.md, "The three shared skeletons that miss"):

- overlapping ends: the two branching points' balls overlap, (r_a + r_b) / |ab| > 1 (dinopet's torso and shoulders,
  1.19; the raw mesh's bridge chunk cannot hold both balls, its quads keep the margin limit);
- bulged: an interior vertex's radius is above `bulge` x the ends' radii interpolated at its arc length (the
  armadillo's torso and neck, 2.03 and 1.62; the section criterion meshes the bridge as one thin edge).

    bench/bridge_classes.py [--bulge 1.3] SKELETON...      (.skel or mesohex .obj with '# mesohex radius' lines)

A bridge is a chain from a vertex with 3 or more edges through vertices with 2 to another with 3 or more. Prints one
line per bridge of either kind: file, ends, their degrees, straight distance, radii, overlap ratio, bulge ratio (and
its vertex), number of joints. Pure Python; leaflet faces are ignored.
"""
import math
import sys


def load(path):
    points, radius, edges = [], {}, set()
    with open(path) as f:
        lines = f.read().split("\n")
    if path.endswith(".skel"):  # ID X Y Z RADIUS K NEIGHBOURS...
        for line in lines[2:]:
            t = line.split()
            if len(t) < 6:
                continue
            i = int(t[0])
            points.append(tuple(float(x) for x in t[1:4]))
            radius[i] = float(t[4])
            for j in t[6:6 + int(t[5])]:
                edges.add((min(i, int(j)), max(i, int(j))))
    else:  # mesohex .obj: radius lines name the vertex as the 'v' lines count them (from 1)
        for line in lines:
            t = line.split()
            if t[:1] == ["v"]:
                points.append(tuple(float(x) for x in t[1:4]))
            elif line.startswith("# mesohex radius"):
                radius[int(t[3]) - 1] = float(t[4])
            elif t[:1] == ["l"]:
                ids = [int(x) - 1 for x in t[1:]]
                for a, b in zip(ids, ids[1:]):
                    edges.add((min(a, b), max(a, b)))
    return points, [radius.get(i, 0.0) for i in range(len(points))], sorted(edges)


def bridges(points, radii, edges):
    adj = [[] for _ in points]
    for a, b in edges:
        adj[a].append(b)
        adj[b].append(a)
    out, seen = [], set()
    for a in (i for i in range(len(points)) if len(adj[i]) >= 3):
        for n in adj[a]:
            chain, prev, cur = [a], a, n
            while len(adj[cur]) == 2 and cur != a:
                chain.append(cur)
                prev, cur = cur, adj[cur][0] if adj[cur][1] == prev else adj[cur][1]
            chain.append(cur)
            if len(adj[cur]) < 3 or cur == a:
                continue
            key = (min(a, cur), max(a, cur), len(chain))
            if key in seen:
                continue
            seen.add(key)
            length = sum(math.dist(points[x], points[y]) for x, y in zip(chain, chain[1:]))
            arc, bulge, at = 0.0, 0.0, -1
            for x, y in zip(chain, chain[1:-1]):
                arc += math.dist(points[x], points[y])
                interpolated = radii[a] + (radii[cur] - radii[a]) * arc / length
                if interpolated > 0 and radii[y] / interpolated > bulge:
                    bulge, at = radii[y] / interpolated, y
            straight = math.dist(points[a], points[cur])
            out.append(dict(a=a, b=cur, degrees=(len(adj[a]), len(adj[cur])), straight=straight, ra=radii[a],
                            rb=radii[cur], overlap=(radii[a] + radii[cur]) / straight if straight > 0 else math.inf,
                            bulge=bulge, at=at, joints=len(chain) - 2))
    return out


def main(argv):
    bulge = 1.3
    if len(argv) > 2 and argv[1] == "--bulge":
        bulge = float(argv[2])
        argv = argv[:1] + argv[3:]
    for path in argv[1:]:
        for b in bridges(*load(path)):
            if b["overlap"] > 1.0 or b["bulge"] > bulge:
                print(f"{path} v{b['a']}-v{b['b']} degrees {b['degrees'][0]},{b['degrees'][1]} "
                      f"distance {b['straight']:.3f} radii {b['ra']:.3f} {b['rb']:.3f} overlap {b['overlap']:.2f} "
                      f"bulge {b['bulge']:.2f} (v{b['at']}) joints {b['joints']}")


if __name__ == "__main__":
    main(sys.argv)
