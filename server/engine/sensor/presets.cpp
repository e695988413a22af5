#include "sensor/presets.h"

#include <cmath>
#include <numbers>

#include "sensor/structured_light_presets.h"

namespace vscan::sensor {
namespace {

// A camera whose vertical field of view follows from the horizontal one and the aspect ratio.
PinholeCamera Camera(uint32_t width, uint32_t height, double horizontal_fov_deg, double near, double far) {
  return CameraFromFov(width, height, horizontal_fov_deg, near, far);
}

std::vector<SensorPreset> MakePresets() {
  std::vector<SensorPreset> presets;
  presets.push_back({"ideal-vga", "Noise-free 640x480 pinhole camera, 60 degree horizontal field of view",
                     "Reference sensor for checking geometry; no measurement error by construction.",
                     Camera(640, 480, 60.0, 0.05, 10.0), {}});
  presets.push_back({"ideal-sxga", "Noise-free 1280x1024 pinhole camera, 40 degree horizontal field of view",
                     "Reference sensor for checking geometry; no measurement error by construction.",
                     Camera(1280, 1024, 40.0, 0.05, 10.0), {}});
  DepthNoise kinect_v1;
  kinect_v1.sigma_c = 1.6e-3;  // sigma_z = 1.6 mm * z^2 (z in metres): 4 cm at 5 m
  kinect_v1.along_ray = true;
  presets.push_back({"kinect-v1-class",
                     "Structured-light depth camera of the Kinect v1 class: 640x480, 57 degrees horizontal, "
                     "0.8-4.0 m, depth noise growing with the square of the distance",
                     "Field of view and working range: Microsoft Kinect for Windows (v1) sensor specification "
                     "(57 x 43 degrees, 0.8-4.0 m). Noise: K. Khoshelham, S. Oude Elberink, 'Accuracy and "
                     "resolution of Kinect depth data for indoor mapping applications', Sensors 12(2), 2012: "
                     "the random depth error grows with the square of the distance to about 4 cm at 5 m, "
                     "modelled here as 1.6 mm x z^2.",
                     Camera(640, 480, 57.0, 0.8, 4.0), kinect_v1});
  DepthNoise kinect_v2;
  kinect_v2.sigma_a = 1.5e-3;
  kinect_v2.along_ray = true;
  presets.push_back({"kinect-v2-class",
                     "Time-of-flight depth camera of the Kinect v2 class: 512x424, 70.6 degrees horizontal, "
                     "0.5-4.5 m, millimetre-level axial noise",
                     "Field of view and working range: Microsoft Kinect for Windows v2 sensor specification "
                     "(70.6 x 60 degrees, 0.5-4.5 m). Noise: P. Fankhauser et al., 'Kinect v2 for mobile robot "
                     "navigation: evaluation and modeling', ICAR 2015, report axial noise of the order of a "
                     "millimetre or two in the central field; modelled here as a constant 1.5 mm.",
                     Camera(512, 424, 70.6, 0.5, 4.5), kinect_v2, std::nullopt, kDefaultModulationFrequencyHz});
  AppendStructuredLightPresets(presets);
  return presets;
}

}  // namespace

const std::vector<SensorPreset>& SensorPresets() {
  static const std::vector<SensorPreset> presets = MakePresets();
  return presets;
}

const SensorPreset* FindSensorPreset(std::string_view name) {
  for (const auto& preset : SensorPresets()) {
    if (preset.name == name) return &preset;
  }
  return nullptr;
}

}  // namespace vscan::sensor
