#include "service/datasets/format/scene_images.h"

#include <cmath>
#include <limits>
#include <unordered_map>

namespace vscan::service::dataset {
namespace {

std::unordered_map<uint32_t, uint16_t> IndexByInstance(const DatasetFrame& frame) {
  std::unordered_map<uint32_t, uint16_t> index;
  for (size_t i = 0; i < frame.objects.size(); ++i) index.emplace(frame.objects[i].instance_id, uint16_t(i + 1));
  return index;
}

bool PositiveFinite(double x) { return std::isfinite(x) && x > 0; }

}  // namespace

StatusOr<std::vector<uint16_t>> QuantizeDepth(const DatasetFrame& frame, double depth_scale_mm) {
  std::vector<uint16_t> units(frame.depth_m.size(), 0);
  for (size_t i = 0; i < units.size(); ++i) {
    const double depth = frame.depth_m[i];
    if (std::isnan(depth) || depth == 0) continue;
    const double value = std::round(depth * 1000.0 / depth_scale_mm);
    if (!(value >= 0 && value <= std::numeric_limits<uint16_t>::max())) {
      const size_t width = frame.camera.width;
      return OutOfRange("depth_m", "the depth " + std::to_string(depth) + " m at pixel (" +
                                       std::to_string(i % width) + ", " + std::to_string(i / width) +
                                       ") does not fit 16 bits at a depth scale of " +
                                       std::to_string(depth_scale_mm) + " mm");
    }
    units[i] = static_cast<uint16_t>(value);
  }
  return units;
}

std::vector<uint16_t> ObjectIndexImage(const DatasetFrame& frame) {
  const auto index = IndexByInstance(frame);
  std::vector<uint16_t> image(frame.instance_ids.size(), 0);
  for (size_t i = 0; i < image.size(); ++i) {
    const auto found = index.find(frame.instance_ids[i]);
    if (frame.instance_ids[i] != 0 && found != index.end()) image[i] = found->second;
  }
  return image;
}

std::vector<VisibleStats> VisibleStatsOf(const std::vector<uint16_t>& object_index, const std::vector<uint16_t>& depth,
                                         uint32_t width, size_t object_count) {
  struct Extent {
    int64_t min_x = std::numeric_limits<int64_t>::max(), min_y = min_x, max_x = -1, max_y = -1;
  };
  std::vector<Extent> extents(object_count);
  std::vector<VisibleStats> stats(object_count);
  for (size_t i = 0; i < object_index.size(); ++i) {
    if (object_index[i] == 0) continue;
    const size_t object = object_index[i] - 1u;
    const int64_t x = int64_t(i % width), y = int64_t(i / width);
    Extent& e = extents[object];
    e.min_x = std::min(e.min_x, x);
    e.min_y = std::min(e.min_y, y);
    e.max_x = std::max(e.max_x, x);
    e.max_y = std::max(e.max_y, y);
    ++stats[object].pixels;
    if (depth[i] != 0) ++stats[object].with_depth;
  }
  for (size_t object = 0; object < object_count; ++object) {
    const Extent& e = extents[object];
    if (e.max_x < 0) continue;
    stats[object].box = {int32_t(e.min_x), int32_t(e.min_y), int32_t(e.max_x - e.min_x), int32_t(e.max_y - e.min_y)};
  }
  return stats;
}

std::vector<uint8_t> VisibleMask(const std::vector<uint16_t>& object_index, size_t object) {
  std::vector<uint8_t> mask(object_index.size(), 0);
  for (size_t i = 0; i < mask.size(); ++i) {
    if (object_index[i] == object + 1) mask[i] = 255;
  }
  return mask;
}

std::vector<uint8_t> AloneMask(const GroundTruthObject& object, size_t pixels) {
  std::vector<uint8_t> mask(pixels, 0);
  for (const uint32_t p : object.alone_mask) {
    if (p < pixels) mask[p] = 255;
  }
  return mask;
}

Status CheckFrame(const DatasetFrame& frame) {
  const CameraIntrinsics& camera = frame.camera;
  if (camera.width == 0 || camera.height == 0) return InvalidArgument("camera", "has no pixels");
  if (!PositiveFinite(camera.fx) || !PositiveFinite(camera.fy) || !std::isfinite(camera.cx) ||
      !std::isfinite(camera.cy)) {
    return InvalidArgument("camera", "fx and fy must be positive, cx and cy finite");
  }
  if (!frame.world_from_camera.matrix().allFinite()) return InvalidArgument("world_from_camera", "is not finite");
  const size_t pixels = size_t{camera.width} * camera.height;
  if (frame.depth_m.size() != pixels) return InvalidArgument("depth_m", "must hold width * height values");
  if (frame.instance_ids.size() != pixels) return InvalidArgument("instance_ids", "must hold width * height values");
  if (!frame.reasons.empty() && frame.reasons.size() != pixels) {
    return InvalidArgument("reasons", "must be empty or hold width * height values");
  }
  if (!frame.gray.empty() && frame.gray.size() != pixels) {
    return InvalidArgument("gray", "must be empty or hold width * height values");
  }
  if (frame.objects.size() > std::numeric_limits<uint16_t>::max()) {
    return InvalidArgument("objects", "more than 65535 do not fit the 16-bit object index image");
  }
  std::unordered_map<uint32_t, uint64_t> counts;
  for (const uint32_t id : frame.instance_ids) {
    if (id != 0) ++counts[id];
  }
  std::unordered_map<uint32_t, size_t> first_with_instance;
  for (size_t i = 0; i < frame.objects.size(); ++i) {
    const GroundTruthObject& object = frame.objects[i];
    const std::string path = "objects[" + std::to_string(i) + "]";
    if (object.obj_id == 0) return InvalidArgument(path + ".obj_id", "part types count from 1");
    if (object.instance_id == 0) return InvalidArgument(path + ".instance_id", "0 stands for no instance");
    const auto [first, inserted] = first_with_instance.emplace(object.instance_id, i);
    if (!inserted) {
      return InvalidArgument(path + ".instance_id", "repeats objects[" + std::to_string(first->second) + "]");
    }
    if (!object.world_from_object.matrix().allFinite()) {
      return InvalidArgument(path + ".world_from_object", "is not finite");
    }
    for (const uint32_t p : object.alone_mask) {
      if (p >= pixels) return InvalidArgument(path + ".alone_mask", "pixel " + std::to_string(p) + " is outside the image");
    }
    const auto found = counts.find(object.instance_id);
    const uint64_t seen = found == counts.end() ? 0 : found->second;
    if (seen != object.visible_pixels) {
      return InvalidArgument(path + ".visible_pixels", std::to_string(object.visible_pixels) +
                                                         " but the instance image shows " + std::to_string(seen));
    }
  }
  return Status::Ok();
}

}  // namespace vscan::service::dataset
