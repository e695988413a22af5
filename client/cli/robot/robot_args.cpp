#include "robot/robot_args.h"

#include <algorithm>

#include "session/args.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {

StatusOr<std::vector<double>> ParseNumberList(const std::string& text, const std::string& option) {
  if (text.empty()) return InvalidArgument(option + ": expected comma-separated numbers");
  const size_t count = static_cast<size_t>(std::count(text.begin(), text.end(), ',')) + 1;
  return ParseNumbers(text, count, option);
}

StatusOr<v1::InverseKinematicsRequest> BuildIkRequest(const IkArgs& args) {
  v1::InverseKinematicsRequest request;
  request.set_robot_id(args.robot_id);
  request.set_mount_id(args.mount_id);
  if (!args.quat.empty() && !args.look_at.empty())
    return InvalidArgument("--quat and --look-at are mutually exclusive");
  if (args.position.empty()) return InvalidArgument("--position: required");
  ASSIGN_OR_RETURN(const Eigen::Vector3d position, ParseVector3(args.position, "--position"));
  if (!args.quat.empty()) {
    ASSIGN_OR_RETURN(const auto q, ParseNumbers(args.quat, 4, "--quat"));
    auto* pose = request.mutable_tool_pose()->mutable_quaternion();
    *pose->mutable_translation() = ToProto(position);
    pose->set_qw(q[0]);
    pose->set_qx(q[1]);
    pose->set_qy(q[2]);
    pose->set_qz(q[3]);
  } else if (!args.look_at.empty()) {
    ASSIGN_OR_RETURN(const Eigen::Vector3d target, ParseVector3(args.look_at, "--look-at"));
    *request.mutable_look_from()->mutable_position() = ToProto(position);
    *request.mutable_look_from()->mutable_target() = ToProto(target);
  } else {
    *request.mutable_tool_position() = ToProto(position);
  }
  if (args.method == "default") {
    request.set_method(v1::IK_METHOD_DEFAULT);
  } else if (args.method == "gradient") {
    request.set_method(v1::IK_METHOD_GRADIENT_DESCENT);
  } else {
    return InvalidArgument("--method: '" + args.method + "' is not one of default, gradient");
  }
  if (!args.seed.empty()) {
    ASSIGN_OR_RETURN(const auto seed, ParseNumberList(args.seed, "--seed"));
    for (double v : seed) request.add_seed(v);
  }
  if (args.tolerance < 0) return InvalidArgument("--tolerance: must be positive");
  if (args.timeout_ms < 0) return InvalidArgument("--timeout-ms: must be positive");
  request.set_tolerance(args.tolerance);
  request.set_timeout_ms(args.timeout_ms);
  request.set_allow_partial(args.allow_partial);
  request.set_avoid_collisions(args.avoid_collisions);
  return request;
}

}  // namespace vscan::cli
