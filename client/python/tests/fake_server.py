"""An in-process fake vscand (SceneService, ScanService, health) for client tests."""

import os
import sys
from concurrent import futures

import grpc
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from vscan_client._stubs import scan_pb2, scan_pb2_grpc, scene_pb2, scene_pb2_grpc  # noqa: E402

N_POINTS = 5000


def make_cloud(n):
    i = np.arange(n, dtype=np.float32)
    return {
        "positions": np.stack([i, -i, 0.5 * i], axis=1).astype("<f4"),
        "normals": np.tile(np.array([0, 0, 1], dtype="<f4"), (n, 1)),
        "ranges": (i + 1).astype("<f4"),
        "intensities": np.full(n, 0.5, dtype="<f4"),
        "instance_ids": np.ones(n, dtype="<u4"),
    }


class FakeScenes(scene_pb2_grpc.SceneServiceServicer):
    def __init__(self):
        self.parts = []
        self.header = None
        self.data = b""
        self.last_add = None
        self.metadata = {}

    def CreateScene(self, request, context):
        self.metadata = dict(context.invocation_metadata())
        return scene_pb2.CreateSceneResponse(scene=scene_pb2.Scene(scene_id="scene-1", name=request.name))

    def ListScenes(self, request, context):
        page = {"": 0, "p2": 1}[request.page_token]
        scenes = [scene_pb2.Scene(scene_id=f"s{page * 2 + k}") for k in range(2)]
        return scene_pb2.ListScenesResponse(scenes=scenes, next_page_token="p2" if page == 0 else "")

    def GetScene(self, request, context):
        context.abort(grpc.StatusCode.NOT_FOUND, f"scene_id: no scene '{request.scene_id}'")

    def UploadMesh(self, request_iterator, context):
        for req in request_iterator:
            if req.WhichOneof("part") == "header":
                self.parts.append("header")
                self.header = req.header
            else:
                self.parts.append(len(req.chunk))
                self.data += req.chunk
        return scene_pb2.UploadMeshResponse(mesh=scene_pb2.Mesh(mesh_id="mesh-1", name=self.header.name))

    def AddObject(self, request, context):
        self.last_add = request
        return scene_pb2.AddObjectResponse(object=scene_pb2.SceneObject(object_id="obj-1", mesh_id=request.mesh_id),
                                           revision=2)

    def SetRotaryTable(self, request, context):
        return scene_pb2.SetRotaryTableResponse(table=request.table, revision=3)


class FakeScans(scan_pb2_grpc.ScanServiceServicer):
    def __init__(self):
        self.cloud = make_cloud(N_POINTS)
        self.announced = N_POINTS
        self.last_request = None

    def Scan(self, request, context):
        self.last_request = request
        fields = [scan_pb2.POINT_FIELD_POSITION, scan_pb2.POINT_FIELD_NORMAL, scan_pb2.POINT_FIELD_RANGE,
                  scan_pb2.POINT_FIELD_INTENSITY, scan_pb2.POINT_FIELD_INSTANCE_ID]
        yield scan_pb2.ScanResponse(header=scan_pb2.ScanHeader(scene_id=request.scene_id, points=self.announced,
                                                               rays=2 * N_POINTS, fields=fields))
        per = 1000
        for index, begin in enumerate(range(0, N_POINTS, per)):
            sl = slice(begin, min(begin + per, N_POINTS))
            chunk = scan_pb2.PointChunk(index=index, count=sl.stop - sl.start,
                                        **{k: v[sl].tobytes() for k, v in self.cloud.items()})
            yield scan_pb2.ScanResponse(chunk=chunk)
        yield scan_pb2.ScanResponse(statistics=scan_pb2.ScanStatistics(points=N_POINTS, hit_ratio=0.5))


class FakeServer:
    """Starts the fakes on a free local port; stop() when done."""

    def __init__(self):
        self.server = grpc.server(futures.ThreadPoolExecutor(max_workers=4))
        self.scenes, self.scans = FakeScenes(), FakeScans()
        scene_pb2_grpc.add_SceneServiceServicer_to_server(self.scenes, self.server)
        scan_pb2_grpc.add_ScanServiceServicer_to_server(self.scans, self.server)
        health = grpc.unary_unary_rpc_method_handler(lambda request, context: b"\x08\x01")
        self.server.add_generic_rpc_handlers(
            (grpc.method_handlers_generic_handler("grpc.health.v1.Health", {"Check": health}),))
        self.port = self.server.add_insecure_port("127.0.0.1:0")
        self.address = f"127.0.0.1:{self.port}"
        self.server.start()

    def stop(self):
        self.server.stop(None)
