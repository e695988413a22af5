#pragma once
// Human-readable lines for robots, mounts and poses.

#include <string>

#include <google/protobuf/repeated_field.h>

#include "vscan/v1/common.pb.h"
#include "vscan/v1/robot.pb.h"

namespace vscan::cli {

// Six significant digits.
std::string FormatNumber(double value);
// "position (x, y, z) m, quaternion wxyz (w, x, y, z)".
std::string DescribeMatrix(const v1::Matrix4& matrix);
// "q1,q2,..." with enough digits to feed back to another command.
std::string JoinNumbers(const google::protobuf::RepeatedField<double>& values);
std::string Describe(const v1::Robot& robot);
std::string Describe(const v1::Joint& joint);
std::string Describe(const v1::Mount& mount);

}  // namespace vscan::cli
