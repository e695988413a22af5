"""Materials and the returned light in the plans that scan, through a real vscand and the CLI: a
campaign whose bunny is black anodised aluminium under a weak emitter loses rays as too dark where a
white one keeps them, and a dataset whose part chooses among three materials per scene records each
scene's choice in scene_materials.json, as an independent reimplementation of the choice predicts."""

import json
import math
import os
import subprocess
import tempfile
import time
import unittest

import grpc

from harness import BUNNY, DATA, VSCAN, VSCAND, Server, cli_result
from test_dataset_job import read_png, tree
from vscan import Client, VscanError
from vscan.jobs import campaign_spec
from vscan.v1 import job_pb2, scan_pb2

PARTS = os.path.join(DATA, "parts")
PANDA = os.path.join(DATA, "robots", "panda")
MASK = (1 << 64) - 1


def campaign_plan(material, light="returned_light: {emitter_w_per_sr: 0.00003}"):
    return f"""name: lit-bunny
scene:
  objects:
    - mesh: {BUNNY}
      unit: m
      on_table: true
      pose: {{xyz: [0.017, 0, -0.033], rpy_deg: [90, 0, 0]}}
      material: {material}
  table: {{centre: [0, 0, 0], axis: [0, 0, 1]}}
robot:
  bundle: {PANDA}
  urdf: panda.urdf
  base_link: panda_link0
  tip_link: panda_hand_tcp
  base_pose: {{xyz: [0.6, 0, 0], rpy_deg: [0, 0, 180]}}
sensor:
  pinhole: {{width: 160, height: 120, horizontal_fov_deg: 60, near: 0.05, far: 2}}
{light}
seed: 1
viewpoints:
  - {{position: [0.30, 0.10, 0.20], target: [0, 0, 0.07]}}
"""


def mix(x, more):
    """splitmix64's step, as the dataset job's material choice takes it."""
    x = (x + 0x9E3779B97F4A7C15 + more) & MASK
    x = ((x ^ (x >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    x = ((x ^ (x >> 27)) * 0x94D049BB133111EB) & MASK
    return x ^ (x >> 31)


def chosen(seed, bin_index, part_index, count):
    return mix(mix(mix(seed, 0x6D6174657269616C), bin_index), part_index) % count


CHOICES = ["machined-aluminium", "black-anodised-aluminium", "white-abs"]


def dataset_plan(seeds, choices=", ".join(CHOICES)):
    return f"""name: lit-bins
bins:
  - name: blocks
    bin: {{inner_size: [0.20, 0.15, 0.10]}}
    parts:
      - {{mesh: {PARTS}/angle_block.STL, unit: in, count: 3, material: {{choose: [{choices}]}}}}
      - {{mesh: {PARTS}/round.stl, unit: cm, scale: 0.25, count: 1}}
    max_simulated_s: 4
seeds: {{first: 1, count: {seeds}}}
sensors:
  - {{name: tof, preset: kinect-v2-class, width: 128, height: 106}}
returned_light: {{}}
"""


class PlanMaterialsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-planmat-")
        cls.server = Server(data_dir=cls.tmp.name).start()

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()
        cls.tmp.cleanup()

    def vscan(self, *args, timeout=300):
        return subprocess.run([VSCAN, "--server", self.server.address, *args], capture_output=True, text=True,
                              timeout=timeout)

    def write(self, name, text):
        path = os.path.join(self.tmp.name, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def run_campaign(self, name, material):
        out = os.path.join(self.tmp.name, name)
        run = self.vscan("--json", "campaign", "run", self.write(name + ".yaml", campaign_plan(material)), "-o", out)
        self.assertEqual(run.returncode, 0, run.stderr + self.server.log())
        result = cli_result(run.stdout)
        with open(os.path.join(out, "campaign.json")) as f:
            report = json.load(f)
        return result, report["steps"][0]

    def test_a_black_anodised_bunny_goes_dark_under_a_weak_emitter_and_a_white_one_does_not(self):
        black, black_step = self.run_campaign("black", "black-anodised-aluminium")
        white, white_step = self.run_campaign("white", "white-abs")
        self.assertEqual(black_step["outcome"], "captured")
        black_dark, white_dark = black_step.get("rejected_dark", 0), white_step.get("rejected_dark", 0)
        # The same rays meet the same bunny: every one is a point or a rejected ray in both scans.
        self.assertEqual(black_step["points"] + black_dark, white_step["points"] + white_dark)
        self.assertNotIn("rejected_saturated", black_step)
        self.assertNotIn("rejected_saturated", white_step)
        # albedo 0.85 against about 0.03: most of the black bunny is too dark, little of the white one.
        self.assertGreater(black_dark, black_step["points"], black_step)
        self.assertLess(white_dark * 10, black_dark, white_step)
        with Client(self.server.address) as client:
            job = client.get_job(black["job"]["jobId"])
            self.assertEqual(job.campaign.returned_light.emitter_w_per_sr, 0.00003)
            scene = client.get_scene(job.campaign.scene_id)
            self.assertEqual(scene.objects[0].material.preset, "black-anodised-aluminium")
            # The Python client's campaign with the same light scans the same rays dark.
            again = client.start_campaign(job.campaign.scene_id, job.campaign.mount_id,
                                          [((0.30, 0.10, 0.20), (0, 0, 0.07))], width=160, height=120, hfov_deg=60,
                                          near=0.05, far=2, seed=1, returned_light={"emitter_w_per_sr": 0.00003})
            done = client.wait_job(again.job_id, timeout=120)
            self.assertEqual(done.campaign.returned_light.emitter_w_per_sr, 0.00003)
            scans = [a for a in done.artifacts if a.name.endswith(".ply")]
            self.assertEqual([a.scan.points for a in scans], [black_step["points"]])
            with self.assertRaises(VscanError) as refused:
                client.validate_campaign(viewpoints=[((0.3, 0.1, 0.2), (0, 0, 0.07))],
                                         returned_light={"exposure_s": 20})
            self.assertIn("spec.returned_light.exposure_s", refused.exception.message)
            with self.assertRaises(ValueError):
                campaign_spec("s", "m", [], returned_light={"exposure": 1})

    def test_next_best_views_count_only_what_the_campaigns_light_would_measure(self):
        black, _ = self.run_campaign("nbv-black", "black-anodised-aluminium")
        white, _ = self.run_campaign("nbv-white", "white-abs")
        gains = {}
        with Client(self.server.address) as client:
            for name, run in (("black", black), ("white", white)):
                job = client.start_model(campaign_job_id=run["job"]["jobId"], evaluate=True, next_best_views=3)
                done = client.wait_job(job.job_id, timeout=300)
                self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
                views = client.model_report(job.job_id)["evaluation"].get("next_best_views", [])
                gains[name] = sum(view["coverage_gain"] for view in views)
        # The same bunny from the same viewpoint missed about as much either way, but a new view of
        # the black one under the same weak light would measure little of it.
        self.assertGreater(gains["white"], 0.05, gains)
        self.assertLess(gains["black"], gains["white"] / 2, gains)

    def test_campaign_plans_with_bad_materials_or_light_are_refused_at_their_line(self):
        with Client(self.server.address) as client:
            scenes_before = len(client.list_scenes())
        unknown = self.vscan("campaign", "run", self.write("unknown.yaml", campaign_plan("unobtainium")))
        self.assertEqual(unknown.returncode, 2, unknown.stderr)
        self.assertIn("unknown.yaml:8: scene.objects[0].material: unknown preset 'unobtainium' (matte-grey",
                      unknown.stderr)
        bright = self.vscan("campaign", "run", self.write("bright.yaml", campaign_plan(
            "white-abs", "returned_light: {emitter_w_per_sr: 0.5,\n  exposure_s: 20}")))
        self.assertEqual(bright.returncode, 2, bright.stderr)
        self.assertIn("bright.yaml:19: returned_light.exposure_s:", bright.stderr)
        nan = self.vscan("campaign", "run", self.write("nan.yaml", campaign_plan(
            "{diffuse_albedo: .nan, metallic: 0, roughness: 0.5, specular_reflectance: 0.04}")))
        self.assertEqual(nan.returncode, 2, nan.stderr)
        self.assertIn("nan.yaml:8: scene.objects[0].material.diffuse_albedo: '.nan' is not finite", nan.stderr)
        with Client(self.server.address) as client:
            self.assertEqual(len(client.list_scenes()), scenes_before)  # nothing was created

    def test_a_datasets_part_takes_one_of_its_materials_per_scene_as_the_seed_says(self):
        seeds = 6
        run = self.vscan("dataset", "run", self.write("lit.yaml", dataset_plan(seeds)), "--watch")
        self.assertEqual(run.returncode, 0, run.stderr + self.server.log())
        job_id = (run.stdout + run.stderr).split("started dataset job ")[1].split()[0]
        root = os.path.join(self.tmp.name, "store", "datasets", job_id)
        with open(os.path.join(root, "scenes.json")) as f:
            scenes = json.load(f)["scenes"]
        self.assertEqual(len(scenes), seeds)
        taken = set()
        for entry in scenes:
            scene = os.path.join(root, "train_pbr", "%06d" % entry["scene_id"])
            with open(os.path.join(scene, "scene_materials.json")) as f:
                instances = json.load(f)["instances"]
            with open(os.path.join(scene, "scene_gt.json")) as f:
                gt = json.load(f)["0"]
            # One entry per placed part, as scene_gt.json lists them.
            self.assertEqual(sorted(i["obj_id"] for i in instances), sorted(p["obj_id"] for p in gt))
            blocks = [i for i in instances if i["obj_id"] == 1]
            rods = [i for i in instances if i["obj_id"] == 2]
            self.assertGreater(len(blocks), 0, instances)
            expected = CHOICES[chosen(entry["seed"], 0, 0, len(CHOICES))]
            for block in blocks:
                self.assertEqual(block["material"], {"preset": expected}, entry)
            for rod in rods:
                self.assertEqual(rod["material"], {"preset": "matte-grey"})  # no material: the default
            taken.add(expected)
        self.assertGreater(len(taken), 1, "six seeds should not all choose the same material")
        # The one-shot shards light and choose the same: the same bytes.
        one_shot = os.path.join(self.tmp.name, "one-shot")
        plan = os.path.join(self.tmp.name, "lit.yaml")
        for args in (["--dataset-shard", plan, "--shard-index", "0", "--shard-count", "2"],
                     ["--dataset-shard", plan, "--shard-index", "1", "--shard-count", "2"], ["--dataset-merge", plan]):
            done = subprocess.run([VSCAND, "--log-level", "warn", *args, "--out", one_shot], capture_output=True,
                                  text=True, timeout=300)
            self.assertEqual(done.returncode, 0, done.stderr)
        self.assertEqual(tree(root), tree(one_shot))

    def run_dataset(self, name, text):
        run = self.vscan("dataset", "run", self.write(name, text), "--watch")
        self.assertEqual(run.returncode, 0, run.stderr + self.server.log())
        job_id = (run.stdout + run.stderr).split("started dataset job ")[1].split()[0]
        return os.path.join(self.tmp.name, "store", "datasets", job_id, "train_pbr", "000000")

    def test_a_datasets_weak_emitter_leaves_its_black_parts_unmeasured(self):
        black = dataset_plan(1, "black-anodised-aluminium")
        visible, dark = {}, {}
        for name, text in (("unlit.yaml", black.replace("returned_light: {}\n", "")),
                           ("lit.yaml", black.replace("returned_light: {}", "returned_light: {emitter_w_per_sr: 1e-5}"))):
            scene = self.run_dataset(name, text)
            with open(os.path.join(scene, "scene_gt_info.json")) as f:
                info = json.load(f)["0"]
            with open(os.path.join(scene, "scene_gt.json")) as f:
                gt = json.load(f)["0"]
            visible[name] = sum(i["px_count_visib"] for i, p in zip(info, gt) if p["obj_id"] == 1)
            reasons, _ = read_png(os.path.join(scene, "reasons", "000000.png"))
            dark[name] = int((reasons == scan_pb2.POINT_STATUS_REJECTED_DARK).sum())
        # The same seed fills the same bin: the blocks the unlit scan sees, the lit one mostly loses,
        # and the reason image says why: those pixels are dark.
        self.assertGreater(visible["unlit.yaml"], 20, visible)
        self.assertLess(visible["lit.yaml"], visible["unlit.yaml"] / 2, visible)
        self.assertEqual(dark["unlit.yaml"], 0, dark)
        self.assertGreaterEqual(dark["lit.yaml"], visible["unlit.yaml"] - visible["lit.yaml"], (dark, visible))

    def test_hostile_plans_are_refused_at_once(self):
        # Within the 1 MiB a plan may take, about 90000 choices: refused by their count.
        huge = dataset_plan(1, ", ".join(["white-abs"] * 90000))
        started = time.monotonic()
        with Client(self.server.address) as client:
            with self.assertRaises(VscanError) as refused:
                client.validate_dataset(self.write("huge.yaml", huge))
            self.assertEqual(refused.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
            self.assertIn("material.choose: at most 64 materials, got 90000", refused.exception.message)
            with self.assertRaises(VscanError) as refused:
                client.validate_campaign(viewpoints=[((0.3, 0.1, 0.2), (0, 0, 0.07))],
                                         returned_light={"min_snr": math.nan})
            self.assertEqual(refused.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
            self.assertIn("spec.returned_light.min_snr", refused.exception.message)
        self.assertLess(time.monotonic() - started, 30)

    def test_dataset_plans_with_bad_materials_are_refused_naming_the_key_and_line(self):
        cases = [
            (dataset_plan(1, "white-abs, unobtainium"),
             "spec.plan_yaml: bins[0].parts[0].material.choose[1]: unknown preset 'unobtainium'"),
            (dataset_plan(1, ""), "spec.plan_yaml: bins[0].parts[0].material.choose: expected at least 1 items (line 6)"),
            (dataset_plan(1, ", ".join(["white-abs"] * 65)),
             "spec.plan_yaml: bins[0].parts[0].material.choose: at most 64 materials, got 65 (line 6)"),
            (dataset_plan(1).replace("returned_light: {}", "returned_light: {exposure_s: 20}"),
             "spec.plan_yaml.returned_light.exposure_s"),
        ]
        for text, key in cases:
            refused = self.vscan("dataset", "run", self.write("bad.yaml", text))
            self.assertNotEqual(refused.returncode, 0, refused.stderr)
            self.assertIn(key, refused.stderr)


if __name__ == "__main__":
    unittest.main()
