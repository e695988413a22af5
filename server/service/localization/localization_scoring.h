#pragma once
// ScorePoses: true and estimated poses of stored meshes scored with the BOP definitions
// (localization/bop_scoring.h). Parts are named by their index in the request.

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "localization/bop_scoring.h"
#include "service/localization/grasp_scoring.h"
#include "scenes/scene_registry.h"
#include "vscan/common/status.h"

namespace vscan::service {

struct ScoringPart {
  std::string mesh_id;
  double scale = 1;
  // Unset: no symmetry (ADD). Set: ADD-S, and MSSD over the symmetries.
  std::optional<localization::PartSymmetries> symmetries;
};

struct ScoringPlan {
  std::vector<ScoringPart> parts;
  std::vector<localization::TrueInstance> truth;          // part_id = index into parts
  std::vector<localization::EstimatedInstance> estimates;  // likewise
  localization::ScoringOptions options;
  // Set: every match is also judged by whether a grasp planned on the estimate holds the true part.
  std::optional<GraspScoring> grasp;
};

struct PoseScores {
  localization::ScanScore scan;
  std::optional<ScanGraspScore> grasp;  // set when the plan has a gripper
};

// The most vertex operations one call may cost (some 10 s on one core of a 2-core VM); each
// pair of an estimate and a valid true instance costs vertices x (symmetry transforms + 1), and
// ADD-S adds kAddSWorkPerVertex per vertex for its k-d tree.
inline constexpr uint64_t kMaxScoringWork = 3'000'000'000;
inline constexpr uint64_t kAddSWorkPerVertex = 20;

// With a gripper the work also counts, per part type with estimates and valid true instances,
// GraspPreparationWork, and GraspJudgementWork per estimate of it.
// NOT_FOUND naming parts[i].mesh_id for an unknown mesh, INVALID_ARGUMENT for a mesh without
// vertices, RESOURCE_EXHAUSTED naming estimates past kMaxScoringWork, CANCELLED once cancel (may
// be null) is set.
StatusOr<localization::ScanScore> ScorePoses(scenes::SceneRegistry& registry, const ScoringPlan& plan,
                                             const std::atomic<bool>* cancel = nullptr);
// ScorePoses, and with plan.grasp the grasp figures; errors of the grasps name the gripper's or
// grasp_options' field, or the part ("parts[i].mesh_id").
StatusOr<PoseScores> ScorePosesWithGrasps(scenes::SceneRegistry& registry, const ScoringPlan& plan,
                                          const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::service
