#pragma once
// The 6x6 Gauss-Newton system of weighted point-to-plane residuals and its rigid update.

#include <optional>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::registration {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Linearised about a fixed centre c: moving source point p (relative position a = p - c) by the
// small rotation w about c and then by t changes the residual n.(p - q) by (a x n).w + n.t.
// Sums over pairs of J J^T and J r with J = (a x n, n), weighted.
class NormalEquations {
 public:
  void Add(const Eigen::Vector3d& a, const Eigen::Vector3d& n, double r, double w) {
    const Eigen::Vector3d axn = a.cross(n);
    const double j[6] = {axn.x(), axn.y(), axn.z(), n.x(), n.y(), n.z()};
    int k = 0;
    for (int row = 0; row < 6; ++row) {
      const double wj = w * j[row];
      for (int col = row; col < 6; ++col) upper_[k++] += wj * j[col];
      rhs_[row] += wj * r;
    }
  }

  void Merge(const NormalEquations& other) {
    for (int k = 0; k < 21; ++k) upper_[k] += other.upper_[k];
    for (int k = 0; k < 6; ++k) rhs_[k] += other.rhs_[k];
  }

  // The increment (w, t) minimising the linearised weighted squares, by LDLT; nullopt when the
  // system is singular or so badly conditioned that some direction is not constrained.
  std::optional<Vector6d> Solve() const;

 private:
  // Row-major upper triangle of J J^T.
  double upper_[21] = {};
  double rhs_[6] = {};
};

// The rigid motion of an increment: rotation exp([w]x) about centre (orthonormal by construction,
// not the linearised I + [w]x), then translation t.
Pose3 IncrementPose(const Vector6d& increment, const Eigen::Vector3d& centre);

// The nearest rotation to a pose's linear part, so rounding does not accumulate over updates.
void Reorthonormalise(Pose3& pose);

}  // namespace vscan::registration
