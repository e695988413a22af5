#include <cmath>

#include "args.h"
#include "robot_args.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

Status FillCamera(const ScanArgs& args, v1::PinholeCamera* camera) {
  if (args.width == 0 || args.height == 0) return InvalidArgument("--width/--height: must be positive");
  camera->set_width(args.width);
  camera->set_height(args.height);
  if (!args.intrinsics.empty()) {
    ASSIGN_OR_RETURN(const auto k, ParseNumbers(args.intrinsics, 4, "--intrinsics"));
    if (k[0] <= 0 || k[1] <= 0) return InvalidArgument("--intrinsics: fx and fy must be positive");
    auto* intrinsics = camera->mutable_intrinsics();
    intrinsics->set_fx(k[0]);
    intrinsics->set_fy(k[1]);
    intrinsics->set_cx(k[2]);
    intrinsics->set_cy(k[3]);
  } else {
    const double hfov = args.hfov_deg.value_or(60.0);
    if (!(hfov > 0 && hfov < 180)) return InvalidArgument("--hfov: must be between 0 and 180 degrees");
    camera->set_horizontal_fov_deg(hfov);
  }
  if (!(args.near > 0) || !(args.far > args.near)) {
    return InvalidArgument("--near/--far: need 0 < near < far");
  }
  camera->set_near(args.near);
  camera->set_far(args.far);
  if (!args.lighting.empty()) {
    ASSIGN_OR_RETURN(const auto l, ParseNumbers(args.lighting, 4, "--lighting"));
    auto* lighting = camera->mutable_lighting();
    lighting->set_power(l[0]);
    lighting->set_constant(l[1]);
    lighting->set_linear(l[2]);
    lighting->set_quadratic(l[3]);
  }
  return Status::Ok();
}

Status FillRobotPose(const ScanArgs& args, v1::RobotPose* robot) {
  if (!args.eye.empty() || !args.target.empty() || !args.pose_matrix.empty()) {
    return InvalidArgument("--mount and --eye/--target/--pose-matrix are mutually exclusive");
  }
  if (args.joints.empty()) return InvalidArgument("--joints: required with --mount");
  ASSIGN_OR_RETURN(const auto q, ParseNumberList(args.joints, "--joints"));
  robot->set_mount_id(args.mount);
  for (double v : q) robot->add_joint_positions(v);
  robot->set_apply_encoder_noise(args.encoder_noise);
  return Status::Ok();
}

StatusOr<Pose3> SensorPose(const ScanArgs& args) {
  if (!args.pose_matrix.empty()) {
    if (!args.eye.empty() || !args.target.empty()) {
      return InvalidArgument("--pose-matrix and --eye/--target are mutually exclusive");
    }
    ASSIGN_OR_RETURN(const auto v, ParseNumbers(args.pose_matrix, 16, "--pose-matrix"));
    const Eigen::Matrix4d m = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(v.data());
    return PoseFromMatrix(m, "--pose-matrix");
  }
  if (args.eye.empty() || args.target.empty()) {
    return InvalidArgument("--eye and --target (or --pose-matrix, or --mount with --joints) are required");
  }
  ASSIGN_OR_RETURN(const auto eye, ParseVector3(args.eye, "--eye"));
  ASSIGN_OR_RETURN(const auto target, ParseVector3(args.target, "--target"));
  ASSIGN_OR_RETURN(const auto up, ParseVector3(args.up, "--up"));
  return PoseFromLookAt(eye, target, up, "--eye/--target/--up");
}

}  // namespace

StatusOr<v1::ScanRequest> BuildScanRequest(const ScanArgs& args) {
  v1::ScanRequest request;
  request.set_scene_id(args.scene_id);
  if (!args.preset.empty()) {
    request.mutable_sensor()->set_preset(args.preset);
  } else {
    RETURN_IF_ERROR(FillCamera(args, request.mutable_sensor()->mutable_pinhole()));
  }

  if (args.mount.empty() && !args.joints.empty()) return InvalidArgument("--joints: needs --mount");
  if (args.mount.empty() && args.encoder_noise) return InvalidArgument("--encoder-noise: needs --mount");
  if (!args.mount.empty()) {
    RETURN_IF_ERROR(FillRobotPose(args, request.mutable_robot()));
  } else if (args.pose_matrix.empty()) {
    RETURN_IF_ERROR(SensorPose(args).status());
    // Send look-at as given so the server reports the same numbers back.
    auto* look_at = request.mutable_pose()->mutable_look_at();
    *look_at->mutable_eye() = ToProto(*ParseVector3(args.eye, "--eye"));
    *look_at->mutable_target() = ToProto(*ParseVector3(args.target, "--target"));
    *look_at->mutable_up() = ToProto(*ParseVector3(args.up, "--up"));
  } else {
    ASSIGN_OR_RETURN(const Pose3 pose, SensorPose(args));
    *request.mutable_pose() = PoseToProto(pose);
  }

  ASSIGN_OR_RETURN(const auto backend, ParseBackend(args.backend));
  request.set_backend(backend);
  ASSIGN_OR_RETURN(const auto frame, ParseFrame(args.frame));
  request.set_frame(frame);
  if (!args.fields.empty()) {
    ASSIGN_OR_RETURN(const auto fields, ParseFields(args.fields));
    for (const auto f : fields) request.add_fields(f);
  }
  if (args.table_angle_deg) {
    if (!std::isfinite(*args.table_angle_deg)) return InvalidArgument("--table-angle: not finite");
    request.set_table_angle_deg(*args.table_angle_deg);
  }
  if (args.chunk_kib) {
    if (*args.chunk_kib < 64 || *args.chunk_kib > 16384) {
      return InvalidArgument("--chunk-kib: must be between 64 and 16384");
    }
    request.set_chunk_bytes(*args.chunk_kib * 1024u);
  }
  request.set_seed(args.seed);
  return request;
}

}  // namespace vscan::cli
