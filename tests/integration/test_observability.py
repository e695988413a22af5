"""vscand's metrics endpoint and JSON logs: counters and histograms move by what the calls did, and
every log line of a call carries the request id its client sent."""

import json
import os
import re
import socket
import subprocess
import tempfile
import unittest
import urllib.request

import grpc

from harness import SOURCE_DIR, VSCAN, ServerTestCase, icosphere_ply, look_at, pinhole, cli_result
from vscan.v1 import common_pb2, scan_pb2, scan_pb2_grpc, scene_pb2, scene_pb2_grpc

SCAN = "/vscan.v1.ScanService/Scan"
GET_SCENE = "/vscan.v1.SceneService/GetScene"
QUICK_PLAN = os.path.join(SOURCE_DIR, "examples", "campaigns", "bunny_panda_quick.yaml")
SAMPLE = re.compile(r'^([a-zA-Z_:][a-zA-Z0-9_:]*)(?:\{(.*)\})? (\S+)$')
LABEL = re.compile(r'([a-zA-Z_][a-zA-Z0-9_]*)="((?:[^"\\]|\\.)*)"')


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def parse_metrics(text):
    """{(name, frozenset of (label, value)): value} and the TYPE of each family."""
    samples, types = {}, {}
    for line in text.splitlines():
        if line.startswith("# TYPE "):
            _, _, name, kind = line.split(" ")
            types[name] = kind
            continue
        if not line or line.startswith("#"):
            continue
        match = SAMPLE.match(line)
        assert match, f"not a sample line: {line!r}"
        name, labels, value = match.groups()
        key = (name, frozenset(LABEL.findall(labels or "")))
        assert key not in samples, f"repeated series: {line!r}"
        samples[key] = float(value)
    return samples, types


def value(samples, name, **labels):
    return samples.get((name, frozenset(labels.items())), 0.0)


class ObservabilityTest(ServerTestCase):
    @classmethod
    def setUpClass(cls):
        cls.metrics_port = free_port()
        cls.server_args = ("--metrics-listen", f"127.0.0.1:{cls.metrics_port}", "--log-format", "json")
        super().setUpClass()

    def scrape(self):
        with urllib.request.urlopen(f"http://127.0.0.1:{self.metrics_port}/metrics", timeout=10) as response:
            self.assertEqual(response.status, 200)
            self.assertTrue(response.headers["Content-Type"].startswith("text/plain; version=0.0.4"))
            return parse_metrics(response.read().decode())

    def test_metrics_and_logs_follow_the_calls(self):
        before, types = self.scrape()
        self.assertEqual(types["vscan_grpc_call_duration_seconds"], "histogram")
        self.assertEqual(types["vscan_scans_total"], "counter")
        self.assertEqual(types["vscan_jobs"], "gauge")

        # A scene with a sphere, each call with its own request id, which comes back in the headers.
        scene, call = self.scenes.CreateScene.with_call(scene_pb2.CreateSceneRequest(name="observed"),
                                                        metadata=[("x-request-id", "obs-create-1")])
        self.assertIn(("x-request-id", "obs-create-1"), call.initial_metadata())
        ply = icosphere_ply(0.1, (0, 0, 0), 2)

        def upload():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                name="sphere.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(ply)))
            yield scene_pb2.UploadMeshRequest(chunk=ply)
        mesh = self.scenes.UploadMesh(upload(), timeout=60, metadata=[("x-request-id", "obs-upload-1")]).mesh
        self.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene.scene_id, mesh_id=mesh.mesh_id))

        # One streamed scan of 160 x 120 rays.
        stream = self.scans.Scan(scan_pb2.ScanRequest(scene_id=scene.scene.scene_id, sensor=pinhole(),
                                                      pose=look_at((0.5, 0, 0), (0, 0, 0))),
                                 timeout=60, metadata=[("x-request-id", "obs-scan-1")])
        messages = list(stream)
        self.assertIn(("x-request-id", "obs-scan-1"), stream.initial_metadata())
        stats = [m.statistics for m in messages if m.HasField("statistics")][-1]
        self.assertEqual(stats.rays, 160 * 120)
        self.assertGreater(stats.streamed_points, 1000)

        # A bad argument, and a call whose id is not usable as given (it gets a fresh one).
        with self.assertRaises(grpc.RpcError) as bad:
            self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=""), metadata=[("x-request-id", "obs-bad-1")])
        self.assertEqual(bad.exception.code(), grpc.StatusCode.INVALID_ARGUMENT)
        self.assertIn(("x-request-id", "obs-bad-1"), bad.exception.initial_metadata())
        _, call = self.scenes.ListMeshes.with_call(scene_pb2.ListMeshesRequest(),
                                                   metadata=[("x-request-id", "has spaces \"and\" quotes")])
        fresh = dict(call.initial_metadata())["x-request-id"]
        self.assertRegex(fresh, r"^[0-9a-f]{16}$")

        after, _ = self.scrape()

        def moved(name, **labels):
            return value(after, name, **labels) - value(before, name, **labels)

        self.assertEqual(moved("vscan_grpc_calls_total", method=SCAN, code="OK"), 1)
        self.assertEqual(moved("vscan_grpc_calls_total", method=GET_SCENE, code="INVALID_ARGUMENT"), 1)
        self.assertEqual(moved("vscan_grpc_errors_total", method=GET_SCENE, code="INVALID_ARGUMENT"), 1)
        self.assertEqual(moved("vscan_grpc_errors_total", method=SCAN, code="OK"), 0)
        self.assertEqual(moved("vscan_grpc_calls_total", method="/vscan.v1.SceneService/CreateScene", code="OK"), 1)
        self.assertEqual(moved("vscan_grpc_call_duration_seconds_count", method=SCAN), 1)
        self.assertEqual(moved("vscan_scans_total", backend="raycast", result="ok"), 1)
        self.assertEqual(moved("vscan_scan_rays_total"), stats.rays)
        self.assertEqual(moved("vscan_scan_points_sent_total"), stats.streamed_points)
        self.assertEqual(moved("vscan_scan_rays_per_second_count"), 1)
        self.assertEqual(moved("vscan_scan_duration_seconds_count", backend="raycast"), 1)
        # The server's own health checks, four a second on an in-process channel, are left out.
        self.assertEqual(value(after, "vscan_grpc_calls_total", method="/grpc.health.v1.Health/Check", code="OK"), 0)

        # The duration histogram of Scan: cumulative buckets ending in +Inf = _count, and a positive sum.
        buckets = sorted(((float(dict(labels)["le"]), v) for (name, labels), v in after.items()
                          if name == "vscan_grpc_call_duration_seconds_bucket" and ("method", SCAN) in labels))
        counts = [v for _, v in buckets]
        self.assertEqual(counts, sorted(counts))
        self.assertEqual(buckets[-1][0], float("inf"))
        self.assertEqual(buckets[-1][1], value(after, "vscan_grpc_call_duration_seconds_count", method=SCAN))
        self.assertGreater(value(after, "vscan_grpc_call_duration_seconds_sum", method=SCAN), 0)

        # Every line of the log is one JSON object; the calls' lines carry their ids.
        self.assertEqual(self.server.stop(), 0)
        with open(self.server.log_path) as f:
            lines = [json.loads(line) for line in f if line.strip()]
        for line in lines:
            self.assertTrue({"time", "level", "logger", "message"} <= line.keys(), line)
        by_id = {}
        for line in lines:
            by_id.setdefault(line.get("request_id"), []).append(line)
        scan_lines = by_id.get("obs-scan-1", [])
        self.assertTrue(any(line["message"].startswith("scan of ") and f"{stats.rays} rays" in line["message"]
                            for line in scan_lines), scan_lines)
        self.assertTrue(any(line.get("method") == SCAN and line.get("code") == "OK" and line["duration_ms"] > 0
                            for line in scan_lines), scan_lines)
        bad_lines = by_id.get("obs-bad-1", [])
        self.assertTrue(any("INVALID_ARGUMENT" in line["message"] or line.get("code") == "INVALID_ARGUMENT"
                            for line in bad_lines), bad_lines)
        self.assertTrue(any(line.get("method") == "/vscan.v1.SceneService/UploadMesh"
                            for line in by_id.get("obs-upload-1", [])))
        self.assertIn(fresh, by_id)
        self.assertNotIn("has spaces \"and\" quotes", by_id)


    def test_job_gauge_and_ended_counts_follow_campaigns(self):
        before, _ = self.scrape()
        with tempfile.TemporaryDirectory() as tmp:
            done = self.cli("--json", "campaign", "run", QUICK_PLAN, "-o", os.path.join(tmp, "quick"))
            self.assertEqual(done.returncode, 0, done.stderr + self.server.log())
            # A long campaign: many table angles at a larger image, cancelled while it runs.
            with open(QUICK_PLAN) as f:
                text = f.read().replace("../../", SOURCE_DIR + "/")
            text = text.replace("rotations: 3", "rotations: 200").replace("width: 320, height: 240",
                                                                         "width: 1280, height: 960")
            plan = os.path.join(tmp, "long.yaml")
            with open(plan, "w") as f:
                f.write(text)
            started = self.cli("--json", "campaign", "run", plan, "--detach")
            self.assertEqual(started.returncode, 0, started.stderr + self.server.log())
            job_id = cli_result(started.stdout)["job"]["jobId"]
            running, _ = self.scrape()
            self.assertEqual(value(running, "vscan_jobs", kind="campaign", state="running"), 1)
            self.assertEqual(self.cli("campaign", "cancel", job_id).returncode, 0)
            self.assertNotEqual(self.cli("campaign", "watch", job_id).returncode, 0)  # it ended cancelled
        after, _ = self.scrape()
        self.assertEqual(value(after, "vscan_jobs", kind="campaign", state="running"), 0)
        for state, moved in (("succeeded", 1), ("cancelled", 1), ("failed", 0)):
            self.assertEqual(value(after, "vscan_jobs_ended_total", kind="campaign", state=state) -
                             value(before, "vscan_jobs_ended_total", kind="campaign", state=state), moved, state)
        # The quick campaign's six steps count as scans, beside those of the cancelled one.
        self.assertGreaterEqual(value(after, "vscan_scans_total", backend="raycast", result="ok") -
                                value(before, "vscan_scans_total", backend="raycast", result="ok"), 6)

    def cli(self, *args):
        return subprocess.run([VSCAN, "--server", self.server.address, *args], capture_output=True, text=True,
                              timeout=300)

if __name__ == "__main__":
    unittest.main()
