#include "capture/pixel_images.h"

#include <algorithm>
#include <cmath>

namespace vscan::capture {
namespace {

bool Kept(uint8_t status) {
  const auto s = static_cast<PointStatus>(status);
  return s == PointStatus::kMeasured || s == PointStatus::kOutlier || s == PointStatus::kFlyingPixel;
}

template <typename T>
void Compact(const std::vector<uint8_t>& statuses, std::vector<T>& values) {
  if (values.empty()) return;
  size_t out = 0;
  for (size_t i = 0; i < statuses.size(); ++i) {
    if (Kept(statuses[i])) values[out++] = values[i];
  }
  values.resize(out);
}

}  // namespace

PixelImages MakePixelImages(const PointCloud& cloud, uint32_t width, uint32_t height, double gray_full_scale) {
  PixelImages images;
  images.width = width;
  images.height = height;
  const size_t pixels = size_t{width} * height;
  images.reasons.assign(pixels, 0);
  images.gray.assign(pixels, 0);
  const bool have_status = cloud.Has(kFieldStatus), have_intensity = cloud.Has(kFieldIntensity);
  if (!cloud.Has(kFieldPixel)) return images;
  const double to_grey = gray_full_scale > 0 ? 65535.0 / gray_full_scale : 0.0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint32_t pixel = cloud.pixels[i];
    if (pixel >= pixels) continue;
    images.reasons[pixel] = have_status ? cloud.statuses[i] : static_cast<uint8_t>(PointStatus::kMeasured);
    if (!have_intensity) continue;
    const double grey = static_cast<double>(cloud.intensities[i]) * to_grey;
    // NaN and negative signals show as black.
    images.gray[pixel] = static_cast<uint16_t>(grey > 0 ? std::lround(std::min(grey, 65535.0)) : 0);
  }
  return images;
}

void DropRejected(PointCloud& cloud) {
  if (!cloud.Has(kFieldStatus)) return;
  const std::vector<uint8_t> statuses = cloud.statuses;
  Compact(statuses, cloud.positions);
  Compact(statuses, cloud.normals);
  Compact(statuses, cloud.ranges);
  Compact(statuses, cloud.intensities);
  Compact(statuses, cloud.instance_ids);
  Compact(statuses, cloud.pixels);
  Compact(statuses, cloud.clean_positions);
  Compact(statuses, cloud.incidence_angles);
  Compact(statuses, cloud.estimated_normals);
  Compact(statuses, cloud.statuses);
}

}  // namespace vscan::capture
