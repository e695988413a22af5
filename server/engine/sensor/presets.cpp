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
  presets.back().illumination = {
      0.036, 0.01, 3.0e-3, 0.15, 830e-9, 31600, 12,
      "Emitter: the 830 nm laser behind a diffractive dot pattern, about 27.6 mW after the diffractive element "
      "over about 54 x 50 degrees (community measurements: OpenKinect wiki 'Hardware info', "
      "https://openkinect.org/wiki/Hardware_info; an Electronics Stack Exchange photodiode measurement), "
      "0.772 sr: 0.036 W/sr as the field's mean (the dots concentrate it). Camera: the Aptina MT9M001 "
      "(5.2 um pixels, binned), data sheet: maximum SNR 45 dB and dynamic range 68.2 dB, hence a full well of "
      "about 31 600 e and 12 e of read noise. Quantum efficiency 0.15 at 830 nm (assumed: the data sheet gives "
      "only a relative response), exposure 10 ms of the 33 ms frame (assumed, not published), aperture f/2 "
      "on the 6 mm lens community calibrations report (assumed)."};

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
  PresetIllumination& v2 = presets.back().illumination;
  v2 = {0, 0.011, 3.3e-3, 0.20, 860e-9, 16000, 10,
        "Camera: C. S. Bamji et al., 'A 0.13 um CMOS System-on-Chip for a 512 x 424 Time-of-Flight Image Sensor "
        "with Multi-Frequency Photo-Demodulation up to 130 MHz and 2 GS/s ADC', IEEE JSSC 50(1), 2015: 10 um "
        "pixels, responsivity 0.14 A/W at 860 nm (a quantum efficiency of 0.20), dynamic range above 64 dB "
        "(full well 16 000 e over 10 e of read noise is 64 dB: the split is assumed). Exposure 11 ms, a third "
        "of the 33 ms frame, one modulation frequency's captures (assumed). Aperture f/1.1 on the 3.65 mm lens "
        "of the factory intrinsics (fx 365.5 px x 10 um; the f-number is assumed). Emitter: three laser diodes "
        "(Chipworks teardown) of unpublished power, derived as the intensity that puts half the full well on "
        "white (albedo 0.9) at the near end of the range, 0.5 m, so that white facing it saturates nowhere in "
        "the range (the camera's multi-gain operation reaches further than one exposure)."};
  v2.emitter_w_per_sr = HalfWellEmitter(presets.back().camera, v2, 0.5);

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
