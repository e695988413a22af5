#pragma once
// What every strip of one scan shares: the scene, the camera's rays and the requested fields.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <embree3/rtcore.h>

#include "raycast/raycast_scene.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"

namespace vscan::raycast {

inline constexpr uint32_t kPacketSide = 4;
inline constexpr uint32_t kPacketLanes = kPacketSide * kPacketSide;

// Fixed for the whole scan, in single precision like Embree.
struct ScanSetup {
  RTCScene scene = nullptr;
  // Instance id per Embree geometry, then a 0 that any other geometry id maps to.
  std::vector<uint32_t> instance_of_geometry;
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t fields = kFieldPosition;
  bool sensor_frame = false;
  float near = 0, far = 0;
  Eigen::Matrix3f world_from_sensor_rotation;
  Eigen::Vector3f origin;
  // Sensor-frame x and y of the z = 1 rays. packet_x holds, for each packet of four columns,
  // the x of its 16 lanes (row-major in the packet); row_y is per row. Both padded to packets.
  uint32_t padded_width = 0;
  std::vector<float> packet_x;
  std::vector<float> row_y;
  float power = 1, constant = 1, linear = 0, quadratic = 0;

  // World direction of the ray with sensor-frame direction (x, y, 1).
  void WorldDirection(float x, float y, float& dx, float& dy, float& dz) const {
    const Eigen::Matrix3f& r = world_from_sensor_rotation;
    dx = r(0, 0) * x + r(0, 1) * y + r(0, 2);
    dy = r(1, 0) * x + r(1, 1) * y + r(1, 2);
    dz = r(2, 0) * x + r(2, 1) * y + r(2, 2);
  }
};

// Precomputes the scan's rays and copies what the strips need; the camera must be valid.
ScanSetup MakeScanSetup(const RaycastScene& scene, const sensor::PinholeCamera& camera,
                        const Pose3& world_from_sensor, const ScanOptions& options);

}  // namespace vscan::raycast
