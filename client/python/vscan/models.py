"""Model jobs of the Client: alignment, reconstruction and evaluation of stored clouds (StartModel),
and the report they leave (model.json)."""

import grpc

from . import convert
from ._stubs import sensor_pb2  # noqa: F401  (puts the generated stubs on sys.path)
from .errors import VscanError
from .reports import parse_report

from vscan.v1 import job_pb2, model_pb2  # noqa: E402

MODEL_REPORT = "model.json"

INITIAL_POSES = {"known": model_pb2.INITIAL_POSE_KNOWN, "features": model_pb2.INITIAL_POSE_FEATURES}
RECONSTRUCTION_METHODS = {"tsdf": model_pb2.RECONSTRUCTION_METHOD_TSDF,
                          "poisson": model_pb2.RECONSTRUCTION_METHOD_POISSON}


def alignment_options(initial_pose=None, voxel_size=0.0, max_correspondence_distance=0.0, min_fitness=0.0,
                      pose_graph=True):
    """AlignmentOptions. initial_pose: "known" or "features" (None: known when every cloud has a sensor
    pose). Lengths in metres; 0 lets the server pick them (min_fitness 0 means 0.3)."""
    options = model_pb2.AlignmentOptions(voxel_size=float(voxel_size),
                                         max_correspondence_distance=float(max_correspondence_distance),
                                         min_fitness=float(min_fitness), skip_pose_graph=not pose_graph)
    if initial_pose is not None:
        options.initial_pose = convert._lookup(INITIAL_POSES, initial_pose, "initial_pose")
    return options


def reconstruction_options(method=None, voxel_size=0.0, poisson_depth=0):
    """ReconstructionOptions. method: "tsdf" or "poisson" (None: TSDF when every scan has a camera and
    pixel coordinates). voxel_size in metres and poisson_depth (8) are the server's choice at 0."""
    options = model_pb2.ReconstructionOptions(voxel_size=float(voxel_size), poisson_depth=int(poisson_depth))
    if method is not None:
        options.method = convert._lookup(RECONSTRUCTION_METHODS, method, "method")
    return options


def evaluation_options(tau=0.0, next_best_views=None):
    """EvaluationOptions. tau in metres (0: 1/200 of the ground truth's diagonal); next_best_views: how
    many to propose (None: 3; 0: none)."""
    options = model_pb2.EvaluationOptions(tau=float(tau))
    if next_best_views == 0:
        options.skip_next_best_views = True
    elif next_best_views is not None:
        options.next_best_views = int(next_best_views)
    return options


def _options(value, build, what):
    """A ready message, a dict of build()'s keyword arguments, or None."""
    if value is None or isinstance(value, dict):
        return build(**(value or {}))
    if not hasattr(value, "DESCRIPTOR"):
        raise ValueError(f"{what}: give a dict of options or a message, got {value!r}")
    return value


def crop_bounds(crop):
    """Bounds from (min, max), each (x, y, z) in metres in the model frame."""
    low, high = crop
    return convert.bounds(low, high, "crop")


def model_spec(cloud_ids=None, campaign_job_id=None, skip_alignment=False, initial_pose=None, voxel_size=0.0,
               max_correspondence_distance=0.0, min_fitness=0.0, pose_graph=True, reconstruct=False, method=None,
               reconstruction_voxel_size=0.0, poisson_depth=0, evaluate=False, tau=0.0, next_best_views=None,
               scene_id="", mount_id="", crop=None, name=""):
    """A ModelSpec: the clouds (cloud_ids, in order) or every scan of campaign_job_id, and what to do
    with them. The alignment options are those of alignment_options(); method, reconstruction_voxel_size
    and poisson_depth those of reconstruction_options(); tau and next_best_views those of
    evaluation_options(). crop: (min, max) corners in the model frame."""
    if (not cloud_ids) == (not campaign_job_id):
        raise ValueError("model_spec: give cloud_ids or campaign_job_id")
    spec = model_pb2.ModelSpec(cloud_ids=list(cloud_ids or ()), campaign_job_id=campaign_job_id or "",
                               skip_alignment=bool(skip_alignment), reconstruct=bool(reconstruct),
                               evaluate=bool(evaluate), scene_id=scene_id, mount_id=mount_id, name=name)
    spec.alignment.CopyFrom(alignment_options(initial_pose, voxel_size, max_correspondence_distance, min_fitness,
                                              pose_graph))
    if reconstruct:
        spec.reconstruction.CopyFrom(reconstruction_options(method, reconstruction_voxel_size, poisson_depth))
    if evaluate:
        spec.evaluation.CopyFrom(evaluation_options(tau, next_best_views))
    if crop is not None:
        spec.crop.CopyFrom(crop_bounds(crop))
    return spec


class ModelCalls:
    """Mixed into Client; uses its job calls."""

    def start_model(self, cloud_ids=None, campaign_job_id=None, spec=None, **options):
        """Starts a model job and returns its Job (QUEUED, kind "model").

        Either a ready model_pb2.ModelSpec as spec, or cloud_ids (or campaign_job_id) and the options
        of model_spec(): e.g. start_model(campaign_job_id=job, evaluate=True, tau=0.001)."""
        if spec is None:
            spec = model_spec(cloud_ids, campaign_job_id, **options)
        return self._call(self._jobs.StartModel, job_pb2.StartModelRequest(spec=spec)).job

    def validate_model(self, cloud_ids=None, campaign_job_id=None, spec=None, **options):
        """Checks a model job as start_model would and starts nothing; raises VscanError naming the field."""
        if spec is None:
            spec = model_spec(cloud_ids, campaign_job_id, **options)
        self._call(self._jobs.StartModel, job_pb2.StartModelRequest(spec=spec, validate_only=True))

    def watch_alignments(self, job_id, timeout=None):
        """Yields a ScanAlignment per scan as the job aligns it (a model job, or a campaign with align),
        until the job ends; get_job() then returns how it ended. A watch sees the events after it
        begins: the scans aligned before that come from the job's model.json once it ends (without
        union_points), so that every scan is yielded once."""
        seen = set()
        for response in self.watch_job(job_id, timeout=timeout):
            if response.HasField("event") and response.event.HasField("alignment"):
                seen.add(response.event.alignment.index)
                yield response.event.alignment
        try:
            report = self.model_report(job_id)
        except VscanError as err:
            if err.code == grpc.StatusCode.NOT_FOUND:  # the job ended without aligning
                return
            raise
        for scan in report.get("alignment", {}).get("scans", []):
            if scan["index"] not in seen:
                yield _alignment_from_report(scan)

    def model_report(self, job_id):
        """The job's model.json as a dict (docs/MODEL.md), read through its message ModelReport
        (proto/vscan/v1/reports.proto): alignment, reconstruction, evaluation.

        Raises VscanError NOT_FOUND when the job left none (it did not align, or has not ended),
        DATA_LOSS when the schema cannot read it."""
        job = self.get_job(job_id)
        artifact = next((a for a in job.artifacts if a.name == MODEL_REPORT), None)
        if artifact is None:
            raise VscanError(grpc.StatusCode.NOT_FOUND,
                             f"job '{job_id}' has no {MODEL_REPORT} (state {job_pb2.JobState.Name(job.state)})")
        _, data = self.read_artifact(job_id, artifact.artifact_id)
        return parse_report(MODEL_REPORT, data)


def _alignment_from_report(scan):
    """A ScanAlignment from one scan of model.json's alignment section."""
    alignment = model_pb2.ScanAlignment(index=scan["index"], cloud_id=scan["cloud_id"], name=scan["name"],
                                        aligned=scan["aligned"], reason=scan["reason"], fitness=scan["fitness"],
                                        inlier_rmse=scan["inlier_rmse"])
    if len(scan.get("pose", [])) == 16:
        alignment.pose.values.extend(scan["pose"])
    if "rotation_error_deg" in scan:
        alignment.has_error = True
        for key in ("rotation_error_deg", "translation_error_m", "initial_rotation_error_deg",
                    "initial_translation_error_m"):
            setattr(alignment, key, scan.get(key, 0.0))
    return alignment
