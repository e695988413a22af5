#include "evaluation/view_hits.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "raycast/scanner.h"

namespace vscan::evaluation {
namespace {

// Pixels of rounding slack around the window a sample's neighbours can project to.
constexpr double kSlackPx = 0.05;

// The widest tangent of a pixel centre's ray along one image axis.
double WidestTangent(uint32_t pixels, double f, double c) {
  return std::max(std::abs(0.5 - c), std::abs(pixels - 0.5 - c)) / f;
}

// Pixels [first, last] whose centres lie within reach of centre (in pixels), clipped to the image;
// false when none do.
bool Window(double centre, double reach, uint32_t pixels, int& first, int& last) {
  const double lo = std::ceil(centre - reach), hi = std::floor(centre + reach);
  if (!(hi >= 0) || !(lo <= pixels - 1.0)) return false;
  first = static_cast<int>(std::max(lo, 0.0));
  last = static_cast<int>(std::min(hi, pixels - 1.0));
  return first <= last;
}

// Whether the pixel's mean signal from a hit (sensor frame, normal facing the sensor) decodes.
bool Measurable(const MeasurableLight& light, const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  const double radiance = sensor::DirectRadiance(light.material, point, normal, light.emitter, Eigen::Vector3d::Zero());
  const double falloff = sensor::OffAxisFalloff(point);
  const double ambient = sensor::AmbientRadiance(light.ambient_irradiance_w_per_m2, light.material);
  // The verdict reads the mean only, so the draw's seed does not matter.
  return sensor::RespondWithAmbient(sensor::ExpectedElectrons(radiance, falloff, light.pixel),
                                    sensor::ExpectedElectrons(ambient, falloff, light.pixel), light.pixel, 0, 0)
             .verdict == sensor::SignalVerdict::kMeasured;
}

}  // namespace

StatusOr<ViewHits> CastView(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                            const Pose3& frame_from_sensor, double max_incidence_deg,
                            const std::atomic<bool>* cancel, const MeasurableLight* light) {
  raycast::ScanOptions scan;
  scan.fields = kFieldPosition | kFieldNormal | kFieldPixel;
  scan.frame = raycast::ScanFrame::kWorld;
  scan.cancel = cancel;
  ASSIGN_OR_RETURN(PointCloud cloud, raycast::Scan(scene, camera, frame_from_sensor, scan));
  ViewHits view;
  view.camera = camera;
  view.frame_from_sensor = frame_from_sensor;
  view.hit_of_pixel.assign(camera.pixel_count(), -1);
  view.hits.reserve(cloud.size());
  const Eigen::Vector3f origin = frame_from_sensor.translation().cast<float>();
  const auto min_cos = static_cast<float>(std::cos(max_incidence_deg * std::numbers::pi / 180));
  // Normals face the sensor, so the cosine is never negative: 90 degrees keeps every hit.
  const bool keep_all = max_incidence_deg >= 90;
  const Eigen::Isometry3d sensor_from_frame = frame_from_sensor.inverse();
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f to_sensor = (origin - cloud.positions[i]).normalized();
    if (!keep_all && cloud.normals[i].dot(to_sensor) < min_cos) continue;
    if (light && !Measurable(*light, sensor_from_frame * cloud.positions[i].cast<double>(),
                             sensor_from_frame.linear() * cloud.normals[i].cast<double>())) {
      continue;
    }
    view.hit_of_pixel[cloud.pixels[i]] = static_cast<int32_t>(view.hits.size());
    view.hits.push_back(cloud.positions[i]);
  }
  return view;
}

SampleBits SamplesNearHits(const ViewHits& view, std::span<const Eigen::Vector3f> samples, double tau) {
  SampleBits seen(samples.size());
  if (view.hits.empty()) return seen;
  const sensor::PinholeCamera& cam = view.camera;
  const Eigen::Isometry3d sensor_from_frame = view.frame_from_sensor.inverse();
  const Eigen::Matrix3f rotation = sensor_from_frame.linear().cast<float>();
  const Eigen::Vector3f translation = sensor_from_frame.translation().cast<float>();
  const auto tau_sq = static_cast<float>(tau * tau);
  const auto near_hit = [&](const Eigen::Vector3f& sample, int32_t hit) {
    return hit >= 0 && (view.hits[static_cast<size_t>(hit)] - sample).squaredNorm() <= tau_sq;
  };
  // A hit q within tau of sample p, both in the sensor frame, has
  //   |x_p / z_p - x_q / z_q| = |(x_p - x_q) + (x_q / z_q)(z_q - z_p)| / z_p <= tau sqrt(1 + t^2) / z_p
  // with t the widest tangent of a pixel's ray, and q projects onto its pixel's centre.
  const double reach_u = cam.fx * tau * std::hypot(1.0, WidestTangent(cam.width, cam.fx, cam.cx));
  const double reach_v = cam.fy * tau * std::hypot(1.0, WidestTangent(cam.height, cam.fy, cam.cy));
  for (size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3f p = rotation * samples[i] + translation;
    const double z = p.z();
    // Hits lie at depths near..far, so a sample farther than tau outside cannot be near one.
    if (z < cam.near - tau || z > cam.far + tau) continue;
    if (!(z > 0)) {
      // At the sensor's own depth (possible only when near < tau): no window, try every hit.
      for (int32_t h = 0; h < static_cast<int32_t>(view.hits.size()); ++h) {
        if (near_hit(samples[i], h)) {
          seen.Set(i);
          break;
        }
      }
      continue;
    }
    int u0, u1, v0, v1;
    if (!Window(cam.fx * p.x() / z + cam.cx - 0.5, reach_u / z + kSlackPx, cam.width, u0, u1) ||
        !Window(cam.fy * p.y() / z + cam.cy - 0.5, reach_v / z + kSlackPx, cam.height, v0, v1)) {
      continue;
    }
    bool found = false;
    for (int v = v0; v <= v1 && !found; ++v) {
      const int32_t* row = view.hit_of_pixel.data() + size_t(v) * cam.width;
      for (int u = u0; u <= u1 && !found; ++u) found = near_hit(samples[i], row[u]);
    }
    if (found) seen.Set(i);
  }
  return seen;
}

}  // namespace vscan::evaluation
