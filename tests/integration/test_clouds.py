"""Stored clouds through a real vscand: PLY and PCD files vscan writes keep every field (in vscan, in
Open3D), list, get, read and delete, refusals that name their field and leave nothing behind, files
Open3D and PCL write in each of their encodings, organised scans, a campaign's scans as clouds of
their job, and the CLI round trip."""

import json
import math
import os
import struct
import subprocess
import tempfile
import unittest

import grpc
import numpy as np
import open3d as o3d

from harness import BUNNY, VSCAN, Server, common_pb2
from test_campaign_service import CampaignFixture, camera, spec
from vscan.v1 import cloud_pb2, cloud_pb2_grpc, job_pb2, scan_pb2, sensor_pb2

from vscan import Client, VscanError, parse_ply

C = grpc.StatusCode
FIELD_ATTRIBUTES = ("positions", "normals", "ranges", "intensities", "instance_ids", "pixels", "clean_positions",
                    "incidence_angles", "statuses", "estimated_normals")
EVERY_FIELD = [scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_NORMAL, scan_pb2.POINT_FIELD_RANGE,
               scan_pb2.POINT_FIELD_INTENSITY, scan_pb2.POINT_FIELD_INSTANCE_ID, scan_pb2.POINT_FIELD_PIXEL,
               scan_pb2.POINT_FIELD_CLEAN_POSITION, scan_pb2.POINT_FIELD_INCIDENCE_ANGLE, scan_pb2.POINT_FIELD_STATUS,
               scan_pb2.POINT_FIELD_ESTIMATED_NORMAL]


def bytes_under(path):
    return sum(os.path.getsize(os.path.join(root, name)) for root, _, names in os.walk(path) for name in names)


def xyz_ply(points):
    """A binary PLY of float x, y, z."""
    head = f"ply\nformat binary_little_endian 1.0\nelement vertex {len(points)}\nproperty float x\n" \
           "property float y\nproperty float z\nend_header\n"
    return head.encode() + b"".join(struct.pack("<3f", *p) for p in points)


DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
# vscan's field names in each format, and Open3D's attribute for each (normals it renames).
O3D_ATTRIBUTES = (("positions", "positions", "positions"), ("normals", "normals", "normals"),
                  ("ranges", "range", "range"), ("intensities", "intensity", "intensity"),
                  ("instance_ids", "instance", "instance"), ("pixels", "pixel", "pixel"),
                  ("clean_positions", ("clean_x", "clean_y", "clean_z"), ("clean_x", "clean_y", "clean_z")),
                  ("incidence_angles", "incidence", "incidence"), ("statuses", "status", "status"),
                  ("estimated_normals", ("enx", "eny", "enz"), ("est_normal_x", "est_normal_y", "est_normal_z")))


def open3d_values(cloud, names):
    """One vscan field as Open3D's tensor cloud holds it (a 1- or 3-column array)."""
    if isinstance(names, tuple):
        return np.concatenate([cloud.point[name].numpy() for name in names], axis=1)
    values = cloud.point[names].numpy()
    return values if values.shape[1] == 3 else values[:, 0]


def pcd_header(data):
    """The header lines of a PCD, up to and with DATA, as a dict."""
    header = {}
    for line in data.split(b"\n"):
        words = line.decode("ascii").split()
        if words and not words[0].startswith("#"):
            header[words[0]] = words[1:]
        if words[:1] == ["DATA"]:
            break
    return header


def run(*args, server):
    return subprocess.run([VSCAN, "--server", server.address, *args], capture_output=True, text=True, timeout=120)


class CloudUploadTest(unittest.TestCase):
    """Uploads of files vscan wrote, and what the server keeps of them."""

    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.addClassCleanup(cls.server.cleanup)
        cls.client = Client(cls.server.address, stream_timeout=120)
        cls.addClassCleanup(cls.client.close)
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-clouds-")
        cls.addClassCleanup(cls.tmp.cleanup)
        cls.blobs = os.path.join(cls.server.data_dir, "store", "blobs")
        cls.scene = cls.bunny_scene()
        # A noisy scan with every field vscan writes, as PLY and as PCD.
        cls.ply, cls.pcd = (os.path.join(cls.tmp.name, name) for name in ("scan.ply", "scan.pcd"))
        for path in (cls.ply, cls.pcd):
            out = run("-q", "scan", cls.scene, "-o", path, "--width", "96", "--height", "72", "--hfov", "40",
                      "--eye", "0,0.1,0.5", "--target", "0,0.1,0", "--up", "0,1,0", "--fields", "all,truth",
                      "--noise", "0.0005", "--estimate-normals=8", "--seed", "4", server=cls.server)
            assert out.returncode == 0, out.stderr

    @classmethod
    def bunny_scene(cls):
        out = run("-q", "mesh", "upload", BUNNY, "--unit", "m", server=cls.server)
        mesh = out.stdout.strip()
        scene = run("-q", "scene", "create", "clouds", server=cls.server).stdout.strip()
        run("-q", "object", "add", scene, mesh, server=cls.server)
        return scene

    def read_bytes(self, path):
        with open(path, "rb") as f:
            return f.read()

    def assertCode(self, code, call, field):
        with self.assertRaises(VscanError) as ctx:
            call()
        self.assertEqual(ctx.exception.code, code, ctx.exception.message)
        self.assertTrue(ctx.exception.message.startswith(field), ctx.exception.message)
        return ctx.exception

    def test_a_ply_written_by_vscan_comes_back_with_every_value(self):
        cloud = self.client.upload_cloud(self.ply, scene_id=self.scene)
        self.assertTrue(cloud.cloud_id.startswith("cld_"))
        self.assertEqual(cloud.name, "scan.ply")
        self.assertEqual(list(cloud.fields), EVERY_FIELD)
        self.assertEqual(cloud.origin, cloud_pb2.CLOUD_ORIGIN_UPLOADED)
        self.assertEqual(cloud.scene_id, self.scene)
        self.assertEqual(cloud.frame, scan_pb2.FRAME_WORLD)
        self.assertFalse(cloud.HasField("sensor_pose"))
        self.assertFalse(cloud.HasField("table_angle_deg"))
        got, data = self.client.read_cloud(cloud.cloud_id)
        self.assertEqual(got, cloud)
        # The stored PLY is canonical (the CLI's file keeps room for its count in a comment); every
        # value survives.
        points, sent = parse_ply(data), parse_ply(self.read_bytes(self.ply))
        self.assertEqual(len(points), cloud.points)
        for attribute in FIELD_ATTRIBUTES:
            np.testing.assert_array_equal(getattr(points, attribute), getattr(sent, attribute), err_msg=attribute)
        self.assertEqual(self.client.get_cloud(cloud.cloud_id), cloud)

    def test_a_pcd_keeps_every_field(self):
        from_ply = parse_ply(self.read_bytes(self.ply))
        cloud = self.client.upload_cloud(self.pcd, name="pcd scan")
        self.assertEqual(list(cloud.fields), EVERY_FIELD)
        points = self.client.read_cloud_points(cloud.cloud_id)
        self.assertEqual(points.cloud.cloud_id, cloud.cloud_id)
        for attribute in FIELD_ATTRIBUTES:
            np.testing.assert_array_equal(getattr(points, attribute), getattr(from_ply, attribute), err_msg=attribute)
        # Unspecified format: the server tells it from the bytes.
        told = self.client.upload_cloud(data=self.read_bytes(self.pcd), name="told")
        self.assertEqual(told.sha256, cloud.sha256)

    def test_the_pose_frame_and_camera_a_client_gives_are_kept(self):
        pose = np.eye(4)
        pose[:3, 3] = (0.1, -0.2, 0.5)
        pose[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
        cloud = self.client.upload_cloud(data=xyz_ply([(0, 0, 1), (0.1, 0, 1)]), name="sensor frame",
                                         sensor_pose=pose, frame="sensor",
                                         camera=(640, 480, 525.0, 525.0, 319.5, 239.5, 0.3, 4.0))
        self.assertEqual(cloud.frame, scan_pb2.FRAME_SENSOR)
        np.testing.assert_allclose(np.reshape(cloud.sensor_pose.values, (4, 4)), pose, atol=1e-12)
        self.assertEqual((cloud.camera.width, cloud.camera.height), (640, 480))
        self.assertEqual(cloud.camera.intrinsics.cx, 319.5)
        self.assertEqual((cloud.camera.near, cloud.camera.far), (0.3, 4.0))

    def test_list_pages_and_delete_frees_the_bytes(self):
        ids = [self.client.upload_cloud(data=xyz_ply([(i, 0, 0), (0, i, 0)]), name=f"c{i}").cloud_id
               for i in range(3)]
        stub = cloud_pb2_grpc.CloudServiceStub(self.server.channel())
        page = stub.ListClouds(cloud_pb2.ListCloudsRequest(page_size=1))
        self.assertEqual(len(page.clouds), 1)
        self.assertTrue(page.next_page_token)
        listed = [c.cloud_id for c in self.client.list_clouds()]
        self.assertEqual(listed, sorted(listed))
        self.assertTrue(set(ids) <= set(listed))

        before = bytes_under(self.blobs)
        deleted = self.client.delete_cloud(ids[0])
        self.assertEqual(deleted.removed_files, 1)
        self.assertGreater(deleted.removed_bytes, 0)
        self.assertEqual(bytes_under(self.blobs), before - deleted.removed_bytes)
        self.assertCode(C.NOT_FOUND, lambda: self.client.get_cloud(ids[0]), "cloud_id")
        self.assertCode(C.NOT_FOUND, lambda: self.client.read_cloud(ids[0]), "cloud_id")
        self.assertCode(C.NOT_FOUND, lambda: self.client.delete_cloud(ids[0]), "cloud_id")
        self.assertNotIn(ids[0], [c.cloud_id for c in self.client.list_clouds()])
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.client.get_cloud(""), "cloud_id")
        with self.assertRaises(grpc.RpcError) as ctx:
            stub.ListClouds(cloud_pb2.ListCloudsRequest(page_token="x"))
        self.assertEqual(ctx.exception.code(), C.INVALID_ARGUMENT)

    def assertRefusedAndNothingStored(self, code, field, requests):
        before = (len(self.client.list_clouds()), bytes_under(self.blobs))
        stub = cloud_pb2_grpc.CloudServiceStub(self.server.channel())
        with self.assertRaises(grpc.RpcError) as ctx:
            stub.UploadCloud(iter(requests), timeout=60)
        self.assertEqual(ctx.exception.code(), code, ctx.exception.details())
        self.assertTrue(ctx.exception.details().startswith(field), ctx.exception.details())
        self.assertEqual((len(self.client.list_clouds()), bytes_under(self.blobs)), before)
        return ctx.exception.details()

    def test_open3d_reads_every_field_of_vscans_files(self):
        """Open3D's tensor reader keeps custom attributes of the types it knows; every field vscan
        writes must be one of them, value for value."""
        sent = parse_ply(self.read_bytes(self.ply))
        for path, column in ((self.ply, 1), (self.pcd, 2)):
            cloud = o3d.t.io.read_point_cloud(path)
            for attribute, *names in O3D_ATTRIBUTES:
                np.testing.assert_array_equal(open3d_values(cloud, names[column - 1]),
                                              getattr(sent, attribute).astype(np.float64), err_msg=f"{path} {attribute}")
            self.assertEqual(cloud.point["instance"].dtype, o3d.core.int32)
            self.assertEqual(cloud.point["status"].dtype, o3d.core.uint8)

    def test_an_organised_scan_is_its_range_image(self):
        path = os.path.join(self.tmp.name, "organised.pcd")
        out = run("--json", "scan", self.scene, "-o", path, "--organized", "--width", "96", "--height", "72",
                  "--hfov", "40", "--eye", "0.3,0.2,0.5", "--target", "0,0.1,0", "--up", "0,1,0",
                  "--fields", "position,range,instance", server=self.server)
        self.assertEqual(out.returncode, 0, out.stderr)
        pose = np.reshape([float(v) for v in json.loads(out.stdout)["header"]["sensorPose"]["values"]], (4, 4))
        flat = os.path.join(self.tmp.name, "flat.ply")
        out = run("-q", "scan", self.scene, "-o", flat, "--width", "96", "--height", "72", "--hfov", "40",
                  "--eye", "0.3,0.2,0.5", "--target", "0,0.1,0", "--up", "0,1,0", "--fields", "position,range,instance,pixel",
                  server=self.server)
        self.assertEqual(out.returncode, 0, out.stderr)
        data = self.read_bytes(path)
        header = pcd_header(data)
        self.assertEqual((header["WIDTH"], header["HEIGHT"], header["POINTS"]), (["96"], ["72"], [str(96 * 72)]))
        self.assertEqual(header["FIELDS"], ["x", "y", "z", "range", "instance", "pixel"])
        # VIEWPOINT is the sensor pose: tx ty tz qw qx qy qz.
        viewpoint = np.array([float(v) for v in header["VIEWPOINT"]])
        np.testing.assert_allclose(viewpoint[:3], pose[:3, 3], atol=1e-6)
        w, x, y, z = viewpoint[3:]
        rotation = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                             [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                             [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        np.testing.assert_allclose(rotation, pose[:3, :3], atol=1e-6)
        # Each point of the flat scan sits at its pixel; every other pixel is a NaN hole.
        body = data[data.index(b"DATA binary\n") + len(b"DATA binary\n"):]
        grid = np.frombuffer(body, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("range", "<f4"),
                                          ("instance", "<i4"), ("pixel", "<i4")], count=96 * 72)
        points = parse_ply(self.read_bytes(flat))
        self.assertGreater(len(points), 100)
        np.testing.assert_array_equal(grid["pixel"], np.arange(96 * 72))
        hit = np.zeros(96 * 72, dtype=bool)
        hit[points.pixels] = True
        np.testing.assert_array_equal(np.stack([grid["x"], grid["y"], grid["z"]], axis=1)[points.pixels],
                                      points.positions)
        np.testing.assert_array_equal(grid["range"][points.pixels], points.ranges)
        self.assertTrue(np.isnan(grid["x"][~hit]).all() and np.isnan(grid["range"][~hit]).all())
        np.testing.assert_array_equal(grid["instance"][points.pixels], points.instance_ids)
        self.assertTrue((grid["instance"][~hit] == 0).all() and (points.instance_ids > 0).any())
        # Open3D reads it; an upload keeps the points and drops the holes.
        self.assertEqual(len(o3d.t.io.read_point_cloud(path).point["positions"]), 96 * 72)
        cloud = self.client.upload_cloud(path)
        self.assertEqual(cloud.points, len(points))
        refused = run("scan", self.scene, "-o", os.path.join(self.tmp.name, "o.ply"), "--organized",
                      "--eye", "0,0.1,0.5", "--target", "0,0.1,0", "--up", "0,1,0", server=self.server)
        self.assertEqual(refused.returncode, 2, refused.stderr)
        self.assertIn("--organized writes a PCD", refused.stderr)

    def upload_requests(self, data, **header):
        return [cloud_pb2.UploadCloudRequest(header=cloud_pb2.CloudHeader(**header)),
                cloud_pb2.UploadCloudRequest(chunk=data)]

    def test_bad_uploads_name_their_field_and_leave_nothing(self):
        good = xyz_ply([(0, 0, 0), (1, 1, 1)])
        scan = self.read_bytes(self.ply)
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "cloud data: ", self.upload_requests(scan[:-9]))
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "cloud data: ",
                                           self.upload_requests(good, format=cloud_pb2.CLOUD_FORMAT_PCD))
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "header.format: ",
                                           self.upload_requests(b"solid cube\nendsolid\n"))
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "cloud data: ", self.upload_requests(xyz_ply([])))
        nan = self.assertRefusedAndNothingStored(
            C.INVALID_ARGUMENT, "cloud data: points[1] (x, y, z): NaN",
            self.upload_requests(xyz_ply([(0, 0, 0), (0, math.nan, 0)])))
        self.assertIn("NaN or infinite", nan)
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "cloud data: points[0] (x, y, z): beyond 10 km",
                                           self.upload_requests(xyz_ply([(2e4, 0, 0)])))
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "header: sent twice", [
            cloud_pb2.UploadCloudRequest(header=cloud_pb2.CloudHeader(name="a")),
            cloud_pb2.UploadCloudRequest(header=cloud_pb2.CloudHeader(name="b")),
            cloud_pb2.UploadCloudRequest(chunk=good)])
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "header: the first message",
                                           [cloud_pb2.UploadCloudRequest(chunk=good)])
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "header.size_bytes: ",
                                           self.upload_requests(good, size_bytes=len(good) + 1))
        self.assertRefusedAndNothingStored(C.RESOURCE_EXHAUSTED, "header.size_bytes: ",
                                           self.upload_requests(good, size_bytes=1 << 40))
        self.assertRefusedAndNothingStored(C.NOT_FOUND, "header.scene_id: ",
                                           self.upload_requests(good, scene_id="scn_0000000000000000"))
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "header.sensor_pose.matrix", self.upload_requests(
            good, sensor_pose=common_pb2.Pose(matrix=common_pb2.Matrix4(values=[2] + [0] * 15))))
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "header.camera.intrinsics.fx", self.upload_requests(
            good, camera=cloud_pb2.CloudCamera(width=64, height=48, near=0.1, far=2)))
        # An absurd size is blamed on the size, not on the focal length that fits no such image.
        self.assertRefusedAndNothingStored(C.RESOURCE_EXHAUSTED, "header.camera.width", self.upload_requests(
            good, camera=cloud_pb2.CloudCamera(width=1 << 31, height=48, near=0.1, far=2,
                                               intrinsics=sensor_pb2.Intrinsics(fx=50, fy=50, cx=32, cy=24))))
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "header.name", self.upload_requests(good, name="a\nb"))
        self.assertRefusedAndNothingStored(C.INVALID_ARGUMENT, "header.frame", self.upload_requests(good, frame=9))


def pcl_expected():
    """The 200 PointXYZINormal points tests/integration/data/pcl holds (its README)."""
    i = np.arange(200, dtype=np.float32)
    a = np.float32(0.05) * i
    positions = np.stack([np.float32(0.1) * np.cos(a), np.float32(0.1) * np.sin(a),
                          np.float32(0.5) + np.float32(0.001) * i], axis=1).astype(np.float32)
    normals = np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], axis=1).astype(np.float32)
    return positions, normals, (np.float32(0.005) * i).astype(np.float32)


class ForeignFileUploadTest(unittest.TestCase):
    """Files Open3D and PCL write, in each of their encodings, uploaded through the CLI and read back
    from the server; hostile variants refused as INVALID_ARGUMENT naming what is wrong."""

    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.addClassCleanup(cls.server.cleanup)
        cls.client = Client(cls.server.address, stream_timeout=120)
        cls.addClassCleanup(cls.client.close)
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-foreign-")
        cls.addClassCleanup(cls.tmp.cleanup)

    def upload_with_cli(self, path):
        out = run("--json", "cloud", "upload", path, server=self.server)
        self.assertEqual(out.returncode, 0, out.stderr)
        cloud_id = json.loads(out.stdout)["cloudId"]
        back = os.path.join(self.tmp.name, cloud_id + ".ply")
        out = run("-q", "cloud", "download", cloud_id, "-o", back, server=self.server)
        self.assertEqual(out.returncode, 0, out.stderr)
        with open(back, "rb") as f:
            return parse_ply(f.read())

    def check(self, points, positions, normals, intensities, text, ulp=False):
        # Text encodings print a limited number of digits (Open3D's PLY six, PCL's eight); ulp: the
        # expected values come from numpy's float32 sin and cos, which may differ from the C
        # library's that made the file by a unit in the last place.
        tolerance = dict(rtol=1e-5, atol=1e-6) if text else dict(rtol=2.5e-7, atol=1e-9) if ulp else dict(rtol=0, atol=0)
        self.assertEqual(len(points), len(positions))
        np.testing.assert_allclose(points.positions, positions, **tolerance)
        np.testing.assert_allclose(points.normals, normals, **tolerance)
        np.testing.assert_allclose(points.intensities, intensities, **tolerance)

    def test_files_open3d_writes(self):
        rng = np.random.default_rng(7)
        positions = rng.uniform(-0.3, 0.3, (500, 3)).astype(np.float32)
        normals = rng.normal(size=(500, 3)).astype(np.float32)
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        intensities = rng.uniform(0, 1, (500, 1)).astype(np.float32)
        cloud = o3d.t.geometry.PointCloud()
        cloud.point.positions = o3d.core.Tensor(positions)
        cloud.point.normals = o3d.core.Tensor(normals)
        cloud.point.intensity = o3d.core.Tensor(intensities)
        for name, options in (("ascii.ply", dict(write_ascii=True)), ("binary.ply", {}),
                              ("ascii.pcd", dict(write_ascii=True)), ("binary.pcd", {}),
                              ("compressed.pcd", dict(compressed=True))):
            with self.subTest(name):
                path = os.path.join(self.tmp.name, "open3d_" + name)
                self.assertTrue(o3d.t.io.write_point_cloud(path, cloud, **options))
                points = self.upload_with_cli(path)
                self.check(points, positions, normals, intensities[:, 0], name.startswith("ascii"))

    def test_files_pcl_writes(self):
        positions, normals, intensities = pcl_expected()
        for name in ("pcl_ascii.ply", "pcl_binary.ply", "pcl_ascii.pcd", "pcl_binary.pcd", "pcl_compressed.pcd"):
            with self.subTest(name):
                points = self.upload_with_cli(os.path.join(DATA, "pcl", name))
                self.check(points, positions, normals, intensities, "ascii" in name, ulp=True)

    def test_organised_pcl_files_keep_their_points_and_drop_their_holes(self):
        u, v = np.meshgrid(np.arange(8), np.arange(6))
        keep = ((u + v) % 3 != 0).ravel()
        expected = np.stack([0.01 * u.ravel(), 0.01 * v.ravel(), np.full(48, 0.75)], axis=1)[keep]
        for name in ("pcl_organised_ascii.pcd", "pcl_organised_binary.pcd", "pcl_organised_compressed.pcd"):
            with self.subTest(name):
                points = self.client.read_cloud_points(
                    self.client.upload_cloud(os.path.join(DATA, "pcl", name)).cloud_id)
                np.testing.assert_allclose(points.positions, expected.astype(np.float32), rtol=1e-6)

    def refused(self, data, *needles):
        with self.assertRaises(VscanError) as ctx:
            self.client.upload_cloud(data=data, name="hostile")
        self.assertEqual(ctx.exception.code, C.INVALID_ARGUMENT, ctx.exception.message)
        self.assertTrue(ctx.exception.message.startswith("cloud data: "), ctx.exception.message)
        for needle in needles:
            self.assertIn(needle, ctx.exception.message)

    def test_hostile_variants_are_invalid_and_name_what_is_wrong(self):
        before = len(self.client.list_clouds())
        with open(os.path.join(DATA, "pcl", "pcl_ascii.ply"), "rb") as f:
            ascii_ply = f.read()
        with open(os.path.join(DATA, "pcl", "pcl_ascii.pcd"), "rb") as f:
            ascii_pcd = f.read()
        with open(os.path.join(DATA, "pcl", "pcl_compressed.pcd"), "rb") as f:
            compressed = f.read()
        body = ascii_ply.index(b"end_header\n") + len(b"end_header\n")
        # Truncated: the text stops inside the vertices.
        self.refused(ascii_ply[:body + 300], "truncated")
        self.refused(ascii_pcd[:-40], "truncated")
        self.refused(compressed[:-100], "truncated", "compressed bytes")
        # A count that lies.
        self.refused(ascii_ply.replace(b"element vertex 200", b"element vertex 900"), "truncated", "vertex")
        self.refused(ascii_pcd.replace(b"POINTS 200", b"POINTS 201"), "truncated")
        self.refused(compressed.replace(b"POINTS 200", b"POINTS 199"), "POINTS 199")
        # Huge declared sizes over a few bytes.
        self.refused(ascii_ply.replace(b"element vertex 200", b"element vertex 4000000000"), "truncated")
        self.refused(ascii_pcd.replace(b"POINTS 200", b"POINTS 18446744073709551615"), "truncated")
        huge = compressed.replace(b"POINTS 200", b"POINTS 100000000")
        sizes = huge.index(b"DATA binary_compressed\n") + len(b"DATA binary_compressed\n")
        huge = huge[:sizes + 4] + struct.pack("<I", 100000000 * 32) + huge[sizes + 8:]  # 32-byte points
        self.refused(huge, "more than LZF can expand to")
        # A value that is no number, named by its point and property.
        self.refused(ascii_pcd.replace(b"\n0.1 0 0.5", b"\n0.1 zero 0.5", 1), "point 0, property 'y'",
                     "'zero' is not a number")
        self.assertEqual(len(self.client.list_clouds()), before)


class CloudLimitTest(unittest.TestCase):
    """--max-upload-mib bounds the bytes sent and the cloud they hold."""

    def test_uploads_beyond_the_limit_are_resource_exhausted(self):
        server = Server(extra_args=["--max-upload-mib", "1"]).start()
        self.addCleanup(server.cleanup)
        client = Client(server.address, stream_timeout=60)
        self.addCleanup(client.close)
        blobs = os.path.join(server.data_dir, "store", "blobs")
        before = bytes_under(blobs)
        with self.assertRaises(VscanError) as ctx:
            client.upload_cloud(data=xyz_ply([(0, 0, 0)] * 100000), name="big")  # 1.2 MB
        self.assertEqual(ctx.exception.code, C.RESOURCE_EXHAUSTED, ctx.exception.message)
        self.assertIn("--max-upload-mib", ctx.exception.message)
        # A small file of one-byte coordinates that would pass the limit once read as floats.
        head = b"ply\nformat binary_little_endian 1.0\nelement vertex 200000\nproperty uchar x\nproperty uchar y\n" \
               b"property uchar z\nend_header\n"
        with self.assertRaises(VscanError) as ctx:
            client.upload_cloud(data=head + bytes(600000), name="grows")
        self.assertEqual(ctx.exception.code, C.RESOURCE_EXHAUSTED, ctx.exception.message)
        self.assertTrue(ctx.exception.message.startswith("cloud data: "), ctx.exception.message)
        self.assertEqual(client.list_clouds(), [])
        self.assertEqual(bytes_under(blobs), before)
        self.assertEqual(client.upload_cloud(data=xyz_ply([(0, 0, 0)] * 1000)).points, 1000)


class CampaignCloudsTest(unittest.TestCase):
    """A campaign's captured scans are clouds of its job, with their poses, until the job goes."""

    def test_a_campaigns_scans_are_clouds_until_its_job_is_deleted(self):
        server = Server().start()
        self.addCleanup(server.cleanup)
        fx = CampaignFixture(server)
        self.addCleanup(fx.close)
        client = Client(server.address, stream_timeout=300)
        self.addCleanup(client.close)
        blobs = os.path.join(server.data_dir, "store", "blobs")
        s = spec(fx.scene.scene_id, fx.mount, viewpoints=[((0.25, 0.0, 0.30), (0.0, 0.0, 0.11))], rotations=2,
                 step=90.0, seed=5, sensor=camera(160, 120), apply_encoder_noise=True)
        job = client.start_campaign(spec=s)
        done = client.wait_job(job.job_id, timeout=300)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        scans = [a for a in done.artifacts if a.HasField("scan")]
        self.assertEqual(len(scans), 2)

        clouds = client.list_clouds(job_id=job.job_id)
        self.assertEqual(sorted(c.name for c in clouds), sorted(a.name for a in scans))
        self.assertEqual(len([c for c in client.list_clouds() if c.job_id == job.job_id]), 2)
        for artifact in scans:
            cloud = next(c for c in clouds if c.name == artifact.name)
            self.assertEqual(cloud.origin, cloud_pb2.CLOUD_ORIGIN_CAMPAIGN_SCAN)
            self.assertEqual(cloud.scene_id, fx.scene.scene_id)
            self.assertEqual(cloud.frame, scan_pb2.FRAME_WORLD)
            self.assertEqual(cloud.points, artifact.scan.points)
            self.assertEqual(cloud.size_bytes, artifact.size_bytes)
            self.assertEqual(cloud.table_angle_deg, artifact.scan.table_angle_deg)
            self.assertEqual(list(cloud.sensor_pose.values), list(artifact.scan.sensor_pose.values))
            self.assertEqual((cloud.camera.width, cloud.camera.height), (160, 120))
            self.assertAlmostEqual(cloud.camera.intrinsics.fx, 80 / math.tan(math.radians(22.5)))
            _, cloud_bytes = client.read_cloud(cloud.cloud_id)
            _, artifact_bytes = client.read_artifact(job.job_id, artifact.artifact_id)
            self.assertEqual(cloud_bytes, artifact_bytes)
            with self.assertRaises(VscanError) as ctx:
                client.delete_cloud(cloud.cloud_id)
            self.assertEqual(ctx.exception.code, C.FAILED_PRECONDITION)
            self.assertTrue(ctx.exception.message.startswith("cloud_id: "), ctx.exception.message)

        before = bytes_under(blobs)
        deleted = client.delete_job(job.job_id)
        self.assertEqual(deleted.removed_files, 3)
        self.assertEqual(bytes_under(blobs), before - deleted.removed_bytes)
        self.assertEqual(client.list_clouds(job_id=job.job_id), [])
        for cloud in clouds:
            with self.assertRaises(VscanError) as ctx:
                client.get_cloud(cloud.cloud_id)
            self.assertEqual(ctx.exception.code, C.NOT_FOUND)


class CloudCliTest(unittest.TestCase):
    def test_upload_list_get_download_delete(self):
        server = Server().start()
        self.addCleanup(server.cleanup)
        tmp = tempfile.TemporaryDirectory(prefix="vscan-cloud-cli-")
        self.addCleanup(tmp.cleanup)
        source = os.path.join(tmp.name, "in.ply")
        with open(source, "wb") as f:
            f.write(xyz_ply([(0.0, 0.0, 1.0), (0.5, 0.25, 1.5), (-0.5, 0.0, 2.0)]))

        def ok(*args):
            out = run(*args, server=server)
            self.assertEqual(out.returncode, 0, out.stderr)
            return out.stdout.strip()

        uploaded = json.loads(ok("--json", "cloud", "upload", source, "--name", "three", "--frame", "sensor",
                                 "--position", "1,2,3", "--rpy", "0,0,90", "--camera", "64,48,50,50,31.5,23.5,0.1,5"))
        cloud_id = uploaded["cloudId"]
        self.assertEqual(uploaded["points"], "3")
        self.assertEqual(uploaded["frame"], "FRAME_SENSOR")
        pose = np.reshape([float(v) for v in uploaded["sensorPose"]["values"]], (4, 4))
        np.testing.assert_allclose(pose[:3, 3], (1, 2, 3))
        np.testing.assert_allclose(pose[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-12)
        self.assertEqual(uploaded["camera"]["width"], 64)

        self.assertEqual(ok("-q", "cloud", "list"), cloud_id)
        self.assertIn("three  3 points (position)  uploaded", ok("cloud", "get", cloud_id))

        as_ply = os.path.join(tmp.name, "out.ply")
        ok("-q", "cloud", "download", cloud_id, "-o", as_ply)
        with open(as_ply, "rb") as a, open(source, "rb") as b:
            self.assertEqual(a.read(), b.read())
        as_pcd = os.path.join(tmp.name, "out.pcd")
        ok("-q", "cloud", "download", cloud_id, "-o", as_pcd)
        again = json.loads(ok("--json", "cloud", "upload", as_pcd))
        self.assertEqual(again["sha256"], uploaded["sha256"])

        deleted = json.loads(ok("--json", "cloud", "delete", again["cloudId"]))
        self.assertEqual(deleted["removedFiles"], 0)  # the first upload holds the same bytes
        deleted = json.loads(ok("--json", "cloud", "delete", cloud_id))
        self.assertEqual(deleted["removedFiles"], 1)
        self.assertEqual(ok("-q", "cloud", "list"), "")

        missing = run("cloud", "get", cloud_id, server=server)
        self.assertEqual(missing.returncode, 3, missing.stderr)
        self.assertIn("NOT_FOUND", missing.stderr)
        unreadable = run("cloud", "upload", os.path.join(tmp.name, "nope.ply"), server=server)
        self.assertEqual(unreadable.returncode, 5, unreadable.stderr)
        bad_file = os.path.join(tmp.name, "bad.ply")
        with open(bad_file, "wb") as f:
            f.write(b"ply\nformat ascii 1.0\nelement vertex 0\nend_header\n")
        refused = run("cloud", "upload", bad_file, server=server)
        self.assertEqual(refused.returncode, 3, refused.stderr)
        self.assertIn("cloud data", refused.stderr)
        usage = run("cloud", "download", cloud_id, "-o", os.path.join(tmp.name, "out.xyz"), server=server)
        self.assertEqual(usage.returncode, 2, usage.stderr)


if __name__ == "__main__":
    unittest.main()
