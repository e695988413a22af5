#pragma once
// Scanning by rasterisation, the two methods of the paper: read back the depth buffer, or a colour
// buffer into which a shader writes the ray length. Output conventions match raycast::Scan.

#include <atomic>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "raster/direct_light.h"
#include "raster/raster_renderer.h"
#include "raycast/raycast_scene.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::raster {

enum class RasterMethod {
  // Depth z from the depth buffer, linearised and unprojected through the pixel centre.
  kDepthBuffer,
  // Range from a 16-bit code over [near_range, far_range] in G and B, intensity in R (8 bits).
  kColourBuffer,
};

enum class DepthFormat {
  kFixed24,          // 24-bit fixed point, d = 0 at near and 1 at far (the paper's setting)
  kFloat32,          // 32-bit float, same mapping
  kFloat32Reversed,  // 32-bit float, d = 1 at near and 0 at far: near-constant relative precision
};

struct RasterOptions {
  uint32_t fields = kFieldsDefault;
  raycast::ScanFrame frame = raycast::ScanFrame::kWorld;
  // Near/far planes hug the scene's bounding box along the view, inside the camera's near/far;
  // false uses the camera's near/far as they are.
  bool hug_scene_bounds = true;
  DepthFormat depth_format = DepthFormat::kFloat32Reversed;
  // Bound on width * height; larger frames are ResourceExhausted.
  uint64_t max_pixels = uint64_t{1} << 26;
  // Checked before rendering and while decoding; when it turns true the scan stops with CANCELLED.
  const std::atomic<bool>* cancel = nullptr;
};

struct RasterStats {
  uint64_t pixels = 0;
  uint64_t points = 0;
  double min_range = 0;
  double max_range = 0;
  double near = 0, far = 0;              // depth planes of the projection
  double near_range = 0, far_range = 0;  // span of the colour method's range code
  bool scene_uploaded = false;           // false when the cached upload was reused
  double upload_ms = 0;
  double render_ms = 0;  // on the render thread: draw and read back
  double decode_ms = 0;  // on the calling thread: pixels to points
  double elapsed_ms = 0;
};

// Renders instances (uploaded once per scene_key and reused while the instances stay the same:
// same mesh objects, poses, scales and ids) from world_from_sensor and returns the covered pixels
// as points in row-major pixel order, depth within [camera.near, camera.far], normals unit and
// facing the sensor.
StatusOr<PointCloud> RasterScan(RasterRenderer& renderer, const std::string& scene_key,
                                std::span<const raycast::SceneInstance> instances,
                                const sensor::PinholeCamera& camera, const Pose3& world_from_sensor,
                                RasterMethod method, const RasterOptions& options, RasterStats* stats = nullptr);

struct LitCloud {
  PointCloud cloud;
  // Per point, the radiance (W / (m^2 sr)) its pixel's fragment shader computed of light's direct
  // term towards the camera (float; the same formulas as sensor::DirectRadiance).
  std::vector<float> direct_radiance;
};

// RasterScan with the returned light's direct term evaluated in the shaders (an extra R32F target).
StatusOr<LitCloud> RasterScanLit(RasterRenderer& renderer, const std::string& scene_key,
                                 std::span<const raycast::SceneInstance> instances,
                                 const sensor::PinholeCamera& camera, const Pose3& world_from_sensor,
                                 RasterMethod method, const DirectLight& light, const RasterOptions& options,
                                 RasterStats* stats = nullptr);

}  // namespace vscan::raster
