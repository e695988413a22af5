#include "api/scan_request.h"

#include <cmath>

#include "api/validate.h"
#include "sensor/presets.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr size_t kMinChunkBytes = 16u << 10;
constexpr size_t kMaxChunkBytes = 3u << 20;  // stays under gRPC's default 4 MiB receive limit
constexpr double kDefaultNear = 0.05;
constexpr double kDefaultFar = 10.0;

StatusOr<sensor::DepthNoise> NoiseFromProto(const v1::NoiseSpec& n) {
  if (n.outlier_rate() != 0) return Unimplemented("noise.outlier_rate: outliers are not supported by this server version");
  if (n.grazing_limit_deg() != 0) {
    return Unimplemented("noise.grazing_limit_deg: grazing drop-out is not supported by this server version");
  }
  if (n.flying_pixels()) return Unimplemented("noise.flying_pixels: not supported by this server version");
  sensor::DepthNoise noise;
  noise.sigma_a = n.sigma_a();
  noise.sigma_b = n.sigma_b();
  noise.sigma_c = n.sigma_c();
  noise.along_ray = n.along_ray();
  noise.depth_step = n.depth_step_m();
  noise.min_intensity = n.min_intensity();
  RETURN_IF_ERROR(sensor::ValidateNoise(noise, "noise"));
  return noise;
}

StatusOr<sensor::LensDistortion> DistortionFromProto(const v1::Distortion& d) {
  sensor::LensDistortion distortion{d.k1(), d.k2(), d.k3(), d.p1(), d.p2()};
  RETURN_IF_ERROR(sensor::ValidateDistortion(distortion, "sensor.pinhole.distortion"));
  return distortion;
}

StatusOr<sensor::PinholeCamera> CameraFromProto(const v1::PinholeCamera& p, const Limits& limits) {
  const std::string field = "sensor.pinhole";
  const double near = p.near() == 0 ? kDefaultNear : p.near();
  const double far = p.far() == 0 ? kDefaultFar : p.far();
  if (p.width() == 0) return InvalidArgument(field + ".width: must be positive");
  if (p.height() == 0) return InvalidArgument(field + ".height: must be positive");
  sensor::PinholeCamera camera;
  switch (p.projection_case()) {
    case v1::PinholeCamera::kIntrinsics: {
      const auto& k = p.intrinsics();
      camera.width = p.width();
      camera.height = p.height();
      camera.fx = k.fx();
      camera.fy = k.fy();
      camera.cx = k.cx();
      camera.cy = k.cy();
      camera.near = near;
      camera.far = far;
      break;
    }
    case v1::PinholeCamera::kHorizontalFovDeg: {
      const double fov = p.horizontal_fov_deg();
      if (!std::isfinite(fov) || fov <= 0 || fov >= 180) {
        return InvalidArgument(field + ".horizontal_fov_deg: must be in (0, 180)");
      }
      camera = sensor::CameraFromFov(p.width(), p.height(), fov, near, far);
      break;
    }
    case v1::PinholeCamera::PROJECTION_NOT_SET:
      return InvalidArgument(field + ": intrinsics or horizontal_fov_deg required");
  }
  if (p.has_lighting()) {
    const auto& l = p.lighting();
    camera.lighting = {l.power(), l.constant(), l.linear(), l.quadratic()};
  }
  RETURN_IF_ERROR(sensor::ValidateCamera(camera, field, limits.max_rays_per_scan));
  return camera;
}

// The sensor pose of a robot-held scan, from the mount and the commanded joints.
StatusOr<RobotPlacement> PlaceRobotSensor(const v1::ScanRequest& request, robots::RobotRegistry& robots,
                                          Pose3* world_from_sensor) {
  const v1::RobotPose& pose = request.robot();
  RETURN_IF_ERROR(RequireId(pose.mount_id(), "robot.mount_id"));
  auto mounted = robots.Mount(pose.mount_id());
  if (!mounted.ok()) {
    const Status& s = mounted.status();
    return s.message().starts_with("mount_id:") ? Status(s.code(), "robot." + s.message()) : s;
  }
  if (mounted->mount.scene_id != request.scene_id()) {
    return FailedPrecondition("robot.mount_id: mount '" + pose.mount_id() + "' is in scene '" +
                              mounted->mount.scene_id + "', not in scene_id '" + request.scene_id() + "'");
  }
  const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(pose.joint_positions().data(),
                                                              pose.joint_positions().size());
  const std::optional<uint64_t> noise_seed =
      pose.apply_encoder_noise() ? std::optional<uint64_t>(request.seed()) : std::nullopt;
  ASSIGN_OR_RETURN(const robots::ArmState state, robots::CommandJoints(*mounted->chain, mounted->placement, q,
                                                                       "robot.joint_positions", noise_seed));
  *world_from_sensor = state.achieved_pose;
  return RobotPlacement{state.commanded_pose, state.achieved};
}

}  // namespace

StatusOr<ScanPlan> ParseScanRequest(const v1::ScanRequest& request, const Limits& limits,
                                    robots::RobotRegistry& robots) {
  ScanPlan plan;
  std::optional<sensor::DepthNoise> preset_noise;
  RETURN_IF_ERROR(RequireId(request.scene_id(), "scene_id"));
  plan.scene_id = request.scene_id();

  switch (request.sensor().kind_case()) {
    case v1::SensorSpec::kPinhole: {
      ASSIGN_OR_RETURN(plan.camera, CameraFromProto(request.sensor().pinhole(), limits));
      ASSIGN_OR_RETURN(plan.distortion, DistortionFromProto(request.sensor().pinhole().distortion()));
      break;
    }
    case v1::SensorSpec::kPreset: {
      const sensor::SensorPreset* preset = sensor::FindSensorPreset(request.sensor().preset());
      if (!preset) {
        return NotFound("sensor.preset: no preset '" + request.sensor().preset() + "' (ListSensorPresets lists them)");
      }
      plan.camera = preset->camera;
      RETURN_IF_ERROR(sensor::ValidateCamera(plan.camera, "sensor.preset", limits.max_rays_per_scan));
      preset_noise = preset->noise;
      break;
    }
    case v1::SensorSpec::kStructuredLight:
      return Unimplemented("sensor.structured_light: not supported by this server version");
    case v1::SensorSpec::KIND_NOT_SET:
      return InvalidArgument("sensor: required (pinhole)");
  }

  switch (request.placement_case()) {
    case v1::ScanRequest::kPose: {
      ASSIGN_OR_RETURN(plan.world_from_sensor, PoseFromProto(request.pose(), "pose"));
      break;
    }
    case v1::ScanRequest::kRobot: {
      ASSIGN_OR_RETURN(plan.robot, PlaceRobotSensor(request, robots, &plan.world_from_sensor));
      break;
    }
    case v1::ScanRequest::PLACEMENT_NOT_SET:
      return InvalidArgument("pose: required");
  }

  switch (request.backend()) {
    case v1::SCAN_BACKEND_UNSPECIFIED:
    case v1::SCAN_BACKEND_RAYCAST: plan.backend = ScanBackend::kRaycast; break;
    case v1::SCAN_BACKEND_RASTER_DEPTH: plan.backend = ScanBackend::kRasterDepth; break;
    case v1::SCAN_BACKEND_RASTER_COLOUR: plan.backend = ScanBackend::kRasterColour; break;
    default:
      return InvalidArgument("backend: unknown value " + std::to_string(request.backend()));
  }

  ASSIGN_OR_RETURN(plan.noise, NoiseFromProto(request.noise()));
  if (preset_noise && !request.has_noise()) plan.noise = *preset_noise;
  plan.seed = request.seed();

  ASSIGN_OR_RETURN(plan.fields, FieldsFromProto(request.fields(), "fields"));

  switch (request.frame()) {
    case v1::FRAME_UNSPECIFIED:
    case v1::FRAME_WORLD: plan.frame = raycast::ScanFrame::kWorld; break;
    case v1::FRAME_SENSOR: plan.frame = raycast::ScanFrame::kSensor; break;
    default: return InvalidArgument("frame: unknown value " + std::to_string(request.frame()));
  }

  if (request.chunk_bytes() != 0) {
    if (request.chunk_bytes() < kMinChunkBytes || request.chunk_bytes() > kMaxChunkBytes) {
      return InvalidArgument("chunk_bytes: must be between " + std::to_string(kMinChunkBytes) + " and " +
                             std::to_string(kMaxChunkBytes));
    }
    plan.chunk_bytes = request.chunk_bytes();
  }

  if (request.has_table_angle_deg()) {
    if (!std::isfinite(request.table_angle_deg())) return InvalidArgument("table_angle_deg: NaN or infinite");
    plan.table_angle_deg = request.table_angle_deg();
  }
  return plan;
}

}  // namespace vscan::api
