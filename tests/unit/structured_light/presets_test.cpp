// Sensor presets: every preset is valid, and the structured-light presets reproduce their data sheets.

#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "sensor/presets.h"

namespace vscan::sensor {
namespace {

// Width (metres) of the strip at depth z and y = 0 that the camera sees and the projector lights.
double LitWidthAt(const StructuredLight& sl, double z) {
  const ProjectorField field(sl);
  const double half_view = z * sl.camera.width / (2 * sl.camera.fx);
  constexpr int kSamples = 20000;
  int lit = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double x = -half_view + (i + 0.5) * 2 * half_view / kSamples;
    if (field.Contains({x, 0, z})) ++lit;
  }
  return 2 * half_view * lit / kSamples;
}

TEST(SensorPresets, EveryPresetIsValidAndNamedOnce) {
  std::set<std::string> names;
  for (const SensorPreset& preset : SensorPresets()) {
    EXPECT_TRUE(names.insert(preset.name).second) << preset.name;
    EXPECT_FALSE(preset.description.empty());
    EXPECT_FALSE(preset.source.empty());
    EXPECT_TRUE(ValidateCamera(preset.camera, preset.name, std::numeric_limits<uint64_t>::max()).ok()) << preset.name;
    EXPECT_TRUE(ValidateNoise(preset.noise, preset.name).ok()) << preset.name;
    if (preset.structured_light) {
      const StructuredLight& sl = *preset.structured_light;
      EXPECT_TRUE(ValidateStructuredLight(sl, preset.name).ok()) << preset.name;
      EXPECT_EQ(sl.camera.width, preset.camera.width);
      EXPECT_EQ(sl.camera.fx, preset.camera.fx);
      EXPECT_EQ(sl.camera.near, preset.camera.near);
      EXPECT_EQ(sl.camera.far, preset.camera.far);
    }
    EXPECT_EQ(FindSensorPreset(preset.name), &preset);
  }
  // The earlier presets keep their names.
  for (const char* name : {"ideal-vga", "ideal-sxga", "kinect-v1-class", "kinect-v2-class"}) {
    ASSERT_NE(FindSensorPreset(name), nullptr) << name;
    EXPECT_FALSE(FindSensorPreset(name)->structured_light.has_value()) << name;
  }
  EXPECT_EQ(FindSensorPreset("no-such-sensor"), nullptr);
}

struct Sheet {
  const char* name;
  double near, far, baseline, mounting_angle_deg;
  // Scanning-area widths at the near, optimal and far distance (0: not in the sheet).
  double optimal_distance, near_width, optimal_width, far_width;
};

// Photoneo PhoXi 3D Scanner S, M and L data-sheet figures (metres, degrees).
const Sheet kSheets[] = {
    {"phoxi-s-class", 0.384, 0.520, 0.230, 15.45, 0, 0, 0, 0},
    {"phoxi-m-class", 0.458, 1.118, 0.350, 11.75, 0.650, 0.317, 0.590, 0.826},
    {"phoxi-l-class", 0.870, 2.150, 0.550, 9.45, 1.239, 0.600, 1.082, 1.644},
};

TEST(StructuredLightPresets, ReproduceTheDataSheetScanVolume) {
  for (const Sheet& sheet : kSheets) {
    SCOPED_TRACE(sheet.name);
    const SensorPreset* preset = FindSensorPreset(sheet.name);
    ASSERT_NE(preset, nullptr);
    ASSERT_TRUE(preset->structured_light.has_value());
    const StructuredLight& sl = *preset->structured_light;
    EXPECT_EQ(sl.camera.width * sl.camera.height, 2064u * 1544u);  // 3.2 Mpx
    EXPECT_DOUBLE_EQ(sl.camera.near, sheet.near);
    EXPECT_DOUBLE_EQ(sl.camera.far, sheet.far);
    EXPECT_DOUBLE_EQ(DisparityBaseline(sl), sheet.baseline);
    EXPECT_DOUBLE_EQ(ProjectorHorizontalFovDeg(sl), 47.5);
    EXPECT_DOUBLE_EQ(ProjectorVerticalFovDeg(sl), 36.0);
    // The axes meet at the angle of the two inward mounting tilts.
    const double vergence = std::atan2(sheet.baseline, sl.convergence_distance) * 180 / std::numbers::pi;
    EXPECT_NEAR(vergence, 2 * sheet.mounting_angle_deg, 1e-9);
    if (sheet.optimal_distance == 0) continue;
    // At the optimal distance the lit field of view is the camera's and matches the sheet within 2 %.
    EXPECT_NEAR(LitWidthAt(sl, sheet.optimal_distance) / sheet.optimal_width, 1.0, 0.02);
    // At the range ends the camera-projector overlap narrows the field; the model stays within 12 %.
    EXPECT_NEAR(LitWidthAt(sl, sheet.near) / sheet.near_width, 1.0, 0.12);
    EXPECT_NEAR(LitWidthAt(sl, sheet.far) / sheet.far_width, 1.0, 0.12);
  }
}

TEST(StructuredLightPresets, NoiseFollowsTheLargeModelsTemporalNoise) {
  // PhoXi 3D Scanner L: temporal noise 0.190 mm (1 sigma) at its optimal 1.239 m.
  const SensorPreset* large = FindSensorPreset("phoxi-l-class");
  ASSERT_NE(large, nullptr);
  EXPECT_NEAR(large->noise.sigma_c * 1.239 * 1.239, 0.190e-3, 1e-9);
  EXPECT_TRUE(large->noise.along_ray);
  // Triangulation: sigma_z = k z^2 / b, so sigma_c * b is the same for every model.
  for (const Sheet& sheet : kSheets) {
    const SensorPreset* preset = FindSensorPreset(sheet.name);
    ASSERT_NE(preset, nullptr);
    EXPECT_NEAR(preset->noise.sigma_c * sheet.baseline, large->noise.sigma_c * 0.550, 1e-12) << sheet.name;
    EXPECT_EQ(preset->noise.sigma_a, 0);
    EXPECT_EQ(preset->noise.sigma_b, 0);
  }
}

}  // namespace
}  // namespace vscan::sensor
