#!/usr/bin/env bash
# Measures the peak resident memory (VmHWM) of vscand over 1280x1024 scans of the Stanford bunny
# filling the frame, each case on a fresh server and data directory. docs/DEPLOY.md records the
# figures and deploy/kustomize/base/statefulset.yaml's memory request and limit rest on them.
# Usage: tests/deploy/measure_memory.sh [build directory, default build/release]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="$(cd "${1:-$ROOT/build/release}" && pwd)"
V="$BUILD/client/cli/vscan"
WORK="$(mktemp -d)"
SERVER=""
trap '[ -n "$SERVER" ] && kill "$SERVER" 2>/dev/null; rm -rf "$WORK"' EXIT

hwm() { awk '/VmHWM/ {print $2}' "/proc/$1/status"; }

# measure LABEL COMMAND: COMMAND runs with $SCAN set to a full-frame 1280x1024 scan of a fresh scene.
measure() {
  rm -rf "$WORK/data" "$WORK/port"
  "$BUILD/server/vscand" --listen 127.0.0.1:0 --port-file "$WORK/port" --data-dir "$WORK/data" \
    --log-level warn >"$WORK/log" 2>&1 &
  SERVER=$!
  for _ in $(seq 100); do [ -s "$WORK/port" ] && break; sleep 0.1; done
  export VSCAN_SERVER="127.0.0.1:$(cat "$WORK/port")"
  local idle mesh scene
  idle=$(hwm "$SERVER")
  mesh=$("$V" -q mesh upload "$ROOT/data/meshes/bunny/bunny_zipper_res2.ply" --unit m)
  scene=$("$V" -q scene create desk)
  "$V" -q object add "$scene" "$mesh" --label bunny --position 0,0,0 --rpy 90,0,0 --on-table >/dev/null
  SCAN="$V -q scan $scene --width 1280 --height 1024 --hfov 40 --eye 0.12,0,0.08 --target 0,0,0.07 --up 0,0,1 --fields all"
  eval "$2"
  printf '%-48s idle %4d MiB   peak %4d MiB\n' "$1" $((idle / 1024)) $(($(hwm "$SERVER") / 1024))
  kill "$SERVER"
  while kill -0 "$SERVER" 2>/dev/null; do sleep 0.1; done
  SERVER=""
}

measure "one ray-cast scan" '$SCAN -o $WORK/a.ply'
measure "three ray-cast scans in a row" 'for i in 1 2 3; do $SCAN -o $WORK/a.ply; done'
measure "one depth-buffer scan (OpenGL, llvmpipe)" '$SCAN -o $WORK/a.ply --backend depth'
measure "one scan with noise, outliers, estimated normals" \
  '$SCAN -o $WORK/a.ply --noise 0.001 --along-ray --outliers 0.01 --outlier-angle 5 --flying-pixels --include-rejected --estimate-normals'
measure "four at once (ray cast x2, depth, colour)" \
  'pids=(); for b in raycast depth colour raycast; do $SCAN -o $WORK/$b$RANDOM.ply --backend $b & pids+=($!); done; wait "${pids[@]}"'
