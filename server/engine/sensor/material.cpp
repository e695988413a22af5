#include "sensor/material.h"

#include <cmath>

namespace vscan::sensor {
namespace {

Status CheckUnit(double value, std::string_view field, std::string_view member) {
  if (!std::isfinite(value)) return InvalidArgument(FieldPath(field, member), "NaN or infinite value");
  if (value < 0 || value > 1) return InvalidArgument(FieldPath(field, member), "must be within [0, 1]");
  return Status::Ok();
}

}  // namespace

Status ValidateMaterial(const Material& material, std::string_view field) {
  RETURN_IF_ERROR(CheckUnit(material.albedo, field, "albedo"));
  RETURN_IF_ERROR(CheckUnit(material.metallic, field, "metallic"));
  RETURN_IF_ERROR(CheckUnit(material.roughness, field, "roughness"));
  return CheckUnit(material.specular_reflectance, field, "specular_reflectance");
}

const std::vector<MaterialPreset>& MaterialPresets() {
  // Single-channel values near the 850 nm of structured-light and ToF emitters where published,
  // else at visible wavelengths (docs/SENSORS.md gives each source and how close it is).
  static const std::vector<MaterialPreset> presets = {
      {"matte-grey", {0.5, 0.0, 0.9, 0.04}, "a grey diffuse surface, vscan's default"},
      {"white-abs", {0.85, 0.0, 0.45, 0.045}, "white ABS plastic, satin"},
      {"black-abs", {0.04, 0.0, 0.4, 0.045}, "black ABS plastic, satin"},
      {"cardboard", {0.55, 0.0, 0.95, 0.04}, "brown corrugated cardboard"},
      {"machined-aluminium", {0.87, 1.0, 0.3, 0.04}, "milled or turned aluminium, bare"},
      {"polished-steel", {0.58, 1.0, 0.05, 0.04}, "polished stainless steel"},
      {"brushed-steel", {0.58, 1.0, 0.35, 0.04}, "brushed or ground stainless steel"},
      {"black-anodised-aluminium", {0.05, 0.0, 0.35, 0.04}, "black anodised aluminium"},
  };
  return presets;
}

const MaterialPreset* FindMaterialPreset(std::string_view name) {
  for (const MaterialPreset& preset : MaterialPresets()) {
    if (preset.name == name) return &preset;
  }
  return nullptr;
}

const Material& DefaultMaterial() { return MaterialPresets().front().material; }

}  // namespace vscan::sensor
