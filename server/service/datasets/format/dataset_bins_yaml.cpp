#include "service/datasets/format/dataset_bins_yaml.h"

#include <filesystem>
#include <set>
#include "service/datasets/format/yaml_fields.h"
#include "sensor/material.h"
#include "vscan/plan/bin_fill_plan.h"

namespace vscan::service::dataset {
namespace {

Status OnlyKeys(const YAML::Node& node, const std::string& source, const std::string& key,
                const std::set<std::string>& keys, const std::string& listed) {
  if (!node.IsMap()) return Refuse(source, key, "must be a mapping (" + listed + ")");
  for (const auto& entry : node) {
    if (!keys.contains(entry.first.Scalar())) {
      return Refuse(source, key + "." + entry.first.Scalar(), "is not a key (" + listed + ")");
    }
  }
  return Status::Ok();
}

StatusOr<std::string> Text(const YAML::Node& node, const std::string& source, const std::string& key) {
  if (!node.IsScalar()) return Refuse(source, key, "must be text");
  return node.Scalar();
}

StatusOr<uint32_t> Whole(const YAML::Node& node, const std::string& source, const std::string& key) {
  uint32_t value = 0;
  if (!node.IsScalar() || !YAML::convert<uint32_t>::decode(node, value)) {
    return Refuse(source, key, "must be a non-negative whole number");
  }
  return value;
}

DatasetPart ToDatasetPart(const plan::PartPlan& part) {
  DatasetPart out;
  out.mesh_file = part.mesh.file;
  out.mesh_id = part.mesh.mesh_id;
  if (!part.mesh.unit.empty()) out.unit = part.mesh.unit;
  out.scale = part.scale.value_or(1.0);
  out.count = part.count;
  out.name = !part.name.empty()          ? part.name
             : part.mesh.file.empty() ? part.mesh.mesh_id
                                       : std::filesystem::path(part.mesh.file).stem().string();
  out.mass_kg = part.mass_kg;
  if (part.density_kg_per_m3) out.density_kg_per_m3 = *part.density_kg_per_m3;
  if (!part.collision.empty()) out.collision = part.collision;
  if (part.material) {
    out.materials = {*part.material};
  } else {
    out.materials = part.material_choices;
  }
  return out;
}

// Every preset a part's material names is one the server knows (the values are the reader's).
Status CheckPresets(const plan::YamlReader& yaml, const plan::YamlAt& material, const DatasetPart& part) {
  const bool choice = plan::IsMaterialChoice(material);
  for (size_t k = 0; k < part.materials.size(); ++k) {
    const std::string& preset = part.materials[k].preset;
    if (preset.empty() || sensor::FindMaterialPreset(preset) != nullptr) continue;
    std::string known;
    for (const sensor::MaterialPreset& p : sensor::MaterialPresets()) known += (known.empty() ? "" : ", ") + p.name;
    const plan::YamlAt at = choice ? plan::YamlReader::Item(plan::YamlReader::Child(material, "choose"), k) : material;
    return yaml.Error(at, "unknown preset '" + preset + "' (" + known + ")");
  }
  return Status::Ok();
}

}  // namespace

StatusOr<BinEntry> ReadBinEntry(const YAML::Node& node, const std::string& source, const std::string& key) {
  if (node.IsScalar()) return BinEntry{node.Scalar(), std::nullopt};
  if (node.IsMap() && node["box"]) {
    return Refuse(source, key + ".box",
                  "is now written as bin plans write it: bin: {inner_size: [x, y, z], wall_thickness: w} "
                  "(docs/DATASETS.md)");
  }
  const plan::YamlReader yaml(source);
  const plan::YamlAt entry_at{node, key, node.Mark()};
  RETURN_IF_ERROR(yaml.ExpectMap(entry_at, {"name", "bin", "parts", "max_simulated_s"}));
  const plan::YamlAt name_at = plan::YamlReader::Child(entry_at, "name");
  if (!plan::YamlReader::Has(name_at)) return yaml.Error(name_at, "required: the bin's name");
  BinEntry entry;
  ASSIGN_OR_RETURN(entry.name, yaml.String(name_at));
  const plan::YamlAt bin_at = plan::YamlReader::Child(entry_at, "bin");
  ASSIGN_OR_RETURN(const plan::BinFillPlan plan,
                   plan::ReadBinFill(yaml, bin_at, plan::YamlReader::Child(entry_at, "parts")));
  if (plan.mesh_bin) return yaml.Error(bin_at, "a dataset's bins are boxes (inner_size, wall_thickness)");
  if (const plan::YamlAt pose = plan::YamlReader::Child(bin_at, "pose"); plan::YamlReader::Has(pose)) {
    return yaml.Error(pose, "a dataset's bin stands at the origin");
  }
  DatasetBinFill fill;
  fill.inner_size_m = plan.box->inner_size;
  if (plan.box->wall_thickness) fill.wall_thickness_m = *plan.box->wall_thickness;
  for (size_t i = 0; i < plan.parts.size(); ++i) {
    DatasetPart part = ToDatasetPart(plan.parts[i]);
    if (!part.materials.empty()) {
      const plan::YamlAt item = plan::YamlReader::Item(plan::YamlReader::Child(entry_at, "parts"), i);
      RETURN_IF_ERROR(CheckPresets(yaml, plan::YamlReader::Child(item, "material"), part));
    }
    fill.parts.push_back(std::move(part));
  }
  if (const plan::YamlAt limit = plan::YamlReader::Child(entry_at, "max_simulated_s"); plan::YamlReader::Has(limit)) {
    ASSIGN_OR_RETURN(fill.max_simulated_s, yaml.Number(limit));
  }
  entry.fill = std::move(fill);
  return entry;
}

StatusOr<SensorEntry> ReadSensorEntry(const YAML::Node& node, const std::string& source, const std::string& key) {
  if (node.IsScalar()) return SensorEntry{node.Scalar(), std::nullopt};
  RETURN_IF_ERROR(OnlyKeys(node, source, key, {"name", "preset", "width", "height"}, "name, preset, width, height"));
  if (!node["preset"]) return Refuse(source, key + ".preset", "is missing");
  SensorEntry entry;
  DatasetSensor setup;
  ASSIGN_OR_RETURN(setup.preset, Text(node["preset"], source, key + ".preset"));
  entry.name = setup.preset;
  if (node["name"]) {
    ASSIGN_OR_RETURN(entry.name, Text(node["name"], source, key + ".name"));
  }
  if (node["width"]) {
    ASSIGN_OR_RETURN(setup.width, Whole(node["width"], source, key + ".width"));
  }
  if (node["height"]) {
    ASSIGN_OR_RETURN(setup.height, Whole(node["height"], source, key + ".height"));
  }
  entry.setup = std::move(setup);
  return entry;
}

}  // namespace vscan::service::dataset
