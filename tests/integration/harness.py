"""Starts a real vscand on a free port with its own data directory, for integration tests."""

import json
import os
import signal
import struct
import subprocess
import sys
import tempfile
import time
import unittest
import zlib

BUILD_DIR = os.environ["VSCAN_BUILD_DIR"]
SOURCE_DIR = os.environ["VSCAN_SOURCE_DIR"]
VSCAND = os.path.join(BUILD_DIR, "server", "vscand")
VSCAN = os.path.join(BUILD_DIR, "client", "cli", "vscan")
VSCAN_LOAD = os.path.join(BUILD_DIR, "bench", "load", "vscan-load")
DATA = os.path.join(SOURCE_DIR, "data")
BUNNY = os.path.join(DATA, "meshes", "bunny", "bunny_zipper_res2.ply")

sys.path.insert(0, os.path.join(BUILD_DIR, "python"))
sys.path.insert(0, os.path.join(SOURCE_DIR, "client", "python"))

import grpc  # noqa: E402
import numpy as np  # noqa: E402
from vscan.v1 import common_pb2, scan_pb2, scan_pb2_grpc, scene_pb2, scene_pb2_grpc, sensor_pb2  # noqa: E402,F401


def cli_result(stdout):
    """The result object of `vscan --json ...`: what follows a job's event lines (one JSON object each)."""
    return json.loads("\n".join(line for line in stdout.splitlines() if not line.startswith('{"event":')))


def cli_events(stdout):
    """The event lines `vscan --json` streamed while a job ran."""
    return [json.loads(line) for line in stdout.splitlines() if line.startswith('{"event":')]


class Server:
    """One vscand process; restartable on the same data directory."""

    def __init__(self, data_dir=None, extra_args=(), wrapper=()):
        """wrapper: a command vscand is started under (it must exec vscand, keeping its pid)."""
        self._tmp = None
        if data_dir is None:
            self._tmp = tempfile.TemporaryDirectory(prefix="vscand-test-")
            data_dir = self._tmp.name
        self.data_dir = data_dir
        self.extra_args = list(extra_args)
        self.wrapper = list(wrapper)
        self.process = None
        self.port = None
        self.log_path = os.path.join(self.data_dir, "vscand.log")

    @property
    def address(self):
        return f"127.0.0.1:{self.port}"

    def start(self):
        port_file = os.path.join(self.data_dir, "port")
        if os.path.exists(port_file):
            os.remove(port_file)
        with open(self.log_path, "ab") as log:
            self.process = subprocess.Popen(
                [*self.wrapper, VSCAND, "--listen", "127.0.0.1:0", "--port-file", port_file,
                 "--data-dir", os.path.join(self.data_dir, "store"), "--log-level", "debug", *self.extra_args],
                stdout=log, stderr=log)
        deadline = time.time() + 30
        while time.time() < deadline:
            if os.path.exists(port_file):
                with open(port_file) as f:
                    self.port = int(f.read().strip())
                return self
            if self.process.poll() is not None:
                raise RuntimeError(f"vscand exited with {self.process.returncode}: {self.log()}")
            time.sleep(0.05)
        raise RuntimeError("vscand did not start in 30 s")

    def kill9(self):
        self.process.send_signal(signal.SIGKILL)
        self.process.wait(timeout=30)

    def stop(self, timeout=30):
        if self.process and self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            return self.process.wait(timeout=timeout)
        return self.process.returncode if self.process else None

    def log(self):
        try:
            with open(self.log_path, errors="replace") as f:
                return f.read()[-4000:]
        except OSError:
            return ""

    def channel(self):
        return grpc.insecure_channel(self.address)

    def cleanup(self):
        self.stop()
        if self._tmp:
            self._tmp.cleanup()


class ServerTestCase(unittest.TestCase):
    """A fresh server per test class, with raw stubs at hand."""

    server_args = ()

    @classmethod
    def setUpClass(cls):
        cls.server = Server(extra_args=cls.server_args).start()
        cls.channel = cls.server.channel()
        cls.scenes = scene_pb2_grpc.SceneServiceStub(cls.channel)
        cls.scans = scan_pb2_grpc.ScanServiceStub(cls.channel)

    @classmethod
    def tearDownClass(cls):
        cls.channel.close()
        cls.server.cleanup()

    def upload(self, path, unit=common_pb2.LENGTH_UNIT_METRE, name=None, chunk=1 << 20, scale=0.0):
        with open(path, "rb") as f:
            data = f.read()
        return self.upload_bytes(data, name or os.path.basename(path), unit, chunk, scale)

    def upload_bytes(self, data, name, unit=common_pb2.LENGTH_UNIT_METRE, chunk=1 << 20, scale=0.0):
        def requests():
            yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                name=name, unit=unit, scale=scale, size_bytes=len(data)))
            for i in range(0, len(data), chunk):
                yield scene_pb2.UploadMeshRequest(chunk=data[i:i + chunk])
        return self.scenes.UploadMesh(requests(), timeout=60).mesh

    def assertCode(self, code, call, field=None):
        with self.assertRaises(grpc.RpcError) as ctx:
            result = call()
            if hasattr(result, "__iter__") and not isinstance(result, (bytes, str)):
                list(result)
        self.assertEqual(ctx.exception.code(), code, ctx.exception.details())
        if field:
            self.assertIn(field, ctx.exception.details())
        return ctx.exception


def look_at(eye, target, up=(0, 0, 1)):
    return common_pb2.Pose(look_at=common_pb2.LookAt(
        eye=common_pb2.Vector3(x=eye[0], y=eye[1], z=eye[2]),
        target=common_pb2.Vector3(x=target[0], y=target[1], z=target[2]),
        up=common_pb2.Vector3(x=up[0], y=up[1], z=up[2])))


def pinhole(width=160, height=120, hfov=60.0, near=0.05, far=10.0):
    return sensor_pb2.SensorSpec(pinhole=sensor_pb2.PinholeCamera(
        width=width, height=height, horizontal_fov_deg=hfov, near=near, far=far))


def scan_points(channel, scene_id):
    """Positions of a small fixed scan of the scene, as an (n, 3) array."""
    scans = scan_pb2_grpc.ScanServiceStub(channel)
    request = scan_pb2.ScanRequest(scene_id=scene_id, sensor=pinhole(160, 120, 40.0),
                                   pose=look_at((0.0, -0.6, 0.1), (0.0, 0.0, 0.1)))
    chunks = [r.chunk for r in scans.Scan(request, timeout=60) if r.WhichOneof("part") == "chunk"]
    return np.concatenate([np.frombuffer(c.positions, dtype="<f4").reshape(-1, 3) for c in chunks])


def icosphere_ply(radius, centre, subdivisions=4):
    """ASCII PLY of an icosphere: an independent mesh with a known surface."""
    import math
    t = (1 + math.sqrt(5)) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
             (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        cache = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(verts[a][i] + verts[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                verts.append(tuple(x / n for x in m))
                cache[key] = len(verts) - 1
            return cache[key]
        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    lines = ["ply", "format ascii 1.0", f"element vertex {len(verts)}", "property float x", "property float y",
             "property float z", f"element face {len(faces)}", "property list uchar int vertex_indices", "end_header"]
    lines += [f"{v[0] * radius + centre[0]:.9f} {v[1] * radius + centre[1]:.9f} {v[2] * radius + centre[2]:.9f}"
              for v in verts]
    lines += [f"3 {a} {b} {c}" for a, b, c in faces]
    return ("\n".join(lines) + "\n").encode()


def status_mib(pid, key):
    """A memory line of /proc/PID/status (VmHWM: the peak resident size, VmRSS: the current one), in MiB."""
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024
    raise RuntimeError(f"no {key}")


def pixel_cloud(columns, rows, spacing, depth):
    """A wall `depth` metres in front of the sensor (sensor frame), one point a pixel, `spacing` apart."""
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {columns * rows}\nproperty float x\nproperty float y\nproperty float z\n"
              "property int pixel\nend_header\n")
    points = np.zeros(columns * rows, dtype=[("xyz", "<f4", 3), ("pixel", "<i4")])
    v, u = np.divmod(np.arange(columns * rows), columns)
    points["xyz"][:, 0] = (u - columns / 2 + 0.5) * spacing
    points["xyz"][:, 1] = (v - rows / 2 + 0.5) * spacing
    points["xyz"][:, 2] = depth
    points["pixel"] = v * columns + u
    return header.encode() + points.tobytes()


def torus_ply(path, around, tube, major=0.05, minor=0.02):
    """A closed torus of around x tube quads (2 x around x tube triangles), binary PLY in metres."""
    i, j = np.meshgrid(np.arange(around), np.arange(tube), indexing="ij")
    u, v = 2 * np.pi * i / around, 2 * np.pi * j / tube
    r = major + minor * np.cos(v)
    vertices = np.stack([r * np.cos(u), r * np.sin(u), minor * np.sin(v)], axis=-1).reshape(-1, 3)
    a = (i * tube + j).ravel()
    b = (((i + 1) % around) * tube + j).ravel()
    c = (((i + 1) % around) * tube + (j + 1) % tube).ravel()
    d = (i * tube + (j + 1) % tube).ravel()
    faces = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    records = np.zeros(len(faces), dtype=[("n", "u1"), ("v", "<i4", 3)])
    records["n"], records["v"] = 3, faces
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                 "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(vertices), len(faces))).encode())
        f.write(vertices.astype("<f4").tobytes())
        f.write(records.tobytes())


def small_scan_seconds(client, scene_id):
    """Seconds a 64 x 48 scan of scene_id takes, and the scan: what shows a server still serving."""
    start = time.monotonic()
    scan = client.scan(scene_id, width=64, height=48, eye=(0.5, 0, 0.2), target=(0, 0, 0.07))
    return time.monotonic() - start, scan


def assert_streams_cancelled(test, streams, channels):
    """Every stream ends CANCELLED (its reader stalled past the server's bound); the channels close."""
    for stream in streams:
        with test.assertRaises(grpc.RpcError) as cancelled:
            for _ in stream:
                pass
        test.assertEqual(cancelled.exception.code(), grpc.StatusCode.CANCELLED, cancelled.exception.details())
    for channel in channels:
        channel.close()


def read_png(data):
    """An independent decoder for 8-bit RGB or RGBA non-interlaced PNG (its bytes or its path): an
    (height, width, 3) uint8 array."""
    if isinstance(data, (str, os.PathLike)):
        with open(data, "rb") as f:
            data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
        pos += 12 + length
    width, height, depth, colour_type, _, _, interlace = header
    assert depth == 8 and colour_type in (2, 6) and interlace == 0, header
    bpp = 3 if colour_type == 2 else 4
    stride = width * bpp
    raw = zlib.decompress(idat)
    out = np.zeros((height, stride), np.int64)
    prev = np.zeros(stride, np.int64)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int64)
        if kind == 0:
            cur = line
        elif kind == 2:
            cur = (line + prev) & 0xFF
        else:
            cur = line.tolist()
            up = prev.tolist()
            for x in range(stride):
                a = cur[x - bpp] if x >= bpp else 0
                b = up[x]
                if kind == 1:
                    cur[x] = (cur[x] + a) & 0xFF
                elif kind == 3:
                    cur[x] = (cur[x] + (a + b) // 2) & 0xFF
                else:
                    c = up[x - bpp] if x >= bpp else 0
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    cur[x] = (cur[x] + (a if pa <= pb and pa <= pc else (b if pb <= pc else c))) & 0xFF
            cur = np.array(cur, np.int64)
        out[y] = cur
        prev = cur
    return out.astype(np.uint8).reshape(height, width, bpp)[:, :, :3]
