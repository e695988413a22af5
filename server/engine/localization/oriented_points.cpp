#include "localization/oriented_points.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "registration/voxel_thinning.h"

namespace vscan::localization {

OrientedPoints ThinOriented(const OrientedPoints& cloud, double voxel, double max_normal_angle_rad) {
  const double inverse = 1.0 / voxel;
  std::vector<std::pair<uint64_t, uint32_t>> keyed;
  keyed.reserve(cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    if (!cloud.points[i].allFinite() || !cloud.normals[i].allFinite()) continue;
    if (const auto key = registration::VoxelKey(cloud.points[i], inverse)) keyed.emplace_back(*key, static_cast<uint32_t>(i));
  }
  std::sort(keyed.begin(), keyed.end());
  const auto min_cos = static_cast<float>(std::cos(max_normal_angle_rad));
  struct Group {
    Eigen::Vector3f point_sum, normal_sum;
    float count;
  };
  std::vector<Group> groups;
  OrientedPoints thin;
  for (size_t begin = 0; begin < keyed.size();) {
    size_t end = begin + 1;
    while (end < keyed.size() && keyed[end].first == keyed[begin].first) ++end;
    groups.clear();
    for (size_t k = begin; k < end; ++k) {
      const Eigen::Vector3f& p = cloud.points[keyed[k].second];
      const Eigen::Vector3f& n = cloud.normals[keyed[k].second];
      auto joined = std::find_if(groups.begin(), groups.end(),
                                 [&](const Group& g) { return g.normal_sum.normalized().dot(n) >= min_cos; });
      if (joined == groups.end()) {
        groups.push_back({p, n, 1});
      } else {
        joined->point_sum += p, joined->normal_sum += n, joined->count += 1;
      }
    }
    for (const Group& g : groups) {
      if (g.normal_sum.squaredNorm() <= 0) continue;
      thin.points.push_back(g.point_sum / g.count);
      thin.normals.push_back(g.normal_sum.normalized());
    }
    begin = end;
  }
  return thin;
}

}  // namespace vscan::localization
