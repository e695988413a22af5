#include "vscan/plan/bin_fill_plan.h"

#include <algorithm>
#include <cctype>
#include <utility>

namespace vscan::plan {
namespace {

struct UnitName {
  const char* short_name;
  double metres;
  std::vector<std::string_view> long_names;
};

const std::vector<UnitName>& Units() {
  static const std::vector<UnitName> kUnits = {{"m", 1.0, {"metre", "meter", "metres", "meters"}},
                                               {"cm", 0.01, {"centimetre", "centimeter"}},
                                               {"mm", 0.001, {"millimetre", "millimeter"}},
                                               {"in", 0.0254, {"inch", "inches"}},
                                               {"ft", 0.3048, {"foot", "feet"}}};
  return kUnits;
}

StatusOr<double> Positive(const YamlReader& yaml, const YamlAt& at, const std::string& what) {
  ASSIGN_OR_RETURN(const double value, yaml.Number(at));
  if (!(value > 0)) return yaml.Error(at, "must be positive" + what);
  return value;
}

// mesh (a file, with its unit) or mesh_id (a stored mesh, in metres) at item's keys.
StatusOr<MeshSource> ReadMeshSource(const YamlReader& yaml, const YamlAt& item) {
  const YamlAt mesh = YamlReader::Child(item, "mesh");
  const YamlAt mesh_id = YamlReader::Child(item, "mesh_id");
  const YamlAt unit = YamlReader::Child(item, "unit");
  if (YamlReader::Has(mesh) == YamlReader::Has(mesh_id)) {
    return yaml.Error(item, "give either mesh (a file) or mesh_id (an uploaded mesh)");
  }
  MeshSource source;
  const YamlAt& named = YamlReader::Has(mesh) ? mesh : mesh_id;
  source.key = named.path;
  source.mark = named.node.Mark();
  if (YamlReader::Has(mesh_id)) {
    if (YamlReader::Has(unit)) return yaml.Error(unit, "an uploaded mesh is in metres already; use scale");
    ASSIGN_OR_RETURN(source.mesh_id, yaml.String(mesh_id));
    return source;
  }
  ASSIGN_OR_RETURN(source.file, yaml.String(mesh));
  if (!YamlReader::Has(unit)) return yaml.Error(unit, "required: the unit the mesh is written in (m, cm, mm, in, ft)");
  ASSIGN_OR_RETURN(const std::string text, yaml.String(unit));
  const std::optional<std::string> short_name = ShortUnitName(text);
  if (!short_name) return yaml.Error(unit, "unknown unit '" + text + "' (m, cm, mm, in, ft)");
  source.unit = *short_name;
  return source;
}

StatusOr<BoxBinPlan> ReadBox(const YamlReader& yaml, const YamlAt& at) {
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"inner_size", "wall_thickness", "pose"}));
  const YamlAt size = YamlReader::Child(at, "inner_size");
  if (!YamlReader::Has(size)) return yaml.Error(size, "required: [length, width, depth] in metres");
  BoxBinPlan box;
  ASSIGN_OR_RETURN(box.inner_size, yaml.Vector3(size));
  if (const YamlAt wall = YamlReader::Child(at, "wall_thickness"); YamlReader::Has(wall)) {
    ASSIGN_OR_RETURN(box.wall_thickness, Positive(yaml, wall, " (metres)"));
  }
  return box;
}

StatusOr<MeshBinPlan> ReadMeshBin(const YamlReader& yaml, const YamlAt& at) {
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"mesh", "mesh_id", "unit", "scale", "pose"}));
  MeshBinPlan bin;
  ASSIGN_OR_RETURN(bin.mesh, ReadMeshSource(yaml, at));
  if (const YamlAt scale = YamlReader::Child(at, "scale"); YamlReader::Has(scale)) {
    ASSIGN_OR_RETURN(bin.scale, Positive(yaml, scale, ""));
  }
  return bin;
}

StatusOr<PartPlan> ReadPart(const YamlReader& yaml, const YamlAt& item) {
  RETURN_IF_ERROR(yaml.ExpectMap(
      item,
      {"mesh", "mesh_id", "unit", "count", "scale", "name", "mass_kg", "density_kg_per_m3", "collision", "material"}));
  PartPlan part;
  ASSIGN_OR_RETURN(part.mesh, ReadMeshSource(yaml, item));
  const YamlAt count = YamlReader::Child(item, "count");
  if (!YamlReader::Has(count)) return yaml.Error(count, "required: how many of this part");
  ASSIGN_OR_RETURN(const uint64_t n, yaml.Integer(count, 1, kMaxPartCount));
  part.count = static_cast<uint32_t>(n);
  if (const YamlAt scale = YamlReader::Child(item, "scale"); YamlReader::Has(scale)) {
    ASSIGN_OR_RETURN(part.scale, Positive(yaml, scale, ""));
  }
  if (const YamlAt name = YamlReader::Child(item, "name"); YamlReader::Has(name)) {
    ASSIGN_OR_RETURN(part.name, yaml.String(name));
  }
  if (const YamlAt mass = YamlReader::Child(item, "mass_kg"); YamlReader::Has(mass)) {
    ASSIGN_OR_RETURN(part.mass_kg, Positive(yaml, mass, " (kilograms)"));
  }
  if (const YamlAt density = YamlReader::Child(item, "density_kg_per_m3"); YamlReader::Has(density)) {
    ASSIGN_OR_RETURN(part.density_kg_per_m3, Positive(yaml, density, " (kilograms per cubic metre)"));
  }
  if (const YamlAt collision = YamlReader::Child(item, "collision"); YamlReader::Has(collision)) {
    ASSIGN_OR_RETURN(part.collision, yaml.String(collision));
    if (part.collision != "convex_hull" && part.collision != "convex_decomposition") {
      return yaml.Error(collision,
                        "unknown collision shape '" + part.collision + "' (convex_hull or convex_decomposition)");
    }
  }
  if (const YamlAt material = YamlReader::Child(item, "material"); YamlReader::Has(material)) {
    part.material_mark = material.node.Mark();
    if (IsMaterialChoice(material)) {
      ASSIGN_OR_RETURN(part.material_choices, ReadMaterialChoice(yaml, material));
    } else {
      ASSIGN_OR_RETURN(part.material, ReadMaterial(yaml, material));
    }
  }
  return part;
}

}  // namespace

StatusOr<MaterialPlan> ReadMaterial(const YamlReader& yaml, const YamlAt& at) {
  MaterialPlan material;
  if (at.node.IsScalar()) {
    ASSIGN_OR_RETURN(material.preset, yaml.String(at));
    return material;
  }
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"diffuse_albedo", "metallic", "roughness", "specular_reflectance"}));
  for (const auto& [key, value] : {std::pair<const char*, double*>{"diffuse_albedo", &material.diffuse_albedo},
                                   {"metallic", &material.metallic},
                                   {"roughness", &material.roughness},
                                   {"specular_reflectance", &material.specular_reflectance}}) {
    const YamlAt child = YamlReader::Child(at, key);
    if (!YamlReader::Has(child)) return yaml.Error(child, "required: a preset's name, or all four values");
    ASSIGN_OR_RETURN(*value, yaml.Number(child));
    // As the server checks them: a roughness of 0 is a mirror no pixel resolves.
    const bool roughness = value == &material.roughness;
    if (roughness ? !(*value > 0 && *value <= 1) : !(*value >= 0 && *value <= 1)) {
      return yaml.Error(child, roughness ? "must be within (0, 1]" : "must be within [0, 1]");
    }
  }
  return material;
}

bool IsMaterialChoice(const YamlAt& at) { return YamlReader::Has(at) && at.node.IsMap() && at.node["choose"]; }

StatusOr<std::vector<MaterialPlan>> ReadMaterialChoice(const YamlReader& yaml, const YamlAt& at) {
  if (!IsMaterialChoice(at)) {
    ASSIGN_OR_RETURN(MaterialPlan one, ReadMaterial(yaml, at));
    return std::vector<MaterialPlan>{std::move(one)};
  }
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"choose"}));
  const YamlAt list = YamlReader::Child(at, "choose");
  if (!YamlReader::Has(list)) return yaml.Error(list, "required: a list of materials to choose from");
  RETURN_IF_ERROR(yaml.ExpectSequence(list, 1));
  // Checked before any item is read, so that a huge list costs nothing more.
  if (list.node.size() > kMaxMaterialChoices) {
    return yaml.Error(list, "at most " + std::to_string(kMaxMaterialChoices) + " materials, got " +
                                std::to_string(list.node.size()));
  }
  std::vector<MaterialPlan> choices;
  for (size_t i = 0; i < list.node.size(); ++i) {
    ASSIGN_OR_RETURN(MaterialPlan material, ReadMaterial(yaml, YamlReader::Item(list, i)));
    choices.push_back(std::move(material));
  }
  return choices;
}

std::optional<std::string> ShortUnitName(std::string_view unit) {
  std::string lowered(unit);
  for (char& c : lowered) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const UnitName& name : Units()) {
    if (lowered == name.short_name ||
        std::find(name.long_names.begin(), name.long_names.end(), lowered) != name.long_names.end()) {
      return std::string(name.short_name);
    }
  }
  return std::nullopt;
}

std::optional<double> MetresPerUnit(std::string_view unit) {
  for (const UnitName& name : Units()) {
    if (unit == name.short_name) return name.metres;
  }
  return std::nullopt;
}

StatusOr<BinFillPlan> ReadBinFill(const YamlReader& yaml, const YamlAt& bin, const YamlAt& parts) {
  if (!YamlReader::Has(bin)) {
    return yaml.Error(bin, "required: {inner_size: [x, y, z], wall_thickness, pose} or {mesh, unit, scale, pose}");
  }
  BinFillPlan plan;
  if (bin.node.IsMap() && (bin.node["mesh"] || bin.node["mesh_id"])) {
    ASSIGN_OR_RETURN(plan.mesh_bin, ReadMeshBin(yaml, bin));
  } else {
    ASSIGN_OR_RETURN(plan.box, ReadBox(yaml, bin));
  }
  if (!YamlReader::Has(parts)) return yaml.Error(parts, "required: a list of {mesh, unit, count, ...}");
  RETURN_IF_ERROR(yaml.ExpectSequence(parts, 1));
  for (size_t i = 0; i < parts.node.size(); ++i) {
    ASSIGN_OR_RETURN(PartPlan part, ReadPart(yaml, YamlReader::Item(parts, i)));
    plan.parts.push_back(std::move(part));
  }
  return plan;
}

}  // namespace vscan::plan
