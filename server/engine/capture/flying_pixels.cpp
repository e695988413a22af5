#include "capture/flying_pixels.h"

#include <atomic>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "capture/pixel_draws.h"

namespace vscan::capture {
namespace {

constexpr uint32_t kNoHit = std::numeric_limits<uint32_t>::max();

// Whether q, seen by the neighbouring pixel, lies more than edge off the plane tangent to the surface
// at p (normal n) along q's ray: a steep but continuous surface changes depth fast between pixels
// without being an edge. A ray that never meets the tangent plane in front of the camera always is.
bool LeavesTheTangentPlane(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& q,
                           double edge) {
  const double np = n.dot(p), nq = n.dot(q);
  if (!(np * nq > 0)) return true;
  return std::abs(q.z() * (1.0 - np / nq)) > edge;
}

}  // namespace

uint64_t MixDepthEdges(const PointCloud& clean, const sensor::PinholeCamera& camera, const MeasurementSpec& spec,
                       std::vector<uint8_t>& status, std::vector<Eigen::Vector3f>& measured) {
  const uint32_t w = camera.width, h = camera.height;
  // A background out of range returns too little light to mix with (and would place the point beyond far).
  std::vector<uint32_t> hit_of_pixel(size_t{w} * h, kNoHit);
  for (size_t i = 0; i < clean.size(); ++i) {
    if (status[i] != static_cast<uint8_t>(PointStatus::kRejectedOutOfRange)) {
      hit_of_pixel[clean.pixels[i]] = static_cast<uint32_t>(i);
    }
  }

  const float edge = static_cast<float>(spec.flying_pixels.edge_m);
  std::atomic<uint64_t> flown{0};
  // Each pixel reads its neighbours' clean hits only and writes its own slots: pixels are independent.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, clean.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    uint64_t local = 0;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (status[i] != static_cast<uint8_t>(PointStatus::kMeasured)) continue;
      const uint32_t pixel = clean.pixels[i];
      const uint32_t u = pixel % w, v = pixel / w;
      const float z = clean.positions[i].z();
      float background = z;
      const auto look = [&](uint32_t q) {
        const uint32_t j = hit_of_pixel[q];
        if (j == kNoHit) return;
        const float depth = clean.positions[j].z();
        if (!(depth - z > edge && depth > background)) return;
        if (LeavesTheTangentPlane(clean.positions[i].cast<double>(), clean.normals[i].cast<double>(),
                                  clean.positions[j].cast<double>(), edge)) {
          background = depth;
        }
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
      ++local;
    }
    flown += local;
  });
  return flown.load();
}

}  // namespace vscan::capture
