#!/usr/bin/env python3
"""Counts the inverted raw hexes of `mesohex_meso_trace SURFACE --geometry` outputs by geometric class
(docs/skeletons.md, "Leaflet-site inversions classified; pinches filled"):
  plate folded quad      a plate whose quad twists by more than 90 degrees (folds back on itself);
  plate skeleton-level   a plate with a non-positive corner Jacobian on the leaflet;
  plate offset fold      a plate whose offsets (up / down) cross while the leaflet quad is fine;
  half-chunk at LL-joint a half-chunk with an end where two leaflets touch (the pillow's point along the side);
  half-chunk skeleton-level / offset fold   the same two levels for the other half-chunks;
  other (chunk)          branch chunks (no second line).
With --by-site (docs/sheets.md, "Where the full-radius meso raw meshes fold"), one markdown row per trace instead: the
offset folds (plates and half-chunks) at plain leaflet sites and at joins (bl-joint / junction), the half-chunks whose
out rays cross (skeleton level) at plain leaflet / LL-joint sites and at joins, the folded plates, the branch chunks;
each with the range of its sites' r/e and fold (`mesohex_meso_trace` prints them per site).
Usage: classify_meso_trace.py [--by-site] TRACE.txt [...]"""
import collections
import re
import sys


def classify(path):
    lines = open(path).read().split("\n")
    count = collections.Counter()
    for i, line in enumerate(lines):
        if not line.startswith("hex"):
            continue
        geo = lines[i + 1] if i + 1 < len(lines) else ""
        level = float(re.search(r"J skeleton (-?[\d.]+)", geo).group(1)) if "J skeleton" in geo else 0.0
        if "plate:" in geo:
            twist = float(re.search(r"twist (\d+)", geo).group(1))
            key = "plate folded quad" if twist > 90 else "plate skeleton-level" if level <= 0 else "plate offset fold"
        elif "half-chunk:" in geo:
            key = ("half-chunk at LL-joint" if "ll_joint" in geo else
                   "half-chunk skeleton-level" if level <= 0 else "half-chunk offset fold")
        else:
            key = "other (" + line.split()[4] + ")"
        count[key] += 1
    return count


def by_site(path):
    lines = open(path).read().split("\n")
    groups = collections.defaultdict(list)
    for i, line in enumerate(lines):
        if not line.startswith("hex"):
            continue
        geo = lines[i + 1] if i + 1 < len(lines) and lines[i + 1].startswith("    ") else ""
        join = re.search(r"site v\d+\s+(\S+)", line).group(1) != "leaflet"
        level = float(re.search(r"J skeleton (-?[\d.]+)", geo).group(1)) if "J skeleton" in geo else 0.0
        if "plate:" in geo and (float(re.search(r"twist (\d+)", geo).group(1)) > 90 or level <= 0):
            key = "folded plates"
        elif "plate:" in geo or ("half-chunk:" in geo and level > 0):
            key = "offset folds at joins" if join else "offset folds, plain leaflet"
        elif "half-chunk:" in geo:
            key = "out rays cross at joins" if join else "out rays cross, plain / LL-joint"
        else:
            key = "branch chunks"
        groups[key].append((float(re.search(r"r/e ([\d.]+)", line).group(1)),
                            float(re.search(r"fold (\d+)", line).group(1))))
    cells = []
    for key in COLUMNS:
        g = groups.get(key, [])
        cells.append(f"{len(g)} ({min(x[0] for x in g):.1f}-{max(x[0] for x in g):.1f}; "
                     f"{min(x[1] for x in g):.0f}-{max(x[1] for x in g):.0f})" if g else "")
    return sum(len(g) for g in groups.values()), cells


COLUMNS = ["offset folds, plain leaflet", "offset folds at joins", "out rays cross, plain / LL-joint",
           "out rays cross at joins", "folded plates", "branch chunks"]

if __name__ == "__main__":
    if sys.argv[1:2] == ["--by-site"]:
        print("| trace | inverted | " + " | ".join(COLUMNS) + " |")
        print("|---" * (len(COLUMNS) + 2) + "|")
        for path in sys.argv[2:]:
            total, cells = by_site(path)
            print(f"| {path} | {total} | " + " | ".join(cells) + " |")
        sys.exit(0)
    for path in sys.argv[1:]:
        c = classify(path)
        print(path, sum(c.values()), ", ".join(f"{k} {n}" for k, n in sorted(c.items())))
