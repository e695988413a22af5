#pragma once
// Alignment without a known pose: keypoints, SHOT descriptors (PCL) and a seeded RANSAC over their
// matches, then point-to-plane ICP. A pair that cannot be aligned is reported as such, never guessed.
// Method, defaults and limits: docs/ALIGNMENT.md.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include <Eigen/Core>

#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::registration {

struct FeatureAlignmentOptions {
  // Both clouds are thinned to this voxel edge (metres); > 0.
  double voxel_size = 0.003;
  // Radius of the normals and of the SHOT support, in voxels.
  double normal_radius_voxels = 3;
  double descriptor_radius_voxels = 10;
  // Keypoints (the points that get a descriptor) lie one per cell of this edge, in voxels; >= 1.
  // The descriptors take most of the time, so it trades time for the matches a small overlap needs.
  double keypoint_spacing_voxels = 3;
  // RANSAC: iterations, and the distance (in voxels) within which a matched keypoint is an inlier.
  int ransac_iterations = 20000;
  double inlier_distance_voxels = 2;
  // The result is accepted when at least this many matches are inliers and, after ICP (which must
  // converge), at least min_fitness of the thinned source points lie within 2 voxels of the target.
  size_t min_inliers = 12;
  double min_fitness = 0.3;
  uint64_t seed = 1;
  // Where the sensor stood, in each cloud's own frame, when known (a scan in its sensor frame: the
  // origin). Normals then face it, which gives both clouds the same sign where they overlap.
  // Otherwise the sign is the shape's call and can differ between two views of one surface, so
  // the consensus is sought with the source's normals as they are and flipped, and the better kept.
  std::optional<Eigen::Vector3f> source_viewpoint;
  std::optional<Eigen::Vector3f> target_viewpoint;
  // Empty, or one per point of that cloud: the direction its surface faces (FeatureCloudOptions::
  // facing), for clouds with no single viewpoint (a union of views, a sampled mesh). A cloud with a
  // viewpoint or facing has known signs; when both have, one sign is tried.
  std::span<const Eigen::Vector3f> source_facing;
  std::span<const Eigen::Vector3f> target_facing;
};

struct FeatureAlignmentResult {
  bool found = false;
  std::string reason;  // why not found
  Pose3 target_from_source = Pose3::Identity();
  size_t keypoints_source = 0;
  size_t keypoints_target = 0;
  size_t matches = 0;
  size_t inliers = 0;
  double fitness = 0;  // after ICP
  // The source's normals were flipped against the target's to reach the consensus.
  bool flipped_normals = false;
};

// InvalidArgument names "features.<option>" for an option out of range; Cancelled when cancel
// becomes true. Too few points or no consensus give found = false with a reason, not an error, and
// the identity as the pose. The same inputs and seed give the same result.
StatusOr<FeatureAlignmentResult> AlignByFeatures(std::span<const Eigen::Vector3f> source,
                                                 std::span<const Eigen::Vector3f> target,
                                                 const FeatureAlignmentOptions& options,
                                                 const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::registration
