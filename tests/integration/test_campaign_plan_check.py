"""`vscan campaign run` checks a plan with the server's own rules (StartCampaign validate_only) before
it uploads anything, names the plan's file and line, and removes what a run created when a later
step fails."""

import json
import os
import subprocess
import tempfile
import unittest

import grpc

from harness import DATA, VSCAN, Server, cli_result

from vscan import Client, VscanError

# Line numbers are found by searching the text, so edits may add or move lines.
PLAN = """name: plan-check
scene:
  objects:
    - mesh: {data}/meshes/bunny/bunny_zipper_res2.ply
      unit: m
      on_table: true
      pose: {{xyz: [0.017, 0, -0.033], rpy_deg: [90, 0, 0]}}
  table: {{centre: [0, 0, 0], axis: [0, 0, 1]}}
robot:
  bundle: {data}/robots/panda
  urdf: panda.urdf
  base_link: panda_link0
  tip_link: panda_hand_tcp
  base_pose: {{xyz: [0.6, 0, 0], rpy_deg: [0, 0, 180]}}
sensor:
  pinhole: {{width: 64, height: 48, horizontal_fov_deg: 60, near: 0.05, far: 2}}
viewpoints:
  - {{position: [0.30, 0.10, 0.20], target: [0, 0, 0.07]}}
rotations: 2
rotation_step_deg: 90
""".format(data=DATA)

SCENE = PLAN[PLAN.index("scene:"):PLAN.index("robot:")]

# Plans the CLI's parser accepts but the server's campaign rules refuse: (name, old, new, key, line of).
BAD = [
    ("rotations_above_3600", "rotations: 2", "rotations: 3601", "rotations: at most 3600", "rotations:"),
    ("width_0", "width: 64", "width: 0", "sensor.pinhole.width:", "pinhole:"),
    ("width_100000", "width: 64", "width: 100000", "sensor.pinhole.width: at most", "pinhole:"),
    ("step_0", "rotation_step_deg: 90", "rotation_step_deg: 0", "rotation_step_deg: must not be 0",
     "rotation_step_deg:"),
    ("step_1e300", "rotation_step_deg: 90", "rotation_step_deg: 1e300", "rotation_step_deg: must be finite",
     "rotation_step_deg:"),
    ("viewpoint_beyond_10_km", "position: [0.30, 0.10, 0.20]", "position: [20000, 0.10, 0.20]",
     "viewpoints[0].position: coordinates beyond 10 km", "position: [20000"),
    ("target_at_position", "target: [0, 0, 0.07]", "target: [0.30, 0.10, 0.20]",
     "viewpoints[0].target: coincides with position", "target: [0.30"),
    ("up_along_view", "target: [0, 0, 0.07]}", "target: [0, 0, 0.07], up: [-0.30, -0.10, -0.13]}",
     "viewpoints[0].up: must not be zero or parallel", "up: [-0.30"),
    ("unknown_preset", "pinhole: {width: 64, height: 48, horizontal_fov_deg: 60, near: 0.05, far: 2}",
     "preset: no-such-sensor", "sensor.preset:", "preset:"),
    # An existing scene the plan names is looked up before the robot is uploaded.
    ("missing_scene", SCENE, "scene_id: scn_0000000000000000\n", "scene_id: no scene", "scene_id:"),
]


class CampaignPlanCheckTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.client = Client(cls.server.address)
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-plan-check-")

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()
        cls.tmp.cleanup()

    def vscan(self, *args, timeout=180):
        return subprocess.run([VSCAN, "--server", self.server.address, *args],
                              capture_output=True, text=True, timeout=timeout)

    def inventory(self):
        return {
            "scenes": sorted(s.scene_id for s in self.client.list_scenes()),
            "meshes": sorted(m.mesh_id for m in self.client.list_meshes()),
            "robots": sorted(r.robot_id for r in self.client.list_robots()),
            "mounts": sorted(m.mount_id for m in self.client.list_mounts()),
        }

    def plan(self, name, *edits):
        """Writes PLAN with each (old, new) edit; returns its path and text."""
        text = PLAN
        for old, new in edits:
            self.assertIn(old, text)
            text = text.replace(old, new, 1)
        path = os.path.join(self.tmp.name, name + ".yaml")
        with open(path, "w") as f:
            f.write(text)
        return path, text

    @staticmethod
    def line_of(text, needle):
        return next(i + 1 for i, line in enumerate(text.splitlines()) if needle in line)

    def run_fails_cleanly(self, path, exit_code, message):
        before, jobs = self.inventory(), len(self.client.list_jobs())
        out = self.vscan("campaign", "run", path, "--no-download")
        self.assertEqual(out.returncode, exit_code, out.stdout + out.stderr)
        self.assertIn(message, out.stderr)
        self.assertEqual(self.inventory(), before, out.stderr)
        self.assertEqual(len(self.client.list_jobs()), jobs)
        return out

    def test_plans_the_server_refuses_fail_before_any_upload(self):
        for name, old, new, message, key in BAD:
            with self.subTest(name):
                path, text = self.plan(name, (old, new))
                out = self.run_fails_cleanly(path, 2, f"{path}:{self.line_of(text, key)}: {message}")
                self.assertNotIn("uploaded", out.stdout)
                self.assertNotIn("removed", out.stderr)

    def test_a_start_refused_after_setup_removes_what_the_run_created(self):
        # Only the scene the run builds shows that its table cannot turn.
        path, text = self.plan("no_table", ("axis: [0, 0, 1]}", "axis: [0, 0, 1], enabled: false}"))
        out = self.run_fails_cleanly(path, 2, f"{path}:{self.line_of(text, 'rotations:')}: rotations: scene ")
        self.assertIn("uploaded mesh", out.stdout)
        self.assertIn("mounted", out.stdout)
        for what in ("mount mnt_", "robot rbt_", "scene scn_", "mesh msh_"):
            self.assertIn(what, out.stderr)

    def test_a_failed_mount_removes_the_robot_scene_and_mesh(self):
        path, text = self.plan("sigma", ("base_pose:", "encoder_sigma: [0.001, 0.001, 0.001]\n  base_pose:"))
        out = self.run_fails_cleanly(path, 2,
                                     f"{path}:{self.line_of(text, 'encoder_sigma:')}: robot.encoder_sigma: expected")
        self.assertIn("removed what this run had created: robot rbt_", out.stderr)

    def test_a_failed_robot_upload_removes_the_scene_and_mesh(self):
        path, _ = self.plan("tip", ("tip_link: panda_hand_tcp", "tip_link: no_such_link"))
        out = self.run_fails_cleanly(path, 3, "tip_link")
        self.assertIn("removed what this run had created: scene scn_", out.stderr)

    def test_a_negative_step_turns_the_table_the_other_way(self):
        path, _ = self.plan("clockwise", ("rotation_step_deg: 90", "rotation_step_deg: -90"))
        out = self.vscan("--json", "campaign", "run", path, "--no-download")
        self.assertEqual(out.returncode, 0, out.stderr)
        result = cli_result(out.stdout)
        self.assertEqual([s["tableAngleDeg"] for s in result["steps"]], [0, -90])
        self.assertEqual(result["job"]["campaign"]["rotationStepDeg"], -90)

    def test_python_client_validates_without_ids_and_starts_nothing(self):
        jobs = len(self.client.list_jobs())
        viewpoints = [((0.3, 0.1, 0.2), (0, 0, 0.07))]
        self.assertIsNone(self.client.validate_campaign(viewpoints=viewpoints, rotations=2, rotation_step_deg=90))
        with self.assertRaises(VscanError) as raised:
            self.client.validate_campaign(viewpoints=viewpoints, rotations=3601, rotation_step_deg=0.1)
        self.assertEqual(raised.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
        self.assertEqual(raised.exception.message, "spec.rotations: at most 3600")
        self.assertEqual(len(self.client.list_jobs()), jobs)


if __name__ == "__main__":
    unittest.main()
