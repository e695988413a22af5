"""A picking job killed with -9 mid-run is INTERRUPTED, its picks so far kept in the scene, and
ResumeJob runs it on from the pile the scene holds until the bin is done with."""

import json
import time
import unittest

from harness import Server  # noqa: I100 (sets the stubs' path first)
from bin_scenes import fill_bin, matrix_pose, upload_part, upload_ur5
from vscan.v1 import job_pb2, job_pb2_grpc, picking_pb2, robot_pb2, robot_pb2_grpc, scene_pb2
from vscan.v1 import scene_pb2_grpc

BLOCKS = 8


def parts_in_scene(scenes, scene_id):
    scene = scenes.GetScene(scene_pb2.GetSceneRequest(scene_id=scene_id), timeout=30).scene
    return sorted(o.label for o in scene.objects if "#" in o.label)


def wait(jobs, job_id, until, timeout=300):
    deadline = time.time() + timeout
    while True:
        job = jobs.GetJob(job_pb2.GetJobRequest(job_id=job_id), timeout=30).job
        if until(job):
            return job
        if time.time() > deadline:
            raise AssertionError(f"job {job_id} still {job_pb2.JobState.Name(job.state)}: {job.message}")
        time.sleep(0.1)


def read_json(jobs, job, name):
    artifact = next(a for a in job.artifacts if a.name == name)
    data = b"".join(r.chunk for r in jobs.ReadArtifact(
        job_pb2.ReadArtifactRequest(job_id=job.job_id, artifact_id=artifact.artifact_id), timeout=60))
    return json.loads(data)


class PickingResumeTest(unittest.TestCase):
    def test_kill9_mid_run_then_resume(self):
        server = Server().start()
        try:
            channel = server.channel()
            scenes = scene_pb2_grpc.SceneServiceStub(channel)
            robots = robot_pb2_grpc.RobotServiceStub(channel)
            jobs = job_pb2_grpc.JobServiceStub(channel)
            block = upload_part(scenes, "angle_block")
            scene_id = scenes.CreateScene(scene_pb2.CreateSceneRequest(name="resume"), timeout=30).scene.scene_id
            bin_job = fill_bin(channel, scene_id, [(block[0], block[1], BLOCKS)], seed=2, inner_size=(0.2, 0.15, 0.1))
            robot_id = upload_ur5(robots)
            mount_id = robots.MountRobot(robot_pb2.MountRobotRequest(
                scene_id=scene_id, robot_id=robot_id,
                base_pose=matrix_pose([[0, 1, 0, 0], [-1, 0, 0, 0.45], [0, 0, 1, 0.3], [0, 0, 0, 1]]),
                tool_offset=matrix_pose([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.1], [0, 0, 0, 1]])),
                timeout=30).mount_id
            spec = job_pb2.PickingSpec(name="resume", bin_job_id=bin_job.job_id, mount_id=mount_id,
                                       gripper=picking_pb2.Gripper(suction=picking_pb2.SuctionCup(diameter=0.010)),
                                       grasp_options=picking_pb2.GraspOptions(max_grasps=1000), width=320, height=256)
            job = jobs.StartPicking(job_pb2.StartPickingRequest(spec=spec), timeout=30).job
            self.assertEqual(job.kind, "picking")
            # Killed once the first pick is done and the run goes on.
            wait(jobs, job.job_id, lambda j: j.steps_done >= 1 or j.state not in (
                job_pb2.JOB_STATE_QUEUED, job_pb2.JOB_STATE_RUNNING))
            channel.close()
            server.kill9()
            server.start()
            channel = server.channel()
            scenes = scene_pb2_grpc.SceneServiceStub(channel)
            jobs = job_pb2_grpc.JobServiceStub(channel)
            interrupted = jobs.GetJob(job_pb2.GetJobRequest(job_id=job.job_id), timeout=30).job
            if interrupted.state == job_pb2.JOB_STATE_SUCCEEDED:
                self.skipTest("the run ended before the kill")
            self.assertEqual(interrupted.state, job_pb2.JOB_STATE_INTERRUPTED, interrupted.message)
            left = parts_in_scene(scenes, scene_id)
            self.assertLess(len(left), BLOCKS)  # the first pick is in the scene
            self.assertGreater(len(left), 0)

            resumed = jobs.ResumeJob(job_pb2.ResumeJobRequest(job_id=job.job_id), timeout=30).job
            self.assertEqual(resumed.job_id, job.job_id)
            done = wait(jobs, job.job_id, lambda j: j.state not in (job_pb2.JOB_STATE_QUEUED, job_pb2.JOB_STATE_RUNNING))
            self.assertEqual(done.state, job_pb2.JOB_STATE_SUCCEEDED, done.message)
            report = read_json(jobs, done, "picking.json")
            self.assertLessEqual(report["parts_at_start"], len(left))
            self.assertEqual(report["parts_at_start"], report["picked"] + report["fell_out"] + report["left"])
            self.assertEqual(len(parts_in_scene(scenes, scene_id)), report["left"])
            self.assertGreaterEqual(report["picked"], 1, report)
            # The resumed run's steps start again at 0; each truth file lists the pile it started from.
            for step in report["steps"]:
                truth = read_json(jobs, done, step["truth_artifact"])
                self.assertEqual(len(truth["parts"]), step["parts_before"])
            # A succeeded job does not resume.
            with self.assertRaises(Exception) as refused:
                jobs.ResumeJob(job_pb2.ResumeJobRequest(job_id=job.job_id), timeout=30)
            self.assertIn("FAILED_PRECONDITION", str(refused.exception))
            channel.close()
        finally:
            server.cleanup()


if __name__ == "__main__":
    unittest.main()
