#!/usr/bin/python3
"""Create a scene, upload a mesh, place it, scan it and summarise the cloud with numpy.

    python client/python/examples/scan_to_numpy.py --mesh data/meshes/bunny/bunny_zipper_res2.ply --unit m

with the vscan package installed (client/python/README.md), or from a source tree with
VSCAN_PY_STUBS=build/release/python PYTHONPATH=client/python in the environment.
"""

import argparse
import os
import sys

import numpy as np

from vscan import Client, VscanError


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default=os.environ.get("VSCAN_SERVER", "127.0.0.1:50051"))
    parser.add_argument("--mesh", required=True, help="PLY, OBJ or STL file")
    parser.add_argument("--unit", required=True, choices=["m", "cm", "mm", "in", "ft"])
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    args = parser.parse_args()

    with Client(args.server) as client:
        scene = client.create_scene("scan_to_numpy")
        mesh = client.upload_mesh(args.mesh, unit=args.unit)
        lo = np.array([mesh.bounds.min.x, mesh.bounds.min.y, mesh.bounds.min.z])
        hi = np.array([mesh.bounds.max.x, mesh.bounds.max.y, mesh.bounds.max.z])
        centre, size = (lo + hi) / 2, float(np.linalg.norm(hi - lo))
        # Sit the mesh on the origin's XY plane, centred.
        position = (-centre[0], -centre[1], -lo[2])
        client.add_object(scene.scene_id, mesh.mesh_id, position=position)

        target = (0.0, 0.0, (hi[2] - lo[2]) / 2)
        eye = (1.5 * size, 0.5 * size, target[2] + 0.75 * size)
        result = client.scan(scene.scene_id, width=args.width, height=args.height, hfov_deg=60.0,
                             eye=eye, target=target, near=0.01, far=10 * size + 1)

        n = len(result)
        print(f"N = {n} points from {result.stats.rays} rays (hit ratio {result.stats.hit_ratio:.3f})")
        if n:
            print(f"bounds min = {result.positions.min(axis=0)}")
            print(f"bounds max = {result.positions.max(axis=0)}")
        if result.ranges is not None and n:
            print(f"mean range = {float(result.ranges.mean()):.4f} m")
        client.delete_scene(scene.scene_id)


if __name__ == "__main__":
    try:
        main()
    except VscanError as err:
        print(f"error: {err}", file=sys.stderr)
        sys.exit(4 if err.unreachable else 3)
