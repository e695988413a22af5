"""Nothing acknowledged is lost: kill -9 the server and find every scene, mesh and object again."""

import unittest

import numpy as np

from harness import BUNNY, Server, common_pb2, scan_points, scene_pb2
from vscan.v1 import scene_pb2_grpc


class RestartTest(unittest.TestCase):
    def test_kill9_and_restart(self):
        server = Server().start()
        try:
            channel = server.channel()
            scenes = scene_pb2_grpc.SceneServiceStub(channel)
            scene = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="durable")).scene
            with open(BUNNY, "rb") as f:
                data = f.read()

            def requests():
                yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
                    name="bunny.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data)))
                yield scene_pb2.UploadMeshRequest(chunk=data)
            mesh = scenes.UploadMesh(requests(), timeout=60).mesh
            pose = common_pb2.Pose(quaternion=common_pb2.QuaternionPose(
                translation=common_pb2.Vector3(x=0.02, y=0.0, z=-0.03), qw=1.0))
            obj = scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id,
                                                              pose=pose, label="bunny")).object
            scenes.SetRotaryTable(scene_pb2.SetRotaryTableRequest(
                scene_id=scene.scene_id, table=scene_pb2.RotaryTable(enabled=True, angle_deg=15)))
            before = scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene
            points_before = scan_points(channel, scene.scene_id)
            channel.close()

            server.kill9()
            server.start()
            channel = server.channel()
            scenes = scene_pb2_grpc.SceneServiceStub(channel)
            after = scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene
            self.assertEqual(before, after)
            self.assertEqual(after.objects[0].object_id, obj.object_id)
            got_mesh = scenes.GetMesh(scene_pb2.GetMeshRequest(mesh_id=mesh.mesh_id)).mesh
            self.assertEqual(got_mesh, mesh)
            points_after = scan_points(channel, scene.scene_id)
            np.testing.assert_array_equal(points_before, points_after)
            channel.close()
        finally:
            server.cleanup()


if __name__ == "__main__":
    unittest.main()
