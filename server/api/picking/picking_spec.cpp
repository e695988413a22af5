#include "api/picking/picking_spec.h"

#include <cmath>

#include "api/bins/bin_fill_spec.h"
#include "api/picking/pick_request.h"
#include "sensor/camera.h"
#include "service/picking/scene_picks.h"
#include "service/job/job_kind.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr uint32_t kMaxImageSide = 4096;
constexpr uint32_t kMaxSteps = 10000;
constexpr double kDefaultEstimatesTimeoutS = 600;
constexpr double kMaxEstimatesTimeoutS = 86400;

}  // namespace

StatusOr<service::PickingPlan> ValidatePicking(const v1::PickingSpec& spec, const store::JobRecord& bin_job,
                                               service::ServiceContext& context) {
  if (bin_job.kind != service::JobKindName(service::JobKind::kBinFill)) {
    return FailedPrecondition("spec.bin_job_id", "job '" + bin_job.job_id + "' is a " + bin_job.kind + " job, not a bin fill");
  }
  if (bin_job.state != store::JobState::kSucceeded) {
    return FailedPrecondition("spec.bin_job_id", "bin fill '" + bin_job.job_id + "' did not succeed (" +
                                                     store::JobStateName(bin_job.state) + ")");
  }
  v1::BinFillSpec bin_spec;
  if (!bin_spec.ParseFromString(bin_job.spec)) {
    return DataLoss("spec.bin_job_id: job '" + bin_job.job_id + "': its stored spec does not parse");
  }
  // The fill's own pick check (its mount may be gone since) is not part of the pile.
  bin_spec.clear_picks();
  service::PickingPlan plan;
  auto bin = ValidateBinFill(bin_spec, context, false);
  if (!bin.ok()) {
    return Status(bin.status().code(), "spec.bin_job_id: the bin fill cannot be read again: " + bin.status().message());
  }
  plan.bin = std::move(bin).value();
  plan.scene_id = plan.bin.request.scene_id;

  if (spec.mount_id().empty()) return InvalidArgument("spec.mount_id", "required");
  auto mounted = context.robots.Mount(spec.mount_id());
  if (!mounted.ok()) return Status(mounted.status().code(), "spec.mount_id: " + mounted.status().message());
  if (mounted->mount.scene_id != plan.scene_id) {
    return FailedPrecondition("spec.mount_id", "mount '" + spec.mount_id() + "' stands in scene '" +
                                                   mounted->mount.scene_id + "', not in the bin's scene '" +
                                                   plan.scene_id + "'");
  }
  plan.mount_id = spec.mount_id();

  // The gripper and options as CheckPicks takes them, named under spec.
  v1::CheckPicksRequest picks;
  picks.set_mount_id(spec.mount_id());
  *picks.mutable_gripper() = spec.gripper();
  *picks.mutable_grasp_options() = spec.grasp_options();
  *picks.mutable_pick_options() = spec.pick_options();
  auto parsed = ParseCheckPicksRequest(picks);
  if (!parsed.ok()) return parsed.status().WithFieldPrefix("spec");
  plan.gripper = parsed->gripper;
  plan.grasp_options = parsed->grasp_options;
  plan.pick_options = parsed->pick_options;
  plan.body_length_m = parsed->body_length_m;
  plan.ik_time_budget = parsed->ik_time_budget;
  for (const Status& checked : {service::CheckPickSettings(*parsed),
                                service::CheckReachWork(*parsed, plan.bin.parts_total())}) {
    if (!checked.ok()) return InRequestTerms(checked).WithFieldPrefix("spec");
  }

  switch (spec.perception()) {
    case v1::PICKING_PERCEPTION_UNSPECIFIED: plan.perception = service::Perception::kBaseline; break;
    case v1::PICKING_PERCEPTION_TRUTH: plan.perception = service::Perception::kTruth; break;
    case v1::PICKING_PERCEPTION_CLIENT: plan.perception = service::Perception::kClient; break;
    default: return InvalidArgument("spec.perception", "unknown value " + std::to_string(spec.perception()));
  }
  const double timeout_s = spec.estimates_timeout_s() == 0 ? kDefaultEstimatesTimeoutS : spec.estimates_timeout_s();
  if (!std::isfinite(timeout_s) || timeout_s < 0.1 || timeout_s > kMaxEstimatesTimeoutS) {
    return InvalidArgument("spec.estimates_timeout_s", "must be 0 (600 s) or in [0.1, " +
                                                           std::to_string(static_cast<int>(kMaxEstimatesTimeoutS)) + "] s");
  }
  plan.estimates_timeout = std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000));
  const uint32_t width = spec.width() == 0 ? 640 : spec.width();
  const uint32_t height = spec.height() == 0 ? 512 : spec.height();
  if (width > kMaxImageSide) return InvalidArgument("spec.width", "at most " + std::to_string(kMaxImageSide));
  if (height > kMaxImageSide) return InvalidArgument("spec.height", "at most " + std::to_string(kMaxImageSide));
  const double fov = spec.horizontal_fov_deg() == 0 ? 50.0 : spec.horizontal_fov_deg();
  if (!std::isfinite(fov) || fov <= 1 || fov >= 170) {
    return InvalidArgument("spec.horizontal_fov_deg", "must be in (1, 170) degrees");
  }
  plan.scan.camera = sensor::CameraFromFov(width, height, fov, 0.05, 10.0);
  if (spec.has_sensor_pose()) {
    ASSIGN_OR_RETURN(plan.scan.world_from_sensor, PoseFromProto(spec.sensor_pose(), "spec.sensor_pose"));
  } else {
    const physics::BinInterior interior = physics::InteriorOf(plan.bin.request.bin);
    const Pose3& world_from_bin = plan.bin.request.bin.world_from_bin;
    const Eigen::Vector3d floor = world_from_bin * Eigen::Vector3d(0.5 * (interior.lo.x() + interior.hi.x()),
                                                                   0.5 * (interior.lo.y() + interior.hi.y()), interior.lo.z());
    const Eigen::Vector3d up = world_from_bin.linear().col(2);
    ASSIGN_OR_RETURN(plan.scan.world_from_sensor,
                     PoseFromLookAt(floor + 0.65 * up, floor, world_from_bin.linear().col(1), "spec.sensor_pose"));
  }
  plan.scan.scene_id = plan.scene_id;
  plan.scan_seed = spec.seed() == 0 ? 1 : spec.seed();
  plan.grasp_options.seed = plan.scan_seed;
  if (spec.max_steps() > kMaxSteps) return InvalidArgument("spec.max_steps", "at most " + std::to_string(kMaxSteps));
  if (spec.max_steps() != 0) plan.session.max_steps = spec.max_steps();
  if (spec.max_failures_in_a_row() > kMaxSteps) {
    return InvalidArgument("spec.max_failures_in_a_row", "at most " + std::to_string(kMaxSteps));
  }
  if (spec.max_failures_in_a_row() != 0) plan.session.max_failures_in_a_row = spec.max_failures_in_a_row();
  if (spec.name().size() > 256) return InvalidArgument("spec.name", "at most 256 bytes");
  return plan;
}

}  // namespace vscan::api
