"""Model jobs from vscan against the in-process fake server: the spec sent, the alignment
events, the report and the artifacts."""

import os
import sys
import tempfile
import unittest

import grpc

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from fake_server import MODEL_FILES, MODEL_REPORT, FakeServer  # noqa: E402
from vscan import Client, VscanError, model_spec  # noqa: E402
from vscan.jobs import campaign_spec  # noqa: E402
from vscan.v1 import model_pb2  # noqa: E402


def _subset(pattern, value):
    """value cut down to the keys pattern has (recursively), to compare with pattern."""
    if isinstance(pattern, dict) and isinstance(value, dict):
        return {k: _subset(v, value[k]) for k, v in pattern.items() if k in value}
    if isinstance(pattern, list) and isinstance(value, list):
        return [_subset(p, v) for p, v in zip(pattern, value)]
    return value


class ModelSpecTest(unittest.TestCase):
    def test_flat_options_fill_every_part(self):
        spec = model_spec(["cld-a", "cld-b"], initial_pose="features", voxel_size=0.002, min_fitness=0.4,
                          pose_graph=False, reconstruct=True, method="poisson", reconstruction_voxel_size=0.001,
                          poisson_depth=9, evaluate=True, tau=0.0005, next_best_views=5, scene_id="scene-1",
                          mount_id="mount-1", crop=((-0.1, -0.1, 0.0), (0.1, 0.1, 0.2)), name="bunny")
        self.assertEqual(list(spec.cloud_ids), ["cld-a", "cld-b"])
        self.assertEqual(spec.alignment.initial_pose, model_pb2.INITIAL_POSE_FEATURES)
        self.assertEqual(spec.alignment.voxel_size, 0.002)
        self.assertEqual(spec.alignment.min_fitness, 0.4)
        self.assertTrue(spec.alignment.skip_pose_graph)
        self.assertTrue(spec.reconstruct)
        self.assertEqual(spec.reconstruction.method, model_pb2.RECONSTRUCTION_METHOD_POISSON)
        self.assertEqual((spec.reconstruction.voxel_size, spec.reconstruction.poisson_depth), (0.001, 9))
        self.assertTrue(spec.evaluate)
        self.assertEqual((spec.evaluation.tau, spec.evaluation.next_best_views), (0.0005, 5))
        self.assertFalse(spec.evaluation.skip_next_best_views)
        self.assertEqual((spec.crop.min.x, spec.crop.max.z), (-0.1, 0.2))
        self.assertEqual((spec.scene_id, spec.mount_id, spec.name), ("scene-1", "mount-1", "bunny"))

    def test_defaults_leave_choices_to_the_server(self):
        spec = model_spec(campaign_job_id="job-1")
        self.assertEqual(spec.campaign_job_id, "job-1")
        self.assertEqual(spec.alignment.initial_pose, model_pb2.INITIAL_POSE_UNSPECIFIED)
        self.assertFalse(spec.alignment.skip_pose_graph)
        self.assertFalse(spec.reconstruct or spec.evaluate)
        self.assertFalse(spec.HasField("reconstruction") or spec.HasField("evaluation") or spec.HasField("crop"))

    def test_zero_next_best_views_skips_them(self):
        spec = model_spec(["cld-a"], evaluate=True, next_best_views=0)
        self.assertTrue(spec.evaluation.skip_next_best_views)
        self.assertEqual(spec.evaluation.next_best_views, 0)

    def test_rejections(self):
        with self.assertRaises(ValueError):
            model_spec()
        with self.assertRaises(ValueError):
            model_spec(["cld-a"], campaign_job_id="job-1")
        with self.assertRaises(ValueError):
            model_spec(["cld-a"], initial_pose="guess")
        with self.assertRaises(ValueError):
            model_spec(["cld-a"], reconstruct=True, method="marching")

    def test_campaign_spec_takes_model_parts(self):
        spec = campaign_spec("scene-1", "mount-1", [((0.3, 0, 0.2), (0, 0, 0.05))], evaluate=True,
                             alignment={"initial_pose": "known", "voxel_size": 0.003},
                             evaluation=model_pb2.EvaluationOptions(tau=0.002))
        self.assertTrue(spec.evaluate)
        self.assertFalse(spec.align)
        self.assertEqual(spec.alignment.initial_pose, model_pb2.INITIAL_POSE_KNOWN)
        self.assertEqual(spec.alignment.voxel_size, 0.003)
        self.assertEqual(spec.evaluation.tau, 0.002)
        self.assertFalse(spec.HasField("reconstruction"))


class ModelCallsTest(unittest.TestCase):
    def setUp(self):
        self.fake = FakeServer()
        self.client = Client(self.fake.address)

    def tearDown(self):
        self.client.close()
        self.fake.stop()

    def test_start_model_sends_the_spec(self):
        job = self.client.start_model(["cld-a", "cld-b"], evaluate=True, tau=0.001)
        self.assertEqual((job.job_id, job.kind), ("job-m1", "model"))
        sent = self.fake.jobs.last_model
        self.assertEqual(list(sent.cloud_ids), ["cld-a", "cld-b"])
        self.assertTrue(sent.evaluate)
        self.assertEqual(sent.evaluation.tau, 0.001)

    def test_validate_model_starts_nothing_and_names_the_field(self):
        self.client.validate_model(campaign_job_id="job-1", reconstruct=True)
        self.assertEqual(self.fake.jobs.validated.campaign_job_id, "job-1")
        self.assertIsNone(self.fake.jobs.last_model)
        with self.assertRaises(VscanError) as caught:
            self.client.validate_model(["cld-a", "missing"])
        self.assertEqual(caught.exception.code, grpc.StatusCode.NOT_FOUND)
        self.assertIn("spec.cloud_ids[1]", caught.exception.message)

    def test_watch_alignments_yields_each_scan(self):
        job = self.client.start_model(["cld-a", "cld-b"])
        scans = list(self.client.watch_alignments(job.job_id))
        self.assertEqual([(s.index, s.cloud_id, s.aligned) for s in scans], [(0, "cld-a", True), (1, "cld-b", False)])
        self.assertAlmostEqual(scans[0].rotation_error_deg, 0.02)
        self.assertEqual(scans[1].reason, "fitness 0.10 below 0.30")

    def test_scans_aligned_before_the_watch_come_from_the_report(self):
        self.fake.jobs.scans_before_watch = 1
        job = self.client.start_model(["cld-a", "cld-b"])
        scans = list(self.client.watch_alignments(job.job_id))
        self.assertEqual([(s.index, s.cloud_id, s.name, s.aligned) for s in scans],
                         [(1, "cld-b", "", False), (0, "cld-a", "a", True)])
        self.assertAlmostEqual(scans[1].fitness, 0.95)
        self.assertFalse(scans[1].has_error)

    def test_model_report_is_the_parsed_json(self):
        # Read through the schema: the file's keys and values, plus the fields it left at their defaults.
        self.client.start_model(["cld-a", "cld-b"], evaluate=True)
        report = self.client.model_report("job-m1")
        self.assertEqual(_subset(MODEL_REPORT, report), MODEL_REPORT)
        self.assertEqual(report["alignment"]["scans"][1]["fitness"], 0)
        self.assertEqual(report["reconstruction"]["artifact"], "mesh.ply")
        self.assertNotIn("mesh", report["evaluation"])  # a section the file left out stays out
        with self.assertRaises(VscanError) as caught:
            self.client.model_report("job-other")
        self.assertEqual(caught.exception.code, grpc.StatusCode.NOT_FOUND)

    def test_download_artifacts(self):
        with tempfile.TemporaryDirectory() as tmp:
            directory = os.path.join(tmp, "out")
            paths = self.client.download_artifacts("job-m1", directory)
            self.assertEqual(sorted(os.path.basename(p) for p in paths), sorted(MODEL_FILES))
            for path in paths:
                with open(path, "rb") as f:
                    self.assertEqual(f.read(), MODEL_FILES[os.path.basename(path)])
            only = self.client.download_artifacts("job-m1", directory, names={"mesh.ply"})
            self.assertEqual(only, [os.path.join(directory, "mesh.ply")])


if __name__ == "__main__":
    unittest.main()
