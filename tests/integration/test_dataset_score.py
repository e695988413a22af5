"""A BOP results file scored against a dataset job's dataset on a real vscand: through the CLI,
agreeing with bop_toolkit_lib on every recall (bench/bop_dataset_score_check.py; skipped, saying
so, without the toolkit); the CLI's table; the Python client; grasp success with a gripper (CLI,
Python); refusals by field that change nothing and leave the server serving."""

import hashlib
import json
import os
import subprocess
import sys
import tempfile
import time
import unittest

import grpc
from harness import SOURCE_DIR, VSCAN, Server
from vscan import Client, VscanError
from vscan.v1 import job_pb2, job_pb2_grpc

sys.path.insert(0, os.path.join(SOURCE_DIR, "bench"))
import bop_dataset_score_check as check  # noqa: E402

IDENTITY = "1 0 0 0 1 0 0 0 1"


def tree_digest(root):
    digest = hashlib.sha256()
    for base, dirs, names in sorted(os.walk(root)):
        dirs.sort()
        for name in sorted(names):
            path = os.path.join(base, name)
            st = os.stat(path)
            digest.update(f"{os.path.relpath(path, root)} {st.st_size} {st.st_mtime_ns}".encode())
    return digest.hexdigest()


def exact_results(root):
    """Every valid true instance estimated exactly (score 1), the first of each image twice (score
    0.5, 10 cm off), and two rows for images the dataset lacks."""
    rows = ["scene_id,im_id,obj_id,score,R,t,time"]
    scenes = sorted(os.listdir(os.path.join(root, "train_pbr")))
    for scene in scenes:
        with open(os.path.join(root, "train_pbr", scene, "scene_gt_info.json")) as f:
            infos = json.load(f)
        with open(os.path.join(root, "train_pbr", scene, "scene_gt.json")) as f:
            for im_id, gts in json.load(f).items():
                for k, gt in enumerate(gts):
                    if infos[im_id][k]["visib_fract"] < 0.1:
                        continue
                    R = " ".join(repr(v) for v in gt["cam_R_m2c"])
                    x, y, z = gt["cam_t_m2c"]
                    rows.append(f"{int(scene)},{im_id},{gt['obj_id']},1,{R},{x!r} {y!r} {z!r},-1")
                    if k == 0:
                        rows.append(f"{int(scene)},{im_id},{gt['obj_id']},0.5,{R},{x + 100!r} {y!r} {z!r},-1")
    rows.append(f"{len(scenes) + 3},0,1,1,{IDENTITY},0 0 500,-1")
    rows.append(f"0,999,1,1,{IDENTITY},0 0 500,-1")
    return "\n".join(rows) + "\n"


class DatasetScoreTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-dsscore-")
        cls.server = Server(data_dir=cls.tmp.name).start()
        plan = os.path.join(cls.tmp.name, "plan.yaml")
        with open(plan, "w") as f:
            f.write(check.plan_text(seeds=3, views=2))
        run = cls.cli("dataset", "run", plan, "--watch")
        assert run.returncode == 0, run.stderr + cls.server.log()
        cls.job_id = (run.stdout + run.stderr).split("started dataset job ")[1].split()[0]
        cls.root = os.path.join(cls.tmp.name, "store", "datasets", cls.job_id)
        cls.csv = os.path.join(cls.tmp.name, "exact.csv")
        with open(cls.csv, "w") as f:
            f.write(exact_results(cls.root))

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()
        cls.tmp.cleanup()

    @classmethod
    def cli(cls, *args, timeout=300):
        return subprocess.run([VSCAN, "--server", cls.server.address, *args], capture_output=True, text=True,
                              timeout=timeout)

    def stub(self):
        return job_pb2_grpc.JobServiceStub(self.server.channel())

    def score(self, csv_bytes, job_id=None):
        request = job_pb2.ScoreDatasetResultsRequest(job_id=job_id or self.job_id, results_csv=csv_bytes)
        return self.stub().ScoreDatasetResults(request, timeout=120)

    def assertRefused(self, code, csv_bytes, *says, job_id=None):
        with self.assertRaises(grpc.RpcError) as caught:
            self.score(csv_bytes, job_id)
        self.assertEqual(caught.exception.code(), code, caught.exception.details())
        for text in says:
            self.assertIn(text, caught.exception.details())

    def test_recalls_agree_with_bop_toolkit(self):
        try:
            bop = check.load_toolkit()
        except ImportError as e:
            self.skipTest(f"bop_toolkit_lib cannot be loaded: {e}")
        # Declares the tube's symmetry and lowers some visibilities in the stored dataset.
        report = check.run_check(VSCAN, self.server.address, self.job_id, self.root, seed=3, workdir=self.tmp.name,
                                 bop=bop)
        self.assertEqual(report["diffs"], [])
        ours, kinds = report["ours"], report["kinds"]
        overall = ours["overall"]
        # The check covered what it is meant to: symmetric-equivalent tubes, invalid instances,
        # absent part types and unknown images, and recalls neither 0 nor 1.
        self.assertGreater(kinds.get("symmetric", 0), 0)
        self.assertGreater(kinds.get("absent part", 0), 0)
        self.assertGreater(ours["trueInstances"], overall["validInstances"])
        self.assertEqual(int(ours["ignoredRows"]), 2)
        self.assertEqual(len(ours["ignoredImages"]), 2)
        self.assertTrue(0 < overall["addRecall"] < 1, overall)
        self.assertTrue(0 < overall["mssdAverageRecall"] < 1, overall)
        self.assertEqual([o["objId"] for o in ours["objects"]], [1, 2])
        self.assertEqual([o.get("usesAddS", False) for o in ours["objects"]], [False, True])
        self.assertEqual(len(ours["scenes"]), 6)
        # The comparison itself can fail: one match more is seen.
        changed = dict(ours, overall=dict(overall, addCorrect=str(int(overall["addCorrect"]) + 1)))
        self.assertIn("ADD(-S) correct", [d[0] for d in check.compare(changed, report["theirs"])])

    def test_exact_estimates_through_the_cli(self):
        run = self.cli("dataset", "score", self.job_id, "--results", self.csv, "--json")
        self.assertEqual(run.returncode, 0, run.stderr)
        ours = json.loads(run.stdout)
        overall = ours["overall"]
        # Every valid instance found at every threshold; the 10 cm duplicates were cut (a lower
        # score than the exact estimate of the same part) or matched nothing.
        self.assertEqual(overall["addCorrect"], overall["validInstances"])
        self.assertEqual(overall["addRecall"], 1)
        self.assertEqual(overall["mssdAverageRecall"], 1)
        self.assertEqual(int(ours["ignoredRows"]), 2)
        self.assertEqual(int(ours["rows"]), int(overall["estimates"]) + 2)
        self.assertEqual(len(ours["scenes"]), int(ours["sceneCount"]))
        self.assertEqual([o["objId"] for o in ours["objects"]], [1, 2])
        run = self.cli("dataset", "score", self.job_id, "--results", self.csv)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertIn("obj_id", run.stdout)
        all_line = [line for line in run.stdout.splitlines() if line.startswith("all ")][0]
        self.assertIn("1.000    1.000", all_line)
        self.assertIn("2 estimates left out: their images are not in the dataset", run.stdout)
        missing = self.cli("dataset", "score", self.job_id, "--results", os.path.join(self.tmp.name, "none.csv"))
        self.assertEqual(missing.returncode, 5, missing.stderr)

    def test_grasp_success_with_jaws_through_the_cli_and_python(self):
        # The views look down within 25 degrees: up is about -z in the camera frame.
        flags = ["--jaws-max-opening", "0.06", "--up", "0", "0", "-1"]
        run = self.cli("dataset", "score", self.job_id, "--results", self.csv, "--json", *flags)
        self.assertEqual(run.returncode, 0, run.stderr)
        ours = json.loads(run.stdout)
        overall = ours["overall"]
        holds, valid = int(overall.get("graspHolds", 0)), int(overall["validInstances"])
        # Exact estimates: a grasp fails only where none approaches from above.
        self.assertGreater(holds, 0)
        self.assertAlmostEqual(overall["graspSuccess"], holds / valid, places=12)
        self.assertEqual(sum(int(o["recall"].get("graspHolds", 0)) for o in ours["objects"]), holds)
        self.assertEqual(sum(int(s["recall"].get("graspHolds", 0)) for s in ours["scenes"]), holds)
        self.assertEqual(overall["addRecall"], 1)
        text = self.cli("dataset", "score", self.job_id, "--results", self.csv, *flags)
        self.assertEqual(text.returncode, 0, text.stderr)
        self.assertIn("grasp", [line for line in text.stdout.splitlines() if line.startswith("obj_id")][0])
        plain = json.loads(self.cli("dataset", "score", self.job_id, "--results", self.csv, "--json").stdout)
        self.assertNotIn("graspSuccess", plain["overall"])

        # Every estimate moved 30 mm sideways in the image: few jaws still close on the true part.
        with open(self.csv) as f:
            lines = f.read().splitlines()
        moved = [lines[0]]
        for line in lines[1:]:
            cells = line.split(",")
            x, y, z = (float(v) for v in cells[5].split())
            cells[5] = f"{x + 30!r} {y!r} {z!r}"
            moved.append(",".join(cells))
        with Client(self.server.address) as client:
            jaws = {"jaws": {"max_opening": 0.06}}
            exact = client.score_dataset_results(self.job_id, self.csv, gripper=jaws, up=(0, 0, -1))
            shifted = client.score_dataset_results(self.job_id, ("\n".join(moved) + "\n").encode(), gripper=jaws,
                                                   up=(0, 0, -1))
            with self.assertRaises(VscanError) as caught:
                client.score_dataset_results(self.job_id, self.csv, gripper=jaws, up=(0, 0, 0))
            self.assertEqual(caught.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
            self.assertIn("up", str(caught.exception))
        self.assertEqual(exact.overall.grasp_holds, holds)
        self.assertLess(shifted.overall.grasp_holds, holds / 4)

    def test_python_client(self):
        with Client(self.server.address) as client:
            response = client.score_dataset_results(self.job_id, self.csv)
            with open(self.csv, "rb") as f:
                again = client.score_dataset_results(self.job_id, f.read())
            with self.assertRaises(VscanError) as caught:
                client.score_dataset_results("job_0000000000000000", b"")
            self.assertEqual(caught.exception.code, grpc.StatusCode.NOT_FOUND)
        cli = json.loads(self.cli("dataset", "score", self.job_id, "--results", self.csv, "--json").stdout)
        self.assertEqual(response.overall.add_correct, int(cli["overall"]["addCorrect"]))
        self.assertEqual(response.overall.mssd_average_recall, cli["overall"]["mssdAverageRecall"])
        self.assertEqual(response.overall, again.overall)
        self.assertEqual([o.obj_id for o in response.objects], [1, 2])

    def test_refusals_name_the_field_and_change_nothing(self):
        before = tree_digest(self.root)
        good = f"0,0,1,0.5,{IDENTITY},0 0 500,-1\n"
        bad = [
            (good + "0,0,1,0.5\n", "results_csv", "line 2: 4 comma-separated fields"),
            (good + good + f"0,0,1,nan,{IDENTITY},0 0 500,-1\n", "line 3, column 4 (score)"),
            (f"0,0,1,0.5,{IDENTITY},0 0 1e19,-1\n", "line 1, column 6 (t)"),
            ("0,0,1,0.5,NaN 0 0 0 1 0 0 0 1,0 0 500,-1\n", "line 1, column 5 (R)"),
            ("0,0,1,0.5,2 0 0 0 1 0 0 0 1,0 0 500,-1\n", "line 1, column 5 (R): not a rotation"),
            (f"-1,0,1,0.5,{IDENTITY},0 0 500,-1\n", "line 1, column 1 (scene_id)"),
            (good + f"0,0,7,0.5,{IDENTITY},0 0 500,-1\n", "line 2, column 3 (obj_id): obj_id 7 is not a part type"),
        ]
        for csv, *says in bad:
            self.assertRefused(grpc.StatusCode.INVALID_ARGUMENT, csv.encode(), *says)
        self.assertRefused(grpc.StatusCode.RESOURCE_EXHAUSTED, b"x" * ((3 << 20) + 1), "results_csv")
        self.assertRefused(grpc.StatusCode.INVALID_ARGUMENT, b"", "job_id", job_id=" ")
        self.assertRefused(grpc.StatusCode.NOT_FOUND, b"", "job_id", job_id="job_0123456789abcdef")
        # Many rows (3 MiB of them, all for one image and part): cut to its valid instances at once.
        row = f"0,0,1,0.5,{IDENTITY},0 0 500,-1\n".encode()
        many = row * ((3 << 20) // len(row))
        start = time.monotonic()
        response = self.score(many)
        self.assertLess(time.monotonic() - start, 60)
        self.assertEqual(response.rows, len(many) // len(row))
        self.assertGreater(response.rows, 60000)
        self.assertEqual(response.overall.estimates, response.rows)
        # The CLI refuses a file past the bound before sending it.
        big = os.path.join(self.tmp.name, "big.csv")
        with open(big, "wb") as f:
            f.write(many + row * 1000)
        run = self.cli("dataset", "score", self.job_id, "--results", big)
        self.assertEqual(run.returncode, 2, run.stderr)
        self.assertIn("--results", run.stderr)
        self.assertEqual(tree_digest(self.root), before)
        self.assertEqual(self.score(good.encode()).rows, 1)

    def test_a_job_that_has_not_succeeded_is_refused(self):
        plan = os.path.join(self.tmp.name, "bad.yaml")
        with open(plan, "w") as f:
            f.write(check.plan_text(seeds=40, views=1))
        started = self.cli("--quiet", "dataset", "run", plan)
        self.assertEqual(started.returncode, 0, started.stderr)
        job_id = started.stdout.split()[-1]
        cancelled = self.cli("dataset", "cancel", job_id)
        self.assertEqual(cancelled.returncode, 0, cancelled.stderr)
        self.assertRefused(grpc.StatusCode.FAILED_PRECONDITION, b"", "job_id", job_id=job_id)


if __name__ == "__main__":
    unittest.main()
