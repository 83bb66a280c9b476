#!/usr/bin/env bash
# Finishing time over every input the project meshes (issue 19 item 3: "every shared or generated input finishes in
# <= 30 s; no stage above 10 us per hex per iteration"). One default `mesohex mesh --surface` run per input, one at
# a time, under /usr/bin/time; prints per input the final hexes, wall and CPU (user + system) seconds, peak resident
# memory per final hex, the fit's iterations and its wall microseconds per hex and iteration, the largest
# stage's wall microseconds per hex and iteration (the report's `stages[].iterations`; one for a one-pass stage), min / avg SJ and Hausdorff.
#
#   bench/finish_all.sh                  generated shapes (thickened, --resolution 3), shared pairs, table1 examples
#   ONLY=generated|shared|table1 bench/finish_all.sh
#   NAMES="torus bird" ONLY=generated bench/finish_all.sh    only these generated shapes
#   MESOHEX=path/to/mesohex OUT=dir THREADS=2 bench/finish_all.sh
#
# Wall times are what a user waits; on a loaded machine read the CPU column (the run's threads summed). The shared
# inputs are read from ../shared/data when it exists (never copied).
set -u
HERE=$(cd "$(dirname "$0")/.." && pwd)
MESOHEX=${MESOHEX:-$HERE/build/bin/mesohex}
OUT=${OUT:-$HERE/out/finish_all}
THREADS=${THREADS:-2}
ONLY=${ONLY:-}
SHARED=${SHARED:-$HERE/../shared/data}
command -v jq >/dev/null || { echo "finish_all.sh: needs jq" >&2; exit 2; }
command -v bc >/dev/null || { echo "finish_all.sh: needs bc" >&2; exit 2; }
[ -x "$MESOHEX" ] || { echo "finish_all.sh: no mesohex binary at $MESOHEX" >&2; exit 2; }
mkdir -p "$OUT"

# run NAME SKELETON DOMAIN: mesh, then one summary line.
run() {
    local name=$1 skel=$2 domain=$3 d="$OUT/$1"
    mkdir -p "$d"
    /usr/bin/time -f '%e %U %S %M' -o "$d/time" "$MESOHEX" mesh "$skel" --surface "$domain" -o "$d/mesh.mesh" \
        --report "$d/report.json" --threads "$THREADS" >"$d/mesh.log" 2>"$d/mesh.err"
    local rc=$?
    read -r wall user sys peak_kb <"$d/time" 2>/dev/null || { wall=nan; user=0; sys=0; peak_kb=0; }
    if [ -s "$d/report.json" ]; then
        jq -r --arg n "$name" --arg rc "$rc" --arg w "$wall" --arg c "$(echo "$user + $sys" | bc)" --arg p "$peak_kb" '
            ([.quality.hexes, 1] | max) as $h | (.fit.iterations // 0) as $it |
            ([.stages[] | select(.stage != "input" and .hexes > 0)
              | {s: .stage, us: (1000 * .ms / (.hexes * ([.iterations // 0, 1] | max)))}]
             | max_by(.us) // {s: "-", us: 0}) as $worst |
            [$n, $rc, $h, $w, $c, (($p | tonumber) * 1024 / $h | floor),
             $it, (if $it > 0 then ([.stages[] | select(.stage == "fit") | .ms] | add) * 1000 / ($h * $it) else 0 end),
             $worst.s, $worst.us, .quality.sj_min, .quality.sj_avg,
             (if .hausdorff then 100 * .hausdorff.relative_max else -1 end)]
            | "\(.[0])\t\(.[1])\t\(.[2])\t\(.[3])\t\(.[4])\t\(.[5])\t\(.[6])\t\(.[7] * 100 | round / 100)\t\(.[8])\t\(.[9] * 10 | round / 10)\t\(.[10] * 1000 | round / 1000)\t\(.[11] * 1000 | round / 1000)\t\(.[12] * 100 | round / 100)"' \
            "$d/report.json"
    else
        printf '%s\t%s\tfail\t%s\t%s\n' "$name" "$rc" "$wall" "$(head -c 120 "$d/mesh.err" | tr '\n' ' ')"
    fi
}

printf 'input\trc\thexes\twall_s\tcpu_s\tB/hex\tfit_it\tfit_us/hex/it\tworst_stage\tus/hex/it\tminSJ\tavgSJ\tH%%\n'
if [ -z "$ONLY" ] || [ "$ONLY" = generated ]; then
    for g in ${NAMES:-$("$MESOHEX" generate --list)}; do
        d="$OUT/gen-$g"
        mkdir -p "$d"
        if "$MESOHEX" generate "$g" -o "$d/skel.obj" >/dev/null 2>&1 &&
            "$MESOHEX" thicken "$d/skel.obj" -o "$d/domain.off" --resolution 3 >/dev/null 2>&1; then
            run "gen-$g" "$d/skel.obj" "$d/domain.off"
        else
            printf '%s\t-\tfail\tgenerate or thicken failed\n' "gen-$g"
        fi
    done
fi
if [ -d "$SHARED" ] && { [ -z "$ONLY" ] || [ "$ONLY" = shared ]; }; then
    for s in cactus aorta; do
        surf=$(ls "$SHARED"/surfaces/$s.* 2>/dev/null | head -1)
        run "shared-$s" "$SHARED/curve-skeletons/$s.skel" "$surf"
    done
    for m in "$SHARED"/medial-meshes/*.ma; do
        b=$(basename "$m" .ma)
        d="$OUT/ma-$b"
        mkdir -p "$d"
        surf=$(ls "$SHARED"/surfaces/$b.* 2>/dev/null | head -1)
        if "$MESOHEX" import "$m" -o "$d/skel.obj" >/dev/null 2>&1; then
            run "ma-$b" "$d/skel.obj" "$surf"
        else
            printf '%s\t-\tfail\timport failed\n' "ma-$b"
        fi
    done
fi
if [ -d "$SHARED" ] && { [ -z "$ONLY" ] || [ "$ONLY" = table1 ]; }; then
    for e in "$HERE"/examples/table1/*.obj; do
        b=$(basename "$e" .obj)
        surf=$(ls "$SHARED"/surfaces/$b.* 2>/dev/null | head -1)
        [ -n "$surf" ] && run "table1-$b" "$e" "$surf"
    done
fi
