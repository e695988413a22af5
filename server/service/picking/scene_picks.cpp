#include "service/picking/scene_picks.h"

#include <chrono>
#include <cmath>
#include <map>
#include <regex>
#include <set>

#include "service/picking/arm_reach.h"

namespace vscan::service {
namespace {

using Clock = std::chrono::steady_clock;

// The parts a bin fill places are labelled "<name>#<instance>".
bool IsBinPartLabel(const std::string& label) {
  static const std::regex pattern(".*#[0-9]+");
  return std::regex_match(label, pattern);
}

std::shared_ptr<const TriangleMesh> Scaled(const std::shared_ptr<const TriangleMesh>& mesh, double scale) {
  if (scale == 1.0) return mesh;
  auto out = std::make_shared<TriangleMesh>(*mesh);
  for (Eigen::Vector3f& v : out->vertices) v *= float(scale);
  return out;
}

Status ValidateRequest(const ScenePickRequest& request) {
  if (request.mount_id.empty()) return InvalidArgument("mount_id", "required");
  std::set<std::string> seen;
  for (size_t i = 0; i < request.part_object_ids.size(); ++i) {
    if (!seen.insert(request.part_object_ids[i]).second) {
      return InvalidArgument("part_object_ids[" + std::to_string(i) + "]", "names an object twice");
    }
  }
  return CheckPickSettings(request);
}

}  // namespace

Status CheckPickSettings(const ScenePickRequest& request) {
  if (!std::isfinite(request.body_length_m) || request.body_length_m < 0 || request.body_length_m > 10) {
    return InvalidArgument("body_length_m", "must be in [0, 10] m (0: the mount's tool offset)");
  }
  if (request.ik_time_budget < std::chrono::milliseconds(1) || request.ik_time_budget > std::chrono::seconds(1)) {
    return InvalidArgument("ik_time_budget_ms", "must be in [1, 1000] ms");
  }
  RETURN_IF_ERROR(grasping::ValidateGraspOptions(request.grasp_options));
  RETURN_IF_ERROR(grasping::ValidatePickOptions(request.pick_options));
  return grasping::ValidateGripper(request.gripper);
}

Status CheckReachWork(const ScenePickRequest& request, size_t parts) {
  // Each reach check may spend the inverse-kinematics budget twice (grasp and pre-grasp).
  const double reach_s = double(parts) * double(request.pick_options.max_reach_checks) * 2 *
                         std::chrono::duration<double>(request.ik_time_budget).count();
  if (reach_s > kMaxReachSeconds) {
    return ResourceExhausted("pick_options.max_reach_checks",
                             "parts x max_reach_checks x 2 x ik_time_budget may take " + std::to_string(int(reach_s)) +
                                 " s; at most " + std::to_string(int(kMaxReachSeconds)));
  }
  return Status::Ok();
}

StatusOr<ScenePicks> CheckScenePicks(ServiceContext& context, const ScenePickRequest& request,
                                     const std::atomic<bool>* cancel) {
  const auto start = Clock::now();
  RETURN_IF_ERROR(ValidateRequest(request));
  ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, context.robots.Mount(request.mount_id));
  const std::string& scene_id = mounted.mount.scene_id;
  ASSIGN_OR_RETURN(const store::SceneRecord scene, context.registry.catalogue().GetScene(scene_id));
  ASSIGN_OR_RETURN(const scenes::ScanTarget target, context.registry.PrepareScan(scene_id, scene.table.angle_deg));

  std::vector<const store::ObjectRecord*> parts;
  if (request.part_object_ids.empty()) {
    for (const store::ObjectRecord& object : target.scene.objects) {
      if (IsBinPartLabel(object.label)) parts.push_back(&object);
    }
    if (parts.empty()) {
      return FailedPrecondition("part_object_ids: empty, and scene '" + scene_id +
                                "' has no object labelled <name>#<n> (a bin fill's parts)");
    }
  } else {
    for (size_t i = 0; i < request.part_object_ids.size(); ++i) {
      const auto it = std::find_if(target.scene.objects.begin(), target.scene.objects.end(),
                                   [&](const store::ObjectRecord& o) { return o.object_id == request.part_object_ids[i]; });
      if (it == target.scene.objects.end()) {
        return NotFound("part_object_ids[" + std::to_string(i) + "]: no object '" + request.part_object_ids[i] +
                        "' in scene '" + scene_id + "'");
      }
      parts.push_back(&*it);
    }
  }

  if (parts.size() > kMaxPickParts) {
    return ResourceExhausted("part_object_ids", std::to_string(parts.size()) + " parts; at most " +
                                                    std::to_string(kMaxPickParts) + " in one call");
  }
  RETURN_IF_ERROR(CheckReachWork(request, parts.size()));

  // Part types are distinct (mesh, scale) pairs; grasps are generated once per type.
  grasping::Pile pile;
  std::map<std::pair<const TriangleMesh*, double>, size_t> type_of;
  std::vector<std::shared_ptr<const TriangleMesh>> type_meshes;
  std::vector<size_t> pile_object;  // pile part -> index into parts
  std::set<uint32_t> part_instances;
  for (size_t p = 0; p < parts.size(); ++p) {
    part_instances.insert(parts[p]->instance_id);
    for (const raycast::SceneInstance& instance : *target.instances) {
      if (instance.instance_id != parts[p]->instance_id) continue;
      const auto key = std::make_pair(instance.mesh.get(), instance.scale);
      auto [it, added] = type_of.emplace(key, type_meshes.size());
      if (added) type_meshes.push_back(Scaled(instance.mesh, instance.scale));
      pile.parts.push_back({it->second, type_meshes[it->second], instance.world_from_object});
      pile_object.push_back(p);
    }
  }
  std::vector<const store::ObjectRecord*> fixture_object;  // pile fixture -> its object (null: none)
  for (const raycast::SceneInstance& instance : *target.instances) {
    if (part_instances.contains(instance.instance_id)) continue;
    pile.fixtures.push_back({Scaled(instance.mesh, instance.scale), instance.world_from_object});
    const auto object = std::find_if(target.scene.objects.begin(), target.scene.objects.end(),
                                     [&](const store::ObjectRecord& o) { return o.instance_id == instance.instance_id; });
    fixture_object.push_back(object == target.scene.objects.end() ? nullptr : &*object);
  }
  // What the engine names by index, by the scene's object id and label.
  const auto object_of = [&](const grasping::PileItem& item) -> const store::ObjectRecord* {
    return item.fixture ? fixture_object[item.index] : parts[pile_object[item.index]];
  };
  const auto name = [](const store::ObjectRecord* object) {
    return object == nullptr ? std::string("a scene instance") : "object '" + object->object_id + "' (" + object->label + ")";
  };
  std::vector<std::vector<grasping::Grasp>> grasps;
  ScenePicks out;
  out.scene_id = scene_id;
  for (const auto& mesh : type_meshes) {
    ASSIGN_OR_RETURN(auto generated, grasping::GenerateGrasps(*mesh, request.gripper, request.grasp_options));
    out.grasps_generated += generated.size();
    grasps.push_back(std::move(generated));
  }

  grasping::PickOptions options = request.pick_options;
  options.sweep.body_length_m =
      request.body_length_m > 0 ? request.body_length_m : mounted.chain->tip_from_tool().translation().norm();
  const auto reach = ArmReach(context, std::make_shared<const robot_registry::MountedRobot>(mounted), request.gripper,
                              request.ik_time_budget, scene.table.angle_deg);
  ASSIGN_OR_RETURN(auto verdicts, grasping::CheckPicks(pile, grasps, request.gripper, options, reach, cancel));

  for (size_t i = 0; i < verdicts.size(); ++i) {
    const store::ObjectRecord& object = *parts[pile_object[i]];
    ObjectPick pick{object.object_id, object.label, std::move(verdicts[i]), {}};
    if (pick.verdict.covered_by) {
      const store::ObjectRecord* cover = object_of(*pick.verdict.covered_by);
      if (cover != nullptr) pick.covered_by_object_id = cover->object_id;
      pick.verdict.detail = name(cover) + " lies on it";
    }
    if (pick.verdict.failure == grasping::PickFailure::kGripperCollision && pick.verdict.blocked_by) {
      pick.verdict.detail = "the gripper's way in meets " + name(object_of(*pick.verdict.blocked_by));
    }
    out.parts.push_back(std::move(pick));
  }
  out.elapsed_s = std::chrono::duration<double>(Clock::now() - start).count();
  return out;
}

}  // namespace vscan::service
