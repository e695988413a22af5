#include "registration/normal_equations.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace vscan::registration {
namespace {

// Smallest pivot over largest below which a direction counts as unconstrained.
constexpr double kMinPivotRatio = 1e-12;

}  // namespace

std::optional<Vector6d> NormalEquations::Solve() const {
  Eigen::Matrix<double, 6, 6> a;
  int k = 0;
  for (int row = 0; row < 6; ++row) {
    for (int col = row; col < 6; ++col) a(row, col) = a(col, row) = upper_[k++];
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(a);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return std::nullopt;
  const Vector6d d = ldlt.vectorD();
  if (!(d.minCoeff() > kMinPivotRatio * d.maxCoeff())) return std::nullopt;
  const Vector6d b = Eigen::Map<const Vector6d>(rhs_);
  Vector6d x = ldlt.solve(-b);
  if (!x.allFinite()) return std::nullopt;
  return x;
}

Pose3 IncrementPose(const Vector6d& increment, const Eigen::Vector3d& centre) {
  const Eigen::Vector3d w = increment.head<3>();
  const double angle = w.norm();
  Pose3 pose = Pose3::Identity();
  if (angle > 0.0) pose.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  pose.translation() = centre - pose.linear() * centre + increment.tail<3>();
  return pose;
}

void Reorthonormalise(Pose3& pose) {
  pose.linear() = Eigen::Quaterniond(pose.linear()).normalized().toRotationMatrix();
}

}  // namespace vscan::registration
