#pragma once
// Pose errors and pose construction shared by the registration tests.

#include <numbers>

#include <Eigen/Geometry>

#include "vscan/common/pose.h"

namespace vscan::registration::testing {

constexpr double kDeg = std::numbers::pi / 180.0;

inline double RotationErrorDeg(const Pose3& a, const Pose3& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() / kDeg;
}

inline double TranslationErrorMm(const Pose3& a, const Pose3& b) {
  return (a.translation() - b.translation()).norm() * 1000.0;
}

inline Pose3 Motion(double angle_deg, const Eigen::Vector3d& axis, const Eigen::Vector3d& translation) {
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::AngleAxisd(angle_deg * kDeg, axis.normalized()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

}  // namespace vscan::registration::testing
