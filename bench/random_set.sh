#!/usr/bin/env bash
# The random evaluation set (issue 16): for seeds FIRST..LAST, `mesohex generate --random SEED`, `mesohex thicken`
# into its domain, default `mesohex mesh --surface` (one thread per run, JOBS runs in parallel), then the
# distribution of min SJ, avg SJ and Hausdorff (% of the domain's bounding-box diagonal) over the seeds.
#
#   bench/random_set.sh N [JOBS]              seeds 1..N (JOBS default 2)
#   FIRST=101 bench/random_set.sh 200         seeds 101..200
#   MESOHEX=path/to/mesohex OUT=dir THICKEN_ARGS="--resolution 3" MESH_ARGS="..." bench/random_set.sh 100
#   SUMMARY_ONLY=1 bench/random_set.sh N      summarise the seeds of OUT already run (a partial run too)
#   SEEDS="3 5 8" bench/random_set.sh 0       only these seeds (N ignored; e.g. the seeds a change touches)
#   DOMAINS=dir                               take skel.obj / domain.off from dir/SEED when there (no regeneration)
#   GEN_ARGS="--family character"             extra `mesohex generate --random SEED` arguments: the character family
#                                             (generators.h, generate_character_skeleton); "--family twinjunction":
#                                             two branching points whose balls overlap (generate_twin_junction_skeleton);
#                                             default none (tree / sheet)
#
# Prints one line per seed (sorted), then: worst, 5th percentile, median of each measure; the seeds with an inverted
# hex; the fraction meeting every target (min SJ >= 0.3, avg >= 0.85, Hausdorff <= 1 %, 0 inverted); the seeds
# missing a target (a miss is a test case, not a tuning target) and the seeds that failed (exit status other than
# 0 and 5, with the first line of stderr). Per seed, OUT/SEED/ keeps the skeleton, domain, mesh, report and logs.
set -u
N=${1:?usage: bench/random_set.sh N [JOBS]}
JOBS=${2:-2}
FIRST=${FIRST:-1}
HERE=$(cd "$(dirname "$0")/.." && pwd)
MESOHEX=${MESOHEX:-$HERE/build/bin/mesohex}
OUT=${OUT:-$HERE/out/random_set}
THICKEN_ARGS=${THICKEN_ARGS:---resolution 3}
MESH_ARGS=${MESH_ARGS:-}
GEN_ARGS=${GEN_ARGS:-}
command -v jq >/dev/null || { echo "random_set.sh: needs jq" >&2; exit 2; }
[ -x "$MESOHEX" ] || { echo "random_set.sh: no mesohex binary at $MESOHEX (build mesohex_cli)" >&2; exit 2; }
mkdir -p "$OUT"
SEED_LIST=${SEEDS:-$(seq "$FIRST" "$N")}
DOMAINS=${DOMAINS:-}

run_seed() {
    local seed=$1 d="$OUT/$1" start end
    mkdir -p "$d"
    start=$(date +%s.%N)
    local rc
    if [ -n "$DOMAINS" ] && [ -s "$DOMAINS/$seed/domain.off" ]; then
        cp "$DOMAINS/$seed/skel.obj" "$DOMAINS/$seed/domain.off" "$DOMAINS/$seed/generate.log" "$d/"
        rc=$?
    else
        # shellcheck disable=SC2086
        "$MESOHEX" generate --random "$seed" $GEN_ARGS -o "$d/skel.obj" >"$d/generate.log" 2>&1 &&
            "$MESOHEX" thicken "$d/skel.obj" -o "$d/domain.off" $THICKEN_ARGS >"$d/thicken.log" 2>&1
        rc=$?
    fi
    if [ $rc -eq 0 ]; then
        # shellcheck disable=SC2086
        "$MESOHEX" mesh "$d/skel.obj" --surface "$d/domain.off" -o "$d/mesh.mesh" --report "$d/report.json" \
            --threads 1 $MESH_ARGS >"$d/mesh.log" 2>"$d/mesh.err"
        rc=$?
    fi
    end=$(date +%s.%N)
    echo "$rc $(echo "$end - $start" | bc)" >"$d/status"
}
export -f run_seed
export MESOHEX OUT THICKEN_ARGS MESH_ARGS DOMAINS GEN_ARGS

t0=$(date +%s)
[ -n "${SUMMARY_ONLY:-}" ] || printf '%s\n' $SEED_LIST | xargs -P "$JOBS" -I{} bash -c 'run_seed {}'
t1=$(date +%s)

rows="$OUT/rows.txt"  # seed kind raw_hexes hexes min avg hausdorff% inverted rc seconds
: >"$rows"
for seed in $SEED_LIST; do
    d="$OUT/$seed"
    [ -f "$d/status" ] || continue  # not run (yet)
    read -r rc secs <"$d/status"
    kind=$(sed -n 's/.*(\(tree\|sheet\|character\|twinjunction\)).*/\1/p' "$d/generate.log")
    if [ -s "$d/report.json" ] && { [ "$rc" = 0 ] || [ "$rc" = 5 ]; }; then
        jq -r --arg s "$seed" --arg k "$kind" --arg rc "$rc" --arg t "$secs" \
            '[$s, $k, .raw_quality.hexes, .quality.hexes, .quality.sj_min, .quality.sj_avg,
              (if .hausdorff then 100 * .hausdorff.relative_max else -1 end), .quality.inverted, $rc, $t] | @tsv' \
            "$d/report.json" >>"$rows"
    else
        printf '%s\t%s\tfail\tfail\tnan\tnan\tnan\tnan\t%s\t%s\n' "$seed" "$kind" "$rc" "$secs" >>"$rows"
    fi
done

printf 'seed\tkind\traw\thexes\tminSJ\tavgSJ\tH%%\tinv\trc\ts\n'
awk -F'\t' '{printf "%s\t%s\t%s\t%s\t%.3f\t%.3f\t%.2f\t%s\t%s\t%.1f\n", $1,$2,$3,$4,$5,$6,$7,$8,$9,$10}' "$rows"
echo
awk -F'\t' -v wall=$((t1 - t0)) '
function sort_asc(a, n,   i, j, t) { for (i = 2; i <= n; ++i) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; --j) a[j + 1] = a[j]; a[j + 1] = t } }
function pick(a, n, q) { return a[int(q * (n - 1)) + 1] }
{
    total++
    if ($3 == "fail") { failed = failed " " $1; nfail++; next }
    n++; mn[n] = $5; av[n] = $6; hd[n] = -$7; raw += $3; hexes += $4; secs += $10
    if ($8 > 0) inv = inv " " $1
    if ($5 >= 0.3 && $6 >= 0.85 && $7 >= 0 && $7 <= 1 && $8 == 0) ok++; else missed = missed " " $1
}
END {
    if (n == 0) { print "no seed meshed"; exit 1 }
    sort_asc(mn, n); sort_asc(av, n); sort_asc(hd, n)
    printf "seeds %d, meshed %d, failed %d; mean raw hexes %.0f, mean hexes %.0f, mean %.1f s per seed, wall %d s\n",
        total, n, nfail, raw / n, hexes / n, secs / n, wall
    printf "            worst    p5   median\n"
    printf "min SJ     %6.3f %6.3f %6.3f\n", mn[1], pick(mn, n, 0.05), pick(mn, n, 0.5)
    printf "avg SJ     %6.3f %6.3f %6.3f\n", av[1], pick(av, n, 0.05), pick(av, n, 0.5)
    printf "Hausdorff %6.2f%% %5.2f%% %5.2f%%\n", -hd[1], -pick(hd, n, 0.05), -pick(hd, n, 0.5)
    printf "seeds with an inverted hex: %d%s\n", split(inv, tmp, " "), inv
    printf "meeting all targets: %d / %d = %.1f %% (failed seeds count as misses)\n", ok, total, 100 * ok / total
    printf "missing seeds:%s\n", missed
    printf "failed seeds:%s\n", failed
}' "$rows"
for seed in $SEED_LIST; do
    [ -f "$OUT/$seed/status" ] || continue
    read -r rc _ <"$OUT/$seed/status"
    if [ "$rc" != 0 ] && [ "$rc" != 5 ]; then
        echo "  seed $seed exit $rc: $(head -c 300 "$OUT/$seed/mesh.err" 2>/dev/null || cat "$OUT/$seed/thicken.log")"
    fi
done
