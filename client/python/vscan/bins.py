"""Bin fill calls of the Client: parts dropped into an open bin (a box or an uploaded mesh), settled by physics, then placed in
the scene (JobService.StartBinFill), and the report they leave (bin.json)."""

from . import convert
from ._stubs import sensor_pb2  # noqa: F401  (puts the generated stubs on sys.path)
from .reports import parse_report

from google.protobuf import json_format  # noqa: E402
from vscan.v1 import job_pb2  # noqa: E402

BIN_REPORT = "bin.json"

_PART_KEYS = {"mesh_id", "count", "scale", "name", "mass_kg", "density_kg_per_m3", "collision"}

_COLLISIONS = {"convex_hull": job_pb2.PART_COLLISION_CONVEX_HULL,
               "convex_decomposition": job_pb2.PART_COLLISION_CONVEX_DECOMPOSITION}


def bin_part(mesh_id, count, scale=1.0, name="", mass_kg=0.0, density_kg_per_m3=0.0, collision="convex_hull",
             material=None):
    """One part type: an uploaded mesh (in metres, converted from the unit declared at upload),
    count of them, an extra uniform scale, a name for the labels "<name>#<k>" (default: the mesh's),
    how it collides: "convex_hull" or "convex_decomposition", and what the placed parts are made
    of (a preset name or a dict of the four values, as upload_mesh takes; None: the mesh's)."""
    if collision not in _COLLISIONS:
        raise ValueError(f"collision: {collision!r} is not one of {sorted(_COLLISIONS)}")
    part = job_pb2.BinPart(mesh_id=mesh_id, count=int(count), scale=float(scale), name=name, mass_kg=float(mass_kg),
                           density_kg_per_m3=float(density_kg_per_m3),
                           collision=_COLLISIONS[collision])
    if material is not None:
        part.material.CopyFrom(convert.material(material))
    return part


def bin_fill_spec(scene_id, inner_size, parts, wall_thickness=0.0, bin_position=(0.0, 0.0, 0.0), bin_quat=None,
                  bin_matrix=None, seed=0, max_simulated_s=0.0, settle_move_m=0.0,
                  settle_turn_rad=0.0, settle_steps=0, time_step_s=0.0, name="", bin_mesh_id=None,
                  bin_mesh_scale=0.0, picks=None):
    """A BinFillSpec. The bin is a box, inner_size its inner (x, y, depth) in metres, or an
    uploaded mesh, bin_mesh_id (with bin_mesh_scale; inner_size then None); parts a list of
    bin_part() messages or dicts of its keyword arguments. The bin stands at bin_position (with
    bin_quat (w, x, y, z)) or bin_matrix (4x4 world_from_bin). Physics bounds left 0 take the
    server's defaults (docs/BINS.md). picks: the pick check after the fill, a job_pb2.BinPicks or a
    dict of its fields ({"mount_id": ..., "gripper": {"suction": {"diameter": 0.012}}, ...})."""
    spec = job_pb2.BinFillSpec(scene_id=scene_id, seed=int(seed), name=name)
    pose = convert.pose(bin_position, quat=bin_quat, matrix=bin_matrix)
    if bin_mesh_id is not None:
        if inner_size is not None or wall_thickness:
            raise ValueError("give inner_size (a box bin) or bin_mesh_id (a mesh bin), not both")
        spec.bin_mesh.mesh_id = bin_mesh_id
        spec.bin_mesh.scale = float(bin_mesh_scale)
        spec.bin_mesh.pose.CopyFrom(pose)
    else:
        spec.bin.inner_size.CopyFrom(convert.vector3(inner_size, "inner_size"))
        spec.bin.wall_thickness = float(wall_thickness)
        spec.bin.pose.CopyFrom(pose)
    for i, part in enumerate(parts):
        if isinstance(part, dict):
            unknown = set(part) - _PART_KEYS
            if unknown:
                raise ValueError(f"parts[{i}]: unknown keys {sorted(unknown)} (expected {sorted(_PART_KEYS)})")
            part = bin_part(**part)
        spec.parts.add().CopyFrom(part)
    physics = spec.physics
    physics.max_simulated_s = float(max_simulated_s)
    physics.settle_move_m = float(settle_move_m)
    physics.settle_turn_rad = float(settle_turn_rad)
    physics.settle_steps = int(settle_steps)
    physics.time_step_s = float(time_step_s)
    if picks is not None:
        if isinstance(picks, dict):
            picks = json_format.ParseDict(picks, job_pb2.BinPicks())
        spec.picks.CopyFrom(picks)
    return spec


class BinCalls:
    """Mixed into Client; uses its job stub and call helpers."""

    def start_bin_fill(self, scene_id=None, inner_size=None, parts=(), spec=None, **options):
        """Starts a bin fill and returns its Job (QUEUED): a ready job_pb2.BinFillSpec as spec, or
        the arguments of bin_fill_spec()."""
        if spec is None:
            spec = bin_fill_spec(scene_id, inner_size, parts, **options)
        return self._call(self._jobs.StartBinFill, job_pb2.StartBinFillRequest(spec=spec)).job

    def validate_bin_fill(self, scene_id="", inner_size=None, parts=(), spec=None, **options):
        """Checks a bin fill as start_bin_fill would and starts nothing; raises VscanError naming the
        field (spec.parts[1].count, ...). Empty ids are not looked up."""
        if spec is None:
            spec = bin_fill_spec(scene_id, inner_size, parts, **options)
        self._call(self._jobs.StartBinFill, job_pb2.StartBinFillRequest(spec=spec, validate_only=True))

    def bin_report(self, job_id):
        """The job's bin.json as a dict, read through its message BinReport (proto/vscan/v1/reports.proto):
        bin, parts with object and instance ids and world poses, end reason, counters, times; None
        when the job has none. Raises VscanError DATA_LOSS when the schema cannot read it."""
        for artifact in self.get_job(job_id).artifacts:
            if artifact.name == BIN_REPORT:
                _, data = self.read_artifact(job_id, artifact.artifact_id)
                return parse_report(BIN_REPORT, data)
        return None

    def bin_fill(self, scene_id=None, inner_size=None, parts=(), spec=None, timeout=None, **options):
        """Starts a bin fill, waits for it to end and returns (Job, bin.json as a dict)."""
        job = self.start_bin_fill(scene_id, inner_size, parts, spec=spec, **options)
        job = self.wait_job(job.job_id, timeout=timeout)
        return job, self.bin_report(job.job_id)
