#!/usr/bin/env python3
"""A bin fill with and without its pick check, through a running vscand: the parts of
examples/bins/mixed_parts.yaml (20 machined parts, 30 x 20 x 15 cm bin, seed 7) filled twice into
two scenes, each with a UR5 on a 0.2 m pedestal 0.5 m beside the bin; the second fill asks for
picks with a 10 mm suction cup. Prints the fill's wall time, the pick check's, the job's time as
the client saw it and the pickable count.

    VSCAN_PY_STUBS=build/release/python /usr/bin/python3 bench/bin_picks_bench.py --server 127.0.0.1:50051
"""

import argparse
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "client", "python"))
if os.environ.get("VSCAN_PY_STUBS"):
    sys.path.insert(0, os.environ["VSCAN_PY_STUBS"])

from vscan import Client  # noqa: E402
from vscan.bins import bin_part  # noqa: E402

PARTS = os.path.join(HERE, "..", "data", "parts")
UR5 = os.path.join(HERE, "..", "data", "robots", "ur5")
# examples/bins/mixed_parts.yaml: file, unit, scale, count.
FIXTURE = (("angle_block.STL", "in", 1.0, 8), ("round.stl", "in", 0.05, 8), ("plate_holes.STL", "mm", 0.25, 4))
INNER = (0.30, 0.20, 0.15)


def fill(client, robot_id, parts, seed, picks):
    scene = client.create_scene(f"bin-picks-bench-{'picks' if picks else 'plain'}")
    mount = client.mount_robot(scene.scene_id, robot_id, position=(-0.5, 0.0, 0.2)).mount_id
    spec_picks = None
    if picks:
        spec_picks = {"mount_id": mount, "gripper": {"suction": {"diameter": 0.010}},
                      "pick_options": {"body_length": 0.08}}
    started = time.monotonic()
    job, report = client.bin_fill(scene.scene_id, INNER, parts, seed=seed, max_simulated_s=40.0, picks=spec_picks,
                                  timeout=900)
    client_s = time.monotonic() - started
    row = {"picks": picks, "state": job.state, "in_bin": report["in_bin"], "client_s": round(client_s, 2),
           "fill_wall_s": round(report["setup_wall_s"] + report["step_wall_s"], 2)}
    if "picks" in report:
        row.update(pick_check_s=round(report["picks"]["elapsed_s"], 2), pickable=report["picks"]["pickable"],
                   parts_checked=report["picks"]["parts_checked"], grasps=report["picks"]["grasps_generated"])
        failures = {}
        for part in report["parts"]:
            failures[part["pick"]["failure"]] = failures.get(part["pick"]["failure"], 0) + 1
        row["verdicts"] = failures
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--server", required=True)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    with Client(args.server) as client:
        robot = client.upload_robot(UR5, urdf="ur5_robot.urdf", base="base_link", tip="tool0", name="ur5")
        parts = []
        for file, unit, scale, count in FIXTURE:
            mesh = client.upload_mesh(os.path.join(PARTS, file), unit=unit)
            parts.append(bin_part(mesh.mesh_id, count, scale=scale, name=os.path.splitext(file)[0]))
        for picks in (False, True):
            print(json.dumps(fill(client, robot.robot_id, parts, args.seed, picks)))


if __name__ == "__main__":
    main()
