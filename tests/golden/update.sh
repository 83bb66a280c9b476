#!/usr/bin/env bash
# Re-records tests/data/golden_hashes.txt from the current code. Only after a deliberate change of the output whose
# effect on quality was measured (say so in the commit message). Usage: tests/golden/update.sh [build-dir]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$here/build}"
cmake --build "$build" --target test_golden
MESOHEX_UPDATE_GOLDEN=1 "$build/tests/unit/test_golden"
git -C "$here" diff --stat -- tests/data/golden_hashes.txt
