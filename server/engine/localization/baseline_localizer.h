#pragma once
// A baseline localizer: finds instances of one part in a scan one after another. The plate the
// parts stand on is removed; then, repeatedly, point-pair-feature voting (ppf_voting.h) proposes
// the best-voted pose among the scan points not yet explained, point-to-plane ICP refines it, and
// the scan points the placed part explains are removed. Method, defaults and limits:
// docs/LOCALIZATION.md.

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "localization/part_model.h"
#include "vscan/common/mesh.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::localization {

struct LocalizerOptions {
  // The fine length (metres) the other lengths are counted in; 0 picks the diagonal of the part's
  // bounding box / 50, or its middle extent / 10 when that is smaller (a long thin part).
  double voxel_size = 0;
  // Points sampled on the part's surface (with its outward normals).
  size_t model_samples = 20000;
  // Point-pair features: both clouds are thinned to this edge (in voxels; 2.5 is 5% of the
  // diagonal, Drost et al.'s choice), which also bins the pair distances; angles are binned by
  // ppf_angle_step_deg; every scene_reference_stride-th thinned scan point votes.
  double ppf_step_voxels = 2.5;
  double ppf_angle_step_deg = 12;
  unsigned scene_reference_stride = 5;
  // Before the search, the points within plane_distance_voxels of the dominant plane are removed
  // when that plane holds at least min_plane_share of the scan: the plate the parts stand on.
  bool remove_support_plane = true;
  double plane_distance_voxels = 1.5;
  double min_plane_share = 0.3;
  // Scan points within this distance of the placed part (and, when the scan has normals, with a
  // normal within max_normal_angle_deg of the part's there) are explained by it and removed.
  double explained_distance_voxels = 2;
  double max_normal_angle_deg = 60;
  // The score of an instance: the share of the part's samples, placed, with a scan point (the
  // plate's left out) within this distance whose normal is within max_normal_angle_deg of the
  // part's there. A scan sees one side, so about half is the most a single view gives.
  double inlier_distance_voxels = 1.5;
  // An instance must explain at least this many scan points and score at least min_score, or the
  // search stops.
  size_t min_explained_points = 100;
  double min_score = 0.08;
  size_t max_instances = 10;
  // Only for a scan without normals: estimated normals are turned towards this point (the
  // sensor's position; the origin for a scan in the sensor frame).
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
  // The sensor's position, when known: candidates are then ranked and checked against what it saw
  // (a placed part's points facing it must lie on the scan's surface, not in front of the scan
  // where the sensor saw through them). Up to view_candidates best-voted candidates are ranked.
  std::optional<Eigen::Vector3d> sensor_position;
  size_t view_candidates = 10000;
  // Of the placed part's points facing the sensor and not hidden, at most this share may lie where
  // the sensor saw past them. True instances of machined metal parts lit by the scanner's own
  // emitter reach 20-45% (their gaps and stray returns), clutter fits more.
  double max_seen_through_share = 0.4;
};

// One part to look for: its mesh (metres, its own frame) and how many instances at most.
struct PartQuery {
  const TriangleMesh* mesh = nullptr;
  size_t max_instances = 0;  // 0: LocalizerOptions::max_instances
  // The mesh's model built with ModelSettingsOf(options), when the caller keeps one; else built here.
  std::shared_ptr<const PartModel> model;
};

// What a part's model is built with, from the localizer's options.
PartModelSettings ModelSettingsOf(const LocalizerOptions& options);

struct LocalizedInstance {
  size_t part = 0;  // index into the parts searched
  Pose3 world_from_part = Pose3::Identity();
  double score = 0;  // see LocalizerOptions::inlier_distance_voxels
  size_t explained_points = 0;
};

// How the search for one part went.
struct PartSearch {
  double voxel_size = 0;    // the one used
  size_t found = 0;         // instances of this part in LocalizationResult::instances
  std::string stop_reason;  // why its search ended
};

struct LocalizationResult {
  std::vector<LocalizedInstance> instances;  // in the order found
  std::vector<PartSearch> parts;             // one per part searched, in the order given
  size_t support_plane_points = 0;           // removed as the plate's
};

// Where a search stands, reported between its stages: the share done (0 to 1) and the
// instances found so far.
struct LocalizeProgress {
  double fraction = 0;
  size_t found = 0;
  std::string stage;
};
using LocalizeProgressCallback = std::function<void(const LocalizeProgress&)>;

// Every part of `parts` in one scan. scan_points in the world frame; scan_normals empty or one per
// point, facing the sensor. InvalidArgument for no parts, a part without a mesh or area ("parts[i]"),
// normals of the wrong count or options out of range (naming "localizer.<option>"); Cancelled when
// cancel turns true. progress, when set, is called on the calling thread.
StatusOr<LocalizationResult> LocalizeParts(std::span<const PartQuery> parts, std::span<const Eigen::Vector3f> scan_points,
                                           std::span<const Eigen::Vector3f> scan_normals,
                                           const LocalizerOptions& options = {},
                                           const std::atomic<bool>* cancel = nullptr,
                                           const LocalizeProgressCallback& progress = {});

// One part (up to options.max_instances instances).
StatusOr<LocalizationResult> LocalizeInstances(const TriangleMesh& part, std::span<const Eigen::Vector3f> scan_points,
                                               std::span<const Eigen::Vector3f> scan_normals,
                                               const LocalizerOptions& options = {},
                                               const std::atomic<bool>* cancel = nullptr);

// The same on a scan cloud: its positions, and its normals when it has them.
StatusOr<LocalizationResult> LocalizeInstances(const TriangleMesh& part, const PointCloud& scan,
                                               const LocalizerOptions& options = {},
                                               const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::localization
