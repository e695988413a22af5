#pragma once
// Which parts of a scene a mounted robot with a gripper on its flange can pick: grasps generated
// per part mesh, then grasping::CheckPicks with the arm's inverse kinematics and collision check
// as its reach test. The mount's tool frame is the gripper's tool centre point (z along the
// approach).

#include <atomic>
#include <chrono>
#include <string>
#include <vector>

#include "grasping/grasp_generation.h"
#include "grasping/pick_checks.h"
#include "service/context/service_context.h"

namespace vscan::service {

struct ScenePickRequest {
  std::string mount_id;
  // The parts; empty: every object labelled "<name>#<n>" (the parts a bin fill placed). Every
  // other object of the scene is a fixture the gripper and the arm must not touch.
  std::vector<std::string> part_object_ids;
  grasping::Gripper gripper;
  grasping::GraspOptions grasp_options;
  grasping::PickOptions pick_options;
  // Zero: the distance from the flange to the mount's tool centre point.
  double body_length_m = 0;
  std::chrono::microseconds ik_time_budget{20000};  // per solve, [1 ms, 1 s]
};

struct ObjectPick {
  std::string object_id;
  std::string label;
  grasping::PickVerdict verdict;
  // When covered: the object lying on it (another part or any other object of the scene). The
  // verdict's detail names objects by id and label.
  std::string covered_by_object_id;
};

struct ScenePicks {
  std::string scene_id;
  std::vector<ObjectPick> parts;  // in request order (or instance order)
  size_t grasps_generated = 0;    // over the distinct part meshes
  double elapsed_s = 0;
};

// At most this many parts in one call, and at most this many seconds of inverse kinematics at worst
// (parts x max_reach_checks x 2 solves x ik_time_budget).
inline constexpr size_t kMaxPickParts = 500;
inline constexpr double kMaxReachSeconds = 300;

// The request's gripper, grasp and pick options, body length and solve budget, without the scene:
// INVALID_ARGUMENT naming the field as the service names it ("body_length_m",
// "gripper.suction.diameter_m").
Status CheckPickSettings(const ScenePickRequest& request);
// RESOURCE_EXHAUSTED naming "pick_options.max_reach_checks" when parts x max_reach_checks x 2 solves
// x ik_time_budget exceeds kMaxReachSeconds.
Status CheckReachWork(const ScenePickRequest& request, size_t parts);

// NOT_FOUND naming "mount_id" or "part_object_ids[i]"; INVALID_ARGUMENT naming the gripper's,
// the options' or the request's field; FAILED_PRECONDITION when no part is named or found;
// RESOURCE_EXHAUSTED naming "part_object_ids" past kMaxPickParts or "pick_options.max_reach_checks"
// past kMaxReachSeconds; CANCELLED once *cancel is set.
StatusOr<ScenePicks> CheckScenePicks(ServiceContext& context, const ScenePickRequest& request,
                                     const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::service
