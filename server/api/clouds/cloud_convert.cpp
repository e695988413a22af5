#include "api/clouds/cloud_convert.h"

#include <google/protobuf/util/time_util.h>

#include "api/transport/validate.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

v1::CloudOrigin OriginToProto(store::CloudOrigin origin) {
  switch (origin) {
    case store::CloudOrigin::kUploaded: return v1::CLOUD_ORIGIN_UPLOADED;
    case store::CloudOrigin::kCampaignScan: return v1::CLOUD_ORIGIN_CAMPAIGN_SCAN;
  }
  return v1::CLOUD_ORIGIN_UNSPECIFIED;
}

v1::Frame FrameToProto(store::CloudFrame frame) {
  return frame == store::CloudFrame::kSensor ? v1::FRAME_SENSOR : v1::FRAME_WORLD;
}

void CameraToProto(const store::CloudCamera& camera, v1::CloudCamera* out) {
  out->set_width(camera.width);
  out->set_height(camera.height);
  v1::Intrinsics* k = out->mutable_intrinsics();
  k->set_fx(camera.fx);
  k->set_fy(camera.fy);
  k->set_cx(camera.cx);
  k->set_cy(camera.cy);
  out->set_near(camera.near);
  out->set_far(camera.far);
}

StatusOr<sensor::PinholeCamera> CloudCameraFromProto(const v1::CloudCamera& c, const std::string& field) {
  sensor::PinholeCamera camera;
  camera.width = c.width();
  camera.height = c.height();
  camera.fx = c.intrinsics().fx();
  camera.fy = c.intrinsics().fy();
  camera.cx = c.intrinsics().cx();
  camera.cy = c.intrinsics().cy();
  camera.near = c.near();
  camera.far = c.far();
  // The size first: an absurd width is the width's fault, not the focal length's.
  RETURN_IF_ERROR(sensor::ValidateImageSize(camera, field));
  // Checked here so that messages name the wire path (ValidateCamera says "<field>.fx").
  RETURN_IF_ERROR(sensor::ValidateIntrinsics(camera, field + ".intrinsics"));
  RETURN_IF_ERROR(sensor::ValidateCamera(camera, field, UINT64_MAX));
  return camera;
}

}  // namespace

void ToProto(const store::CloudRecord& cloud, v1::Cloud* out) {
  out->set_cloud_id(cloud.cloud_id);
  out->set_name(cloud.name);
  out->set_points(cloud.points);
  FieldsToProto(cloud.fields, out->mutable_fields());
  out->set_origin(OriginToProto(cloud.origin));
  out->set_job_id(cloud.job_id);
  out->set_scene_id(cloud.scene_id);
  out->set_frame(FrameToProto(cloud.frame));
  if (cloud.world_from_sensor) vscan::ToProto(Pose3(*cloud.world_from_sensor), out->mutable_sensor_pose());
  if (cloud.camera) CameraToProto(*cloud.camera, out->mutable_camera());
  if (cloud.table_angle_deg) out->set_table_angle_deg(*cloud.table_angle_deg);
  out->set_size_bytes(cloud.size_bytes);
  out->set_sha256(cloud.sha256);
  *out->mutable_create_time() = google::protobuf::util::TimeUtil::MillisecondsToTimestamp(cloud.create_time_ms);
}

StatusOr<service::CloudUpload> CloudUploadFromProto(const v1::CloudHeader& header) {
  service::CloudUpload upload;
  RETURN_IF_ERROR(CheckText(header.name(), "header.name"));
  upload.name = header.name();
  switch (header.format()) {
    case v1::CLOUD_FORMAT_UNSPECIFIED: upload.format = service::CloudFileFormat::kDetect; break;
    case v1::CLOUD_FORMAT_PLY: upload.format = service::CloudFileFormat::kPly; break;
    case v1::CLOUD_FORMAT_PCD: upload.format = service::CloudFileFormat::kPcd; break;
    default: return InvalidArgument("header.format", "unknown value " + std::to_string(header.format()));
  }
  switch (header.frame()) {
    case v1::FRAME_UNSPECIFIED:
    case v1::FRAME_WORLD: upload.frame = store::CloudFrame::kWorld; break;
    case v1::FRAME_SENSOR: upload.frame = store::CloudFrame::kSensor; break;
    default: return InvalidArgument("header.frame", "unknown value " + std::to_string(header.frame()));
  }
  if (header.has_sensor_pose()) {
    ASSIGN_OR_RETURN(upload.world_from_sensor, PoseFromProto(header.sensor_pose(), "header.sensor_pose"));
  }
  if (header.has_camera()) {
    ASSIGN_OR_RETURN(upload.camera, CloudCameraFromProto(header.camera(), "header.camera"));
  }
  if (!header.scene_id().empty()) RETURN_IF_ERROR(RequireId(header.scene_id(), "header.scene_id"));
  upload.scene_id = header.scene_id();
  return upload;
}

Status InHeader(const Status& status) {
  if (status.ok() || !NamesAField(status.code())) return status;
  if (status.message().starts_with(service::kCloudDataField)) return status;
  if (!status.field().empty()) return status.WithFieldPrefix("header");
  return Status(status.code(), "header." + status.message());
}

}  // namespace vscan::api
