#pragma once
// Turns an uploaded bundle into a robot: checks paths and limits, parses the URDF, builds the
// chain, and prepares the catalogue record and the blob to store.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "robot/chain.h"
#include "robot/urdf_bundle.h"
#include "store/robot_catalogue.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::robot_registry {

struct RobotUpload {
  std::string name;  // empty: the URDF's robot name
  std::string urdf_path;
  std::string base_link;  // empty: the URDF's root link
  std::string tip_link;   // empty: the one deepest link below the base
  Pose3 tip_from_tool = Pose3::Identity();
  std::vector<robot::BundleFile> files;
};

struct ImportedRobot {
  store::RobotRecord record;  // everything but robot_id, bundle_sha256 and create time
  std::string bundle_blob;
  std::shared_ptr<const robot::KinematicChain> chain;
};

// Errors name the request field: "files[i].path: ..." for a path that escapes the bundle,
// "header.urdf_path: ...", "header.base_link: ..." (INVALID_ARGUMENT), RESOURCE_EXHAUSTED past limits.
StatusOr<ImportedRobot> ImportRobot(RobotUpload upload, const robot::BundleLimits& limits);

// The chain of a stored robot, rebuilt from its bundle.
StatusOr<std::shared_ptr<const robot::KinematicChain>> LoadStoredChain(const store::RobotRecord& record,
                                                                       std::vector<robot::BundleFile> files);

}  // namespace vscan::robot_registry
