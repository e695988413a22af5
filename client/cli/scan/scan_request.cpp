#include <algorithm>
#include <cmath>

#include "robot/robot_args.h"
#include "session/args.h"
#include "vscan/common/chunk_limits.h"
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

bool AnyNoise(const ScanArgs& a) {
  return !a.noise_sigma.empty() || a.along_ray || a.depth_step_m || a.min_intensity || a.outlier_rate ||
         a.outlier_angle_deg || a.outlier_origin_m || a.grazing_limit_deg || a.flying_pixels || a.flying_pixel_edge_m;
}

// Only what the CLI can tell by itself; the server checks ranges and says which field is wrong.
Status FillNoise(const ScanArgs& a, v1::NoiseSpec* noise) {
  if (!a.noise_sigma.empty()) {
    ASSIGN_OR_RETURN(const auto sigma, ParseNumberList(a.noise_sigma, "--noise"));
    if (sigma.empty() || sigma.size() > 3) return InvalidArgument("--noise: expected a[,b[,c]]");
    noise->set_sigma_a(sigma[0]);
    if (sigma.size() > 1) noise->set_sigma_b(sigma[1]);
    if (sigma.size() > 2) noise->set_sigma_c(sigma[2]);
  }
  noise->set_along_ray(a.along_ray);
  noise->set_depth_step_m(a.depth_step_m.value_or(0));
  noise->set_min_intensity(a.min_intensity.value_or(0));
  noise->set_outlier_rate(a.outlier_rate.value_or(0));
  noise->set_outlier_angle_deg(a.outlier_angle_deg.value_or(0));
  noise->set_outlier_origin_m(a.outlier_origin_m.value_or(0));
  noise->set_grazing_limit_deg(a.grazing_limit_deg.value_or(0));
  noise->set_flying_pixels(a.flying_pixels);
  noise->set_flying_pixel_edge_m(a.flying_pixel_edge_m.value_or(0));
  return Status::Ok();
}


void AddEstimatedNormals(const ScanArgs& a, v1::ScanRequest* request) {
  if (request->fields().empty()) {
    for (const auto f : {v1::POINT_FIELD_POSITION, v1::POINT_FIELD_NORMAL, v1::POINT_FIELD_RANGE,
                         v1::POINT_FIELD_INTENSITY, v1::POINT_FIELD_INSTANCE_ID}) {
      request->add_fields(f);
    }
  }
  const auto& fields = request->fields();
  if (std::find(fields.begin(), fields.end(), v1::POINT_FIELD_ESTIMATED_NORMAL) == fields.end()) {
    request->add_fields(v1::POINT_FIELD_ESTIMATED_NORMAL);
  }
  request->mutable_normal_estimation()->set_k(a.estimate_normals_k.value_or(0));
  request->mutable_normal_estimation()->set_max_distance(a.normal_max_distance.value_or(0));
}

}  // namespace

// "on", or key=value pairs naming ReturnedLight's fields; the server checks the values' ranges.
Status FillReturnedLight(const std::string& text, v1::ReturnedLight* light) {
  if (text == "on") return Status::Ok();
  const auto* descriptor = light->GetDescriptor();
  size_t at = 0;
  while (at <= text.size()) {
    const size_t end = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, end - at);
    const size_t equals = item.find('=');
    const auto* field = equals == std::string::npos ? nullptr : descriptor->FindFieldByName(item.substr(0, equals));
    const bool count = field != nullptr && field->cpp_type() == google::protobuf::FieldDescriptor::CPPTYPE_UINT32;
    if (field == nullptr || (field->cpp_type() != google::protobuf::FieldDescriptor::CPPTYPE_DOUBLE && !count)) {
      return InvalidArgument("--returned-light", "'" + item + "' is not key=value with a key of vscan.v1.ReturnedLight (" +
                                                     "emitter_w_per_sr, exposure_s, full_well_e, ...), nor 'on'");
    }
    ASSIGN_OR_RETURN(const auto value, ParseNumbers(item.substr(equals + 1), 1, "--returned-light " + field->name()));
    if (count) {
      // A count (indirect_samples, indirect_stride_px): a whole number the field can hold.
      if (!(value[0] >= 0 && value[0] <= 4294967295.0) || value[0] != std::floor(value[0])) {
        return InvalidArgument("--returned-light " + field->name(), "must be a whole number in [0, 4294967295]");
      }
      light->GetReflection()->SetUInt32(light, field, static_cast<uint32_t>(value[0]));
    } else {
      light->GetReflection()->SetDouble(light, field, value[0]);
    }
    at = end + 1;
  }
  return Status::Ok();
}

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
    if (*args.chunk_kib < kMinChunkBytes / 1024 || *args.chunk_kib > kMaxChunkBytes / 1024) {
      return InvalidArgument("--chunk-kib", "must be between " + std::to_string(kMinChunkBytes / 1024) + " and " +
                                                std::to_string(kMaxChunkBytes / 1024));
    }
    request.set_chunk_bytes(*args.chunk_kib * 1024u);
  }
  if (AnyNoise(args)) RETURN_IF_ERROR(FillNoise(args, request.mutable_noise()));
  request.set_include_rejected(args.include_rejected);
  if (args.returned_light) RETURN_IF_ERROR(FillReturnedLight(*args.returned_light, request.mutable_returned_light()));
  if (args.normal_max_distance && !args.estimate_normals_k) {
    return InvalidArgument("--normal-max-distance: needs --estimate-normals");
  }
  if (args.estimate_normals_k) AddEstimatedNormals(args, &request);
  request.set_seed(args.seed);
  return request;
}

}  // namespace vscan::cli
