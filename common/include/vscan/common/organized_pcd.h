#pragma once
// A scan as the range image it is: an organised PCD of WIDTH x HEIGHT points, row by row, each point
// at its pixel (v * width + u), NaN where no point came back, and the sensor pose in VIEWPOINT; the
// layout PCL's organised algorithms (isOrganized(), at(u, v), integral-image normals) expect.

#include <cstdint>
#include <string>

#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan {

struct RangeImageLayout {
  uint32_t width = 0;
  uint32_t height = 0;
  // Where the points were seen from, in the cloud's frame (world_from_sensor for a world-frame
  // scan, identity for a sensor-frame one).
  Pose3 viewpoint = Pose3::Identity();
};

// width * height points: point i of `cloud` at index pixels[i]; the holes have NaN in every float
// field, 0 in instance and status, and their own index as pixel. INVALID_ARGUMENT without the pixel
// field, for an empty image, a pixel outside it, or two points on one pixel.
StatusOr<PointCloud> OrganizeByPixel(const PointCloud& cloud, uint32_t width, uint32_t height);

// Writes OrganizeByPixel's cloud as binary PCD with WIDTH, HEIGHT and VIEWPOINT (tx ty tz qw qx qy qz)
// set, into a temporary file renamed into place.
Status WriteOrganizedPcd(const PointCloud& cloud, const RangeImageLayout& image, const std::string& path);

}  // namespace vscan
