#!/usr/bin/env bash
# mesohex project script.
#   ./mesohex.sh demo    install what is missing, build (Release), mesh data/tiny/tripod.obj in its domain, print the quality
#   ./mesohex.sh test    install what is missing, build, run the whole test suite (what CI runs)
#   ./mesohex.sh deps | build | bench
set -euo pipefail
cd "$(dirname "$0")"
ROOT=$(pwd)
BUILD=${MESOHEX_BUILD_DIR:-$ROOT/build}
JOBS=${MESOHEX_JOBS:-$(nproc)}

# Every Debian package the project needs (build, tests, benchmarks).
PACKAGES=(build-essential cmake pkg-config libeigen3-dev libtbb-dev libcli11-dev nlohmann-json3-dev libcpp-httplib-dev
          libgtest-dev libgmock-dev libbenchmark-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev
          python3 python3-meshio python3-numpy
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
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMESOHEX_WERROR=ON >/dev/null
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
  test) deps; build; run_tests ;;
  demo) deps; build; demo ;;
  bench) deps; build; "$BUILD/bench/mesohex_bench" ;;
  *) echo "usage: $0 demo|test|deps|build|bench" >&2; exit 2 ;;
esac
