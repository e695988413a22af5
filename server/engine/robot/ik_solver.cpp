#include "robot/ik_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "robot/ik_common.h"
#include "robot/kinematics_kernel.h"
#include "random/seeded_draws.h"

namespace vscan::robot {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Damping = kErrorWeight * (half the squared error) + kDampingBias (Sugihara's rule).
constexpr double kErrorWeight = 1.0;
constexpr double kDampingBias = 1e-7;
// An attempt restarts when its best cost has not dropped by kProgress over kStallIterations.
constexpr double kProgress = 0.99;
constexpr int kStallIterations = 5;
constexpr int kAttemptIterations = 100;
constexpr int kClockStride = 4;

class LevenbergMarquardt {
 public:
  LevenbergMarquardt(const KinematicChain& chain, const IkGoal& goal, const IkOptions& options)
      : chain_(chain), goal_(goal), options_(options), rng_(options.random_seed) {}

  // Runs until within tolerance (true) or out of time or iterations (false); q ends at the answer
  // or at the lowest-error configuration visited.
  bool Run(JointBuffer& q, IkClock::time_point start) {
    const IkClock::time_point deadline = start + options_.time_budget;
    JointBuffer best_q = q;
    double best_cost = std::numeric_limits<double>::infinity();
    double attempt_best = best_cost;
    int stalled = 0;
    int attempt_iterations = 0;
    for (iterations_ = 0; iterations_ < options_.max_iterations; ++iterations_) {
      const Pose3 T = ToolPoseAndJacobian(chain_, q.data(), &J_);
      const Vector6d e = ErrorAndProjectedJacobian(T);
      if (e.head<3>().norm() <= options_.position_tolerance && e.tail<3>().norm() <= options_.orientation_tolerance) {
        return true;
      }
      const double cost = e.squaredNorm();
      if (cost < best_cost) {
        best_cost = cost;
        best_q = q;
      }
      if (iterations_ % kClockStride == 0 && IkClock::now() >= deadline) break;
      if (cost < attempt_best * kProgress) {
        attempt_best = cost;
        stalled = 0;
      } else {
        ++stalled;
      }
      if (stalled >= kStallIterations || attempt_iterations >= kAttemptIterations) {
        Randomize(q);
        ++restarts_;
        attempt_best = std::numeric_limits<double>::infinity();
        stalled = attempt_iterations = 0;
        continue;
      }
      ++attempt_iterations;
      Step(e, kErrorWeight * 0.5 * cost + kDampingBias, q);
      EnforceLimits(q);
    }
    q = best_q;
    return false;
  }

  int iterations() const { return iterations_; }
  int restarts() const { return restarts_; }

 private:
  // q += J^T (J J^T + damping I)^-1 e. A joint resting on a limit that the step pushes further is
  // locked (its column zeroed) and the step solved again, so the other joints take up its share.
  void Step(const Vector6d& e, double damping, JointBuffer& q) {
    JointBuffer dq(q.size());
    for (int pass = 0; pass < 2; ++pass) {
      Matrix6d A;
      A.noalias() = J_.lazyProduct(J_.transpose());
      A.diagonal().array() += damping;
      dq.noalias() = J_.transpose() * A.llt().solve(e);
      bool locked = false;
      for (int i = 0; i < q.size(); ++i) {
        const ChainJoint& j = chain_.joints()[i];
        if ((q[i] <= j.lower && dq[i] < 0) || (q[i] >= j.upper && dq[i] > 0)) {
          J_.col(i).setZero();
          locked = true;
        }
      }
      if (!locked) break;
    }
    q += dq;
  }

  // Twist error towards the goal; for reduced goals, zeroes what the goal leaves free in J_.
  Vector6d ErrorAndProjectedJacobian(const Pose3& T) {
    Vector6d e;
    e.head<3>() = goal_.base_from_tool.translation() - T.translation();
    switch (goal_.kind) {
      case IkGoalKind::kPose: {
        Eigen::Quaterniond q_err(goal_.base_from_tool.linear() * T.linear().transpose());
        if (q_err.w() < 0) q_err.coeffs() = -q_err.coeffs();
        const double n = q_err.vec().norm();
        e.tail<3>() = n > 1e-300 ? Eigen::Vector3d(q_err.vec() * (2.0 * std::atan2(n, q_err.w()) / n))
                                 : Eigen::Vector3d(2.0 * q_err.vec());
        break;
      }
      case IkGoalKind::kLookAt: {
        const Eigen::Vector3d z = T.linear().col(2);
        const Eigen::Vector3d c = z.cross(goal_.view_direction);
        const double s = c.norm();
        const double angle = std::atan2(s, z.dot(goal_.view_direction));
        if (s > 1e-12) {
          e.tail<3>() = c * (angle / s);
        } else {  // aligned, or exactly opposite: turn about any axis normal to z
          e.tail<3>() = z.unitOrthogonal() * angle;
        }
        const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - z * z.transpose();
        J_.bottomRows<3>() = P * J_.bottomRows<3>();
        break;
      }
      case IkGoalKind::kPosition:
        e.tail<3>().setZero();
        J_.bottomRows<3>().setZero();
        break;
    }
    return e;
  }

  void EnforceLimits(JointBuffer& q) const {
    for (int i = 0; i < q.size(); ++i) {
      const ChainJoint& j = chain_.joints()[i];
      if (q[i] >= j.lower && q[i] <= j.upper) continue;
      if (j.type == JointType::kRevolute && j.upper - j.lower >= kTwoPi) {
        const double wrapped = j.lower + std::fmod(std::fmod(q[i] - j.lower, kTwoPi) + kTwoPi, kTwoPi);
        if (wrapped <= j.upper) {
          q[i] = wrapped;
          continue;
        }
      }
      q[i] = std::clamp(q[i], j.lower, j.upper);
    }
  }

  void Randomize(JointBuffer& q) {
    for (int i = 0; i < q.size(); ++i) {
      const ChainJoint& j = chain_.joints()[i];
      q[i] = j.sample_lower + (j.sample_upper - j.sample_lower) * rng_.Uniform();
    }
  }

  const KinematicChain& chain_;
  const IkGoal& goal_;
  const IkOptions& options_;
  random::SplitMix64Stream rng_;  // deterministic and cheap; restarts need no more
  JacobianBuffer J_;
  int iterations_ = 0;
  int restarts_ = 0;
};

}  // namespace

StatusOr<IkResult> SolveIk(const KinematicChain& chain, const IkGoal& goal, const Eigen::VectorXd& seed,
                           const IkOptions& options, IkResult* nearest) {
  const IkClock::time_point start = IkClock::now();
  ASSIGN_OR_RETURN(const Eigen::VectorXd clamped, PrepareIkInputs(chain, goal, seed, options.check_reach, start, nearest));
  JointBuffer q = clamped;
  LevenbergMarquardt solver(chain, goal, options);
  solver.Run(q, start);
  IkResult result = MakeIkResult(chain, goal, q.data(), solver.iterations(), solver.restarts(), start);
  if (WithinTolerance(result, options.position_tolerance, options.orientation_tolerance)) return result;
  return NotReached(result, "the IK solver", nearest);
}

}  // namespace vscan::robot
