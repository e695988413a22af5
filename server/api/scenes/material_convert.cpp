#include "api/scenes/material_convert.h"

#include <cmath>
#include <string>

#include "sensor/material.h"

namespace vscan::api {
namespace {

Status CheckMaterialFraction(double value, std::string_view field, std::string_view member, bool zero_allowed) {
  const std::string path = FieldPath(field, member);
  if (!std::isfinite(value)) return InvalidArgument(path + ": NaN or infinite value");
  if (zero_allowed ? !(value >= 0 && value <= 1) : !(value > 0 && value <= 1)) {
    return InvalidArgument(path + ": " + std::to_string(value) + " is outside " + (zero_allowed ? "[0, 1]" : "(0, 1]"));
  }
  return Status::Ok();
}

std::string KnownMaterialPresets() {
  std::string names;
  for (const sensor::MaterialPreset& preset : sensor::MaterialPresets()) {
    if (!names.empty()) names += ", ";
    names += preset.name;
  }
  return names;
}

}  // namespace

StatusOr<store::MaterialRecord> MaterialFromProto(const v1::Material& material, std::string_view field) {
  store::MaterialRecord record;
  if (!material.preset().empty()) {
    if (material.has_values()) {
      return InvalidArgument(std::string(field) + ": give a preset or values, not both");
    }
    if (sensor::FindMaterialPreset(material.preset()) == nullptr) {
      // The name is quoted only while it is short and printable, so a hostile one cannot flood the message.
      std::string shown = material.preset().size() <= 64 ? material.preset() : material.preset().substr(0, 64) + "...";
      for (char& c : shown) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
      }
      return InvalidArgument(FieldPath(field, "preset") + ": unknown preset '" + shown +
                             "' (known: " + KnownMaterialPresets() + ")");
    }
    record.preset = material.preset();
    return record;
  }
  if (!material.has_values()) return InvalidArgument(std::string(field) + ": give a preset or values");
  const std::string values_field = FieldPath(field, "values");
  const v1::MaterialValues& values = material.values();
  RETURN_IF_ERROR(CheckMaterialFraction(values.diffuse_albedo(), values_field, "diffuse_albedo", true));
  RETURN_IF_ERROR(CheckMaterialFraction(values.metallic(), values_field, "metallic", true));
  RETURN_IF_ERROR(CheckMaterialFraction(values.roughness(), values_field, "roughness", false));
  RETURN_IF_ERROR(CheckMaterialFraction(values.specular_reflectance(), values_field, "specular_reflectance", true));
  record.albedo = values.diffuse_albedo();
  record.metallic = values.metallic();
  record.roughness = values.roughness();
  record.specular_reflectance = values.specular_reflectance();
  return record;
}

StatusOr<std::optional<store::MaterialRecord>> OptionalMaterialFromProto(bool has, const v1::Material& material,
                                                                          std::string_view field) {
  if (!has) return std::optional<store::MaterialRecord>();
  ASSIGN_OR_RETURN(store::MaterialRecord record, MaterialFromProto(material, field));
  return std::optional<store::MaterialRecord>(std::move(record));
}

void ToProto(const store::MaterialRecord& material, v1::Material* out) {
  if (!material.preset.empty()) {
    out->set_preset(material.preset);
    return;
  }
  v1::MaterialValues* values = out->mutable_values();
  values->set_diffuse_albedo(material.albedo);
  values->set_metallic(material.metallic);
  values->set_roughness(material.roughness);
  values->set_specular_reflectance(material.specular_reflectance);
}

}  // namespace vscan::api
