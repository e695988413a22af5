#include "service/picking/picking_session.h"

#include <cmath>
#include <map>

#include "service/clouds/cloud_store.h"
#include "service/localization/localization_run.h"
#include "service/picking/arm_reach.h"
#include "service/scan/scan_backends.h"

namespace vscan::service {
namespace {

using PartKey = std::pair<size_t, size_t>;  // type, instance

// The fill's parts among the scene's objects ("<part name>#<instance + 1>") and the object of each.
struct ScenePile {
  std::vector<physics::PlacedPart> parts;
  std::map<PartKey, std::string> object_of;
};

StatusOr<ScenePile> PileInScene(ServiceContext& context, const PickingPlan& plan, double table_angle_deg) {
  ASSIGN_OR_RETURN(const store::SceneRecord scene, context.registry.catalogue().GetScene(plan.scene_id));
  std::map<std::string, size_t> type_of;
  for (size_t t = 0; t < plan.bin.parts.size(); ++t) type_of.emplace(plan.bin.parts[t].name, t);
  ScenePile pile;
  for (const store::ObjectRecord& object : scene.objects) {
    const size_t hash = object.label.rfind('#');
    if (hash == std::string::npos || hash + 1 >= object.label.size()) continue;
    const auto type = type_of.find(object.label.substr(0, hash));
    if (type == type_of.end()) continue;
    const std::string number = object.label.substr(hash + 1);
    if (number.find_first_not_of("0123456789") != std::string::npos || number.size() > 6) continue;
    const size_t instance = std::stoul(number);
    if (instance == 0) continue;
    const PartKey key{type->second, instance - 1};
    if (!pile.object_of.emplace(key, object.object_id).second) continue;  // a label used twice: the first
    pile.parts.push_back(
        {key.first, key.second, scenes::SceneRegistry::WorldFromObject(scene, object, table_angle_deg)});
  }
  return pile;
}

// Writes the pile into the scene: parts no longer in it removed, moved ones moved.
Status WritePile(ServiceContext& context, const std::string& scene_id, std::map<PartKey, std::string>& object_of,
                 std::map<PartKey, Pose3>& written, const std::vector<physics::PlacedPart>& pile) {
  std::map<PartKey, const physics::PlacedPart*> now;
  for (const physics::PlacedPart& part : pile) now.emplace(PartKey{part.type, part.instance}, &part);
  for (auto it = written.begin(); it != written.end();) {
    const auto kept = now.find(it->first);
    if (kept == now.end()) {
      RETURN_IF_ERROR(context.registry.catalogue().RemoveObject(scene_id, object_of.at(it->first)).status());
      it = written.erase(it);
      continue;
    }
    const Pose3& pose = kept->second->world_from_part;
    if (!pose.matrix().isApprox(it->second.matrix(), 1e-12)) {
      RETURN_IF_ERROR(context.registry.catalogue()
                          .MoveObject(scene_id, object_of.at(it->first), pose.matrix(), std::nullopt)
                          .status());
      it->second = pose;
    }
    ++it;
  }
  return Status::Ok();
}

StatusOr<std::vector<picking::Estimate>> Localize(ServiceContext& context, const PickingPlan& plan,
                                                  const std::vector<physics::PlacedPart>& pile,
                                                  const PointCloud& cloud, const std::atomic<bool>* cancel) {
  LocalizePlan localize;
  localize.points = cloud.positions;
  localize.options = plan.localizer;
  localize.normal_source = NormalSource::kEstimate;
  localize.viewpoint = plan.scan.world_from_sensor.translation();
  std::vector<size_t> counts(plan.bin.parts.size(), 0);
  for (const physics::PlacedPart& part : pile) ++counts[part.type];
  std::vector<size_t> type_of_query;
  for (size_t t = 0; t < plan.bin.parts.size(); ++t) {
    if (counts[t] == 0) continue;
    const BinPartRequest& part = plan.bin.request.parts[t];
    localize.parts.push_back({part.mesh_id, part.scale, counts[t], "bin.parts[" + std::to_string(t) + "].mesh_id"});
    type_of_query.push_back(t);
  }
  std::vector<picking::Estimate> out;
  if (localize.parts.empty() || localize.points.empty()) return out;
  ASSIGN_OR_RETURN(const LocalizeOutcome outcome, RunLocalize(context.registry, StoredCloudsOf(context), localize,
                                                              cancel, {}, context.part_models.get()));
  for (const localization::LocalizedInstance& instance : outcome.result.instances) {
    out.push_back({type_of_query[instance.part], instance.world_from_part, instance.score});
  }
  return out;
}

}  // namespace

StatusOr<picking::EmptyBinResult> RunPickingSession(ServiceContext& context, const PickingPlan& plan,
                                                    const std::atomic<bool>* cancel, const PickingObserver& observer) {
  ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, context.robots.Mount(plan.mount_id));
  if (mounted.mount.scene_id != plan.scene_id) {
    return FailedPrecondition("mount_id: mount '" + plan.mount_id + "' stands in scene '" + mounted.mount.scene_id +
                              "', not in the bin's scene '" + plan.scene_id + "'");
  }
  ASSIGN_OR_RETURN(const store::SceneRecord scene, context.registry.catalogue().GetScene(plan.scene_id));
  const double table_angle = scene.table.angle_deg;
  ASSIGN_OR_RETURN(ScenePile start, PileInScene(context, plan, table_angle));
  if (start.parts.empty()) {
    return FailedPrecondition("bin_job_id: scene '" + plan.scene_id + "' holds none of the fill's parts");
  }

  picking::Cell cell;
  cell.bin = plan.bin.request.bin;
  cell.types = plan.bin.parts;
  cell.gripper = plan.gripper;
  cell.pick_options = plan.pick_options;
  cell.pick_options.sweep.body_length_m =
      plan.body_length_m > 0 ? plan.body_length_m : mounted.chain->tip_from_tool().translation().norm();
  cell.physics = plan.bin.request.options;
  for (const physics::PartType& type : cell.types) {
    ASSIGN_OR_RETURN(auto grasps, grasping::GenerateGrasps(type.mesh, plan.gripper, plan.grasp_options));
    cell.grasps.push_back(std::move(grasps));
  }
  cell.reach = ArmReach(context, std::make_shared<const robot_registry::MountedRobot>(mounted), plan.gripper,
                        plan.ik_time_budget, table_angle);

  std::map<PartKey, Pose3> written;
  for (const physics::PlacedPart& part : start.parts) written.emplace(PartKey{part.type, part.instance}, part.world_from_part);
  // A run that goes on after an interruption may find a step's settling half written: the pile
  // settles first (a settled pile barely moves).
  ASSIGN_OR_RETURN(const physics::FillResult settled,
                   physics::SettlePile(cell.bin, cell.types, start.parts, cell.physics, cancel));
  start.parts = settled.parts;
  RETURN_IF_ERROR(WritePile(context, plan.scene_id, start.object_of, written, start.parts));
  size_t step = 0;
  Status written_status = Status::Ok();
  const picking::Perceive perceive =
      [&](const std::vector<physics::PlacedPart>& pile) -> StatusOr<std::vector<picking::Estimate>> {
    RETURN_IF_ERROR(written_status);  // the scene must show the pile the step scans
    StepView view;
    view.step = observer.first_step + step++;
    view.truth = pile;
    for (const auto& grasps : cell.grasps) view.grasps_per_type.push_back(grasps.size());
    if (plan.perception == Perception::kTruth) {
      for (const physics::PlacedPart& part : pile) view.estimates.push_back({part.type, part.world_from_part, 1.0});
    } else {
      ScanPlan scan = plan.scan;
      scan.scene_id = plan.scene_id;
      scan.table_angle_deg = table_angle;
      scan.measurement.seed = plan.scan_seed + view.step;
      ASSIGN_OR_RETURN(const scenes::ScanTarget target, context.registry.PrepareScan(plan.scene_id, table_angle));
      raycast::ScanStats stats;
      ASSIGN_OR_RETURN(view.scan, RunScanBackend(scan, target, context.raster, cancel, &stats));
      if (plan.perception == Perception::kClient) {
        if (!observer.client_estimates) return Internal("client perception without a source of estimates");
        if (observer.perceived) observer.perceived(view);
        return observer.client_estimates(view);
      }
      ASSIGN_OR_RETURN(view.estimates, Localize(context, plan, pile, view.scan, cancel));
    }
    if (observer.perceived) observer.perceived(view);
    return view.estimates;
  };
  const auto stepped = [&](const picking::PickStep& record, const std::vector<physics::PlacedPart>& pile) {
    if (written_status.ok()) written_status = WritePile(context, plan.scene_id, start.object_of, written, pile);
    if (!observer.stepped) return;
    picking::PickStep numbered = record;
    numbered.step += observer.first_step;
    observer.stepped(numbered, pile);
  };
  ASSIGN_OR_RETURN(picking::EmptyBinResult result,
                   picking::EmptyBin(cell, start.parts, perceive, plan.session, cancel, stepped));
  RETURN_IF_ERROR(written_status);
  for (picking::PickStep& record : result.steps) record.step += observer.first_step;
  return result;
}

}  // namespace vscan::service
