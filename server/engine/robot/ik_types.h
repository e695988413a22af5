#pragma once
// Goals, options and results shared by the inverse-kinematics solvers.

#include <chrono>
#include <cstdint>
#include <string_view>

#include <Eigen/Core>

#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::robot {

enum class IkGoalKind {
  kPose,      // position and orientation of the tool
  kPosition,  // position only
  kLookAt,    // position and the direction of tool z; rotation about tool z is free
};

struct IkGoal {
  IkGoalKind kind = IkGoalKind::kPose;
  Pose3 base_from_tool = Pose3::Identity();  // kPosition and kLookAt use the translation only
  Eigen::Vector3d view_direction = Eigen::Vector3d::UnitZ();  // kLookAt: unit, base frame

  const Eigen::Vector3d position() const { return base_from_tool.translation(); }
};

IkGoal PoseGoal(const Pose3& base_from_tool);
IkGoal PositionGoal(const Eigen::Vector3d& base_position);
// "Stand here and look at that point": the tool at sensor_position with tool z towards target.
StatusOr<IkGoal> LookAtGoal(const Eigen::Vector3d& sensor_position, const Eigen::Vector3d& target,
                            std::string_view field = "goal");

// InvalidArgument "<field>...: ..." for non-finite values, a non-rigid pose or a zero direction.
Status ValidateIkGoal(const IkGoal& goal, std::string_view field = "goal");

// What the solvers call "within tolerance".
struct GoalErrors {
  double position = 0.0;     // |p_goal - p_tool|, metres
  double orientation = 0.0;  // radians: kPose, angle of R_goal^T R_tool; kLookAt, angle between
                             // tool z and view_direction; kPosition, 0
};
GoalErrors MeasureGoalErrors(const IkGoal& goal, const Pose3& base_from_tool);

struct IkResult {
  Eigen::VectorXd joint_positions;  // within limits; continuous joints wrapped into [-pi, pi]
  Pose3 base_from_tool = Pose3::Identity();  // the pose joint_positions achieve
  double position_error = 0.0;
  double orientation_error = 0.0;
  int iterations = 0;
  int restarts = 0;
  double elapsed_seconds = 0.0;
};

// Production solver settings (ik_solver.h).
struct IkOptions {
  double position_tolerance = 1e-5;     // metres
  double orientation_tolerance = 1e-5;  // radians
  std::chrono::microseconds time_budget{5000};
  int max_iterations = 1'000'000;  // over all restarts; the time budget normally ends first
  uint64_t random_seed = 1;        // drives the restart configurations
  bool check_reach = true;         // refuse positions beyond ReachUpperBound before solving
};

}  // namespace vscan::robot
