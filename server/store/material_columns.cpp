#include "store/material_columns.h"

#include <string>

namespace vscan::store {

void BindMaterial(sqlite::Statement& s, int first, const std::optional<MaterialRecord>& material) {
  if (!material) {
    for (int i = 0; i < 5; ++i) s.BindNull(first + i);
    return;
  }
  if (!material->preset.empty()) {
    s.Bind(first, std::string_view(material->preset));
    for (int i = 1; i < 5; ++i) s.BindNull(first + i);
    return;
  }
  s.BindNull(first);
  s.Bind(first + 1, material->albedo).Bind(first + 2, material->metallic);
  s.Bind(first + 3, material->roughness).Bind(first + 4, material->specular_reflectance);
}

StatusOr<std::optional<MaterialRecord>> ReadMaterial(const sqlite::Statement& s, int first, std::string_view what) {
  int values = 0;
  for (int i = 1; i < 5; ++i) values += s.IsNull(first + i) ? 0 : 1;
  const bool has_preset = !s.IsNull(first);
  if (!has_preset && values == 0) return std::optional<MaterialRecord>();
  if (has_preset ? values != 0 : values != 4) {
    return DataLoss("catalogue: the material of " + std::string(what) + " is neither a preset nor four values");
  }
  MaterialRecord material;
  if (has_preset) {
    material.preset = s.Text(first);
    if (material.preset.empty()) {
      return DataLoss("catalogue: the material of " + std::string(what) + " has an empty preset");
    }
    return std::optional<MaterialRecord>(std::move(material));
  }
  material.albedo = s.Double(first + 1);
  material.metallic = s.Double(first + 2);
  material.roughness = s.Double(first + 3);
  material.specular_reflectance = s.Double(first + 4);
  return std::optional<MaterialRecord>(std::move(material));
}

}  // namespace vscan::store
