#pragma once
// A finished fill into its scene: the bin as a new mesh and one object per part at its settled
// pose, in one transaction and one new revision.

#include <string>
#include <vector>

#include "physics/bin_fill.h"
#include "service/bins/bin_fill_plan.h"
#include "scenes/scene_registry.h"
#include "store/catalogue.h"

namespace vscan::service {

struct BinPlacement {
  store::ObjectRecord bin;
  // parts[i] is the object of result.parts[i], labelled "<part name>#<instance + 1>".
  std::vector<store::ObjectRecord> parts;
  uint64_t revision = 0;
};

// NOT_FOUND when the scene (or a part's mesh) went away while the bin filled.
StatusOr<BinPlacement> PlaceBinInScene(scenes::SceneRegistry& registry, const BinFillPlan& plan,
                                       const physics::FillResult& result);

// "<name>#<instance + 1>"
std::string PartLabel(const std::string& name, size_t instance);

}  // namespace vscan::service
