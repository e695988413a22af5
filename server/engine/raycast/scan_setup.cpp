#include "raycast/scan_setup.h"

#include <algorithm>

#include "raycast/embree_scene.h"

namespace vscan::raycast {

ScanSetup MakeScanSetup(const RaycastScene& scene, const sensor::PinholeCamera& camera,
                        const Pose3& world_from_sensor, const ScanOptions& options) {
  ScanSetup s;
  const auto& embree = EmbreeOf(scene);
  s.scene = embree.scene;
  s.instance_of_geometry = embree.instance_of_geometry;
  s.instance_of_geometry.push_back(0);
  s.width = camera.width;
  s.height = camera.height;
  s.fields = options.fields | kFieldPosition;
  s.sensor_frame = options.frame == ScanFrame::kSensor;
  s.near = static_cast<float>(camera.near);
  s.far = static_cast<float>(camera.far);
  s.world_from_sensor_rotation = world_from_sensor.linear().cast<float>();
  s.origin = world_from_sensor.translation().cast<float>();
  const auto padded = [](uint32_t n) { return (n + kPacketSide - 1) / kPacketSide * kPacketSide; };
  // Padding lanes repeat the last pixel so their directions stay finite.
  s.padded_width = padded(camera.width);
  s.packet_x.resize(size_t{kPacketSide} * s.padded_width);
  for (uint32_t u0 = 0; u0 < s.padded_width; u0 += kPacketSide) {
    for (uint32_t i = 0; i < kPacketLanes; ++i) {
      const uint32_t u = std::min(u0 + i % kPacketSide, camera.width - 1);
      s.packet_x[size_t{kPacketSide} * u0 + i] = camera.RayThroughPixel(u, 0).x();
    }
  }
  s.row_y.resize(padded(camera.height));
  for (uint32_t v = 0; v < s.row_y.size(); ++v) {
    s.row_y[v] = camera.RayThroughPixel(0, std::min(v, camera.height - 1)).y();
  }
  s.power = static_cast<float>(camera.lighting.power);
  s.constant = static_cast<float>(camera.lighting.constant);
  s.linear = static_cast<float>(camera.lighting.linear);
  s.quadratic = static_cast<float>(camera.lighting.quadratic);
  return s;
}

}  // namespace vscan::raycast
