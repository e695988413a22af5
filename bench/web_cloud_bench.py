#!/usr/bin/python3
"""The web view drawing a 1,000,000-point cloud: starts a vscand from the build with --web-listen,
uploads a cloud of that many points (a torus surface with intensity and instance ids, through the
Python client), and runs bench/web_cloud_bench.js (node, puppeteer-core from .tools/, Debian's
chromium headless with WebGL on the CPU) against ?cloud=ID on loopback: time from navigation to the
first frame drawn, and the frame rate while the orbit controls turn the view.

  VSCAN_BUILD_DIR=build/release VSCAN_SOURCE_DIR=. /usr/bin/python3 bench/web_cloud_bench.py --runs 5

Prints the figures as a Markdown table (docs/BENCHMARKS.md, "Web view")."""

import argparse
import json
import os
import socket
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
os.environ.setdefault("VSCAN_SOURCE_DIR", os.path.join(HERE, ".."))
os.environ.setdefault("VSCAN_BUILD_DIR", os.path.join(HERE, "..", "build", "release"))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "integration"))
sys.path.insert(0, os.path.join(HERE, "..", "client", "python"))

import numpy as np  # noqa: E402
from harness import SOURCE_DIR, Server  # noqa: E402
from vscan import Client  # noqa: E402

TOKEN = "web-cloud-bench"
CHROMIUM = "/usr/bin/chromium"
PUPPETEER = os.path.abspath(os.path.join(SOURCE_DIR, ".tools", "node_modules", "puppeteer-core"))


def torus_cloud(path, points, seed=1):
    """A binary PLY of points on a torus (major 0.3 m, minor 0.1 m): x y z, intensity, instance (8 arcs)."""
    rng = np.random.default_rng(seed)
    u = rng.uniform(0, 2 * np.pi, points)
    v = rng.uniform(0, 2 * np.pi, points)
    rows = np.empty(points, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("intensity", "<f4"),
                                   ("instance", "<i4")])
    rows["x"] = (0.3 + 0.1 * np.cos(v)) * np.cos(u)
    rows["y"] = (0.3 + 0.1 * np.cos(v)) * np.sin(u)
    rows["z"] = 0.1 * np.sin(v)
    rows["intensity"] = 0.5 + 0.5 * np.cos(v)
    rows["instance"] = (u / (2 * np.pi) * 8).astype(np.int32) + 1
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {points}\nproperty float x\nproperty float y\n"
              "property float z\nproperty float intensity\nproperty int instance\nend_header\n")
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(rows.tobytes())


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--frames", type=int, default=20, help="frames of one turn while rotating")
    parser.add_argument("--max-points", default="1000000,250000",
                        help="the page's ?max_points= values to run (comma-separated; the server thins to them)")
    parser.add_argument("--size", default="1280x720", help="page size in CSS pixels")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="vscan-web-bench-") as tmp:
        token_file = os.path.join(tmp, "token")
        with open(token_file, "w") as f:
            f.write(TOKEN + "\n")
        web = f"127.0.0.1:{free_port()}"
        server = Server(extra_args=("--token-file", token_file, "--web-listen", web, "--max-upload-mib", "1024")).start()
        try:
            cloud_path = os.path.join(tmp, "torus.ply")
            torus_cloud(cloud_path, args.points)
            with Client(server.address, token=TOKEN, stream_timeout=600) as client:
                cloud = client.upload_cloud(cloud_path, name="torus")
            results = []
            for max_points in args.max_points.split(","):
                url = f"http://{web}/?cloud={cloud.cloud_id}&max_points={int(max_points)}#token={TOKEN}"
                run = subprocess.run(["node", os.path.join(HERE, "web_cloud_bench.js"), PUPPETEER, CHROMIUM, url,
                                      str(args.runs), str(args.frames), args.size],
                                     capture_output=True, text=True, timeout=1800)
                if run.returncode != 0:
                    raise SystemExit(f"web_cloud_bench.js failed: {run.stdout}{run.stderr}")
                result = json.loads(run.stdout.strip().splitlines()[-1])
                if result["errors"]:
                    raise SystemExit(f"the page logged errors: {result['errors']}")
                results.append(result)
        finally:
            server.cleanup()
    print(f"cloud of {cloud.points} points, page {args.size}, {args.runs} runs each (median, min, max)")
    print("| points sent | navigation to first frame (ms) | frames per second while a drag turns it (points drawn) "
          "| frames per second drawing every point |")
    print("|---|---|---|---|")
    spread = lambda v, f: f"{statistics.median(v):{f}} ({min(v):{f}}–{max(v):{f}})"  # noqa: E731
    for result in results:
        print(f"| {result['points']:,} | {spread(result['first_frame_ms'], '.0f')} | "
              f"{spread(result['rotate_fps'], '.2f')} ({result['points_while_turning']:,}) | "
              f"{spread(result['rotate_fps_all_points'], '.2f')} |")


if __name__ == "__main__":
    main()
