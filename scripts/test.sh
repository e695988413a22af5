#!/usr/bin/env bash
# Sets up a Debian 12 machine, builds, and runs the whole test suite (unit, integration, lint, fuzz).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PRESET="${VSCAN_PRESET:-release}"
"$ROOT/scripts/install-deps.sh" build
# What only the tests need (clang for the fuzz targets, the Python packages, npm and buf, kubectl)
# installs while the build runs: the download and unpacking wait on the network and the disk.
mkdir -p "$ROOT/build"
"$ROOT/scripts/install-deps.sh" test >"$ROOT/build/install-test-deps.log" 2>&1 &
test_deps=$!
build_status=0
"$ROOT/scripts/build.sh" || build_status=$?
if ! wait "$test_deps"; then
  cat "$ROOT/build/install-test-deps.log"
  echo "test.sh: the tests' packages did not install" >&2
  exit 1
fi
[ "$build_status" -eq 0 ] || exit "$build_status"
cd "$ROOT"
# The test fuzz.build configures and compiles the fuzz targets with clang while the other tests run
# (many of which wait on a server); their ten-second runs (label fuzz) follow it in the same call.
# One test more than there are cores: integration tests spend part of their time waiting on their
# server (the suite took 240 s with 2 at once on 2 cores, 219 s with 3, 223 s with 4).
exec ctest --preset "$PRESET" -j "$(($(nproc) + 1))" --timeout 600
