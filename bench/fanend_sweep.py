#!/usr/bin/env python3
"""Sweep of issue 22's check configurations through raw `mesohex mesh` runs (docs/blocks.md, "Sweep of the check
configurations").

For every generated configuration (fan-edge ends `fanend -n 3|4 -m 1..5`, T / X fans, fan blocks, Y fans, walls on
plates, flanges (walls above, or above and below, a chain on part of a plate's border; `cornerflanges`: the chain from
the plate's corner), cube stars, Y and
tetrahedral stars, and T / X fans whose top fan end carries a 3-edge branch turned theta degrees off the fan line
towards azimuth phi) at radius scales from 0.5 to 2.6, runs `mesohex mesh` (raw, defaults, one thread) with
`--report` and classifies the run:

  clean       accepted, valid, Euler characteristic equal to the skeleton's, hex count and irregular edges exactly as
              predicted, no inverted hex (and where a block is accepted: fewer interior irregular edges than the
              paper's layout, `--no-blocks`; 120-degree and tetrahedral stars and Y fans: no block)
  inverted    accepted with an inverted raw hex (exit status 5)
  predicted   prediction mismatch (hex count or irregular edges)
  euler       Euler characteristic of the mesh differs from the skeleton's, or the mesh is not valid
  blocks      a block on a star that must not get one, or a block with no fewer irregular edges than the paper's layout
  refused     refused at analysis (exit status 3) with a message naming a skeleton vertex and an edit
  refused-vague refused naming the vertex, but saying the repair "did not run" where it ran and refused on the input
              sampling (the analysis judges the resampled skeleton, on which the failing condition does not show)
  refused-bad refused without naming the vertex or without an edit suggestion
  error       any other exit status (crash, invalid input)

Prints the counts per class and per family, then a table of every run not clean or refused (and of bad refusals).

  bench/fanend_sweep.py [--mesohex build/bin/mesohex] [--out DIR] [--families fanend,angled,...] [--scales 0.5:2.6:0.05]
                        [--jobs 2] [--list-refused] [--tsv FILE] [--generator BINARY]

--tsv FILE writes one line per run (family, configuration, radius scale, class, detail), in configuration order, to
compare two builds run by run.
"""
import argparse
import concurrent.futures
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def frange(spec):
    lo, hi, step = (float(x) for x in spec.split(":"))
    n = int(round((hi - lo) / step))
    return [round(lo + i * step, 4) for i in range(n + 1)]


def configurations(families, scales, angle_scales):
    """(family, label, generator args, angled (theta, phi) or None, radius scale)."""
    out = []
    for s in scales:
        if "fanend" in families:
            for n in (3, 4):
                for m in (1, 2, 3, 4, 5):
                    out.append(("fanend", f"fanend -n {n} -m {m}", ["fanend", "-n", str(n), "-m", str(m)], None, s))
        if "fans" in families:
            for name in ("tfan", "xfan"):
                for n in (1, 2, 3):
                    for m in (1, 2, 3):
                        out.append(("fans", f"{name} -n {n} -m {m}", [name, "-n", str(n), "-m", str(m)], None, s))
            for n in (3, 4):
                for m in (1, 2, 3, 4):
                    out.append(("fans", f"fanblock -n {n} -m {m}", ["fanblock", "-n", str(n), "-m", str(m)], None, s))
            for m in (1, 2, 3):
                out.append(("fans", f"yfan -m {m}", ["yfan", "-m", str(m)], None, s))
        if "walls" in families:
            for name in ("wall", "wallboth", "walledge", "walledgeboth"):
                for n in (4, 6):
                    for m in (1, 2, 3):
                        out.append(("walls", f"{name} -n {n} -m {m}", [name, "-n", str(n), "-m", str(m)], None, s))
        if "flanges" in families:
            for name in ("flange", "flangeup"):
                for n in (4, 6):
                    for m in (1, 2, 3):
                        out.append(("flanges", f"{name} -n {n} -m {m}", [name, "-n", str(n), "-m", str(m)], None, s))
        if "cornerflanges" in families:
            for name in ("flangecorner", "flangecornerup"):
                for n in (4, 6):
                    for m in (1, 2, 3):
                        out.append(
                            ("cornerflanges", f"{name} -n {n} -m {m}", [name, "-n", str(n), "-m", str(m)], None, s))
        if "stars" in families:
            for n in (3, 4, 5, 6):
                for m in (1, 2, 3):
                    out.append(("stars", f"cubestar -n {n} -m {m}", ["cubestar", "-n", str(n), "-m", str(m)], None, s))
            for name in ("ystar", "tetrastar"):
                for m in (1, 2, 3):
                    out.append(("stars", f"{name} -m {m}", [name, "-m", str(m)], None, s))
    if "angled" in families:
        # The top fan end (0, 0, 1) of `fanend -m 1` with its 3-edge branch turned theta degrees off +z (the fan line)
        # towards azimuth phi: 270 = -y (the T's empty side), 45 = between two leaflets, 0 = in the +x leaflet's
        # plane, 22.5 = 22.5 degrees off it.
        thetas = [0, 20, 40, 45, 50, 55, 60, 65, 70, 80, 90, 100, 110, 120, 130, 135, 140, 150, 170]
        for s in angle_scales:
            for n in (3, 4):
                for phi in (270.0, 45.0, 0.0, 22.5):
                    for theta in thetas:
                        label = f"{'T' if n == 3 else 'X'} theta {theta} phi {phi:g}"
                        out.append(("angled", label, ["fanend", "-n", str(n), "-m", "1"], (theta, phi), s))
    return out


def turn_branch(path, theta, phi):
    """Rewrite the last three vertices of a `fanend -m 1` skeleton (its branch of unit edges from (0, 0, 1))."""
    lines = open(path).read().split("\n")
    vs = [i for i, l in enumerate(lines) if l.startswith("v ")]
    t, p = math.radians(theta), math.radians(phi)
    d = (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t))
    for k, i in enumerate(vs[-3:], start=1):
        lines[i] = "v %.17g %.17g %.17g" % (k * d[0], k * d[1], 1 + k * d[2])
    open(path, "w").write("\n".join(lines))


def interior_irregular(q):
    return sum(q["singular_edges"]["interior"].values())


MESH_ARGS = []  # --mesh-args: extra options for every mesh run
GENERATOR = []  # --generator: the binary that generates the skeletons (default: the meshing one)


def run(binary, out, idx, cfg):
    family, label, gen, angled, s = cfg
    base = os.path.join(out, f"c{idx}")
    obj = base + ".obj"
    g = subprocess.run([GENERATOR[0] if GENERATOR else binary, "generate", *gen, "--radius-scale", str(s), "-o", obj], capture_output=True, text=True)
    if g.returncode != 0:
        return (cfg, "gen-error", g.stderr.strip().split("\n")[-1][:160])
    if angled:
        turn_branch(obj, *angled)
    rep = base + ".json"
    if os.path.exists(rep):
        os.remove(rep)
    m = subprocess.run([binary, "mesh", obj, "-o", base + ".mesh", "--report", rep, "-q", "--threads", "1", *MESH_ARGS],
                       capture_output=True, text=True)
    err = m.stderr.strip()
    if m.returncode == 3:
        last = err.split("\n")[-1]
        ok = "vertex" in last and "edit" in last
        # "did not run": the repair ran on the input and refused, but the analysis judges the resampled skeleton,
        # where the failing condition does not show (the message then names no measured condition).
        vague = "did not run" in last
        return (cfg, "refused" if ok and not vague else ("refused-vague" if ok else "refused-bad"), last[:400])
    if m.returncode not in (0, 5) or not os.path.exists(rep):
        return (cfg, "error", f"exit {m.returncode}: {err[-200:]}")
    r = json.load(open(rep))
    q, p = r["quality"], r["predicted"]
    detail = f"min SJ {q['sj_min']:.3f}"
    if q["inverted"] > 0:
        return (cfg, "inverted", f"{q['inverted']} inverted, {detail}, {q['hexes']} hexes")
    if q.get("problems") or q["euler_characteristic"] != r["skeleton"]["euler_characteristic"]:
        return (cfg, "euler", f"Euler {q['euler_characteristic']} vs {r['skeleton']['euler_characteristic']}, "
                f"problems {q.get('problems')}")
    if not r["prediction_matches"] or p["hexes"] != q["hexes"] or p["irregular_edges"] != q["singular_edges"]:
        return (cfg, "predicted", f"hexes {q['hexes']} vs {p['hexes']}")
    blocks = p["compatible_blocks"] + p["fan_blocks"]["edges"] + p["fan_blocks"]["caps"]
    no_block_star = gen[0] in ("ystar", "tetrastar", "yfan")
    if no_block_star and blocks > 0:
        return (cfg, "blocks", f"{blocks} blocks on a star that must not get one")
    if blocks > 0:
        rep2 = base + "_paper.json"
        m2 = subprocess.run([binary, "mesh", obj, "-o", base + "_paper.mesh", "--no-blocks", "--report", rep2, "-q",
                             "--threads", "1"], capture_output=True, text=True)
        if m2.returncode in (0, 5) and os.path.exists(rep2):
            paper = interior_irregular(json.load(open(rep2))["quality"])
            mine = interior_irregular(q)
            if mine >= paper:
                return (cfg, "blocks", f"interior irregular {mine} with blocks, {paper} paper layout")
            detail += f", irregular {mine} < paper {paper}"
    return (cfg, "clean", detail)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesohex", default=os.path.join(HERE, "build", "bin", "mesohex"))
    ap.add_argument("--out", default="/tmp/fanend_sweep")
    ap.add_argument("--families", default="fanend,angled,fans,walls,flanges,stars")
    ap.add_argument("--scales", default="0.5:2.6:0.05", help="radius scales lo:hi:step")
    ap.add_argument("--angle-scales", default="0.5:2.6:0.1", help="radius scales of the angled branches")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--list-refused", action="store_true", help="also list every refusal with its message")
    ap.add_argument("--tsv", help="write one line per run (family, configuration, scale, class, detail) to this file")
    ap.add_argument("--mesh-args", default="", help="extra options for every mesh run, e.g. '--fan-cap-branches'")
    ap.add_argument("--generator", help="generate the skeletons with this binary (e.g. a newer build's generators, "
                    "meshed by --mesohex)")
    a = ap.parse_args()
    MESH_ARGS.extend(a.mesh_args.split())
    if a.generator:
        GENERATOR.append(a.generator)
    os.makedirs(a.out, exist_ok=True)
    cfgs = configurations(set(a.families.split(",")), frange(a.scales), frange(a.angle_scales))
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as ex:
        results = list(ex.map(lambda ic: run(a.mesohex, a.out, *ic), enumerate(cfgs)))
    if a.tsv:
        with open(a.tsv, "w") as t:
            for cfg, k, d in results:
                t.write(f"{cfg[0]}\t{cfg[1]}\t{cfg[4]:g}\t{k}\t{d}\n")
    classes = ["clean", "inverted", "predicted", "euler", "blocks", "refused", "refused-vague", "refused-bad", "error",
               "gen-error"]
    fams = sorted({c[0] for c in cfgs})
    print("family     " + " ".join(f"{c:>13}" for c in classes))
    for f in fams + ["all"]:
        row = [sum(1 for cfg, k, _ in results if k == c and (f == "all" or cfg[0] == f)) for c in classes]
        print(f"{f:10} " + " ".join(f"{x:>13}" for x in row))
    bad = [x for x in results if x[1] not in ("clean", "refused", "gen-error")]
    if a.list_refused:
        bad += [x for x in results if x[1] == "refused"]
    # Group consecutive radius scales of the same configuration and class into one row.
    rows = {}
    for cfg, k, d in bad:
        rows.setdefault((cfg[1], k), []).append((cfg[4], d))
    if rows:
        print("\nconfiguration                        class        radius scales: detail (at the first scale)")
    for (label, k), v in sorted(rows.items()):
        v.sort()
        sc = [x[0] for x in v]
        print(f"{label:36} {k:12} {sc[0]:g}-{sc[-1]:g} ({len(sc)}): {v[0][1]}")
    gen_err = sorted({cfg[1] for cfg, k, _ in results if k == "gen-error"})
    if gen_err:
        print("\nnot generated:", ", ".join(gen_err))
    return 1 if any(k not in ("clean", "refused", "gen-error") for _, k, _ in results) else 0


if __name__ == "__main__":
    sys.exit(main())
