"""Robots end to end: bundles, kinematics against an independent FK, mounts, robot-held scans,
restart, and the CLI."""

import glob
import json
import math
import os
import re
import subprocess
import tempfile
import unittest
import xml.etree.ElementTree as ET

import grpc
import numpy as np

from harness import DATA, VSCAN, Server, ServerTestCase, common_pb2, icosphere_ply, pinhole, scan_pb2
from vscan.v1 import robot_pb2, robot_pb2_grpc, scene_pb2

C = grpc.StatusCode
PANDA_DIR = os.path.join(DATA, "robots", "panda")
UR5_DIR = os.path.join(DATA, "robots", "ur5")
PANDA = dict(urdf="panda.urdf", base="panda_link0", tip="panda_hand_tcp")
UR5 = dict(urdf="ur5_robot.urdf", base="base_link", tip="tool0")


# -- an independent forward kinematics, straight from the URDF --------------------------------------

def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def axis_angle(axis, angle):
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx @ kx


def transform(rotation=np.eye(3), translation=(0, 0, 0)):
    t = np.eye(4)
    t[:3, :3] = rotation
    t[:3, 3] = translation
    return t


class UrdfChain:
    """The joints from base to tip as written in the URDF, evaluated with numpy."""

    def __init__(self, path, base, tip):
        root = ET.parse(path).getroot()
        by_child = {j.find("child").get("link"): j for j in root.findall("joint")}
        joints, link = [], tip
        while link != base:
            joint = by_child[link]
            joints.append(joint)
            link = joint.find("parent").get("link")
        self.joints = []
        for j in reversed(joints):
            origin = j.find("origin")
            xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
            rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
            axis = j.find("axis")
            axis = [float(v) for v in axis.get("xyz").split()] if axis is not None else [1, 0, 0]
            limit = j.find("limit")
            lo, hi = (float(limit.get("lower")), float(limit.get("upper"))) if limit is not None else (0, 0)
            self.joints.append(dict(name=j.get("name"), type=j.get("type"), origin=transform(rpy_matrix(*rpy), xyz),
                                    axis=axis, lower=lo, upper=hi))
        self.moving = [j for j in self.joints if j["type"] != "fixed"]

    def fk(self, q):
        t, i = np.eye(4), 0
        for j in self.joints:
            t = t @ j["origin"]
            if j["type"] in ("revolute", "continuous"):
                t = t @ transform(axis_angle(j["axis"], q[i]))
                i += 1
            elif j["type"] == "prismatic":
                t = t @ transform(translation=np.asarray(j["axis"], float) * q[i])
                i += 1
        return t

    def random_q(self, rng, margin=0.05):
        return [rng.uniform(j["lower"] + margin, j["upper"] - margin) for j in self.moving]


def matrix(m):
    return np.array(m.values).reshape(4, 4)


def to_matrix4(t):
    return common_pb2.Matrix4(values=[float(v) for v in np.asarray(t).reshape(-1)])


def to_pose(t):
    return common_pb2.Pose(matrix=to_matrix4(t))


def rotation_angle(a, b):
    r = a[:3, :3].T @ b[:3, :3]
    return math.acos(max(-1.0, min(1.0, (np.trace(r) - 1) / 2)))


def bundle_requests(header, files, piece=4096):
    """Header, then each file split into pieces; only a file's first piece names it."""
    yield robot_pb2.UploadRobotRequest(header=header)
    for path, data in files:
        for offset in range(0, max(len(data), 1), piece):
            yield robot_pb2.UploadRobotRequest(file=robot_pb2.RobotBundleFile(
                path=path if offset == 0 else "", content=data[offset:offset + piece]))


def read(path):
    with open(path, "rb") as f:
        return f.read()


def panda_files():
    files = [("panda.urdf", read(os.path.join(PANDA_DIR, "panda.urdf")))]
    for stl in sorted(glob.glob(os.path.join(PANDA_DIR, "meshes", "collision", "*.stl"))):
        files.append(("meshes/collision/" + os.path.basename(stl), read(stl)))
    return files


def upload_panda(robots, name="panda", tool=None):
    header = robot_pb2.RobotBundleHeader(name=name, urdf_path=PANDA["urdf"], base_link=PANDA["base"],
                                         tip_link=PANDA["tip"])
    if tool is not None:
        header.tool_offset.CopyFrom(to_pose(tool))
    return robots.UploadRobot(bundle_requests(header, panda_files()), timeout=60).robot


def upload_ur5(robots):
    header = robot_pb2.RobotBundleHeader(name="ur5", urdf_path=UR5["urdf"], base_link=UR5["base"], tip_link=UR5["tip"])
    return robots.UploadRobot(bundle_requests(header, [(UR5["urdf"], read(os.path.join(UR5_DIR, UR5["urdf"])))]),
                              timeout=60).robot


def sensor_offset():
    """tip_from_sensor of the test scanner: 5 cm along the flange, turned 30 degrees about its z."""
    return transform(axis_angle([0, 0, 1], math.radians(30)), [0.0, 0.02, 0.05])


def base_pose():
    """world_from_base of the test mount."""
    return transform(axis_angle([0, 0, 1], math.radians(40)), [0.3, -0.2, 0.1])


class RobotTestBase(ServerTestCase):
    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.robots = robot_pb2_grpc.RobotServiceStub(cls.channel)
        cls.panda_chain = UrdfChain(os.path.join(PANDA_DIR, PANDA["urdf"]), PANDA["base"], PANDA["tip"])
        cls.ur5_chain = UrdfChain(os.path.join(UR5_DIR, UR5["urdf"]), UR5["base"], UR5["tip"])
        cls.panda = upload_panda(cls.robots)
        cls.ur5 = upload_ur5(cls.robots)

    def fk(self, robot_id, q, **kwargs):
        return self.robots.ForwardKinematics(robot_pb2.ForwardKinematicsRequest(
            robot_id=robot_id, joint_positions=q, **kwargs), timeout=10)

    def sphere_scene(self, centre, radius=0.08):
        scene = self.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="robot-scan")).scene
        mesh = self.upload_bytes(icosphere_ply(radius, centre), "sphere.ply")
        self.scenes.AddObject(scene_pb2.AddObjectRequest(scene_id=scene.scene_id, mesh_id=mesh.mesh_id, label="ball"))
        return self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene

    def mount(self, scene_id, robot_id, **kwargs):
        return self.robots.MountRobot(robot_pb2.MountRobotRequest(scene_id=scene_id, robot_id=robot_id, **kwargs),
                                      timeout=10)


class BundleTest(RobotTestBase):
    def test_panda_bundle_with_meshes(self):
        r = self.panda
        self.assertTrue(r.robot_id.startswith("rbt_"))
        self.assertEqual((r.base_link, r.tip_link, r.urdf_path), (PANDA["base"], PANDA["tip"], PANDA["urdf"]))
        self.assertEqual([j.name for j in r.joints], [f"panda_joint{i}" for i in range(1, 8)])
        self.assertTrue(all(j.type == robot_pb2.JOINT_TYPE_REVOLUTE for j in r.joints))
        self.assertAlmostEqual(r.joints[0].upper, 2.8973)
        self.assertAlmostEqual(r.joints[0].max_velocity, 2.175)
        self.assertEqual(r.file_count, 11)
        # Collision meshes travelled with the bundle; only the visual .dae files are missing.
        self.assertTrue(r.warnings)
        for w in r.warnings:
            self.assertIn("visual", w)
            self.assertIn(".dae", w)
        self.assertGreater(r.reach, 0.8)
        self.assertEqual(self.robots.GetRobot(robot_pb2.GetRobotRequest(robot_id=r.robot_id)).robot, r)

    def test_ur5_urdf_only_warns_about_every_mesh(self):
        r = self.ur5
        self.assertEqual(len(r.joints), 6)
        self.assertEqual(r.file_count, 1)
        self.assertTrue(any("collision" in w and "base.stl" in w for w in r.warnings), r.warnings)
        self.assertTrue(any("visual" in w for w in r.warnings))

    def test_list_robots_pages(self):
        seen, token = [], ""
        while True:
            page = self.robots.ListRobots(robot_pb2.ListRobotsRequest(page_size=1, page_token=token))
            seen += [r.robot_id for r in page.robots]
            token = page.next_page_token
            if not token:
                break
        self.assertIn(self.panda.robot_id, seen)
        self.assertIn(self.ur5.robot_id, seen)
        self.assertEqual(seen, sorted(seen))

    def test_escaping_paths_are_refused_and_change_nothing(self):
        before = list(self.robots.ListRobots(robot_pb2.ListRobotsRequest()).robots)
        urdf = read(os.path.join(UR5_DIR, UR5["urdf"]))
        header = robot_pb2.RobotBundleHeader(urdf_path=UR5["urdf"], base_link=UR5["base"], tip_link=UR5["tip"])
        for bad in ("../evil.stl", "/etc/passwd", "meshes/../../evil.stl"):
            err = self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(
                bundle_requests(header, [(UR5["urdf"], urdf), (bad, b"solid x\nendsolid x\n")]), timeout=30))
            self.assertIn("files[1].path", err.details())
        # A mesh reference that climbs out of its package.
        evil = urdf.replace(b"package://example-robot-data/robots/ur_description/meshes/ur5/collision/base.stl",
                            b"package://x/../../evil.stl")
        err = self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(
            bundle_requests(header, [(UR5["urdf"], evil)]), timeout=30))
        self.assertIn("package://x/../../evil.stl", err.details())
        self.assertIn("collision", err.details())
        self.assertEqual(list(self.robots.ListRobots(robot_pb2.ListRobotsRequest()).robots), before)

    def test_bad_uploads(self):
        urdf = read(os.path.join(UR5_DIR, UR5["urdf"]))
        header = robot_pb2.RobotBundleHeader(urdf_path=UR5["urdf"], base_link=UR5["base"], tip_link="no_such_link")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(
            bundle_requests(header, [(UR5["urdf"], urdf)]), timeout=30), "header.tip_link")
        header = robot_pb2.RobotBundleHeader(urdf_path="missing.urdf")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(
            bundle_requests(header, [(UR5["urdf"], urdf)]), timeout=30), "urdf_path")
        header = robot_pb2.RobotBundleHeader(urdf_path=UR5["urdf"])
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(
            bundle_requests(header, [(UR5["urdf"], b"<robot name='x'><link")]), timeout=30), "urdf")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(
            bundle_requests(header, [(UR5["urdf"], urdf), ("a.stl", b"1"), ("./a.stl", b"2")]), timeout=30),
            "files[2].path")
        huge = robot_pb2.RobotBundleHeader(urdf_path=UR5["urdf"], size_bytes=1 << 40)
        self.assertCode(C.RESOURCE_EXHAUSTED, lambda: self.robots.UploadRobot(
            bundle_requests(huge, [(UR5["urdf"], urdf)]), timeout=30), "header.size_bytes")
        no_header = iter([robot_pb2.UploadRobotRequest(file=robot_pb2.RobotBundleFile(path="a", content=b"x"))])
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.robots.UploadRobot(no_header, timeout=30), "header")


class KinematicsTest(RobotTestBase):
    def test_fk_matches_the_urdf(self):
        rng = np.random.default_rng(7)
        for robot, chain in ((self.panda, self.panda_chain), (self.ur5, self.ur5_chain)):
            for _ in range(20):
                q = chain.random_q(rng)
                got = self.fk(robot.robot_id, q)
                np.testing.assert_allclose(matrix(got.tool_pose), chain.fk(q), atol=1e-9)
                np.testing.assert_allclose(matrix(got.achieved_tool_pose), chain.fk(q), atol=1e-9)
                self.assertEqual(got.link_poses[0].link, robot.base_link)
                self.assertEqual(got.link_poses[-1].link, robot.tip_link)
                np.testing.assert_allclose(matrix(got.link_poses[-1].pose), chain.fk(q), atol=1e-9)

    def test_fk_bad_input(self):
        rid = self.panda.robot_id
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.fk(rid, [0.0] * 6), "joint_positions")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.fk(rid, [0, 0, 0, -1, 0, 1, float("nan")]),
                        "joint_positions[6]")
        self.assertCode(C.OUT_OF_RANGE, lambda: self.fk(rid, [3.5, 0, 0, -1, 0, 1, 0]), "joint_positions[0]")
        self.assertCode(C.NOT_FOUND, lambda: self.fk("rbt_nope", [0.0]), "robot_id")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.fk("", [0.0]), "robot_id")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.fk(rid, [0, 0, 0, -1, 0, 1, 0], apply_encoder_noise=True),
                        "apply_encoder_noise")

    def ik(self, **kwargs):
        return self.robots.InverseKinematics(robot_pb2.InverseKinematicsRequest(**kwargs), timeout=30)

    def test_ik_round_trips(self):
        rng = np.random.default_rng(11)
        for robot, chain in ((self.panda, self.panda_chain), (self.ur5, self.ur5_chain)):
            for _ in range(8):
                goal = chain.fk(chain.random_q(rng))
                answer = self.ik(robot_id=robot.robot_id, tool_pose=to_pose(goal), timeout_ms=1000)
                self.assertTrue(answer.reached)
                achieved = matrix(self.fk(robot.robot_id, list(answer.joint_positions)).tool_pose)
                self.assertLess(np.linalg.norm(achieved[:3, 3] - goal[:3, 3]), 1e-5)
                self.assertLess(rotation_angle(achieved, goal), 1e-5)
                np.testing.assert_allclose(chain.fk(list(answer.joint_positions)), achieved, atol=1e-9)
                np.testing.assert_allclose(matrix(answer.tool_pose), achieved, atol=1e-9)

    def test_ik_gradient_descent_and_reduced_goals(self):
        rng = np.random.default_rng(5)
        goal = self.panda_chain.fk(self.panda_chain.random_q(rng))
        answer = self.ik(robot_id=self.panda.robot_id, tool_position=common_pb2.Vector3(
            x=goal[0, 3], y=goal[1, 3], z=goal[2, 3]), method=robot_pb2.IK_METHOD_GRADIENT_DESCENT,
            tolerance=1e-4, timeout_ms=3000)
        self.assertTrue(answer.reached)
        got = self.panda_chain.fk(list(answer.joint_positions))
        self.assertLess(np.linalg.norm(got[:3, 3] - goal[:3, 3]), 1e-4)

        target = np.array([0.5, 0.3, 0.0])
        position = np.array([0.4, 0.0, 0.5])
        answer = self.ik(robot_id=self.panda.robot_id, timeout_ms=1000, look_from=robot_pb2.LookFrom(
            position=common_pb2.Vector3(x=position[0], y=position[1], z=position[2]),
            target=common_pb2.Vector3(x=target[0], y=target[1], z=target[2])))
        got = self.panda_chain.fk(list(answer.joint_positions))
        self.assertLess(np.linalg.norm(got[:3, 3] - position), 1e-5)
        view = (target - position) / np.linalg.norm(target - position)
        self.assertGreater(got[:3, 2] @ view, 1 - 1e-9)

    def test_unreachable_is_out_of_range_with_the_miss(self):
        far = common_pb2.Vector3(x=2.5, y=0.0, z=0.3)
        err = self.assertCode(C.OUT_OF_RANGE, lambda: self.ik(robot_id=self.panda.robot_id, tool_position=far),
                              "tool_position")
        miss = float(re.search(r"misses by ([0-9.eE+-]+) m", err.details()).group(1))
        self.assertGreater(miss, 2.5 - self.panda.reach - 0.4)
        self.assertIn("nearest reachable tool pose", err.details())

        partial = self.ik(robot_id=self.panda.robot_id, tool_position=far, allow_partial=True)
        self.assertFalse(partial.reached)
        self.assertEqual(len(partial.joint_positions), 7)
        nearest = matrix(partial.tool_pose)
        np.testing.assert_allclose(self.panda_chain.fk(list(partial.joint_positions)), nearest, atol=1e-9)
        self.assertAlmostEqual(partial.miss_distance, np.linalg.norm(nearest[:3, 3] - [2.5, 0.0, 0.3]), places=9)
        self.assertAlmostEqual(partial.miss_distance, partial.position_error, places=12)
        self.assertGreater(partial.miss_distance, 1.0)

    def test_ik_bad_input(self):
        rid = self.panda.robot_id
        pose = to_pose(self.panda_chain.fk([0, -0.5, 0, -2, 0, 1.5, 0.7]))
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.ik(robot_id=rid), "tool_pose")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.ik(robot_id=rid, tool_pose=pose, seed=[0.0]), "seed")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.ik(robot_id=rid, tool_pose=pose, timeout_ms=-1), "timeout_ms")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.ik(robot_id=rid, tool_pose=pose, method=9), "method")
        bad = common_pb2.Pose(matrix=common_pb2.Matrix4(values=[2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]))
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.ik(robot_id=rid, tool_pose=bad), "tool_pose")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.ik(robot_id=rid, look_from=robot_pb2.LookFrom(
            position=common_pb2.Vector3(x=0.3), target=common_pb2.Vector3(x=0.3))), "look_from")


class MountTest(RobotTestBase):
    Q = [0.2, -0.3, 0.1, -2.0, 0.05, 1.8, 0.6]

    def expected_sensor(self, q):
        return base_pose() @ self.panda_chain.fk(q) @ sensor_offset()

    def scan(self, scene_id, mount_id, q, seed=0, noise=False):
        request = scan_pb2.ScanRequest(scene_id=scene_id, sensor=pinhole(120, 90, 50.0, near=0.05, far=3.0),
                                       seed=seed, robot=scan_pb2.RobotPose(mount_id=mount_id, joint_positions=q,
                                                                           apply_encoder_noise=noise))
        header, points, ids = None, [], []
        for r in self.scans.Scan(request, timeout=60):
            if r.WhichOneof("part") == "header":
                header = r.header
            elif r.WhichOneof("part") == "chunk":
                points.append(np.frombuffer(r.chunk.positions, dtype="<f4").reshape(-1, 3))
                ids.append(np.frombuffer(r.chunk.instance_ids, dtype="<u4"))
        return header, np.concatenate(points) if points else np.zeros((0, 3)), np.concatenate(ids) if ids else []

    def test_mount_and_scan_from_joint_state(self):
        sensor = self.expected_sensor(self.Q)
        centre = sensor[:3, 3] + 0.6 * sensor[:3, 2]
        scene = self.sphere_scene(centre)
        mounted = self.mount(scene.scene_id, self.panda.robot_id, base_pose=to_pose(base_pose()),
                             tool_offset=to_pose(sensor_offset()))
        self.assertEqual(mounted.revision, scene.revision + 1)
        self.assertTrue(mounted.mount_id.startswith("mnt_"))
        self.assertEqual(self.robots.GetMount(robot_pb2.GetMountRequest(mount_id=mounted.mount_id)).mount,
                         mounted.mount)

        header, points, ids = self.scan(scene.scene_id, mounted.mount_id, self.Q)
        np.testing.assert_allclose(matrix(header.sensor_pose), sensor, atol=1e-9)
        np.testing.assert_allclose(matrix(header.commanded_sensor_pose), sensor, atol=1e-9)
        np.testing.assert_allclose(list(header.achieved_joint_positions), self.Q)
        self.assertEqual(header.scene_revision, mounted.revision)
        self.assertGreater(len(points), 500)
        self.assertTrue(np.all(np.asarray(ids) == 1))
        radii = np.linalg.norm(points - centre, axis=1)
        self.assertLess(np.max(np.abs(radii - 0.08)), 0.003)

        # World-frame kinematics through the mount agree with the scan.
        fk = self.robots.ForwardKinematics(robot_pb2.ForwardKinematicsRequest(mount_id=mounted.mount_id,
                                                                              joint_positions=self.Q))
        np.testing.assert_allclose(matrix(fk.tool_pose), sensor, atol=1e-9)
        ik = self.robots.InverseKinematics(robot_pb2.InverseKinematicsRequest(
            mount_id=mounted.mount_id, tool_pose=to_pose(sensor), timeout_ms=1000))
        self.assertTrue(ik.reached)
        np.testing.assert_allclose(self.expected_sensor(list(ik.joint_positions)), sensor, atol=2e-5)

    def test_encoder_noise_moves_the_achieved_pose(self):
        scene = self.sphere_scene([0.0, 0.0, -5.0])
        mounted = self.mount(scene.scene_id, self.panda.robot_id, base_pose=to_pose(base_pose()),
                             tool_offset=to_pose(sensor_offset()), encoder_sigma=[0.01])
        self.assertEqual(list(mounted.mount.encoder_sigma), [0.01] * 7)
        header, _, _ = self.scan(scene.scene_id, mounted.mount_id, self.Q, seed=42, noise=True)
        achieved = list(header.achieved_joint_positions)
        self.assertGreater(np.max(np.abs(np.subtract(achieved, self.Q))), 1e-4)
        np.testing.assert_allclose(matrix(header.commanded_sensor_pose), self.expected_sensor(self.Q), atol=1e-9)
        np.testing.assert_allclose(matrix(header.sensor_pose), self.expected_sensor(achieved), atol=1e-9)
        again, _, _ = self.scan(scene.scene_id, mounted.mount_id, self.Q, seed=42, noise=True)
        self.assertEqual(list(again.achieved_joint_positions), achieved)
        quiet, _, _ = self.scan(scene.scene_id, mounted.mount_id, self.Q, seed=42, noise=False)
        self.assertEqual(list(quiet.achieved_joint_positions), self.Q)

        fk = self.robots.ForwardKinematics(robot_pb2.ForwardKinematicsRequest(
            mount_id=mounted.mount_id, joint_positions=self.Q, apply_encoder_noise=True, encoder_noise_seed=42))
        self.assertEqual(list(fk.achieved_joint_positions), achieved)

    def test_bad_mounts_and_robot_scans(self):
        scene = self.sphere_scene([0.0, 0.0, -5.0])
        other = self.scenes.CreateScene(scene_pb2.CreateSceneRequest(name="other")).scene
        rid = self.panda.robot_id
        nan_pose = common_pb2.Pose(quaternion=common_pb2.QuaternionPose(qw=float("nan")))
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.mount(scene.scene_id, rid, base_pose=nan_pose), "base_pose")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.mount(scene.scene_id, rid, encoder_sigma=[0.1, 0.2]),
                        "encoder_sigma")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.mount(scene.scene_id, rid, encoder_sigma=[-1]),
                        "encoder_sigma[0]")
        self.assertCode(C.NOT_FOUND, lambda: self.mount("scn_nope", rid), "scene_id")
        self.assertCode(C.NOT_FOUND, lambda: self.mount(scene.scene_id, "rbt_nope"), "robot_id")
        after = self.scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene
        self.assertEqual(after.revision, scene.revision)

        self.assertTrue(self.mount(other.scene_id, rid, links_visible=True).mount.links_visible)
        mounted = self.mount(scene.scene_id, rid)
        self.assertCode(C.FAILED_PRECONDITION, lambda: self.scan(other.scene_id, mounted.mount_id, self.Q),
                        "robot.mount_id")
        self.assertCode(C.NOT_FOUND, lambda: self.scan(scene.scene_id, "mnt_nope", self.Q), "robot.mount_id")
        self.assertCode(C.INVALID_ARGUMENT, lambda: self.scan(scene.scene_id, mounted.mount_id, self.Q[:3]),
                        "robot.joint_positions")
        out_of_range = list(self.Q)
        out_of_range[3] = 0.5
        self.assertCode(C.OUT_OF_RANGE, lambda: self.scan(scene.scene_id, mounted.mount_id, out_of_range),
                        "robot.joint_positions[3]")

    def test_delete_and_unmount(self):
        robot = upload_ur5(self.robots)
        scene = self.sphere_scene([0.0, 0.0, -5.0])
        mounted = self.mount(scene.scene_id, robot.robot_id)
        self.assertCode(C.FAILED_PRECONDITION, lambda: self.robots.DeleteRobot(
            robot_pb2.DeleteRobotRequest(robot_id=robot.robot_id)), "robot_id")
        listed = self.robots.ListMounts(robot_pb2.ListMountsRequest(scene_id=scene.scene_id)).mounts
        self.assertEqual([m.mount_id for m in listed], [mounted.mount_id])
        unmounted = self.robots.UnmountRobot(robot_pb2.UnmountRobotRequest(mount_id=mounted.mount_id))
        self.assertEqual(unmounted.revision, mounted.revision + 1)
        self.assertCode(C.NOT_FOUND, lambda: self.robots.GetMount(robot_pb2.GetMountRequest(mount_id=mounted.mount_id)))
        self.robots.DeleteRobot(robot_pb2.DeleteRobotRequest(robot_id=robot.robot_id))
        self.assertCode(C.NOT_FOUND, lambda: self.robots.GetRobot(robot_pb2.GetRobotRequest(robot_id=robot.robot_id)))
        # The first UR5 shares the bundle, so its blob must still be there.
        self.fk(self.ur5.robot_id, [0.0] * 6)

    def test_deleting_a_scene_removes_its_mounts(self):
        robot = upload_ur5(self.robots)
        scene = self.sphere_scene([0.0, 0.0, -5.0])
        mounted = self.mount(scene.scene_id, robot.robot_id)
        self.scenes.DeleteScene(scene_pb2.DeleteSceneRequest(scene_id=scene.scene_id))
        self.assertCode(C.NOT_FOUND, lambda: self.robots.GetMount(robot_pb2.GetMountRequest(mount_id=mounted.mount_id)))
        self.robots.DeleteRobot(robot_pb2.DeleteRobotRequest(robot_id=robot.robot_id))


class RobotRestartTest(unittest.TestCase):
    def test_kill9_keeps_robots_and_mounts(self):
        server = Server().start()
        try:
            channel = server.channel()
            robots = robot_pb2_grpc.RobotServiceStub(channel)
            from vscan.v1 import scene_pb2_grpc
            scenes = scene_pb2_grpc.SceneServiceStub(channel)
            robot = upload_panda(robots, tool=sensor_offset())
            scene = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="durable")).scene
            mounted = robots.MountRobot(robot_pb2.MountRobotRequest(
                scene_id=scene.scene_id, robot_id=robot.robot_id, base_pose=to_pose(base_pose()),
                encoder_sigma=[0.001] * 7))
            q = MountTest.Q
            fk_before = robots.ForwardKinematics(robot_pb2.ForwardKinematicsRequest(
                mount_id=mounted.mount_id, joint_positions=q))
            channel.close()

            server.kill9()
            server.start()
            channel = server.channel()
            robots = robot_pb2_grpc.RobotServiceStub(channel)
            scenes = scene_pb2_grpc.SceneServiceStub(channel)
            self.assertEqual(robots.GetRobot(robot_pb2.GetRobotRequest(robot_id=robot.robot_id)).robot, robot)
            self.assertEqual(robots.GetMount(robot_pb2.GetMountRequest(mount_id=mounted.mount_id)).mount,
                             mounted.mount)
            self.assertEqual(scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene.scene_id)).scene.revision,
                             mounted.revision)
            fk_after = robots.ForwardKinematics(robot_pb2.ForwardKinematicsRequest(
                mount_id=mounted.mount_id, joint_positions=q))
            self.assertEqual(fk_after, fk_before)
            chain = UrdfChain(os.path.join(PANDA_DIR, PANDA["urdf"]), PANDA["base"], PANDA["tip"])
            np.testing.assert_allclose(matrix(fk_after.tool_pose), base_pose() @ chain.fk(q) @ sensor_offset(),
                                       atol=1e-9)
            channel.close()
        finally:
            server.cleanup()


class RobotPythonClientTest(unittest.TestCase):
    def test_client_robot_calls(self):
        from vscan import Client, VscanError
        server = Server().start()
        try:
            with Client(server.address) as client:
                chain = UrdfChain(os.path.join(PANDA_DIR, PANDA["urdf"]), PANDA["base"], PANDA["tip"])
                robot = client.upload_robot(PANDA_DIR, PANDA["urdf"], PANDA["base"], PANDA["tip"], chunk_bytes=3000)
                self.assertEqual(len(robot.joints), 7)
                self.assertEqual(robot.file_count, 13)
                self.assertIn(robot.robot_id, [r.robot_id for r in client.list_robots()])
                q = MountTest.Q
                fk = client.forward_kinematics(robot.robot_id, q)
                np.testing.assert_allclose(matrix(fk.tool_pose), chain.fk(q), atol=1e-9)
                goal = chain.fk(q)
                ik = client.inverse_kinematics(robot.robot_id, matrix=goal, timeout_ms=1000)
                self.assertTrue(ik.reached)
                np.testing.assert_allclose(chain.fk(list(ik.joint_positions)), goal, atol=2e-5)
                with self.assertRaises(VscanError) as err:
                    client.inverse_kinematics(robot.robot_id, position=(3, 0, 0))
                self.assertEqual(err.exception.code, C.OUT_OF_RANGE)
                partial = client.inverse_kinematics(robot.robot_id, position=(3, 0, 0), allow_partial=True)
                self.assertFalse(partial.reached)

                sensor = base_pose() @ goal @ sensor_offset()
                centre = sensor[:3, 3] + 0.5 * sensor[:3, 2]
                path = os.path.join(server.data_dir, "ball.ply")
                with open(path, "wb") as f:
                    f.write(icosphere_ply(0.08, centre))
                scene = client.create_scene("py-robot")
                client.add_object(scene.scene_id, client.upload_mesh(path, unit="m").mesh_id)
                mounted = client.mount_robot(scene.scene_id, robot.robot_id, matrix=base_pose(),
                                             tool_matrix=sensor_offset(), encoder_sigma=0.0)
                self.assertEqual([m.mount_id for m in client.list_mounts(scene.scene_id)], [mounted.mount_id])
                result = client.scan(scene.scene_id, width=100, height=80, mount_id=mounted.mount_id, joints=q)
                self.assertGreater(len(result), 100)
                np.testing.assert_allclose(matrix(result.header.sensor_pose), sensor, atol=1e-9)
                self.assertEqual(client.unmount_robot(mounted.mount_id), mounted.revision + 1)
                client.delete_robot(robot.robot_id)
        finally:
            server.cleanup()


class RobotCliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server().start()

    @classmethod
    def tearDownClass(cls):
        cls.server.cleanup()

    def vscan(self, *args):
        return subprocess.run([VSCAN, "--server", self.server.address, *args], capture_output=True, text=True,
                              timeout=120)

    def ok(self, *args):
        out = self.vscan(*args)
        self.assertEqual(out.returncode, 0, out.stderr)
        return out.stdout.strip()

    def test_robot_commands(self):
        robot = self.ok("-q", "robot", "upload", PANDA_DIR, "--urdf", "panda.urdf", "--base", "panda_link0",
                        "--tip", "panda_hand_tcp")
        self.assertTrue(robot.startswith("rbt_"))
        self.assertIn(robot, self.ok("-q", "robot", "list").split())
        info = json.loads(self.ok("--json", "robot", "get", robot))
        self.assertEqual(len(info["joints"]), 7)
        self.assertEqual(info["fileCount"], 13)  # the URDF, ten STL files, LICENSE and SOURCE.md

        ur5 = self.ok("-q", "robot", "upload", os.path.join(UR5_DIR, "ur5_robot.urdf"), "--base", "base_link",
                      "--tip", "tool0")
        self.assertIn("warning:", self.ok("robot", "get", ur5))

        chain = UrdfChain(os.path.join(PANDA_DIR, PANDA["urdf"]), PANDA["base"], PANDA["tip"])
        q = [0.1, -0.4, 0.2, -2.1, 0.0, 1.7, 0.5]
        fk = json.loads(self.ok("--json", "robot", "fk", robot, ",".join(map(str, q))))
        goal = chain.fk(q)
        np.testing.assert_allclose(np.array(fk["toolPose"]["values"]).reshape(4, 4), goal, atol=1e-9)

        position = ",".join(f"{v:.17g}" for v in goal[:3, 3])
        joints = self.ok("-q", "robot", "ik", robot, "--position", position, "--timeout-ms", "500")
        got = chain.fk([float(v) for v in joints.split(",")])
        self.assertLess(np.linalg.norm(got[:3, 3] - goal[:3, 3]), 1e-5)
        look = self.ok("robot", "ik", robot, "--position", "0.4,0,0.5", "--look-at", "0.5,0.2,0", "--method", "default")
        self.assertIn("reached", look)

        far = self.vscan("robot", "ik", robot, "--position", "3,0,0")
        self.assertEqual(far.returncode, 3, far.stderr)
        self.assertIn("OUT_OF_RANGE", far.stderr)
        self.assertIn("misses by", far.stderr)
        partial = self.ok("robot", "ik", robot, "--position", "3,0,0", "--partial")
        self.assertIn("not reached", partial)

        scene = self.ok("-q", "scene", "create", "robot-cli")
        mount = self.ok("-q", "robot", "mount", scene, robot, "--position", "0.1,0,0", "--rpy", "0,0,90",
                        "--tool-position", "0,0,0.05", "--encoder-sigma", "0.001")
        self.assertTrue(mount.startswith("mnt_"))
        self.assertIn(mount, self.ok("-q", "robot", "mounts", scene).split())
        out = os.path.join(tempfile.mkdtemp(prefix="vscan-robot-cli-"), "scan.ply")
        report = json.loads(self.ok("--json", "scan", scene, "-o", out, "--width", "64", "--height", "48",
                                    "--mount", mount, "--joints", ",".join(map(str, q))))
        expected = transform(axis_angle([0, 0, 1], math.pi / 2), [0.1, 0, 0]) @ goal @ transform(
            translation=[0, 0, 0.05])
        np.testing.assert_allclose(np.array(report["header"]["sensorPose"]["values"]).reshape(4, 4), expected,
                                   atol=1e-9)
        noisy = json.loads(self.ok("--json", "scan", scene, "-o", out, "--width", "64", "--height", "48",
                                   "--mount", mount, "--joints", ",".join(map(str, q)), "--encoder-noise",
                                   "--seed", "3"))
        self.assertNotEqual(noisy["header"]["achievedJointPositions"], q)

        self.assertEqual(self.vscan("robot", "delete", robot).returncode, 3)
        self.ok("robot", "unmount", mount)
        self.ok("robot", "delete", robot)
        self.assertEqual(self.vscan("robot", "get", robot).returncode, 3)

    def test_usage_and_local_errors(self):
        self.assertEqual(self.vscan("robot", "fk", "rbt_x", "1,abc").returncode, 2)
        self.assertEqual(self.vscan("robot", "ik", "rbt_x").returncode, 2)
        self.assertEqual(self.vscan("robot", "upload", "/nonexistent/robot.urdf").returncode, 5)
        self.assertEqual(self.vscan("scan", "scn_x", "-o", "/tmp/x.ply", "--joints", "1,2").returncode, 2)
        self.assertEqual(self.vscan("scan", "scn_x", "-o", "/tmp/x.ply", "--mount", "m", "--eye", "1,0,0",
                                    "--target", "0,0,0").returncode, 2)


if __name__ == "__main__":
    unittest.main()
