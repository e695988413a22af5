#pragma once
// The paper's outliers: a seeded fraction of the surviving rays is re-cast with its direction
// tilted within a cone and/or its origin moved within a ball; the point is the perturbed ray's hit,
// reported at the original pixel.

#include <cstdint>
#include <vector>

#include "capture/measurement_spec.h"
#include "raycast/raycast_scene.h"
#include "sensor/camera.h"
#include "vscan/common/pose.h"

namespace vscan::capture {

struct OutlierCounts {
  uint64_t outliers = 0;  // pixels now reporting a perturbed hit
  uint64_t missed = 0;    // perturbed rays that hit nothing in range: the pixel is dropped
};

// Picks the outlier pixels among status == MEASURED with a per-pixel draw below spec.outliers.rate,
// casts their perturbed rays (up to max_distance) and writes the hits into measured (sensor frame)
// with status OUTLIER; a miss, or a hit whose depth lies outside [camera.near, camera.far], gets
// status UNSPECIFIED (dropped).
OutlierCounts CastOutliers(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                           const Pose3& world_from_sensor, const PointCloud& clean, const MeasurementSpec& spec,
                           float max_distance, std::vector<uint8_t>& status,
                           std::vector<Eigen::Vector3f>& measured);

}  // namespace vscan::capture
