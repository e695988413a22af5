// ScanService.ListSensorPresets: the named sensors a scan request may use.

#include "api/scan_service.h"
#include "api/unary.h"
#include "sensor/presets.h"

namespace vscan::api {
namespace {

void ToProto(const sensor::SensorPreset& preset, v1::SensorPreset* out) {
  out->set_name(preset.name);
  out->set_description(preset.description);
  out->set_source(preset.source);
  const sensor::PinholeCamera& c = preset.camera;
  auto* pinhole = out->mutable_spec()->mutable_pinhole();
  pinhole->set_width(c.width);
  pinhole->set_height(c.height);
  auto* k = pinhole->mutable_intrinsics();
  k->set_fx(c.fx);
  k->set_fy(c.fy);
  k->set_cx(c.cx);
  k->set_cy(c.cy);
  pinhole->set_near(c.near);
  pinhole->set_far(c.far);
  auto* lighting = pinhole->mutable_lighting();
  lighting->set_power(c.lighting.power);
  lighting->set_constant(c.lighting.constant);
  lighting->set_linear(c.lighting.linear);
  lighting->set_quadratic(c.lighting.quadratic);
  auto* noise = out->mutable_noise();
  noise->set_sigma_a(preset.noise.sigma_a);
  noise->set_sigma_b(preset.noise.sigma_b);
  noise->set_sigma_c(preset.noise.sigma_c);
  noise->set_along_ray(preset.noise.along_ray);
  noise->set_depth_step_m(preset.noise.depth_step);
  noise->set_min_intensity(preset.noise.min_intensity);
}

}  // namespace

grpc::ServerUnaryReactor* ScanService::ListSensorPresets(grpc::CallbackServerContext* ctx,
                                                         const v1::ListSensorPresetsRequest*,
                                                         v1::ListSensorPresetsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListSensorPresets", [&]() -> Status {
    for (const auto& preset : sensor::SensorPresets()) ToProto(preset, response->add_presets());
    return Status::Ok();
  });
}

}  // namespace vscan::api
