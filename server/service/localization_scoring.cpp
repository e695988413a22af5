#include "service/localization_scoring.h"

#include <utility>

namespace vscan::service {

StatusOr<localization::ScanScore> ScorePoses(ServiceContext& context, const ScoringPlan& plan) {
  std::vector<localization::PartDefinition> parts;
  parts.reserve(plan.parts.size());
  for (size_t i = 0; i < plan.parts.size(); ++i) {
    const ScoringPart& part = plan.parts[i];
    const std::string field = "parts[" + std::to_string(i) + "].mesh_id";
    auto mesh = context.registry.LoadMesh(part.mesh_id);
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
  return localization::ScoreScan(parts, plan.truth, plan.estimates, plan.options);
}

}  // namespace vscan::service
