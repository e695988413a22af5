"""Every bad input gets the most specific status, names its field, and changes nothing."""

import math
import unittest

import grpc

from harness import BUNNY, ServerTestCase, common_pb2, icosphere_ply, look_at, pinhole, scan_pb2, scene_pb2, sensor_pb2
from vscan.v1 import job_pb2, job_pb2_grpc

C = grpc.StatusCode


class BadInputTest(ServerTestCase):
    server_args = ("--max-upload-mib", "1", "--max-rays", "1000000")

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.scene = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="bad-input")).scene
        mesh = ServerTestCase.upload_bytes(cls, icosphere_ply(0.1, (0, 0, 0), 2), "sphere.ply")
        cls.mesh = mesh
        added = cls.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=cls.scene.scene_id, mesh_id=mesh.mesh_id))
        cls.object = added.object

    def revision(self):
        return self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=self.scene.scene_id)).scene.revision

    def mesh_count(self):
        return len(self.scenes.ListMeshes(scene_pb2.ListMeshesRequest()).meshes)

    def scan(self, **kw):
        req = dict(scene_id=self.scene.scene_id, sensor=pinhole(), pose=look_at((0.5, 0, 0), (0, 0, 0)))
        req.update(kw)
        return lambda: list(self.scans.Scan(scan_pb2.ScanRequest(**req), timeout=30))

    # Unknown ids
    def test_unknown_ids(self):
        self.assertCode(C.NOT_FOUND, lambda: self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id="scn_nope")),
                        "scene_id")
        self.assertCode(C.NOT_FOUND, lambda: self.scenes.GetMesh(scene_pb2.GetMeshRequest(mesh_id="msh_nope")),
                        "mesh_id")
        self.assertCode(C.NOT_FOUND, self.scan(scene_id="scn_nope"), "scene_id")
        before = self.revision()
        self.assertCode(C.NOT_FOUND, lambda: self.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=self.scene.scene_id, mesh_id="msh_nope")), "mesh_id")
        self.assertCode(C.NOT_FOUND, lambda: self.scenes.RemoveObject(scene_pb2.RemoveObjectRequest(
            scene_id=self.scene.scene_id, object_id="obj_nope")), "object_id")
        self.assertEqual(before, self.revision())

    def test_ids_that_no_record_can_have_are_invalid_not_unknown(self):
        jobs = job_pb2_grpc.JobServiceStub(self.channel)
        before = self.revision()
        for bad in ("scn_\x00ab", "scn_\u00e9t\u00e9", "../../etc/passwd", "scn_a/b", "scn_.."):
            self.assertCode(C.INVALID_ARGUMENT,
                            lambda: self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=bad)), "scene_id")
            self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.RemoveObject(scene_pb2.RemoveObjectRequest(
                scene_id=self.scene.scene_id, object_id=bad)), "object_id")
            self.assertCode(C.INVALID_ARGUMENT, lambda: jobs.GetJob(job_pb2.GetJobRequest(job_id=bad)), "job_id")
        self.assertEqual(before, self.revision())

    def test_missing_ids(self):
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.GetScene(scene_pb2.GetSceneRequest()), "scene_id")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(scene_id=""), "scene_id")

    # Poses
    def test_nan_and_non_rigid_poses(self):
        before = self.revision()
        nan = common_pb2.Pose(matrix=common_pb2.Matrix4(values=[math.nan] + [0.0] * 15))
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.MoveObject(scene_pb2.MoveObjectRequest(
            scene_id=self.scene.scene_id, object_id=self.object.object_id, pose=nan)), "pose")
        sheared = common_pb2.Pose(matrix=common_pb2.Matrix4(values=[2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]))
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=self.scene.scene_id, mesh_id=self.mesh.mesh_id, pose=sheared)), "pose.matrix")
        short = common_pb2.Pose(matrix=common_pb2.Matrix4(values=[1, 0, 0]))
        self.assertCode(C.INVALID_ARGUMENT, self.scan(pose=short), "pose.matrix.values")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(pose=look_at((0, 0, 0), (0, 0, 0))), "pose.look_at")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(pose=look_at((math.nan, 0, 0), (0, 0, 0))), "pose.look_at.eye")
        bad_quat = common_pb2.Pose(quaternion=common_pb2.QuaternionPose(qw=2.0))
        self.assertCode(C.INVALID_ARGUMENT, self.scan(pose=bad_quat), "pose.quaternion")
        self.assertCode(C.INVALID_ARGUMENT, lambda: list(self.scans.Scan(scan_pb2.ScanRequest(
            scene_id=self.scene.scene_id, sensor=pinhole()))), "pose")
        self.assertEqual(before, self.revision())

    def test_bad_scale_changes_nothing(self):
        before = self.revision()
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=self.scene.scene_id, mesh_id=self.mesh.mesh_id, scale=-1)), "scale")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=self.scene.scene_id, mesh_id=self.mesh.mesh_id, scale=math.inf)), "scale")
        table = scene_pb2.RotaryTable(enabled=True, angle_deg=math.nan)
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.SetRotaryTable(scene_pb2.SetRotaryTableRequest(
            scene_id=self.scene.scene_id, table=table)), "table.angle_deg")
        self.assertEqual(before, self.revision())

    # Sensors and resolutions
    def test_resolutions_and_ranges(self):
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=pinhole(width=0)), "sensor.pinhole.width")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=pinhole(height=0)), "sensor.pinhole.height")
        self.assertCode(C.RESOURCE_EXHAUSTED, self.scan(sensor=pinhole(width=2000, height=2000)), "sensor.pinhole")
        self.assertCode(C.RESOURCE_EXHAUSTED, self.scan(sensor=pinhole(width=100000, height=1)), "sensor.pinhole.width")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=pinhole(near=2.0, far=1.0)), "near")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=pinhole(near=1.0, far=1.0)), "near")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=pinhole(hfov=180)), "horizontal_fov_deg")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=pinhole(near=-1.0)), "near")
        bad_k = sensor_pb2.SensorSpec(pinhole=sensor_pb2.PinholeCamera(
            width=10, height=10, intrinsics=sensor_pb2.Intrinsics(fx=0, fy=10, cx=5, cy=5)))
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=bad_k), "fx")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=sensor_pb2.SensorSpec()), "sensor")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(chunk_bytes=10), "chunk_bytes")

    def test_unknown_enums_bad_noise_and_unknown_presets(self):
        self.assertCode(C.INVALID_ARGUMENT, self.scan(backend=99), "backend")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(noise=sensor_pb2.NoiseSpec(outlier_rate=0.01)),
                        "noise.outlier_rate")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(noise=sensor_pb2.NoiseSpec(sigma_a=-1)), "noise")
        self.assertCode(C.NOT_FOUND, self.scan(sensor=sensor_pb2.SensorSpec(preset="kinect")), "sensor.preset")

    # Geometry beyond the physical bounds (docs/API.md, "Bounds"): refused where it enters, so that
    # no ray the server builds can abort it.
    def intrinsics(self, fx, fy, cx, cy, width=64, height=48, **kw):
        return sensor_pb2.PinholeCamera(width=width, height=height,
                                        intrinsics=sensor_pb2.Intrinsics(fx=fx, fy=fy, cx=cx, cy=cy), **kw)

    def test_huge_and_tiny_geometry_is_refused(self):
        field = "sensor.pinhole.intrinsics."
        for (fx, fy, cx, cy), name in [((1e-20, 1e-20, 320, 240), "fx"), ((1, 1, 1e20, 240), "cx"),
                                       ((1, 1, 32, 1e20), "cy"), ((1e20, 50, 32, 24), "fx"),
                                       ((0.02, 50, 32, 24), "fx"), ((50, math.nan, 32, 24), "fy")]:
            sensor = sensor_pb2.SensorSpec(pinhole=self.intrinsics(fx, fy, cx, cy))
            self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=sensor), field + name)
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=pinhole(near=1e-20)), "sensor.pinhole.near")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=pinhole(far=1e19)), "sensor.pinhole.far")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(pose=look_at((2e18, 0, 0.2), (0, 0, 0.07))), "pose.look_at.eye")
        self.assertCode(C.INVALID_ARGUMENT, self.scan(pose=look_at((0.5, 0, 0), (0, 1e19, 0))), "pose.look_at.target")
        matrix = common_pb2.Pose(matrix=common_pb2.Matrix4(values=[1, 0, 0, 1e19, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]))
        self.assertCode(C.INVALID_ARGUMENT, self.scan(pose=matrix), "pose.matrix translation")
        quat = common_pb2.Pose(quaternion=common_pb2.QuaternionPose(
            qw=1, translation=common_pb2.Vector3(x=0, y=-1e19, z=0)))
        self.assertCode(C.INVALID_ARGUMENT, self.scan(pose=quat), "pose.quaternion.translation")
        tiny = sensor_pb2.SensorSpec(structured_light=sensor_pb2.StructuredLightScanner(
            camera=self.intrinsics(1e-20, 1e-20, 32, 24), projector_offset=common_pb2.Vector3(x=0.1)))
        self.assertCode(C.INVALID_ARGUMENT, self.scan(sensor=tiny), "sensor.structured_light.camera.intrinsics.fx")
        # Still serving, and a sensible request near the bounds works.
        near_bounds = sensor_pb2.SensorSpec(pinhole=self.intrinsics(40, 40, 32, 24, near=1e-6, far=1e5))
        self.assertEqual(self.scan(sensor=near_bounds)()[-1].statistics.rays, 64 * 48)

    def test_campaign_with_absurd_intrinsics_is_refused_at_start(self):
        jobs = job_pb2_grpc.JobServiceStub(self.channel)
        spec = job_pb2.CampaignSpec(
            scene_id=self.scene.scene_id, sensor=sensor_pb2.SensorSpec(pinhole=self.intrinsics(1e-20, 1e-20, 32, 24)),
            viewpoints=[job_pb2.Viewpoint(position=common_pb2.Vector3(x=0.5), target=common_pb2.Vector3())])
        self.assertCode(C.INVALID_ARGUMENT, lambda: jobs.StartCampaign(job_pb2.StartCampaignRequest(
            spec=spec, validate_only=True), timeout=10), "sensor.pinhole.intrinsics.fx")

    def test_campaign_plans_are_checked_before_anything_exists(self):
        jobs = job_pb2_grpc.JobServiceStub(self.channel)
        before = len(jobs.ListJobs(job_pb2.ListJobsRequest()).jobs)
        view = job_pb2.Viewpoint(position=common_pb2.Vector3(x=0.5), target=common_pb2.Vector3())

        def check(code, field, **kw):
            spec = dict(sensor=pinhole(), viewpoints=[view])
            spec.update(kw)
            self.assertCode(code, lambda: jobs.StartCampaign(job_pb2.StartCampaignRequest(
                spec=job_pb2.CampaignSpec(**spec), validate_only=True), timeout=10), field)
        check(C.INVALID_ARGUMENT, "spec.rotations", rotations=3601, rotation_step_deg=1)
        check(C.INVALID_ARGUMENT, "spec.sensor.pinhole.width", sensor=pinhole(width=0))
        check(C.RESOURCE_EXHAUSTED, "spec.sensor.pinhole.width", sensor=pinhole(width=100000, height=1))
        check(C.INVALID_ARGUMENT, "spec.rotation_step_deg", rotations=2, rotation_step_deg=0)
        check(C.INVALID_ARGUMENT, "spec.rotation_step_deg", rotations=2, rotation_step_deg=1e300)
        check(C.INVALID_ARGUMENT, "spec.viewpoints[0].position",
              viewpoints=[job_pb2.Viewpoint(position=common_pb2.Vector3(x=2e4), target=common_pb2.Vector3())])
        check(C.NOT_FOUND, "spec.scene_id", scene_id="scn_0000000000000000")
        check(C.INVALID_ARGUMENT, "spec.scene_id", mount_id="mnt_0000000000000000")
        self.assertEqual(before, len(jobs.ListJobs(job_pb2.ListJobsRequest()).jobs))

    def test_objects_and_meshes_beyond_the_world_bounds_change_nothing(self):
        before, meshes = self.revision(), self.mesh_count()
        far = common_pb2.Pose(quaternion=common_pb2.QuaternionPose(qw=1, translation=common_pb2.Vector3(x=1e39)))
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=self.scene.scene_id, mesh_id=self.mesh.mesh_id, pose=far)), "pose.quaternion.translation")
        # A sphere of 0.1 m scaled by 1e6 reaches 100 km.
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=self.scene.scene_id, mesh_id=self.mesh.mesh_id, scale=1e6)), "scale")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.MoveObject(scene_pb2.MoveObjectRequest(
            scene_id=self.scene.scene_id, object_id=self.object.object_id, pose=look_at((0, 0, 0), (1, 0, 0)),
            scale=1e6)), "scale")
        table = scene_pb2.RotaryTable(enabled=True, centre=common_pb2.Vector3(z=1e19), axis=common_pb2.Vector3(z=1))
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.SetRotaryTable(scene_pb2.SetRotaryTableRequest(
            scene_id=self.scene.scene_id, table=table)), "table.centre")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.upload_bytes(
            icosphere_ply(1e38, (0, 0, 0), 1), "huge.ply"), "mesh data")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.upload_bytes(
            icosphere_ply(1, (0, 0, 0), 1), "sphere.ply", scale=1e5), "mesh data")
        self.assertEqual(before, self.revision())
        self.assertEqual(meshes, self.mesh_count())
        self.assertGreater(self.scan()()[-1].statistics.points, 0, "the scene still scans")

    def test_unknown_mesh_format(self):
        data = icosphere_ply(1, (0, 0, 0), 1)

        def requests():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                name="sphere.ply", unit=common_pb2.LENGTH_UNIT_METRE, format=99, size_bytes=len(data)))
            yield scene_pb2.UploadMeshRequest(chunk=data)
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.UploadMesh(requests(), timeout=30), "header.format")

    def test_garbage_page_tokens(self):
        for token in ("garbage", "scn_", "scn_zzzzzzzzzzzzzzzz", "msh_0123456789abcdef"):
            self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.ListScenes(
                scene_pb2.ListScenesRequest(page_token=token)), "page_token")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.ListMeshes(
            scene_pb2.ListMeshesRequest(page_token="scn_0123456789abcdef")), "page_token")
        jobs = job_pb2_grpc.JobServiceStub(self.channel)
        self.assertCode(C.INVALID_ARGUMENT, lambda: jobs.ListJobs(job_pb2.ListJobsRequest(page_token="x")),
                        "page_token")
        self.scenes.ListScenes(scene_pb2.ListScenesRequest(page_token="scn_0123456789abcdef"))

    def test_names_with_control_characters(self):
        before = len(self.scenes.ListScenes(scene_pb2.ListScenesRequest()).scenes)
        for name in ("two\nlines", "nul\x00byte", "bell\x07"):
            self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.CreateScene(
                scene_pb2.CreateSceneRequest(name=name)), "name")
            self.assertCode(C.INVALID_ARGUMENT, lambda: self.upload_bytes(
                icosphere_ply(1, (0, 0, 0), 1), name + ".ply"), "header.name")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=self.scene.scene_id, mesh_id=self.mesh.mesh_id, label="a\nb")), "label")
        self.assertEqual(before, len(self.scenes.ListScenes(scene_pb2.ListScenesRequest()).scenes))

    # Meshes
    def test_malformed_meshes_change_nothing(self):
        before = self.mesh_count()
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.upload_bytes(b"ply\nformat ascii 1.0\ngarbage", "x.ply"),
                        "mesh data")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.upload_bytes(b"", "empty.stl"), "mesh data")
        no_faces = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" \
                   b"property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.upload_bytes(no_faces, "nofaces.ply"), "mesh data")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.upload_bytes(
            icosphere_ply(1, (0, 0, 0), 1), "sphere.ply", unit=common_pb2.LENGTH_UNIT_UNSPECIFIED), "header.unit")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.upload_bytes(
            icosphere_ply(1, (0, 0, 0), 1), "sphere.ply", scale=-2), "header.scale")
        self.assertEqual(before, self.mesh_count())

    def test_upload_without_header(self):
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scenes.UploadMesh(
            iter([scene_pb2.UploadMeshRequest(chunk=b"abc")])), "header")

    def test_oversize_upload(self):
        before = self.mesh_count()
        big = b"solid x\n" + b" " * (2 << 20)
        self.assertCode(C.RESOURCE_EXHAUSTED, lambda: self.upload_bytes(big, "big.stl"), "size_bytes")

        def no_size():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(name="big.stl",
                                                                          unit=common_pb2.LENGTH_UNIT_METRE))
            for _ in range(3):
                yield scene_pb2.UploadMeshRequest(chunk=b" " * (900 << 10))
        self.assertCode(C.RESOURCE_EXHAUSTED, lambda: self.scenes.UploadMesh(no_size()), "chunk")
        self.assertEqual(before, self.mesh_count())

    def test_mesh_in_use_cannot_be_deleted(self):
        self.assertCode(C.FAILED_PRECONDITION, lambda: self.scenes.DeleteMesh(scene_pb2.DeleteMeshRequest(
            mesh_id=self.mesh.mesh_id)), "mesh_id")
        self.scenes.GetMesh(scene_pb2.GetMeshRequest(mesh_id=self.mesh.mesh_id))

    def test_bunny_still_scans_after_rejections(self):
        mesh = self.upload(BUNNY)
        self.assertGreater(mesh.triangle_count, 16000)


if __name__ == "__main__":
    unittest.main()
