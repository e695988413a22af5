#pragma once
// Kinematics of a placed robot: forward and inverse kinematics in the frame the robot stands in
// (its own base frame, or the world for a mount), with optional encoder noise.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "robot/chain.h"
#include "robot/ik_types.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::robot_registry {

// Where a chain stands and how exact its encoders are.
struct Placement {
  Pose3 frame_from_base = Pose3::Identity();  // world_from_base for a mount
  Eigen::VectorXd encoder_sigma;              // empty or one per joint
};

// The joints a caller commands and where the arm lands; poses of the tool in the placement frame.
struct ArmState {
  Eigen::VectorXd commanded;
  Eigen::VectorXd achieved;  // commanded plus encoder noise, clamped into the limits
  Pose3 commanded_pose = Pose3::Identity();
  Pose3 achieved_pose = Pose3::Identity();
};

// Checks q (errors name field, OUT_OF_RANGE beyond a limit) and evaluates both poses. With a
// noise seed, achieved = commanded + N(0, sigma); without one, achieved = commanded.
StatusOr<ArmState> CommandJoints(const robot::KinematicChain& chain, const Placement& placement,
                                 const Eigen::VectorXd& q, std::string_view field,
                                 std::optional<uint64_t> noise_seed = std::nullopt);

enum class IkSolverKind { kDefault, kGradientDescent };

struct IkSettings {
  IkSolverKind solver = IkSolverKind::kDefault;
  double position_tolerance = 1e-5;
  double orientation_tolerance = 1e-5;
  std::chrono::microseconds time_budget{50000};
  // The default solver's iterations over all its restarts; with a time budget that never ends
  // first, answers depend on the goal and seed alone.
  int max_iterations = 1'000'000;
};

struct IkAnswer {
  robot::IkResult result;  // base frame, as the solver reports it
  Pose3 frame_from_tool = Pose3::Identity();
  bool reached = false;
  double miss_distance = 0.0;  // metres; 0 when reached
  Status failure;              // when not reached: the OUT_OF_RANGE status, naming the goal
};

// Solves for a goal given in the placement frame. Unreachable goals are not errors here: the
// answer carries the nearest configuration found and a message naming the miss and that pose.
// INVALID_ARGUMENT for a bad goal or seed (an empty seed means the middle of the limits).
StatusOr<IkAnswer> SolveInPlacement(const robot::KinematicChain& chain, const Placement& placement,
                                    const robot::IkGoal& frame_goal, const Eigen::VectorXd& seed,
                                    const IkSettings& settings);

}  // namespace vscan::robot_registry
