#include "service/scan/scan_pixel_images.h"

namespace vscan::service {

ScanPlan WithPixelImageFields(ScanPlan plan) {
  plan.fields |= kFieldsForPixelImages;
  plan.measurement.fields = plan.fields;
  plan.measurement.include_rejected = true;
  return plan;
}

capture::PixelImages TakePixelImages(const ScanPlan& plan, PointCloud& cloud) {
  const double full_scale =
      plan.measurement.returned_light ? plan.measurement.returned_light->pixel.full_well_e : 1.0;
  capture::PixelImages images = capture::MakePixelImages(cloud, plan.camera.width, plan.camera.height, full_scale);
  if (!plan.measurement.include_rejected) capture::DropRejected(cloud);
  return images;
}

}  // namespace vscan::service
