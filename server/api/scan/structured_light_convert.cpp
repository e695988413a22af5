#include "api/scan/structured_light_convert.h"

#include <string>

#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr char kField[] = "sensor.structured_light";

}  // namespace

StatusOr<sensor::StructuredLight> StructuredLightFromProto(const v1::StructuredLightScanner& proto,
                                                           const sensor::PinholeCamera& camera, const service::Limits& limits) {
  const std::string field = kField;
  if (!proto.has_camera()) return InvalidArgument(FieldPath(field, "camera"), "required");
  if (!proto.has_projector_offset()) {
    return InvalidArgument(FieldPath(field, "projector_offset"),
                           "required (the projector's position in the camera frame)");
  }
  sensor::StructuredLight sl;
  sl.camera = camera;
  sl.projector_offset = FromProto(proto.projector_offset());
  sl.projector_hfov_deg = proto.projector_horizontal_fov_deg();
  sl.projector_vfov_deg = proto.projector_vertical_fov_deg();
  sl.disparity_step_px = proto.disparity_step_px();
  sl.convergence_distance = proto.convergence_distance();
  RETURN_IF_ERROR(sensor::ValidateStructuredLight(sl, field));
  RETURN_IF_ERROR(sensor::ValidateCamera(sl.camera, field + ".camera", limits.max_rays_per_scan));
  return sl;
}

void ToProto(const sensor::PinholeCamera& c, v1::PinholeCamera* out) {
  out->set_width(c.width);
  out->set_height(c.height);
  auto* k = out->mutable_intrinsics();
  k->set_fx(c.fx);
  k->set_fy(c.fy);
  k->set_cx(c.cx);
  k->set_cy(c.cy);
  out->set_near(c.near);
  out->set_far(c.far);
  auto* lighting = out->mutable_lighting();
  lighting->set_power(c.lighting.power);
  lighting->set_constant(c.lighting.constant);
  lighting->set_linear(c.lighting.linear);
  lighting->set_quadratic(c.lighting.quadratic);
}

void ToProto(const sensor::StructuredLight& sl, v1::StructuredLightScanner* out) {
  ToProto(sl.camera, out->mutable_camera());
  *out->mutable_projector_offset() = vscan::ToProto(sl.projector_offset);
  out->set_projector_horizontal_fov_deg(sl.projector_hfov_deg);
  out->set_projector_vertical_fov_deg(sl.projector_vfov_deg);
  out->set_disparity_step_px(sl.disparity_step_px);
  out->set_convergence_distance(sl.convergence_distance);
}

}  // namespace vscan::api
