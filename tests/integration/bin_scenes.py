"""Filled bins of the fixture parts, scanned with ground truth, through a running vscand's raw
stubs: the parts uploaded, a bin filled (StartBinFill), a scan from above with the scene objects'
true poses, and the cloud and truth written as `vscan localize` and `vscan score` read them
(PLY with estimated normals, SCAN.gt.json). Shared by the integration test and
bench/bin_localization.py."""

import json
import math
import os
import time

import numpy as np
from google.protobuf import json_format

from vscan.v1 import common_pb2, job_pb2, job_pb2_grpc, robot_pb2, scan_pb2, scene_pb2

PARTS_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data", "parts")
UR5_URDF = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data", "robots", "ur5", "ur5_robot.urdf")

# name: (file, unit, scale); the sizes of examples/bins/mixed_parts.yaml on the bins work.
FIXTURE_PARTS = {
    "angle_block": ("angle_block.STL", common_pb2.LENGTH_UNIT_INCH, 1.0),
    "round": ("round.stl", common_pb2.LENGTH_UNIT_CENTIMETRE, 0.127),
    "plate_holes": ("plate_holes.STL", common_pb2.LENGTH_UNIT_MILLIMETRE, 0.25),
}


def upload_part(scenes, name):
    """Uploads a fixture part; returns (mesh_id, scale)."""
    file, unit, scale = FIXTURE_PARTS[name]
    with open(os.path.join(PARTS_DIR, file), "rb") as f:
        data = f.read()

    def requests():
        yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(name=file, unit=unit, size_bytes=len(data)))
        for i in range(0, len(data), 1 << 20):
            yield scene_pb2.UploadMeshRequest(chunk=data[i:i + (1 << 20)])
    return scenes.UploadMesh(requests(), timeout=60).mesh.mesh_id, scale


def fill_bin(channel, scene_id, parts, seed, inner_size=(0.24, 0.18, 0.10), timeout=300):
    """parts: [(mesh_id, scale, count)]. Returns the finished Job (raises unless it succeeded)."""
    jobs = job_pb2_grpc.JobServiceStub(channel)
    spec = job_pb2.BinFillSpec(scene_id=scene_id, seed=seed, name="bin")
    spec.bin.inner_size.CopyFrom(common_pb2.Vector3(x=inner_size[0], y=inner_size[1], z=inner_size[2]))
    for mesh_id, scale, count in parts:
        spec.parts.add(mesh_id=mesh_id, scale=scale, count=count)
    job = jobs.StartBinFill(job_pb2.StartBinFillRequest(spec=spec), timeout=60).job
    deadline = time.time() + timeout
    while job.state in (job_pb2.JOB_STATE_QUEUED, job_pb2.JOB_STATE_RUNNING):
        if time.time() > deadline:
            raise RuntimeError(f"bin fill {job.job_id} still {job.state} after {timeout} s")
        time.sleep(0.2)
        job = jobs.GetJob(job_pb2.GetJobRequest(job_id=job.job_id), timeout=30).job
    if job.state != job_pb2.JOB_STATE_SUCCEEDED:
        raise RuntimeError(f"bin fill {job.job_id} ended {job.state}: {job.message}")
    return job


def scan_bin(scans, scene_id, width, height, height_m, hfov_deg=48.8, noise=None, seed=0, inner_size=(0.24, 0.18),
             returned_light=None):
    """A scan from height_m above the bin's floor centre (x right along the bin's length) with
    estimated normals and ground truth; with returned_light, lit by the sensor's emitter and the
    objects' materials. Returns (positions, estimated_normals, header, statistics)."""
    request = scan_pb2.ScanRequest(scene_id=scene_id, seed=seed, frame=scan_pb2.FRAME_WORLD, ground_truth=True)
    camera = request.sensor.pinhole
    camera.width, camera.height, camera.horizontal_fov_deg = width, height, hfov_deg
    camera.near, camera.far = 0.05, 3.0
    request.pose.look_at.eye.CopyFrom(common_pb2.Vector3(x=0, y=0, z=height_m))
    request.pose.look_at.target.CopyFrom(common_pb2.Vector3(x=0, y=0, z=0))
    request.pose.look_at.up.CopyFrom(common_pb2.Vector3(x=0, y=1, z=0))
    request.fields.extend([scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_ESTIMATED_NORMAL])
    if noise is not None:
        request.noise.CopyFrom(noise)
    if returned_light is not None:
        request.returned_light.CopyFrom(returned_light)
    header, stats, positions, normals = None, None, [], []
    for message in scans.Scan(request, timeout=300):
        kind = message.WhichOneof("part")
        if kind == "header":
            header = message.header
        elif kind == "chunk":
            positions.append(np.frombuffer(message.chunk.positions, dtype="<f4").reshape(-1, 3))
            normals.append(np.frombuffer(message.chunk.estimated_normals, dtype="<f4").reshape(-1, 3))
        else:
            stats = message.statistics
    positions = np.concatenate(positions) if positions else np.zeros((0, 3), "<f4")
    normals = np.concatenate(normals) if normals else np.zeros((0, 3), "<f4")
    # Points with too few neighbours get a zero normal; the localizer wants unit normals or none.
    keep = np.linalg.norm(normals, axis=1) > 0.5
    return positions[keep], normals[keep], header, stats


def sensor_preset(scans, name):
    """The server's SensorPreset of that name (its noise, returned light, ...)."""
    for preset in scans.ListSensorPresets(scan_pb2.ListSensorPresetsRequest(), timeout=30).presets:
        if preset.name == name:
            return preset
    raise KeyError(name)


def preset_noise(scans, name):
    """The NoiseSpec a sensor preset applies."""
    return sensor_preset(scans, name).noise


def write_ply(path, positions, normals):
    """Binary little-endian PLY with x y z and the estimated normals enx eny enz."""
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(positions)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              "property float enx\nproperty float eny\nproperty float enz\nend_header\n")
    body = np.hstack([positions, normals]).astype("<f4").tobytes()
    with open(path, "wb") as f:
        f.write(header.encode() + body)


def write_ground_truth(path, job_id, header, stats, cloud_path, points):
    """SCAN.gt.json in the layout `vscan bin scan` writes."""
    objects = [json_format.MessageToDict(o, preserving_proto_field_name=True, including_default_value_fields=True)
               for o in stats.objects]
    with open(path, "w") as f:
        json.dump({"job_id": job_id, "scene_id": header.scene_id, "scene_revision": header.scene_revision,
                   "world_from_sensor": list(header.sensor_pose.values), "width": header.width,
                   "height": header.height, "cloud": cloud_path, "points": points, "objects": objects}, f)


def height_for(inner_size, hfov_deg, width, height, margin=1.15):
    """Sensor height above the floor at which the bin's opening fills the view."""
    tan_h = math.tan(math.radians(hfov_deg) / 2)
    tan_v = tan_h * height / width
    return margin * max((inner_size[0] / 2 + 0.01) / tan_h, (inner_size[1] / 2 + 0.01) / tan_v)


def matrix_pose(rows):
    """A Pose from a 4 x 4 matrix given row by row."""
    return common_pb2.Pose(matrix=common_pb2.Matrix4(values=[v for row in rows for v in row]))


def upload_ur5(robots):
    """Uploads the UR5 fixture (its URDF alone: no link meshes) through a RobotService stub; its id."""
    with open(UR5_URDF, "rb") as f:
        urdf = f.read()

    def requests():
        yield robot_pb2.UploadRobotRequest(header=robot_pb2.RobotBundleHeader(
            name="ur5", urdf_path="ur5_robot.urdf", base_link="base_link", tip_link="tool0"))
        yield robot_pb2.UploadRobotRequest(file=robot_pb2.RobotBundleFile(path="ur5_robot.urdf", content=urdf))
    return robots.UploadRobot(requests(), timeout=60).robot.robot_id
