#include "api/robot/robot_convert.h"

#include "api/job/job_convert.h"
#include "api/transport/stored_enum_convert.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

void SetPose(const Eigen::Matrix4d& m, v1::Pose* out) { vscan::ToProto(Pose3(m), out->mutable_matrix()); }

}  // namespace

void ToProto(const store::RobotRecord& robot, v1::Robot* out) {
  out->set_robot_id(robot.robot_id);
  out->set_name(robot.name);
  out->set_base_link(robot.base_link);
  out->set_tip_link(robot.tip_link);
  for (const store::JointRecord& j : robot.joints) {
    v1::Joint* joint = out->add_joints();
    joint->set_name(j.name);
    joint->set_type(*kJointKinds.Forward(j.type));
    joint->set_lower(j.lower);
    joint->set_upper(j.upper);
    joint->set_max_velocity(j.max_velocity);
  }
  out->set_reach(robot.reach);
  for (const std::string& warning : robot.warnings) out->add_warnings(warning);
  out->set_urdf_path(robot.urdf_path);
  SetPose(robot.tool_offset, out->mutable_tool_offset());
  out->set_bundle_sha256(robot.bundle_sha256);
  out->set_bundle_bytes(robot.bundle_bytes);
  out->set_file_count(robot.file_count);
  SetTime(robot.create_time_ms, out->mutable_create_time());
}

void ToProto(const store::MountRecord& mount, const Eigen::Matrix4d& robot_tool, v1::Mount* out) {
  out->set_mount_id(mount.mount_id);
  out->set_scene_id(mount.scene_id);
  out->set_robot_id(mount.robot_id);
  SetPose(mount.base_pose, out->mutable_base_pose());
  SetPose(mount.tool_offset.value_or(robot_tool), out->mutable_tool_offset());
  out->set_links_visible(mount.links_visible);
  for (double sigma : mount.encoder_sigma) out->add_encoder_sigma(sigma);
  SetTime(mount.create_time_ms, out->mutable_create_time());
}

void ToProto(const Eigen::VectorXd& values, google::protobuf::RepeatedField<double>* out) {
  out->Clear();
  for (Eigen::Index i = 0; i < values.size(); ++i) out->Add(values[i]);
}

}  // namespace vscan::api
