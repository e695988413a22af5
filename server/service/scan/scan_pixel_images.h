#pragma once
// The per-pixel images of a scan (ScanPlan.pixel_images, and every dataset view): the plan is
// widened to measure every ray with its status and intensity, the images are read off the cloud, and
// the cloud is cut back to what the plan returns.

#include "capture/pixel_images.h"
#include "service/scan/scan_plan.h"
#include "vscan/common/point_cloud.h"

namespace vscan::service {

// What a scan with per-pixel images measures on top of the asked fields.
inline constexpr uint32_t kFieldsForPixelImages = kFieldPixel | kFieldStatus | kFieldIntensity;

// plan measuring every ray, rejected ones included, with kFieldsForPixelImages.
ScanPlan WithPixelImageFields(ScanPlan plan);

// The images of cloud (measured under WithPixelImageFields(plan)); then drops the rejected rays
// unless plan.measurement.include_rejected. The grey full scale is the full well under the returned
// light, else the fixed lighting's intensity 1.
capture::PixelImages TakePixelImages(const ScanPlan& plan, PointCloud& cloud);

}  // namespace vscan::service
