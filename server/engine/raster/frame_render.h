#pragma once
// Draws one frame of a scan into the render thread's framebuffer and reads back what the method needs.

#include <cstdint>
#include <memory>

#include "raster/direct_light.h"
#include "raster/gpu_scene.h"
#include "raster/raster_scanner.h"
#include "raster/render_state.h"
#include "raster/view_planes.h"

namespace vscan::raster {

// Read-back buffers; image row v is buffer row v.
struct RenderedFrame {
  uint32_t width = 0, height = 0;
  std::unique_ptr<uint32_t[]> faces;  // face index + 1, 0 where nothing was hit
  std::unique_ptr<uint32_t[]> depth;  // depth method: GL_UNSIGNED_INT codes (24-bit) or float bits
  std::unique_ptr<uint8_t[]> colour;  // colour method: RGBA8
  std::unique_ptr<float[]> radiance;  // with direct light: its radiance towards the camera, W/(m^2 sr)

  bool empty() const { return faces == nullptr; }
};

struct FrameRequest {
  const sensor::PinholeCamera* camera = nullptr;
  Pose3 world_from_sensor = Pose3::Identity();
  Eigen::Vector3d scene_centre = Eigen::Vector3d::Zero();  // world position of the uploaded origin
  ViewPlanes planes;
  RasterMethod method = RasterMethod::kDepthBuffer;
  DepthFormat depth_format = DepthFormat::kFloat32Reversed;
  // Set: the lit program also writes the direct term's radiance per pixel, read back as radiance.
  const DirectLight* direct_light = nullptr;
};

Status RenderFrame(RenderState& state, const GpuScene& scene, const FrameRequest& request, RenderedFrame& out);

// Attenuation of the camera's light at range r: I = power * cos / Attenuation(r).
inline double Attenuation(const sensor::Lighting& l, double range) {
  return l.constant + (l.linear + l.quadratic * range) * range;
}

}  // namespace vscan::raster
