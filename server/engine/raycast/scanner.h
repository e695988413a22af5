#pragma once
// The ray-cast depth scanner: one ray per pixel in coherent 4x4 packets over all cores.

#include <atomic>
#include <cstdint>

#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"
#include "raycast/raycast_scene.h"
#include "sensor/camera.h"

namespace vscan::raycast {

enum class ScanFrame { kWorld, kSensor };

struct ScanOptions {
  uint32_t fields = kFieldsDefault;
  ScanFrame frame = ScanFrame::kWorld;
  // Polled between packets; when it turns true the scan stops with CANCELLED.
  const std::atomic<bool>* cancel = nullptr;
};

struct ScanStats {
  uint64_t rays = 0;
  uint64_t points = 0;
  double min_range = 0;
  double max_range = 0;
  double elapsed_ms = 0;
};

// Points in row-major pixel order; normals are unit and face the sensor.
StatusOr<PointCloud> Scan(const RaycastScene& scene, const sensor::PinholeCamera& camera,
                          const Pose3& world_from_sensor, const ScanOptions& options, ScanStats* stats = nullptr);

}  // namespace vscan::raycast
