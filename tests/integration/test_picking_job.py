"""Picking jobs through a real vscand: bins of fixture parts filled in scenes, a UR5 on a pedestal
beside each bin with a 0.1 m tool offset, then a truth-perception job through `vscan pick` (the
pile in every step's truth, the scene afterwards, the tool on the picked part's surface), a
baseline job through Client.start_picking (its scans), a cancelled job resumed, and hostile specs refused
by field with no job created, a good validate_only passing after each."""

import json
import math
import os
import subprocess
import tempfile
import time

import grpc
import numpy as np
import open3d as o3d

from harness import DATA, VSCAN, ServerTestCase, cli_events  # first: puts the stubs on sys.path
from bin_scenes import FIXTURE_PARTS, PARTS_DIR, fill_bin, upload_part
from vscan import Client, SuctionCup, VscanError, parse_ply

from vscan.v1 import job_pb2, job_pb2_grpc  # noqa: E402

C = grpc.StatusCode
UR5_DIR = os.path.join(DATA, "robots", "ur5")
CUP = SuctionCup(diameter=0.010)
CUP_FLAGS = ("--suction-diameter", "0.010")
# The UR5's base beside the bin (0.45 m along +y, turned to face it) on a 0.3 m pedestal, and the
# cup's tool centre point 0.1 m beyond the flange.
WORLD_FROM_BASE = [[0, 1, 0, 0], [-1, 0, 0, 0.45], [0, 0, 1, 0.30], [0, 0, 0, 1]]
TOOL_OFFSET = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.10], [0, 0, 0, 1]]
SMALL_IMAGE = {"width": 320, "height": 256}
INCH_M = 0.0254
# A fill's part types are named after their mesh files.
BLOCK_NAME = FIXTURE_PARTS["angle_block"][0]


def angle_block_surface():
    """A distance query on the angle block's surface in its part frame (metres, the bin's scale)."""
    file, _, scale = FIXTURE_PARTS["angle_block"]
    mesh = o3d.io.read_triangle_mesh(os.path.join(PARTS_DIR, file))
    mesh.scale(INCH_M * scale, center=(0, 0, 0))
    surface = o3d.t.geometry.RaycastingScene()
    surface.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(mesh))
    return surface


class PickingJobTest(ServerTestCase):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-picking-")
        cls.client = Client(cls.server.address, timeout=120)
        cls.jobs = job_pb2_grpc.JobServiceStub(cls.channel)
        cls.parts = {name: upload_part(cls.scenes, name) for name in ("angle_block", "plate_holes")}
        cls.robot = cls.client.upload_robot(UR5_DIR, urdf="ur5_robot.urdf", base="base_link", tip="tool0",
                                            name="ur5").robot_id

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.tmp.cleanup()
        super().tearDownClass()

    # -- helpers ----------------------------------------------------------------------------------

    def filled_cell(self, seed, blocks=6, plates=2):
        """A fresh scene with a settled bin of angle blocks and plates and the UR5 beside it:
        (bin fill job, mount id, scene id)."""
        scene = self.client.create_scene(f"picking-{seed}").scene_id
        counts = [(*self.parts["angle_block"], blocks), (*self.parts["plate_holes"], plates)]
        fill = fill_bin(self.channel, scene, [c for c in counts if c[2] > 0], seed)
        mount = self.client.mount_robot(scene, self.robot, matrix=WORLD_FROM_BASE, tool_matrix=TOOL_OFFSET).mount_id
        return fill, mount, scene

    def part_labels(self, scene):
        return {o.label for o in self.client.get_scene(scene).objects if "#" in o.label}

    def vscan(self, *args):
        return subprocess.run([VSCAN, "--server", self.server.address, *args], capture_output=True, text=True,
                              timeout=300)

    def cli(self, *args):
        done = self.vscan(*args)
        self.assertEqual(done.returncode, 0, done.stderr + done.stdout)
        return done.stdout

    def artifact(self, job_id, name):
        for artifact in self.client.get_job(job_id).artifacts:
            if artifact.name == name:
                return self.client.read_artifact(job_id, artifact.artifact_id)[1]
        self.fail(f"job {job_id} has no {name}")

    def job_ids(self):
        return {j.job_id for j in self.client.list_jobs()}

    # -- (a) true poses through the CLI -----------------------------------------------------------

    def test_truth_job_through_the_cli_picks_parts_off_the_pile(self):
        fill, mount, scene = self.filled_cell(seed=3)
        labels_before = self.part_labels(scene)
        self.assertEqual(len(labels_before), 8)
        started = time.time()
        out = self.vscan("--json", "pick", "run", "--bin-job", fill.job_id, "--mount", mount, *CUP_FLAGS, "--truth",
                         "--max-grasps", "1000", "--name", "truth pick", "--watch")
        self.assertEqual(out.returncode, 0, out.stderr + out.stdout)
        events = cli_events(out.stdout)
        self.assertTrue(any(": picked angle_block.STL#" in e["event"].get("message", "") or
                            ": picked plate_holes.STL#" in e["event"].get("message", "") for e in events), events)
        report = json.loads(out.stdout.splitlines()[-1])  # --json: picking.json last
        job_id = report["job_id"]
        self.assertEqual(report["state"], "SUCCEEDED", report["message"])
        self.assertEqual(report["perception"], "truth")
        self.assertEqual(report["parts_at_start"], 8)
        self.assertGreaterEqual(report["picked"], 1, report)
        self.assertEqual(report["picked"] + report["fell_out"] + report["left"], 8, report)
        self.assertEqual(report["outcomes"].get("picked", 0), report["picked"])
        self.assertEqual(len(report["steps"]), sum(report["outcomes"].values()))
        self.assertLess(time.time() - started, 240)

        # Every step's truth lists the pile it started from; the tool of every pick is on the part.
        block = angle_block_surface()
        picked_labels, block_contacts = set(), 0
        for step in report["steps"]:
            truth = self.client.picking_step_truth(job_id, step["step"])
            self.assertEqual(step["truth_artifact"], f"step-{step['step']:03d}-truth.json")
            self.assertEqual(len(truth["parts"]), step["parts_before"], step)
            self.assertEqual(step["scan_artifact"], "")  # true poses: no scan
            if step["outcome"] != "picked":
                continue
            label = f"{step['picked_part']}#{step['picked_instance'] + 1}"
            self.assertNotIn(label, picked_labels)
            picked_labels.add(label)
            part = next(p for p in truth["parts"]
                        if p["part"] == step["picked_part"] and p["instance"] == step["picked_instance"])
            tool = np.asarray(step["world_from_tool"]).reshape(4, 4)
            if step["picked_part"] != BLOCK_NAME:
                continue
            world_from_part = np.asarray(part["world_from_part"]).reshape(4, 4)
            contact = np.linalg.solve(world_from_part, np.append(tool[:3, 3], 1.0))[:3]
            distance = block.compute_distance(o3d.core.Tensor([contact], dtype=o3d.core.Dtype.Float32)).numpy()[0]
            self.assertLess(distance, 0.002, (label, contact, distance))
            block_contacts += 1
        self.assertEqual(len(picked_labels), report["picked"])
        self.assertGreaterEqual(block_contacts, 1, "no angle block was picked to check its contact")

        # The scene lost the picked parts (and any that fell out), and nothing else.
        removed = labels_before - self.part_labels(scene)
        self.assertTrue(picked_labels <= removed, (picked_labels, removed))
        self.assertEqual(len(removed), report["picked"] + report["fell_out"], (removed, report))
        if report["fell_out"] == 0:
            self.assertEqual(removed, picked_labels)

        # The text summary, and the generic job commands for the kind.
        summary = self.cli("pick", "watch", job_id).splitlines()
        self.assertTrue(summary[-1].startswith(f"{report['picked']} of 8 parts picked in {len(report['steps'])} steps: "
                                               f"{report['picked']} picked"), summary)
        self.assertIn(f"; end: {report['end']}", summary[-1])
        got = self.cli("pick", "get", job_id).splitlines()
        self.assertIn(job_id, got[0])
        self.assertIn("'truth pick'", got[0])
        self.assertEqual(got[-1], summary[-1])
        listed = self.cli("pick", "list")
        self.assertIn(job_id, listed)
        self.assertNotIn(fill.job_id, listed)  # bin fills are not picking jobs
        artifacts = self.cli("pick", "artifacts", job_id)
        for name in ["picking.json"] + [s["truth_artifact"] for s in report["steps"]]:
            self.assertIn(name, artifacts)
        self.assertEqual(self.client.picking_report(job_id), report)

    # -- (b) a scan and the baseline localizer through Python --------------------------------------

    def test_baseline_job_through_python_scans_and_picks(self):
        fill, mount, scene = self.filled_cell(seed=5, blocks=6, plates=0)
        job = self.client.start_picking(fill.job_id, mount, CUP, max_grasps=1000, **SMALL_IMAGE)
        self.assertEqual(job.kind, "picking")
        self.assertEqual(job.picking.bin_job_id, fill.job_id)
        self.assertEqual(job.picking.perception, job_pb2.PICKING_PERCEPTION_UNSPECIFIED)
        job = self.client.wait_job(job.job_id, timeout=240)
        self.assertEqual(job.state, job_pb2.JOB_STATE_SUCCEEDED, job.message)
        report = self.client.picking_report(job.job_id)
        self.assertEqual(report["perception"], "baseline")
        self.assertEqual(report["parts_at_start"], 6)
        self.assertGreaterEqual(report["picked"], 1, report)
        scanned = [s for s in report["steps"] if s["scan_artifact"]]
        self.assertEqual(len(scanned), len(report["steps"]))
        for step in scanned:
            self.assertEqual(step["scan_artifact"], f"step-{step['step']:03d}.ply")
            points = parse_ply(self.artifact(job.job_id, step["scan_artifact"])).positions
            self.assertGreater(len(points), 10000)
            self.assertTrue(np.isfinite(points).all())
            self.assertGreater(step["perceive_s"], 0)
            truth = self.client.picking_step_truth(job.job_id, step["step"])
            self.assertEqual(len(truth["parts"]), step["parts_before"])
            self.assertEqual(len(truth["estimates"]), step["estimates"])

    # -- (c) cancel and resume ---------------------------------------------------------------------

    def test_cancel_ends_the_job_with_its_report_and_resume_goes_on(self):
        fill, mount, _ = self.filled_cell(seed=7)
        started = json.loads(self.cli("--json", "pick", "run", "--bin-job", fill.job_id, "--mount", mount,
                                      *CUP_FLAGS, "--max-grasps", "1000", "--width", "320", "--height", "256",
                                      "--max-steps", "10000", "--max-failures", "10000"))
        job_id = started["job"]["jobId"]
        deadline = time.time() + 60
        while self.client.get_job(job_id).state == job_pb2.JOB_STATE_QUEUED and time.time() < deadline:
            time.sleep(0.05)
        self.cli("pick", "cancel", job_id)
        job = self.client.wait_job(job_id, timeout=120)
        self.assertEqual(job.state, job_pb2.JOB_STATE_CANCELLED, job.message)
        report = self.client.picking_report(job_id)
        self.assertIsNotNone(report, [a.name for a in job.artifacts])
        self.assertEqual(report["state"], "CANCELLED")
        self.assertLess(len(report["steps"]), 8)
        # Resumed, it goes on from the pile the scene holds: the cancelled run's picks stay done.
        out = self.cli("--json", "pick", "resume", job_id, "--watch")
        resumed = json.loads(out.splitlines()[-1])
        self.assertEqual(resumed["job_id"], job_id)
        self.assertEqual(resumed["state"], "SUCCEEDED", resumed["message"])
        self.assertEqual(resumed["parts_at_start"], 8 - report["picked"] - report["fell_out"], (report, resumed))
        self.assertGreaterEqual(report["picked"] + resumed["picked"], 1)
        # An ended job deletes through the kind's group, and is gone.
        self.cli("pick", "delete", job_id)
        gone = self.vscan("pick", "get", job_id)
        self.assertEqual(gone.returncode, 3, gone.stdout + gone.stderr)
        self.assertNotIn(job_id, self.job_ids())

    # -- (d) hostile specs -----------------------------------------------------------------------

    def assertRefused(self, code, field, spec, good):
        """spec (a PickingSpec or None for none) is refused naming field; no job appears; good passes."""
        before = self.job_ids()
        request = job_pb2.StartPickingRequest() if spec is None else job_pb2.StartPickingRequest(spec=spec)
        with self.assertRaises(grpc.RpcError) as refused:
            self.jobs.StartPicking(request, timeout=60)
        self.assertEqual(refused.exception.code(), code, refused.exception.details())
        self.assertIn(field, refused.exception.details())
        self.assertEqual(self.job_ids(), before)
        self.jobs.StartPicking(job_pb2.StartPickingRequest(spec=good, validate_only=True), timeout=60)

    def test_hostile_specs_are_refused_by_field(self):
        fill, mount, _ = self.filled_cell(seed=11, blocks=3, plates=1)
        good = job_pb2.PickingSpec(bin_job_id=fill.job_id, mount_id=mount)
        good.gripper.suction.diameter = 0.010
        self.client.validate_picking(fill.job_id, mount, CUP)

        def spec(**changes):
            out = job_pb2.PickingSpec()
            out.CopyFrom(good)
            for name, value in changes.items():
                setattr(out, name, value)
            return out

        def cup(diameter):
            out = spec()
            out.gripper.suction.diameter = diameter
            return out

        no_gripper = spec()
        no_gripper.ClearField("gripper")

        # A job that is not a bin fill, and a bin fill that did not succeed.
        other = self.client.start_picking(fill.job_id, mount, CUP, truth=True, max_steps=1)
        other = self.client.wait_job(other.job_id, timeout=120)
        self.assertEqual(other.state, job_pb2.JOB_STATE_SUCCEEDED, other.message)
        stopped = self.client.start_bin_fill(self.client.create_scene("stopped").scene_id, (0.24, 0.18, 0.10),
                                             [{"mesh_id": self.parts["angle_block"][0], "count": 200}])
        stopped = self.client.cancel_job(stopped.job_id)
        stopped = self.client.wait_job(stopped.job_id, timeout=120)
        self.assertNotEqual(stopped.state, job_pb2.JOB_STATE_SUCCEEDED)
        # A mount in another scene.
        elsewhere = self.client.create_scene("elsewhere").scene_id
        foreign = self.client.mount_robot(elsewhere, self.robot, matrix=WORLD_FROM_BASE).mount_id

        cases = [
            (C.INVALID_ARGUMENT, "spec", None),
            (C.INVALID_ARGUMENT, "spec.bin_job_id", spec(bin_job_id="")),
            (C.NOT_FOUND, "spec.bin_job_id", spec(bin_job_id="job_0000000000000000")),
            (C.INVALID_ARGUMENT, "spec.bin_job_id", spec(bin_job_id="../../etc/passwd")),
            (C.FAILED_PRECONDITION, "spec.bin_job_id", spec(bin_job_id=other.job_id)),
            (C.FAILED_PRECONDITION, "spec.bin_job_id", spec(bin_job_id=stopped.job_id)),
            (C.FAILED_PRECONDITION, "spec.mount_id", spec(mount_id=foreign)),
            (C.INVALID_ARGUMENT, "spec.mount_id", spec(mount_id="")),
            (C.NOT_FOUND, "spec.mount_id", spec(mount_id="mnt_0000000000000000")),
            (C.INVALID_ARGUMENT, "spec.gripper.suction.diameter", cup(math.nan)),
            (C.INVALID_ARGUMENT, "spec.gripper.suction.diameter", cup(1e19)),
            (C.INVALID_ARGUMENT, "spec.gripper", no_gripper),
            (C.INVALID_ARGUMENT, "spec.width", spec(width=100000)),
            (C.INVALID_ARGUMENT, "spec.max_steps", spec(max_steps=10 ** 9)),
            (C.INVALID_ARGUMENT, "spec.horizontal_fov_deg", spec(horizontal_fov_deg=math.nan)),
            (C.INVALID_ARGUMENT, "spec.perception", spec(perception=7)),
        ]
        for code, field, bad in cases:
            with self.subTest(field=field, spec=str(bad)[:80]):
                self.assertRefused(code, field, bad, good)

        # The front doors say the same: the CLI exits 3 naming the field, Python raises VscanError.
        done = self.vscan("pick", "run", "--bin-job", fill.job_id, "--mount", mount, "--suction-diameter", "1e19",
                          "--validate-only")
        self.assertEqual(done.returncode, 3, done.stdout + done.stderr)
        self.assertIn("spec.gripper.suction.diameter", done.stderr)
        with self.assertRaises(VscanError) as refused:
            self.client.start_picking(fill.job_id, foreign, CUP)
        self.assertEqual(refused.exception.code, C.FAILED_PRECONDITION)
        self.assertIn("spec.mount_id", refused.exception.message)
        self.assertIn("the server accepts", self.cli("pick", "run", "--bin-job", fill.job_id, "--mount", mount,
                                                     *CUP_FLAGS, "--validate-only"))
