#include "registration/point_to_plane_icp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "registration/normal_equations.h"
#include "registration/spatial_order.h"
#include "registration/target_index.h"
#include "registration/warm_nearest.h"

namespace vscan::registration {
namespace {

using spatial::KdTree;

// Source points per task: fixed blocks keep the sums' order, and so the result, independent of
// scheduling.
constexpr size_t kGrain = 512;
// Pairs sampled (evenly over the spatial order) for the medians behind the rejection distance and
// the residual scale.
constexpr size_t kScaleSamples = 8192;
// The subset stage hands over to all points once its updates are below this many tolerances.
constexpr double kCoarseTolerance = 10.0;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// The nearest target point of one source point in the current iteration; no slot when none lies
// within the maximum distance, a NaN residual when the normals disagree.
struct Pair {
  float dist_sq;
  uint32_t slot;
  double residual;
};

struct Inputs {
  std::span<const Eigen::Vector3f> source;
  std::span<const Eigen::Vector3f> source_normals;
  const TargetIndex& target;
  const IcpOptions& options;
};

Status ValidateTarget(std::span<const Eigen::Vector3f> target, std::span<const Eigen::Vector3f> target_normals) {
  if (target_normals.size() != target.size()) {
    return InvalidArgument("target_normals", "needs one normal per target point, got " +
                                                 std::to_string(target_normals.size()) + " for " +
                                                 std::to_string(target.size()));
  }
  constexpr size_t kMaxPoints = std::numeric_limits<uint32_t>::max() - 1;
  if (target.size() > kMaxPoints) return InvalidArgument("icp", "at most 2^32-2 points per cloud");
  return Status::Ok();
}

Status Validate(std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> source_normals,
                const Pose3& initial, const IcpOptions& o) {
  const auto finite_non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!source_normals.empty() && source_normals.size() != source.size()) {
    return InvalidArgument("source_normals", "must be empty or one per source point, got " +
                                                 std::to_string(source_normals.size()) + " for " +
                                                 std::to_string(source.size()));
  }
  constexpr size_t kMaxPoints = std::numeric_limits<uint32_t>::max() - 1;
  if (source.size() > kMaxPoints) {
    return InvalidArgument("icp", "at most 2^32-2 points per cloud");
  }
  if (!initial.matrix().allFinite()) return InvalidArgument("initial_target_from_source", "must be finite");
  if (!std::isfinite(o.max_correspondence_distance) || o.max_correspondence_distance <= 0.0) {
    return InvalidArgument("icp.max_correspondence_distance", "must be finite and > 0");
  }
  if (!finite_non_negative(o.rejection_factor)) {
    return InvalidArgument("icp.rejection_factor", "must be finite and >= 0");
  }
  if (!(o.max_normal_angle >= 0.0 && o.max_normal_angle <= std::numbers::pi)) {
    return InvalidArgument("icp.max_normal_angle", "must be in [0, pi]");
  }
  if (!finite_non_negative(o.kernel_width)) return InvalidArgument("icp.kernel_width", "must be finite and >= 0");
  if (!finite_non_negative(o.rotation_tolerance)) {
    return InvalidArgument("icp.rotation_tolerance", "must be finite and >= 0");
  }
  if (!finite_non_negative(o.translation_tolerance)) {
    return InvalidArgument("icp.translation_tolerance", "must be finite and >= 0");
  }
  if (o.max_iterations < 1) return InvalidArgument("icp.max_iterations", "must be >= 1");
  if (o.min_correspondences < 6) return InvalidArgument("icp.min_correspondences", "must be >= 6");
  return Status::Ok();
}

// Nearest target point of each active source point under `pose`, warm-started from each point's
// last search (warm[i] for source point i) or, for a point without one, its predecessor's in the
// spatial order.
void FindPairs(const Inputs& in, const Pose3& pose, std::span<const uint32_t> active, std::vector<WarmStart>& warm,
               std::vector<Pair>& pairs) {
  const Eigen::Matrix3d rotation = pose.linear();
  const Eigen::Vector3d translation = pose.translation();
  const auto max_sq = static_cast<float>(in.options.max_correspondence_distance * in.options.max_correspondence_distance);
  const double min_cos = std::cos(in.options.max_normal_angle);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, active.size(), kGrain),
      [&](const tbb::blocked_range<size_t>& r) {
        const WarmStart* previous = nullptr;
        for (size_t j = r.begin(); j != r.end(); ++j) {
          const uint32_t i = active[j];
          const Eigen::Vector3d p = rotation * in.source[i].cast<double>() + translation;
          const spatial::Neighbor nb = WarmNearest(in.target.tree(), p.cast<float>(), max_sq, warm[i], previous);
          if (warm[i].slot != KdTree::kNoSlot) previous = &warm[i];
          if (nb.slot == KdTree::kNoSlot) {
            pairs[j] = {std::numeric_limits<float>::infinity(), KdTree::kNoSlot, kNan};
            continue;
          }
          const Eigen::Vector3d n = in.target.normal(nb.slot).cast<double>();
          double residual = n.dot(p - in.target.point(nb.slot).cast<double>());
          if (!in.source_normals.empty()) {
            const double cos = std::abs(n.dot(rotation * in.source_normals[i].cast<double>()));
            if (!(cos >= min_cos)) residual = kNan;
          }
          pairs[j] = {nb.dist_sq, nb.slot, residual};
        }
      },
      tbb::simple_partitioner());
}

struct Thresholds {
  double rejection_distance = 0.0;
  double scale = 0.0;
};

// The rejection distance (rejection_factor times the median pair distance, at most the maximum)
// and the robust scale of the residuals of the pairs inside it, from an even sample of the pairs.
Thresholds EstimateThresholds(const IcpOptions& options, std::span<const Pair> pairs) {
  const size_t stride = std::max<size_t>(1, pairs.size() / kScaleSamples);
  std::vector<float> values;
  values.reserve(pairs.size() / stride + 1);
  for (size_t j = 0; j < pairs.size(); j += stride) {
    if (pairs[j].slot != KdTree::kNoSlot && !std::isnan(pairs[j].residual)) values.push_back(pairs[j].dist_sq);
  }
  Thresholds t;
  if (values.empty()) return t;
  t.rejection_distance = options.max_correspondence_distance;
  if (options.rejection_factor > 0.0) {
    t.rejection_distance = std::min(t.rejection_distance, options.rejection_factor * std::sqrt(Median(values)));
  }
  const auto rejection_sq = static_cast<float>(t.rejection_distance * t.rejection_distance);
  values.clear();
  for (size_t j = 0; j < pairs.size(); j += stride) {
    const Pair& p = pairs[j];
    if (p.slot != KdTree::kNoSlot && !std::isnan(p.residual) && p.dist_sq <= rejection_sq) {
      values.push_back(static_cast<float>(std::abs(p.residual)));
    }
  }
  // A floor for exact data, whose residuals can all be zero.
  t.scale = std::max(MadScale(values), 1e-12);
  return t;
}

struct Sums {
  NormalEquations equations;
  size_t found = 0;
  size_t accepted = 0;
  double sum_sq = 0.0;

  void Merge(const Sums& other) {
    equations.Merge(other.equations);
    found += other.found;
    accepted += other.accepted;
    sum_sq += other.sum_sq;
  }
};

// Weighted normal equations of the pairs that pass the rejection distance, in fixed blocks summed
// in a fixed order.
Sums Accumulate(const Inputs& in, const Pose3& pose, std::span<const uint32_t> active, std::span<const Pair> pairs,
                const Thresholds& thresholds) {
  const auto rejection_sq = static_cast<float>(thresholds.rejection_distance * thresholds.rejection_distance);
  const double width = KernelWidth(in.options.kernel, in.options.kernel_width) * thresholds.scale;
  const Eigen::Vector3d centre = in.target.centroid();
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, active.size(), kGrain), Sums{},
      [&](const tbb::blocked_range<size_t>& r, Sums sums) {
        for (size_t j = r.begin(); j != r.end(); ++j) {
          const Pair& pair = pairs[j];
          if (pair.slot == KdTree::kNoSlot) continue;
          ++sums.found;
          if (std::isnan(pair.residual) || pair.dist_sq > rejection_sq) continue;
          ++sums.accepted;
          sums.sum_sq += pair.residual * pair.residual;
          const double w = RobustWeight(in.options.kernel, pair.residual, width);
          if (w <= 0.0) continue;
          const Eigen::Vector3d p = pose * in.source[active[j]].cast<double>();
          sums.equations.Add(p - centre, in.target.normal(pair.slot).cast<double>(), pair.residual, w);
        }
        return sums;
      },
      [](Sums a, const Sums& b) {
        a.Merge(b);
        return a;
      });
}

// Every stride-th point of the spatial order, about `count` points spread evenly over the cloud.
std::vector<uint32_t> EvenSubset(std::span<const uint32_t> order, size_t count) {
  const size_t stride = order.size() / count;
  std::vector<uint32_t> subset;
  subset.reserve(order.size() / stride + 1);
  for (size_t k = stride / 2; k < order.size(); k += stride) subset.push_back(order[k]);
  return subset;
}

}  // namespace

const char* IcpStopName(IcpStop stop) {
  switch (stop) {
    case IcpStop::kConverged:
      return "converged";
    case IcpStop::kMaxIterations:
      return "max_iterations";
    case IcpStop::kTooFewCorrespondences:
      return "too_few_correspondences";
    case IcpStop::kDegenerate:
      return "degenerate";
  }
  return "unknown";
}

StatusOr<IcpResult> PointToPlaneIcp(std::span<const Eigen::Vector3f> source,
                                    std::span<const Eigen::Vector3f> target,
                                    std::span<const Eigen::Vector3f> target_normals,
                                    const Pose3& initial_target_from_source, const IcpOptions& options,
                                    std::span<const Eigen::Vector3f> source_normals) {
  RETURN_IF_ERROR(ValidateTarget(target, target_normals));
  RETURN_IF_ERROR(Validate(source, source_normals, initial_target_from_source, options));
  const TargetIndex index(target, target_normals);
  return PointToPlaneIcp(source, index, initial_target_from_source, options, source_normals);
}

StatusOr<IcpResult> PointToPlaneIcp(std::span<const Eigen::Vector3f> source, const TargetIndex& index,
                                    const Pose3& initial_target_from_source, const IcpOptions& options,
                                    std::span<const Eigen::Vector3f> source_normals) {
  RETURN_IF_ERROR(Validate(source, source_normals, initial_target_from_source, options));
  const Inputs in{source, source_normals, index, options};
  const std::vector<uint32_t> order = MortonOrder(source);
  const bool start_coarse = options.coarse_points > 0 && order.size() > 2 * options.coarse_points;
  const std::vector<uint32_t> subset = start_coarse ? EvenSubset(order, options.coarse_points) : std::vector<uint32_t>{};
  std::span<const uint32_t> active = start_coarse ? std::span<const uint32_t>(subset) : std::span<const uint32_t>(order);

  IcpResult result;
  result.target_from_source = initial_target_from_source;
  result.stop = IcpStop::kMaxIterations;
  std::vector<WarmStart> warm(source.size());
  std::vector<Pair> pairs(order.size());
  bool coarse = start_coarse;
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    Pose3& pose = result.target_from_source;
    const std::span<Pair> active_pairs(pairs.data(), active.size());
    FindPairs(in, pose, active, warm, pairs);
    const Thresholds thresholds = EstimateThresholds(options, active_pairs);
    const Sums sums = Accumulate(in, pose, active, active_pairs, thresholds);
    result.iterations = iteration;
    result.fitness = active.empty() ? 0.0 : static_cast<double>(sums.found) / static_cast<double>(active.size());
    result.correspondences = sums.accepted;
    result.inlier_rmse = sums.accepted > 0 ? std::sqrt(sums.sum_sq / static_cast<double>(sums.accepted)) : 0.0;
    result.rejection_distance = thresholds.rejection_distance;
    result.residual_scale = thresholds.scale;
    if (sums.accepted < options.min_correspondences) {
      result.stop = IcpStop::kTooFewCorrespondences;
      break;
    }
    const std::optional<Vector6d> increment = sums.equations.Solve();
    if (!increment) {
      result.stop = IcpStop::kDegenerate;
      break;
    }
    pose = IncrementPose(*increment, index.centroid()) * pose;
    Reorthonormalise(pose);
    result.last_rotation_step = increment->head<3>().norm();
    result.last_translation_step = increment->tail<3>().norm();
    const double slack = coarse ? kCoarseTolerance : 1.0;
    if (increment->head<3>().norm() < slack * options.rotation_tolerance &&
        increment->tail<3>().norm() < slack * options.translation_tolerance) {
      if (!coarse) {
        result.stop = IcpStop::kConverged;
        result.converged = true;
        break;
      }
      coarse = false;
      active = order;
    }
  }
  return result;
}

}  // namespace vscan::registration
