"""`vscan campaign` against a real vscand: a YAML plan run end to end, its scans, the job commands."""

import json
import math
import os
import subprocess
import tempfile
import unittest

import numpy as np

from harness import BUNNY, SOURCE_DIR, VSCAN, Server, cli_result
from test_cli import read_ply

PLAN = os.path.join(SOURCE_DIR, "examples", "campaigns", "bunny_panda_quick.yaml")


def bunny_vertices_on_table():
    """The bunny's vertices placed as the plan places it: roll 90 degrees, then (0.017, 0, -0.033)."""
    with open(BUNNY) as f:
        count = 0
        while True:
            line = f.readline().split()
            if line[:2] == ["element", "vertex"]:
                count = int(line[2])
            if line == ["end_header"]:
                break
        v = np.array([[float(x) for x in f.readline().split()[:3]] for _ in range(count)])
    # Rx(90): (x, y, z) -> (x, -z, y).
    return np.stack([v[:, 0] + 0.017, -v[:, 2], v[:, 1] - 0.033], axis=1)


def rotate_z(points, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return points @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T


class CampaignCliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-campaign-")
        cls.out_dir = os.path.join(cls.tmp.name, "quick")
        cls.run_result = cls.vscan("--json", "campaign", "run", PLAN, "-o", cls.out_dir, timeout=600)

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()
        cls.tmp.cleanup()

    @classmethod
    def vscan(cls, *args, timeout=120):
        return subprocess.run([VSCAN, "--server", cls.server.address, *args],
                              capture_output=True, text=True, timeout=timeout)

    def ran(self):
        """The JSON `campaign run` printed, after checking it succeeded."""
        out = self.run_result
        self.assertEqual(out.returncode, 0, out.stderr + self.server.log())
        return cli_result(out.stdout)

    def test_run_succeeds_with_every_scan(self):
        result = self.ran()
        self.assertEqual(result["job"]["state"], "JOB_STATE_SUCCEEDED")
        self.assertEqual(result["job"]["kind"], "campaign")
        self.assertEqual(result["job"]["stepsTotal"], 6)
        self.assertEqual(len(result["steps"]), 6)
        self.assertTrue(all(step["captured"] and step["poseReached"] for step in result["steps"]), result["steps"])
        # Rotation-major: steps 0, 1 at the first table angle, 2, 3 at 120 degrees, 4, 5 at 240.
        self.assertEqual([s["tableAngleDeg"] for s in result["steps"]], [0, 0, 120, 120, 240, 240])
        # Exact encoders: the arm reaches what its IK commands.
        for step in result["steps"]:
            self.assertLess(step["positionErrorM"], 1e-6)
        self.assertEqual(os.path.realpath(result["outputDir"]), os.path.realpath(self.out_dir))

    def test_downloaded_plys_parse_and_lie_on_the_bunny(self):
        result = self.ran()
        plys = sorted(f for f in os.listdir(self.out_dir) if f.endswith(".ply"))
        self.assertEqual(len(plys), 6, os.listdir(self.out_dir))
        mesh = bunny_vertices_on_table()
        by_file = {step["file"]: step for step in result["steps"]}
        rng = np.random.default_rng(0)
        for name in plys:
            step = by_file[name]
            ply = read_ply(os.path.join(self.out_dir, name))
            self.assertEqual(len(ply["x"]), step["points"], name)
            self.assertGreater(step["points"], 1000, name)
            for prop in ("nx", "ny", "nz", "instance"):
                self.assertIn(prop, ply, name)
            self.assertTrue(np.all(ply["instance"] == 1), name)
            normals = np.stack([ply["nx"], ply["ny"], ply["nz"]], axis=1)
            np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-4)
            # World-frame points turned back by the table angle lie on the bunny as placed.
            world = np.stack([ply["x"], ply["y"], ply["z"]], axis=1).astype(np.float64)
            on_table = rotate_z(world, -step["tableAngleDeg"])
            sample = on_table[rng.choice(len(on_table), size=min(400, len(on_table)), replace=False)]
            nearest = np.sqrt(((sample[:, None, :] - mesh[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
            self.assertLess(np.median(nearest), 0.002, name)
            self.assertLess(np.percentile(nearest, 99), 0.003, name)

    def test_job_json_and_artifacts_download_again(self):
        result = self.ran()
        job_id = result["job"]["jobId"]
        with open(os.path.join(self.out_dir, "job.json")) as f:
            self.assertEqual(json.load(f)["jobId"], job_id)
        again = os.path.join(self.tmp.name, "again")
        out = self.vscan("campaign", "artifacts", job_id, "-o", again)
        self.assertEqual(out.returncode, 0, out.stderr)
        for name in os.listdir(self.out_dir):
            if name.endswith(".ply"):
                with open(os.path.join(self.out_dir, name), "rb") as a, open(os.path.join(again, name), "rb") as b:
                    self.assertEqual(a.read(), b.read(), name)

    def test_list_get_and_watch(self):
        job_id = self.ran()["job"]["jobId"]
        listed = self.vscan("campaign", "list")
        self.assertEqual(listed.returncode, 0, listed.stderr)
        self.assertIn(job_id, listed.stdout)
        self.assertIn("SUCCEEDED", listed.stdout)
        self.assertIn("bunny-panda-quick", listed.stdout)

        got = self.vscan("--json", "campaign", "get", job_id)
        self.assertEqual(got.returncode, 0, got.stderr)
        job = cli_result(got.stdout)
        self.assertEqual(job["state"], "JOB_STATE_SUCCEEDED")
        self.assertEqual(len([a for a in job["artifacts"] if a["name"].endswith(".ply")]), 6)
        self.assertEqual(job["campaign"]["name"], "bunny-panda-quick")

        text = self.vscan("campaign", "get", job_id)
        self.assertEqual(text.returncode, 0, text.stderr)
        self.assertIn("SUCCEEDED", text.stdout)
        self.assertIn("2 viewpoints x 3 table angles", text.stdout)

        # Watching a finished job returns at once with its outcome.
        watched = self.vscan("campaign", "watch", job_id)
        self.assertEqual(watched.returncode, 0, watched.stderr)
        self.assertIn("6 of 6 scans", watched.stdout)

        missing = self.vscan("campaign", "get", "no-such-job")
        self.assertEqual(missing.returncode, 3)
        self.assertIn("NOT_FOUND", missing.stderr)

    def test_malformed_plan_exits_2_naming_the_line(self):
        with open(PLAN) as f:
            text = f.read().replace("../../data/", os.path.join(SOURCE_DIR, "data") + "/")
        lines = text.splitlines()
        index = next(i for i, line in enumerate(lines) if "position: [0.25, -0.15, 0.35]" in line)
        lines[index] = "  - {position: [0.25, -0.15, 0.35], target: [0, 0]}"
        bad = os.path.join(self.tmp.name, "bad.yaml")
        with open(bad, "w") as f:
            f.write("\n".join(lines) + "\n")
        scenes_before = self.vscan("-q", "scene", "list").stdout
        out = self.vscan("campaign", "run", bad, "-o", os.path.join(self.tmp.name, "bad"))
        self.assertEqual(out.returncode, 2, out.stderr)
        self.assertIn(f"{bad}:{index + 1}: viewpoints[1].target: expected 3 numbers", out.stderr)
        # Rejected before anything was uploaded or created.
        self.assertEqual(self.vscan("-q", "scene", "list").stdout, scenes_before)
        self.assertFalse(os.path.exists(os.path.join(self.tmp.name, "bad")))

    def test_unreadable_plan_exits_5(self):
        out = self.vscan("campaign", "run", os.path.join(self.tmp.name, "missing.yaml"))
        self.assertEqual(out.returncode, 5, out.stderr)


if __name__ == "__main__":
    unittest.main()
