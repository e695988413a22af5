"""Localization calls of the Client: the server's baseline localizer and BOP scoring of poses
(LocalizationService, docs/LOCALIZATION.md)."""

import grpc
import numpy as np

from . import convert
from .errors import from_rpc_error
from .grasp_scoring import set_grasp_scoring

from vscan.v1 import localization_pb2, localization_pb2_grpc  # noqa: E402

NORMAL_SOURCES = {
    "auto": localization_pb2.NORMAL_SOURCE_UNSPECIFIED,
    "estimate": localization_pb2.NORMAL_SOURCE_ESTIMATE,
    "cloud": localization_pb2.NORMAL_SOURCE_CLOUD,
}


def _packed(array, what):
    values = np.ascontiguousarray(np.asarray(array, dtype="<f4"))
    if values.ndim != 2 or values.shape[1] != 3:
        raise ValueError(f"{what}: need an (N, 3) array, got shape {values.shape}")
    return values.tobytes()


def part_symmetry(continuous=(), discrete=()):
    """A PartSymmetry: continuous is a list of (axis, point) pairs, discrete a list of 4x4
    transforms, both in the part's frame (metres)."""
    out = localization_pb2.PartSymmetry()
    for axis, point in continuous:
        out.continuous.add(axis=convert.vector3(axis, "axis"), point=convert.vector3(point, "point"))
    for transform in discrete:
        out.discrete.add().matrix.CopyFrom(convert.matrix4(transform, "discrete"))
    return out


def scored_part(mesh_id, scale=1.0, symmetry=None):
    """A ScoredPart; symmetry a PartSymmetry (see part_symmetry) or None for none."""
    part = localization_pb2.ScoredPart(mesh_id=mesh_id, scale=scale)
    if symmetry is not None:
        part.symmetry.CopyFrom(symmetry)
    return part


def _part(item):
    if isinstance(item, localization_pb2.ScoredPart):
        return item
    if isinstance(item, str):
        return scored_part(item)
    if isinstance(item, dict):
        return scored_part(item["mesh_id"], item.get("scale", 1.0), item.get("symmetry"))
    return scored_part(*item)


def _true_pose(item):
    if isinstance(item, localization_pb2.TruePose):
        return item
    part, matrix = item[0], item[1]
    out = localization_pb2.TruePose(part=part, world_from_part=convert.pose(matrix=matrix))
    if len(item) > 2 and item[2] is not None:
        out.visible_fraction = float(item[2])
    if len(item) > 3:
        out.instance_id = int(item[3])
    return out


def _estimate(item):
    if isinstance(item, localization_pb2.EstimatedPose):
        return item
    part, matrix, score = item
    return localization_pb2.EstimatedPose(part=part, world_from_part=convert.pose(matrix=matrix), score=float(score))


def truth_from_objects(objects, parts):
    """TruePoses from a ground-truth scan's ObjectTruth entries (ScanResult.objects, or the objects
    of a .gt.json as dicts) for the parts listed as (mesh_id, scale); objects of other meshes (the
    bin) are left out."""
    index = {(mesh_id, float(scale)): i for i, (mesh_id, scale) in enumerate(parts)}
    out = []
    for obj in objects:
        if isinstance(obj, dict):
            mesh_id, scale = obj["mesh_id"], float(obj.get("scale", 1.0) or 1.0)
            matrix, fraction, instance = obj["world_from_object"]["values"], obj["visible_fraction"], obj["instance_id"]
        else:
            mesh_id, scale = obj.mesh_id, obj.scale or 1.0
            matrix, fraction, instance = obj.world_from_object.values, obj.visible_fraction, obj.instance_id
        part = index.get((mesh_id, float(scale)))
        if part is not None:
            out.append(_true_pose((part, matrix, fraction, instance)))
    return out


def localize_part(mesh_id, scale=1.0, max_instances=0):
    """A LocalizePart: a mesh at a scale (0: 1), at most max_instances instances (0: the call's)."""
    return localization_pb2.LocalizePart(mesh_id=mesh_id, scale=float(scale), max_instances=int(max_instances))


def _localize_part(item):
    if isinstance(item, localization_pb2.LocalizePart):
        return item
    if isinstance(item, str):
        return localize_part(item)
    if isinstance(item, dict):
        return localize_part(item["mesh_id"], item.get("scale", 1.0), item.get("max_instances", 0))
    return localize_part(*item)


def pose_matrix(matrix4):
    """A Matrix4 of a response as a 4x4 numpy array."""
    return np.asarray(matrix4.values, dtype=float).reshape(4, 4)


class LocalizationCalls:
    """Mixed into Client; uses its channel, metadata and call helpers."""

    @property
    def _localization(self):
        stub = self.__dict__.get("_localization_stub")
        if stub is None:
            stub = self.__dict__["_localization_stub"] = localization_pb2_grpc.LocalizationServiceStub(self._channel)
        return stub

    def localize(self, mesh_id=None, cloud_id=None, points=None, normals=None, scale=1.0, max_instances=0,
                 min_score=0.0, voxel_size=0.0, normal_source="auto", viewpoint=None, remove_support_plane=None,
                 timeout=None, parts=None, progress=None):
        """Finds instances of one part (mesh_id at scale) or of several (parts) in a stored cloud
        (cloud_id) or in points ((N, 3), at most 131072, with optional unit normals). Returns the
        LocalizeResponse: estimates with part (the index into parts), world_from_part (the cloud's
        frame), score and explained_points; per part its voxel, found count and stop reason; and
        localize_ms.

        parts: 1 to 16 of mesh ids, (mesh_id, scale[, max_instances]) tuples, dicts or LocalizeParts
        (see localize_part), instead of mesh_id and scale; max_instances is then each part's default.
        progress: a callable given each LocalizeProgress (fraction, found, stage) while the search
        runs (the call then streams, LocalizeWithProgress). normal_source: "auto", "estimate" or
        "cloud". timeout: seconds (default: the client's stream_timeout, no deadline unless set)."""
        if (cloud_id is None) == (points is None):
            raise ValueError("localize: give cloud_id or points")
        if (mesh_id is None) == (parts is None):
            raise ValueError("localize: give mesh_id or parts")
        if parts is None:
            request = localization_pb2.LocalizeRequest(mesh_id=mesh_id, scale=scale)
        else:
            request = localization_pb2.LocalizeRequest(parts=[_localize_part(p) for p in parts])
        if cloud_id is not None:
            request.cloud_id = cloud_id
        else:
            request.points.positions = _packed(points, "points")
            if normals is not None:
                request.points.normals = _packed(normals, "normals")
        options = request.options
        options.max_instances = max_instances
        options.min_score = min_score
        options.voxel_size = voxel_size
        options.normal_source = convert._lookup(NORMAL_SOURCES, normal_source, "normal_source")
        if viewpoint is not None:
            options.viewpoint.CopyFrom(convert.vector3(viewpoint, "viewpoint"))
        if remove_support_plane is not None:
            options.remove_support_plane = bool(remove_support_plane)
        timeout = timeout or self._stream_timeout
        try:
            if progress is None:
                return self._localization.Localize(request, timeout=timeout, metadata=self._metadata)
            return self._localize_streamed(request, timeout, progress)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None

    def _localize_streamed(self, request, timeout, progress):
        stream = self._localization.LocalizeWithProgress(
            localization_pb2.LocalizeWithProgressRequest(localize=request), timeout=timeout, metadata=self._metadata)
        response = None
        try:
            for update in stream:
                if update.HasField("progress"):
                    progress(update.progress)
                elif update.HasField("response"):
                    response = update.response
        finally:
            stream.cancel()  # no-op once the stream ended; stops the search if the callback raised
        if response is None:
            raise RuntimeError("LocalizeWithProgress ended without a response")
        return response

    def score_poses(self, parts, truth, estimates, min_visible_fraction=None, add_threshold=None,
                    mssd_thresholds=(), keep_all_estimates=False, timeout=None, gripper=None, up=None,
                    max_grasps=None, grasp_seed=None):
        """Scores estimates against the truth with BOP's definitions; returns the ScorePosesResponse
        (per part and overall ADD(-S) recall and MSSD average recall, matches with their errors).

        parts: mesh ids, (mesh_id, scale[, symmetry]) tuples, dicts or ScoredParts; truth:
        (part, 4x4 world_from_part, visible_fraction, instance_id) tuples or TruePoses (see
        truth_from_objects); estimates: (part, 4x4, score) tuples or EstimatedPoses. part is an
        index into parts.

        gripper (vscan.SuctionCup, vscan.ParallelJaws, a dict or a vscan.v1.Gripper) adds the
        grasp figures: per match grasp_holds and grasp_failure, per part and overall grasp_success
        (grasps that hold / valid true instances). up: the direction against gravity in the poses'
        frame (default +z)."""
        request = localization_pb2.ScorePosesRequest(
            parts=[_part(p) for p in parts],
            truth=[_true_pose(t) for t in truth],
            estimates=[_estimate(e) for e in estimates],
        )
        if min_visible_fraction is not None:
            request.options.min_visible_fraction = min_visible_fraction
        if add_threshold is not None:
            request.options.add_threshold = add_threshold
        request.options.mssd_thresholds.extend(mssd_thresholds)
        request.options.keep_all_estimates = keep_all_estimates
        set_grasp_scoring(request, gripper, up=up, max_grasps=max_grasps, seed=grasp_seed)
        return self._call(self._localization.ScorePoses, request, timeout=timeout)
