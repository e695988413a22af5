// A preset's camera and emitter figures in a scan's returned light: taken for every value the
// request leaves 0, overridden by each value it sets, and the generic defaults for presets without.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "api/scan/returned_light_request.h"
#include "api/scan/sensor_request.h"
#include "capture/returned_light.h"
#include "sensor/pixel_radiometry.h"
#include "sensor/presets.h"

namespace vscan::api {
namespace {

SensorSettings PresetSensor(const std::string& name) {
  v1::SensorSpec spec;
  spec.set_preset(name);
  auto settings = SensorFromProto(spec, service::Limits{});
  EXPECT_TRUE(settings.ok()) << settings.status().ToString();
  return *settings;
}

capture::ReturnedLightSpec Light(const v1::ReturnedLight& request, const SensorSettings& sensor) {
  auto light = ReturnedLightFromProto(request, sensor.camera, sensor.structured_light, sensor.modulation_frequency_hz,
                                      sensor.illumination);
  EXPECT_TRUE(light.ok()) << light.status().ToString();
  return *light;
}

double Gain(const sensor::PinholeCamera& camera, double exposure_s, double pupil_m, double qe, double wavelength_m) {
  sensor::PinholePixel pixel;
  pixel.exposure_s = exposure_s;
  pixel.aperture_area_m2 = std::numbers::pi * pupil_m * pupil_m / 4;
  pixel.quantum_efficiency = qe;
  pixel.wavelength_m = wavelength_m;
  return capture::CameraPixelGain(camera, pixel);
}

TEST(PresetLight, EveryScannerPresetCarriesItsCameraFiguresAndTheirSource) {
  size_t with_light = 0;
  for (const sensor::SensorPreset& preset : sensor::SensorPresets()) {
    const sensor::PresetIllumination& l = preset.illumination;
    if (l.full_well_e == 0) continue;
    ++with_light;
    EXPECT_GT(l.exposure_s, 0) << preset.name;
    EXPECT_GT(l.read_noise_e, 0) << preset.name;
    EXPECT_GT(l.quantum_efficiency, 0) << preset.name;
    EXPECT_LE(l.quantum_efficiency, 1) << preset.name;
    EXPECT_GT(l.wavelength_m, 0) << preset.name;
    EXPECT_GT(l.aperture_diameter_m, 0) << preset.name;
    EXPECT_GT(l.emitter_w_per_sr, 0) << preset.name;
    EXPECT_GT(l.source.size(), 40u) << preset.name;
    // Every preset's figures lie within what a request may ask for.
    Light(v1::ReturnedLight{}, PresetSensor(preset.name));
  }
  // The structured-light and time-of-flight classes: phoxi S, M, L and the two Kinects.
  EXPECT_GE(with_light, 5u);
}

TEST(PresetLight, ARequestLeavingValuesZeroTakesThePresets) {
  const SensorSettings sensor = PresetSensor("phoxi-m-class");
  const sensor::PresetIllumination& l = sensor.illumination;
  ASSERT_GT(l.full_well_e, 0);
  const capture::ReturnedLightSpec light = Light(v1::ReturnedLight{}, sensor);
  EXPECT_EQ(light.pixel.full_well_e, l.full_well_e);
  EXPECT_EQ(light.pixel.read_noise_e, l.read_noise_e);
  EXPECT_EQ(light.emitter.radiant_intensity_w_per_sr, l.emitter_w_per_sr);
  EXPECT_DOUBLE_EQ(light.pixel.gain_e,
                   Gain(sensor.camera, l.exposure_s, l.aperture_diameter_m, l.quantum_efficiency, l.wavelength_m));
}

TEST(PresetLight, EachValueTheRequestSetsOverridesThePresets) {
  const SensorSettings sensor = PresetSensor("kinect-v2-class");
  const sensor::PresetIllumination& l = sensor.illumination;
  ASSERT_GT(l.full_well_e, 0);
  v1::ReturnedLight request;
  request.set_exposure_s(2 * l.exposure_s);
  request.set_full_well_e(123456);
  request.set_emitter_w_per_sr(0.25);
  const capture::ReturnedLightSpec light = Light(request, sensor);
  EXPECT_EQ(light.pixel.full_well_e, 123456);
  EXPECT_EQ(light.pixel.read_noise_e, l.read_noise_e);
  EXPECT_EQ(light.emitter.radiant_intensity_w_per_sr, 0.25);
  // The gain is linear in the exposure.
  EXPECT_NEAR(light.pixel.gain_e,
              2 * Gain(sensor.camera, l.exposure_s, l.aperture_diameter_m, l.quantum_efficiency, l.wavelength_m),
              1e-9 * light.pixel.gain_e);
  EXPECT_EQ(light.modulation_frequency_hz, sensor.modulation_frequency_hz);
}

TEST(PresetLight, APresetWithoutFiguresTakesTheGenericDefaults) {
  const SensorSettings sensor = PresetSensor("ideal-vga");
  EXPECT_EQ(sensor.illumination.full_well_e, 0);
  const capture::ReturnedLightSpec light = Light(v1::ReturnedLight{}, sensor);
  EXPECT_EQ(light.pixel.full_well_e, 10000);
  EXPECT_EQ(light.pixel.read_noise_e, 5);
  EXPECT_EQ(light.emitter.radiant_intensity_w_per_sr, 1.0);
  EXPECT_DOUBLE_EQ(light.pixel.gain_e, Gain(sensor.camera, 0.01, 0.004, 0.3, 850e-9));
}

}  // namespace
}  // namespace vscan::api
