#!/usr/bin/env python3
"""Counts the inverted raw hexes of `mesohex_meso_trace SURFACE --geometry` outputs by geometric class
(docs/skeletons.md, "Leaflet-site inversions classified; pinches filled"):
  plate folded quad      a plate whose quad twists by more than 90 degrees (folds back on itself);
  plate skeleton-level   a plate with a non-positive corner Jacobian on the leaflet;
  plate offset fold      a plate whose offsets (up / down) cross while the leaflet quad is fine;
  half-chunk at LL-joint a half-chunk with an end where two leaflets touch (the pillow's point along the side);
  half-chunk skeleton-level / offset fold   the same two levels for the other half-chunks;
  other (chunk)          branch chunks (no second line).
Usage: classify_meso_trace.py TRACE.txt [...]"""
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


if __name__ == "__main__":
    for path in sys.argv[1:]:
        c = classify(path)
        print(path, sum(c.values()), ", ".join(f"{k} {n}" for k, n in sorted(c.items())))
