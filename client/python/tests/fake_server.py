"""An in-process fake vscand (SceneService, ScanService, model jobs of JobService, health) for client tests."""

import json
import os
import sys
from concurrent import futures

import grpc
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from vscan._stubs import scan_pb2, scan_pb2_grpc, scene_pb2, scene_pb2_grpc  # noqa: E402
from vscan.v1 import job_pb2, job_pb2_grpc, model_pb2  # noqa: E402

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


# The report the fake model job leaves: two scans, one aligned, a mesh and an evaluation.
MODEL_REPORT = {
    "job_id": "job-m1", "kind": "model", "state": "SUCCEEDED", "frame": "model (world, table at 0 deg)",
    "scene_id": "scene-1", "clouds": 2, "crop": {"kind": "none"},
    "alignment": {"initial_pose": "known", "voxel_size": 0.002, "pose_graph": True, "seconds": 0.5, "aligned": 1,
                  "unaligned": 1,
                  "scans": [{"index": 0, "cloud_id": "cld-a", "name": "a", "aligned": True, "reason": "",
                             "fitness": 0.95},
                            {"index": 1, "cloud_id": "cld-b", "name": "b", "aligned": False,
                             "reason": "fitness 0.10 below 0.30"}],
                  "artifact": "aligned.ply"},
    "reconstruction": {"method": "poisson", "voxel_size": 0.001, "vertices": 300, "triangles": 596, "seconds": 0.2,
                       "artifact": "mesh.ply"},
    "evaluation": {"tau": 0.001, "ground_truth": {"objects": ["obj-1"], "area_m2": 0.01, "samples": 5000},
                   "union": {"precision": 0.9, "recall": 0.6, "f_score": 0.72, "accuracy_mean": 0.0004,
                             "accuracy_median": 0.0003, "completeness_mean": 0.002, "completeness_median": 0.0008,
                             "chamfer": 0.0012},
                   "coverage": 0.6, "uncovered_artifact": "uncovered.ply", "coverage_image": "coverage.png",
                   "next_best_views": [{"position": [0.3, 0.0, 0.2], "target": [0.0, 0.0, 0.05],
                                        "table_angle_deg": 180.0, "coverage_gain": 0.25, "coverage_after": 0.85}]},
}

# Artifact name -> bytes of the fake model job.
MODEL_FILES = {
    "model.json": json.dumps(MODEL_REPORT, indent=2).encode(),
    "aligned.ply": b"ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
                   b"property float y\nproperty float z\nend_header\n",
    "mesh.ply": b"mesh bytes",
    "uncovered.ply": b"uncovered bytes",
    "coverage.png": b"\x89PNG fake",
}


class FakeJobs(job_pb2_grpc.JobServiceServicer):
    """Model jobs: StartModel checks a little and records the spec; the job then has run already."""

    def __init__(self):
        self.last_model = None
        self.validated = None
        self.final_state = job_pb2.JOB_STATE_SUCCEEDED
        # Alignments a watch misses, as one that begins after the job aligned them does.
        self.scans_before_watch = 0

    def _job(self, state, with_artifacts):
        job = job_pb2.Job(job_id="job-m1", kind="model", state=state, steps_total=2,
                          steps_done=2 if state == self.final_state else 0)
        if self.last_model is not None:
            job.model.CopyFrom(self.last_model)
        if with_artifacts:
            for index, (name, data) in enumerate(MODEL_FILES.items()):
                job.artifacts.add(artifact_id=f"art-{index}", name=name, size_bytes=len(data),
                                  media_type="application/json" if name.endswith(".json") else "model/ply")
        return job

    def StartModel(self, request, context):
        spec = request.spec
        for index, cloud_id in enumerate(spec.cloud_ids):
            if cloud_id == "missing":
                context.abort(grpc.StatusCode.NOT_FOUND, f"spec.cloud_ids[{index}]: no cloud 'missing'")
        if spec.alignment.voxel_size > 0.1:
            context.abort(grpc.StatusCode.INVALID_ARGUMENT, "spec.alignment.voxel_size: must be at most 0.1 m")
        if request.validate_only:
            self.validated = spec
            return job_pb2.StartModelResponse()
        self.last_model = spec
        return job_pb2.StartModelResponse(job=self._job(job_pb2.JOB_STATE_QUEUED, False))

    def GetJob(self, request, context):
        if request.job_id != "job-m1":
            context.abort(grpc.StatusCode.NOT_FOUND, f"job_id: no job '{request.job_id}'")
        return job_pb2.GetJobResponse(job=self._job(self.final_state, True))

    def WatchJob(self, request, context):
        yield job_pb2.WatchJobResponse(job=self._job(job_pb2.JOB_STATE_RUNNING, False))
        scans = [model_pb2.ScanAlignment(cloud_id="cld-a", index=0, aligned=True, fitness=0.95, inlier_rmse=0.0002,
                                         has_error=True, rotation_error_deg=0.02, translation_error_m=0.00005),
                 model_pb2.ScanAlignment(cloud_id="cld-b", index=1, aligned=False, reason="fitness 0.10 below 0.30")]
        for sequence, scan in enumerate(scans, 1):
            if sequence <= self.scans_before_watch:
                continue
            job = self._job(job_pb2.JOB_STATE_RUNNING, False)
            job.steps_done = sequence
            yield job_pb2.WatchJobResponse(job=job, event=job_pb2.JobEvent(sequence=sequence, step=sequence - 1,
                                                                           message=f"scan {sequence - 1} aligned",
                                                                           alignment=scan))
        yield job_pb2.WatchJobResponse(job=self._job(self.final_state, False),
                                       event=job_pb2.JobEvent(sequence=3, message="model job finished"))

    def ReadArtifact(self, request, context):
        names = list(MODEL_FILES)
        index = int(request.artifact_id.split("-")[1])
        data = MODEL_FILES[names[index]]
        artifact = job_pb2.Artifact(artifact_id=request.artifact_id, name=names[index], size_bytes=len(data))
        yield job_pb2.ReadArtifactResponse(chunk=data[:5], artifact=artifact)
        yield job_pb2.ReadArtifactResponse(chunk=data[5:])


class FakeServer:
    """Starts the fakes on a free local port; stop() when done."""

    def __init__(self):
        self.server = grpc.server(futures.ThreadPoolExecutor(max_workers=4))
        self.scenes, self.scans = FakeScenes(), FakeScans()
        scene_pb2_grpc.add_SceneServiceServicer_to_server(self.scenes, self.server)
        scan_pb2_grpc.add_ScanServiceServicer_to_server(self.scans, self.server)
        self.jobs = FakeJobs()
        job_pb2_grpc.add_JobServiceServicer_to_server(self.jobs, self.server)
        health = grpc.unary_unary_rpc_method_handler(lambda request, context: b"\x08\x01")
        self.server.add_generic_rpc_handlers(
            (grpc.method_handlers_generic_handler("grpc.health.v1.Health", {"Check": health}),))
        self.port = self.server.add_insecure_port("127.0.0.1:0")
        self.address = f"127.0.0.1:{self.port}"
        self.server.start()

    def stop(self):
        self.server.stop(None)
