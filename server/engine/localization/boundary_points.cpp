#include "localization/boundary_points.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "spatial/kd_tree.h"

namespace vscan::localization {
namespace {

constexpr size_t kNeighbours = 24;
constexpr size_t kMinSurfaceNeighbours = 3;
constexpr float kMinNormalCos = 0.866f;
constexpr double kMinGapRad = std::numbers::pi / 2;

}  // namespace

std::vector<Eigen::Vector3f> RimDirections(const OrientedPoints& cloud, double radius) {
  std::vector<Eigen::Vector3f> rims(cloud.points.size(), Eigen::Vector3f::Zero());
  if (cloud.points.empty()) return rims;
  const spatial::KdTree tree(cloud.points);
  const auto max_sq = static_cast<float>(radius * radius);
  const auto max_height = static_cast<float>(radius / 4);
  tbb::parallel_for(size_t{0}, cloud.points.size(), [&](size_t i) {
    std::array<spatial::Neighbor, kNeighbours> found{};
    const size_t count = tree.Knn(cloud.points[i], max_sq, found);
    const Eigen::Vector3f& n = cloud.normals[i];
    const Eigen::Vector3f u = n.unitOrthogonal(), v = n.cross(u);
    std::array<double, kNeighbours> angles{};
    size_t surface = 0;
    for (size_t k = 0; k < count; ++k) {
      const uint32_t j = tree.original_index(found[k].slot);
      if (j == i || cloud.normals[j].dot(n) < kMinNormalCos) continue;
      const Eigen::Vector3f d = cloud.points[j] - cloud.points[i];
      if (std::abs(d.dot(n)) > max_height) continue;
      angles[surface++] = std::atan2(d.dot(v), d.dot(u));
    }
    if (surface < kMinSurfaceNeighbours) return;
    std::sort(angles.begin(), angles.begin() + static_cast<long>(surface));
    double widest = angles[0] + 2 * std::numbers::pi - angles[surface - 1], middle = angles[surface - 1] + widest / 2;
    for (size_t k = 1; k < surface; ++k) {
      if (angles[k] - angles[k - 1] > widest) widest = angles[k] - angles[k - 1], middle = angles[k - 1] + widest / 2;
    }
    if (widest < kMinGapRad) return;
    rims[i] = (static_cast<float>(std::cos(middle)) * u + static_cast<float>(std::sin(middle)) * v).normalized();
  });
  return rims;
}

}  // namespace vscan::localization
