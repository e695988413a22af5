#!/usr/bin/env python3
"""Picking jobs emptying filled bins, as a user runs them: through a running vscand, K bins of the
fixture parts (the pick_check counts, different seeds) are filled, a UR5 is mounted beside each on
a 0.3 m pedestal with a 10 mm suction cup's centre point 0.1 m beyond its flange (as
bench/pick_check.py), and a picking job empties the bin, once with the parts' true poses and once
from scans with the baseline localizer (each on its own fill of the same seed). Prints per bin and
perception the parts picked, the steps by outcome, the seconds a step took (perceive + plan +
settle from picking.json: median and max) and the job's wall time as this client sees it (start
call to the end seen by its watch).

--perception client-vs-truth runs, per bin, a true-pose job and a client-perception job whose
localizer is instant: it answers each awaited step with the step's truth file, so the difference is
the round trip (the step's scan and artifacts, the client's download of the scan and the truth file,
the submit, the job's wake-up). It prints, per step (median), the client's download and submit
seconds and the job's wait from the moment it awaited to the estimates' arrival as the client sees
it (awaited event seen to submit answered).

    VSCAN_PY_STUBS=build/release/python PYTHONPATH=client/python /usr/bin/python3 bench/picking_job.py \\
        --server 127.0.0.1:50051 --bins 3
"""

import argparse
import json
import os
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "integration"))
sys.path.insert(0, os.path.join(HERE, "..", "client", "python"))
if os.environ.get("VSCAN_PY_STUBS"):
    sys.path.insert(0, os.environ["VSCAN_PY_STUBS"])

import grpc  # noqa: E402
from bin_scenes import FIXTURE_PARTS, fill_bin, upload_part, upload_ur5  # noqa: E402
from pick_check import COUNTS, INNER  # noqa: E402
from vscan import Client, SuctionCup  # noqa: E402
from vscan.v1 import robot_pb2_grpc, scene_pb2_grpc  # noqa: E402

BASE = [[0, 1, 0, 0], [-1, 0, 0, 0.45], [0, 0, 1, 0.30], [0, 0, 0, 1]]
TOOL = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.10], [0, 0, 0, 1]]
CUP = SuctionCup(diameter=0.010)


def run_job(client, channel, parts, robot_id, seed, truth, args):
    scene = client.create_scene(f"picking-{seed}-{'truth' if truth else 'baseline'}").scene_id
    fill = fill_bin(channel, scene, [(parts[n][0], parts[n][1], COUNTS[n]) for n in parts], seed, inner_size=INNER)
    mount = client.mount_robot(scene, robot_id, matrix=BASE, tool_matrix=TOOL).mount_id
    time.sleep(args.pause)
    start = time.monotonic()
    job = client.start_picking(fill.job_id, mount, CUP, truth=truth, max_grasps=args.grasps)
    job = client.wait_job(job.job_id)
    wall = time.monotonic() - start
    return report_row(client, job, seed, wall)


def report_row(client, job, seed, wall):
    report = client.picking_report(job.job_id)
    step_s = [s["perceive_s"] + s["plan_s"] + s["settle_s"] for s in report["steps"]]
    return {"seed": seed, "perception": report["perception"], "state": report["state"],
            "parts": report["parts_at_start"], "picked": report["picked"], "fell_out": report["fell_out"],
            "left": report["left"], "end": report.get("end"), "outcomes": report["outcomes"],
            "steps": len(report["steps"]), "step_s_median": statistics.median(step_s) if step_s else 0.0,
            "step_s_max": max(step_s, default=0.0),
            "perceive_s_median": statistics.median([s["perceive_s"] for s in report["steps"]] or [0.0]),
            "plan_s_median": statistics.median([s["plan_s"] for s in report["steps"]] or [0.0]),
            "settle_s_median": statistics.median([s["settle_s"] for s in report["steps"]] or [0.0]),
            "wall_s": wall, "job_id": job.job_id}


def run_client_job(client, channel, parts, robot_id, seed, args):
    """A client-perception job answered instantly from each step's truth file; the row has the
    same figures as run_job's plus the client's per-step download, submit and round-trip seconds."""
    scene = client.create_scene(f"picking-{seed}-client").scene_id
    fill = fill_bin(channel, scene, [(parts[n][0], parts[n][1], COUNTS[n]) for n in parts], seed, inner_size=INNER)
    mount = client.mount_robot(scene, robot_id, matrix=BASE, tool_matrix=TOOL).mount_id
    time.sleep(args.pause)
    start = time.monotonic()
    job = client.start_picking(fill.job_id, mount, CUP, perception="client", max_grasps=args.grasps)
    download_s, submit_s, round_trip_s, sent = [], [], [], set()
    for response in client.watch_job(job.job_id):
        if not response.job.HasField("awaiting_estimates") or response.job.awaiting_estimates.step in sent:
            continue
        seen = time.monotonic()
        awaited = response.job.awaiting_estimates
        points = client.picking_step_scan(job.job_id, awaited)
        truth = client.picking_step_truth(job.job_id, awaited.step)
        downloaded = time.monotonic()
        estimates = [(p["part"], [p["world_from_part"][r * 4:r * 4 + 4] for r in range(4)], 1.0) for p in truth["parts"]]
        client.submit_picking_estimates(job.job_id, awaited.step, estimates)
        submitted = time.monotonic()
        sent.add(awaited.step)
        download_s.append(downloaded - seen)
        submit_s.append(submitted - downloaded)
        round_trip_s.append(submitted - seen)
        del points
    job = client.get_job(job.job_id)
    wall = time.monotonic() - start
    row = report_row(client, job, seed, wall)
    row.update({"download_s_median": statistics.median(download_s or [0.0]),
                "submit_s_median": statistics.median(submit_s or [0.0]),
                "round_trip_s_median": statistics.median(round_trip_s or [0.0]),
                "round_trip_s_max": max(round_trip_s, default=0.0)})
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--server", default="127.0.0.1:50051")
    parser.add_argument("--bins", type=int, default=3)
    parser.add_argument("--first-seed", type=int, default=1)
    parser.add_argument("--pause", type=float, default=2.0, help="idle seconds before each job")
    parser.add_argument("--grasps", type=int, default=1000, help="grasps kept per part type, best first")
    parser.add_argument("--perception", choices=("both", "truth", "baseline", "client-vs-truth"), default="both")
    parser.add_argument("--json", help="write every figure here")
    args = parser.parse_args()

    channel = grpc.insecure_channel(args.server)
    scenes = scene_pb2_grpc.SceneServiceStub(channel)
    robots = robot_pb2_grpc.RobotServiceStub(channel)
    parts = {name: upload_part(scenes, name) for name in FIXTURE_PARTS}
    robot_id = upload_ur5(robots)
    modes = {"both": (True, False), "truth": (True,), "baseline": (False,), "client-vs-truth": (True, "client")}[
        args.perception]
    rows = []
    with Client(args.server) as client:
        for k in range(args.bins):
            seed = args.first_seed + k
            for truth in modes:
                if truth == "client":
                    row = run_client_job(client, channel, parts, robot_id, seed, args)
                else:
                    row = run_job(client, channel, parts, robot_id, seed, truth, args)
                rows.append(row)
                outcomes = ", ".join(f"{v} {k.replace('_', ' ')}" for k, v in sorted(row["outcomes"].items()))
                print(f"bin seed {seed}, {row['perception']}: {row['state']}, {row['picked']} of {row['parts']} "
                      f"picked in {row['steps']} steps ({outcomes}; {row['fell_out']} fell out, end: {row['end']}); "
                      f"step s median {row['step_s_median']:.2f} max {row['step_s_max']:.2f} (perceive "
                      f"{row['perceive_s_median']:.2f}, plan {row['plan_s_median']:.2f}, settle "
                      f"{row['settle_s_median']:.2f}); job wall {row['wall_s']:.1f} s", flush=True)
                if "round_trip_s_median" in row:
                    print(f"  client per step, median: download {row['download_s_median']:.3f} s, submit "
                          f"{row['submit_s_median']:.3f} s, awaited seen to submit answered "
                          f"{row['round_trip_s_median']:.3f} s (max {row['round_trip_s_max']:.3f})", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
