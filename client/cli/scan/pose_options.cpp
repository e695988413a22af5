#include "scan/pose_options.h"

namespace vscan::cli {

void AddPoseOptions(CLI::App* cmd, PoseArgs& pose, const std::string& what) {
  auto* position = cmd->add_option("--position", pose.position, what + "Translation x,y,z in metres");
  auto* rpy = cmd->add_option("--rpy", pose.rpy, what + "Roll,pitch,yaw in degrees, applied as Rz*Ry*Rx");
  auto* quat = cmd->add_option("--quat", pose.quat, what + "Unit quaternion w,x,y,z");
  auto* matrix =
      cmd->add_option("--matrix", pose.matrix, what + "Rigid 4x4 matrix, 16 comma-separated values, row-major");
  rpy->excludes(quat)->excludes(matrix);
  quat->excludes(matrix);
  matrix->excludes(position);
}

}  // namespace vscan::cli
