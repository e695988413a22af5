"""client/python as a user installs it: pip, offline, into a virtual environment on Debian's grpcio
and numpy; `import vscan` from that environment alone then scans a sphere on a real vscand."""

import json
import os
import re
import shutil
import subprocess
import tempfile
import textwrap
import unittest

from harness import BUNNY, SOURCE_DIR, Server, icosphere_ply

# Run by the environment's python with no PYTHONPATH: prints what it saw as one JSON line.
SCAN_SCRIPT = textwrap.dedent("""
    import json, sys
    import numpy as np
    import vscan
    from vscan.v1 import scan_pb2
    address, mesh_path, radius, cx, cy, cz = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:7])
    centre = np.array([cx, cy, cz])
    with vscan.Client(address) as client:
        health = client.health()
        scene = client.create_scene("package-sphere")
        mesh = client.upload_mesh(mesh_path, unit="m")
        client.add_object(scene.scene_id, mesh.mesh_id)
        result = client.scan(scene.scene_id, width=160, height=120, hfov_deg=40.0,
                             eye=tuple(centre + [0.0, -1.2, 0.2]), target=tuple(centre))
        distances = np.linalg.norm(result.positions - centre, axis=1)
        print(json.dumps({"package": vscan.__file__, "stubs": scan_pb2.__file__, "health": health,
                          "points": len(result), "min": float(distances.min()), "max": float(distances.max())}))
""")


def run_checked(args, **kwargs):
    out = subprocess.run(args, capture_output=True, text=True, timeout=240, **kwargs)
    if out.returncode != 0:
        raise AssertionError(f"{args} exited {out.returncode}\n{out.stdout}\n{out.stderr}")
    return out


class PythonPackageTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-package-")
        cls.server = Server().start()
        # A copy of the sources (pip builds in place), laid out as in the repository: setup.py reads ../../proto.
        src = os.path.join(cls.tmp.name, "src")
        shutil.copytree(os.path.join(SOURCE_DIR, "client", "python"), os.path.join(src, "client", "python"),
                        ignore=shutil.ignore_patterns("__pycache__", "build", "*.egg-info"))
        shutil.copytree(os.path.join(SOURCE_DIR, "proto"), os.path.join(src, "proto"))
        venv = os.path.join(cls.tmp.name, "venv")
        cls.site = os.path.join(venv, "lib")
        cls.python = os.path.join(venv, "bin", "python")
        # No PYTHONPATH, and stubs generated at install time from proto/, not taken from the build directory.
        cls.env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VSCAN_PY_STUBS")}
        cls.cwd = os.path.join(cls.tmp.name, "elsewhere")
        os.makedirs(cls.cwd)
        try:
            run_checked(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv])
            run_checked([cls.python, "-m", "pip", "install", "--no-index", "--no-build-isolation", "--no-deps",
                         "--disable-pip-version-check", os.path.join(src, "client", "python")], env=cls.env)
        except Exception:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()
        cls.tmp.cleanup()

    def test_installed_package_scans_a_sphere(self):
        radius, centre = 0.2, (0.05, 0.1, 0.3)
        mesh = os.path.join(self.tmp.name, "sphere.ply")
        with open(mesh, "wb") as f:
            f.write(icosphere_ply(radius, centre, 4))
        out = run_checked([self.python, "-c", SCAN_SCRIPT, self.server.address, mesh, str(radius),
                           *map(str, centre)], cwd=self.cwd, env=self.env)
        seen = json.loads(out.stdout.strip().splitlines()[-1])

        self.assertTrue(seen["package"].startswith(self.site), seen["package"])
        self.assertTrue(seen["stubs"].startswith(os.path.join(os.path.dirname(seen["package"]), "v1")), seen["stubs"])
        self.assertEqual(seen["health"], "SERVING")
        # The sphere spans 19 of the 40 degrees across: a disc of about 4500 of the 19200 pixels.
        self.assertGreater(seen["points"], 3500)
        # Every hit lies on the icosphere: between its inscribed radius (faces) and its vertices.
        self.assertGreater(seen["min"], radius * 0.995)
        self.assertLess(seen["max"], radius * 1.0001)

    def test_example_runs_on_the_installed_package(self):
        out = run_checked([self.python, os.path.join(SOURCE_DIR, "client", "python", "examples", "scan_to_numpy.py"),
                           "--server", self.server.address, "--mesh", BUNNY, "--unit", "m"], cwd=self.cwd, env=self.env)
        points = re.search(r"N = (\d+) points", out.stdout)
        self.assertIsNotNone(points, out.stdout)
        self.assertGreater(int(points.group(1)), 1000)


if __name__ == "__main__":
    unittest.main()
