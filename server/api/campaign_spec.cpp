#include "api/campaign_spec.h"

#include <cmath>
#include <optional>

#include "api/robot_collision.h"
#include "api/scan_request.h"
#include "api/validate.h"
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

StatusOr<std::vector<CampaignViewpoint>> Viewpoints(const v1::CampaignSpec& spec) {
  if (spec.viewpoints().empty()) return InvalidArgument("viewpoints", "at least one viewpoint required");
  if (spec.viewpoints_size() > kMaxCampaignViewpoints) {
    return InvalidArgument("viewpoints", "at most " + std::to_string(kMaxCampaignViewpoints) + " viewpoints");
  }
  std::vector<CampaignViewpoint> out;
  for (int i = 0; i < spec.viewpoints_size(); ++i) {
    const v1::Viewpoint& v = spec.viewpoints(i);
    const std::string field = Index("viewpoints", i);
    CampaignViewpoint vp;
    ASSIGN_OR_RETURN(vp.position, Point(v.has_position(), v.position(), field + ".position"));
    ASSIGN_OR_RETURN(vp.target, Point(v.has_target(), v.target(), field + ".target"));
    if ((vp.target - vp.position).norm() < 1e-6) {
      return InvalidArgument(FieldPath(field, "target"), "coincides with position; the sensor must look somewhere");
    }
    if (v.has_up()) {
      // The whole sensor pose, as a look_at Pose gives it: the IK then also matches the image's up.
      ASSIGN_OR_RETURN(const Eigen::Vector3d up, Point(true, v.up(), field + ".up"));
      const Eigen::Vector3d view = (vp.target - vp.position).normalized();
      if (up.norm() < 1e-9 || up.normalized().cross(view).norm() < 1e-6) {
        return InvalidArgument(FieldPath(field, "up"), "must not be zero or parallel to the view direction");
      }
      ASSIGN_OR_RETURN(const Pose3 world_from_sensor, PoseFromLookAt(vp.position, vp.target, up, field));
      vp.goal = robot::PoseGoal(world_from_sensor);
    } else {
      ASSIGN_OR_RETURN(vp.goal, robot::LookAtGoal(vp.position, vp.target, field));
    }
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

// The middle of the arm's joint limits; unset in a dry run that names no mount.
using Home = std::optional<Eigen::VectorXd>;

// The scene must exist, hold the mount, and have a table when the campaign turns it. A dry run
// looks up only the ids it is given: a client checks a plan before it creates the scene and mount.
StatusOr<Home> CheckSceneAndMount(const v1::CampaignSpec& spec, uint32_t rotations, bool dry_run,
                                  ServiceContext& context) {
  if (dry_run && spec.scene_id().empty() && spec.mount_id().empty()) return Home();
  RETURN_IF_ERROR(RequireId(spec.scene_id(), "scene_id"));
  ASSIGN_OR_RETURN(const store::SceneRecord scene, context.registry.catalogue().GetScene(spec.scene_id()));
  if (rotations > 1 && !scene.table.enabled) {
    return FailedPrecondition("rotations", "scene '" + spec.scene_id() + "' has no rotary table enabled to turn (" +
                              std::to_string(rotations) + " rotations asked)");
  }
  if (dry_run && spec.mount_id().empty()) return Home();
  RETURN_IF_ERROR(RequireId(spec.mount_id(), "mount_id"));
  ASSIGN_OR_RETURN(const robots::MountedRobot mounted, context.robots.Mount(spec.mount_id()));
  if (mounted.mount.scene_id != spec.scene_id()) {
    return FailedPrecondition("mount_id", "mount '" + spec.mount_id() + "' is in scene '" + mounted.mount.scene_id +
                              "', not in scene_id '" + spec.scene_id() + "'");
  }
  if (spec.reject_collisions()) {
    // Fails now, rather than at the first step, when collision checking is not available.
    auto probe = FindRobotCollision(context, spec.mount_id(), mounted.chain->MidLimits(), spec.start_angle_deg());
    if (!probe.ok()) {
      const Status& s = probe.status();
      return s.field() == "reject_collisions" ? s : Status(s.code(), "reject_collisions", s.message());
    }
  }
  return Home(mounted.chain->MidLimits());
}

// The ScanRequest every step's scan is parsed from, at the first table angle. Without a mount (a
// dry run) the sensor stands at a fixed pose instead: only where it stands depends on the mount.
v1::ScanRequest FirstStepRequest(const v1::CampaignSpec& spec, const Home& home) {
  if (home) return StepScanRequest(spec, *home, spec.start_angle_deg(), spec.seed());
  v1::ScanRequest request = StepScanRequest(spec, Eigen::VectorXd(), spec.start_angle_deg(), spec.seed());
  if (request.scene_id().empty()) request.set_scene_id("validate-only");  // never looked up by the parser
  request.mutable_pose()->mutable_look_at()->mutable_target()->set_x(1.0);
  return request;
}

StatusOr<CampaignPlan> Validate(const v1::CampaignSpec& spec, bool dry_run, ServiceContext& context) {
  CampaignPlan plan;
  plan.spec = spec;
  RETURN_IF_ERROR(CheckText(spec.name(), "name"));
  if (spec.align()) {
    return Status(StatusCode::kUnimplemented, "align", "campaign alignment is not supported by this server version");
  }
  if (spec.reconstruct()) {
    return Status(StatusCode::kUnimplemented, "reconstruct",
                  "campaign reconstruction is not supported by this server version");
  }
  ASSIGN_OR_RETURN(plan.viewpoints, Viewpoints(spec));

  plan.rotations = spec.rotations() == 0 ? 1 : spec.rotations();
  if (plan.rotations > kMaxCampaignRotations) {
    return InvalidArgument("rotations", "at most " + std::to_string(kMaxCampaignRotations));
  }
  const uint64_t steps = uint64_t{plan.rotations} * plan.viewpoints.size();
  if (steps > kMaxCampaignSteps) {
    return InvalidArgument("rotations", std::to_string(plan.rotations) + " rotations x " +
                           std::to_string(plan.viewpoints.size()) + " viewpoints = " + std::to_string(steps) +
                           " scans, more than the " + std::to_string(kMaxCampaignSteps) + " a campaign may hold");
  }
  RETURN_IF_ERROR(CheckAngles(spec, plan.rotations));
  ASSIGN_OR_RETURN(const Home home, CheckSceneAndMount(spec, plan.rotations, dry_run, context));
  // Sensor, noise, backend, fields and frame, checked by the parser every step's scan goes through.
  RETURN_IF_ERROR(ParseScanRequest(FirstStepRequest(spec, home), context.options.limits, context.robots).status());
  return plan;
}

}  // namespace

v1::ScanRequest StepScanRequest(const v1::CampaignSpec& spec, const Eigen::VectorXd& joints, double table_angle_deg,
                                uint64_t seed) {
  v1::ScanRequest request;
  request.set_scene_id(spec.scene_id());
  *request.mutable_sensor() = spec.sensor();
  if (spec.has_noise()) *request.mutable_noise() = spec.noise();
  request.set_seed(seed);
  request.set_backend(spec.backend());
  *request.mutable_fields() = spec.fields();
  request.set_frame(spec.frame());
  request.set_table_angle_deg(table_angle_deg);
  v1::RobotPose* robot = request.mutable_robot();
  robot->set_mount_id(spec.mount_id());
  robot->mutable_joint_positions()->Assign(joints.data(), joints.data() + joints.size());
  robot->set_apply_encoder_noise(spec.apply_encoder_noise());
  return request;
}

Status InSpec(const Status& status) {
  if (status.ok() || !NamesAField(status.code())) return status;
  if (!status.field().empty()) return status.WithFieldPrefix("spec");
  // Errors not (yet) built with a field still lead with their path as text.
  return Status(status.code(), "spec." + status.message());
}

StatusOr<CampaignPlan> ValidateCampaign(const v1::CampaignSpec& spec, ServiceContext& context, bool validate_only) {
  auto plan = Validate(spec, validate_only, context);
  if (!plan.ok()) return InSpec(plan.status());
  return plan;
}

}  // namespace vscan::api
