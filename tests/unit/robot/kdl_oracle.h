#pragma once
// orocos KDL as an independent oracle for forward kinematics and Jacobians.

#include <memory>
#include <string>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace urdf {
class ModelInterface;
}

namespace vscan::robot::testing {

class KdlOracle {
 public:
  // Builds KDL's chain base -> tip with kdl_parser; aborts if KDL refuses the model.
  KdlOracle(const urdf::ModelInterface& model, const std::string& base, const std::string& tip);
  ~KdlOracle();
  KdlOracle(const KdlOracle&) = delete;
  KdlOracle& operator=(const KdlOracle&) = delete;

  int dof() const;
  Pose3 Fk(const Eigen::VectorXd& q) const;
  Eigen::Matrix<double, 6, Eigen::Dynamic> Jacobian(const Eigen::VectorXd& q) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vscan::robot::testing
