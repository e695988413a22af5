#include "localization/prepared_scan.h"

#include <utility>
#include <vector>

#include "localization/large_planes.h"
#include "normals/normal_estimation.h"

namespace vscan::localization {
namespace {

constexpr uint64_t kPlaneSeed = 1;
// Planar pieces wider than this many times the largest part are bin walls, rims or tables; their
// points are connected when within kLinkVoxels voxels; planes with fewer points are not looked for.
constexpr double kLargePlaneExtent = 1.5;
constexpr double kLinkVoxels = 3;
constexpr size_t kMinLargePlanePoints = 500;

// The scan with a unit normal per point facing the sensor: its own, or estimated and turned
// towards the viewpoint (points without a normal are dropped).
StatusOr<OrientedPoints> WithNormals(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                                     double voxel, const LocalizerOptions& options,
                                     const std::atomic<bool>* cancel) {
  OrientedPoints scan;
  if (!normals.empty()) {
    for (size_t i = 0; i < points.size(); ++i) {
      if (!points[i].allFinite() || !normals[i].allFinite()) continue;
      scan.points.push_back(points[i]);
      scan.normals.push_back(normals[i].normalized());
    }
    return scan;
  }
  normals::NormalOptions normal_options;
  normal_options.max_distance = static_cast<float>(3 * voxel);
  normal_options.viewpoint = options.viewpoint.cast<float>();
  normal_options.cancel = cancel;
  ASSIGN_OR_RETURN(const std::vector<Eigen::Vector3f> estimated, normals::EstimateNormals(points, normal_options));
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite() || !estimated[i].allFinite()) continue;
    scan.points.push_back(points[i]);
    scan.normals.push_back(estimated[i]);
  }
  return scan;
}

}  // namespace

StatusOr<PreparedScan> PrepareScan(std::span<const Eigen::Vector3f> scan_points, std::span<const Eigen::Vector3f> scan_normals,
                                   double voxel, double largest_part, const LocalizerOptions& options,
                                   const std::atomic<bool>* cancel) {
  PreparedScan prepared;
  ASSIGN_OR_RETURN(const OrientedPoints scan, WithNormals(scan_points, scan_normals, voxel, options, cancel));
  if (options.sensor_position) prepared.view.emplace(scan.points, *options.sensor_position, voxel);
  OrientedPoints thin = ThinOriented(scan, voxel, kFaceSplitAngleRad);
  if (options.remove_support_plane) {
    const double distance = options.plane_distance_voxels * voxel;
    if (auto plane = FindDominantPlane(thin.points, distance, options.min_plane_share, kPlaneSeed)) {
      OrientedPoints kept;
      for (size_t i = 0; i < thin.points.size(); ++i) {
        if (plane->Distance(thin.points[i]) <= distance) continue;
        kept.points.push_back(thin.points[i]);
        kept.normals.push_back(thin.normals[i]);
      }
      for (const auto& p : scan.points) prepared.support_plane_points += plane->Distance(p) <= distance ? 1 : 0;
      size_t above = 0;
      for (const auto& p : kept.points) above += plane->normal.dot(p.cast<double>()) + plane->offset > 0 ? 1 : 0;
      if (2 * above < kept.points.size()) plane->normal = -plane->normal, plane->offset = -plane->offset;
      prepared.support = plane;
      thin = std::move(kept);
    }
    LargePlaneSettings large;
    large.distance = distance;
    large.link = kLinkVoxels * voxel;
    large.min_extent = kLargePlaneExtent * largest_part;
    large.min_points = kMinLargePlanePoints;
    large.seed = kPlaneSeed;
    if (prepared.support) large.support_normal = prepared.support->normal;
    const std::vector<bool> on_large = MarkLargePlanes(thin, large);
    OrientedPoints kept;
    for (size_t i = 0; i < thin.points.size(); ++i) {
      if (on_large[i]) continue;
      kept.points.push_back(thin.points[i]);
      kept.normals.push_back(thin.normals[i]);
    }
    thin = std::move(kept);
  }
  prepared.points = std::move(thin);
  return prepared;
}

}  // namespace vscan::localization
