#include "api/campaign/campaign_spec.h"

#include <cmath>
#include <optional>

#include "api/model/model_spec.h"
#include "api/scan/scan_request.h"
#include "api/transport/validate.h"
#include "service/model/model_run.h"
#include "vscan/common/physical_limits.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr double kMaxAbsAngleDeg = 1e6;

std::string Index(const char* field, int i) { return std::string(field) + "[" + std::to_string(i) + "]"; }

StatusOr<Eigen::Vector3d> Point(bool has, const v1::Vector3& p, const std::string& field) {
  if (!has) return InvalidArgument(field, "required");
  const Eigen::Vector3d point = FromProto(p);
  RETURN_IF_ERROR(CheckPosition(point, field));
  return point;
}

// World +z, as CAMPAIGNS.md documents; +x for a view that looks straight up or down.
Eigen::Vector3d DefaultViewpointUp(const Eigen::Vector3d& view) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  return z.cross(view).norm() < 1e-3 ? Eigen::Vector3d::UnitX() : z;
}

StatusOr<std::vector<service::CampaignViewpoint>> Viewpoints(const v1::CampaignSpec& spec) {
  if (spec.viewpoints().empty()) return InvalidArgument("viewpoints", "at least one viewpoint required");
  if (spec.viewpoints_size() > service::kMaxCampaignViewpoints) {
    return InvalidArgument("viewpoints", "at most " + std::to_string(service::kMaxCampaignViewpoints) + " viewpoints");
  }
  std::vector<service::CampaignViewpoint> out;
  for (int i = 0; i < spec.viewpoints_size(); ++i) {
    const v1::Viewpoint& v = spec.viewpoints(i);
    const std::string field = Index("viewpoints", i);
    service::CampaignViewpoint vp;
    ASSIGN_OR_RETURN(vp.position, Point(v.has_position(), v.position(), field + ".position"));
    ASSIGN_OR_RETURN(vp.target, Point(v.has_target(), v.target(), field + ".target"));
    if ((vp.target - vp.position).norm() < 1e-6) {
      return InvalidArgument(FieldPath(field, "target"), "coincides with position; the sensor must look somewhere");
    }
    const Eigen::Vector3d view = (vp.target - vp.position).normalized();
    Eigen::Vector3d up = DefaultViewpointUp(view);
    if (v.has_up()) {
      ASSIGN_OR_RETURN(up, Point(true, v.up(), field + ".up"));
      if (up.norm() < 1e-9 || up.normalized().cross(view).norm() < 1e-6) {
        return InvalidArgument(FieldPath(field, "up"), "must not be zero or parallel to the view direction");
      }
    }
    // The whole sensor pose, as a look_at Pose gives it: the IK also matches the image's up.
    ASSIGN_OR_RETURN(const Pose3 world_from_sensor, PoseFromLookAt(vp.position, vp.target, up, field));
    vp.goal = robot::PoseGoal(world_from_sensor);
    out.push_back(std::move(vp));
  }
  return out;
}

Status CheckAngles(const v1::CampaignSpec& spec, uint32_t rotations) {
  if (!std::isfinite(spec.start_angle_deg()) || std::abs(spec.start_angle_deg()) > kMaxAbsAngleDeg) {
    return InvalidArgument("start_angle_deg", "must be finite and within +-1e6");
  }
  if (!std::isfinite(spec.rotation_step_deg()) || std::abs(spec.rotation_step_deg()) > 360.0) {
    return InvalidArgument("rotation_step_deg", "must be finite and within +-360");
  }
  if (rotations > 1 && spec.rotation_step_deg() == 0.0) {
    return InvalidArgument("rotation_step_deg", "must not be 0 when rotations is " + std::to_string(rotations));
  }
  return Status::Ok();
}

// The ids a start needs, syntax only; a dry run checks only the ids it is given. The service
// layer looks them up.
Status CheckIds(const v1::CampaignSpec& spec, bool dry_run) {
  if (dry_run && spec.scene_id().empty() && spec.mount_id().empty()) return Status::Ok();
  RETURN_IF_ERROR(RequireId(spec.scene_id(), "scene_id"));
  if (dry_run && spec.mount_id().empty()) return Status::Ok();
  return RequireId(spec.mount_id(), "mount_id");
}

// The sensor, noise, backend, fields, frame and returned light every step scans with, checked by the parser of
// ScanRequests (the spec names them as a ScanRequest does). The sensor pose is a stand-in: each
// step puts the sensor where the arm holds it.
StatusOr<service::ScanPlan> StepScanSettings(const v1::CampaignSpec& spec, const service::Limits& limits,
                                             robot_registry::RobotRegistry& robots) {
  v1::ScanRequest request;
  request.set_scene_id(spec.scene_id().empty() ? "validate-only" : spec.scene_id());
  *request.mutable_sensor() = spec.sensor();
  if (spec.has_noise()) *request.mutable_noise() = spec.noise();
  request.set_seed(spec.seed());
  request.set_backend(spec.backend());
  *request.mutable_fields() = spec.fields();
  request.set_frame(spec.frame());
  if (spec.has_returned_light()) *request.mutable_returned_light() = spec.returned_light();
  request.mutable_pose()->mutable_look_at()->mutable_target()->set_x(1.0);
  return ParseScanRequest(request, limits, robots);
}

StatusOr<service::CampaignPlan> Validate(const v1::CampaignSpec& spec, bool dry_run,
                                         service::ServiceContext& context) {
  service::CampaignPlan plan;
  RETURN_IF_ERROR(CheckText(spec.name(), "name"));
  ASSIGN_OR_RETURN(plan.viewpoints, Viewpoints(spec));

  plan.rotations = spec.rotations() == 0 ? 1 : spec.rotations();
  if (plan.rotations > service::kMaxCampaignRotations) {
    return InvalidArgument("rotations", "at most " + std::to_string(service::kMaxCampaignRotations));
  }
  const uint64_t steps = uint64_t{plan.rotations} * plan.viewpoints.size();
  if (steps > service::kMaxCampaignSteps) {
    return InvalidArgument("rotations", std::to_string(plan.rotations) + " rotations x " +
                           std::to_string(plan.viewpoints.size()) + " viewpoints = " + std::to_string(steps) +
                           " scans, more than the " + std::to_string(service::kMaxCampaignSteps) +
                           " a campaign may hold");
  }
  RETURN_IF_ERROR(CheckAngles(spec, plan.rotations));
  RETURN_IF_ERROR(CheckIds(spec, dry_run));
  plan.name = spec.name();
  plan.scene_id = spec.scene_id();
  plan.mount_id = spec.mount_id();
  plan.seed = spec.seed();
  plan.start_angle_deg = spec.start_angle_deg();
  plan.rotation_step_deg = spec.rotation_step_deg();
  plan.reject_collisions = spec.reject_collisions();
  plan.apply_encoder_noise = spec.apply_encoder_noise();
  ASSIGN_OR_RETURN(plan.scan, StepScanSettings(spec, context.options.limits, context.robots));
  RETURN_IF_ERROR(service::CheckCampaignWorld(context, plan, dry_run));
  if (spec.align() || spec.reconstruct() || spec.evaluate()) {
    ASSIGN_OR_RETURN(const service::ModelRequest request, ModelRequestFromCampaign(spec));
    const bool pixels = (plan.scan.fields & kFieldPixel) != 0;
    ASSIGN_OR_RETURN(plan.model, service::PlanCampaignModel(context, request, plan.scene_id, plan.mount_id, pixels));
    plan.model->returned_light = plan.scan.measurement.returned_light;
    plan.model_steps = service::CampaignModelSteps(*plan.model);
  }
  return plan;
}

}  // namespace

Status InSpec(const Status& status) {
  if (status.ok() || !NamesAField(status.code())) return status;
  if (!status.field().empty()) return status.WithFieldPrefix("spec");
  // Errors not (yet) built with a field still lead with their path as text.
  return Status(status.code(), "spec." + status.message());
}

StatusOr<service::CampaignPlan> ValidateCampaign(const v1::CampaignSpec& spec, service::ServiceContext& context,
                                                 bool validate_only) {
  auto plan = Validate(spec, validate_only, context);
  if (!plan.ok()) return InSpec(plan.status());
  return plan;
}

}  // namespace vscan::api
