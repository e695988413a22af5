#pragma once
// Protobuf messages filled from a plan's YAML mappings, keys by field name.

#include <google/protobuf/message.h>

#include "vscan/plan/yaml_reader.h"

namespace vscan::cli {

using plan::ParentKey;
using plan::ParsePlanDocument;
using plan::ReadPlanFile;
using plan::YamlAt;
using plan::YamlReader;

// Fills message from a map whose keys are its field names (scalars, enums by their value names
// without the enum's prefix, nested messages; a vscan.v1.Vector3 may also be written [x, y, z]);
// at most one field of each oneof.
Status FillMessage(const YamlReader& yaml, const YamlAt& at, google::protobuf::Message* message);

}  // namespace vscan::cli
