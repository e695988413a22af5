"""Peer localizers for bench/bin_localization.py, run on the same scans as vscan's and scored by the
same ScorePoses call: Open3D's global registration pipeline (in this process) and PCL's FPFH +
SampleConsensusPrerejective pipeline (bench/localization_pcl_peer, one process per scan and part).

Both get what vscan's Localize gets and nothing more: the scan's positions, the sensor's position,
the part's file at its unit and scale, and the most instances to look for (the part's count in the
bin). Both return world_from_part in the part file's frame at its scale, the frame of the truth.

Lengths come from the part, by vscan's own rule: the voxel is the part's bounding-box diagonal / 50,
or its middle extent / 10 when smaller (angle block 1.08 mm, pin 0.65 mm, plate 1.83 mm).
Open3D: the scan thinned to the voxel, the floor removed by segment_plane (1.5 voxels, 1000
iterations), normals from neighbours within 3 voxels turned towards the sensor; features on the scan
and on 20000 samples of the part both thinned to the feature step (2.5 voxels, vscan's point-pair
step), FPFH within 5 steps; RANSAC on feature matches (3 points, distance 1.5 steps, edge-length
check 0.9 and distance check, at most 100000 iterations at confidence 0.999), then point-to-plane ICP
(30 iterations, 2 voxels) against the thinned scan. An instance is kept when at least 10% of the
part's samples (thinned to the voxel) lie within 1.5 voxels of the scan; its scan points within one
step go before the next search; the search stops at the part's count or at the first instance below
10%. PCL: the same lengths in bench/localization_pcl.cpp.
"""

import json
import os
import subprocess
import tempfile
import time

import numpy as np
from bin_scenes import FIXTURE_PARTS, PARTS_DIR

from vscan.v1 import common_pb2, localization_pb2

METRES_PER_UNIT = {common_pb2.LENGTH_UNIT_METRE: 1.0, common_pb2.LENGTH_UNIT_MILLIMETRE: 0.001,
                   common_pb2.LENGTH_UNIT_CENTIMETRE: 0.01, common_pb2.LENGTH_UNIT_INCH: 0.0254}
MODEL_SAMPLES = 20000
FEATURE_STEP_VOXELS = 2.5
MIN_SCORE = 0.1


def part_voxel(extent):
    extent = np.sort(np.asarray(extent, dtype=float))
    return min(float(np.linalg.norm(extent)) / 50, extent[1] / 10)


def rigid(matrix):
    """The nearest rotation (ScorePoses wants an orthonormal one; the peers' are float sums)."""
    m = np.array(matrix, dtype=float).reshape(4, 4)
    u, _, vt = np.linalg.svd(m[:3, :3])
    d = np.sign(np.linalg.det(u @ vt))
    m[:3, :3] = u @ np.diag([1, 1, d]) @ vt
    m[3] = (0, 0, 0, 1)
    return m


class Open3dPeer:
    label = "Open3D 0.16 FPFH + RANSAC + point-to-plane ICP"

    def __init__(self):
        import open3d as o3d
        o3d.utility.random.seed(1)  # segment_plane's and RANSAC's draws
        self.o3d = o3d
        self.reg = o3d.pipelines.registration
        self.models = {}

    def _model(self, path, metres_per_unit):
        key = (path, metres_per_unit)
        if key not in self.models:
            o3d = self.o3d
            mesh = o3d.io.read_triangle_mesh(path)
            mesh.scale(metres_per_unit, center=np.zeros(3))
            voxel = part_voxel(mesh.get_max_bound() - mesh.get_min_bound())
            step = FEATURE_STEP_VOXELS * voxel
            samples = mesh.sample_points_uniformly(MODEL_SAMPLES, use_triangle_normal=True)
            fine = samples.voxel_down_sample(voxel)
            fine.normalize_normals()
            coarse = samples.voxel_down_sample(step)
            coarse.normalize_normals()
            features = self.reg.compute_fpfh_feature(coarse, o3d.geometry.KDTreeSearchParamHybrid(radius=5 * step,
                                                                                                   max_nn=100))
            self.models[key] = (voxel, fine, coarse, features)
        return self.models[key]

    def localize(self, positions, viewpoint, path, metres_per_unit, max_instances):
        """[(world_from_part 4x4, score)], voxel."""
        o3d, reg = self.o3d, self.reg
        voxel, model_fine, model_coarse, model_features = self._model(path, metres_per_unit)
        step = FEATURE_STEP_VOXELS * voxel
        scan = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.asarray(positions, dtype=float)))
        fine = scan.voxel_down_sample(voxel)
        _, floor = fine.segment_plane(distance_threshold=1.5 * voxel, ransac_n=3, num_iterations=1000)
        fine = fine.select_by_index(floor, invert=True)
        fine.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=3 * voxel, max_nn=30))
        fine.orient_normals_towards_camera_location(np.asarray(viewpoint, dtype=float))
        coarse = fine.voxel_down_sample(step)
        coarse.normalize_normals()
        features = reg.compute_fpfh_feature(coarse, o3d.geometry.KDTreeSearchParamHybrid(radius=5 * step, max_nn=100))

        found = []
        while len(found) < max_instances and len(coarse.points) >= 10 and len(fine.points) >= 10:
            guess = reg.registration_ransac_based_on_feature_matching(
                model_coarse, coarse, model_features, features, False, 1.5 * step,
                reg.TransformationEstimationPointToPoint(False), 3,
                [reg.CorrespondenceCheckerBasedOnEdgeLength(0.9), reg.CorrespondenceCheckerBasedOnDistance(1.5 * step)],
                reg.RANSACConvergenceCriteria(100000, 0.999))
            if guess.fitness == 0:
                break
            refined = reg.registration_icp(model_fine, fine, 2 * voxel, guess.transformation,
                                           reg.TransformationEstimationPointToPlane(),
                                           reg.ICPConvergenceCriteria(max_iteration=30))
            pose = rigid(refined.transformation)
            score = reg.evaluate_registration(model_fine, fine, 1.5 * voxel, pose).fitness
            if score < MIN_SCORE:
                break
            found.append((pose, score))
            placed = o3d.geometry.PointCloud(model_fine).transform(pose)
            keep_fine = np.flatnonzero(np.asarray(fine.compute_point_cloud_distance(placed)) > step)
            keep = np.flatnonzero(np.asarray(coarse.compute_point_cloud_distance(placed)) > step)
            if len(keep) == len(coarse.points):
                break
            fine = fine.select_by_index(keep_fine)
            coarse = coarse.select_by_index(keep)
            kept = reg.Feature()
            kept.data = np.ascontiguousarray(features.data[:, keep])
            features = kept
        return found, voxel


class PclPeer:
    label = "PCL 1.13 FPFH + SampleConsensusPrerejective + ICP"

    def __init__(self, executable):
        if not os.access(executable, os.X_OK):
            raise FileNotFoundError(f"{executable}: build it (cmake --build build/release "
                                    "--target localization_pcl_peer)")
        self.executable = executable
        self.scan_path = None

    def set_scan(self, positions):
        """Writes the scan's positions to a temporary PLY for the driver."""
        self.close()
        fd, self.scan_path = tempfile.mkstemp(suffix=".ply", prefix="bin-scan-")
        header = ("ply\nformat binary_little_endian 1.0\n"
                  f"element vertex {len(positions)}\n"
                  "property float x\nproperty float y\nproperty float z\nend_header\n").encode()
        with os.fdopen(fd, "wb") as f:
            f.write(header + np.asarray(positions, dtype="<f4").tobytes())

    def close(self):
        if self.scan_path:
            os.unlink(self.scan_path)
            self.scan_path = None

    def localize(self, positions, viewpoint, path, metres_per_unit, max_instances):
        del positions  # in the file set_scan wrote
        out = subprocess.run([self.executable, self.scan_path, path, repr(metres_per_unit), str(max_instances)] +
                             [repr(float(v)) for v in viewpoint], capture_output=True, text=True, timeout=3600,
                             check=True)
        answer = json.loads(out.stdout)
        return [(rigid(i["world_from_part"]), i["score"]) for i in answer["instances"]], answer["voxel"]


class PeerBench:
    """Runs each peer on every scan, scores it with the scan's truth, and tallies as for vscan."""

    def __init__(self, names, counts, tally, peer_names, pcl_executable, conditions=("clean", "noisy")):
        self.names, self.counts, self.conditions = names, counts, conditions
        self.peers = {}
        for peer in peer_names:
            if peer == "open3d":
                self.peers[peer] = Open3dPeer()
            elif peer == "pcl":
                self.peers[peer] = PclPeer(pcl_executable)
            else:
                raise ValueError(f"--peers: unknown peer {peer!r} (open3d, pcl, none)")
        self.tallies = {(p, c, n): tally() for p in self.peers for c in conditions for n in names + ["all"]}
        self.times = {(p, c): [] for p in self.peers for c in conditions}
        self.runs = []

    def run_scan(self, localizer, condition, seed, positions, world_from_sensor, scored):
        """scored: vscan's ScorePosesRequest for this scan; only its parts and truth are used, to score."""
        viewpoint = [world_from_sensor[3], world_from_sensor[7], world_from_sensor[11]]
        for peer_name, peer in self.peers.items():
            if isinstance(peer, PclPeer):
                peer.set_scan(positions)
            request = localization_pb2.ScorePosesRequest(parts=scored.parts, truth=scored.truth)
            scan_s = 0.0
            try:
                for i, name in enumerate(self.names):
                    file, unit, scale = FIXTURE_PARTS[name]
                    start = time.monotonic()
                    found, voxel = peer.localize(positions, viewpoint, os.path.join(PARTS_DIR, file),
                                                 METRES_PER_UNIT[unit] * scale, self.counts[name])
                    seconds = time.monotonic() - start
                    scan_s += seconds
                    for pose, score in found:
                        request.estimates.add(part=i, score=score, world_from_part=common_pb2.Pose(
                            matrix=common_pb2.Matrix4(values=pose.reshape(-1).tolist())))
                    self.runs.append({"peer": peer_name, "seed": seed, "condition": condition, "part": name,
                                      "found": len(found), "seconds": seconds, "voxel": voxel})
            finally:
                if isinstance(peer, PclPeer):
                    peer.close()
            score = localizer.ScorePoses(request, timeout=300)
            self.times[(peer_name, condition)].append(scan_s)
            for part in score.parts:
                self.tallies[(peer_name, condition, self.names[part.part])].add(part)
                self.tallies[(peer_name, condition, "all")].add(part)
            print(f"  {peer_name}: ADD(-S) recall {score.add_recall:.3f}, MSSD AR {score.mssd_average_recall:.3f}, "
                  f"{scan_s:.1f} s", flush=True)

    def report(self, fmt):
        summary = {}
        if not self.peers:
            return summary
        print("\n| peer | part | valid instances | "
              + " | ".join(f"ADD(-S) recall {c} | MSSD AR {c}" for c in self.conditions) + " |")
        print("|---|---|---|" + "---|---|" * len(self.conditions))
        for peer_name, peer in self.peers.items():
            summary[peer_name] = {"label": peer.label, "parts": {}}
            for name in self.names + ["all"]:
                figures, cells = {}, []
                for c in self.conditions:
                    t = self.tallies[(peer_name, c, name)]
                    figures.update({f"valid_{c}": t.valid, f"add_recall_{c}": t.recall(), f"mssd_ar_{c}": t.mssd_ar()})
                    cells.append(f"{t.add_correct}/{t.valid} = {fmt(t.recall())} | {fmt(t.mssd_ar())}")
                summary[peer_name]["parts"][name] = figures
                valid = " / ".join(str(self.tallies[(peer_name, c, name)].valid) for c in self.conditions)
                print(f"| {peer.label} | {name} | {valid} | " + " | ".join(cells) + " |")
        for (peer_name, condition), seconds in self.times.items():
            t = np.array(seconds)
            summary[peer_name][f"scan_seconds_{condition}"] = seconds
            print(f"{self.peers[peer_name].label}, time per scan ({len(self.names)} part types), {condition}: "
                  f"median {np.median(t):.1f} s, max {t.max():.1f} s")
        summary["runs"] = self.runs
        return summary
