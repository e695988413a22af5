#include "registration/feature_cloud.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "normals/normal_estimation.h"
#include "registration/normal_orientation.h"
#include "spatial/kd_tree.h"
#include "vscan/common/cancel_flag.h"

namespace vscan::registration {
namespace {

// Neighbours per point in the orientation graph.
constexpr int kOrientationNeighbours = 8;
// Cell indices beyond this would lose integer precision in a double; such points are far outside
// any scan and are left out.
constexpr double kMaxCellIndex = 0x1.0p52;

struct CellEntry {
  std::array<int64_t, 3> cell;
  uint32_t index;
  auto operator<=>(const CellEntry&) const = default;
};

// The finite points with their cells of edge `edge`, sorted by cell and then by index.
std::vector<CellEntry> SortedByCell(std::span<const Eigen::Vector3f> points, double edge) {
  std::vector<CellEntry> entries;
  entries.reserve(points.size());
  for (uint32_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d scaled = points[i].cast<double>() / edge;
    if (!scaled.allFinite() || scaled.cwiseAbs().maxCoeff() > kMaxCellIndex) continue;
    entries.push_back({{static_cast<int64_t>(std::floor(scaled.x())), static_cast<int64_t>(std::floor(scaled.y())),
                        static_cast<int64_t>(std::floor(scaled.z()))},
                       i});
  }
  std::sort(entries.begin(), entries.end());
  return entries;
}

// Calls visit(begin, end) for each run of entries that share a cell.
template <class Visit>
void ForEachCell(const std::vector<CellEntry>& entries, Visit visit) {
  for (size_t begin = 0; begin < entries.size();) {
    size_t end = begin + 1;
    while (end < entries.size() && entries[end].cell == entries[begin].cell) ++end;
    visit(begin, end);
    begin = end;
  }
}

}  // namespace

std::vector<Eigen::Vector3f> ThinToVoxels(std::span<const Eigen::Vector3f> points, double voxel) {
  const std::vector<CellEntry> entries = SortedByCell(points, voxel);
  std::vector<Eigen::Vector3f> thinned;
  ForEachCell(entries, [&](size_t begin, size_t end) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t e = begin; e < end; ++e) sum += points[entries[e].index].cast<double>();
    thinned.push_back((sum / static_cast<double>(end - begin)).cast<float>());
  });
  return thinned;
}

std::vector<uint32_t> SpreadKeypoints(std::span<const Eigen::Vector3f> points, double spacing) {
  const std::vector<CellEntry> entries = SortedByCell(points, spacing);
  std::vector<uint32_t> keypoints;
  ForEachCell(entries, [&](size_t begin, size_t end) {
    const Eigen::Vector3d centre =
        (Eigen::Vector3d(static_cast<double>(entries[begin].cell[0]), static_cast<double>(entries[begin].cell[1]),
                         static_cast<double>(entries[begin].cell[2])) +
         Eigen::Vector3d::Constant(0.5)) *
        spacing;
    uint32_t best = entries[begin].index;
    double best_sq = (points[best].cast<double>() - centre).squaredNorm();
    for (size_t e = begin + 1; e < end; ++e) {
      const double sq = (points[entries[e].index].cast<double>() - centre).squaredNorm();
      if (sq < best_sq) {
        best_sq = sq;
        best = entries[e].index;
      }
    }
    keypoints.push_back(best);
  });
  return keypoints;
}

StatusOr<FeatureCloud> PrepareFeatureCloud(std::span<const Eigen::Vector3f> points,
                                           const FeatureCloudOptions& options) {
  const std::vector<Eigen::Vector3f> thinned = ThinToVoxels(points, options.voxel);
  if (IsCancelled(options.cancel)) return Cancelled("features: cancelled");

  // About as many neighbours as a surface sampled once per voxel has within the radius.
  const double radius_in_voxels = options.normal_radius / options.voxel;
  normals::NormalOptions normal_options;
  normal_options.k =
      static_cast<int>(std::clamp(std::ceil(std::numbers::pi * radius_in_voxels * radius_in_voxels), 8.0, 256.0));
  normal_options.max_distance = static_cast<float>(options.normal_radius);
  normal_options.orient_towards_viewpoint = options.viewpoint.has_value();
  if (options.viewpoint) normal_options.viewpoint = *options.viewpoint;
  normal_options.cancel = options.cancel;
  ASSIGN_OR_RETURN(const std::vector<Eigen::Vector3f> normals, normals::EstimateNormals(thinned, normal_options));

  FeatureCloud cloud;
  cloud.points.reserve(thinned.size());
  cloud.normals.reserve(thinned.size());
  for (size_t i = 0; i < thinned.size(); ++i) {
    if (!normals[i].allFinite()) continue;
    cloud.points.push_back(thinned[i]);
    cloud.normals.push_back(normals[i]);
  }
  if (!options.facing.empty()) {
    const spatial::KdTree input(points);
    const float reach_sq = static_cast<float>(options.voxel * options.voxel);
    for (size_t i = 0; i < cloud.points.size(); ++i) {
      const uint32_t slot = input.NearestTwo(cloud.points[i], reach_sq)[0].slot;
      if (slot == spatial::KdTree::kNoSlot) continue;
      if (cloud.normals[i].dot(options.facing[input.original_index(slot)]) < 0) cloud.normals[i] = -cloud.normals[i];
    }
  } else if (!options.viewpoint) {
    OrientNormalsConsistently(cloud.points, cloud.normals, kOrientationNeighbours,
                              static_cast<float>(options.normal_radius));
  }
  if (IsCancelled(options.cancel)) return Cancelled("features: cancelled");
  cloud.keypoints = SpreadKeypoints(cloud.points, options.keypoint_spacing);
  return cloud;
}

}  // namespace vscan::registration
