#include "evaluation/thinned_camera.h"

#include <algorithm>
#include <cmath>

namespace vscan::evaluation {
namespace {

uint32_t ThinnedSide(uint32_t pixels, uint32_t stride) {
  return std::max<uint32_t>(1, pixels / std::max<uint32_t>(stride, 1));
}

}  // namespace

uint64_t ThinnedPixelCount(const sensor::PinholeCamera& camera, uint32_t stride) {
  return uint64_t{ThinnedSide(camera.width, stride)} * ThinnedSide(camera.height, stride);
}

uint32_t BudgetStride(const sensor::PinholeCamera& camera, uint64_t max_rays) {
  max_rays = std::max<uint64_t>(max_rays, 1);
  const uint32_t widest = std::max({camera.width, camera.height, 1u});
  // Whole blocks only, so this stride's image has at most pixel_count / stride^2 <= max_rays pixels.
  const double estimate = std::ceil(std::sqrt(static_cast<double>(camera.pixel_count()) / max_rays));
  auto stride = static_cast<uint32_t>(std::clamp(estimate, 1.0, static_cast<double>(widest)));
  while (stride < widest && ThinnedPixelCount(camera, stride) > max_rays) ++stride;
  while (stride > 1 && ThinnedPixelCount(camera, stride - 1) <= max_rays) --stride;
  return stride;
}

uint32_t SpacingStride(const sensor::PinholeCamera& camera, double spacing, double distance) {
  // One pixel spans distance / f across the rays; the shorter focal length gives the wider pixel.
  const double pixel = distance / std::min(camera.fx, camera.fy);
  const double stride = std::floor(spacing / pixel);
  const double widest = std::max({camera.width, camera.height, 1u});
  return static_cast<uint32_t>(std::clamp(std::isfinite(stride) ? stride : widest, 1.0, widest));
}

sensor::PinholeCamera ThinCamera(const sensor::PinholeCamera& camera, uint32_t stride) {
  sensor::PinholeCamera thin = camera;
  const double s = std::max<uint32_t>(stride, 1);
  thin.width = ThinnedSide(camera.width, stride);
  thin.height = ThinnedSide(camera.height, stride);
  // Thinned pixel u spans original [u s, (u + 1) s): its centre (u + 0.5) s maps to (u + 0.5).
  thin.fx = camera.fx / s;
  thin.fy = camera.fy / s;
  thin.cx = camera.cx / s;
  thin.cy = camera.cy / s;
  return thin;
}

}  // namespace vscan::evaluation
