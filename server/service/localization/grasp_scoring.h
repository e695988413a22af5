#pragma once
// Would a grasp planned on an estimated pose have held the true part? Per part type the grasps
// are generated once; each matched estimate takes the best grasp that approaches from above at
// the estimated pose, and that grasp is tried against the true part (grasping::GraspTarget).
// Method: docs/LOCALIZATION.md, "Grasp success".

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "grasping/grasp_generation.h"
#include "grasping/grasp_outcome.h"
#include "grasping/gripper.h"
#include "localization/bop_scoring.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::service {

// The planned grasp approaches at most this far from straight down (-up).
inline constexpr double kMaxPlannedApproachTiltDeg = 60;
// Why an estimate gets no grasp: the gripper has none on the part at all, or none of the kept
// grasps (grasp_options.max_grasps, best first) approaches from above at the estimated pose.
inline constexpr std::string_view kNoGraspOfThePart = "the gripper has no grasp on the part";
inline constexpr std::string_view kNoGraspFromAbove = "no grasp of the part approaches from above at the estimated pose";

struct GraspScoring {
  grasping::Gripper gripper;
  grasping::GraspOptions grasp_options;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // against gravity, in the poses' frame; non-zero
};

struct GraspVerdict {
  bool holds = false;
  std::string failure;  // empty when it holds
};

// INVALID_ARGUMENT naming field for a zero, tiny or non-finite vector; else the unit vector.
StatusOr<Eigen::Vector3d> UnitUp(const Eigen::Vector3d& up, std::string_view field);

// INVALID_ARGUMENT naming "gripper.*", "grasp_options.*" (GenerateGrasps' ranges) or "up", checked
// before any work is counted or done.
Status ValidateGraspScoring(const GraspScoring& scoring);

// Operations preparing one part type takes (GenerateGrasps counted as it bounds itself, plus the
// true geometry's samples), and one judgement of an estimate (every grasp's approach, the rays).
uint64_t GraspPreparationWork(const TriangleMesh& mesh, const GraspScoring& scoring);
uint64_t GraspJudgementWork(const TriangleMesh& mesh, const GraspScoring& scoring);

// One part type's grasps (part frame, best first) and its true geometry.
class PartGraspJudge {
 public:
  // mesh in metres, as the poses are. Errors of GenerateGrasps and GraspTarget::Make.
  static StatusOr<PartGraspJudge> Make(const TriangleMesh& mesh, const GraspScoring& scoring);

  // The best grasp within kMaxPlannedApproachTiltDeg of -up at world_from_estimate, tried with
  // truth_from_estimate = world_from_truth^-1 * world_from_estimate.
  GraspVerdict Judge(const Pose3& world_from_truth, const Pose3& world_from_estimate) const;

  size_t grasp_count() const { return grasps_.size(); }

 private:
  std::vector<grasping::Grasp> grasps_;
  std::shared_ptr<const grasping::GraspTarget> target_;
  Eigen::Vector3d up_ = Eigen::Vector3d::UnitZ();
};

// One part type's grasp figures in a scan: per matched true instance a verdict.
struct PartGraspScore {
  size_t valid_instances = 0;
  size_t holds = 0;
  // Parallel to PartScore::instances; unset for an instance no estimate matched.
  std::vector<std::optional<GraspVerdict>> instances;
  // holds / valid_instances (the ADD recall's denominator); unset without valid instances.
  std::optional<double> success;
};

struct ScanGraspScore {
  std::vector<PartGraspScore> parts;  // in the order of ScanScore::parts
  size_t valid_instances = 0;
  size_t holds = 0;
  std::optional<double> success;
};

// judges[i] serves score.parts[i]; it may be null for a part without matches. Poses are the ones
// ScoreScan was given. CANCELLED once cancel (may be null) is set, polled between estimates.
StatusOr<ScanGraspScore> JudgeScanGrasps(const localization::ScanScore& score,
                                         std::span<const PartGraspJudge* const> judges,
                                         std::span<const localization::TrueInstance> truth,
                                         std::span<const localization::EstimatedInstance> estimates,
                                         const std::atomic<bool>* cancel);

}  // namespace vscan::service
