"""The web view's datasets (vscand --web-listen): a dataset job's scenes, views and files over HTTP, and
one view drawn by the page in headless chromium, compared with the dataset's own files."""

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np

from harness import SOURCE_DIR, VSCAN, Server, read_png
from web_harness import http_get, run_page, web_listen

sys.path.insert(0, os.path.join(SOURCE_DIR, "tests", "unit", "service", "datasets", "format"))
from dataset_layout_test import read_png as read_grey_png  # noqa: E402  (8- and 16-bit grey)

TOKEN = "web-datasets-token"
WIDTH, HEIGHT = 200, 160


def palette():
    """The page's instance colours, read from web/common.js (PALETTE)."""
    with open(os.path.join(SOURCE_DIR, "web", "common.js")) as f:
        text = f.read()
    numbers = re.search(r"PALETTE = \[([^\]]*)\]", text).group(1)
    return [[(v >> 16) & 255, (v >> 8) & 255, v & 255] for v in (int(n, 16) for n in re.findall(r"0x[0-9a-f]+", numbers))]


def box_obj(half):
    """A closed box centred on its origin, faces outward, as OBJ text (metres)."""
    a, b, c = half
    vertices = [(-a, -b, -c), (a, -b, -c), (a, b, -c), (-a, b, -c), (-a, -b, c), (a, -b, c), (a, b, c), (-a, b, c)]
    faces = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5), (4, 8, 7), (4, 7, 3), (1, 5, 8),
             (1, 8, 4), (2, 3, 7), (2, 7, 6)]
    return "".join(f"v {x} {y} {z}\n" for x, y, z in vertices) + "".join(f"f {i} {j} {k}\n" for i, j, k in faces)


def plan_text(mesh):
    return f"""name: web-boxes
bins:
  - name: boxes
    bin: {{inner_size: [0.20, 0.15, 0.08]}}
    parts:
      - {{mesh: {mesh}, unit: m, count: 4}}
    max_simulated_s: 3
seeds: [7]
sensors:
  - {{name: sxga, preset: ideal-sxga, width: {WIDTH}, height: {HEIGHT}}}
views: {{count: 2, cone_deg: 15, distance_m: [0.42, 0.48]}}
"""


class WebDatasetsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-web-ds-")
        _, cls.web, web_args = web_listen(cls.tmp.name, TOKEN)
        cls.server = Server(data_dir=cls.tmp.name, extra_args=web_args).start()
        mesh = os.path.join(cls.tmp.name, "box.obj")
        with open(mesh, "w") as f:
            f.write(box_obj((0.025, 0.018, 0.012)))
        plan = os.path.join(cls.tmp.name, "plan.yaml")
        with open(plan, "w") as f:
            f.write(plan_text(mesh))
        run = subprocess.run([VSCAN, "--server", cls.server.address, "--token", TOKEN, "dataset", "run", plan,
                              "--watch"], capture_output=True, text=True, timeout=240)
        if run.returncode != 0:
            raise RuntimeError(run.stdout + run.stderr + cls.server.log())
        cls.job_id = (run.stdout + run.stderr).split("started dataset job ")[1].split()[0]
        cls.root = os.path.join(cls.tmp.name, "store", "datasets", cls.job_id)
        cls.scene = os.path.join(cls.root, "train_pbr", "000000")
        with open(os.path.join(cls.scene, "scene_camera.json")) as f:
            cls.cameras = json.load(f)
        with open(os.path.join(cls.scene, "scene_gt.json")) as f:
            cls.gt = json.load(f)
        with open(os.path.join(cls.scene, "scene_gt_info.json")) as f:
            cls.gt_info = json.load(f)
        cls.browser_runs = {}

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()
        cls.tmp.cleanup()

    def get(self, path, token=TOKEN):
        """(status, content type, body) of one request, its path sent as it is."""
        return http_get(self.web, path, token)

    def get_json(self, path):
        status, content_type, body = self.get(path)
        self.assertEqual((status, content_type), (200, "application/json"), body)
        return json.loads(body)

    # Over HTTP.

    def test_lists_the_job_its_scenes_and_views(self):
        listed = {d["job_id"]: d for d in self.get_json("/api/datasets")["datasets"]}
        job = listed[self.job_id]
        self.assertEqual((job["state"], job["scene_count"], job["scenes_complete"]), ("SUCCEEDED", 1, 1))
        dataset = self.get_json(f"/api/datasets/{self.job_id}")
        self.assertEqual(dataset["splits"], [{"split": "train_pbr", "more": False,
                                              "scenes": [{"scene_id": "000000", "views": [0, 1]}]}])
        self.assertEqual(dataset["models"], [{"obj_id": 1, "file": "models/obj_000001.ply"}])
        self.assertEqual(dataset["depth_scale_mm"], 0.1)

    def test_a_view_is_its_camera_and_ground_truth(self):
        for view in ("0", "1"):
            got = self.get_json(f"/api/datasets/{self.job_id}/scenes/000000/views/{view}")
            self.assertEqual(got["camera"], self.cameras[view])
            self.assertEqual(len(got["objects"]), len(self.gt[view]))
            for i, (obj, gt, info) in enumerate(zip(got["objects"], self.gt[view], self.gt_info[view])):
                self.assertEqual(obj["gt_index"], i)
                for key, value in {**gt, **info}.items():
                    self.assertEqual(obj[key], value, key)
                self.assertEqual(obj["mask_visib"], f"train_pbr/000000/mask_visib/{int(view):06d}_{i:06d}.png")
            self.assertEqual(got["images"]["gray"], f"train_pbr/000000/gray/{int(view):06d}.png")
        status, content_type, body = self.get(f"/api/datasets/{self.job_id}/files/{got['images']['depth']}")
        self.assertEqual((status, content_type), (200, "image/png"))
        with open(os.path.join(self.root, got["images"]["depth"]), "rb") as f:
            self.assertEqual(body, f.read())
        self.assertEqual(self.get(f"/api/datasets/{self.job_id}/scenes/000000/views/2")[0], 404)
        self.assertEqual(self.get(f"/api/datasets/{self.job_id}/scenes/000001/views/0")[0], 404)
        self.assertEqual(self.get(f"/api/datasets/{self.job_id}/scenes/x/views/0")[0], 400)

    def test_a_running_job_shows_its_complete_scenes_only(self):
        plan = os.path.join(self.tmp.name, "running.yaml")
        with open(os.path.join(self.tmp.name, "plan.yaml")) as f:
            text = f.read().replace("seeds: [7]", "seeds: [1, 2, 3, 4]").replace("name: web-boxes", "name: running")
        with open(plan, "w") as f:
            f.write(text)
        run = subprocess.run([VSCAN, "--server", self.server.address, "--token", TOKEN, "dataset", "run", plan],
                             capture_output=True, text=True, timeout=60)
        self.assertEqual(run.returncode, 0, run.stderr)
        job_id = (run.stdout + run.stderr).split("started dataset job ")[1].split()[0]
        root = os.path.join(self.tmp.name, "store", "datasets", job_id)
        seen = []
        deadline = time.time() + 120
        while time.time() < deadline:
            dataset = self.get_json(f"/api/datasets/{job_id}")
            scenes = dataset["splits"][0]["scenes"] if dataset["splits"] else []
            seen.append((dataset["state"], len(scenes)))
            # Each listed scene is whole: its record written last is there, and its views answer.
            for scene in scenes:
                self.assertTrue(os.path.exists(os.path.join(root, "train_pbr", scene["scene_id"], "scene_files.json")))
                self.assertEqual(scene["views"], [0, 1])
                got = self.get_json(f"/api/datasets/{job_id}/scenes/{scene['scene_id']}/views/1")
                status, _, _ = self.get(f"/api/datasets/{job_id}/files/{got['images']['instances']}")
                self.assertEqual(status, 200)
            self.assertEqual(dataset["scenes_complete"], len(scenes))
            if dataset["state"] not in ("QUEUED", "RUNNING"):
                break
            time.sleep(0.05)
        self.assertEqual(seen[-1], ("SUCCEEDED", 4))
        # It was seen running with some scenes and not others.
        self.assertTrue(any(state == "RUNNING" and 0 < n < 4 for state, n in seen), seen)

    def test_wrong_token_gets_nothing(self):
        files = f"/api/datasets/{self.job_id}/files/"
        for path in ("/api/datasets", f"/api/datasets/{self.job_id}", f"/api/datasets/{self.job_id}/scenes/0/views/0",
                     files + "train_pbr/000000/gray/000000.png"):
            for token in (None, "wrong", ""):
                status, _, body = self.get(path, token)
                self.assertEqual(status, 401, (path, token))
                self.assertNotIn(self.job_id.encode(), body)
                self.assertNotIn(b"PNG", body)

    def test_hostile_file_paths(self):
        files = f"/api/datasets/{self.job_id}/files/"
        # A link inside the dataset to the token file, and a file beside the dataset.
        os.symlink(os.path.join(self.tmp.name, "token"), os.path.join(self.scene, "leak.json"))
        with open(os.path.join(self.root, "..", "beside.json"), "w") as f:
            f.write(json.dumps({"secret": TOKEN}))
        try:
            for path in ("../../../token", "%2e%2e/%2e%2e/%2e%2e/token", "%2e%2e/beside.json", "..%2fbeside.json",
                         "%2E%2E/beside.json", "train_pbr/000000/../../../beside.json", "/etc/passwd",
                         "%2fetc%2fpasswd", "train_pbr/000000/leak.json", "a" * 4000 + ".png", "x/" * 300 + "x.png",
                         "train_pbr/000000/gray/", "jobs.sqlite", "../store/catalogue.sqlite",
                         "train_pbr/000000/gray\\..\\..\\..\\beside.json"):
                status, _, body = self.get(files + path)
                self.assertIn(status, (400, 404), path)
                self.assertNotIn(TOKEN.encode(), body, path)
                self.assertNotIn(b"root:", body, path)
            # Refused by the API for their path (civetweb resolves "..", also encoded, and "//" before).
            for path in ("a" * 300 + ".png", "train_pbr/000000.partial/x.png", "train_pbr/000000/x.png.tmp-0", "x/.png"):
                self.assertEqual(self.get(files + path)[0], 400, path)
            self.assertEqual(self.get(files + "train_pbr/000000/leak.json")[0], 404)
            # civetweb ends the decoded path at %00: what follows it is dropped, never read as the
            # file's name or type.
            with open(os.path.join(self.root, "dataset.json"), "rb") as f:
                manifest = f.read()
            self.assertEqual(self.get(files + "dataset.json%00.png"), (200, "application/json", manifest))
            status, _, body = self.get(files + "dataset.json%00/../../../token")
            self.assertIn(status, (200, 400, 404))
            self.assertNotIn(TOKEN.encode(), body)
        finally:
            os.remove(os.path.join(self.scene, "leak.json"))
            os.remove(os.path.join(self.root, "..", "beside.json"))

    # In a browser.

    def browse(self, steps):
        steps_path = os.path.join(self.tmp.name, "steps.json")
        with open(steps_path, "w") as f:
            json.dump(steps, f)
        return run_page(self, "dataset_page.js", steps_path, timeout=120)

    def url(self, query, token=TOKEN):
        return f"http://{self.web}/?{query}#token={token}"

    def shot(self, name):
        return os.path.join(self.tmp.name, name)

    @staticmethod
    def pixel(seen, image, u, v):
        """The screenshot's colour at the middle of image pixel (u, v) as the page drew it."""
        view = seen["view"]
        s = view["scale"]
        x = int(round(view["canvas"][0])) + u * s + s // 2
        y = int(round(view["canvas"][1])) + v * s + s // 2
        return image[y, x].astype(int)

    def test_browser_draws_a_view_and_reports_clicks(self):
        view_query = f"dataset={self.job_id}&scene=000000&view=0"
        masks = [read_grey_png(os.path.join(self.scene, "mask_visib", f"000000_{i:06d}.png"))[0]
                 for i in range(len(self.gt["0"]))]
        depth = read_grey_png(os.path.join(self.scene, "depth", "000000.png"))[0].astype(int)
        grey = read_grey_png(os.path.join(self.scene, "gray", "000000.png"))[0].astype(int)
        camera = self.cameras["0"]
        k_matrix = np.array(camera["cam_K"]).reshape(3, 3)
        # The most visible box, and a pixel of its visible mask at (or near) its projected origin.
        chosen = max(range(len(masks)), key=lambda i: self.gt_info["0"][i]["visib_fract"])
        self.assertGreater(self.gt_info["0"][chosen]["visib_fract"], 0.9)
        rows, cols = np.nonzero(masks[chosen])
        t = np.array(self.gt["0"][chosen]["cam_t_m2c"])
        origin = k_matrix @ t / t[2]
        nearest = int(np.argmin((cols - origin[0]) ** 2 + (rows - origin[1]) ** 2))
        click_u, click_v = int(cols[nearest]), int(rows[nearest])
        empty_v, empty_u = [int(a[0]) for a in np.nonzero(sum(masks) == 0)]

        # The picture's page first: the clicks land where the page says the pixels are, which the
        # first step reports; so the page is opened once to learn its layout, then again to click.
        layout = self.browse([{"url": self.url(view_query + "&overlays=masks"), "screenshot": self.shot("masks.png")}])
        [masks_page] = layout
        view = masks_page["view"]
        s = view["scale"]
        left, top = int(round(view["canvas"][0])), int(round(view["canvas"][1]))

        def at(u, v):
            return [left + u * s + s // 2, top + v * s + s // 2]

        steps = [
            {"url": self.url(view_query + "&overlays=grey"), "screenshot": self.shot("grey.png")},
            {"url": self.url(view_query + "&overlays=depth"), "screenshot": self.shot("depth.png")},
            {"url": self.url(view_query + "&overlays=boxes"), "screenshot": self.shot("boxes.png")},
            {"url": self.url(view_query), "screenshot": self.shot("all.png"),
             "clicks": [at(empty_u, empty_v), at(click_u, click_v)], "after_clicks_screenshot": self.shot("picked.png"),
             "follow_view": "1"},
            {"url": self.url(view_query, token="wrong")},
            {"url": self.url("")},
            {"url": self.url(f"dataset={self.job_id}")},
        ]
        grey_page, depth_page, boxes_page, full_page, wrong_page, index_page, dataset_page = self.browse(steps)
        for page in (masks_page, grey_page, depth_page, boxes_page, full_page, index_page, dataset_page):
            self.assertEqual(page["consoleErrors"], [])
            self.assertEqual(page["errorText"], "")
            origin_prefix = f"http://{self.web}/"
            self.assertEqual([r for r in page["requests"] if not r.startswith(origin_prefix)], [])
        self.assertEqual((view["width"], view["height"]), (WIDTH, HEIGHT))
        self.assertGreaterEqual(s, 1)

        # Masks alone: each object's visible pixels in its colour at the page's opacity over black,
        # the rest black.
        image = read_png(self.shot("masks.png"))
        alpha = view["maskAlpha"]
        drawn = view["objects"]
        self.assertEqual(len(drawn), len(masks))
        colours = palette()
        self.assertEqual(len(colours), 10)
        for i, mask in enumerate(masks):
            visible = mask > 0
            # The instance palette of the scene view, by the part's instance id.
            self.assertEqual(drawn[i]["colour"], colours[self.gt["0"][i]["instance_id"] % len(colours)])
            self.assertEqual(drawn[i]["obj_id"], self.gt["0"][i]["obj_id"])
            self.assertEqual(drawn[i]["mask_pixels"], int(visible.sum()))
            self.assertEqual(drawn[i]["mask_pixels"], self.gt_info["0"][i]["px_count_visib"])
            expected = np.floor(alpha * np.array(drawn[i]["colour"]) + 0.5)
            for v, u in zip(*np.nonzero(visible)):
                np.testing.assert_allclose(self.pixel(masks_page, image, u, v), expected, atol=2,
                                           err_msg=f"object {i} at ({u}, {v})")
        for v, u in zip(*np.nonzero(sum(masks) == 0)):
            np.testing.assert_array_equal(self.pixel(masks_page, image, u, v), [0, 0, 0])

        # Grey alone: the grey image, scaled so that greyWhite is white.
        image = read_png(self.shot("grey.png"))
        # White is the 99.5th percentile of the lit pixels.
        lit = np.sort(grey[grey > 0])
        white = grey_page["view"]["greyWhite"]
        self.assertEqual(white, lit[int(np.ceil(len(lit) * 0.995)) - 1])
        expected = np.minimum(255, np.floor(grey * 255 / white + 0.5))
        self.assertGreater(expected.max(), 200)
        shown = np.array([[self.pixel(grey_page, image, u, v)[0] for u in range(WIDTH)] for v in range(HEIGHT)])
        self.assertLessEqual(np.abs(shown - expected).max(), 1)

        # Depth alone: measured pixels in false colour from blue (near) to red (far), the rest black.
        image = read_png(self.shot("depth.png"))
        measured = depth > 0
        self.assertEqual(depth_page["view"]["depth"], {"near": int(depth[measured].min()), "far": int(depth[measured].max())})
        shown = np.array([[self.pixel(depth_page, image, u, v) for u in range(WIDTH)] for v in range(HEIGHT)])
        self.assertTrue((shown[~measured] == 0).all())
        self.assertTrue((shown[measured].max(axis=1) > 0).all())
        near_v, near_u = np.unravel_index(np.argmin(np.where(measured, depth, 1 << 20)), depth.shape)
        far_v, far_u = np.unravel_index(np.argmax(depth), depth.shape)
        self.assertGreater(shown[near_v, near_u][2], shown[near_v, near_u][0])
        self.assertGreater(shown[far_v, far_u][0], shown[far_v, far_u][2])

        # Boxes alone: bbox_visib's pixels framed, in the object's colour.
        image = read_png(self.shot("boxes.png"))
        boxes = {b["gt_index"]: b for b in boxes_page["view"]["boxes"]}
        for i, info in enumerate(self.gt_info["0"]):
            x, y, w, h = info["bbox_visib"]
            if x < 0:
                self.assertNotIn(i, boxes)
                continue
            self.assertEqual(boxes[i]["rect"], [x * s, y * s, (x + w + 1) * s, (y + h + 1) * s])
            # The left and bottom edges (labels sit above the top one) show the colour.
            edge = [(left + x * s, top + yy) for yy in range(y * s + 2, (y + h + 1) * s - 2)]
            edge += [(left + xx, top + (y + h + 1) * s - 1) for xx in range(x * s + 2, (x + w + 1) * s - 2)]
            coloured = [np.abs(image[py, px].astype(int) - boxes[i]["colour"]).max() <= 3 for px, py in edge]
            self.assertGreater(np.mean(coloured), 0.8, i)

        # Poses: each origin where cam_K projects cam_t_m2c, inside the object's full box, and for the
        # most visible box on its visible mask.
        for i, (gt, info) in enumerate(zip(self.gt["0"], self.gt_info["0"])):
            t = np.array(gt["cam_t_m2c"])
            expected_origin = (k_matrix @ t / t[2])[:2]
            np.testing.assert_allclose(drawn[i]["origin"], expected_origin, atol=1e-6)
            x, y, w, h = info["bbox_obj"]
            if x >= 0:
                self.assertTrue(x - 0.5 <= expected_origin[0] <= x + w + 0.5, (i, expected_origin, info["bbox_obj"]))
                self.assertTrue(y - 0.5 <= expected_origin[1] <= y + h + 0.5, (i, expected_origin, info["bbox_obj"]))
        ou, ov = (int(np.floor(c + 0.5)) for c in drawn[chosen]["origin"])
        self.assertTrue(masks[chosen][ov - 1:ov + 2, ou - 1:ou + 2].any(), (ou, ov))

        # Clicks: on the chosen box's mask, its obj_id and the depth image's value there; off every
        # mask, no object and that pixel's depth.
        background, picked = full_page["picks"]
        self.assertEqual((picked["picked"]["u"], picked["picked"]["v"]), (click_u, click_v))
        self.assertEqual(picked["picked"]["object"]["obj_id"], self.gt["0"][chosen]["obj_id"])
        self.assertEqual(picked["picked"]["object"]["gt_index"], chosen)
        self.assertEqual(picked["picked"]["object"]["bbox_visib"], self.gt_info["0"][chosen]["bbox_visib"])
        self.assertEqual(picked["picked"]["depth_raw"], depth[click_v, click_u])
        self.assertGreater(depth[click_v, click_u], 0)
        self.assertAlmostEqual(picked["picked"]["depth_mm"], depth[click_v, click_u] * camera["depth_scale"], places=6)
        self.assertIn(f"obj_id {self.gt['0'][chosen]['obj_id']}, gt {chosen}", picked["panel"])
        millimetres = repr(round(float(depth[click_v, click_u] * camera["depth_scale"]), 3)).removesuffix(".0")
        self.assertIn(f"depth: {millimetres} mm", picked["panel"])
        self.assertEqual((background["picked"]["u"], background["picked"]["v"]), (empty_u, empty_v))
        self.assertIsNone(background["picked"]["object"])
        self.assertEqual(background["picked"]["depth_raw"], depth[empty_v, empty_u])
        self.assertIn("none (no visible mask here)", background["panel"])
        # Everything on: the masks are blended over the grey, so the chosen box's pixels are neither
        # plain grey nor black.
        image = read_png(self.shot("all.png"))
        self.assertEqual(full_page["view"]["overlays"], ["grey", "masks", "boxes", "axes"])
        coloured = [np.ptp(self.pixel(full_page, image, u, v)) > 20 for v, u in zip(*np.nonzero(masks[chosen]))]
        self.assertGreater(np.mean(coloured), 0.5)
        # Set VSCAN_WEB_SCREENSHOT to keep the picture (docs/images/web_dataset.png is made so).
        if os.environ.get("VSCAN_WEB_SCREENSHOT"):
            shutil.copyfile(self.shot("picked.png"), os.environ["VSCAN_WEB_SCREENSHOT"])

        # The link to view 1 on the page shows it in place, and the address names it.
        followed = full_page["followed"]
        self.assertEqual((followed["view"]["scene_id"], followed["view"]["view"]), ("000000", 1))
        self.assertIn(f"dataset={self.job_id}&scene=000000&view=1", followed["location"])
        self.assertEqual(len(followed["view"]["objects"]), len(self.gt["1"]))

        # A wrong token: the 401 on the page and nothing drawn.
        self.assertIn("401", wrong_page["errorText"])
        self.assertIsNone(wrong_page["view"])
        # The page without a view lists the dataset.
        self.assertIn(self.job_id, index_page["text"])
        self.assertIn("1 of 1 scenes", index_page["text"])
        # The dataset without a view: its scenes and their views, nothing drawn yet.
        self.assertIn("train_pbr/000000: views 0 1", dataset_page["text"])
        self.assertIsNone(dataset_page["view"])


if __name__ == "__main__":
    unittest.main()
