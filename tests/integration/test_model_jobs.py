"""Model jobs through a real vscand: `vscan align|reconstruct|evaluate` and the Python client on the
scans of a small campaign (the bunny on a turning table, a Panda with noisy encoders), and a
campaign plan that evaluates its own scans.

What the server reports is checked against the scene as the plan built it: the aligned scans and
the mesh lie on the bunny as placed, and the coverage agrees with one computed here from the
downloaded union and the bunny's own mesh (Open3D, independent of vscand)."""

import json
import os
import subprocess
import tempfile
import unittest

import numpy as np
import open3d as o3d

from harness import BUNNY, SOURCE_DIR, VSCAN, Server, cli_result
from test_campaign_cli import bunny_vertices_on_table
from test_cli import read_ply

from vscan import Client, VscanError

DATA = os.path.join(SOURCE_DIR, "data")

# The quick example plan with noisy encoders and pixel coordinates (so that TSDF can run): 6 scans.
PLAN = f"""name: model-quick
scene:
  objects:
    - mesh: {BUNNY}
      unit: m
      label: bunny
      on_table: true
      pose: {{xyz: [0.017, 0, -0.033], rpy_deg: [90, 0, 0]}}
  table: {{centre: [0, 0, 0], axis: [0, 0, 1]}}
robot:
  bundle: {DATA}/robots/panda
  urdf: panda.urdf
  base_link: panda_link0
  tip_link: panda_hand_tcp
  base_pose: {{xyz: [0.6, 0, 0], rpy_deg: [0, 0, 180]}}
  encoder_sigma: 0.0002
sensor:
  pinhole: {{width: 320, height: 240, horizontal_fov_deg: 60, near: 0.05, far: 2}}
fields: [normal, pixel]
seed: 1
apply_encoder_noise: true
viewpoints:
  - {{position: [0.30, 0.10, 0.20], target: [0, 0, 0.07]}}
  - {{position: [0.25, -0.15, 0.35], target: [0, 0, 0.07]}}
rotations: 3
"""

SCANS = 6
server = None
tmp = None
campaign = None  # the JSON `vscan campaign run` printed


def vscan(*args, timeout=600):
    return subprocess.run([VSCAN, "--server", server.address, *args], capture_output=True, text=True,
                          timeout=timeout)


def write_plan(name, extra=""):
    path = os.path.join(tmp.name, name)
    with open(path, "w") as f:
        f.write(PLAN + extra)
    return path


def setUpModule():
    global server, tmp, campaign
    server = Server().start()
    tmp = tempfile.TemporaryDirectory(prefix="vscan-model-")
    out = vscan("--json", "campaign", "run", write_plan("plan.yaml"), "--no-download")
    if out.returncode != 0:
        raise RuntimeError(f"campaign run failed: {out.stderr}\n{server.log()}")
    campaign = cli_result(out.stdout)


def tearDownModule():
    server.cleanup()
    tmp.cleanup()


def bunny_mesh():
    """The bunny's mesh placed as the plan places it (Open3D, from the source file)."""
    mesh = o3d.io.read_triangle_mesh(BUNNY)
    vertices = bunny_vertices_on_table()
    assert len(vertices) == len(mesh.vertices)
    mesh.vertices = o3d.utility.Vector3dVector(vertices)
    return mesh


def distances(points, reference):
    """Each point's distance to the nearest point of reference (both (N, 3))."""
    a = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.asarray(points, dtype=np.float64)))
    b = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(np.asarray(reference, dtype=np.float64)))
    return np.asarray(a.compute_point_cloud_distance(b))


def xyz(ply):
    return np.stack([ply["x"], ply["y"], ply["z"]], axis=1).astype(np.float64)


class ModelCliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.job = campaign["job"]["jobId"]
        cls.align = vscan("--json", "align", "--campaign", cls.job)
        cls.align_text = vscan("align", "--campaign", cls.job, "--name", "text")
        cls.out_dir = os.path.join(tmp.name, "reconstructed")
        cls.reconstruct = vscan("--json", "reconstruct", "--campaign", cls.job, "--out", cls.out_dir)
        cls.eval_dir = os.path.join(tmp.name, "evaluated")
        cls.evaluate = vscan("--json", "evaluate", "--campaign", cls.job, "--out", cls.eval_dir)
        cls.evaluate_text = vscan("evaluate", "--campaign", cls.job, "--reconstruct", "--next-best-views", "2")

    def result(self, run):
        self.assertEqual(run.returncode, 0, run.stderr + server.log())
        return cli_result(run.stdout)

    def test_align_reports_every_scan_with_its_pose_error(self):
        result = self.result(self.align)
        self.assertEqual(result["job"]["kind"], "model")
        self.assertEqual(result["job"]["state"], "JOB_STATE_SUCCEEDED")
        alignments = result["alignments"]
        self.assertEqual(sorted(a.get("index", 0) for a in alignments), list(range(SCANS)))
        for a in alignments:
            self.assertTrue(a["aligned"], a)
            self.assertTrue(a["hasError"], a)
            self.assertGreater(a["fitness"], 0.5, a)
            # Encoder noise of 0.2 mrad per joint: a fraction of a degree and of a millimetre at most.
            self.assertLess(a["rotationErrorDeg"], 0.5, a)
            self.assertLess(a["translationErrorM"], 0.002, a)
        model = result["model"]
        self.assertEqual(model["kind"], "model")
        self.assertEqual(model["clouds"], SCANS)
        self.assertEqual(model["alignment"]["aligned"], SCANS)
        self.assertEqual(model["alignment"]["unaligned"], 0)
        self.assertEqual(model["alignment"]["initial_pose"], "known")
        # Campaign scans come with their true pose, and the arm's reading was off by the encoder noise.
        self.assertGreater(model["alignment"]["initial_rotation_error_deg"]["max"], 0.0)
        self.assertNotIn("reconstruction", model)
        self.assertNotIn("evaluation", model)

    def test_align_prints_a_line_per_scan_and_the_summary(self):
        out = self.align_text
        self.assertEqual(out.returncode, 0, out.stderr)
        scan_lines = [line for line in out.stdout.splitlines() if "] scan " in line and ": fitness " in line]
        self.assertEqual(len(scan_lines), SCANS, out.stdout)
        self.assertTrue(all("rot err" in line and "trans err" in line for line in scan_lines), scan_lines)
        self.assertIn(f"alignment: {SCANS} of {SCANS} scans aligned (known initial poses", out.stdout)

    def test_reconstruct_leaves_a_mesh_on_the_bunny(self):
        result = self.result(self.reconstruct)
        files = {os.path.basename(f) for f in result["files"]}
        self.assertTrue({"model.json", "aligned.ply", "mesh.ply", "job.json"} <= files, files)
        model = result["model"]
        mesh = o3d.io.read_triangle_mesh(os.path.join(self.out_dir, "mesh.ply"))
        self.assertEqual(len(mesh.vertices), model["reconstruction"]["vertices"])
        self.assertEqual(len(mesh.triangles), model["reconstruction"]["triangles"])
        self.assertGreater(len(mesh.triangles), 1000)
        # The reconstruction is in the model frame: on the bunny as placed at table angle 0.
        truth = bunny_mesh().sample_points_uniformly(50000).points
        near = distances(np.asarray(mesh.vertices), truth)
        self.assertLess(np.median(near), 0.002)
        with open(os.path.join(self.out_dir, "model.json")) as f:
            self.assertEqual(json.load(f)["reconstruction"], model["reconstruction"])
        text = vscan("reconstruct", "--campaign", self.job, "--out", os.path.join(tmp.name, "again"))
        self.assertEqual(text.returncode, 0, text.stderr)
        self.assertIn("look at it with `vscan render ", text.stdout)

    def test_evaluate_agrees_with_an_independent_coverage(self):
        result = self.result(self.evaluate)
        evaluation = result["model"]["evaluation"]
        tau = evaluation["tau"]
        self.assertGreater(tau, 0)
        union = evaluation["union"]
        # Noise-free range: every aligned point lies on the true surface.
        self.assertGreater(union["precision"], 0.95)
        self.assertGreater(evaluation["coverage"], 0.2)
        self.assertLess(evaluation["coverage"], 1.0)
        # Coverage recomputed here: the share of the true surface within tau of the aligned union.
        aligned = xyz(read_ply(os.path.join(self.eval_dir, "aligned.ply")))
        samples = np.asarray(bunny_mesh().sample_points_uniformly(40000).points)
        covered = np.mean(distances(samples, aligned) <= tau)
        self.assertAlmostEqual(evaluation["coverage"], covered, delta=0.05)
        self.assertTrue(os.path.exists(os.path.join(self.eval_dir, "uncovered.ply")))
        with open(os.path.join(self.eval_dir, "coverage.png"), "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_next_best_views_add_coverage(self):
        evaluation = self.result(self.evaluate)["model"]["evaluation"]
        views = evaluation["next_best_views"]
        self.assertGreater(len(views), 0, evaluation.get("next_best_views_note"))
        before = evaluation["coverage"]
        for view in views:
            self.assertGreater(view["coverage_gain"], 0)
            # Each view's coverage counts the views listed before it.
            self.assertAlmostEqual(view["coverage_after"], before + view["coverage_gain"], delta=1e-3)
            before = view["coverage_after"]
            self.assertGreater(np.linalg.norm(np.subtract(view["position"], view["target"])), 0.05)

    def test_evaluate_prints_the_verdict(self):
        out = self.evaluate_text
        self.assertEqual(out.returncode, 0, out.stderr + server.log())
        self.assertIn("evaluation at tau ", out.stdout)
        self.assertRegex(out.stdout, r"\n  union +\d+\.\d %")
        self.assertRegex(out.stdout, r"\n  mesh +\d+\.\d %")
        self.assertIn("  coverage ", out.stdout)
        self.assertRegex(out.stdout, r"\n  1\. position .* table .* deg  \+")
        self.assertNotIn("\n  3. position", out.stdout)

    def test_model_commands_find_the_jobs(self):
        job_id = self.result(self.align)["job"]["jobId"]
        listed = vscan("model", "list")
        self.assertEqual(listed.returncode, 0, listed.stderr)
        self.assertIn(job_id, listed.stdout)
        self.assertNotIn(self.job, listed.stdout)  # the campaign is not a model job
        watched = vscan("model", "watch", job_id)
        self.assertEqual(watched.returncode, 0, watched.stderr)
        self.assertIn(f"alignment: {SCANS} of {SCANS} scans aligned", watched.stdout)

    def test_errors_exit_with_the_conventions(self):
        missing = vscan("align", "--campaign", "no-such-job")
        self.assertEqual(missing.returncode, 3, missing.stderr)
        self.assertIn("--campaign", missing.stderr)
        valid = vscan("evaluate", "--campaign", self.job, "--validate")
        self.assertEqual(valid.returncode, 0, valid.stderr)
        self.assertEqual(vscan("align", "--campaign", self.job, "--initial", "guess").returncode, 2)


class ModelPythonTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.client = Client(server.address, stream_timeout=600)
        cls.campaign_job = campaign["job"]["jobId"]

    @classmethod
    def tearDownClass(cls):
        cls.client.close()

    def test_start_watch_report_download(self):
        job = self.client.start_model(campaign_job_id=self.campaign_job, evaluate=True, next_best_views=0)
        self.assertEqual(job.kind, "model")
        scans = list(self.client.watch_alignments(job.job_id))
        self.assertEqual(sorted(s.index for s in scans), list(range(SCANS)))
        self.assertTrue(all(s.aligned for s in scans))
        report = self.client.model_report(job.job_id)
        self.assertEqual(report["job_id"], job.job_id)
        self.assertEqual(report["alignment"]["aligned"], SCANS)
        self.assertEqual(report["evaluation"]["next_best_views"], [])
        by_cloud = {s["cloud_id"]: s for s in report["alignment"]["scans"]}
        for scan in scans:
            self.assertAlmostEqual(by_cloud[scan.cloud_id]["fitness"], scan.fitness, places=6)
        directory = os.path.join(tmp.name, "python")
        paths = self.client.download_artifacts(job.job_id, directory, names={"model.json", "aligned.ply"})
        self.assertEqual(sorted(os.path.basename(p) for p in paths), ["aligned.ply", "model.json"])
        with open(os.path.join(directory, "model.json")) as f:
            self.assertEqual(json.load(f), report)

    def test_uploaded_clouds_align_from_their_sensor_poses(self):
        # The two scans at table angle 0, downloaded and uploaded again as plain clouds (no table
        # angle) with the pose the arm reached: a model job on cloud ids.
        clouds = sorted(self.client.list_clouds(self.campaign_job), key=lambda c: c.name)[:2]
        uploaded = []
        for cloud in clouds:
            got, data = self.client.read_cloud(cloud.cloud_id)
            uploaded.append(self.client.upload_cloud(data=data, name="again-" + got.name, format="ply",
                                                     sensor_pose=list(got.sensor_pose.values),
                                                     scene_id=got.scene_id).cloud_id)
        job = self.client.start_model(uploaded, voxel_size=0.002)
        done = self.client.wait_job(job.job_id)
        self.assertEqual(done.job_id, job.job_id)
        report = self.client.model_report(job.job_id)
        self.assertEqual(report["clouds"], 2)
        self.assertEqual([s["cloud_id"] for s in report["alignment"]["scans"]], uploaded)
        self.assertEqual(report["alignment"]["voxel_size"], 0.002)

    def test_refusals_name_the_field(self):
        with self.assertRaises(VscanError) as caught:
            self.client.validate_model(["no-such-cloud"])
        self.assertIn("spec.cloud_ids[0]", caught.exception.message)


class CampaignEvaluatesItsScansTest(unittest.TestCase):
    def test_campaign_run_prints_the_model_summary(self):
        plan = write_plan("evaluate.yaml", "align: true\nevaluate: true\nevaluation: {next_best_views: 1}\n")
        out = vscan("campaign", "run", plan, "-o", os.path.join(tmp.name, "campaign-evaluated"))
        self.assertEqual(out.returncode, 0, out.stderr + server.log())
        self.assertIn(f"alignment: {SCANS} of {SCANS} scans aligned", out.stdout)
        self.assertIn("evaluation at tau ", out.stdout)
        self.assertIn("  coverage ", out.stdout)
        with open(os.path.join(tmp.name, "campaign-evaluated", "model.json")) as f:
            model = json.load(f)
        # The campaign's own report: its kind and the scene its ground truth came from.
        self.assertEqual(model["kind"], "campaign")
        self.assertTrue(model["scene_id"], model)
        with open(os.path.join(tmp.name, "campaign-evaluated", "job.json")) as f:
            self.assertIn(f'"{model["scene_id"]}"', f.read())


if __name__ == "__main__":
    unittest.main()
