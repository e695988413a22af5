"""Dataset jobs on a real vscand through the CLI: run and watch, the layout complete, the same bytes
as the one-shot shard mode, a job killed (kill -9) or cancelled mid-way resumed without touching its
finished scenes, the Python client's calls, and bad plans refused naming the key without creating a
job."""

import json
import os
import subprocess
import sys
import tempfile
import time
import unittest

import grpc
import numpy as np
from harness import SOURCE_DIR, VSCAN, VSCAND, Server, cli_result
from test_dataset_shards import read_cloud
from vscan.v1 import job_pb2

sys.path.insert(0, os.path.join(SOURCE_DIR, "tests", "unit", "service", "datasets", "format"))
from dataset_layout_test import read_png  # noqa: E402  (the layout test's own PNG decoder)

PARTS = os.path.join(SOURCE_DIR, "data", "parts")


def plan_text(seeds):
    return f"""name: job-bins
bins:
  - name: blocks
    bin: {{inner_size: [0.20, 0.15, 0.10]}}
    parts:
      - {{mesh: {PARTS}/angle_block.STL, unit: in, count: 4}}
    max_simulated_s: 4
  - name: rods
    bin: {{inner_size: [0.25, 0.20, 0.10]}}
    parts:
      - {{mesh: {PARTS}/round.stl, unit: cm, scale: 0.25, count: 2}}
      - {{mesh: {PARTS}/angle_block.STL, unit: in, count: 1}}
    max_simulated_s: 4
seeds: {{first: 1, count: {seeds}}}
sensors:
  - {{name: tof, preset: kinect-v2-class, width: 256, height: 212}}
"""


def tree(root):
    files = {}
    for base, _, names in os.walk(root):
        for name in names:
            path = os.path.join(base, name)
            with open(path, "rb") as f:
                files[os.path.relpath(path, root)] = f.read()
    return files


def stamps(scene_dir):
    out = {}
    for base, _, names in os.walk(scene_dir):
        for name in names:
            st = os.stat(os.path.join(base, name))
            out[os.path.join(base, name)] = (st.st_ino, st.st_mtime_ns)
    return out


class DatasetJobTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory(prefix="vscan-dsjob-")
        self.server = Server(data_dir=self.tmp.name).start()

    def tearDown(self):
        self.server.stop()
        self.tmp.cleanup()

    def vscan(self, *args, timeout=300):
        return subprocess.run([VSCAN, "--server", self.server.address, *args], capture_output=True, text=True,
                              timeout=timeout)

    def write_plan(self, name, text):
        path = os.path.join(self.tmp.name, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def dataset_dir(self, job_id):
        return os.path.join(self.tmp.name, "store", "datasets", job_id)

    def job(self, job_id):
        got = self.vscan("--json", "campaign", "get", job_id)
        self.assertEqual(got.returncode, 0, got.stderr)
        return cli_result(got.stdout)

    def test_run_watch_download_equals_the_one_shot_shards(self):
        plan = self.write_plan("plan.yaml", plan_text(2))
        run = self.vscan("dataset", "run", plan, "--watch")
        self.assertEqual(run.returncode, 0, run.stderr + self.server.log())
        job_id = run.stdout.split("started dataset job ")[1].split()[0] if "started" in run.stdout else None
        if job_id is None:
            job_id = run.stderr.split("started dataset job ")[1].split()[0]
        self.assertIn("4 of 4", run.stdout + run.stderr)
        served = self.dataset_dir(job_id)
        self.assertTrue(os.path.exists(os.path.join(served, "scenes.json")))
        downloaded = os.path.join(self.tmp.name, "downloaded")
        got = self.vscan("dataset", "download", job_id, downloaded)
        self.assertEqual(got.returncode, 0, got.stderr)
        one_shot = os.path.join(self.tmp.name, "one-shot")
        for args in (["--dataset-shard", plan, "--shard-index", "1", "--shard-count", "2"],
                     ["--dataset-shard", plan, "--shard-index", "0", "--shard-count", "2"], ["--dataset-merge", plan]):
            done = subprocess.run([VSCAND, "--log-level", "warn", *args, "--out", one_shot], capture_output=True,
                                  text=True, timeout=300)
            self.assertEqual(done.returncode, 0, done.stderr)
        served_files, downloaded_files, one_shot_files = tree(served), tree(downloaded), tree(one_shot)
        self.assertEqual(len(served_files), len(one_shot_files))
        self.assertEqual(served_files, downloaded_files)
        self.assertEqual(served_files, one_shot_files)

    def test_several_views_a_scene_agree_with_their_clouds_and_the_one_shot_shards(self):
        views = "views: {count: 3, cone_deg: 30, distance_m: [0.6, 0.8]}\n"
        plan = self.write_plan("views.yaml", plan_text(1) + views)
        run = self.vscan("dataset", "run", plan, "--watch")
        self.assertEqual(run.returncode, 0, run.stderr + self.server.log())
        job_id = (run.stdout + run.stderr).split("started dataset job ")[1].split()[0]
        served = self.dataset_dir(job_id)
        tilts = []
        for scene_id in range(2):
            scene = os.path.join(served, "train_pbr", "%06d" % scene_id)
            with open(os.path.join(scene, "scene_camera.json")) as f:
                cameras = json.load(f)
            with open(os.path.join(scene, "scene_gt.json")) as f:
                gts = json.load(f)
            self.assertEqual(list(cameras), ["0", "1", "2"])
            world_parts = None
            for im_id, camera in cameras.items():
                world_from_camera = np.array(camera["world_from_camera"]).reshape(4, 4)
                axis = world_from_camera[:3, 2]
                tilts.append(np.degrees(np.arccos(-axis[2])))
                self.assertLessEqual(tilts[-1], 30.0 + 1e-9)
                # The depth image and the cloud of a view are one measurement: every cloud point
                # projects to a pixel whose depth is its own.
                k = np.array(camera["cam_K"]).reshape(3, 3)
                image, _ = read_png(os.path.join(scene, "depth", "%06d.png" % int(im_id)))
                depth = image.astype(float) * camera["depth_scale"]
                cloud = read_cloud(os.path.join(scene, "cloud", "%06d.ply" % int(im_id)))
                self.assertEqual(len(cloud), int((depth > 0).sum()))
                points = np.stack([cloud["x"], cloud["y"], cloud["z"]], axis=1).astype(float) * 1000.0
                in_camera = (points - world_from_camera[:3, 3] * 1000.0) @ world_from_camera[:3, :3]
                u = np.floor(in_camera[:, 0] / in_camera[:, 2] * k[0, 0] + k[0, 2] + 0.5).astype(int)
                v = np.floor(in_camera[:, 1] / in_camera[:, 2] * k[1, 1] + k[1, 2] + 0.5).astype(int)
                np.testing.assert_allclose(depth[v, u], in_camera[:, 2], atol=0.1)
                # The reason image says measured (or outlier, flying pixel) exactly where there is a
                # depth, and the grey image is black only where no surface was met or the light grazes.
                reasons, _ = read_png(os.path.join(scene, "reasons", "%06d.png" % int(im_id)))
                gray, gray_depth = read_png(os.path.join(scene, "gray", "%06d.png" % int(im_id)))
                self.assertEqual(gray_depth, 16)
                self.assertEqual(reasons.shape, depth.shape)
                np.testing.assert_array_equal(np.isin(reasons, (1, 2, 3)), depth > 0)
                self.assertTrue(np.all(gray[reasons == 0] == 0))
                self.assertGreater(np.mean(gray[depth > 0] > 0), 0.99)
                # The parts stand where they stand whichever view sees them.
                parts = []
                for gt in gts[im_id]:
                    pose = np.eye(4)
                    pose[:3, :3] = np.array(gt["cam_R_m2c"]).reshape(3, 3)
                    pose[:3, 3] = np.array(gt["cam_t_m2c"]) / 1000.0
                    parts.append(world_from_camera @ pose)
                if world_parts is None:
                    world_parts = parts
                np.testing.assert_allclose(parts, world_parts, atol=1e-9)
        self.assertGreater(max(tilts), 5.0)
        one_shot = os.path.join(self.tmp.name, "one-shot-views")
        for args in (["--dataset-shard", plan, "--shard-index", "0", "--shard-count", "1"], ["--dataset-merge", plan]):
            done = subprocess.run([VSCAND, "--log-level", "warn", *args, "--out", one_shot], capture_output=True,
                                  text=True, timeout=300)
            self.assertEqual(done.returncode, 0, done.stderr)
        self.assertEqual(tree(served), tree(one_shot))

    def test_killed_job_resumes_keeping_finished_scenes(self):
        plan = self.write_plan("plan.yaml", plan_text(12))
        started = self.vscan("--json", "dataset", "run", plan)
        self.assertEqual(started.returncode, 0, started.stderr)
        job_id = cli_result(started.stdout)["job"]["jobId"]
        deadline = time.time() + 120
        while self.job(job_id).get("stepsDone", 0) < 3:
            self.assertLess(time.time(), deadline, "the job made no progress")
            time.sleep(0.02)
        self.server.kill9()
        scenes = os.path.join(self.dataset_dir(job_id), "train_pbr")
        finished = sorted(n for n in os.listdir(scenes) if not n.endswith(".partial"))
        self.assertGreaterEqual(len(finished), 3)
        self.assertLess(len(finished), 24, "the job ended before the kill; the plan is too small")
        before = {}
        for name in finished:
            before.update(stamps(os.path.join(scenes, name)))
        self.server.start()
        self.assertEqual(self.job(job_id)["state"], "JOB_STATE_INTERRUPTED")
        resumed = self.vscan("dataset", "run", plan, "--resume", job_id, "--watch")
        self.assertEqual(resumed.returncode, 0, resumed.stderr + self.server.log())
        # The job's final message (a watch that starts late misses the first event, which says the same).
        self.assertIn(f"({24 - len(finished)} written, {len(finished)} found finished)", resumed.stdout)
        after = stamps(scenes)
        for path, stamp in before.items():
            self.assertEqual(after[path], stamp, path)
        self.assertEqual(len(os.listdir(scenes)), 24)
        with open(os.path.join(self.dataset_dir(job_id), "scenes.json")) as f:
            self.assertEqual(json.load(f)["scene_count"], 24)
        merged = subprocess.run([VSCAND, "--dataset-merge", plan, "--out", self.dataset_dir(job_id)],
                                capture_output=True, text=True, timeout=300)
        self.assertEqual(merged.returncode, 0, merged.stderr)

    def finished_scenes(self, job_id):
        scenes = os.path.join(self.dataset_dir(job_id), "train_pbr")
        return sorted(n for n in os.listdir(scenes) if not n.endswith(".partial"))

    def test_cancelled_job_resumes_skipping_finished_scenes(self):
        plan = self.write_plan("plan.yaml", plan_text(12))
        started = self.vscan("--json", "dataset", "run", plan)
        self.assertEqual(started.returncode, 0, started.stderr)
        job_id = cli_result(started.stdout)["job"]["jobId"]
        deadline = time.time() + 120
        while self.job(job_id).get("stepsDone", 0) < 2:
            self.assertLess(time.time(), deadline, "the job made no progress")
            time.sleep(0.02)
        cancelled = self.vscan("dataset", "cancel", job_id)
        self.assertEqual(cancelled.returncode, 0, cancelled.stderr)
        watched = self.vscan("--json", "dataset", "watch", job_id)
        self.assertEqual(cli_result(watched.stdout)["job"]["state"], "JOB_STATE_CANCELLED")
        scenes = os.path.join(self.dataset_dir(job_id), "train_pbr")
        self.assertEqual([n for n in os.listdir(scenes) if n.endswith(".partial")], [])
        finished = self.finished_scenes(job_id)
        self.assertGreaterEqual(len(finished), 2)
        self.assertLess(len(finished), 24, "the job ended before the cancel; the plan is too small")
        before = {}
        for name in finished:
            before.update(stamps(os.path.join(scenes, name)))
        resumed = self.vscan("dataset", "run", plan, "--resume", job_id, "--watch")
        self.assertEqual(resumed.returncode, 0, resumed.stderr + self.server.log())
        # The job's final message (a watch that starts late misses the first event, which says the same).
        self.assertIn(f"({24 - len(finished)} written, {len(finished)} found finished)", resumed.stdout)
        after = stamps(scenes)
        for path, stamp in before.items():
            self.assertEqual(after[path], stamp, path)
        self.assertEqual(len(self.finished_scenes(job_id)), 24)

    def test_python_client_runs_watches_and_cancels(self):
        from vscan import Client, VscanError

        plan = self.write_plan("plan.yaml", plan_text(12))
        with Client(self.server.address) as client:
            job = client.start_dataset(plan)
            self.assertEqual(job.kind, "dataset")
            self.assertEqual(job.steps_total, 24)
            messages = []
            for update in client.watch_job(job.job_id):
                messages.append(update.event.message)
                if update.job.steps_done >= 1:
                    client.cancel_job(job.job_id)
                    break
            self.assertIn("scene 1 of 24 written", messages)
            self.assertEqual(client.wait_job(job.job_id).state, job_pb2.JOB_STATE_CANCELLED)
            downloaded = os.path.join(self.tmp.name, "downloaded")
            resumed = client.run_dataset(plan, resume_job_id=job.job_id, directory=downloaded)
            self.assertEqual(resumed.state, job_pb2.JOB_STATE_SUCCEEDED, resumed.message)
            self.assertEqual(resumed.steps_done, 24)
            self.assertEqual(tree(downloaded), tree(self.dataset_dir(job.job_id)))
            with self.assertRaises(VscanError) as refused:
                client.validate_dataset(self.write_plan("bad.yaml", plan_text(2).replace("count: 4", "count: 0")))
            self.assertEqual(refused.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
            self.assertIn("bins[0].parts[0].count", refused.exception.message)

    def test_a_bin_too_small_for_its_parts_is_reported_or_fails_the_plan_that_asks(self):
        small = plan_text(1).replace("inner_size: [0.20, 0.15, 0.10]", "inner_size: [0.07, 0.07, 0.03]")
        small = small.replace("unit: in, count: 4", "unit: in, count: 30")
        run = self.vscan("dataset", "run", self.write_plan("small.yaml", small), "--watch")
        self.assertEqual(run.returncode, 0, run.stderr + self.server.log())
        self.assertIn("scenes hold fewer parts than planned (bin full), see their scene_fill.json: 0",
                      run.stdout + run.stderr)
        strict = self.vscan("dataset", "run", self.write_plan("strict.yaml", small + "fail_on_underfilled_bin: true\n"),
                            "--watch")
        self.assertNotEqual(strict.returncode, 0, strict.stdout)
        self.assertIn("scenes[0]: the bin took", strict.stdout + strict.stderr)
        self.assertIn("of 30 parts and the plan sets fail_on_underfilled_bin", strict.stdout + strict.stderr)

    def test_the_server_reads_the_plan_and_names_its_mesh_files(self):
        from vscan import Client, VscanError
        from vscan.v1 import common_pb2

        with Client(self.server.address) as client:
            files = client.plan_mesh_files(plan_text(1))
            self.assertEqual([(f.path, f.unit) for f in files],
                             [(PARTS + "/angle_block.STL", common_pb2.LENGTH_UNIT_INCH),
                              (PARTS + "/round.stl", common_pb2.LENGTH_UNIT_CENTIMETRE)])
            with self.assertRaises(VscanError) as refused:
                client.plan_mesh_files(plan_text(1).replace("unit: cm", "unit: furlong"))
            self.assertEqual(refused.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
            self.assertIn("spec.plan_yaml: bins[1].parts[0].unit: unknown unit 'furlong' (m, cm, mm, in, ft) (line 11)",
                          refused.exception.message)
            self.assertEqual(list(client.list_jobs()), [])  # listing starts nothing

    def test_bad_plans_are_refused_naming_the_key(self):
        good = plan_text(2)
        cases = [
            (good.replace("unit: in, count: 4", "unit: in, count: 0"), "spec.plan_yaml: bins[0].parts[0].count"),
            (good.replace("preset: kinect-v2-class", "preset: no-such-camera"), "spec.plan_yaml.sensors[0].preset"),
            (good.replace("seeds:", "colour: red\nseeds:"), "spec.plan_yaml: colour"),
            (good.replace("inner_size: [0.20, 0.15, 0.10]", "inner_size: [0.20, 0.15, -1]"),
             "spec.plan_yaml: bins[0].bin.inner_size"),
            (good + "views: {count: 0}\n", "spec.plan_yaml: views.count: must be within [1, 1000]"),
            (good + "views: {count: 4, distance_m: [0.3, 0.7]}\n",
             "views.distance_m: [0.3, 0.7] m to the bin's floor leaves the working range [0.5, 4.5] m of sensors[0]"),
            (good + "camera_height_m: 5\n", "camera_height_m: [5, 5] m to the bin's floor leaves the working range"),
            (good.replace("angle_block.STL, unit: in, count: 1", "angle_block.STL, unit: mm, count: 1"),
             "spec.plan_yaml: bins[1].parts[1].unit: " + PARTS + "/angle_block.STL is in in at bins[0].parts[0]"),
            (good.replace("bin: {inner_size: [0.20, 0.15, 0.10]}", "box: {inner_size_m: [0.2, 0.15, 0.1]}"),
             "spec.plan_yaml: bins[0].box: is now written as bin plans write it"),
        ]
        for text, key in cases:
            refused = self.vscan("dataset", "run", self.write_plan("bad.yaml", text))
            self.assertEqual(refused.returncode, 3, refused.stderr)
            self.assertIn(key, refused.stderr)
        resumed = self.vscan("dataset", "run", self.write_plan("ok.yaml", good), "--resume", "job_missing")
        self.assertEqual(resumed.returncode, 3)
        self.assertIn("spec.resume_job_id", resumed.stderr)
        listed = self.vscan("--json", "dataset", "list")
        self.assertEqual(listed.returncode, 0, listed.stderr)
        self.assertEqual(cli_result(listed.stdout).get("jobs", []), [])


if __name__ == "__main__":
    unittest.main()
