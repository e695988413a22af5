#!/usr/bin/env bash
# Sets up a Debian 12 machine, builds, and runs the whole test suite (unit, integration, lint).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/scripts/install-deps.sh"
"$ROOT/scripts/build.sh"
"$ROOT/scripts/build-fuzzers.sh"
cd "$ROOT"
ctest --preset "${VSCAN_PRESET:-release}" -j "$(nproc)" --timeout 600
