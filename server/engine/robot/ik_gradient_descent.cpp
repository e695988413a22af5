#include "robot/ik_gradient_descent.h"

#include <algorithm>
#include <array>

#include "robot/ik_common.h"
#include "robot/kinematics_kernel.h"

namespace vscan::robot {
namespace {

struct Evaluation {
  double cost = 0.0;
  GoalErrors errors;
};

class CoordinateDescent {
 public:
  CoordinateDescent(const KinematicChain& chain, const IkGoal& goal, const GradientDescentOptions& options)
      : chain_(chain), joints_(chain.joints()), goal_(goal), options_(options) {}

  // Returns true when within tolerance; q holds the final configuration either way.
  bool Run(JointBuffer& q, IkClock::time_point start) {
    const IkClock::time_point deadline = start + options_.time_budget;
    const int n = chain_.dof();
    Evaluation current = Evaluate(ToolPose(chain_, q.data()));
    double scale = 1.0;
    for (sweeps_ = 0; sweeps_ < options_.max_sweeps; ++sweeps_) {
      if (Converged(current)) return true;
      if (options_.learning_rate * scale < options_.min_learning_rate || IkClock::now() >= deadline) break;
      ComputePrefixes(q);
      Pose3 T_joint_tool = chain_.last_joint_from_tool();  // from joint j's moved frame to the tool
      bool improved = false;
      for (int j = n - 1; j >= 0; --j) {
        const double step = scale * (joints_[j].type == JointType::kPrismatic ? options_.prismatic_learning_rate
                                                                              : options_.learning_rate);
        const double from = q[j];
        for (const double direction : {1.0, -1.0}) {
          const double trial = std::clamp(from + direction * step, joints_[j].lower, joints_[j].upper);
          if (trial == from) continue;
          const Evaluation e = Evaluate(PoseWithJointAt(j, trial, T_joint_tool));
          if (e.cost < current.cost) {  // keeps the better direction, if any beats staying put
            current = e;
            q[j] = trial;
            improved = true;
          }
        }
        Pose3 motion = Pose3::Identity();
        ApplyJointMotion(joints_[j], q[j], motion);
        T_joint_tool = joints_[j].T_prev_joint * (motion * T_joint_tool);
      }
      if (!improved) scale *= options_.step_shrink;
    }
    return Converged(current);
  }

  int sweeps() const { return sweeps_; }

 private:
  // prefix_[j]: base to joint j's frame before it moves; valid for joints below the one being tried.
  void ComputePrefixes(const JointBuffer& q) {
    Pose3 T = Pose3::Identity();
    for (int j = 0; j < chain_.dof(); ++j) {
      T = T * joints_[j].T_prev_joint;
      prefix_[j] = T;
      ApplyJointMotion(joints_[j], q[j], T);
    }
  }

  Pose3 PoseWithJointAt(int j, double value, const Pose3& T_joint_tool) const {
    Pose3 T = prefix_[j];
    ApplyJointMotion(joints_[j], value, T);
    return T * T_joint_tool;
  }

  Evaluation Evaluate(const Pose3& T) const {
    Evaluation e;
    e.errors = MeasureGoalErrors(goal_, T);
    const double weighted = options_.orientation_weight * e.errors.orientation;
    e.cost = e.errors.position * e.errors.position + weighted * weighted;
    return e;
  }

  bool Converged(const Evaluation& e) const {
    return e.errors.position <= options_.position_tolerance && e.errors.orientation <= options_.orientation_tolerance;
  }

  const KinematicChain& chain_;
  const std::vector<ChainJoint>& joints_;
  const IkGoal& goal_;
  const GradientDescentOptions& options_;
  std::array<Pose3, kMaxChainJoints> prefix_;
  int sweeps_ = 0;
};

}  // namespace

StatusOr<IkResult> SolveIkGradientDescent(const KinematicChain& chain, const IkGoal& goal, const Eigen::VectorXd& seed,
                                          const GradientDescentOptions& options, IkResult* nearest) {
  const IkClock::time_point start = IkClock::now();
  ASSIGN_OR_RETURN(const Eigen::VectorXd clamped, PrepareIkInputs(chain, goal, seed, options.check_reach, start, nearest));
  JointBuffer q = clamped;
  CoordinateDescent descent(chain, goal, options);
  descent.Run(q, start);
  IkResult result = MakeIkResult(chain, goal, q.data(), descent.sweeps(), 0, start);
  if (WithinTolerance(result, options.position_tolerance, options.orientation_tolerance)) return result;
  return NotReached(result, "gradient descent", nearest);
}

}  // namespace vscan::robot
