#!/usr/bin/env python3
"""A dataset job with and without its pick check, through a running vscand: the plan
bench/data/bins_per_minute.yaml (50 parts in a 30 x 20 x 15 cm bin, scanned at 1280 x 1024) run as
a job as it is, then with a picks section (the UR5 of data/robots/ur5 on a 0.2 m pedestal 0.5 m
beside the bin's centre, a 10 mm suction cup, body_length 0.08 m, every other value the default),
alternately, --runs times each. Prints each job's wall time as the client saw it (start to
SUCCEEDED) and, for the picks jobs, the verdicts over the dataset's scene_pickable.json files.

    VSCAN_PY_STUBS=build/release/python /usr/bin/python3 bench/dataset_picks_bench.py --server 127.0.0.1:50051
"""

import argparse
import json
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "client", "python"))
if os.environ.get("VSCAN_PY_STUBS"):
    sys.path.insert(0, os.environ["VSCAN_PY_STUBS"])

from vscan import Client  # noqa: E402
from vscan.v1 import job_pb2  # noqa: E402

PLAN = os.path.join(HERE, "data", "bins_per_minute.yaml")
UR5 = os.path.join(HERE, "..", "data", "robots", "ur5")


def picks_section(robot_id):
    return (f"picks:\n  robot_id: {robot_id}\n  base: {{xyz: [-0.5, 0, 0.2], rpy_deg: [0, 0, 0]}}\n"
            "  gripper: {suction: {diameter: 0.010}}\n  pick_options: {body_length: 0.08}\n")


def run(client, plan_path, picks, seeds):
    started = time.monotonic()
    job = client.run_dataset(plan_path, timeout=3600)
    wall_s = time.monotonic() - started
    row = {"picks": picks, "seeds": seeds, "state": job_pb2.JobState.Name(job.state), "job_wall_s": round(wall_s, 2)}
    if picks and job.state == job_pb2.JOB_STATE_SUCCEEDED:
        verdicts = {}
        with tempfile.TemporaryDirectory(prefix="dataset-picks-bench-") as directory:
            client.download_dataset(job.job_id, directory)
            scenes = os.path.join(directory, "train_pbr")
            for scene in sorted(os.listdir(scenes)):
                with open(os.path.join(scenes, scene, "scene_pickable.json")) as f:
                    for part in json.load(f):
                        verdicts[part["failure"]] = verdicts.get(part["failure"], 0) + 1
        row["verdicts"] = verdicts
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--server", required=True)
    parser.add_argument("--seeds", type=int, default=6, help="seeds 1..N of the plan")
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    with open(PLAN) as f:
        text = f.read().replace("seeds: {first: 1, count: 6}", f"seeds: {{first: 1, count: {args.seeds}}}")
    with Client(args.server) as client:
        robot = client.upload_robot(UR5, urdf="ur5_robot.urdf", base="base_link", tip="tool0", name="ur5")
        # Beside the plan so that its relative mesh paths still resolve.
        plans = {}
        for picks in (False, True):
            path = os.path.join(HERE, "data", f".dataset_picks_bench_{'picks' if picks else 'plain'}.yaml")
            with open(path, "w") as f:
                f.write(text + (picks_section(robot.robot_id) if picks else ""))
            plans[picks] = path
        try:
            for _ in range(args.runs):
                for picks in (False, True):
                    print(json.dumps(run(client, plans[picks], picks, args.seeds)), flush=True)
        finally:
            for path in plans.values():
                os.remove(path)


if __name__ == "__main__":
    main()
