#pragma once
// A depth image with its camera and pose: what TSDF fusion integrates.

#include <span>
#include <vector>

#include "sensor/camera.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::reconstruction {

// depth[v * width + u] is the z of the surface seen through pixel (u, v)'s centre in the sensor frame
// (x right, y down, z forward), in metres; 0 where the pixel saw nothing.
struct RangeImage {
  sensor::PinholeCamera camera;
  Pose3 world_from_sensor = Pose3::Identity();
  std::vector<float> depth;
};

enum class CloudFrame { kWorld, kSensor };

// Rebuilds the depth image of a scan from its cloud: each point's pixel field places it, its
// position (in `frame`) gives the depth. InvalidArgument names "cloud" when the pixel field is
// missing or a pixel lies outside the camera's image.
StatusOr<RangeImage> RangeImageFromScan(const PointCloud& cloud, const sensor::PinholeCamera& camera,
                                        const Pose3& world_from_sensor, CloudFrame frame = CloudFrame::kWorld);

// Checks sizes, the depth array's length and the pose; messages start with field.
Status ValidateRangeImage(const RangeImage& image, std::string_view field);

}  // namespace vscan::reconstruction
