#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "grasping/grasp_generation.h"
#include "grasping/gripper.h"
#include "vscan_test/meshes.h"

namespace vscan::grasping {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

void ExpectRefused(const Gripper& gripper, const std::string& field) {
  const Status s = ValidateGripper(gripper);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << field;
  EXPECT_EQ(s.field(), field);
  // Generation refuses it the same way and produces nothing.
  const auto grasps = GenerateGrasps(test::MakeBox({0, 0, 0}, {0.04, 0.03, 0.02}), gripper, {});
  ASSERT_FALSE(grasps.ok());
  EXPECT_EQ(grasps.status().field(), field);
}

TEST(GripperTest, DefaultsAreValid) {
  EXPECT_TRUE(ValidateGripper(SuctionCup{}).ok());
  EXPECT_TRUE(ValidateGripper(ParallelJaws{}).ok());
}

TEST(GripperTest, BadSuctionValuesNameTheField) {
  for (const double bad : {kNan, 0.0, -0.01, 1e19, std::numeric_limits<double>::infinity()}) {
    SuctionCup cup;
    cup.diameter_m = bad;
    ExpectRefused(cup, "gripper.suction.diameter_m");
    cup = {};
    cup.stroke_m = bad;
    ExpectRefused(cup, "gripper.suction.stroke_m");
    cup = {};
    cup.max_tilt_deg = bad;
    ExpectRefused(cup, "gripper.suction.max_tilt_deg");
    cup = {};
    cup.min_flat_fraction = bad;
    ExpectRefused(cup, "gripper.suction.min_flat_fraction");
  }
  SuctionCup cup;
  cup.max_tilt_deg = 90;
  ExpectRefused(cup, "gripper.suction.max_tilt_deg");
  cup = {};
  cup.min_flat_fraction = 1.5;
  ExpectRefused(cup, "gripper.suction.min_flat_fraction");
}

TEST(GripperTest, BadJawValuesNameTheField) {
  for (const double bad : {kNan, 0.0, -1.0, 1e19, 2.5}) {
    ParallelJaws jaws;
    jaws.min_opening_m = bad;
    ExpectRefused(jaws, "gripper.jaws.min_opening_m");
    jaws = {};
    jaws.max_opening_m = bad;
    ExpectRefused(jaws, "gripper.jaws.max_opening_m");
    jaws = {};
    jaws.finger_width_m = bad;
    ExpectRefused(jaws, "gripper.jaws.finger_width_m");
    jaws = {};
    jaws.finger_depth_m = bad;
    ExpectRefused(jaws, "gripper.jaws.finger_depth_m");
    jaws = {};
    jaws.finger_length_m = bad;
    ExpectRefused(jaws, "gripper.jaws.finger_length_m");
    jaws = {};
    jaws.finger_thickness_m = bad;
    ExpectRefused(jaws, "gripper.jaws.finger_thickness_m");
  }
  ParallelJaws jaws;
  jaws.min_opening_m = 0.06;
  jaws.max_opening_m = 0.05;
  ExpectRefused(jaws, "gripper.jaws.max_opening_m");
  for (const double bad : {kNan, 0.0, 90.0, 1e19}) {
    jaws = {};
    jaws.max_friction_angle_deg = bad;
    ExpectRefused(jaws, "gripper.jaws.max_friction_angle_deg");
  }
}

TEST(GripperTest, BadOptionsAndMeshesNameTheField) {
  const TriangleMesh box = test::MakeBox({0, 0, 0}, {0.04, 0.03, 0.02});
  GraspOptions options;
  options.max_grasps = 0;
  EXPECT_EQ(GenerateGrasps(box, SuctionCup{}, options).status().field(), "grasp_options.max_grasps");
  options = {};
  options.surface_samples = size_t{1} << 40;
  EXPECT_EQ(GenerateGrasps(box, SuctionCup{}, options).status().field(), "grasp_options.surface_samples");
  options = {};
  options.candidates = 0;
  EXPECT_EQ(GenerateGrasps(box, SuctionCup{}, options).status().field(), "grasp_options.candidates");
  options = {};
  options.approaches_per_pair = 1000;
  EXPECT_EQ(GenerateGrasps(box, ParallelJaws{}, options).status().field(), "grasp_options.approaches_per_pair");
  options = {};
  options.flatness_tolerance_m = kNan;
  EXPECT_EQ(GenerateGrasps(box, SuctionCup{}, options).status().field(), "grasp_options.flatness_tolerance_m");

  // Within each range but too much work together: refused before any is done.
  options = {};
  options.candidates = 100000;
  options.surface_samples = 2000000;
  const auto too_much = GenerateGrasps(box, SuctionCup{}, options);
  EXPECT_EQ(too_much.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(too_much.status().field(), "grasp_options.candidates");
  EXPECT_EQ(GenerateGrasps(box, ParallelJaws{}, options).status().code(), StatusCode::kResourceExhausted);

  EXPECT_EQ(GenerateGrasps(TriangleMesh{}, SuctionCup{}, {}).status().field(), "mesh");
  TriangleMesh broken = box;
  broken.triangles.push_back({0, 1, 999});
  EXPECT_EQ(GenerateGrasps(broken, SuctionCup{}, {}).status().field(), "mesh");
  broken = box;
  broken.vertices[0].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(GenerateGrasps(broken, ParallelJaws{}, {}).status().field(), "mesh");
  broken = box;
  broken.vertices[0].x() = 1e19f;
  EXPECT_EQ(GenerateGrasps(broken, ParallelJaws{}, {}).status().field(), "mesh");
  TriangleMesh flat;  // all triangles degenerate: no area to sample
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  EXPECT_EQ(GenerateGrasps(flat, SuctionCup{}, {}).status().field(), "mesh");
}

}  // namespace
}  // namespace vscan::grasping
