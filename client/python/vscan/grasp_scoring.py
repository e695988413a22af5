"""The gripper of score_poses and score_dataset_results: whether a grasp planned on each estimate
would have held the true part (docs/LOCALIZATION.md, "Grasp success").

A gripper is a SuctionCup or ParallelJaws (these, or any dataclass of that name and fields), a dict
{"suction": {...}} or {"jaws": {...}} of their fields, or a vscan.v1.Gripper. Metres and degrees;
a field left at None takes the server's default. Values go to the server as given: it validates
them and names the field it refuses."""

from dataclasses import dataclass, fields, is_dataclass
from typing import Optional

from ._stubs import sensor_pb2  # noqa: F401  (puts the generated stubs on sys.path)

from vscan.v1 import common_pb2, picking_pb2  # noqa: E402


@dataclass
class SuctionCup:
    """A suction cup; metres and degrees (None: the server's default, docs/GRASPING.md)."""
    diameter: Optional[float] = None
    stroke: Optional[float] = None
    max_tilt_deg: Optional[float] = None
    min_flat_fraction: Optional[float] = None


@dataclass
class ParallelJaws:
    """Parallel jaws; metres and degrees (None: the server's default, docs/GRASPING.md)."""
    max_opening: Optional[float] = None
    min_opening: Optional[float] = None
    finger_width: Optional[float] = None
    finger_depth: Optional[float] = None
    finger_length: Optional[float] = None
    finger_thickness: Optional[float] = None
    max_friction_angle_deg: Optional[float] = None


def scoring_gripper(gripper):
    """A vscan.v1.Gripper from any form the module docstring names."""
    if isinstance(gripper, picking_pb2.Gripper):
        return gripper
    if isinstance(gripper, dict):
        if len(gripper) != 1 or next(iter(gripper)) not in ("suction", "jaws"):
            raise ValueError("gripper: a dict needs one key, 'suction' or 'jaws'")
        kind, values = next(iter(gripper.items()))
        gripper = (SuctionCup if kind == "suction" else ParallelJaws)(**values)
    kind = type(gripper).__name__
    if not is_dataclass(gripper) or kind not in ("SuctionCup", "ParallelJaws"):
        raise TypeError(f"gripper: SuctionCup, ParallelJaws, a dict or a vscan.v1.Gripper, not {kind}")
    out = picking_pb2.Gripper()
    target = out.suction if kind == "SuctionCup" else out.jaws
    target.SetInParent()
    for field in fields(gripper):
        value = getattr(gripper, field.name)
        if value is not None:
            setattr(target, field.name, float(value))
    return out


def set_grasp_scoring(request, gripper, up=None, max_grasps=None, seed=None, candidates=None):
    """Fills a ScorePosesRequest's or ScoreDatasetResultsRequest's gripper, up and grasp_options;
    gripper None leaves them unset (no grasp figures)."""
    if gripper is None:
        return
    request.gripper.CopyFrom(scoring_gripper(gripper))
    if up is not None:
        x, y, z = (float(v) for v in up)
        request.up.CopyFrom(common_pb2.Vector3(x=x, y=y, z=z))
    if max_grasps is not None:
        request.grasp_options.max_grasps = int(max_grasps)
    if seed is not None:
        request.grasp_options.seed = int(seed)
    if candidates is not None:
        request.grasp_options.candidates = int(candidates)
