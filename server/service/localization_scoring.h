#pragma once
// ScorePoses: true and estimated poses of stored meshes scored with the BOP definitions
// (localization/bop_scoring.h). Parts are named by their index in the request.

#include <optional>
#include <string>
#include <vector>

#include "localization/bop_scoring.h"
#include "service/service_context.h"
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
};

// NOT_FOUND naming parts[i].mesh_id for an unknown mesh, INVALID_ARGUMENT for a mesh without
// vertices.
StatusOr<localization::ScanScore> ScorePoses(ServiceContext& context, const ScoringPlan& plan);

}  // namespace vscan::service
