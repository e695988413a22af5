"""The service end to end through raw stubs: health, reflection, scenes, scans, deadlines, shutdown."""

import math
import os
import shlex
import subprocess
import time
import unittest

import grpc
import numpy as np

from harness import (BUNNY, SOURCE_DIR, Server, ServerTestCase, common_pb2, icosphere_ply, look_at, pinhole, scan_pb2,
                     scene_pb2, sensor_pb2)
from vscan.v1 import job_pb2, job_pb2_grpc, robot_pb2, robot_pb2_grpc, scene_pb2_grpc

C = grpc.StatusCode


def collect(responses):
    header, chunks, stats = None, [], None
    for r in responses:
        kind = r.WhichOneof("part")
        if kind == "header":
            header = r.header
        elif kind == "chunk":
            chunks.append(r.chunk)
        else:
            stats = r.statistics
    return header, chunks, stats


class ServiceTest(ServerTestCase):
    def test_health_serving(self):
        check = self.channel.unary_unary("/grpc.health.v1.Health/Check",
                                         request_serializer=lambda b: b, response_deserializer=lambda b: b)
        self.assertEqual(check(b"", timeout=10), b"\x08\x01")  # status: SERVING

    def test_reflection_lists_services(self):
        info = self.channel.stream_stream("/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo",
                                          request_serializer=lambda b: b, response_deserializer=lambda b: b)
        reply = b"".join(info(iter([b"\x3a\x00"]), timeout=10))  # list_services: ""
        for name in (b"vscan.v1.SceneService", b"vscan.v1.ScanService", b"vscan.v1.RobotService"):
            self.assertIn(name, reply)

    def test_the_documented_buf_curl_lists_every_method(self):
        buf = os.path.join(SOURCE_DIR, ".tools", "node_modules", ".bin", "buf")
        if not os.path.exists(buf):
            self.skipTest("buf is not installed (scripts/install-deps.sh puts it in .tools)")
        with open(os.path.join(SOURCE_DIR, "docs", "API.md")) as f:
            [line] = [line.strip() for line in f if "buf curl" in line and "--list-methods" in line]
        command = shlex.split(line.replace("npx @bufbuild/buf", buf).replace("127.0.0.1:50051", self.server.address))
        listed = subprocess.run(command, capture_output=True, text=True, timeout=60)
        self.assertEqual(listed.returncode, 0, listed.stderr)
        methods = listed.stdout.split()
        for method in ("grpc.health.v1.Health/Check", "vscan.v1.ScanService/Scan", "vscan.v1.JobService/WatchJob"):
            self.assertIn(method, methods)

    def test_bin_fill_is_served_and_checks_its_spec(self):
        jobs = job_pb2_grpc.JobServiceStub(self.channel)
        self.assertCode(C.INVALID_ARGUMENT, lambda: jobs.StartBinFill(job_pb2.StartBinFillRequest()), "spec")
        spec = job_pb2.BinFillSpec(scene_id="scn_0000000000000000")
        spec.bin.inner_size.x, spec.bin.inner_size.y, spec.bin.inner_size.z = 0.3, 0.2, 0.1
        spec.parts.add(mesh_id="msh_0000000000000000", count=1)
        self.assertCode(C.NOT_FOUND, lambda: jobs.StartBinFill(job_pb2.StartBinFillRequest(spec=spec)),
                        "spec.scene_id")

    def test_robot_service_is_served(self):
        robots = robot_pb2_grpc.RobotServiceStub(self.channel)
        self.assertCode(C.NOT_FOUND, lambda: robots.GetRobot(robot_pb2.GetRobotRequest(robot_id="r")), "robot_id")

    def test_scene_lifecycle_and_revisions(self):
        scene = self.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="life")).scene
        self.assertEqual(scene.revision, 1)
        mesh = self.upload(BUNNY)
        added = self.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id,
                                                                 label="bunny", on_table=True))
        self.assertEqual(added.revision, 2)
        self.assertEqual(added.object.instance_id, 1)
        moved = self.scenes.MoveObject(scene_pb2.MoveObjectRequest(
            scene_id=scene.scene_id, object_id=added.object.object_id,
            pose=common_pb2.Pose(quaternion=common_pb2.QuaternionPose(
                translation=common_pb2.Vector3(x=0.1), qw=1.0)), scale=2.0))
        self.assertEqual(moved.revision, 3)
        self.assertEqual(moved.object.scale, 2.0)
        table = self.scenes.SetRotaryTable(scene_pb2.SetRotaryTableRequest(
            scene_id=scene.scene_id, table=scene_pb2.RotaryTable(enabled=True, angle_deg=30)))
        self.assertEqual(table.revision, 4)
        got = self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene
        self.assertEqual(got.revision, 4)
        self.assertEqual(got.objects[0].label, "bunny")
        self.assertEqual(got.table.axis.z, 1.0)
        self.assertAlmostEqual(got.objects[0].pose.matrix.values[3], 0.1)
        removed = self.scenes.RemoveObject(scene_pb2.RemoveObjectRequest(scene_id=scene.scene_id,
                                                                         object_id=added.object.object_id))
        self.assertEqual(removed.revision, 5)
        self.scenes.DeleteScene(scene_pb2.DeleteSceneRequest(scene_id=scene.scene_id))
        self.assertCode(C.NOT_FOUND, lambda: self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)))

    def test_list_pages(self):
        ids = {self.scenes.CreateScene(scene_pb2.CreateSceneRequest(name=f"p{i}")).scene.scene_id for i in range(5)}
        seen, token = set(), ""
        while True:
            page = self.scenes.ListScenes(scene_pb2.ListScenesRequest(page_size=2, page_token=token))
            self.assertLessEqual(len(page.scenes), 2)
            seen |= {s.scene_id for s in page.scenes}
            token = page.next_page_token
            if not token:
                break
        self.assertTrue(ids <= seen)

    def sphere_scene(self, radius=0.2, centre=(0.0, 0.0, 0.0)):
        scene = self.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="sphere")).scene
        mesh = self.upload_bytes(icosphere_ply(radius, centre, 4), "sphere.ply")
        self.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id))
        return scene

    def test_scan_streams_chunks_that_numpy_reads(self):
        radius = 0.2
        scene = self.sphere_scene(radius)
        request = scan_pb2.ScanRequest(scene_id=scene.scene_id, sensor=pinhole(320, 240, 40.0),
                                       pose=look_at((1.0, 0.0, 0.0), (0, 0, 0)), chunk_bytes=16 << 10,
                                       fields=[scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_NORMAL,
                                               scan_pb2.POINT_FIELD_RANGE, scan_pb2.POINT_FIELD_INSTANCE_ID,
                                               scan_pb2.POINT_FIELD_PIXEL])
        header, chunks, stats = collect(self.scans.Scan(request, timeout=60))
        self.assertEqual(header.rays, 320 * 240)
        # Streamed as rows are cast: the header cannot count them, the statistics do.
        self.assertEqual((header.points, header.chunk_count), (0, 0))
        self.assertGreater(len(chunks), 1)
        self.assertEqual([c.index for c in chunks], list(range(len(chunks))))
        self.assertEqual(len(chunks), stats.chunk_count)
        self.assertEqual(sum(c.count for c in chunks), stats.streamed_points)
        self.assertEqual(stats.points, stats.streamed_points)
        pos = np.concatenate([np.frombuffer(c.positions, dtype="<f4").reshape(-1, 3) for c in chunks])
        nrm = np.concatenate([np.frombuffer(c.normals, dtype="<f4").reshape(-1, 3) for c in chunks])
        rng = np.concatenate([np.frombuffer(c.ranges, dtype="<f4") for c in chunks])
        ids = np.concatenate([np.frombuffer(c.instance_ids, dtype="<u4") for c in chunks])
        pix = np.concatenate([np.frombuffer(c.pixels, dtype="<u4") for c in chunks])
        r = np.linalg.norm(pos, axis=1)
        # Icosphere (4 subdivisions) chords sag below the sphere by under 0.3% of the radius.
        self.assertLess(np.max(np.abs(r - radius)), 0.003 * radius)
        self.assertTrue(np.all(ids == 1))
        self.assertTrue(np.all(np.diff(pix.astype(np.int64)) > 0))
        np.testing.assert_allclose(rng, np.linalg.norm(pos - np.array([1.0, 0, 0]), axis=1), rtol=1e-5)
        cosang = np.sum(nrm * (pos / r[:, None]), axis=1)
        self.assertGreater(np.min(cosang), math.cos(math.radians(6)))
        # Disc of the sphere seen from 1 m: compare the hit count with the analytic solid angle.
        fx = header.intrinsics.fx
        half_angle = math.asin(radius / 1.0)
        expected = math.pi * (fx * math.tan(half_angle)) ** 2
        self.assertAlmostEqual(stats.points / expected, 1.0, delta=0.03)

    def test_raster_backends_agree_with_ray_casting(self):
        scene = self.sphere_scene(0.2, (0.0, 0.0, 0.0))
        clouds = {}
        for backend in (scan_pb2.SCAN_BACKEND_RAYCAST, scan_pb2.SCAN_BACKEND_RASTER_DEPTH,
                        scan_pb2.SCAN_BACKEND_RASTER_COLOUR):
            request = scan_pb2.ScanRequest(scene_id=scene.scene_id, sensor=pinhole(320, 240, 40.0), backend=backend,
                                           pose=look_at((1.0, 0.0, 0.0), (0, 0, 0)),
                                           fields=[scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_PIXEL])
            header, chunks, _ = collect(self.scans.Scan(request, timeout=120))
            self.assertEqual(header.backend, backend)
            pos = np.concatenate([np.frombuffer(c.positions, dtype="<f4").reshape(-1, 3) for c in chunks])
            pix = np.concatenate([np.frombuffer(c.pixels, dtype="<u4") for c in chunks])
            clouds[backend] = dict(zip(pix.tolist(), pos))
        reference = clouds[scan_pb2.SCAN_BACKEND_RAYCAST]
        for backend, tolerance in ((scan_pb2.SCAN_BACKEND_RASTER_DEPTH, 1e-4),
                                   (scan_pb2.SCAN_BACKEND_RASTER_COLOUR, 2e-4)):
            cloud = clouds[backend]
            common = reference.keys() & cloud.keys()
            # Coverage may differ only on the silhouette.
            self.assertGreater(len(common), 0.995 * max(len(reference), len(cloud)))
            diff = max(float(np.linalg.norm(reference[p] - cloud[p])) for p in common)
            self.assertLess(diff, tolerance, backend)

    def plane_scene(self, distance):
        ply = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
               f"-5 -5 {distance}\n5 -5 {distance}\n5 5 {distance}\n-5 5 {distance}\n3 0 1 2\n3 0 2 3\n").encode()
        scene = self.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="plane")).scene
        mesh = self.upload_bytes(ply, "plane.ply")
        self.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id))
        return scene

    def test_noise_and_distortion_follow_their_models(self):
        scene = self.plane_scene(2.0)
        eye_down_z = common_pb2.Pose(matrix=common_pb2.Matrix4(values=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]))

        def scan(noise=None, distortion=None, seed=7):
            sensor = pinhole(400, 300, 60.0)
            if distortion:
                sensor.pinhole.distortion.CopyFrom(distortion)
            request = scan_pb2.ScanRequest(scene_id=scene.scene_id, sensor=sensor, pose=eye_down_z, seed=seed,
                                           frame=scan_pb2.FRAME_SENSOR, noise=noise,
                                           fields=[scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_PIXEL])
            _, chunks, _ = collect(self.scans.Scan(request, timeout=60))
            return np.concatenate([np.frombuffer(c.positions, dtype="<f4").reshape(-1, 3) for c in chunks])

        clean = scan()
        np.testing.assert_allclose(clean[:, 2], 2.0, rtol=1e-6)
        # sigma(z) = a + b z + c z^2 at z = 2: 0.001 + 0.002 + 0.004 = 0.007 m, along z here (isotropic).
        noisy = scan(noise=sensor_pb2.NoiseSpec(sigma_a=0.001, sigma_b=0.001, sigma_c=0.001))
        self.assertAlmostEqual(float(np.std(noisy[:, 2] - 2.0)) / 0.007, 1.0, delta=0.03)
        np.testing.assert_array_equal(noisy, scan(noise=sensor_pb2.NoiseSpec(sigma_a=0.001, sigma_b=0.001,
                                                                            sigma_c=0.001)))
        self.assertFalse(np.array_equal(noisy, scan(noise=sensor_pb2.NoiseSpec(sigma_a=0.001, sigma_b=0.001,
                                                                              sigma_c=0.001), seed=8)))
        k1, p1 = 0.05, 0.002
        distorted = scan(distortion=sensor_pb2.Distortion(k1=k1, p1=p1))
        x, y = clean[:, 0] / 2.0, clean[:, 1] / 2.0
        r2 = x * x + y * y
        expected_x = (x * (1 + k1 * r2) + 2 * p1 * x * y) * 2.0
        expected_y = (y * (1 + k1 * r2) + p1 * (r2 + 2 * y * y)) * 2.0
        np.testing.assert_allclose(distorted[:, 0], expected_x, atol=2e-6)
        np.testing.assert_allclose(distorted[:, 1], expected_y, atol=2e-6)

    def test_sensor_presets_carry_their_noise(self):
        presets = {p.name: p for p in self.scans.ListSensorPresets(scan_pb2.ListSensorPresetsRequest()).presets}
        self.assertIn("ideal-vga", presets)
        kinect = presets["kinect-v1-class"]
        self.assertEqual((kinect.spec.pinhole.width, kinect.spec.pinhole.height), (640, 480))
        self.assertIn("Khoshelham", kinect.source)
        scene = self.plane_scene(2.0)
        identity = common_pb2.Pose(matrix=common_pb2.Matrix4(values=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]))
        request = scan_pb2.ScanRequest(scene_id=scene.scene_id, sensor=sensor_pb2.SensorSpec(preset="kinect-v1-class"),
                                       pose=identity, seed=3, frame=scan_pb2.FRAME_SENSOR)
        header, chunks, _ = collect(self.scans.Scan(request, timeout=60))
        self.assertEqual(header.width, 640)
        pos = np.concatenate([np.frombuffer(c.positions, dtype="<f4").reshape(-1, 3) for c in chunks]).astype(float)
        # Noise along the ray: the point stays on its ray; its offset from the plane along the ray is N(0, c z^2).
        along = np.linalg.norm(pos, axis=1) * (1.0 - 2.0 / pos[:, 2])
        expected = kinect.noise.sigma_c * 2.0 ** 2
        self.assertAlmostEqual(float(np.std(along)) / expected, 1.0, delta=0.03)

    def test_table_turns_objects_on_it(self):
        scene = self.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="table")).scene
        mesh = self.upload_bytes(icosphere_ply(0.05, (0.0, 0.0, 0.0), 2), "small.ply")
        pose = common_pb2.Pose(quaternion=common_pb2.QuaternionPose(translation=common_pb2.Vector3(x=0.3), qw=1))
        self.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id,
                                                         pose=pose, on_table=True))
        self.scenes.SetRotaryTable(scene_pb2.SetRotaryTableRequest(
            scene_id=scene.scene_id, table=scene_pb2.RotaryTable(enabled=True, angle_deg=90)))
        request = scan_pb2.ScanRequest(scene_id=scene.scene_id, sensor=pinhole(200, 200, 90.0),
                                       pose=look_at((0, 0, 2.0), (0, 0, 0), up=(0, 1, 0)))
        _, chunks, _ = collect(self.scans.Scan(request, timeout=60))
        pos = np.concatenate([np.frombuffer(c.positions, dtype="<f4").reshape(-1, 3) for c in chunks])
        centre = pos.mean(axis=0)
        # Turned 90 degrees about +Z: the sphere moved from +X to +Y.
        self.assertAlmostEqual(centre[0], 0.0, delta=0.01)
        self.assertAlmostEqual(centre[1], 0.3, delta=0.01)
        request.table_angle_deg = 0.0
        _, chunks, _ = collect(self.scans.Scan(request, timeout=60))
        pos = np.concatenate([np.frombuffer(c.positions, dtype="<f4").reshape(-1, 3) for c in chunks])
        self.assertAlmostEqual(pos.mean(axis=0)[0], 0.3, delta=0.01)

    def test_deadline_stops_a_large_scan(self):
        scene = self.sphere_scene()
        request = scan_pb2.ScanRequest(scene_id=scene.scene_id, sensor=pinhole(4096, 4096, 60.0),
                                       pose=look_at((1.0, 0.0, 0.0), (0, 0, 0)))
        self.assertCode(C.DEADLINE_EXCEEDED, lambda: list(self.scans.Scan(request, timeout=0.05)))
        # The server is still there and answers.
        self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id))


class TokenTest(unittest.TestCase):
    def test_token_is_required_when_configured(self):
        import os
        import tempfile
        with tempfile.NamedTemporaryFile("w", suffix=".token", delete=False) as f:
            f.write("s3cret\n")
        server = Server(extra_args=("--token-file", f.name)).start()
        try:
            with server.channel() as channel:
                scenes = scene_pb2_grpc.SceneServiceStub(channel)
                with self.assertRaises(grpc.RpcError) as ctx:
                    scenes.ListScenes(scene_pb2.ListScenesRequest(), timeout=10)
                self.assertEqual(ctx.exception.code(), C.UNAUTHENTICATED)
                with self.assertRaises(grpc.RpcError) as ctx:
                    scenes.ListScenes(scene_pb2.ListScenesRequest(), timeout=10,
                                      metadata=[("authorization", "Bearer wrong")])
                self.assertEqual(ctx.exception.code(), C.UNAUTHENTICATED)
                scenes.ListScenes(scene_pb2.ListScenesRequest(), timeout=10,
                                  metadata=[("authorization", "Bearer s3cret")])
                # The scheme is case-insensitive (RFC 6750 / 7235); the token is not.
                for header in ("bearer s3cret", "BEARER s3cret", "Bearer  s3cret"):
                    scenes.ListScenes(scene_pb2.ListScenesRequest(), timeout=10,
                                      metadata=[("authorization", header)])
                for header in ("Bearer S3CRET", "Basic s3cret", "Bearers3cret", "Bearer ", "s3cret"):
                    with self.assertRaises(grpc.RpcError) as ctx:
                        scenes.ListScenes(scene_pb2.ListScenesRequest(), timeout=10,
                                          metadata=[("authorization", header)])
                    self.assertEqual(ctx.exception.code(), C.UNAUTHENTICATED, header)
        finally:
            server.cleanup()
            os.unlink(f.name)


class ShutdownTest(unittest.TestCase):
    def test_sigterm_stops_cleanly(self):
        server = Server().start()
        try:
            start = time.time()
            self.assertEqual(server.stop(timeout=30), 0, server.log())
            self.assertLess(time.time() - start, 15)
            self.assertIn("stopped", server.log())
        finally:
            server.cleanup()


if __name__ == "__main__":
    unittest.main()
