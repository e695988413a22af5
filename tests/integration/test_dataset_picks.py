"""Dataset jobs that check picks, on a real vscand through the CLI and the Python client: a UR5
uploaded, a plan whose picks section names it, scene_pickable.json read from the downloaded
dataset beside scene_gt.json; bad picks sections (unknown robot, NaN or huge base, huge counts)
refused naming the key without creating a job; the one-shot shard refusing a plan with picks."""

import json
import os
import subprocess
import tempfile
import unittest

import numpy as np
from harness import SOURCE_DIR, VSCAN, VSCAND, Server, cli_result

UR5_DIR = os.path.join(SOURCE_DIR, "data", "robots", "ur5")

# A 40 x 30 x 20 mm block, its frame at its centre.
BLOCK_OBJ = """v -0.02 -0.015 -0.01
v 0.02 -0.015 -0.01
v 0.02 0.015 -0.01
v -0.02 0.015 -0.01
v -0.02 -0.015 0.01
v 0.02 -0.015 0.01
v 0.02 0.015 0.01
v -0.02 0.015 0.01
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
"""


def plan_text(block, robot_id, base="{xyz: [-0.45, 0, 0.2], rpy_deg: [0, 0, 0]}", extra=""):
    return f"""name: picked-blocks
bins:
  - name: blocks
    bin: {{inner_size: [0.30, 0.20, 0.12]}}
    parts:
      - {{mesh: {block}, unit: m, count: 3}}
    max_simulated_s: 4
seeds: [1, 2]
sensors:
  - {{name: cam, preset: ideal-vga, width: 96, height: 72}}
picks:
  robot_id: {robot_id}
  base: {base}
  gripper: {{suction: {{diameter: 0.012}}}}
  grasp_options: {{max_grasps: 100}}
  pick_options: {{body_length: 0.08{extra}}}
"""


class DatasetPicksTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-dspicks-")
        cls.server = Server(data_dir=cls.tmp.name).start()
        cls.block = os.path.join(cls.tmp.name, "block.obj")
        with open(cls.block, "w") as f:
            f.write(BLOCK_OBJ)
        uploaded = cls.vscan("-q", "robot", "upload", UR5_DIR, "--urdf", "ur5_robot.urdf", "--base", "base_link",
                             "--tip", "tool0")
        assert uploaded.returncode == 0, uploaded.stderr
        cls.robot_id = uploaded.stdout.strip()

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()
        cls.tmp.cleanup()

    @classmethod
    def vscan(cls, *args, timeout=300):
        return subprocess.run([VSCAN, "--server", cls.server.address, *args], capture_output=True, text=True,
                              timeout=timeout)

    def write_plan(self, name, text):
        path = os.path.join(self.tmp.name, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def check_scene(self, scene):
        with open(os.path.join(scene, "scene_gt.json")) as f:
            gt = json.load(f)["0"]
        with open(os.path.join(scene, "scene_pickable.json")) as f:
            picks = json.load(f)
        self.assertEqual([p["instance_id"] for p in picks], [g["instance_id"] for g in gt])
        self.assertEqual([p["obj_id"] for p in picks], [g["obj_id"] for g in gt])
        for pick in picks:
            if pick["pickable"]:
                self.assertEqual(pick["failure"], "PICK_FAILURE_UNSPECIFIED")
                rotation = np.array(pick["grasp"]["world_R_tool"]).reshape(3, 3)
                np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), atol=1e-6)
                # From above within the 60 degree tilt, the cup within the bin (millimetres).
                self.assertLessEqual(rotation[2, 2], -0.5 + 1e-9)
                t = np.array(pick["grasp"]["world_t_tool"])
                self.assertLess(np.abs(t[:2]).max(), 160)
                self.assertTrue(0 <= t[2] <= 120, t)
            else:
                self.assertIsNone(pick["grasp"])
                self.assertTrue(pick["failure"].startswith("PICK_FAILURE_"), pick)
            covered_by = pick["covered_by"]
            self.assertTrue(-1 <= covered_by < len(picks))
        return picks

    def test_cli_job_writes_scene_pickable_beside_scene_gt(self):
        plan = self.write_plan("plan.yaml", plan_text(self.block, self.robot_id))
        run = self.vscan("dataset", "run", plan, "--watch")
        self.assertEqual(run.returncode, 0, run.stderr + self.server.log())
        job_id = (run.stdout + run.stderr).split("started dataset job ")[1].split()[0]
        downloaded = os.path.join(self.tmp.name, "downloaded")
        got = self.vscan("dataset", "download", job_id, downloaded)
        self.assertEqual(got.returncode, 0, got.stderr)
        pickable = 0
        for scene_id in range(2):
            picks = self.check_scene(os.path.join(downloaded, "train_pbr", "%06d" % scene_id))
            self.assertEqual(len(picks), 3)
            pickable += sum(p["pickable"] for p in picks)
        self.assertGreater(pickable, 0, "no block of two bins was pickable")
        with open(os.path.join(downloaded, "dataset.json")) as f:
            manifest = json.load(f)
        self.assertEqual(manifest["plan"]["picks"]["robot_id"], self.robot_id)
        self.assertEqual(manifest["plan"]["picks"]["gripper"]["kind"], "suction")

    def test_python_client_runs_a_plan_with_picks(self):
        from vscan import Client

        far = plan_text(self.block, self.robot_id, base="{xyz: [-3, 0, 0.2]}")
        plan = self.write_plan("far.yaml", far.replace("seeds: [1, 2]", "seeds: [5]"))
        directory = os.path.join(self.tmp.name, "python")
        with Client(self.server.address) as client:
            client.run_dataset(plan, directory=directory)
        picks = self.check_scene(os.path.join(directory, "train_pbr", "000000"))
        self.assertFalse(any(p["pickable"] for p in picks))
        self.assertTrue(all(p["failure"] in ("PICK_FAILURE_UNREACHABLE", "PICK_FAILURE_COVERED",
                                             "PICK_FAILURE_NO_GRASP", "PICK_FAILURE_GRIPPER_COLLISION")
                            for p in picks))
        self.assertIn("PICK_FAILURE_UNREACHABLE", [p["failure"] for p in picks])

    def test_bad_picks_are_refused_naming_the_key_without_a_job(self):
        before = cli_result(self.vscan("--json", "dataset", "list").stdout).get("jobs", [])
        cases = [
            (plan_text(self.block, "rbt_missing"), "spec.plan_yaml.picks.robot_id: no robot 'rbt_missing'"),
            (plan_text(self.block, self.robot_id, base="{xyz: [.nan, 0, 0.2]}"), "picks.base.xyz"),
            (plan_text(self.block, self.robot_id, base="{xyz: [1e19, 0, 0.2]}"), "picks.base.xyz: must be within"),
            (plan_text(self.block, self.robot_id, base="{xyz: [0, 0, 0], rpy_deg: [1e19, 0, 0]}"),
             "picks.base.rpy_deg"),
            (plan_text(self.block, self.robot_id, extra=", max_reach_checks: 1000000000000"),
             "picks.pick_options.max_reach_checks: must be in [1, 1000]"),
            (plan_text(self.block, self.robot_id, extra=", max_reach_checks: 1000, ik_iterations: 100000"),
             "picks.pick_options.max_reach_checks: parts x max_reach_checks"),
            (plan_text(self.block, self.robot_id).replace("max_grasps: 100", "max_grasps: 1e19"),
             "picks.grasp_options.max_grasps"),
            (plan_text(self.block, self.robot_id).replace("diameter: 0.012", "diameter: -1"),
             "picks.gripper.suction.diameter"),
        ]
        for text, key in cases:
            refused = self.vscan("dataset", "run", self.write_plan("bad.yaml", text))
            self.assertEqual(refused.returncode, 3, refused.stderr)
            self.assertIn(key, refused.stderr, text)
        after = cli_result(self.vscan("--json", "dataset", "list").stdout).get("jobs", [])
        self.assertEqual(len(after), len(before))

    def test_one_shot_shards_refuse_a_plan_with_picks(self):
        plan = self.write_plan("shard.yaml", plan_text(self.block, self.robot_id))
        done = subprocess.run([VSCAND, "--log-level", "warn", "--dataset-shard", plan, "--out",
                               os.path.join(self.tmp.name, "one-shot")], capture_output=True, text=True, timeout=60)
        self.assertEqual(done.returncode, 2, done.stderr)
        self.assertIn("picks", done.stderr)
        self.assertIn("run this plan as a dataset job", done.stderr)


if __name__ == "__main__":
    unittest.main()
