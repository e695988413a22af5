#include "registration/feature_alignment.h"

#include <cmath>
#include <tuple>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "registration/descriptor_matching.h"
#include "registration/feature_cloud.h"
#include "registration/match_consensus.h"
#include "registration/point_to_plane_icp.h"
#include "registration/shot_descriptors.h"
#include "spatial/kd_tree.h"
#include "vscan/common/cancel_flag.h"

namespace vscan::registration {
namespace {

// Below this many thinned points a cloud has too little surface for descriptors of its shape.
constexpr size_t kMinPoints = 100;
// ICP starts from the consensus, which is within a few inlier distances.
constexpr double kIcpReachInInlierDistances = 2.0;
// The fitness counts source points within this many voxels of the target.
constexpr double kFitnessVoxels = 2.0;
constexpr int kMaxRansacIterations = 10'000'000;
// The last ICP runs on clouds thinned to the voxel over this.
constexpr double kFineVoxelDivisor = 2.0;
// ICP that ran out of iterations while its updates stay under this share of a voxel (and the turn
// of that move at a voxel's distance) has settled: noisy pairs that change between iterations keep
// it from the micrometre tolerances, where clouds that slide keep moving by much more.
constexpr double kSettledVoxels = 0.01;
constexpr double kSettledRadians = 1e-3;

bool Settled(const IcpResult& icp, double voxel) {
  return icp.stop == IcpStop::kMaxIterations && icp.last_translation_step < kSettledVoxels * voxel &&
         icp.last_rotation_step < kSettledRadians;
}

Status Validate(const FeatureAlignmentOptions& o) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(o.voxel_size)) {
    return InvalidArgument("features.voxel_size", "must be finite and > 0, got " + std::to_string(o.voxel_size));
  }
  if (!std::isfinite(o.normal_radius_voxels) || o.normal_radius_voxels < 1.0) {
    return InvalidArgument("features.normal_radius_voxels",
                           "must be finite and >= 1, got " + std::to_string(o.normal_radius_voxels));
  }
  if (!std::isfinite(o.descriptor_radius_voxels) || o.descriptor_radius_voxels < o.normal_radius_voxels) {
    return InvalidArgument("features.descriptor_radius_voxels", "must be finite and >= normal_radius_voxels, got " +
                                                                    std::to_string(o.descriptor_radius_voxels));
  }
  if (!std::isfinite(o.keypoint_spacing_voxels) || o.keypoint_spacing_voxels < 1.0) {
    return InvalidArgument("features.keypoint_spacing_voxels",
                           "must be finite and >= 1, got " + std::to_string(o.keypoint_spacing_voxels));
  }
  if (o.ransac_iterations < 1 || o.ransac_iterations > kMaxRansacIterations) {
    return InvalidArgument("features.ransac_iterations",
                           "must be in [1, 10000000], got " + std::to_string(o.ransac_iterations));
  }
  if (!positive(o.inlier_distance_voxels)) {
    return InvalidArgument("features.inlier_distance_voxels",
                           "must be finite and > 0, got " + std::to_string(o.inlier_distance_voxels));
  }
  if (o.min_inliers < 3) {
    return InvalidArgument("features.min_inliers", "must be >= 3, got " + std::to_string(o.min_inliers));
  }
  if (!(o.min_fitness >= 0.0 && o.min_fitness <= 1.0)) {
    return InvalidArgument("features.min_fitness", "must be in [0, 1], got " + std::to_string(o.min_fitness));
  }
  return Status::Ok();
}

std::string Millimetres(double metres) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g mm", metres * 1000.0);
  return text;
}

FeatureAlignmentResult NotAligned(FeatureAlignmentResult result, std::string reason) {
  result.found = false;
  result.reason = std::move(reason);
  result.target_from_source = Pose3::Identity();
  return result;
}

// The share of source points within `reach` of a target point once moved by target_from_source.
double Fitness(std::span<const Eigen::Vector3f> source, const spatial::KdTree& target, const Pose3& target_from_source,
               double reach) {
  const Eigen::Matrix3f rotation = target_from_source.linear().cast<float>();
  const Eigen::Vector3f translation = target_from_source.translation().cast<float>();
  const auto reach_sq = static_cast<float>(reach * reach);
  const size_t near = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, source.size(), 1024), size_t{0},
      [&](const tbb::blocked_range<size_t>& range, size_t count) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          if (target.NearestTwo(rotation * source[i] + translation, reach_sq)[0].slot != spatial::KdTree::kNoSlot) {
            ++count;
          }
        }
        return count;
      },
      [](size_t a, size_t b) { return a + b; });
  return source.empty() ? 0.0 : static_cast<double>(near) / static_cast<double>(source.size());
}

// The positions of the mutually nearest keypoints by SHOT descriptor, pair by pair.
struct MatchedKeypoints {
  std::vector<Eigen::Vector3f> source, target;
};

StatusOr<MatchedKeypoints> Match(const FeatureCloud& from, const ShotDescriptors& from_shot, const FeatureCloud& to,
                                 const ShotDescriptors& to_shot, const std::atomic<bool>* cancel) {
  ASSIGN_OR_RETURN(const std::vector<DescriptorMatch> matches,
                   MatchMutualNearest(from_shot.values, to_shot.values, cancel));
  MatchedKeypoints matched;
  matched.source.reserve(matches.size());
  matched.target.reserve(matches.size());
  for (const DescriptorMatch& m : matches) {
    matched.source.push_back(from.points[from_shot.points[m.source]]);
    matched.target.push_back(to.points[to_shot.points[m.target]]);
  }
  return matched;
}

// One sign of the source's normals: its matches and their consensus.
struct SignedConsensus {
  size_t matches = 0;
  Consensus consensus;
};

}  // namespace

StatusOr<FeatureAlignmentResult> AlignByFeatures(std::span<const Eigen::Vector3f> source,
                                                 std::span<const Eigen::Vector3f> target,
                                                 const FeatureAlignmentOptions& options,
                                                 const std::atomic<bool>* cancel) {
  RETURN_IF_ERROR(Validate(options));
  for (const auto& [facing, points, name] : {std::tuple{options.source_facing, source, "features.source_facing"},
                                             std::tuple{options.target_facing, target, "features.target_facing"}}) {
    if (!facing.empty() && facing.size() != points.size()) {
      return InvalidArgument(name, "has " + std::to_string(facing.size()) + " directions for " +
                                       std::to_string(points.size()) + " points");
    }
  }
  const double voxel = options.voxel_size;
  const double inlier_distance = options.inlier_distance_voxels * voxel;
  FeatureAlignmentResult result;

  FeatureCloudOptions prepare{.voxel = voxel,
                              .normal_radius = options.normal_radius_voxels * voxel,
                              .keypoint_spacing = options.keypoint_spacing_voxels * voxel,
                              .viewpoint = options.source_viewpoint,
                              .facing = options.source_facing,
                              .cancel = cancel};
  ASSIGN_OR_RETURN(FeatureCloud from, PrepareFeatureCloud(source, prepare));
  prepare.viewpoint = options.target_viewpoint;
  prepare.facing = options.target_facing;
  ASSIGN_OR_RETURN(const FeatureCloud to, PrepareFeatureCloud(target, prepare));
  for (const auto& [cloud, name] : {std::pair{static_cast<const FeatureCloud*>(&from), "source"}, std::pair{&to, "target"}}) {
    if (cloud->points.size() < kMinPoints) {
      return NotAligned(result, std::string("too few points: the ") + name + " has " +
                                    std::to_string(cloud->points.size()) + " with normals after thinning to " +
                                    Millimetres(voxel) + " voxels, at least " + std::to_string(kMinPoints) +
                                    " are needed");
    }
  }

  const double radius = options.descriptor_radius_voxels * voxel;
  ASSIGN_OR_RETURN(const ShotDescriptors to_shot, DescribeWithShot(to.points, to.normals, to.keypoints, radius, cancel));
  ASSIGN_OR_RETURN(ShotDescriptors from_shot,
                   DescribeWithShot(from.points, from.normals, from.keypoints, radius, cancel));
  result.keypoints_source = from_shot.points.size();
  result.keypoints_target = to_shot.points.size();
  if (result.keypoints_source < options.min_inliers || result.keypoints_target < options.min_inliers) {
    return NotAligned(result, "too few keypoints: " + std::to_string(result.keypoints_source) + " in the source and " +
                                  std::to_string(result.keypoints_target) + " in the target, min_inliers is " +
                                  std::to_string(options.min_inliers));
  }
  const ConsensusOptions consensus_options{.iterations = options.ransac_iterations,
                                           .inlier_distance = inlier_distance,
                                           .seed = options.seed,
                                           .cancel = cancel};
  const auto seek = [&](const FeatureCloud& source_cloud,
                        const ShotDescriptors& source_shot) -> StatusOr<SignedConsensus> {
    ASSIGN_OR_RETURN(const MatchedKeypoints matched, Match(source_cloud, source_shot, to, to_shot, cancel));
    SignedConsensus found{.matches = matched.source.size(), .consensus = {}};
    if (found.matches < options.min_inliers) return found;
    ASSIGN_OR_RETURN(found.consensus, FindMatchConsensus(matched.source, matched.target, consensus_options));
    return found;
  };
  ASSIGN_OR_RETURN(SignedConsensus best, seek(from, from_shot));
  const bool signs_known = (options.source_viewpoint.has_value() || !options.source_facing.empty()) &&
                           (options.target_viewpoint.has_value() || !options.target_facing.empty());
  if (!signs_known) {
    for (Eigen::Vector3f& n : from.normals) n = -n;
    ASSIGN_OR_RETURN(from_shot, DescribeWithShot(from.points, from.normals, from.keypoints, radius, cancel));
    ASSIGN_OR_RETURN(const SignedConsensus other, seek(from, from_shot));
    if (other.consensus.inliers > best.consensus.inliers) {
      best = other;
      result.flipped_normals = true;
    } else {
      for (Eigen::Vector3f& n : from.normals) n = -n;
    }
  }
  result.matches = best.matches;
  result.inliers = best.consensus.inliers;
  const Consensus& consensus = best.consensus;
  if (result.matches < options.min_inliers) {
    return NotAligned(result, "too few matches: " + std::to_string(result.matches) +
                                  " mutual nearest descriptors, min_inliers is " + std::to_string(options.min_inliers));
  }
  if (result.inliers < options.min_inliers) {
    return NotAligned(result, "no consensus: the best of " + std::to_string(options.ransac_iterations) +
                                  " hypotheses" + (signs_known ? "" : " (for either sign of the source's normals)") +
                                  " has " + std::to_string(result.inliers) + " inliers among " +
                                  std::to_string(result.matches) + " matches, min_inliers is " +
                                  std::to_string(options.min_inliers));
  }

  IcpOptions icp;
  icp.max_correspondence_distance = kIcpReachInInlierDistances * inlier_distance;
  ASSIGN_OR_RETURN(const IcpResult refined, PointToPlaneIcp(from.points, to.points, to.normals,
                                                            consensus.target_from_source, icp, from.normals));
  if (IsCancelled(cancel)) return Cancelled("features: cancelled");
  // From a start this close a real alignment settles within a few iterations; ICP that keeps
  // sliding (shapeless clouds, a plane on a plane) has no single answer.
  if (!refined.converged && !Settled(refined, voxel)) {
    return NotAligned(result, std::string("ICP from the consensus did not converge: ") + IcpStopName(refined.stop));
  }
  const spatial::KdTree target_tree(to.points);
  result.fitness = Fitness(from.points, target_tree, refined.target_from_source, kFitnessVoxels * voxel);
  if (result.fitness < options.min_fitness) {
    return NotAligned(result, "fitness " + std::to_string(result.fitness) + " after ICP is below min_fitness " +
                                  std::to_string(options.min_fitness));
  }
  result.found = true;
  result.target_from_source = refined.target_from_source;
  // The pose is right; the last ICP on clouds thinned to half a voxel takes out most of what the
  // coarse voxels' centroids leave (they shift where a voxel is cut by an edge, differently per view).
  // ICP ignores the normals' signs, so the fine normals are turned towards any point (no spanning tree).
  FeatureCloudOptions fine{.voxel = voxel / kFineVoxelDivisor,
                           .normal_radius = options.normal_radius_voxels * voxel,
                           .keypoint_spacing = options.keypoint_spacing_voxels * voxel,
                           .viewpoint = Eigen::Vector3f::Zero(),
                           .cancel = cancel};
  ASSIGN_OR_RETURN(const FeatureCloud fine_from, PrepareFeatureCloud(source, fine));
  ASSIGN_OR_RETURN(const FeatureCloud fine_to, PrepareFeatureCloud(target, fine));
  IcpOptions fine_icp;
  fine_icp.max_correspondence_distance = voxel;
  ASSIGN_OR_RETURN(const IcpResult polished, PointToPlaneIcp(fine_from.points, fine_to.points, fine_to.normals,
                                                             refined.target_from_source, fine_icp, fine_from.normals));
  if (IsCancelled(cancel)) return Cancelled("features: cancelled");
  if (polished.converged) result.target_from_source = polished.target_from_source;
  return result;
}

}  // namespace vscan::registration
