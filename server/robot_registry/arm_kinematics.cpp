#include "robot_registry/arm_kinematics.h"

#include <sstream>

#include <Eigen/Geometry>

#include "robot/encoder_noise.h"
#include "robot/forward_kinematics.h"
#include "robot/ik_gradient_descent.h"
#include "robot/ik_solver.h"
#include "robot/reach.h"

namespace vscan::robot_registry {
namespace {

robot::IkGoal InBaseFrame(const robot::IkGoal& goal, const Pose3& base_from_frame) {
  robot::IkGoal out = goal;
  out.base_from_tool = base_from_frame * goal.base_from_tool;
  out.view_direction = base_from_frame.linear() * goal.view_direction;
  return out;
}

StatusOr<robot::IkResult> RunSolver(const robot::KinematicChain& chain, const robot::IkGoal& goal,
                                    const Eigen::VectorXd& seed, const IkSettings& settings, robot::IkResult* nearest) {
  // The solvers search for the nearest configuration even beyond reach, so the answer can say
  // how close the arm gets; the time budget bounds the search.
  if (settings.solver == IkSolverKind::kGradientDescent) {
    robot::GradientDescentOptions options;
    options.position_tolerance = settings.position_tolerance;
    options.orientation_tolerance = settings.orientation_tolerance;
    options.time_budget = settings.time_budget;
    options.check_reach = false;
    return robot::SolveIkGradientDescent(chain, goal, seed, options, nearest);
  }
  robot::IkOptions options;
  options.position_tolerance = settings.position_tolerance;
  options.orientation_tolerance = settings.orientation_tolerance;
  options.time_budget = settings.time_budget;
  options.max_iterations = settings.max_iterations;
  options.check_reach = false;
  return robot::SolveIk(chain, goal, seed, options, nearest);
}

std::string DescribeNearest(const robot::KinematicChain& chain, const robot::IkGoal& base_goal,
                            const robot::IkResult& nearest, const Pose3& frame_from_tool) {
  std::ostringstream out;
  out.precision(6);
  const Eigen::Vector3d p = frame_from_tool.translation();
  const Eigen::Quaterniond q(frame_from_tool.linear());
  out << "; nearest reachable tool pose: position (" << p.x() << ", " << p.y() << ", " << p.z()
      << ") m, quaternion wxyz (" << q.w() << ", " << q.x() << ", " << q.y() << ", " << q.z() << "), joint_positions [";
  for (int i = 0; i < nearest.joint_positions.size(); ++i) out << (i ? ", " : "") << nearest.joint_positions[i];
  out << "]";
  const double distance = (base_goal.position() - robot::FirstJointOrigin(chain)).norm();
  const double reach = robot::ReachUpperBound(chain);
  if (distance > reach) {
    out << "; the goal lies " << distance << " m from the first joint, beyond the arm's reach of " << reach << " m";
  }
  return out.str();
}

}  // namespace

StatusOr<ArmState> CommandJoints(const robot::KinematicChain& chain, const Placement& placement,
                                 const Eigen::VectorXd& q, std::string_view field, std::optional<uint64_t> noise_seed) {
  RETURN_IF_ERROR(robot::ValidateJointPositions(chain, q, field));
  ArmState state;
  state.commanded = q;
  state.achieved = q;
  if (noise_seed && placement.encoder_sigma.size() > 0) {
    ASSIGN_OR_RETURN(Eigen::VectorXd noisy, robot::AddEncoderNoise(q, placement.encoder_sigma, *noise_seed));
    state.achieved = robot::ClampToLimits(chain, std::move(noisy));
  }
  ASSIGN_OR_RETURN(const Pose3 commanded, robot::ForwardKinematics(chain, state.commanded));
  ASSIGN_OR_RETURN(const Pose3 achieved, robot::ForwardKinematics(chain, state.achieved));
  state.commanded_pose = placement.frame_from_base * commanded;
  state.achieved_pose = placement.frame_from_base * achieved;
  return state;
}

StatusOr<IkAnswer> SolveInPlacement(const robot::KinematicChain& chain, const Placement& placement,
                                    const robot::IkGoal& frame_goal, const Eigen::VectorXd& seed,
                                    const IkSettings& settings) {
  const robot::IkGoal goal = InBaseFrame(frame_goal, placement.frame_from_base.inverse());
  const Eigen::VectorXd start = seed.size() == 0 ? chain.MidLimits() : seed;
  robot::IkResult nearest;
  auto solved = RunSolver(chain, goal, start, settings, &nearest);
  IkAnswer answer;
  if (solved.ok()) {
    answer.result = std::move(solved).value();
    answer.reached = true;
  } else if (solved.status().code() == StatusCode::kOutOfRange) {
    answer.result = std::move(nearest);
    answer.miss_distance = answer.result.position_error;
  } else {
    return solved.status();
  }
  answer.frame_from_tool = placement.frame_from_base * answer.result.base_from_tool;
  if (!answer.reached) {
    const Status& s = solved.status();
    const std::string nearest_pose = DescribeNearest(chain, goal, answer.result, answer.frame_from_tool);
    answer.failure = Status(s.code(), s.field(), std::string(s.text()) + nearest_pose);
  }
  return answer;
}

}  // namespace vscan::robot_registry
