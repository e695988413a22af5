"""The measurement model through a real vscand: ground truth decodes, counters agree, noise and
outliers follow their spec, bad values name their field."""

import os
import subprocess
import tempfile
import unittest

import grpc
import numpy as np

from harness import VSCAN, Server, common_pb2, icosphere_ply, look_at, pinhole, scan_pb2, scan_pb2_grpc, sensor_pb2

from vscan import Client, VscanError

C = grpc.StatusCode
S = scan_pb2

TRUTH = ["position", "normal", "range", "intensity", "instance", "pixel", "clean", "incidence", "status"]


def square_ply(half, z):
    """A square facing -z at depth z (two triangles)."""
    lines = ["ply", "format ascii 1.0", "element vertex 4", "property float x", "property float y",
             "property float z", "element face 2", "property list uchar int vertex_indices", "end_header"]
    lines += [f"{x} {y} {z}" for x, y in ((-half, -half), (half, -half), (half, half), (-half, half))]
    lines += ["3 0 1 2", "3 0 2 3"]
    return ("\n".join(lines) + "\n").encode()


def cube_ply(half, height):
    """A closed box [-half, half]^2 x [0, height]."""
    corners = [(x, y, z) for z in (0.0, height) for y in (-half, half) for x in (-half, half)]
    faces = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4), (2, 6, 7), (2, 7, 3),
             (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    lines = ["ply", "format ascii 1.0", f"element vertex {len(corners)}", "property float x", "property float y",
             "property float z", f"element face {len(faces)}", "property list uchar int vertex_indices",
             "end_header"]
    lines += [f"{x} {y} {z}" for x, y, z in corners]
    lines += [f"3 {a} {b} {c}" for a, b, c in faces]
    return ("\n".join(lines) + "\n").encode()


def segment_hits_box(starts, end, lo, hi):
    """Whether each segment starts[i] -> end passes through the axis-aligned box (slab test)."""
    d = end[None, :] - starts
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (lo[None, :] - starts) / d
        t2 = (hi[None, :] - starts) / d
    t_in = np.nanmax(np.minimum(t1, t2), axis=1)
    t_out = np.nanmin(np.maximum(t1, t2), axis=1)
    return (t_in <= t_out) & (t_out > 0) & (t_in < 1)


class MeasurementTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.client = Client(cls.server.address)
        cls.tmp = tempfile.TemporaryDirectory()

        def mesh(name, data):
            path = os.path.join(cls.tmp.name, name)
            with open(path, "wb") as f:
                f.write(data)
            return cls.client.upload_mesh(path, unit="m").mesh_id

        # Plane scene: a 40 m square at z = 0 seen from 1 m above, straight down.
        cls.plane_scene = cls.client.create_scene("plane").scene_id
        cls.client.add_object(cls.plane_scene, mesh("plane.ply", square_ply(20.0, 0.0)))
        # Sphere in front of a wall 4 m behind it.
        cls.sphere_scene = cls.client.create_scene("sphere").scene_id
        cls.client.add_object(cls.sphere_scene, mesh("sphere.ply", icosphere_ply(0.3, (0, 0, 0), 5)))
        cls.client.add_object(cls.sphere_scene, mesh("wall.ply", square_ply(10.0, -4.0)))
        # Structured light: a 10 cm cube standing on the plane, its top at z = 0.1.
        cls.post_scene = cls.client.create_scene("post").scene_id
        cls.client.add_object(cls.post_scene, mesh("floor.ply", square_ply(20.0, 0.0)))
        cls.client.add_object(cls.post_scene, mesh("cube.ply", cube_ply(0.05, 0.1)))

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.tmp.cleanup()
        cls.server.cleanup()

    def plane_scan(self, noise, **kw):
        return self.client.scan(self.plane_scene, width=200, height=150, hfov_deg=60, eye=(0, 0, 1), target=(0, 0, 0),
                                up=(0, 1, 0), fields=TRUTH, noise=noise, seed=kw.pop("seed", 11), **kw)

    def sphere_scan(self, noise, **kw):
        return self.client.scan(self.sphere_scene, width=160, height=160, hfov_deg=40, eye=(0, 0, 1.5),
                                target=(0, 0, 0), up=(0, 1, 0), far=3.0, noise=noise, **kw)

    def test_ground_truth_fields_decode_with_their_dtypes(self):
        result = self.sphere_scan(sensor_pb2.NoiseSpec(sigma_a=0.001), fields=TRUTH + ["estimated_normal"],
                                  normal_estimation=(12, 0.0))
        n = len(result)
        self.assertGreater(n, 5000)
        self.assertEqual((result.clean_positions.dtype, result.clean_positions.shape), (np.float32, (n, 3)))
        self.assertEqual((result.incidence_angles.dtype, result.incidence_angles.shape), (np.float32, (n,)))
        self.assertEqual((result.statuses.dtype, result.statuses.shape), (np.uint8, (n,)))
        self.assertEqual((result.estimated_normals.dtype, result.estimated_normals.shape), (np.float32, (n, 3)))
        np.testing.assert_allclose(np.linalg.norm(result.estimated_normals, axis=1), 1.0, atol=1e-4)
        # Clean positions lie on the sphere; measured ones are a millimetre off.
        np.testing.assert_allclose(np.linalg.norm(result.clean_positions, axis=1), 0.3, atol=2e-3)
        self.assertTrue(np.all(result.statuses == S.POINT_STATUS_MEASURED))
        self.assertTrue(np.all((result.incidence_angles >= 0) & (result.incidence_angles <= np.pi / 2)))
        # The wall lies beyond far: counted, not returned.
        self.assertGreater(result.stats.rejected_out_of_range, 0)
        self.assertGreater(result.stats.measurement_ms, 0)

    def test_status_counts_match_statistics(self):
        noise = sensor_pb2.NoiseSpec(grazing_limit_deg=65, min_intensity=0.5, outlier_rate=0.05, outlier_angle_deg=3,
                                     flying_pixels=True)
        result = self.sphere_scan(noise, fields=TRUTH, include_rejected=True, seed=3)
        counts = np.bincount(result.statuses, minlength=9)
        s = result.stats
        self.assertEqual(counts[S.POINT_STATUS_OUTLIER], s.outliers)
        self.assertEqual(counts[S.POINT_STATUS_FLYING_PIXEL], s.flying_pixels)
        self.assertEqual(counts[S.POINT_STATUS_REJECTED_OUT_OF_RANGE], s.rejected_out_of_range)
        self.assertEqual(counts[S.POINT_STATUS_REJECTED_GRAZING], s.rejected_grazing)
        self.assertEqual(counts[S.POINT_STATUS_REJECTED_DIM], s.rejected_dim)
        returned = counts[S.POINT_STATUS_MEASURED] + counts[S.POINT_STATUS_OUTLIER] + counts[S.POINT_STATUS_FLYING_PIXEL]
        self.assertEqual(returned, s.points)
        for name in ("outliers", "rejected_out_of_range", "rejected_grazing", "rejected_dim"):
            self.assertGreater(getattr(s, name), 0, name)
        rejected = result.statuses >= S.POINT_STATUS_REJECTED_OUT_OF_RANGE
        np.testing.assert_array_equal(result.positions[rejected], result.clean_positions[rejected])
        # Without include_rejected: the same counters, only returned points.
        again = self.sphere_scan(noise, fields=TRUTH, seed=3)
        self.assertEqual(len(again), s.points)
        self.assertEqual(again.stats.rejected_grazing, s.rejected_grazing)
        np.testing.assert_array_equal(again.positions, result.positions[~rejected])

    def test_outlier_rate_within_tolerance(self):
        result = self.plane_scan(sensor_pb2.NoiseSpec(outlier_rate=0.08, outlier_angle_deg=4))
        outlier = result.statuses == S.POINT_STATUS_OUTLIER
        self.assertAlmostEqual(outlier.mean(), 0.08, delta=0.008)
        self.assertEqual(outlier.sum(), result.stats.outliers)
        moved = np.any(result.positions != result.clean_positions, axis=1)
        np.testing.assert_array_equal(moved, outlier)
        np.testing.assert_allclose(result.positions[:, 2], 0.0, atol=1e-4)  # still on the plane

    def test_along_ray_sigma_matches_spec(self):
        sigma = 0.002
        result = self.plane_scan(sensor_pb2.NoiseSpec(sigma_a=sigma, along_ray=True), frame="sensor")
        eye = np.zeros(3)
        residual = np.linalg.norm(result.positions - eye, axis=1) - np.linalg.norm(result.clean_positions - eye, axis=1)
        self.assertAlmostEqual(residual.std() / sigma, 1.0, delta=0.03)
        self.assertLess(abs(residual.mean()), 3 * sigma / np.sqrt(len(residual)) + 1e-6)
        # Along the ray: the measured point stays on the clean point's line of sight.
        direction = result.clean_positions / np.linalg.norm(result.clean_positions, axis=1)[:, None]
        lateral = np.cross(result.positions, direction)
        self.assertLess(np.abs(lateral).max(), 1e-5)

    def test_seed_reproduces_bits(self):
        noise = sensor_pb2.NoiseSpec(sigma_a=0.001, outlier_rate=0.05, outlier_origin_m=0.01)
        a, b = self.plane_scan(noise, seed=5), self.plane_scan(noise, seed=5)
        c = self.plane_scan(noise, seed=6)
        self.assertEqual(a.positions.tobytes(), b.positions.tobytes())
        self.assertNotEqual(a.positions.tobytes(), c.positions.tobytes())

    def test_cli_writes_ground_truth_ply(self):
        out = os.path.join(self.tmp.name, "truth.ply")
        subprocess.run([VSCAN, "--server", self.server.address, "scan", self.sphere_scene, "-o", out, "--width", "80",
                        "--height", "80", "--hfov", "40", "--eye", "0,0,1.5", "--target", "0,0,0", "--up", "0,1,0",
                        "--far", "3", "--fields", "position,truth", "--include-rejected", "--grazing-limit", "60",
                        "--outliers", "0.05", "--outlier-angle", "2", "--estimate-normals=8", "--seed", "2"],
                       check=True, capture_output=True, timeout=60)
        with open(out, "rb") as f:
            header = f.read(1024).split(b"end_header")[0].decode()
        for prop in ("float clean_x", "float incidence", "uchar status", "float enx"):
            self.assertIn(prop, header)

    def structured_light(self, offset_x, vfov=60.0):
        sl = sensor_pb2.StructuredLightScanner(projector_offset=common_pb2.Vector3(x=offset_x),
                                               projector_horizontal_fov_deg=60.0, projector_vertical_fov_deg=vfov)
        sl.camera.CopyFrom(pinhole(width=240, height=180, hfov=50.0, near=0.3, far=2.0).pinhole)
        return sensor_pb2.SensorSpec(structured_light=sl)

    def test_structured_light_shadow_follows_the_projector(self):
        # Camera 1 m above the floor looking down, image x along world +x: the projector stands at
        # (0.2, 0, 1), so the cube's shadow falls on the floor at x < 0.
        projector = np.array([0.2, 0.0, 1.0])
        lo, hi = np.array([-0.05, -0.05, 0.0]), np.array([0.05, 0.05, 0.1])
        result = self.client.scan(self.post_scene, sensor=self.structured_light(0.2), eye=(0, 0, 1),
                                  target=(0, 0, 0), up=(0, 1, 0), fields=TRUTH, include_rejected=True, seed=3)
        status = result.statuses
        shadowed = result.clean_positions[status == S.POINT_STATUS_REJECTED_SHADOWED]
        lit = result.clean_positions[status == S.POINT_STATUS_MEASURED]
        self.assertGreater(len(shadowed), 100)
        self.assertEqual(result.stats.rejected_shadowed, len(shadowed))
        self.assertLess(shadowed[:, 0].max(), -0.04)
        # Every shadowed point is blocked by the cube and no measured point is, but for a band of a
        # couple of pixels (about 2.5 mm at 1 m) along the shadow's edges.
        blocked_lit = segment_hits_box(lit, projector, lo + 0.003, hi - 0.003)
        self.assertEqual(int(blocked_lit.sum()), 0)
        blocked_shadow = segment_hits_box(shadowed, projector, lo - 0.003, hi + 0.003)
        self.assertTrue(np.all(blocked_shadow))
        # The projector on the other side moves the shadow to x > 0.
        mirrored = self.client.scan(self.post_scene, sensor=self.structured_light(-0.2), eye=(0, 0, 1),
                                    target=(0, 0, 0), up=(0, 1, 0), fields=TRUTH, include_rejected=True, seed=3)
        other = mirrored.clean_positions[mirrored.statuses == S.POINT_STATUS_REJECTED_SHADOWED]
        self.assertGreater(other[:, 0].min(), 0.04)

    def test_structured_light_projector_field_limits_rows(self):
        result = self.client.scan(self.post_scene, sensor=self.structured_light(0.2, vfov=20.0), eye=(0, 0, 1),
                                  target=(0, 0, 0), up=(0, 1, 0), fields=TRUTH, include_rejected=True)
        unlit = result.statuses == S.POINT_STATUS_REJECTED_UNLIT
        self.assertEqual(result.stats.rejected_unlit, int(unlit.sum()))
        # Floor points more than tan(10 deg) * 1 m from the projector's axis in y are unlit; so are
        # those beyond tan(30 deg) * 1 m from it in x (x < 0.2 - 0.577).
        x, y = result.clean_positions[:, 0], result.clean_positions[:, 1]
        floor = result.clean_positions[:, 2] < 1e-3
        np.testing.assert_array_equal(unlit[floor & (np.abs(y) > 0.18)], True)
        np.testing.assert_array_equal(unlit[floor & (x < -0.387)], True)
        np.testing.assert_array_equal(unlit[floor & (np.abs(y) < 0.17) & (x > -0.367)], False)

    def test_structured_light_preset_scans(self):
        result = self.client.scan(self.post_scene, preset="phoxi-m-class", eye=(0, 0, 0.8), target=(0, 0, 0),
                                  up=(0, 1, 0), fields=TRUTH, seed=5)
        self.assertGreater(len(result), 100000)
        self.assertGreater(result.stats.rejected_shadowed, 0)
        self.assertTrue(np.all(result.statuses == S.POINT_STATUS_MEASURED))

    def test_bad_values_name_their_field(self):
        stub = scan_pb2_grpc.ScanServiceStub(self.server.channel())

        def code(field, **kw):
            request = dict(scene_id=self.plane_scene, sensor=pinhole(), pose=look_at((0, 0, 1), (0, 0, 0), (0, 1, 0)))
            request.update(kw)
            with self.assertRaises(grpc.RpcError) as ctx:
                list(stub.Scan(S.ScanRequest(**request), timeout=30))
            self.assertEqual(ctx.exception.code(), C.INVALID_ARGUMENT, ctx.exception.details())
            self.assertTrue(ctx.exception.details().startswith(field), ctx.exception.details())

        N = sensor_pb2.NoiseSpec
        code("noise.outlier_rate", noise=N(outlier_rate=1.5, outlier_angle_deg=1))
        code("noise.outlier_rate", noise=N(outlier_rate=0.1))
        code("noise.outlier_angle_deg", noise=N(outlier_rate=0.1, outlier_angle_deg=90))
        code("noise.outlier_origin_m", noise=N(outlier_rate=0.1, outlier_origin_m=-1))
        code("noise.grazing_limit_deg", noise=N(grazing_limit_deg=95))
        code("noise.flying_pixel_edge_m", noise=N(flying_pixels=True, flying_pixel_edge_m=-0.1))
        est = [S.POINT_FIELD_POSITION, S.POINT_FIELD_ESTIMATED_NORMAL]
        code("normal_estimation.k", fields=est, normal_estimation=S.NormalEstimation(k=2))
        code("normal_estimation.k", fields=est, normal_estimation=S.NormalEstimation(k=129))
        code("normal_estimation.max_distance", fields=est, normal_estimation=S.NormalEstimation(max_distance=-1))
        code("normal_estimation", normal_estimation=S.NormalEstimation(k=8))
        code("fields", fields=[99])
        with self.assertRaises(VscanError):
            self.plane_scan(N(outlier_rate=float("nan"), outlier_angle_deg=1))

    def test_non_finite_values_name_their_field(self):
        stub = scan_pb2_grpc.ScanServiceStub(self.server.channel())
        est = [S.POINT_FIELD_POSITION, S.POINT_FIELD_ESTIMATED_NORMAL]

        def structured(camera=None, **kw):
            sl = sensor_pb2.StructuredLightScanner(projector_offset=common_pb2.Vector3(x=0.1), **kw)
            sl.camera.CopyFrom(camera or pinhole().pinhole)
            return sensor_pb2.SensorSpec(structured_light=sl)

        def intrinsics(**kw):
            k = dict(fx=100.0, fy=100.0, cx=80.0, cy=60.0)
            k.update(kw)
            return sensor_pb2.PinholeCamera(width=160, height=120, intrinsics=sensor_pb2.Intrinsics(**k))

        for bad in (float("nan"), float("inf"), -float("inf")):
            cases = [("noise." + name, dict(noise=sensor_pb2.NoiseSpec(**{name: bad})))
                     for name in ("sigma_a", "sigma_b", "sigma_c", "outlier_rate", "outlier_angle_deg",
                                  "outlier_origin_m", "grazing_limit_deg", "min_intensity", "depth_step_m",
                                  "flying_pixel_edge_m")]
            cases.append(("normal_estimation.max_distance",
                          dict(fields=est, normal_estimation=S.NormalEstimation(k=8, max_distance=bad))))
            for name in ("projector_horizontal_fov_deg", "projector_vertical_fov_deg", "disparity_step_px",
                         "convergence_distance"):
                cases.append(("sensor.structured_light." + name, dict(sensor=structured(**{name: bad}))))
            cases.append(("sensor.structured_light.projector_offset",
                          dict(sensor=sensor_pb2.SensorSpec(structured_light=sensor_pb2.StructuredLightScanner(
                              camera=pinhole().pinhole, projector_offset=common_pb2.Vector3(x=0.1, z=bad))))))
            for name in ("fx", "fy", "cx", "cy"):
                cases.append(("sensor.structured_light.camera.intrinsics." + name,
                              dict(sensor=structured(camera=intrinsics(**{name: bad})))))
                cases.append(("sensor.pinhole.intrinsics." + name,
                              dict(sensor=sensor_pb2.SensorSpec(pinhole=intrinsics(**{name: bad})))))
            for name in ("near", "far"):
                camera = pinhole().pinhole
                setattr(camera, name, bad)
                cases.append(("sensor.structured_light.camera." + name, dict(sensor=structured(camera=camera))))
            camera = pinhole().pinhole
            camera.distortion.k1 = bad
            cases.append(("sensor.structured_light.camera.distortion.k1", dict(sensor=structured(camera=camera))))
            for field, kw in cases:
                request = dict(scene_id=self.plane_scene, sensor=pinhole(),
                               pose=look_at((0, 0, 1), (0, 0, 0), (0, 1, 0)))
                request.update(kw)
                with self.subTest(field=field, value=bad):
                    with self.assertRaises(grpc.RpcError) as ctx:
                        list(stub.Scan(S.ScanRequest(**request), timeout=30))
                    self.assertEqual(ctx.exception.code(), C.INVALID_ARGUMENT, ctx.exception.details())
                    self.assertTrue(ctx.exception.details().startswith(field + ":"), ctx.exception.details())

    def test_raster_measured_statuses_match_ray_casting(self):
        # The wall lies beyond far: ray casting finds it (out of range), the raster backend does not; in
        # range, both must give the same verdicts, at the sphere's rim included.
        for noise, status in ((sensor_pb2.NoiseSpec(flying_pixels=True), S.POINT_STATUS_MEASURED),
                              (sensor_pb2.NoiseSpec(grazing_limit_deg=60), S.POINT_STATUS_REJECTED_GRAZING)):
            clouds = {}
            for backend in ("raycast", "depth"):
                result = self.sphere_scan(noise, fields=TRUTH, include_rejected=True, backend=backend)
                keep = result.statuses != S.POINT_STATUS_REJECTED_OUT_OF_RANGE
                clouds[backend] = dict(zip(result.pixels[keep].tolist(), result.statuses[keep].tolist()))
            ray, raster = clouds["raycast"], clouds["depth"]
            common = ray.keys() & raster.keys()
            self.assertGreater(len(common), 0.99 * max(len(ray), len(raster)))
            same = sum(ray[p] == raster[p] for p in common)
            self.assertGreater(same, 0.995 * len(common), noise)
            self.assertGreater(sum(ray[p] == status for p in common), 100)

    def test_every_ray_rejected_with_estimated_normals(self):
        # Seen from 1 m with far = 0.5: every hit is out of range.
        result = self.client.scan(self.plane_scene, width=64, height=48, hfov_deg=60, eye=(0, 0, 1),
                                  target=(0, 0, 0), up=(0, 1, 0), far=0.5, fields=TRUTH + ["estimated_normal"],
                                  normal_estimation=(8, 0.0), include_rejected=True, noise=sensor_pb2.NoiseSpec())
        self.assertEqual(len(result), 64 * 48)
        self.assertTrue(np.all(result.statuses == S.POINT_STATUS_REJECTED_OUT_OF_RANGE))
        self.assertTrue(np.all(result.estimated_normals == 0))
        self.assertEqual(result.stats.points, 0)
        self.assertEqual(result.stats.rejected_out_of_range, 64 * 48)


if __name__ == "__main__":
    unittest.main()
