#!/usr/bin/python3
"""Fill a bin with the fixture parts, scan it from above and print each part's visible fraction.

    python client/python/examples/bin_fill.py

with the vscan package installed (client/python/README.md), or from a source tree with
VSCAN_PY_STUBS=build/release/python PYTHONPATH=client/python in the environment.
"""

import argparse
import os
import sys

import numpy as np

from vscan import Client, VscanError, bin_part

HERE = os.path.dirname(os.path.abspath(__file__))

PARTS = os.path.join(HERE, "..", "..", "..", "data", "parts")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default=os.environ.get("VSCAN_SERVER", "127.0.0.1:50051"))
    parser.add_argument("--blocks", type=int, default=8)
    parser.add_argument("--pins", type=int, default=8)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()

    with Client(args.server) as client:
        scene = client.create_scene("bin_fill example")
        block = client.upload_mesh(os.path.join(PARTS, "angle_block.STL"), unit="in")
        pin = client.upload_mesh(os.path.join(PARTS, "round.stl"), unit="in")
        job, report = client.bin_fill(scene.scene_id, (0.30, 0.20, 0.15),
                                      [bin_part(block.mesh_id, args.blocks, name="angle_block"),
                                       bin_part(pin.mesh_id, args.pins, scale=0.05, name="pin")],
                                      seed=args.seed, max_simulated_s=40)
        print(f"job {job.job_id}: {job.message}")
        if not report or not report["applied"]:
            return 1
        print(f"{report['in_bin']} parts in the bin after {report['simulated_s']:.2f} s simulated, "
              f"deepest overlap {report['max_part_part_penetration_m'] * 1e3:.2f} mm")

        # 0.6 m above the floor, looking down, the bin's +y up in the image.
        result = client.scan(scene.scene_id, width=640, height=480, hfov_deg=45.0, eye=(0, 0, 0.6),
                             target=(0, 0, 0), up=(0, 1, 0), fields=["position", "instance"], ground_truth=True)
        ids, counts = np.unique(result.instance_ids, return_counts=True)
        print(f"{len(result)} points of {len(ids)} objects")
        for o in sorted(result.objects, key=lambda o: -o.visible_fraction):
            height = o.world_from_object.values[11]
            print(f"  {o.label:16s} instance {o.instance_id:3d}  z {height:+.3f} m  "
                  f"visible {o.visible_points:6d} of {o.unoccluded_points:6d} ({o.visible_fraction:.2f})")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except VscanError as err:
        print(f"error: {err}", file=sys.stderr)
        sys.exit(3)
