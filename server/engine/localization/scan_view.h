#pragma once
// What the sensor saw, for checking a placed part against it: per cell of a grid over the plane
// perpendicular to the view direction (at unit depth), the nearest depth of a scan point in it.

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "localization/oriented_points.h"
#include "vscan/common/pose.h"

namespace vscan::localization {

class ScanView {
 public:
  // Cells of cell_at_depth (metres) at the scan's median depth; at most 4 million cells (a wide
  // view coarsens them).
  ScanView(std::span<const Eigen::Vector3f> points, const Eigen::Vector3d& sensor, double cell_at_depth);

  struct Tally {
    size_t on_surface = 0;    // facing the sensor, on the scan's surface
    size_t seen_through = 0;  // facing the sensor, in front of what it saw there
    double SeenThroughShare() const {
      return on_surface + seen_through == 0 ? 0.0
                                            : static_cast<double>(seen_through) /
                                                  static_cast<double>(on_surface + seen_through);
    }
  };

  // The part's points (model, placed by pose) facing the sensor within about 72 degrees: on the
  // scan's surface (depth within tolerance), seen through (the sensor saw further), or hidden or
  // unseen (neither).
  Tally Check(const OrientedPoints& model, const Pose3& pose, double tolerance) const;

 private:
  std::optional<size_t> Cell(const Eigen::Vector3d& d, double z) const;

  Eigen::Vector3d sensor_, axis_x_ = Eigen::Vector3d::UnitX(), axis_y_ = Eigen::Vector3d::UnitY(),
                           axis_z_ = Eigen::Vector3d::UnitZ();
  double cell_ = 1, lo_u_ = 0, lo_v_ = 0;
  size_t width_ = 0, height_ = 0;
  std::vector<float> depth_;
};

}  // namespace vscan::localization
