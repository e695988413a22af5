#include "robot/ik_common.h"

#include <cmath>
#include <numbers>
#include <sstream>

#include "robot/kinematics_kernel.h"
#include "robot/reach.h"

namespace vscan::robot {
namespace {

double WrapAngle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

}  // namespace

StatusOr<Eigen::VectorXd> PrepareIkInputs(const KinematicChain& chain, const IkGoal& goal, const Eigen::VectorXd& seed,
                                          bool check_reach, IkClock::time_point start, IkResult* nearest) {
  RETURN_IF_ERROR(ValidateIkGoal(goal));
  if (seed.size() != chain.dof()) {
    return InvalidArgument("seed: expected " + std::to_string(chain.dof()) + " joint positions, got " +
                           std::to_string(seed.size()));
  }
  if (!seed.allFinite()) return InvalidArgument("seed: NaN or infinite value");
  // A seed read from noisy encoders may sit a hair outside the limits; that is not an error.
  Eigen::VectorXd q = ClampToLimits(chain, seed);
  if (check_reach) {
    Status reach = CheckWithinReach(chain, goal.position(), "goal.position");
    if (!reach.ok()) {
      if (nearest != nullptr) *nearest = MakeIkResult(chain, goal, q.data(), 0, 0, start);
      return reach;
    }
  }
  return q;
}

IkResult MakeIkResult(const KinematicChain& chain, const IkGoal& goal, const double* q, int iterations, int restarts,
                      IkClock::time_point start) {
  IkResult result;
  result.joint_positions = Eigen::Map<const Eigen::VectorXd>(q, chain.dof());
  for (int i = 0; i < chain.dof(); ++i) {
    if (chain.joints()[i].type == JointType::kContinuous) result.joint_positions[i] = WrapAngle(result.joint_positions[i]);
  }
  result.base_from_tool = ToolPose(chain, result.joint_positions.data());
  const GoalErrors errors = MeasureGoalErrors(goal, result.base_from_tool);
  result.position_error = errors.position;
  result.orientation_error = errors.orientation;
  result.iterations = iterations;
  result.restarts = restarts;
  result.elapsed_seconds = std::chrono::duration<double>(IkClock::now() - start).count();
  return result;
}

bool WithinTolerance(const IkResult& result, double position_tolerance, double orientation_tolerance) {
  return result.position_error <= position_tolerance && result.orientation_error <= orientation_tolerance;
}

Status NotReached(const IkResult& best, const char* solver, IkResult* nearest) {
  std::ostringstream out;
  out << solver << " did not reach the goal within tolerance (" << best.iterations << " iterations, "
      << best.restarts << " restarts, " << best.elapsed_seconds * 1e3 << " ms); the nearest pose misses by "
      << best.position_error << " m and " << best.orientation_error << " rad";
  if (nearest != nullptr) *nearest = best;
  return OutOfRange("goal", out.str());
}

}  // namespace vscan::robot
