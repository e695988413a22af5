#!/usr/bin/env bash
# Configures and builds a CMake preset (default: release). Extra arguments go to the build.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PRESET="${VSCAN_PRESET:-release}"
cd "$ROOT"
export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/ccache}"
# Lets clones in different directories share cached objects.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}"
cmake --preset "$PRESET" >/dev/null
cmake --build --preset "$PRESET" -j "${VSCAN_JOBS:-$(nproc)}" "$@"
