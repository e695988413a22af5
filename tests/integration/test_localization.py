"""LocalizationService through a real vscand: a bin of angle blocks filled and scanned with ground
truth, localized and scored with the CLI (vscan localize, vscan score, BOP results CSV) and the
Python client; a bin of angle blocks and pins searched for both in one call (CLI, Python, progress
streamed); grasp success beside the recalls with a gripper (CLI, Python); refusals named by field;
a deadline and a cancel stop a search.

The localizer's recall on a filled bin is measured in BENCHMARKS.md (on this bin it finds 3 of the
6 blocks); here a correct pipeline is told apart by poses that agree with the truth to a few
millimetres at most, which a mistake of frame, unit or matrix order could not give."""

import csv
import json
import math
import os
import subprocess
import tempfile
import time

import grpc
import numpy as np

from harness import VSCAN, ServerTestCase, scene_pb2  # first: puts the stubs on sys.path
from bin_scenes import fill_bin, height_for, scan_bin, upload_part, write_ground_truth, write_ply
from vscan.v1 import common_pb2, localization_pb2, localization_pb2_grpc
from vscan import Client, VscanError, truth_from_objects

INNER = (0.16, 0.12, 0.08)


def matrix(values):
    return common_pb2.Pose(matrix=common_pb2.Matrix4(values=list(values)))


IDENTITY = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
# Of the six blocks, at least this many found and matched with an ADD error below EXACT metres (5%
# of the block's 51 mm diameter).
MIN_EXACT = 2
EXACT = 0.0025
# The bin of two part types.
MIXED_BLOCKS, MIXED_PINS = 4, 3


class LocalizationTest(ServerTestCase):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.stub = localization_pb2_grpc.LocalizationServiceStub(cls.channel)
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-localize-")
        cls.mesh_id, _ = upload_part(cls.scenes, "angle_block")
        scene = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="bin"), timeout=30).scene
        cls.job = fill_bin(cls.channel, scene.scene_id, [(cls.mesh_id, 1.0, 6)], seed=3, inner_size=INNER)
        height = height_for(INNER, 50, 320, 240)
        cls.positions, cls.normals, header, cls.stats = scan_bin(cls.scans, scene.scene_id, 320, 240, height,
                                                                 hfov_deg=50, inner_size=INNER)
        cls.cloud = os.path.join(cls.tmp.name, "bin.ply")
        cls.truth = os.path.join(cls.tmp.name, "bin.gt.json")
        write_ply(cls.cloud, cls.positions, cls.normals)
        write_ground_truth(cls.truth, cls.job.job_id, header, cls.stats, cls.cloud, len(cls.positions))
        cls.estimates = None
        # Two part types: angle blocks and pins (the tube at 0.127, 6.5 mm across), seen at 640 x 480.
        cls.pin_id, cls.pin_scale = upload_part(cls.scenes, "round")
        mixed = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="mixed"), timeout=30).scene
        mixed_job = fill_bin(cls.channel, mixed.scene_id, [(cls.mesh_id, 1.0, MIXED_BLOCKS),
                                                           (cls.pin_id, cls.pin_scale, MIXED_PINS)],
                             seed=5, inner_size=INNER)
        cls.mixed_positions, cls.mixed_normals, mixed_header, cls.mixed_stats = scan_bin(
            cls.scans, mixed.scene_id, 640, 480, height_for(INNER, 50, 640, 480), hfov_deg=50, inner_size=INNER)
        cls.mixed_cloud = os.path.join(cls.tmp.name, "mixed.ply")
        cls.mixed_truth = os.path.join(cls.tmp.name, "mixed.gt.json")
        write_ply(cls.mixed_cloud, cls.mixed_positions, cls.mixed_normals)
        write_ground_truth(cls.mixed_truth, mixed_job.job_id, mixed_header, cls.mixed_stats, cls.mixed_cloud,
                           len(cls.mixed_positions))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()
        super().tearDownClass()

    def cli(self, *args):
        done = subprocess.run([VSCAN, "--server", self.server.address, *args], capture_output=True, text=True,
                              timeout=300)
        self.assertEqual(done.returncode, 0, done.stderr + done.stdout)
        return done.stdout

    def localize_file(self):
        """estimates.json of `vscan localize` on the bin's PLY; the search runs once per class."""
        cls = type(self)
        if cls.estimates is None:
            path = os.path.join(self.tmp.name, "estimates.json")
            self.cli("localize", "--cloud", self.cloud, "--mesh", self.mesh_id, "--max", "8", "--out", path)
            cls.estimates = path
        return cls.estimates

    def assertExactMatches(self, matches, error=lambda m: m["addError"], matched=lambda m: "estimateIndex" in m):
        exact = [m for m in matches if matched(m) and error(m) < EXACT]
        self.assertGreaterEqual(len(exact), MIN_EXACT, matches)

    def test_cli_localizes_and_scores_a_noise_free_bin(self):
        estimates = self.localize_file()
        with open(estimates) as f:
            found = json.load(f)
        self.assertEqual(found["frame"], "world")
        self.assertGreater(found["localize_ms"], 0)
        self.assertGreaterEqual(len(found["estimates"]), MIN_EXACT)
        self.assertTrue(all(e["mesh_id"] == self.mesh_id and len(e["world_from_part"]) == 16
                            for e in found["estimates"]))
        report = json.loads(self.cli("--json", "score", "--truth", self.truth, "--estimates", estimates))
        self.assertEqual(len(report["parts"]), 1)
        part = report["parts"][0]
        self.assertEqual(part["meshId"], self.mesh_id)
        self.assertFalse(part["usesAddS"])
        # The bin itself is left out: only the angle blocks seen above the visibility cut count.
        seen = sum(1 for o in self.stats.objects if o.mesh_id == self.mesh_id and o.visible_fraction >= 0.1)
        self.assertEqual(int(report["validInstances"]), seen)
        self.assertEqual(len(part["matches"]), seen)
        self.assertExactMatches(part["matches"])
        self.assertAlmostEqual(report["addRecall"], int(part["addCorrect"]) / seen, places=12)
        self.assertGreaterEqual(report["mssdAverageRecall"], MIN_EXACT / seen - 1e-12)
        text = self.cli("bin", "score", "--truth", self.truth, "--estimates", estimates)
        self.assertIn("ADD(-S)", text)
        self.assertIn(self.mesh_id, text)

    def test_bop_results_csv_scores_as_the_json_does(self):
        estimates = self.localize_file()
        with open(estimates) as f:
            found = json.load(f)["estimates"]
        with open(self.truth) as f:
            world_from_sensor = np.array(json.load(f)["world_from_sensor"]).reshape(4, 4)
        sensor_from_world = np.linalg.inv(world_from_sensor)
        path = os.path.join(self.tmp.name, "results.csv")
        with open(path, "w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(["scene_id", "im_id", "obj_id", "score", "R", "t", "time"])
            for e in found:
                pose = sensor_from_world @ np.array(e["world_from_part"]).reshape(4, 4)
                writer.writerow([1, 0, 7, e["score"], " ".join(f"{v:.12g}" for v in pose[:3, :3].ravel()),
                                 " ".join(f"{v * 1000:.12g}" for v in pose[:3, 3]), -1])
        from_json = json.loads(self.cli("--json", "score", "--truth", self.truth, "--estimates", estimates))
        from_csv = json.loads(self.cli("--json", "score", "--truth", self.truth, "--estimates", path,
                                       "--bop-obj", f"7={self.mesh_id}"))
        self.assertGreater(from_json["addRecall"], 0)
        self.assertEqual(from_csv["addRecall"], from_json["addRecall"])
        self.assertAlmostEqual(from_csv["mssdAverageRecall"], from_json["mssdAverageRecall"], places=9)
        # Millimetres and the camera frame, undone: the same estimates matched with the same errors.
        for a, b in zip(from_csv["parts"][0]["matches"], from_json["parts"][0]["matches"]):
            self.assertEqual(a.get("estimateIndex"), b.get("estimateIndex"))
            self.assertAlmostEqual(a["addError"], b["addError"], places=7)

    def test_python_client_localizes_sent_points_and_scores_them(self):
        self.assertLessEqual(len(self.positions), 131072)
        with Client(self.server.address) as client:
            # The scan's estimated normals sent along and used as they are.
            found = client.localize(self.mesh_id, points=self.positions, normals=self.normals, max_instances=8,
                                    normal_source="cloud")
            self.assertEqual(found.points, len(self.positions))
            parts = [(self.mesh_id, 1.0)]
            truth = truth_from_objects(self.stats.objects, parts)
            estimates = [(0, e.world_from_part.values, e.score) for e in found.estimates]
            score = client.score_poses(parts, truth, estimates)
            self.assertTrue(score.HasField("add_recall"))
            self.assertExactMatches(score.parts[0].matches, error=lambda m: m.add_error,
                                    matched=lambda m: m.HasField("estimate_index"))
            # The true poses as estimates: every valid instance matched with zero error.
            exact = client.score_poses(parts, truth, [(t.part, t.world_from_part.matrix.values, 1) for t in truth])
            self.assertEqual(exact.add_recall, 1.0)
            self.assertEqual(exact.mssd_average_recall, 1.0)
            self.assertTrue(all(m.HasField("estimate_index") and m.add_error < 1e-6 for m in exact.parts[0].matches))
            # A scan can count a few more points on an object than it gives alone: still fully visible.
            over = [localization_pb2.TruePose(part=t.part, world_from_part=t.world_from_part, visible_fraction=1.02)
                    for t in truth[:1]]
            counted = client.score_poses(parts, over, [(0, over[0].world_from_part.matrix.values, 1)])
            self.assertEqual(counted.add_recall, 1.0)
            # No estimates: an answer, every valid instance missed.
            none = client.score_poses(parts, truth, [])
            self.assertEqual(none.add_recall, 0.0)
            self.assertFalse(any(m.HasField("estimate_index") for m in none.parts[0].matches))

    def test_a_deadline_stops_a_search_and_the_server_carries_on(self):
        request = localization_pb2.LocalizeRequest(mesh_id=self.mesh_id)
        request.points.positions = self.positions[:100000].astype("<f4").tobytes()
        request.options.viewpoint.z = 1
        with self.assertRaises(grpc.RpcError) as ctx:
            self.stub.Localize(request, timeout=0.05)
        self.assertEqual(ctx.exception.code(), grpc.StatusCode.DEADLINE_EXCEEDED)
        score = self.stub.ScorePoses(localization_pb2.ScorePosesRequest(
            parts=[localization_pb2.ScoredPart(mesh_id=self.mesh_id)]), timeout=30)
        self.assertFalse(score.HasField("add_recall"))

    def test_a_hair_fine_voxel_is_refused_at_once_and_the_server_carries_on(self):
        for voxel in (1e-5, 3e-4):
            request = localization_pb2.LocalizeRequest(mesh_id=self.mesh_id)
            request.points.positions = self.positions[:2000].astype("<f4").tobytes()
            request.options.voxel_size = voxel
            request.options.viewpoint.z = 1
            start = time.time()
            self.assertCode(grpc.StatusCode.RESOURCE_EXHAUSTED, lambda: self.stub.Localize(request, timeout=60),
                            "options.voxel_size")
            self.assertLess(time.time() - start, 5.0)
        score = self.stub.ScorePoses(localization_pb2.ScorePosesRequest(
            parts=[localization_pb2.ScoredPart(mesh_id=self.mesh_id)]), timeout=5)
        self.assertFalse(score.HasField("add_recall"))

    def test_grasp_success_with_a_suction_cup_through_the_cli_and_python(self):
        estimates = self.localize_file()
        report = json.loads(self.cli("--json", "score", "--truth", self.truth, "--estimates", estimates,
                                     "--suction-diameter", "0.01"))
        part = report["parts"][0]
        holds = sum(1 for m in part["matches"] if m.get("graspHolds"))
        self.assertEqual(int(report["graspHolds"]), holds)
        self.assertAlmostEqual(report["graspSuccess"], holds / int(report["validInstances"]), places=12)
        # A grasp holds only for a matched estimate, and says why when it does not.
        for m in part["matches"]:
            if "estimateIndex" not in m:
                self.assertFalse(m["graspHolds"])
            elif not m.get("graspHolds"):
                self.assertTrue(m["graspFailure"], m)
        text = self.cli("score", "--truth", self.truth, "--estimates", estimates, "--suction-diameter", "0.01")
        self.assertIn("grasp", text.splitlines()[0])
        plain = json.loads(self.cli("--json", "score", "--truth", self.truth, "--estimates", estimates))
        self.assertNotIn("graspSuccess", plain)
        self.assertEqual(plain["addRecall"], report["addRecall"])

        cup = {"suction": {"diameter": 0.01}}
        with Client(self.server.address) as client:
            parts = [(self.mesh_id, 1.0)]
            truth = truth_from_objects(self.stats.objects, parts)
            exact = client.score_poses(parts, truth, [(t.part, t.world_from_part.matrix.values, 1) for t in truth],
                                       gripper=cup)
            # On the true pose a grasp fails only when none approaches from above.
            matches = exact.parts[0].matches
            self.assertGreater(exact.grasp_holds, 0)
            for m in matches:
                self.assertTrue(m.grasp_holds or m.grasp_failure in (
                    "no grasp of the part approaches from above at the estimated pose",
                    "the gripper has no grasp on the part"), m)
            # 5 mm too high: ADD(-S) calls every one correct (10% of 51 mm), yet the cups stop short.
            high = []
            for t in truth:
                pose = np.array(t.world_from_part.matrix.values).reshape(4, 4)
                pose[2, 3] += 0.005
                high.append((t.part, pose.ravel(), 1))
            lifted = client.score_poses(parts, truth, high, gripper=cup)
            self.assertEqual(lifted.add_recall, 1.0)
            self.assertLess(lifted.grasp_holds, exact.grasp_holds)
            self.assertAlmostEqual(lifted.grasp_success, lifted.grasp_holds / lifted.valid_instances, places=12)
            self.assertTrue(any(m.grasp_failure == "the cup meets no surface of the part"
                                for m in lifted.parts[0].matches))
            # Refusals name the field and leave the server serving.
            for gripper, up, field in [({"suction": {"diameter": math.nan}}, None, "gripper.suction.diameter"),
                                       ({"jaws": {"max_opening": math.inf}}, None, "gripper.jaws.max_opening"),
                                       (cup, (0, 0, 0), "up"), (cup, (math.nan, 0, 1), "up")]:
                with self.assertRaises(VscanError) as caught:
                    client.score_poses(parts, truth, high, gripper=gripper, up=up)
                self.assertEqual(caught.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
                self.assertIn(field, str(caught.exception))
            self.assertEqual(client.score_poses(parts, truth, high).add_recall, 1.0)

    def test_refusals_name_their_field(self):
        invalid, not_found = grpc.StatusCode.INVALID_ARGUMENT, grpc.StatusCode.NOT_FOUND
        localize = localization_pb2.LocalizeRequest

        def points(values):
            return localization_pb2.InlinePoints(positions=np.asarray(values, "<f4").tobytes())
        self.assertCode(invalid, lambda: self.stub.Localize(localize(mesh_id=self.mesh_id)), "source")
        self.assertCode(not_found, lambda: self.stub.Localize(localize(cloud_id="cld_0000000000000000",
                                                                       mesh_id=self.mesh_id)), "cloud_id")
        self.assertCode(not_found, lambda: self.stub.Localize(localize(points=points([[0, 0, 0]]),
                                                                       mesh_id="msh_0000000000000000")), "mesh_id")
        self.assertCode(invalid, lambda: self.stub.Localize(localize(points=points([[0, 0, 0], [math.nan, 0, 0]]),
                                                                     mesh_id=self.mesh_id)), "points.positions[1]")
        self.assertCode(invalid, lambda: self.stub.Localize(localize(
            points=localization_pb2.InlinePoints(positions=b"\0" * 13), mesh_id=self.mesh_id)), "points.positions")
        self.assertCode(grpc.StatusCode.RESOURCE_EXHAUSTED, lambda: self.stub.Localize(localize(
            points=points(np.zeros((131073, 3))), mesh_id=self.mesh_id)), "points.positions")
        self.assertCode(invalid, lambda: self.stub.Localize(localize(
            points=points([[0, 0, 0]]), mesh_id=self.mesh_id,
            options=localization_pb2.LocalizeOptions(max_instances=101))), "options.max_instances")
        self.assertCode(invalid, lambda: self.stub.Localize(localize(
            points=points([[0, 0, 0]]), mesh_id=self.mesh_id,
            options=localization_pb2.LocalizeOptions(min_score=1.5))), "options.min_score")
        self.assertCode(grpc.StatusCode.FAILED_PRECONDITION, lambda: self.stub.Localize(localize(
            points=points([[0, 0, 0]]), mesh_id=self.mesh_id,
            options=localization_pb2.LocalizeOptions(normal_source=localization_pb2.NORMAL_SOURCE_CLOUD))),
            "options.normal_source")

        part = localization_pb2.ScoredPart(mesh_id=self.mesh_id)
        score = localization_pb2.ScorePosesRequest
        skewed = [1, 0.2, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score()), "parts")
        self.assertCode(not_found, lambda: self.stub.ScorePoses(score(parts=[
            part, localization_pb2.ScoredPart(mesh_id="msh_0000000000000000")])), "parts[1].mesh_id")
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score(parts=[part], truth=[
            localization_pb2.TruePose(part=0, world_from_part=matrix(skewed))])), "truth[0].world_from_part.matrix")
        nan_pose = IDENTITY[:7] + [math.nan] + IDENTITY[8:]
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score(parts=[part], estimates=[
            localization_pb2.EstimatedPose(part=0, world_from_part=matrix(IDENTITY)),
            localization_pb2.EstimatedPose(part=0, world_from_part=matrix(nan_pose))])),
            "estimates[1].world_from_part.matrix")
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score(parts=[part], estimates=[
            localization_pb2.EstimatedPose(part=2, world_from_part=matrix(IDENTITY))])), "estimates[0].part")
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score(parts=[part], estimates=[
            localization_pb2.EstimatedPose(part=0, world_from_part=matrix(IDENTITY), score=math.nan)])),
            "estimates[0].score")
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score(parts=[part], truth=[
            localization_pb2.TruePose(part=0, world_from_part=matrix(IDENTITY), visible_fraction=-1)])),
            "truth[0].visible_fraction")
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score(parts=[part], estimates=[
            localization_pb2.EstimatedPose(part=0, world_from_part=matrix(IDENTITY))] * 10001)), "estimates")
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score(
            parts=[part], options=localization_pb2.ScoringOptions(add_threshold=0))), "options.add_threshold")
        self.assertCode(invalid, lambda: self.stub.ScorePoses(score(parts=[localization_pb2.ScoredPart(
            mesh_id=self.mesh_id, symmetry=localization_pb2.PartSymmetry(
                continuous=[localization_pb2.ContinuousSymmetry()]))])), "parts[0].symmetry.continuous[0].axis")

    def test_cli_refuses_a_missing_unit_and_a_bad_truth_file(self):
        mesh_file = os.path.join(os.path.dirname(__file__), "..", "..", "data", "parts", "angle_block.STL")
        done = subprocess.run([VSCAN, "--server", self.server.address, "localize", "--cloud", self.cloud, "--mesh",
                               mesh_file, "--out", os.path.join(self.tmp.name, "x.json")],
                              capture_output=True, text=True, timeout=60)
        self.assertEqual(done.returncode, 2, done.stderr)
        self.assertIn("--units", done.stderr)
        bad = os.path.join(self.tmp.name, "bad.gt.json")
        with open(bad, "w") as f:
            json.dump({"objects": [{"mesh_id": self.mesh_id, "world_from_object": {"values": [1, 2, 3]}}]}, f)
        estimates = self.localize_file()
        done = subprocess.run([VSCAN, "--server", self.server.address, "score", "--truth", bad, "--estimates",
                               estimates], capture_output=True, text=True, timeout=60)
        self.assertEqual(done.returncode, 2, done.stderr)
        self.assertIn("objects[0].world_from_object", done.stderr)


    # Two part types in one search.

    def mixed_parts(self):
        return [(self.mesh_id, 1.0, MIXED_BLOCKS), (self.pin_id, self.pin_scale, MIXED_PINS)]

    def assertMixedFound(self, estimates, parts, part_of):
        """Every estimate names a part searched, no part beyond its max_instances; the count per part."""
        per_part = [0, 0]
        for e in estimates:
            self.assertIn(part_of(e), (0, 1))
            per_part[part_of(e)] += 1
        self.assertEqual(len(parts), 2)
        self.assertLessEqual(per_part[0], MIXED_BLOCKS)
        self.assertLessEqual(per_part[1], MIXED_PINS)
        return per_part

    def test_cli_localizes_two_part_types_in_one_call_and_scores_each(self):
        path = os.path.join(self.tmp.name, "mixed.json")
        done = subprocess.run([VSCAN, "--server", self.server.address, "localize", "--cloud", self.mixed_cloud,
                               "--mesh", self.mesh_id, "--mesh", self.pin_id, "--scale", "1",
                               "--scale", str(self.pin_scale), "--max", str(MIXED_BLOCKS), "--max", str(MIXED_PINS),
                               "--progress", "--out", path], capture_output=True, text=True, timeout=300)
        self.assertEqual(done.returncode, 0, done.stderr + done.stdout)
        # stderr is no terminal here: --progress prints a line per stage, ending at 100%.
        progress = [line for line in done.stderr.splitlines() if line.startswith("localizing ")]
        self.assertGreaterEqual(len(progress), 2, done.stderr)
        self.assertIn("100.0%", progress[-1])
        self.assertIn("part 1 " + self.pin_id, done.stdout)
        with open(path) as f:
            found = json.load(f)
        self.assertEqual([(p["mesh_id"], p["scale"], p["max_instances"]) for p in found["parts"]],
                         self.mixed_parts())
        per_part = self.assertMixedFound(found["estimates"], found["parts"], lambda e: e["part"])
        for e in found["estimates"]:
            self.assertEqual(e["mesh_id"], found["parts"][e["part"]]["mesh_id"])
            self.assertEqual(e["scale"], found["parts"][e["part"]]["scale"])
        self.assertEqual([p["found"] for p in found["parts"]], per_part)
        self.assertTrue(all(p["stop_reason"] and p["voxel_size"] > 0 for p in found["parts"]))

        report = json.loads(self.cli("--json", "score", "--truth", self.mixed_truth, "--estimates", path))
        self.assertEqual([p["meshId"] for p in report["parts"]], [self.mesh_id, self.pin_id])
        blocks, pins = report["parts"]
        self.assertEqual(int(blocks["validInstances"]), seen(self.mixed_stats, self.mesh_id))
        self.assertEqual(int(pins["validInstances"]), seen(self.mixed_stats, self.pin_id))
        self.assertGreater(int(pins["validInstances"]), 0)
        self.assertExactMatches(blocks["matches"])

    def test_python_client_localizes_several_parts_with_progress(self):
        updates = []
        with Client(self.server.address) as client:
            with open(self.mixed_truth) as f:
                world_from_sensor = np.array(json.load(f)["world_from_sensor"]).reshape(4, 4)
            cloud_id = client.upload_cloud(self.mixed_cloud, sensor_pose=world_from_sensor).cloud_id
            streamed = client.localize(parts=self.mixed_parts(), cloud_id=cloud_id, progress=updates.append)
            unary = client.localize(parts=self.mixed_parts(), cloud_id=cloud_id)
            client.delete_cloud(cloud_id)
            parts = [(m, s) for m, s, _ in self.mixed_parts()]
            truth = truth_from_objects(self.mixed_stats.objects, parts)
            estimates = [(e.part, e.world_from_part.values, e.score) for e in streamed.estimates]
            score = client.score_poses(parts, truth, estimates)
        self.assertGreaterEqual(len(updates), 2)
        fractions = [u.fraction for u in updates]
        self.assertEqual(fractions, sorted(fractions))
        self.assertEqual(fractions[0], 0.0)
        self.assertLessEqual(fractions[-1], 1.0)
        self.assertTrue(all(u.stage for u in updates))
        self.assertLessEqual(updates[-1].found, len(streamed.estimates))
        # The stream's response is what the unary call answers.
        self.assertEqual([p.found for p in streamed.parts], [p.found for p in unary.parts])
        self.assertEqual([p.part for p in streamed.parts], [0, 1])
        self.assertEqual(streamed.voxel_size, streamed.parts[0].voxel_size)
        self.assertEqual(streamed.stop_reason, streamed.parts[0].stop_reason)
        for a, b in zip(streamed.estimates, unary.estimates):
            self.assertEqual(a.part, b.part)
            np.testing.assert_allclose(a.world_from_part.values, b.world_from_part.values, atol=1e-9)
        per_part = self.assertMixedFound(streamed.estimates, streamed.parts, lambda e: e.part)
        self.assertEqual([p.found for p in streamed.parts], per_part)
        self.assertExactMatches(score.parts[0].matches, error=lambda m: m.add_error,
                                matched=lambda m: m.HasField("estimate_index"))

    def streamed(self, request, timeout=None):
        return self.stub.LocalizeWithProgress(localization_pb2.LocalizeWithProgressRequest(localize=request),
                                              timeout=timeout)

    def big_search(self):
        """Both parts in the first bin's 100,000 points: seconds of work on two cores."""
        request = localization_pb2.LocalizeRequest(parts=[
            localization_pb2.LocalizePart(mesh_id=self.mesh_id, max_instances=20),
            localization_pb2.LocalizePart(mesh_id=self.pin_id, scale=self.pin_scale, max_instances=20)])
        request.points.positions = self.positions[:100000].astype("<f4").tobytes()
        request.options.viewpoint.z = 1
        request.options.min_score = 0.01
        return request

    def test_a_cancelled_stream_stops_its_search_and_the_server_carries_on(self):
        stream = self.streamed(self.big_search())
        first = next(stream)
        self.assertTrue(first.HasField("progress"), first)
        cancelled_at = time.time()
        stream.cancel()
        with self.assertRaises(grpc.RpcError) as ctx:
            for _ in stream:
                pass
        self.assertEqual(ctx.exception.code(), grpc.StatusCode.CANCELLED)
        # The search itself returns CANCELLED (not the answer, thrown away) soon after.
        while not any("LocalizeWithProgress -> " in line and "localization cancelled" in line
                      for line in self.server.log().splitlines()):
            self.assertLess(time.time() - cancelled_at, 30, self.server.log())
            time.sleep(0.1)
        score = self.stub.ScorePoses(localization_pb2.ScorePosesRequest(
            parts=[localization_pb2.ScoredPart(mesh_id=self.mesh_id)]), timeout=10)
        self.assertFalse(score.HasField("add_recall"))

    def test_a_deadline_stops_a_streamed_search(self):
        start = time.time()
        with self.assertRaises(grpc.RpcError) as ctx:
            for _ in self.streamed(self.big_search(), timeout=0.5):
                pass
        self.assertEqual(ctx.exception.code(), grpc.StatusCode.DEADLINE_EXCEEDED)
        self.assertLess(time.time() - start, 5)

    def test_a_reader_that_pauses_still_gets_the_answer_last(self):
        # One message, then nothing read for a while: the server keeps only the latest progress and
        # the stream still ends with the answer.
        request = localization_pb2.LocalizeRequest(parts=[
            localization_pb2.LocalizePart(mesh_id=m, scale=s, max_instances=n) for m, s, n in self.mixed_parts()])
        request.points.positions = self.positions[:50000].astype("<f4").tobytes()
        request.options.viewpoint.z = 1
        stream = self.streamed(request)
        next(stream)
        time.sleep(2)
        rest = list(stream)
        self.assertTrue(rest and rest[-1].HasField("response"), rest[-1:] if rest else rest)
        self.assertTrue(all(m.HasField("progress") for m in rest[:-1]))

    def test_part_refusals_name_their_field(self):
        invalid, not_found = grpc.StatusCode.INVALID_ARGUMENT, grpc.StatusCode.NOT_FOUND
        points = localization_pb2.InlinePoints(positions=np.zeros((1, 3), "<f4").tobytes())

        def request(*parts, **fields):
            return localization_pb2.LocalizeRequest(points=points, parts=list(parts), **fields)

        block = localization_pb2.LocalizePart(mesh_id=self.mesh_id)
        part = localization_pb2.LocalizePart
        cases = [
            (invalid, request(block, mesh_id=self.mesh_id), "parts"),
            (invalid, request(block, scale=2), "scale"),
            (invalid, request(block, part(mesh_id=self.pin_id, scale=math.nan)), "parts[1].scale"),
            (invalid, request(block, part(mesh_id=self.pin_id, scale=-1)), "parts[1].scale"),
            (invalid, request(block, part(mesh_id=self.pin_id, scale=1e19)), "parts[1].scale"),
            (invalid, request(part(mesh_id=self.mesh_id, max_instances=101)), "parts[0].max_instances"),
            (invalid, request(block, part(mesh_id="")), "parts[1].mesh_id"),
            (invalid, request(block, part(mesh_id=self.mesh_id, scale=1)), "parts[1]"),
            (invalid, request(*[part(mesh_id=self.mesh_id, scale=1 + i) for i in range(17)]), "parts"),
            (not_found, request(block, part(mesh_id="msh_0000000000000000")), "parts[1].mesh_id"),
        ]
        for code, bad, field in cases:
            with self.subTest(field=field):
                self.assertCode(code, lambda: self.stub.Localize(bad, timeout=30), field)
                self.assertCode(code, lambda: self.streamed(bad, timeout=30), field)
        with Client(self.server.address) as client:
            with self.assertRaises(ValueError):
                client.localize(self.mesh_id, parts=[self.mesh_id], points=np.zeros((1, 3)))


def seen(stats, mesh_id):
    return sum(1 for o in stats.objects if o.mesh_id == mesh_id and o.visible_fraction >= 0.1)
