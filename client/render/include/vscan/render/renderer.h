#pragma once
// Draws a cloud (screen-space splats) or a mesh (headlight Lambert shading) into an image, on a
// headless EGL context of its own made current on the calling thread for the call.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"
#include "vscan/render/image.h"
#include "vscan/render/view.h"

namespace vscan::render {

struct RenderOptions {
  uint32_t width = 1024;
  uint32_t height = 768;
  // Splat diameter in pixels; splats of 3 pixels and more are round, smaller ones square.
  float point_size = 2.0f;
  std::array<uint8_t, 3> background = {255, 255, 255};
};

// Light grey, lit by a light at the eye: ambient + (1 - ambient) * |cos(angle to the eye)|.
inline constexpr float kMeshGrey = 0.8f;
inline constexpr float kMeshAmbient = 0.12f;

// colours holds one RGB in [0, 1] per point. bounds enclose the points (near and far planes).
StatusOr<Image> RenderCloud(const PointCloud& cloud, const std::vector<Eigen::Vector3f>& colours,
                            const Bounds& bounds, const View& view, const RenderOptions& options);

StatusOr<Image> RenderMesh(const TriangleMesh& mesh, const Bounds& bounds, const View& view,
                           const RenderOptions& options);

}  // namespace vscan::render
