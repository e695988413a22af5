"""One data directory, one server: a second vscand on it refuses to start, naming the first, and
touches nothing; the lock goes with the first server however it stops."""

import os
import subprocess
import unittest

from harness import VSCAND, Server, scene_pb2
from vscan.v1 import scene_pb2_grpc


def snapshot(store):
    """Every file of the store but the lock, with its size and modification time."""
    files = {}
    for root, _, names in os.walk(store):
        for name in names:
            path = os.path.join(root, name)
            if name != "vscand.lock":
                st = os.stat(path)
                files[os.path.relpath(path, store)] = (st.st_size, st.st_mtime_ns)
    return files


class DataDirLockTest(unittest.TestCase):
    def start_second(self, store):
        return subprocess.run([VSCAND, "--listen", "127.0.0.1:0", "--data-dir", store],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=30, text=True)

    def test_second_server_refuses_and_lock_is_released(self):
        first = Server().start()
        try:
            store = os.path.join(first.data_dir, "store")
            with first.channel() as channel:
                scenes = scene_pb2_grpc.SceneServiceStub(channel)
                scene = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="mine")).scene
                before = snapshot(store)

                second = self.start_second(store)
                self.assertNotEqual(second.returncode, 0, second.stdout)
                self.assertIn(f"'{store}' is in use by another vscand (pid {first.process.pid})", second.stdout)
                self.assertNotIn("INTERRUPTED", second.stdout)

                self.assertIsNone(first.process.poll())
                self.assertEqual(scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene, scene)
                self.assertEqual(snapshot(store), before)

            self.assertEqual(first.stop(), 0)
            first.start()  # the same data directory, after a clean stop
            first.kill9()
            first.start()  # and after kill -9
            with first.channel() as channel:
                scenes = scene_pb2_grpc.SceneServiceStub(channel)
                self.assertEqual(scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene, scene)
        finally:
            first.cleanup()


if __name__ == "__main__":
    unittest.main()
