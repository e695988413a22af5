#pragma once
// orocos KDL's joint-limited Newton-Raphson IK as the benchmark peer.

#include <chrono>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace urdf {
class ModelInterface;
}

namespace vscan::bench {

class KdlIk {
 public:
  // ChainIkSolverPos_NR_JL over ChainFkSolverPos_recursive and ChainIkSolverVel_pinv,
  // max_iterations per attempt and eps (KDL's per-component twist tolerance).
  KdlIk(const urdf::ModelInterface& model, const std::string& base, const std::string& tip, int max_iterations,
        double eps);
  ~KdlIk();

  // One NR_JL attempt from seed; true when KDL reports convergence.
  bool Solve(const Pose3& target, const Eigen::VectorXd& seed, Eigen::VectorXd* q);
  // NR_JL from seed, then from uniform random seeds within the limits until KDL reports
  // convergence or budget elapses (how TRAC-IK runs KDL as its baseline).
  bool SolveWithRestarts(const Pose3& target, const Eigen::VectorXd& seed, std::chrono::microseconds budget,
                         Eigen::VectorXd* q);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vscan::bench
