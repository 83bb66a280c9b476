#!/usr/bin/env bash
# fuzz/run.sh [SECONDS] [TARGET ...]: builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz/ and runs each
# TARGET (default: hex skeleton surface medial analysis) for SECONDS (default 60), one after the other, on a seed
# corpus made from the project's test inputs (fuzz/make_seeds.py) plus the saved corpus fuzz/corpus/<target>.
# New inputs go to build-fuzz/corpus/<target>; crashes, leaks, timeouts (> 10 s per input) and out-of-memory
# (> 2 GB) to build-fuzz/artifacts/. Prints execs/s and total execs per target. Needs clang and libclang-rt-14-dev.
# To keep a finding as a regression input: copy it (small files only) into fuzz/corpus/<target>/.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SECS="${1:-60}"
shift || true
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(hex skeleton surface medial analysis)
BUILD="${MESOHEX_FUZZ_BUILD:-$ROOT/build-fuzz}"
JOBS="${JOBS:-2}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

CXX="${FUZZ_CXX:-clang++}" cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMESOHEX_SANITIZE=ON \
  -DMESOHEX_FUZZ=ON -DMESOHEX_BUILD_TESTS=OFF -DMESOHEX_BUILD_BENCH=OFF -DMESOHEX_WERROR=ON "${launcher[@]}" >/dev/null
cmake --build "$BUILD" -j "$JOBS" --target "${TARGETS[@]/#/fuzz_}"
rm -rf "$BUILD/seeds"
python3 "$ROOT/fuzz/make_seeds.py" "$ROOT" "$BUILD/seeds" >/dev/null
mkdir -p "$BUILD/artifacts" "$BUILD/logs"
status=0
for t in "${TARGETS[@]}"; do
  mkdir -p "$BUILD/corpus/$t"
  dirs=("$BUILD/corpus/$t" "$BUILD/seeds/$t")
  [ -d "$ROOT/fuzz/corpus/$t" ] && dirs+=("$ROOT/fuzz/corpus/$t")
  log="$BUILD/logs/$t.log"
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$BUILD/fuzz/fuzz_$t" "${dirs[@]}" -max_total_time="$SECS" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$BUILD/artifacts/$t-" -print_final_stats=1 >"$log" 2>&1 || status=1
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  echo "fuzz_$t: ${execs:-?} execs in ${SECS} s (${rate:-?} execs/s); log $log"
  grep -E "^(==[0-9]+==ERROR|SUMMARY|.*runtime error)" "$log" | head -5 || true
done
ls "$BUILD/artifacts" | head -20
exit $status
