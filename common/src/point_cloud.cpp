#include "vscan/common/point_cloud.h"

namespace vscan {

void PointCloud::Resize(size_t n) {
  fields |= kFieldPosition;
  positions.resize(n);
  normals.resize(Has(kFieldNormal) ? n : 0);
  ranges.resize(Has(kFieldRange) ? n : 0);
  intensities.resize(Has(kFieldIntensity) ? n : 0);
  instance_ids.resize(Has(kFieldInstanceId) ? n : 0);
  pixels.resize(Has(kFieldPixel) ? n : 0);
  clean_positions.resize(Has(kFieldCleanPosition) ? n : 0);
  incidence_angles.resize(Has(kFieldIncidence) ? n : 0);
  statuses.resize(Has(kFieldStatus) ? n : 0);
  estimated_normals.resize(Has(kFieldEstimatedNormal) ? n : 0);
}

size_t PointCloud::BytesPerPoint() const {
  size_t b = 12;
  if (Has(kFieldNormal)) b += 12;
  if (Has(kFieldRange)) b += 4;
  if (Has(kFieldIntensity)) b += 4;
  if (Has(kFieldInstanceId)) b += 4;
  if (Has(kFieldPixel)) b += 4;
  if (Has(kFieldCleanPosition)) b += 12;
  if (Has(kFieldIncidence)) b += 4;
  if (Has(kFieldStatus)) b += 1;
  if (Has(kFieldEstimatedNormal)) b += 12;
  return b;
}

}  // namespace vscan
