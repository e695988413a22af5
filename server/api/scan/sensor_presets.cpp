// ScanService.ListSensorPresets: the named sensors a scan request may use.

#include "api/scan/scan_service.h"
#include "api/scan/structured_light_convert.h"
#include "api/transport/unary.h"
#include "sensor/presets.h"

namespace vscan::api {
namespace {

void PresetToProto(const sensor::SensorPreset& preset, v1::SensorPreset* out) {
  out->set_name(preset.name);
  out->set_description(preset.description);
  out->set_source(preset.source);
  if (preset.structured_light) {
    api::ToProto(*preset.structured_light, out->mutable_spec()->mutable_structured_light());
  } else {
    api::ToProto(preset.camera, out->mutable_spec()->mutable_pinhole());
  }
  auto* noise = out->mutable_noise();
  noise->set_sigma_a(preset.noise.sigma_a);
  noise->set_sigma_b(preset.noise.sigma_b);
  noise->set_sigma_c(preset.noise.sigma_c);
  noise->set_along_ray(preset.noise.along_ray);
  noise->set_depth_step_m(preset.noise.depth_step);
  noise->set_min_intensity(preset.noise.min_intensity);
  const sensor::PresetIllumination& light = preset.illumination;
  auto* returned_light = out->mutable_returned_light();
  returned_light->set_emitter_w_per_sr(light.emitter_w_per_sr);
  returned_light->set_exposure_s(light.exposure_s);
  returned_light->set_aperture_diameter_m(light.aperture_diameter_m);
  returned_light->set_quantum_efficiency(light.quantum_efficiency);
  returned_light->set_wavelength_m(light.wavelength_m);
  returned_light->set_full_well_e(light.full_well_e);
  returned_light->set_read_noise_e(light.read_noise_e);
  returned_light->set_modulation_frequency_hz(preset.modulation_frequency_hz);
  out->set_returned_light_source(light.source);
}

}  // namespace

grpc::ServerUnaryReactor* ScanService::ListSensorPresets(grpc::CallbackServerContext* ctx,
                                                         const v1::ListSensorPresetsRequest*,
                                                         v1::ListSensorPresetsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListSensorPresets", [&]() -> Status {
    for (const auto& preset : sensor::SensorPresets()) PresetToProto(preset, response->add_presets());
    return Status::Ok();
  });
}

}  // namespace vscan::api
