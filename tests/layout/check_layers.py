"""Holds the server's layers to what docs/ARCHITECTURE.md says: the engine includes nothing above
it, the service layer knows no gRPC or protobuf, and each folder of server/service/ includes only
the service folders it may use (the same graph its CMake link lines give)."""

import os
import re
import sys
import unittest

ROOT = os.environ.get("VSCAN_SOURCE_DIR") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SERVER = os.path.join(ROOT, "server")
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)

# Each service folder and the service folders it may include (besides itself).
SERVICE_USES = {
    "context": set(),
    "job": set(),
    "robot": {"context"},
    "picking": {"context", "job", "robot", "scan", "clouds", "localization", "bins"},
    "scan": {"context", "robot"},
    "clouds": {"context"},
    "localization": {"context", "clouds"},
    "model": {"context", "job", "scan", "clouds"},
    "campaign": {"context", "job", "scan", "robot", "clouds", "model"},
    "bins": {"job"},
    "datasets": {"context", "job", "scan", "robot", "localization"},
}
# Folders under server/ that sit above the engine and the service layer.
ABOVE_ENGINE = ("service/", "api/", "scenes/", "robot_registry/", "jobs/", "store/", "guards/", "observability/")


def sources(folder):
    for base, _, names in os.walk(folder):
        for name in names:
            if name.endswith((".h", ".cpp")):
                path = os.path.join(base, name)
                with open(path, encoding="utf-8") as f:
                    yield os.path.relpath(path, SERVER), INCLUDE.findall(f.read())


class Layers(unittest.TestCase):
    def test_every_service_folder_is_known(self):
        folders = {d for d in os.listdir(os.path.join(SERVER, "service"))
                   if os.path.isdir(os.path.join(SERVER, "service", d))}
        self.assertEqual(folders, set(SERVICE_USES))
        loose = [n for n in os.listdir(os.path.join(SERVER, "service")) if n.endswith((".h", ".cpp"))]
        self.assertEqual(loose, [], "every service file belongs to a folder")

    def test_service_folders_include_only_what_they_may_use(self):
        wrong = []
        for path, includes in sources(os.path.join(SERVER, "service")):
            folder = path.split(os.sep)[1]
            for inc in includes:
                if inc.startswith("service/"):
                    used = inc.split("/")[1]
                    if used != folder and used not in SERVICE_USES[folder]:
                        wrong.append(f"{path} includes {inc}")
                if inc.startswith(("grpc", "google/protobuf", "vscan/v1/")) or inc.endswith(".pb.h"):
                    wrong.append(f"{path} includes {inc} (no gRPC or protobuf below server/api)")
                if inc.startswith("api/"):
                    wrong.append(f"{path} includes {inc}")
        self.assertEqual(wrong, [])

    def test_the_engine_includes_nothing_above_it(self):
        wrong = [f"{path} includes {inc}" for path, includes in sources(os.path.join(SERVER, "engine"))
                 for inc in includes if inc.startswith(ABOVE_ENGINE)]
        self.assertEqual(wrong, [])

    def test_the_check_sees_a_violation(self):
        # The pattern must match the include lines the tree really uses.
        self.assertEqual(INCLUDE.findall('#include "service/model/model_run.h"\n'), ["service/model/model_run.h"])


if __name__ == "__main__":
    sys.exit(unittest.main())
