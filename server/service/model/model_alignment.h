#pragma once
// The alignment stage of a model job: every scan in turn against the union of the scans aligned
// before it (from its known pose, or from feature matches when its pose is unknown), then the pose
// graph, the set placed where it best agrees with the known poses, and each pose's error against
// the truth when the server knows it.

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "service/job/job_events.h"
#include "service/model/model_crop.h"
#include "service/model/model_plan.h"
#include "service/model/model_scans.h"
#include "vscan/common/pose.h"

namespace vscan::service {

struct AlignmentSettings {
  double voxel_size = 0;  // 0: from the first scan's size
  double max_correspondence_distance = 0;
  double min_fitness = kDefaultMinFitness;
  bool pose_graph = true;
};

struct AlignedScans {
  // One per cloud of the plan, in its order.
  std::vector<ScanAlignmentRecord> scans;
  std::vector<std::optional<Pose3>> truth;  // true model_from_sensor, when known
  // False when the first scan aligned had no known pose: the poses are then in that scan's frame.
  bool in_model_frame = true;
  std::string initial_pose;  // "known", "features" or "known+features"
  double voxel_size = 0;
  double seconds = 0;
};

// Called after each scan is added (done scans so far), with its alignment against the scans before.
using ScanAlignedCallback = std::function<Status(const ScanAlignmentRecord& scan, size_t done)>;

// Aligns scans one at a time, each against the union of those before it (a model job's clouds in
// order, or a campaign's scans as they are captured). Finish retries the scans whose features
// matched nothing, runs the pose graph and places the set. CANCELLED when cancel becomes true.
class ModelAligner {
 public:
  ModelAligner(const AlignmentSettings& settings, ScanAlignedCallback on_scan, const std::atomic<bool>* cancel);
  ~ModelAligner();
  ModelAligner(const ModelAligner&) = delete;
  ModelAligner& operator=(const ModelAligner&) = delete;

  // scan.index is its place in the job's list of clouds; on_scan reports it.
  Status Add(ModelScan scan);
  StatusOr<AlignedScans> Finish();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// Every cloud of plan through a ModelAligner. CANCELLED when cancel becomes true.
StatusOr<AlignedScans> AlignScans(const StoredClouds& clouds, const ModelPlan& plan, const ModelCrop& crop,
                                  const AlignmentSettings& settings, const ScanAlignedCallback& on_scan,
                                  const std::atomic<bool>* cancel);

// The clouds as they are (skip_alignment): each at its stored pose.
StatusOr<AlignedScans> TakeScansAsTheyAre(const StoredClouds& clouds, const ModelPlan& plan, const ModelCrop& crop,
                                          const std::atomic<bool>* cancel);

// Rotation (degrees) and translation (metres) between two poses.
double RotationErrorDeg(const Pose3& a, const Pose3& b);
double TranslationError(const Pose3& a, const Pose3& b);

// The rigid motion that best lays the poses `from` onto `to` (sensor positions and a point ahead
// of each sensor at `reach` metres), least squares.
Pose3 FitPoses(const std::vector<Pose3>& from, const std::vector<Pose3>& to, double reach);

}  // namespace vscan::service
