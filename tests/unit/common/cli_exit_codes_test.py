"""The vscan CLI's exit codes and output against the in-process fake server.

Needs VSCAN_CLI (path to the vscan binary) and VSCAN_PY_STUBS (the generated Python stubs).
"""

import json
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "client", "python", "tests"))

from fake_server import N_POINTS, FakeServer  # noqa: E402

CLI = os.environ.get("VSCAN_CLI")


@unittest.skipUnless(CLI, "set VSCAN_CLI to the vscan binary")
class CliExitCodes(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.fake = FakeServer()
        cls.tmp = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.fake.stop()
        cls.tmp.cleanup()

    def run_cli(self, *args, server=None):
        env = dict(os.environ, VSCAN_SERVER=server or self.fake.address)
        return subprocess.run([CLI, *args], capture_output=True, text=True, env=env, timeout=60)

    def test_help_is_success_and_documents_exit_codes(self):
        r = self.run_cli("--help")
        self.assertEqual(r.returncode, 0)
        self.assertIn("Exit codes", r.stdout)
        self.assertEqual(self.run_cli("scan", "--help").returncode, 0)

    def test_usage_errors_exit_2(self):
        self.assertEqual(self.run_cli().returncode, 2)
        self.assertEqual(self.run_cli("frobnicate").returncode, 2)
        self.assertEqual(self.run_cli("scene", "get").returncode, 2)
        self.assertEqual(self.run_cli("mesh", "upload", "x.stl").returncode, 2)  # --unit missing
        self.assertEqual(self.run_cli("object", "add", "s", "m", "--quat", "1,1,0,0").returncode, 2)
        self.assertEqual(self.run_cli("scan", "s", "-o", "x.txt", "--eye", "1,0,0", "--target", "0,0,0").returncode, 2)
        self.assertEqual(self.run_cli("scan", "s", "-o", "x.ply", "--width", "abc").returncode, 2)

    def test_server_error_exits_3(self):
        r = self.run_cli("scene", "get", "nope")
        self.assertEqual(r.returncode, 3)
        self.assertIn("error: NOT_FOUND: ", r.stderr)
        r = self.run_cli("--json", "scene", "get", "nope")
        self.assertEqual(r.returncode, 3)
        self.assertEqual(json.loads(r.stdout)["error"]["code"], "NOT_FOUND")

    def test_unreachable_exits_4(self):
        r = self.run_cli("--timeout", "5", "scene", "list", server="127.0.0.1:1")
        self.assertEqual(r.returncode, 4)
        self.assertIn("error: UNAVAILABLE", r.stderr)

    def test_local_io_errors_exit_5(self):
        missing = os.path.join(self.tmp.name, "missing.stl")
        self.assertEqual(self.run_cli("mesh", "upload", missing, "--unit", "mm").returncode, 5)
        out = os.path.join(self.tmp.name, "no", "dir", "out.ply")
        r = self.run_cli("scan", "scene-1", "-o", out, "--eye", "1,0,0", "--target", "0,0,0")
        self.assertEqual(r.returncode, 5)

    def test_health(self):
        r = self.run_cli("health")
        self.assertEqual((r.returncode, r.stdout.strip()), (0, "SERVING"))
        self.assertEqual(json.loads(self.run_cli("--json", "health").stdout), {"status": "SERVING"})

    def test_quiet_prints_ids(self):
        r = self.run_cli("-q", "scene", "create", "demo")
        self.assertEqual((r.returncode, r.stdout), (0, "scene-1\n"))

    def test_scan_writes_cloud_and_json(self):
        out = os.path.join(self.tmp.name, "scan.ply")
        r = self.run_cli("--json", "scan", "scene-1", "-o", out, "--eye", "1,0,0", "--target", "0,0,0",
                         "--fields", "position,normal,range,intensity,instance")
        self.assertEqual(r.returncode, 0, r.stderr)
        report = json.loads(r.stdout)
        self.assertEqual(report["output"], out)
        self.assertEqual(report["header"]["points"], str(N_POINTS))
        with open(out, "rb") as f:
            data = f.read()
        header_end = data.index(b"end_header\n") + len(b"end_header\n")
        self.assertIn(b"element vertex %d\n" % N_POINTS, data[:header_end])
        self.assertEqual(len(data) - header_end, N_POINTS * 36)
        self.assertEqual(self.fake.scans.last_request.pose.look_at.eye.x, 1)


if __name__ == "__main__":
    unittest.main()
