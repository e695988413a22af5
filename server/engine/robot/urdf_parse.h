#pragma once
// urdfdom behind a Status: parse failures come back as InvalidArgument("urdf: ...").

#include <memory>
#include <string>

#include "vscan/common/status.h"

namespace urdf {
class ModelInterface;
}

namespace vscan::robot {

// Parses URDF XML with urdfdom. The message carries urdfdom's own error lines when it logged any.
StatusOr<std::shared_ptr<const urdf::ModelInterface>> ParseUrdfXml(const std::string& xml);

}  // namespace vscan::robot
