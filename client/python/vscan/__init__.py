"""Python client for vscan, the 3D scanning simulator.

    from vscan import Client
    with Client("127.0.0.1:50051") as c:
        scene = c.create_scene("demo")
        mesh = c.upload_mesh("bunny.ply", unit="m")
        c.add_object(scene.scene_id, mesh.mesh_id)
        result = c.scan(scene.scene_id, eye=(0.4, 0, 0.2), target=(0, 0, 0.05))
        print(result.positions.shape)
        cloud = c.upload_cloud("scan.pcd", frame="sensor", sensor_pose=world_from_sensor)
        points = c.read_cloud_points(cloud.cloud_id)
        job = c.start_model(campaign_job_id=campaign, evaluate=True)
        for scan in c.watch_alignments(job.job_id):
            print(scan.index, scan.fitness)
        report = c.model_report(job.job_id)   # model.json as a dict
        job, report = c.bin_fill(scene.scene_id, (0.3, 0.2, 0.15), [bin_part(mesh.mesh_id, 20)])
        truth = c.scan(scene.scene_id, eye=(0, 0, 0.6), target=(0, 0, 0), up=(0, 1, 0),
                       ground_truth=True).objects
        found = c.localize(mesh.mesh_id, cloud_id=cloud.cloud_id)
        grasps = c.generate_grasps(mesh.mesh_id, SuctionCup(diameter=0.012))
        picks = c.check_picks(mount_id, SuctionCup(diameter=0.012))

The generated stubs are the subpackage vscan.v1: an installed package carries them; from a source
tree set VSCAN_PY_STUBS to <build>/python (or put that directory on sys.path).
"""

import os as _os
import sys as _sys
from pkgutil import extend_path as _extend_path

# Without installed stubs, vscan.v1 is found in <build>/python/vscan/v1: the package spans every
# "vscan" directory on sys.path.
_build_stubs = _os.environ.get("VSCAN_PY_STUBS")
if _build_stubs and _build_stubs not in _sys.path:
    _sys.path.append(_build_stubs)
__path__ = _extend_path(__path__, __name__)

from .bins import bin_fill_spec, bin_part  # noqa: E402
from .client import Client  # noqa: E402
from .clouds import CloudPoints, parse_ply  # noqa: E402
from .errors import VscanError  # noqa: E402
from .localization import localize_part, part_symmetry, pose_matrix, scored_part, truth_from_objects  # noqa: E402
from .models import alignment_options, evaluation_options, model_spec, reconstruction_options  # noqa: E402
from .picking import ParallelJaws, SuctionCup  # noqa: E402
from .picking_jobs import picking_spec  # noqa: E402
from .scan_result import ScanResult  # noqa: E402

__all__ = ["Client", "bin_fill_spec", "bin_part", "CloudPoints", "ScanResult", "VscanError", "alignment_options",
           "evaluation_options", "localize_part", "model_spec", "ParallelJaws", "parse_ply", "part_symmetry", "picking_spec",
           "pose_matrix", "reconstruction_options",
           "scored_part", "SuctionCup", "truth_from_objects"]
