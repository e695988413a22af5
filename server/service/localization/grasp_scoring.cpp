#include "service/localization/grasp_scoring.h"

#include <cmath>
#include <numbers>
#include <variant>

#include <Eigen/Geometry>

namespace vscan::service {
namespace {

// GraspTarget::Make's own samples of the true surface (OutcomeOptions' default).
constexpr uint64_t kTargetSamples = 20000;
// A suction seal check visits at most every one of the true part's samples.
constexpr uint64_t kSealWork = kTargetSamples;

}  // namespace

StatusOr<Eigen::Vector3d> UnitUp(const Eigen::Vector3d& up, std::string_view field) {
  if (!up.allFinite()) return InvalidArgument(std::string(field), "must be finite");
  // Scaled by its largest component first, so that 1e200 does not overflow the norm.
  const double largest = up.cwiseAbs().maxCoeff();
  if (!(largest > 1e-9)) return InvalidArgument(std::string(field), "must be a non-zero direction (against gravity)");
  return Eigen::Vector3d((up / largest).normalized());
}

Status ValidateGraspScoring(const GraspScoring& scoring) {
  RETURN_IF_ERROR(grasping::ValidateGripper(scoring.gripper));
  const grasping::GraspOptions& o = scoring.grasp_options;
  if (o.max_grasps < 1 || o.max_grasps > 100000) return InvalidArgument("grasp_options.max_grasps", "must be in [1, 100000]");
  if (o.surface_samples < 100 || o.surface_samples > 2000000) {
    return InvalidArgument("grasp_options.surface_samples", "must be in [100, 2000000]");
  }
  if (o.candidates < 1 || o.candidates > 100000) return InvalidArgument("grasp_options.candidates", "must be in [1, 100000]");
  if (o.approaches_per_pair < 1 || o.approaches_per_pair > 64) {
    return InvalidArgument("grasp_options.approaches_per_pair", "must be in [1, 64]");
  }
  return UnitUp(scoring.up, "up").status();
}

uint64_t GraspPreparationWork(const TriangleMesh& mesh, const GraspScoring& scoring) {
  const grasping::GraspOptions& o = scoring.grasp_options;
  const bool jaws = std::holds_alternative<grasping::ParallelJaws>(scoring.gripper);
  // As GenerateGrasps bounds itself: every candidate against every sample (and, jaws, triangle).
  const uint64_t per_candidate =
      jaws ? mesh.triangles.size() + 2 * uint64_t{o.surface_samples} * o.approaches_per_pair : uint64_t{o.surface_samples};
  return uint64_t{o.candidates} * per_candidate + o.surface_samples + kTargetSamples + mesh.triangles.size();
}

uint64_t GraspJudgementWork(const TriangleMesh& mesh, const GraspScoring& scoring) {
  // The grasps scanned for one from above, two rays over every triangle, the seal.
  return uint64_t{scoring.grasp_options.max_grasps} + 2 * mesh.triangles.size() + kSealWork;
}

StatusOr<PartGraspJudge> PartGraspJudge::Make(const TriangleMesh& mesh, const GraspScoring& scoring) {
  PartGraspJudge judge;
  ASSIGN_OR_RETURN(judge.grasps_, grasping::GenerateGrasps(mesh, scoring.gripper, scoring.grasp_options));
  ASSIGN_OR_RETURN(judge.target_, grasping::GraspTarget::Make(mesh, scoring.gripper));
  ASSIGN_OR_RETURN(judge.up_, UnitUp(scoring.up, "up"));
  return judge;
}

GraspVerdict PartGraspJudge::Judge(const Pose3& world_from_truth, const Pose3& world_from_estimate) const {
  if (grasps_.empty()) return {false, std::string(kNoGraspOfThePart)};
  const double min_cos = std::cos(kMaxPlannedApproachTiltDeg * std::numbers::pi / 180);
  const Eigen::Matrix3d world_from_part = world_from_estimate.linear();
  for (const grasping::Grasp& grasp : grasps_) {
    const Eigen::Vector3d approach = world_from_part * grasp.approach;
    // The tolerance keeps a grasp exactly at the limit in despite rounding.
    if (approach.dot(-up_) < min_cos - 1e-12) continue;
    const grasping::GraspOutcome outcome = target_->Try(grasp, world_from_truth.inverse() * world_from_estimate);
    return {outcome.holds, outcome.why};
  }
  return {false, std::string(kNoGraspFromAbove)};
}

StatusOr<ScanGraspScore> JudgeScanGrasps(const localization::ScanScore& score,
                                         std::span<const PartGraspJudge* const> judges,
                                         std::span<const localization::TrueInstance> truth,
                                         std::span<const localization::EstimatedInstance> estimates,
                                         const std::atomic<bool>* cancel) {
  ScanGraspScore out;
  for (size_t p = 0; p < score.parts.size(); ++p) {
    const localization::PartScore& part = score.parts[p];
    PartGraspScore grasps;
    grasps.valid_instances = part.valid_instances;
    for (const localization::InstanceResult& instance : part.instances) {
      if (!instance.estimate_index) {
        grasps.instances.emplace_back();
        continue;
      }
      if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return Cancelled("scoring cancelled");
      if (p >= judges.size() || judges[p] == nullptr) return Internal("no grasps prepared for a matched part");
      const GraspVerdict verdict = judges[p]->Judge(truth[instance.true_index].world_from_part,
                                                    estimates[*instance.estimate_index].world_from_part);
      if (verdict.holds) ++grasps.holds;
      grasps.instances.push_back(verdict);
    }
    if (grasps.valid_instances > 0) grasps.success = double(grasps.holds) / double(grasps.valid_instances);
    out.valid_instances += grasps.valid_instances;
    out.holds += grasps.holds;
    out.parts.push_back(std::move(grasps));
  }
  if (out.valid_instances > 0) out.success = double(out.holds) / double(out.valid_instances);
  return out;
}

}  // namespace vscan::service
