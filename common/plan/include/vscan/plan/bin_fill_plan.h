#pragma once
// A bin fill as plans write it: the bin (a box or a mesh) and the parts dropped into it. One reader
// for every plan that fills a bin: `vscan bin fill PLAN` and each bin of a dataset plan
// (docs/BINS.md, "Bin plans"; docs/DATASETS.md, "The plan file").

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vscan/plan/yaml_reader.h"

namespace vscan::plan {

inline constexpr uint64_t kMaxPartCount = 100000;

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

// A preset's name, or the four values (checked by the server: docs/SENSORS.md, "Where materials
// are set").
struct MaterialPlan {
  std::string preset;
  double diffuse_albedo = 0, metallic = 0, roughness = 0, specular_reflectance = 0;
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

// bin: {inner_size, wall_thickness, pose} or {mesh | mesh_id, unit, scale, pose}; parts: a list of
// {mesh | mesh_id, unit, count, scale, name, mass_kg, density_kg_per_m3, collision, material}. Errors name
// the key path and line; sizes and totals are the fill's own checks. The bin's pose is allowed but
// not read: plans read poses with their own rules (bin.pose).
StatusOr<BinFillPlan> ReadBinFill(const YamlReader& yaml, const YamlAt& bin, const YamlAt& parts);

}  // namespace vscan::plan
