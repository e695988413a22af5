"""PickingService through a real vscand: a UR5 on a 0.2 m pedestal over 40 x 30 x 20 mm blocks
(one within reach, one 2.5 m away, one under another), checked with `vscan picks` and
Client.check_picks; grasps of the block with `vscan grasps` and Client.generate_grasps; hostile
requests refused by field, the server answering a good request after each."""

import json
import math
import os
import struct
import subprocess
import tempfile

import grpc
import numpy as np

from harness import DATA, VSCAN, ServerTestCase  # first: puts the stubs on sys.path
from vscan import Client, ParallelJaws, SuctionCup, VscanError

C = grpc.StatusCode
UR5_DIR = os.path.join(DATA, "robots", "ur5")
# The block's corners in millimetres, its bottom face on z = 0.
BLOCK_MM = ((-20.0, -15.0, 0.0), (20.0, 15.0, 20.0))
CUP = SuctionCup(diameter=0.012)
CUP_FLAGS = ("--suction-diameter", "0.012")
# The UR5 carries no tool offset: the gripper's body behind the flange is given.
BODY = 0.08


def box_triangles(low, high):
    """The 12 triangles of an axis-aligned box, wound counter-clockwise seen from outside."""
    corners = [(x, y, z) for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])]
    centre = np.mean(corners, axis=0)
    faces = []
    for axis in range(3):
        for side in (0, 1):
            quad = [c for c in corners if c[axis] == (low, high)[side][axis]]
            a, b, d, c = (np.array(p) for p in quad)  # quad order: a b / c d in the other two axes
            for tri in ((a, b, c), (a, c, d)):
                normal = np.cross(tri[1] - tri[0], tri[2] - tri[0])
                if np.dot(normal, np.mean(tri, axis=0) - centre) < 0:
                    tri = (tri[0], tri[2], tri[1])
                faces.append(tri)
    return faces


def binary_stl(triangles):
    out = bytearray(b"vscan picks test block".ljust(80, b" "))
    out += struct.pack("<I", len(triangles))
    for tri in triangles:
        normal = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        normal = normal / np.linalg.norm(normal)
        out += struct.pack("<12fH", *normal, *tri[0], *tri[1], *tri[2], 0)
    return bytes(out)


def ascii_stl(triangles, name="floor"):
    lines = [f"solid {name}"]
    for tri in triangles:
        normal = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        normal = normal / np.linalg.norm(normal)
        lines.append("  facet normal {:.6f} {:.6f} {:.6f}\n    outer loop".format(*normal))
        lines += ["      vertex {:.6f} {:.6f} {:.6f}".format(*v) for v in tri]
        lines.append("    endloop\n  endfacet")
    lines.append(f"endsolid {name}")
    return ("\n".join(lines) + "\n").encode()


def floor_triangles(half):
    """A square at z = 0 facing up."""
    a, b, c, d = (np.array(p, float) for p in ((-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)))
    return [(a, b, c), (a, c, d)]


def write_scene_files(directory):
    """block.stl (binary, millimetres) and floor.stl (ASCII, a 2 m square in metres); their paths."""
    block, floor = os.path.join(directory, "block.stl"), os.path.join(directory, "floor.stl")
    with open(block, "wb") as f:
        f.write(binary_stl(box_triangles(*BLOCK_MM)))
    with open(floor, "wb") as f:
        f.write(ascii_stl(floor_triangles(1.0)))
    return block, floor


class PicksTest(ServerTestCase):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-picks-")
        block_path, floor_path = write_scene_files(cls.tmp.name)
        cls.client = Client(cls.server.address, timeout=120)
        cls.block = cls.client.upload_mesh(block_path, unit="mm").mesh_id
        floor = cls.client.upload_mesh(floor_path, unit="m").mesh_id
        cls.scene = cls.client.create_scene("picks").scene_id
        cls.client.add_object(cls.scene, floor, label="floor")

        def block(position, label):
            return cls.client.add_object(cls.scene, cls.block, position=position, label=label).object_id
        cls.near = block((0.45, 0.1, 0.0), "block#1")
        cls.far = block((2.5, 0.0, 0.0), "block#2")
        cls.under = block((0.4, -0.1, 0.0), "block#3")
        cls.over = block((0.41, -0.1, 0.0202), "block#4")
        robot = cls.client.upload_robot(UR5_DIR, urdf="ur5_robot.urdf", base="base_link", tip="tool0", name="ur5")
        cls.mount = cls.client.mount_robot(cls.scene, robot.robot_id, position=(0, 0, 0.2)).mount_id

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.tmp.cleanup()
        super().tearDownClass()

    def vscan(self, *args):
        return subprocess.run([VSCAN, "--server", self.server.address, *args], capture_output=True, text=True,
                              timeout=300)

    def cli(self, *args):
        done = self.vscan(*args)
        self.assertEqual(done.returncode, 0, done.stderr + done.stdout)
        return done.stdout

    def assertRefused(self, code, field, call):
        with self.assertRaises(VscanError) as refused:
            call()
        self.assertEqual(refused.exception.code, code, refused.exception.message)
        self.assertIn(field, refused.exception.message)

    def assertCliRefused(self, field, *args):
        done = self.vscan(*args)
        self.assertEqual(done.returncode, 3, done.stderr + done.stdout)
        self.assertIn(field, done.stderr)

    # -- the verdicts, through both front doors ---------------------------------------------------

    def assertNearBlockPicked(self, tool, joints):
        """The cup on the near block's top face (z = 20 mm, within its 40 x 30 mm), pointing down."""
        tool = np.asarray(tool).reshape(4, 4)
        self.assertAlmostEqual(tool[2, 3], 0.02, delta=1e-5)
        self.assertLess(abs(tool[0, 3] - 0.45), 0.02)
        self.assertLess(abs(tool[1, 3] - 0.1), 0.015)
        self.assertAlmostEqual(tool[2, 2], -1.0, delta=1e-5)
        self.assertEqual(len(joints), 6)

    def test_cli_picks_each_block_with_its_verdict(self):
        out = json.loads(self.cli("--json", "picks", "--mount", self.mount, *CUP_FLAGS, "--body-length", str(BODY)))
        parts = {p["objectId"]: p for p in out["parts"]}
        self.assertEqual(set(parts), {self.near, self.far, self.under, self.over})
        self.assertEqual(out["sceneId"], self.scene)
        near = parts[self.near]
        self.assertTrue(near["pickable"], near)
        self.assertEqual(near["label"], "block#1")
        self.assertNearBlockPicked(near["worldFromTool"]["matrix"]["values"], near["jointPositions"])
        self.assertEqual(parts[self.far]["failure"], "PICK_FAILURE_UNREACHABLE", parts[self.far])
        self.assertFalse(parts[self.far]["pickable"])
        self.assertEqual(parts[self.under]["failure"], "PICK_FAILURE_COVERED", parts[self.under])
        self.assertEqual(parts[self.under]["coveredByObjectId"], self.over)
        self.assertTrue(parts[self.over]["pickable"], parts[self.over])
        self.assertEqual(out["pickable"], 2)

        # The text: one line per part, then the summary.
        text = self.cli("picks", "--mount", self.mount, "--part", self.near, "--part", self.far, "--part",
                        self.under, "--part", self.over, *CUP_FLAGS, "--body-length", str(BODY)).splitlines()
        self.assertEqual(len(text), 5, text)
        self.assertTrue(text[0].startswith(f"block#1  {self.near}  pickable: grasp "), text[0])
        self.assertIn("approach (", text[0])
        self.assertIn("tool at (", text[0])
        self.assertTrue(text[1].startswith(f"block#2  {self.far}  UNREACHABLE"), text[1])
        self.assertTrue(text[2].startswith(f"block#3  {self.under}  COVERED"), text[2])
        self.assertIn(f"covered by {self.over}", text[2])
        self.assertTrue(text[3].startswith(f"block#4  {self.over}  pickable: "), text[3])
        self.assertTrue(text[4].startswith("2 of 4 parts pickable"), text[4])

    def test_python_client_picks_each_block_with_its_verdict(self):
        picks = self.client.check_picks(self.mount, CUP, body_length=BODY)
        self.assertEqual(picks.scene_id, self.scene)
        self.assertEqual([p.object_id for p in picks.parts], [self.near, self.far, self.under, self.over])
        near = picks.by_object(self.near)
        self.assertTrue(near.pickable, near)
        self.assertIsNone(near.failure)
        self.assertNearBlockPicked(near.world_from_tool, near.joint_positions)
        self.assertEqual(picks.by_object(self.far).failure, "UNREACHABLE")
        self.assertIsNone(picks.by_object(self.far).world_from_tool)
        under = picks.by_object(self.under)
        self.assertEqual(under.failure, "COVERED")
        self.assertEqual(under.covered_by_object_id, self.over)
        self.assertEqual(picks.pickable, 2)
        self.assertGreater(picks.grasps_generated, 0)
        # Named parts only, in the order named; the gripper as a dict.
        named = self.client.check_picks(self.mount, {"suction": {"diameter": 0.012}}, [self.over, self.under],
                                        body_length=BODY)
        self.assertEqual([p.object_id for p in named.parts], [self.over, self.under])
        self.assertEqual(named.parts[1].failure, "COVERED")
        self.assertEqual(named.parts[1].covered_by_object_id, self.over)

    def test_grasps_of_the_block_are_sorted_and_in_unit_range(self):
        out = json.loads(self.cli("--json", "grasps", "--mesh", self.block, *CUP_FLAGS, "--max-grasps", "50"))
        qualities = [g["quality"] for g in out["grasps"]]
        self.assertGreater(len(qualities), 0)
        self.assertLessEqual(len(qualities), 50)
        self.assertEqual(qualities, sorted(qualities, reverse=True))
        self.assertTrue(all(0 <= q <= 1 for q in qualities), qualities)

        grasps = self.client.generate_grasps(self.block, CUP, max_grasps=50)
        self.assertEqual([g.quality for g in grasps], qualities)  # the same seed: the same grasps
        for grasp in grasps:
            # The cup's centre on the block's surface, the approach along minus a face normal.
            self.assertTrue(np.allclose(grasp.approach, grasp.part_from_tool[:3, 2]))
            self.assertAlmostEqual(np.abs(grasp.approach).max(), 1.0, delta=1e-6)
            low, high = np.array(BLOCK_MM) / 1000
            self.assertTrue(np.all(grasp.position >= low - 1e-6) and np.all(grasp.position <= high + 1e-6))
            self.assertEqual(grasp.opening, 0)

        text = self.cli("grasps", "--mesh", self.block, *CUP_FLAGS, "--max-grasps", "5").splitlines()
        self.assertTrue(text[0].startswith("5 grasps in "), text)
        self.assertEqual(len(text), 2 + 5)
        self.assertEqual(float(text[2].split()[1]), round(qualities[0], 3))

        # Jaws opening to 35 mm grip the block across its 30 and 20 mm sides.
        jaws = self.client.generate_grasps(self.block, ParallelJaws(max_opening=0.035), max_grasps=200)
        self.assertGreater(len(jaws), 0)
        self.assertTrue(all(abs(g.opening - 0.03) < 1e-4 or abs(g.opening - 0.02) < 1e-4 for g in jaws))
        jaw_cli = json.loads(self.cli("--json", "grasps", "--mesh", self.block, "--jaws-max-opening", "0.035",
                                      "--max-grasps", "200"))
        self.assertEqual(len(jaw_cli["grasps"]), len(jaws))
        # Scale: the block at 2x is 60 mm tall; a 50 mm cup then fits its 80 x 60 faces.
        self.assertEqual(self.client.generate_grasps(self.block, SuctionCup(diameter=0.05)), [])
        self.assertGreater(len(self.client.generate_grasps(self.block, SuctionCup(diameter=0.05), scale=2)), 0)

    # -- hostile requests ----------------------------------------------------------------------------

    def assertStillServing(self):
        picks = self.client.check_picks(self.mount, CUP, [self.near], body_length=BODY)
        self.assertTrue(picks.parts[0].pickable)

    def test_hostile_requests_are_refused_by_field_and_change_nothing(self):
        hostile = [
            (C.INVALID_ARGUMENT, "gripper", lambda: self.client.check_picks(self.mount, None)),
            (C.INVALID_ARGUMENT, "gripper", lambda: self.client.generate_grasps(self.block, None)),
            (C.INVALID_ARGUMENT, "gripper.suction.diameter",
             lambda: self.client.check_picks(self.mount, SuctionCup(diameter=math.nan))),
            (C.INVALID_ARGUMENT, "gripper.suction.diameter",
             lambda: self.client.check_picks(self.mount, SuctionCup(diameter=1e19))),
            (C.INVALID_ARGUMENT, "gripper.suction.diameter",
             lambda: self.client.generate_grasps(self.block, SuctionCup(diameter=math.nan))),
            (C.INVALID_ARGUMENT, "gripper.suction.diameter",
             lambda: self.client.generate_grasps(self.block, SuctionCup(diameter=1e19))),
            (C.INVALID_ARGUMENT, "gripper.jaws.max_opening",
             lambda: self.client.generate_grasps(self.block, ParallelJaws(max_opening=math.inf))),
            (C.NOT_FOUND, "mount_id", lambda: self.client.check_picks("mnt_nothere", CUP)),
            (C.NOT_FOUND, "part_object_ids[0]", lambda: self.client.check_picks(self.mount, CUP, ["obj_nothere"])),
            (C.INVALID_ARGUMENT, "part_object_ids[1]",
             lambda: self.client.check_picks(self.mount, CUP, [self.near, self.near])),
            (C.INVALID_ARGUMENT, "pick_options.ik_time_budget_ms",
             lambda: self.client.check_picks(self.mount, CUP, ik_time_budget_ms=5000)),
            (C.INVALID_ARGUMENT, "scale", lambda: self.client.generate_grasps(self.block, CUP, scale=math.nan)),
            (C.INVALID_ARGUMENT, "scale", lambda: self.client.generate_grasps(self.block, CUP, scale=1e19)),
            (C.NOT_FOUND, "msh_nothere", lambda: self.client.generate_grasps("msh_nothere", CUP)),
            # Ids no record can have.
            (C.INVALID_ARGUMENT, "mesh_id", lambda: self.client.generate_grasps("../" + self.block, CUP)),
            (C.INVALID_ARGUMENT, "mount_id", lambda: self.client.check_picks("", CUP)),
            (C.INVALID_ARGUMENT, "part_object_ids[1]", lambda: self.client.check_picks(self.mount, CUP,
                                                                                      [self.near, "obj\x00"])),
            # Options beyond their bounds.
            (C.INVALID_ARGUMENT, "pick_options.max_reach_checks",
             lambda: self.client.check_picks(self.mount, CUP, max_reach_checks=2**32 - 1)),
            (C.INVALID_ARGUMENT, "pick_options.approach_distance",
             lambda: self.client.check_picks(self.mount, CUP, approach_distance=math.nan)),
            (C.INVALID_ARGUMENT, "grasp_options.max_grasps",
             lambda: self.client.generate_grasps(self.block, CUP, max_grasps=2**32 - 1)),
            (C.INVALID_ARGUMENT, "pick_options.body_length",
             lambda: self.client.check_picks(self.mount, CUP, body_length=1e19)),
        ]
        revision = self.client.get_scene(self.scene).revision
        for code, field, call in hostile:
            with self.subTest(field=field, code=code):
                self.assertRefused(code, field, call)
                self.assertStillServing()
        self.assertEqual(self.client.get_scene(self.scene).revision, revision)
        self.assertEqual(self.server.process.poll(), None)

    def test_cli_sends_values_as_given_and_reports_the_servers_refusal(self):
        self.assertCliRefused("gripper", "picks", "--mount", self.mount)
        self.assertCliRefused("gripper.suction.diameter", "picks", "--mount", self.mount, "--suction-diameter", "nan")
        self.assertCliRefused("gripper.suction.diameter", "grasps", "--mesh", self.block, "--suction-diameter",
                              "1e19")
        self.assertCliRefused("pick_options.ik_time_budget_ms", "picks", "--mount", self.mount, *CUP_FLAGS, "--ik-budget-ms", "5000")
        self.assertCliRefused("part_object_ids[1]", "picks", "--mount", self.mount, *CUP_FLAGS, "--part", self.near,
                              "--part", self.near)
        self.assertCliRefused("scale", "grasps", "--mesh", self.block, *CUP_FLAGS, "--scale", "nan")
        # What cannot be parsed, or one gripper's flags mixed with the other's, never reaches the server.
        for args in (("grasps", "--mesh", self.block, "--suction-diameter", "wide"),
                     ("grasps", "--mesh", self.block, "--max-grasps", "-1"),
                     ("grasps", "--mesh", self.block, "--suction-diameter", "0.01", "--jaws-max-opening", "0.03")):
            with self.subTest(args=args):
                done = self.vscan(*args)
                self.assertEqual(done.returncode, 2, done.stderr + done.stdout)
        self.assertStillServing()
