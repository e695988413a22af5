#pragma once
// A material as plans write it, without YAML, for the code that carries it on (dataset scenes).

#include <string>

namespace vscan::plan {

// A preset's name (which the server knows: docs/SENSORS.md, "Where materials are set"), or the
// four values, each within [0, 1] (roughness (0, 1]).
struct MaterialPlan {
  std::string preset;
  double diffuse_albedo = 0, metallic = 0, roughness = 0, specular_reflectance = 0;
  bool operator==(const MaterialPlan&) const = default;
};

}  // namespace vscan::plan
