#!/usr/bin/env bash
# Configures build/fuzz with clang and builds the libFuzzer targets (fuzz/README.md). They link the
# regular build's libraries (VSCAN_PRESET, default release; not asan), which this builds first.
# --fuzz-only leaves the regular build alone (it must be built) and only configures and builds
# build/fuzz: the test fuzz.build runs it, so that the targets compile while other tests run.
set -euo pipefail
STAGE="${1:-all}"
case "$STAGE" in all|--fuzz-only) ;; *) echo "build-fuzzers: unknown option $STAGE" >&2; exit 2;; esac
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PRESET="${VSCAN_PRESET:-release}"
if [ "$PRESET" = asan ]; then
  echo "build-fuzzers: the asan preset's libraries carry GCC's sanitizer runtime; use release or debug" >&2
  exit 2
fi
cd "$ROOT"
export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/ccache}"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$ROOT}"
JOBS="${VSCAN_JOBS:-$(nproc)}"
FUZZ_DIR="${VSCAN_FUZZ_BUILD_DIR:-$ROOT/build/fuzz}"
PREBUILT_DIR="${VSCAN_PREBUILT_DIR:-$ROOT/build/$PRESET}"
if grep -q -- '^CMAKE_CXX_FLAGS:.*-fsanitize' "$PREBUILT_DIR/CMakeCache.txt" 2>/dev/null; then
  echo "build-fuzzers: $PREBUILT_DIR is a sanitizer build, whose libraries carry GCC's runtime" >&2
  exit 2
fi

if [ "$STAGE" = all ]; then
  cmake --preset "$PRESET" >/dev/null
  cmake --build --preset "$PRESET" -j "$JOBS" --target vscan_api vscan_cli_args
fi

launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
# lld links clang's sanitizer runtime without gold's warnings about its local symbols.
linker=""
if command -v ld.lld >/dev/null 2>&1; then linker=lld; fi
# -O0 with line tables: half the compiler CPU of -O1 (the plan reader's batch: 12 s against 26 s),
# and the fuzz runs are bounded by time, not by inputs.
cmake -S . -B "$FUZZ_DIR" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O0 -gline-tables-only" \
  -DVSCAN_BUILD_FUZZERS=ON -DVSCAN_BUILD_TESTS=OFF -DVSCAN_BUILD_BENCH=OFF -DVSCAN_WERROR=ON -DVSCAN_LINKER="$linker" \
  -DVSCAN_PREBUILT_DIR="$PREBUILT_DIR" "${launcher[@]}" >/dev/null
cmake --build "$FUZZ_DIR" -j "$JOBS" --target fuzzers
