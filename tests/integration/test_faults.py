"""What survives kill -9 in the middle of uploads, scans and campaigns, what `vscan campaign resume`
makes of an interrupted campaign, and what a full disk does to uploads and jobs.

A bin fill killed mid-way is in test_bins.py; a dataset job killed and resumed in test_dataset_job.py.
"""

import hashlib
import json
import os
import shutil
import subprocess
import tempfile
import threading
import time
import unittest

import grpc
import numpy as np

from harness import BUNNY, VSCAN, Server, common_pb2, icosphere_ply, look_at, pinhole, scan_pb2, scan_points, scene_pb2
from test_campaign_service import VIEWPOINTS, CampaignFixture, camera, parse_ply, spec, wait_for
from test_robots import PANDA, bundle_requests, panda_files, read, upload_ur5
from vscan.v1 import job_pb2, robot_pb2, robot_pb2_grpc, scan_pb2_grpc, scene_pb2_grpc

from vscan import Client, VscanError

C = grpc.StatusCode


def store_files(root):
    """Every file under root (hidden temp files too), relative to it."""
    found = set()
    for directory, _, names in os.walk(root):
        for name in names:
            found.add(os.path.relpath(os.path.join(directory, name), root))
    return found


def blob_files(store):
    return store_files(os.path.join(store, "blobs"))


def mesh_requests(data, name, chunk, sent=None, hold=None, stop_after=None):
    """Header and chunks of a mesh upload; with hold, stops after stop_after chunks until hold is set."""
    yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
        name=name, unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data)))
    for count, offset in enumerate(range(0, len(data), chunk)):
        if stop_after is not None and count == stop_after:
            sent.set()
            hold.wait()
            return
        yield scene_pb2.UploadMeshRequest(chunk=data[offset:offset + chunk])


def held_stream(requests, count, sent, hold):
    """The first count messages of requests, then waits for hold."""
    for i, message in enumerate(requests):
        if i == count:
            sent.set()
            hold.wait()
            return
        yield message


def kill_mid_stream(test, server, call, requests_of):
    """Starts a client-streaming call, lets part of it reach the server, kills the server."""
    sent, hold = threading.Event(), threading.Event()
    future = call.future(requests_of(sent, hold), timeout=60)
    test.assertTrue(sent.wait(30), "the client never sent its first chunks")
    time.sleep(0.5)  # the chunks reach the server
    server.kill9()
    hold.set()
    with test.assertRaises(grpc.RpcError):
        future.result()


class KillDuringUploadTest(unittest.TestCase):
    def test_mesh_upload_killed_leaves_nothing_and_earlier_meshes_whole(self):
        server = Server().start()
        store = os.path.join(server.data_dir, "store")
        try:
            with server.channel() as channel:
                scenes = scene_pb2_grpc.SceneServiceStub(channel)
                bunny = scenes.UploadMesh(mesh_requests(read(BUNNY), "bunny.ply", 1 << 20), timeout=60).mesh
                ball_data = icosphere_ply(0.05, (0, 0, 0.05), subdivisions=3)
                ball = scenes.UploadMesh(mesh_requests(ball_data, "ball.ply", 1 << 20), timeout=60).mesh
                blobs_before = blob_files(store)
                big = icosphere_ply(0.08, (0, 0, 0.08), subdivisions=6)
                kill_mid_stream(self, server, scenes.UploadMesh,
                                lambda sent, hold: mesh_requests(big, "big.ply", 64 << 10, sent, hold, stop_after=8))
            server.start()
            with server.channel() as channel:
                scenes = scene_pb2_grpc.SceneServiceStub(channel)
                listed = scenes.ListMeshes(scene_pb2.ListMeshesRequest(), timeout=10).meshes
                self.assertEqual(sorted(m.mesh_id for m in listed), sorted([bunny.mesh_id, ball.mesh_id]))
                self.assertEqual(blob_files(store), blobs_before)
                for mesh in (bunny, ball):
                    self.assertEqual(scenes.GetMesh(scene_pb2.GetMeshRequest(mesh_id=mesh.mesh_id)).mesh, mesh)
                    with open(os.path.join(store, "blobs", mesh.sha256[:2], mesh.sha256), "rb") as f:
                        self.assertEqual(hashlib.sha256(f.read()).hexdigest(), mesh.sha256)
                scene = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="after")).scene
                scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=bunny.mesh_id))
                self.assertGreater(len(scan_points(channel, scene.scene_id)), 1000)
                again = scenes.UploadMesh(mesh_requests(big, "big.ply", 64 << 10), timeout=60).mesh
                self.assertEqual(again.vertex_count, 40962)
                listed = scenes.ListMeshes(scene_pb2.ListMeshesRequest(), timeout=10).meshes
                self.assertIn(again.mesh_id, [m.mesh_id for m in listed])
        finally:
            server.cleanup()

    def test_robot_upload_killed_leaves_nothing_and_earlier_robots_whole(self):
        server = Server().start()
        store = os.path.join(server.data_dir, "store")
        try:
            panda = panda_files()
            panda_header = robot_pb2.RobotBundleHeader(name="panda", urdf_path=PANDA["urdf"], base_link=PANDA["base"],
                                                       tip_link=PANDA["tip"])
            with server.channel() as channel:
                robots = robot_pb2_grpc.RobotServiceStub(channel)
                ur5 = upload_ur5(robots)
                fk = robots.ForwardKinematics(robot_pb2.ForwardKinematicsRequest(
                    robot_id=ur5.robot_id, joint_positions=[0.1, -0.5, 0.4, 0.0, 0.3, 0.0]), timeout=10)
                blobs_before = blob_files(store)
                pieces = sum(max(1, -(-len(data) // 4096)) for _, data in panda)
                self.assertGreater(pieces, 8)
                kill_mid_stream(self, server, robots.UploadRobot,
                                lambda sent, hold: held_stream(bundle_requests(panda_header, panda), pieces // 2,
                                                               sent, hold))
            server.start()
            with server.channel() as channel:
                robots = robot_pb2_grpc.RobotServiceStub(channel)
                listed = robots.ListRobots(robot_pb2.ListRobotsRequest(), timeout=10).robots
                self.assertEqual([r.robot_id for r in listed], [ur5.robot_id])
                self.assertEqual(blob_files(store), blobs_before)
                self.assertEqual(robots.GetRobot(robot_pb2.GetRobotRequest(robot_id=ur5.robot_id)).robot, ur5)
                with open(os.path.join(store, "blobs", ur5.bundle_sha256[:2], ur5.bundle_sha256), "rb") as f:
                    self.assertEqual(hashlib.sha256(f.read()).hexdigest(), ur5.bundle_sha256)
                fk_after = robots.ForwardKinematics(robot_pb2.ForwardKinematicsRequest(
                    robot_id=ur5.robot_id, joint_positions=[0.1, -0.5, 0.4, 0.0, 0.3, 0.0]), timeout=10)
                self.assertEqual(fk_after, fk)
                again = robots.UploadRobot(bundle_requests(panda_header, panda), timeout=60).robot
                self.assertEqual(len(again.joints), 7)
        finally:
            server.cleanup()


class KillDuringScanTest(unittest.TestCase):
    def test_scene_survives_a_kill_mid_scan_and_scans_the_same(self):
        server = Server().start()
        try:
            with server.channel() as channel:
                scenes = scene_pb2_grpc.SceneServiceStub(channel)
                mesh = scenes.UploadMesh(mesh_requests(read(BUNNY), "bunny.ply", 1 << 20), timeout=60).mesh
                scene = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="scanned")).scene
                scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id,
                                                            label="bunny"))
                before = scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene
                points_before = scan_points(channel, scene.scene_id)
                large = scan_pb2.ScanRequest(scene_id=scene.scene_id, sensor=pinhole(4000, 3000, 40.0),
                                             pose=look_at((0.0, -0.6, 0.1), (0.0, 0.0, 0.1)))
                stream = scan_pb2_grpc.ScanServiceStub(channel).Scan(large, timeout=60)
                chunks = 0
                for response in stream:
                    chunks += response.WhichOneof("part") == "chunk"
                    if chunks == 2:
                        break
                self.assertEqual(chunks, 2)
                server.kill9()
                with self.assertRaises(grpc.RpcError):
                    list(stream)
            server.start()
            with server.channel() as channel:
                scenes = scene_pb2_grpc.SceneServiceStub(channel)
                self.assertEqual(scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene, before)
                self.assertEqual(scenes.GetMesh(scene_pb2.GetMeshRequest(mesh_id=mesh.mesh_id)).mesh, mesh)
                np.testing.assert_array_equal(scan_points(channel, scene.scene_id), points_before)
        finally:
            server.cleanup()


def scan_artifacts(job):
    return [a for a in job.artifacts if a.HasField("scan")]


def kill_after_two_scans(server, fx, job_id):
    """Waits until the campaign has stored two scans, then kills the server (-9)."""
    def two_scans():
        got = fx.jobs.GetJob(job_pb2.GetJobRequest(job_id=job_id), timeout=10).job
        return got if len(scan_artifacts(got)) >= 2 else None
    wait_for(two_scans, what="two scans")
    fx.close()
    server.kill9()


class KillDuringCampaignTest(unittest.TestCase):
    """Eight table angles of two viewpoints with encoder noise: killed after two scans, resumed by the CLI."""

    STEPS = 16

    def campaign(self, fx):
        return spec(fx.scene.scene_id, fx.mount, viewpoints=VIEWPOINTS, rotations=8, step=45.0,
                    sensor=camera(160, 120), seed=11, apply_encoder_noise=True, name="killed")

    def vscan(self, server, *args):
        return subprocess.run([VSCAN, "--server", server.address, *args], capture_output=True, text=True, timeout=300)

    def test_killed_campaign_resumes_to_the_scans_of_an_uninterrupted_run(self):
        server = Server().start()
        out = tempfile.mkdtemp(prefix="vscan-resume-")
        try:
            fx = CampaignFixture(server)
            job_id = fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=self.campaign(fx)), timeout=30).job.job_id
            kill_after_two_scans(server, fx, job_id)
            server.start()
            with Client(server.address) as client:
                interrupted = client.get_job(job_id)
                self.assertEqual(interrupted.state, job_pb2.JOB_STATE_INTERRUPTED)
                self.assertLess(interrupted.steps_done, interrupted.steps_total)
                kept = {a.name: a.artifact_id for a in scan_artifacts(interrupted)}
                self.assertGreaterEqual(len(kept), 2)

            resumed = self.vscan(server, "campaign", "resume", job_id, "--watch", "-o", out)
            self.assertEqual(resumed.returncode, 0, resumed.stdout + resumed.stderr + server.log())
            self.assertIn(f"resumed campaign job {job_id} ({len(kept)} scans stored, {self.STEPS} steps)", resumed.stderr
                          + resumed.stdout)

            with Client(server.address) as client:
                job = client.get_job(job_id)
                self.assertEqual(job.state, job_pb2.JOB_STATE_SUCCEEDED, job.message)
                self.assertEqual(job.steps_done, job.steps_total)
                scans = scan_artifacts(job)
                names = [a.name for a in scans]
                self.assertEqual(len(names), len(set(names)), "a step was captured twice")
                self.assertEqual(len(names), self.STEPS)
                # The scans stored before the kill are the same artifacts, not captured again.
                for name, artifact_id in kept.items():
                    self.assertEqual({a.name: a.artifact_id for a in scans}[name], artifact_id)
                self.assertEqual([a.name for a in job.artifacts].count("campaign.json"), 1)
                self.assertEqual(job.artifacts[-1].name, "campaign.json")
                summary = json.loads(client.read_artifact(job_id, job.artifacts[-1].artifact_id)[1])
                self.assertEqual(summary["state"], "SUCCEEDED")
                self.assertEqual([s["step"] for s in summary["steps"]], list(range(self.STEPS)))
                self.assertTrue(all(s["outcome"] == "captured" for s in summary["steps"]))
                resumed_bytes = {}
                for artifact in scans:
                    _, data = client.read_artifact(job_id, artifact.artifact_id)
                    points, _ = parse_ply(data)
                    self.assertEqual(len(points), artifact.scan.points)
                    with open(os.path.join(out, artifact.name), "rb") as f:
                        self.assertEqual(f.read(), data)
                    resumed_bytes[artifact.name] = data

                # The same campaign run without interruption: every scan byte for byte the same,
                # those captured before the kill and those captured by the resumed run.
                again = client.get_job(job_id).campaign
                whole = client.wait_job(client.start_campaign(spec=again).job_id, timeout=120)
                self.assertEqual(whole.state, job_pb2.JOB_STATE_SUCCEEDED, whole.message)
                for artifact in scan_artifacts(whole):
                    _, data = client.read_artifact(whole.job_id, artifact.artifact_id)
                    self.assertEqual(data, resumed_bytes[artifact.name], artifact.name)
                self.assertEqual(sorted(resumed_bytes), sorted(a.name for a in scan_artifacts(whole)))

                # Only ended campaigns that did not succeed resume.
                with self.assertRaises(VscanError) as err:
                    client.resume_job(job_id)
                self.assertEqual(err.exception.code, C.FAILED_PRECONDITION)
                self.assertIn(job_id, str(err.exception))
                with self.assertRaises(VscanError) as err:
                    client.resume_job("job_0123456789abcdef")
                self.assertEqual(err.exception.code, C.NOT_FOUND)
            refused = self.vscan(server, "campaign", "resume", job_id)
            self.assertEqual(refused.returncode, 3, refused.stderr)
            self.assertIn("succeeded", refused.stderr)
        finally:
            shutil.rmtree(out, ignore_errors=True)
            server.cleanup()

    def test_cancelled_campaign_resumes_with_later_event_numbers_within_the_queue_bound(self):
        server = Server(extra_args=["--max-queued-jobs", "1"]).start()
        try:
            fx = CampaignFixture(server)
            long = spec(fx.scene.scene_id, fx.mount, viewpoints=VIEWPOINTS * 2, rotations=100, step=3.6,
                        sensor=camera(160, 120), name="long")
            with Client(server.address) as client:
                first = client.start_campaign(spec=long)
                sequences = []

                def follow():
                    for message in client.watch_job(first.job_id, timeout=120):
                        if message.HasField("event"):
                            sequences.append(message.event.sequence)
                follower = threading.Thread(target=follow)
                follower.start()
                wait_for(lambda: len(scan_artifacts(client.get_job(first.job_id))) >= 2, what="two scans")
                with self.assertRaises(VscanError) as err:
                    client.resume_job(first.job_id)
                self.assertEqual(err.exception.code, C.FAILED_PRECONDITION)
                self.assertIn("has not ended", str(err.exception))
                client.cancel_job(first.job_id)
                follower.join(60)
                cancelled = client.get_job(first.job_id)
                self.assertEqual(cancelled.state, job_pb2.JOB_STATE_CANCELLED)
                stored = len(scan_artifacts(cancelled))

                # While the queue is full a resume is refused like a start.
                running = client.start_campaign(spec=long)
                wait_for(lambda: client.get_job(running.job_id).state == job_pb2.JOB_STATE_RUNNING, what="a start")
                queued = client.start_campaign(spec=long)
                with self.assertRaises(VscanError) as err:
                    client.resume_job(first.job_id)
                self.assertEqual(err.exception.code, C.RESOURCE_EXHAUSTED)
                self.assertEqual(client.get_job(first.job_id).state, job_pb2.JOB_STATE_CANCELLED)
                client.cancel_job(queued.job_id)
                client.cancel_job(running.job_id)
                wait_for(lambda: client.get_job(running.job_id).state == job_pb2.JOB_STATE_CANCELLED, what="cancel")

                reopened = client.resume_job(first.job_id)
                self.assertEqual(reopened.state, job_pb2.JOB_STATE_QUEUED)
                self.assertEqual(len(scan_artifacts(reopened)), stored)
                self.assertNotIn("campaign.json", [a.name for a in reopened.artifacts])
                later = []
                for message in client.watch_job(first.job_id, timeout=120):
                    if message.HasField("event"):
                        later.append(message.event.sequence)
                        if len(later) == 3:
                            break
                self.assertGreater(later[0], max(sequences))
                self.assertEqual(later, sorted(later))
                client.cancel_job(first.job_id)
                done = client.wait_job(first.job_id, timeout=60)
                self.assertEqual(done.state, job_pb2.JOB_STATE_CANCELLED)
                names = [a.name for a in scan_artifacts(done)]
                self.assertEqual(len(names), len(set(names)))
                self.assertGreaterEqual(len(names), stored)
            fx.close()
        finally:
            server.cleanup()


class ResumeAligningCampaignTest(unittest.TestCase):
    """A campaign that aligns its scans as it captures them, killed and resumed: the resumed run
    aligns the stored scans again and its model equals that of an uninterrupted run."""

    def test_resumed_campaign_models_every_scan_as_an_uninterrupted_run(self):
        server = Server().start()
        try:
            fx = CampaignFixture(server)
            campaign = spec(fx.scene.scene_id, fx.mount, viewpoints=VIEWPOINTS, rotations=8, step=45.0,
                            sensor=camera(160, 120), seed=5, name="aligned", align=True)
            job_id = fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=campaign), timeout=30).job.job_id
            kill_after_two_scans(server, fx, job_id)
            server.start()
            with Client(server.address) as client:
                interrupted = client.get_job(job_id)
                self.assertEqual(interrupted.state, job_pb2.JOB_STATE_INTERRUPTED)
                self.assertLess(len(scan_artifacts(interrupted)), 16)
                client.resume_job(job_id)
                job = client.wait_job(job_id, timeout=180)
                self.assertEqual(job.state, job_pb2.JOB_STATE_SUCCEEDED, job.message)
                self.assertEqual([a.name for a in job.artifacts].count("model.json"), 1)
                resumed = client.model_report(job_id)["alignment"]
                whole_job = client.wait_job(client.start_campaign(spec=campaign).job_id, timeout=180)
                self.assertEqual(whole_job.state, job_pb2.JOB_STATE_SUCCEEDED, whole_job.message)
                whole = client.model_report(whole_job.job_id)["alignment"]
            self.assertEqual(resumed["aligned"], 16)
            self.assertEqual(resumed["unaligned"], 0)
            self.assertEqual([scan["name"] for scan in resumed["scans"]], [scan["name"] for scan in whole["scans"]])
            for mine, theirs in zip(resumed["scans"], whole["scans"]):
                np.testing.assert_allclose(mine["pose"], theirs["pose"], atol=1e-9, err_msg=mine["name"])
        finally:
            server.cleanup()


class TmpfsStore:
    """A small tmpfs as the server's data directory, kept across restarts of the server.

    Unprivileged: a user and mount namespace (unshare -rm) holds the mount, and vscand enters it
    (nsenter); the files are read through /proc/<holder>/root. As root without namespaces: a real
    mount, unmounted at the end."""

    def __init__(self, data_dir, size_mib):
        self.store = os.path.join(data_dir, "store")
        os.makedirs(self.store)
        ready = os.path.join(data_dir, "mounted")
        self.holder = subprocess.Popen(
            ["unshare", "-rm", "sh", "-c",
             f"mount -t tmpfs -o size={size_mib}m tmpfs '{self.store}' && touch '{ready}' && exec sleep 100000"],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        deadline = time.time() + 10
        while not os.path.exists(ready) and self.holder.poll() is None and time.time() < deadline:
            time.sleep(0.02)
        if os.path.exists(ready):
            self.wrapper = ["nsenter", "-t", str(self.holder.pid), "-U", "-m", "--preserve-credentials"]
            self.view = f"/proc/{self.holder.pid}/root{self.store}"
            self.mounted = False
            return
        refusal = self.holder.stderr.read().decode(errors="replace") if self.holder.poll() is not None else "timeout"
        self.holder = None
        if os.geteuid() != 0:
            raise RuntimeError("a tmpfs for the full-disk test needs `unshare -rm` (refused here: " + refusal +
                               ") or root for a plain `mount -t tmpfs`")
        subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size_mib}m", "tmpfs", self.store], check=True)
        self.wrapper, self.view, self.mounted = [], self.store, True

    def close(self):
        if self.holder:
            self.holder.kill()
            self.holder.wait()
        if self.mounted:
            subprocess.run(["umount", self.store], check=False)


class FullDiskTest(unittest.TestCase):
    SIZE_MIB = 16

    def blob_sha256(self, view, sha):
        with open(os.path.join(view, "blobs", sha[:2], sha), "rb") as f:
            return hashlib.sha256(f.read()).hexdigest()

    def check_store(self, server, disk, meshes):
        """Every acknowledged mesh listed and byte for byte whole; no temp file; a scene scans."""
        leftovers = [f for f in store_files(os.path.join(disk.view, "blobs")) if ".tmp" in f]
        self.assertEqual(leftovers, [])
        with server.channel() as channel:
            scenes = scene_pb2_grpc.SceneServiceStub(channel)
            listed = {m.mesh_id: m for m in scenes.ListMeshes(scene_pb2.ListMeshesRequest(), timeout=10).meshes}
            for mesh in meshes:
                self.assertEqual(listed.get(mesh.mesh_id), mesh)
                self.assertEqual(self.blob_sha256(disk.view, mesh.sha256), mesh.sha256)
            # Every catalogue row names a blob that is there.
            for mesh in listed.values():
                self.assertTrue(os.path.exists(os.path.join(disk.view, "blobs", mesh.sha256[:2], mesh.sha256)))
            scene = scenes.ListScenes(scene_pb2.ListScenesRequest(), timeout=10).scenes[0]
            self.assertGreater(len(scan_points(channel, scene.scene_id)), 500)

    def test_full_disk_refuses_uploads_fails_jobs_and_keeps_what_was_stored(self):
        data_dir = tempfile.mkdtemp(prefix="vscand-full-")
        disk = TmpfsStore(data_dir, self.SIZE_MIB)
        server = Server(data_dir=data_dir, wrapper=disk.wrapper)
        try:
            server.start()
            fx = CampaignFixture(server)
            ball = icosphere_ply(0.05, (0.3, 0.3, 0.05), subdivisions=5)
            scenes = fx.scenes
            meshes = [scenes.GetMesh(scene_pb2.GetMeshRequest(
                mesh_id=fx.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=fx.scene.scene_id)).scene.objects[0]
                .mesh_id)).mesh]
            for i in range(3):
                meshes.append(self.upload_scaled(scenes, ball, i))

            # A campaign of large scans fills the disk and fails naming the scan it could not store.
            big = spec(fx.scene.scene_id, fx.mount, viewpoints=VIEWPOINTS, rotations=100, step=3.6,
                       sensor=camera(1280, 960), name="filler")
            with Client(server.address) as client:
                filler = client.wait_job(client.start_campaign(spec=big).job_id, timeout=120)
            self.assertEqual(filler.state, job_pb2.JOB_STATE_FAILED, filler.message)
            self.assertRegex(filler.message, r"^cannot store scan-r\d\d-v\d\d\.ply: .*no space left")
            self.assertGreater(len(scan_artifacts(filler)), 0)

            # Uploads are refused once nothing fits, naming the mesh and the full disk.
            refusal = None
            for i in range(3, 60):
                try:
                    meshes.append(self.upload_scaled(scenes, ball, i))
                except grpc.RpcError as err:
                    refusal = err
                    break
            self.assertIsNotNone(refusal, "the disk never filled")
            self.assertEqual(refusal.code(), C.RESOURCE_EXHAUSTED, refusal.details())
            self.assertIn("no space left", refusal.details())
            self.assertIn("mesh 'ball-", refusal.details())
            self.check_store(server, disk, meshes)
            fx.close()

            server.stop()
            server.start()
            self.check_store(server, disk, meshes)
            with Client(server.address) as client:
                after = client.get_job(filler.job_id)
                self.assertEqual(after.state, job_pb2.JOB_STATE_FAILED)
                self.assertEqual(after.message, filler.message)
                for artifact in scan_artifacts(after)[:3]:
                    points, _ = parse_ply(client.read_artifact(after.job_id, artifact.artifact_id)[1])
                    self.assertEqual(len(points), artifact.scan.points)
            with server.channel() as channel:
                scenes = scene_pb2_grpc.SceneServiceStub(channel)
                for mesh in meshes[-2:]:
                    scenes.DeleteMesh(scene_pb2.DeleteMeshRequest(mesh_id=mesh.mesh_id), timeout=10)
                fresh = self.upload_scaled(scenes, ball, 99)
                self.assertEqual(self.blob_sha256(disk.view, fresh.sha256), fresh.sha256)
        finally:
            server.stop()
            disk.close()
            shutil.rmtree(data_dir, ignore_errors=True)

    def upload_scaled(self, scenes, data, i):
        """The same file at another scale: other stored geometry, another blob."""
        def requests():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                name=f"ball-{i}.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data), scale=1.0 + 0.01 * i))
            yield scene_pb2.UploadMeshRequest(chunk=data)
        return scenes.UploadMesh(requests(), timeout=60).mesh


if __name__ == "__main__":
    unittest.main()
