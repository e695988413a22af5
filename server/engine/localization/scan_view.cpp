#include "localization/scan_view.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vscan::localization {
namespace {

// A part's point faces the sensor when its normal is within about 72 degrees of the ray back.
constexpr double kMinFacingCos = 0.3;
// A bounded grid: a wide field of view coarsens the cell rather than growing without limit.
constexpr double kMaxCells = 4e6;

}  // namespace

ScanView::ScanView(std::span<const Eigen::Vector3f> points, const Eigen::Vector3d& sensor, double cell_at_depth)
    : sensor_(sensor) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p.cast<double>();
  if (points.empty() || (mean / static_cast<double>(points.size()) - sensor).norm() <= 0) return;
  axis_z_ = (mean / static_cast<double>(points.size()) - sensor).normalized();
  axis_x_ = axis_z_.unitOrthogonal();
  axis_y_ = axis_z_.cross(axis_x_);
  std::vector<double> depths;
  double lo_u = 1e9, lo_v = 1e9, hi_u = -1e9, hi_v = -1e9;
  for (const auto& p : points) {
    const Eigen::Vector3d d = p.cast<double>() - sensor;
    const double z = d.dot(axis_z_);
    if (z <= 0) continue;
    depths.push_back(z);
    lo_u = std::min(lo_u, d.dot(axis_x_) / z), hi_u = std::max(hi_u, d.dot(axis_x_) / z);
    lo_v = std::min(lo_v, d.dot(axis_y_) / z), hi_v = std::max(hi_v, d.dot(axis_y_) / z);
  }
  if (depths.empty()) return;
  std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2), depths.end());
  cell_ = cell_at_depth / depths[depths.size() / 2];
  while ((hi_u - lo_u) / cell_ * (hi_v - lo_v) / cell_ > kMaxCells) cell_ *= 1.5;
  lo_u_ = lo_u, lo_v_ = lo_v;
  width_ = static_cast<size_t>((hi_u - lo_u) / cell_) + 1;
  height_ = static_cast<size_t>((hi_v - lo_v) / cell_) + 1;
  depth_.assign(width_ * height_, std::numeric_limits<float>::infinity());
  for (const auto& p : points) {
    const Eigen::Vector3d d = p.cast<double>() - sensor;
    const double z = d.dot(axis_z_);
    if (z <= 0) continue;
    if (const auto cell = Cell(d, z)) depth_[*cell] = std::min(depth_[*cell], static_cast<float>(z));
  }
}

ScanView::Tally ScanView::Check(const OrientedPoints& model, const Pose3& pose, double tolerance) const {
  Tally tally;
  if (depth_.empty()) return tally;
  for (size_t i = 0; i < model.points.size(); ++i) {
    const Eigen::Vector3d p = pose * model.points[i].cast<double>();
    const Eigen::Vector3d d = p - sensor_;
    // Points seen at a grazing angle are left out: their depth changes fastest across a cell.
    if ((pose.linear() * model.normals[i].cast<double>()).dot(d) > -kMinFacingCos * d.norm()) continue;
    const double z = d.dot(axis_z_);
    if (z <= 0) continue;
    const auto cell = Cell(d, z);
    if (!cell || !std::isfinite(depth_[*cell])) continue;
    const double seen = depth_[*cell];
    if (std::abs(seen - z) <= tolerance) {
      ++tally.on_surface;
    } else if (seen > z + tolerance) {
      ++tally.seen_through;
    }
  }
  return tally;
}

std::optional<size_t> ScanView::Cell(const Eigen::Vector3d& d, double z) const {
  const double u = (d.dot(axis_x_) / z - lo_u_) / cell_, v = (d.dot(axis_y_) / z - lo_v_) / cell_;
  if (!(u >= 0 && v >= 0 && u < static_cast<double>(width_) && v < static_cast<double>(height_))) return std::nullopt;
  return static_cast<size_t>(v) * width_ + static_cast<size_t>(u);
}

}  // namespace vscan::localization
