"""Picking jobs of the Client: a mounted robot empties the bin a succeeded bin fill left in its scene,
step by step (JobService.StartPicking), and the reports it leaves (picking.json, and each step's
step-NNN-truth.json), docs/GRASPING.md "Emptying a bin"."""

import numpy as np

from . import convert
from ._stubs import sensor_pb2  # noqa: F401  (puts the generated stubs on sys.path)
from .clouds import parse_ply
from .picking import _PICK_OPTIONS, gripper_message
from .reports import parse_report

from vscan.v1 import job_pb2  # noqa: E402

PICKING_REPORT = "picking.json"

# start_picking's keyword options that are fields of PickingSpec itself.
_SPEC_OPTIONS = {"name", "width", "height", "horizontal_fov_deg", "seed", "max_steps", "max_failures_in_a_row",
                 "estimates_timeout_s"}

_PERCEPTIONS = {
    "baseline": job_pb2.PICKING_PERCEPTION_UNSPECIFIED,
    "truth": job_pb2.PICKING_PERCEPTION_TRUTH,
    "client": job_pb2.PICKING_PERCEPTION_CLIENT,
}


def picking_spec(bin_job_id, mount_id, gripper, truth=False, sensor_pose=None, perception=None, **options):
    """A job_pb2.PickingSpec. gripper: SuctionCup, ParallelJaws or a dict (vscan.picking). truth:
    plan on the parts' true poses rather than a scan and the baseline localizer. perception:
    "baseline", "truth" or "client" (your own localizer: run_picking), overriding truth.
    sensor_pose: a 4x4 world_from_sensor (None: 0.65 m above the bin's floor, looking down).
    options: name, width, height, horizontal_fov_deg, seed, max_steps, max_failures_in_a_row,
    estimates_timeout_s, and check_picks' grasp and pick options (max_grasps, body_length,
    approach_distance, ...); 0 or absent takes the server's default."""
    spec = job_pb2.PickingSpec(bin_job_id=bin_job_id, mount_id=mount_id, gripper=gripper_message(gripper))
    if truth:
        spec.perception = job_pb2.PICKING_PERCEPTION_TRUTH
    if perception is not None:
        if perception not in _PERCEPTIONS:
            raise ValueError(f"perception: one of {', '.join(_PERCEPTIONS)}, not {perception!r}")
        spec.perception = _PERCEPTIONS[perception]
    if sensor_pose is not None:
        spec.sensor_pose.CopyFrom(convert.pose(matrix=sensor_pose))
    for name, value in options.items():
        if name in _SPEC_OPTIONS:
            setattr(spec, name, value)
        elif name in _PICK_OPTIONS:
            message, field = _PICK_OPTIONS[name]
            setattr(getattr(spec, message), field, value)
        else:
            known = ", ".join(sorted(_SPEC_OPTIONS | set(_PICK_OPTIONS)))
            raise TypeError(f"start_picking: unknown option {name!r}; one of {known}")
    return spec


class PickingJobCalls:
    """Mixed into Client; uses its job stub and call helpers."""

    def start_picking(self, bin_job_id, mount_id, gripper, truth=False, spec=None, **options):
        """Starts a picking job and returns its Job (QUEUED): a ready job_pb2.PickingSpec as spec, or
        the arguments of picking_spec(). Raises VscanError naming the field it refuses."""
        if spec is None:
            spec = picking_spec(bin_job_id, mount_id, gripper, truth, **options)
        return self._call(self._jobs.StartPicking, job_pb2.StartPickingRequest(spec=spec)).job

    def validate_picking(self, bin_job_id, mount_id, gripper, truth=False, spec=None, **options):
        """Checks a picking job as start_picking would and starts nothing; raises VscanError naming
        the field (spec.mount_id, spec.gripper.suction.diameter, ...)."""
        if spec is None:
            spec = picking_spec(bin_job_id, mount_id, gripper, truth, **options)
        self._call(self._jobs.StartPicking, job_pb2.StartPickingRequest(spec=spec, validate_only=True))

    def submit_picking_estimates(self, job_id, step, estimates, frame="world"):
        """Sends what your localizer found in step step's scan to a picking job with client perception
        (JobService.SubmitPickingEstimates); returns how many the job stored. estimates: (part name,
        4x4 pose, score) tuples, the pose world_from_part (frame="world") or camera_from_part in the
        scan's sensor frame (frame="camera"). Raises VscanError: FAILED_PRECONDITION when the job
        awaits another step (named) or nothing, ALREADY_EXISTS for a step sent already,
        INVALID_ARGUMENT naming the estimate (estimates[3].part, estimates[0].world_from_part...)."""
        if frame not in ("world", "camera"):
            raise ValueError(f"frame: 'world' or 'camera', not {frame!r}")
        request = job_pb2.SubmitPickingEstimatesRequest(job_id=job_id, step=int(step))
        for part, pose, score in estimates:
            estimate = request.estimates.add(part=part, score=float(score))
            getattr(estimate, "world_from_part" if frame == "world" else "camera_from_part").CopyFrom(
                convert.pose(matrix=pose))
        return self._call(self._jobs.SubmitPickingEstimates, request).accepted

    def picking_step_scan(self, job_id, awaited):
        """The points (N x 3 float32 numpy array, world frame, metres) of the scan a job awaiting
        estimates stored (awaited: Job.awaiting_estimates); an empty array when the scan saw nothing."""
        if awaited.scan_artifact:
            for artifact in self.get_job(job_id).artifacts:
                if artifact.name == awaited.scan_artifact:
                    _, data = self.read_artifact(job_id, artifact.artifact_id)
                    return parse_ply(data).positions
        return np.zeros((0, 3), dtype=np.float32)

    def run_picking(self, spec, estimator, frame="world", timeout=None, job_id=None):
        """Runs a picking job with your localizer and returns the ended Job (as get_job does). spec: a
        job_pb2.PickingSpec (picking_spec(...)); its perception is set to client. For each step the job
        awaits, estimator(step, points) is called with the step's scan (points: N x 3 numpy array,
        world frame) and returns (part name, 4x4 pose, score) tuples in frame (see
        submit_picking_estimates). job_id: follow a job already started (or resumed) instead. When
        estimator raises, the job is cancelled and the error raised."""
        if job_id is None:
            started = job_pb2.PickingSpec()
            started.CopyFrom(spec)
            started.perception = job_pb2.PICKING_PERCEPTION_CLIENT
            job_id = self._call(self._jobs.StartPicking, job_pb2.StartPickingRequest(spec=started)).job.job_id
        sent = set()
        try:
            for response in self.watch_job(job_id, timeout=timeout):
                if not response.job.HasField("awaiting_estimates"):
                    continue
                awaited = response.job.awaiting_estimates
                if awaited.step in sent:
                    continue
                points = self.picking_step_scan(job_id, awaited)
                self.submit_picking_estimates(job_id, awaited.step, estimator(awaited.step, points), frame=frame)
                sent.add(awaited.step)
        except BaseException:
            job = self.get_job(job_id)
            if job.state in (job_pb2.JOB_STATE_QUEUED, job_pb2.JOB_STATE_RUNNING):
                self.cancel_job(job_id)
            raise
        return self.get_job(job_id)

    def picking_report(self, job_id):
        """The job's picking.json as a dict, read through its message PickingReport
        (proto/vscan/v1/reports.proto): parts_at_start, picked, fell_out, left, end, outcomes and one
        dict per step (outcome, picked_part and picked_instance, world_from_tool, perceive_s, plan_s,
        settle_s, its scan and truth artifacts); None when the job has none (it has not ended)."""
        return self._job_report(job_id, PICKING_REPORT)

    def picking_step_truth(self, job_id, step):
        """Step step's step-NNN-truth.json as a dict (PickingStepTruth): the true parts the step started
        from and the estimates perception made, each with world_from_part; None when absent."""
        return self._job_report(job_id, f"step-{int(step):03d}-truth.json")

    def _job_report(self, job_id, name):
        for artifact in self.get_job(job_id).artifacts:
            if artifact.name == name:
                _, data = self.read_artifact(job_id, artifact.artifact_id)
                return parse_report(name, data)
        return None
