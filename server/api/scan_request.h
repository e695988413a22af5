#pragma once
// A validated ScanRequest in engine terms.

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "api/server_options.h"
#include "capture/measurement_spec.h"
#include "raycast/scanner.h"
#include "robots/robot_registry.h"
#include "sensor/camera.h"
#include "sensor/measurement.h"
#include "vscan/common/chunk_limits.h"
#include "vscan/common/pose.h"
#include "vscan/v1/scan.pb.h"

namespace vscan::api {

// A robot-held sensor: where the commanded joints put it and the joints the arm reached.
struct RobotPlacement {
  Pose3 commanded_world_from_sensor = Pose3::Identity();
  Eigen::VectorXd achieved_joint_positions;
  std::string mount_id;
};

enum class ScanBackend { kRaycast, kRasterDepth, kRasterColour };

struct ScanPlan {
  std::string scene_id;
  ScanBackend backend = ScanBackend::kRaycast;
  sensor::PinholeCamera camera;
  Pose3 world_from_sensor = Pose3::Identity();
  raycast::ScanFrame frame = raycast::ScanFrame::kWorld;
  uint32_t fields = kFieldsDefault;
  size_t chunk_bytes = kDefaultChunkBytes;
  std::optional<double> table_angle_deg;
  // Distortion, noise, artefacts, rejected rays and normal estimation on top of the clean scan
  // (its fields equal the plan's).
  capture::MeasurementSpec measurement;
  // Set for robot-held scans; world_from_sensor is then the pose the arm reached.
  std::optional<RobotPlacement> robot;
};

// The request's backend and frame enums (errors name "backend" and "frame").
StatusOr<ScanBackend> BackendFromProto(int backend);
StatusOr<raycast::ScanFrame> FrameFromProto(int frame);

// Checks every field of the request; the first problem found is returned, naming its field.
// Robot placements are resolved through robots.
StatusOr<ScanPlan> ParseScanRequest(const v1::ScanRequest& request, const Limits& limits,
                                    robots::RobotRegistry& robots);

}  // namespace vscan::api
