"""Robot inputs that once hung or crashed the server are refused at the door: URDFs whose joints
are not a tree, URDF geometry beyond the physical bounds, mount and tool offsets and IK goals out
of range, and bundle directories whose symbolic links lead elsewhere."""

import os
import subprocess
import tempfile
import threading
import time
import unittest

import grpc

from harness import VSCAN, Server, ServerTestCase, common_pb2, icosphere_ply, look_at, pinhole, scan_pb2
from vscan.v1 import robot_pb2, robot_pb2_grpc, scene_pb2
from vscan import Client

C = grpc.StatusCode
FAR = 1e19


def link(name, geometry=""):
    visual = f"<visual><geometry>{geometry}</geometry></visual>" if geometry else ""
    return f"<link name='{name}'>{visual}</link>"


def joint(name, parent, child, xyz="0 0 0.1", kind="revolute", limits="lower='-1' upper='1'"):
    return (f"<joint name='{name}' type='{kind}'><parent link='{parent}'/><child link='{child}'/>"
            f"<origin xyz='{xyz}'/><axis xyz='0 0 1'/><limit {limits} effort='1' velocity='1'/></joint>")


def robot(*parts):
    return ("<robot name='r'>" + "".join(parts) + "</robot>").encode()


BOX = "<box size='0.05 0.05 0.2'/>"
ARM = robot(link("base"), link("upper", BOX), link("fore", BOX), joint("j1", "base", "upper"),
            joint("j2", "upper", "fore"))


def upload_requests(urdf, tip="", extra=(), tool=None):
    header = robot_pb2.RobotBundleHeader(urdf_path="r.urdf", tip_link=tip)
    if tool is not None:
        header.tool_offset.CopyFrom(tool)
    yield robot_pb2.UploadRobotRequest(header=header)
    for path, data in (("r.urdf", urdf), *extra):
        yield robot_pb2.UploadRobotRequest(file=robot_pb2.RobotBundleFile(path=path, content=data))


def translation_pose(x):
    return common_pb2.Pose(matrix=common_pb2.Matrix4(values=[1, 0, 0, x, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]))


def quaternion_pose(x):
    return common_pb2.Pose(quaternion=common_pb2.QuaternionPose(qw=1, translation=common_pb2.Vector3(x=x)))


# Graphs urdfdom accepts but that are not trees; each once pinned a worker for good.
NOT_TREES = {
    "three-cycle": (robot(link("base"), link("a"), link("b"), link("c"), joint("j0", "base", "a"),
                          joint("j1", "a", "b"), joint("j2", "b", "c"), joint("j3", "c", "a")), "",
                    "joints: cycle through joints j1 -> j2 -> j3 -> j1"),
    "two-cycle, default tip": (robot(link("base"), link("a"), link("b"), joint("j1", "base", "a"),
                                     joint("j2", "a", "b"), joint("j3", "b", "a")), "",
                               "joints: cycle through joints j2 -> j3 -> j2"),
    "two-cycle, explicit tip": (robot(link("base"), link("a"), link("b"), joint("j1", "base", "a"),
                                      joint("j2", "a", "b"), joint("j3", "b", "a")), "b",
                                "joints: cycle through joints j2 -> j3 -> j2"),
    "self-joint": (robot(link("base"), link("a"), joint("j1", "base", "a"), joint("loop", "a", "a")), "",
                   "joints['loop']: parent and child are the same link 'a'"),
    "cycle beside the root": (robot(link("base"), link("a"), link("c"), link("d"), joint("j1", "base", "a"),
                                    joint("jc", "c", "d"), joint("jd", "d", "c")), "a",
                              "joints: cycle through joints jc -> jd -> jc"),
    "two parents": (robot(link("base"), link("a"), link("b"), link("c"), joint("ja", "base", "a"),
                          joint("jb", "base", "b"), joint("jc1", "a", "c"), joint("jc2", "b", "c")), "c",
                    "links['c']: child of two joints, 'jc1' and 'jc2'"),
}


class RobotRefusalsTest(ServerTestCase):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.robots = robot_pb2_grpc.RobotServiceStub(cls.channel)
        cls.scene = cls.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="refusals")).scene
        mesh = ServerTestCase.upload_bytes(cls, icosphere_ply(0.1, (0, 0, 0), 2), "sphere.ply")
        cls.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=cls.scene.scene_id, mesh_id=mesh.mesh_id))
        cls.arm = cls.robots.UploadRobot(upload_requests(ARM), timeout=30).robot

    def robot_ids(self):
        return [r.robot_id for r in self.robots.ListRobots(robot_pb2.ListRobotsRequest(), timeout=10).robots]

    def points(self, **kwargs):
        request = dict(scene_id=self.scene.scene_id, sensor=pinhole(), pose=look_at((0.5, 0, 0), (0, 0, 0)))
        request.update(kwargs)
        return list(self.scans.Scan(scan_pb2.ScanRequest(**request), timeout=30))[-1].statistics.points

    def test_joint_graphs_that_are_not_trees_are_refused_promptly(self):
        before = self.robot_ids()
        for name, (urdf, tip, message) in NOT_TREES.items():
            with self.subTest(name):
                started = time.monotonic()
                self.assertCode(C.INVALID_ARGUMENT,
                                lambda: self.robots.UploadRobot(upload_requests(urdf, tip), timeout=10), message)
                self.assertLess(time.monotonic() - started, 5)
        self.assertEqual(before, self.robot_ids())
        self.assertGreater(self.points(), 0, "the server still scans")

    def test_urdf_geometry_beyond_the_bounds_is_refused(self):
        before = self.robot_ids()
        cases = {
            "joints['j1'].origin.xyz": robot(link("base"), link("a", BOX), joint("j1", "base", "a", xyz="1e300 0 0")),
            "links['a'].visual[0].origin.xyz": robot(
                link("base"), "<link name='a'><visual><origin xyz='0 0 -2e4'/><geometry>" + BOX +
                "</geometry></visual></link>", joint("j1", "base", "a")),
            "links['a'].visual[0].box.size": robot(link("base"), link("a", "<box size='1 1 1e300'/>"),
                                                   joint("j1", "base", "a")),
            "links['a'].visual[0].sphere.radius": robot(link("base"), link("a", "<sphere radius='1e300'/>"),
                                                        joint("j1", "base", "a")),
            "links['a'].visual[0].mesh.scale": robot(
                link("base"), link("a", "<mesh filename='m.stl' scale='1e300 1 1'/>"), joint("j1", "base", "a")),
            "joints['j1'].limit": robot(link("base"), link("a", BOX),
                                        joint("j1", "base", "a", kind="prismatic", limits="lower='0' upper='1e300'")),
        }
        for field, urdf in cases.items():
            with self.subTest(field):
                self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(
                    upload_requests(urdf, extra=(("m.stl", b"solid m\nendsolid m\n"),)), timeout=10), field)
        self.assertEqual(before, self.robot_ids())

    def test_a_robot_at_the_bounds_scans(self):
        # A joint origin and a box edge at the coordinate bound are accepted, and scanning a scene
        # that holds the links neither aborts the server nor loses the scene.
        urdf = robot(link("base"), link("a", "<box size='0.1 1e4 0.1'/>"), joint("j1", "base", "a", xyz="1e4 0 0"))
        far = self.robots.UploadRobot(upload_requests(urdf), timeout=30).robot
        mount = self.robots.MountRobot(robot_pb2.MountRobotRequest(
            scene_id=self.scene.scene_id, robot_id=far.robot_id, base_pose=translation_pose(-1e3),
            links_visible=True), timeout=10)
        try:
            self.assertGreater(self.points(), 0)
        finally:
            self.robots.UnmountRobot(robot_pb2.UnmountRobotRequest(mount_id=mount.mount_id), timeout=10)

    def test_mount_and_tool_offsets_far_away_are_refused(self):
        scene_id, robot_id = self.scene.scene_id, self.arm.robot_id
        for pose, where in ((translation_pose(FAR), "matrix translation"),
                            (quaternion_pose(FAR), "quaternion.translation")):
            with self.subTest(where):
                self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.MountRobot(robot_pb2.MountRobotRequest(
                    scene_id=scene_id, robot_id=robot_id, base_pose=pose), timeout=10), "base_pose")
                self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.MountRobot(robot_pb2.MountRobotRequest(
                    scene_id=scene_id, robot_id=robot_id, tool_offset=pose), timeout=10), "tool_offset")
                self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(
                    upload_requests(ARM, tool=pose), timeout=10), "header.tool_offset")
        mounts = self.robots.ListMounts(robot_pb2.ListMountsRequest(scene_id=scene_id), timeout=10).mounts
        self.assertEqual(len(mounts), 0)

    def test_ik_goals_far_away_are_refused(self):
        mount = self.robots.MountRobot(robot_pb2.MountRobotRequest(
            scene_id=self.scene.scene_id, robot_id=self.arm.robot_id), timeout=10)
        far = common_pb2.Vector3(x=1e300)
        near = common_pb2.Vector3(x=0.1, z=0.2)
        try:
            for target in ({"robot_id": self.arm.robot_id}, {"mount_id": mount.mount_id}):
                goals = {
                    "tool_position": dict(tool_position=far),
                    "look_from.position": dict(look_from=robot_pb2.LookFrom(position=far, target=near)),
                    "look_from.target": dict(look_from=robot_pb2.LookFrom(position=near, target=far)),
                    "tool_pose": dict(tool_pose=translation_pose(1e300)),
                }
                for field, goal in goals.items():
                    with self.subTest(field, **target):
                        err = self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.InverseKinematics(
                            robot_pb2.InverseKinematicsRequest(**target, **goal, allow_partial=True), timeout=10),
                            field)
                        self.assertNotIn("inf", err.details())
        finally:
            self.robots.UnmountRobot(robot_pb2.UnmountRobotRequest(mount_id=mount.mount_id), timeout=10)


class SymlinkBundleTest(unittest.TestCase):
    """`vscan robot upload` and the Python client refuse links that lead out of the bundle."""

    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()
        cls.tmp = tempfile.TemporaryDirectory(prefix="vscan-links-")

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()
        cls.tmp.cleanup()

    def bundle(self, name):
        root = os.path.join(self.tmp.name, name)
        os.makedirs(os.path.join(root, "meshes"))
        with open(os.path.join(root, "r.urdf"), "wb") as f:
            f.write(ARM)
        with open(os.path.join(root, "meshes", "real.stl"), "wb") as f:
            f.write(b"solid m\nendsolid m\n")
        return root

    def upload(self, root):
        return subprocess.run([VSCAN, "--server", self.server.address, "-q", "robot", "upload", root, "--urdf",
                               "r.urdf"], capture_output=True, text=True, timeout=60)

    def client(self):
        return Client(self.server.address)

    def robot_count(self):
        with self.client() as client:
            return len(client.list_robots())

    def test_links_out_of_the_bundle_are_refused_as_local_errors(self):
        secret = os.path.join(self.tmp.name, "secret.txt")
        with open(secret, "w") as f:
            f.write("not for the server\n")
        before = self.robot_count()
        for name, target in (("file", secret), ("etc", "/etc/passwd"), ("relative", "../../secret.txt"),
                             ("directory", self.tmp.name)):
            with self.subTest(name):
                root = self.bundle("out-" + name)
                evil = os.path.join(root, "meshes", "evil")
                os.symlink(target, evil)
                out = self.upload(root)
                self.assertEqual(out.returncode, 5, out.stderr)
                self.assertIn(evil, out.stderr)
                self.assertIn("leaves the bundle", out.stderr)
                with self.client() as client, self.assertRaises(ValueError) as raised:
                    client.upload_robot(root, urdf="r.urdf")
                self.assertIn(evil, str(raised.exception))
        self.assertEqual(before, self.robot_count())

    def test_links_inside_the_bundle_are_followed(self):
        root = self.bundle("inside")
        os.symlink("real.stl", os.path.join(root, "meshes", "alias.stl"))
        os.symlink("meshes", os.path.join(root, "more"))  # a directory link inside: not descended
        out = self.upload(root)
        self.assertEqual(out.returncode, 0, out.stderr)
        with self.client() as client:
            uploaded = client.get_robot(out.stdout.strip())
        self.assertEqual(uploaded.file_count, 3)  # r.urdf, meshes/real.stl, meshes/alias.stl


class NotTreesDoNotHoldTheServerTest(unittest.TestCase):
    """Bundles that once pinned a core each: after them the server still scans and stops on SIGTERM."""

    def test_scans_and_stops_after_cyclic_uploads(self):
        server = Server().start()
        try:
            with server.channel() as channel:
                robots = robot_pb2_grpc.RobotServiceStub(channel)
                codes = []

                def upload(urdf, tip):
                    try:
                        robots.UploadRobot(upload_requests(urdf, tip), timeout=10)
                        codes.append(C.OK)
                    except grpc.RpcError as err:
                        codes.append(err.code())
                # Several at once, more than the workers of a 2-core machine.
                threads = [threading.Thread(target=upload, args=(urdf, tip))
                           for urdf, tip, _ in list(NOT_TREES.values()) * 2]
                for t in threads:
                    t.start()
                for t in threads:
                    t.join(timeout=30)
                self.assertEqual(codes, [C.INVALID_ARGUMENT] * len(threads))

                scan = sphere_scan(channel)
                self.assertGreater(scan(), 0, "the server still scans")
            started = time.monotonic()
            self.assertEqual(server.stop(timeout=20), 0, server.log())
            self.assertLess(time.monotonic() - started, 10)
        finally:
            server.cleanup()


def sphere_scan(channel):
    """A one-sphere scene on channel; returns a function that scans it and counts the points."""
    from vscan.v1 import scan_pb2_grpc, scene_pb2_grpc
    scenes = scene_pb2_grpc.SceneServiceStub(channel)
    scans = scan_pb2_grpc.ScanServiceStub(channel)
    scene = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="after"), timeout=10).scene
    data = icosphere_ply(0.1, (0, 0, 0), 2)

    def requests():
        yield scene_pb2.UploadMeshRequest(header=scene_pb2.MeshHeader(
            name="sphere.ply", unit=common_pb2.LENGTH_UNIT_METRE, size_bytes=len(data)))
        yield scene_pb2.UploadMeshRequest(chunk=data)
    mesh = scenes.UploadMesh(requests(), timeout=30).mesh
    scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id), timeout=10)

    def scan():
        request = scan_pb2.ScanRequest(scene_id=scene.scene_id, sensor=pinhole(), pose=look_at((0.5, 0, 0), (0, 0, 0)))
        return list(scans.Scan(request, timeout=30))[-1].statistics.points
    return scan


if __name__ == "__main__":
    unittest.main()
