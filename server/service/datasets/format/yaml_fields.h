#pragma once
// The plan readers' field checks: an error names the plan file and the key.

#include <string>

#include <yaml-cpp/yaml.h>

#include "vscan/common/status.h"

namespace vscan::service::dataset {

inline Status Refuse(const std::string& source, const std::string& key, const std::string& what) {
  return InvalidArgument(source + ": " + key + ": " + what);
}

inline StatusOr<double> Number(const YAML::Node& node, const std::string& source, const std::string& key) {
  double value = 0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value)) return Refuse(source, key, "must be a number");
  return value;
}

}  // namespace vscan::service::dataset
