#!/usr/bin/python3
"""Scan the bunny with a campaign, then align, reconstruct and evaluate the scans in a model job.

A UR5 beside a rotary table carries a camera round the Stanford bunny (3 viewpoints x 4 table
angles, noisy encoders). The model job aligns the scans starting from the poses the arm reported,
reconstructs the surface, scores it against the bunny's true mesh and proposes where to look next.

    python client/python/examples/campaign_to_model.py --server 127.0.0.1:50051 --out bunny-model

with the vscan package installed (client/python/README.md), or from a source tree with
VSCAN_PY_STUBS=build/release/python PYTHONPATH=client/python in the environment.
"""

import argparse
import math
import os
import sys

from vscan import Client, VscanError
from vscan.v1 import job_pb2

HERE = os.path.dirname(os.path.abspath(__file__))

DATA = os.path.normpath(os.path.join(HERE, "..", "..", "..", "data"))
TARGET = (0.0, 0.0, 0.07)
VIEWPOINTS = [((0.30, 0.00, 0.12), TARGET), ((0.25, 0.20, 0.25), TARGET), ((0.12, 0.00, 0.38), TARGET)]


def set_up(client):
    """The bunny on the table and a UR5 mounted beside it; returns (scene_id, mount_id)."""
    scene = client.create_scene("campaign_to_model").scene_id
    bunny = client.upload_mesh(os.path.join(DATA, "meshes", "bunny", "bunny_zipper_res2.ply"), unit="m")
    # The bunny is modelled +y up: roll it upright and stand it on the table.
    half = math.sqrt(0.5)
    client.add_object(scene, bunny.mesh_id, position=(0.017, 0.0, -0.033), quat=(half, half, 0.0, 0.0),
                      label="bunny", on_table=True)
    client.set_table(scene, angle_deg=0.0)
    ur5 = client.upload_robot(os.path.join(DATA, "robots", "ur5"), urdf="ur5_robot.urdf", base="base_link",
                              tip="tool0")
    mount = client.mount_robot(scene, ur5.robot_id, position=(0.7, 0.0, 0.0), quat=(0.0, 0.0, 0.0, 1.0),
                               tool_position=(0.0, 0.0, 0.05), encoder_sigma=0.0002).mount_id
    return scene, mount


def print_metrics(name, metrics):
    print(f"  {name:5}  precision {metrics['precision']:.1%}  recall {metrics['recall']:.1%}  "
          f"F {metrics['f_score']:.1%}  accuracy {metrics['accuracy_mean'] * 1e3:.3f} mm  "
          f"completeness {metrics['completeness_mean'] * 1e3:.3f} mm")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default=os.environ.get("VSCAN_SERVER", "127.0.0.1:50051"))
    parser.add_argument("--rotations", type=int, default=4)
    parser.add_argument("--out", help="directory for the model job's files (model.json, mesh.ply, ...)")
    args = parser.parse_args()

    with Client(args.server) as client:
        scene, mount = set_up(client)
        campaign = client.start_campaign(scene, mount, VIEWPOINTS, rotations=args.rotations,
                                         rotation_step_deg=360.0 / args.rotations, width=320, height=240,
                                         hfov_deg=50.0, near=0.05, far=1.0, fields=["normal", "pixel"],
                                         encoder_noise=True, seed=1, name="campaign_to_model")
        campaign = client.wait_job(campaign.job_id)
        print(f"campaign {campaign.job_id}: {campaign.steps_done} of {campaign.steps_total} steps")

        job = client.start_model(campaign_job_id=campaign.job_id, reconstruct=True, evaluate=True,
                                 next_best_views=3, name="campaign_to_model")
        for scan in client.watch_alignments(job.job_id):
            if not scan.aligned:
                print(f"scan {scan.index + 1} ({scan.name}): not aligned: {scan.reason}")
            elif scan.has_error:
                print(f"scan {scan.index + 1} ({scan.name}): fitness {scan.fitness:.3f}, pose error {scan.rotation_error_deg:.3f} deg "
                      f"and {scan.translation_error_m * 1e3:.3f} mm (from {scan.initial_rotation_error_deg:.3f} deg "
                      f"and {scan.initial_translation_error_m * 1e3:.3f} mm)")
            else:
                print(f"scan {scan.index + 1} ({scan.name}): fitness {scan.fitness:.3f}")
        job = client.get_job(job.job_id)
        if job.state != job_pb2.JOB_STATE_SUCCEEDED:
            print(f"model job {job.job_id} ended {job_pb2.JobState.Name(job.state)}: {job.message}", file=sys.stderr)
            return 3
        report = client.model_report(job.job_id)

        alignment = report["alignment"]
        print(f"aligned {alignment['aligned']} of {alignment['aligned'] + alignment['unaligned']} scans")
        if "reconstruction" in report:
            mesh = report["reconstruction"]
            print(f"mesh ({mesh['method']}): {mesh['vertices']} vertices, {mesh['triangles']} triangles")
        evaluation = report["evaluation"]
        print(f"at tau {evaluation['tau'] * 1e3:.3f} mm:")
        for part in ("union", "mesh"):
            if part in evaluation:
                print_metrics(part, evaluation[part])
        print(f"coverage of the true surface: {evaluation['coverage']:.1%}")
        for rank, view in enumerate(evaluation.get("next_best_views", []), 1):
            x, y, z = view["position"]
            print(f"next best view {rank}: stand at ({x:.3f}, {y:.3f}, {z:.3f}) m with the table at "
                  f"{view['table_angle_deg']:.0f} deg: +{view['coverage_gain']:.1%} -> {view['coverage_after']:.1%}")
        if not evaluation.get("next_best_views"):
            print(f"no next best views: {evaluation.get('next_best_views_note', '')}")
        if args.out:
            paths = client.download_artifacts(job.job_id, args.out)
            print(f"{len(paths)} files in {args.out}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except VscanError as err:
        print(f"error: {err}", file=sys.stderr)
        sys.exit(3)
