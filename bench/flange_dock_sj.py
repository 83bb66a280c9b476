#!/usr/bin/env python3
"""Paper check of a block structure not built yet: a flange's wall docked on the plate's border (docs/blocks.md,
"The flange docked on the plate's border"). Writes, for radius scales 0.5 - 2.6 (r = 0.3 x scale, plate edge L = 1),
the worst corner scaled Jacobian of today's column at the flange end w (the closed form of "Thick flanges: the bound
r < L / 2") and of the hexes touching w's column in the docked structure, placed by hand: P's plates and border
half-chunks are boxes there (P flat, its column straight) and are left out; the wall's first-row halves and its end
half-chunk's halves are listed. Standard library only; no project code.

Frame: P's border on x = 0 (P on x > 0), chain along +y from w = 0, x = (0, -1, 0) the next border vertex, the wall in
the plane x = 0 above P. Usage: python3 bench/flange_dock_sj.py
"""
import math


def add(a, b):
    return tuple(p + q for p, q in zip(a, b))


def sub(a, b):
    return tuple(p - q for p, q in zip(a, b))


def mul(k, a):
    return tuple(k * p for p in a)


def unit(a):
    n = math.sqrt(sum(p * p for p in a))
    return mul(1 / n, a)


def det3(a, b, c):
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])


# VTK corner order: bottom 0-3 counter-clockwise seen from above, 4-7 above them; per corner its three neighbours in
# right-handed order (positive for a valid hex).
NEIGHBOURS = ((1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3))


def min_sj(bottom, top):
    p = list(bottom) + list(top)
    return min(det3(*(unit(sub(p[n], p[c])) for n in nb)) for c, nb in enumerate(NEIGHBOURS))


def docked_hexes(r, rows):
    X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    w = (0.0, 0.0, 0.0)
    x, xp, s, c1, s1 = mul(-1, Y), sub(X, Y), X, Y, add(X, Y)
    v, v1 = Z, add(Y, Z)
    # v's out copy: an end-edge vertex (rows > 1) or the wall's corner (one row: on the diagonal).
    ov = sub(v, mul(r, Y)) if rows > 1 else add(v, mul(r, sub(Z, Y)))

    def up(p):  # P's up copy
        return add(p, mul(r, Z))

    def out_up(p):  # P's out-up copy
        return add(up(p), mul(-r, X))

    return {
        "wall row +n": ([up(w), up(s), up(s1), up(c1)], [v, add(v, mul(r, X)), add(v1, mul(r, X)), v1]),
        "wall row -n": ([up(w), up(c1), out_up(c1), out_up(w)], [v, v1, sub(v1, mul(r, X)), sub(v, mul(r, X))]),
        "wall end +n": ([up(w), up(x), up(xp), up(s)], [v, ov, add(ov, mul(r, X)), add(v, mul(r, X))]),
        "wall end -n": ([up(w), out_up(w), out_up(x), up(x)], [v, sub(v, mul(r, X)), sub(ov, mul(r, X)), ov]),
    }


def today(r):
    return (1 - 2 * r) / (2 * math.sqrt(r * r + (1 - r / math.sqrt(2)) ** 2 + ((1 - 1 / math.sqrt(2)) * r) ** 2))


def main():
    print("scale\tr\ttoday_at_w\tdocked_2rows\tdocked_1row\tdocked_hexes_2rows")
    for i in range(15):
        scale = 0.5 + 0.15 * i
        r = 0.3 * scale
        two = {k: min_sj(*h) for k, h in docked_hexes(r, 2).items()}
        one = {k: min_sj(*h) for k, h in docked_hexes(r, 1).items()}
        detail = " ".join(f"{k}={v:.3f}" for k, v in two.items())
        print(f"{scale:.2f}\t{r:.3f}\t{today(r):+.3f}\t{min(two.values()):+.3f}\t{min(one.values()):+.3f}\t{detail}")


if __name__ == "__main__":
    main()
