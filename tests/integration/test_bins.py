"""Bin fills against a real vscand: `vscan bin fill` of a small plan, `vscan bin scan` with ground truth,
bad specs refused naming their field, a bin given as a mesh, and what a restart keeps."""

import json
import math
import os
import subprocess
import tempfile
import time
import unittest

import numpy as np

from harness import DATA, VSCAN, Server, cli_events, cli_result, torus_ply
from test_cli import read_ply

import grpc  # noqa: E402
from vscan.v1 import job_pb2, job_pb2_grpc, scene_pb2, scene_pb2_grpc  # noqa: E402
from vscan import Client, VscanError, bin_part  # noqa: E402

C = grpc.StatusCode

PLAN = """\
name: small-bin
scene: bins-test
bin:
  inner_size: [0.20, 0.15, 0.10]
  pose: {{xyz: [0.1, 0.0, 0.0], rpy_deg: [0, 0, 30]}}
parts:
  - mesh: {parts}/angle_block.STL
    unit: in
    count: {blocks}
  - mesh: {parts}/round.stl
    unit: in
    scale: 0.05
    count: {pins}
seed: 3
physics: {{max_simulated_s: {seconds}}}
"""


def write_plan(directory, name="plan.yaml", blocks=4, pins=4, seconds=20):
    path = os.path.join(directory, name)
    with open(path, "w") as f:
        f.write(PLAN.format(parts=os.path.join(DATA, "parts"), blocks=blocks, pins=pins, seconds=seconds))
    return path


def vscan(server, *args, timeout=300):
    return subprocess.run([VSCAN, "--server", server.address, *args], capture_output=True, text=True,
                          timeout=timeout)


def matrix(values):
    return np.array(values, dtype=float).reshape(4, 4)


class BinCliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-bins-")
        cls.plan = write_plan(cls.tmp.name)
        cls.out_dir = os.path.join(cls.tmp.name, "fill")
        cls.fill = vscan(cls.server, "--json", "bin", "fill", cls.plan, "-o", cls.out_dir)
        cls.client = Client(cls.server.address)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()
        cls.tmp.cleanup()

    def filled(self):
        self.assertEqual(self.fill.returncode, 0, self.fill.stderr + self.server.log())
        return cli_result(self.fill.stdout)

    def test_fill_puts_the_bin_and_its_parts_into_the_scene(self):
        out = self.filled()
        self.assertEqual(out["job"]["state"], "JOB_STATE_SUCCEEDED")
        with open(os.path.join(self.out_dir, "bin.json")) as f:
            report = json.load(f)
        self.assertEqual(report["parts"], out["bin"]["parts"])
        self.assertEqual(report["end"], out["bin"]["end"])
        self.assertTrue(report["applied"])
        self.assertIn(report["end"], ("settled", "full", "time_bound"))
        self.assertEqual(report["spawned"], 8)
        self.assertEqual(report["in_bin"] + len(report["outside"]), 8)
        self.assertEqual(report["seed"], 3)
        self.assertEqual([t["source_unit"] for t in report["types"]], ["in", "in"])

        scene = self.client.get_scene(out["sceneId"])
        self.assertEqual(scene.name, "bins-test")
        self.assertEqual(scene.revision, report["scene_revision"])
        objects = {o.object_id: o for o in scene.objects}
        self.assertEqual(len(objects), 1 + report["in_bin"])
        bin_object = objects[report["bin"]["object_id"]]
        self.assertEqual(bin_object.label, "small-bin")
        self.assertEqual(bin_object.instance_id, report["bin"]["instance_id"])
        for part in report["parts"]:
            placed = objects[part["object_id"]]
            self.assertEqual(placed.label, f"{part['name']}#{part['instance'] + 1}")
            self.assertEqual(placed.instance_id, part["instance_id"])
            np.testing.assert_allclose(matrix(placed.pose.matrix.values), matrix(part["world_from_part"]), atol=1e-9)
        # The bin frame turns 30 degrees about z at x = 0.1, as the plan says.
        world_from_bin = matrix(report["bin"]["world_from_bin"])
        np.testing.assert_allclose(world_from_bin[:3, 3], [0.1, 0.0, 0.0], atol=1e-12)
        self.assertAlmostEqual(math.degrees(math.atan2(world_from_bin[1, 0], world_from_bin[0, 0])), 30.0)
        np.testing.assert_allclose(matrix(bin_object.pose.matrix.values), world_from_bin, atol=1e-12)

    def test_scan_writes_instance_ids_that_match_the_ground_truth(self):
        job_id = self.filled()["job"]["jobId"]
        cloud = os.path.join(self.tmp.name, "scan.ply")
        out = vscan(self.server, "bin", "scan", job_id, "-o", cloud)
        self.assertEqual(out.returncode, 0, out.stderr + self.server.log())
        with open(os.path.join(self.tmp.name, "scan.gt.json")) as f:
            truth = json.load(f)
        points = read_ply(cloud)
        self.assertEqual(len(points["x"]), truth["points"])
        by_instance = {o["instance_id"]: o for o in truth["objects"]}
        ids, counts = np.unique(points["instance"], return_counts=True)
        for instance, count in zip(ids, counts):
            self.assertIn(int(instance), by_instance)
            self.assertEqual(int(by_instance[int(instance)]["visible_points"]), int(count))
        for o in truth["objects"]:
            self.assertGreaterEqual(o["visible_fraction"], 0.0)
            self.assertLessEqual(o["visible_fraction"], 1.0)
            world = matrix(o["world_from_object"]["values"])
            sensor = matrix(o["sensor_from_object"]["values"])
            np.testing.assert_allclose(matrix(truth["world_from_sensor"]) @ sensor, world, atol=1e-5)
        # The default view holds the whole opening: points on the top of each of the four walls.
        world = np.stack([points["x"], points["y"], points["z"], np.ones(len(points["x"]))])
        yaw = math.radians(30)
        world_from_bin = np.array([[math.cos(yaw), -math.sin(yaw), 0, 0.1], [math.sin(yaw), math.cos(yaw), 0, 0],
                                   [0, 0, 1, 0], [0, 0, 0, 1]])
        local = np.linalg.inv(world_from_bin) @ world
        rim = local[:, local[2] > 0.099]
        for axis, edge in ((0, 0.105), (1, 0.08)):
            self.assertGreater(np.sum(rim[axis] > edge), 10, f"the rim beyond +{edge} m along axis {axis}")
            self.assertGreater(np.sum(rim[axis] < -edge), 10, f"the rim beyond -{edge} m along axis {axis}")
        report = self.client.bin_report(job_id)
        seen_parts = {o["object_id"] for o in truth["objects"]} - {report["bin"]["object_id"]}
        self.assertTrue(seen_parts <= {p["object_id"] for p in report["parts"]})
        self.assertGreater(len(seen_parts), 0)

    def test_json_streams_the_events_through_a_pipe_while_the_fill_runs(self):
        plan = write_plan(self.tmp.name, "streamed.yaml", blocks=6, pins=6)
        with open(plan) as f:
            text = f.read().replace("scene: bins-test", "scene: bins-streamed")
        with open(plan, "w") as f:
            f.write(text)
        cli = subprocess.Popen([VSCAN, "--server", self.server.address, "--json", "bin", "fill", plan, "-o",
                                os.path.join(self.tmp.name, "streamed")], stdout=subprocess.PIPE, text=True)
        try:
            first = json.loads(cli.stdout.readline())
            # A line reached the pipe while the command still ran: it was not held until the job ended.
            self.assertIsNone(cli.poll())
            self.assertIn("event", first)
            self.assertIn(first["state"], ("JOB_STATE_QUEUED", "JOB_STATE_RUNNING"))
            rest = cli.stdout.read()
            self.assertEqual(cli.wait(timeout=300), 0)
        finally:
            if cli.poll() is None:
                cli.kill()
            cli.stdout.close()
        events = cli_events(rest)
        self.assertTrue(events)
        self.assertEqual(events[-1]["state"], "JOB_STATE_SUCCEEDED")
        self.assertEqual(cli_result(rest)["job"]["state"], "JOB_STATE_SUCCEEDED")

    def test_bad_specs_are_refused_naming_the_field_and_change_nothing(self):
        scene_id = self.filled()["sceneId"]
        before = self.client.get_scene(scene_id)
        jobs_before = len(self.client.list_jobs())
        mesh_id = self.client.bin_report(self.filled()["job"]["jobId"])["types"][0]["mesh_id"]
        stub = job_pb2_grpc.JobServiceStub(self.server.channel())

        def start(inner_size=(0.2, 0.15, 0.1), counts=(3,), mesh=mesh_id, validate_only=False):
            spec = job_pb2.BinFillSpec(scene_id=scene_id)
            spec.bin.inner_size.x, spec.bin.inner_size.y, spec.bin.inner_size.z = inner_size
            for count in counts:
                spec.parts.add(mesh_id=mesh, count=count)
            return lambda: stub.StartBinFill(job_pb2.StartBinFillRequest(spec=spec, validate_only=validate_only))

        cases = [
            (start(inner_size=(math.nan, 0.15, 0.1)), C.INVALID_ARGUMENT, "spec.bin.inner_size"),
            (start(inner_size=(1e19, 0.15, 0.1)), C.INVALID_ARGUMENT, "spec.bin.inner_size"),
            (start(inner_size=(0.2, 1e-20, 0.1)), C.INVALID_ARGUMENT, "spec.bin.inner_size"),
            (start(counts=(0,)), C.INVALID_ARGUMENT, "spec.parts[0].count"),
            (start(counts=(300, 201)), C.INVALID_ARGUMENT, "spec.parts[1].count"),
            (start(mesh="msh_0000000000000000"), C.NOT_FOUND, "spec.parts[0].mesh_id"),
            (start(mesh="msh_0000000000000000", validate_only=True), C.NOT_FOUND, "spec.parts[0].mesh_id"),
        ]
        for call, code, field in cases:
            with self.assertRaises(grpc.RpcError) as caught:
                call()
            self.assertEqual(caught.exception.code(), code, caught.exception.details())
            self.assertTrue(caught.exception.details().startswith(field), caught.exception.details())
        with self.assertRaises(VscanError) as caught:
            self.client.start_bin_fill(scene_id, (0.2, 0.15, 0.1), [bin_part(mesh_id, 1, scale=1e-20)])
        self.assertIn("spec.parts[0].scale", str(caught.exception))
        self.assertEqual(self.client.get_scene(scene_id), before)
        self.assertEqual(len(self.client.list_jobs()), jobs_before)
        start(validate_only=True)()  # a good spec checks out and starts nothing
        self.assertEqual(len(self.client.list_jobs()), jobs_before)

    def test_parts_can_collide_as_their_convex_decomposition(self):
        scene_id = self.filled()["sceneId"]
        mesh_id = self.client.bin_report(self.filled()["job"]["jobId"])["types"][0]["mesh_id"]
        job, report = self.client.bin_fill(scene_id, (0.12, 0.1, 0.08),
                                           [bin_part(mesh_id, 4, collision="convex_decomposition")],
                                           seed=5, max_simulated_s=20, bin_position=(1.0, 0.0, 0.0), timeout=240)
        self.assertEqual(job.state, job_pb2.JOB_STATE_SUCCEEDED, self.server.log())
        self.assertEqual(report["types"][0]["collision"], "convex_decomposition")
        self.assertEqual(report["in_bin"], 4)
        self.assertLess(report["max_part_part_penetration_m"], 0.002)
        # The pieces stay in the data directory, so that no later fill or restart cuts the mesh again.
        kept = os.listdir(os.path.join(self.server.data_dir, "store", "decompositions"))
        self.assertTrue(any(name.endswith(".pieces") for name in kept), kept)
        with self.assertRaises(ValueError):
            bin_part(mesh_id, 1, collision="sphere")

    def test_a_mesh_too_large_to_decompose_is_refused_at_once(self):
        scene_id = self.filled()["sceneId"]
        # A torus of 150 x 75 quads (22,500 triangles): past the bound, since its cuts cannot be stopped.
        path = os.path.join(self.tmp.name, "torus.ply")
        torus_ply(path, 150, 75)
        mesh_id = self.client.upload_mesh(path, unit="m").mesh_id
        stub = job_pb2_grpc.JobServiceStub(self.server.channel())
        jobs_before = len(self.client.list_jobs())
        for validate_only in (True, False):
            spec = job_pb2.BinFillSpec(scene_id=scene_id)
            spec.bin.inner_size.x, spec.bin.inner_size.y, spec.bin.inner_size.z = 0.3, 0.3, 0.2
            spec.parts.add(mesh_id=mesh_id, count=2, collision=job_pb2.PART_COLLISION_CONVEX_DECOMPOSITION)
            started = time.monotonic()
            with self.assertRaises(grpc.RpcError) as caught:
                stub.StartBinFill(job_pb2.StartBinFillRequest(spec=spec, validate_only=validate_only), timeout=20)
            self.assertLess(time.monotonic() - started, 2.0)
            self.assertEqual(caught.exception.code(), grpc.StatusCode.RESOURCE_EXHAUSTED, caught.exception.details())
            self.assertTrue(caught.exception.details().startswith("spec.parts[0].mesh"), caught.exception.details())
            self.assertIn("this one has 22500", caught.exception.details())
        self.assertEqual(len(self.client.list_jobs()), jobs_before)

    def test_part_materials_become_the_placed_objects_materials(self):
        text = PLAN.format(parts=os.path.join(DATA, "parts"), blocks=2, pins=2, seconds=10)
        text = text.replace("    count: 2\n", "    count: 2\n    material: black-anodised-aluminium\n", 1)
        text = text.replace("    scale: 0.05\n", "    scale: 0.05\n    material: {diffuse_albedo: 0.3, metallic: 0, "
                            "roughness: 0.6, specular_reflectance: 0.05}\n")
        path = os.path.join(self.tmp.name, "materials.yaml")
        with open(path, "w") as f:
            f.write(text.replace("scene: bins-test", "scene: bins-materials"))
        fill = vscan(self.server, "--json", "bin", "fill", path, "-o", os.path.join(self.tmp.name, "materials"))
        self.assertEqual(fill.returncode, 0, fill.stderr)
        scene = self.client.get_scene(cli_result(fill.stdout)["sceneId"])
        parts = [o for o in scene.objects if "#" in o.label]
        self.assertEqual(len(parts), 4)
        for placed in parts:
            if placed.label.startswith("angle_block#"):
                self.assertEqual(placed.material.preset, "black-anodised-aluminium")
            else:
                self.assertEqual(placed.material.values.roughness, 0.6, placed.label)
        self.assertFalse(next(o for o in scene.objects if "#" not in o.label).HasField("material"))  # the bin
        # A scan of the bin with the returned light sees them: the black anodised blocks go dark first.
        cloud = os.path.join(self.tmp.name, "materials.ply")
        lit = vscan(self.server, "--json", "bin", "scan", cli_result(fill.stdout)["job"]["jobId"], "-o", cloud,
                    "--returned-light", "emitter_w_per_sr=0.002")
        self.assertEqual(lit.returncode, 0, lit.stderr)
        self.assertGreater(int(cli_result(lit.stdout)["statistics"].get("rejectedDark", 0)), 0, lit.stdout)
        usage = vscan(self.server, "bin", "scan", cli_result(fill.stdout)["job"]["jobId"], "-o", cloud,
                      "--returned-light", "colour=red")
        self.assertEqual(usage.returncode, 2, usage.stderr)
        bad = os.path.join(self.tmp.name, "bad_material.yaml")
        with open(bad, "w") as f:
            f.write(text.replace("black-anodised-aluminium", "unobtainium"))
        out = vscan(self.server, "bin", "fill", bad)
        self.assertNotEqual(out.returncode, 0, out.stdout)
        self.assertIn("bad_material.yaml:10: parts[0].material.preset", out.stderr)
        self.assertIn("unknown preset 'unobtainium'", out.stderr)

    def test_plan_errors_name_the_plan_line(self):
        too_many = write_plan(self.tmp.name, "too_many.yaml", blocks=300, pins=300)
        out = vscan(self.server, "bin", "fill", too_many)
        self.assertEqual(out.returncode, 2, out.stderr)
        self.assertIn("too_many.yaml:13: parts[1].count", out.stderr)
        zero = write_plan(self.tmp.name, "zero.yaml", blocks=0)
        out = vscan(self.server, "bin", "fill", zero)
        self.assertEqual(out.returncode, 2, out.stderr)
        self.assertIn("zero.yaml:9: parts[0].count", out.stderr)

    def test_render_colours_a_scan_by_instance(self):
        job_id = self.filled()["job"]["jobId"]
        cloud = os.path.join(self.tmp.name, "render.ply")
        self.assertEqual(vscan(self.server, "bin", "scan", job_id, "-o", cloud).returncode, 0)
        png = os.path.join(self.tmp.name, "render.png")
        out = vscan(self.server, "render", cloud, "-o", png, "--color", "instance")
        self.assertEqual(out.returncode, 0, out.stderr)
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


def write_tote_stl(path, floor=(160, 120), top=(220, 160), depth=100):
    """An open tote with sloped walls as ASCII STL (millimetres): floor at z = 0, opening at depth."""
    fx, fy, tx, ty = floor[0] / 2, floor[1] / 2, top[0] / 2, top[1] / 2
    v = [(-fx, -fy, 0), (fx, -fy, 0), (fx, fy, 0), (-fx, fy, 0),
         (-tx, -ty, depth), (tx, -ty, depth), (tx, ty, depth), (-tx, ty, depth)]
    triangles = [(0, 1, 2), (0, 2, 3)]
    for k in range(4):
        n = (k + 1) % 4
        triangles += [(k, k + 4, n + 4), (k, n + 4, n)]
    with open(path, "w") as f:
        f.write("solid tote\n")
        for t in triangles:
            f.write("facet normal 0 0 0\nouter loop\n")
            for i in t:
                f.write("vertex %g %g %g\n" % v[i])
            f.write("endloop\nendfacet\n")
        f.write("endsolid tote\n")


MESH_PLAN = """\
name: tote-bin
scene: bins-tote
bin:
  mesh: tote.stl
  unit: mm
  scale: 1
  pose: {{xyz: [0.3, 0.1, 0.0], rpy_deg: [0, 0, 20]}}
parts:
  - mesh: {parts}/angle_block.STL
    unit: in
    count: 5
seed: 5
physics: {{max_simulated_s: 20}}
"""


class MeshBinTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-mesh-bin-")
        write_tote_stl(os.path.join(cls.tmp.name, "tote.stl"))
        cls.plan = os.path.join(cls.tmp.name, "tote.yaml")
        with open(cls.plan, "w") as f:
            f.write(MESH_PLAN.format(parts=os.path.join(DATA, "parts")))
        cls.client = Client(cls.server.address)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.cleanup()
        cls.tmp.cleanup()

    def test_a_plan_with_a_mesh_bin_fills_the_uploaded_tote(self):
        out_dir = os.path.join(self.tmp.name, "fill")
        fill = vscan(self.server, "--json", "bin", "fill", self.plan, "-o", out_dir)
        self.assertEqual(fill.returncode, 0, fill.stderr + self.server.log())
        report = cli_result(fill.stdout)["bin"]
        self.assertTrue(report["applied"])
        self.assertEqual(report["end"], "settled", report["end_message"])
        self.assertEqual(report["in_bin"], 5)
        self.assertNotIn("inner_size", report["bin"])
        np.testing.assert_allclose(report["bin"]["bounds_min"], [-0.11, -0.08, 0.0], atol=1e-6)
        np.testing.assert_allclose(report["bin"]["bounds_max"], [0.11, 0.08, 0.1], atol=1e-6)

        scene = self.client.get_scene(cli_result(fill.stdout)["sceneId"])
        objects = {o.object_id: o for o in scene.objects}
        bin_object = objects[report["bin"]["object_id"]]
        self.assertEqual(bin_object.mesh_id, report["bin"]["mesh_id"])  # the uploaded tote itself
        self.assertEqual(bin_object.label, "tote-bin")
        world_from_bin = matrix(report["bin"]["world_from_bin"])
        np.testing.assert_allclose(matrix(bin_object.pose.matrix.values), world_from_bin, atol=1e-12)
        np.testing.assert_allclose(world_from_bin[:3, 3], [0.3, 0.1, 0.0], atol=1e-12)
        self.assertEqual(self.client.get_mesh(bin_object.mesh_id).triangle_count, 10)
        bin_from_world = np.linalg.inv(world_from_bin)
        for part in report["parts"]:
            centre = bin_from_world @ matrix(part["world_from_part"])[:, 3]
            self.assertLessEqual(abs(centre[0]), 0.11, part["label"])
            self.assertLessEqual(abs(centre[1]), 0.08, part["label"])
            self.assertGreaterEqual(centre[2], 0.0, part["label"])
            self.assertLessEqual(centre[2], 0.1, part["label"])

        # Scanned from above with no height given: the tote's stored bounds place the sensor.
        cloud = os.path.join(out_dir, "scan.ply")
        scan = vscan(self.server, "bin", "scan", cli_result(fill.stdout)["job"]["jobId"], "-o", cloud)
        self.assertEqual(scan.returncode, 0, scan.stderr)
        with open(os.path.splitext(cloud)[0] + ".gt.json") as f:
            truth = json.load(f)
        sensor_height = matrix(truth["world_from_sensor"])[2, 3]
        self.assertGreater(sensor_height, 0.1 + 0.05, "above the rim, beyond the near limit")
        seen = {o["label"] for o in truth["objects"] if o["visible_fraction"] > 0}
        self.assertTrue({p["label"] for p in report["parts"]} <= seen, seen)

    def test_a_plan_naming_an_unknown_bin_mesh_points_at_its_line(self):
        plan = os.path.join(self.tmp.name, "unknown-tote.yaml")
        with open(plan, "w") as f:
            f.write(MESH_PLAN.format(parts=os.path.join(DATA, "parts"))
                    .replace("  mesh: tote.stl\n  unit: mm\n", "  mesh_id: msh_0000000000000000\n"))
        out = vscan(self.server, "bin", "fill", plan)
        self.assertEqual(out.returncode, 2, out.stderr)
        self.assertIn("unknown-tote.yaml:4: bin_mesh.mesh_id", out.stderr)

    def test_python_fills_a_mesh_bin_and_bad_mesh_bins_are_refused(self):
        scene = self.client.create_scene("tote-python")
        tote = self.client.upload_mesh(os.path.join(self.tmp.name, "tote.stl"), unit="mm")
        block = self.client.upload_mesh(os.path.join(DATA, "parts", "angle_block.STL"), unit="in")
        job, report = self.client.bin_fill(scene.scene_id, parts=[bin_part(block.mesh_id, 3)], bin_mesh_id=tote.mesh_id,
                                           seed=2, max_simulated_s=20, timeout=120)
        self.assertEqual(report["bin"]["mesh_id"], tote.mesh_id, job.message)
        self.assertEqual(report["in_bin"], 3)
        objects = self.client.get_scene(scene.scene_id).objects
        self.assertEqual(objects[0].mesh_id, tote.mesh_id)
        self.assertEqual(objects[0].instance_id, report["bin"]["instance_id"])

        def refused(**bin_options):
            with self.assertRaises(VscanError) as caught:
                self.client.validate_bin_fill(scene.scene_id, parts=[bin_part(block.mesh_id, 1)], **bin_options)
            return caught.exception

        unknown = refused(bin_mesh_id="msh_0000000000000000")
        self.assertEqual(unknown.code, C.NOT_FOUND)
        self.assertIn("spec.bin_mesh.mesh_id", unknown.message)
        nan_scale = refused(bin_mesh_id=tote.mesh_id, bin_mesh_scale=float("nan"))
        self.assertEqual(nan_scale.code, C.INVALID_ARGUMENT)
        self.assertIn("spec.bin_mesh.scale", nan_scale.message)
        flat = refused(bin_mesh_id=tote.mesh_id, bin_mesh_scale=1e-3)  # 0.1 mm deep: no volume
        self.assertEqual(flat.code, C.INVALID_ARGUMENT)
        self.assertIn("spec.bin_mesh.scale", flat.message)
        self.assertEqual(len(self.client.get_scene(scene.scene_id).objects), 1 + 3)  # refusals changed nothing


class BinRestartTest(unittest.TestCase):
    def test_a_restart_keeps_a_finished_fill_and_interrupts_a_running_one(self):
        server = Server().start()
        tmp = tempfile.TemporaryDirectory(prefix="vscan-bins-restart-")
        try:
            out = vscan(server, "--json", "bin", "fill", write_plan(tmp.name), "-o", os.path.join(tmp.name, "a"))
            self.assertEqual(out.returncode, 0, out.stderr + server.log())
            done = cli_result(out.stdout)
            with Client(server.address) as client:
                scene_before = client.get_scene(done["sceneId"])
                # A long fill into a scene of its own, killed once it has reported progress.
                big = write_plan(tmp.name, "big.yaml", blocks=40, pins=40, seconds=300)
                with open(big) as f:
                    text = f.read().replace("scene: bins-test", "scene: bins-restart")
                with open(big, "w") as f:
                    f.write(text)
                started = vscan(server, "--json", "bin", "fill", big, "--detach")
                self.assertEqual(started.returncode, 0, started.stderr + server.log())
                running = cli_result(started.stdout)
                deadline = time.time() + 120
                while "simulated" not in client.get_job(running["job"]["jobId"]).message:
                    self.assertLess(time.time(), deadline, server.log())
                    time.sleep(0.2)
                busy_before = client.get_scene(running["sceneId"])
            server.kill9()
            server.start()
            with Client(server.address) as client:
                finished = client.get_job(done["job"]["jobId"])
                self.assertEqual(finished.state, job_pb2.JOB_STATE_SUCCEEDED)
                self.assertEqual(client.get_scene(done["sceneId"]), scene_before)
                self.assertEqual(client.bin_report(finished.job_id)["scene_revision"], scene_before.revision)
                stopped = client.get_job(running["job"]["jobId"])
                self.assertEqual(stopped.state, job_pb2.JOB_STATE_INTERRUPTED)
                self.assertEqual(client.get_scene(running["sceneId"]), busy_before)
                self.assertEqual(len(busy_before.objects), 0)
        finally:
            server.cleanup()
            tmp.cleanup()


if __name__ == "__main__":
    unittest.main()
