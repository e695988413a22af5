"""vscan against an in-process fake server (needs VSCAN_PY_STUBS or the stubs on sys.path)."""

import os
import sys
import tempfile
import unittest

import grpc
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from fake_server import N_POINTS, FakeServer  # noqa: E402
from vscan import Client, VscanError, parse_ply  # noqa: E402
from vscan._stubs import common_pb2, scan_pb2, scene_pb2  # noqa: E402


class ClientTest(unittest.TestCase):
    def setUp(self):
        self.fake = FakeServer()
        self.scenes, self.scans = self.fake.scenes, self.fake.scans
        self.client = Client(self.fake.address, token="tok")

    def tearDown(self):
        self.client.close()
        self.fake.stop()

    def test_health(self):
        self.assertEqual(self.client.health(), "SERVING")

    def test_create_scene_sends_token(self):
        self.assertEqual(self.client.create_scene("x").name, "x")
        self.assertEqual(self.scenes.metadata.get("authorization"), "Bearer tok")

    def test_list_scenes_follows_pages(self):
        self.assertEqual([s.scene_id for s in self.client.list_scenes()], ["s0", "s1", "s2", "s3"])

    def test_errors_carry_code(self):
        with self.assertRaises(VscanError) as caught:
            self.client.get_scene("nope")
        self.assertEqual(caught.exception.code, grpc.StatusCode.NOT_FOUND)
        self.assertIn("nope", caught.exception.message)
        self.assertFalse(caught.exception.unreachable)

    def test_unreachable(self):
        with Client("127.0.0.1:1", timeout=2) as c, self.assertRaises(VscanError) as caught:
            c.list_scenes()
        self.assertTrue(caught.exception.unreachable)

    def test_upload_mesh(self):
        with tempfile.NamedTemporaryFile(suffix=".STL") as f:
            f.write(bytes(range(256)) * 10000)
            f.flush()
            mesh = self.client.upload_mesh(f.name, unit="mm", scale=2)
        self.assertEqual(mesh.mesh_id, "mesh-1")
        self.assertEqual(self.scenes.parts[0], "header")
        self.assertEqual(self.scenes.parts[1:], [1 << 20, 1 << 20, 2560000 - (2 << 20)])
        self.assertEqual(self.scenes.header.size_bytes, 2560000)
        self.assertEqual(self.scenes.header.format, scene_pb2.MESH_FORMAT_STL)
        self.assertEqual(self.scenes.header.unit, common_pb2.LENGTH_UNIT_MILLIMETRE)
        self.assertEqual(self.scenes.header.scale, 2)
        self.assertEqual(len(self.scenes.data), 2560000)

    def test_add_object_pose(self):
        obj = self.client.add_object("scene-1", "mesh-1", position=(1, 2, 3), quat=(0, 0, 0, 1), label="a")
        self.assertEqual(obj.object_id, "obj-1")
        q = self.scenes.last_add.pose.quaternion
        self.assertEqual((q.translation.x, q.translation.z, q.qz), (1, 3, 1))
        self.client.add_object("scene-1", "mesh-1", matrix=np.eye(4))
        self.assertEqual(list(self.scenes.last_add.pose.matrix.values), list(np.eye(4).ravel()))
        with self.assertRaises(ValueError):
            self.client.add_object("scene-1", "mesh-1", matrix=np.eye(3))

    def test_materials_travel_on_upload_and_placement(self):
        with tempfile.NamedTemporaryFile(suffix=".stl") as f:
            f.write(b"solid x\nendsolid x\n")
            f.flush()
            self.client.upload_mesh(f.name, unit="m", material="machined-aluminium")
            self.assertEqual(self.scenes.header.material.preset, "machined-aluminium")
            self.client.upload_mesh(f.name, unit="m")
            self.assertFalse(self.scenes.header.HasField("material"))
        values = dict(diffuse_albedo=0.25, metallic=1, roughness=0.5, specular_reflectance=0.04)
        self.client.add_object("scene-1", "mesh-1", material=values)
        sent = self.scenes.last_add.material
        self.assertEqual(sent.preset, "")
        self.assertEqual((sent.values.diffuse_albedo, sent.values.metallic, sent.values.roughness),
                         (0.25, 1.0, 0.5))
        self.client.add_object("scene-1", "mesh-1")
        self.assertFalse(self.scenes.last_add.HasField("material"))
        with self.assertRaises(ValueError):
            self.client.add_object("scene-1", "mesh-1", material={"diffuse_albedo": 0.5})
        with self.assertRaises(TypeError):
            self.client.add_object("scene-1", "mesh-1", material=0.5)

    def test_set_table(self):
        table = self.client.set_table("scene-1", 30, axis=(0, 0, 1))
        self.assertTrue(table.enabled)
        self.assertEqual(table.angle_deg, 30)

    def test_scan_to_numpy(self):
        seen = []
        result = self.client.scan("scene-1", eye=(1, 0, 0), target=(0, 0, 0), fields=["position", "range"],
                                  frame="sensor", table_angle_deg=10, progress=lambda d, t: seen.append((d, t)))
        request = self.scans.last_request
        self.assertEqual(request.pose.look_at.eye.x, 1)
        self.assertEqual(request.frame, scan_pb2.FRAME_SENSOR)
        self.assertEqual(request.table_angle_deg, 10)
        self.assertEqual(list(request.fields), [scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_RANGE])
        self.assertEqual(len(result), N_POINTS)
        self.assertEqual(result.positions.shape, (N_POINTS, 3))
        self.assertEqual(result.positions.dtype, np.float32)
        np.testing.assert_array_equal(result.positions, self.scans.cloud["positions"])
        np.testing.assert_array_equal(result.normals, self.scans.cloud["normals"])
        np.testing.assert_array_equal(result.ranges, self.scans.cloud["ranges"])
        self.assertEqual(result.instance_ids.dtype, np.uint32)
        self.assertIsNone(result.pixels)
        self.assertEqual(result.stats.hit_ratio, 0.5)
        self.assertEqual(seen[-1], (N_POINTS, N_POINTS))
        result.positions[0, 0] = 42  # writable

    def test_scan_short_stream_is_data_loss(self):
        self.scans.announced = N_POINTS + 1
        with self.assertRaises(VscanError) as caught:
            self.client.scan("scene-1", eye=(1, 0, 0), target=(0, 0, 0))
        self.assertEqual(caught.exception.code, grpc.StatusCode.DATA_LOSS)

    def test_scan_needs_a_pose(self):
        with self.assertRaises(ValueError):
            self.client.scan("scene-1")


class ParsePlyTest(unittest.TestCase):
    def test_every_field_vscan_writes_becomes_an_array(self):
        props = [("x", "float"), ("y", "float"), ("z", "float"), ("nx", "float"), ("ny", "float"), ("nz", "float"),
                 ("range", "float"), ("intensity", "float"), ("instance", "uint"), ("pixel", "uint"),
                 ("clean_x", "float"), ("clean_y", "float"), ("clean_z", "float"), ("incidence", "float"),
                 ("status", "uchar"), ("enx", "float"), ("eny", "float"), ("enz", "float")]
        dtype = np.dtype([(name, {"float": "<f4", "uint": "<u4", "uchar": "u1"}[kind]) for name, kind in props])
        rows = np.zeros(3, dtype=dtype)
        for i, name in enumerate(dtype.names):
            rows[name] = np.arange(3) + 10 * i
        head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + \
            "".join(f"property {kind} {name}\n" for name, kind in props) + "end_header\n"
        points = parse_ply(head.encode() + rows.tobytes())
        self.assertEqual(len(points), 3)
        np.testing.assert_array_equal(points.positions[1], [1, 11, 21])
        self.assertEqual(points.positions.dtype, np.float32)
        np.testing.assert_array_equal(points.instance_ids, [80, 81, 82])
        self.assertEqual(points.instance_ids.dtype, np.uint32)
        self.assertEqual(points.statuses.dtype, np.uint8)
        np.testing.assert_array_equal(points.estimated_normals[:, 2], [170, 171, 172])

    def test_only_binary_vertices_are_read(self):
        with self.assertRaises(ValueError):
            parse_ply(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n")
        with self.assertRaises(ValueError):
            parse_ply(b"# .PCD v0.7\n")
        positions_only = b"ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n" \
            b"property float y\nproperty float z\nend_header\n" + np.float32([1, 2, 3]).tobytes()
        self.assertIsNone(parse_ply(positions_only).normals)


if __name__ == "__main__":
    unittest.main()


class BinFillSpecTest(unittest.TestCase):
    def test_picks_as_a_dict_become_the_specs_pick_section(self):
        from vscan.bins import bin_fill_spec
        picks = {"mount_id": "mnt_1", "gripper": {"suction": {"diameter": 0.012}},
                 "grasp_options": {"max_grasps": 200}, "pick_options": {"body_length": 0.08}}
        spec = bin_fill_spec("scn_1", (0.3, 0.2, 0.1), [], picks=picks)
        self.assertTrue(spec.HasField("picks"))
        self.assertEqual(spec.picks.mount_id, "mnt_1")
        self.assertEqual(spec.picks.gripper.suction.diameter, 0.012)
        self.assertEqual(spec.picks.grasp_options.max_grasps, 200)
        self.assertEqual(spec.picks.pick_options.body_length, 0.08)
        self.assertFalse(bin_fill_spec("scn_1", (0.3, 0.2, 0.1), []).HasField("picks"))
        with self.assertRaises(Exception):
            bin_fill_spec("scn_1", (0.3, 0.2, 0.1), [], picks={"mount": "mnt_1"})
