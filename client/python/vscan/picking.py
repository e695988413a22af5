"""Picking calls of the Client: a gripper's grasps of a stored mesh and which parts of a mount's
scene the robot could pick (PickingService, docs/GRASPING.md).

Values go to the server as given: it validates them and names the field it refuses. A gripper
field left at None takes the server's default."""

from dataclasses import dataclass, fields
from typing import Optional

import grpc
import numpy as np

from .errors import from_rpc_error

from vscan.v1 import picking_pb2, picking_pb2_grpc  # noqa: E402


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


@dataclass
class Grasp:
    """A grasp in the part's frame: the tool frame (4x4, z along the approach into the part), the
    approach, a quality in [0, 1] and, for jaws, the distance between the contacts (metres)."""
    quality: float
    part_from_tool: np.ndarray
    approach: np.ndarray
    opening: float

    @property
    def position(self):
        return self.part_from_tool[:3, 3]


@dataclass
class PartPick:
    """One part's verdict. failure: None when pickable, else "COVERED", "NO_GRASP",
    "GRIPPER_COLLISION", "UNREACHABLE" or "ARM_COLLISION" (the furthest check any grasp reached).
    world_from_tool (4x4) and joint_positions are set when pickable; covered_by_object_id when
    covered."""
    object_id: str
    label: str
    pickable: bool
    failure: Optional[str]
    detail: str
    grasp_index: Optional[int]
    world_from_tool: Optional[np.ndarray]
    joint_positions: np.ndarray
    covered_by_object_id: str
    grasps_from_above: int
    grasps_clear: int
    reach_checks: int


@dataclass
class Picks:
    """CheckPicks' answer: the parts in request order (or the scene's), how many are pickable."""
    scene_id: str
    parts: list
    pickable: int
    grasps_generated: int
    elapsed_ms: float

    def by_object(self, object_id):
        return next(p for p in self.parts if p.object_id == object_id)


# CheckPicks' keyword options: (message, field).
_PICK_OPTIONS = {
    "approach_distance": ("pick_options", "approach_distance"),
    "max_approach_tilt_deg": ("pick_options", "max_approach_tilt_deg"),
    "cover_distance": ("pick_options", "cover_distance"),
    "max_reach_checks": ("pick_options", "max_reach_checks"),
    "body_length": ("pick_options", "body_length"),
    "ik_time_budget_ms": ("pick_options", "ik_time_budget_ms"),
    "max_grasps": ("grasp_options", "max_grasps"),
    "seed": ("grasp_options", "seed"),
    "candidates": ("grasp_options", "candidates"),
    "surface_samples": ("grasp_options", "surface_samples"),
}


def gripper_message(gripper):
    """A vscan.v1.Gripper from a SuctionCup, a ParallelJaws, a dict with "suction" or "jaws" (a
    dict of that dataclass's fields), or the message itself; None: no gripper (the server refuses)."""
    out = picking_pb2.Gripper()
    if gripper is None:
        return out
    if isinstance(gripper, picking_pb2.Gripper):
        return gripper
    if isinstance(gripper, dict):
        if len(gripper) != 1 or next(iter(gripper)) not in ("suction", "jaws"):
            raise ValueError("gripper: a dict needs one key, 'suction' or 'jaws'")
        kind, values = next(iter(gripper.items()))
        gripper = (SuctionCup if kind == "suction" else ParallelJaws)(**values)
    if isinstance(gripper, SuctionCup):
        target = out.suction
    elif isinstance(gripper, ParallelJaws):
        target = out.jaws
    else:
        raise TypeError(f"gripper: SuctionCup, ParallelJaws or a dict, not {type(gripper).__name__}")
    target.SetInParent()
    for field in fields(gripper):
        value = getattr(gripper, field.name)
        if value is not None:
            setattr(target, field.name, float(value))
    return out


def _matrix(pose):
    return np.asarray(pose.matrix.values, dtype=float).reshape(4, 4)


def _vector(v):
    return np.array([v.x, v.y, v.z], dtype=float)


def _grasp(message):
    return Grasp(quality=message.quality, part_from_tool=_matrix(message.part_from_tool),
                 approach=_vector(message.approach), opening=message.opening)


def _failure(value):
    if value == picking_pb2.PICK_FAILURE_UNSPECIFIED:
        return None
    return picking_pb2.PickFailure.Name(value).removeprefix("PICK_FAILURE_")


def _part_pick(message):
    return PartPick(
        object_id=message.object_id, label=message.label, pickable=message.pickable,
        failure=_failure(message.failure), detail=message.detail,
        grasp_index=message.grasp_index if message.pickable else None,
        world_from_tool=_matrix(message.world_from_tool) if message.pickable else None,
        joint_positions=np.asarray(message.joint_positions, dtype=float),
        covered_by_object_id=message.covered_by_object_id, grasps_from_above=message.grasps_from_above,
        grasps_clear=message.grasps_clear, reach_checks=message.reach_checks)


class PickingCalls:
    """Mixed into Client; uses its channel, metadata and call helpers."""

    @property
    def _picking(self):
        stub = self.__dict__.get("_picking_stub")
        if stub is None:
            stub = self.__dict__["_picking_stub"] = picking_pb2_grpc.PickingServiceStub(self._channel)
        return stub

    def _picking_call(self, method, request, timeout):
        try:
            return method(request, timeout=timeout or self._stream_timeout, metadata=self._metadata)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None

    def generate_grasps(self, mesh_id, gripper, scale=1.0, max_grasps=100, seed=1, timeout=None):
        """The gripper's grasps of a stored mesh at a scale, best first: a list of Grasp in the part's
        frame. gripper: SuctionCup, ParallelJaws or a dict (see gripper_message). timeout: seconds
        (default: the client's stream_timeout, no deadline unless set)."""
        request = picking_pb2.GenerateGraspsRequest(mesh_id=mesh_id, scale=float(scale),
                                                    gripper=gripper_message(gripper))
        request.options.max_grasps = int(max_grasps)
        request.options.seed = int(seed)
        response = self._picking_call(self._picking.GenerateGrasps, request, timeout)
        return [_grasp(g) for g in response.grasps]

    def check_picks(self, mount_id, gripper, part_object_ids=None, timeout=None, **pick_options):
        """Which parts of the mount's scene the robot could pick with the gripper on its flange (the
        mount's tool frame is the gripper's tool centre point): a Picks of one PartPick per part.

        part_object_ids: the parts (None: every object labelled "<name>#<n>"). pick_options:
        approach_distance, max_approach_tilt_deg, cover_distance, body_length (metres, degrees),
        max_reach_checks, ik_time_budget_ms, and the grasp options max_grasps, seed, candidates,
        surface_samples; 0 or absent takes the server's default."""
        request = picking_pb2.CheckPicksRequest(mount_id=mount_id, gripper=gripper_message(gripper),
                                                part_object_ids=list(part_object_ids or []))
        for name, value in pick_options.items():
            if name not in _PICK_OPTIONS:
                raise TypeError(f"check_picks: unknown option {name!r}; one of {', '.join(sorted(_PICK_OPTIONS))}")
            message, field = _PICK_OPTIONS[name]
            setattr(getattr(request, message), field, value)
        response = self._picking_call(self._picking.CheckPicks, request, timeout)
        return Picks(scene_id=response.scene_id, parts=[_part_pick(p) for p in response.parts],
                     pickable=response.pickable, grasps_generated=response.grasps_generated,
                     elapsed_ms=response.elapsed_ms)
