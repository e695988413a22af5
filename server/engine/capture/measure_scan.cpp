#include "capture/measure_scan.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/parallel_for.h>

#include "capture/flying_pixels.h"
#include "capture/indirect_light.h"
#include "capture/outlier_rays.h"
#include "capture/ray_verdicts.h"
#include "normals/normal_estimation.h"
#include "sensor/structured_light_visibility.h"
#include "vscan/common/physical_limits.h"

namespace vscan::capture {
namespace {

constexpr double kExtendedNear = 1e-4;
constexpr double kExtendedFarFactor = 4.0;
constexpr size_t kBlock = 16384;
using StatusCounts = std::array<uint64_t, static_cast<size_t>(PointStatus::kRejectedInterreflection) + 1>;

bool Returned(uint8_t status) {
  const auto s = static_cast<PointStatus>(status);
  return s == PointStatus::kMeasured || s == PointStatus::kOutlier || s == PointStatus::kFlyingPixel;
}

bool Rejected(uint8_t status) { return status >= static_cast<uint8_t>(PointStatus::kRejectedOutOfRange); }

Status CheckClean(const PointCloud& c, uint32_t needed) {
  if (needed & ~c.fields) return InvalidArgument("clean cloud: lacks fields of CleanFieldsFor(spec)");
  const size_t n = c.size();
  const auto wrong = [&](uint32_t field, size_t size) { return (needed & field) && size != n; };
  if (wrong(kFieldNormal, c.normals.size()) || wrong(kFieldIntensity, c.intensities.size()) ||
      wrong(kFieldInstanceId, c.instance_ids.size()) || wrong(kFieldPixel, c.pixels.size())) {
    return InvalidArgument("clean cloud: arrays of different lengths");
  }
  return Status::Ok();
}

// Distortion, noise and quantisation of every returned point; a point quantised away is dropped.
// sigma_factor (empty: 1 everywhere) widens each point's depth noise for its signal.
uint64_t ApplyNoise(const PointCloud& clean, const MeasurementSpec& spec, const std::vector<double>& sigma_factor,
                    std::vector<uint8_t>& status, std::vector<Eigen::Vector3f>& measured) {
  sensor::DepthNoise noise = spec.noise;
  noise.min_intensity = 0;  // dim points were already rejected with a reason
  if (!spec.distortion.any() && !noise.any()) return 0;
  std::atomic<uint64_t> dropped{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, clean.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    uint64_t local = 0;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (!Returned(status[i])) continue;
      Eigen::Vector3d p = measured[i].cast<double>();
      sensor::DepthNoise own = noise;
      if (!sigma_factor.empty()) {
        own.sigma_a *= sigma_factor[i];
        own.sigma_b *= sigma_factor[i];
        own.sigma_c *= sigma_factor[i];
      }
      if (sensor::MeasurePoint(p, spec.distortion, own, spec.seed, clean.pixels[i])) {
        measured[i] = p.cast<float>();
      } else {
        status[i] = static_cast<uint8_t>(PointStatus::kUnspecified);
        ++local;
      }
    }
    dropped += local;
  });
  return dropped.load();
}

// The projector's verdict comes right after out of range and before grazing and dim.
// Returns 1 for each point the projector's light does not reach.
std::vector<uint8_t> RejectUnlit(const raycast::RaycastScene& scene, const Pose3& world_from_sensor,
                                 const sensor::StructuredLight& sl, const PointCloud& clean,
                                 std::vector<uint8_t>& status) {
  const std::vector<sensor::ProjectorVisibility> lit =
      sensor::ProjectorVisibilityOf(scene, world_from_sensor, sl, clean.positions);
  std::vector<uint8_t> hidden(lit.size());
  for (size_t i = 0; i < status.size(); ++i) {
    hidden[i] = lit[i] != sensor::ProjectorVisibility::kLit;
    if (status[i] == static_cast<uint8_t>(PointStatus::kRejectedOutOfRange)) continue;
    if (lit[i] == sensor::ProjectorVisibility::kUnlit) status[i] = static_cast<uint8_t>(PointStatus::kRejectedUnlit);
    if (lit[i] == sensor::ProjectorVisibility::kShadowed) {
      status[i] = static_cast<uint8_t>(PointStatus::kRejectedShadowed);
    }
  }
  return hidden;
}

struct SignalEffects {
  std::vector<double> sigma_factor;  // on each ray's depth noise
  std::vector<double> range_scale;   // time of flight with indirect light: measured over true range
};

// The returned light's verdicts on the rays no earlier rule rejected, its measured electrons as the
// intensity, each ray's factor on the depth noise, and with indirect light the interreflection
// verdict (structured light) or the multipath range (time of flight) (docs/SENSORS.md, "The
// returned signal", "Indirect light").
StatusOr<SignalEffects> JudgeSignals(const raycast::RaycastScene& scene, const Pose3& world_from_sensor,
                                     const sensor::PinholeCamera& camera, const MeasurementSpec& spec,
                                     const std::atomic<bool>* cancel, std::span<const uint8_t> emitter_hidden,
                                     std::span<const float> direct_radiance, PointCloud& clean,
                                     std::vector<uint8_t>& status) {
  const ReturnedLightSpec& light = *spec.returned_light;
  std::vector<IndirectReturn> indirect;
  std::vector<double> indirect_radiance;
  if (light.indirect_samples > 0) {
    std::vector<uint8_t> wanted(status.size());
    for (size_t i = 0; i < status.size(); ++i) wanted[i] = status[i] == static_cast<uint8_t>(PointStatus::kMeasured);
    ASSIGN_OR_RETURN(indirect,
                     IndirectReturns(scene, world_from_sensor, camera, clean, light, spec.seed, wanted, cancel));
    indirect_radiance.resize(indirect.size());
    for (size_t i = 0; i < indirect.size(); ++i) indirect_radiance[i] = indirect[i].radiance;
  }
  const std::vector<sensor::PixelSignal> signals =
      ReturnedSignals(clean, light, spec.seed, indirect_radiance, emitter_hidden, direct_radiance);
  SignalEffects effects{std::vector<double>(signals.size(), 1.0), {}};
  const bool time_of_flight = !indirect.empty() && light.modulation_frequency_hz > 0 && !spec.structured_light;
  if (time_of_flight) effects.range_scale.assign(signals.size(), 1.0);
  const bool interreflection = !indirect.empty() && spec.structured_light.has_value();
  const bool intensities = clean.Has(kFieldIntensity);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, signals.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (intensities) clean.intensities[i] = static_cast<float>(signals[i].measured_e);
      if (status[i] != static_cast<uint8_t>(PointStatus::kMeasured)) continue;
      // The indirect light in electrons, on the same scale as the signal's mean.
      const double to_electrons =
          indirect.empty()
              ? 0.0
              : sensor::ExpectedElectrons(1.0, sensor::OffAxisFalloff(clean.positions[i].cast<double>()), light.pixel);
      const double indirect_e = indirect.empty() ? 0.0 : to_electrons * indirect[i].radiance;
      const double direct_e = signals[i].expected_e - indirect_e - signals[i].ambient_e;
      if (signals[i].verdict == sensor::SignalVerdict::kDark) {
        status[i] = static_cast<uint8_t>(PointStatus::kRejectedDark);
      } else if (signals[i].verdict == sensor::SignalVerdict::kSaturated) {
        status[i] = static_cast<uint8_t>(PointStatus::kRejectedSaturated);
      } else if (interreflection && direct_e < light.interreflection_ratio * indirect_e) {
        status[i] = static_cast<uint8_t>(PointStatus::kRejectedInterreflection);
      } else {
        effects.sigma_factor[i] = SignalSigmaFactor(light, signals[i]);
        if (time_of_flight) {
          const Eigen::Vector3d p = clean.positions[i].cast<double>();
          const double range = p.norm();
          const double path = (light.emitter.position - p).norm() + range;
          effects.range_scale[i] = MultipathRange(light.emitter.position, p / range, path, direct_e,
                                                  to_electrons * indirect[i].phasor, light.modulation_frequency_hz) /
                                   range;
        }
      }
    }
  });
  return effects;
}

// Disparity quantisation of the returned points; a point left with no depth is dropped.
uint64_t QuantiseDisparities(const sensor::StructuredLight& sl, std::vector<uint8_t>& status,
                             std::vector<Eigen::Vector3f>& measured) {
  if (!(sl.disparity_step_px > 0)) return 0;
  std::vector<size_t> index;
  std::vector<Eigen::Vector3f> points;
  for (size_t i = 0; i < status.size(); ++i) {
    if (!Returned(status[i])) continue;
    index.push_back(i);
    points.push_back(measured[i]);
  }
  sensor::QuantiseDisparity(sl, points);
  uint64_t dropped = 0;
  for (size_t k = 0; k < index.size(); ++k) {
    if (points[k].allFinite()) {
      measured[index[k]] = points[k];
    } else {
      status[index[k]] = static_cast<uint8_t>(PointStatus::kUnspecified);
      ++dropped;
    }
  }
  return dropped;
}

// How many rays of each PointStatus a block holds, and the range span of its returned points.
struct BlockTally {
  StatusCounts of_status{};
  size_t kept = 0;
  double min_range = std::numeric_limits<double>::infinity(), max_range = 0;
};

void Count(const StatusCounts& n, MeasureStats& stats) {
  const auto at = [&](PointStatus s) { return n[static_cast<size_t>(s)]; };
  stats.outliers = at(PointStatus::kOutlier);
  stats.flying_pixels = at(PointStatus::kFlyingPixel);
  stats.points = at(PointStatus::kMeasured) + stats.outliers + stats.flying_pixels;
  stats.rejected_out_of_range = at(PointStatus::kRejectedOutOfRange);
  stats.rejected_shadowed = at(PointStatus::kRejectedShadowed);
  stats.rejected_grazing = at(PointStatus::kRejectedGrazing);
  stats.rejected_dim = at(PointStatus::kRejectedDim);
  stats.rejected_unlit = at(PointStatus::kRejectedUnlit);
  stats.rejected_dark = at(PointStatus::kRejectedDark);
  stats.rejected_saturated = at(PointStatus::kRejectedSaturated);
  stats.rejected_interreflection = at(PointStatus::kRejectedInterreflection);
}

// Normals of the returned points, in clean-cloud order; 0,0,0 for the others and where too few
// neighbours were found.
StatusOr<std::vector<Eigen::Vector3f>> EstimatedNormals(const std::vector<uint8_t>& status,
                                                        const std::vector<Eigen::Vector3f>& measured,
                                                        const NormalEstimationSpec& spec,
                                                        const std::atomic<bool>* cancel) {
  std::vector<Eigen::Vector3f> points;
  std::vector<size_t> index;
  for (size_t i = 0; i < status.size(); ++i) {
    if (!Returned(status[i])) continue;
    points.push_back(measured[i]);
    index.push_back(i);
  }
  normals::NormalOptions options;
  options.k = spec.k;
  options.max_distance = static_cast<float>(spec.max_distance);
  options.viewpoint = Eigen::Vector3f::Zero();
  options.cancel = cancel;
  ASSIGN_OR_RETURN(std::vector<Eigen::Vector3f> estimated, normals::EstimateNormals(points, options));
  std::vector<Eigen::Vector3f> out(status.size(), Eigen::Vector3f::Zero());
  for (size_t k = 0; k < index.size(); ++k) {
    if (estimated[k].allFinite()) out[index[k]] = estimated[k];
  }
  return out;
}

// The output when every ray is kept: slot i is ray i, so the working arrays become the cloud's
// instead of being copied. Rejected rays sit at their clean positions in measured (only returned
// rays are ever moved).
PointCloud TakeEveryRay(uint32_t fields, PointCloud& clean, std::vector<Eigen::Vector3f>& measured,
                        std::vector<float>& incidence, std::vector<uint8_t>& status,
                        std::vector<Eigen::Vector3f>& estimated) {
  PointCloud out;
  out.fields = fields;
  out.positions = std::move(measured);
  if (out.Has(kFieldNormal)) out.normals = std::move(clean.normals);
  if (out.Has(kFieldRange)) {
    out.ranges.resize(out.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, out.size(), kBlock), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) out.ranges[i] = out.positions[i].norm();
    });
  }
  if (out.Has(kFieldIntensity)) out.intensities = std::move(clean.intensities);
  if (out.Has(kFieldInstanceId)) out.instance_ids = std::move(clean.instance_ids);
  if (out.Has(kFieldPixel)) out.pixels = std::move(clean.pixels);
  if (out.Has(kFieldCleanPosition)) out.clean_positions = std::move(clean.positions);
  if (out.Has(kFieldIncidence)) out.incidence_angles = std::move(incidence);
  if (out.Has(kFieldStatus)) out.statuses = std::move(status);
  if (out.Has(kFieldEstimatedNormal)) out.estimated_normals = std::move(estimated);
  return out;
}

}  // namespace

uint32_t CleanFieldsFor(const MeasurementSpec& spec) {
  uint32_t fields = kFieldPosition | kFieldPixel;
  if (spec.grazing_limit_deg > 0 || spec.flying_pixels.enabled || (spec.fields & (kFieldNormal | kFieldIncidence))) {
    fields |= kFieldNormal;
  }
  if (spec.noise.min_intensity > 0 || (spec.fields & kFieldIntensity)) fields |= kFieldIntensity;
  if (spec.fields & kFieldInstanceId) fields |= kFieldInstanceId;
  if (spec.returned_light) fields |= kFieldNormal | kFieldInstanceId;
  return fields;
}

sensor::PinholeCamera ExtendedRangeCamera(const sensor::PinholeCamera& camera) {
  sensor::PinholeCamera extended = camera;
  extended.near = std::min(camera.near, kExtendedNear);
  extended.far = std::min(camera.far * kExtendedFarFactor, kMaxFarM);
  return extended;
}

StatusOr<PointCloud> MeasureScan(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                 const Pose3& world_from_sensor, PointCloud clean, const MeasurementSpec& spec,
                                 const std::atomic<bool>* cancel, MeasureStats* stats,
                                 std::span<const float> direct_radiance) {
  const auto start = std::chrono::steady_clock::now();
  RETURN_IF_ERROR(CheckClean(clean, CleanFieldsFor(spec)));
  if (!direct_radiance.empty() && direct_radiance.size() != clean.size()) {
    return InvalidArgument("direct_radiance: one per clean point");
  }
  MeasureStats local;
  MeasureStats& s = stats ? *stats : local;
  s = MeasureStats{};
  s.hits = clean.size();

  std::vector<uint8_t> status;
  std::vector<float> incidence;
  JudgeRays(clean, camera, spec, status, incidence);
  std::vector<uint8_t> emitter_hidden;
  if (spec.structured_light) {
    emitter_hidden = RejectUnlit(scene, world_from_sensor, *spec.structured_light, clean, status);
  }
  SignalEffects signal;
  if (spec.returned_light) {
    ASSIGN_OR_RETURN(signal,
                     JudgeSignals(scene, world_from_sensor, camera, spec, cancel, emitter_hidden, direct_radiance,
                                  clean, status));
  }
  std::vector<Eigen::Vector3f> measured = clean.positions;
  for (size_t i = 0; i < signal.range_scale.size(); ++i) measured[i] *= static_cast<float>(signal.range_scale[i]);
  if (spec.outliers.any()) {
    const float max_distance = static_cast<float>(ExtendedRangeCamera(camera).far * 2.0);
    s.dropped += CastOutliers(scene, camera, world_from_sensor, clean, spec, max_distance, status, measured).missed;
  }
  if (spec.flying_pixels.enabled) MixDepthEdges(clean, camera, spec, status, measured);
  s.dropped += ApplyNoise(clean, spec, signal.sigma_factor, status, measured);
  if (spec.structured_light) s.dropped += QuantiseDisparities(*spec.structured_light, status, measured);

  std::vector<Eigen::Vector3f> estimated;
  if (spec.fields & kFieldEstimatedNormal) {
    ASSIGN_OR_RETURN(estimated, EstimatedNormals(status, measured, spec.normal_estimation, cancel));
  }

  const auto keep = [&](size_t i) { return Returned(status[i]) || (spec.include_rejected && Rejected(status[i])); };
  // Output slots per block first, so that blocks fill the output in parallel and in pixel order; the
  // counters and the range span come with them.
  const size_t blocks = (status.size() + kBlock - 1) / kBlock;
  std::vector<BlockTally> tally(blocks);
  tbb::parallel_for(size_t{0}, blocks, [&](size_t b) {
    BlockTally& t = tally[b];
    for (size_t i = b * kBlock, end = std::min(status.size(), i + kBlock); i < end; ++i) {
      ++t.of_status[status[i]];
      t.kept += keep(i);
      if (!Returned(status[i])) continue;
      const double range = measured[i].norm();
      t.min_range = std::min(t.min_range, range);
      t.max_range = std::max(t.max_range, range);
    }
  });
  std::vector<size_t> first(blocks + 1, 0);
  StatusCounts of_status{};
  double min_range = std::numeric_limits<double>::infinity(), max_range = 0;
  for (size_t b = 0; b < blocks; ++b) {
    first[b + 1] = first[b] + tally[b].kept;
    for (size_t k = 0; k < of_status.size(); ++k) of_status[k] += tally[b].of_status[k];
    min_range = std::min(min_range, tally[b].min_range);
    max_range = std::max(max_range, tally[b].max_range);
  }
  Count(of_status, s);
  s.min_range = s.points ? min_range : 0;
  s.max_range = max_range;

  if (first[blocks] == status.size()) {
    PointCloud out = TakeEveryRay(spec.fields | kFieldPosition, clean, measured, incidence, status, estimated);
    s.elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
  }
  PointCloud out;
  out.fields = spec.fields | kFieldPosition;
  out.Resize(first[blocks]);
  tbb::parallel_for(size_t{0}, blocks, [&](size_t b) {
    size_t k = first[b];
    for (size_t i = b * kBlock, end = std::min(status.size(), i + kBlock); i < end; ++i) {
      if (!keep(i)) continue;
      const Eigen::Vector3f& p = Returned(status[i]) ? measured[i] : clean.positions[i];
      out.positions[k] = p;
      if (out.Has(kFieldNormal)) out.normals[k] = clean.normals[i];
      if (out.Has(kFieldRange)) out.ranges[k] = p.norm();
      if (out.Has(kFieldIntensity)) out.intensities[k] = clean.intensities[i];
      if (out.Has(kFieldInstanceId)) out.instance_ids[k] = clean.instance_ids[i];
      if (out.Has(kFieldPixel)) out.pixels[k] = clean.pixels[i];
      if (out.Has(kFieldCleanPosition)) out.clean_positions[k] = clean.positions[i];
      if (out.Has(kFieldIncidence)) out.incidence_angles[k] = incidence[i];
      if (out.Has(kFieldStatus)) out.statuses[k] = status[i];
      if (out.Has(kFieldEstimatedNormal)) out.estimated_normals[k] = estimated[i];
      ++k;
    }
  });
  s.elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

StatusOr<PointCloud> ScanMeasured(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                  const Pose3& world_from_sensor, const MeasurementSpec& spec,
                                  raycast::ScanFrame frame, const std::atomic<bool>* cancel,
                                  raycast::ScanStats* scan_stats, MeasureStats* stats) {
  raycast::ScanOptions options;
  options.fields = CleanFieldsFor(spec);
  options.frame = raycast::ScanFrame::kSensor;
  options.cancel = cancel;
  ASSIGN_OR_RETURN(PointCloud clean,
                   raycast::Scan(scene, ExtendedRangeCamera(camera), world_from_sensor, options, scan_stats));
  ASSIGN_OR_RETURN(PointCloud cloud, MeasureScan(scene, camera, world_from_sensor, std::move(clean), spec, cancel, stats));
  if (frame == raycast::ScanFrame::kWorld) SensorToWorld(world_from_sensor, cloud);
  return cloud;
}

void SensorToWorld(const Pose3& world_from_sensor, PointCloud& cloud) {
  const Eigen::Affine3f transform(world_from_sensor.matrix().cast<float>());
  const Eigen::Matrix3f rotation = transform.linear();
  const auto each = [](std::vector<Eigen::Vector3f>& values, const auto& map) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, values.size(), kBlock), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) values[i] = map(values[i]);
    });
  };
  each(cloud.positions, [&](const Eigen::Vector3f& p) -> Eigen::Vector3f { return transform * p; });
  each(cloud.clean_positions, [&](const Eigen::Vector3f& p) -> Eigen::Vector3f { return transform * p; });
  each(cloud.normals, [&](const Eigen::Vector3f& n) -> Eigen::Vector3f { return rotation * n; });
  each(cloud.estimated_normals, [&](const Eigen::Vector3f& n) -> Eigen::Vector3f { return rotation * n; });
}

}  // namespace vscan::capture
