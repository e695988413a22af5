"""Materials end to end: a mesh's default and an object's override set through the CLI, the Python
client and raw stubs, read back, refused when wrong (with nothing stored), and kept over kill -9."""

import json
import math
import subprocess
import unittest

import grpc

from harness import BUNNY, VSCAN, Server, common_pb2, scene_pb2
from vscan import Client, VscanError
from vscan.v1 import scene_pb2_grpc

C = grpc.StatusCode


class MaterialsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()

    def vscan(self, *args):
        return subprocess.run([VSCAN, "--server", self.server.address, *args],
                              capture_output=True, text=True, timeout=120)

    def ok(self, *args):
        out = self.vscan(*args)
        self.assertEqual(out.returncode, 0, out.stderr)
        return out.stdout.strip()

    def refused(self, field_message, *args):
        out = self.vscan(*args)
        self.assertEqual(out.returncode, 3, out.stdout + out.stderr)
        self.assertIn("INVALID_ARGUMENT", out.stderr)
        self.assertIn(field_message, out.stderr)

    def scene_json(self, scene):
        return json.loads(self.ok("--json", "scene", "get", scene))

    def test_cli_sets_reads_refuses_and_keeps_materials_over_kill9(self):
        listed = json.loads(self.ok("--json", "materials"))["presets"]
        self.assertEqual(listed[0]["name"], "matte-grey")
        by_name = {p["name"]: p for p in listed}
        self.assertEqual(len(by_name), 8)
        self.assertEqual(by_name["machined-aluminium"]["values"],
                         {"diffuseAlbedo": 0.87, "metallic": 1, "roughness": 0.3, "specularReflectance": 0.04})
        self.assertIn("black-anodised-aluminium", self.ok("materials"))

        mesh = self.ok("-q", "mesh", "upload", BUNNY, "--unit", "m", "--material", "machined-aluminium")
        self.assertEqual(json.loads(self.ok("--json", "mesh", "get", mesh))["material"],
                         {"preset": "machined-aluminium"})
        self.assertIn("material machined-aluminium", self.ok("mesh", "get", mesh))
        bare_mesh = self.ok("-q", "mesh", "upload", BUNNY, "--unit", "m")
        self.assertNotIn("material", json.loads(self.ok("--json", "mesh", "get", bare_mesh)))

        scene = self.ok("-q", "scene", "create", "materials")
        black = self.ok("-q", "object", "add", scene, mesh, "--material", "black-abs")
        plain = self.ok("-q", "object", "add", scene, mesh)
        valued = self.ok("-q", "object", "add", scene, bare_mesh, "--material",
                         "albedo=0.3,metallic=0,roughness=0.6,specular=0.05")
        got = self.scene_json(scene)
        objects = {o["objectId"]: o for o in got["objects"]}
        self.assertEqual(objects[black]["material"], {"preset": "black-abs"})
        self.assertNotIn("material", objects[plain])
        self.assertEqual(objects[valued]["material"]["values"],
                         {"diffuseAlbedo": 0.3, "metallic": 0, "roughness": 0.6, "specularReflectance": 0.05})
        text = self.ok("scene", "get", scene).splitlines()
        line = {oid: next(l for l in text if oid in l) for oid in objects}
        self.assertIn("material black-abs", line[black])
        self.assertIn("material machined-aluminium (the mesh's)", line[plain])
        self.assertIn("material albedo 0.3 metallic 0 roughness 0.6 specular 0.05", line[valued])

        # Refusals name the field and store nothing: same revision, same objects, same meshes.
        revision = got["revision"]
        meshes_before = self.ok("-q", "mesh", "list").split()
        self.refused("material.preset: unknown preset 'unobtainium' (known: matte-grey,",
                     "object", "add", scene, mesh, "--material", "unobtainium")
        self.refused("material.values.diffuse_albedo: NaN", "object", "add", scene, mesh,
                     "--material", "albedo=nan,metallic=0,roughness=0.5,specular=0.04")
        self.refused("material.values.metallic", "object", "set-material", scene, plain,
                     "--material", "albedo=0.5,metallic=1e19,roughness=0.5,specular=0.04")
        self.refused("material.values.roughness", "object", "set-material", scene, plain,
                     "--material", "albedo=0.5,metallic=0,roughness=0,specular=0.04")
        self.refused("header.material.preset: unknown preset 'steel'",
                     "mesh", "upload", BUNNY, "--unit", "m", "--material", "steel")
        usage = self.vscan("object", "add", scene, mesh, "--material", "albedo=0.5")
        self.assertEqual(usage.returncode, 2, usage.stderr)
        self.assertEqual(self.scene_json(scene), got)
        self.assertEqual(self.ok("-q", "mesh", "list").split(), meshes_before)

        # An override set, replaced and cleared; each a new revision.
        self.ok("object", "set-material", scene, plain, "--material", "cardboard")
        self.ok("object", "set-material", scene, black, "--clear")
        after = self.scene_json(scene)
        self.assertEqual(int(after["revision"]), int(revision) + 2)
        objects = {o["objectId"]: o for o in after["objects"]}
        self.assertEqual(objects[plain]["material"], {"preset": "cardboard"})
        self.assertNotIn("material", objects[black])
        self.assertIn("material machined-aluminium (the mesh's)",
                      next(l for l in self.ok("scene", "get", scene).splitlines() if black in l))

        # Acknowledged is durable: kill -9, not a clean stop.
        self.server.kill9()
        self.server.start()
        self.assertEqual(self.scene_json(scene), after)
        self.assertEqual(json.loads(self.ok("--json", "mesh", "get", mesh))["material"],
                         {"preset": "machined-aluminium"})
        self.assertNotIn("material", json.loads(self.ok("--json", "mesh", "get", bare_mesh)))

    def test_raw_requests_with_both_or_bad_values_are_refused(self):
        with self.server.channel() as channel:
            scenes = scene_pb2_grpc.SceneServiceStub(channel)
            scene = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="raw")).scene
            with open(BUNNY, "rb") as f:
                data = f.read()

            def upload(material):
                def requests():
                    yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                        name="bunny.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data), material=material))
                    yield scene_pb2.UploadMeshRequest(chunk=data)
                return scenes.UploadMesh(requests(), timeout=60).mesh

            values = scene_pb2.MaterialValues(diffuse_albedo=0.5, metallic=0, roughness=0.5, specular_reflectance=0.04)
            mesh = upload(scene_pb2.Material(values=values))
            self.assertEqual(mesh.material.values, values)
            both = scene_pb2.Material(preset="cardboard", values=values)
            neither = scene_pb2.Material()
            bad = [
                (both, "material: give a preset or values, not both"),
                (neither, "material: give a preset or values"),
                (scene_pb2.Material(values=scene_pb2.MaterialValues(
                    diffuse_albedo=math.nan, roughness=0.5)), "material.values.diffuse_albedo: NaN"),
                (scene_pb2.Material(values=scene_pb2.MaterialValues(
                    diffuse_albedo=0.5, roughness=1e19)), "material.values.roughness"),
                (scene_pb2.Material(values=scene_pb2.MaterialValues(
                    diffuse_albedo=0.5, roughness=0.5, specular_reflectance=-math.inf)),
                 "material.values.specular_reflectance: NaN or infinite"),
            ]
            meshes = len(scenes.ListMeshes(scene_pb2.ListMeshesRequest()).meshes)
            for material, message in bad:
                for call in (lambda: scenes.AddObject(scene_pb2.AddObjectRequest(
                                 scene_id=scene.scene_id, mesh_id=mesh.mesh_id, material=material)),
                             lambda: upload(material)):
                    with self.assertRaises(grpc.RpcError) as caught:
                        call()
                    self.assertEqual(caught.exception.code(), C.INVALID_ARGUMENT, caught.exception.details())
                    self.assertIn(message, caught.exception.details())
            stored = scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene
            self.assertEqual((stored.revision, len(stored.objects)), (scene.revision, 0))
            self.assertEqual(len(scenes.ListMeshes(scene_pb2.ListMeshesRequest()).meshes), meshes)
            with self.assertRaises(grpc.RpcError) as caught:
                scenes.SetObjectMaterial(scene_pb2.SetObjectMaterialRequest(
                    scene_id=scene.scene_id, object_id="obj_0000000000000000"))
            self.assertEqual(caught.exception.code(), C.NOT_FOUND)

    def test_python_client_round_trip(self):
        with Client(self.server.address) as client:
            presets = client.list_material_presets()
            self.assertEqual(presets[0].name, "matte-grey")
            self.assertEqual(presets[0].values.roughness, 0.9)
            values = dict(diffuse_albedo=0.2, metallic=0.5, roughness=0.25, specular_reflectance=0.03)
            mesh = client.upload_mesh(BUNNY, unit="m", material=values)
            self.assertEqual(mesh.material.values.metallic, 0.5)
            self.assertEqual(client.get_mesh(mesh.mesh_id).material, mesh.material)
            scene = client.create_scene("py")
            obj = client.add_object(scene.scene_id, mesh.mesh_id, material="polished-steel")
            self.assertEqual(obj.material.preset, "polished-steel")
            self.assertEqual(client.get_scene(scene.scene_id).objects[0].material.preset, "polished-steel")
            cleared = client.set_object_material(scene.scene_id, obj.object_id, None)
            self.assertFalse(cleared.HasField("material"))
            self.assertFalse(client.get_scene(scene.scene_id).objects[0].HasField("material"))
            with self.assertRaises(VscanError) as caught:
                client.set_object_material(scene.scene_id, obj.object_id, "unobtainium")
            self.assertIn("material.preset", str(caught.exception))


if __name__ == "__main__":
    unittest.main()
