#include "capture/ray_verdicts.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

namespace vscan::capture {

void JudgeRays(const PointCloud& clean, const sensor::PinholeCamera& camera, const MeasurementSpec& spec,
               std::vector<uint8_t>& status, std::vector<float>& incidence) {
  const size_t n = clean.size();
  status.assign(n, static_cast<uint8_t>(PointStatus::kMeasured));
  incidence.assign(n, 0.0f);
  const double grazing = spec.grazing_limit_deg * std::numbers::pi / 180.0;
  // With the returned light, its dark verdict takes the place of the intensity threshold.
  const double min_intensity = spec.returned_light ? 0.0 : spec.noise.min_intensity;
  // The arc cosine is only paid for when grazing drop-out or the incidence field needs it.
  const bool has_normals = clean.Has(kFieldNormal) && (grazing > 0 || (spec.fields & kFieldIncidence) != 0);
  const bool has_intensity = clean.Has(kFieldIntensity);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3f& p = clean.positions[i];
      if (has_normals) {
        const float length = p.norm();
        const float cosine = length > 0 ? std::abs(clean.normals[i].dot(p)) / length : 1.0f;
        incidence[i] = std::acos(std::clamp(cosine, 0.0f, 1.0f));
      }
      PointStatus verdict = PointStatus::kMeasured;
      if (p.z() < camera.near || p.z() > camera.far) {
        verdict = PointStatus::kRejectedOutOfRange;
      } else if (grazing > 0 && incidence[i] > grazing) {
        verdict = PointStatus::kRejectedGrazing;
      } else if (min_intensity > 0 && has_intensity && !(clean.intensities[i] >= min_intensity)) {
        verdict = PointStatus::kRejectedDim;
      }
      status[i] = static_cast<uint8_t>(verdict);
    }
  });
}

}  // namespace vscan::capture
