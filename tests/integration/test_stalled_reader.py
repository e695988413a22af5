"""A client that stops reading a scan does not keep its slot: after --stalled-reader-seconds
without a read the server cancels the stream, logs it, and the next scan runs."""

import time
import unittest

import grpc

from harness import ServerTestCase, icosphere_ply, look_at, pinhole, scan_pb2, scene_pb2
from vscan.v1 import scan_pb2_grpc

C = grpc.StatusCode


def full_log(server):
    with open(server.log_path, errors="replace") as f:
        return f.read()


class StalledReaderTest(ServerTestCase):
    server_args = ("--max-concurrent-scans", "1", "--stalled-reader-seconds", "1")

    def scan_request(self, size):
        # A sphere that fills the view: every ray hits, some 36 bytes a point with the default fields.
        return scan_pb2.ScanRequest(scene_id=self.scene_id, sensor=pinhole(size, size, 15.0, near=0.1, far=10.0),
                                    pose=look_at((0.0, -3.0, 0.0), (0.0, 0.0, 0.0)))

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        mesh = cls.upload_bytes(cls, icosphere_ply(1.0, (0.0, 0.0, 0.0), 3), "sphere.ply")
        cls.scene_id = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="stall")).scene.scene_id
        cls.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=cls.scene_id, mesh_id=mesh.mesh_id))

    def test_stalled_reader_is_cancelled_and_frees_its_slot(self):
        # Its own connection, so that its full flow-control window cannot hold up the other scans.
        stalled_channel = grpc.insecure_channel(self.server.address, options=[("grpc.use_local_subchannel_pool", 1)])
        stalled = scan_pb2_grpc.ScanServiceStub(stalled_channel).Scan(self.scan_request(2048), timeout=120)
        header = next(stalled).header
        # Every ray hits: some 36 bytes a ray, far more than the windows between us hold.
        self.assertGreater(header.rays * 36 >> 20, 100)

        start = time.time()
        while True:
            try:
                list(self.scans.Scan(self.scan_request(64), timeout=30))
                break
            except grpc.RpcError as e:
                self.assertEqual(e.code(), C.RESOURCE_EXHAUSTED, e.details())
                self.assertLess(time.time() - start, 20, "the stalled scan still holds the only slot")
                time.sleep(0.2)
        self.assertIn(f"scan of {self.scene_id}: the client has not read for 1.0 s; cancelling the call",
                      full_log(self.server))

        parts = []
        try:
            for response in stalled:
                parts.append(response.WhichOneof("part"))
            self.assertNotIn("statistics", parts)
        except grpc.RpcError as e:
            self.assertEqual(e.code(), C.CANCELLED, e.details())
        stalled_channel.close()


if __name__ == "__main__":
    unittest.main()
