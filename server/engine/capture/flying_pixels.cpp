#include "capture/flying_pixels.h"

#include <cmath>
#include <limits>

#include "capture/pixel_draws.h"

namespace vscan::capture {

uint64_t MixDepthEdges(const PointCloud& clean, const sensor::PinholeCamera& camera, const MeasurementSpec& spec,
                       std::vector<uint8_t>& status, std::vector<Eigen::Vector3f>& measured) {
  const uint32_t w = camera.width, h = camera.height;
  constexpr float kNoHit = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> depth(size_t{w} * h, kNoHit);
  for (size_t i = 0; i < clean.size(); ++i) depth[clean.pixels[i]] = clean.positions[i].z();

  const float edge = static_cast<float>(spec.flying_pixels.edge_m);
  uint64_t flown = 0;
  for (size_t i = 0; i < clean.size(); ++i) {
    if (status[i] != static_cast<uint8_t>(PointStatus::kMeasured)) continue;
    const uint32_t pixel = clean.pixels[i];
    const uint32_t u = pixel % w, v = pixel / w;
    const float z = depth[pixel];
    float background = z;
    const auto look = [&](uint32_t q) {
      // NaN (no hit) never compares greater.
      if (depth[q] - z > edge && depth[q] > background) background = depth[q];
    };
    if (u > 0) look(pixel - 1);
    if (u + 1 < w) look(pixel + 1);
    if (v > 0) look(pixel - w);
    if (v + 1 < h) look(pixel + w);
    if (background == z) continue;
    PixelDraws draws(spec.seed, DrawStream::kFlyingPixel, pixel);
    const double mixed = z + draws.Uniform() * (background - z);
    measured[i] = (clean.positions[i].cast<double>() * (mixed / z)).cast<float>();
    status[i] = static_cast<uint8_t>(PointStatus::kFlyingPixel);
    ++flown;
  }
  return flown;
}

}  // namespace vscan::capture
