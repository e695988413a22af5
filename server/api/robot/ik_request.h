#pragma once
// RobotService.InverseKinematics' request checks: the goal and the solver settings it asks for,
// before any robot is looked up.

#include "robot/ik_types.h"
#include "robot_registry/arm_kinematics.h"
#include "vscan/common/status.h"
#include "vscan/v1/robot.pb.h"

namespace vscan::api {

// Bounds of the settings a request may ask for.
inline constexpr double kMaxIkTimeoutMs = 5000.0;
inline constexpr double kMaxIkPositionTolerance = 1.0;  // metres

struct IkRequestPlan {
  robot::IkGoal goal;
  robot_registry::IkSettings settings;
};

// INVALID_ARGUMENT naming the field: no goal, a goal with a missing or non-finite part or beyond
// the physical bounds, an unknown method, a tolerance or timeout outside its range.
StatusOr<IkRequestPlan> ParseInverseKinematicsRequest(const v1::InverseKinematicsRequest& request);

}  // namespace vscan::api
