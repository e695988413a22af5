#pragma once
// Robot catalogue records and kinematics results -> wire messages.

#include <google/protobuf/repeated_field.h>
#include <Eigen/Core>

#include "store/robot_catalogue.h"
#include "vscan/v1/robot.pb.h"

namespace vscan::api {

void ToProto(const store::RobotRecord& robot, v1::Robot* out);
// robot_tool: tip_from_tool of the mounted robot, reported when the mount has no tool of its own.
void ToProto(const store::MountRecord& mount, const Eigen::Matrix4d& robot_tool, v1::Mount* out);
void ToProto(const Eigen::VectorXd& values, google::protobuf::RepeatedField<double>* out);

}  // namespace vscan::api
