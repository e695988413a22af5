"""A picking job in the web view (?picking=JOB_ID): the page in headless chromium draws each step's
pile from its truth file, marks the part picked and the planned tool, and plays the steps."""

import json
import os
import unittest

from harness import SOURCE_DIR
from web_harness import WebServerTestCase, run_page
from vscan.v1 import job_pb2, job_pb2_grpc, picking_pb2

from vscan import Client, bin_part

TOKEN = "web-picking-token"
BLOCKS = 5


class WebPickingTest(WebServerTestCase):
    token = TOKEN

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.client = Client(cls.server.address, token=TOKEN, stream_timeout=120)
        c = cls.client
        scene = c.create_scene("web picking")
        block = c.upload_mesh(os.path.join(SOURCE_DIR, "data", "parts", "angle_block.STL"), unit="in")
        bin_job, _ = c.bin_fill(scene.scene_id, (0.2, 0.15, 0.1), [bin_part(block.mesh_id, BLOCKS)], seed=4,
                                name="web picking pile", timeout=120)
        robot = c.upload_robot(os.path.join(SOURCE_DIR, "data", "robots", "ur5"), urdf="ur5_robot.urdf",
                               base="base_link", tip="tool0")
        mount = c.mount_robot(scene.scene_id, robot.robot_id, matrix=[[0, 1, 0, 0], [-1, 0, 0, 0.45], [0, 0, 1, 0.3],
                                                                      [0, 0, 0, 1]], tool_position=(0, 0, 0.1))
        jobs = job_pb2_grpc.JobServiceStub(c._channel)  # the raw call: the client's own arrives separately
        spec = job_pb2.PickingSpec(name="web picking", bin_job_id=bin_job.job_id, mount_id=mount.mount_id,
                                   perception=job_pb2.PICKING_PERCEPTION_TRUTH,
                                   gripper=picking_pb2.Gripper(suction=picking_pb2.SuctionCup(diameter=0.010)),
                                   grasp_options=picking_pb2.GraspOptions(max_grasps=1000))
        started = jobs.StartPicking(job_pb2.StartPickingRequest(spec=spec), metadata=c._metadata, timeout=30).job
        cls.job = c.wait_job(started.job_id, timeout=120)
        artifact = next(a for a in cls.job.artifacts if a.name == "picking.json")
        cls.report = json.loads(c.read_artifact(cls.job.job_id, artifact.artifact_id)[1])

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        super().tearDownClass()

    def test_the_page_replays_each_step_with_its_pick(self):
        self.assertEqual(self.job.state, job_pb2.JOB_STATE_SUCCEEDED, self.job.message)
        self.assertGreater(len(self.report["steps"]), 1)
        shot = os.path.join(self.tmp.name, "picking.png")
        url = f"http://{self.web}/?picking={self.job.job_id}#token={TOKEN}"
        seen = run_page(self, "picking_page.js", url, shot, "960x540")
        self.assertEqual(seen["consoleErrors"], [])
        self.assertEqual(seen["errorText"], "")
        view = seen["view"]
        self.assertEqual(view["steps"], len(self.report["steps"]))
        self.assertEqual(view["picked"], self.report["picked"])
        self.assertEqual(view["parts"], self.report["parts_at_start"])
        for step, drawn in zip(self.report["steps"], seen["steps"]):
            self.assertEqual(drawn["visible"], step["parts_before"], step)
            if step["outcome"] == "picked":
                self.assertEqual(drawn["picked"], f"{step['picked_part']}#{step['picked_instance'] + 1}")
                self.assertEqual(len(drawn["tool"]), 3)
                for got, want in zip(drawn["tool"], step["world_from_tool"][3::4][:3]):
                    self.assertAlmostEqual(got, want, places=5)
        self.assertEqual(seen["slider"]["step"], seen["slider"]["asked"])
        self.assertEqual(seen["played"]["playingText"], "pause")
        self.assertEqual(seen["played"]["endStep"], len(self.report["steps"]) - 1)
        self.assertGreater(os.path.getsize(shot), 1000)


if __name__ == "__main__":
    unittest.main()
