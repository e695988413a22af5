#pragma once
// The ray-cast depth scanner: one ray per pixel in coherent 4x4 packets over all cores.

#include <atomic>
#include <cstdint>

#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"
#include "raycast/raycast_scene.h"
#include "raycast/row_sink.h"
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
  // Image rows cast and delivered; fewer than the camera's height when the scan was cancelled.
  uint32_t rows = 0;
};

// Points in row-major pixel order; normals are unit and face the sensor.
StatusOr<PointCloud> Scan(const RaycastScene& scene, const sensor::PinholeCamera& camera,
                          const Pose3& world_from_sensor, const ScanOptions& options, ScanStats* stats = nullptr);

// The same scan, streamed: the sink gets the points row block by row block, in row-major pixel
// order, while later rows are cast (the blocks joined are Scan's cloud, bit for bit). When the sink
// has no room the cast pauses. stats, when given, is filled also when the scan is cancelled.
Status ScanRows(const RaycastScene& scene, const sensor::PinholeCamera& camera, const Pose3& world_from_sensor,
                const ScanOptions& options, RowSink& sink, ScanStats* stats = nullptr);

}  // namespace vscan::raycast
