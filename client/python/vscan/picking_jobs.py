"""Picking jobs of the Client: a mounted robot empties the bin a succeeded bin fill left in its scene,
step by step (JobService.StartPicking), and the reports it leaves (picking.json, and each step's
step-NNN-truth.json), docs/GRASPING.md "Emptying a bin"."""

from . import convert
from ._stubs import sensor_pb2  # noqa: F401  (puts the generated stubs on sys.path)
from .picking import _PICK_OPTIONS, gripper_message
from .reports import parse_report

from vscan.v1 import job_pb2  # noqa: E402

PICKING_REPORT = "picking.json"

# start_picking's keyword options that are fields of PickingSpec itself.
_SPEC_OPTIONS = {"name", "width", "height", "horizontal_fov_deg", "seed", "max_steps", "max_failures_in_a_row"}


def picking_spec(bin_job_id, mount_id, gripper, truth=False, sensor_pose=None, **options):
    """A job_pb2.PickingSpec. gripper: SuctionCup, ParallelJaws or a dict (vscan.picking). truth:
    plan on the parts' true poses rather than a scan and the baseline localizer. sensor_pose: a 4x4
    world_from_sensor (None: 0.65 m above the bin's floor, looking down). options: name, width,
    height, horizontal_fov_deg, seed, max_steps, max_failures_in_a_row, and check_picks' grasp and
    pick options (max_grasps, body_length, approach_distance, ...); 0 or absent takes the server's
    default."""
    spec = job_pb2.PickingSpec(bin_job_id=bin_job_id, mount_id=mount_id, gripper=gripper_message(gripper))
    if truth:
        spec.perception = job_pb2.PICKING_PERCEPTION_TRUTH
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
