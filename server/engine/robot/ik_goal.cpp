#include <cmath>

#include <Eigen/Geometry>

#include "robot/ik_types.h"

namespace vscan::robot {
namespace {

constexpr double kRigidTolerance = 1e-6;

// Angle between two unit vectors, accurate for tiny angles too.
double AngleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

IkGoal PoseGoal(const Pose3& base_from_tool) { return IkGoal{IkGoalKind::kPose, base_from_tool, Eigen::Vector3d::UnitZ()}; }

IkGoal PositionGoal(const Eigen::Vector3d& base_position) {
  IkGoal goal{IkGoalKind::kPosition, Pose3::Identity(), Eigen::Vector3d::UnitZ()};
  goal.base_from_tool.translation() = base_position;
  return goal;
}

StatusOr<IkGoal> LookAtGoal(const Eigen::Vector3d& sensor_position, const Eigen::Vector3d& target,
                            std::string_view field) {
  const std::string f(field);
  if (!sensor_position.allFinite()) return InvalidArgument(f + ".sensor_position: NaN or infinite value");
  if (!target.allFinite()) return InvalidArgument(f + ".target: NaN or infinite value");
  const Eigen::Vector3d view = target - sensor_position;
  if (view.norm() < 1e-9) return InvalidArgument(f + ": sensor_position and target coincide");
  IkGoal goal{IkGoalKind::kLookAt, Pose3::Identity(), view.normalized()};
  goal.base_from_tool.translation() = sensor_position;
  return goal;
}

Status ValidateIkGoal(const IkGoal& goal, std::string_view field) {
  const std::string f(field);
  if (!goal.base_from_tool.matrix().allFinite()) return InvalidArgument(f + ".pose: NaN or infinite value");
  if (goal.kind == IkGoalKind::kPose) {
    const Eigen::Matrix3d R = goal.base_from_tool.linear();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kRigidTolerance ||
        R.determinant() < 0) {
      return InvalidArgument(f + ".pose: rotation is not a proper orthonormal matrix");
    }
  }
  if (goal.kind == IkGoalKind::kLookAt) {
    if (!goal.view_direction.allFinite() || std::abs(goal.view_direction.norm() - 1.0) > kRigidTolerance) {
      return InvalidArgument(f + ".view_direction: must be a finite unit vector");
    }
  }
  return Status::Ok();
}

GoalErrors MeasureGoalErrors(const IkGoal& goal, const Pose3& base_from_tool) {
  GoalErrors errors;
  errors.position = (goal.base_from_tool.translation() - base_from_tool.translation()).norm();
  switch (goal.kind) {
    case IkGoalKind::kPose: {
      const Eigen::Quaterniond q(goal.base_from_tool.linear().transpose() * base_from_tool.linear());
      errors.orientation = 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
      break;
    }
    case IkGoalKind::kLookAt: errors.orientation = AngleBetween(base_from_tool.linear().col(2), goal.view_direction); break;
    case IkGoalKind::kPosition: break;
  }
  return errors;
}

}  // namespace vscan::robot
