#include "api/scan/scan_request.h"

#include <cmath>

#include "api/scan/measurement_request.h"
#include "api/scan/returned_light_request.h"
#include "api/scan/sensor_request.h"
#include "api/transport/validate.h"
#include "service/robot/robot_placement.h"
#include "vscan/common/chunk_limits.h"
#include "vscan/common/physical_limits.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

// The sensor pose of a robot-held scan, from the mount and the commanded joints.
StatusOr<service::RobotPlacement> PlaceRobotSensor(const v1::ScanRequest& request,
                                                   robot_registry::RobotRegistry& robots,
                                                   Pose3* world_from_sensor) {
  const v1::RobotPose& pose = request.robot();
  RETURN_IF_ERROR(RequireId(pose.mount_id(), "robot.mount_id"));
  const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(pose.joint_positions().data(),
                                                              pose.joint_positions().size());
  const std::optional<uint64_t> noise_seed =
      pose.apply_encoder_noise() ? std::optional<uint64_t>(request.seed()) : std::nullopt;
  auto placed = service::PlaceRobotSensor(robots, request.scene_id(), pose.mount_id(), q, noise_seed, world_from_sensor);
  if (!placed.ok() && !placed.status().field().empty()) return placed.status().WithFieldPrefix("robot");
  return placed;
}

}  // namespace

StatusOr<ScanBackend> BackendFromProto(int backend) {
  switch (backend) {
    case v1::SCAN_BACKEND_UNSPECIFIED:
    case v1::SCAN_BACKEND_RAYCAST: return ScanBackend::kRaycast;
    case v1::SCAN_BACKEND_RASTER_DEPTH: return ScanBackend::kRasterDepth;
    case v1::SCAN_BACKEND_RASTER_COLOUR: return ScanBackend::kRasterColour;
    default: return InvalidArgument("backend", "unknown value " + std::to_string(backend));
  }
}

StatusOr<raycast::ScanFrame> FrameFromProto(int frame) {
  switch (frame) {
    case v1::FRAME_UNSPECIFIED:
    case v1::FRAME_WORLD: return raycast::ScanFrame::kWorld;
    case v1::FRAME_SENSOR: return raycast::ScanFrame::kSensor;
    default: return InvalidArgument("frame", "unknown value " + std::to_string(frame));
  }
}

StatusOr<ScanPlan> ParseScanRequest(const v1::ScanRequest& request, const service::Limits& limits,
                                    robot_registry::RobotRegistry& robots) {
  ScanPlan plan;
  RETURN_IF_ERROR(RequireId(request.scene_id(), "scene_id"));
  plan.scene_id = request.scene_id();

  ASSIGN_OR_RETURN(const SensorSettings sensing, SensorFromProto(request.sensor(), limits));
  plan.camera = sensing.camera;

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
      return InvalidArgument("pose", "required");
  }

  ASSIGN_OR_RETURN(plan.backend, BackendFromProto(request.backend()));

  ASSIGN_OR_RETURN(plan.fields, FieldsFromProto(request.fields(), "fields"));
  ASSIGN_OR_RETURN(plan.measurement, MeasurementFromProto(request, plan.fields));
  ASSIGN_OR_RETURN(plan.measurement.noise, NoiseFromProto(request.noise()));
  if (sensing.preset_noise && !request.has_noise()) plan.measurement.noise = *sensing.preset_noise;
  plan.measurement.distortion = sensing.distortion;
  plan.measurement.structured_light = sensing.structured_light;
  if (request.has_returned_light()) {
    ASSIGN_OR_RETURN(plan.measurement.returned_light,
                     ReturnedLightFromProto(request.returned_light(), plan.camera, sensing.structured_light,
                                            sensing.modulation_frequency_hz, sensing.illumination));
  }
  plan.measurement.seed = request.seed();

  ASSIGN_OR_RETURN(plan.frame, FrameFromProto(request.frame()));
  plan.ground_truth = request.ground_truth();
  plan.pixel_images = request.pixel_images();

  if (request.chunk_bytes() != 0) {
    if (request.chunk_bytes() < kMinChunkBytes || request.chunk_bytes() > kMaxChunkBytes) {
      return InvalidArgument("chunk_bytes", "must be between " + std::to_string(kMinChunkBytes) + " and " +
                             std::to_string(kMaxChunkBytes));
    }
    plan.chunk_bytes = request.chunk_bytes();
  }

  if (request.has_table_angle_deg()) {
    if (!std::isfinite(request.table_angle_deg())) return InvalidArgument("table_angle_deg", "NaN or infinite");
    plan.table_angle_deg = request.table_angle_deg();
  }
  return plan;
}

}  // namespace vscan::api
