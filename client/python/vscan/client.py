"""A synchronous Python client for vscand."""

import os

import grpc

from . import convert
from ._stubs import robot_pb2_grpc, scan_pb2, scan_pb2_grpc, scene_pb2, scene_pb2_grpc, sensor_pb2
from .bins import BinCalls
from .clouds import CloudCalls
from .datasets import DatasetCalls
from .errors import VscanError, from_rpc_error
from .jobs import JobCalls
from .localization import LocalizationCalls
from .models import ModelCalls
from .picking import PickingCalls
from .picking_jobs import PickingJobCalls
from .robots import RobotCalls
from .scan_result import ScanAssembler

_CHUNK_BYTES = 1 << 20
_HEALTH_STATUS = {0: "UNKNOWN", 1: "SERVING", 2: "NOT_SERVING", 3: "SERVICE_UNKNOWN"}


def _encode_health_request(service):
    # grpc.health.v1.HealthCheckRequest { string service = 1; }, encoded by hand so that no
    # extra package is needed.
    data = service.encode()
    if not data:
        return b""
    length, prefix = len(data), bytearray()
    while True:
        byte = length & 0x7F
        length >>= 7
        prefix.append(byte | (0x80 if length else 0))
        if not length:
            break
    return b"\x0a" + bytes(prefix) + data


def _decode_health_response(data):
    # HealthCheckResponse { ServingStatus status = 1; }: a single small varint field.
    if len(data) >= 2 and data[0] == 0x08:
        return _HEALTH_STATUS.get(data[1], str(data[1]))
    return "UNKNOWN"


def _read(path):
    if not path:
        return None
    with open(path, "rb") as f:
        return f.read()


class Client(RobotCalls, JobCalls, ModelCalls, CloudCalls, BinCalls, LocalizationCalls, DatasetCalls, PickingCalls,
             PickingJobCalls):
    """Talks to one vscand. Failed calls raise VscanError.

    address: "host:port". token: bearer token sent with every call. root_cert: PEM file of the
    CA certificates to trust (turns TLS on). client_cert, client_key: PEM files of a client
    certificate and its private key for a server that requires them (mutual TLS; both or neither;
    turns TLS on). tls: TLS with gRPC's default roots when no root_cert is given. timeout: seconds
    per unary call (None: no deadline); scans and uploads use stream_timeout.
    """

    def __init__(self, address="127.0.0.1:50051", token=None, root_cert=None, timeout=30.0, stream_timeout=None,
                 client_cert=None, client_key=None, tls=False):
        if bool(client_cert) != bool(client_key):
            raise ValueError("client_cert and client_key go together")
        # A fixed 8 MiB stream window from the first byte: gRPC's probing starts a new channel at
        # 64 KiB and grows it too late for a single scan.
        options = [
            ("grpc.max_receive_message_length", 64 << 20),
            ("grpc.http2.bdp_probe", 0),
            ("grpc.http2.lookahead_bytes", 8 << 20),
        ]
        if tls or root_cert or client_cert:
            credentials = grpc.ssl_channel_credentials(
                root_certificates=_read(root_cert), private_key=_read(client_key),
                certificate_chain=_read(client_cert))
            self._channel = grpc.secure_channel(address, credentials, options=options)
        else:
            self._channel = grpc.insecure_channel(address, options=options)
        self._metadata = (("authorization", f"Bearer {token}"),) if token else None
        self._timeout = timeout
        self._stream_timeout = stream_timeout
        self._scenes = scene_pb2_grpc.SceneServiceStub(self._channel)
        self._scans = scan_pb2_grpc.ScanServiceStub(self._channel)
        self._robots = robot_pb2_grpc.RobotServiceStub(self._channel)
        self._health = self._channel.unary_unary(
            "/grpc.health.v1.Health/Check",
            request_serializer=_encode_health_request,
            response_deserializer=_decode_health_response,
        )

    def close(self):
        self._channel.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _call(self, method, request, timeout=None):
        try:
            return method(request, timeout=timeout or self._timeout, metadata=self._metadata)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None

    # -- health ---------------------------------------------------------------------------------

    def health(self, service=""):
        """"SERVING", "NOT_SERVING", ... for the server ("") or a named service."""
        return self._call(self._health, service)

    # -- scenes ---------------------------------------------------------------------------------

    def create_scene(self, name):
        return self._call(self._scenes.CreateScene, scene_pb2.CreateSceneRequest(name=name)).scene

    def get_scene(self, scene_id):
        return self._call(self._scenes.GetScene, scene_pb2.GetSceneRequest(scene_id=scene_id)).scene

    def list_scenes(self):
        return self._pages(self._scenes.ListScenes, scene_pb2.ListScenesRequest, "scenes")

    def delete_scene(self, scene_id):
        self._call(self._scenes.DeleteScene, scene_pb2.DeleteSceneRequest(scene_id=scene_id))

    def _pages(self, method, request_type, field):
        items, token = [], ""
        while True:
            page = self._call(method, request_type(page_token=token))
            items.extend(getattr(page, field))
            if not page.next_page_token or page.next_page_token == token:
                return items
            token = page.next_page_token

    # -- meshes ---------------------------------------------------------------------------------

    def upload_mesh(self, path, unit, scale=1.0, name=None, format=None, chunk_bytes=_CHUNK_BYTES, material=None):
        """Uploads a PLY/OBJ/STL file written in `unit` ("m", "cm", "mm", "in", "ft"); returns the Mesh.

        material is the default of the mesh's objects: a preset name such as "machined-aluminium"
        (list_material_presets), a dict of diffuse_albedo, metallic, roughness and
        specular_reflectance, or None for the server's default (matte-grey)."""
        size = os.path.getsize(path)
        header = scene_pb2.MeshHeader(
            name=name or os.path.basename(path),
            format=convert.mesh_format(format, path),
            unit=convert.unit(unit),
            scale=float(scale),
            size_bytes=size,
            material=convert.material(material),
        )

        def requests():
            yield scene_pb2.UploadMeshRequest(header=header)
            with open(path, "rb") as f:
                while True:
                    data = f.read(chunk_bytes)
                    if not data:
                        return
                    yield scene_pb2.UploadMeshRequest(chunk=data)

        try:
            response = self._scenes.UploadMesh(requests(), timeout=self._stream_timeout, metadata=self._metadata)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None
        return response.mesh

    def get_mesh(self, mesh_id):
        return self._call(self._scenes.GetMesh, scene_pb2.GetMeshRequest(mesh_id=mesh_id)).mesh

    def list_meshes(self):
        return self._pages(self._scenes.ListMeshes, scene_pb2.ListMeshesRequest, "meshes")

    def delete_mesh(self, mesh_id):
        self._call(self._scenes.DeleteMesh, scene_pb2.DeleteMeshRequest(mesh_id=mesh_id))

    # -- objects and table ----------------------------------------------------------------------

    def add_object(self, scene_id, mesh_id, position=(0.0, 0.0, 0.0), quat=None, matrix=None, scale=1.0,
                   label="", on_table=False, material=None):
        """Places a mesh instance; quat is (w, x, y, z), matrix a rigid 4x4. Returns the SceneObject.

        material overrides the mesh's for this object (a preset name, a dict of values as in
        upload_mesh, or None to use the mesh's)."""
        request = scene_pb2.AddObjectRequest(
            scene_id=scene_id,
            mesh_id=mesh_id,
            pose=convert.pose(position, quat, matrix),
            scale=float(scale),
            label=label,
            on_table=on_table,
            material=convert.material(material),
        )
        return self._call(self._scenes.AddObject, request).object

    def move_object(self, scene_id, object_id, position=(0.0, 0.0, 0.0), quat=None, matrix=None, scale=0.0):
        """Sets an object's pose (and scale unless 0). Returns the SceneObject."""
        request = scene_pb2.MoveObjectRequest(
            scene_id=scene_id, object_id=object_id, pose=convert.pose(position, quat, matrix), scale=float(scale)
        )
        return self._call(self._scenes.MoveObject, request).object

    def set_object_material(self, scene_id, object_id, material=None):
        """Sets an object's material override (a preset name or a dict of values as in
        upload_mesh); None clears it, so that the object takes its mesh's again. Returns the
        SceneObject."""
        request = scene_pb2.SetObjectMaterialRequest(
            scene_id=scene_id, object_id=object_id, material=convert.material(material)
        )
        return self._call(self._scenes.SetObjectMaterial, request).object

    def list_material_presets(self):
        """The named materials the server knows (name, values, description); the first is the default."""
        return list(self._call(self._scenes.ListMaterialPresets, scene_pb2.ListMaterialPresetsRequest()).presets)

    def remove_object(self, scene_id, object_id):
        """Returns the scene's new revision."""
        request = scene_pb2.RemoveObjectRequest(scene_id=scene_id, object_id=object_id)
        return self._call(self._scenes.RemoveObject, request).revision

    def set_table(self, scene_id, angle_deg, centre=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), enabled=True):
        """Configures the rotary table; returns the RotaryTable the server stored."""
        table = scene_pb2.RotaryTable(
            enabled=enabled,
            centre=convert.vector3(centre, "centre"),
            axis=convert.vector3(axis, "axis"),
            angle_deg=float(angle_deg),
        )
        request = scene_pb2.SetRotaryTableRequest(scene_id=scene_id, table=table)
        return self._call(self._scenes.SetRotaryTable, request).table

    # -- scanning -------------------------------------------------------------------------------

    def list_sensor_presets(self):
        return list(self._call(self._scans.ListSensorPresets, scan_pb2.ListSensorPresetsRequest()).presets)

    def scan(self, scene_id, width=640, height=480, hfov_deg=60.0, eye=None, target=None, up=(0.0, 0.0, 1.0),
             near=0.05, far=10.0, fields=None, frame="world", intrinsics=None, pose_matrix=None,
             backend="raycast", seed=0, table_angle_deg=None, chunk_bytes=None, lighting=None, noise=None,
             preset=None, progress=None, mount_id=None, joints=None, encoder_noise=False,
             include_rejected=False, normal_estimation=None, sensor=None, ground_truth=False,
             returned_light=None, pixel_images=False):
        """Scans a scene and returns a ScanResult with numpy arrays.

        Place the camera with eye/target/up, a 4x4 world_from_sensor pose_matrix, or on a robot:
        mount_id and the robot's joints (encoder_noise: perturb them by the mount's encoder sigma,
        seeded by seed; header.sensor_pose is then where the arm landed). intrinsics is
        (fx, fy, cx, cy) instead of hfov_deg; lighting is (power, constant, linear, quadratic);
        noise a sensor_pb2.NoiseSpec. fields: names from "position", "normal", "range",
        "intensity", "instance", "pixel", and the ground truth "clean", "incidence", "status",
        "estimated_normal" (None: the server default). include_rejected also returns rejected rays
        at their clean positions; normal_estimation is (k, max_distance) for "estimated_normal".
        sensor, a sensor_pb2.SensorSpec (e.g. a structured-light scanner), replaces preset and the
        camera arguments. progress(points, total) is called after each chunk (total 0: not known
        until the scan ends, as for streamed ray-cast scans). ground_truth fills result.objects:
        each scene object in view with its true poses and visible fraction (ObjectTruth messages).
        returned_light lights the scene with the sensor's own emitter and each object's material: True
        for the defaults, or a dict of sensor_pb2.ReturnedLight's fields ({"emitter_w_per_sr": 0.01,
        "exposure_s": 0.02, "indirect_samples": 64, ...}); rays too dark or saturated get status "dark"
        or "saturated", structured-light rays drowned by indirect light "interreflection", and
        intensity is the measured electrons. pixel_images fills result.reasons and result.gray,
        (height, width) arrays: each pixel's PointStatus (0 where the ray met no surface) and the grey
        image of the returned signal (uint16, 65535 at full scale).
        """
        request = scan_pb2.ScanRequest(scene_id=scene_id, seed=int(seed), frame=convert.frame(frame),
                                       backend=convert.backend(backend))
        if sensor is not None:
            request.sensor.CopyFrom(sensor)
        elif preset:
            request.sensor.preset = preset
        else:
            camera = request.sensor.pinhole
            camera.width, camera.height = int(width), int(height)
            camera.near, camera.far = float(near), float(far)
            if intrinsics is not None:
                fx, fy, cx, cy = (float(v) for v in intrinsics)
                camera.intrinsics.CopyFrom(sensor_pb2.Intrinsics(fx=fx, fy=fy, cx=cx, cy=cy))
            else:
                camera.horizontal_fov_deg = float(hfov_deg)
            if lighting is not None:
                power, constant, linear, quadratic = (float(v) for v in lighting)
                camera.lighting.CopyFrom(
                    sensor_pb2.Lighting(power=power, constant=constant, linear=linear, quadratic=quadratic))
        if mount_id is not None:
            if joints is None:
                raise ValueError("scan: mount_id needs joints")
            request.robot.mount_id = mount_id
            request.robot.joint_positions.extend(convert.numbers(joints, "joints"))
            request.robot.apply_encoder_noise = bool(encoder_noise)
        elif pose_matrix is not None:
            request.pose.matrix.CopyFrom(convert.matrix4(pose_matrix, "pose_matrix"))
        elif eye is not None and target is not None:
            request.pose.CopyFrom(convert.look_at(eye, target, up))
        else:
            raise ValueError("scan: give eye and target, pose_matrix, or mount_id and joints")
        if fields:
            request.fields.extend(convert.fields(fields))
        if table_angle_deg is not None:
            request.table_angle_deg = float(table_angle_deg)
        if chunk_bytes:
            request.chunk_bytes = int(chunk_bytes)
        if noise is not None:
            request.noise.CopyFrom(noise)
        request.include_rejected = bool(include_rejected)
        request.ground_truth = bool(ground_truth)
        request.pixel_images = bool(pixel_images)
        convert.returned_light(returned_light, request.returned_light)
        if normal_estimation is not None:
            k, max_distance = normal_estimation
            request.normal_estimation.k = int(k)
            request.normal_estimation.max_distance = float(max_distance)

        assembler = ScanAssembler(progress)
        stream = self._scans.Scan(request, timeout=self._stream_timeout, metadata=self._metadata)
        try:
            for message in stream:
                try:
                    assembler.add(message)
                except ValueError as err:
                    stream.cancel()
                    raise VscanError(grpc.StatusCode.DATA_LOSS, str(err)) from None
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None
        try:
            return assembler.result()
        except ValueError as err:
            raise VscanError(grpc.StatusCode.DATA_LOSS, str(err)) from None
