#!/usr/bin/env python3
"""The baseline localizer on filled bins, as a user runs it: through a running vscand, K bins of the
fixture parts (different seeds) are filled, each is scanned from above at 1280x1024 clean and with
a sensor preset's noise, every part type is localized in each stored scan (one Localize call for all
of them) and the estimates are scored with ScorePoses. Prints ADD(-S) recall and BOP's MSSD average
recall per part and overall, clean and noisy, and the localize time per scan. With
--gripper-diameter D the estimates are scored a second time with a suction cup of that diameter:
the grasp success (a grasp planned on each estimate holds the true part) beside the recalls, and
the time of ScorePoses with and without the gripper.

    VSCAN_PY_STUBS=build/release/python /usr/bin/python3 bench/bin_localization.py \\
        --server 127.0.0.1:50051 --bins 3 --json bin_localization.json
"""

import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "integration"))  # bin_scenes: fill, scan, write
sys.path.insert(0, os.path.join(HERE, "..", "client", "python"))
if os.environ.get("VSCAN_PY_STUBS"):
    sys.path.insert(0, os.environ["VSCAN_PY_STUBS"])

import grpc  # noqa: E402
from bin_scenes import FIXTURE_PARTS, fill_bin, preset_noise, scan_bin, sensor_preset, upload_part  # noqa: E402
from localization_peers import PeerBench  # noqa: E402
from vscan.v1 import (cloud_pb2, cloud_pb2_grpc, common_pb2, localization_pb2,  # noqa: E402
                      localization_pb2_grpc, scan_pb2_grpc, scene_pb2, scene_pb2_grpc)

INNER = (0.24, 0.18, 0.10)
COUNTS = {"angle_block": 6, "round": 6, "plate_holes": 3}
# The "materials" scans: each part type made of a machined part's material, lit by the sensor
# preset's own emitter and camera (its returned light), so that dark and saturated pixels leave
# the gaps a real scanner leaves, with the preset's noise.
MATERIALS = {"angle_block": "machined-aluminium", "round": "brushed-steel", "plate_holes": "black-anodised-aluminium"}
CONDITIONS = ("clean", "noisy", "materials")
# The tube's axis is its z axis (0 to 61 cm in the file): any turn about it, and a half turn about x
# through its middle.
TUBE_LENGTH_M = 0.6096
# The plate (203.2 x 304.8 x 12.7 mm in the file, its corner at the origin) and its five holes are
# symmetric under half turns about the three axes through its centre: turned so, its surface lies
# within 1.2 mm of itself (99% of it within 0.55 mm) on a 92 mm part at the bench's 0.25.
PLATE_SIZE_M = (0.2032, 0.3048, 0.0127)


def half_turn(diagonal, centre):
    """A half turn about an axis through centre: diagonal is the rotation's diagonal (two -1s)."""
    m = np.diag(list(diagonal) + [1.0])
    m[:3, 3] = np.array(centre) - np.diag(diagonal) @ np.array(centre)
    return common_pb2.Pose(matrix=common_pb2.Matrix4(values=list(m.ravel())))


def symmetry(name, scale):
    if name == "plate_holes":
        centre = [v * scale / 2 for v in PLATE_SIZE_M]
        return localization_pb2.PartSymmetry(
            discrete=[half_turn(d, centre) for d in ((-1, -1, 1), (1, -1, -1), (-1, 1, -1))])
    if name != "round":
        return None
    length = TUBE_LENGTH_M * scale
    flip = [1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, length, 0, 0, 0, 1]
    return localization_pb2.PartSymmetry(
        continuous=[localization_pb2.ContinuousSymmetry(axis=common_pb2.Vector3(z=1), point=common_pb2.Vector3())],
        discrete=[common_pb2.Pose(matrix=common_pb2.Matrix4(values=flip))])


def set_materials(scenes, scene_id, parts):
    """Gives every part of the scene its type's material from MATERIALS."""
    material_of = {parts[name][0]: material for name, material in MATERIALS.items()}
    for o in scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene_id), timeout=30).scene.objects:
        if o.mesh_id in material_of:
            scenes.SetObjectMaterial(scene_pb2.SetObjectMaterialRequest(
                scene_id=scene_id, object_id=o.object_id, material=scene_pb2.Material(preset=material_of[o.mesh_id])),
                timeout=30)


def save_scan(base, positions, normals, header, stats, part_index):
    """BASE.ply (x y z nx ny nz) and BASE.txt: the sensor's position, then per true part its index,
    visible fraction and world_from_part row by row, as bench/localize_saved_scan.cpp reads them."""
    os.makedirs(os.path.dirname(base) or ".", exist_ok=True)
    ply = ("ply\nformat binary_little_endian 1.0\n"
           f"element vertex {len(positions)}\n"
           "property float x\nproperty float y\nproperty float z\n"
           "property float nx\nproperty float ny\nproperty float nz\nend_header\n").encode()
    with open(base + ".ply", "wb") as f:
        f.write(ply + np.hstack([positions, normals]).astype("<f4").tobytes())
    pose = list(header.sensor_pose.values)
    with open(base + ".txt", "w") as f:
        f.write(f"{pose[3]} {pose[7]} {pose[11]}\n")
        for o in stats.objects:
            if o.mesh_id in part_index:
                f.write(f"{part_index[o.mesh_id]} {o.visible_fraction} " +
                        " ".join(repr(v) for v in o.world_from_object.values) + "\n")


def upload_scan(clouds, positions, normals, world_from_sensor, name):
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(positions)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              "property float enx\nproperty float eny\nproperty float enz\nend_header\n").encode()
    data = header + np.hstack([positions, normals]).astype("<f4").tobytes()
    pose = common_pb2.Pose(matrix=common_pb2.Matrix4(values=list(world_from_sensor)))

    def requests():
        yield cloud_pb2.UploadCloudRequest(header=cloud_pb2.CloudHeader(
            name=name, format=cloud_pb2.CLOUD_FORMAT_PLY, sensor_pose=pose, size_bytes=len(data)))
        for i in range(0, len(data), 1 << 20):
            yield cloud_pb2.UploadCloudRequest(chunk=data[i:i + (1 << 20)])
    return clouds.UploadCloud(requests(), timeout=120).cloud.cloud_id


class Tally:
    """Valid instances, ADD(-S) hits and MSSD hits per threshold, pooled over scans."""

    def __init__(self):
        self.valid, self.add_correct, self.mssd_correct = 0, 0, None
        self.grasp_holds, self.grasp_failures = 0, {}

    def add_grasps(self, part):
        self.grasp_holds += part.grasp_holds
        for m in part.matches:
            why = m.grasp_failure if m.HasField("estimate_index") else "no estimate matched"
            if why:
                self.grasp_failures[why] = self.grasp_failures.get(why, 0) + 1

    def grasp_success(self):
        return self.grasp_holds / self.valid if self.valid else None

    def add(self, part):
        self.valid += part.valid_instances
        self.add_correct += part.add_correct
        hits = np.array(part.mssd_recalls) * part.valid_instances
        self.mssd_correct = hits if self.mssd_correct is None else self.mssd_correct + hits

    def recall(self):
        return self.add_correct / self.valid if self.valid else None

    def mssd_ar(self):
        return float(np.mean(self.mssd_correct / self.valid)) if self.valid else None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--server", default="127.0.0.1:50051")
    parser.add_argument("--bins", type=int, default=3)
    parser.add_argument("--first-seed", type=int, default=1)
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=1024)
    parser.add_argument("--hfov", type=float, default=48.8, help="the phoxi-m-class camera's")
    parser.add_argument("--distance", type=float, default=0.65, help="sensor above the bin floor, m")
    parser.add_argument("--preset", default="phoxi-m-class", help="sensor preset whose noise the noisy scans get")
    parser.add_argument("--json", help="write every figure here")
    parser.add_argument("--save-scans", metavar="DIR",
                        help="also write each scan as DIR/SEED-CONDITION.ply and .txt, the input of "
                             "build/release/bench/localize_saved_scan")
    parser.add_argument("--peers", default="open3d,pcl", help="peer localizers on the same scans: open3d, pcl, none")
    parser.add_argument("--pcl-peer", help="the localization_pcl_peer executable",
                        default=os.path.join(HERE, "..", "build", "release", "bench", "localization_pcl_peer"))
    parser.add_argument("--gripper-diameter", type=float,
                        help="also score with a suction cup of this diameter (m): grasp success and ScorePoses times")
    parser.add_argument("--max-grasps", type=int, help="grasps kept per part type, best first (server default 100)")
    parser.add_argument("--conditions", default=",".join(CONDITIONS), help="of clean, noisy, materials")
    args = parser.parse_args()
    conditions = [c for c in args.conditions.split(",") if c in CONDITIONS]

    channel = grpc.insecure_channel(args.server, options=[("grpc.max_receive_message_length", 64 << 20)])
    scenes = scene_pb2_grpc.SceneServiceStub(channel)
    scans = scan_pb2_grpc.ScanServiceStub(channel)
    clouds = cloud_pb2_grpc.CloudServiceStub(channel)
    localizer = localization_pb2_grpc.LocalizationServiceStub(channel)
    noise = preset_noise(scans, args.preset)
    light = sensor_preset(scans, args.preset).returned_light
    parts = {name: upload_part(scenes, name) for name in FIXTURE_PARTS}
    names = list(parts)
    scored_parts = [localization_pb2.ScoredPart(mesh_id=parts[n][0], scale=parts[n][1], symmetry=symmetry(n, parts[n][1]))
                    for n in names]

    tallies = {(c, n): Tally() for c in CONDITIONS for n in names + ["all"]}
    times = {c: [] for c in CONDITIONS}
    score_ms = {"without_gripper": [], "with_gripper": []}
    peers = PeerBench(names, COUNTS, Tally, [p for p in args.peers.split(",") if p not in ("", "none")], args.pcl_peer,
                      CONDITIONS)
    runs = []
    for k in range(args.bins):
        seed = args.first_seed + k
        scene = scenes.CreateScene(scene_pb2.CreateSceneRequest(name=f"bench-bin-{seed}"), timeout=30).scene
        job = fill_bin(channel, scene.scene_id, [(parts[n][0], parts[n][1], COUNTS[n]) for n in names], seed,
                       inner_size=INNER)
        for condition in conditions:
            if condition == "materials":
                set_materials(scenes, scene.scene_id, parts)
            positions, normals, header, stats = scan_bin(
                scans, scene.scene_id, args.width, args.height, args.distance, hfov_deg=args.hfov,
                noise=None if condition == "clean" else noise, seed=seed, inner_size=INNER[:2],
                returned_light=light if condition == "materials" else None)
            cloud_id = upload_scan(clouds, positions, normals, header.sensor_pose.values, f"bin-{seed}-{condition}")
            if args.save_scans:
                save_scan(os.path.join(args.save_scans, f"{seed}-{condition}"), positions, normals, header, stats,
                          {parts[n][0]: i for i, n in enumerate(names)})
            request = localization_pb2.ScorePosesRequest(parts=scored_parts)
            index = {(p.mesh_id, p.scale): i for i, p in enumerate(scored_parts)}
            for o in stats.objects:
                part = index.get((o.mesh_id, o.scale))
                if part is not None:
                    request.truth.add(part=part, world_from_part=common_pb2.Pose(matrix=o.world_from_object),
                                      visible_fraction=o.visible_fraction, instance_id=o.instance_id)
            # Every part type in one call: the scan is prepared once for all of them.
            start = time.monotonic()
            found = localizer.Localize(localization_pb2.LocalizeRequest(
                cloud_id=cloud_id, parts=[localization_pb2.LocalizePart(
                    mesh_id=parts[n][0], scale=parts[n][1], max_instances=COUNTS[n]) for n in names]), timeout=900)
            wall_ms = (time.monotonic() - start) * 1000
            scan_ms = found.localize_ms
            for e in found.estimates:
                request.estimates.add(part=e.part, world_from_part=common_pb2.Pose(matrix=e.world_from_part),
                                      score=e.score)
            for i, name in enumerate(names):
                runs.append({"seed": seed, "condition": condition, "part": name, "found": found.parts[i].found,
                             "localize_ms": found.localize_ms, "wall_ms": wall_ms, "points": found.points,
                             "stop": found.parts[i].stop_reason})
            start = time.monotonic()
            score = localizer.ScorePoses(request, timeout=300)
            score_ms["without_gripper"].append((time.monotonic() - start) * 1000)
            times[condition].append(scan_ms)
            for part in score.parts:
                tallies[(condition, names[part.part])].add(part)
                tallies[(condition, "all")].add(part)
            grasp_text = ""
            if args.gripper_diameter:
                request.gripper.suction.diameter = args.gripper_diameter
                if args.max_grasps:
                    request.grasp_options.max_grasps = args.max_grasps
                start = time.monotonic()
                graspd = localizer.ScorePoses(request, timeout=300)
                score_ms["with_gripper"].append((time.monotonic() - start) * 1000)
                request.ClearField("gripper")
                request.ClearField("grasp_options")
                for part in graspd.parts:
                    tallies[(condition, names[part.part])].add_grasps(part)
                    tallies[(condition, "all")].add_grasps(part)
                grasp_text = (f", grasp success {graspd.grasp_success:.3f}; ScorePoses "
                              f"{score_ms['without_gripper'][-1]:.0f} ms, with the cup {score_ms['with_gripper'][-1]:.0f} ms")
            print(f"bin seed {seed} {condition}: {len(positions)} points, {len(request.truth)} parts in view, "
                  f"ADD(-S) recall {score.add_recall:.3f}, MSSD AR {score.mssd_average_recall:.3f}, "
                  f"localize {scan_ms / 1000:.1f} s{grasp_text}", flush=True)
            peers.run_scan(localizer, condition, seed, positions, header.sensor_pose.values, request)
            clouds.DeleteCloud(cloud_pb2.DeleteCloudRequest(cloud_id=cloud_id), timeout=30)
        scenes.DeleteScene(scene_pb2.DeleteSceneRequest(scene_id=scene.scene_id), timeout=30)

    def fmt(v):
        return "-" if v is None else f"{v:.3f}"
    print(f"\n{args.bins} bins, {args.width}x{args.height}, sensor {args.distance} m above the floor; "
          f"noisy: {args.preset} noise; materials: {args.preset} noise and returned light, parts of "
          + ", ".join(f"{n} {m}" for n, m in MATERIALS.items()))
    grasping = bool(args.gripper_diameter)
    columns = "ADD(-S) recall {c} | MSSD AR {c}" + (" | grasp success {c}" if grasping else "")
    print("| part | valid instances | " + " | ".join(columns.format(c=c) for c in conditions) + " |")
    print("|---|---|" + ("---|---|---|" if grasping else "---|---|") * len(conditions))
    summary = {}
    for name in names + ["all"]:
        summary[name] = {}
        row = []
        for c in conditions:
            t = tallies[(c, name)]
            summary[name].update({f"valid_{c}": t.valid, f"add_recall_{c}": t.recall(), f"mssd_ar_{c}": t.mssd_ar()})
            row.append(f"{fmt(t.recall())} | {fmt(t.mssd_ar())}")
            if grasping:
                summary[name][f"grasp_success_{c}"] = t.grasp_success()
                summary[name][f"grasp_failures_{c}"] = t.grasp_failures
                row[-1] += f" | {t.grasp_holds}/{t.valid} = {fmt(t.grasp_success())}"
        print(f"| {name} | " + " / ".join(str(tallies[(c, name)].valid) for c in conditions) + " | " + " | ".join(row) + " |")
    if grasping:
        for c in conditions:
            for name in names:
                failures = tallies[(c, name)].grasp_failures
                print(f"grasp failures {c} {name}: " + ", ".join(f"{n} {why}" for why, n in sorted(failures.items())))
        for key, values in score_ms.items():
            print(f"ScorePoses {key.replace('_', ' ')}: median {np.median(values):.0f} ms, max {np.max(values):.0f} ms "
                  f"over {len(values)} scans")
    for condition in conditions:
        t = np.array(times[condition]) / 1000
        print(f"localize time per scan ({len(names)} part types), {condition}: median {np.median(t):.1f} s, "
              f"max {t.max():.1f} s")
    peer_summary = peers.report(fmt)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"args": vars(args), "summary": summary, "runs": runs, "scan_localize_ms": times, "score_ms": score_ms,
                       "peers": peer_summary}, f, indent=1)


if __name__ == "__main__":
    main()
