#!/usr/bin/env bash
# The main job: set up, build, start vscand on the embedded defaults, run a scan campaign of the
# Stanford bunny on a turntable with a UR5-held camera that aligns each scan as it comes, rebuild
# and score the surface, and leave binary PLY files, the verdict and a summary in vscan-demo/.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="${VSCAN_DEMO_DIR:-$ROOT/vscan-demo}"
BIN="$ROOT/build/${VSCAN_PRESET:-release}"

"$ROOT/scripts/install-deps.sh" build
"$ROOT/scripts/build.sh" --target vscand vscan

rm -rf "$OUT/port"
mkdir -p "$OUT"
# The web view (docs/WEB.md) on loopback: a free port unless VSCAN_DEMO_WEB names one.
WEB="${VSCAN_DEMO_WEB:-127.0.0.1:$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')}"
"$BIN/server/vscand" --listen 127.0.0.1:0 --port-file "$OUT/port" --data-dir "$OUT/data" --web-listen "$WEB" \
  2>"$OUT/vscand.log" &
SERVER_PID=$!
trap 'kill -TERM $SERVER_PID 2>/dev/null; wait $SERVER_PID 2>/dev/null || true' EXIT
for _ in $(seq 300); do [ -s "$OUT/port" ] && break; sleep 0.1; done
[ -s "$OUT/port" ] || { echo "vscand did not start; see $OUT/vscand.log"; exit 1; }
export VSCAN_SERVER="127.0.0.1:$(cat "$OUT/port")"
vscan() { "$BIN/client/cli/vscan" "$@"; }

vscan health
# The whole scan plan is examples/campaigns/bunny_ur5.yaml: the bunny on a turntable, a UR5 with a
# depth camera beside it, 4 viewpoints x 10 table angles. The CLI sets it up, runs the campaign on
# the server, follows it and downloads every scan with its poses.
rm -rf "$OUT/campaign"
vscan campaign run "$ROOT/examples/campaigns/bunny_ur5.yaml" -o "$OUT/campaign"

# summary.txt: one line per scan from the job's record, then the totals (also printed).
/usr/bin/python3 - "$OUT/campaign/job.json" "$OUT/summary.txt" <<'PY'
import json, math, sys
job = json.load(open(sys.argv[1]))

def translation(m):
    v = m["values"]
    return (v[3], v[7], v[11])

scans = sorted((a for a in job.get("artifacts", []) if "scan" in a), key=lambda a: a["name"])
lines = [f"{'scan':18} {'viewpoint':>9} {'table deg':>9} {'points':>9} {'pose error mm':>13}"]
errors = []
for a in scans:
    s = a["scan"]
    errors.append(math.dist(translation(s["commandedSensorPose"]), translation(s["sensorPose"])) * 1000)
    lines.append(f"{a['name']:18} {s.get('viewpointIndex', 0):9d} {s.get('tableAngleDeg', 0):9.1f} "
                 f"{int(s['points']):9d} {errors[-1]:13.3f}")
points = sum(int(a["scan"]["points"]) for a in scans)
totals = [f"campaign {job['campaign']['name']} ({job['jobId']}): {job['state'].removeprefix('JOB_STATE_')}, "
          f"{len(scans)} of {len(job['campaign']['viewpoints']) * job['campaign'].get('rotations', 1)} scans, "
          f"{points} points",
          f"pose error from encoder noise: mean {sum(errors) / max(len(errors), 1):.3f} mm, "
          f"max {max(errors, default=0):.3f} mm"]
open(sys.argv[2], "w").write("\n".join(lines + [""] + totals) + "\n")
print("\n".join(totals))
PY
# A picture of the first scan from its viewpoint, drawn headless with OpenGL.
vscan render "$OUT/campaign/scan-r00-v00.ply" -o "$OUT/scan-r00-v00.png" --color normal --width 800 --height 600 \
  --eye 0.30,0,0.12 --target 0,0,0.07 --up 0,0,1
# The surface rebuilt from the 40 aligned scans, shaded; coverage.png beside it marks what no scan saw.
vscan render "$OUT/campaign/mesh.ply" -o "$OUT/mesh.png" --width 800 --height 600 \
  --eye 0.30,0.1,0.2 --target 0,0,0.07 --up 0,0,1

# A bin: 20 machined parts (examples/bins/mixed_parts.yaml) dropped with Bullet until they settle,
# placed in their scene, then scanned from above with ground truth per part, and drawn by instance.
rm -rf "$OUT/bin"
vscan --json bin fill "$ROOT/examples/bins/mixed_parts.yaml" -o "$OUT/bin" >"$OUT/bin-fill.json"
# --json streams the fill's events a line each, then the result.
BIN_JOB="$(grep -m1 -o '"jobId":"[^"]*"' "$OUT/bin-fill.json" | cut -d'"' -f4)"
vscan bin scan "$BIN_JOB" -o "$OUT/bin/scan.ply"
vscan render "$OUT/bin/scan.ply" -o "$OUT/bin-scan.png" --color instance --width 800 --height 600
/usr/bin/python3 - "$OUT/bin/bin.json" "$OUT/bin/scan.gt.json" <<'PY'
import json, sys
fill, truth = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
parts = [o for o in truth["objects"] if o["object_id"] != fill["bin"]["object_id"]]
seen = sum(1 for o in parts if o["visible_fraction"] > 0.1)
print(f"bin {fill['name']}: {fill['in_bin']} of {fill['spawned']} parts in the bin, {fill['end']} after "
      f"{fill['simulated_s']:.1f} simulated s; the scan sees {seen} of them more than 10%")
PY
echo "demo: PLY files in $OUT/campaign, the verdict in $OUT/campaign/model.json, summary in $OUT/summary.txt," \
  "pictures in $OUT/scan-r00-v00.png, $OUT/mesh.png, $OUT/campaign/coverage.png and $OUT/bin-scan.png;" \
  "the bin in $OUT/bin (bin.json, scan.ply, scan.gt.json)"

# Where to look: the web view of the campaign (viewpoints, scans, union, mesh, coverage) and of the
# bin (its parts settling, by instance).
CAMPAIGN_JOB="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["jobId"])' "$OUT/campaign/job.json")"
BIN_SCENE="$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["scene_id"])' "$OUT/bin/bin.json")"
# The bin's scan as a stored cloud, so that the page can show each point's fields and ground truth.
BIN_CLOUD="$(vscan -q cloud upload "$OUT/bin/scan.ply" --name bin-scan --scene "$BIN_SCENE")"
echo "see it in a browser (the web view, docs/WEB.md):"
echo "  the campaign: $(vscan view --no-open "$CAMPAIGN_JOB" --web "$WEB")"
echo "  the bin fill: $(vscan view --no-open "$BIN_JOB" --web "$WEB")"
echo "  its scene:    $(vscan view --no-open "$BIN_SCENE" --web "$WEB")"
echo "  its scan:     $(vscan view --no-open "$BIN_CLOUD" --web "$WEB")"
if [ -t 0 ] && [ -t 1 ]; then
  read -r -p "vscand serves these until you press Enter. " _
else
  echo "vscand stops with this script; serve them again with:"
  echo "  $BIN/server/vscand --data-dir $OUT/data --web-listen $WEB"
fi
