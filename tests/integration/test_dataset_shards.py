"""Datasets written the way the Kubernetes pods write them: `vscand --dataset-shard` with the index
set by hand, then `vscand --dataset-merge`; two shards merged equal one process byte for byte."""

import json
import os
import subprocess
import tempfile
import unittest

import numpy as np

from harness import SOURCE_DIR, VSCAND

PLAN = os.path.join(SOURCE_DIR, "tests", "integration", "data", "small_dataset_plan.yaml")


def vscand(*args):
    return subprocess.run([VSCAND, "--log-level", "warn", *args], capture_output=True, text=True, timeout=600)


def shard(plan, out, index, count):
    return vscand("--dataset-shard", plan, "--out", out, "--shard-index", str(index), "--shard-count", str(count))


def merge(plan, out):
    return vscand("--dataset-merge", plan, "--out", out)


# The table under the bin: in the cloud with this instance id, never in the ground truth.
TABLE_INSTANCE = 0xFFFFFFFE


def read_cloud(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    count = int(next(line for line in header if line.startswith("element vertex")).split()[2])
    kinds = {"float": "<f4", "int": "<i4", "uint": "<u4", "uchar": "u1", "double": "<f8"}
    fields = [(line.split()[2], kinds[line.split()[1]]) for line in header if line.startswith("property")]
    return np.frombuffer(data[end:], dtype=np.dtype(fields), count=count)


def tree(root):
    files = {}
    for base, _, names in os.walk(root):
        for name in names:
            path = os.path.join(base, name)
            with open(path, "rb") as f:
                files[os.path.relpath(path, root)] = f.read()
    return files


class DatasetShardsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-dataset-")
        cls.sharded = os.path.join(cls.tmp.name, "sharded")
        cls.whole = os.path.join(cls.tmp.name, "whole")
        cls.shard_runs = [shard(PLAN, cls.sharded, i, 2) for i in (1, 0)]
        cls.merge_run = merge(PLAN, cls.sharded)
        cls.whole_runs = [shard(PLAN, cls.whole, 0, 1), merge(PLAN, cls.whole)]

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_two_shards_merged_equal_one_process(self):
        for run in [*self.shard_runs, self.merge_run, *self.whole_runs]:
            self.assertEqual(run.returncode, 0, run.stderr)
        sharded, whole = tree(self.sharded), tree(self.whole)
        self.assertEqual(sorted(sharded), sorted(whole))
        for path in whole:
            self.assertEqual(sharded[path], whole[path], path)

    def test_every_scene_has_parts_with_ground_truth(self):
        with open(os.path.join(self.whole, "scenes.json")) as f:
            index = json.load(f)
        self.assertEqual(index["scene_count"], 4)
        self.assertEqual([(s["seed"], s["bin"]) for s in index["scenes"]],
                         [(7, "blocks"), (7, "blocks-and-rod"), (8, "blocks"), (8, "blocks-and-rod")])
        with open(os.path.join(self.whole, "models", "models_info.json")) as f:
            models = json.load(f)
        self.assertEqual(sorted(models), ["1", "2"])  # angle_block and the short round
        with open(os.path.join(self.whole, "camera.json")) as f:
            camera = json.load(f)  # one sensor: BOP's single camera file
        self.assertEqual((camera["width"], camera["height"]), (128, 106))
        for obj_id in (1, 2):
            self.assertTrue(os.path.isfile(os.path.join(self.whole, "models", "obj_%06d.ply" % obj_id)))
        self.assertAlmostEqual(models["2"]["size_z"], 152.4, delta=0.5)  # 60.96 cm x 0.25, in mm
        for scene in index["scenes"]:
            scene_dir = os.path.join(self.whole, "train_pbr", f"{scene['scene_id']:06d}")
            with open(os.path.join(scene_dir, "scene_gt.json")) as f:
                gt = json.load(f)["0"]
            with open(os.path.join(scene_dir, "scene_gt_info.json")) as f:
                info = json.load(f)["0"]
            self.assertGreaterEqual(len(gt), 2, scene)
            with open(os.path.join(scene_dir, "scene_fill.json")) as f:
                fill = json.load(f)
            self.assertEqual(fill["underfilled"], fill["parts_placed"] < fill["parts_planned"], scene)
            # The fill's overlaps measured on the parts' true meshes: within the 0.5 mm bound.
            self.assertLessEqual(fill["mesh_overlap"]["max_part_part_m"], 0.0005, scene)
            self.assertLessEqual(fill["mesh_overlap"]["max_part_bin_m"], 0.0005, scene)
            self.assertEqual(len(gt), len(info))
            seen = [entry for entry in info if entry["px_count_visib"] > 0]
            self.assertTrue(seen, scene)
            for entry in info:
                self.assertIsInstance(entry["px_count_all"], int)
                self.assertGreaterEqual(entry["visib_fract"], 0.0)
                self.assertLessEqual(entry["visib_fract"], 1.0)
            self.assertNotIn(TABLE_INSTANCE, [entry["instance_id"] for entry in gt])
            for gt_id in range(len(gt)):
                for folder in ("mask", "mask_visib"):
                    self.assertTrue(os.path.isfile(os.path.join(scene_dir, folder, "000000_%06d.png" % gt_id)))
            with open(os.path.join(scene_dir, "scene_camera.json")) as f:
                world_from_camera = np.array(json.load(f)["0"]["world_from_camera"]).reshape(4, 4)
            cloud = read_cloud(os.path.join(scene_dir, "cloud", "000000.ply"))
            # vscan writes instance ids as int32 (what Open3D reads); the table's id is 0xFFFFFFFE as uint32.
            table = cloud[cloud["instance"].astype(np.uint32) == TABLE_INSTANCE]
            self.assertGreater(len(table), 100, scene)
            xyz = np.stack([table["x"], table["y"], table["z"]], axis=1).astype(np.float64)
            in_camera = (xyz - world_from_camera[:3, 3]) @ world_from_camera[:3, :3]
            # The table's top is the bin's outer floor: 0.6 m plus the 10 mm floor below the camera.
            self.assertAlmostEqual(float(np.median(in_camera[:, 2])), 0.61, delta=0.01)
            for entry in gt:
                # Parts lie in the bin, 0.6 m below the camera less the bin's depth at most.
                self.assertGreater(entry["cam_t_m2c"][2], 480)
                self.assertLess(entry["cam_t_m2c"][2], 620)

    def test_merge_names_the_scenes_a_missing_shard_owns(self):
        with tempfile.TemporaryDirectory(prefix="vscan-dataset-") as out:
            self.assertEqual(shard(PLAN, out, 0, 2).returncode, 0)
            merged = merge(PLAN, out)
            self.assertNotEqual(merged.returncode, 0)
            self.assertIn("000002", merged.stderr)
            self.assertFalse(os.path.exists(os.path.join(out, "scenes.json")))

    def test_bad_plans_are_refused_naming_the_key(self):
        with open(PLAN) as f:
            text = f.read().replace("../../../data/parts/", os.path.join(SOURCE_DIR, "data", "parts") + "/")
        cases = [
            (text.replace("unit: in, count: 3", "unit: in, count: 0"), "bins[0].parts[0].count"),
            (text.replace("unit: cm,", "unit: furlong,"), "bins[1].parts[1].unit"),
            (text.replace("preset: kinect-v2-class", "preset: no-such-camera"), "sensors[0].preset"),
            (text.replace("angle_block.STL, unit: in, count: 3", "missing.stl, unit: in, count: 3"),
             "bins[0].parts[0].mesh"),
        ]
        with tempfile.TemporaryDirectory(prefix="vscan-dataset-") as out:
            plan = os.path.join(out, "bad_plan.yaml")
            for bad, key in cases:
                with open(plan, "w") as f:
                    f.write(bad)
                run = shard(plan, os.path.join(out, "ds"), 0, 1)
                self.assertEqual(run.returncode, 2, run.stderr)
                self.assertIn(key, run.stderr)
                self.assertFalse(os.path.exists(os.path.join(out, "ds")), key)

    def test_shard_arguments_are_checked(self):
        with tempfile.TemporaryDirectory(prefix="vscan-dataset-") as out:
            run = shard(PLAN, out, 2, 2)
            self.assertEqual(run.returncode, 2)
            self.assertIn("shard_index", run.stderr)


if __name__ == "__main__":
    unittest.main()
