"""The web view's jobs and clouds: its API over HTTP while a campaign runs, and the campaign and cloud
pages in headless chromium following a small aligning, reconstructing, evaluating campaign live."""

import json
import math
import os
import shutil
import signal
import socket
import struct
import subprocess
import tempfile
import threading
import time
import unittest

import grpc
import numpy as np

from harness import Server, read_png
from test_campaign_service import TARGET, VIEWPOINTS, CampaignFixture, camera, parse_ply, spec
from web_harness import http_get, need_browser, page_command, web_listen
from vscan.v1 import job_pb2, sensor_pb2

from vscan import Client

TOKEN = "web-campaign-token"
# Some 1.1 m from the UR5's base, beyond its 0.85 m reach: every step there is unreachable.
UNREACHABLE = ((-0.45, 0.0, 0.35), TARGET)
MAX_POINTS = 1500  # per cloud, as the page is asked to thin
ROTATIONS = 3
SCANS = 2 * ROTATIONS  # the two reachable viewpoints at each table angle
# The page's viewpoint colours by outcome (web/job_view.js).
COLOURS = {"reached": (0x00, 0xe0, 0x00), "unreachable": (0xff, 0x00, 0x00), "colliding": (0xff, 0xff, 0x00)}
SCREENSHOT_SIZE = (640, 480)


class _Token(grpc.UnaryUnaryClientInterceptor, grpc.UnaryStreamClientInterceptor, grpc.StreamUnaryClientInterceptor,
             grpc.StreamStreamClientInterceptor):
    """Adds the bearer token to every call of a channel (the campaign fixture's stubs send none)."""

    def _with_token(self, details):
        metadata = list(details.metadata or []) + [("authorization", f"Bearer {TOKEN}")]
        return details._replace(metadata=metadata) if hasattr(details, "_replace") else _Details(details, metadata)

    def intercept_unary_unary(self, continuation, details, request):
        return continuation(self._with_token(details), request)

    def intercept_unary_stream(self, continuation, details, request):
        return continuation(self._with_token(details), request)

    def intercept_stream_unary(self, continuation, details, requests):
        return continuation(self._with_token(details), requests)

    def intercept_stream_stream(self, continuation, details, requests):
        return continuation(self._with_token(details), requests)


class _Details(grpc.ClientCallDetails):
    def __init__(self, details, metadata):
        self.method = details.method
        self.timeout = details.timeout
        self.metadata = metadata
        self.credentials = details.credentials
        self.wait_for_ready = getattr(details, "wait_for_ready", None)
        self.compression = getattr(details, "compression", None)


class _AuthedServer:
    def __init__(self, server):
        self.server = server

    def channel(self):
        return grpc.intercept_channel(self.server.channel(), _Token())


def parse_cloud(body):
    """The API's cloud layout (docs/WEB.md) as (header dict, {field: array})."""
    magic, version, fields, count, total, width, height = struct.unpack("<4sIIIQII", body[:32])
    assert (magic, version) == (b"VSCL", 1), (magic, version)
    at = 32
    arrays = {}

    def take(name, dtype, per_point):
        nonlocal at
        array = np.frombuffer(body, dtype, count * per_point, at)
        at += array.nbytes
        arrays[name] = array.reshape(count, per_point) if per_point > 1 else array

    take("position", "<f4", 3)
    for bit, name, dtype, per in ((1, "normal", "<f4", 3), (2, "range", "<f4", 1), (3, "intensity", "<f4", 1),
                                  (4, "instance", "<u4", 1), (5, "pixel", "<u4", 1), (6, "clean", "<f4", 3),
                                  (7, "incidence", "<f4", 1), (8, "status", "u1", 1), (9, "estimated", "<f4", 3)):
        if fields & (1 << bit):
            take(name, dtype, per)
            if name == "status":
                at += (4 - count % 4) % 4
    assert at == len(body), (at, len(body))
    return {"fields": fields, "count": count, "total": total, "width": width, "height": height}, arrays


class WebCampaignTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-web-campaign-")
        cls.addClassCleanup(cls.tmp.cleanup)
        cls.web_port, cls.web, web_args = web_listen(cls.tmp.name, TOKEN)
        # One job at a time: a job started behind another waits QUEUED, so a page can open on it first.
        cls.server = Server(extra_args=(*web_args, "--max-concurrent-jobs", "1")).start()
        cls.addClassCleanup(cls.server.cleanup)
        cls.fx = CampaignFixture(_AuthedServer(cls.server))
        cls.addClassCleanup(cls.fx.close)
        cls.client = Client(cls.server.address, token=TOKEN, stream_timeout=300)
        cls.addClassCleanup(cls.client.close)

    def get(self, path, token=TOKEN, timeout=10):
        """(status, content type, body) of one request to the web view."""
        return http_get(self.web, path, token, timeout=timeout)

    def blocker(self):
        """A long campaign (180 scans of 640 x 480) that holds the only job slot until cancelled."""
        return self.client.start_campaign(spec=spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=VIEWPOINTS,
                                                    rotations=90, step=4.0, sensor=camera(640, 480), name="blocker"))

    def campaign_spec(self):
        s = spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=VIEWPOINTS + [UNREACHABLE],
                 rotations=ROTATIONS, step=360.0 / ROTATIONS, sensor=camera(640, 480), seed=3, name="web campaign", align=True, reconstruct=True,
                 evaluate=True)
        s.reconstruction.poisson_depth = 6
        s.evaluation.next_best_views = 1
        return s

    def test_api_while_a_job_runs(self):
        blocker = self.blocker()
        queued = self.client.start_campaign(spec=spec(self.fx.scene.scene_id, self.fx.mount, viewpoints=VIEWPOINTS[:1],
                                                      rotations=1, sensor=camera(80, 60), name="queued"))
        stalled = []
        try:
            # Newest first, with their names and progress.
            status, content_type, body = self.get("/api/jobs")
            self.assertEqual((status, content_type), (200, "application/json"))
            jobs = json.loads(body)["jobs"]
            self.assertEqual([j["job_id"] for j in jobs[:2]], [queued.job_id, blocker.job_id])
            self.assertEqual(jobs[0]["name"], "queued")
            self.assertEqual(jobs[0]["kind"], "campaign")
            self.assertEqual(jobs[0]["state"], "QUEUED")
            self.assertEqual(jobs[0]["steps_total"], 1)
            status, _, body = self.get(f"/api/jobs/{queued.job_id}")
            self.assertEqual(status, 200)
            self.assertEqual(json.loads(body)["campaign"]["name"], "queued")
            # The sensor as the page draws its frustum: the pinhole's intrinsics (45 degrees across 80 pixels).
            status, _, body = self.get(f"/api/jobs/{queued.job_id}/sensor")
            self.assertEqual(status, 200, body)
            sensor = json.loads(body)
            self.assertEqual((sensor["camera"]["width"], sensor["camera"]["height"]), (80, 60))
            self.assertAlmostEqual(sensor["camera"]["fx"], 40 / math.tan(math.radians(22.5)), places=6)
            self.assertIsNone(sensor["projector"])
            # A structured-light preset, resolved by the server: the projector beside the camera.
            light = self.client.start_campaign(spec=spec(self.fx.scene.scene_id, self.fx.mount,
                                                         viewpoints=VIEWPOINTS[:1], rotations=1, name="light",
                                                         sensor=sensor_pb2.SensorSpec(preset="phoxi-m-class")))
            self.client.cancel_job(light.job_id)
            status, _, body = self.get(f"/api/jobs/{light.job_id}/sensor")
            self.assertEqual(status, 200, body)
            projector = json.loads(body)["projector"]
            self.assertGreater(projector["horizontal_fov_deg"], 10)
            self.assertGreater(np.linalg.norm(np.array(projector["sensor_from_projector"])[:3, 3]), 0.05)
            for path in ("/api/jobs/job_0000000000000000", "/api/jobs/job_0000000000000000/events",
                         "/api/clouds/cld_0000000000000000", "/api/clouds?job=job_0000000000000000"):
                self.assertEqual(self.get(path)[0], 404, path)
            for query in ("max_points=0", "max_points=5000001", "max_points=x"):
                status, _, body = self.get(f"/api/clouds/cld_0000000000000000?{query}")
                self.assertEqual(status, 400, query)
                self.assertIn(b"max_points", body)
            self.assertEqual(self.get("/api/clouds?job=a%2Fb")[0], 400)

            # A wrong or missing token: 401 and nothing of the jobs, on the events stream too.
            for path in ("/api/jobs", f"/api/jobs/{queued.job_id}", f"/api/jobs/{queued.job_id}/events",
                         "/api/clouds", f"/api/clouds?job={blocker.job_id}"):
                for token in (None, "wrong", ""):
                    status, content_type, body = self.get(path, token)
                    self.assertEqual(status, 401, (path, token))
                    self.assertNotIn(queued.job_id.encode(), body)
                    self.assertNotIn(b"event-stream", (content_type or "").encode())

            # An events stream of a queued job: the snapshot at once, then it stays open.
            events = socket.create_connection(("127.0.0.1", self.web_port))
            events.settimeout(10)
            events.sendall(f"GET /api/jobs/{queued.job_id}/events HTTP/1.1\r\nHost: x\r\n"
                           f"Authorization: Bearer {TOKEN}\r\n\r\n".encode())
            stalled.append(events)
            head = b""
            while b"data: " not in head:
                head += events.recv(65536)
            self.assertIn(b"200 OK", head)
            self.assertIn(b"Content-Type: text/event-stream", head)
            self.assertIn(f'"job_id":"{queued.job_id}"'.encode(), head)
            # Clients that open streams and never read them, beside half-sent requests: whole
            # requests are still answered at once, and the streams beyond the bound are refused.
            for _ in range(6):
                s = socket.create_connection(("127.0.0.1", self.web_port))
                s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
                s.sendall(f"GET /api/jobs/{blocker.job_id}/events HTTP/1.1\r\nHost: x\r\n"
                          f"Authorization: Bearer {TOKEN}\r\n\r\n".encode())
                stalled.append(s)
            for _ in range(4):
                s = socket.create_connection(("127.0.0.1", self.web_port))
                s.sendall(b"GET /api/jobs HTTP/1.1\r\nHost: x\r\n")
                stalled.append(s)
            time.sleep(0.5)
            started = time.time()
            status, _, body = self.get("/api/jobs")
            self.assertEqual(status, 200)
            self.assertIn(blocker.job_id.encode(), body)
            self.assertLess(time.time() - started, 2)
            # Seven streams are open (the first and six stalled): the eighth is served, a ninth is not.
            eighth = socket.create_connection(("127.0.0.1", self.web_port))
            eighth.sendall(f"GET /api/jobs/{blocker.job_id}/events HTTP/1.1\r\nHost: x\r\n"
                           f"Authorization: Bearer {TOKEN}\r\n\r\n".encode())
            stalled.append(eighth)
            eighth.settimeout(10)
            self.assertIn(b"200 OK", eighth.recv(4096))
            status, _, body = self.get(f"/api/jobs/{blocker.job_id}/events")
            self.assertEqual(status, 503, body)
            self.assertEqual(self.client.get_job(queued.job_id).job_id, queued.job_id)  # gRPC answers too
        finally:
            for s in stalled:
                s.close()
            self.client.cancel_job(blocker.job_id)
            self.client.cancel_job(queued.job_id)
            self.client.wait_job(blocker.job_id, timeout=120)
            self.client.wait_job(queued.job_id, timeout=120)
        # The streams went with their clients: new ones are served again.
        deadline = time.time() + 15
        while time.time() < deadline:
            status, _, body = self.get(f"/api/jobs/{queued.job_id}/events")
            if status == 200:
                break
            time.sleep(0.2)
        self.assertEqual(status, 200)
        # An ended job's stream: the snapshot, then the end.
        self.assertTrue(body.startswith(b"data: {\"job\":"), body[:100])
        self.assertTrue(body.endswith(b"event: end\ndata: {}\n\n"), body[-100:])
        self.assertIn(b"JOB_STATE_CANCELLED", body)

    # In a browser.

    def open_page(self, url, mode, on_ready=None):
        need_browser(self)
        shot = os.path.join(self.tmp.name, f"{mode}.png")
        page = subprocess.Popen(page_command("campaign_page.js", url, shot, "x".join(map(str, SCREENSHOT_SIZE)), mode),
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        timer = threading.Timer(240, page.kill)
        timer.start()
        try:
            lines = []
            for line in page.stdout:
                lines.append(line)
                if line.strip() == "READY" and on_ready:
                    on_ready()
            stderr = page.stderr.read()
            page.wait()
        finally:
            timer.cancel()
            page.stdout.close()
            page.stderr.close()
        self.assertEqual(page.returncode, 0, "".join(lines) + stderr)
        seen = json.loads(lines[-1])
        with open(shot, "rb") as f:
            return seen, read_png(f.read()), shot

    def page_url(self, query):
        return f"http://{self.web}/?{query}#token={TOKEN}"

    def test_browser_follows_a_campaign_as_it_runs(self):
        blocker = self.blocker()
        job = self.client.start_campaign(spec=self.campaign_spec())
        # The page opens on the queued campaign; once it is drawn the blocker goes and the campaign runs.
        seen, image, shot = self.open_page(self.page_url(f"job={job.job_id}&max_points={MAX_POINTS}"), "job",
                                           on_ready=lambda: self.client.cancel_job(blocker.job_id))
        done = self.client.wait_job(job.job_id, timeout=120)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        if os.environ.get("VSCAN_WEB_SCREENSHOT"):
            shutil.copyfile(shot, os.environ["VSCAN_WEB_SCREENSHOT"])
        if os.environ.get("VSCAN_WEB_CAMPAIGN_DUMP"):
            with open(os.environ["VSCAN_WEB_CAMPAIGN_DUMP"], "w") as f:
                json.dump(seen, f, indent=1)
        self.assertEqual(seen["consoleErrors"], [])
        self.assertEqual(seen["errorText"], "")
        origin = f"http://{self.web}/"
        self.assertEqual([r for r in seen["requests"] if not r.startswith(origin)], [])
        self.assertIn(f"{origin}api/jobs/{job.job_id}/events", seen["requests"])
        view = seen["view"]
        self.assertTrue(view["ended"])
        self.assertEqual(view["state"], "SUCCEEDED")

        # What the job stored: the scans as clouds, the reports.
        status, _, body = self.get(f"/api/clouds?job={job.job_id}")
        self.assertEqual(status, 200)
        clouds = json.loads(body)["clouds"]
        captured = [a for a in done.artifacts if a.name.startswith("scan-")]
        self.assertEqual(len(clouds), SCANS)
        self.assertEqual(sorted(c["name"] for c in clouds), sorted(a.name for a in captured))
        report = self.client.model_report(job.job_id)
        aligned = report["alignment"]["aligned"]
        self.assertGreater(aligned, 0)

        # Each scan came in as the campaign captured it: the page's record of what it showed, and
        # the samples taken from outside, grow scan by scan.
        history = view["history"]
        scans_seen = [h["scans"] for h in history]
        self.assertEqual(sorted(set(scans_seen)), list(range(0, SCANS + 1)) if 0 in scans_seen else list(range(1, SCANS + 1)))
        self.assertEqual(scans_seen, sorted(scans_seen))
        shown = [h["shown"] for h in history]
        self.assertEqual(shown, sorted(shown))
        growth = [h["shown"] for h in history if h["scans"] > 0]
        self.assertGreaterEqual(len(set(growth)), SCANS)
        aligned_seen = [h["aligned"] for h in history]
        self.assertEqual(aligned_seen, sorted(aligned_seen))
        self.assertEqual(max(aligned_seen), aligned)
        samples = seen["samples"]
        self.assertEqual([s["shown"] for s in samples], sorted(s["shown"] for s in samples))
        # Sampled while it ran: the page showed at least two partial states before the last.
        partial = {s["shown"] for s in samples if 0 < s["scans"] < SCANS}
        self.assertGreaterEqual(len(partial), 2, samples)
        self.assertEqual(samples[-1]["scans"], SCANS)

        # The final count is every stored cloud thinned to the bound.
        thinned = sum(min(c["points"], MAX_POINTS) for c in clouds)
        self.assertEqual(view["points"]["scans"] + view["points"]["aligned"], thinned)
        self.assertTrue(any(c["points"] > MAX_POINTS for c in clouds), [c["points"] for c in clouds])
        self.assertEqual(view["scans_shown"], SCANS)
        self.assertEqual(view["aligned_shown"], aligned)
        self.assertGreater(view["union_points"], 0)

        # The arm drawn where it stood for the last scan the page added.
        last = max(captured, key=lambda a: (a.scan.rotation_index, a.scan.viewpoint_index))
        self.assertEqual(view["robot"]["mount_id"], self.fx.mount)
        np.testing.assert_allclose(view["robot"]["joints"], list(last.scan.achieved_joint_positions), atol=1e-12)
        # The camera's field (a pinhole: no projector) drawn at that scan's pose.
        record = next(c for c in clouds if c["name"] == last.name)
        np.testing.assert_allclose(np.array(view["sensor_field"]["world_from_sensor"]).reshape(4, 4),
                                   np.array(record["world_from_sensor"]), atol=1e-5)
        self.assertEqual(view["sensor_field"]["lines"], 1)

        # Viewpoints coloured by outcome, where the page says it drew them.
        outcomes = [v["outcome"] for v in view["viewpoints"]]
        self.assertEqual(outcomes, ["reached", "reached", "unreachable"])
        for viewpoint in view["viewpoints"]:
            x, y = viewpoint["pixel"]
            self.assertTrue(0 <= x < SCREENSHOT_SIZE[0] and 0 <= y < SCREENSHOT_SIZE[1], viewpoint)
            expected = np.array(COLOURS[viewpoint["outcome"]])
            self.assertEqual(viewpoint["colour"], list(expected))
            patch = image[y - 1:y + 2, x - 1:x + 2].reshape(-1, 3).astype(int)
            self.assertLess(np.abs(patch - expected).max(axis=1).min(), 30, (viewpoint, patch.tolist()))

        # The mesh, the verdict and the uncovered surface (magenta) from model.json's evaluation.
        evaluation = report["evaluation"]
        self.assertAlmostEqual(view["coverage"], evaluation["coverage"])
        self.check_mesh(job.job_id, done, view)
        self.assertGreater(view["points"]["uncovered"], 0)
        magenta = (np.abs(image.astype(int) - (255, 0, 255)).max(axis=2) < 40).sum()
        self.assertGreater(magenta, 10)
        self.assertIn("coverage", seen["text"])
        # The next best views, clicked: each tells what it adds.
        views = evaluation["next_best_views"]
        self.assertEqual(len(view["next_best_views"]), len(views))
        for pick, expected in zip(seen["picks"], views):
            self.assertEqual(pick["picked"]["coverage_gain"], expected["coverage_gain"])
            self.assertEqual(pick["picked"]["coverage_after"], expected["coverage_after"])
            self.assertIn("coverage after", pick["panel"])

        # A scan in the cloud view: drawn by instance, and a click on a point reports its fields.
        scan = clouds[0]
        self.check_cloud_page(job.job_id, scan, [a for a in captured if a.name == scan["name"]][0])
        self.check_model_page(job.job_id)

        # The index page lists the jobs, newest first, each a link to its view.
        seen, _, _ = self.open_page(f"http://{self.web}/#token={TOKEN}", "index")
        self.assertEqual(seen["consoleErrors"], [])
        self.assertIn(f"web campaign (campaign, SUCCEEDED, {done.steps_done} of {done.steps_total} steps, {job.job_id})",
                      seen["text"])
        self.assertLess(seen["text"].index("web model"), seen["text"].index("web campaign"))

    def check_mesh(self, job_id, job, view):
        """The page drew mesh.ply whole: its triangles and bounds are those of the file."""
        [mesh] = [a for a in job.artifacts if a.name == "mesh.ply"]
        status, _, ply = self.get(f"/api/jobs/{job_id}/artifacts/{mesh.artifact_id}")
        self.assertEqual(status, 200)
        end = ply.index(b"end_header\n") + len(b"end_header\n")
        header = ply[:end].decode()
        vertices = int(header.split("element vertex ")[1].split()[0])
        faces = int(header.split("element face ")[1].split()[0])
        rows = np.frombuffer(ply, np.dtype([("one", "u1"), ("x", "<f4"), ("y", "<f4"), ("z", "<f4")]), vertices, end)
        xyz = np.c_[rows["x"], rows["y"], rows["z"]]
        self.assertEqual(view["mesh_triangles"], faces)
        np.testing.assert_allclose(view["mesh_bounds"], [xyz.min(axis=0), xyz.max(axis=0)], atol=1e-6)

    def check_model_page(self, campaign_job_id):
        """A model job on the campaign's scans: its aligned clouds and mesh, in the same view."""
        model = self.client.start_model(campaign_job_id=campaign_job_id, reconstruct=True, poisson_depth=6,
                                        name="web model")
        done = self.client.wait_job(model.job_id, timeout=120)
        self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
        report = self.client.model_report(model.job_id)
        seen, _, _ = self.open_page(self.page_url(f"job={model.job_id}&max_points={MAX_POINTS}"), "job")
        self.assertEqual(seen["consoleErrors"], [])
        view = seen["view"]
        self.assertEqual(view["kind"], "model")
        self.assertTrue(view["ended"])
        # An ended job: its events are gone, so the scans and their poses come from model.json.
        self.check_mesh(model.job_id, done, view)
        self.assertEqual(view["aligned_shown"], report["alignment"]["aligned"])
        self.assertEqual(view["points"]["union"], 0)
        clouds = {c["cloud_id"]: c for c in json.loads(self.get(f"/api/clouds?job={campaign_job_id}")[2])["clouds"]}
        self.assertEqual(view["points"]["aligned"], sum(min(clouds[s["cloud_id"]]["points"], MAX_POINTS)
                                                        for s in report["alignment"]["scans"] if s["aligned"]))

    def check_cloud_page(self, job_id, cloud, artifact):
        seen, image, shot = self.open_page(self.page_url(f"cloud={cloud['cloud_id']}&max_points={MAX_POINTS}"), "cloud")
        # Set VSCAN_WEB_CLOUD_SCREENSHOT to keep the picture (docs/images/web_cloud.png is made so).
        if os.environ.get("VSCAN_WEB_CLOUD_SCREENSHOT"):
            shutil.copyfile(shot, os.environ["VSCAN_WEB_CLOUD_SCREENSHOT"])
        self.assertEqual(seen["consoleErrors"], [])
        view = seen["view"]
        self.assertEqual(view["shown_points"], min(cloud["points"], MAX_POINTS))
        self.assertEqual(view["total_points"], cloud["points"])
        self.assertEqual(view["coloured_by"], "instance")
        # The stored scan, read as its PLY artifact: the page's points are its points i * total // shown.
        status, content_type, ply = self.get(f"/api/jobs/{job_id}/artifacts/{artifact.artifact_id}")
        self.assertEqual((status, content_type), (200, "model/ply"))
        positions, _ = parse_ply(ply)
        end = ply.index(b"end_header\n") + len(b"end_header\n")
        header = ply[:end].decode().splitlines()
        types = {"float": "<f4", "uint": "<u4", "int": "<i4", "uchar": "u1"}
        dtype = np.dtype([(line.split()[2], types[line.split()[1]]) for line in header if line.startswith("property")])
        rows = np.frombuffer(ply[end:], dtype=dtype, count=len(positions))
        shown, total = view["shown_points"], view["total_points"]
        status, _, body = self.get(f"/api/clouds/{cloud['cloud_id']}?max_points={MAX_POINTS}")
        header_fields, arrays = parse_cloud(body)
        kept = np.arange(shown, dtype=np.int64) * total // shown
        np.testing.assert_array_equal(arrays["position"], positions[kept].astype(np.float32))
        np.testing.assert_array_equal(arrays["range"], rows["range"][kept])
        np.testing.assert_array_equal(arrays["instance"], rows["instance"][kept].astype(np.uint32))
        picked = [p for p in seen["picks"] if p["picked"]]
        self.assertGreaterEqual(len(picked), len(view["samples"]) // 2, seen["picks"])
        for pick in picked:
            p = pick["picked"]
            i = p["index"]
            self.assertEqual(p["cloud_id"], cloud["cloud_id"])
            # The point picked is a point drawn under the click, with the stored point's fields.
            self.assertAlmostEqual(p["range"], float(rows["range"][kept[i]]), places=3)
            self.assertAlmostEqual(p["intensity"], float(rows["intensity"][kept[i]]), places=3)
            self.assertEqual(p["instance_id"], int(rows["instance"][kept[i]]))
            np.testing.assert_allclose(p["position"], positions[kept[i]], atol=1e-3)
            self.assertIn(f"range: {p['range']} m", pick["panel"])
            self.assertIn(f"instance: {p['instance_id']}", pick["panel"])
        self.assertIsNone(seen["picks"][-1]["picked"])


class WebStopTest(unittest.TestCase):
    """vscand stopping while a page follows a running job: the stream ends at once, not with the job."""

    def test_stop_ends_the_streams_without_waiting_for_the_job(self):
        with tempfile.TemporaryDirectory(prefix="vscan-web-stop-") as tmp:
            port, _, web_args = web_listen(tmp, TOKEN)
            server = Server(extra_args=(*web_args, "--grace-seconds", "1")).start()
            self.addCleanup(server.cleanup)
            fx = CampaignFixture(_AuthedServer(server))
            self.addCleanup(fx.close)
            with Client(server.address, token=TOKEN) as client:
                # Some 180 scans of 640 x 480: it runs far longer than the test.
                job = client.start_campaign(spec=spec(fx.scene.scene_id, fx.mount, viewpoints=VIEWPOINTS,
                                                      rotations=90, step=4.0, sensor=camera(640, 480)))
                with socket.create_connection(("127.0.0.1", port)) as events:
                    events.settimeout(10)
                    events.sendall(f"GET /api/jobs/{job.job_id}/events HTTP/1.1\r\nHost: x\r\n"
                                   f"Authorization: Bearer {TOKEN}\r\n\r\n".encode())
                    received = b""
                    while b"JOB_STATE_RUNNING" not in received:
                        chunk = events.recv(65536)
                        self.assertTrue(chunk, received)
                        received += chunk
                    server.process.send_signal(signal.SIGTERM)
                    stopped = time.time()
                    while True:
                        chunk = events.recv(65536)
                        if not chunk:
                            break
                        received += chunk
                    closed_after = time.time() - stopped
                self.assertEqual(server.process.wait(timeout=60), 0)
            # The stream closed at once (the job still ran; it ends INTERRUPTED as vscand stops), and
            # without the end event, which is for jobs that end.
            self.assertLess(closed_after, 3)
            self.assertNotIn(b"event: end", received)
            self.assertIn("INTERRUPTED", server.log())


if __name__ == "__main__":
    unittest.main()
