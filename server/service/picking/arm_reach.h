#pragma once
// A mounted arm as the reach test of a pick: inverse kinematics to the grasp and to the
// pre-grasp (a cup's rotation about its axis left free), then the arm checked against the scene at
// both configurations.

#include <chrono>
#include <memory>

#include "grasping/pick_checks.h"
#include "robot_registry/robot_registry.h"
#include "service/context/service_context.h"

namespace vscan::service {

// The callback may be called from several threads at once; it keeps mounted alive.
grasping::ReachCheck ArmReach(ServiceContext& context, std::shared_ptr<const robot_registry::MountedRobot> mounted,
                              const grasping::Gripper& gripper, std::chrono::microseconds ik_time_budget,
                              double table_angle_deg);

}  // namespace vscan::service
