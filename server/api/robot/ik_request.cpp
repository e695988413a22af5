#include "api/robot/ik_request.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "api/transport/validate.h"
#include "vscan/common/physical_limits.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr double kDefaultTolerance = 1e-5;
constexpr double kDefaultTimeoutMs = 50.0;

StatusOr<robot::IkGoal> GoalFromRequest(const v1::InverseKinematicsRequest& request) {
  switch (request.goal_case()) {
    case v1::InverseKinematicsRequest::kToolPose: {
      ASSIGN_OR_RETURN(const Pose3 pose, PoseFromProto(request.tool_pose(), "tool_pose"));
      return robot::PoseGoal(pose);
    }
    case v1::InverseKinematicsRequest::kLookFrom: {
      const auto& look = request.look_from();
      if (!look.has_position()) return InvalidArgument("look_from.position: required");
      if (!look.has_target()) return InvalidArgument("look_from.target: required");
      const Eigen::Vector3d position = FromProto(look.position());
      const Eigen::Vector3d target = FromProto(look.target());
      RETURN_IF_ERROR(CheckPosition(position, "look_from.position"));
      RETURN_IF_ERROR(CheckPosition(target, "look_from.target"));
      return robot::LookAtGoal(position, target, "look_from");
    }
    case v1::InverseKinematicsRequest::kToolPosition: {
      const Eigen::Vector3d position = FromProto(request.tool_position());
      RETURN_IF_ERROR(CheckPosition(position, "tool_position"));
      return robot::PositionGoal(position);
    }
    case v1::InverseKinematicsRequest::GOAL_NOT_SET: break;
  }
  return InvalidArgument("tool_pose: required (or look_from, or tool_position)");
}

StatusOr<double> PositiveOrDefault(double value, double fallback, double max, const char* field, const char* unit) {
  if (value == 0.0) return fallback;
  if (!std::isfinite(value) || value < 0 || value > max) {
    char bound[32];
    std::snprintf(bound, sizeof(bound), "%g", max);
    return InvalidArgument(std::string(field) + ": must be a finite number in (0, " + bound + "] " + unit +
                           " (0 means the default)");
  }
  return value;
}

StatusOr<robot_registry::IkSettings> SettingsFromRequest(const v1::InverseKinematicsRequest& request) {
  robot_registry::IkSettings settings;
  switch (request.method()) {
    case v1::IK_METHOD_UNSPECIFIED:
    case v1::IK_METHOD_DEFAULT: settings.solver = robot_registry::IkSolverKind::kDefault; break;
    case v1::IK_METHOD_GRADIENT_DESCENT: settings.solver = robot_registry::IkSolverKind::kGradientDescent; break;
    default: return InvalidArgument("method: unknown value " + std::to_string(request.method()));
  }
  ASSIGN_OR_RETURN(settings.position_tolerance,
                   PositiveOrDefault(request.tolerance(), kDefaultTolerance, kMaxIkPositionTolerance, "tolerance", "m"));
  ASSIGN_OR_RETURN(settings.orientation_tolerance,
                   PositiveOrDefault(request.orientation_tolerance_rad(), kDefaultTolerance, std::numbers::pi,
                                     "orientation_tolerance_rad", "rad"));
  ASSIGN_OR_RETURN(const double timeout_ms,
                   PositiveOrDefault(request.timeout_ms(), kDefaultTimeoutMs, kMaxIkTimeoutMs, "timeout_ms", "ms"));
  settings.time_budget = std::chrono::microseconds(static_cast<int64_t>(timeout_ms * 1000.0));
  return settings;
}

}  // namespace

StatusOr<IkRequestPlan> ParseInverseKinematicsRequest(const v1::InverseKinematicsRequest& request) {
  IkRequestPlan plan;
  ASSIGN_OR_RETURN(plan.goal, GoalFromRequest(request));
  ASSIGN_OR_RETURN(plan.settings, SettingsFromRequest(request));
  return plan;
}

}  // namespace vscan::api
