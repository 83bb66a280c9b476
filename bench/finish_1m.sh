#!/usr/bin/env bash
# Issue 19 item 4: a >= 1 M-hex final mesh from a skeleton, end to end, with per-stage time and memory per hex.
# The generated torus in its thickened domain, 4 levels (3.1 M hexes), fitted after FIT_LEVELS (default 1) levels and
# inherited after; peak memory of the whole process from /usr/bin/time -v.
#
#   bench/finish_1m.sh [LEVELS [FIT_LEVELS]]      (needs build/bin/mesohex and build/bench/mesohex_finish_levels)
set -eu
LEVELS=${1:-4}
FIT_LEVELS=${2:-1}
HERE=$(cd "$(dirname "$0")/.." && pwd)
OUT=${OUT:-$HERE/out/finish_1m}
mkdir -p "$OUT"
"$HERE/build/bin/mesohex" generate torus -o "$OUT/torus.obj" >/dev/null
[ -s "$OUT/torus.off" ] || "$HERE/build/bin/mesohex" thicken "$OUT/torus.obj" -o "$OUT/torus.off" --resolution 3 >/dev/null
/usr/bin/time -v "$HERE/build/bench/mesohex_finish_levels" "$OUT/torus.obj" "$OUT/torus.off" --levels "$LEVELS" \
    --fit-levels "$FIT_LEVELS" -o "$OUT/torus_l$LEVELS.mesh" 2>"$OUT/time.txt"
grep -E "User time|System time|Elapsed|Maximum resident" "$OUT/time.txt"
