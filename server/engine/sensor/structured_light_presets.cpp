#include "sensor/structured_light_presets.h"

#include <cmath>
#include <numbers>
#include <string>
#include <utility>

namespace vscan::sensor {
namespace {

// PhoXi 3D Scanner family figures shared by every model.
constexpr uint32_t kWidth = 2064;   // full-resolution capturing mode, 3.2 Mpx
constexpr uint32_t kHeight = 1544;
constexpr double kProjectorHfovDeg = 47.5;
constexpr double kProjectorVfovDeg = 36.0;
// The large model's temporal noise, 0.190 mm (1 sigma) at its 1.239 m sweet spot with a 0.55 m
// baseline, scaled by the triangulation law sigma_z = k z^2 / b (same camera, so the same k).
constexpr double kNoiseK = 0.190e-3 * 0.55 / (1.239 * 1.239);

constexpr char kFamilySource[] =
    " Shared by the family: 2064 x 1544 camera (3.2 Mpx capturing mode) and a 47.5 x 36.0 degree projection "
    "angle (Photoneo, 'PhoXi 3D scanners family', https://wiki.photoneo.com/index.php/PhoXi_3D_scanners_family)."
    " Baseline b and camera mounting angle a of each model: the per-model virtual-scanner parameters shipped "
    "with Photoneo's (Skeletex Research) PhoXi processing software (Utils/ScannerDefinitions.h: PHOXI_S, "
    "PHOXI_M, PHOXI_L; camera and projector both turned inward by a). Convergence (derived): vscan puts the projector at (b, 0, 0) in the camera frame with its axis meeting the "
    "camera axis at z_c = b / tan(2a). Noise (derived): the PhoXi 3D Scanner L data sheet gives a temporal "
    "noise of 0.190 mm (1 sigma) at 1.239 m with b = 0.55 m; the other models follow from the triangulation "
    "law sigma_z = k z^2 / b with the same k, applied along the ray. The data sheets' calibration accuracy "
    "(a systematic deformation of space) is not modelled.";

constexpr char kLightSource[] =
    "Projector: a visible red laser, 639 nm (S) and 637 nm (M, L) (Photoneo, 'PhoXi 3D scanners family'). Its "
    "radiant power over the field is not published (the laser-safety figures are not it): derived as the "
    "intensity that puts half the full well on white (albedo 0.9) at the model's optimal distance (S: the "
    "middle of its range) at the shortest exposure. Exposure: 10.24 ms, the shortest single-pattern exposure "
    "(10.24-100.352 ms in Photoneo's GenICam examples). Camera: not named by Photoneo; 2064 x 1544 at 3.45 um "
    "is the geometry of Sony's Pregius IMX265/IMX252, whose cameras' EMVA 1288 data give a full well of about "
    "10 500 e and a dynamic range of 72.7 dB (Allied Vision Mako G-319, IMX265), hence 2.4 e of read noise. "
    "Quantum efficiency 0.55 at 637 nm (assumed, from the Pregius monochrome spectral curve). Aperture "
    "(assumed, not published): f/2.8 on the focal length the field of view and the 3.45 um pixel give.";

struct Model {
  const char* name;
  const char* description;
  const char* source;
  double horizontal_fov_deg;
  double near, far;
  double baseline;
  double mounting_angle_deg;
  double design_distance;  // where white fills half the well (the optimal scanning distance)
  double wavelength_nm;
};

constexpr double kPixelPitchM = 3.45e-6;

SensorPreset MakePreset(const Model& m) {
  StructuredLight sl;
  sl.camera = CameraFromFov(kWidth, kHeight, m.horizontal_fov_deg, m.near, m.far);
  sl.projector_offset = Eigen::Vector3d(m.baseline, 0, 0);
  sl.projector_hfov_deg = kProjectorHfovDeg;
  sl.projector_vfov_deg = kProjectorVfovDeg;
  sl.convergence_distance = m.baseline / std::tan(2.0 * m.mounting_angle_deg * std::numbers::pi / 180.0);
  DepthNoise noise;
  noise.sigma_c = kNoiseK / m.baseline;
  noise.along_ray = true;
  SensorPreset preset;
  preset.name = m.name;
  preset.description = m.description;
  preset.source = std::string(m.source) + kFamilySource;
  preset.camera = sl.camera;
  preset.noise = noise;
  preset.structured_light = std::move(sl);
  PresetIllumination& light = preset.illumination;
  light.exposure_s = 10.24e-3;
  light.aperture_diameter_m = preset.camera.fx * kPixelPitchM / 2.8;
  light.quantum_efficiency = 0.55;
  light.wavelength_m = m.wavelength_nm * 1e-9;
  light.full_well_e = 10500;
  light.read_noise_e = 2.4;
  light.emitter_w_per_sr = HalfWellEmitter(preset.camera, light, m.design_distance);
  light.source = kLightSource;
  return preset;
}

// Horizontal field of view that spans `width` metres at `distance` metres.
double FovSpanning(double width, double distance) {
  return 2.0 * std::atan(width / (2.0 * distance)) * 180.0 / std::numbers::pi;
}

}  // namespace

void AppendStructuredLightPresets(std::vector<SensorPreset>& presets) {
  // The small model's data sheet scanning area was not available; its camera is taken as the mean of the
  // medium and large models' (the family shares one camera module).
  const double medium_fov = FovSpanning(0.590, 0.650);
  const double large_fov = FovSpanning(1.082, 1.239);
  presets.push_back(MakePreset(
      {"phoxi-s-class",
       "Small-volume industrial structured-light scanner of the Photoneo PhoXi 3D Scanner S class: "
       "2064x1544, 0.384-0.520 m, 0.23 m baseline",
       "Photoneo PhoXi 3D Scanner S data sheet (https://www.photoneo.com/products/phoxi-scan-s/): scanning range "
       "384-520 mm; b = 230 mm, a = 15.45 degrees. Field of view (assumed): 48.0 degrees "
       "horizontal, the mean of the M and L models' sheet-derived values.",
       0.5 * (medium_fov + large_fov), 0.384, 0.520, 0.230, 15.45, 0.452, 639}));
  presets.push_back(MakePreset(
      {"phoxi-m-class",
       "Medium-volume industrial structured-light scanner of the Photoneo PhoXi 3D Scanner M class: "
       "2064x1544, 0.458-1.118 m, 0.35 m baseline",
       "Photoneo PhoXi 3D Scanner M data sheet (https://www.photoneo.com/products/phoxi-scan-m/): scanning range "
       "458-1118 mm, optimal scanning distance 650 mm, scanning area 317 x 303 mm (near), 590 x 421 mm "
       "(optimal), 826 x 877 mm (far); b = 350 mm, a = 11.75 degrees. Field of view "
       "(derived): the 590 mm width at 650 mm gives 48.8 degrees horizontal.",
       medium_fov, 0.458, 1.118, 0.350, 11.75, 0.650, 637}));
  presets.push_back(MakePreset(
      {"phoxi-l-class",
       "Large-volume industrial structured-light scanner of the Photoneo PhoXi 3D Scanner L class: "
       "2064x1544, 0.870-2.150 m, 0.55 m baseline",
       "Photoneo PhoXi 3D Scanner L data sheet (https://www.photoneo.com/products/phoxi-scan-l/): scanning range "
       "870-2150 mm, optimal scanning distance 1239 mm, scanning area 600 x 568 mm (near), 1082 x 802 mm "
       "(optimal), 1644 x 1388 mm (far), point-to-point distance 0.524 mm, temporal noise 0.190 mm and "
       "calibration accuracy 0.200 mm (1 sigma); b = 550 mm, a = 9.45 degrees. Field of "
       "view (derived): the 1082 mm width at 1239 mm gives 47.2 degrees horizontal.",
       large_fov, 0.870, 2.150, 0.550, 9.45, 1.239, 637}));
}

}  // namespace vscan::sensor
