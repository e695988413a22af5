"""`vscan render` on a real scan: the PNG it writes is decoded here independently of libpng."""

import json
import os
import subprocess
import tempfile
import unittest

import numpy as np

from harness import BUNNY, VSCAN, Server, read_png


class RenderTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-render-")
        mesh = cls.run_ok("-q", "mesh", "upload", BUNNY, "--unit", "m")
        scene = cls.run_ok("-q", "scene", "create", "render")
        cls.run_ok("-q", "object", "add", scene, mesh, "--label", "bunny", "--rpy", "90,0,0", "--on-table")
        scan = ["--width", "320", "--height", "256", "--hfov", "40", "--eye", "0.5,0,0.2", "--target", "0,0,0.07",
                "--up", "0,0,1"]
        cls.cloud = os.path.join(cls.tmp.name, "bunny.ply")
        cls.run_ok("-q", "scan", scene, "-o", cls.cloud, *scan)
        cls.bare_cloud = os.path.join(cls.tmp.name, "bare.pcd")
        cls.run_ok("-q", "scan", scene, "-o", cls.bare_cloud, *scan, "--fields", "position")

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()
        cls.tmp.cleanup()

    @classmethod
    def vscan(cls, *args):
        return subprocess.run([VSCAN, "--server", cls.server.address, *args], capture_output=True, text=True,
                              timeout=120)

    @classmethod
    def run_ok(cls, *args):
        out = cls.vscan(*args)
        if out.returncode != 0:
            raise AssertionError(f"vscan {' '.join(args)} exited {out.returncode}: {out.stderr}")
        return out.stdout.strip()

    def assert_object_centred(self, image, background, min_fraction=0.02):
        mask = np.any(image != np.array(background, np.uint8), axis=2)
        height, width = mask.shape
        self.assertGreater(mask.mean(), min_fraction, "too few object pixels")
        self.assertLess(mask.mean(), 0.8, "the object should not fill the image")
        ys, xs = np.nonzero(mask)
        self.assertLess(abs(xs.mean() - width / 2), 0.15 * width)
        self.assertLess(abs(ys.mean() - height / 2), 0.15 * height)
        for corner in (image[0, 0], image[0, -1], image[-1, 0], image[-1, -1]):
            self.assertEqual(tuple(corner), tuple(background))
        return mask

    def test_default_view_frames_the_scan_on_the_requested_background(self):
        out = os.path.join(self.tmp.name, "normals.png")
        report = json.loads(self.run_ok("--json", "render", self.cloud, "-o", out, "--color", "normal",
                                        "--width", "400", "--height", "300", "--background", "20,40,60"))
        self.assertEqual(report["output"], out)
        self.assertEqual((report["width"], report["height"]), (400, 300))
        self.assertGreater(report["points"], 5000)
        self.assertGreater(report["renderMs"], 0)
        image = read_png(out)
        self.assertEqual(image.shape, (300, 400, 3))
        mask = self.assert_object_centred(image, (20, 40, 60))
        # Normal colouring: (n + 1) / 2, and the scanner saw the surfaces facing it along +x.
        self.assertGreater(image[mask][:, 0].mean(), 128)

    def test_explicit_eye_and_depth_colouring(self):
        out = os.path.join(self.tmp.name, "depth.png")
        self.run_ok("-q", "render", self.cloud, "-o", out, "--color", "depth", "--eye", "0.45,0.1,0.25",
                    "--target", "0,0,0.07", "--width", "320", "--height", "240", "--point-size", "3")
        image = read_png(out)
        self.assertEqual(image.shape, (240, 320, 3))
        mask = self.assert_object_centred(image, (255, 255, 255))
        self.assertGreater(len({tuple(p) for p in image[mask]}), 20, "depth should spread over the colour map")

    def test_mesh_file_is_drawn_shaded_grey(self):
        out = os.path.join(self.tmp.name, "mesh.png")
        report = json.loads(self.run_ok("--json", "render", BUNNY, "-o", out, "--width", "200", "--height", "200",
                                        "--up", "0,1,0", "--background", "0,0,0"))
        self.assertEqual(report["triangles"], 16301)
        self.assertNotIn("points", report)
        image = read_png(out)
        mask = self.assert_object_centred(image, (0, 0, 0))
        lit = image[mask]
        self.assertTrue(np.all(lit[:, 0] == lit[:, 1]) and np.all(lit[:, 1] == lit[:, 2]))

    def test_missing_field_is_a_usage_error_naming_it(self):
        out = os.path.join(self.tmp.name, "missing.png")
        for colour in ("intensity", "instance", "normal"):
            result = self.vscan("render", self.bare_cloud, "-o", out, "--color", colour)
            self.assertEqual(result.returncode, 2, result.stderr)
            self.assertIn("--color", result.stderr)
            self.assertIn(colour, result.stderr)
        self.assertFalse(os.path.exists(out))
        self.run_ok("-q", "render", self.bare_cloud, "-o", out, "--color", "height", "--width", "64", "--height", "48")
        self.assertEqual(read_png(out).shape, (48, 64, 3))

    def test_bad_arguments_exit_2_and_missing_files_exit_5(self):
        out = os.path.join(self.tmp.name, "bad.png")
        for args in (["--color", "rainbow"], ["--background", "300,0,0"], ["--width", "0"], ["--up", "0,0,0"],
                     ["--eye", "1,2"]):
            result = self.vscan("render", self.cloud, "-o", out, *args)
            self.assertEqual(result.returncode, 2, f"{args}: {result.stderr}")
        self.assertIn("--color", self.vscan("render", self.cloud, "-o", out, "--color", "rainbow").stderr)
        self.assertEqual(self.vscan("render", self.cloud, "-o", out + ".jpg").returncode, 2)
        self.assertEqual(self.vscan("render", BUNNY, "-o", out, "--color", "depth").returncode, 2)
        self.assertEqual(self.vscan("render", os.path.join(self.tmp.name, "none.ply"), "-o", out).returncode, 5)
        self.assertEqual(self.vscan("render", self.cloud, "-o", os.path.join(self.tmp.name, "no", "x.png")).returncode,
                         5)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    unittest.main()
