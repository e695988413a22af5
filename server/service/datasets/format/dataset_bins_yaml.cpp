#include "service/datasets/format/dataset_bins_yaml.h"

#include <filesystem>
#include <set>
#include "service/datasets/format/yaml_fields.h"

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

StatusOr<DatasetPart> ReadPart(const YAML::Node& node, const std::string& source, const std::string& key) {
  RETURN_IF_ERROR(OnlyKeys(node, source, key,
                           {"mesh", "mesh_id", "unit", "scale", "count", "name", "mass_kg", "density_kg_per_m3",
                            "collision"},
                           "mesh, mesh_id, unit, scale, count, name, mass_kg, density_kg_per_m3, collision"));
  DatasetPart part;
  if (node["mesh"]) {
    ASSIGN_OR_RETURN(part.mesh_file, Text(node["mesh"], source, key + ".mesh"));
  }
  if (node["mesh_id"]) {
    ASSIGN_OR_RETURN(part.mesh_id, Text(node["mesh_id"], source, key + ".mesh_id"));
  }
  if (node["unit"]) {
    ASSIGN_OR_RETURN(part.unit, Text(node["unit"], source, key + ".unit"));
  }
  if (node["scale"]) {
    ASSIGN_OR_RETURN(part.scale, Number(node["scale"], source, key + ".scale"));
  }
  if (node["mass_kg"]) {
    ASSIGN_OR_RETURN(part.mass_kg, Number(node["mass_kg"], source, key + ".mass_kg"));
  }
  if (node["density_kg_per_m3"]) {
    ASSIGN_OR_RETURN(part.density_kg_per_m3, Number(node["density_kg_per_m3"], source, key + ".density_kg_per_m3"));
  }
  if (node["collision"]) {
    ASSIGN_OR_RETURN(part.collision, Text(node["collision"], source, key + ".collision"));
  }
  if (!node["count"]) return Refuse(source, key + ".count", "is missing");
  ASSIGN_OR_RETURN(part.count, Whole(node["count"], source, key + ".count"));
  if (node["name"]) {
    ASSIGN_OR_RETURN(part.name, Text(node["name"], source, key + ".name"));
  } else {
    part.name = part.mesh_file.empty() ? part.mesh_id : std::filesystem::path(part.mesh_file).stem().string();
  }
  return part;
}

Status ReadBox(const YAML::Node& node, const std::string& source, const std::string& key, DatasetBinFill& fill) {
  RETURN_IF_ERROR(OnlyKeys(node, source, key, {"inner_size_m", "wall_m"}, "inner_size_m, wall_m"));
  const YAML::Node size = node["inner_size_m"];
  if (!size || !size.IsSequence() || size.size() != 3) {
    return Refuse(source, key + ".inner_size_m", "must be [length, width, depth] in metres");
  }
  for (size_t axis = 0; axis < 3; ++axis) {
    ASSIGN_OR_RETURN(fill.inner_size_m[static_cast<Eigen::Index>(axis)],
                     Number(size[axis], source, key + ".inner_size_m[" + std::to_string(axis) + "]"));
  }
  if (node["wall_m"]) {
    ASSIGN_OR_RETURN(fill.wall_thickness_m, Number(node["wall_m"], source, key + ".wall_m"));
  }
  return Status::Ok();
}

}  // namespace

StatusOr<BinEntry> ReadBinEntry(const YAML::Node& node, const std::string& source, const std::string& key) {
  if (node.IsScalar()) return BinEntry{node.Scalar(), std::nullopt};
  RETURN_IF_ERROR(OnlyKeys(node, source, key, {"name", "box", "parts", "max_simulated_s"},
                           "name, box, parts, max_simulated_s"));
  for (const char* required : {"name", "box", "parts"}) {
    if (!node[required]) return Refuse(source, key + "." + required, "is missing");
  }
  BinEntry entry;
  ASSIGN_OR_RETURN(entry.name, Text(node["name"], source, key + ".name"));
  DatasetBinFill fill;
  RETURN_IF_ERROR(ReadBox(node["box"], source, key + ".box", fill));
  if (!node["parts"].IsSequence()) return Refuse(source, key + ".parts", "must be a list of parts");
  for (size_t i = 0; i < node["parts"].size(); ++i) {
    ASSIGN_OR_RETURN(DatasetPart part, ReadPart(node["parts"][i], source, key + ".parts[" + std::to_string(i) + "]"));
    fill.parts.push_back(std::move(part));
  }
  if (node["max_simulated_s"]) {
    ASSIGN_OR_RETURN(fill.max_simulated_s, Number(node["max_simulated_s"], source, key + ".max_simulated_s"));
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
