"""`vscan align|reconstruct|evaluate` and `vscan model` against the in-process fake server: the spec
each command sends, the lines it prints while the job runs, the report, the files and the exit codes.

Needs VSCAN_CLI (path to the vscan binary) and VSCAN_PY_STUBS (the generated Python stubs).
"""

import json
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "client", "python", "tests"))

from fake_server import MODEL_FILES, FakeServer  # noqa: E402
from vscan.v1 import job_pb2, model_pb2  # noqa: E402

CLI = os.environ.get("VSCAN_CLI")


@unittest.skipUnless(CLI, "set VSCAN_CLI to the vscan binary")
class CliModelCommands(unittest.TestCase):
    def setUp(self):
        self.fake = FakeServer()
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.fake.stop()
        self.tmp.cleanup()

    def run_cli(self, *args):
        env = dict(os.environ, VSCAN_SERVER=self.fake.address)
        return subprocess.run([CLI, *args], capture_output=True, text=True, env=env, timeout=60)

    def test_align_sends_its_options_and_prints_each_scan_and_the_report(self):
        r = self.run_cli("align", "cld-a", "cld-b", "--initial", "features", "--voxel", "0.002", "--max-distance",
                         "0.01", "--min-fitness", "0.4", "--no-pose-graph", "--scene", "scene-1", "--name", "two")
        self.assertEqual(r.returncode, 0, r.stderr)
        spec = self.fake.jobs.last_model
        self.assertEqual(list(spec.cloud_ids), ["cld-a", "cld-b"])
        self.assertEqual(spec.alignment.initial_pose, model_pb2.INITIAL_POSE_FEATURES)
        self.assertEqual((spec.alignment.voxel_size, spec.alignment.max_correspondence_distance), (0.002, 0.01))
        self.assertEqual(spec.alignment.min_fitness, 0.4)
        self.assertTrue(spec.alignment.skip_pose_graph)
        self.assertFalse(spec.reconstruct or spec.evaluate)
        self.assertEqual((spec.scene_id, spec.name), ("scene-1", "two"))
        lines = r.stdout.splitlines()
        self.assertEqual(lines[0], "started model job job-m1 on 2 clouds")
        self.assertIn("[1/2] scan 1 cld-a: fitness 0.950, rmse 0.200 mm, rot err 0.020 deg, trans err 0.050 mm", lines)
        self.assertIn("[2/2] scan 2 cld-b: NOT aligned: fitness 0.10 below 0.30", lines)
        self.assertIn("[2/2] model job finished", lines)
        self.assertIn("alignment: 1 of 2 scans aligned (known initial poses, voxel 2.000 mm, pose graph) in 0.5 s",
                      lines)
        self.assertIn("  scan 1 (cld-b 'b') NOT aligned: fitness 0.10 below 0.30", lines)
        self.assertTrue(any(line.startswith("job job-m1 SUCCEEDED in ") for line in lines), lines)

    def test_reconstruct_downloads_and_points_at_the_mesh(self):
        out = os.path.join(self.tmp.name, "model")
        r = self.run_cli("reconstruct", "--campaign", "job-c", "--method", "poisson", "--voxel", "0.001",
                         "--align-voxel", "0.003", "--depth", "9", "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        spec = self.fake.jobs.last_model
        self.assertEqual(spec.campaign_job_id, "job-c")
        self.assertTrue(spec.reconstruct)
        self.assertEqual(spec.reconstruction.method, model_pb2.RECONSTRUCTION_METHOD_POISSON)
        self.assertEqual((spec.reconstruction.voxel_size, spec.reconstruction.poisson_depth), (0.001, 9))
        self.assertEqual(spec.alignment.voxel_size, 0.003)
        for name, data in MODEL_FILES.items():
            with open(os.path.join(out, name), "rb") as f:
                self.assertEqual(f.read(), data, name)
        self.assertTrue(os.path.exists(os.path.join(out, "job.json")))
        mesh = os.path.join(out, "mesh.ply")
        self.assertIn(f"mesh: {mesh}; look at it with `vscan render {mesh} -o mesh.png`", r.stdout)
        self.assertIn("reconstruction: poisson, voxel 1.000 mm: 300 vertices, 596 triangles in 0.2 s: mesh.ply",
                      r.stdout)

    def test_evaluate_prints_the_verdict(self):
        r = self.run_cli("evaluate", "cld-a", "cld-b", "--tau", "0.001", "--next-best-views", "4", "--mount",
                         "mount-1", "--reconstruct")
        self.assertEqual(r.returncode, 0, r.stderr)
        spec = self.fake.jobs.last_model
        self.assertTrue(spec.evaluate and spec.reconstruct)
        self.assertEqual((spec.evaluation.tau, spec.evaluation.next_best_views), (0.001, 4))
        self.assertEqual(spec.mount_id, "mount-1")
        lines = r.stdout.splitlines()
        self.assertIn("evaluation at tau 1.000 mm against 1 object (0.0100 m2, 5000 samples):", lines)
        self.assertIn("  union      90.0 %   60.0 %   72.0 %    0.400 / 0.300    2.000 / 0.800       1.200", lines)
        self.assertIn("  coverage 60.0 % (uncovered.ply, coverage.png)", lines)
        self.assertIn("  1. position 0.300, 0.000, 0.200  target 0.000, 0.000, 0.050  table 180.0 deg  +25.0 % -> "
                      "85.0 %", lines)
        # Not downloaded: the mesh stays on the server and the command says how to fetch it.
        self.assertIn("mesh.ply is on the server; fetch it with `vscan model artifacts job-m1 -o DIR`", lines)

    def test_json_output_carries_the_alignments_and_the_report(self):
        r = self.run_cli("--json", "evaluate", "cld-a", "cld-b", "--no-next-best-views")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(self.fake.jobs.last_model.evaluation.skip_next_best_views)
        lines = r.stdout.splitlines()
        # The job's events stream first, one JSON object a line, then the result.
        events = [json.loads(line) for line in lines[:-1]]
        self.assertTrue(events and all("event" in e and "state" in e for e in events), events)
        out = json.loads(lines[-1])
        self.assertEqual(out["job"]["state"], "JOB_STATE_SUCCEEDED")
        self.assertEqual([a["cloudId"] for a in out["alignments"]], ["cld-a", "cld-b"])
        self.assertEqual(out["model"]["evaluation"]["coverage"], 0.6)
        self.assertEqual(out["model"]["alignment"]["scans"][1]["reason"], "fitness 0.10 below 0.30")
        self.assertEqual(out["files"], [])

    def test_failed_job_exits_3_after_its_report(self):
        self.fake.jobs.final_state = job_pb2.JOB_STATE_FAILED
        r = self.run_cli("align", "cld-a", "cld-b")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("job job-m1 FAILED", r.stdout)

    def test_no_wait_and_quiet_print_the_job_id(self):
        r = self.run_cli("-q", "align", "cld-a", "--no-wait")
        self.assertEqual((r.returncode, r.stdout), (0, "job-m1\n"))
        r = self.run_cli("align", "cld-a", "--no-wait")
        self.assertIn("follow it with `vscan model watch job-m1`", r.stdout)

    def test_model_watch_follows_and_downloads(self):
        out = os.path.join(self.tmp.name, "watched")
        r = self.run_cli("model", "watch", "job-m1", "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("[1/2] scan 1 cld-a: fitness 0.950", r.stdout)
        self.assertTrue(os.path.exists(os.path.join(out, "model.json")))

    def test_validate_starts_nothing(self):
        r = self.run_cli("reconstruct", "cld-a", "--validate")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("the server accepts this model job on 1 cloud", r.stdout)
        self.assertIsNone(self.fake.jobs.last_model)
        self.assertTrue(self.fake.jobs.validated.reconstruct)

    def test_server_errors_name_the_option(self):
        r = self.run_cli("align", "cld-a", "missing")
        self.assertEqual(r.returncode, 3)
        self.assertIn("error: NOT_FOUND: CLOUD_ID[1]: spec.cloud_ids[1]: no cloud 'missing'", r.stderr)
        r = self.run_cli("evaluate", "cld-a", "--align-voxel", "0.5")
        self.assertEqual(r.returncode, 3)
        self.assertIn("error: INVALID_ARGUMENT: --align-voxel: spec.alignment.voxel_size: must be at most 0.1 m",
                      r.stderr)
        r = self.run_cli("--json", "align", "cld-a", "--voxel", "0.5")
        self.assertEqual(json.loads(r.stdout)["error"]["code"], "INVALID_ARGUMENT")

    def test_usage_errors_exit_2_before_any_call(self):
        for args in (("align",), ("align", "cld-a", "--campaign", "job-1"), ("align", "cld-a", "--initial", "guess"),
                     ("align", "cld-a", "--voxel", "-1"), ("align", "cld-a", "--crop", "0,0,0,1,1"),
                     ("align", "cld-a", "--tau", "0.001"), ("evaluate", "cld-a", "--method", "tsdf"),
                     ("evaluate", "cld-a", "--next-best-views", "2", "--no-next-best-views"),
                     ("reconstruct", "cld-a", "--skip-alignment", "--initial", "known"),
                     ("align", "cld-a", "--min-fitness", "nan")):
            r = self.run_cli(*args)
            self.assertEqual(r.returncode, 2, (args, r.stderr))
            self.assertTrue(r.stderr, args)
        self.assertIsNone(self.fake.jobs.last_model)

    def test_help_lists_the_commands(self):
        r = self.run_cli("--help")
        self.assertEqual(r.returncode, 0)
        for command in ("align", "reconstruct", "evaluate", "model"):
            self.assertIn(command, r.stdout)
        r = self.run_cli("evaluate", "--help")
        self.assertEqual(r.returncode, 0)
        for option in ("--tau", "--next-best-views", "--reconstruct", "--align-voxel", "--crop", "--mount"):
            self.assertIn(option, r.stdout)
        r = self.run_cli("model", "--help")
        for command in ("list", "watch", "cancel", "delete", "artifacts"):
            self.assertIn(command, r.stdout)


if __name__ == "__main__":
    unittest.main()
