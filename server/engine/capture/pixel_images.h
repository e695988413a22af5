#pragma once
// The camera's per-pixel images of a measured scan: why each pixel has (or lacks) a measurement,
// and the grey texture image a structured-light or time-of-flight camera returns beside its depth
// (docs/SENSORS.md, "Per-pixel images").

#include <cstdint>
#include <vector>

#include "vscan/common/point_cloud.h"

namespace vscan::capture {

struct PixelImages {
  uint32_t width = 0;
  uint32_t height = 0;
  // Row-major: the PointStatus of the pixel's ray; kUnspecified (0) where it met no surface.
  std::vector<uint8_t> reasons;
  // Row-major: the pixel's signal as 16-bit grey, 65535 at full scale; 0 where it met no surface.
  std::vector<uint16_t> gray;
};

// From a measured cloud that holds every ray (rejected ones included) with pixels, statuses and
// intensities. gray_full_scale is the intensity shown as 65535 (the full well in electrons under the
// returned light, 1 for the fixed lighting); brighter pixels clip there. Points whose pixel lies
// outside the image are ignored.
PixelImages MakePixelImages(const PointCloud& cloud, uint32_t width, uint32_t height, double gray_full_scale);

// Removes the rejected rays (every status but measured, outlier and flying pixel), keeping the
// order of the rest.
void DropRejected(PointCloud& cloud);

}  // namespace vscan::capture
