#pragma once
// Extracts a kinematic chain from a parsed URDF.

#include <string>

#include "robot/chain.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace urdf {
class ModelInterface;
}

namespace vscan::robot {

struct ChainSpec {
  std::string base_link;  // empty: the URDF's root link
  std::string tip_link;   // empty: the deepest link below base, when exactly one is deepest
  Pose3 tip_from_tool = Pose3::Identity();
};

// NotFound for an unknown link ("base_link: no link 'x'"); InvalidArgument when the tip is not
// below the base, the default tip is ambiguous, the path holds a floating, planar or mimic joint,
// or the links loop (LoadUrdfBundle refuses such URDFs first; the walks stay bounded regardless).
StatusOr<KinematicChain> BuildChain(const urdf::ModelInterface& model, const ChainSpec& spec);

}  // namespace vscan::robot
