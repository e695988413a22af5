#!/usr/bin/python3
"""Run a scan campaign from Python and merge its scans with numpy.

A UR5 beside a rotary table carries a camera round the Stanford bunny: 4 viewpoints x 4 table
angles. Each scan comes back as a PLY artifact with the pose the arm was commanded to and the pose
it reached (noisy encoders); turning every scan back by its table angle merges them in the
bunny's frame.

    python client/python/examples/campaign_to_numpy.py --server 127.0.0.1:50051

with the vscan package installed (client/python/README.md), or from a source tree with
VSCAN_PY_STUBS=build/release/python PYTHONPATH=client/python in the environment.
"""

import argparse
import math
import os
import sys

import numpy as np

from vscan import Client, VscanError

HERE = os.path.dirname(os.path.abspath(__file__))

DATA = os.path.normpath(os.path.join(HERE, "..", "..", "..", "data"))
TARGET = (0.0, 0.0, 0.07)
VIEWPOINTS = [((0.30, 0.00, 0.12), TARGET), ((0.25, 0.20, 0.25), TARGET), ((0.25, -0.20, 0.25), TARGET),
              ((0.12, 0.00, 0.38), TARGET)]


def ply_positions(data):
    """x, y, z of a binary little-endian PLY as vscan writes it."""
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    types = {"float": "<f4", "uint": "<u4", "int": "<i4", "uchar": "u1"}
    dtype = np.dtype([(line.split()[2], types[line.split()[1]]) for line in header if line.startswith("property")])
    rows = np.frombuffer(data, dtype=dtype, count=count, offset=end)
    return np.c_[rows["x"], rows["y"], rows["z"]].astype(np.float64)


def turn_z(points, angle_deg):
    """Rotates points about the table's axis (world z through the origin)."""
    a = math.radians(angle_deg)
    c, s = math.cos(a), math.sin(a)
    return points @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default=os.environ.get("VSCAN_SERVER", "127.0.0.1:50051"))
    parser.add_argument("--rotations", type=int, default=4)
    args = parser.parse_args()

    with Client(args.server) as client:
        scene = client.create_scene("campaign_to_numpy").scene_id
        bunny = client.upload_mesh(os.path.join(DATA, "meshes", "bunny", "bunny_zipper_res2.ply"), unit="m")
        # The bunny is modelled +y up: roll it upright and stand it on the table.
        half = math.sqrt(0.5)
        client.add_object(scene, bunny.mesh_id, position=(0.017, 0.0, -0.033), quat=(half, half, 0.0, 0.0),
                          label="bunny", on_table=True)
        client.set_table(scene, angle_deg=0.0)
        ur5 = client.upload_robot(os.path.join(DATA, "robots", "ur5"), urdf="ur5_robot.urdf", base="base_link",
                                  tip="tool0")
        # 0.7 m from the table's axis, turned to face it; the camera 5 cm in front of the flange.
        mount = client.mount_robot(scene, ur5.robot_id, position=(0.7, 0.0, 0.0), quat=(0.0, 0.0, 0.0, 1.0),
                                   tool_position=(0.0, 0.0, 0.05), encoder_sigma=0.0002).mount_id

        job = client.start_campaign(scene, mount, VIEWPOINTS, rotations=args.rotations,
                                    rotation_step_deg=360.0 / args.rotations, width=320, height=240, hfov_deg=50.0,
                                    near=0.05, far=1.0, encoder_noise=True, seed=1, name="campaign_to_numpy")
        done = client.wait_job(job.job_id)
        scans = [a for a in done.artifacts if a.HasField("scan")]
        print(f"job {done.job_id}: {len(scans)} scans of {done.steps_total} steps")

        merged, errors = [], []
        for artifact in scans:
            _, data = client.read_artifact(done.job_id, artifact.artifact_id)
            merged.append(turn_z(ply_positions(data), -artifact.scan.table_angle_deg))
            commanded = np.array(artifact.scan.commanded_sensor_pose.values).reshape(4, 4)
            reached = np.array(artifact.scan.sensor_pose.values).reshape(4, 4)
            errors.append(np.linalg.norm(commanded[:3, 3] - reached[:3, 3]))
        cloud = np.concatenate(merged)
        lo, hi = cloud.min(axis=0), cloud.max(axis=0)
        print(f"merged: {len(cloud)} points, bounds {np.round(lo, 3)} .. {np.round(hi, 3)} m")
        print(f"sensor pose error from encoder noise: mean {np.mean(errors) * 1e3:.3f} mm, "
              f"max {np.max(errors) * 1e3:.3f} mm")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except VscanError as err:
        print(f"error: {err}", file=sys.stderr)
        sys.exit(3)
