#include "registration/pair_information.h"

#include <algorithm>
#include <cmath>

namespace vscan::registration {

PairInformation ComputePairInformation(std::span<const Eigen::Vector3f> source,
                                       std::span<const Eigen::Vector3f> source_normals, const TargetIndex& target,
                                       const Pose3& target_from_source, const IcpResult& fit,
                                       const IcpOptions& options, double sigma_floor) {
  PairInformation out;
  if (target.size() == 0) return out;
  const Eigen::Matrix3d rotation = target_from_source.linear();
  const auto max_sq = static_cast<float>(fit.rejection_distance * fit.rejection_distance);
  const double min_cos = std::cos(options.max_normal_angle);
  // The floor keeps exact data, whose residual scale is next to zero, from weighing rounding out.
  const double width = KernelWidth(options.kernel, options.kernel_width) * std::max(fit.residual_scale, sigma_floor);
  Matrix6d hessian = Matrix6d::Zero();
  double weighted_sq = 0.0;
  for (size_t i = 0; i < source.size(); ++i) {
    if (!source[i].allFinite()) continue;
    const Eigen::Vector3d p = source[i].cast<double>();
    const Eigen::Vector3d q = target_from_source * p;
    const spatial::Neighbor nb = target.tree().NearestTwo(q.cast<float>(), max_sq)[0];
    if (nb.slot == spatial::KdTree::kNoSlot) continue;
    const Eigen::Vector3d n = target.normal(nb.slot).cast<double>();
    if (!source_normals.empty() && !(std::abs(n.dot(rotation * source_normals[i].cast<double>())) >= min_cos)) {
      continue;
    }
    const double r = n.dot(q - target.point(nb.slot).cast<double>());
    const double w = RobustWeight(options.kernel, r, width);
    if (w <= 0.0) continue;
    const Eigen::Vector3d m = rotation.transpose() * n;
    Eigen::Matrix<double, 6, 1> j;
    j << p.cross(m), m;
    hessian.selfadjointView<Eigen::Lower>().rankUpdate(j, w);
    weighted_sq += w * r * r;
    out.weight_sum += w;
  }
  if (out.weight_sum <= 0.0) return out;
  out.sigma = std::max(std::sqrt(weighted_sq / out.weight_sum), sigma_floor);
  hessian.triangularView<Eigen::StrictlyUpper>() = hessian.transpose();
  out.information = hessian / (out.sigma * out.sigma);
  return out;
}

}  // namespace vscan::registration
