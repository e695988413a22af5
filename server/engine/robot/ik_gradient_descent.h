#pragma once
// The paper's inverse kinematics: per-joint trial moves both ways, tip joint first.

#include <chrono>

#include <Eigen/Core>

#include "robot/chain.h"
#include "robot/ik_types.h"
#include "vscan/common/status.h"

namespace vscan::robot {

struct GradientDescentOptions {
  double learning_rate = 0.2;              // first step of a revolute joint, radians
  double prismatic_learning_rate = 0.02;   // first step of a prismatic joint, metres
  double step_shrink = 0.5;                // applied after a sweep in which no move helped
  double min_learning_rate = 1e-12;        // stop once the revolute step falls below this
  double orientation_weight = 0.1;         // metres of cost per radian of orientation error
  double position_tolerance = 1e-5;        // metres
  double orientation_tolerance = 1e-5;     // radians
  std::chrono::microseconds time_budget{5000};
  int max_sweeps = 1'000'000;
  bool check_reach = true;
};

// Each sweep visits the joints from the one nearest the end effector to the base; each joint
// tries a move of +step and -step (clamped to its limits) and keeps the one that lowers
// |p_goal - p|^2 + (orientation_weight * orientation error)^2, if either does. A sweep in which
// no move helps shrinks every step by step_shrink. Errors, success and failure as SolveIk.
StatusOr<IkResult> SolveIkGradientDescent(const KinematicChain& chain, const IkGoal& goal, const Eigen::VectorXd& seed,
                                          const GradientDescentOptions& options = {}, IkResult* nearest = nullptr);

}  // namespace vscan::robot
