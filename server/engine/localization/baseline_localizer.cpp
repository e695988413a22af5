#include "localization/baseline_localizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "localization/boundary_points.h"
#include "localization/hypothesis.h"
#include "localization/oriented_points.h"
#include "localization/part_model.h"
#include "localization/prepared_scan.h"
#include "localization/ppf_voting.h"
#include "localization/scan_view.h"

namespace vscan::localization {
namespace {

// Candidates refined and verified per instance still wanted, best first, in each round.
constexpr size_t kCandidatesPerInstance = 8;
constexpr size_t kMinCandidates = 24;
// A hypothesis with more of its explained scan points than this already taken by an accepted
// instance is that instance again (or a fit onto it).
constexpr double kMaxSharedSurface = 0.3;
// In the ranking of voted candidates, one with a fifth of its facing points seen through drops to
// nothing (hypotheses are ordered with a milder weight: hypothesis.h).
constexpr double kRankSeenThroughWeight = 5;
constexpr double kScanVoxelsPerExtent = 80;
// A part cannot stand in the plate it lies on: a hypothesis with more of its points than this
// behind the support plane is a fit through it.
constexpr double kMaxBelowSupport = 0.05;
// Rounds of voting on the scan points no instance has taken.
constexpr size_t kMaxRounds = 3;

bool Positive(double v) { return std::isfinite(v) && v > 0; }

Status Validate(const LocalizerOptions& o, size_t points, size_t normals) {
  if (normals != 0 && normals != points) {
    return InvalidArgument("scan_normals", "must be empty or one per point, got " + std::to_string(normals) +
                                               " for " + std::to_string(points) + " points");
  }
  if (!(std::isfinite(o.voxel_size) && o.voxel_size >= 0)) {
    return InvalidArgument("localizer.voxel_size", "must be >= 0");
  }
  if (o.model_samples < 1000) return InvalidArgument("localizer.model_samples", "must be >= 1000");
  if (!(Positive(o.ppf_step_voxels) && o.ppf_step_voxels >= 1)) {
    return InvalidArgument("localizer.ppf_step_voxels", "must be >= 1");
  }
  if (!(o.ppf_angle_step_deg >= 1 && o.ppf_angle_step_deg <= 45)) {
    return InvalidArgument("localizer.ppf_angle_step_deg", "must be in [1, 45]");
  }
  if (o.scene_reference_stride < 1) return InvalidArgument("localizer.scene_reference_stride", "must be >= 1");
  if (!Positive(o.plane_distance_voxels)) return InvalidArgument("localizer.plane_distance_voxels", "must be > 0");
  if (!(o.min_plane_share > 0 && o.min_plane_share <= 1)) {
    return InvalidArgument("localizer.min_plane_share", "must be in (0, 1]");
  }
  if (!Positive(o.explained_distance_voxels)) {
    return InvalidArgument("localizer.explained_distance_voxels", "must be > 0");
  }
  if (!(o.max_normal_angle_deg > 0 && o.max_normal_angle_deg <= 180)) {
    return InvalidArgument("localizer.max_normal_angle_deg", "must be in (0, 180]");
  }
  if (!Positive(o.inlier_distance_voxels)) return InvalidArgument("localizer.inlier_distance_voxels", "must be > 0");
  if (!(o.min_score >= 0 && o.min_score <= 1)) return InvalidArgument("localizer.min_score", "must be in [0, 1]");
  if (o.max_instances < 1) return InvalidArgument("localizer.max_instances", "must be >= 1");
  if (!o.viewpoint.allFinite()) return InvalidArgument("localizer.viewpoint", "must be finite");
  if (o.sensor_position && !o.sensor_position->allFinite()) {
    return InvalidArgument("localizer.sensor_position", "must be finite");
  }
  if (o.view_candidates < 1) return InvalidArgument("localizer.view_candidates", "must be >= 1");
  if (!(o.max_seen_through_share >= 0 && o.max_seen_through_share <= 1)) {
    return InvalidArgument("localizer.max_seen_through_share", "must be in [0, 1]");
  }
  return Status::Ok();
}


bool IsCancelled(const std::atomic<bool>* cancel) {
  return cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

// A part's search state over the rounds.
struct PartState {
  size_t max_instances = 0;
  std::unique_ptr<ScanGrid> grid;
  PartSearch summary;
};

// Puts the best-voted candidates in the order of what the sensor saw of them placed as voted (within
// one PPF step: a voted pose is within about one bin of the truth): the points on the scan's
// surface, times the votes, less for points the sensor saw past. Votes alone rank a small part (the
// pin) below hundreds of fits onto clutter.
void RankByView(const ScanView& view, const PartModel& part, size_t count, std::vector<PoseCandidate>& candidates) {
  count = std::min(count, candidates.size());
  std::vector<std::pair<double, size_t>> ranked(count);
  tbb::parallel_for(size_t{0}, count, [&](size_t c) {
    const ScanView::Tally seen = view.Check(part.ppf_points, candidates[c].scene_from_part, part.ppf_step);
    ranked[c] = {static_cast<double>(seen.on_surface) * static_cast<double>(candidates[c].votes) *
                     std::max(0.0, 1 - kRankSeenThroughWeight * seen.SeenThroughShare()),
                 c};
  });
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<PoseCandidate> reordered;
  reordered.reserve(candidates.size());
  for (const auto& [score, c] : ranked) reordered.push_back(candidates[c]);
  for (size_t c = count; c < candidates.size(); ++c) reordered.push_back(candidates[c]);
  candidates = std::move(reordered);
}

// The prepared scan's points no accepted instance has taken, thinned to the part's PPF step.
OrientedPoints Unclaimed(const PreparedScan& scan, const std::vector<bool>& claimed, double step) {
  OrientedPoints left;
  for (size_t i = 0; i < scan.points.points.size(); ++i) {
    if (claimed[i]) continue;
    left.points.push_back(scan.points.points[i]);
    left.normals.push_back(scan.points.normals[i]);
  }
  return ThinOriented(left, step, kFaceSplitAngleRad);
}



}  // namespace

PartModelSettings ModelSettingsOf(const LocalizerOptions& options) {
  PartModelSettings settings;
  settings.voxel_size = options.voxel_size;
  settings.samples = options.model_samples;
  settings.ppf_step_voxels = options.ppf_step_voxels;
  settings.angle_step_rad = options.ppf_angle_step_deg * std::numbers::pi / 180;
  settings.scene_reference_stride = options.scene_reference_stride;
  return settings;
}

StatusOr<LocalizationResult> LocalizeParts(std::span<const PartQuery> parts, std::span<const Eigen::Vector3f> scan_points,
                                           std::span<const Eigen::Vector3f> scan_normals,
                                           const LocalizerOptions& options, const std::atomic<bool>* cancel,
                                           const LocalizeProgressCallback& progress) {
  RETURN_IF_ERROR(Validate(options, scan_points.size(), scan_normals.size()));
  if (parts.empty()) return InvalidArgument("parts", "must name at least one part");
  const PartModelSettings settings = ModelSettingsOf(options);
  std::vector<std::shared_ptr<const PartModel>> models;
  double scan_voxel = std::numeric_limits<double>::infinity(), largest_part = 0;
  for (size_t p = 0; p < parts.size(); ++p) {
    const std::string field = "parts[" + std::to_string(p) + "]";
    if (parts[p].mesh == nullptr) return InvalidArgument(field, "has no mesh");
    std::shared_ptr<const PartModel> model = parts[p].model;
    if (!model) {
      ASSIGN_OR_RETURN(PartModel built, BuildPartModel(*parts[p].mesh, field, settings));
      model = std::make_shared<const PartModel>(std::move(built));
    }
    // The scan is checked at the finest part's voxel, but no finer than its extent / 80: a long
    // thin part's voxel (a share of its width) would multiply the points every check visits.
    scan_voxel = std::min(scan_voxel, options.voxel_size > 0 ? model->voxel
                                                              : std::max(model->voxel, model->extent / kScanVoxelsPerExtent));
    largest_part = std::max(largest_part, model->extent);
    models.push_back(std::move(model));
    if (IsCancelled(cancel)) return Cancelled("localization cancelled");
  }
  const auto report = [&](double fraction, size_t found, const std::string& stage) {
    if (progress) progress(LocalizeProgress{fraction, found, stage});
  };
  ASSIGN_OR_RETURN(const PreparedScan scan, PrepareScan(scan_points, scan_normals, scan_voxel, largest_part, options, cancel));
  if (IsCancelled(cancel)) return Cancelled("localization cancelled");
  report(0.05, 0, "scan prepared");

  LocalizationResult result;
  result.support_plane_points = scan.support_plane_points;
  std::vector<PartState> states(models.size());
  for (size_t p = 0; p < models.size(); ++p) {
    states[p].max_instances = parts[p].max_instances > 0 ? parts[p].max_instances : options.max_instances;
    states[p].grid = std::make_unique<ScanGrid>(scan.points.points, kIcpReachInPpfSteps * models[p]->ppf_step);
    states[p].summary.voxel_size = models[p]->voxel;
  }
  std::vector<bool> claimed(scan.points.points.size(), false);
  const double steps = static_cast<double>(kMaxRounds * models.size());
  for (size_t round = 0; round < kMaxRounds; ++round) {
    std::vector<Hypothesis> hypotheses;
    for (size_t p = 0; p < models.size(); ++p) {
      PartState& state = states[p];
      const PartModel& part = *models[p];
      if (state.summary.found >= state.max_instances || !state.summary.stop_reason.empty()) continue;
      const OrientedPoints scene = Unclaimed(scan, claimed, part.ppf_step);
      if (scene.points.size() < 10) {
        state.summary.stop_reason = "too few scan points left";
        continue;
      }
      const std::vector<Eigen::Vector3f> rims = RimDirections(scene, kRimRadiusInPpfSteps * part.ppf_step);
      std::vector<PoseCandidate> candidates = part.ppf->Vote(scene.points, scene.normals, rims, cancel);
      if (IsCancelled(cancel)) return Cancelled("localization cancelled");
      if (candidates.empty()) {
        state.summary.stop_reason = "no pose candidates";
        continue;
      }
      if (scan.view) RankByView(*scan.view, part, options.view_candidates, candidates);
      const size_t wanted = state.max_instances - state.summary.found;
      const size_t tried = std::min(candidates.size(), std::max(kMinCandidates, kCandidatesPerInstance * wanted));
      std::vector<StatusOr<Hypothesis>> verified(tried, Hypothesis{});
      const Verifier verifier(part, *state.grid, scan, options);
      tbb::parallel_for(size_t{0}, tried, [&](size_t c) {
        if (IsCancelled(cancel)) return;
        verified[c] = verifier.Verify(candidates[c].scene_from_part);
      });
      if (IsCancelled(cancel)) return Cancelled("localization cancelled");
      for (auto& h : verified) {
        if (!h.ok()) return h.status();
        h->part = p;
        hypotheses.push_back(std::move(*h));
      }
      report(0.05 + 0.9 * static_cast<double>(round * models.size() + p + 1) / steps, result.instances.size(),
             "round " + std::to_string(round + 1) + ": part " + std::to_string(p) + " voted and verified");
    }
    if (hypotheses.empty()) break;
    // Best first across every part: an instance takes its scan points, and a later hypothesis that
    // explains mostly taken points is a repeat or a fit onto another part.
    std::stable_sort(hypotheses.begin(), hypotheses.end(),
                     [](const Hypothesis& a, const Hypothesis& b) { return a.Quality() > b.Quality(); });
    size_t accepted = 0;
    std::vector<std::string> rejected(models.size());
    for (const Hypothesis& h : hypotheses) {
      PartState& state = states[h.part];
      if (state.summary.found >= state.max_instances) continue;
      std::string why;
      if (h.below_support > kMaxBelowSupport) {
        why = "the best candidate lies " + std::to_string(static_cast<int>(100 * h.below_support)) +
              "% inside the plane the parts stand on";
      } else if (h.view.SeenThroughShare() > options.max_seen_through_share) {
        why = "the best candidate lies where the sensor saw past " + std::to_string(h.view.seen_through) + " of its " +
              std::to_string(h.view.on_surface + h.view.seen_through) + " points facing it";
      } else if (h.explained.size() < options.min_explained_points || h.score < options.min_score) {
        why = "the best candidate explains " + std::to_string(h.explained.size()) + " points with score " +
              std::to_string(h.score);
      } else {
        size_t taken = 0;
        for (const uint32_t i : h.explained) taken += claimed[i] ? 1 : 0;
        if (static_cast<double>(taken) > kMaxSharedSurface * static_cast<double>(h.explained.size())) continue;
      }
      if (!why.empty()) {
        if (rejected[h.part].empty()) rejected[h.part] = why;
        continue;
      }
      for (const uint32_t i : h.explained) claimed[i] = true;
      result.instances.push_back({h.part, h.pose, h.score, h.explained.size()});
      ++state.summary.found;
      ++accepted;
    }
    for (size_t p = 0; p < models.size(); ++p) {
      PartSearch& summary = states[p].summary;
      if (summary.found >= states[p].max_instances && summary.stop_reason.empty()) {
        summary.stop_reason = "max_instances reached";
      }
    }
    if (accepted == 0) {
      for (size_t p = 0; p < models.size(); ++p) {
        if (states[p].summary.stop_reason.empty()) {
          states[p].summary.stop_reason = rejected[p].empty() ? "every candidate repeats a found instance" : rejected[p];
        }
      }
      break;
    }
  }
  for (PartState& state : states) {
    if (state.summary.stop_reason.empty()) state.summary.stop_reason = "search rounds exhausted";
    result.parts.push_back(std::move(state.summary));
  }
  report(1.0, result.instances.size(), "done");
  return result;
}

StatusOr<LocalizationResult> LocalizeInstances(const TriangleMesh& part, std::span<const Eigen::Vector3f> scan_points,
                                               std::span<const Eigen::Vector3f> scan_normals,
                                               const LocalizerOptions& options, const std::atomic<bool>* cancel) {
  const PartQuery query{&part, options.max_instances};
  return LocalizeParts(std::span<const PartQuery>(&query, 1), scan_points, scan_normals, options, cancel);
}

StatusOr<LocalizationResult> LocalizeInstances(const TriangleMesh& part, const PointCloud& scan,
                                               const LocalizerOptions& options, const std::atomic<bool>* cancel) {
  const std::span<const Eigen::Vector3f> normals =
      scan.Has(kFieldNormal) ? std::span<const Eigen::Vector3f>(scan.normals) : std::span<const Eigen::Vector3f>();
  return LocalizeInstances(part, scan.positions, normals, options, cancel);
}

}  // namespace vscan::localization

