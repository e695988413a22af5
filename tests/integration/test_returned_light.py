"""The returned light through a real vscand, the CLI and the Python client: two squares side by side
with materials of known albedo, lit by the camera's own emitter; the dark one is rejected as dark
where the numbers say so, the white one saturates when the emitter is strong, the electrons follow
the albedos, and bad values are refused naming their field."""

import math
import os
import subprocess
import tempfile
import unittest

import grpc
import numpy as np

from harness import VSCAN, Server
from vscan import Client, VscanError
from vscan.v1 import scan_pb2

C = grpc.StatusCode

# Lambertian (no specular lobe: F0 = 0) so the signal is albedo / pi x I cos / r^2.
WHITE = {"diffuse_albedo": 0.9, "metallic": 0.0, "roughness": 1.0, "specular_reflectance": 0.0}
BLACK = {"diffuse_albedo": 0.03, "metallic": 0.0, "roughness": 1.0, "specular_reflectance": 0.0}
EYE, TARGET = (0.0, -0.6, 0.8), (0.0, 0.0, 0.0)  # 1 m away, 37 degrees off the squares' normal


def quad_ply(path, corners):
    """Two triangles over four corners (x, y, z), in order."""
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n")
        for x, y, z in corners:
            f.write(f"{x} {y} {z}\n")
        f.write("3 0 1 2\n3 0 2 3\n")


def square_ply(path, x0, x1):
    """A 0.2 m square on z = 0 from x0 to x1, y in [-0.1, 0.1], facing +z."""
    quad_ply(path, [(x0, -0.1, 0), (x1, -0.1, 0), (x1, 0.1, 0), (x0, 0.1, 0)])


def add_squares(client, directory, scene):
    """The white square right of x = 0 (its mesh's material) and the black one left of it (its
    object's): returns their instance ids (white, black)."""
    left, right = os.path.join(directory, "left.ply"), os.path.join(directory, "right.ply")
    square_ply(left, -0.2, 0.0)
    square_ply(right, 0.0, 0.2)
    white = client.add_object(scene, client.upload_mesh(right, "m", material=WHITE).mesh_id)
    black = client.add_object(scene, client.upload_mesh(left, "m").mesh_id, material=BLACK)
    return white.instance_id, black.instance_id


class ReturnedLightTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.server = Server().start()
        cls.client = Client(cls.server.address)
        cls.scene = cls.client.create_scene("returned-light").scene_id
        cls.white_id, cls.black_id = add_squares(cls.client, cls.tmp.name, cls.scene)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()
        cls.tmp.cleanup()

    def scan(self, backend="raycast", **light):
        return self.client.scan(self.scene, width=160, height=120, hfov_deg=40, eye=EYE, target=TARGET,
                                fields=["position", "intensity", "instance", "status"], include_rejected=True,
                                returned_light=light or True, seed=3, backend=backend)

    def by_object(self, result, status):
        statuses = np.asarray(result.statuses)
        instances = np.asarray(result.instance_ids)
        return {name: np.mean(statuses[instances == oid] == status)
                for name, oid in (("white", self.white_id), ("black", self.black_id))}

    def test_a_dark_material_is_rejected_as_dark_and_a_white_one_measured(self):
        # White: 0.9 / pi x 0.002 W/sr x cos 37 / 1 m^2 x about 8e6 e per unit radiance: about 3700 e;
        # black 30 times less, about 120 e at an SNR near 10. A tenth of the power puts black under 5.
        result = self.scan(emitter_w_per_sr=0.0002)
        dark = self.by_object(result, scan_pb2.POINT_STATUS_REJECTED_DARK)
        measured = self.by_object(result, scan_pb2.POINT_STATUS_MEASURED)
        self.assertGreater(dark["black"], 0.95, dark)
        self.assertEqual(measured["white"], 1.0, measured)
        self.assertEqual(result.stats.rejected_dark, int(np.sum(np.asarray(result.statuses) ==
                                                                 scan_pb2.POINT_STATUS_REJECTED_DARK)))

    def test_the_electrons_follow_the_albedos_and_a_strong_emitter_saturates_the_white(self):
        result = self.scan(emitter_w_per_sr=0.002)
        intensity, instances = np.asarray(result.intensities), np.asarray(result.instance_ids)
        measured = np.asarray(result.statuses) == scan_pb2.POINT_STATUS_MEASURED
        white = intensity[(instances == self.white_id) & measured]
        black = intensity[(instances == self.black_id) & measured]
        self.assertGreater(len(white), 1000)
        self.assertGreater(len(black), 1000)
        # The two squares sit symmetrically about the view's vertical plane: their mean signals
        # stand in the albedos' ratio, 30.
        self.assertAlmostEqual(np.mean(white) / np.mean(black), 30.0, delta=1.5)
        strong = self.by_object(self.scan(emitter_w_per_sr=0.05), scan_pb2.POINT_STATUS_REJECTED_SATURATED)
        self.assertEqual(strong["white"], 1.0, strong)
        self.assertEqual(strong["black"], 0.0, strong)

    def test_ambient_light_brightens_every_pixel_but_darkens_the_black_one(self):
        # Black: about 120 e of the emitter's light, an SNR near 10 alone. An ambient 0.03 W/m^2 adds
        # about 1400 e of its own (albedo 0.03 / pi x 0.03 x the gain): the emitter's share now
        # stands near 3 sigmas and does not decode. White keeps an SNR near 17.
        plain = self.scan(emitter_w_per_sr=0.002, full_well_e=1e6)
        lit = self.scan(emitter_w_per_sr=0.002, full_well_e=1e6, ambient_irradiance_w_per_m2=0.03)
        self.assertLess(self.by_object(plain, scan_pb2.POINT_STATUS_REJECTED_DARK)["black"], 0.1)
        self.assertGreater(self.by_object(lit, scan_pb2.POINT_STATUS_REJECTED_DARK)["black"], 0.9)
        self.assertEqual(self.by_object(lit, scan_pb2.POINT_STATUS_MEASURED)["white"], 1.0)
        white = [np.mean(np.asarray(r.intensities)[np.asarray(r.instance_ids) == self.white_id]) for r in (plain, lit)]
        self.assertGreater(white[1], 5 * white[0], white)
        with self.assertRaises(VscanError) as caught:
            self.scan(ambient_irradiance_w_per_m2=1e19)
        self.assertIn("returned_light.ambient_irradiance_w_per_m2", caught.exception.message)

    def test_the_raster_backends_judge_the_same_light(self):
        for backend in ("depth", "colour"):
            drawn = self.scan(backend=backend, emitter_w_per_sr=0.0002)
            dark = self.by_object(drawn, scan_pb2.POINT_STATUS_REJECTED_DARK)
            self.assertGreater(dark["black"], 0.95, (backend, dark))
            self.assertEqual(self.by_object(drawn, scan_pb2.POINT_STATUS_MEASURED)["white"], 1.0, backend)

    def test_the_cli_scans_with_the_returned_light_and_refuses_bad_values(self):
        out_file = os.path.join(self.tmp.name, "scan.ply")
        args = [VSCAN, "--server", self.server.address, "scan", self.scene, "-o", out_file, "--width", "160",
                "--height", "120", "--hfov", "40", "--eye", ",".join(map(str, EYE)),
                "--target", ",".join(map(str, TARGET))]
        ran = subprocess.run(args + ["--returned-light", "emitter_w_per_sr=0.0002"], capture_output=True, text=True)
        self.assertEqual(ran.returncode, 0, ran.stderr)
        self.assertRegex(ran.stdout + ran.stderr, r"\d+ dark")
        for value, field in (("emitter_w_per_sr=2e6", "returned_light.emitter_w_per_sr"),
                             ("exposure_s=1e19", "returned_light.exposure_s"),
                             ("full_well_e=-1", "returned_light.full_well_e"),
                             ("emitter_half_angle_deg=1e-20,aperture_diameter_m=5", "returned_light.aperture_diameter_m")):
            refused = subprocess.run(args + ["--returned-light", value], capture_output=True, text=True)
            self.assertEqual(refused.returncode, 3, refused.stdout + refused.stderr)
            self.assertIn("INVALID_ARGUMENT", refused.stderr)
            self.assertIn(field, refused.stderr)
        for value in ("colour=red", "emitter_w_per_sr=nan", "exposure_s", "aperture_diameter_m=1e-400"):  # the CLI's own checks
            usage = subprocess.run(args + ["--returned-light", value], capture_output=True, text=True)
            self.assertEqual(usage.returncode, 2, usage.stderr)
            self.assertIn("--returned-light", usage.stderr)

    def test_a_preset_brings_its_camera_and_emitter_and_the_request_overrides_them(self):
        preset = [p for p in self.client.list_sensor_presets() if p.name == "kinect-v2-class"][0]
        light, camera = preset.returned_light, preset.spec.pinhole
        self.assertGreater(light.full_well_e, 0)
        self.assertGreater(light.read_noise_e, 0)
        self.assertEqual(light.modulation_frequency_hz, 20e6)
        self.assertIn("Bamji", preset.returned_light_source)
        # The preset's gain: QE t A Omega lambda / (h c), Omega = 1 / (fx fy) on the axis.
        pupil_area = math.pi * light.aperture_diameter_m ** 2 / 4
        gain = (light.quantum_efficiency * light.exposure_s * pupil_area / (camera.intrinsics.fx * camera.intrinsics.fy)
                * light.wavelength_m / (6.62607015e-34 * 299792458.0))
        # An emitter putting about a third of the well on the white square (37 degrees, 1 m; the
        # cos^4 of the square's pixels takes a little more off).
        emitter = light.full_well_e / 3 / (gain * 0.9 / math.pi * math.cos(math.radians(37)))

        def white(**values):
            result = self.client.scan(self.scene, preset="kinect-v2-class", eye=EYE, target=TARGET,
                                      fields=["position", "intensity", "instance", "status"], include_rejected=True,
                                      returned_light={"emitter_w_per_sr": emitter, **values}, seed=3)
            return np.asarray(result.intensities)[np.asarray(result.instance_ids) == self.white_id]

        at_preset = white()
        self.assertGreater(len(at_preset), 500)
        self.assertLess(np.max(at_preset), light.full_well_e)
        self.assertGreater(np.mean(at_preset), 0.2 * light.full_well_e)
        # Half the preset's exposure halves the electrons; ten times the emitter fills the preset's well.
        self.assertAlmostEqual(np.mean(white(exposure_s=light.exposure_s / 2)) / np.mean(at_preset), 0.5, delta=0.02)
        self.assertEqual(np.max(white(emitter_w_per_sr=10 * emitter)), np.float32(light.full_well_e))
        cli = subprocess.run([VSCAN, "--server", self.server.address, "sensors", "--verbose"], capture_output=True,
                             text=True)
        self.assertEqual(cli.returncode, 0, cli.stderr)
        self.assertRegex(cli.stdout, r"light: exposure [0-9.]+ ms, full well [0-9.e+]+ e, read noise [0-9.]+ e "
                                     r"\(dynamic range [0-9.]+ dB\)")
        self.assertIn("light source:", cli.stdout)

    def test_python_refusals_name_the_field(self):
        for light, field in (({"min_snr": math.inf}, "returned_light.min_snr"),
                             ({"emitter_half_angle_deg": 270}, "returned_light.emitter_half_angle_deg"),
                             ({"wavelength_m": 1e-12}, "returned_light.wavelength_m")):
            with self.assertRaises(VscanError) as caught:
                self.scan(**light)
            self.assertEqual(caught.exception.code, C.INVALID_ARGUMENT)
            self.assertIn(field, caught.exception.message)


if __name__ == "__main__":
    unittest.main()
