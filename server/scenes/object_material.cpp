#include "scenes/object_material.h"

#include <string>

namespace vscan::scenes {

StatusOr<sensor::Material> MaterialOf(const store::MaterialRecord& record) {
  if (record.preset.empty()) {
    return sensor::Material{record.albedo, record.metallic, record.roughness, record.specular_reflectance};
  }
  const sensor::MaterialPreset* preset = sensor::FindMaterialPreset(record.preset);
  if (preset == nullptr) return DataLoss("catalogue: unknown material preset '" + record.preset + "'");
  return preset->material;
}

StatusOr<sensor::Material> EffectiveMaterial(const store::ObjectRecord& object, const store::MeshRecord& mesh) {
  if (object.material) return MaterialOf(*object.material);
  if (mesh.material) return MaterialOf(*mesh.material);
  return sensor::DefaultMaterial();
}

}  // namespace vscan::scenes
