#include "capture/measure_scan.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/parallel_for.h>

#include "capture/flying_pixels.h"
#include "capture/outlier_rays.h"
#include "capture/ray_verdicts.h"
#include "normals/normal_estimation.h"
#include "sensor/structured_light_visibility.h"

namespace vscan::capture {
namespace {

constexpr double kExtendedNear = 1e-4;
constexpr double kExtendedFarFactor = 4.0;
constexpr uint32_t kCleanFields = kFieldsAll;
constexpr size_t kBlock = 16384;

bool Returned(uint8_t status) {
  const auto s = static_cast<PointStatus>(status);
  return s == PointStatus::kMeasured || s == PointStatus::kOutlier || s == PointStatus::kFlyingPixel;
}

bool Rejected(uint8_t status) { return status >= static_cast<uint8_t>(PointStatus::kRejectedOutOfRange); }

Status CheckClean(const PointCloud& c) {
  const uint32_t missing = kCleanFields & ~c.fields;
  if (missing) return InvalidArgument("clean cloud: needs normal, range, intensity, instance id and pixel fields");
  const size_t n = c.size();
  if (c.normals.size() != n || c.ranges.size() != n || c.intensities.size() != n || c.instance_ids.size() != n ||
      c.pixels.size() != n) {
    return InvalidArgument("clean cloud: arrays of different lengths");
  }
  return Status::Ok();
}

// Distortion, noise and quantisation of every returned point; a point quantised away is dropped.
uint64_t ApplyNoise(const PointCloud& clean, const MeasurementSpec& spec, std::vector<uint8_t>& status,
                    std::vector<Eigen::Vector3f>& measured) {
  sensor::DepthNoise noise = spec.noise;
  noise.min_intensity = 0;  // dim points were already rejected with a reason
  if (!spec.distortion.any() && !noise.any()) return 0;
  std::atomic<uint64_t> dropped{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, clean.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    uint64_t local = 0;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (!Returned(status[i])) continue;
      Eigen::Vector3d p = measured[i].cast<double>();
      if (sensor::MeasurePoint(p, spec.distortion, noise, spec.seed, clean.pixels[i])) {
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
void RejectUnlit(const raycast::RaycastScene& scene, const Pose3& world_from_sensor, const sensor::StructuredLight& sl,
                 const PointCloud& clean, std::vector<uint8_t>& status) {
  const std::vector<sensor::ProjectorVisibility> lit =
      sensor::ProjectorVisibilityOf(scene, world_from_sensor, sl, clean.positions);
  for (size_t i = 0; i < status.size(); ++i) {
    if (status[i] == static_cast<uint8_t>(PointStatus::kRejectedOutOfRange)) continue;
    if (lit[i] == sensor::ProjectorVisibility::kUnlit) status[i] = static_cast<uint8_t>(PointStatus::kRejectedUnlit);
    if (lit[i] == sensor::ProjectorVisibility::kShadowed) {
      status[i] = static_cast<uint8_t>(PointStatus::kRejectedShadowed);
    }
  }
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

void Count(const std::vector<uint8_t>& status, MeasureStats& stats) {
  for (const uint8_t s : status) {
    switch (static_cast<PointStatus>(s)) {
      case PointStatus::kMeasured: ++stats.points; break;
      case PointStatus::kOutlier:
        ++stats.points;
        ++stats.outliers;
        break;
      case PointStatus::kFlyingPixel:
        ++stats.points;
        ++stats.flying_pixels;
        break;
      case PointStatus::kRejectedOutOfRange: ++stats.rejected_out_of_range; break;
      case PointStatus::kRejectedShadowed: ++stats.rejected_shadowed; break;
      case PointStatus::kRejectedGrazing: ++stats.rejected_grazing; break;
      case PointStatus::kRejectedDim: ++stats.rejected_dim; break;
      case PointStatus::kRejectedUnlit: ++stats.rejected_unlit; break;
      case PointStatus::kUnspecified: break;
    }
  }
}

// Normals of the returned points, in clean-cloud order; 0,0,0 for the others and where too few
// neighbours were found.
StatusOr<std::vector<Eigen::Vector3f>> EstimatedNormals(const std::vector<uint8_t>& status,
                                                        const std::vector<Eigen::Vector3f>& measured,
                                                        const NormalEstimationSpec& spec) {
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
  ASSIGN_OR_RETURN(std::vector<Eigen::Vector3f> estimated, normals::EstimateNormals(points, options));
  std::vector<Eigen::Vector3f> out(status.size(), Eigen::Vector3f::Zero());
  for (size_t k = 0; k < index.size(); ++k) {
    if (estimated[k].allFinite()) out[index[k]] = estimated[k];
  }
  return out;
}

}  // namespace

sensor::PinholeCamera ExtendedRangeCamera(const sensor::PinholeCamera& camera) {
  sensor::PinholeCamera extended = camera;
  extended.near = std::min(camera.near, kExtendedNear);
  extended.far = camera.far * kExtendedFarFactor;
  return extended;
}

StatusOr<PointCloud> MeasureScan(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                 const Pose3& world_from_sensor, PointCloud clean, const MeasurementSpec& spec,
                                 MeasureStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  RETURN_IF_ERROR(CheckClean(clean));
  MeasureStats local;
  MeasureStats& s = stats ? *stats : local;
  s = MeasureStats{};
  s.hits = clean.size();

  std::vector<uint8_t> status;
  std::vector<float> incidence;
  JudgeRays(clean, camera, spec, status, incidence);
  if (spec.structured_light) RejectUnlit(scene, world_from_sensor, *spec.structured_light, clean, status);
  std::vector<Eigen::Vector3f> measured = clean.positions;
  if (spec.outliers.any()) {
    const float max_distance = static_cast<float>(ExtendedRangeCamera(camera).far * 2.0);
    s.dropped += CastOutliers(scene, camera, world_from_sensor, clean, spec, max_distance, status, measured).missed;
  }
  if (spec.flying_pixels.enabled) MixDepthEdges(clean, camera, spec, status, measured);
  s.dropped += ApplyNoise(clean, spec, status, measured);
  if (spec.structured_light) s.dropped += QuantiseDisparities(*spec.structured_light, status, measured);
  Count(status, s);

  std::vector<Eigen::Vector3f> estimated;
  if (spec.fields & kFieldEstimatedNormal) {
    ASSIGN_OR_RETURN(estimated, EstimatedNormals(status, measured, spec.normal_estimation));
  }

  const auto keep = [&](size_t i) { return Returned(status[i]) || (spec.include_rejected && Rejected(status[i])); };
  // Output slots per block first, so that blocks fill the output in parallel and in pixel order.
  const size_t blocks = (status.size() + kBlock - 1) / kBlock;
  std::vector<size_t> first(blocks + 1, 0);
  tbb::parallel_for(size_t{0}, blocks, [&](size_t b) {
    size_t kept = 0;
    for (size_t i = b * kBlock, end = std::min(status.size(), i + kBlock); i < end; ++i) kept += keep(i);
    first[b + 1] = kept;
  });
  for (size_t b = 0; b < blocks; ++b) first[b + 1] += first[b];

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
  double min_range = std::numeric_limits<double>::infinity(), max_range = 0;
  for (size_t i = 0; i < status.size(); ++i) {
    if (!Returned(status[i])) continue;
    const double range = measured[i].norm();
    min_range = std::min(min_range, range);
    max_range = std::max(max_range, range);
  }
  s.min_range = s.points ? min_range : 0;
  s.max_range = max_range;
  s.elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

StatusOr<PointCloud> ScanMeasured(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                  const Pose3& world_from_sensor, const MeasurementSpec& spec,
                                  raycast::ScanFrame frame, const std::atomic<bool>* cancel,
                                  raycast::ScanStats* scan_stats, MeasureStats* stats) {
  raycast::ScanOptions options;
  options.fields = kCleanFields;
  options.frame = raycast::ScanFrame::kSensor;
  options.cancel = cancel;
  ASSIGN_OR_RETURN(PointCloud clean,
                   raycast::Scan(scene, ExtendedRangeCamera(camera), world_from_sensor, options, scan_stats));
  ASSIGN_OR_RETURN(PointCloud cloud, MeasureScan(scene, camera, world_from_sensor, std::move(clean), spec, stats));
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
