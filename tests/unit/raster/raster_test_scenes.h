#pragma once
// Renderer, meshes and per-pixel views shared by the raster tests.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "raster/raster_renderer.h"
#include "raycast/raycast_scene.h"
#include "sensor/camera.h"
#include "vscan/common/mesh.h"
#include "vscan/common/point_cloud.h"

namespace vscan::raster::testing {

// One renderer per test process; fails the calling test (and returns nullptr) without EGL/GL.
RasterRenderer* SharedRenderer();

// The bunny of data/meshes/bunny, in metres.
std::shared_ptr<const TriangleMesh> Bunny();

// Index into the cloud of each pixel (u + v * width), -1 where the cloud has no point.
// The cloud must carry kFieldPixel.
std::vector<int64_t> PointOfPixel(const PointCloud& cloud, const sensor::PinholeCamera& camera);

}  // namespace vscan::raster::testing
