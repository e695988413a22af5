#include "part_shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace vscan::localization::testing {

std::vector<Eigen::Vector3f> CubeWithFaceCentres(double half) {
  const auto h = static_cast<float>(half);
  std::vector<Eigen::Vector3f> vertices;
  for (const float x : {-h, h}) {
    for (const float y : {-h, h}) {
      for (const float z : {-h, h}) vertices.emplace_back(x, y, z);
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (const float s : {-h, h}) {
      Eigen::Vector3f c = Eigen::Vector3f::Zero();
      c[axis] = s;
      vertices.push_back(c);
    }
  }
  return vertices;
}

std::vector<Pose3> CubeRotations() {
  // Signed permutation matrices with determinant +1.
  std::vector<Pose3> rotations;
  std::array<int, 3> perm{0, 1, 2};
  do {
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
      for (int row = 0; row < 3; ++row) r(row, perm[row]) = ((signs >> row) & 1) != 0 ? -1 : 1;
      if (r.determinant() < 0) continue;
      Pose3 pose = Pose3::Identity();
      pose.linear() = r;
      rotations.push_back(pose);
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  return rotations;
}

std::vector<Eigen::Vector3f> Rings(double radius, int count, const std::vector<double>& heights) {
  std::vector<Eigen::Vector3f> vertices;
  for (const double z : heights) {
    for (int i = 0; i < count; ++i) {
      const double a = 2 * std::numbers::pi * i / count;
      vertices.emplace_back(Eigen::Vector3d(radius * std::cos(a), radius * std::sin(a), z).cast<float>());
    }
  }
  return vertices;
}

}  // namespace vscan::localization::testing
