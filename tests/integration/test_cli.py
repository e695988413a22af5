"""The vscan CLI against a real vscand: files it writes, JSON it prints, exit codes it returns."""

import json
import os
import subprocess
import tempfile
import unittest

import numpy as np

from harness import BUNNY, VSCAN, Server

PLY_TYPES = {"float": "<f4", "uint": "<u4", "int": "<i4", "uchar": "u1", "double": "<f8"}


def read_ply(path):
    """An independent binary PLY reader: returns {property: array}."""
    with open(path, "rb") as f:
        assert f.readline().strip() == b"ply"
        fmt = f.readline().split()
        assert fmt[1] == b"binary_little_endian", fmt
        count, props = 0, []
        while True:
            line = f.readline().decode().split()
            if line[0] == "element":
                count = int(line[2])
            elif line[0] == "property":
                props.append((line[2], PLY_TYPES[line[1]]))
            elif line[0] == "end_header":
                break
        data = np.frombuffer(f.read(), dtype=np.dtype(props), count=count)
    return {name: data[name] for name, _ in props}


class CliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-cli-")

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()
        cls.tmp.cleanup()

    def vscan(self, *args, server=None):
        return subprocess.run([VSCAN, "--server", server or self.server.address, *args],
                              capture_output=True, text=True, timeout=120)

    def ok(self, *args):
        out = self.vscan(*args)
        self.assertEqual(out.returncode, 0, out.stderr)
        return out.stdout.strip()

    def bunny_scene(self):
        mesh = self.ok("-q", "mesh", "upload", BUNNY, "--unit", "m")
        scene = self.ok("-q", "scene", "create", "cli")
        self.ok("-q", "object", "add", scene, mesh, "--label", "bunny", "--on-table")
        return scene

    def test_health(self):
        self.assertIn("SERVING", self.ok("health"))

    def test_sensors_lists_presets(self):
        names = self.ok("-q", "sensors").split()
        self.assertIn("kinect-v1-class", names)
        self.assertIn("source:", self.ok("sensors", "--verbose"))

    def test_scan_writes_ply_with_every_field(self):
        scene = self.bunny_scene()
        out = os.path.join(self.tmp.name, "bunny.ply")
        report = json.loads(self.ok("--json", "scan", scene, "-o", out, "--width", "320", "--height", "240",
                                    "--hfov", "40", "--eye", "0,0.1,0.5", "--target", "0,0.1,0", "--up", "0,1,0",
                                    "--fields", "all"))
        stats = report["statistics"]
        ply = read_ply(out)
        n = int(stats["points"])
        self.assertGreater(n, 5000)
        self.assertEqual(len(ply["x"]), n)
        for prop in ("x", "y", "z", "nx", "ny", "nz", "range", "intensity", "instance", "pixel"):
            self.assertIn(prop, ply)
        xyz = np.stack([ply["x"], ply["y"], ply["z"]], axis=1)
        # The bunny spans about 0.16 x 0.15 x 0.12 m around (-0.02, 0.11, 0).
        self.assertTrue(np.all(xyz.min(axis=0) > [-0.11, 0.02, -0.07]))
        self.assertTrue(np.all(xyz.max(axis=0) < [0.07, 0.2, 0.07]))
        np.testing.assert_allclose(ply["range"], np.linalg.norm(xyz - [0, 0.1, 0.5], axis=1), rtol=1e-5)
        self.assertTrue(np.all(ply["instance"] == 1))
        self.assertAlmostEqual(stats["hitRatio"], n / (320 * 240), places=6)

    def test_scan_writes_pcd(self):
        scene = self.bunny_scene()
        out = os.path.join(self.tmp.name, "bunny.pcd")
        self.ok("-q", "scan", scene, "-o", out, "--width", "160", "--height", "120", "--hfov", "40",
                "--eye", "0,0.1,0.5", "--target", "0,0.1,0", "--up", "0,1,0")
        with open(out, "rb") as f:
            header = f.read(600).split(b"DATA binary\n")[0].decode()
        self.assertIn("FIELDS x y z", header)
        points = int([l for l in header.splitlines() if l.startswith("POINTS")][0].split()[1])
        self.assertGreater(points, 500)

    def test_table_and_scene_commands(self):
        scene = self.bunny_scene()
        self.ok("table", "set", scene, "--axis", "0,1,0", "--angle", "45")
        got = json.loads(self.ok("--json", "scene", "get", scene))
        self.assertEqual(got["table"]["angleDeg"], 45)
        self.assertEqual(int(got["revision"]), 3)
        self.assertIn(scene, self.ok("-q", "scene", "list").split())

    def test_exit_codes(self):
        usage = self.vscan("scene", "frobnicate")
        self.assertEqual(usage.returncode, 2, usage.stderr)
        missing_unit = self.vscan("mesh", "upload", BUNNY)
        self.assertEqual(missing_unit.returncode, 2, missing_unit.stderr)
        server_error = self.vscan("scene", "get", "scn_missing")
        self.assertEqual(server_error.returncode, 3)
        self.assertIn("NOT_FOUND", server_error.stderr)
        self.assertIn("scene_id", server_error.stderr)
        as_json = self.vscan("--json", "scene", "get", "scn_missing")
        self.assertEqual(json.loads(as_json.stdout)["error"]["code"], "NOT_FOUND")
        unreachable = self.vscan("--timeout", "2", "scene", "list", server="127.0.0.1:1")
        self.assertEqual(unreachable.returncode, 4, unreachable.stderr)
        scene = self.ok("-q", "scene", "create", "io")
        io_error = self.vscan("scan", scene, "-o", "/nonexistent-dir/x.ply", "--eye", "1,0,0", "--target", "0,0,0")
        self.assertEqual(io_error.returncode, 5, io_error.stderr)
        no_file = self.vscan("mesh", "upload", "/nonexistent.ply", "--unit", "m")
        self.assertEqual(no_file.returncode, 5, no_file.stderr)
        self.assertIn("/nonexistent.ply", no_file.stderr)
        self.assertNotIn("NOT_FOUND", no_file.stderr, "a local file error is not a server answer")

    def test_token_with_a_newline_is_a_usage_error(self):
        for token in ("s3cret\nx", "two words", "tab\there"):
            result = self.vscan("--token", token, "scene", "list")
            self.assertEqual(result.returncode, 2, result.stderr)
            self.assertIn("bearer_token", result.stderr)

    def test_sub_millisecond_timeout_is_still_a_deadline(self):
        scene = self.bunny_scene()
        result = self.vscan("--timeout", "0.000001", "scan", scene, "-o", os.path.join(self.tmp.name, "t.ply"),
                            "--width", "1280", "--height", "1024", "--eye", "0.5,0,0.2", "--target", "0,0,0.07")
        self.assertEqual(result.returncode, 4, result.stderr)
        self.assertIn("DEADLINE_EXCEEDED", result.stderr)
        for bad in ("0", "-1", "1e300", "nan"):
            self.assertEqual(self.vscan("--timeout", bad, "scene", "list").returncode, 2, bad)


if __name__ == "__main__":
    unittest.main()
