#pragma once
// A dataset plan's picks section (docs/DATASETS.md, "Picks"): a robot standing beside each bin with
// a gripper on its flange, and the grasp and pick options every scene's parts are checked with.

#include <cstddef>
#include <optional>
#include <string>

#include "grasping/grasp_generation.h"
#include "grasping/gripper.h"
#include "grasping/pick_checks.h"
#include "vscan/common/pose.h"

namespace vscan::service::dataset {

struct DatasetPicks {
  std::string robot_id;                      // a stored robot, resolved when a job starts
  Pose3 world_from_base = Pose3::Identity();  // the dataset's world: the bin's frame
  std::optional<Pose3> flange_from_tool;     // unset: the robot's own tool
  grasping::Gripper gripper;
  grasping::GraspOptions grasp_options;
  grasping::PickOptions pick_options;        // pick_options.sweep.body_length_m 0: the tool's distance
  // Iterations of each inverse-kinematics solve: a count, not a time, so that verdicts are the
  // same on every run and machine.
  size_t ik_iterations = 2000;
};

// Iterations per solve, and the most solves x iterations one scene's picks may cost
// (parts x max_reach_checks x 2 solves x ik_iterations).
inline constexpr size_t kMinIkIterations = 10;
inline constexpr size_t kMaxIkIterations = 100'000;
inline constexpr double kMaxIkIterationsPerScene = 1e8;

// "suction" or "jaws".
const char* GripperKind(const grasping::Gripper& gripper);

}  // namespace vscan::service::dataset
