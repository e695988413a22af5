"""Imports the generated vscan.v1 stubs.

An installed package carries them in vscan/v1. In a source tree they are generated at build time
into <build>/python/vscan/v1, which vscan/__init__.py adds to this package's search path.
"""

try:
    from vscan.v1 import common_pb2, scan_pb2, scan_pb2_grpc, scene_pb2, scene_pb2_grpc, sensor_pb2
    from vscan.v1 import robot_pb2, robot_pb2_grpc
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError(
        "vscan needs its generated vscan.v1 stubs: install the package (pip install client/python) or, "
        "from a source tree, set VSCAN_PY_STUBS to <build>/python or add that directory to sys.path"
    ) from exc

__all__ = ["common_pb2", "robot_pb2", "robot_pb2_grpc", "scan_pb2", "scan_pb2_grpc", "scene_pb2", "scene_pb2_grpc",
           "sensor_pb2"]
