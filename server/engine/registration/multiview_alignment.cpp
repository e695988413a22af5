#include "registration/multiview_alignment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "normals/normal_estimation.h"
#include "registration/pair_information.h"
#include "registration/pose_graph.h"
#include "registration/scan_overlap.h"
#include "registration/target_index.h"
#include "registration/voxel_thinning.h"
#include "registration/voxel_union.h"
#include "vscan/common/cancel_flag.h"

namespace vscan::registration {
namespace {

// Thinned points a scan needs to be aligned, or to be the anchor.
constexpr size_t kMinPoints = 100;
constexpr double kDefaultReachVoxels = 5.0;
constexpr double kDefaultCorrectionReaches = 3.0;
// Normals of a thinned scan: neighbours, and the radius (in voxels) beyond which they are dropped.
constexpr int kNormalNeighbours = 16;
constexpr double kNormalRadiusVoxels = 5.0;
// Pose graph: candidate partners per scan, points sampled to measure a pair's overlap, the floor of
// a pair's residual scale and the Huber width on an edge's disagreement (both in voxels, as an RMS
// point-to-plane distance: consistent edges disagree by far less than a voxel, a wrong fit by more).
constexpr size_t kPartnersPerScan = 6;
constexpr size_t kOverlapSamples = 2000;
constexpr double kSigmaFloorVoxels = 1e-3;
constexpr double kHuberWidthVoxels = 0.5;
// Pairwise ICP: reach in voxels and iterations (see FitPair).
constexpr double kPairReachVoxels = 1.0;
constexpr int kPairIterations = 10;

Status CancelledStatus() { return Cancelled("multiview alignment: cancelled"); }

std::vector<Eigen::Vector3f> Transformed(const Pose3& pose, std::span<const Eigen::Vector3f> points) {
  std::vector<Eigen::Vector3f> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) out[i] = (pose * points[i].cast<double>()).cast<float>();
  return out;
}

std::vector<Eigen::Vector3f> Rotated(const Pose3& pose, std::span<const Eigen::Vector3f> normals) {
  std::vector<Eigen::Vector3f> out(normals.size());
  for (size_t i = 0; i < normals.size(); ++i) out[i] = (pose.linear() * normals[i].cast<double>()).cast<float>();
  return out;
}

// RMS distance the points travel from pose `from` to pose `to`.
double RmsTravel(std::span<const Eigen::Vector3f> points, const Pose3& from, const Pose3& to) {
  if (points.empty()) return 0.0;
  double sum = 0.0;
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3d q = p.cast<double>();
    sum += (to * q - from * q).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

std::string Format(const char* format, auto... args) {
  char text[256];
  std::snprintf(text, sizeof(text), format, args...);
  return text;
}

bool StoppedWell(const IcpResult& fit) {
  return fit.stop == IcpStop::kConverged || fit.stop == IcpStop::kMaxIterations;
}

// Aligned scans as pose-graph nodes, in the model frame at their current poses.
struct GraphNodes {
  std::vector<size_t> scan;  // scan index of each node
  size_t anchor = 0;
  std::vector<Pose3> poses;
  std::vector<std::vector<Eigen::Vector3f>> points;
  std::vector<std::vector<Eigen::Vector3f>> normals;
  std::vector<std::optional<TargetIndex>> indices;
};

struct ScanRecord {
  Pose3 initial = Pose3::Identity();
  std::optional<Matrix6d> prior;  // information of the initial pose
  ViewAlignment alignment;
  // Thinned, sensor frame; empty when there were too few.
  std::vector<Eigen::Vector3f> points;
  // One per point, sensor frame, facing the sensor.
  std::vector<Eigen::Vector3f> normals;
};

}  // namespace

struct MultiviewAligner::State {
  MultiviewOptions options;
  // With the correspondence distance resolved.
  IcpOptions icp;
  double max_correction = 0.0;
  std::vector<ScanRecord> scans;
  std::optional<size_t> anchor;
  VoxelUnion merged;

  State(const MultiviewOptions& o, const IcpOptions& resolved, double correction)
      : options(o), icp(resolved), max_correction(correction), merged(o.voxel_size) {}

  double reach() const { return icp.max_correspondence_distance; }

  void Merge(const ScanRecord& scan) {
    const Pose3& pose = scan.alignment.model_from_sensor;
    merged.Add(Transformed(pose, scan.points), Rotated(pose, scan.normals));
  }

  // ICP of the scan against the union from its initial pose, judged by how ICP stopped, the
  // fitness and the size of the correction.
  StatusOr<ViewAlignment> AlignToUnion(const ScanRecord& scan) const {
    ASSIGN_OR_RETURN(const IcpResult fit, PointToPlaneIcp(scan.points, merged.points(), merged.normals(),
                                                          scan.initial, icp, scan.normals));
    ViewAlignment a;
    a.model_from_sensor = scan.initial;
    a.fitness = fit.fitness;
    a.inlier_rmse = fit.inlier_rmse;
    a.iterations = fit.iterations;
    const double correction = RmsTravel(scan.points, scan.initial, fit.target_from_source);
    if (!StoppedWell(fit)) {
      a.reason = Format("ICP stopped: %s (fitness %.3f)", IcpStopName(fit.stop), fit.fitness);
    } else if (fit.fitness < options.min_fitness) {
      a.reason = Format("fitness %.3f below min_fitness %.3f (ICP %s)", fit.fitness, options.min_fitness,
                        IcpStopName(fit.stop));
    } else if (correction > max_correction) {
      a.reason = Format("correction %.4f m beyond max_correction %.4f m (fitness %.3f): the initial pose is "
                        "outside ICP's reach or ICP settled in a wrong minimum",
                        correction, max_correction, fit.fitness);
    } else {
      a.aligned = true;
      a.model_from_sensor = fit.target_from_source;
    }
    return a;
  }

  Status RetryUnaligned(const std::atomic<bool>* cancel);
  GraphNodes CollectNodes() const;
  StatusOr<std::optional<PoseGraphEdge>> FitPair(const GraphNodes& g, size_t target, size_t source) const;
  Status RunPoseGraph(const std::atomic<bool>* cancel);
};

MultiviewAligner::MultiviewAligner(std::unique_ptr<State> state) : state_(std::move(state)) {}
MultiviewAligner::MultiviewAligner(MultiviewAligner&&) noexcept = default;
MultiviewAligner& MultiviewAligner::operator=(MultiviewAligner&&) noexcept = default;
MultiviewAligner::~MultiviewAligner() = default;

StatusOr<MultiviewAligner> MultiviewAligner::Create(const MultiviewOptions& options) {
  if (!std::isfinite(options.voxel_size) || options.voxel_size <= 0.0) {
    return InvalidArgument("alignment.voxel_size", "must be finite and > 0");
  }
  if (!(options.min_fitness >= 0.0 && options.min_fitness <= 1.0)) {
    return InvalidArgument("alignment.min_fitness", "must be in [0, 1]");
  }
  if (!std::isfinite(options.max_correction)) return InvalidArgument("alignment.max_correction", "must be finite");
  if (!(options.min_pair_overlap >= 0.0 && options.min_pair_overlap <= 1.0)) {
    return InvalidArgument("alignment.min_pair_overlap", "must be in [0, 1]");
  }
  IcpOptions icp = options.icp;
  if (icp.max_correspondence_distance <= 0.0) {
    icp.max_correspondence_distance = kDefaultReachVoxels * options.voxel_size;
  }
  // ICP's own checks, run on empty clouds, so that its rules are written in one place.
  const auto check = PointToPlaneIcp({}, {}, {}, Pose3::Identity(), icp);
  if (!check.ok()) return check.status();
  const double max_correction = options.max_correction > 0.0
                                    ? options.max_correction
                                    : kDefaultCorrectionReaches * icp.max_correspondence_distance;
  return MultiviewAligner(std::make_unique<State>(options, icp, max_correction));
}

StatusOr<ViewAlignment> MultiviewAligner::Add(ViewScan scan, const std::atomic<bool>* cancel) {
  State& s = *state_;
  if (IsCancelled(cancel)) return CancelledStatus();
  if (!scan.initial_model_from_sensor.matrix().allFinite()) {
    return InvalidArgument("scan.initial_model_from_sensor", "must be finite");
  }
  if (scan.initial_information) {
    const Matrix6d& info = *scan.initial_information;
    if (!info.allFinite() || !info.isApprox(info.transpose(), 1e-9) || info.diagonal().minCoeff() <= 0) {
      return InvalidArgument("scan.initial_information", "must be finite, symmetric and positive on its diagonal");
    }
  }
  ScanRecord record;
  record.initial = scan.initial_model_from_sensor;
  record.prior = scan.initial_information;
  record.alignment.model_from_sensor = record.initial;
  record.points = ThinToVoxelCentroids(scan.points, s.options.voxel_size);
  scan.points = {};
  if (record.points.size() < kMinPoints) {
    record.alignment.reason = Format("too few points: %zu after thinning to %g m voxels (needs %zu)",
                                     record.points.size(), s.options.voxel_size, kMinPoints);
    record.points.clear();
    s.scans.push_back(std::move(record));
    return s.scans.back().alignment;
  }
  if (IsCancelled(cancel)) return CancelledStatus();

  normals::NormalOptions normal_options;
  normal_options.k = kNormalNeighbours;
  normal_options.max_distance = static_cast<float>(kNormalRadiusVoxels * s.options.voxel_size);
  // In the sensor frame the sensor is the origin.
  normal_options.viewpoint = Eigen::Vector3f::Zero();
  normal_options.cancel = cancel;
  auto normals = normals::EstimateNormals(record.points, normal_options);
  if (!normals.ok()) return normals.status().code() == StatusCode::kCancelled ? CancelledStatus() : normals.status();
  record.normals = std::move(normals).value();

  if (!s.anchor) {
    record.alignment.aligned = true;
    record.alignment.fitness = 1.0;
    s.anchor = s.scans.size();
  } else {
    ASSIGN_OR_RETURN(record.alignment, s.AlignToUnion(record));
    if (IsCancelled(cancel)) return CancelledStatus();
  }
  if (record.alignment.aligned) s.Merge(record);
  s.scans.push_back(std::move(record));
  return s.scans.back().alignment;
}

std::vector<Eigen::Vector3f> MultiviewAligner::UnionPoints() const { return state_->merged.points(); }

size_t MultiviewAligner::UnionSize() const { return state_->merged.size(); }

size_t MultiviewAligner::size() const { return state_->scans.size(); }

StatusOr<std::vector<ViewAlignment>> MultiviewAligner::Finish(const std::atomic<bool>* cancel) {
  State& s = *state_;
  if (IsCancelled(cancel)) return CancelledStatus();
  RETURN_IF_ERROR(s.RetryUnaligned(cancel));
  if (s.options.pose_graph) RETURN_IF_ERROR(s.RunPoseGraph(cancel));
  std::vector<ViewAlignment> alignments;
  alignments.reserve(s.scans.size());
  for (const ScanRecord& scan : s.scans) alignments.push_back(scan.alignment);
  return alignments;
}

// A scan that found too little of the union when it came may overlap scans that came later.
Status MultiviewAligner::State::RetryUnaligned(const std::atomic<bool>* cancel) {
  for (ScanRecord& scan : scans) {
    if (scan.alignment.aligned || scan.points.empty()) continue;
    if (IsCancelled(cancel)) return CancelledStatus();
    ASSIGN_OR_RETURN(ViewAlignment retried, AlignToUnion(scan));
    if (!retried.aligned) continue;
    scan.alignment = std::move(retried);
    Merge(scan);
  }
  return Status::Ok();
}

GraphNodes MultiviewAligner::State::CollectNodes() const {
  GraphNodes g;
  for (size_t i = 0; i < scans.size(); ++i) {
    if (!scans[i].alignment.aligned) continue;
    if (anchor && i == *anchor) g.anchor = g.scan.size();
    g.scan.push_back(i);
  }
  const size_t n = g.scan.size();
  g.poses.resize(n);
  g.points.resize(n);
  g.normals.resize(n);
  g.indices.resize(n);
  tbb::parallel_for(size_t{0}, n, [&](size_t k) {
    const ScanRecord& scan = scans[g.scan[k]];
    g.poses[k] = scan.alignment.model_from_sensor;
    g.points[k] = Transformed(g.poses[k], scan.points);
    g.normals[k] = Rotated(g.poses[k], scan.normals);
    g.indices[k].emplace(g.points[k], g.normals[k]);
  });
  return g;
}

// The edge of one candidate pair, if the pair overlaps enough and its fit holds; the smaller scan
// is the source, so that its share within reach of the other is the overlap.
StatusOr<std::optional<PoseGraphEdge>> MultiviewAligner::State::FitPair(const GraphNodes& g, size_t target,
                                                                         size_t source) const {
  if (g.points[source].size() > g.points[target].size()) std::swap(source, target);
  const double overlap = OverlapShare(g.points[source], g.normals[source], *g.indices[target], reach(),
                                      icp.max_normal_angle, kOverlapSamples);
  if (overlap < options.min_pair_overlap) return std::optional<PoseGraphEdge>();
  const double voxel = options.voxel_size;
  // The scans already lie on the union to a fraction of a voxel, so a pair needs no more reach than
  // the spacing of the thinned points, and few iterations. A longer reach lets points beyond the
  // edge of the other scan pair with its rim, which biases pairs that overlap little.
  IcpOptions pair_icp = icp;
  pair_icp.max_correspondence_distance = std::min(icp.max_correspondence_distance, kPairReachVoxels * voxel);
  pair_icp.max_iterations = std::min(icp.max_iterations, kPairIterations);
  const ScanRecord& moving = scans[g.scan[source]];
  ASSIGN_OR_RETURN(const IcpResult fit, PointToPlaneIcp(moving.points, g.points[target], g.normals[target],
                                                        g.poses[source], pair_icp, moving.normals));
  // A pair that ICP moves apart by more than a voxel has slid along surfaces that do not pin it.
  if (!StoppedWell(fit) || RmsTravel(moving.points, g.poses[source], fit.target_from_source) > voxel) {
    return std::optional<PoseGraphEdge>();
  }
  const PairInformation info = ComputePairInformation(moving.points, moving.normals, *g.indices[target],
                                                      fit.target_from_source, fit, pair_icp, kSigmaFloorVoxels * voxel);
  if (info.weight_sum < static_cast<double>(icp.min_correspondences)) return std::optional<PoseGraphEdge>();
  PoseGraphEdge edge;
  edge.from = target;
  edge.to = source;
  edge.measured = g.poses[target].inverse() * fit.target_from_source;
  edge.information = info.information;
  // The whitened error of an edge is sqrt(weight_sum) / sigma times the RMS point-to-plane distance
  // its disagreement opens between the pair's points.
  edge.huber_width = kHuberWidthVoxels * voxel * std::sqrt(info.weight_sum) / info.sigma;
  return std::optional<PoseGraphEdge>(edge);
}

Status MultiviewAligner::State::RunPoseGraph(const std::atomic<bool>* cancel) {
  const GraphNodes g = CollectNodes();
  if (g.scan.size() < 2) return Status::Ok();
  if (IsCancelled(cancel)) return CancelledStatus();
  const std::vector<std::pair<size_t, size_t>> candidates = CandidatePairs(g.points, reach(), kPartnersPerScan);
  std::vector<StatusOr<std::optional<PoseGraphEdge>>> fitted(candidates.size(), std::optional<PoseGraphEdge>());
  // Each pair is fitted on its own, so the edges do not depend on the schedule.
  tbb::parallel_for(size_t{0}, candidates.size(), [&](size_t c) {
    if (!IsCancelled(cancel)) fitted[c] = FitPair(g, candidates[c].first, candidates[c].second);
  });
  if (IsCancelled(cancel)) return CancelledStatus();
  std::vector<PoseGraphEdge> edges;
  for (const auto& edge : fitted) {
    if (!edge.ok()) return edge.status();
    if (*edge) edges.push_back(**edge);
  }
  // Scans whose initial pose is known to some firmness hang from a fixed model-frame node by it;
  // the graph then needs no anchor scan held where it started.
  std::vector<Pose3> poses = g.poses;
  size_t fixed = g.anchor;
  const size_t model_node = poses.size();
  for (size_t k = 0; k < g.scan.size(); ++k) {
    const ScanRecord& scan = scans[g.scan[k]];
    if (!scan.prior) continue;
    PoseGraphEdge prior;
    prior.from = model_node;
    prior.to = k;
    prior.measured = scan.initial;
    prior.information = *scan.prior;
    edges.push_back(prior);
    fixed = model_node;
  }
  if (fixed == model_node) poses.push_back(Pose3::Identity());
  PoseGraphOptions graph_options;
  graph_options.cancel = cancel;
  ASSIGN_OR_RETURN(const PoseGraphResult graph,
                   OptimizePoseGraph(std::move(poses), edges, std::span<const size_t>(&fixed, 1), graph_options));
  for (size_t k = 0; k < g.scan.size(); ++k) scans[g.scan[k]].alignment.model_from_sensor = graph.poses[k];
  merged.Clear();
  for (const ScanRecord& scan : scans) {
    if (scan.alignment.aligned) Merge(scan);
  }
  return Status::Ok();
}

}  // namespace vscan::registration
