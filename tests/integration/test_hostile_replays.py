"""Requests a hostile client sends, replayed with other sizes and values than those first reported:
each answers fast with the documented code naming its field, or ends within its bound, and after
each the server still serves a small scan within two seconds and stays under its memory bound."""

import os
import subprocess
import tempfile
import textwrap
import time
import unittest

import grpc
import numpy as np

from harness import (DATA, SOURCE_DIR, VSCAN, Server, assert_streams_cancelled, small_scan_seconds, status_mib,
                     torus_ply)
from vscan import Client, VscanError, bin_part, part_symmetry, scored_part
from vscan.v1 import job_pb2, job_pb2_grpc

C = grpc.StatusCode
BOUND_MIB = 768
# What vscand holds besides one request: its libraries, the Embree scenes, the catalogue.
BASELINE_MIB = 400
UR5_PLAN = os.path.join(SOURCE_DIR, "examples", "campaigns", "bunny_ur5.yaml")


class HostileReplays(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server(extra_args=["--max-request-memory-mib", str(BOUND_MIB),
                                        "--stalled-reader-seconds", "3"]).start()
        cls.client = Client(cls.server.address, timeout=120)
        cls.tmp = tempfile.TemporaryDirectory()
        cls.scene_id = cls.client.create_scene("small").scene_id
        bunny = cls.client.upload_mesh(os.path.join(DATA, "meshes", "bunny", "bunny_zipper_res2.ply"), unit="m")
        cls.client.add_object(cls.scene_id, bunny.mesh_id)
        # The first scan builds the scene's ray-casting structure; the checks time the ones after.
        small_scan_seconds(cls.client, cls.scene_id)
        cls.block_id = cls.client.upload_mesh(os.path.join(DATA, "parts", "angle_block.STL"), unit="in").mesh_id

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()
        cls.tmp.cleanup()

    def assertStillServing(self):
        seconds, scan = small_scan_seconds(self.client, self.scene_id)
        self.assertLess(seconds, 2.0)
        self.assertGreater(len(scan.positions), 100)
        self.assertLess(status_mib(self.server.process.pid, "VmHWM"), BOUND_MIB + BASELINE_MIB)

    def assertRefused(self, code, call, *needles, within_s=5.0):
        start = time.monotonic()
        with self.assertRaises(VscanError) as err:
            call()
        self.assertLess(time.monotonic() - start, within_s, err.exception.message)
        self.assertEqual(err.exception.code, code, err.exception.message)
        for needle in needles:
            self.assertIn(needle, err.exception.message)
        return err.exception.message

    def test_localize_at_a_voxel_finer_than_its_table_allows(self):
        rng = np.random.default_rng(3)
        points = np.column_stack([rng.uniform(-0.05, 0.05, (3000, 2)), np.full(3000, 0.4)]).astype(np.float32)
        for voxel in (2e-5, 1e-4):
            self.assertRefused(C.RESOURCE_EXHAUSTED, lambda: self.client.localize(
                self.block_id, points=points, voxel_size=voxel, viewpoint=(0, 0, 0)), "options.voxel_size")
        self.assertStillServing()

    def test_score_poses_on_a_part_of_two_hundred_thousand_vertices(self):
        path = os.path.join(self.tmp.name, "dense_torus.ply")
        torus_ply(path, 500, 400)  # 200,000 vertices
        part = self.client.upload_mesh(path, unit="m").mesh_id
        # Nothing to score: no diameter over every vertex pair, an answer at once, twice in a row.
        for _ in range(2):
            start = time.monotonic()
            score = self.client.score_poses([part], [], [(0, np.eye(4), 1.0)], timeout=3)
            self.assertLess(time.monotonic() - start, 3.0)
            self.assertEqual(score.parts[0].estimates, 1)
            self.assertFalse(score.HasField("add_recall"))
        self.assertStillServing()
        # 30 x 30 poses of a part with a symmetry axis: refused up front, or scored within the bound.
        axis = part_symmetry(continuous=[((0, 0, 1), (0, 0, 0))])
        poses = [np.array([[1, 0, 0, 0.3 * k], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float) for k in range(30)]
        start = time.monotonic()
        try:
            self.client.score_poses([scored_part(part, symmetry=axis)], [(0, p, 1.0, k) for k, p in enumerate(poses)],
                                    [(0, p, 1.0) for p in poses], timeout=60)
        except VscanError as err:
            self.assertEqual(err.code, C.RESOURCE_EXHAUSTED, err.message)
            self.assertIn("estimates", err.message)
        self.assertLess(time.monotonic() - start, 30.0)
        self.assertStillServing()
        # 8000 x 8000 poses of a small part: refused before any scoring.
        many = [np.array([[1, 0, 0, 0.01 * k], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float) for k in range(8000)]
        self.assertRefused(C.RESOURCE_EXHAUSTED, lambda: self.client.score_poses(
            [self.block_id], [(0, p, 1.0, k) for k, p in enumerate(many)], [(0, p, 1.0) for p in many], timeout=60),
            "estimates", within_s=10.0)
        self.assertStillServing()

    def test_a_decomposition_past_its_triangle_bound_is_refused_while_others_are_served(self):
        path = os.path.join(self.tmp.name, "torus.ply")
        torus_ply(path, 150, 75)  # 22,500 triangles: past the bound, since the cuts cannot be stopped
        mesh_id = self.client.upload_mesh(path, unit="m").mesh_id
        scene_id = self.client.create_scene("decomposition").scene_id
        for call in (self.client.validate_bin_fill, self.client.start_bin_fill):
            self.assertRefused(C.RESOURCE_EXHAUSTED, lambda: call(
                scene_id, (0.3, 0.3, 0.2), [bin_part(mesh_id, 3, collision="convex_decomposition")]),
                "spec.parts[0].mesh", "this one has 22500", within_s=2.0)
        self.assertStillServing()

    def test_a_plan_of_half_a_million_scenes_is_refused(self):
        plan = os.path.join(self.tmp.name, "huge.yaml")
        with open(plan, "w") as f:
            f.write(textwrap.dedent(f"""\
                name: huge
                bins:
                  - name: blocks
                    bin: {{inner_size: [0.3, 0.2, 0.12], wall_thickness: 0.01}}
                    parts:
                      - {{mesh: {os.path.join(DATA, "parts", "angle_block.STL")}, unit: in, count: 2}}
                seeds: {{first: 1, count: 500000}}
                sensors: [ideal-vga]
                """))
        self.assertRefused(C.RESOURCE_EXHAUSTED, lambda: self.client.validate_dataset(plan),
                           "spec.plan_yaml.seeds", "500000 scenes")
        self.assertStillServing()

    def test_unread_artifact_streams_hold_a_chunk_each_and_are_cancelled(self):
        out = subprocess.run([VSCAN, "--server", self.server.address, "--json", "campaign", "run", UR5_PLAN,
                              "--no-download"], capture_output=True, text=True, timeout=300)
        self.assertEqual(out.returncode, 0, out.stderr)
        job = [j for j in self.client.list_jobs() if j.kind == "campaign"][-1]
        job = self.client.get_job(job.job_id)
        union = next(a for a in job.artifacts if a.name == "aligned.ply")
        self.assertGreater(union.size_bytes, 8 << 20)
        before = status_mib(self.server.process.pid, "VmRSS")
        channels, streams = [], []
        for _ in range(6):
            channel = grpc.insecure_channel(self.server.address, options=[("grpc.use_local_subchannel_pool", 1)])
            stream = job_pb2_grpc.JobServiceStub(channel).ReadArtifact(
                job_pb2.ReadArtifactRequest(job_id=job.job_id, artifact_id=union.artifact_id), timeout=60)
            next(stream)
            channels.append(channel)
            streams.append(stream)
        time.sleep(0.5)
        grown = status_mib(self.server.process.pid, "VmRSS") - before
        self.assertLess(grown, union.size_bytes / 2**20 * 2,
                        f"{grown:.0f} MiB more resident with 6 unread streams of a "
                        f"{union.size_bytes / 2**20:.0f} MiB artifact")
        self.assertStillServing()
        time.sleep(4)  # past --stalled-reader-seconds
        assert_streams_cancelled(self, streams, channels)
        self.assertStillServing()

    def test_messages_name_the_field_and_quote_no_raw_bytes(self):
        header = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n" + b"\0" * 300
        message = self.assertRefused(C.INVALID_ARGUMENT, lambda: self.client.upload_cloud(data=header, format="ply"))
        self.assertNotIn("\0", message)
        self.assertLess(len(message), 400)
        for bad in ("job_\x00\x01", "job_\u2603", "../job_0000000000000000"):
            self.assertRefused(C.INVALID_ARGUMENT, lambda: self.client.get_job(bad), "job_id")
        self.assertStillServing()


if __name__ == "__main__":
    unittest.main()
