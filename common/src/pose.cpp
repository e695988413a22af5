#include "vscan/common/pose.h"

#include <cmath>
#include <string>

#include "vscan/common/physical_limits.h"

namespace vscan {
namespace {

constexpr double kRigidTolerance = 1e-5;

std::string Field(std::string_view f) { return std::string(f); }

}  // namespace

bool AllFinite(const Eigen::Vector3d& v) { return v.allFinite(); }

StatusOr<Pose3> PoseFromMatrix(const Eigen::Matrix4d& m, std::string_view field) {
  if (!m.allFinite()) return InvalidArgument(Field(field) + ": matrix has NaN or infinite values");
  if (std::abs(m(3, 0)) > kRigidTolerance || std::abs(m(3, 1)) > kRigidTolerance ||
      std::abs(m(3, 2)) > kRigidTolerance || std::abs(m(3, 3) - 1.0) > kRigidTolerance) {
    return InvalidArgument(Field(field) + ": last row must be 0 0 0 1");
  }
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const double orth_error = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orth_error > kRigidTolerance) {
    return InvalidArgument(Field(field) + ": rotation is not orthonormal (scale or shear is not a rigid pose)");
  }
  if (r.determinant() < 0) return InvalidArgument(Field(field) + ": rotation is a reflection (determinant -1)");
  RETURN_IF_ERROR(CheckPosition(m.topRightCorner<3, 1>(), Field(field) + " translation (values 3, 7, 11)"));
  Pose3 pose = Pose3::Identity();
  // Re-orthonormalise so accumulated float error does not leak into the scene.
  pose.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
  pose.translation() = m.topRightCorner<3, 1>();
  return pose;
}

StatusOr<Pose3> PoseFromQuaternion(const Eigen::Vector3d& t, const Eigen::Quaterniond& q,
                                   std::string_view field) {
  RETURN_IF_ERROR(CheckPosition(t, Field(field) + ".translation"));
  if (!q.coeffs().allFinite()) return InvalidArgument(Field(field) + ": quaternion has NaN or infinite values");
  const double norm = q.norm();
  if (std::abs(norm - 1.0) > 1e-3) {
    return InvalidArgument(Field(field) + ": quaternion must have unit length (got " + std::to_string(norm) + ")");
  }
  Pose3 pose = Pose3::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = t;
  return pose;
}

StatusOr<Pose3> PoseFromLookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                               const Eigen::Vector3d& up, std::string_view field) {
  RETURN_IF_ERROR(CheckPosition(eye, Field(field) + ".eye"));
  RETURN_IF_ERROR(CheckPosition(target, Field(field) + ".target"));
  if (!up.allFinite()) return InvalidArgument(Field(field) + ".up: NaN or infinite value");
  const Eigen::Vector3d forward = target - eye;
  if (forward.norm() < 1e-9) return InvalidArgument(Field(field) + ": eye and target coincide");
  if (up.norm() < 1e-9) return InvalidArgument(Field(field) + ".up: zero vector");
  const Eigen::Vector3d z = forward.normalized();
  const Eigen::Vector3d right = z.cross(up);
  if (right.norm() < 1e-9 * up.norm()) return InvalidArgument(Field(field) + ".up: parallel to the view direction");
  const Eigen::Vector3d x = right.normalized();
  const Eigen::Vector3d y = z.cross(x);
  Pose3 pose = Pose3::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = y;
  pose.linear().col(2) = z;
  pose.translation() = eye;
  return pose;
}

Pose3 RotationAboutLine(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double angle_rad) {
  const Eigen::Vector3d a = axis.norm() > 0 ? axis.normalized() : Eigen::Vector3d::UnitZ();
  Pose3 pose = Pose3::Identity();
  pose.translate(centre);
  pose.rotate(Eigen::AngleAxisd(angle_rad, a));
  pose.translate(-centre);
  return pose;
}

}  // namespace vscan
