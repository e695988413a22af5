"""The Python client against a real vscand: scans come back as numpy arrays with real geometry."""

import math
import os
import re
import subprocess
import sys
import unittest

import numpy as np

from harness import BUILD_DIR, BUNNY, SOURCE_DIR, Server, icosphere_ply

from vscan import Client, VscanError


class PythonClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.client = Client(cls.server.address)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()

    def test_sphere_scan_in_numpy(self):
        radius, centre = 0.25, np.array([0.1, -0.2, 0.5])
        path = os.path.join(self.server.data_dir, "sphere.ply")
        with open(path, "wb") as f:
            f.write(icosphere_ply(radius, centre, 4))
        mesh = self.client.upload_mesh(path, unit="m")
        scene = self.client.create_scene("py-sphere")
        self.client.add_object(scene.scene_id, mesh.mesh_id, label="ball")
        eye = centre + np.array([0.0, -1.5, 0.3])
        result = self.client.scan(scene.scene_id, width=256, height=192, hfov_deg=35.0, eye=tuple(eye),
                                  target=tuple(centre),
                                  fields=["position", "normal", "range", "intensity", "instance", "pixel"])
        self.assertEqual(result.positions.dtype, np.float32)
        self.assertEqual(result.positions.shape, (len(result), 3))
        self.assertEqual(len(result), result.stats.streamed_points)
        self.assertGreater(len(result), 1000)
        # Chunks were written into one array per field, allocated for every ray: no join copy.
        self.assertEqual(result.header.points, 0)
        for array in (result.positions, result.normals, result.pixels):
            self.assertIsNotNone(array.base)
            self.assertGreaterEqual(array.base.size, result.header.rays * (array.size // len(result)))
        r = np.linalg.norm(result.positions - centre, axis=1)
        self.assertLess(np.max(np.abs(r - radius)), 0.003 * radius)
        np.testing.assert_allclose(result.ranges, np.linalg.norm(result.positions - eye, axis=1), rtol=1e-5)
        radial = (result.positions - centre) / r[:, None]
        self.assertGreater(np.min(np.sum(result.normals * radial, axis=1)), math.cos(math.radians(6)))
        self.assertTrue(np.all(result.instance_ids == 1))
        # Default lighting: I = cos(incidence) / 1, the normal against the unit ray.
        rays = (result.positions - eye) / result.ranges[:, None]
        expected = np.abs(np.sum(result.normals * rays, axis=1))
        np.testing.assert_allclose(result.intensities, expected, atol=1e-5)

    def test_sensor_frame_points_have_positive_depth(self):
        mesh = self.client.upload_mesh(BUNNY, unit="m")
        scene = self.client.create_scene("py-bunny")
        self.client.add_object(scene.scene_id, mesh.mesh_id)
        result = self.client.scan(scene.scene_id, width=200, height=160, hfov_deg=40.0, eye=(0.0, 0.1, 0.5),
                                  target=(0.0, 0.1, 0.0), up=(0, 1, 0), frame="sensor", near=0.2, far=1.0)
        self.assertGreater(len(result), 1000)
        z = result.positions[:, 2]
        self.assertTrue(np.all((z >= 0.2) & (z <= 1.0)))

    def test_errors_raise_with_codes(self):
        with self.assertRaises(VscanError) as ctx:
            self.client.get_scene("scn_missing")
        self.assertEqual(ctx.exception.code.name, "NOT_FOUND")

    def test_example_runs(self):
        env = dict(os.environ, VSCAN_PY_STUBS=os.path.join(BUILD_DIR, "python"),
                   PYTHONPATH=os.path.join(SOURCE_DIR, "client", "python"))
        out = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "client", "python", "examples",
                                                           "scan_to_numpy.py"),
                              "--server", self.server.address, "--mesh", BUNNY, "--unit", "m"],
                             env=env, capture_output=True, text=True, timeout=120)
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertIn("points", out.stdout)

    def test_campaign_example_merges_scans_in_the_bunny_frame(self):
        env = dict(os.environ, VSCAN_PY_STUBS=os.path.join(BUILD_DIR, "python"),
                   PYTHONPATH=os.path.join(SOURCE_DIR, "client", "python"))
        out = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "client", "python", "examples",
                                                           "campaign_to_numpy.py"),
                              "--server", self.server.address, "--rotations", "4"],
                             env=env, capture_output=True, text=True, timeout=300)
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertIn("16 scans of 16 steps", out.stdout)
        # Turned back by their table angles, the scans form one bunny: about 15 cm tall, standing on z = 0.
        bounds = re.search(r"bounds \[([^\]]+)\] \.\. \[([^\]]+)\]", out.stdout)
        self.assertIsNotNone(bounds, out.stdout)
        lo = np.array([float(v) for v in bounds.group(1).split()])
        hi = np.array([float(v) for v in bounds.group(2).split()])
        self.assertAlmostEqual(lo[2], 0.0, delta=0.005)
        self.assertAlmostEqual(hi[2], 0.154, delta=0.01)
        # 15.6 cm nose to tail along x, 12 cm across: a quarter turn left unturned would swap them.
        self.assertAlmostEqual(hi[0] - lo[0], 0.156, delta=0.008)
        self.assertAlmostEqual(hi[1] - lo[1], 0.121, delta=0.008)


if __name__ == "__main__":
    unittest.main()
