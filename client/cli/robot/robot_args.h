#pragma once
// Command-line values of the robot commands: joint lists and IK goals.

#include <string>
#include <vector>

#include "vscan/common/status.h"
#include "vscan/v1/robot.pb.h"

namespace vscan::cli {

// One or more comma-separated finite numbers ("0.1,-0.5,1").
StatusOr<std::vector<double>> ParseNumberList(const std::string& text, const std::string& option);

// The options of `vscan robot ik`; empty strings were not given.
struct IkArgs {
  std::string robot_id;
  std::string mount_id;
  std::string position;  // x,y,z (required)
  std::string quat;      // w,x,y,z: a full pose goal
  std::string look_at;   // x,y,z: look at this point with the tool's z axis
  std::string method = "default";
  std::string seed;  // q1,q2,...
  double tolerance = 0.0;
  double timeout_ms = 0.0;
  bool allow_partial = false;
  bool avoid_collisions = false;
};

// Only --position: the tool origin alone; with --quat: the full pose; with --look-at: look from.
StatusOr<v1::InverseKinematicsRequest> BuildIkRequest(const IkArgs& args);

}  // namespace vscan::cli
