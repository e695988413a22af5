#include "service/localization/localization_scoring.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <utility>

namespace vscan::service {
namespace {

// Vertex operations a part costs per pair of an estimate and a valid true instance: MSSD places
// every vertex once per symmetry transform, ADD once, ADD-S also builds and searches a k-d tree.
uint64_t PairWork(const localization::PartDefinition& part, double symmetry_step) {
  const uint64_t vertices = part.vertices.size();
  const uint64_t transforms = std::max<size_t>(1, localization::SymmetryTransforms(part.symmetries, symmetry_step).size());
  const uint64_t add = part.symmetries.any() ? kAddSWorkPerVertex : 1;
  return vertices * (transforms + add);
}

bool IsCancelled(const std::atomic<bool>* cancel) { return cancel != nullptr && cancel->load(std::memory_order_relaxed); }

// RESOURCE_EXHAUSTED before any scoring when the pairs (and the grasps) would cost more than
// kMaxScoringWork. graspable[i]: part i's grasps are needed (it has estimates and valid truths).
Status CheckScoringWork(const std::vector<localization::PartDefinition>& parts,
                        const std::vector<std::shared_ptr<const TriangleMesh>>& meshes, const ScoringPlan& plan,
                        std::vector<bool>& graspable) {
  std::vector<uint64_t> estimates(parts.size()), truths(parts.size());
  // Unknown part ids are ScoreScan's to refuse, naming the field.
  for (const localization::EstimatedInstance& e : plan.estimates) {
    if (e.part_id < parts.size()) ++estimates[e.part_id];
  }
  for (const localization::TrueInstance& t : plan.truth) {
    if (t.part_id < parts.size() && t.visible_fraction >= plan.options.min_visible_fraction) ++truths[t.part_id];
  }
  long double work = 0;
  graspable.assign(parts.size(), false);
  for (size_t i = 0; i < parts.size(); ++i) {
    work += static_cast<long double>(estimates[i]) * truths[i] * PairWork(parts[i], plan.options.symmetry_step);
    if (plan.grasp && estimates[i] > 0 && truths[i] > 0) {
      graspable[i] = true;
      work += static_cast<long double>(GraspPreparationWork(*meshes[i], *plan.grasp)) +
              static_cast<long double>(estimates[i]) * GraspJudgementWork(*meshes[i], *plan.grasp);
    }
  }
  if (work <= kMaxScoringWork) return Status::Ok();
  return ResourceExhausted("estimates", "scoring every estimate against every true instance of its part takes " +
                                            std::to_string(static_cast<uint64_t>(work / 1e6)) +
                                            " million operations (vertices x (symmetry transforms + 1) per "
                                            "pair, and with a gripper each part type's grasp generation and "
                                            "each estimate's grasp), more than the " +
                                            std::to_string(kMaxScoringWork / 1000000) +
                                            " million one call may take; send fewer poses or part types, a mesh "
                                            "with fewer vertices, or fewer grasp candidates");
}

// The mesh scaled to the part's size, as the poses measure it.
TriangleMesh ScaledMesh(const TriangleMesh& mesh, double scale) {
  TriangleMesh scaled = mesh;
  for (Eigen::Vector3f& v : scaled.vertices) v *= static_cast<float>(scale);
  return scaled;
}

}  // namespace

StatusOr<localization::ScanScore> ScorePoses(scenes::SceneRegistry& registry, const ScoringPlan& plan,
                                             const std::atomic<bool>* cancel) {
  ASSIGN_OR_RETURN(PoseScores scores, ScorePosesWithGrasps(registry, plan, cancel));
  return std::move(scores.scan);
}

StatusOr<PoseScores> ScorePosesWithGrasps(scenes::SceneRegistry& registry, const ScoringPlan& plan,
                                          const std::atomic<bool>* cancel) {
  if (plan.grasp) RETURN_IF_ERROR(ValidateGraspScoring(*plan.grasp));
  std::vector<localization::PartDefinition> parts;
  std::vector<std::shared_ptr<const TriangleMesh>> meshes;
  parts.reserve(plan.parts.size());
  for (size_t i = 0; i < plan.parts.size(); ++i) {
    const ScoringPart& part = plan.parts[i];
    const std::string field = "parts[" + std::to_string(i) + "].mesh_id";
    auto mesh = registry.LoadMesh(part.mesh_id);
    if (!mesh.ok()) {
      if (mesh.status().code() == StatusCode::kNotFound) return NotFound(field, "no mesh '" + part.mesh_id + "'");
      return mesh.status();
    }
    if ((*mesh)->vertices.empty()) return InvalidArgument(field, "the mesh has no vertices");
    localization::PartDefinition definition;
    definition.part_id = static_cast<uint32_t>(i);
    definition.vertices = (*mesh)->vertices;
    for (Eigen::Vector3f& v : definition.vertices) v *= static_cast<float>(part.scale);
    if (part.symmetries) definition.symmetries = *part.symmetries;
    parts.push_back(std::move(definition));
    meshes.push_back(*mesh);
  }
  std::vector<bool> graspable;
  RETURN_IF_ERROR(CheckScoringWork(parts, meshes, plan, graspable));
  localization::ScoringOptions options = plan.options;
  options.cancel = cancel;
  PoseScores out;
  ASSIGN_OR_RETURN(out.scan, localization::ScoreScan(parts, plan.truth, plan.estimates, options));
  if (!plan.grasp) return out;

  std::vector<std::optional<PartGraspJudge>> judges(parts.size());
  std::vector<const PartGraspJudge*> judge_of(parts.size(), nullptr);
  for (size_t i = 0; i < parts.size(); ++i) {
    if (!graspable[i]) continue;
    if (IsCancelled(cancel)) return Cancelled("scoring cancelled");
    auto judge = PartGraspJudge::Make(ScaledMesh(*meshes[i], plan.parts[i].scale), *plan.grasp);
    // The request's fields (gripper, grasp_options) keep their names; the mesh's are the part's.
    if (!judge.ok() && judge.status().field() == "mesh") {
      return judge.status().WithFieldPrefix("parts[" + std::to_string(i) + "]");
    }
    if (!judge.ok()) return judge.status();
    judges[i] = std::move(*judge);
    judge_of[i] = &*judges[i];
  }
  ASSIGN_OR_RETURN(out.grasp, JudgeScanGrasps(out.scan, judge_of, plan.truth, plan.estimates, cancel));
  return out;
}

}  // namespace vscan::service
