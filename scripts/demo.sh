#!/usr/bin/env bash
# The main job: set up, build, start vscand on the embedded defaults, scan the Stanford bunny on a
# turning table from a few poses, and leave binary PLY files and a summary in vscan-demo/.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${VSCAN_DEMO_DIR:-$ROOT/vscan-demo}"
BIN="$ROOT/build/${VSCAN_PRESET:-release}"

"$ROOT/scripts/install-deps.sh"
"$ROOT/scripts/build.sh" --target vscand vscan

rm -rf "$OUT/scans" "$OUT/port"
mkdir -p "$OUT/scans"
"$BIN/server/vscand" --listen 127.0.0.1:0 --port-file "$OUT/port" --data-dir "$OUT/data" \
  2>"$OUT/vscand.log" &
SERVER_PID=$!
trap 'kill -TERM $SERVER_PID 2>/dev/null; wait $SERVER_PID 2>/dev/null || true' EXIT
for _ in $(seq 300); do [ -s "$OUT/port" ] && break; sleep 0.1; done
[ -s "$OUT/port" ] || { echo "vscand did not start; see $OUT/vscand.log"; exit 1; }
export VSCAN_SERVER="127.0.0.1:$(cat "$OUT/port")"
vscan() { "$BIN/client/cli/vscan" "$@"; }

vscan health
MESH=$(vscan -q mesh upload "$ROOT/data/meshes/bunny/bunny_zipper_res2.ply" --unit m --name bunny)
SCENE=$(vscan -q scene create bunny-demo)
vscan -q object add "$SCENE" "$MESH" --label bunny --on-table >/dev/null
# The bunny stands with +Y up; the table turns about +Y under it.
vscan -q table set "$SCENE" --centre -0.017,0,0 --axis 0,1,0 --angle 0 >/dev/null

CAMERA=(--width 1280 --height 1024 --hfov 40 --near 0.1 --far 2 --target -0.017,0.11,0 --fields all)
n=0
for angle in 0 90 180 270; do
  n=$((n + 1))
  vscan --json scan "$SCENE" -o "$OUT/scans/bunny_${n}_table${angle}.ply" "${CAMERA[@]}" \
    --up 0,1,0 --eye 0.45,0.2,0.1 --table-angle "$angle" >"$OUT/scans/bunny_${n}_table${angle}.json"
done
vscan --json scan "$SCENE" -o "$OUT/scans/bunny_5_top.ply" "${CAMERA[@]}" --up 0,0,-1 \
  --eye -0.017,0.6,0.001 >"$OUT/scans/bunny_5_top.json"

/usr/bin/python3 - "$OUT/scans" <<'PY' | tee "$OUT/summary.txt"
import json, os, sys
d = sys.argv[1]
print(f"{'scan':28} {'points':>9} {'hit ratio':>9} {'server ms':>9} {'total ms':>9}")
for name in sorted(f for f in os.listdir(d) if f.endswith(".json")):
    r = json.load(open(os.path.join(d, name)))
    s = r["statistics"]
    print(f"{os.path.basename(r['output']):28} {int(s['points']):9d} {s['hitRatio']:9.3f} "
          f"{s['scanMs']:9.1f} {r['clientMs']:9.1f}")
PY
echo "demo: PLY files in $OUT/scans, summary in $OUT/summary.txt"
