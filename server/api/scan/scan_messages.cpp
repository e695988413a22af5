#include "api/scan/scan_messages.h"

#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

v1::ScanBackend BackendToProto(ScanBackend backend) {
  switch (backend) {
    case ScanBackend::kRasterDepth: return v1::SCAN_BACKEND_RASTER_DEPTH;
    case ScanBackend::kRasterColour: return v1::SCAN_BACKEND_RASTER_COLOUR;
    case ScanBackend::kRaycast: break;
  }
  return v1::SCAN_BACKEND_RAYCAST;
}

}  // namespace

void FillScanHeader(const ScanPlan& plan, uint64_t scene_revision, v1::ScanHeader* header) {
  header->set_scene_id(plan.scene_id);
  header->set_scene_revision(scene_revision);
  vscan::ToProto(plan.world_from_sensor, header->mutable_sensor_pose());
  if (plan.robot) {
    vscan::ToProto(plan.robot->commanded_world_from_sensor, header->mutable_commanded_sensor_pose());
    const Eigen::VectorXd& q = plan.robot->achieved_joint_positions;
    header->mutable_achieved_joint_positions()->Assign(q.data(), q.data() + q.size());
  }
  header->set_width(plan.camera.width);
  header->set_height(plan.camera.height);
  auto* k = header->mutable_intrinsics();
  k->set_fx(plan.camera.fx);
  k->set_fy(plan.camera.fy);
  k->set_cx(plan.camera.cx);
  k->set_cy(plan.camera.cy);
  header->set_near(plan.camera.near);
  header->set_far(plan.camera.far);
  FieldsToProto(plan.fields, header->mutable_fields());
  header->set_frame(plan.frame == raycast::ScanFrame::kSensor ? v1::FRAME_SENSOR : v1::FRAME_WORLD);
  header->set_backend(BackendToProto(plan.backend));
  header->set_rays(plan.camera.pixel_count());
  header->set_pixel_images(plan.pixel_images);
}

void ObjectTruthToProto(const service::ObjectTruth& object, v1::ObjectTruth* out) {
  out->set_object_id(object.object_id);
  out->set_instance_id(object.instance_id);
  out->set_mesh_id(object.mesh_id);
  out->set_label(object.label);
  out->set_scale(object.scale);
  vscan::ToProto(object.world_from_object, out->mutable_world_from_object());
  vscan::ToProto(object.sensor_from_object, out->mutable_sensor_from_object());
  out->set_visible_points(object.visible_points);
  out->set_unoccluded_points(object.unoccluded_points);
  out->set_visible_fraction(object.visible_fraction);
}

void FillScanStatistics(const raycast::ScanStats& stats, const capture::MeasureStats& m, v1::ScanStatistics* s) {
  s->set_rays(stats.rays);
  s->set_points(stats.points);
  s->set_hit_ratio(stats.rays ? static_cast<double>(stats.points) / static_cast<double>(stats.rays) : 0.0);
  s->set_min_range(stats.min_range);
  s->set_max_range(stats.max_range);
  s->set_scan_ms(stats.elapsed_ms);
  s->set_outliers(m.outliers);
  s->set_flying_pixels(m.flying_pixels);
  s->set_rejected_out_of_range(m.rejected_out_of_range);
  s->set_rejected_shadowed(m.rejected_shadowed);
  s->set_rejected_grazing(m.rejected_grazing);
  s->set_rejected_dim(m.rejected_dim);
  s->set_rejected_unlit(m.rejected_unlit);
  s->set_rejected_dark(m.rejected_dark);
  s->set_rejected_saturated(m.rejected_saturated);
  s->set_rejected_interreflection(m.rejected_interreflection);
  s->set_measurement_ms(m.elapsed_ms);
}

}  // namespace vscan::api
