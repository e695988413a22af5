#include "evaluation/next_best_views.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include <tbb/parallel_for.h>

#include "evaluation/greedy_cover.h"
#include "evaluation/thinned_camera.h"
#include "evaluation/view_hits.h"
#include "raycast/raycast_scene.h"
#include "spatial/kd_tree.h"

namespace vscan::evaluation {
namespace {

// Rays this far apart on a surface facing the sensor leave no point of it farther than tau / 2
// from a hit, and none farther than tau up to about 68 degrees of incidence.
constexpr double kRaySpacingPerTau = 1.0 / std::numbers::sqrt2;

bool IsCancelled(const std::atomic<bool>* cancel) {
  return cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

Status ValidateOptions(const NextBestViewOptions& o) {
  if (o.max_views < 1) return InvalidArgument("next_best_views.max_views", "must be at least 1");
  if (!(o.tau > 0) || !std::isfinite(o.tau)) {
    return InvalidArgument("next_best_views.tau", "must be finite and positive");
  }
  if (!(o.max_incidence_deg > 0 && o.max_incidence_deg <= 90)) {
    return InvalidArgument("next_best_views.max_incidence_deg", "must be in (0, 90]");
  }
  if (o.max_rays_per_view < 1) return InvalidArgument("next_best_views.max_rays_per_view", "must be at least 1");
  if (o.min_gain_samples < 1) return InvalidArgument("next_best_views.min_gain_samples", "must be at least 1");
  if (o.light) {
    RETURN_IF_ERROR(sensor::ValidateEmitter(o.light->emitter, "next_best_views.light.emitter"));
    RETURN_IF_ERROR(sensor::ValidatePixelResponse(o.light->pixel, "next_best_views.light.pixel"));
    RETURN_IF_ERROR(sensor::ValidateMaterial(o.light->material, "next_best_views.light.material"));
  }
  return Status::Ok();
}

Status ValidateInputs(std::span<const Eigen::Vector3f> samples, std::span<const uint8_t> covered,
                      const sensor::PinholeCamera& camera, std::span<const CandidateView> candidates) {
  if (covered.size() != samples.size()) {
    return InvalidArgument("covered", "must have one entry per sample (" + std::to_string(covered.size()) + " for " +
                                          std::to_string(samples.size()) + " samples)");
  }
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].allFinite()) return InvalidArgument("samples[" + std::to_string(i) + "]", "NaN or infinite");
  }
  RETURN_IF_ERROR(sensor::ValidateCamera(camera, "next_best_views.camera", camera.pixel_count()));
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (!candidates[i].frame_from_sensor.matrix().allFinite()) {
      return InvalidArgument("next_best_views.candidates[" + std::to_string(i) + "].frame_from_sensor",
                             "NaN or infinite");
    }
  }
  return Status::Ok();
}

// The samples not covered yet, in an order of their own, with the sphere around their bounds.
struct Missed {
  std::vector<Eigen::Vector3f> points;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  float radius = 0;
};

Missed MissedSamples(std::span<const Eigen::Vector3f> samples, std::span<const uint8_t> covered) {
  Missed missed;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f hi = -lo;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (covered[i] != 0) continue;
    missed.points.push_back(samples[i]);
    lo = lo.cwiseMin(samples[i]);
    hi = hi.cwiseMax(samples[i]);
  }
  if (missed.points.empty()) return missed;
  missed.centre = (lo + hi) / 2;
  missed.radius = (hi - lo).norm() / 2;
  // In the kd-tree's leaf order, neighbours in the list are neighbours in space, so each view
  // reads its hit image in runs.
  const spatial::KdTree tree(missed.points);
  for (uint32_t slot = 0; slot < tree.size(); ++slot) missed.points[slot] = tree.point(slot);
  return missed;
}

// Fine enough that hits are at most tau / sqrt(2) apart on the far side of the missed samples,
// when the ray budget allows; coarser when it does not.
uint32_t ViewStride(const sensor::PinholeCamera& camera, const Pose3& frame_from_sensor, const Missed& missed,
                    const NextBestViewOptions& options) {
  const double to_centre = (frame_from_sensor.translation() - missed.centre.cast<double>()).norm();
  const double farthest = std::clamp(to_centre + missed.radius, camera.near, camera.far);
  return std::max(BudgetStride(camera, options.max_rays_per_view),
                  SpacingStride(camera, kRaySpacingPerTau * options.tau, farthest));
}

}  // namespace

StatusOr<std::vector<ViewPick>> PickNextBestViews(const TriangleMesh& mesh, std::span<const Eigen::Vector3f> samples,
                                                  std::span<const uint8_t> covered,
                                                  const sensor::PinholeCamera& camera,
                                                  std::span<const CandidateView> candidates,
                                                  const NextBestViewOptions& options,
                                                  const std::atomic<bool>* cancel) {
  RETURN_IF_ERROR(ValidateOptions(options));
  RETURN_IF_ERROR(ValidateInputs(samples, covered, camera, candidates));
  const Missed missed = MissedSamples(samples, covered);
  if (missed.points.empty() || candidates.empty() || mesh.empty()) return std::vector<ViewPick>{};

  raycast::SceneInstance instance;
  instance.mesh = std::make_shared<const TriangleMesh>(mesh);
  ASSIGN_OR_RETURN(const auto scene,
                   raycast::RaycastScene::Build(std::span<const raycast::SceneInstance>(&instance, 1)));

  std::vector<SampleBits> seen(candidates.size(), SampleBits(missed.points.size()));
  std::vector<std::optional<Status>> failures(candidates.size());
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t c) {
    if (IsCancelled(cancel)) return;
    const Pose3& pose = candidates[c].frame_from_sensor;
    const sensor::PinholeCamera thin = ThinCamera(camera, ViewStride(camera, pose, missed, options));
    StatusOr<ViewHits> view =
        CastView(*scene, thin, pose, options.max_incidence_deg, cancel, options.light ? &*options.light : nullptr);
    if (!view.ok()) {
      failures[c] = view.status();
      return;
    }
    seen[c] = SamplesNearHits(*view, missed.points, options.tau);
  });
  if (IsCancelled(cancel)) return Cancelled("next best views cancelled");
  for (size_t c = 0; c < candidates.size(); ++c) {
    if (failures[c]) return failures[c]->WithFieldPrefix("next_best_views.candidates[" + std::to_string(c) + "]");
  }

  const size_t already = samples.size() - missed.points.size();
  std::vector<ViewPick> picks;
  size_t gained = 0;
  for (const CoverPick& pick : GreedyMaxCoverage(seen, missed.points.size(), options.max_views,
                                                 options.min_gain_samples)) {
    gained += pick.gain;
    picks.push_back({pick.set, pick.gain, static_cast<double>(already + gained) / static_cast<double>(samples.size())});
  }
  return picks;
}

}  // namespace vscan::evaluation
