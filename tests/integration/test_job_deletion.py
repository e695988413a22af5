"""Deleting campaign jobs through a real vscand: the data directory shrinks, the artifacts answer
NOT_FOUND, what other rows use stays, running jobs are refused, and retention deletes by itself."""

import json
import os
import subprocess
import time
import unittest

import grpc

from harness import VSCAN, Server, cli_result
from test_campaign_service import CampaignFixture, spec, wait_for
from vscan.v1 import job_pb2, scene_pb2

from vscan import Client, VscanError

C = grpc.StatusCode
ONE_VIEW = [((0.25, 0.0, 0.30), (0.0, 0.0, 0.11))]


def bytes_under(path):
    return sum(os.path.getsize(os.path.join(root, name)) for root, _, names in os.walk(path) for name in names)


class JobDeletionTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.addClassCleanup(cls.server.cleanup)
        cls.fx = CampaignFixture(cls.server)
        cls.client = Client(cls.server.address, stream_timeout=300)
        cls.blobs = os.path.join(cls.server.data_dir, "store", "blobs")

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.fx.close()

    def small_campaign(self, rotations=2):
        job = self.client.start_campaign(spec=spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=ONE_VIEW,
                                                   rotations=rotations, step=90.0, seed=3))
        done = self.client.wait_job(job.job_id, timeout=300)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        return done

    def assertCode(self, code, call):
        with self.assertRaises(VscanError) as ctx:
            call()
        self.assertEqual(ctx.exception.code, code, ctx.exception.message)
        return ctx.exception

    def test_deleting_a_campaign_shrinks_the_data_directory(self):
        done = self.small_campaign()
        self.assertEqual(len(done.artifacts), 3)
        before = bytes_under(self.blobs)
        deleted = self.client.delete_job(done.job_id)
        self.assertEqual(deleted.removed_files, 3)
        self.assertEqual(deleted.removed_bytes, sum(a.size_bytes for a in done.artifacts))
        self.assertEqual(bytes_under(self.blobs), before - deleted.removed_bytes)

        self.assertCode(C.NOT_FOUND, lambda: self.client.get_job(done.job_id))
        for artifact in done.artifacts:
            self.assertCode(C.NOT_FOUND, lambda: self.client.read_artifact(done.job_id, artifact.artifact_id))
        self.assertNotIn(done.job_id, [j.job_id for j in self.client.list_jobs()])
        self.assertCode(C.NOT_FOUND, lambda: self.client.delete_job(done.job_id))
        # The mesh and the robot bundle the campaign used stay: a new campaign still runs.
        self.small_campaign(rotations=1)

    def test_a_scan_other_jobs_share_stays_until_the_last_goes(self):
        first = self.small_campaign()
        second = self.small_campaign()
        # Same spec and seed: the same scans, so the same blobs.
        self.assertEqual([a.size_bytes for a in first.artifacts[:2]], [a.size_bytes for a in second.artifacts[:2]])
        kept = self.client.delete_job(first.job_id)
        _, data = self.client.read_artifact(second.job_id, second.artifacts[0].artifact_id)
        self.assertEqual(len(data), second.artifacts[0].size_bytes)
        gone = self.client.delete_job(second.job_id)
        self.assertGreater(gone.removed_files + kept.removed_files, 0)
        self.assertLess(kept.removed_files, 3)

    def test_a_running_job_must_be_cancelled_first(self):
        job = self.client.start_campaign(spec=spec(self.fx.scene.scene_id, self.fx.mount, rotations=200, step=1.0))
        error = self.assertCode(C.FAILED_PRECONDITION, lambda: self.client.delete_job(job.job_id))
        self.assertTrue(error.message.startswith("job_id:"), error.message)
        self.assertIn("cancel it first", error.message)
        self.client.cancel_job(job.job_id)
        ended = self.client.wait_job(job.job_id, timeout=120)
        self.assertEqual(ended.state, job_pb2.JOB_STATE_CANCELLED)
        self.client.delete_job(job.job_id)
        self.assertCode(C.NOT_FOUND, lambda: self.client.get_job(job.job_id))

    def test_bad_ids(self):
        self.assertCode(C.NOT_FOUND, lambda: self.client.delete_job("job_0000000000000000"))
        error = self.assertCode(C.INVALID_ARGUMENT, lambda: self.client.delete_job(""))
        self.assertTrue(error.message.startswith("job_id"), error.message)

    def test_cli_campaign_delete(self):
        done = self.small_campaign(rotations=1)
        run = subprocess.run([VSCAN, "--server", self.server.address, "--json", "campaign", "delete", done.job_id],
                             capture_output=True, text=True, timeout=60)
        self.assertEqual(run.returncode, 0, run.stderr)
        out = cli_result(run.stdout)
        self.assertEqual(out["jobId"], done.job_id)
        self.assertEqual(out["removedFiles"], 2)
        again = subprocess.run([VSCAN, "--server", self.server.address, "campaign", "delete", done.job_id],
                               capture_output=True, text=True, timeout=60)
        self.assertEqual(again.returncode, 3, again.stderr)
        self.assertIn("NOT_FOUND", again.stderr)


class RetentionTest(unittest.TestCase):
    def test_ended_jobs_expire_and_their_files_go(self):
        server = Server(extra_args=["--job-retention-hours", "0.002", "--job-retention-check-seconds", "1"]).start()
        self.addCleanup(server.cleanup)
        fx = CampaignFixture(server)
        self.addCleanup(fx.close)
        client = Client(server.address, stream_timeout=300)
        self.addCleanup(client.close)
        blobs = os.path.join(server.data_dir, "store", "blobs")
        before = bytes_under(blobs)
        job = client.start_campaign(spec=spec(fx.scene.scene_id, fx.mount, viewpoints=ONE_VIEW, rotations=1))
        done = client.wait_job(job.job_id, timeout=300)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        self.assertGreater(bytes_under(blobs), before)

        def expired():
            try:
                client.get_job(job.job_id)
                return False
            except VscanError as err:
                return err.code == C.NOT_FOUND
        wait_for(expired, timeout=30, what="the job to expire")
        # Its blobs go right after its row, in the same retention pass.
        wait_for(lambda: bytes_under(blobs) == before, timeout=10, what="the job's blobs to go")
        # Scenes are not jobs: retention leaves them alone.
        fx.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=fx.scene.scene_id))


if __name__ == "__main__":
    unittest.main()
