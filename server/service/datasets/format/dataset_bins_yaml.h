#pragma once
// The bin and sensor entries of a plan file: a bare name, or a mapping that describes the bin's
// fill or the sensor's preset (docs/DATASETS.md, "The plan file"). Used by dataset_plan_yaml.cpp.

#include <optional>
#include <string>

#include <yaml-cpp/yaml.h>

#include "service/datasets/format/dataset_bins.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

struct BinEntry {
  std::string name;
  std::optional<DatasetBinFill> fill;
};

struct SensorEntry {
  std::string name;
  std::optional<DatasetSensor> setup;
};

// key is the entry's path, e.g. "bins[1]"; errors read "<source>: <key>.<member>: ...".
StatusOr<BinEntry> ReadBinEntry(const YAML::Node& node, const std::string& source, const std::string& key);
StatusOr<SensorEntry> ReadSensorEntry(const YAML::Node& node, const std::string& source, const std::string& key);

}  // namespace vscan::service::dataset
