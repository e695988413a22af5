#include "service/campaign/campaign_plan.h"

#include "service/scan/request_memory.h"
#include "service/robot/robot_collision.h"
#include "service/robot/robot_placement.h"

namespace vscan::service {

StatusOr<ScanPlan> StepScanPlan(ServiceContext& context, const CampaignPlan& plan, const Eigen::VectorXd& joints,
                                double table_angle_deg, uint64_t seed) {
  ScanPlan scan = plan.scan;
  scan.scene_id = plan.scene_id;
  scan.table_angle_deg = table_angle_deg;
  scan.measurement.seed = seed;
  const std::optional<uint64_t> noise_seed = plan.apply_encoder_noise ? std::optional<uint64_t>(seed) : std::nullopt;
  ASSIGN_OR_RETURN(scan.robot, PlaceRobotSensor(context.robots, plan.scene_id, plan.mount_id, joints, noise_seed,
                                                &scan.world_from_sensor));
  return scan;
}

Status CheckCampaignWorld(ServiceContext& context, const CampaignPlan& plan, bool dry_run) {
  RETURN_IF_ERROR(CheckRequestMemory(ScanMemoryBytes(plan.scan, false), context.options.limits, "sensor",
                                     "each scan of the campaign"));
  if (dry_run && plan.scene_id.empty() && plan.mount_id.empty()) return Status::Ok();
  if (plan.scene_id.empty()) return InvalidArgument("scene_id", "required");
  ASSIGN_OR_RETURN(const store::SceneRecord scene, context.registry.catalogue().GetScene(plan.scene_id));
  if (plan.rotations > 1 && !scene.table.enabled) {
    return FailedPrecondition("rotations", "scene '" + plan.scene_id + "' has no rotary table enabled to turn (" +
                              std::to_string(plan.rotations) + " rotations asked)");
  }
  if (dry_run && plan.mount_id.empty()) return Status::Ok();
  if (plan.mount_id.empty()) return InvalidArgument("mount_id", "required");
  ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, context.robots.Mount(plan.mount_id));
  if (mounted.mount.scene_id != plan.scene_id) {
    return FailedPrecondition("mount_id", "mount '" + plan.mount_id + "' is in scene '" + mounted.mount.scene_id +
                              "', not in scene_id '" + plan.scene_id + "'");
  }
  const Eigen::VectorXd home = mounted.chain->MidLimits();
  if (plan.reject_collisions) {
    // Fails now, rather than at the first step, when collision checking is not available.
    auto probe = FindRobotCollision(context, plan.mount_id, home, plan.start_angle_deg);
    if (!probe.ok()) {
      const Status& s = probe.status();
      return s.field() == "reject_collisions" ? s : Status(s.code(), "reject_collisions", s.message());
    }
  }
  return StepScanPlan(context, plan, home, plan.start_angle_deg, plan.seed).status();
}

}  // namespace vscan::service
