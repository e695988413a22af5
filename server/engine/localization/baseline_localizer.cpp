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

#include "localization/model_samples.h"
#include "localization/ppf_voting.h"
#include "localization/support_plane.h"
#include "normals/normal_estimation.h"
#include "registration/point_to_plane_icp.h"
#include "registration/voxel_thinning.h"
#include "spatial/kd_tree.h"

namespace vscan::localization {
namespace {

// The most part points the point-pair table is built over (it holds every ordered pair).
constexpr size_t kMaxPpfModelPoints = 3000;
// Fewer remaining scan points than this cannot hold another instance worth a search.
constexpr size_t kMinSearchPoints = 100;
// Parts are compared at this many voxels across their bounding box's diagonal by default.
constexpr double kVoxelsPerDiagonal = 50;
// ... and at least this many across its middle extent, so that a long thin part (a rod) is not
// reduced to a line.
constexpr double kVoxelsPerMiddleExtent = 10;
// A voted pose is within about one bin of the truth; ICP pairs points up to two bins apart.
constexpr double kIcpReachInPpfSteps = 2;
// Votes for poses within this many PPF steps and angle steps are pooled.
constexpr double kClusterDistanceInSteps = 2;
constexpr double kClusterAngleInSteps = 2.5;
constexpr uint64_t kSeed = 1;
// Candidates refined and checked per search, best-voted first, before the search gives up.
constexpr size_t kCandidatesTried = 5;
// A candidate with more of its surface than this on a found instance's is that instance again.
constexpr double kMaxSharedSurface = 0.3;
// A part's point faces the sensor when its normal is within about 72 degrees of the ray back.
constexpr double kMinFacingCos = 0.3;
// In the view ranking, a candidate with a fifth of its facing points seen through drops to nothing.
constexpr double kSeenThroughWeight = 5;
// Searches that only clear leftovers of found instances are bounded by this many per instance.
constexpr size_t kSearchesPerInstance = 3;

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

struct OrientedPoints {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;
};

// The voxel centroids, each with the normal of its nearest original point.
OrientedPoints Thin(const OrientedPoints& cloud, double voxel) {
  OrientedPoints thin;
  thin.points = registration::ThinToVoxelCentroids(cloud.points, voxel);
  const spatial::KdTree tree(cloud.points);
  std::array<spatial::Neighbor, 1> nearest{};
  thin.normals.reserve(thin.points.size());
  for (const auto& p : thin.points) {
    tree.Knn(p, std::numeric_limits<float>::infinity(), nearest);
    thin.normals.push_back(cloud.normals[tree.original_index(nearest[0].slot)]);
  }
  return thin;
}

// Keeps the points (and their normals) not marked.
void RemoveMarked(const std::vector<bool>& marked, OrientedPoints& cloud) {
  size_t kept = 0;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    if (marked[i]) continue;
    cloud.points[kept] = cloud.points[i];
    cloud.normals[kept] = cloud.normals[i];
    ++kept;
  }
  cloud.points.resize(kept);
  cloud.normals.resize(kept);
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
// the same way as its surface there.
std::vector<bool> NearPart(const OrientedPoints& model, const Pose3& world_from_part, const OrientedPoints& scan,
                           double distance, double min_cos) {
  std::vector<Eigen::Vector3f> placed(model.points.size());
  for (size_t i = 0; i < placed.size(); ++i) {
    placed[i] = (world_from_part * model.points[i].cast<double>()).cast<float>();
  }
  const spatial::KdTree tree(placed);
  const Eigen::Matrix3f rotation = world_from_part.linear().cast<float>();
  const auto max_sq = static_cast<float>(distance * distance);
  std::array<spatial::Neighbor, 1> nearest{};
  std::vector<bool> near(scan.points.size(), false);
  for (size_t i = 0; i < scan.points.size(); ++i) {
    if (tree.Knn(scan.points[i], max_sq, nearest) == 0) continue;
    const Eigen::Vector3f part_normal = rotation * model.normals[tree.original_index(nearest[0].slot)];
    near[i] = part_normal.dot(scan.normals[i]) >= min_cos;
  }
  return near;
}

// The share of the part's samples, placed, with a point of `cloud` within distance.
double InlierShare(const OrientedPoints& model, const Pose3& pose, const spatial::KdTree& cloud, double distance) {
  const auto max_sq = static_cast<float>(distance * distance);
  std::array<spatial::Neighbor, 1> nearest{};
  size_t inliers = 0;
  for (const auto& p : model.points) {
    if (cloud.Knn((pose * p.cast<double>()).cast<float>(), max_sq, nearest) == 1) ++inliers;
  }
  return static_cast<double>(inliers) / static_cast<double>(model.points.size());
}

// The share of the part's samples, placed, with a scan point within distance whose normal is
// within acos(min_cos) of the part's there: the verification score.
double ExplainedShare(const OrientedPoints& model, const Pose3& pose, const OrientedPoints& scan,
                      const spatial::KdTree& scan_tree, double distance, double min_cos) {
  const auto max_sq = static_cast<float>(distance * distance);
  const Eigen::Matrix3f rotation = pose.linear().cast<float>();
  std::array<spatial::Neighbor, 1> nearest{};
  size_t inliers = 0;
  for (size_t i = 0; i < model.points.size(); ++i) {
    if (scan_tree.Knn((pose * model.points[i].cast<double>()).cast<float>(), max_sq, nearest) == 0) continue;
    const Eigen::Vector3f& scan_normal = scan.normals[scan_tree.original_index(nearest[0].slot)];
    if ((rotation * model.normals[i]).dot(scan_normal) >= min_cos) ++inliers;
  }
  return static_cast<double>(inliers) / static_cast<double>(model.points.size());
}

// What the sensor saw: per cell of a grid over the plane perpendicular to the view direction (at
// unit depth), the nearest depth of a scan point in it.
class DepthGrid {
 public:
  DepthGrid(std::span<const Eigen::Vector3f> points, const Eigen::Vector3d& sensor, double cell_at_depth) : sensor_(sensor) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : points) mean += p.cast<double>();
    if (points.empty() || (mean / static_cast<double>(points.size()) - sensor).norm() <= 0) return;
    axis_z_ = (mean / static_cast<double>(points.size()) - sensor).normalized();
    axis_x_ = axis_z_.unitOrthogonal();
    axis_y_ = axis_z_.cross(axis_x_);
    double median_depth = 0;
    std::vector<double> depths;
    double lo_u = 1e9, lo_v = 1e9, hi_u = -1e9, hi_v = -1e9;
    for (const auto& p : points) {
      const Eigen::Vector3d d = p.cast<double>() - sensor;
      const double z = d.dot(axis_z_);
      if (z <= 0) continue;
      depths.push_back(z);
      lo_u = std::min(lo_u, d.dot(axis_x_) / z), hi_u = std::max(hi_u, d.dot(axis_x_) / z);
      lo_v = std::min(lo_v, d.dot(axis_y_) / z), hi_v = std::max(hi_v, d.dot(axis_y_) / z);
    }
    if (depths.empty()) return;
    std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2), depths.end());
    median_depth = depths[depths.size() / 2];
    cell_ = cell_at_depth / median_depth;
    // A bounded grid: a wide field of view coarsens the cell rather than growing without limit.
    constexpr double kMaxCells = 4e6;
    while ((hi_u - lo_u) / cell_ * (hi_v - lo_v) / cell_ > kMaxCells) cell_ *= 1.5;
    lo_u_ = lo_u, lo_v_ = lo_v;
    width_ = static_cast<size_t>((hi_u - lo_u) / cell_) + 1;
    height_ = static_cast<size_t>((hi_v - lo_v) / cell_) + 1;
    depth_.assign(width_ * height_, std::numeric_limits<float>::infinity());
    for (const auto& p : points) {
      const Eigen::Vector3d d = p.cast<double>() - sensor;
      const double z = d.dot(axis_z_);
      if (z <= 0) continue;
      const auto cell = Cell(d, z);
      if (cell) depth_[*cell] = std::min(depth_[*cell], static_cast<float>(z));
    }
  }

  struct Tally {
    size_t on_surface = 0;    // facing the sensor, on the scan's surface
    size_t seen_through = 0;  // facing the sensor, in front of what it saw there
  };

  // The part's points (model, placed by pose) facing the sensor: on the scan's surface (depth within
  // tolerance), seen through (the sensor saw further), or hidden or unseen (neither).
  Tally Check(const OrientedPoints& model, const Pose3& pose, double tolerance) const {
    Tally tally;
    if (depth_.empty()) return tally;
    for (size_t i = 0; i < model.points.size(); ++i) {
      const Eigen::Vector3d p = pose * model.points[i].cast<double>();
      const Eigen::Vector3d d = p - sensor_;
      // Points seen at a grazing angle are left out: their depth changes fastest across a cell.
      if ((pose.linear() * model.normals[i].cast<double>()).dot(d) > -kMinFacingCos * d.norm()) continue;
      const double z = d.dot(axis_z_);
      if (z <= 0) continue;
      const auto cell = Cell(d, z);
      if (!cell || !std::isfinite(depth_[*cell])) continue;
      const double seen = depth_[*cell];
      if (std::abs(seen - z) <= tolerance) {
        ++tally.on_surface;
      } else if (seen > z + tolerance) {
        ++tally.seen_through;
      }
    }
    return tally;
  }

 private:
  std::optional<size_t> Cell(const Eigen::Vector3d& d, double z) const {
    const double u = (d.dot(axis_x_) / z - lo_u_) / cell_, v = (d.dot(axis_y_) / z - lo_v_) / cell_;
    if (!(u >= 0 && v >= 0 && u < static_cast<double>(width_) && v < static_cast<double>(height_))) return std::nullopt;
    return static_cast<size_t>(v) * width_ + static_cast<size_t>(u);
  }

  Eigen::Vector3d sensor_, axis_x_ = Eigen::Vector3d::UnitX(), axis_y_ = Eigen::Vector3d::UnitY(),
                           axis_z_ = Eigen::Vector3d::UnitZ();
  double cell_ = 1, lo_u_ = 0, lo_v_ = 0;
  size_t width_ = 0, height_ = 0;
  std::vector<float> depth_;
};

// Point-to-plane ICP of the scan points within reach of the part placed at `start` onto the part's
// surface.
StatusOr<Pose3> Refine(const OrientedPoints& model, const OrientedPoints& scan, const Pose3& start, double reach) {
  const std::vector<bool> near = NearPart(model, start, scan, reach, -1);
  OrientedPoints source;
  for (size_t i = 0; i < near.size(); ++i) {
    if (!near[i]) continue;
    source.points.push_back(scan.points[i]);
    source.normals.push_back(scan.normals[i]);
  }
  registration::IcpOptions icp;
  icp.max_correspondence_distance = reach;
  if (source.points.size() < icp.min_correspondences) return start;
  ASSIGN_OR_RETURN(const registration::IcpResult fit,
                   registration::PointToPlaneIcp(source.points, model.points, model.normals, start.inverse(), icp,
                                                 source.normals));
  // A degenerate stop keeps the pose reached so far: the directions the view leaves free (a face
  // seen alone can slide within itself) stay as voted, the others are refined.
  return fit.stop == registration::IcpStop::kTooFewCorrespondences ? start : fit.target_from_source.inverse();
}

// Puts the best-voted candidates in the order of what the sensor saw of them placed as voted (within
// one PPF step: a voted pose is within about one bin of the truth): the points on the scan's
// surface, times the votes, less for points the sensor saw past. Votes alone
// rank a small part (the pin) below hundreds of fits onto clutter.
void RankByView(const DepthGrid& seen, const OrientedPoints& model, double ppf_step, size_t count,
                std::vector<PoseCandidate>& candidates) {
  count = std::min(count, candidates.size());
  std::vector<std::pair<double, size_t>> ranked(count);
  for (size_t c = 0; c < count; ++c) {
    const DepthGrid::Tally view = seen.Check(model, candidates[c].scene_from_part, ppf_step);
    const double through = static_cast<double>(view.seen_through) /
                           static_cast<double>(std::max<size_t>(1, view.on_surface + view.seen_through));
    ranked[c] = {static_cast<double>(view.on_surface) * static_cast<double>(candidates[c].votes) *
                     std::max(0.0, 1 - kSeenThroughWeight * through),
                 c};
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<PoseCandidate> reordered;
  reordered.reserve(candidates.size());
  for (const auto& [score, c] : ranked) reordered.push_back(candidates[c]);
  for (size_t c = count; c < candidates.size(); ++c) reordered.push_back(candidates[c]);
  candidates = std::move(reordered);
}

// A wide pass from the voted pose, then a tight one that leaves out the scan points of neighbours
// the wide pass may have drawn in.
StatusOr<Pose3> RefineVoted(const OrientedPoints& model, const OrientedPoints& scan, const Pose3& voted,
                            double wide_reach, double tight_reach) {
  ASSIGN_OR_RETURN(const Pose3 coarse, Refine(model, scan, voted, wide_reach));
  return Refine(model, scan, coarse, tight_reach);
}

// The surface of the instances accepted so far, for telling a new candidate from one of them.
class AcceptedSurface {
 public:
  void Add(const OrientedPoints& model, const Pose3& world_from_part) {
    for (const auto& p : model.points) points_.push_back((world_from_part * p.cast<double>()).cast<float>());
    tree_ = std::make_unique<spatial::KdTree>(points_);
  }

  // The share of the model's points, placed, within distance of an accepted instance's surface.
  double SharedShare(const OrientedPoints& model, const Pose3& world_from_part, double distance) const {
    if (!tree_) return 0;
    return InlierShare(model, world_from_part, *tree_, distance);
  }

 private:
  std::vector<Eigen::Vector3f> points_;
  std::unique_ptr<spatial::KdTree> tree_;
};

double DefaultVoxel(const TriangleMesh& part) {
  Eigen::Vector3f lo, hi;
  part.Bounds(lo, hi);
  Eigen::Vector3f extents = hi - lo;
  std::sort(extents.data(), extents.data() + 3);
  return std::min(static_cast<double>(extents.norm()) / kVoxelsPerDiagonal,
                  static_cast<double>(extents[1]) / kVoxelsPerMiddleExtent);
}

// A part as the search uses it: its samples at three densities and its pair table.
struct PartModel {
  OrientedPoints samples;     // all of them
  OrientedPoints model;       // thinned to the voxel
  OrientedPoints ppf_points;  // thinned to the PPF step
  double voxel = 0, ppf_step = 0;
  std::unique_ptr<PpfModel> ppf;
  size_t max_instances = 0;
};

StatusOr<PartModel> BuildPartModel(const TriangleMesh& part, const std::string& field, const LocalizerOptions& options) {
  const ModelSamples samples = SampleModel(part, options.model_samples, kSeed);
  if (samples.points.empty()) return InvalidArgument(field, "has no surface");
  PartModel m;
  m.voxel = options.voxel_size > 0 ? options.voxel_size : DefaultVoxel(part);
  m.ppf_step = options.ppf_step_voxels * m.voxel;
  m.samples = {samples.points, samples.normals};
  m.model = Thin(m.samples, m.voxel);
  m.ppf_points = Thin(m.samples, m.ppf_step);
  // The pair table grows with the square of these points: 3000 make 9 million pairs (144 MiB). A
  // voxel of the localizer's own choosing (a long thin part's) coarsens the table's step to fit.
  while (options.voxel_size == 0 && m.ppf_points.points.size() > kMaxPpfModelPoints) {
    m.ppf_step *= 1.05 * std::sqrt(static_cast<double>(m.ppf_points.points.size()) / kMaxPpfModelPoints);
    m.ppf_points = Thin(m.samples, m.ppf_step);
  }
  if (m.ppf_points.points.size() > kMaxPpfModelPoints) {
    return ResourceExhausted("options.voxel_size",
                             "a voxel of " + std::to_string(m.voxel * 1e3) + " mm leaves " +
                                 std::to_string(m.ppf_points.points.size()) +
                                 " points on the part for its pair table, more than the " +
                                 std::to_string(kMaxPpfModelPoints) +
                                 " it may hold; use a larger voxel (0 picks one from the part's size)");
  }
  PpfSettings settings;
  settings.distance_step = m.ppf_step;
  settings.angle_step_rad = options.ppf_angle_step_deg * std::numbers::pi / 180;
  settings.scene_reference_stride = options.scene_reference_stride;
  settings.cluster_distance = kClusterDistanceInSteps * m.ppf_step;
  settings.cluster_angle_rad = kClusterAngleInSteps * settings.angle_step_rad;
  m.ppf = std::make_unique<PpfModel>(m.ppf_points.points, m.ppf_points.normals, settings);
  return m;
}

// The scan as every part's search sees it: normals, what the sensor saw, the plate removed.
struct PreparedScan {
  OrientedPoints parts;  // the plate's points removed
  std::optional<DepthGrid> seen;
  size_t support_plane_points = 0;
};

StatusOr<PreparedScan> PrepareScan(std::span<const Eigen::Vector3f> scan_points, std::span<const Eigen::Vector3f> scan_normals,
                                   double voxel, const LocalizerOptions& options, const std::atomic<bool>* cancel) {
  PreparedScan prepared;
  ASSIGN_OR_RETURN(OrientedPoints scan, WithNormals(scan_points, scan_normals, voxel, options, cancel));
  if (options.sensor_position) prepared.seen.emplace(scan.points, *options.sensor_position, voxel);
  if (options.remove_support_plane) {
    const double distance = options.plane_distance_voxels * voxel;
    if (auto plane = FindDominantPlane(scan.points, distance, options.min_plane_share, kSeed)) {
      std::vector<bool> on_plane(scan.points.size());
      for (size_t i = 0; i < scan.points.size(); ++i) on_plane[i] = plane->Distance(scan.points[i]) <= distance;
      RemoveMarked(on_plane, scan);
      prepared.support_plane_points = plane->inliers;
    }
  }
  prepared.parts = std::move(scan);
  return prepared;
}

// One part's instances, one search after another; appends them to instances (tagged part_index).
StatusOr<PartSearch> SearchPart(const PartModel& part, size_t part_index, const PreparedScan& prepared,
                                const LocalizerOptions& options, const std::atomic<bool>* cancel,
                                std::vector<LocalizedInstance>& instances) {
  PartSearch outcome;
  outcome.voxel_size = part.voxel;
  const double voxel = part.voxel, ppf_step = part.ppf_step;
  const OrientedPoints& all_samples = part.samples;
  const OrientedPoints& model = part.model;
  const OrientedPoints& ppf_model_points = part.ppf_points;
  const PpfModel& ppf = *part.ppf;
  const std::optional<DepthGrid>& seen = prepared.seen;
  OrientedPoints scan = prepared.parts;
  const OrientedPoints& parts_scan = prepared.parts;
  const spatial::KdTree parts_tree(parts_scan.points);
  const double min_cos = std::cos(options.max_normal_angle_deg * std::numbers::pi / 180);
  const double explained_distance = options.explained_distance_voxels * voxel;
  AcceptedSurface accepted_surface;
  for (size_t search = 0;; ++search) {
    if (IsCancelled(cancel)) return Cancelled("localization cancelled");
    if (outcome.found >= part.max_instances) {
      outcome.stop_reason = "max_instances reached";
      break;
    }
    if (scan.points.size() < kMinSearchPoints) {
      outcome.stop_reason = "too few scan points left";
      break;
    }
    if (search >= kSearchesPerInstance * part.max_instances) {
      outcome.stop_reason = "search limit reached";
      break;
    }
    const OrientedPoints scene = Thin(scan, ppf_step);
    std::vector<PoseCandidate> candidates = ppf.Vote(scene.points, scene.normals, cancel);
    if (seen) RankByView(*seen, ppf_model_points, ppf_step, options.view_candidates, candidates);
    if (IsCancelled(cancel)) return Cancelled("localization cancelled");
    std::optional<LocalizedInstance> accepted;
    bool absorbed = false;
    std::vector<bool> explained;
    std::string rejected;
    for (size_t c = 0; c < candidates.size() && c < kCandidatesTried && !accepted && !absorbed; ++c) {
      ASSIGN_OR_RETURN(const Pose3 refined, RefineVoted(all_samples, scan, candidates[c].scene_from_part,
                                                        kIcpReachInPpfSteps * ppf_step, explained_distance));
      LocalizedInstance instance;
      instance.world_from_part = refined;
      explained = NearPart(all_samples, refined, scan, explained_distance, min_cos);
      for (const bool e : explained) instance.explained_points += e ? 1 : 0;
      if (accepted_surface.SharedShare(model, refined, explained_distance) > kMaxSharedSurface) {
        // A found instance again, on scan points its removal left behind: they are its, not new.
        absorbed = instance.explained_points > 0;
        continue;
      }
      if (seen) {
        const DepthGrid::Tally view = seen->Check(model, refined, explained_distance);
        if (static_cast<double>(view.seen_through) >
            options.max_seen_through_share * static_cast<double>(view.on_surface + view.seen_through)) {
          if (rejected.empty()) {
            rejected = "the best candidate lies where the sensor saw past " + std::to_string(view.seen_through) +
                       " of its " + std::to_string(view.on_surface + view.seen_through) + " points facing it";
          }
          continue;
        }
      }
      instance.score = ExplainedShare(model, refined, parts_scan, parts_tree, options.inlier_distance_voxels * voxel,
                                      min_cos);
      if (instance.explained_points >= options.min_explained_points && instance.score >= options.min_score) {
        accepted = instance;
      } else if (rejected.empty()) {
        rejected = "the best candidate explains " + std::to_string(instance.explained_points) +
                   " points with score " + std::to_string(instance.score);
      }
    }
    if (absorbed) {
      RemoveMarked(explained, scan);
      continue;
    }
    if (!accepted) {
      outcome.stop_reason = candidates.empty() ? "no pose candidates"
                           : rejected.empty() ? "every candidate repeats a found instance"
                                              : rejected;
      break;
    }
    RemoveMarked(explained, scan);
    accepted_surface.Add(model, accepted->world_from_part);
    accepted->part = part_index;
    instances.push_back(*accepted);
    ++outcome.found;
  }
  return outcome;
}

}  // namespace

StatusOr<LocalizationResult> LocalizeParts(std::span<const PartQuery> parts, std::span<const Eigen::Vector3f> scan_points,
                                           std::span<const Eigen::Vector3f> scan_normals,
                                           const LocalizerOptions& options, const std::atomic<bool>* cancel,
                                           const LocalizeProgressCallback& progress) {
  RETURN_IF_ERROR(Validate(options, scan_points.size(), scan_normals.size()));
  if (parts.empty()) return InvalidArgument("parts", "must name at least one part");
  std::vector<PartModel> models;
  double scan_voxel = std::numeric_limits<double>::infinity();
  for (size_t p = 0; p < parts.size(); ++p) {
    const std::string field = "parts[" + std::to_string(p) + "]";
    if (parts[p].mesh == nullptr) return InvalidArgument(field, "has no mesh");
    ASSIGN_OR_RETURN(PartModel model, BuildPartModel(*parts[p].mesh, field, options));
    model.max_instances = parts[p].max_instances > 0 ? parts[p].max_instances : options.max_instances;
    scan_voxel = std::min(scan_voxel, model.voxel);
    models.push_back(std::move(model));
    if (IsCancelled(cancel)) return Cancelled("localization cancelled");
  }
  const auto report = [&](double fraction, size_t found, const std::string& stage) {
    if (progress) progress(LocalizeProgress{fraction, found, stage});
  };
  ASSIGN_OR_RETURN(const PreparedScan prepared, PrepareScan(scan_points, scan_normals, scan_voxel, options, cancel));
  report(0.05, 0, "scan prepared");
  LocalizationResult result;
  result.support_plane_points = prepared.support_plane_points;
  for (size_t p = 0; p < models.size(); ++p) {
    ASSIGN_OR_RETURN(PartSearch searched, SearchPart(models[p], p, prepared, options, cancel, result.instances));
    result.parts.push_back(std::move(searched));
    report(0.05 + 0.95 * static_cast<double>(p + 1) / static_cast<double>(models.size()), result.instances.size(),
           "part " + std::to_string(p) + " searched");
  }
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
