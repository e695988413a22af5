#!/usr/bin/env python3
"""What share of a bin of machined parts a phoxi-m-class scanner returns, with materials and the
returned light against the geometry-only model, and why the rest is missing. Through a running
vscand: one bin of the fixture parts is filled once; each row gives every part one material
(SetObjectMaterial, so the pile is the same) and scans it from the scanner's optimal distance with
include_rejected; the part pixels are counted by the status of their rays.

    VSCAN_PY_STUBS=build/release/python /usr/bin/python3 bench/bin_material_share.py \\
        --server 127.0.0.1:50051 [--json share.json]
"""

import argparse
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "client", "python"))
if os.environ.get("VSCAN_PY_STUBS"):
    sys.path.insert(0, os.environ["VSCAN_PY_STUBS"])

from vscan import Client  # noqa: E402
from vscan.bins import bin_part  # noqa: E402
from vscan.v1 import scan_pb2  # noqa: E402

PARTS = os.path.join(HERE, "..", "data", "parts")
# file, unit, scale, count: the fixture's machined parts.
FIXTURE = (("angle_block.STL", "in", 1.0, 6), ("round.stl", "cm", 0.127, 6), ("plate_holes.STL", "mm", 0.25, 3))
INNER = (0.24, 0.18, 0.10)
# phoxi-m-class: 0.458-1.118 m, optimal 0.65 m from the scanner to the scene.
HEIGHT_M = 0.65
MATERIALS = ("white-abs", "machined-aluminium", "brushed-steel", "polished-steel", "black-anodised-aluminium")
STATUSES = {
    "returned": (scan_pb2.POINT_STATUS_MEASURED, scan_pb2.POINT_STATUS_OUTLIER, scan_pb2.POINT_STATUS_FLYING_PIXEL),
    "dark": (scan_pb2.POINT_STATUS_REJECTED_DARK,),
    "saturated": (scan_pb2.POINT_STATUS_REJECTED_SATURATED,),
    "interreflection": (scan_pb2.POINT_STATUS_REJECTED_INTERREFLECTION,),
    "shadowed or unlit": (scan_pb2.POINT_STATUS_REJECTED_SHADOWED, scan_pb2.POINT_STATUS_REJECTED_UNLIT),
    "grazing or out of range": (scan_pb2.POINT_STATUS_REJECTED_GRAZING, scan_pb2.POINT_STATUS_REJECTED_OUT_OF_RANGE),
}


def shares(result, part_ids):
    on_part = np.isin(result.instance_ids, part_ids)
    statuses = result.statuses[on_part]
    total = max(1, int(on_part.sum()))
    return {name: float(np.isin(statuses, codes).sum()) / total for name, codes in STATUSES.items()}, total


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--server", required=True)
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--indirect-samples", type=int, default=16)
    parser.add_argument("--emitter-w-per-sr", type=float, default=0.0,
                        help="the emitter's radiant intensity (default 0: the preset's own)")
    parser.add_argument("--json")
    args = parser.parse_args()
    client = Client(args.server)
    scene = client.create_scene("material-share").scene_id
    parts = []
    for name, unit, scale, count in FIXTURE:
        mesh = client.upload_mesh(os.path.join(PARTS, name), unit)
        parts.append(bin_part(mesh.mesh_id, count, scale=scale))
    job, report = client.bin_fill(scene, INNER, parts, seed=args.seed, timeout=600)
    placed = [(p["object_id"], p["instance_id"]) for p in report["parts"] if "object_id" in p]
    part_ids = np.array([instance for _, instance in placed], dtype=np.uint32)

    def scan(light):
        return client.scan(scene, preset="phoxi-m-class", eye=(0, 0, HEIGHT_M), target=(0, 0, 0), up=(0, 1, 0),
                           fields=["position", "instance", "status"], include_rejected=True, seed=args.seed,
                           returned_light=light)

    rows = []
    geometry, rays = shares(scan(None), part_ids)
    rows.append({"material": "(geometry only: no returned light)", "light": "none", "part_rays": rays, **geometry})
    for material in MATERIALS:
        for object_id, _ in placed:
            client.set_object_material(scene, object_id, material)
        # The preset's own camera and emitter unless --emitter-w-per-sr sets the emitter.
        direct = {"emitter_w_per_sr": args.emitter_w_per_sr} if args.emitter_w_per_sr > 0 else {}
        for label, light in (("direct", direct or True),
                             ("direct + 1 bounce", {**direct, "indirect_samples": args.indirect_samples,
                                                    "indirect_stride_px": 8})):
            share, rays = shares(scan(light), part_ids)
            rows.append({"material": material, "light": label, "part_rays": rays, **share})
    names = list(STATUSES)
    print("| Parts | Light | " + " | ".join(names) + " |")
    print("|---|---|" + "---|" * len(names))
    for row in rows:
        print(f"| {row['material']} | {row['light']} | " + " | ".join(f"{100 * row[n]:.1f} %" for n in names) + " |")
    print(f"{len(placed)} parts placed, {rows[0]['part_rays']} rays on them; seed {args.seed}, "
          f"emitter {args.emitter_w_per_sr or 'of the preset'} W/sr, {args.indirect_samples} indirect samples at stride 8")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"rows": rows, "parts_placed": len(placed), "seed": args.seed}, f, indent=1)


if __name__ == "__main__":
    main()
