#pragma once
// The five catalogue columns that hold a mesh's or an object's material (schema version 6):
// material_preset, then material_albedo, _metallic, _roughness, _specular. All NULL: no material;
// a preset: its name and NULL values; explicit values: NULL preset and the four numbers.

#include <optional>
#include <string_view>

#include "store/catalogue.h"
#include "store/sqlite_statement.h"

namespace vscan::store {

inline constexpr std::string_view kMaterialColumns =
    "material_preset, material_albedo, material_metallic, material_roughness, material_specular";

// Binds parameters first .. first + 4 in kMaterialColumns' order.
void BindMaterial(sqlite::Statement& s, int first, const std::optional<MaterialRecord>& material);
// Reads columns first .. first + 4; DATA_LOSS naming `what` when a row is neither of the three forms.
StatusOr<std::optional<MaterialRecord>> ReadMaterial(const sqlite::Statement& s, int first, std::string_view what);

}  // namespace vscan::store
