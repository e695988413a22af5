#pragma once
// A bin of six blocks in front of a UR5 with a suction cup, and the picking plan that empties it.

#include <gtest/gtest.h>

#include "sensor/camera.h"
#include "service/bins/bin_fill_simulation.h"
#include "service/bins/bin_scene.h"
#include "service/picking/picking_session.h"
#include "service_world.h"
#include "vscan_test/meshes.h"

namespace vscan::service {

inline Pose3 Placed(double x, double y, double z) {
  Pose3 pose = Pose3::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

// Six 40 x 30 x 20 mm blocks dropped into a 16 x 12 x 8 cm bin 0.45 m in front of a UR5 on a
// 0.2 m pedestal; a 12 mm suction cup; a camera 0.6 m above the bin looking down.
class PickingSessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = world_.EmptyScene();
    BinFillRequest request;
    request.scene_id = scene_;
    request.name = "bin";
    request.bin.inner_size = Eigen::Vector3d(0.16, 0.12, 0.08);
    request.bin.world_from_bin = Placed(0.45, 0, 0);
    request.options.seed = 3;
    BinPartRequest block;
    block.mesh_id = world_.AddMesh(test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02}), "block");
    block.name = "block";
    block.count = 6;
    request.parts.push_back(block);
    auto bin = PlanBinFill(world_.context().registry, request);
    ASSERT_TRUE(bin.ok()) << bin.status().ToString();
    const physics::FillResult fill = SimulateBinFill(*bin, nullptr, nullptr);
    ASSERT_EQ(fill.end, physics::FillEnd::kSettled) << fill.message;
    ASSERT_EQ(fill.parts.size(), 6u);
    ASSERT_TRUE(PlaceBinInScene(world_.context().registry, *bin, fill).ok());

    plan_.mount_id = world_.Mount("ur5", scene_, Placed(0, 0, 0.2));
    plan_.scene_id = scene_;
    plan_.bin = *bin;
    grasping::SuctionCup cup;
    cup.diameter_m = 0.012;
    plan_.gripper = cup;
    plan_.grasp_options.max_grasps = 300;
    plan_.body_length_m = 0.08;
    plan_.scan.camera = sensor::CameraFromFov(320, 256, 50, 0.05, 3.0);
    plan_.scan.world_from_sensor = *PoseFromLookAt({0.45, 0, 0.6}, {0.45, 0, 0}, {0, 1, 0}, "pose");
  }

  size_t PartsInScene() {
    const auto scene = world_.context().registry.catalogue().GetScene(scene_);
    EXPECT_TRUE(scene.ok());
    size_t parts = 0;
    for (const auto& object : scene->objects) parts += object.label.rfind("block#", 0) == 0;
    return parts;
  }

  testing::ServiceWorld world_;
  std::string scene_;
  PickingPlan plan_;
};

}  // namespace vscan::service
