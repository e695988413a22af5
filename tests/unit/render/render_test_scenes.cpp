#include "render_test_scenes.h"

#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>

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

TriangleMesh Icosphere(float radius, const Eigen::Vector3f& centre, int subdivisions) {
  const float t = (1 + std::sqrt(5.0f)) / 2;
  std::vector<Eigen::Vector3f> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<std::array<uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mids;
    const auto mid = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto found = mids.find(key);
      if (found != mids.end()) return found->second;
      v.push_back((v[a] + v[b]).normalized());
      const auto index = static_cast<uint32_t>(v.size() - 1);
      mids.emplace(key, index);
      return index;
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (const auto& [a, b, c] : f) {
      const uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.push_back({a, ab, ca});
      next.push_back({b, bc, ab});
      next.push_back({c, ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = std::move(next);
  }
  TriangleMesh mesh;
  for (const auto& p : v) mesh.vertices.push_back(centre + radius * p);
  mesh.triangles = std::move(f);
  return mesh;
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

TempDir::TempDir() {
  std::random_device seed;
  path = std::filesystem::temp_directory_path() / ("vscan-render-test-" + std::to_string(seed()));
  std::filesystem::create_directories(path);
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path, ec);
}

}  // namespace vscan::render::test
