#!/usr/bin/env python3
"""Pick checks on filled bins, as a user runs them: through a running vscand, K bins of the fixture
parts (different seeds) are filled, a UR5 is mounted beside each on a pedestal with a gripper's
tool centre point 0.1 m beyond its flange, and CheckPicks is called for a suction cup and for
parallel jaws. Prints per bin and gripper the pickable count, the failures by kind, and the call's
wall time seen by this client (after an idle pause) and by the server, over several runs.

    VSCAN_PY_STUBS=build/release/python /usr/bin/python3 bench/pick_check.py \\
        --server 127.0.0.1:50051 --bins 3 --runs 3
"""

import argparse
import collections
import json
import os
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "integration"))
if os.environ.get("VSCAN_PY_STUBS"):
    sys.path.insert(0, os.environ["VSCAN_PY_STUBS"])

import grpc  # noqa: E402
from bin_scenes import FIXTURE_PARTS, fill_bin, matrix_pose, upload_part, upload_ur5  # noqa: E402
from vscan.v1 import picking_pb2, picking_pb2_grpc, robot_pb2, robot_pb2_grpc, scene_pb2, scene_pb2_grpc  # noqa: E402

INNER = (0.24, 0.18, 0.10)
COUNTS = {"angle_block": 6, "round": 6, "plate_holes": 3}
GRIPPERS = {
    "suction 10 mm": picking_pb2.Gripper(suction=picking_pb2.SuctionCup(diameter=0.010)),
    "jaws 2-40 mm": picking_pb2.Gripper(jaws=picking_pb2.ParallelJaws(min_opening=0.002, max_opening=0.040,
                                                                       finger_width=0.008, finger_depth=0.008)),
}


def spread(values):
    return f"{min(values):.0f} / {statistics.median(values):.0f} / {max(values):.0f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--server", default="127.0.0.1:50051")
    parser.add_argument("--bins", type=int, default=3)
    parser.add_argument("--first-seed", type=int, default=1)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--pause", type=float, default=2.0, help="idle seconds before each timed call")
    parser.add_argument("--grasps", type=int, default=1000, help="grasps kept per part type, best first")
    parser.add_argument("--json", help="write every figure here")
    args = parser.parse_args()

    channel = grpc.insecure_channel(args.server)
    scenes = scene_pb2_grpc.SceneServiceStub(channel)
    robots = robot_pb2_grpc.RobotServiceStub(channel)
    picking = picking_pb2_grpc.PickingServiceStub(channel)
    parts = {name: upload_part(scenes, name) for name in FIXTURE_PARTS}
    robot_id = upload_ur5(robots)
    rows = []
    for k in range(args.bins):
        seed = args.first_seed + k
        scene_id = scenes.CreateScene(scene_pb2.CreateSceneRequest(name=f"picks-{seed}"), timeout=30).scene.scene_id
        fill_bin(channel, scene_id, [(parts[n][0], parts[n][1], COUNTS[n]) for n in parts], seed, inner_size=INNER)
        # Beside the bin's long side on a 0.3 m pedestal, turned to face it; the gripper's centre
        # point 0.1 m beyond the flange.
        base = [[0, 1, 0, 0], [-1, 0, 0, 0.45], [0, 0, 1, 0.30], [0, 0, 0, 1]]
        tool = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.10], [0, 0, 0, 1]]
        mount_id = robots.MountRobot(robot_pb2.MountRobotRequest(
            scene_id=scene_id, robot_id=robot_id, base_pose=matrix_pose(base), tool_offset=matrix_pose(tool)),
            timeout=30).mount_id
        for name, gripper in GRIPPERS.items():
            walls, server_ms = [], []
            for _ in range(args.runs):
                time.sleep(args.pause)
                start = time.monotonic()
                answer = picking.CheckPicks(picking_pb2.CheckPicksRequest(
                    mount_id=mount_id, gripper=gripper, grasp_options=picking_pb2.GraspOptions(max_grasps=args.grasps)),
                    timeout=600)
                walls.append((time.monotonic() - start) * 1000)
                server_ms.append(answer.elapsed_ms)
            failures = collections.Counter(picking_pb2.PickFailure.Name(p.failure) for p in answer.parts if not p.pickable)
            row = {"seed": seed, "gripper": name, "parts": len(answer.parts), "pickable": answer.pickable,
                   "failures": dict(failures), "grasps": answer.grasps_generated, "wall_ms": walls,
                   "server_ms": server_ms}
            rows.append(row)
            print(f"bin seed {seed}, {name}: {answer.pickable} of {len(answer.parts)} pickable "
                  f"({', '.join(f'{v} {k[13:].lower()}' for k, v in sorted(failures.items()))}); "
                  f"{answer.grasps_generated} grasps; wall ms min/median/max {spread(walls)}, "
                  f"server {spread(server_ms)}", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
