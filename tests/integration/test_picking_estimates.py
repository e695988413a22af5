"""Picking jobs planned on a client's own localizer through a real vscand: Client.run_picking with an
estimator that answers each step with the pile from the step's truth file (what a localizer would
approximate) empties the bin as the truth perception does; the CLI's `vscan pick run --perception
client` and `vscan pick estimates`; hostile submits refused by field with the job still waiting;
a server stopped while a job waits, and one killed with -9, then ResumeJob going on from the step
the job waited on."""

import json
import math
import os
import subprocess
import tempfile
import time
import unittest

import grpc
import numpy as np

from harness import VSCAN, Server, ServerTestCase  # first: puts the stubs on sys.path
from bin_scenes import fill_bin, upload_part
from test_picking_job import CUP, CUP_FLAGS, TOOL_OFFSET, UR5_DIR, WORLD_FROM_BASE
from vscan import Client, VscanError, picking_spec

from vscan.v1 import job_pb2, job_pb2_grpc, scene_pb2_grpc  # noqa: E402

C = grpc.StatusCode
SMALL = {"width": 320, "height": 256, "max_grasps": 1000}
ENDED = (job_pb2.JOB_STATE_SUCCEEDED, job_pb2.JOB_STATE_FAILED, job_pb2.JOB_STATE_CANCELLED,
         job_pb2.JOB_STATE_INTERRUPTED)


def truth_estimator(client, job_id, seen=None):
    """estimator(step, points) answering with the true pile of the step's truth file."""
    def estimate(step, points):
        if seen is not None:
            seen.append((step, len(points)))
        truth = client.picking_step_truth(job_id, step)
        return [(p["part"], np.asarray(p["world_from_part"]).reshape(4, 4), 1.0) for p in truth["parts"]]
    return estimate


def wait_until(client, job_id, until, timeout=120):
    deadline = time.time() + timeout
    while True:
        job = client.get_job(job_id)
        if until(job):
            return job
        if time.time() > deadline:
            raise AssertionError(f"job {job_id} {job_pb2.JobState.Name(job.state)}: {job.message}")
        time.sleep(0.05)


def awaiting(step):
    return lambda job: (job.HasField("awaiting_estimates") and job.awaiting_estimates.step == step) or \
        job.state in ENDED


class Cell:
    """A UR5 beside a settled bin of angle blocks in a fresh scene of client's server."""

    def __init__(self, client, channel, robot, block, seed, blocks=4):
        scene = client.create_scene(f"estimates-{seed}").scene_id
        self.fill = fill_bin(channel, scene, [(*block, blocks)], seed)
        self.mount = client.mount_robot(scene, robot, matrix=WORLD_FROM_BASE, tool_matrix=TOOL_OFFSET).mount_id
        self.scene = scene

    def spec(self, perception, **options):
        return picking_spec(self.fill.job_id, self.mount, CUP, perception=perception, **{**SMALL, **options})


class PickingEstimatesTest(ServerTestCase):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.client = Client(cls.server.address, timeout=120)
        cls.jobs = job_pb2_grpc.JobServiceStub(cls.channel)
        cls.block = upload_part(cls.scenes, "angle_block")
        cls.robot = cls.client.upload_robot(UR5_DIR, urdf="ur5_robot.urdf", base="base_link", tip="tool0",
                                            name="ur5").robot_id

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        super().tearDownClass()

    def cell(self, seed, blocks=4):
        return Cell(self.client, self.channel, self.robot, self.block, seed, blocks)

    def test_python_loop_with_the_true_poses_picks_as_the_truth_perception_does(self):
        truth_job = self.client.start_picking(None, None, None, spec=self.cell(seed=5).spec("truth"))
        truth_report = self.client.picking_report(self.client.wait_job(truth_job.job_id).job_id)

        cell = self.cell(seed=5)  # the same fill in a scene of its own
        job = self.client.start_picking(None, None, None, spec=cell.spec("client"))
        seen = []
        done = self.client.run_picking(None, truth_estimator(self.client, job.job_id, seen), job_id=job.job_id,
                                       timeout=300)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        self.assertFalse(done.HasField("awaiting_estimates"))
        report = self.client.picking_report(done.job_id)
        self.assertEqual(report["perception"], "client")
        self.assertEqual([s["outcome"] for s in report["steps"]], [s["outcome"] for s in truth_report["steps"]])
        self.assertEqual(report["picked"], truth_report["picked"])
        self.assertGreaterEqual(report["picked"], 1, report)
        self.assertEqual(report["end"], truth_report["end"])
        # One estimator call per step, each on the step's scan of the pile.
        self.assertEqual([s for s, _ in seen], [s["step"] for s in report["steps"]])
        self.assertTrue(all(points > 1000 for _, points in seen), seen)
        for step in report["steps"]:
            self.assertEqual(step["scan_artifact"], f"step-{step['step']:03d}.ply")
            self.assertEqual(step["estimates"], step["parts_before"])

    def test_camera_frame_estimates_are_taken_in_the_scan_sensor_frame(self):
        cell = self.cell(seed=6, blocks=3)
        job = self.client.start_picking(None, None, None, spec=cell.spec("client", max_steps=1))
        awaited = wait_until(self.client, job.job_id, awaiting(0)).awaiting_estimates
        world_from_sensor = np.asarray(awaited.world_from_sensor.values).reshape(4, 4)
        truth = self.client.picking_step_truth(job.job_id, 0)
        in_camera = [(p["part"], np.linalg.solve(world_from_sensor, np.asarray(p["world_from_part"]).reshape(4, 4)),
                      1.0) for p in truth["parts"]]
        self.assertEqual(self.client.submit_picking_estimates(job.job_id, 0, in_camera, frame="camera"), 3)
        done = self.client.wait_job(job.job_id)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        self.assertEqual(self.client.picking_report(job.job_id)["steps"][0]["outcome"], "picked")

    def test_cli_runs_a_client_job_and_sends_a_truth_file_as_estimates(self):
        cell = self.cell(seed=7, blocks=3)
        out = self.vscan("--quiet", "pick", "run", "--bin-job", cell.fill.job_id, "--mount", cell.mount, *CUP_FLAGS,
                         "--perception", "client", "--estimates-timeout", "120", "--max-steps", "2",
                         "--max-grasps", "1000", "--width", "320", "--height", "256")
        job_id = out.strip().splitlines()[-1]
        self.assertTrue(job_id.startswith("job_"), out)
        with tempfile.TemporaryDirectory() as tmp:
            for step in range(2):
                job = wait_until(self.client, job_id, awaiting(step))
                self.assertEqual(job.state, job_pb2.JOB_STATE_RUNNING, job.message)
                self.assertIn(f"awaiting estimates for step {step} (scan step-{step:03d}.ply)",
                              self.vscan("pick", "get", job_id))
                path = os.path.join(tmp, f"truth-{step}.json")
                with open(path, "w") as f:
                    json.dump(self.client.picking_step_truth(job_id, step), f)
                said = self.vscan("pick", "estimates", job_id, "--step", str(step), path, "--from-parts")
                self.assertIn(f"step {step}: {3 - step} estimates stored", said)
            done = self.client.wait_job(job_id)
            self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
            report = self.client.picking_report(job_id)
            self.assertEqual(report["perception"], "client")
            self.assertEqual(report["picked"], 2, report)
            self.assertEqual(len(report["steps"]), 2)
            late = self.run_vscan("pick", "estimates", job_id, "--step", "2", path)
            self.assertEqual(late.returncode, 3, late.stderr)
            self.assertIn("not running", late.stderr)

    def test_hostile_submits_are_refused_by_field_and_the_job_still_waits(self):
        cell = self.cell(seed=8, blocks=3)
        for timeout in (math.nan, -1.0, 1e19, 0.01):
            with self.assertRaises(VscanError) as refused:
                self.client.validate_picking(None, None, None, spec=cell.spec("client", estimates_timeout_s=timeout))
            self.assertEqual(refused.exception.code, C.INVALID_ARGUMENT)
            self.assertIn("spec.estimates_timeout_s", str(refused.exception))
        truth_cell = self.cell(seed=9, blocks=2)  # filled first: a waiting job holds a job runner
        job = self.client.start_picking(None, None, None, spec=cell.spec("client"))
        wait_until(self.client, job.job_id, awaiting(0))
        truth = self.client.picking_step_truth(job.job_id, 0)
        good = [(p["part"], np.asarray(p["world_from_part"]).reshape(4, 4), 1.0) for p in truth["parts"]]
        part = good[0][0]
        nan_pose = np.eye(4)
        nan_pose[0, 3] = math.nan
        far_pose = np.eye(4)
        far_pose[2, 3] = 1e19

        def shifted(i):
            pose = np.eye(4)
            pose[:3, 3] = (0.45 + 1e-5 * i, 0.0, 0.05)
            return pose

        def submit(estimates, step=0, job_id=job.job_id, **kwargs):
            return lambda: self.client.submit_picking_estimates(job_id, step, estimates, **kwargs)

        cases = [
            (C.NOT_FOUND, submit(good, job_id="job_0123456789abcdef"), "job_id"),
            (C.INVALID_ARGUMENT, submit(good, job_id="not a job"), "job_id"),
            (C.FAILED_PRECONDITION, submit(good, step=1), "awaits the estimates of step 0"),
            (C.FAILED_PRECONDITION, submit(good, step=4294967295), "step 0"),
            (C.INVALID_ARGUMENT, submit([good[0], (part, nan_pose, 1.0)]), "estimates[1].world_from_part"),
            (C.INVALID_ARGUMENT, submit([(part, far_pose, 1.0)]), "estimates[0].world_from_part"),
            (C.INVALID_ARGUMENT, submit([(part, far_pose, 1.0)], frame="camera"), "estimates[0].camera_from_part"),
            (C.INVALID_ARGUMENT, submit([good[0], ("no such part", np.eye(4), 1.0)]), "estimates[1].part"),
            (C.INVALID_ARGUMENT, submit([good[0], good[1], good[0]]), "estimates[2]"),
            (C.INVALID_ARGUMENT, submit([(part, np.eye(4), math.nan)]), "estimates[0].score"),
            (C.INVALID_ARGUMENT, submit([(part, 2 * np.eye(4), 1.0)]), "estimates[0].world_from_part"),
            (C.RESOURCE_EXHAUSTED, submit([(part, np.eye(4), 1.0)] * 10001), "estimates"),
            # Under the count bound, but the plan would test every grasp of each (138 a block).
            (C.RESOURCE_EXHAUSTED, submit([(part, shifted(i), 1.0) for i in range(9999)]), "grasps, at most 1e6"),
        ]
        for code, call, field in cases:
            with self.assertRaises(VscanError) as refused:
                call()
            self.assertEqual(refused.exception.code, code, (field, str(refused.exception)))
            self.assertIn(field, str(refused.exception))
        # Neither pose, or both, through the raw stub.
        for pose_fields in ({}, {"world_from_part": 1, "camera_from_part": 1}):
            request = job_pb2.SubmitPickingEstimatesRequest(job_id=job.job_id, step=0)
            estimate = request.estimates.add(part=part, score=1.0)
            for field in pose_fields:
                getattr(estimate, field).matrix.values.extend(np.eye(4).ravel())
            with self.assertRaises(grpc.RpcError) as refused:
                self.jobs.SubmitPickingEstimates(request, timeout=30)
            self.assertEqual(refused.exception.code(), C.INVALID_ARGUMENT)
            self.assertIn("estimates[0].world_from_part", refused.exception.details())
        # Nothing was taken: the job still waits on step 0 and no estimates file was written.
        still = self.client.get_job(job.job_id)
        self.assertEqual(still.awaiting_estimates.step, 0, still.message)
        store = os.path.join(self.server.data_dir, "store", "picking", job.job_id)
        self.assertFalse(os.path.exists(os.path.join(store, "step-000-estimates.json")))
        # A truth job takes no estimates.
        truth_job = self.client.start_picking(None, None, None, spec=truth_cell.spec("truth"))
        with self.assertRaises(VscanError) as refused:
            self.client.submit_picking_estimates(truth_job.job_id, 0, good)
        self.assertEqual(refused.exception.code, C.FAILED_PRECONDITION)
        self.assertIn("does not take client estimates", str(refused.exception))

        # The good ones are stored before the answer; the same step again is refused.
        self.assertEqual(self.client.submit_picking_estimates(job.job_id, 0, good), 3)
        with open(os.path.join(store, "step-000-estimates.json")) as f:
            self.assertEqual(len(json.load(f)["estimates"]), 3)
        with self.assertRaises(VscanError) as refused:
            self.client.submit_picking_estimates(job.job_id, 0, good)
        self.assertIn(refused.exception.code, (C.ALREADY_EXISTS, C.FAILED_PRECONDITION), str(refused.exception))

        # A cancel while the job waits on step 1 ends it at once.
        wait_until(self.client, job.job_id, awaiting(1))
        asked = time.time()
        self.client.cancel_job(job.job_id)
        cancelled = wait_until(self.client, job.job_id, lambda j: j.state in ENDED, timeout=30)
        self.assertLess(time.time() - asked, 2.0)
        self.assertEqual(cancelled.state, job_pb2.JOB_STATE_CANCELLED, cancelled.message)
        self.assertFalse(cancelled.HasField("awaiting_estimates"))
        with self.assertRaises(VscanError) as refused:
            self.client.submit_picking_estimates(job.job_id, 1, good)
        self.assertEqual(refused.exception.code, C.FAILED_PRECONDITION)
        self.assertIn("not running", str(refused.exception))
        # Deleting the job removes its directory of estimates.
        self.assertTrue(os.path.exists(store))
        self.client.delete_job(job.job_id)
        self.assertFalse(os.path.exists(store))
        self.client.wait_job(truth_job.job_id)

    def test_a_step_waits_no_longer_than_its_bound(self):
        cell = self.cell(seed=10, blocks=2)
        job = self.client.start_picking(None, None, None, spec=cell.spec("client", estimates_timeout_s=1.0))
        done = wait_until(self.client, job.job_id, lambda j: j.state in ENDED, timeout=60)
        self.assertEqual(done.state, job_pb2.JOB_STATE_FAILED)
        self.assertIn("step 0: no estimates came within 1 s (spec.estimates_timeout_s)", done.message)

    def run_vscan(self, *args):
        return subprocess.run([VSCAN, "--server", self.server.address, *args], capture_output=True, text=True,
                              timeout=300)

    def vscan(self, *args):
        done = self.run_vscan(*args)
        self.assertEqual(done.returncode, 0, done.stderr + done.stdout)
        return done.stdout


class PickingEstimatesRestartTest(unittest.TestCase):
    def test_a_waiting_job_neither_holds_up_a_stop_nor_loses_a_step_to_kill9(self):
        server = Server().start()
        client = None
        try:
            client = Client(server.address, timeout=120)
            channel = server.channel()
            block = upload_part(scene_pb2_grpc.SceneServiceStub(channel), "angle_block")
            robot = client.upload_robot(UR5_DIR, urdf="ur5_robot.urdf", base="base_link", tip="tool0",
                                        name="ur5").robot_id
            cell = Cell(client, channel, robot, block, seed=11, blocks=4)
            channel.close()
            job = client.start_picking(None, None, None, spec=cell.spec("client"))
            estimator = truth_estimator(client, job.job_id)
            wait_until(client, job.job_id, awaiting(0))

            # A stop while the job waits is not held up by it; the job is INTERRUPTED.
            client.close()
            asked = time.time()
            server.stop(timeout=30)
            self.assertLess(time.time() - asked, 10.0)
            server.start()
            client = Client(server.address, timeout=120)
            estimator = truth_estimator(client, job.job_id)
            self.assertEqual(client.get_job(job.job_id).state, job_pb2.JOB_STATE_INTERRUPTED)
            client.resume_job(job.job_id)
            awaited = wait_until(client, job.job_id, awaiting(0))
            self.assertEqual(awaited.awaiting_estimates.scan_artifact, "step-000.ply")
            client.submit_picking_estimates(job.job_id, 0, estimator(0, []))

            # Killed while waiting on step 1: the resumed job waits on step 1 again, not on 0.
            wait_until(client, job.job_id, awaiting(1))
            client.close()
            server.kill9()
            server.start()
            client = Client(server.address, timeout=120)
            self.assertEqual(client.get_job(job.job_id).state, job_pb2.JOB_STATE_INTERRUPTED)
            client.resume_job(job.job_id)
            estimator = truth_estimator(client, job.job_id)
            resumed = wait_until(client, job.job_id, lambda j: j.HasField("awaiting_estimates") or j.state in ENDED)
            self.assertEqual(resumed.awaiting_estimates.step, 1, resumed.message)
            done = client.run_picking(None, estimator, job_id=job.job_id, timeout=300)
            self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
            report = client.picking_report(job.job_id)
            self.assertEqual(report["steps"][0]["step"], 1)
            self.assertGreaterEqual(report["picked"], 1, report)
            self.assertEqual(report["parts_at_start"], report["picked"] + report["fell_out"] + report["left"])
        finally:
            if client:
                client.close()
            server.cleanup()


if __name__ == "__main__":
    unittest.main()
