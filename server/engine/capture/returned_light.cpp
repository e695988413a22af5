#include "capture/returned_light.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>

namespace vscan::capture {
namespace {

// The signal's draws must not repeat the depth noise's, which come from (seed, pixel) too.
constexpr uint64_t kSignalStream = 0x5349474e414c5f45ull;

}  // namespace

Status ValidateReturnedLight(const ReturnedLightSpec& spec, std::string_view field) {
  const std::string at(field);
  RETURN_IF_ERROR(sensor::ValidateEmitter(spec.emitter, at + ".emitter"));
  RETURN_IF_ERROR(sensor::ValidatePixelResponse(spec.pixel, at + ".pixel"));
  RETURN_IF_ERROR(sensor::ValidateMaterial(spec.default_material, at + ".default_material"));
  for (size_t i = 0; i < spec.materials.size(); ++i) {
    RETURN_IF_ERROR(sensor::ValidateMaterial(spec.materials[i], at + ".materials[" + std::to_string(i) + "]"));
  }
  if (!std::isfinite(spec.reference_e) || spec.reference_e < 0) {
    return InvalidArgument(at + ".reference_e", "must be finite and not negative (electrons)");
  }
  if (!(spec.ambient_irradiance_w_per_m2 >= 0 && spec.ambient_irradiance_w_per_m2 <= kMaxAmbientIrradiance)) {
    return InvalidArgument(at + ".ambient_irradiance_w_per_m2", "must be in [0, 1e4] W/m^2");
  }
  if (spec.indirect_samples > kMaxIndirectSamples) {
    return InvalidArgument(at + ".indirect_samples", "must be at most " + std::to_string(kMaxIndirectSamples));
  }
  if (spec.indirect_stride_px < 1 || spec.indirect_stride_px > kMaxIndirectStridePx) {
    return InvalidArgument(at + ".indirect_stride_px", "must be in [1, " + std::to_string(kMaxIndirectStridePx) + "]");
  }
  if (!std::isfinite(spec.modulation_frequency_hz) || spec.modulation_frequency_hz < 0 ||
      spec.modulation_frequency_hz > kMaxModulationFrequencyHz) {
    return InvalidArgument(at + ".modulation_frequency_hz", "must be in [0, 1e10] Hz");
  }
  if (!std::isfinite(spec.interreflection_ratio) || spec.interreflection_ratio < 0) {
    return InvalidArgument(at + ".interreflection_ratio", "must be finite and not negative");
  }
  return Status::Ok();
}

double CameraPixelGain(const sensor::PinholeCamera& camera, sensor::PinholePixel pixel) {
  pixel.pixel_solid_angle_sr = 1.0 / (camera.fx * camera.fy);
  return sensor::PixelGain(pixel);
}

std::vector<sensor::PixelSignal> ReturnedSignals(const PointCloud& clean, const ReturnedLightSpec& spec,
                                                 uint64_t seed, std::span<const double> indirect_radiance,
                                                 std::span<const uint8_t> emitter_hidden,
                                                 std::span<const float> direct_radiance) {
  std::vector<sensor::PixelSignal> signals(clean.size());
  const bool has_ids = clean.Has(kFieldInstanceId);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, clean.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const uint32_t id = has_ids ? clean.instance_ids[i] : 0;
      const sensor::Material& material =
          id != 0 && id < spec.materials.size() ? spec.materials[id] : spec.default_material;
      const Eigen::Vector3d point = clean.positions[i].cast<double>();
      const bool hidden = !emitter_hidden.empty() && emitter_hidden[i] != 0;
      double direct = 0;  // none where the emitter is hidden
      if (!hidden && !direct_radiance.empty()) {
        direct = direct_radiance[i];
      } else if (!hidden) {
        // The side the camera sees: a mesh's winding need not point its normals outwards.
        Eigen::Vector3d normal = clean.normals[i].cast<double>();
        if (normal.dot(point) > 0) normal = -normal;
        direct = sensor::DirectRadiance(material, point, normal, spec.emitter, Eigen::Vector3d::Zero());
      }
      const double radiance = direct + (indirect_radiance.empty() ? 0.0 : indirect_radiance[i]);
      const double falloff = sensor::OffAxisFalloff(point);
      const double ambient_e = sensor::ExpectedElectrons(AmbientRadiance(spec, material), falloff, spec.pixel);
      signals[i] = sensor::RespondWithAmbient(sensor::ExpectedElectrons(radiance, falloff, spec.pixel), ambient_e,
                                              spec.pixel, seed ^ kSignalStream, clean.pixels[i]);
    }
  });
  return signals;
}

double AmbientRadiance(const ReturnedLightSpec& spec, const sensor::Material& material) {
  return sensor::AmbientRadiance(spec.ambient_irradiance_w_per_m2, material);
}

double SignalSigmaFactor(const ReturnedLightSpec& spec, const sensor::PixelSignal& signal) {
  if (!(spec.reference_e > 0)) return 1.0;
  if (!(signal.ambient_e > 0)) {
    return sensor::SignalDepthSigma(1.0, spec.reference_e, signal.expected_e, spec.pixel.read_noise_e);
  }
  // The ambient light's shot noise joins the floor: SNR = active / sqrt(active + ambient + read^2).
  const double floor = std::sqrt(spec.pixel.read_noise_e * spec.pixel.read_noise_e + signal.ambient_e);
  const double active = signal.expected_e - signal.ambient_e;
  const double snr_reference = spec.reference_e / std::hypot(std::sqrt(spec.reference_e), spec.pixel.read_noise_e);
  const double snr = active / std::hypot(std::sqrt(std::max(0.0, active)), floor);
  return snr > 0 ? snr_reference / snr : std::numeric_limits<double>::infinity();
}

}  // namespace vscan::capture
