"""Dataset jobs of the Client (StartDataset): every bin of a plan filled under every seed and seen by
every sensor, written by the server in the layout of docs/DATASETS.md and returned as dataset.tar."""

import io
import os
import tarfile

import grpc

from ._stubs import sensor_pb2  # noqa: F401  (puts the generated stubs on sys.path)
from .errors import VscanError
from .grasp_scoring import set_grasp_scoring

from vscan.v1 import job_pb2  # noqa: E402

DATASET_TAR = "dataset.tar"
# The server's bound on ScoreDatasetResultsRequest.results_csv.
MAX_RESULTS_CSV_BYTES = 3 << 20


class DatasetCalls:
    """Mixed into Client; uses its job and mesh calls."""

    def _dataset_spec(self, plan_path, resume_job_id):
        with open(plan_path) as f:
            text = f.read()
        spec = job_pb2.DatasetSpec(plan_yaml=text, resume_job_id=resume_job_id or "")
        plan_dir = os.path.dirname(os.path.abspath(plan_path))
        for named in self.plan_mesh_files(text):
            spec.mesh_ids[named.path] = self.upload_mesh(os.path.join(plan_dir, named.path), named.unit).mesh_id
        return spec

    def plan_mesh_files(self, plan_text):
        """The mesh files a dataset plan's parts name (PlanMeshFile: path as the plan writes it, unit),
        each once, as the server reads the plan: the client parses no YAML of its own."""
        request = job_pb2.StartDatasetRequest(spec=job_pb2.DatasetSpec(plan_yaml=plan_text), list_mesh_files=True)
        return list(self._call(self._jobs.StartDataset, request).mesh_files)

    def start_dataset(self, plan_path, resume_job_id=None):
        """Uploads the plan's mesh files and starts a dataset job; returns its Job (QUEUED, kind
        "dataset"). resume_job_id continues the directory of that ended dataset job."""
        spec = self._dataset_spec(plan_path, resume_job_id)
        return self._call(self._jobs.StartDataset, job_pb2.StartDatasetRequest(spec=spec)).job

    def validate_dataset(self, plan_path):
        """Checks the plan as start_dataset would (its meshes are uploaded) and starts nothing."""
        spec = self._dataset_spec(plan_path, None)
        self._call(self._jobs.StartDataset, job_pb2.StartDatasetRequest(spec=spec, validate_only=True))

    def run_dataset(self, plan_path, resume_job_id=None, directory=None, timeout=None):
        """start_dataset, then follows the job until it ends and returns it (GetJob); with directory,
        a job that succeeded is downloaded there. Watch a job with watch_job (one event per scene)
        and cancel it with cancel_job; the scenes it finished stay for resume_job_id."""
        job = self.wait_job(self.start_dataset(plan_path, resume_job_id).job_id, timeout=timeout)
        if directory is not None and job.state == job_pb2.JOB_STATE_SUCCEEDED:
            self.download_dataset(job.job_id, directory)
        return job

    def download_dataset(self, job_id, directory):
        """Extracts the finished job's dataset.tar into directory; returns the paths written."""
        for artifact in self.get_job(job_id).artifacts:
            if artifact.name == DATASET_TAR:
                _, data = self.read_artifact(job_id, artifact.artifact_id)
                return _extract(data, directory)
        raise VscanError(grpc.StatusCode.FAILED_PRECONDITION, f"job {job_id} has no {DATASET_TAR}")

    def score_dataset_results(self, job_id, results, timeout=600, gripper=None, up=None, max_grasps=None,
                              grasp_seed=None):
        """Scores BOP results (scene_id,im_id,obj_id,score,R,t,time; R row-major, t in mm) against the
        ground truth of the succeeded dataset job job_id, as bop_toolkit's evaluation does (ADD(-S)
        recall at 10% of the diameter, MSSD average recall). results is the CSV's bytes, or the path
        of the file (str or os.PathLike). Returns the ScoreDatasetResultsResponse: overall, objects
        (per obj_id) and scenes, each a DatasetRecall (valid_instances, estimates, add_correct,
        add_recall, mssd_average_recall, mssd_recalls).

        gripper (see score_poses) adds grasp_holds and grasp_success to every DatasetRecall, the models
        and poses taken in metres; up is the direction against gravity in the camera frame (default
        +z)."""
        if isinstance(results, (str, os.PathLike)):
            with open(results, "rb") as f:
                results = f.read()
        if len(results) > MAX_RESULTS_CSV_BYTES:
            raise VscanError(grpc.StatusCode.RESOURCE_EXHAUSTED,
                             f"results_csv: {len(results)} bytes, more than the {MAX_RESULTS_CSV_BYTES >> 20} MiB "
                             "the server takes in one call")
        request = job_pb2.ScoreDatasetResultsRequest(job_id=job_id, results_csv=bytes(results))
        set_grasp_scoring(request, gripper, up=up, max_grasps=max_grasps, seed=grasp_seed)
        return self._call(self._jobs.ScoreDatasetResults, request, timeout=timeout)


def _extract(data, directory):
    """Writes the regular files of a dataset tar under directory, refusing names that leave it."""
    paths = []
    with tarfile.open(fileobj=io.BytesIO(data)) as tar:
        for member in tar.getmembers():
            parts = member.name.split("/")
            if not member.isfile() or member.name.startswith("/") or ".." in parts:
                raise VscanError(grpc.StatusCode.DATA_LOSS, f"{DATASET_TAR}: an unsafe entry '{member.name}'")
            path = os.path.join(directory, *parts)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "wb") as out:
                out.write(tar.extractfile(member).read())
            paths.append(path)
    return paths
