"""Scan campaigns as durable jobs, end to end through a real vscand: a UR5 beside a rotary table
scans the bunny from look-at viewpoints; events, artifacts, cancellation, restarts, bad specs."""

import json
import math
import os
import re
import threading
import time
import unittest

import grpc
import numpy as np

from harness import BUNNY, Server, common_pb2, pinhole, scene_pb2, scene_pb2_grpc
from test_robots import (UR5, UR5_DIR, UrdfChain, axis_angle, matrix, to_pose, transform, upload_panda,
                         upload_ur5)
from vscan.v1 import job_pb2, job_pb2_grpc, robot_pb2, robot_pb2_grpc, sensor_pb2

from vscan import Client, VscanError

C = grpc.StatusCode
TARGET = (0.0, 0.0, 0.11)
VIEWPOINTS = [((0.25, 0.0, 0.30), TARGET), ((0.22, 0.2, 0.20), TARGET)]
FAR_AWAY = ((-1.5, 0.0, 0.3), TARGET)  # some 2 m from the arm's base: beyond a UR5's 0.85 m reach
MARGIN = 0.003  # metres around the bunny's bounding box


def bunny_vertices():
    """The bunny's vertices as stored (metres, y up)."""
    with open(BUNNY) as f:
        text = f.read()
    header, body = text.split("end_header\n", 1)
    count = int(re.search(r"element vertex (\d+)", header).group(1))
    return np.array([[float(x) for x in line.split()[:3]] for line in body.splitlines()[:count]])


def upright():
    """object_from_file of the bunny on the table: its +y turned to world +z."""
    return transform(axis_angle([1, 0, 0], math.pi / 2))


def on_table(vertices, angle_deg):
    """The bunny's vertices in the world when the table (centre 0, axis z) stands at angle_deg."""
    return (transform(axis_angle([0, 0, 1], math.radians(angle_deg))) @ upright() @
            np.c_[vertices, np.ones(len(vertices))].T).T[:, :3]


def world_box(vertices, angle_deg):
    """Bounding box of the bunny at that table angle, grown by MARGIN."""
    world = on_table(vertices, angle_deg)
    return world.min(axis=0) - MARGIN, world.max(axis=0) + MARGIN


def surface_distance(points, vertices, angle_deg):
    """Distance from each point to the nearest bunny vertex at that table angle."""
    world = on_table(vertices, angle_deg)
    return np.sqrt(((points[:, None, :] - world[None, :, :]) ** 2).sum(axis=2).min(axis=1))


def parse_ply(data):
    """Positions of a binary little-endian PLY as the server writes it."""
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    assert header[1] == "format binary_little_endian 1.0", header[1]
    count = int(header[2].split()[2])
    types = {"float": "<f4", "uint": "<u4", "int": "<i4", "uchar": "u1"}
    dtype = np.dtype([(line.split()[2], types[line.split()[1]]) for line in header if line.startswith("property")])
    assert len(data) - end == count * dtype.itemsize, (len(data) - end, count, dtype.itemsize)
    rows = np.frombuffer(data[end:], dtype=dtype, count=count)
    return np.c_[rows["x"], rows["y"], rows["z"]].astype(float), dtype.names


def camera(width=640, height=480, hfov=45.0):
    return pinhole(width, height, hfov, near=0.05, far=2.0)


def vec(p):
    return common_pb2.Vector3(x=p[0], y=p[1], z=p[2])


def spec(scene_id, mount_id, viewpoints=VIEWPOINTS, rotations=3, step=120.0, **kwargs):
    s = job_pb2.CampaignSpec(scene_id=scene_id, mount_id=mount_id, rotations=rotations, rotation_step_deg=step,
                             **kwargs)
    if not s.HasField("sensor"):
        s.sensor.CopyFrom(camera())
    for position, target in viewpoints:
        s.viewpoints.add(position=vec(position), target=vec(target))
    return s


class CampaignFixture:
    """A bunny on a rotary table and a UR5 mounted beside it, facing it."""

    def __init__(self, server):
        self.channel = server.channel()
        self.scenes = scene_pb2_grpc.SceneServiceStub(self.channel)
        self.robots = robot_pb2_grpc.RobotServiceStub(self.channel)
        self.jobs = job_pb2_grpc.JobServiceStub(self.channel)
        self.ur5 = upload_ur5(self.robots)
        self.scene = self.bunny_scene()
        self.base = transform(axis_angle([0, 0, 1], math.pi), [0.55, 0.0, 0.0])
        self.mount = self.mount_ur5(self.scene)

    def bunny_scene(self, table=True):
        scene = self.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="campaign")).scene
        with open(BUNNY, "rb") as f:
            data = f.read()

        def requests():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                name="bunny.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data)))
            yield scene_pb2.UploadMeshRequest(chunk=data)
        mesh = self.scenes.UploadMesh(requests(), timeout=60).mesh
        self.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id, label="bunny",
                                                         pose=to_pose(upright()), on_table=True))
        if table:
            self.scenes.SetRotaryTable(scene_pb2.SetRotaryTableRequest(
                scene_id=scene.scene_id, table=scene_pb2.RotaryTable(enabled=True, axis=common_pb2.Vector3(z=1))))
        return scene

    def mount_ur5(self, scene, **kwargs):
        return self.robots.MountRobot(robot_pb2.MountRobotRequest(
            scene_id=scene.scene_id, robot_id=self.ur5.robot_id, base_pose=to_pose(self.base), **kwargs),
            timeout=10).mount_id

    def close(self):
        self.channel.close()


def wait_for(predicate, timeout=120, what="condition"):
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


class CampaignTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.addClassCleanup(cls.server.cleanup)  # also when the fixture below fails
        cls.fx = CampaignFixture(cls.server)
        cls.client = Client(cls.server.address, stream_timeout=300)
        cls.vertices = bunny_vertices()
        cls.chain = UrdfChain(os.path.join(UR5_DIR, UR5["urdf"]), UR5["base"], UR5["tip"])

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.fx.close()

    def assertCode(self, code, call, field=None):
        with self.assertRaises(grpc.RpcError) as ctx:
            result = call()
            if hasattr(result, "__iter__"):
                list(result)
        self.assertEqual(ctx.exception.code(), code, ctx.exception.details())
        if field:
            self.assertTrue(ctx.exception.details().startswith(field), ctx.exception.details())
        return ctx.exception

    def run_campaign(self, s):
        job = self.client.start_campaign(spec=s)
        self.assertEqual(job.state, job_pb2.JOB_STATE_QUEUED)
        responses = list(self.client.watch_job(job.job_id, timeout=300))
        return job, responses, self.client.get_job(job.job_id)

    def check_events(self, responses, final_state):
        self.assertFalse(responses[0].HasField("event"))
        events = [r.event for r in responses[1:]]
        # A watch may join after the first events, or after the end: it then starts from the job as it is.
        if not events:
            self.assertEqual(responses[0].job.state, final_state)
            return events
        first = events[0].sequence
        self.assertGreaterEqual(first, 1)
        self.assertEqual([e.sequence for e in events], list(range(first, first + len(events))))
        self.assertEqual(responses[-1].job.state, final_state)
        for r in responses[1:-1]:
            self.assertEqual(r.job.state, job_pb2.JOB_STATE_RUNNING)
        return events

    def test_two_viewpoints_three_rotations_of_the_bunny(self):
        job, responses, done = self.run_campaign(spec(self.fx.scene.scene_id, self.fx.mount, seed=7, name="bunny"))
        events = self.check_events(responses, job_pb2.JOB_STATE_SUCCEEDED)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED)
        self.assertEqual((done.steps_done, done.steps_total, done.progress), (6, 6, 1.0))
        self.assertEqual(done.campaign.name, "bunny")
        self.assertEqual(done.message, responses[-1].job.message)
        self.assertIn("6 scans captured", done.message)

        names = [a.name for a in done.artifacts]
        self.assertEqual(names, [f"scan-r{r:02}-v{v:02}.ply" for r in range(3) for v in range(2)] + ["campaign.json"])
        # What the watch saw: the artifacts in its first response, then one per artifact event.
        scan_events = [e for e in events if e.HasField("artifact") and e.artifact.name.endswith(".ply")]
        seen = list(responses[0].job.artifacts) + [e.artifact for e in events if e.HasField("artifact")]
        self.assertEqual(seen, list(done.artifacts))
        self.assertEqual([e.step for e in scan_events], [names.index(e.artifact.name) for e in scan_events])
        self.assertTrue(all(e.pose_reached for e in scan_events))
        progress = [r.job.progress for r in responses[1:]]
        self.assertEqual(progress, sorted(progress))

        multi_chunk = 0
        for artifact in done.artifacts[:6]:
            info = artifact.scan
            r, v = divmod(names.index(artifact.name), 2)
            self.assertEqual((info.rotation_index, info.viewpoint_index), (r, v))
            self.assertEqual(info.table_angle_deg, 120.0 * r)
            self.assertEqual(artifact.media_type, "model/ply")
            # Without encoder noise the arm lands where it was commanded.
            np.testing.assert_array_equal(matrix(info.sensor_pose), matrix(info.commanded_sensor_pose))
            self.assertEqual(list(info.achieved_joint_positions), list(info.commanded_joint_positions))
            pose = matrix(info.sensor_pose)
            position, target = np.array(VIEWPOINTS[v][0]), np.array(TARGET)
            np.testing.assert_allclose(pose[:3, 3], position, atol=1e-4)
            self.assertGreater(pose[:3, 2] @ (target - position) / np.linalg.norm(target - position), 1 - 1e-6)
            # The commanded joints put the UR5 there, by an independent forward kinematics.
            np.testing.assert_allclose(self.fx.base @ self.chain.fk(list(info.commanded_joint_positions)), pose,
                                       atol=1e-9)

            chunks = list(self.fx.jobs.ReadArtifact(job_pb2.ReadArtifactRequest(
                job_id=job.job_id, artifact_id=artifact.artifact_id), timeout=60))
            self.assertEqual(chunks[0].artifact, artifact)
            self.assertTrue(all(len(c.chunk) <= 1 << 20 for c in chunks))
            self.assertEqual(len(chunks), max(1, math.ceil(artifact.size_bytes / (1 << 20))))
            multi_chunk += len(chunks) > 1
            data = b"".join(c.chunk for c in chunks)
            self.assertEqual(len(data), artifact.size_bytes)
            points, fields = parse_ply(data)
            self.assertEqual(fields[:6], ("x", "y", "z", "nx", "ny", "nz"))
            self.assertEqual(len(points), info.points)
            self.assertGreater(len(points), 5000)
            lo, hi = world_box(self.vertices, info.table_angle_deg)
            self.assertTrue(np.all((points >= lo) & (points <= hi)), (points.min(0), points.max(0), lo, hi))
            # On the bunny's surface as the table turned it, and not as it would stand a quarter turn on.
            sample = points[::max(1, len(points) // 400)]
            self.assertLess(np.percentile(surface_distance(sample, self.vertices, info.table_angle_deg), 95), 0.004)
            self.assertGreater(np.median(surface_distance(sample, self.vertices, info.table_angle_deg + 90)), 0.01)
        self.assertGreater(multi_chunk, 0)

        summary_artifact, raw = self.client.read_artifact(job.job_id, done.artifacts[6].artifact_id)
        self.assertEqual(summary_artifact.media_type, "application/json")
        summary = json.loads(raw)
        self.assertEqual(summary["state"], "SUCCEEDED")
        self.assertEqual(summary["scans_captured"], 6)
        self.assertEqual([s["file"] for s in summary["steps"]], names[:6])
        self.assertTrue(all(s["reached"] and s["outcome"] == "captured" for s in summary["steps"]))
        np.testing.assert_allclose(np.reshape(summary["steps"][3]["sensor_pose"], (4, 4)),
                                   matrix(done.artifacts[3].scan.sensor_pose), atol=1e-12)
        self.assertEqual(len({s["seed"] for s in summary["steps"]}), 6)

        # A watch on a finished job returns the job and ends.
        again = list(self.fx.jobs.WatchJob(job_pb2.WatchJobRequest(job_id=job.job_id), timeout=30))
        self.assertEqual(len(again), 1)
        self.assertEqual(again[0].job, done)

    def test_encoder_noise_separates_commanded_and_true_pose(self):
        noisy_mount = self.fx.mount_ur5(self.fx.scene, encoder_sigma=[0.002])
        base = dict(viewpoints=VIEWPOINTS[:1], rotations=2, step=90.0, seed=11, sensor=camera(160, 120))
        _, _, noisy = self.run_campaign(spec(self.fx.scene.scene_id, noisy_mount, apply_encoder_noise=True, **base))
        _, _, quiet = self.run_campaign(spec(self.fx.scene.scene_id, noisy_mount, **base))
        self.assertEqual(noisy.state, job_pb2.JOB_STATE_SUCCEEDED)
        scans = noisy.artifacts[:2]
        for artifact in scans:
            info = artifact.scan
            offset = np.linalg.norm(matrix(info.sensor_pose)[:3, 3] - matrix(info.commanded_sensor_pose)[:3, 3])
            self.assertGreater(offset, 1e-5)
            self.assertLess(offset, 0.05)
            np.testing.assert_allclose(self.fx.base @ self.chain.fk(list(info.achieved_joint_positions)),
                                       matrix(info.sensor_pose), atol=1e-9)
        # Same commanded joints, a distinct noise draw per step.
        self.assertEqual(list(scans[0].scan.commanded_joint_positions), list(scans[1].scan.commanded_joint_positions))
        self.assertNotEqual(list(scans[0].scan.achieved_joint_positions),
                            list(scans[1].scan.achieved_joint_positions))
        for artifact in quiet.artifacts[:2]:
            np.testing.assert_array_equal(matrix(artifact.scan.sensor_pose), matrix(artifact.scan.commanded_sensor_pose))

    def test_unreachable_viewpoint_is_recorded_and_skipped(self):
        s = spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=[VIEWPOINTS[0], FAR_AWAY], rotations=1,
                 sensor=camera(160, 120))
        job, responses, done = self.run_campaign(s)
        events = self.check_events(responses, job_pb2.JOB_STATE_SUCCEEDED)
        self.assertEqual((done.steps_done, done.steps_total), (2, 2))
        self.assertEqual([a.name for a in done.artifacts], ["scan-r00-v00.ply", "campaign.json"])
        # The watch may join after the first events; those it saw carry the step and its verdict.
        for skipped in (e for e in events if "unreachable" in e.message):
            self.assertEqual(skipped.step, 1)
            self.assertFalse(skipped.pose_reached)
        summary = json.loads(self.client.read_artifact(job.job_id, done.artifacts[1].artifact_id)[1])
        match = re.fullmatch(r"viewpoint 1 at 0 deg: unreachable, misses by ([0-9.e+-]+) m",
                             summary["steps"][1]["message"])
        self.assertIsNotNone(match, summary["steps"][1]["message"])
        self.assertGreater(float(match.group(1)), 0.5)
        self.assertEqual([s["outcome"] for s in summary["steps"]], ["captured", "unreachable"])
        self.assertFalse(summary["steps"][1]["reached"])
        self.assertNotIn("file", summary["steps"][1])

    def test_reject_collisions_skips_poses_that_touch_the_scene(self):
        # A Panda beside the bunny with a 30 cm plate through its shoulder (z = 0.25): every
        # configuration puts panda_link1 through the plate, which the camera does not see.
        scene = self.fx.bunny_scene()
        self.add_box(scene.scene_id, "plate", (0.40, -0.15, 0.24), (0.70, 0.15, 0.26))
        panda = upload_panda(self.fx.robots, name="panda-collisions")
        mount = self.fx.robots.MountRobot(robot_pb2.MountRobotRequest(
            scene_id=scene.scene_id, robot_id=panda.robot_id, base_pose=to_pose(self.fx.base)), timeout=10).mount_id
        plain = spec(scene.scene_id, mount, viewpoints=VIEWPOINTS[:1], rotations=2, sensor=camera(160, 120))
        _, _, done = self.run_campaign(plain)
        self.assertEqual([a.name for a in done.artifacts], ["scan-r00-v00.ply", "scan-r01-v00.ply", "campaign.json"])

        checked = job_pb2.CampaignSpec()
        checked.CopyFrom(plain)
        checked.reject_collisions = True
        job, responses, done = self.run_campaign(checked)
        self.check_events(responses, job_pb2.JOB_STATE_SUCCEEDED)
        self.assertEqual((done.steps_done, done.steps_total), (2, 2))
        self.assertEqual([a.name for a in done.artifacts], ["campaign.json"])
        # The watch may have joined after the first events; the job's summary has every step.
        summary = json.loads(self.client.read_artifact(job.job_id, done.artifacts[0].artifact_id)[1])
        self.assertEqual([s["outcome"] for s in summary["steps"]], ["collision", "collision"])
        for step, angle in zip(summary["steps"], (0, 120)):
            self.assertRegex(step["message"],
                             rf"viewpoint 0 at {angle} deg: skipped, link 'panda_link\d' touches object .*plate")

    def add_box(self, scene_id, label, lo, hi):
        corners = [(x, y, z) for z in (lo[2], hi[2]) for y in (lo[1], hi[1]) for x in (lo[0], hi[0])]
        faces = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4), (2, 6, 7), (2, 7, 3),
                 (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
        lines = ["ply", "format ascii 1.0", "element vertex 8", "property float x", "property float y",
                 "property float z", "element face 12", "property list uchar int vertex_indices", "end_header"]
        lines += [f"{x} {y} {z}" for x, y, z in corners] + [f"3 {a} {b} {c}" for a, b, c in faces]
        data = ("\n".join(lines) + "\n").encode()

        def requests():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                name=label + ".ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data)))
            yield scene_pb2.UploadMeshRequest(chunk=data)
        mesh = self.fx.scenes.UploadMesh(requests(), timeout=60).mesh
        self.fx.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene_id, mesh_id=mesh.mesh_id, label=label))

    def test_up_fixes_the_turn_about_the_view_axis(self):
        up = (0.0, 1.0, 1.0)
        s = spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=VIEWPOINTS[:1], rotations=1,
                 sensor=camera(80, 60))
        s.viewpoints[0].up.CopyFrom(vec(up))
        _, _, done = self.run_campaign(s)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        # The same pose a ScanService scan placed by look_at with that up uses.
        eye, target = VIEWPOINTS[0]
        scanned = self.client.scan(self.fx.scene.scene_id, width=80, height=60, eye=eye, target=target, up=up)
        np.testing.assert_allclose(matrix(done.artifacts[0].scan.sensor_pose), matrix(scanned.header.sensor_pose),
                                   atol=1e-4)

    def test_without_up_the_image_is_upright(self):
        s = spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=VIEWPOINTS[1:], rotations=1,
                 sensor=camera(80, 60))
        _, _, done = self.run_campaign(s)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        pose = matrix(done.artifacts[0].scan.sensor_pose)
        # The documented default up, world +z: the image's x axis is level and its y axis (down) falls.
        self.assertAlmostEqual(pose[2, 0], 0.0, places=4)
        self.assertLess(pose[2, 1], 0.0)
        eye, target = VIEWPOINTS[1]
        scanned = self.client.scan(self.fx.scene.scene_id, width=80, height=60, eye=eye, target=target,
                                   up=(0.0, 0.0, 1.0))
        np.testing.assert_allclose(pose, matrix(scanned.header.sensor_pose), atol=1e-4)

    def test_cancel_mid_run(self):
        s = spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=VIEWPOINTS * 2, rotations=60, step=6.0)
        job = self.client.start_campaign(spec=s)
        self.assertEqual(job.steps_total, 240)
        seen = []
        for response in self.client.watch_job(job.job_id, timeout=300):
            seen.append(response)
            if response.event.HasField("artifact") and len([r for r in seen if r.event.HasField("artifact")]) == 2:
                cancelled = self.client.cancel_job(job.job_id)
                self.assertIn(cancelled.state, (job_pb2.JOB_STATE_RUNNING, job_pb2.JOB_STATE_CANCELLED))
        self.check_events(seen, job_pb2.JOB_STATE_CANCELLED)
        done = self.client.get_job(job.job_id)
        self.assertEqual(done.state, job_pb2.JOB_STATE_CANCELLED)
        self.assertLess(done.steps_done, 10)
        self.assertIn("cancelled", done.message)
        self.assertEqual(done.artifacts[-1].name, "campaign.json")
        for artifact in done.artifacts[:-1]:
            points, _ = parse_ply(self.client.read_artifact(job.job_id, artifact.artifact_id)[1])
            self.assertEqual(len(points), artifact.scan.points)
        with self.assertRaises(VscanError) as err:
            self.client.cancel_job(job.job_id)
        self.assertEqual(err.exception.code, C.FAILED_PRECONDITION)
        self.assertTrue(err.exception.message.startswith("job_id:"))

    def test_watchers_that_come_and_go_while_the_job_is_cancelled(self):
        s = spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=VIEWPOINTS, rotations=60, step=6.0,
                 sensor=camera(80, 60))
        job = self.client.start_campaign(spec=s)
        followers, errors = [[] for _ in range(2)], []

        def follow(seen):
            seen.extend(self.fx.jobs.WatchJob(job_pb2.WatchJobRequest(job_id=job.job_id), timeout=120))

        def come_and_go(k):
            try:
                for round_ in range(6):
                    stream = self.fx.jobs.WatchJob(job_pb2.WatchJobRequest(job_id=job.job_id), timeout=120)
                    for i, _ in enumerate(stream):
                        if i >= (k + round_) % 4:
                            break
                    stream.cancel()
            except grpc.RpcError as err:
                if err.code() != C.CANCELLED:
                    errors.append(err)
        threads = [threading.Thread(target=follow, args=(seen,)) for seen in followers]
        threads += [threading.Thread(target=come_and_go, args=(k,)) for k in range(6)]
        for t in threads:
            t.start()
        wait_for(lambda: len(self.client.get_job(job.job_id).artifacts) >= 3, what="three scans")
        self.client.cancel_job(job.job_id)
        for t in threads:
            t.join()
        self.assertEqual(errors, [])
        for seen in followers:
            self.check_events(seen, job_pb2.JOB_STATE_CANCELLED)
        self.assertEqual(self.client.get_job(job.job_id).state, job_pb2.JOB_STATE_CANCELLED)

    def test_bad_specs_name_their_field_and_create_no_job(self):
        scene, mount, jobs = self.fx.scene.scene_id, self.fx.mount, self.fx.jobs
        before = len(self.client.list_jobs())
        other = self.fx.bunny_scene(table=False)
        other_mount = self.fx.mount_ur5(other)

        def start(s):
            return jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=s), timeout=30)

        def edited(**changes):
            s = spec(scene, mount)
            for key, value in changes.items():
                setattr(s, key, value)
            return s

        nan = float("nan")
        self.assertCode(C.INVALID_ARGUMENT, lambda: jobs.StartCampaign(job_pb2.StartCampaignRequest()), "spec:")
        self.assertCode(C.NOT_FOUND, lambda: start(spec("scn_0000000000000000", mount)), "spec.scene_id")
        self.assertCode(C.NOT_FOUND, lambda: start(spec(scene, "mnt_0000000000000000")), "spec.mount_id")
        self.assertCode(C.FAILED_PRECONDITION, lambda: start(spec(scene, other_mount)), "spec.mount_id")
        self.assertCode(C.FAILED_PRECONDITION, lambda: start(spec(other.scene_id, other_mount)), "spec.rotations")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(spec(scene, mount, viewpoints=[])), "spec.viewpoints")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(spec(scene, mount, viewpoints=[
            VIEWPOINTS[0], (TARGET, TARGET)])), "spec.viewpoints[1].target")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(spec(scene, mount, viewpoints=[
            ((nan, 0, 0.3), TARGET)])), "spec.viewpoints[0].position")
        missing_target = spec(scene, mount)
        missing_target.viewpoints[1].ClearField("target")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(missing_target), "spec.viewpoints[1].target")
        parallel_up = spec(scene, mount)
        parallel_up.viewpoints[0].up.CopyFrom(vec(np.subtract(TARGET, VIEWPOINTS[0][0])))
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(parallel_up), "spec.viewpoints[0].up")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(spec(scene, mount, rotations=5000, step=1.0)),
                        "spec.rotations")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(spec(scene, mount, viewpoints=VIEWPOINTS * 500,
                                                               rotations=20, step=1.0)), "spec.rotations")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(spec(scene, mount, step=0.0)), "spec.rotation_step_deg")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(edited(start_angle_deg=nan)), "spec.start_angle_deg")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(spec(scene, mount, sensor=pinhole(0, 120))),
                        "spec.sensor.pinhole.width")
        self.assertCode(C.NOT_FOUND, lambda: start(spec(scene, mount, sensor=sensor_pb2.SensorSpec(preset="nope"))),
                        "spec.sensor.preset")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(edited(backend=42)), "spec.backend")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(edited(frame=42)), "spec.frame")
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(spec(scene, mount, noise=sensor_pb2.NoiseSpec(
            sigma_a=-1.0))), "spec.noise")
        bad_voxel = edited(align=True)
        bad_voxel.alignment.voxel_size = -1e-3
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(bad_voxel), "spec.alignment.voxel_size")
        bad_tau = edited(evaluate=True)
        bad_tau.evaluation.tau = nan
        self.assertCode(C.INVALID_ARGUMENT, lambda: start(bad_tau), "spec.evaluation.tau")
        # TSDF fuses range images: it needs each point's pixel, which the default fields do not keep.
        tsdf = edited(reconstruct=True)
        tsdf.reconstruction.method = 1
        self.assertCode(C.FAILED_PRECONDITION, lambda: start(tsdf), "spec.reconstruction.method")
        self.assertEqual(len(self.client.list_jobs()), before)

        self.assertCode(C.INVALID_ARGUMENT, lambda: jobs.StartBinFill(job_pb2.StartBinFillRequest()), "spec")
        self.assertCode(C.INVALID_ARGUMENT, lambda: jobs.GetJob(job_pb2.GetJobRequest()), "job_id")
        self.assertCode(C.NOT_FOUND, lambda: jobs.GetJob(job_pb2.GetJobRequest(job_id="job_0000000000000000")),
                        "job_id")
        self.assertCode(C.NOT_FOUND, lambda: jobs.WatchJob(job_pb2.WatchJobRequest(job_id="job_0000000000000000")),
                        "job_id")
        self.assertCode(C.NOT_FOUND, lambda: jobs.CancelJob(job_pb2.CancelJobRequest(job_id="job_0000000000000000")),
                        "job_id")
        self.assertCode(C.INVALID_ARGUMENT, lambda: jobs.ListJobs(job_pb2.ListJobsRequest(page_size=-1)), "page_size")

    def test_list_jobs_pages_and_reading_unknown_artifacts(self):
        for _ in range(3):
            self.client.start_campaign(spec=spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=VIEWPOINTS[:1],
                                                 rotations=1, sensor=camera(80, 60)))
        ids, token = [], ""
        while True:
            page = self.fx.jobs.ListJobs(job_pb2.ListJobsRequest(page_size=1, page_token=token), timeout=10)
            self.assertLessEqual(len(page.jobs), 1)
            ids += [j.job_id for j in page.jobs]
            if not page.next_page_token:
                break
            token = page.next_page_token
        self.assertGreaterEqual(len(ids), 3)
        self.assertEqual(ids, sorted(set(ids)))
        for job_id in ids:
            self.client.wait_job(job_id, timeout=120)
        self.assertCode(C.NOT_FOUND, lambda: self.fx.jobs.ReadArtifact(job_pb2.ReadArtifactRequest(
            job_id=ids[0], artifact_id="art_0000000000000000"), timeout=10), "artifact_id")


class CampaignListBoundsTest(unittest.TestCase):
    def test_list_pages_fit_a_client_with_default_message_limits(self):
        # Each job carries its 1000-viewpoint spec (some 60 kB): 80 of them are more than the 4 MiB a
        # gRPC client accepts by default, which a page of 100 must not exceed.
        server = Server().start()
        try:
            fx = CampaignFixture(server)
            views = [((0.25, 0.0001 * (i + 1), 0.3), (0.001, 0.002, 0.11)) for i in range(1000)]
            big = spec(fx.scene.scene_id, fx.mount, viewpoints=views, rotations=1, sensor=camera(8, 6))
            self.assertGreater(80 * big.ByteSize(), 4 << 20)
            started = []
            for _ in range(80):
                job = fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=big), timeout=30).job
                fx.jobs.CancelJob(job_pb2.CancelJobRequest(job_id=job.job_id), timeout=30)
                started.append(job.job_id)
            fx.close()
            with Client(server.address) as client:
                for job_id in started:
                    self.assertEqual(client.wait_job(job_id, timeout=120).state, job_pb2.JOB_STATE_CANCELLED)
            with grpc.insecure_channel(server.address) as channel:  # gRPC's default limits
                jobs = job_pb2_grpc.JobServiceStub(channel)
                ids, token, pages = [], "", 0
                while True:
                    page = jobs.ListJobs(job_pb2.ListJobsRequest(page_token=token), timeout=30)
                    pages += 1
                    self.assertLessEqual(page.ByteSize(), 4 << 20)
                    self.assertTrue(all(len(j.campaign.viewpoints) == 1000 for j in page.jobs))
                    ids += [j.job_id for j in page.jobs]
                    if not page.next_page_token:
                        break
                    token = page.next_page_token
            self.assertEqual(ids, sorted(started))
            self.assertGreater(pages, 1)
        finally:
            server.cleanup()


class CampaignQueueTest(unittest.TestCase):
    def test_concurrent_starts_never_overfill_the_queue(self):
        server = Server(extra_args=["--max-queued-jobs", "2"]).start()
        try:
            fx = CampaignFixture(server)
            running = fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(
                spec=spec(fx.scene.scene_id, fx.mount, **CampaignRestartTest.LONG)), timeout=30).job
            wait_for(lambda: fx.jobs.GetJob(job_pb2.GetJobRequest(job_id=running.job_id), timeout=10).job.state ==
                     job_pb2.JOB_STATE_RUNNING, what="the first job to run")
            small = spec(fx.scene.scene_id, fx.mount, viewpoints=VIEWPOINTS[:1], rotations=1, sensor=camera(8, 6))
            results = []

            def start():
                try:
                    results.append(fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=small), timeout=30).job)
                except grpc.RpcError as err:
                    results.append(err)
            threads = [threading.Thread(target=start) for _ in range(16)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            accepted = [r.job_id for r in results if isinstance(r, job_pb2.Job)]
            refused = [r for r in results if isinstance(r, grpc.RpcError)]
            self.assertEqual(len(accepted), 2, [e.details() for e in refused])
            self.assertEqual({e.code() for e in refused}, {C.RESOURCE_EXHAUSTED})
            with Client(server.address) as client:
                # A refused start leaves no job behind.
                self.assertEqual(sorted(j.job_id for j in client.list_jobs()), sorted([running.job_id] + accepted))
                client.cancel_job(running.job_id)
                for job_id in accepted:
                    self.assertEqual(client.wait_job(job_id, timeout=120).state, job_pb2.JOB_STATE_SUCCEEDED)
            fx.close()
        finally:
            server.cleanup()


class CampaignStorageFailureTest(unittest.TestCase):
    def test_a_scan_that_cannot_be_stored_fails_the_job_and_keeps_the_server(self):
        server = Server().start()
        blobs = os.path.join(server.data_dir, "store", "blobs")
        try:
            fx = CampaignFixture(server)
            s = spec(fx.scene.scene_id, fx.mount, **CampaignRestartTest.LONG)
            job = fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=s), timeout=30).job

            def scans_done():
                got = fx.jobs.GetJob(job_pb2.GetJobRequest(job_id=job.job_id), timeout=10).job
                return got if len(got.artifacts) >= 2 else None
            wait_for(scans_done, what="two scans")
            # The blob store's directory turns into a file: every later blob write fails.
            os.rename(blobs, blobs + ".away")
            with open(blobs, "w") as f:
                f.write("not a directory\n")
            with Client(server.address) as client:
                done = client.wait_job(job.job_id, timeout=120)
                self.assertEqual(done.state, job_pb2.JOB_STATE_FAILED)
                self.assertRegex(done.message, r"^cannot store scan-r\d\d-v\d\d\.ply: .*blobs")
                self.assertGreaterEqual(len(done.artifacts), 2)
                self.assertLess(done.steps_done, done.steps_total)
                self.assertTrue(all(a.name.endswith(".ply") for a in done.artifacts))
                os.remove(blobs)
                os.rename(blobs + ".away", blobs)
                # What was stored before stays whole, and the server still runs campaigns.
                for artifact in done.artifacts:
                    points, _ = parse_ply(client.read_artifact(job.job_id, artifact.artifact_id)[1])
                    self.assertEqual(len(points), artifact.scan.points)
                small = spec(fx.scene.scene_id, fx.mount, viewpoints=VIEWPOINTS[:1], rotations=1, sensor=camera(80, 60))
                again = client.wait_job(client.start_campaign(spec=small).job_id, timeout=120)
                self.assertEqual(again.state, job_pb2.JOB_STATE_SUCCEEDED, again.message)
            fx.close()
        finally:
            server.cleanup()


class CampaignRestartTest(unittest.TestCase):
    LONG = dict(viewpoints=VIEWPOINTS * 2, rotations=100, step=3.6)

    def start_long(self, server):
        fx = CampaignFixture(server)
        job = fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=spec(fx.scene.scene_id, fx.mount, **self.LONG)),
                                    timeout=30).job

        def scans_done():
            got = fx.jobs.GetJob(job_pb2.GetJobRequest(job_id=job.job_id), timeout=10).job
            return got if len(got.artifacts) >= 2 else None
        running = wait_for(scans_done, what="two scans")
        fx.close()
        return job.job_id, running

    def test_kill9_leaves_interrupted_job_with_readable_scans(self):
        server = Server().start()
        try:
            job_id, _ = self.start_long(server)
            server.kill9()
            # A scan the killed server was encoding is left in its scratch directory.
            scratch = os.path.join(server.data_dir, "store", "tmp", job_id)
            os.makedirs(scratch, exist_ok=True)
            with open(os.path.join(scratch, "scan-r00-v01.ply"), "wb") as f:
                f.write(b"ply\n")
            server.start()
            self.assertFalse(os.path.exists(scratch))
            with Client(server.address) as client:
                job = client.get_job(job_id)
                self.assertEqual(job.state, job_pb2.JOB_STATE_INTERRUPTED)
                self.assertEqual(job.message, "server stopped while the job ran")
                self.assertGreaterEqual(len(job.artifacts), 2)
                self.assertEqual(job.steps_done, len(job.artifacts))
                self.assertLess(job.steps_done, job.steps_total)
                for artifact in job.artifacts:
                    _, data = client.read_artifact(job_id, artifact.artifact_id)
                    points, _ = parse_ply(data)
                    self.assertEqual(len(points), artifact.scan.points)
                with self.assertRaises(VscanError) as err:
                    client.cancel_job(job_id)
                self.assertEqual(err.exception.code, C.FAILED_PRECONDITION)
        finally:
            server.cleanup()

    def test_sigterm_interrupts_running_jobs_quickly(self):
        server = Server(extra_args=["--grace-seconds", "20"]).start()
        try:
            job_id, _ = self.start_long(server)
            start = time.time()
            self.assertEqual(server.stop(timeout=30), 0)
            self.assertLess(time.time() - start, 10)
            server.start()
            with Client(server.address) as client:
                job = client.get_job(job_id)
                self.assertEqual(job.state, job_pb2.JOB_STATE_INTERRUPTED)
                self.assertTrue(job.message.startswith("server stopped while the job ran after"), job.message)
                self.assertEqual(job.artifacts[-1].name, "campaign.json")
                summary = json.loads(client.read_artifact(job_id, job.artifacts[-1].artifact_id)[1])
                self.assertEqual(summary["state"], "INTERRUPTED")
                self.assertEqual(len(summary["steps"]), job.steps_done)
        finally:
            server.cleanup()


if __name__ == "__main__":
    unittest.main()
