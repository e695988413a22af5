"""Per-pixel images through a real vscand, the Python client and the CLI: a white and a black square
under the returned light, with a wall beyond the far limit; each pixel's reason agrees with the
status of its ray in an include_rejected scan, the grey image follows the measured electrons, the
points do not change when the images are asked for, and the CLI's PNGs read back in Open3D."""

import os
import subprocess
import tempfile
import unittest

import numpy as np
import open3d as o3d

from harness import VSCAN, Server
from test_returned_light import EYE, TARGET, add_squares, quad_ply
from vscan import Client
from vscan.v1 import scan_pb2

WIDTH, HEIGHT = 160, 120
LIGHT = {"emitter_w_per_sr": 0.0002, "full_well_e": 20000}


class PixelImagesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.server = Server().start()
        cls.client = Client(cls.server.address)
        wall = os.path.join(cls.tmp.name, "wall.ply")
        # Far behind the squares, beyond the 2 m far limit but within four times it.
        quad_ply(wall, [(-3, 3, -2), (3, 3, -2), (3, 3, 4), (-3, 3, 4)])
        cls.scene = cls.client.create_scene("pixel-images").scene_id
        cls.white_id, cls.black_id = add_squares(cls.client, cls.tmp.name, cls.scene)
        cls.client.add_object(cls.scene, cls.client.upload_mesh(wall, "m").mesh_id)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()
        cls.tmp.cleanup()

    def scan(self, **kwargs):
        return self.client.scan(self.scene, width=WIDTH, height=HEIGHT, hfov_deg=70, eye=EYE, target=TARGET,
                                far=2.0, seed=5, returned_light=LIGHT, **kwargs)

    def test_each_pixel_has_the_reason_of_its_ray_and_the_grey_of_its_signal(self):
        every = self.scan(fields=["position", "intensity", "instance", "pixel", "status"], include_rejected=True)
        imaged = self.scan(fields=["position", "intensity", "instance", "pixel", "status"], pixel_images=True)
        self.assertEqual(imaged.reasons.shape, (HEIGHT, WIDTH))
        self.assertEqual(imaged.gray.dtype, np.uint16)
        expected = np.zeros(WIDTH * HEIGHT, dtype=np.uint8)
        expected[every.pixels] = every.statuses
        np.testing.assert_array_equal(imaged.reasons.reshape(-1), expected)
        reasons = set(np.unique(imaged.reasons).tolist())
        for status in (scan_pb2.POINT_STATUS_MEASURED, scan_pb2.POINT_STATUS_REJECTED_DARK,
                       scan_pb2.POINT_STATUS_REJECTED_OUT_OF_RANGE, scan_pb2.POINT_STATUS_UNSPECIFIED):
            self.assertIn(status, reasons)
        # The black square is dark, the white one measured, pixel by pixel through the instance ids.
        instance_at = np.zeros(WIDTH * HEIGHT, dtype=np.uint32)
        instance_at[every.pixels] = every.instance_ids
        flat = imaged.reasons.reshape(-1)
        self.assertGreater(np.mean(flat[instance_at == self.black_id] == scan_pb2.POINT_STATUS_REJECTED_DARK), 0.95)
        self.assertTrue(np.all(flat[instance_at == self.white_id] == scan_pb2.POINT_STATUS_MEASURED))
        # Grey: the measured electrons over the full well, on every pixel with a surface, rejected or not.
        grey = np.zeros(WIDTH * HEIGHT)
        grey[every.pixels] = np.clip(np.round(every.intensities * 65535.0 / LIGHT["full_well_e"]), 0, 65535)
        np.testing.assert_allclose(imaged.gray.reshape(-1), grey, atol=1)
        white, black = (np.mean(imaged.gray.reshape(-1)[instance_at == oid]) for oid in (self.white_id, self.black_id))
        self.assertAlmostEqual(white / black, 0.9 / 0.03, delta=0.05 * 30)
        self.assertTrue(np.all(imaged.gray.reshape(-1)[flat == 0] == 0))

    def test_the_points_are_the_same_with_or_without_the_images(self):
        fields = ["position", "intensity", "pixel", "status"]
        for include_rejected in (False, True):
            plain = self.scan(fields=fields, include_rejected=include_rejected)
            imaged = self.scan(fields=fields, include_rejected=include_rejected, pixel_images=True)
            self.assertIsNone(plain.reasons)
            np.testing.assert_array_equal(plain.pixels, imaged.pixels)
            np.testing.assert_array_equal(plain.positions, imaged.positions)
            np.testing.assert_array_equal(plain.statuses, imaged.statuses)
            self.assertEqual(plain.stats.rejected_dark, imaged.stats.rejected_dark)
        # A clean scan (no returned light): the fixed lighting's intensity is the grey, no ray rejected.
        clean = self.client.scan(self.scene, width=WIDTH, height=HEIGHT, hfov_deg=70, eye=EYE, target=TARGET,
                                 far=2.0, fields=["position", "pixel", "intensity"])
        clean_imaged = self.client.scan(self.scene, width=WIDTH, height=HEIGHT, hfov_deg=70, eye=EYE, target=TARGET,
                                        far=2.0, fields=["position", "pixel", "intensity"], pixel_images=True)
        self.assertEqual(clean_imaged.stats.points, len(clean))
        # The clean scan's fast path transforms each hit to the world, the measured one the sensor-frame
        # point: the same points to float rounding.
        np.testing.assert_array_equal(clean.pixels, clean_imaged.pixels)
        np.testing.assert_allclose(clean.positions, clean_imaged.positions, atol=1e-6)
        measured = clean_imaged.reasons.reshape(-1)[clean.pixels]
        self.assertTrue(np.all(measured == scan_pb2.POINT_STATUS_MEASURED))
        np.testing.assert_allclose(clean_imaged.gray.reshape(-1)[clean.pixels],
                                   np.clip(np.round(clean.intensities * 65535.0), 0, 65535), atol=1)

    def test_the_cli_writes_both_images_as_png(self):
        out = os.path.join(self.tmp.name, "cli")
        cloud = os.path.join(self.tmp.name, "cli.ply")
        ran = subprocess.run([VSCAN, "--server", self.server.address, "scan", self.scene, "-o", cloud,
                              "--width", str(WIDTH), "--height", str(HEIGHT), "--hfov", "70", "--far", "2",
                              "--eye", "0,-0.6,0.8", "--target", "0,0,0", "--seed", "5",
                              "--returned-light", "emitter_w_per_sr=0.0002,full_well_e=20000", "--images", out],
                             capture_output=True, text=True)
        self.assertEqual(ran.returncode, 0, ran.stderr)
        self.assertIn("reasons.png", ran.stdout)
        reasons = np.asarray(o3d.io.read_image(os.path.join(out, "reasons.png")))
        gray = np.asarray(o3d.io.read_image(os.path.join(out, "gray.png")))
        self.assertEqual(reasons.shape, (HEIGHT, WIDTH))
        self.assertEqual(gray.dtype, np.uint16)
        python = self.scan(fields=["position"], pixel_images=True)
        np.testing.assert_array_equal(reasons, python.reasons)
        np.testing.assert_array_equal(gray, python.gray)


if __name__ == "__main__":
    unittest.main()
