#pragma once
// The signal each pixel of a clean scan receives from the sensor's own emitter, off each object's
// material: the direct term of docs/SENSORS.md, "The returned signal", applied to a whole scan.

#include <cstdint>
#include <span>
#include <vector>

#include "sensor/camera.h"
#include "sensor/material.h"
#include "sensor/pixel_radiometry.h"
#include "sensor/returned_signal.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::capture {

struct ReturnedLightSpec {
  // In the sensor frame: at the camera for a time-of-flight or depth camera, at the projector for
  // structured light.
  sensor::Emitter emitter;
  // Electrons per unit radiance on the optical axis (PixelGain) and the pixel's limits.
  sensor::PixelResponse pixel;
  // materials[id] is the material of the object with instance id `id`; ids past the end (and 0,
  // no object) take default_material.
  std::vector<sensor::Material> materials;
  sensor::Material default_material;
  // The depth noise's sigma holds at this many electrons and grows as the signal falls
  // (SignalDepthSigma); 0: the depth noise does not follow the signal.
  double reference_e = 0;
  // One-bounce indirect light (capture/indirect_light.h): Monte Carlo samples per computed pixel,
  // at most kMaxIndirectSamples; 0: direct light only.
  uint32_t indirect_samples = 0;
  // The indirect light is computed on every indirect_stride_px-th pixel of each row and column and
  // interpolated between them on the same surface; 1: on every pixel. In [1, kMaxIndirectStridePx].
  uint32_t indirect_stride_px = 4;
  // Time of flight: the depth is the phase of the returned light at this modulation frequency (Hz);
  // 0: the sensor does not measure time of flight, and the depth stays the surface's.
  double modulation_frequency_hz = 0;
  // Structured light: a pixel decodes only when its direct electrons are at least this many times
  // its indirect ones (Gupta et al.'s condition for binary codes is 1).
  double interreflection_ratio = 1.0;
  // A uniform ambient light in the camera's band, the irradiance it puts on every surface (W/m^2);
  // 0: none. Each surface sends it back as a diffuse reflector of its material's albedo.
  double ambient_irradiance_w_per_m2 = 0;
};

inline constexpr double kMaxAmbientIrradiance = 1e4;

// The radiance a surface of this material sends back of the ambient light: E albedo / pi.
double AmbientRadiance(const ReturnedLightSpec& spec, const sensor::Material& material);

inline constexpr uint32_t kMaxIndirectSamples = 4096;
inline constexpr uint32_t kMaxIndirectStridePx = 64;
inline constexpr double kMaxModulationFrequencyHz = 1e10;

// Emitter and pixel checked (ValidateEmitter, ValidatePixelResponse), every material
// (ValidateMaterial), reference_e finite and non-negative; INVALID_ARGUMENT naming
// "<field>.<member>".
Status ValidateReturnedLight(const ReturnedLightSpec& spec, std::string_view field);

// The gain of a camera pixel: the pixel's solid angle is the camera's (1 / (fx fy) on the axis),
// the rest from `pixel` (aperture, exposure, quantum efficiency, wavelength).
double CameraPixelGain(const sensor::PinholeCamera& camera, sensor::PinholePixel pixel);

// One PixelSignal per point of clean (sensor frame, with normals, instance ids and pixels): the
// material's direct radiance towards the camera at the origin, plus indirect_radiance[i] when given
// (the indirect light, capture/indirect_light.h), the cos^4 fall-off of the pixel's ray, then the
// pixel's response with its noise drawn from (seed, pixel index). Where emitter_hidden[i] is 1 (a
// projector's shadow or outside its field) the emitter's direct light does not reach the point.
// direct_radiance, when given (one per point), is the direct radiance already evaluated (the raster
// shaders'), used instead of DirectRadiance; emitter_hidden still zeroes it.
std::vector<sensor::PixelSignal> ReturnedSignals(const PointCloud& clean, const ReturnedLightSpec& spec,
                                                 uint64_t seed, std::span<const double> indirect_radiance = {},
                                                 std::span<const uint8_t> emitter_hidden = {},
                                                 std::span<const float> direct_radiance = {});

// The factor on the depth noise's sigma at this signal: SignalDepthSigma(1, reference_e, expected_e,
// read_noise_e), 1 when reference_e is 0.
double SignalSigmaFactor(const ReturnedLightSpec& spec, const sensor::PixelSignal& signal);

}  // namespace vscan::capture
