"""The web view's robots, its HTTPS and `vscan view` for every kind of id, against a real vscand."""

import json
import os
import shutil
import socket
import ssl
import stat
import subprocess
import tempfile
import time
import unittest
import urllib.error
import urllib.request

import numpy as np

from harness import SOURCE_DIR, VSCAN, Server, common_pb2, icosphere_ply, read_png
from test_campaign_service import CampaignFixture, spec
from test_robot_links import Q, upload_ur5_with_boxes
from test_robots import matrix, to_pose, transform
from web_harness import BACKGROUND, WebServerTestCase, free_port, http_get, run_page
from vscan.v1 import job_pb2, robot_pb2, robot_pb2_grpc, scene_pb2

TOKEN = "web-robot-token"


def decode_mesh(body):
    assert body[:4] == b"VSMH", body[:4]
    vertices, triangles = np.frombuffer(body, "<u4", 2, 8)
    return np.frombuffer(body, "<f4", vertices * 3, 16).reshape(-1, 3), int(triangles)


class WebRobotTest(WebServerTestCase):
    token = TOKEN

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        auth = [("authorization", f"Bearer {TOKEN}")]
        cls.auth = auth
        cls.robots = robot_pb2_grpc.RobotServiceStub(cls.channel)
        # robot_pb2_grpc stubs take the token per call; upload_ur5_with_boxes does not pass it.
        cls.ur5 = upload_ur5_with_boxes(_WithToken(cls.robots, auth))
        cls.scene = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="arm"), metadata=auth).scene
        cls.base = transform(translation=(0.1, -0.2, 0.0))
        cls.mount_id = cls.robots.MountRobot(robot_pb2.MountRobotRequest(
            scene_id=cls.scene.scene_id, robot_id=cls.ur5.robot_id, base_pose=to_pose(cls.base)),
            metadata=auth, timeout=10).mount_id
        # A ball on a rotary table in front of the arm.
        data = icosphere_ply(0.08, (0, 0, 0), 3)

        def requests():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                name="ball.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data)))
            yield scene_pb2.UploadMeshRequest(chunk=data)
        mesh = cls.scenes.UploadMesh(requests(), metadata=auth, timeout=60).mesh
        cls.scenes.SetRotaryTable(scene_pb2.SetRotaryTableRequest(scene_id=cls.scene.scene_id, table=scene_pb2.RotaryTable(
            enabled=True, centre=common_pb2.Vector3(x=0.3, y=0.45), axis=common_pb2.Vector3(z=1), angle_deg=30)),
            metadata=auth)
        cls.scenes.AddObject(scene_pb2.AddObjectRequest(
            scene_id=cls.scene.scene_id, mesh_id=mesh.mesh_id, label="ball", on_table=True,
            pose=to_pose(transform(translation=(0.3, 0.45, 0.08)))), metadata=auth)

    def get(self, path, token=TOKEN):
        status, _, body = http_get(self.web, path, token, timeout=30)
        return status, body

    def fk(self, q):
        return self.robots.ForwardKinematics(robot_pb2.ForwardKinematicsRequest(mount_id=self.mount_id,
                                                                                joint_positions=q),
                                             metadata=self.auth)

    def test_scene_lists_its_mount(self):
        status, body = self.get(f"/api/scenes/{self.scene.scene_id}")
        self.assertEqual(status, 200, body)
        scene = json.loads(body)
        self.assertEqual(scene["mounts"], [{"mount_id": self.mount_id, "robot_id": self.ur5.robot_id}])
        self.assertEqual(scene["table"], {"enabled": True, "angle_deg": 30, "centre": [0.3, 0.45, 0], "axis": [0, 0, 1]})

    def test_sensor_and_links_stand_where_forward_kinematics_puts_them(self):
        for q in (None, Q):
            status, body = self.get(f"/api/mounts/{self.mount_id}" + (f"?joints={','.join(map(str, q))}" if q else ""))
            self.assertEqual(status, 200, body)
            pose = json.loads(body)
            fk = self.fk(pose["joints"])
            if q:
                np.testing.assert_allclose(pose["joints"], q)
            # The sensor on the flange: the mount's tool pose in the world, as the gRPC API gives it.
            np.testing.assert_allclose(np.array(pose["world_from_sensor"]), matrix(fk.tool_pose), atol=1e-9)
            np.testing.assert_allclose(np.array(pose["world_from_base"]), self.base, atol=1e-12)
            # Each link box (spanning its link's origin) placed at the link's forward-kinematics pose.
            links = {p.link: matrix(p.pose) for p in fk.link_poses}
            shapes = [s for s in pose["shapes"] if s["link"] in links]
            self.assertGreaterEqual(len(shapes), 5, [s["link"] for s in pose["shapes"]])
            for shape in shapes:
                k = pose["shapes"].index(shape)
                status, mesh = self.get(f"/api/mounts/{self.mount_id}/shapes/{k}")
                self.assertEqual(status, 200)
                vertices, triangles = decode_mesh(mesh)
                self.assertEqual(triangles, shape["triangles"])
                world = np.array(shape["world_from_shape"])
                placed = vertices @ world[:3, :3].T + world[:3, 3]
                origin = links[shape["link"]][:3, 3]
                # The box holds its link origin (thickened by 0.04 m around the segment).
                self.assertTrue(np.all(placed.min(0) <= origin + 1e-4) and np.all(placed.max(0) >= origin - 1e-4),
                                (shape["link"], placed.min(0), placed.max(0), origin))

    def test_bad_joints_and_ids_are_refused(self):
        path = f"/api/mounts/{self.mount_id}?joints="
        for joints in ("1,2", "0,0,0,0,0,0,0", "nan,0,0,0,0,0", "1e19,0,0,0,0,0", "0,,0,0,0,0", "a,0,0,0,0,0",
                       "99,0,0,0,0,0"):
            status, body = self.get(path + joints)
            self.assertEqual(status, 400, joints)
            self.assertIn(b"joints", body, joints)
        for bad in ("/api/mounts/mnt_0000000000000000", f"/api/mounts/{self.mount_id}/shapes/9999",
                    f"/api/mounts/{self.mount_id}/shapes/-1", f"/api/mounts/{self.mount_id}/other/0"):
            self.assertEqual(self.get(bad)[0], 404, bad)
        for token in (None, "wrong"):
            status, body = self.get(f"/api/mounts/{self.mount_id}", token=token)
            self.assertEqual(status, 401)
            self.assertNotIn(self.ur5.robot_id.encode(), body)

    def test_browser_draws_the_robot(self):
        url = f"http://{self.web}/?scene={self.scene.scene_id}#token={TOKEN}"
        shot = os.path.join(self.tmp.name, "robot.png")
        seen = run_page(self, "view_page.js", url, shot, "640x480")
        self.assertEqual(seen["consoleErrors"], [])
        self.assertEqual(seen["errorText"], "")
        [robot] = seen["view"]["robots"]
        self.assertEqual(robot["mount_id"], self.mount_id)
        # Set VSCAN_WEB_SCREENSHOT to keep the picture (docs/images/web_robot.png is made so).
        if os.environ.get("VSCAN_WEB_SCREENSHOT"):
            shutil.copyfile(shot, os.environ["VSCAN_WEB_SCREENSHOT"])
        with open(shot, "rb") as f:
            image = read_png(f.read()).astype(int)
        # The arm fills the framed view: grey link pixels (equal channels), well off the background.
        grey = (np.abs(image - BACKGROUND).max(axis=2) > 40) & (np.ptp(image, axis=2) < 12)
        self.assertGreater(grey.mean(), 0.02)
        for x, y in robot["link_pixels"]:
            if 2 <= x < 638 and 2 <= y < 478:
                self.assertTrue(grey[y - 2:y + 3, x - 2:x + 3].any(), (x, y))


class _WithToken:
    """A robot stub whose calls carry the bearer token."""

    def __init__(self, stub, auth):
        self.stub, self.auth = stub, auth

    def __getattr__(self, name):
        call = getattr(self.stub, name)
        return lambda request, **kwargs: call(request, metadata=self.auth, **kwargs)


class WebViewCommandTest(unittest.TestCase):
    """`vscan view ID` names the view of a scene, a job by its kind, or a stored cloud; it opens a
    browser only when there is a display and a terminal."""

    @classmethod
    def setUpClass(cls):
        cls.web = f"127.0.0.1:{free_port()}"
        cls.server = Server(extra_args=("--web-listen", cls.web)).start()
        cls.addClassCleanup(cls.server.cleanup)
        cls.fx = CampaignFixture(cls.server)
        cls.addClassCleanup(cls.fx.close)
        started = cls.fx.jobs.StartCampaign(job_pb2.StartCampaignRequest(spec=spec(
            cls.fx.scene.scene_id, cls.fx.mount, viewpoints=[((0.25, 0.0, 0.30), (0.0, 0.0, 0.11))], rotations=1,
            step=90.0, seed=3)))
        cls.job_id = started.job.job_id

    def view(self, *args, env=None):
        return subprocess.run([VSCAN, "--server", self.server.address, "--json", "view", *args, "--web", self.web],
                              capture_output=True, text=True, timeout=30, env=env)

    def test_ids_choose_their_view(self):
        for id_, query in ((self.fx.scene.scene_id, "scene"), (self.job_id, "job"), ("cld_0123456789abcdef", "cloud")):
            run = self.view(id_)
            self.assertEqual(run.returncode, 0, run.stderr)
            self.assertEqual(json.loads(run.stdout), {"url": f"http://{self.web}/?{query}={id_}", "opened": False})
        run = self.view("job_0000000000000000")
        self.assertEqual(run.returncode, 3, run.stderr)  # NOT_FOUND from the server
        self.assertIn("NOT_FOUND", run.stderr)
        run = self.view("robot-1")
        self.assertEqual(run.returncode, 2)
        self.assertIn("ID", run.stderr)

    def test_opens_a_browser_only_with_a_display_and_a_terminal(self):
        with tempfile.TemporaryDirectory() as tmp:
            opened = os.path.join(tmp, "opened")
            fake = os.path.join(tmp, "xdg-open")
            with open(fake, "w") as f:
                f.write(f"#!/bin/sh\necho \"$1\" > {opened}\n")
            os.chmod(fake, stat.S_IRWXU)
            env = {**os.environ, "PATH": tmp + os.pathsep + os.environ["PATH"], "DISPLAY": ":7"}
            command = f"{VSCAN} view {self.fx.scene.scene_id} --web {self.web}"
            # Under a terminal (script gives the command one) with a display: opened.
            run = subprocess.run(["script", "-qec", command, "/dev/null"], capture_output=True, text=True,
                                 timeout=30, env=env)
            self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
            url = f"http://{self.web}/?scene={self.fx.scene.scene_id}"
            for _ in range(100):
                if os.path.exists(opened):
                    break
                subprocess.run(["sleep", "0.05"])
            with open(opened) as f:
                self.assertEqual(f.read().strip(), url)
            os.remove(opened)
            # --no-open, no terminal, or no display: only printed.
            for args, environment in ((["script", "-qec", command + " --no-open", "/dev/null"], env),
                                      (command.split(), env),
                                      (["script", "-qec", command, "/dev/null"],
                                       {k: v for k, v in env.items() if k != "DISPLAY"})):
                run = subprocess.run(args, capture_output=True, text=True, timeout=30, env=environment)
                self.assertEqual(run.returncode, 0, run.stdout + run.stderr)
                self.assertIn(url, run.stdout)
            subprocess.run(["sleep", "0.5"])
            self.assertFalse(os.path.exists(opened))


def make_certs(directory):
    subprocess.run([os.path.join(SOURCE_DIR, "scripts", "make-test-certs.sh"), directory], check=True,
                   capture_output=True, timeout=60)
    return lambda name: os.path.join(directory, name)


class WebViewTlsTest(unittest.TestCase):
    """With --tls-cert and --tls-key the web view speaks HTTPS with gRPC's certificate; with
    --tls-client-ca it wants a client certificate that CA signed."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-web-tls-")
        cls.addClassCleanup(cls.tmp.cleanup)
        cls.cert = staticmethod(make_certs(cls.tmp.name))

    def start(self, mutual):
        web = f"127.0.0.1:{free_port()}"
        args = ["--web-listen", web, "--tls-cert", self.cert("server.crt"), "--tls-key", self.cert("server.key")]
        if mutual:
            args += ["--tls-client-ca", self.cert("ca.crt")]
        server = Server(extra_args=args).start()
        self.addCleanup(server.cleanup)
        return web

    def fetch(self, url, client_cert=False):
        context = ssl.create_default_context(cafile=self.cert("ca.crt"))
        context.check_hostname = False
        if client_cert:
            context.load_cert_chain(self.cert("client.crt"), self.cert("client.key"))
        with urllib.request.urlopen(url, timeout=10, context=context) as response:
            return response.status, response.read()

    def test_https_with_the_grpc_certificate(self):
        web = self.start(mutual=False)
        status, body = self.fetch(f"https://{web}/api/scenes")
        self.assertEqual(status, 200)
        self.assertIn(b'"scenes"', body)
        # Plain HTTP gets no answer from a TLS port.
        with self.assertRaises((urllib.error.URLError, ConnectionError, OSError)):
            urllib.request.urlopen(f"http://{web}/api/scenes", timeout=10).read()
        # A client that does not trust the CA refuses the server.
        with self.assertRaises(urllib.error.URLError):
            urllib.request.urlopen(f"https://{web}/api/scenes", timeout=10, context=ssl.create_default_context())

    def test_stalled_clients_leave_the_https_port_answering(self):
        web = self.start(mutual=False)
        host, port = web.split(":")
        # Twelve connections that never start the handshake, and one that sends half a request.
        stalled = [socket.create_connection((host, int(port)), timeout=10) for _ in range(12)]
        context = ssl.create_default_context(cafile=self.cert("ca.crt"))
        context.check_hostname = False
        half = context.wrap_socket(socket.create_connection((host, int(port)), timeout=10))
        half.sendall(b"GET /api/scenes HTTP/1.1\r\nHost: x\r\n")
        stalled.append(half)
        try:
            started = time.monotonic()
            self.assertEqual(self.fetch(f"https://{web}/api/scenes")[0], 200)
            self.assertLess(time.monotonic() - started, 3)
        finally:
            for connection in stalled:
                connection.close()

    def test_client_certificates_with_a_client_ca(self):
        web = self.start(mutual=True)
        self.assertEqual(self.fetch(f"https://{web}/api/scenes", client_cert=True)[0], 200)
        with self.assertRaises((urllib.error.URLError, ConnectionError, ssl.SSLError, OSError)):
            self.fetch(f"https://{web}/api/scenes")


if __name__ == "__main__":
    unittest.main()
