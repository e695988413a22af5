"""A bin fill in the web view (?bin=JOB_ID): /api/bins over HTTP, the replay it recorded, and the page
in headless chromium (the pile in its instance colours, picking, the replay's first and last frames)."""

import json
import os
import shutil
import struct
import subprocess
import time
import unittest

import numpy as np

from harness import SOURCE_DIR, VSCAN, read_png
from web_harness import BACKGROUND, WebServerTestCase, http_get, need_browser, run_page
from vscan.v1 import job_pb2

from vscan import Client, bin_part

TOKEN = "web-bins-token"
PARTS = 4
INNER_SIZE = (0.30, 0.20, 0.06)


def decode_replay(data):
    """bin_replay.bin as (interval, [(type, instance)], times, poses[frame, part, 7])."""
    magic, version, parts, frames, interval, reserved = struct.unpack_from("<4sIIIfI", data)
    assert (magic, version, reserved) == (b"VSBR", 1, 0), (magic, version, reserved)
    assert len(data) == 24 + 8 * parts + frames * (4 + 28 * parts), len(data)
    table = np.frombuffer(data, "<u4", 2 * parts, 24).reshape(-1, 2)
    rows = np.frombuffer(data, "<f4", frames * (1 + 7 * parts), 24 + 8 * parts).reshape(frames, 1 + 7 * parts)
    return interval, [tuple(int(v) for v in row) for row in table], rows[:, 0], rows[:, 1:].reshape(frames, parts, 7)


def rotate(q, v):
    """v turned by the unit quaternion q = (x, y, z, w)."""
    u, w = np.asarray(q[:3], float), float(q[3])
    return v + 2 * w * np.cross(u, v) + 2 * np.cross(u, np.cross(u, v))


class WebBinsTest(WebServerTestCase):
    token = TOKEN

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.client = Client(cls.server.address, token=TOKEN, stream_timeout=120)
        c = cls.client
        cls.scene = c.create_scene("web bins")
        cls.block = c.upload_mesh(os.path.join(SOURCE_DIR, "data", "parts", "angle_block.STL"), unit="in")
        # One job at a time (--max-concurrent-jobs 1): a long fill runs while a second waits and is
        # cancelled before it runs, so that it ends with no replay (as fills from before the replay).
        blocker = c.start_bin_fill(cls.scene.scene_id, (0.3, 0.2, 0.15), [bin_part(cls.block.mesh_id, 60)], seed=1,
                                   max_simulated_s=300, name="blocker")
        deadline = time.time() + 60
        while "simulated" not in c.get_job(blocker.job_id).message:  # running, past its first second
            if time.time() > deadline:
                raise RuntimeError(f"the first fill did not start: {cls.server.log()}")
            time.sleep(0.1)
        queued = c.start_bin_fill(cls.scene.scene_id, (0.3, 0.2, 0.15), [bin_part(cls.block.mesh_id, 2)], seed=2,
                                  name="never run")
        c.cancel_job(queued.job_id)
        cls.unrun = c.wait_job(queued.job_id, timeout=60)
        c.cancel_job(blocker.job_id)
        cls.cancelled = c.wait_job(blocker.job_id, timeout=120)
        # The fill the page shows: a few blocks in a wide, shallow bin, a short simulation.
        job, cls.report = c.bin_fill(cls.scene.scene_id, INNER_SIZE, [bin_part(cls.block.mesh_id, PARTS)], seed=3,
                                     max_simulated_s=8, name="web pile", timeout=120)
        cls.job = job

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        super().tearDownClass()

    def get(self, path, token=TOKEN):
        return http_get(self.web, path, token)

    def replay(self):
        status, content_type, body = self.get(f"/api/bins/{self.job.job_id}/replay")
        self.assertEqual((status, content_type), (200, "application/octet-stream"))
        return decode_replay(body)

    def test_the_fills_ended_as_planned(self):
        self.assertEqual(self.job.state, job_pb2.JOB_STATE_SUCCEEDED, self.job.message)
        self.assertEqual(self.report["in_bin"], PARTS)
        self.assertEqual(self.unrun.state, job_pb2.JOB_STATE_CANCELLED)
        self.assertEqual(self.cancelled.state, job_pb2.JOB_STATE_CANCELLED)
        names = [a.name for a in self.job.artifacts]
        self.assertIn("bin_replay.bin", names)
        self.assertIn("bin.json", names)
        self.assertEqual([a.name for a in self.unrun.artifacts], [])

    def test_api_needs_the_token(self):
        for path in (f"/api/bins/{self.job.job_id}", f"/api/bins/{self.job.job_id}/replay"):
            for token in (None, "wrong", ""):
                status, _, body = self.get(path, token)
                self.assertEqual(status, 401, (path, token))
                self.assertNotIn(self.job.job_id.encode(), body)
                self.assertNotIn(b"VSBR", body)

    def test_the_bin_json_names_every_part_with_its_object(self):
        status, content_type, body = self.get(f"/api/bins/{self.job.job_id}")
        self.assertEqual((status, content_type), (200, "application/json"))
        bin = json.loads(body)
        self.assertEqual((bin["job_id"], bin["state"], bin["name"]), (self.job.job_id, "SUCCEEDED", "web pile"))
        self.assertTrue(bin["replay"])
        self.assertEqual(bin["scene_id"], self.scene.scene_id)
        self.assertEqual(bin["bin"]["kind"], "box")
        np.testing.assert_allclose(bin["bin"]["inner_size"], INNER_SIZE)
        self.assertEqual(len(bin["parts"]), PARTS)
        objects = {o.object_id: o for o in self.client.get_scene(self.scene.scene_id).objects}
        for part, reported in zip(bin["parts"], self.report["parts"]):
            self.assertEqual(part["object_id"], reported["object_id"])
            self.assertEqual(part["instance_id"], objects[part["object_id"]].instance_id)
            self.assertEqual((part["name"], part["mesh_id"], part["scale"]),
                             (reported["name"], self.block.mesh_id, 1))
            np.testing.assert_allclose(np.array(part["world_from_part"]).ravel(), reported["world_from_part"])
        self.assertEqual(bin["types"][0]["mesh_id"], self.block.mesh_id)

        # A job that never ran has no bin.json and no replay; unknown ids and other paths are 404.
        status, _, body = self.get(f"/api/bins/{self.unrun.job_id}")
        self.assertEqual(status, 200)
        unrun = json.loads(body)
        self.assertEqual((unrun["state"], unrun["report"], unrun["replay"], unrun["parts"]),
                         ("CANCELLED", False, False, []))
        status, _, body = self.get(f"/api/bins/{self.unrun.job_id}/replay")
        self.assertEqual(status, 404)
        self.assertIn(b"recorded no replay", body)
        for path in ("/api/bins/job_0000000000000000", "/api/bins/job_0000000000000000/replay", "/api/bins",
                     f"/api/bins/{self.job.job_id}/other", "/api/bins/a%2Fb"):
            self.assertEqual(self.get(path)[0], 404, path)

    def test_the_replay_drops_the_parts_from_above_to_the_pile_of_bin_json(self):
        interval, parts, times, poses = self.replay()
        self.assertAlmostEqual(interval, 1 / 30, places=6)
        self.assertEqual(sorted(parts), [(0, i) for i in range(PARTS)])
        self.assertEqual(times[0], 0)
        np.testing.assert_allclose(np.diff(times[:-1]), 1 / 30, atol=1e-5)
        self.assertAlmostEqual(float(times[-1]), self.report["simulated_s"], places=4)
        # The last frame is bin.json's pile (the mesh frame of each part, float32).
        index = {key: i for i, key in enumerate(parts)}
        for reported in self.report["parts"]:
            pose = poses[-1, index[(reported["type"], reported["instance"])]]
            matrix = np.array(reported["world_from_part"]).reshape(4, 4)
            np.testing.assert_allclose(pose[:3], matrix[:3, 3], atol=1e-6)
            np.testing.assert_allclose(rotate(pose[3:], np.array([1.0, 0, 0])), matrix[:3, 0], atol=1e-5)
        # The first frame has the first drop in the air above the rim; each part ends lower.
        dropped = [i for i in range(len(parts)) if not np.isnan(poses[0, i, 0])]
        self.assertGreaterEqual(len(dropped), 1)
        self.assertTrue(np.isnan(poses[0]).any() or len(dropped) == PARTS)
        for i in dropped:
            self.assertGreater(poses[0, i, 2], INNER_SIZE[2])
            self.assertLess(poses[-1, i, 2], poses[0, i, 2] - 0.02)
        # The cancelled fill recorded its partial run as well (as its bin.json has its parts).
        status, _, body = self.get(f"/api/bins/{self.cancelled.job_id}/replay")
        self.assertEqual(status, 200)
        self.assertGreater(len(decode_replay(body)[1]), 0)

    # In a browser.

    def open_page(self):
        need_browser(self)
        # The address `vscan view` gives for a bin fill job (it asks the server for the job's kind).
        run = subprocess.run([VSCAN, "--server", self.server.address, "--token", TOKEN, "view", self.job.job_id,
                              "--web", self.web, "--no-open"], capture_output=True, text=True, timeout=30)
        self.assertEqual(run.returncode, 0, run.stderr)
        url = run.stdout.strip()
        self.assertEqual(url, f"http://{self.web}/?bin={self.job.job_id}#token={TOKEN}")
        shot = os.path.join(self.tmp.name, "bin.png")
        picked = os.path.join(self.tmp.name, "bin-picked.png")
        seen = run_page(self, "bin_page.js", url, shot, picked, "960x540")
        with open(shot, "rb") as f:
            image = read_png(f.read())
        return seen, image, picked

    def test_browser_says_a_fill_that_never_ran_has_no_pile(self):
        shot = os.path.join(self.tmp.name, "unrun.png")
        url = f"http://{self.web}/?bin={self.unrun.job_id}#token={TOKEN}"
        seen = run_page(self, "view_page.js", url, shot, "640x360")
        self.assertEqual(seen["consoleErrors"], [])
        self.assertIn("CANCELLED", seen["title"])
        self.assertIn("the fill ended before its physics ran", seen["text"])
        self.assertEqual((seen["view"]["parts"], seen["view"]["frames"]), ([], 0))

    def test_browser_plays_the_fill_and_picks_each_part(self):
        seen, image, picked = self.open_page()
        if os.environ.get("VSCAN_WEB_SCREENSHOT"):
            shutil.copyfile(picked, os.environ["VSCAN_WEB_SCREENSHOT"])
        self.assertEqual(seen["consoleErrors"], [])
        self.assertEqual(seen["errorText"], "")
        origin = f"http://{self.web}/"
        self.assertEqual([r for r in seen["requests"] if not r.startswith(origin)], [])
        self.assertIn(f"{origin}api/bins/{self.job.job_id}/replay", seen["requests"])
        self.assertTrue(seen["sceneLink"].startswith(f"{origin}?scene={self.scene.scene_id}"), seen["sceneLink"])
        view = seen["view"]
        _, parts, times, poses = self.replay()
        self.assertEqual((view["frames"], view["frame"]), (len(times), len(times) - 1))
        self.assertEqual(image.shape, (540, 960, 3))
        by_object = {p["object_id"]: p for p in self.report["parts"]}
        palette = {tuple(p["colour"]) for p in view["parts"]}
        self.assertEqual(len(view["parts"]), PARTS)
        self.assertEqual(len(seen["picks"]), PARTS)
        for part, pick in zip(view["parts"], seen["picks"]):
            reported = by_object[part["object_id"]]
            self.assertEqual(part["instance_id"], reported["instance_id"])
            self.assertIn(reported["object_id"], seen["text"])  # the table of parts
            x, y = part["pixel"]
            self.assertTrue(0 <= x < 960 and 0 <= y < 540, part["pixel"])
            # The part's colour where the page projects it: lit, so darker on faces turned away, but
            # nearer in hue to its own colour than to any other part's, and not the background.
            pixel = image[y, x].astype(float)
            self.assertGreater(np.abs(pixel - BACKGROUND).max(), 40, (part, pixel.tolist()))
            hue = pixel / np.linalg.norm(pixel)
            nearest = max(palette, key=lambda c: float(np.dot(hue, np.array(c) / np.linalg.norm(c))))
            self.assertEqual(list(nearest), part["colour"], (part, pixel.tolist()))
            # A click there names the part.
            self.assertEqual(pick["at"], [x, y])
            self.assertEqual(pick["picked"]["instance_id"], reported["instance_id"])
            self.assertEqual(pick["picked"]["object_id"], reported["object_id"])
            self.assertEqual(pick["picked"]["type"], reported["type"])
            self.assertIn(f"instance: {reported['instance_id']}", pick["panel"])
            self.assertIn(f"object: {reported['object_id']}", pick["panel"])
        # The page's first frame has the first drop in the air, above where those parts end.
        first, last = seen["first"], seen["last"]
        self.assertEqual((first["frame"], last["frame"]), (0, len(times) - 1))
        self.assertEqual(first["time"], 0)
        in_air = [i for i, c in enumerate(first["centres"]) if c is not None]
        self.assertGreaterEqual(len(in_air), 1)
        for i in in_air:
            self.assertGreater(first["centres"][i][2], INNER_SIZE[2])
            self.assertLess(last["centres"][i][2], first["centres"][i][2] - 0.02)
        for i, part in enumerate(view["parts"]):
            np.testing.assert_allclose(last["centres"][i], part["centre"], atol=1e-6)
        # The slider shows the frame it is set to; play runs from the first frame to the last (in
        # simulated time, one second a second) and stops there.
        self.assertEqual(seen["slider"]["frame"], seen["slider"]["asked"])
        self.assertGreater(seen["slider"]["asked"], 0)
        played = seen["played"]
        self.assertEqual((played["playingText"], played["endText"]), ("pause", "play"))
        self.assertGreater(played["seconds"], 0.5 * float(times[-1]))


if __name__ == "__main__":
    unittest.main()
