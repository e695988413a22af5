#pragma once
// Point-pair-feature voting (Drost, Ulrich, Navab, Ilic, "Model Globally, Match Locally: Efficient
// and Robust 3D Object Recognition", CVPR 2010): scene point pairs look up the model pairs with
// the same quantized feature, each vote fixes a pose, and the poses the most pairs agree on are the
// candidates.

#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::localization {

struct PpfSettings {
  // Pair distances are binned by this (metres), the three angles and the rotation about the
  // reference normal by angle_step_rad.
  double distance_step = 0.002;
  double angle_step_rad = 0.2094;  // 12 degrees
  // Every n-th scene point is a reference point that votes.
  unsigned scene_reference_stride = 5;
  // Poses this close (metres, radians) count as one candidate.
  double cluster_distance = 0.005;
  double cluster_angle_rad = 0.5236;  // 30 degrees
};

struct PoseCandidate {
  Pose3 scene_from_part = Pose3::Identity();
  uint32_t votes = 0;  // summed over the reference points whose best pose fell in the cluster
};

// The model's pair table, built once (quadratic in the model's points) and searched per scene.
// Pairs whose normals are parallel to within one angle step are left out, in the model and the
// scene alike: on a flat face every such pair looks the same and they would swamp the table.
// Rim pairs take their place there: any point paired with a point on a surface's rim
// (boundary_points.h), keyed by the distance, the angles of the reference's normal and the rim's
// outward direction to the line between them, and the angles between the reference's normal and
// the rim's direction and normal (after Drost and Ilic's pairs of edge points, 3DIMPVT 2012).
class PpfModel {
 public:
  // Points and unit outward normals in the part frame, of equal length; rims empty, or one
  // direction per point (zero off the rim).
  PpfModel(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
           std::span<const Eigen::Vector3f> rims, const PpfSettings& settings);

  // Candidates by decreasing votes, each the vote-weighted mean of the poses pooled into it. The
  // scene's normals must face out of its surfaces as the model's do; rims as the model's. Polls
  // cancel between reference points (an empty list when it is set).
  std::vector<PoseCandidate> Vote(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                                  std::span<const Eigen::Vector3f> rims, const std::atomic<bool>* cancel = nullptr) const;

  size_t pair_count() const { return entries_.size(); }
  // What the table holds in memory.
  size_t memory_bytes() const { return entries_.capacity() * sizeof(Entry) + runs_.capacity() * sizeof(Run); }

 private:
  struct Entry {
    uint64_t key;
    uint32_t slot;   // reference * alpha_bins_: the reference's first accumulator slot
    uint16_t alpha;  // the pair's angle about the reference normal, in the reference's local frame, in 2^-16 turns
  };
  std::optional<uint64_t> Key(const Eigen::Vector3f& p1, const Eigen::Vector3f& n1, const Eigen::Vector3f& p2,
                              const Eigen::Vector3f& n2) const;
  std::optional<uint64_t> RimKey(const Eigen::Vector3f& p1, const Eigen::Vector3f& n1, const Eigen::Vector3f& p2,
                                 const Eigen::Vector3f& n2, const Eigen::Vector3f& rim2) const;

  PpfSettings settings_;
  std::vector<Eigen::Vector3f> points_, normals_;
  float max_distance_ = 0;
  std::vector<Entry> entries_;  // sorted by key
  // Each key's run [begin, end) in entries_, in an open-addressed table (linear probing, a power
  // of two at most half full): one probe per scene pair, mostly within one cache line.
  struct Run {
    uint64_t key;
    uint32_t begin, end;  // end == 0: an empty slot
  };
  const Run* FindRun(uint64_t key) const;
  std::vector<Run> runs_;
  uint64_t run_mask_ = 0;
  uint32_t alpha_bins_ = 1;
};

}  // namespace vscan::localization
