"""Model jobs end to end through a real vscand: a campaign scans the bunny on a rotary table with a
UR5, then StartModel aligns its scans, rebuilds and judges the surface; bad specs create no job."""

import json
import math
import unittest

import grpc
import numpy as np

from harness import Server, common_pb2
from test_campaign_service import TARGET, CampaignFixture, camera, parse_ply, spec
from vscan.v1 import cloud_pb2, cloud_pb2_grpc, job_pb2, model_pb2, scan_pb2

C = grpc.StatusCode
VIEWPOINTS = [((0.25, 0.0, 0.30), TARGET), ((0.27, 0.0, 0.12), TARGET)]


class ModelServiceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.addClassCleanup(cls.server.cleanup)
        cls.fx = CampaignFixture(cls.server)
        cls.addClassCleanup(cls.fx.close)
        cls.clouds = cloud_pb2_grpc.CloudServiceStub(cls.fx.channel)
        s = spec(cls.fx.scene.scene_id, cls.fx.mount, viewpoints=VIEWPOINTS, rotations=4, step=90.0, seed=3,
                 sensor=camera(320, 240, 40.0), fields=[scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_PIXEL])
        job = cls.fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=s), timeout=30).job
        cls.campaign = cls.wait(job.job_id)
        assert cls.campaign.state == job_pb2.JOB_STATE_SUCCEEDED, cls.campaign.message

    @classmethod
    def wait(cls, job_id, responses=None):
        for response in cls.fx.jobs.WatchJob(job_pb2.WatchJobRequest(job_id=job_id), timeout=300):
            if responses is not None:
                responses.append(response)
        return cls.fx.jobs.GetJob(job_pb2.GetJobRequest(job_id=job_id), timeout=30).job

    def start(self, model_spec, validate_only=False):
        return self.fx.jobs.StartModel(job_pb2.StartModelRequest(spec=model_spec, validate_only=validate_only),
                                       timeout=60)

    def artifact(self, job, name):
        found = [a for a in job.artifacts if a.name == name]
        self.assertEqual(len(found), 1, name)
        chunks = self.fx.jobs.ReadArtifact(job_pb2.ReadArtifactRequest(job_id=job.job_id,
                                                                       artifact_id=found[0].artifact_id), timeout=60)
        return b"".join(c.chunk for c in chunks)

    def assertRefused(self, code, field, model_spec):
        jobs_before = len(self.fx.jobs.ListJobs(job_pb2.ListJobsRequest(), timeout=30).jobs)
        with self.assertRaises(grpc.RpcError) as ctx:
            self.start(model_spec)
        self.assertEqual(ctx.exception.code(), code, ctx.exception.details())
        self.assertTrue(ctx.exception.details().startswith(field + ": "), ctx.exception.details())
        self.assertEqual(len(self.fx.jobs.ListJobs(job_pb2.ListJobsRequest(), timeout=30).jobs), jobs_before)

    def test_bad_specs_are_refused_naming_their_field(self):
        self.assertRefused(C.INVALID_ARGUMENT, "spec.cloud_ids", model_pb2.ModelSpec())
        self.assertRefused(C.NOT_FOUND, "spec.cloud_ids[0]", model_pb2.ModelSpec(cloud_ids=["cld_00000000deadbeef"]))
        self.assertRefused(C.NOT_FOUND, "spec.campaign_job_id",
                           model_pb2.ModelSpec(campaign_job_id="job_00000000deadbeef"))
        good = self.campaign.job_id
        self.assertRefused(C.INVALID_ARGUMENT, "spec.alignment.voxel_size", model_pb2.ModelSpec(
            campaign_job_id=good, alignment=model_pb2.AlignmentOptions(voxel_size=math.nan)))
        self.assertRefused(C.INVALID_ARGUMENT, "spec.alignment.voxel_size", model_pb2.ModelSpec(
            campaign_job_id=good, alignment=model_pb2.AlignmentOptions(voxel_size=1e19)))
        self.assertRefused(C.INVALID_ARGUMENT, "spec.evaluation.next_best_views", model_pb2.ModelSpec(
            campaign_job_id=good, evaluate=True, evaluation=model_pb2.EvaluationOptions(next_best_views=21)))
        self.assertRefused(C.INVALID_ARGUMENT, "spec.crop.max", model_pb2.ModelSpec(
            campaign_job_id=good, crop=common_pb2.Bounds(min=common_pb2.Vector3())))
        self.assertRefused(C.NOT_FOUND, "spec.scene_id", model_pb2.ModelSpec(
            campaign_job_id=good, scene_id="scn_00000000deadbeef"))
        # A dry run checks the same and starts nothing.
        self.assertFalse(self.start(model_pb2.ModelSpec(campaign_job_id=good, evaluate=True),
                                    validate_only=True).HasField("job"))

    def test_a_model_job_aligns_rebuilds_and_judges_the_campaign(self):
        model_spec = model_pb2.ModelSpec(campaign_job_id=self.campaign.job_id, reconstruct=True, evaluate=True,
                                         evaluation=model_pb2.EvaluationOptions(tau=0.002, skip_next_best_views=True),
                                         name="bunny model")
        job = self.start(model_spec).job
        self.assertEqual(job.kind, "model")
        self.assertEqual(job.state, job_pb2.JOB_STATE_QUEUED)
        responses = []
        done = self.wait(job.job_id, responses)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        self.assertEqual(done.model, model_spec)
        self.assertEqual((done.steps_done, done.steps_total), (8 + 3, 8 + 3))
        self.assertTrue(done.message.startswith("8 of 8 scans aligned"), done.message)

        alignments = [r.event.alignment for r in responses if r.HasField("event") and r.event.HasField("alignment")]
        self.assertEqual([a.index for a in alignments], list(range(8)))
        scans = {c.name: c.cloud_id for c in self.clouds.ListClouds(cloud_pb2.ListCloudsRequest(
            job_id=self.campaign.job_id), timeout=30).clouds}
        self.assertEqual(sorted(a.cloud_id for a in alignments), sorted(scans.values()))
        for a in alignments:
            self.assertTrue(a.aligned, a.reason)
            self.assertTrue(a.has_error)
            self.assertLess(a.rotation_error_deg, 0.05)
            self.assertLess(a.translation_error_m, 2e-4)
            self.assertEqual(len(a.pose.values), 16)

        self.assertEqual(sorted(a.name for a in done.artifacts),
                         ["aligned.ply", "coverage.png", "mesh.ply", "model.json", "uncovered.ply"])
        report = json.loads(self.artifact(done, "model.json"))
        self.assertEqual((report["kind"], report["state"], report["clouds"]), ("model", "SUCCEEDED", 8))
        self.assertEqual(report["alignment"]["aligned"], 8)
        self.assertEqual(report["reconstruction"]["method"], "tsdf")
        evaluation = report["evaluation"]
        self.assertGreater(evaluation["union"]["precision"], 0.98)
        self.assertGreater(evaluation["coverage"], 0.5)
        self.assertLessEqual(evaluation["coverage"], 1.0)
        self.assertGreater(evaluation["mesh"]["f_score"], 0.7)
        self.assertTrue(self.artifact(done, "coverage.png").startswith(b"\x89PNG"))
        points, _ = parse_ply(self.artifact(done, "aligned.ply"))
        self.assertGreater(len(points), 1000)
        mesh = self.artifact(done, "mesh.ply")
        header = mesh[:mesh.index(b"end_header")].decode()
        self.assertIn(f"element face {report['reconstruction']['triangles']}", header)
        # The union lies in the model frame: the bunny on its table at 0 degrees, about the table axis.
        self.assertLess(np.abs(points[:, :2].mean(axis=0)).max(), 0.05)


if __name__ == "__main__":
    unittest.main()
