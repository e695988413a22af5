"""Ray-cast scans stream while they are cast: a slow client holds the cast back instead of the
server buffering the cloud, and a client that cancels stops the cast at once."""

import re
import time
import unittest

import grpc

from harness import ServerTestCase, icosphere_ply, look_at, pinhole, scan_pb2, scene_pb2
from vscan.v1 import scan_pb2_grpc

SIZE = 4096
CANCELLED_LINE = re.compile(r"scan of (\S+): cancelled after (\d+) of (\d+) rows; "
                            r"the cast stopped ([0-9.]+) ms after the cancel")


def memory_kib(pid):
    """VmRSS and VmHWM of a process, in KiB."""
    values = {}
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            key, _, rest = line.partition(":")
            if key in ("VmRSS", "VmHWM"):
                values[key] = int(rest.split()[0])
    return values["VmRSS"], values["VmHWM"]


class StreamScanTest(ServerTestCase):
    server_args = ("--max-rays", str(SIZE * SIZE), "--stalled-reader-seconds", "600")

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        mesh = cls.upload_bytes(cls, icosphere_ply(1.0, (0.0, 0.0, 0.0), 3), "sphere.ply")
        cls.scene_id = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="stream")).scene.scene_id
        cls.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=cls.scene_id, mesh_id=mesh.mesh_id))

    def request(self, size):
        # The sphere fills the view: every ray hits, 36 bytes a point with the default fields.
        return scan_pb2.ScanRequest(scene_id=self.scene_id, sensor=pinhole(size, size, 15.0, near=0.1, far=10.0),
                                    pose=look_at((0.0, -3.0, 0.0), (0.0, 0.0, 0.0)))

    def own_stub(self):
        channel = grpc.insecure_channel(self.server.address, options=[("grpc.use_local_subchannel_pool", 1)])
        return channel, scan_pb2_grpc.ScanServiceStub(channel)

    def cancelled_line(self, seen_before):
        """The server's account of the cancelled scan (waits for it to be logged)."""
        deadline = time.time() + 10
        while time.time() < deadline:
            with open(self.server.log_path, errors="replace") as f:
                matches = CANCELLED_LINE.findall(f.read())
            if len(matches) > seen_before:
                _, rows, height, ms = matches[seen_before]
                return int(rows), int(height), float(ms)
            time.sleep(0.05)
        self.fail("no cancellation line in the server log: " + self.server.log())

    def count_cancelled_lines(self):
        with open(self.server.log_path, errors="replace") as f:
            return len(CANCELLED_LINE.findall(f.read()))

    def test_a_slow_reader_holds_back_the_cast_not_server_memory(self):
        list(self.scans.Scan(self.request(256), timeout=60))  # threads and buffers warmed up
        pid = self.server.process.pid
        rss_before, _ = memory_kib(pid)
        before = self.count_cancelled_lines()

        channel, stub = self.own_stub()
        call = stub.Scan(self.request(SIZE), timeout=300)
        header = next(call).header
        self.assertEqual(header.rays, SIZE * SIZE)
        self.assertEqual(header.points, 0)  # streamed: not known before the cast
        chunks, peak_kib = 0, 0
        start = time.time()
        for response in call:
            chunks += response.WhichOneof("part") == "chunk"
            peak_kib = max(peak_kib, memory_kib(pid)[1])
            if time.time() - start > 3.0:
                break
            time.sleep(0.05)
        call.cancel()
        channel.close()
        rows, height, _ = self.cancelled_line(before)
        peak_kib = max(peak_kib, memory_kib(pid)[1])

        self.assertGreaterEqual(chunks, 30)
        # The whole cloud is 576 MiB; the cast got no further than the client's reading allows.
        self.assertEqual(height, SIZE)
        self.assertLess(rows, SIZE // 2)
        growth_mib = (peak_kib - rss_before) / 1024
        self.assertLess(growth_mib, 64, f"server grew by {growth_mib:.1f} MiB while a slow client read")

    def test_cancel_stops_the_cast_within_50_ms(self):
        for slow in (False, True):
            with self.subTest(client="stalled" if slow else "reading"):
                before = self.count_cancelled_lines()
                channel, stub = self.own_stub()
                call = stub.Scan(self.request(SIZE), timeout=300)
                self.assertEqual(next(call).WhichOneof("part"), "header")
                self.assertEqual(next(call).WhichOneof("part"), "chunk")
                if slow:
                    time.sleep(1.0)  # the window fills and the cast pauses
                else:
                    for _ in range(20):
                        next(call)
                call.cancel()
                channel.close()
                rows, height, stopped_ms = self.cancelled_line(before)
                self.assertLess(rows, height)
                self.assertLess(stopped_ms, 50.0)

        # The server is free for the next scan, which runs to its end.
        parts = [r.WhichOneof("part") for r in self.scans.Scan(self.request(64), timeout=60)]
        self.assertEqual(parts[-1], "statistics")


    def test_default_chunks_hold_at_most_32768_points(self):
        def chunk_counts(fields, chunk_bytes=0):
            request = self.request(512)  # 262,144 points
            request.fields.extend(fields)
            request.chunk_bytes = chunk_bytes
            return [r.chunk.count for r in self.scans.Scan(request, timeout=60) if r.WhichOneof("part") == "chunk"]

        positions = [scan_pb2.POINT_FIELD_POSITION]
        # 12 bytes a point: a MiB would be 87,381 points, a third of this frame before the first chunk.
        self.assertEqual(chunk_counts(positions)[:-1], [32768] * 7)
        self.assertEqual(chunk_counts(positions, 1 << 20)[0], (1 << 20) // 12)
        # 36 bytes a point (the default fields): the MiB is the smaller bound.
        self.assertEqual(chunk_counts([])[0], (1 << 20) // 36)

if __name__ == "__main__":
    unittest.main()
