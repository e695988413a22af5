#include "sensor/returned_signal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "random/seeded_draws.h"
#include "sensor/brdf.h"

namespace vscan::sensor {
namespace {

Status CheckMember(double value, bool positive, std::string_view field, std::string_view member) {
  if (!std::isfinite(value)) return InvalidArgument(FieldPath(field, member), "NaN or infinite value");
  if (positive && !(value > 0)) return InvalidArgument(FieldPath(field, member), "must be > 0");
  if (value < 0) return InvalidArgument(FieldPath(field, member), "must be >= 0");
  return Status::Ok();
}

double Snr(double signal_e, double read_noise_e) {
  return signal_e / std::sqrt(signal_e + read_noise_e * read_noise_e);
}

}  // namespace

Status ValidateEmitter(const Emitter& emitter, std::string_view field) {
  if (!emitter.position.allFinite()) return InvalidArgument(FieldPath(field, "position"), "NaN or infinite value");
  RETURN_IF_ERROR(CheckMember(emitter.radiant_intensity_w_per_sr, false, field, "radiant_intensity_w_per_sr"));
  if (!emitter.axis.allFinite()) return InvalidArgument(FieldPath(field, "axis"), "NaN or infinite value");
  if (!(emitter.axis.norm() > 0)) return InvalidArgument(FieldPath(field, "axis"), "must not be zero");
  const double half_angle = emitter.cone_half_angle_rad;
  if (!std::isfinite(half_angle)) {
    return InvalidArgument(FieldPath(field, "cone_half_angle_rad"), "NaN or infinite value");
  }
  if (!(half_angle > 0) || half_angle > std::numbers::pi) {
    return InvalidArgument(FieldPath(field, "cone_half_angle_rad"), "must be within (0, pi]");
  }
  return Status::Ok();
}

Status ValidatePixelResponse(const PixelResponse& response, std::string_view field) {
  RETURN_IF_ERROR(CheckMember(response.gain_e, true, field, "gain_e"));
  RETURN_IF_ERROR(CheckMember(response.full_well_e, true, field, "full_well_e"));
  RETURN_IF_ERROR(CheckMember(response.read_noise_e, false, field, "read_noise_e"));
  return CheckMember(response.min_snr, false, field, "min_snr");
}

double DirectRadiance(const Material& material, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                      const Emitter& emitter, const Eigen::Vector3d& camera) {
  const Eigen::Vector3d to_emitter = emitter.position - point;
  const double d2 = to_emitter.squaredNorm();
  if (!(d2 > 0)) return 0;
  const Eigen::Vector3d l = to_emitter / std::sqrt(d2);
  if (emitter.cone_half_angle_rad < std::numbers::pi &&
      -l.dot(emitter.axis.normalized()) < std::cos(emitter.cone_half_angle_rad)) {
    return 0;
  }
  const Eigen::Vector3d v = (camera - point).normalized();
  const double cos_l = normal.dot(l);
  if (!(cos_l > 0)) return 0;
  return EvaluateBrdf(material, normal, l, v) * emitter.radiant_intensity_w_per_sr * cos_l / d2;
}

double ExpectedElectrons(double radiance, double off_axis_falloff, const PixelResponse& response) {
  return response.gain_e * radiance * off_axis_falloff;
}

PixelSignal RespondToRadiance(double radiance, const PixelResponse& response, uint64_t seed, uint64_t key) {
  return RespondToElectrons(ExpectedElectrons(radiance, 1, response), response, seed, key);
}

PixelSignal RespondToElectrons(double expected_e, const PixelResponse& response, uint64_t seed, uint64_t key) {
  PixelSignal out;
  out.expected_e = std::max(0.0, expected_e);
  out.noise_e = std::sqrt(out.expected_e + response.read_noise_e * response.read_noise_e);
  random::KeyedNormals normals(seed, key);
  out.measured_e = std::clamp(out.expected_e + out.noise_e * normals.Next(), 0.0, response.full_well_e);
  if (out.expected_e >= response.full_well_e) {
    out.verdict = SignalVerdict::kSaturated;
  } else if (!(out.noise_e > 0) || out.expected_e / out.noise_e < response.min_snr) {
    out.verdict = SignalVerdict::kDark;
  }
  return out;
}

PixelSignal RespondWithAmbient(double emitter_e, double ambient_e, const PixelResponse& response, uint64_t seed,
                               uint64_t key) {
  PixelSignal signal = RespondToElectrons(emitter_e + ambient_e, response, seed, key);
  signal.ambient_e = ambient_e;
  if (ambient_e > 0 && signal.verdict == SignalVerdict::kMeasured && emitter_e < response.min_snr * signal.noise_e) {
    signal.verdict = SignalVerdict::kDark;
  }
  return signal;
}

double AmbientRadiance(double irradiance_w_per_m2, const Material& material) {
  return irradiance_w_per_m2 * material.albedo / std::numbers::pi;
}

double SignalDepthSigma(double sigma_reference_m, double reference_e, double signal_e, double read_noise_e) {
  if (!(signal_e > 0)) return std::numeric_limits<double>::infinity();
  return sigma_reference_m * Snr(reference_e, read_noise_e) / Snr(signal_e, read_noise_e);
}

}  // namespace vscan::sensor
