#pragma once
// Turns a read-back frame into points: depth or range per covered pixel, unprojected through the
// pixel centre, with the face's normal and instance id. Runs on the calling thread, in parallel.

#include <atomic>
#include <cstdint>
#include <vector>

#include "raster/frame_render.h"
#include "raster/scene_geometry.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::raster {

struct DecodeRequest {
  const sensor::PinholeCamera* camera = nullptr;
  Pose3 world_from_sensor = Pose3::Identity();
  ViewPlanes planes;
  RasterMethod method = RasterMethod::kDepthBuffer;
  DepthFormat depth_format = DepthFormat::kFloat32Reversed;
  uint32_t fields = kFieldsDefault;
  bool sensor_frame = false;
  const std::atomic<bool>* cancel = nullptr;
};

struct DecodedFrame {
  PointCloud cloud;
  // Point i's pixel's radiance from the direct light, when the frame was rendered lit; else empty.
  std::vector<float> direct_radiance;
  double min_range = 0, max_range = 0;
};

StatusOr<DecodedFrame> DecodeFrame(const RenderedFrame& frame, const SceneFaces& faces, const DecodeRequest& request);

}  // namespace vscan::raster
