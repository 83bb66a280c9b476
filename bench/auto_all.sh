#!/usr/bin/env bash
# `mesohex auto` on every closed manifold surface of the shared data (issue 17 item 3), one at a time, single-threaded:
# one default `auto SURFACE -o OUT.mesh --report OUT.json --threads 1 -q` run per surface (plus EXTRA arguments),
# under `nice -n 5` and /usr/bin/time. Prints per surface the answer (curve / meso / refused), hexes, min / avg SJ,
# Hausdorff (% of the bbox diagonal), inverted hexes, wall and CPU (user + system) seconds, and whether it meets
# every target (valid, no inverted hex, Hausdorff <= 1 %, min SJ >= 0.3, avg SJ >= 0.85, CPU <= 60 s); then the count.
#
#   bench/auto_all.sh                                   all 22
#   NAMES="torque knob" bench/auto_all.sh               only these
#   MESOHEX=path/to/mesohex OUT=dir EXTRA="--no-extend-rims" bench/auto_all.sh
#
# The surfaces are read from ../shared/data/surfaces (never copied). On a loaded machine read the CPU column.
set -u
HERE=$(cd "$(dirname "$0")/.." && pwd)
MESOHEX=${MESOHEX:-$HERE/build/bin/mesohex}
OUT=${OUT:-$HERE/out/auto_all}
EXTRA=${EXTRA:-}
SURFACES=${SURFACES:-$HERE/../shared/data/surfaces}
NAMES=${NAMES:-airplane1 aorta armchair bearing_plate bracket_inches cactus chair1 cup cylinder_plate deckel dtorus
    dualocta hand hand_loopycuts holes2 knob pinion plate1 plate3 sculpt torque wrench}
command -v jq >/dev/null || { echo "auto_all.sh: needs jq" >&2; exit 2; }
[ -x "$MESOHEX" ] || { echo "auto_all.sh: no mesohex binary at $MESOHEX" >&2; exit 2; }
mkdir -p "$OUT"
met=0
total=0
printf 'surface\trc\tanswer\thexes\tminSJ\tavgSJ\tH%%\tinverted\twall_s\tcpu_s\tmeets\n'
for n in $NAMES; do
    f=$(ls "$SURFACES/$n".* 2>/dev/null | head -1)
    [ -n "$f" ] || { printf '%s\tmissing\n' "$n"; continue; }
    total=$((total + 1))
    # shellcheck disable=SC2086
    /usr/bin/time -f '%e %U %S' -o "$OUT/$n.time" nice -n 5 "$MESOHEX" auto "$f" -o "$OUT/$n.mesh" \
        --report "$OUT/$n.json" --threads 1 -q $EXTRA >"$OUT/$n.log" 2>"$OUT/$n.err"
    rc=$?
    # (time's first line says "Command exited with non-zero status N" when the run refused)
    read -r wall user sys < <(tail -n 1 "$OUT/$n.time" 2>/dev/null) || { wall=nan; user=0; sys=0; }
    cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.1f", u + s }')
    if [ "$rc" = 0 ] && [ -s "$OUT/$n.json" ]; then
        line=$(jq -r --arg cpu "$cpu" '
            (.hausdorff.relative_max * 100) as $h |
            ((.quality.valid) and (.quality.inverted == 0) and ($h <= 1) and (.quality.sj_min >= 0.3) and
             (.quality.sj_avg >= 0.85) and (($cpu | tonumber) <= 60)) as $ok |
            "\(.skeleton_kind)\t\(.quality.hexes)\t\(.quality.sj_min * 1000 | round / 1000)\t\(.quality.sj_avg * 1000 | round / 1000)\t\($h * 100 | round / 100)\t\(.quality.inverted)\t\(if $ok then "yes" else "no" end)"' \
            "$OUT/$n.json")
        ok=${line##*$'\t'}
        [ "$ok" = yes ] && met=$((met + 1))
        printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$n" "$rc" "${line%$'\t'*}" "$wall" "$cpu" "$ok"
    else
        printf '%s\t%s\trefused\t\t\t\t\t\t%s\t%s\tno\n' "$n" "$rc" "$wall" "$cpu"
    fi
done
echo "meets: $met of $total"
