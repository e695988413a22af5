"""The read-only web view (vscand --web-listen): its API over HTTP, and its page in headless chromium."""

import json
import os
import shutil
import socket
import struct
import subprocess
import tempfile
import unittest
import urllib.request

import numpy as np

from harness import VSCAN, VSCAND, common_pb2, icosphere_ply, read_png, scene_pb2
from web_harness import BACKGROUND, WebServerTestCase, free_port, http_get, run_page

TOKEN = "web-view-token"


class WebViewTest(WebServerTestCase):
    token = TOKEN

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        # The port file is written once the web view serves too: no waiting for it here.
        auth = [("authorization", f"Bearer {TOKEN}")]
        # One sphere of radius 0.2 at (0.3, 0.2, 0.1), and a second scene left empty.
        cls.scene = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="web <view>"), metadata=auth).scene
        cls.empty = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="empty"), metadata=auth).scene
        data = icosphere_ply(0.2, (0, 0, 0), 3)

        def requests():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                name="sphere.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data)))
            yield scene_pb2.UploadMeshRequest(chunk=data)
        cls.mesh = cls.scenes.UploadMesh(requests(), metadata=auth, timeout=60).mesh
        pose = common_pb2.Pose(quaternion=common_pb2.QuaternionPose(
            translation=common_pb2.Vector3(x=0.3, y=0.2, z=0.1), qw=1.0))
        cls.object = cls.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=cls.scene.scene_id, mesh_id=cls.mesh.mesh_id, pose=pose, label="ball", scale=1.0,
            material=scene_pb2.Material(preset="cardboard")),
            metadata=auth).object
        # Three spheres side by side for picking: a preset, explicit values, and the mesh's (default) material.
        cls.row = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="row"), metadata=auth).scene
        materials = (scene_pb2.Material(preset="cardboard"),
                     scene_pb2.Material(values=scene_pb2.MaterialValues(
                         diffuse_albedo=0.5, metallic=0.0, roughness=0.25, specular_reflectance=0.04)),
                     None)
        cls.row_objects = []
        # Along (3, 2, 0), square to the page's view direction (1, -1.5, 1): a row across the page.
        for t, label, material in zip((-1, 0, 1), ("left", "middle", "right"), materials):
            pose = common_pb2.Pose(quaternion=common_pb2.QuaternionPose(
                translation=common_pb2.Vector3(x=0.5 * t * 3 / 13 ** 0.5, y=0.5 * t * 2 / 13 ** 0.5, z=0.2), qw=1.0))
            cls.row_objects.append(cls.scenes.AddObject(scene_pb2.AddObjectRequest(
                scene_id=cls.row.scene_id, mesh_id=cls.mesh.mesh_id, pose=pose, label=label, scale=1.0,
                material=material), metadata=auth).object)

    def get(self, path, token=TOKEN, method="GET"):
        """(status, content type, body) of one request to the web view."""
        return http_get(self.web, path, token, method)

    def test_api_needs_the_token(self):
        for path in ("/api/scenes", f"/api/scenes/{self.scene.scene_id}", f"/api/meshes/{self.mesh.mesh_id}"):
            for token in (None, "wrong", TOKEN + "x", ""):
                status, _, body = self.get(path, token)
                self.assertEqual(status, 401, (path, token))
                self.assertNotIn(self.scene.scene_id.encode(), body)
                self.assertNotIn(b"VSMH", body)

    def test_clients_that_stall_hold_neither_the_view_nor_the_grpc_server(self):
        # Twelve connections that send half a request and then nothing, and one that asks for the
        # mesh and never reads: a whole request beside them is still answered at once.
        stalled = []
        try:
            for _ in range(12):
                s = socket.create_connection(("127.0.0.1", self.web_port))
                s.sendall(b"GET /api/scenes HTTP/1.1\r\nHost: x\r\n")
                stalled.append(s)
            reader = socket.create_connection(("127.0.0.1", self.web_port))
            reader.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
            reader.sendall(f"GET /api/meshes/{self.mesh.mesh_id} HTTP/1.1\r\nHost: x\r\n"
                           f"Authorization: Bearer {TOKEN}\r\n\r\n".encode())
            stalled.append(reader)
            status, _, body = self.get("/api/scenes")
            self.assertEqual(status, 200)
            self.assertIn(self.scene.scene_id.encode(), body)
            scene = self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=self.scene.scene_id),
                                         metadata=[("authorization", f"Bearer {TOKEN}")], timeout=10).scene
            self.assertEqual(scene.scene_id, self.scene.scene_id)
        finally:
            for s in stalled:
                s.close()

    def test_scene_list_and_scene(self):
        status, content_type, body = self.get("/api/scenes")
        self.assertEqual((status, content_type), (200, "application/json"))
        listed = {s["scene_id"]: s for s in json.loads(body)["scenes"]}
        self.assertEqual(listed[self.scene.scene_id]["name"], "web <view>")
        self.assertEqual(listed[self.scene.scene_id]["object_count"], 1)
        self.assertEqual(listed[self.empty.scene_id]["object_count"], 0)

        status, _, body = self.get(f"/api/scenes/{self.scene.scene_id}")
        self.assertEqual(status, 200)
        scene = json.loads(body)
        self.assertEqual(scene["name"], "web <view>")
        self.assertEqual(len(scene["objects"]), 1)
        placed = scene["objects"][0]
        self.assertEqual(placed["object_id"], self.object.object_id)
        self.assertEqual(placed["mesh_id"], self.mesh.mesh_id)
        self.assertEqual(placed["label"], "ball")
        self.assertEqual(placed["instance_id"], self.object.instance_id)
        np.testing.assert_allclose(placed["world_from_object"],
                                   [[1, 0, 0, 0.3], [0, 1, 0, 0.2], [0, 0, 1, 0.1], [0, 0, 0, 1]], atol=1e-12)
        # The material in effect (the object's own here), so that the page can show it.
        self.assertEqual(placed["material"]["preset"], "cardboard")
        presets = {p.name: p.values for p in self.scenes.ListMaterialPresets(
            scene_pb2.ListMaterialPresetsRequest(), metadata=[("authorization", f"Bearer {TOKEN}")]).presets}
        self.assertEqual(placed["material"]["albedo"], presets["cardboard"].diffuse_albedo)
        self.assertEqual(placed["material"]["roughness"], presets["cardboard"].roughness)

    def test_mesh_binary_matches_the_upload(self):
        status, content_type, body = self.get(f"/api/meshes/{self.mesh.mesh_id}")
        self.assertEqual((status, content_type), (200, "application/octet-stream"))
        magic, version, vertices, triangles = struct.unpack("<4sIII", body[:16])
        self.assertEqual((magic, version), (b"VSMH", 1))
        self.assertEqual((vertices, triangles), (self.mesh.vertex_count, self.mesh.triangle_count))
        self.assertEqual(len(body), 16 + 12 * vertices + 12 * triangles)
        positions = np.frombuffer(body, "<f4", vertices * 3, 16).reshape(-1, 3)
        np.testing.assert_allclose(np.linalg.norm(positions, axis=1), 0.2, rtol=1e-5)
        indices = np.frombuffer(body, "<u4", triangles * 3, 16 + 12 * vertices)
        self.assertEqual(indices.max(), vertices - 1)

    def test_unknown_ids_and_methods(self):
        for path in ("/api/scenes/scn_0000000000000000", "/api/meshes/msh_0000000000000000", "/api/scenes/a%2Fb",
                     "/api/nothing", "/nothing.js"):
            self.assertEqual(self.get(path)[0], 404, path)
        for method in ("POST", "PUT", "DELETE"):
            self.assertEqual(self.get("/api/scenes", method=method)[0], 405, method)
            self.assertEqual(self.get("/", method=method)[0], 405, method)

    def test_page_and_three_js_are_served_without_the_token(self):
        status, content_type, body = self.get("/", token=None)
        self.assertEqual((status, content_type), (200, "text/html; charset=utf-8"))
        self.assertIn(b'src="app.js"', body)
        with urllib.request.urlopen(f"http://{self.web}/", timeout=10) as response:
            self.assertIn("default-src 'self'", response.headers["Content-Security-Policy"])
        status, content_type, body = self.get("/app.js", token=None)
        self.assertEqual((status, content_type), (200, "text/javascript; charset=utf-8"))
        for path in ("build/three.module.js", "examples/jsm/controls/OrbitControls.js"):
            status, _, body = self.get("/three/" + path, token=None)
            self.assertEqual(status, 200, path)
            with open("/usr/share/javascript/three/" + path, "rb") as f:
                self.assertEqual(body, f.read(), path)

    def test_cli_prints_the_page_address(self):
        run = subprocess.run([VSCAN, "--token", "a b/c", "view", self.scene.scene_id, "--web", self.web],
                             capture_output=True, text=True, timeout=30)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertEqual(run.stdout.strip(), f"http://{self.web}/?scene={self.scene.scene_id}#token=a%20b%2Fc")
        run = subprocess.run([VSCAN, "--json", "view"], capture_output=True, text=True, timeout=30,
                             env={**os.environ, "VSCAN_WEB": self.web, "VSCAN_TOKEN": ""})
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertEqual(json.loads(run.stdout), {"url": f"http://{self.web}/", "opened": False})
        run = subprocess.run([VSCAN, "view"], capture_output=True, text=True, timeout=30,
                             env={k: v for k, v in os.environ.items() if k != "VSCAN_WEB"})
        self.assertEqual(run.returncode, 2)
        self.assertIn("--web", run.stderr)

    # In a browser: what a person would see.

    def open_page(self, url, size="320x240", mode=""):
        shot = os.path.join(self.tmp.name, "page.png")
        seen = run_page(self, "view_page.js", url, shot, size, mode)
        with open(shot, "rb") as f:
            return seen, read_png(f.read())

    def view_url(self, scene_id, token):
        return subprocess.run([VSCAN, "--token", token, "view", scene_id, "--web", self.web],
                              capture_output=True, text=True, timeout=30, check=True).stdout.strip()

    def test_browser_draws_the_scene(self):
        seen, image = self.open_page(self.view_url(self.scene.scene_id, TOKEN))
        self.assertEqual(seen["consoleErrors"], [])
        # Offline: everything the page loads comes from vscand (page, app.js, three.js, the API).
        origin = f"http://{self.web}/"
        self.assertEqual([r for r in seen["requests"] if not r.startswith(origin)], [])
        self.assertIn(origin + "three/build/three.module.js", seen["requests"])
        self.assertIn(f"{origin}api/meshes/{self.mesh.mesh_id}", seen["requests"])
        self.assertEqual(seen["errorText"], "")
        self.assertIn(self.object.object_id, seen["text"])  # the object table
        self.assertEqual(image.shape, (240, 320, 3))
        [drawn] = seen["view"]["objects"]
        self.assertEqual(drawn["object_id"], self.object.object_id)
        x, y = drawn["pixel"]
        # Framed by the camera: the sphere's centre projects near the middle of the page.
        self.assertLess(abs(x - 160), 40)
        self.assertLess(abs(y - 120), 40)
        expected = np.array(drawn["colour"])
        self.assertGreater(np.abs(expected - BACKGROUND).max(), 100)
        # Lit from the camera, the side facing it shows (close to) the object's colour ...
        centre = image[y - 2:y + 3, x - 2:x + 3].reshape(-1, 3).astype(int)
        self.assertLess(np.abs(centre - expected).max(), 40, (centre.tolist(), expected.tolist()))
        # ... and pixels well outside it the background.
        for corner in (image[5, 300], image[230, 5], image[230, 315]):
            np.testing.assert_array_equal(corner, BACKGROUND)
        # The sphere (radius 0.2 of the framed 0.2) covers a good part of the page.
        covered = (np.abs(image.astype(int) - expected).max(axis=2) < 80).mean()
        self.assertGreater(covered, 0.1)

    def test_browser_click_reports_the_object_hit(self):
        seen, image = self.open_page(self.view_url(self.row.scene_id, TOKEN), "640x480", "pick")
        self.assertEqual(seen["consoleErrors"], [])
        self.assertEqual(seen["errorText"], "")
        # Set VSCAN_WEB_SCREENSHOT to keep the picture (docs/images/web_scene.png is made so).
        if os.environ.get("VSCAN_WEB_SCREENSHOT"):
            shutil.copyfile(os.path.join(self.tmp.name, "page.png"), os.environ["VSCAN_WEB_SCREENSHOT"])
        self.assertEqual(image.shape, (480, 640, 3))
        instances = [o.instance_id for o in self.row_objects]
        self.assertEqual(len(set(instances)), 3)
        drawn = {o["object_id"]: o for o in seen["view"]["objects"]}
        # One click per sphere at its projected centre, in the page's order, then one on the background.
        self.assertEqual(len(seen["picks"]), 4)
        xs = []
        for pick, object in zip(seen["picks"], self.row_objects):
            x, y = drawn[object.object_id]["pixel"]
            xs.append(x)
            self.assertEqual(pick["at"], [x, y])
            # The click landed on the sphere as drawn (its colour), and the page names that sphere.
            self.assertLess(np.abs(image[y, x].astype(int) - drawn[object.object_id]["colour"]).max(), 40)
            self.assertEqual(pick["picked"]["object_id"], object.object_id)
            self.assertEqual(pick["picked"]["label"], object.label)
            self.assertEqual(pick["picked"]["instance_id"], object.instance_id)
            self.assertIn(f"instance: {object.instance_id}", pick["panel"])
            self.assertIn(f"label: {object.label}", pick["panel"])
            self.assertIn(f"object: {object.object_id}", pick["panel"])
        # Side by side along x: left, middle, right on the page too.
        self.assertEqual(xs, sorted(xs))
        # The screenshot follows a last click on the left sphere: a yellow box marks it, and only it.
        yellow_y, yellow_x = np.nonzero((image[:, :, 0] > 200) & (image[:, :, 1] > 200) & (image[:, :, 2] < 80))
        self.assertGreater(len(yellow_x), 20)
        self.assertLess(yellow_x.min(), xs[0])
        self.assertGreater(yellow_x.max(), xs[0])
        self.assertLess(yellow_x.max(), xs[1])
        left, middle, right = (p["picked"]["material"] for p in seen["picks"][:3])
        self.assertEqual(left["preset"], "cardboard")
        self.assertIn("material: cardboard (albedo", seen["picks"][0]["panel"])
        self.assertEqual((middle["preset"], middle["albedo"], middle["roughness"]), ("", 0.5, 0.25))
        self.assertIn("material: albedo 0.5, metallic 0, roughness 0.25, specular 0.04", seen["picks"][1]["panel"])
        self.assertEqual(right["preset"], "matte-grey")
        background = seen["picks"][3]
        self.assertEqual(background["at"], [635, 475])
        np.testing.assert_array_equal(image[475, 635], BACKGROUND)
        self.assertIsNone(background["picked"])
        self.assertEqual(background["panel"].strip(), "nothing picked")

    def test_browser_with_a_wrong_token_shows_an_error_and_no_scene(self):
        seen, image = self.open_page(self.view_url(self.scene.scene_id, "wrong"))
        self.assertIn("401", seen["errorText"])
        self.assertIsNone(seen["view"])
        self.assertNotIn(self.object.object_id, seen["text"])
        self.assertTrue(any("401" in e for e in seen["consoleErrors"]), seen["consoleErrors"])

    def test_browser_lists_scenes_without_a_scene_id(self):
        seen, _ = self.open_page(self.view_url("", TOKEN))
        self.assertEqual(seen["consoleErrors"], [])
        self.assertIn(self.scene.scene_id, seen["text"])
        self.assertIn(self.empty.scene_id, seen["text"])


class WebViewRefusalTest(unittest.TestCase):
    """vscand does not start half-way: a web view it cannot serve stops it with the reason."""

    def run_vscand(self, *args):
        with tempfile.TemporaryDirectory(prefix="vscand-web-") as data:
            return subprocess.run([VSCAND, "--listen", "127.0.0.1:0", "--data-dir", data, *args],
                                  capture_output=True, text=True, timeout=60)

    def test_missing_three_js(self):
        run = self.run_vscand("--web-listen", f"127.0.0.1:{free_port()}", "--web-three-dir", "/nonexistent")
        self.assertEqual(run.returncode, 1)
        self.assertIn("cannot read '/nonexistent/build/three.module.js'", run.stdout + run.stderr)

    def test_address_in_use(self):
        with socket.socket() as busy:
            busy.bind(("127.0.0.1", 0))
            busy.listen()
            address = f"127.0.0.1:{busy.getsockname()[1]}"
            run = self.run_vscand("--web-listen", address)
        self.assertEqual(run.returncode, 1)
        self.assertIn(f"--web-listen: cannot listen on '{address}'", run.stdout + run.stderr)


if __name__ == "__main__":
    unittest.main()
