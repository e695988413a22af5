#include "service/localization/localization_scoring.h"

#include <algorithm>
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

// RESOURCE_EXHAUSTED before any scoring when the pairs would cost more than kMaxScoringWork.
Status CheckScoringWork(const std::vector<localization::PartDefinition>& parts, const ScoringPlan& plan) {
  std::vector<uint64_t> estimates(parts.size()), truths(parts.size());
  // Unknown part ids are ScoreScan's to refuse, naming the field.
  for (const localization::EstimatedInstance& e : plan.estimates) {
    if (e.part_id < parts.size()) ++estimates[e.part_id];
  }
  for (const localization::TrueInstance& t : plan.truth) {
    if (t.part_id < parts.size() && t.visible_fraction >= plan.options.min_visible_fraction) ++truths[t.part_id];
  }
  long double work = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    work += static_cast<long double>(estimates[i]) * truths[i] * PairWork(parts[i], plan.options.symmetry_step);
  }
  if (work <= kMaxScoringWork) return Status::Ok();
  return ResourceExhausted("estimates", "scoring every estimate against every true instance of its part takes " +
                                            std::to_string(static_cast<uint64_t>(work / 1e6)) +
                                            " million vertex operations (vertices x (symmetry transforms + 1) per "
                                            "pair), more than the " + std::to_string(kMaxScoringWork / 1000000) +
                                            " million one call may take; send fewer poses, or a mesh with fewer "
                                            "vertices");
}

}  // namespace

StatusOr<localization::ScanScore> ScorePoses(scenes::SceneRegistry& registry, const ScoringPlan& plan,
                                             const std::atomic<bool>* cancel) {
  std::vector<localization::PartDefinition> parts;
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
  }
  RETURN_IF_ERROR(CheckScoringWork(parts, plan));
  localization::ScoringOptions options = plan.options;
  options.cancel = cancel;
  return localization::ScoreScan(parts, plan.truth, plan.estimates, options);
}

}  // namespace vscan::service
