"""The gripper of score_poses and score_dataset_results: whether a grasp planned on each estimate
would have held the true part (docs/LOCALIZATION.md, "Grasp success"). The gripper takes the forms
of the picking calls (vscan.picking.gripper_message): a SuctionCup or ParallelJaws, a dict
{"suction": {...}} or {"jaws": {...}} of their fields, or a vscan.v1.Gripper."""

from .picking import gripper_message

from vscan.v1 import common_pb2  # noqa: E402


def set_grasp_scoring(request, gripper, up=None, max_grasps=None, seed=None):
    """Fills a ScorePosesRequest's or ScoreDatasetResultsRequest's gripper, up and grasp_options;
    gripper None leaves them unset (no grasp figures)."""
    if gripper is None:
        return
    request.gripper.CopyFrom(gripper_message(gripper))
    if up is not None:
        x, y, z = (float(v) for v in up)
        request.up.CopyFrom(common_pb2.Vector3(x=x, y=y, z=z))
    if max_grasps is not None:
        request.grasp_options.max_grasps = int(max_grasps)
    if seed is not None:
        request.grasp_options.seed = int(seed)
