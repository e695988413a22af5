"""The server's bounds on dataset jobs: plans past --max-dataset-scenes and plans whose estimate
cannot fit --max-data-mib are refused before a job exists; a job whose scenes pass the quota while
it writes fails RESOURCE_EXHAUSTED keeping its scenes (resumed once space is freed) while the server
keeps answering scans; DeleteJob removes a dataset's directory with the last job that names it, and
a restart removes the directories no job names and counts the others against the quota."""

import os
import unittest

import grpc
from harness import DATA, SOURCE_DIR, Server, small_scan_seconds
from vscan import Client, VscanError
from vscan.v1 import job_pb2

C = grpc.StatusCode
PARTS = os.path.join(SOURCE_DIR, "data", "parts")
MIB = 1 << 20


def plan_text(seeds, width=128, height=106, name="bounded"):
    return f"""name: {name}
bins:
  - name: blocks
    bin: {{inner_size: [0.20, 0.15, 0.10]}}
    parts:
      - {{mesh: {PARTS}/angle_block.STL, unit: in, count: 3}}
    max_simulated_s: 4
  - name: rods
    bin: {{inner_size: [0.25, 0.20, 0.10]}}
    parts:
      - {{mesh: {PARTS}/round.stl, unit: cm, scale: 0.25, count: 1}}
      - {{mesh: {PARTS}/angle_block.STL, unit: in, count: 2}}
    max_simulated_s: 4
seeds: {{first: 1, count: {seeds}}}
sensors:
  - {{name: tof, preset: kinect-v2-class, width: {width}, height: {height}}}
"""


def tree_bytes(root):
    total = 0
    for base, _, names in os.walk(root):
        for name in names:
            total += os.path.getsize(os.path.join(base, name))
    return total


def scene_dirs(root):
    scenes = os.path.join(root, "train_pbr")
    return sorted(os.listdir(scenes)) if os.path.isdir(scenes) else []


def stamps(root):
    out = {}
    for base, _, names in os.walk(os.path.join(root, "train_pbr")):
        for name in names:
            st = os.stat(os.path.join(base, name))
            out[os.path.join(base, name)] = (st.st_ino, st.st_mtime_ns)
    return out


class DatasetBoundsTest(unittest.TestCase):
    def start(self, *args, data_dir=None):
        server = Server(data_dir=data_dir, extra_args=args).start()
        self.addCleanup(server.cleanup)
        return server

    def plan(self, server, name, text):
        path = os.path.join(server.data_dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def datasets(self, server):
        return os.path.join(server.data_dir, "store", "datasets")

    def refused(self, call, code, *needles):
        with self.assertRaises(VscanError) as err:
            call()
        self.assertEqual(err.exception.code, code, err.exception.message)
        for needle in needles:
            self.assertIn(needle, err.exception.message)
        return err.exception.message

    def dataset_jobs(self, client):
        return [job.job_id for job in client.list_jobs() if job.kind == "dataset"]

    def test_plans_past_the_scene_bound_are_refused_naming_seeds_and_the_flag(self):
        server = self.start("--max-dataset-scenes", "10")
        with Client(server.address) as client:
            over = self.plan(server, "over.yaml", plan_text(6))  # 6 seeds x 2 bins = 12 scenes
            for call in (client.validate_dataset, client.start_dataset):
                self.refused(lambda: call(over), C.RESOURCE_EXHAUSTED, "spec.plan_yaml.seeds", "12 scenes",
                             "--max-dataset-scenes", "at most 10")
            client.validate_dataset(self.plan(server, "fits.yaml", plan_text(5)))  # 10 scenes
            # Parts in a bin have a fixed bound of the plan format (500), not the server's: INVALID_ARGUMENT.
            crowded = self.plan(server, "crowded.yaml", plan_text(1).replace("unit: in, count: 3", "unit: in, count: 501"))
            self.refused(lambda: client.validate_dataset(crowded), C.INVALID_ARGUMENT, "spec.plan_yaml",
                         "bins[0].parts", "at most 500")
            self.assertEqual(self.dataset_jobs(client), [])
        # The default bound (100000) refuses a plan of a million scenes before a mesh is read.
        default = self.start()
        with Client(default.address) as client:
            million = self.plan(default, "million.yaml", plan_text(500000))
            message = self.refused(lambda: client.validate_dataset(million), C.RESOURCE_EXHAUSTED,
                                   "spec.plan_yaml.seeds", "1000000 scenes", "at most 100000")
            self.assertIn("--max-dataset-scenes", message)
            self.assertEqual(self.dataset_jobs(client), [])

    def test_quota_refuses_up_front_fails_past_it_and_resumes_once_space_is_freed(self):
        server = self.start("--max-data-mib", "12")
        with Client(server.address) as client:
            bunny = client.upload_mesh(os.path.join(DATA, "meshes", "bunny", "bunny_zipper_res2.ply"), unit="m")
            scene = client.create_scene("small")
            client.add_object(scene.scene_id, bunny.mesh_id)

            # 128 scenes of 256 x 212 are estimated far past 12 MiB: refused, no job, nothing written.
            big = self.plan(server, "big.yaml", plan_text(64, 256, 212))
            for call in (client.validate_dataset, client.start_dataset):
                self.refused(lambda: call(big), C.RESOURCE_EXHAUSTED, "spec.plan_yaml", "--max-data-mib",
                             "the plan's 128 images")
            self.assertEqual(self.dataset_jobs(client), [])
            self.assertEqual(os.listdir(self.datasets(server)) if os.path.isdir(self.datasets(server)) else [], [])

            # 12 scenes (about 5 MiB, as much again for the tar) fit alone; two of them do not, and the
            # second is admitted while the first is still queued or running.
            plan = self.plan(server, "plan.yaml", plan_text(6))
            first = client.start_dataset(plan)
            second = client.start_dataset(plan)
            self.assertEqual(client.wait_job(first.job_id, timeout=300).state, job_pb2.JOB_STATE_SUCCEEDED)
            failed = client.wait_job(second.job_id, timeout=300)
            self.assertEqual(failed.state, job_pb2.JOB_STATE_FAILED, failed.message)
            self.assertIn("RESOURCE_EXHAUSTED", failed.message)
            self.assertIn("--max-data-mib", failed.message)
            root = os.path.join(self.datasets(server), second.job_id)
            written = scene_dirs(root)
            self.assertTrue(0 < len(written) < 12, written)
            self.assertEqual(len(written), failed.steps_done)
            self.assertFalse([name for name in written if name.endswith(".partial")])
            # The data directory stayed within the bound (a scene's estimate of slack aside).
            used = tree_bytes(os.path.join(server.data_dir, "store"))
            self.assertLess(used, 12 * MIB + MIB, used)

            # The server still answers a small scan at once.
            self.assertLess(small_scan_seconds(client, scene.scene_id)[0], 2.0)

            # Deleting the first job frees its directory and tar; the second resumes and completes.
            before = stamps(root)
            freed = client.delete_job(first.job_id)
            self.assertFalse(os.path.exists(os.path.join(self.datasets(server), first.job_id)))
            self.assertGreater(freed.removed_bytes, 8 * MIB)
            resumed = client.start_dataset(plan, resume_job_id=second.job_id)
            done = client.wait_job(resumed.job_id, timeout=300)
            self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
            self.assertEqual(len(scene_dirs(root)), 12)
            after = stamps(root)
            self.assertEqual({path: after[path] for path in before}, before, "finished scenes were rewritten")

    def test_restart_counts_dataset_directories_against_the_quota(self):
        server = self.start("--max-data-mib", "12")
        with Client(server.address) as client:
            job = client.run_dataset(self.plan(server, "plan.yaml", plan_text(6)), timeout=300)
            self.assertEqual(job.state, job_pb2.JOB_STATE_SUCCEEDED, job.message)
        server.stop()
        server.start()
        with Client(server.address) as client:
            # The directory (about 5 MiB) and its tar (as much) leave no room for 4 more scenes and
            # their tar (about 3 MiB by the estimate); the tar alone would.
            small = self.plan(server, "small.yaml", plan_text(2))
            self.refused(lambda: client.start_dataset(small), C.RESOURCE_EXHAUSTED, "--max-data-mib")
            client.delete_job(job.job_id)
            client.validate_dataset(small)

    def test_delete_removes_the_directory_with_the_last_job_naming_it_and_restart_sweeps_orphans(self):
        server = self.start()
        datasets = self.datasets(server)
        with Client(server.address) as client:
            plan = self.plan(server, "plan.yaml", plan_text(2))
            first = client.run_dataset(plan, timeout=300)
            self.assertEqual(first.state, job_pb2.JOB_STATE_SUCCEEDED, first.message)
            root = os.path.join(datasets, first.job_id)
            self.assertEqual(len(scene_dirs(root)), 4)
            # A resumption writes the same directory: deleting the first job keeps it for the second.
            second = client.run_dataset(plan, resume_job_id=first.job_id, timeout=300)
            self.assertEqual(second.state, job_pb2.JOB_STATE_SUCCEEDED, second.message)
            client.delete_job(first.job_id)
            self.assertEqual(len(scene_dirs(root)), 4)
            freed = client.delete_job(second.job_id)
            self.assertFalse(os.path.exists(root))
            self.assertGreater(freed.removed_bytes, 0)
            self.assertEqual(os.listdir(datasets), [])

            # A running job is refused, as other kinds are, and its directory stays.
            running = client.start_dataset(self.plan(server, "long.yaml", plan_text(40)))
            for event in client.watch_job(running.job_id, timeout=300):
                if event.job.steps_done >= 1:
                    break
            self.refused(lambda: client.delete_job(running.job_id), C.FAILED_PRECONDITION)
            running_root = os.path.join(datasets, running.job_id)
            self.assertTrue(os.path.isdir(running_root))
            client.cancel_job(running.job_id)
            self.assertEqual(client.wait_job(running.job_id, timeout=300).state, job_pb2.JOB_STATE_CANCELLED)
            kept = client.run_dataset(plan, timeout=300)
            self.assertEqual(kept.state, job_pb2.JOB_STATE_SUCCEEDED, kept.message)
        server.stop()

        # What a stop between the catalogue's delete and the removal leaves, a removal cut short,
        # and a directory vscand did not make.
        orphan = os.path.join(datasets, "job_00000000deadbeef")
        aside = os.path.join(datasets, ".removing-job_00000000feedface")
        foreign = os.path.join(datasets, "notes")
        for path in (orphan, aside, foreign):
            os.makedirs(os.path.join(path, "train_pbr", "000000"))
            with open(os.path.join(path, "train_pbr", "000000", "x.bin"), "wb") as f:
                f.write(b"x" * 1000)
        server.start()
        self.assertFalse(os.path.exists(orphan))
        self.assertFalse(os.path.exists(aside))
        self.assertTrue(os.path.isdir(foreign))
        self.assertEqual(len(scene_dirs(os.path.join(datasets, kept.job_id))), 4)
        self.assertTrue(os.path.isdir(running_root))
        with Client(server.address) as client:
            client.delete_job(running.job_id)
            client.delete_job(kept.job_id)
        self.assertFalse(os.path.exists(running_root))
        self.assertFalse(os.path.exists(os.path.join(datasets, kept.job_id)))
        self.assertEqual(os.listdir(datasets), ["notes"])


if __name__ == "__main__":
    unittest.main()
