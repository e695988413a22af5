"""Cloud calls of the Client: stored point clouds (CloudService), and binary PLY as numpy arrays."""

import os
from dataclasses import dataclass
from typing import Optional

import grpc
import numpy as np

from . import convert
from ._stubs import common_pb2, sensor_pb2
from .errors import VscanError, from_rpc_error

from vscan.v1 import cloud_pb2, cloud_pb2_grpc  # noqa: E402

_CHUNK_BYTES = 1 << 20

CLOUD_FORMATS = {"ply": cloud_pb2.CLOUD_FORMAT_PLY, "pcd": cloud_pb2.CLOUD_FORMAT_PCD}

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "<i2", "int16": "<i2", "ushort": "<u2",
    "uint16": "<u2", "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4", "float": "<f4",
    "float32": "<f4", "double": "<f8", "float64": "<f8",
}

# CloudPoints attribute -> the PLY properties vscan writes it as.
_PLY_FIELDS = (
    ("positions", ("x", "y", "z")),
    ("normals", ("nx", "ny", "nz")),
    ("ranges", ("range",)),
    ("intensities", ("intensity",)),
    ("instance_ids", ("instance",)),
    ("pixels", ("pixel",)),
    ("clean_positions", ("clean_x", "clean_y", "clean_z")),
    ("incidence_angles", ("incidence",)),
    ("statuses", ("status",)),
    ("estimated_normals", ("enx", "eny", "enz")),
)


@dataclass
class CloudPoints:
    """A cloud's points. Arrays have one row per point; absent fields are None."""

    cloud: Optional[cloud_pb2.Cloud]
    positions: np.ndarray  # (N, 3) float32, in cloud.frame
    normals: Optional[np.ndarray] = None  # (N, 3) float32
    ranges: Optional[np.ndarray] = None  # (N,) float32
    intensities: Optional[np.ndarray] = None  # (N,) float32
    instance_ids: Optional[np.ndarray] = None  # (N,) uint32
    pixels: Optional[np.ndarray] = None  # (N,) uint32
    clean_positions: Optional[np.ndarray] = None  # (N, 3) float32
    incidence_angles: Optional[np.ndarray] = None  # (N,) float32, radians
    statuses: Optional[np.ndarray] = None  # (N,) uint8, scan_pb2.PointStatus values
    estimated_normals: Optional[np.ndarray] = None  # (N, 3) float32

    def __len__(self):
        return int(self.positions.shape[0])


def parse_ply(data, cloud=None):
    """CloudPoints of a binary little-endian PLY as vscan writes it (ReadCloud, campaign artifacts)."""
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise ValueError("not a binary PLY file")
    body = end + len(b"end_header\n")
    lines = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in lines:
        raise ValueError("only binary little-endian PLY is read")
    count, columns, in_vertex = None, [], False
    for line in lines:
        words = line.split()
        if words[:1] == ["element"]:
            if count is not None:
                break
            in_vertex = words[1] == "vertex"
            if not in_vertex:
                raise ValueError(f"element {words[1]!r} before the vertices")
            count = int(words[2])
        elif words[:1] == ["property"] and in_vertex:
            if words[1] == "list" or words[1] not in _PLY_TYPES:
                raise ValueError(f"unsupported vertex property: {line!r}")
            columns.append((words[2], _PLY_TYPES[words[1]]))
    if count is None:
        raise ValueError("no vertex element")
    rows = np.frombuffer(data, dtype=np.dtype(columns), count=count, offset=body)
    arrays = {}
    for attribute, names in _PLY_FIELDS:
        if all(name in rows.dtype.names for name in names):
            values = np.stack([rows[name] for name in names], axis=1) if len(names) == 3 else rows[names[0]].copy()
            if attribute in ("instance_ids", "pixels") and values.dtype == np.dtype("<i4"):
                values = values.view("<u4")  # vscan writes these uint32 values as int32 (what Open3D reads)
            arrays[attribute] = values
    if "positions" not in arrays:
        raise ValueError("the vertices need x, y and z")
    return CloudPoints(cloud=cloud, **arrays)


def cloud_camera(camera):
    """A CloudCamera from (width, height, fx, fy, cx, cy, near, far), or one as it is."""
    if camera is None or isinstance(camera, cloud_pb2.CloudCamera):
        return camera
    width, height, fx, fy, cx, cy, near, far = camera
    return cloud_pb2.CloudCamera(width=int(width), height=int(height),
                                 intrinsics=sensor_pb2.Intrinsics(fx=fx, fy=fy, cx=cx, cy=cy), near=near, far=far)


def cloud_format(value, path=None):
    """An explicit format ("ply", "pcd"), the one the file extension names, or unspecified (the
    server tells it from the bytes)."""
    if value is None and path is not None:
        value = os.path.splitext(path)[1].lstrip(".").lower()
        if value not in CLOUD_FORMATS:
            return cloud_pb2.CLOUD_FORMAT_UNSPECIFIED
    if value is None:
        return cloud_pb2.CLOUD_FORMAT_UNSPECIFIED
    return convert._lookup(CLOUD_FORMATS, value, "format")


class CloudCalls:
    """Mixed into Client; uses its channel, metadata and call helpers."""

    @property
    def _clouds(self):
        stub = self.__dict__.get("_cloud_stub")
        if stub is None:
            stub = self.__dict__["_cloud_stub"] = cloud_pb2_grpc.CloudServiceStub(self._channel)
        return stub

    def upload_cloud(self, path=None, name=None, format=None, sensor_pose=None, frame="world", camera=None,
                     scene_id="", data=None, chunk_bytes=_CHUNK_BYTES):
        """Uploads a binary PLY or PCD file (path) or its bytes (data); returns the Cloud.

        sensor_pose: world_from_sensor as a 4x4 matrix or a common_pb2.Pose, when known. frame: the
        frame the points are in, "world" or "sensor". camera: (width, height, fx, fy, cx, cy, near,
        far) or a CloudCamera. The format is the one given, else the file extension's, else the
        server tells it from the bytes.
        """
        if (path is None) == (data is None):
            raise ValueError("upload_cloud: give path or data")
        size = os.path.getsize(path) if data is None else len(data)
        if sensor_pose is not None and not isinstance(sensor_pose, common_pb2.Pose):
            sensor_pose = convert.pose(matrix=sensor_pose)
        header = cloud_pb2.CloudHeader(
            name=name or (os.path.basename(path) if path else ""),
            format=cloud_format(format, path),
            sensor_pose=sensor_pose,
            frame=convert.frame(frame),
            camera=cloud_camera(camera),
            scene_id=scene_id,
            size_bytes=size,
        )

        def requests():
            yield cloud_pb2.UploadCloudRequest(header=header)
            if data is not None:
                for offset in range(0, len(data), chunk_bytes):
                    yield cloud_pb2.UploadCloudRequest(chunk=data[offset:offset + chunk_bytes])
                return
            with open(path, "rb") as f:
                while True:
                    chunk = f.read(chunk_bytes)
                    if not chunk:
                        return
                    yield cloud_pb2.UploadCloudRequest(chunk=chunk)

        try:
            response = self._clouds.UploadCloud(requests(), timeout=self._stream_timeout, metadata=self._metadata)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None
        return response.cloud

    def get_cloud(self, cloud_id):
        return self._call(self._clouds.GetCloud, cloud_pb2.GetCloudRequest(cloud_id=cloud_id)).cloud

    def list_clouds(self, job_id=""):
        """Every cloud, or only the scans of job_id."""
        items, token = [], ""
        while True:
            page = self._call(self._clouds.ListClouds, cloud_pb2.ListCloudsRequest(page_token=token, job_id=job_id))
            items.extend(page.clouds)
            if not page.next_page_token or page.next_page_token == token:
                return items
            token = page.next_page_token

    def delete_cloud(self, cloud_id):
        """Deletes an uploaded cloud; returns DeleteCloudResponse (files and bytes freed).

        Raises VscanError with FAILED_PRECONDITION for a campaign's scan (it goes with its job)."""
        return self._call(self._clouds.DeleteCloud, cloud_pb2.DeleteCloudRequest(cloud_id=cloud_id))

    def read_cloud(self, cloud_id):
        """Returns (Cloud, bytes): the stored binary PLY."""
        stream = self._clouds.ReadCloud(cloud_pb2.ReadCloudRequest(cloud_id=cloud_id), timeout=self._stream_timeout,
                                        metadata=self._metadata)
        cloud, chunks = None, []
        try:
            for message in stream:
                if cloud is None:
                    cloud = message.cloud
                chunks.append(message.chunk)
        except grpc.RpcError as err:
            raise from_rpc_error(err) from None
        data = b"".join(chunks)
        if cloud is None or len(data) != cloud.size_bytes:
            expected = f"{cloud.size_bytes} bytes" if cloud else "a first message with the cloud"
            raise VscanError(grpc.StatusCode.DATA_LOSS,
                             f"cloud '{cloud_id}': got {len(data)} bytes, expected {expected}")
        return cloud, data

    def read_cloud_points(self, cloud_id):
        """The cloud's points as numpy arrays (CloudPoints, with the Cloud in .cloud)."""
        cloud, data = self.read_cloud(cloud_id)
        return parse_ply(data, cloud)
