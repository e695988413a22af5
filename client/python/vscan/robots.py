"""Robot calls of the Client: bundles, kinematics and mounts (RobotService)."""

import os

import grpc

from . import convert
from ._stubs import robot_pb2
from .errors import from_rpc_error

_CHUNK_BYTES = 1 << 20


def _check_link(local, root):
    """Refuses a symbolic link that resolves outside the bundle directory root (already resolved)."""
    target = os.path.realpath(local)
    if os.path.commonpath([target, root]) != root:
        raise ValueError(f"{local}: symbolic link to '{target}' leaves the bundle directory")


def _bundle_files(path):
    """[(bundle path, local path)] of a directory (paths relative to it) or of one file.

    Links to directories are not descended into; links that lead out of the directory are refused.
    """
    if not os.path.isdir(path):
        return [(os.path.basename(path), path)]
    root = os.path.realpath(path)
    files = []
    for parent, dirs, names in os.walk(path):
        for name in dirs + names:
            local = os.path.join(parent, name)
            if os.path.islink(local):
                _check_link(local, root)
        for name in names:
            local = os.path.join(parent, name)
            if os.path.isfile(local):
                files.append((os.path.relpath(local, path).replace(os.sep, "/"), local))
    return sorted(files)


def _optional_pose(position, quat, matrix):
    if position is None and quat is None and matrix is None:
        return None
    return convert.pose(position if position is not None else (0.0, 0.0, 0.0), quat, matrix)


class RobotCalls:
    """Mixed into Client; uses its channel, metadata and call helpers."""

    def upload_robot(self, path, urdf=None, base="", tip="", name="", tool_position=None, tool_quat=None,
                     tool_matrix=None, chunk_bytes=_CHUNK_BYTES):
        """Uploads a URDF robot and returns the Robot (its warnings name missing meshes).

        path: a directory (the bundle: every file below it, paths relative to it) or a single URDF
        file. urdf: the URDF's path inside the directory (default: the only .urdf file). base, tip:
        the chain's links (default: the root and the deepest link). The tool offset (tip_from_tool)
        is tool_position + tool_quat (w, x, y, z), or tool_matrix.
        """
        files = _bundle_files(path)
        if urdf is None:
            urdfs = [p for p, _ in files if p.lower().endswith(".urdf")]
            if len(urdfs) != 1:
                raise ValueError(f"urdf: required, {path} holds {len(urdfs)} .urdf files")
            urdf = urdfs[0]
        header = robot_pb2.RobotBundleHeader(name=name, urdf_path=urdf, base_link=base, tip_link=tip,
                                             size_bytes=sum(os.path.getsize(local) for _, local in files))
        tool = _optional_pose(tool_position, tool_quat, tool_matrix)
        if tool is not None:
            header.tool_offset.CopyFrom(tool)

        def requests():
            yield robot_pb2.UploadRobotRequest(header=header)
            for bundle_path, local in files:
                with open(local, "rb") as f:
                    first = True
                    while True:
                        data = f.read(chunk_bytes)
                        if not data and not first:
                            break
                        yield robot_pb2.UploadRobotRequest(
                            file=robot_pb2.RobotBundleFile(path=bundle_path if first else "", content=data))
                        first = False
                        if not data:
                            break

        try:
            response = self._robots.UploadRobot(requests(), timeout=self._stream_timeout, metadata=self._metadata)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None
        return response.robot

    def get_robot(self, robot_id):
        return self._call(self._robots.GetRobot, robot_pb2.GetRobotRequest(robot_id=robot_id)).robot

    def list_robots(self):
        return self._pages(self._robots.ListRobots, robot_pb2.ListRobotsRequest, "robots")

    def delete_robot(self, robot_id):
        self._call(self._robots.DeleteRobot, robot_pb2.DeleteRobotRequest(robot_id=robot_id))

    def forward_kinematics(self, robot_id="", joints=(), mount_id="", encoder_noise_seed=None):
        """The ForwardKinematicsResponse: tool_pose (base frame, or world for a mount) and link poses.

        With mount_id and encoder_noise_seed, achieved_* report where the arm lands with the
        mount's encoder noise.
        """
        request = robot_pb2.ForwardKinematicsRequest(
            robot_id=robot_id, mount_id=mount_id, joint_positions=convert.numbers(joints, "joints"))
        if encoder_noise_seed is not None:
            request.apply_encoder_noise = True
            request.encoder_noise_seed = int(encoder_noise_seed)
        return self._call(self._robots.ForwardKinematics, request)

    def inverse_kinematics(self, robot_id="", position=None, quat=None, matrix=None, look_at=None, seed=None,
                           method="default", tolerance=0.0, orientation_tolerance=0.0, timeout_ms=0.0,
                           allow_partial=False, mount_id="", encoder_noise_seed=None, avoid_collisions=False):
        """The InverseKinematicsResponse for a goal in the base frame (or the world, with mount_id).

        Goal: position alone; position + quat (w, x, y, z); a 4x4 matrix; or position + look_at
        (the tool's z axis towards that point). An unreachable goal raises VscanError
        (OUT_OF_RANGE) unless allow_partial, which answers with reached=False and the nearest
        configuration. avoid_collisions (with mount_id) only accepts a solution whose arm is clear of
        the scene.
        """
        request = robot_pb2.InverseKinematicsRequest(
            robot_id=robot_id, mount_id=mount_id, method=convert.ik_method(method), tolerance=float(tolerance),
            orientation_tolerance_rad=float(orientation_tolerance), timeout_ms=float(timeout_ms),
            allow_partial=bool(allow_partial), avoid_collisions=bool(avoid_collisions))
        if matrix is not None or quat is not None:
            request.tool_pose.CopyFrom(convert.pose(position if position is not None else (0.0, 0.0, 0.0), quat,
                                                    matrix))
        elif look_at is not None:
            request.look_from.position.CopyFrom(convert.vector3(position, "position"))
            request.look_from.target.CopyFrom(convert.vector3(look_at, "look_at"))
        elif position is not None:
            request.tool_position.CopyFrom(convert.vector3(position, "position"))
        else:
            raise ValueError("inverse_kinematics: give position (with quat or look_at), or matrix")
        if seed is not None:
            request.seed.extend(convert.numbers(seed, "seed"))
        if encoder_noise_seed is not None:
            request.apply_encoder_noise = True
            request.encoder_noise_seed = int(encoder_noise_seed)
        return self._call(self._robots.InverseKinematics, request)

    def mount_robot(self, scene_id, robot_id, position=(0.0, 0.0, 0.0), quat=None, matrix=None, tool_position=None,
                    tool_quat=None, tool_matrix=None, encoder_sigma=None, links_visible=False):
        """Places a robot in a scene (world_from_base from position + quat, or matrix); the tool offset
        (tip_from_sensor) defaults to the robot's; links_visible puts its links in scans.
        Returns the MountRobotResponse (mount_id, revision, mount)."""
        request = robot_pb2.MountRobotRequest(scene_id=scene_id, robot_id=robot_id,
                                              base_pose=convert.pose(position, quat, matrix),
                                              links_visible=bool(links_visible))
        tool = _optional_pose(tool_position, tool_quat, tool_matrix)
        if tool is not None:
            request.tool_offset.CopyFrom(tool)
        if encoder_sigma is not None:
            sigma = [encoder_sigma] if isinstance(encoder_sigma, (int, float)) else encoder_sigma
            request.encoder_sigma.extend(convert.numbers(sigma, "encoder_sigma"))
        return self._call(self._robots.MountRobot, request)

    def get_mount(self, mount_id):
        return self._call(self._robots.GetMount, robot_pb2.GetMountRequest(mount_id=mount_id)).mount

    def list_mounts(self, scene_id=""):
        items, token = [], ""
        while True:
            page = self._call(self._robots.ListMounts, robot_pb2.ListMountsRequest(scene_id=scene_id, page_token=token))
            items.extend(page.mounts)
            if not page.next_page_token or page.next_page_token == token:
                return items
            token = page.next_page_token

    def unmount_robot(self, mount_id):
        """Returns the scene's new revision."""
        return self._call(self._robots.UnmountRobot, robot_pb2.UnmountRobotRequest(mount_id=mount_id)).revision
