#!/usr/bin/env bash
# Sets up a Debian 12 machine, builds, and runs the whole test suite (unit, integration, lint, fuzz).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PRESET="${VSCAN_PRESET:-release}"
"$ROOT/scripts/install-deps.sh"
"$ROOT/scripts/build.sh"
cd "$ROOT"
# The fuzz targets compile with clang while the other tests run (many of which wait on a server);
# their ten-second runs (label fuzz) follow once they are built.
"$ROOT/scripts/build-fuzzers.sh" --configure-only
mkdir -p build/fuzz
"$ROOT/scripts/build-fuzzers.sh" --build-only >build/fuzz/build.log 2>&1 &
fuzz_build=$!
status=0
ctest --preset "$PRESET" -j "$(nproc)" --timeout 600 -LE '^fuzz$' || status=$?
if ! wait "$fuzz_build"; then
  cat build/fuzz/build.log
  echo "test.sh: the fuzz targets did not build" >&2
  exit 1
fi
ctest --preset "$PRESET" -j "$(nproc)" --timeout 600 -L '^fuzz$' || status=$?
exit "$status"
