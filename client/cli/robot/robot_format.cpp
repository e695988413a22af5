#include "robot/robot_format.h"

#include <Eigen/Geometry>

#include "session/text_format.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

// Six significant digits: what a person reads in a robot's description.
std::string Number(double v) { return Format("%.6g", v); }

const char* JointTypeName(v1::JointType type) {
  switch (type) {
    case v1::JOINT_TYPE_REVOLUTE: return "revolute";
    case v1::JOINT_TYPE_CONTINUOUS: return "continuous";
    case v1::JOINT_TYPE_PRISMATIC: return "prismatic";
    case v1::JOINT_TYPE_FIXED: return "fixed";
    default: return "unknown";
  }
}

std::string DescribePose(const v1::Pose& pose) {
  if (pose.kind_case() != v1::Pose::kMatrix) return "(not a matrix)";
  return DescribeMatrix(pose.matrix());
}

}  // namespace

std::string FormatNumber(double value) { return Number(value); }

std::string DescribeMatrix(const v1::Matrix4& matrix) {
  const auto pose = PoseFromProto(matrix, "pose");
  if (!pose.ok()) return "(invalid pose: " + pose.status().message() + ")";
  const Eigen::Vector3d p = pose->translation();
  const Eigen::Quaterniond q(pose->linear());
  return "position (" + Number(p.x()) + ", " + Number(p.y()) + ", " + Number(p.z()) + ") m, quaternion wxyz (" +
         Number(q.w()) + ", " + Number(q.x()) + ", " + Number(q.y()) + ", " + Number(q.z()) + ")";
}

std::string JoinNumbers(const google::protobuf::RepeatedField<double>& values) {
  std::string out;
  for (int i = 0; i < values.size(); ++i) out += (i ? "," : "") + Format("%.17g", values[i]);
  return out;
}

std::string Describe(const v1::Robot& robot) {
  return robot.robot_id() + "  '" + robot.name() + "'  " + robot.base_link() + " -> " + robot.tip_link() + "  " +
         std::to_string(robot.joints_size()) + " joints  reach " + Format("%.3f", robot.reach()) + " m  " +
         std::to_string(robot.warnings_size()) + " warnings";
}

std::string Describe(const v1::Joint& joint) {
  return joint.name() + " (" + JointTypeName(joint.type()) + ") [" + Number(joint.lower()) + ", " +
         Number(joint.upper()) + "]";
}

std::string Describe(const v1::Mount& mount) {
  std::string out = mount.mount_id() + "  scene " + mount.scene_id() + "  robot " + mount.robot_id() + "  base " +
                    DescribePose(mount.base_pose()) + "  tool " + DescribePose(mount.tool_offset());
  if (mount.encoder_sigma_size() > 0) out += "  encoder sigma " + JoinNumbers(mount.encoder_sigma());
  return out;
}

}  // namespace vscan::cli
