"""Locates the generated vscan.v1 stubs and imports them.

The stubs are generated at build time into <build>/python. Put that directory on sys.path, or
name it in the environment variable VSCAN_PY_STUBS.
"""

import os
import sys

_extra = os.environ.get("VSCAN_PY_STUBS")
if _extra and _extra not in sys.path:
    sys.path.insert(0, _extra)

try:
    from vscan.v1 import common_pb2, scan_pb2, scan_pb2_grpc, scene_pb2, scene_pb2_grpc, sensor_pb2  # noqa: E402
    from vscan.v1 import robot_pb2, robot_pb2_grpc  # noqa: E402
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError(
        "vscan_client needs the generated vscan.v1 Python stubs: set VSCAN_PY_STUBS to <build>/python "
        "or add that directory to sys.path"
    ) from exc

__all__ = ["common_pb2", "robot_pb2", "robot_pb2_grpc", "scan_pb2", "scan_pb2_grpc", "scene_pb2", "scene_pb2_grpc",
           "sensor_pb2"]
