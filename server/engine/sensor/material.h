#pragma once
// What a surface is made of, as an active sensor sees it at its own (near-infrared or visible)
// wavelength: a diffuse albedo and a microfacet specular lobe (docs/SENSORS.md, "Materials").

#include <string>
#include <string_view>
#include <vector>

#include "vscan/common/status.h"

namespace vscan::sensor {

// Perceptual roughness below this is treated as this: GGX with a smaller alpha is a mirror whose
// lobe no pixel or sample can resolve.
inline constexpr double kMinRoughness = 0.02;

struct Material {
  // Dielectrics: the diffuse reflectance. Metals (metallic = 1): the reflectance at normal
  // incidence, which tints the specular lobe; metals have no diffuse term.
  double albedo = 0.5;
  double metallic = 0.0;              // 0 dielectric, 1 metal; in between blends the two
  double roughness = 0.5;             // perceptual; the GGX width is alpha = roughness^2
  double specular_reflectance = 0.04; // a dielectric's reflectance at normal incidence (F0)
};

// Every member finite and within [0, 1]; INVALID_ARGUMENT naming "<field>.<member>".
Status ValidateMaterial(const Material& material, std::string_view field);

struct MaterialPreset {
  std::string name;
  Material material;
  std::string description;  // what it stands for and where its numbers come from
};

// The named materials (docs/SENSORS.md lists them with their sources); the first is the default.
const std::vector<MaterialPreset>& MaterialPresets();
// nullptr for an unknown name.
const MaterialPreset* FindMaterialPreset(std::string_view name);
// What a surface with no material set is made of: the first preset (matte-grey).
const Material& DefaultMaterial();

}  // namespace vscan::sensor
