#pragma once
// Which material each part instance of a dataset scene is made of: a part type with several
// materials takes one per (seed, bin), so that the sensors of one fill see the same bin, and
// scene_materials.json records them beside the BOP files (docs/DATASETS.md).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vscan/plan/material_plan.h"

namespace vscan::service {
class JsonWriter;
}

namespace vscan::service::dataset {

// The index among `count` materials part type `part_index` of bin `bin_index` takes under the
// scene's seed: the same inputs give the same index, on every build (splitmix64 steps).
size_t PartMaterialIndex(uint64_t seed, size_t bin_index, size_t part_index, size_t count);

struct InstanceMaterial {
  uint32_t instance_id = 0;  // as in the instance images and scene_gt.json's order
  uint32_t obj_id = 0;
  std::string part;  // the part type's name
  plan::MaterialPlan material;
};

// {"preset": NAME} or {diffuse_albedo, metallic, roughness, specular_reflectance}, as a value.
void WriteMaterial(JsonWriter& json, const plan::MaterialPlan& material);

// {"instances": [{"instance_id", "obj_id", "part", "material": {"preset"} or {the four values}}]}.
std::string SceneMaterialsJson(const std::vector<InstanceMaterial>& instances);

}  // namespace vscan::service::dataset
