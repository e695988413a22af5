#!/usr/bin/python3
"""How long a cancel takes, per job kind and stage: starts a vscand from the build, runs each job
until it reaches the stage, cancels it, and times CancelJob's return to the job's end (CANCELLED).
Calls (Localize) are timed from their deadline to their answer. After every case a 64 x 48 scan is
timed, to show that the server kept serving.

  VSCAN_BUILD_DIR=build/release VSCAN_SOURCE_DIR=. /usr/bin/python3 bench/cancel_latency.py --runs 3

Prints a Markdown table (docs/OPERATIONS.md, "Cancel times"); --verbose prints each job's messages."""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
os.environ.setdefault("VSCAN_SOURCE_DIR", os.path.join(HERE, ".."))
os.environ.setdefault("VSCAN_BUILD_DIR", os.path.join(HERE, "..", "build", "release"))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "integration"))
sys.path.insert(0, os.path.join(HERE, "..", "client", "python"))

import grpc  # noqa: E402
import numpy as np  # noqa: E402
from harness import BUNNY, DATA, SOURCE_DIR, VSCAN, Server, pixel_cloud, torus_ply  # noqa: E402
from vscan import Client, VscanError, bin_part  # noqa: E402
from vscan.v1 import job_pb2, localization_pb2, localization_pb2_grpc  # noqa: E402

ENDED = {job_pb2.JOB_STATE_SUCCEEDED, job_pb2.JOB_STATE_FAILED, job_pb2.JOB_STATE_CANCELLED}
UR5_PLAN = os.path.join(SOURCE_DIR, "examples", "campaigns", "bunny_ur5.yaml")
DATASET_PLAN = os.path.join(SOURCE_DIR, "examples", "datasets", "parts_bins.yaml")


def cli_job(server, *args):
    out = subprocess.run([VSCAN, "--server", server.address, "--json", *args], capture_output=True, text=True,
                         timeout=120, cwd=tempfile.gettempdir())
    found = re.search(r'"jobId":\s*"(job_[0-9a-f]+)"', out.stdout)
    if out.returncode != 0 or not found:
        raise RuntimeError(f"vscan {' '.join(args)}: {out.returncode} {out.stderr[-500:]}")
    return found.group(1)


class Bench:
    def __init__(self, server, client, verbose):
        self.server, self.client, self.verbose = server, client, verbose
        self.tmp = tempfile.TemporaryDirectory(prefix="vscan-cancel-")
        self.campaign = cli_job(server, "campaign", "run", UR5_PLAN, "--no-download")
        self.client.wait_job(self.campaign, timeout=300)
        self.scene_id = self.client.create_scene("small-scan").scene_id
        bunny = self.client.upload_mesh(BUNNY, unit="m")
        self.client.add_object(self.scene_id, bunny.mesh_id)
        block = self.client.upload_mesh(os.path.join(DATA, "parts", "angle_block.STL"), unit="in")
        self.block_id = block.mesh_id
        torus = os.path.join(self.tmp.name, "torus.ply")
        torus_ply(torus, 30, 32)  # 1920 triangles: a ring, so the decomposition cuts it
        self.torus_id = self.client.upload_mesh(torus, unit="m").mesh_id
        side = 640
        f = 2.0 / 0.005
        self.walls = [self.client.upload_cloud(data=pixel_cloud(side, side, 0.005, 2.0), format="ply", frame="sensor",
                                               sensor_pose=np.eye(4), camera=(side, side, f, f, side / 2, side / 2,
                                                                              0.1, 10.0)).cloud_id
                      for _ in range(3)]

    def small_scan_s(self):
        start = time.monotonic()
        self.client.scan(self.scene_id, width=64, height=48, eye=(0.5, 0, 0.2), target=(0, 0, 0.07))
        return time.monotonic() - start

    def cancel_at(self, job_id, pattern, after_s=0.0, limit_s=300):
        """Waits until the job's message matches pattern, then after_s, cancels; the seconds from the
        cancel to the job's end, the end state, and whether the stage was reached while running."""
        deadline = time.monotonic() + limit_s
        last = None
        while time.monotonic() < deadline:
            job = self.client.get_job(job_id)
            if self.verbose and job.message != last:
                print(f"    {job.message[:120]}", file=sys.stderr)
                last = job.message
            if job.state in ENDED:
                return None, job.state, False
            if re.search(pattern, job.message):
                break
            time.sleep(0.02)
        time.sleep(after_s)
        asked = time.monotonic()
        try:
            self.client.cancel_job(job_id)
        except VscanError as err:
            if err.code != grpc.StatusCode.FAILED_PRECONDITION:
                raise
            return None, self.client.get_job(job_id).state, False  # it ended first
        ended = self.client.wait_job(job_id, timeout=limit_s)
        return time.monotonic() - asked, ended.state, True

    # Each case starts its job (run: the repetition's index) and returns (job_id, pattern, after_s).
    def campaign_scanning(self, run):
        return cli_job(self.server, "campaign", "run", UR5_PLAN, "--detach"), r"scan (\d\d) captured", 0.0

    def campaign_mesh(self, run):
        return cli_job(self.server, "campaign", "run", UR5_PLAN, "--detach"), r"aligned\.ply written", 0.2

    def campaign_coverage(self, run):
        return cli_job(self.server, "campaign", "run", UR5_PLAN, "--detach"), r"mesh\.ply written", 0.2

    def model_alignment(self, run):
        job = self.client.start_model(campaign_job_id=self.campaign)
        return job.job_id, r"aligned, fitness", 0.0

    def model_poisson(self, run):
        job = self.client.start_model(campaign_job_id=self.campaign, reconstruct=True, method="poisson",
                                      poisson_depth=10)
        return job.job_id, r"aligned\.ply written", 1.0

    def model_tsdf(self, run):
        """Runs 0, 1, 2, ... cancel while blocks are allocated, integrated, then meshed (about 2, 5
        and 20 s into the 30 s job)."""
        job = self.client.start_model(self.walls, skip_alignment=True, reconstruct=True, method="tsdf",
                                      reconstruction_voxel_size=0.001)
        return job.job_id, r"aligned\.ply written", (1.0, 5.0, 20.0)[run % 3]

    def bin_simulation(self, run):
        scene_id = self.client.create_scene("cancel-fill").scene_id
        job = self.client.start_bin_fill(scene_id, (0.45, 0.35, 0.25), [bin_part(self.block_id, 60)])
        return job.job_id, r"simulated", 0.0

    def bin_decomposition(self, run):
        scene_id = self.client.create_scene("cancel-decomposition").scene_id
        job = self.client.start_bin_fill(scene_id, (0.3, 0.3, 0.2),
                                         [bin_part(self.torus_id, 2, collision="convex_decomposition")])
        return job.job_id, r".", 0.3

    def dataset_scenes(self, run):
        return cli_job(self.server, "dataset", "run", DATASET_PLAN), r"scene", 1.0

    def dataset_tar(self, run):
        return cli_job(self.server, "dataset", "run", DATASET_PLAN), r"every scene checked", 0.0

    def localize_deadline(self):
        """A Localize call with a 0.5 s deadline: seconds from the deadline to the answer."""
        stub = localization_pb2_grpc.LocalizationServiceStub(self.client._channel)
        rng = np.random.default_rng(1)
        request = localization_pb2.LocalizeRequest(mesh_id=self.block_id)
        request.points.positions = (rng.uniform(-0.1, 0.1, (100000, 3)) + [0, 0, 0.5]).astype("<f4").tobytes()
        request.options.viewpoint.z = 1
        start = time.monotonic()
        try:
            stub.Localize(request, timeout=0.5)
            return None, "answered before its deadline", False
        except grpc.RpcError as err:
            return time.monotonic() - start - 0.5, err.code().name, True


CASES = [
    ("campaign", "scanning (robot moves, scans)", "campaign_scanning"),
    ("campaign", "union and TSDF mesh", "campaign_mesh"),
    ("campaign", "coverage", "campaign_coverage"),
    ("model", "alignment (40 scans)", "model_alignment"),
    ("model", "Poisson solve, depth 10 (vscan-poisson)", "model_poisson"),
    ("model", "TSDF fusion, 3 x 410k points at 1 mm: blocks, integration, mesh", "model_tsdf"),
    ("bin fill", "simulation, 60 parts", "bin_simulation"),
    ("bin fill", "convex decomposition, 1920 triangles (the first run; later ones reuse its pieces)", "bin_decomposition"),
    ("dataset", "scenes (fill, render, write)", "dataset_scenes"),
    ("dataset", "dataset.tar (16 scenes, 48 images)", "dataset_tar"),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--only", help="run the cases whose method name contains one of these (comma-separated)")
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args()
    server = Server().start()
    try:
        with Client(server.address, timeout=300) as client:
            bench = Bench(server, client, args.verbose)
            print("| job kind | stage | cancel to end, s: median (min–max) | end state | small scan after, s (max) |")
            print("|---|---|---|---|---|")
            cases = CASES + [("call", "Localize, 100k points, 0.5 s deadline", "localize_deadline")]
            for kind, stage, method in cases:
                if args.only and not any(name in method for name in args.only.split(",")):
                    continue
                times, states, scans = [], set(), []
                for run in range(args.runs):
                    if kind == "call":
                        seconds, state, reached = bench.localize_deadline()
                    else:
                        job_id, pattern, after = getattr(bench, method)(run)
                        seconds, state, reached = bench.cancel_at(job_id, pattern, after)
                        state = job_pb2.JobState.Name(state).removeprefix("JOB_STATE_")
                    states.add(state)
                    if reached:
                        times.append(seconds)
                    scans.append(bench.small_scan_s())
                spread = (f"{statistics.median(times):.2f} ({min(times):.2f}–{max(times):.2f})" if times
                          else "ended before the cancel")
                print(f"| {kind} | {stage} | {spread} | {', '.join(sorted(states))} | {max(scans):.2f} |",
                      flush=True)
    finally:
        server.cleanup()


if __name__ == "__main__":
    main()
