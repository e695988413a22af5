"""Stopping a busy server: SIGTERM cancels running calls once --grace-seconds is over and the
server exits within seconds even when work ignores the cancellation; kill -9 takes the mesh-import
helper down with the server."""

import os
import signal
import subprocess
import threading
import time
import unittest

import grpc

from harness import Server, common_pb2, icosphere_ply, look_at, pinhole, scan_pb2, scene_pb2
from vscan.v1 import scan_pb2_grpc, scene_pb2_grpc

SPHERE = icosphere_ply(1.0, (0.0, 0.0, 0.0), 3)


def full_log(server):
    with open(server.log_path, errors="replace") as f:
        return f.read()


def upload(channel, data):
    def requests():
        yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
            name="sphere.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data)))
        yield scene_pb2.UploadMeshRequest(chunk=data)
    return scene_pb2_grpc.SceneServiceStub(channel).UploadMesh(requests(), timeout=120).mesh


def in_background(call):
    """Runs call on a thread; the returned dict gets 'result' or 'error'."""
    outcome = {}

    def run():
        try:
            outcome["result"] = call()
        except grpc.RpcError as e:
            outcome["error"] = e
    threading.Thread(target=run, daemon=True).start()
    return outcome


def helpers_of(pid):
    """Pids of the vscan-mesh-import processes whose parent is pid."""
    found = []
    for entry in os.listdir("/proc"):
        try:
            with open(f"/proc/{entry}/stat") as f:
                stat = f.read()
        except (OSError, ValueError):
            continue
        name, rest = stat[stat.index("(") + 1:stat.rindex(")")], stat[stat.rindex(")") + 2:].split()
        if name.startswith("vscan-mesh-imp") and int(rest[1]) == pid and rest[0] != "Z":
            found.append(int(entry))
    return found


def running(pid):
    """Alive and not a zombie waiting to be reaped by its new parent."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            stat = f.read()
    except OSError:
        return False
    return stat[stat.rindex(")") + 2] != "Z"


def wait_for(predicate, seconds):
    deadline = time.time() + seconds
    while time.time() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    return predicate()


class ShutdownTest(unittest.TestCase):
    def start_server(self, *args, env=None):
        saved = dict(os.environ)
        os.environ.update(env or {})
        try:
            server = Server(extra_args=("--grace-seconds", "1", *args)).start()
        finally:
            os.environ.clear()
            os.environ.update(saved)
        self.addCleanup(server.cleanup)
        return server

    def stop_within(self, server, seconds):
        server.process.send_signal(signal.SIGTERM)
        try:
            code = server.process.wait(timeout=seconds)
        except subprocess.TimeoutExpired:
            server.kill9()
            self.fail(f"vscand was still running {seconds} s after SIGTERM")
        return code

    def test_sigterm_cancels_a_busy_scan(self):
        server = self.start_server("--max-rays", str(1 << 25), "--max-request-memory-mib", "8192")
        channel = server.channel()
        self.addCleanup(channel.close)
        mesh = upload(channel, SPHERE)
        scenes = scene_pb2_grpc.SceneServiceStub(channel)
        scene_id = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="busy")).scene.scene_id
        scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene_id, mesh_id=mesh.mesh_id))
        request = scan_pb2.ScanRequest(
            scene_id=scene_id, sensor=pinhole(4096, 4096, 15.0, near=0.1, far=10.0),
            pose=look_at((0.0, -3.0, 0.0), (0.0, 0.0, 0.0)),
            fields=[scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_ESTIMATED_NORMAL],
            normal_estimation=scan_pb2.NormalEstimation(k=64))
        scan = in_background(lambda: list(scan_pb2_grpc.ScanServiceStub(channel).Scan(request, timeout=600)))
        time.sleep(2)
        self.assertEqual(scan, {}, "the scan ended before SIGTERM; it should keep the server busy")

        code = self.stop_within(server, 15)
        self.assertIn(code, (0, 1))
        log = full_log(server)
        self.assertIn(f"scan of {scene_id}: call cancelled", log[log.index("received SIGTERM"):])
        self.assertNotIn("result", scan)

    def test_sigterm_stops_a_server_whose_work_ignores_cancellation(self):
        # The helper hangs; the upload waits for it until --mesh-import-timeout, far beyond the grace.
        server = self.start_server("--mesh-import-timeout", "120", env={"VSCAN_MESH_IMPORT_TEST_CRASH": "hang"})
        channel = server.channel()
        self.addCleanup(channel.close)
        in_background(lambda: upload(channel, SPHERE))
        helpers = wait_for(lambda: helpers_of(server.process.pid), 20)
        self.assertTrue(helpers, "the mesh-import helper never started")

        code = self.stop_within(server, 15)
        self.assertEqual(code, 1)
        self.assertIn("exiting without them", full_log(server))
        self.assertTrue(wait_for(lambda: not any(running(p) for p in helpers), 5), "the helper outlived the server")

    def test_kill9_takes_the_mesh_import_helper_down(self):
        server = self.start_server("--mesh-import-timeout", "120", env={"VSCAN_MESH_IMPORT_TEST_CRASH": "hang"})
        channel = server.channel()
        self.addCleanup(channel.close)
        in_background(lambda: upload(channel, SPHERE))
        helpers = wait_for(lambda: helpers_of(server.process.pid), 20)
        self.assertTrue(helpers, "the mesh-import helper never started")
        server.kill9()
        gone = wait_for(lambda: not any(running(p) for p in helpers), 3)
        for pid in helpers:
            if running(pid):
                os.kill(pid, signal.SIGKILL)
        self.assertTrue(gone, "the mesh-import helper outlived the server")


if __name__ == "__main__":
    unittest.main()
