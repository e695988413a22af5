#pragma once
// A bin fill as plans write it: the bin (a box or a mesh) and the parts dropped into it. One reader
// for every plan that fills a bin: `vscan bin fill PLAN` and each bin of a dataset plan
// (docs/BINS.md, "Bin plans"; docs/DATASETS.md, "The plan file").

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vscan/plan/material_plan.h"
#include "vscan/plan/yaml_reader.h"

namespace vscan::plan {

inline constexpr uint64_t kMaxPartCount = 100000;
// Materials one `material: {choose: [...]}` may list.
inline constexpr size_t kMaxMaterialChoices = 64;

// A mesh file in its unit (as the plan writes the path; relative paths start at the plan's
// directory), or a stored mesh by id (in metres).
struct MeshSource {
  std::string file;
  std::string unit;  // m, cm, mm, in or ft; set with file only
  std::string mesh_id;
  // Where the plan names it ("parts[1].mesh"), for errors found later (a file that is missing).
  std::string key;
  YAML::Mark mark;
};

struct PartPlan {
  MeshSource mesh;
  uint32_t count = 0;
  std::optional<double> scale;
  std::string name;  // empty: the caller's default (the file's stem)
  std::optional<double> mass_kg;
  std::optional<double> density_kg_per_m3;
  std::string collision;  // "", "convex_hull" or "convex_decomposition"
  std::optional<MaterialPlan> material;
  // `material: {choose: [...]}`: one of these per scene (dataset plans only; a bin fill refuses it).
  std::vector<MaterialPlan> material_choices;
  YAML::Mark material_mark;  // where material: stands, for errors found later
};

struct BoxBinPlan {
  Eigen::Vector3d inner_size = Eigen::Vector3d::Zero();
  std::optional<double> wall_thickness;
};

struct MeshBinPlan {
  MeshSource mesh;
  std::optional<double> scale;
};

struct BinFillPlan {
  // Exactly one of the two.
  std::optional<BoxBinPlan> box;
  std::optional<MeshBinPlan> mesh_bin;
  std::vector<PartPlan> parts;
};

// The unit's short name for m, cm, mm, in, ft or their long names (metre, meter, inch, feet, ...);
// nullopt for anything else.
std::optional<std::string> ShortUnitName(std::string_view unit);
// Metres per unit of a short unit name; nullopt for an unknown name.
std::optional<double> MetresPerUnit(std::string_view unit);

// material: NAME, or {diffuse_albedo, metallic, roughness, specular_reflectance}, all four, each
// within [0, 1] (roughness (0, 1]), as the server checks them. Names are not looked up here: the
// plan's reader or the server knows the presets.
StatusOr<MaterialPlan> ReadMaterial(const YamlReader& yaml, const YamlAt& at);
// A material as ReadMaterial reads it, or {choose: [material, ...]} with 1 to kMaxMaterialChoices
// materials; one material is a list of one.
StatusOr<std::vector<MaterialPlan>> ReadMaterialChoice(const YamlReader& yaml, const YamlAt& at);
// Whether at is written as a choice ({choose: ...}).
bool IsMaterialChoice(const YamlAt& at);

// bin: {inner_size, wall_thickness, pose} or {mesh | mesh_id, unit, scale, pose}; parts: a list of
// {mesh | mesh_id, unit, count, scale, name, mass_kg, density_kg_per_m3, collision, material}; material may be a
// choice (material_choices), which callers that take one material refuse. Errors name
// the key path and line; sizes and totals are the fill's own checks. The bin's pose is allowed but
// not read: plans read poses with their own rules (bin.pose).
StatusOr<BinFillPlan> ReadBinFill(const YamlReader& yaml, const YamlAt& bin, const YamlAt& parts);

}  // namespace vscan::plan
