"""A bin fill with a picks block against a real vscand: `vscan bin fill` prints how many parts are
pickable, bin.json read back through the Python client agrees with the scene (each pickable part's
tool lies on that part's surface, approaching from above), and a bad picks section is refused
naming its field with no job created."""

import math
import os
import struct
import subprocess
import tempfile
import unittest

import numpy as np

from harness import DATA, VSCAN, Server

import grpc  # noqa: E402
from vscan import Client, VscanError  # noqa: E402
from vscan.bins import bin_fill_spec  # noqa: E402

UR5_DIR = os.path.join(DATA, "robots", "ur5")
# The block, millimetres: 40 x 30 x 20 with its base on z = 0.
LO = np.array([-20.0, -15.0, 0.0])
HI = np.array([20.0, 15.0, 20.0])

PLAN = """\
name: picks-bin
scene: picks-test
bin:
  inner_size: [0.16, 0.12, 0.08]
  pose: {{xyz: [0.45, 0.0, 0.0]}}
parts:
  - mesh: {block}
    unit: mm
    count: 5
    name: block
seed: 5
physics: {{max_simulated_s: 20}}
picks:
  mount_id: {mount}
  gripper: {{suction: {{diameter: 0.012}}}}
  grasp_options: {{max_grasps: 200}}
  pick_options: {{body_length: 0.08}}
"""


def write_box_stl(path, lo, hi):
    """A closed box as binary STL, wound counter-clockwise seen from outside."""
    corners = [np.array([x, y, z]) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    triangles = []
    for a, b, c, d in quads:
        triangles += [(a, b, c), (a, c, d)]
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(triangles)))
        for tri in triangles:
            p = [corners[i] for i in tri]
            n = np.cross(p[1] - p[0], p[2] - p[0])
            n /= np.linalg.norm(n)
            f.write(struct.pack("<3f", *n))
            for v in p:
                f.write(struct.pack("<3f", *v))
            f.write(b"\0\0")
    # The winding above must face out: every normal points away from the centre.
    centre = (np.array(lo) + np.array(hi)) / 2
    for tri in triangles:
        p = [corners[i] for i in tri]
        assert np.dot(np.cross(p[1] - p[0], p[2] - p[0]), p[0] - centre) > 0


def distance_to_block_mm(p):
    outside = np.maximum(np.maximum(LO - p, p - HI), 0.0)
    if np.linalg.norm(outside) > 0:
        return float(np.linalg.norm(outside))
    return float(np.min(np.minimum(p - LO, HI - p)))


def matrix(values):
    return np.array(values, dtype=float).reshape(4, 4)


class BinPicksTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.client = Client(cls.server.address)
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-bin-picks-")
        robot = cls.client.upload_robot(UR5_DIR, urdf="ur5_robot.urdf", base="base_link", tip="tool0", name="ur5")
        cls.scene = cls.client.create_scene("picks-test")
        cls.mount = cls.client.mount_robot(cls.scene.scene_id, robot.robot_id, position=(0, 0, 0.2)).mount_id
        cls.other_scene = cls.client.create_scene("elsewhere")
        cls.other_mount = cls.client.mount_robot(cls.other_scene.scene_id, robot.robot_id).mount_id
        block = os.path.join(cls.tmp.name, "block.stl")
        write_box_stl(block, LO, HI)
        cls.plan = os.path.join(cls.tmp.name, "plan.yaml")
        with open(cls.plan, "w") as f:
            f.write(PLAN.format(block=block, mount=cls.mount))
        cls.out_dir = os.path.join(cls.tmp.name, "fill")
        cls.fill = subprocess.run([VSCAN, "--server", cls.server.address, "bin", "fill", cls.plan, "-o", cls.out_dir],
                                  capture_output=True, text=True, timeout=280)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()
        cls.tmp.cleanup()

    def test_every_pickable_part_has_its_tool_on_its_own_surface(self):
        self.assertEqual(self.fill.returncode, 0, self.fill.stdout + self.fill.stderr + self.server.log())
        jobs = [j for j in self.client.list_jobs() if j.bin_fill.scene_id == self.scene.scene_id]
        self.assertEqual(len(jobs), 1)
        report = self.client.bin_report(jobs[0].job_id)
        picks = report["picks"]
        self.assertEqual(picks["mount_id"], self.mount)
        self.assertEqual(picks["parts_checked"], len(report["parts"]))
        self.assertIn(f"{picks['pickable']} of {picks['parts_checked']} parts pickable", self.fill.stdout)

        objects = {o.object_id: o for o in self.client.get_scene(self.scene.scene_id).objects}
        pickable = 0
        for part in report["parts"]:
            pick = part["pick"]
            if not pick["pickable"]:
                self.assertNotEqual(pick["failure"], "none")
                continue
            pickable += 1
            # The part's pose as the scene holds it, not as bin.json says.
            world_from_part = matrix(objects[part["object_id"]].pose.matrix.values)
            world_from_tool = matrix(pick["world_from_tool"])
            tool_in_part_mm = (np.linalg.inv(world_from_part) @ world_from_tool[:, 3])[:3] * 1000
            self.assertLess(distance_to_block_mm(tool_in_part_mm), 1.0, part["label"])
            down = -world_from_tool[2, 2]
            self.assertGreaterEqual(down, math.cos(math.radians(60)) - 1e-9, part["label"])
            np.testing.assert_allclose(world_from_part @ matrix(pick["part_from_tool"]), world_from_tool, atol=1e-9)
            self.assertEqual(len(pick["joint_positions"]), 6)
        self.assertEqual(pickable, picks["pickable"])
        self.assertGreater(pickable, 0)

    def spec(self, **picks):
        fields = {"mount_id": self.mount, "gripper": {"suction": {"diameter": 0.012}}}
        fields.update(picks)
        return bin_fill_spec(self.scene.scene_id, (0.16, 0.12, 0.08), [], picks=fields)

    def test_a_bad_picks_section_is_refused_naming_its_field_and_creates_no_job(self):
        meshes = self.client.list_meshes()
        part = [{"mesh_id": meshes[0].mesh_id, "count": 2}]
        before = len(self.client.list_jobs())
        cases = [
            ({"mount_id": "mnt_nothere"}, grpc.StatusCode.NOT_FOUND, "spec.picks.mount_id"),
            ({"mount_id": self.other_mount}, grpc.StatusCode.FAILED_PRECONDITION, "spec.picks.mount_id"),
            ({"gripper": {"suction": {"diameter": "NaN"}}}, grpc.StatusCode.INVALID_ARGUMENT,
             "spec.picks.gripper.suction.diameter"),
            ({"gripper": {}}, grpc.StatusCode.INVALID_ARGUMENT, "spec.picks.gripper"),
            ({"pick_options": {"body_length": 1e19}}, grpc.StatusCode.INVALID_ARGUMENT,
             "spec.picks.pick_options.body_length"),
        ]
        for picks, code, field in cases:
            spec = self.spec(**picks)
            del spec.parts[:]
            spec.parts.add(mesh_id=part[0]["mesh_id"], count=2)
            with self.assertRaises(VscanError, msg=str(picks)) as caught:
                self.client.start_bin_fill(spec=spec)
            self.assertEqual(caught.exception.code, code, caught.exception.message)
            self.assertTrue(caught.exception.message.startswith(field), caught.exception.message)
        self.assertEqual(len(self.client.list_jobs()), before)


if __name__ == "__main__":
    unittest.main()
