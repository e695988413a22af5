#pragma once
// The scan as every part's search sees it: with unit normals, thinned to the finest part's voxel, the
// plate the parts stand on and every plane piece wider than any part removed, and what the sensor saw.

#include <atomic>
#include <cstddef>
#include <optional>
#include <span>

#include <Eigen/Core>

#include "localization/baseline_localizer.h"
#include "localization/oriented_points.h"
#include "localization/scan_view.h"
#include "localization/support_plane.h"
#include "vscan/common/status.h"

namespace vscan::localization {

struct PreparedScan {
  OrientedPoints points;
  std::optional<ScanView> view;  // with the sensor's position
  size_t support_plane_points = 0;
  // The plane the parts stand on, its normal turned to the side most of the other points are on.
  std::optional<Plane> support;
};

// Normals as given (one per point) or estimated towards options.viewpoint within 3 voxels;
// options.remove_support_plane removes the dominant plane and the plane pieces wider than 1.5 times
// largest_part (metres). Cancelled through the normal estimation.
StatusOr<PreparedScan> PrepareScan(std::span<const Eigen::Vector3f> scan_points, std::span<const Eigen::Vector3f> scan_normals,
                                   double voxel, double largest_part, const LocalizerOptions& options,
                                   const std::atomic<bool>* cancel);

}  // namespace vscan::localization
