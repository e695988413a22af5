#include "localization/baseline_localizer.h"

#include <algorithm>
#include <array>
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
#include "localization/large_planes.h"
#include "localization/oriented_points.h"
#include "localization/part_model.h"
#include "localization/ppf_voting.h"
#include "localization/scan_grid.h"
#include "localization/scan_view.h"
#include "localization/support_plane.h"
#include "normals/normal_estimation.h"
#include "registration/point_to_plane_icp.h"
#include "spatial/kd_tree.h"

namespace vscan::localization {
namespace {

// A voted pose is within about one bin of the truth; ICP pairs points up to two bins apart.
constexpr double kIcpReachInPpfSteps = 2;
constexpr uint64_t kPlaneSeed = 1;
// Candidates refined and verified per instance still wanted, best first, in each round.
constexpr size_t kCandidatesPerInstance = 8;
constexpr size_t kMinCandidates = 24;
// A hypothesis with more of its explained scan points than this already taken by an accepted
// instance is that instance again (or a fit onto it).
constexpr double kMaxSharedSurface = 0.3;
// In the ranking of voted candidates, one with a fifth of its facing points seen through drops to
// nothing; refined hypotheses are ordered with a milder weight (half seen through: nothing), as
// true instances of shiny parts have a share of their facing points where the scan saw deeper.
constexpr double kRankSeenThroughWeight = 5;
constexpr double kSeenThroughWeight = 2;
// Planar pieces wider than this many times the largest part are bin walls, rims or tables; their
// points are connected when within kLinkVoxels voxels; planes with fewer points are not looked for.
constexpr double kLargePlaneExtent = 1.5;
constexpr double kLinkVoxels = 3;
constexpr size_t kMinLargePlanePoints = 500;
constexpr double kScanVoxelsPerExtent = 80;
// The most scan points a candidate's ICP runs on.
constexpr size_t kMaxIcpPoints = 2000;
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

// The scan with a unit normal per point facing the sensor: its own, or estimated and turned
// towards the viewpoint (points without a normal are dropped).
StatusOr<OrientedPoints> WithNormals(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                                     double voxel, const LocalizerOptions& options,
                                     const std::atomic<bool>* cancel) {
  OrientedPoints scan;
  if (!normals.empty()) {
    for (size_t i = 0; i < points.size(); ++i) {
      if (!points[i].allFinite() || !normals[i].allFinite()) continue;
      scan.points.push_back(points[i]);
      scan.normals.push_back(normals[i].normalized());
    }
    return scan;
  }
  normals::NormalOptions normal_options;
  normal_options.max_distance = static_cast<float>(3 * voxel);
  normal_options.viewpoint = options.viewpoint.cast<float>();
  normal_options.cancel = cancel;
  ASSIGN_OR_RETURN(const std::vector<Eigen::Vector3f> estimated, normals::EstimateNormals(points, normal_options));
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite() || !estimated[i].allFinite()) continue;
    scan.points.push_back(points[i]);
    scan.normals.push_back(estimated[i]);
  }
  return scan;
}

// Marks the points near the part placed by world_from_part and, with max_normal_cos > -1, facing

// The scan as every part's search sees it: thinned to the finest part's voxel, the plate removed,
// and what the sensor saw.
struct PreparedScan {
  OrientedPoints points;
  std::optional<ScanView> view;
  size_t support_plane_points = 0;
  // The plane the parts stand on, its normal turned to the side most of the other points are on.
  std::optional<Plane> support;
};

StatusOr<PreparedScan> PrepareScan(std::span<const Eigen::Vector3f> scan_points, std::span<const Eigen::Vector3f> scan_normals,
                                   double voxel, double largest_part, const LocalizerOptions& options,
                                   const std::atomic<bool>* cancel) {
  PreparedScan prepared;
  ASSIGN_OR_RETURN(const OrientedPoints scan, WithNormals(scan_points, scan_normals, voxel, options, cancel));
  if (options.sensor_position) prepared.view.emplace(scan.points, *options.sensor_position, voxel);
  OrientedPoints thin = ThinOriented(scan, voxel, kFaceSplitAngleRad);
  if (options.remove_support_plane) {
    const double distance = options.plane_distance_voxels * voxel;
    if (auto plane = FindDominantPlane(thin.points, distance, options.min_plane_share, kPlaneSeed)) {
      OrientedPoints kept;
      for (size_t i = 0; i < thin.points.size(); ++i) {
        if (plane->Distance(thin.points[i]) <= distance) continue;
        kept.points.push_back(thin.points[i]);
        kept.normals.push_back(thin.normals[i]);
      }
      for (const auto& p : scan.points) prepared.support_plane_points += plane->Distance(p) <= distance ? 1 : 0;
      size_t above = 0;
      for (const auto& p : kept.points) above += plane->normal.dot(p.cast<double>()) + plane->offset > 0 ? 1 : 0;
      if (2 * above < kept.points.size()) plane->normal = -plane->normal, plane->offset = -plane->offset;
      prepared.support = plane;
      thin = std::move(kept);
    }
    LargePlaneSettings large;
    large.distance = distance;
    large.link = kLinkVoxels * voxel;
    large.min_extent = kLargePlaneExtent * largest_part;
    large.min_points = kMinLargePlanePoints;
    large.seed = kPlaneSeed;
    const std::vector<bool> on_large = MarkLargePlanes(thin, large);
    OrientedPoints kept;
    for (size_t i = 0; i < thin.points.size(); ++i) {
      if (on_large[i]) continue;
      kept.points.push_back(thin.points[i]);
      kept.normals.push_back(thin.normals[i]);
    }
    thin = std::move(kept);
  }
  prepared.points = std::move(thin);
  return prepared;
}

// One part placed somewhere, refined and checked against the scan.
struct Hypothesis {
  size_t part = 0;
  Pose3 pose = Pose3::Identity();
  double score = 0;
  ScanView::Tally view;
  double below_support = 0;  // share of its points inside what the parts stand on
  std::vector<uint32_t> explained;  // prepared scan points it accounts for
  double Quality() const { return score * std::max(0.0, 1 - kSeenThroughWeight * view.SeenThroughShare()); }
};

// A part's search state over the rounds.
struct PartState {
  const PartModel* model = nullptr;
  size_t max_instances = 0;
  std::unique_ptr<ScanGrid> grid;
  PartSearch summary;
};

// Checks candidate poses of one part against the prepared scan.
class Verifier {
 public:
  Verifier(const PartModel& part, const ScanGrid& grid, const PreparedScan& scan, const LocalizerOptions& options)
      : part_(part), grid_(grid), scan_(scan), options_(options),
        min_cos_(std::cos(options.max_normal_angle_deg * std::numbers::pi / 180)) {}

  StatusOr<Hypothesis> Verify(const Pose3& voted) const {
    const double wide = kIcpReachInPpfSteps * part_.ppf_step;
    const double tight = options_.explained_distance_voxels * part_.voxel;
    ASSIGN_OR_RETURN(const Pose3 coarse, Refine(voted, wide));
    ASSIGN_OR_RETURN(const Pose3 refined, Refine(coarse, tight));
    Hypothesis h;
    h.pose = refined;
    h.explained = Near(refined, tight, min_cos_);
    h.score = ExplainedShare(refined, h.explained);
    if (scan_.view) h.view = scan_.view->Check(part_.model, refined, tight);
    if (scan_.support) h.below_support = BelowSupport(refined, tight);
    return h;
  }

 private:
  // The prepared scan points within reach of the placed part's surface (and, with min_cos > -1,
  // facing as it does there).
  std::vector<uint32_t> Near(const Pose3& world_from_part, double reach, double min_cos) const {
    std::vector<Eigen::Vector3f> placed(part_.ppf_points.points.size());
    for (size_t i = 0; i < placed.size(); ++i) {
      placed[i] = (world_from_part * part_.ppf_points.points[i].cast<double>()).cast<float>();
    }
    std::vector<uint32_t> gathered;
    grid_.Gather(placed, gathered);
    const Eigen::Isometry3f part_from_world = world_from_part.inverse().cast<float>();
    const auto max_sq = static_cast<float>(reach * reach);
    std::array<spatial::Neighbor, 1> nearest{};
    std::vector<uint32_t> near;
    const Eigen::AlignedBox3f reach_box(part_.bounds.min().array() - static_cast<float>(reach),
                                        part_.bounds.max().array() + static_cast<float>(reach));
    for (const uint32_t i : gathered) {
      const Eigen::Vector3f local = part_from_world * scan_.points.points[i];
      if (!reach_box.contains(local) || part_.model_tree->Knn(local, max_sq, nearest) == 0) continue;
      if (min_cos > -1) {
        const Eigen::Vector3f& normal = part_.model.normals[part_.model_tree->original_index(nearest[0].slot)];
        if (normal.dot(part_from_world.linear() * scan_.points.normals[i]) < min_cos) continue;
      }
      near.push_back(i);
    }
    std::sort(near.begin(), near.end());
    return near;
  }

  // The share of the part's points, placed, farther than depth behind the support plane.
  double BelowSupport(const Pose3& world_from_part, double depth) const {
    size_t below = 0;
    for (const auto& p : part_.model.points) {
      const Eigen::Vector3d world = world_from_part * p.cast<double>();
      below += scan_.support->normal.dot(world) + scan_.support->offset < -depth ? 1 : 0;
    }
    return static_cast<double>(below) / static_cast<double>(std::max<size_t>(1, part_.model.points.size()));
  }

  // Point-to-plane ICP of the scan points within reach of the part placed at start onto the part's
  // surface. A degenerate stop keeps the pose reached so far: the directions the view leaves free
  // (a face seen alone can slide within itself) stay as voted, the others are refined.
  StatusOr<Pose3> Refine(const Pose3& start, double reach) const {
    const std::vector<uint32_t> near = Near(start, reach, -1);
    registration::IcpOptions icp;
    icp.max_correspondence_distance = reach;
    // A hundredth of a millimetre and a tenth of a milliradian are finer than any check after it.
    icp.translation_tolerance = 1e-5;
    icp.rotation_tolerance = 1e-4;
    icp.max_iterations = 30;
    if (near.size() < icp.min_correspondences) return start;
    // An even share of the points is enough to pull a pose within reach onto the surface.
    const size_t stride = (near.size() + kMaxIcpPoints - 1) / kMaxIcpPoints;
    std::vector<Eigen::Vector3f> points, normals;
    points.reserve(near.size() / stride + 1);
    normals.reserve(near.size() / stride + 1);
    for (size_t k = 0; k < near.size(); k += stride) {
      points.push_back(scan_.points.points[near[k]]);
      normals.push_back(scan_.points.normals[near[k]]);
    }
    ASSIGN_OR_RETURN(const registration::IcpResult fit,
                     registration::PointToPlaneIcp(points, *part_.icp_target, start.inverse(), icp, normals));
    return fit.stop == registration::IcpStop::kTooFewCorrespondences ? start : fit.target_from_source.inverse();
  }

  // The share of the part's points, placed, with an explained scan point within the inlier
  // distance whose normal is within max_normal_angle_deg of the part's there.
  double ExplainedShare(const Pose3& world_from_part, const std::vector<uint32_t>& explained) const {
    if (explained.empty()) return 0;
    const Eigen::Isometry3f part_from_world = world_from_part.inverse().cast<float>();
    std::vector<Eigen::Vector3f> local(explained.size());
    for (size_t k = 0; k < explained.size(); ++k) local[k] = part_from_world * scan_.points.points[explained[k]];
    const spatial::KdTree tree(local);
    const double distance = options_.inlier_distance_voxels * part_.voxel;
    const auto max_sq = static_cast<float>(distance * distance);
    std::array<spatial::Neighbor, 1> nearest{};
    size_t inliers = 0;
    for (size_t i = 0; i < part_.model.points.size(); ++i) {
      if (tree.Knn(part_.model.points[i], max_sq, nearest) == 0) continue;
      const Eigen::Vector3f normal =
          part_from_world.linear() * scan_.points.normals[explained[tree.original_index(nearest[0].slot)]];
      if (part_.model.normals[i].dot(normal) >= min_cos_) ++inliers;
    }
    return static_cast<double>(inliers) / static_cast<double>(part_.model.points.size());
  }

  const PartModel& part_;
  const ScanGrid& grid_;
  const PreparedScan& scan_;
  const LocalizerOptions& options_;
  double min_cos_;
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
    states[p].model = models[p].get();
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

