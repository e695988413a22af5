"""Builds the vscan package with its vscan.v1 stubs, generated from proto/ while building.

Where the stubs come from, first that applies:
- VSCAN_PY_STUBS=<build>/python: copied from a CMake build (target vscan_python_stubs);
- grpc_tools (python3-grpc-tools, or pip's grpcio-tools): python -m grpc_tools.protoc;
- protoc and grpc_python_plugin on PATH (Debian: protobuf-compiler, protobuf-compiler-grpc).
The .proto files are read from VSCAN_PROTO_DIR, by default ../../proto of this directory.
"""

import glob
import importlib.util
import os
import shutil
import subprocess
import sys

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))


def copy_built_stubs(stubs_root, out_dir):
    stubs = sorted(glob.glob(os.path.join(stubs_root, "vscan", "v1", "*_pb2*.py")))
    if not stubs:
        raise RuntimeError(f"VSCAN_PY_STUBS={stubs_root} holds no vscan/v1/*_pb2*.py: build vscan_python_stubs")
    for path in stubs:
        shutil.copy(path, out_dir)


def protoc_command():
    if importlib.util.find_spec("grpc_tools") is not None:
        return [sys.executable, "-m", "grpc_tools.protoc"]
    protoc, plugin = shutil.which("protoc"), shutil.which("grpc_python_plugin")
    if not protoc or not plugin:
        raise RuntimeError("generating the vscan.v1 stubs needs grpc_tools, or protoc and grpc_python_plugin, "
                           "or VSCAN_PY_STUBS naming a build's python directory")
    return [protoc, f"--plugin=protoc-gen-grpc_python={plugin}"]


def generate_stubs(out_root):
    proto_dir = os.path.abspath(os.environ.get("VSCAN_PROTO_DIR", os.path.join(HERE, "..", "..", "proto")))
    protos = sorted(glob.glob(os.path.join(proto_dir, "vscan", "v1", "*.proto")))
    if not protos:
        raise RuntimeError(f"no vscan/v1/*.proto under {proto_dir}: set VSCAN_PROTO_DIR")
    subprocess.run(protoc_command() + ["-I", proto_dir, f"--python_out={out_root}", f"--grpc_python_out={out_root}",
                                       *protos], check=True)


class BuildPyWithStubs(build_py):
    """The package's modules, then vscan/v1/*_pb2*.py beside them in the build directory."""

    def run(self):
        super().run()
        out_dir = os.path.join(self.build_lib, "vscan", "v1")
        shutil.rmtree(out_dir, ignore_errors=True)  # no stubs left from an older proto set
        os.makedirs(out_dir, exist_ok=True)
        stubs_root = os.environ.get("VSCAN_PY_STUBS")
        if stubs_root:
            copy_built_stubs(stubs_root, out_dir)
        else:
            generate_stubs(self.build_lib)
        with open(os.path.join(out_dir, "__init__.py"), "w", encoding="utf-8") as f:
            f.write('"""Generated from proto/vscan/v1."""\n')


setup(cmdclass={"build_py": BuildPyWithStubs})
