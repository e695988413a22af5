#pragma once
// A scan in engine terms: what a ScanRequest asks for once it has been checked.

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "capture/measurement_spec.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"
#include "service/robot/robot_placement.h"
#include "vscan/common/chunk_limits.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"

namespace vscan::service {

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
  // Each scene object in view with its true pose and visible fraction (the whole-cloud path).
  bool ground_truth = false;
  // The camera's per-pixel images (ScanOutcome.images): every ray is measured with its status, and
  // the rejected ones are dropped afterwards unless measurement.include_rejected.
  bool pixel_images = false;
};

}  // namespace vscan::service
