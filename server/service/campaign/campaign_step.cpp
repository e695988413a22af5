#include "service/campaign/campaign_step.h"

#include "service/robot/robot_collision.h"
#include "service/scan/scan_backends.h"
#include "service/scan/scan_target.h"
#include "random/seeded_draws.h"

namespace vscan::service {
namespace {

constexpr double kIkTolerance = 1e-5;
constexpr std::chrono::milliseconds kIkBudget{200};

}  // namespace

uint64_t StepSeed(uint64_t campaign_seed, uint32_t step) {
  return random::SplitMix64(campaign_seed ^ random::SplitMix64(step));
}

StatusOr<ViewpointSolution> SolveViewpoint(const robot_registry::MountedRobot& mounted,
                                           const CampaignViewpoint& viewpoint) {
  robot_registry::IkSettings settings;
  settings.position_tolerance = kIkTolerance;
  settings.orientation_tolerance = kIkTolerance;
  settings.time_budget = kIkBudget;
  ASSIGN_OR_RETURN(const robot_registry::IkAnswer answer,
                   robot_registry::SolveInPlacement(*mounted.chain, mounted.placement, viewpoint.goal, {}, settings));
  ViewpointSolution solution;
  solution.reached = answer.reached;
  solution.miss_distance = answer.miss_distance;
  solution.joints = answer.result.joint_positions;
  return solution;
}

StatusOr<StepResult> RunStep(ServiceContext& context, const CampaignPlan& plan, const ViewpointSolution& solution,
                             double table_angle_deg, uint64_t seed, const std::atomic<bool>* cancel) {
  StepResult result;
  result.seed = seed;
  if (!solution.reached) {
    result.outcome = StepResult::Outcome::kUnreachable;
    return result;
  }
  ASSIGN_OR_RETURN(const ScanPlan scan, StepScanPlan(context, plan, solution.joints, table_angle_deg, seed));
  if (!scan.robot) return Internal("campaign: the step's scan plan has no robot placement");
  result.arm.commanded = solution.joints;
  result.arm.achieved = scan.robot->achieved_joint_positions;
  result.arm.commanded_pose = scan.robot->commanded_world_from_sensor;
  result.arm.achieved_pose = scan.world_from_sensor;
  if (plan.reject_collisions) {
    ASSIGN_OR_RETURN(const std::optional<std::string> collision,
                     FindRobotCollision(context, plan.mount_id, result.arm.achieved, table_angle_deg));
    if (collision) {
      result.outcome = StepResult::Outcome::kCollision;
      result.collision = *collision;
      return result;
    }
  }
  ASSIGN_OR_RETURN(const scenes::ScanTarget target, PrepareScanTarget(context, scan));
  capture::MeasureStats measured;
  ASSIGN_OR_RETURN(result.cloud, RunScanBackend(scan, target, context.raster, cancel, &result.stats, &measured));
  result.rejected_dark = measured.rejected_dark;
  result.rejected_saturated = measured.rejected_saturated;
  result.outcome = StepResult::Outcome::kCaptured;
  return result;
}

}  // namespace vscan::service
