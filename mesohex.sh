#!/usr/bin/env bash
# mesohex project script.
#   ./mesohex.sh demo    install what is missing, build (Release), mesh data/tiny/tripod.obj in its domain, print the quality
#   ./mesohex.sh test    install what is missing, build, run the whole test suite (what CI runs), then a short
#                        ASan/UBSan run of the fuzz corpus replay and the property tests (build-asan/)
#   ./mesohex.sh deps | build | bench
set -euo pipefail
cd "$(dirname "$0")"
ROOT=$(pwd)
BUILD=${MESOHEX_BUILD_DIR:-$ROOT/build}
JOBS=${MESOHEX_JOBS:-$(nproc)}
# When ccache is used (build, sanitizer_tests), paths below the project are hashed relative to it, so a clone in
# another folder reuses what an earlier build compiled.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$ROOT}

# Every Debian package the project needs (build, tests, benchmarks).
PACKAGES=(build-essential cmake pkg-config libeigen3-dev libtbb-dev libcli11-dev nlohmann-json3-dev libcpp-httplib-dev
          libgtest-dev libgmock-dev libbenchmark-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev
          python3 python3-meshio python3-numpy clang clang-format libclang-rt-14-dev
          libexodusii-dev netcdf-bin python3-netcdf4 libmetis-dev
          pybind11-dev python3-pybind11 python3-dev python3-pytest python3-distributed
          nodejs npm chromium)   # the studio page (apps/studio/web: three.js via npm) and its headless-browser test

deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    # A nodejs package that bundles npm (e.g. NodeSource's) conflicts with Debian's npm: the command is enough.
    if [ "$p" = npm ] && command -v npm >/dev/null 2>&1; then continue; fi
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "mesohex.sh: installing ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
  web_deps
}

# The studio page's npm packages (three, playwright-core), exactly as pinned by package-lock.json; run again only
# when the lock file changed since the last install or node_modules is missing.
web_deps() {
  local web="$ROOT/apps/studio/web" stamp="$ROOT/apps/studio/web/node_modules/.mesohex-lock.sha256"
  local want
  want=$(sha256sum "$web/package-lock.json" | cut -d' ' -f1)
  if [ ! -d "$web/node_modules" ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
    echo "mesohex.sh: npm ci in apps/studio/web"
    npm ci --prefix "$web" --no-audit --no-fund
    echo "$want" > "$stamp"
  fi
}

build() {
  # ccache, when the machine has it, makes rebuilds of unchanged files free (it is optional, not a dependency).
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMESOHEX_WERROR=ON "${launcher[@]}" >/dev/null
  cmake --build "$BUILD" -j "$JOBS"
}

run_tests() {
  local args=(--test-dir "$BUILD" --output-on-failure -j "$JOBS" --timeout 1200)
  if [ -d "$ROOT/../shared/data" ]; then
    echo "mesohex.sh: ../shared/data found: running every test, shared_data ones included"
  else
    echo "mesohex.sh: ../shared/data not found: skipping the tests labelled shared_data"
    args+=(-LE shared_data)
  fi
  ctest "${args[@]}"
}

# After the normal suite: a short ASan/UBSan run (the readers' fuzz-corpus replay and the pipeline property tests only)
# in its own build directory, building only those targets. Skipped when the compiler cannot link a sanitized program.
# MESOHEX_NO_SANITIZE=1 skips it.
sanitizer_tests() {
  [ "${MESOHEX_NO_SANITIZE:-0}" = 1 ] && return 0
  local dir=${MESOHEX_ASAN_BUILD_DIR:-$ROOT/build-asan} probe
  probe=$(mktemp -d)
  if ! echo 'int main() { return 0; }' | ${CXX:-c++} -x c++ -fsanitize=address,undefined - -o "$probe/a" 2>/dev/null \
     || ! "$probe/a"; then
    echo "mesohex.sh: the compiler cannot build with -fsanitize=address,undefined: sanitizer run skipped"
    rm -rf "$probe"
    return 0
  fi
  rm -rf "$probe"
  echo "mesohex.sh: sanitizer run (ASan + UBSan): fuzz corpus replay and property tests in $dir"
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMESOHEX_SANITIZE=ON -DMESOHEX_WERROR=ON \
    -DMESOHEX_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
  cmake --build "$dir" -j "$JOBS" --target sanitizer_short  # the 5 corpus replays + test_properties (no CGAL, no Eigen)
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    ctest --test-dir "$dir" --output-on-failure -j "$JOBS" --timeout 600 -R '^(fuzz_corpus\.|PipelineProperties\.)'
}

demo() {
  mkdir -p "$ROOT/out"
  # The domain of the example is the surface its skeleton describes (spheres + round cones), built by `thicken`.
  "$BUILD/bin/mesohex" thicken data/tiny/tripod.obj -o out/tripod.off --resolution 3
  "$BUILD/bin/mesohex" mesh data/tiny/tripod.obj --surface out/tripod.off -o out/tripod.mesh --report out/tripod.json
  "$BUILD/bin/mesohex" quality out/tripod.mesh
}

case "${1:-}" in
  deps) deps ;;
  build) deps; build ;;
  test) deps; build; run_tests; sanitizer_tests ;;
  demo) deps; build; demo ;;
  bench) deps; build; "$BUILD/bench/mesohex_bench" ;;
  *) echo "usage: $0 demo|test|deps|build|bench" >&2; exit 2 ;;
esac
