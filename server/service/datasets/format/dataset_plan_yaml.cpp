#include "service/datasets/format/dataset_plan_yaml.h"

#include <map>
#include <set>
#include <utility>

#include <yaml-cpp/yaml.h>

#include "service/datasets/format/dataset_bins_yaml.h"
#include "service/datasets/format/dataset_picks_yaml.h"
#include "service/datasets/format/yaml_fields.h"

namespace vscan::service::dataset {
namespace {

// A mesh file is one uploaded mesh (spec.mesh_ids is keyed by its path): one unit wherever it is named.
Status OneUnitAFile(const DatasetPlan& plan, const std::string& source) {
  std::map<std::string, std::pair<std::string, std::string>> first;  // file -> unit, key
  for (size_t b = 0; b < plan.bin_fills.size(); ++b) {
    for (size_t p = 0; p < plan.bin_fills[b].parts.size(); ++p) {
      const DatasetPart& part = plan.bin_fills[b].parts[p];
      if (part.mesh_file.empty()) continue;
      const std::string key = "bins[" + std::to_string(b) + "].parts[" + std::to_string(p) + "]";
      const auto [at, added] = first.emplace(part.mesh_file, std::make_pair(part.unit, key));
      if (!added && at->second.first != part.unit) {
        return Refuse(source, key + ".unit",
                      part.mesh_file + " is in " + at->second.first + " at " + at->second.second +
                          "; one file is one mesh, so copy it for another unit");
      }
    }
  }
  return Status::Ok();
}

// Bare names, or mappings that describe each bin's fill: every bin one way.
Status ReadBins(const YAML::Node& node, const std::string& source, DatasetPlan& plan) {
  if (!node.IsSequence()) return Refuse(source, "bins", "must be a list of bins");
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = "bins[" + std::to_string(i) + "]";
    ASSIGN_OR_RETURN(BinEntry entry, ReadBinEntry(node[i], source, key));
    if (entry.fill.has_value() != (i == 0 ? node[0].IsMap() : !plan.bin_fills.empty())) {
      return Refuse(source, key, "describe every bin's fill or none");
    }
    plan.bins.push_back(std::move(entry.name));
    if (entry.fill) plan.bin_fills.push_back(std::move(*entry.fill));
  }
  return OneUnitAFile(plan, source);
}

// Preset names, or mappings with a name, a preset and a resolution; a bare name is a preset.
Status ReadSensors(const YAML::Node& node, const std::string& source, DatasetPlan& plan) {
  if (!node.IsSequence()) return Refuse(source, "sensors", "must be a list of sensors");
  for (size_t i = 0; i < node.size(); ++i) {
    ASSIGN_OR_RETURN(SensorEntry entry, ReadSensorEntry(node[i], source, "sensors[" + std::to_string(i) + "]"));
    plan.sensor_setups.push_back(entry.setup ? *entry.setup : DatasetSensor{entry.name, 0, 0});
    plan.sensors.push_back(std::move(entry.name));
  }
  return Status::Ok();
}

StatusOr<uint64_t> Count(const YAML::Node& node, const std::string& source, const std::string& key) {
  uint64_t value = 0;
  if (!node.IsScalar() || !YAML::convert<uint64_t>::decode(node, value)) {
    return Refuse(source, key, "must be a non-negative whole number");
  }
  return value;
}

StatusOr<std::vector<uint64_t>> Seeds(const YAML::Node& node, const std::string& source) {
  if (node.IsSequence()) {
    std::vector<uint64_t> seeds;
    for (size_t i = 0; i < node.size(); ++i) {
      ASSIGN_OR_RETURN(const uint64_t seed, Count(node[i], source, "seeds[" + std::to_string(i) + "]"));
      seeds.push_back(seed);
    }
    return seeds;
  }
  if (!node.IsMap()) return Refuse(source, "seeds", "must be a list of seeds or {first, count}");
  for (const auto& entry : node) {
    const std::string key = entry.first.Scalar();
    if (key != "first" && key != "count") return Refuse(source, "seeds." + key, "is not a key (first, count)");
  }
  if (!node["first"] || !node["count"]) return Refuse(source, "seeds", "needs both first and count");
  ASSIGN_OR_RETURN(const uint64_t first, Count(node["first"], source, "seeds.first"));
  ASSIGN_OR_RETURN(const uint64_t count, Count(node["count"], source, "seeds.count"));
  if (count > kMaxScenes) return Refuse(source, "seeds.count", "must be at most " + std::to_string(kMaxScenes));
  if (first + count < first) return Refuse(source, "seeds", "the range passes the largest seed");
  return SeedRange(first, count);
}

// {count, cone_deg, distance_m}: distance_m one number or [min, max].
Status ReadViews(const YAML::Node& node, const std::string& source, DatasetViews& views) {
  if (!node.IsMap()) return Refuse(source, "views", "must be a mapping (count, cone_deg, distance_m)");
  for (const auto& entry : node) {
    const std::string key = entry.first.Scalar();
    if (key != "count" && key != "cone_deg" && key != "distance_m") {
      return Refuse(source, "views." + key, "is not a key (count, cone_deg, distance_m)");
    }
  }
  if (node["count"]) {
    ASSIGN_OR_RETURN(const uint64_t count, Count(node["count"], source, "views.count"));
    if (count < 1 || count > kMaxViewsPerScene) {
      return Refuse(source, "views.count", "must be within [1, " + std::to_string(kMaxViewsPerScene) + "]");
    }
    views.count = static_cast<uint32_t>(count);
  }
  if (node["cone_deg"]) {
    ASSIGN_OR_RETURN(views.cone_deg, Number(node["cone_deg"], source, "views.cone_deg"));
  }
  if (const YAML::Node distance = node["distance_m"]) {
    if (distance.IsSequence()) {
      if (distance.size() != 2) return Refuse(source, "views.distance_m", "must be one distance or [min, max]");
      ASSIGN_OR_RETURN(views.min_distance_m, Number(distance[0], source, "views.distance_m[0]"));
      ASSIGN_OR_RETURN(views.max_distance_m, Number(distance[1], source, "views.distance_m[1]"));
    } else {
      ASSIGN_OR_RETURN(views.min_distance_m, Number(distance, source, "views.distance_m"));
      views.max_distance_m = views.min_distance_m;
    }
    if (views.max_distance_m <= 0) return Refuse(source, "views.distance_m", "must be positive");
  }
  return Status::Ok();
}

StatusOr<DatasetPlan> PlanFromNode(const YAML::Node& root, const std::string& source) {
  if (!root.IsMap()) return InvalidArgument(source + ": the plan must be a mapping");
  static const std::set<std::string> kKeys = {"name",           "bins",           "seeds",
                                              "sensors",        "depth_scale_mm", "camera_height_m",
                                              "fail_on_underfilled_bin", "views", "returned_light",
                                              "picks"};
  for (const auto& entry : root) {
    if (!kKeys.contains(entry.first.Scalar())) {
      return Refuse(source, entry.first.Scalar(),
                    "is not a key (name, bins, seeds, sensors, depth_scale_mm, camera_height_m, views, "
                    "fail_on_underfilled_bin, returned_light, picks)");
    }
  }
  for (const char* key : {"bins", "seeds", "sensors"}) {
    if (!root[key]) return Refuse(source, key, "is missing");
  }
  DatasetPlan plan;
  if (root["name"]) {
    if (!root["name"].IsScalar()) return Refuse(source, "name", "must be text");
    plan.name = root["name"].Scalar();
  }
  RETURN_IF_ERROR(ReadBins(root["bins"], source, plan));
  ASSIGN_OR_RETURN(plan.seeds, Seeds(root["seeds"], source));
  RETURN_IF_ERROR(ReadSensors(root["sensors"], source, plan));
  if (root["depth_scale_mm"]) {
    if (!root["depth_scale_mm"].IsScalar() ||
        !YAML::convert<double>::decode(root["depth_scale_mm"], plan.depth_scale_mm)) {
      return Refuse(source, "depth_scale_mm", "must be a number");
    }
  }
  if (root["camera_height_m"]) {
    if (!root["camera_height_m"].IsScalar() ||
        !YAML::convert<double>::decode(root["camera_height_m"], plan.camera_height_m)) {
      return Refuse(source, "camera_height_m", "must be a number");
    }
  }
  if (root["views"]) RETURN_IF_ERROR(ReadViews(root["views"], source, plan.views));
  if (root["fail_on_underfilled_bin"]) {
    if (!root["fail_on_underfilled_bin"].IsScalar() ||
        !YAML::convert<bool>::decode(root["fail_on_underfilled_bin"], plan.fail_on_underfilled_bin)) {
      return Refuse(source, "fail_on_underfilled_bin", "must be true or false");
    }
  }
  if (root["returned_light"]) {
    const plan::YamlReader yaml(source);
    const plan::YamlAt top{root, "", root.Mark()};
    ASSIGN_OR_RETURN(plan.returned_light,
                     plan::ReadReturnedLight(yaml, plan::YamlReader::Child(top, "returned_light")));
  }
  if (root["picks"]) {
    const plan::YamlReader yaml(source);
    const plan::YamlAt top{root, "", root.Mark()};
    ASSIGN_OR_RETURN(plan.picks, ReadDatasetPicks(yaml, plan::YamlReader::Child(top, "picks")));
  }
  const Status checked = CheckPlan(plan);
  if (!checked.ok()) return Refuse(source, checked.field(), std::string(checked.text()));
  return plan;
}

// yaml-cpp recurses once per level, so a few thousand brackets or indents would overflow the stack
// (or answer "bad file"): the text's nesting is bounded before it is parsed. Flow levels are
// counted outside quotes and comments; a block level costs at least one column of indentation.
constexpr int kMaxNesting = 64;
constexpr size_t kMaxIndent = 256;

Status CheckNesting(std::string_view text, const std::string& source) {
  int depth = 0;
  char quote = 0;
  bool comment = false;
  size_t line = 1, column = 0;
  bool indenting = true;
  for (const char c : text) {
    if (c == '\n') {
      ++line;
      column = 0;
      indenting = true;
      comment = false;
      continue;
    }
    if (indenting && c == ' ' && ++column > kMaxIndent) {
      return InvalidArgument(source + ": line " + std::to_string(line) + ": indented more than " +
                             std::to_string(kMaxIndent) + " columns: nested too deep for a plan");
    }
    if (c != ' ') indenting = false;
    if (comment) continue;
    if (quote != 0) {
      if (c == quote) quote = 0;
      continue;
    }
    if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#') {
      comment = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNesting) {
        return InvalidArgument(source + ": line " + std::to_string(line) + ": more than " +
                               std::to_string(kMaxNesting) + " nested lists or mappings: nested too deep for a plan");
      }
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return Status::Ok();
}

}  // namespace

StatusOr<DatasetPlan> ParseDatasetPlanYaml(std::string_view text, const std::string& source) {
  RETURN_IF_ERROR(CheckNesting(text, source));
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    return InvalidArgument(source + ": not YAML: " + e.what());
  }
  try {
    return PlanFromNode(root, source);
  } catch (const YAML::Exception& e) {
    return InvalidArgument(source + ": " + e.what());
  }
}

}  // namespace vscan::service::dataset
