#pragma once
// The light an active sensor's own emitter (a structured-light projector, a ToF illuminator)
// returns to one camera pixel, and what the pixel makes of it: electrons with shot and read noise,
// a full well, and the verdicts dark and saturated (docs/SENSORS.md, "The returned signal").
// Direct light only: one bounce from the emitter to the surface to the camera.

#include <cstdint>
#include <numbers>
#include <string_view>

#include <Eigen/Core>

#include "sensor/material.h"
#include "vscan/common/status.h"

namespace vscan::sensor {

// A point source in the sensor frame, of the same radiant intensity in every direction it lights:
// those within cone_half_angle_rad of axis (a projector's or an illuminator's field; pi lights
// every direction).
struct Emitter {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double radiant_intensity_w_per_sr = 1.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double cone_half_angle_rad = std::numbers::pi;
};

// Position finite, intensity finite and non-negative, axis finite and non-zero, half angle within
// (0, pi]; INVALID_ARGUMENT naming "<field>.<member>".
Status ValidateEmitter(const Emitter& emitter, std::string_view field);

// One pixel over one exposure. gain_e folds the quantum efficiency, the exposure time, the
// aperture's area, the pixel's solid angle and the photon energy into electrons per unit of scene
// radiance (W / (m^2 sr)); a pixel covered by one surface collects gain_e x L whatever its distance.
struct PixelResponse {
  double gain_e = 1e6;
  double full_well_e = 10000;  // electrons at saturation
  double read_noise_e = 5;     // sigma of the noise floor, electrons
  double min_snr = 5;          // a signal below this many sigmas of its own noise does not decode
};

// gain_e, full_well_e positive, read_noise_e and min_snr non-negative, all finite;
// INVALID_ARGUMENT naming "<field>.<member>".
Status ValidatePixelResponse(const PixelResponse& response, std::string_view field);

// Radiance (W / (m^2 sr)) that `point` (normal `normal`) sends to the camera at `camera`, lit by
// `emitter`: L = f_r(l, v) I cos(theta_l) / d^2, d the emitter's distance to the point, l and v the
// unit directions to the emitter and the camera. Zero where the emitter or the camera is behind
// the surface, or the point lies outside the emitter's cone.
double DirectRadiance(const Material& material, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                      const Emitter& emitter, const Eigen::Vector3d& camera);

enum class SignalVerdict : uint8_t { kMeasured, kDark, kSaturated };

struct PixelSignal {
  double expected_e = 0;  // the mean: gain_e x radiance
  double noise_e = 0;     // its sigma: sqrt(expected_e + read_noise_e^2) (shot noise and the floor)
  double measured_e = 0;  // one draw: expected + noise, clipped to [0, full_well_e]
  // Of expected_e, the ambient light's share: it fills the well and adds shot noise, but carries
  // no pattern or modulation, so it does not count towards decoding.
  double ambient_e = 0;
  SignalVerdict verdict = SignalVerdict::kMeasured;
};

// The mean electrons of a pixel that sees `radiance` along a ray whose OffAxisFalloff is
// `off_axis_falloff` (1 on the optical axis): gain_e x radiance x off_axis_falloff.
double ExpectedElectrons(double radiance, double off_axis_falloff, const PixelResponse& response);

// The pixel's response to a mean of expected_e electrons: kSaturated when the mean reaches the full
// well, else kDark when expected_e / noise_e is below min_snr. The draw depends only on
// (seed, key), e.g. the pixel's index.
PixelSignal RespondToElectrons(double expected_e, const PixelResponse& response, uint64_t seed, uint64_t key);
// RespondToElectrons(ExpectedElectrons(radiance, 1, response), ...): a pixel on the optical axis, or
// a radiance the caller has already multiplied by the fall-off.
PixelSignal RespondToRadiance(double radiance, const PixelResponse& response, uint64_t seed, uint64_t key);
// RespondToElectrons(emitter_e + ambient_e, ...) with ambient_e recorded: the ambient light fills the
// well and adds its shot noise, but only the emitter's light decodes, so a pixel is also kDark when
// emitter_e stands below min_snr of the whole pixel's noise.
PixelSignal RespondWithAmbient(double emitter_e, double ambient_e, const PixelResponse& response, uint64_t seed,
                               uint64_t key);
// The radiance a uniform ambient irradiance (W/m^2) sends back off a surface: E albedo / pi, a diffuse
// reflector of the material's albedo.
double AmbientRadiance(double irradiance_w_per_m2, const Material& material);

// Depth noise that follows from the signal: a sensor whose depth sigma is sigma_reference_m at a
// signal of reference_e electrons has sigma_reference_m x SNR(reference_e) / SNR(signal_e) at
// signal_e, SNR(S) = S / sqrt(S + read_noise_e^2); infinite for no signal.
double SignalDepthSigma(double sigma_reference_m, double reference_e, double signal_e, double read_noise_e);

}  // namespace vscan::sensor
