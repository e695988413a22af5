#include "render_test_scenes.h"

#include <limits>
#include <string>

#include "vscan/render/colour_map.h"

namespace vscan::render::test {

PointCloud GridCloud(float half, int samples, const std::function<Eigen::Vector3f(float, float)>& place) {
  PointCloud cloud;
  cloud.fields = kFieldPosition;
  for (int i = 0; i < samples; ++i) {
    for (int j = 0; j < samples; ++j) {
      const float u = -half + 2 * half * static_cast<float>(i) / static_cast<float>(samples - 1);
      const float v = -half + 2 * half * static_cast<float>(j) / static_cast<float>(samples - 1);
      cloud.positions.push_back(place(u, v));
    }
  }
  return cloud;
}

Bounds BoundsOf(const std::vector<Eigen::Vector3f>& points) {
  Bounds b;
  b.min.setConstant(std::numeric_limits<float>::infinity());
  b.max = -b.min;
  for (const auto& p : points) {
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  }
  return b;
}

float InverseTurbo(const std::array<uint8_t, 3>& rgb) {
  constexpr int kSamples = 1024;
  const Eigen::Vector3f pixel(rgb[0], rgb[1], rgb[2]);
  float best_t = 0, best = std::numeric_limits<float>::infinity();
  for (int i = 0; i < kSamples; ++i) {
    const float t = static_cast<float>(i) / (kSamples - 1);
    const float d = (Turbo(t) * 255.0f - pixel).squaredNorm();
    if (d < best) {
      best = d;
      best_t = t;
    }
  }
  return best_t;
}

}  // namespace vscan::render::test
