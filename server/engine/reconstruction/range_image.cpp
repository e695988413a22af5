#include "reconstruction/range_image.h"

#include <string>

namespace vscan::reconstruction {

StatusOr<RangeImage> RangeImageFromScan(const PointCloud& cloud, const sensor::PinholeCamera& camera,
                                        const Pose3& world_from_sensor, CloudFrame frame) {
  if (!cloud.Has(kFieldPixel) || cloud.pixels.size() != cloud.size()) {
    return InvalidArgument("cloud: the pixel field is needed to rebuild a depth image");
  }
  RangeImage image{camera, world_from_sensor, std::vector<float>(camera.pixel_count(), 0.0f)};
  const Eigen::Isometry3f sensor_from_world = world_from_sensor.inverse().cast<float>();
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.pixels[i] >= image.depth.size()) {
      return InvalidArgument("cloud: pixel " + std::to_string(cloud.pixels[i]) + " of point " + std::to_string(i) +
                             " lies outside the " + std::to_string(camera.width) + "x" +
                             std::to_string(camera.height) + " image");
    }
    const Eigen::Vector3f p = frame == CloudFrame::kWorld ? sensor_from_world * cloud.positions[i] : cloud.positions[i];
    if (p.allFinite() && p.z() > 0) image.depth[cloud.pixels[i]] = p.z();
  }
  return image;
}

Status ValidateRangeImage(const RangeImage& image, std::string_view field) {
  const std::string f(field);
  const sensor::PinholeCamera& c = image.camera;
  if (c.width == 0 || c.height == 0) return InvalidArgument(f + ".camera: empty image");
  if (!(c.fx > 0) || !(c.fy > 0) || !std::isfinite(c.cx) || !std::isfinite(c.cy)) {
    return InvalidArgument(f + ".camera: fx and fy must be positive, cx and cy finite");
  }
  if (image.depth.size() != c.pixel_count()) {
    return InvalidArgument(f + ".depth: " + std::to_string(image.depth.size()) + " values for " +
                           std::to_string(c.pixel_count()) + " pixels");
  }
  if (!image.world_from_sensor.matrix().allFinite()) return InvalidArgument(f + ".world_from_sensor: not finite");
  return Status::Ok();
}

}  // namespace vscan::reconstruction
