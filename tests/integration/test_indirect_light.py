"""One-bounce indirect light through a real vscand, the CLI and the Python client, in concave corners
of two white walls placed through the API: a time-of-flight camera measures the corner behind its
true surface (multipath) and a plain camera only brighter, a structured-light scanner refuses the
grazing wall's pixels by the fold as interreflection, and bad values are refused naming their field."""

import math
import os
import subprocess
import tempfile
import unittest

import grpc
import numpy as np

from harness import VSCAN, Server
from vscan import Client, VscanError
from vscan.v1 import common_pb2, scan_pb2, sensor_pb2

C = grpc.StatusCode

# Lambertian (F0 = 0): the BRDF is albedo / pi.
WHITE = {"diffuse_albedo": 0.9, "metallic": 0.0, "roughness": 1.0, "specular_reflectance": 0.0}
IDENTITY = np.eye(4)  # world_from_sensor: the sensor frame is the world (x right, y down, z forward)
MEASURED = scan_pb2.POINT_STATUS_MEASURED
INTERREFLECTION = scan_pb2.POINT_STATUS_REJECTED_INTERREFLECTION


def wall_ply(path, fold, along, length, half_height):
    """A rectangle from the fold line (through fold, along y, |y| <= half_height) out along `along`."""
    fold, along = np.asarray(fold, float), np.asarray(along, float)
    corners = [fold + (0, -half_height, 0), fold + (0, half_height, 0),
               fold + along * length + (0, half_height, 0), fold + along * length + (0, -half_height, 0)]
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n")
        for c in corners:
            f.write(f"{c[0]} {c[1]} {c[2]}\n")
        f.write("3 0 1 2\n3 0 2 3\n")


# ToF corner: fold 1 m ahead, the walls at 45 degrees each side, both facing the camera.
S2 = math.sqrt(0.5)
TOF = {"fold": (0.0, 0.0, 1.0), "a": (S2, 0.0, -S2), "b": (-S2, 0.0, -S2), "length": 0.6, "half_height": 0.6}
# Structured-light corner, for a projector 0.35 m to the camera's right: wall A (to the left) faces
# the projector, wall B (to the right) takes its light at about 86 degrees.
ALPHA = math.radians(25)
SL = {"fold": (0.0, 0.0, 0.9), "a": (-math.cos(ALPHA), 0.0, -math.sin(ALPHA)),
      "b": (math.sin(ALPHA), 0.0, -math.cos(ALPHA)), "length": 0.35, "half_height": 0.3}


class IndirectLightTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.server = Server().start()
        cls.client = Client(cls.server.address)
        cls.scenes, cls.walls = {}, {}
        for name, corner in (("tof", TOF), ("sl", SL)):
            scene = cls.client.create_scene("corner-" + name).scene_id
            ids = {}
            for wall in ("a", "b"):
                path = os.path.join(cls.tmp.name, f"{name}-{wall}.ply")
                wall_ply(path, corner["fold"], corner[wall], corner["length"], corner["half_height"])
                mesh = cls.client.upload_mesh(path, "m", material=WHITE).mesh_id
                ids[wall] = cls.client.add_object(scene, mesh).instance_id
            cls.scenes[name], cls.walls[name] = scene, ids

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()
        cls.tmp.cleanup()

    def scan(self, name, light, **kw):
        return self.client.scan(self.scenes[name], pose_matrix=IDENTITY, frame="sensor", seed=5,
                                fields=["position", "intensity", "instance", "clean", "status"],
                                include_rejected=True, returned_light=light, **kw)

    def from_fold(self, name, result):
        corner = SL if name == "sl" else TOF
        clean = np.asarray(result.clean_positions, float) - corner["fold"]
        instances = np.asarray(result.instance_ids)
        along = np.where(instances == self.walls[name]["a"], clean @ np.asarray(corner["a"]),
                         clean @ np.asarray(corner["b"]))
        return along, instances

    def tof_bias_by_the_fold(self, result):
        along, instances = self.from_fold("tof", result)
        statuses = np.asarray(result.statuses)
        chosen = (instances == self.walls["tof"]["a"]) & (along > 0.03) & (along < 0.3) & (statuses == MEASURED)
        self.assertGreater(int(np.sum(chosen)), 1000)
        measured = np.linalg.norm(result.positions[chosen], axis=1)
        true = np.linalg.norm(result.clean_positions[chosen], axis=1)
        return float(np.mean(measured - true)), result.intensities[chosen]

    def test_a_time_of_flight_camera_measures_the_corner_behind_its_surface(self):
        light = {"emitter_w_per_sr": 0.005}
        direct_bias, direct_e = self.tof_bias_by_the_fold(self.scan("tof", light, preset="kinect-v2-class"))
        bias, electrons = self.tof_bias_by_the_fold(
            self.scan("tof", dict(light, indirect_samples=64), preset="kinect-v2-class"))
        # The preset's 1.5 mm noise averages out over thousands of pixels; the multipath bias does
        # not (a few centimetres by the fold, tests/unit/capture/indirect_light_test.cpp).
        self.assertLess(abs(direct_bias), 0.001)
        self.assertGreater(bias, 0.015)
        self.assertGreater(np.mean(electrons) / np.mean(direct_e), 1.15)  # the indirect light adds signal

    def test_a_plain_camera_gets_brighter_but_not_biased_unless_it_measures_time_of_flight(self):
        camera = {"width": 160, "height": 120, "hfov_deg": 60, "near": 0.3, "far": 3.0}
        light = {"emitter_w_per_sr": 0.002, "indirect_samples": 32}
        bias, electrons = self.tof_bias_by_the_fold(self.scan("tof", light, **camera))
        self.assertEqual(bias, 0.0)
        _, direct_e = self.tof_bias_by_the_fold(self.scan("tof", {"emitter_w_per_sr": 0.002}, **camera))
        self.assertGreater(np.mean(electrons) / np.mean(direct_e), 1.15)
        tof_bias, _ = self.tof_bias_by_the_fold(self.scan("tof", dict(light, modulation_frequency_hz=20e6), **camera))
        self.assertGreater(tof_bias, 0.015)

    def sl_sensor(self):
        scanner = sensor_pb2.StructuredLightScanner(projector_offset=common_pb2.Vector3(x=0.35),
                                                    projector_horizontal_fov_deg=47.5, projector_vertical_fov_deg=36.0,
                                                    convergence_distance=0.805)
        scanner.camera.CopyFrom(sensor_pb2.PinholeCamera(width=256, height=192, horizontal_fov_deg=48.8, near=0.3,
                                                         far=2.0))
        return sensor_pb2.SensorSpec(structured_light=scanner)

    def test_structured_light_refuses_the_grazing_walls_pixels_by_the_fold(self):
        light = {"emitter_w_per_sr": 0.003}
        direct = self.scan("sl", light, sensor=self.sl_sensor())
        self.assertEqual(direct.stats.rejected_interreflection, 0)
        result = self.scan("sl", dict(light, indirect_samples=64), sensor=self.sl_sensor())
        statuses = np.asarray(result.statuses)
        along, instances = self.from_fold("sl", result)
        rejected = statuses == INTERREFLECTION
        self.assertEqual(result.stats.rejected_interreflection, int(np.sum(rejected)))
        on_a, on_b = instances == self.walls["sl"]["a"], instances == self.walls["sl"]["b"]
        by_fold = on_b & (along < 0.05) & ((statuses == MEASURED) | rejected)
        self.assertGreater(int(np.sum(by_fold)), 200)
        self.assertGreater(np.mean(rejected[by_fold]), 0.95)
        self.assertEqual(int(np.sum(rejected & on_a)), 0)  # the facing wall decodes
        self.assertGreater(int(np.sum(on_a & (statuses == MEASURED))), 5000)

    def test_the_raster_backends_keep_the_direct_light(self):
        light = {"emitter_w_per_sr": 0.003}
        for backend in ("depth", "colour"):
            direct = self.scan("sl", light, sensor=self.sl_sensor(), backend=backend)
            with_indirect = self.scan("sl", dict(light, indirect_samples=64), sensor=self.sl_sensor(), backend=backend)
            self.assertEqual(with_indirect.stats.rejected_interreflection, 0, backend)
            self.assertEqual(with_indirect.intensities.tobytes(), direct.intensities.tobytes(), backend)

    def test_refusals_name_the_field(self):
        for light, field in (({"indirect_samples": 1_000_000_000}, "returned_light.indirect_samples"),
                             ({"indirect_samples": 4097}, "returned_light.indirect_samples"),
                             ({"indirect_stride_px": 65}, "returned_light.indirect_stride_px"),
                             ({"modulation_frequency_hz": -1.0}, "returned_light.modulation_frequency_hz"),
                             ({"modulation_frequency_hz": math.nan}, "returned_light.modulation_frequency_hz"),
                             ({"interreflection_ratio": math.inf}, "returned_light.interreflection_ratio")):
            with self.assertRaises(VscanError) as caught:
                self.scan("tof", light, width=32, height=24)
            self.assertEqual(caught.exception.code, C.INVALID_ARGUMENT)
            self.assertIn(field, caught.exception.message)
        # Each bound alone is fine, but every pixel of a VGA frame at 4096 samples is 1.3e9 bounces.
        with self.assertRaises(VscanError) as caught:
            self.scan("tof", {"indirect_samples": 4096, "indirect_stride_px": 1}, width=640, height=480)
        self.assertEqual(caught.exception.code, C.INVALID_ARGUMENT)
        self.assertIn("returned_light.indirect_samples", caught.exception.message)
        # A structured-light sensor does not measure time of flight.
        with self.assertRaises(VscanError) as caught:
            self.scan("sl", {"modulation_frequency_hz": 20e6}, sensor=self.sl_sensor())
        self.assertEqual(caught.exception.code, C.INVALID_ARGUMENT)
        self.assertIn("returned_light.modulation_frequency_hz", caught.exception.message)

    def test_the_cli_prints_interreflection_and_refuses_bad_values(self):
        out_file = os.path.join(self.tmp.name, "scan.ply")
        args = [VSCAN, "--server", self.server.address, "scan", self.scenes["sl"], "-o", out_file,
                "--preset", "phoxi-m-class", "--pose-matrix", ",".join(str(v) for v in IDENTITY.flatten()),
                "--fields", "position"]
        ran = subprocess.run(args + ["--returned-light", "emitter_w_per_sr=0.2,indirect_samples=16,indirect_stride_px=8"],
                             capture_output=True, text=True, timeout=120)
        self.assertEqual(ran.returncode, 0, ran.stderr)
        self.assertRegex(ran.stdout + ran.stderr, r"[1-9]\d* interreflection")
        for value, field in (("indirect_samples=5000", "returned_light.indirect_samples"),
                             ("indirect_stride_px=100", "returned_light.indirect_stride_px"),
                             ("interreflection_ratio=-2", "returned_light.interreflection_ratio")):
            refused = subprocess.run(args + ["--returned-light", value], capture_output=True, text=True, timeout=60)
            self.assertEqual(refused.returncode, 3, refused.stdout + refused.stderr)
            self.assertIn("INVALID_ARGUMENT", refused.stderr)
            self.assertIn(field, refused.stderr)
        for value in ("indirect_samples=1.5", "indirect_samples=-3"):  # the CLI's own checks on a count
            usage = subprocess.run(args + ["--returned-light", value], capture_output=True, text=True, timeout=60)
            self.assertEqual(usage.returncode, 2, usage.stderr)
            self.assertIn("--returned-light", usage.stderr)


if __name__ == "__main__":
    unittest.main()
