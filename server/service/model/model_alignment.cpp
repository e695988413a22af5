#include "service/model/model_alignment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "registration/feature_alignment.h"
#include "registration/multiview_alignment.h"
#include "service/model/model_scans.h"

namespace vscan::service {
namespace {

// A scan whose aligned pose disagrees with its known pose by more than this many times the median
// disagreement is left out of the fit that places the aligned set.
constexpr double kOutlierMisfits = 4.0;

// The alignment voxel picked from an object's size (its bounding-box diagonal).
double VoxelForSize(double size) { return std::clamp(size / 100.0, 2e-4, 0.05); }

double Diagonal(const std::vector<Eigen::Vector3f>& points) {
  if (points.empty()) return 0;
  Eigen::Vector3f min = points.front(), max = points.front();
  for (const Eigen::Vector3f& p : points) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  return (max - min).cast<double>().norm();
}

double MeanRange(const std::vector<Eigen::Vector3f>& points) {
  if (points.empty()) return 0;
  double sum = 0;
  for (const Eigen::Vector3f& p : points) sum += p.norm();
  return sum / static_cast<double>(points.size());
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

void SetErrors(ScanAlignmentRecord& record, const Pose3& truth, const Pose3& initial, const Pose3& gauge) {
  record.has_error = true;
  record.rotation_error_deg = RotationErrorDeg(gauge * record.model_from_sensor, truth);
  record.translation_error_m = TranslationError(gauge * record.model_from_sensor, truth);
  record.initial_rotation_error_deg = RotationErrorDeg(gauge * initial, truth);
  record.initial_translation_error_m = TranslationError(gauge * initial, truth);
}

// Adds the time of its scope to a total.
class Timer {
 public:
  explicit Timer(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  ~Timer() { total_ += Elapsed(); }
  Timer(const Timer&) = delete;
  Timer& operator=(const Timer&) = delete;
  double Elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  double& total_;
  const std::chrono::steady_clock::time_point start_;
};

}  // namespace

class ModelAligner::Impl {
 public:
  Impl(const AlignmentSettings& settings, ScanAlignedCallback on_scan, const std::atomic<bool>* cancel)
      : settings_(settings), on_scan_(std::move(on_scan)), cancel_(cancel) {}

  Status Add(ModelScan scan) {
    if (Stopped()) return vscan::Cancelled("alignment stopped");
    const Timer timer(seconds_);
    Grow(scan.index + 1);
    const size_t index = scan.index;
    ASSIGN_OR_RETURN(const bool added, AddOne(scan));
    // A scan whose features found no partner is kept to try again against the grown union.
    if (!added) unmatched_.push_back(std::move(scan));
    return on_scan_(out_.scans[index], ++done_);
  }

  StatusOr<AlignedScans> Finish() {
    const Timer timer(seconds_);
    for (bool progress = true; progress && !unmatched_.empty();) {
      progress = false;
      std::vector<ModelScan> still;
      for (ModelScan& scan : unmatched_) {
        if (Stopped()) return vscan::Cancelled("alignment stopped");
        ASSIGN_OR_RETURN(const bool added, AddOne(scan));
        if (added) {
          progress = true;
          RETURN_IF_ERROR(on_scan_(out_.scans[scan.index], done_));
        } else {
          still.push_back(std::move(scan));
        }
      }
      unmatched_ = std::move(still);
    }
    RETURN_IF_ERROR(FinishGraph());
    out_.voxel_size = options_.voxel_size;
    out_.initial_pose = any_known_ && any_features_ ? "known+features" : (any_features_ ? "features" : "known");
    out_.seconds = seconds_ + timer.Elapsed();
    return std::move(out_);
  }

 private:
  void Grow(size_t n) {
    if (out_.scans.size() >= n) return;
    out_.scans.resize(n);
    out_.truth.resize(n);
    initial_.resize(n, Pose3::Identity());
    started_.resize(n, false);
    features_.resize(n, false);
  }

  bool Stopped() const { return cancel_ && cancel_->load(); }

  Status Create(const ModelScan& first) {
    options_.voxel_size = settings_.voxel_size > 0 ? settings_.voxel_size : VoxelForSize(Diagonal(first.points));
    options_.icp.max_correspondence_distance = settings_.max_correspondence_distance;
    options_.min_fitness = settings_.min_fitness;
    options_.pose_graph = settings_.pose_graph;
    ASSIGN_OR_RETURN(auto aligner, registration::MultiviewAligner::Create(options_));
    aligner_.emplace(std::move(aligner));
    return Status::Ok();
  }

  // False when the scan's pose is unknown and its features matched nothing (it was not added).
  StatusOr<bool> AddOne(ModelScan& scan) {
    if (!aligner_) RETURN_IF_ERROR(Create(scan));
    ScanAlignmentRecord& record = out_.scans[scan.index];
    record.cloud_id = scan.cloud_id;
    record.name = scan.name;
    record.index = static_cast<uint32_t>(scan.index);
    out_.truth[scan.index] = scan.true_model_from_sensor;
    features_[scan.index] = scan.features;
    any_features_ = any_features_ || scan.features;
    any_known_ = any_known_ || !scan.features;
    ranges_.push_back(MeanRange(scan.points));
    Pose3 start = scan.initial_model_from_sensor;
    if (scan.features) {
      start = Pose3::Identity();
      if (anchored_) {
        registration::FeatureAlignmentOptions features;
        features.voxel_size = 2 * options_.voxel_size;
        features.min_fitness = settings_.min_fitness;
        features.source_viewpoint = scan.sensor_origin;
        const std::vector<Eigen::Vector3f> target = aligner_->UnionPoints();
        ASSIGN_OR_RETURN(const registration::FeatureAlignmentResult match,
                         registration::AlignByFeatures(scan.points, target, features, cancel_));
        if (!match.found) {
          record.aligned = false;
          record.reason = "no pose from features: " + match.reason;
          return false;
        }
        start = match.target_from_source;
      }
    }
    initial_[scan.index] = start;
    started_[scan.index] = true;
    ASSIGN_OR_RETURN(const registration::ViewAlignment view,
                     aligner_->Add(registration::ViewScan{std::move(scan.points), start,
                                                          scan.features ? std::nullopt : scan.initial_information},
                                   cancel_));
    any_prior_ = any_prior_ || (!scan.features && scan.initial_information);
    added_.push_back(scan.index);
    if (!anchored_ && view.aligned) {
      anchored_ = true;
      out_.in_model_frame = !scan.features;
    }
    Fill(record, view);
    record.union_points = aligner_->UnionSize();
    if (out_.in_model_frame && out_.truth[scan.index]) {
      SetErrors(record, *out_.truth[scan.index], start, Pose3::Identity());
    }
    return true;
  }

  static void Fill(ScanAlignmentRecord& record, const registration::ViewAlignment& view) {
    record.aligned = view.aligned;
    record.reason = view.reason;
    record.model_from_sensor = view.model_from_sensor;
    record.fitness = view.fitness;
    record.inlier_rmse = view.inlier_rmse;
  }

  Status FinishGraph() {
    if (!aligner_) return Status::Ok();
    ASSIGN_OR_RETURN(const std::vector<registration::ViewAlignment> views, aligner_->Finish(cancel_));
    if (views.size() != added_.size()) return Internal("alignment: the pose graph returned a different scan count");
    for (size_t k = 0; k < views.size(); ++k) Fill(out_.scans[added_[k]], views[k]);
    const double reach = Median(ranges_);
    // The pose graph already weighed the known poses by their firmness when it had them.
    if (out_.in_model_frame && !(any_prior_ && settings_.pose_graph)) PlaceOnKnownPoses(reach);
    // Errors against the truth; a set in its own frame is first laid onto the truth as a whole.
    std::vector<Pose3> from, to;
    for (size_t i = 0; i < out_.scans.size(); ++i) {
      if (out_.truth[i] && out_.scans[i].aligned) {
        from.push_back(out_.scans[i].model_from_sensor);
        to.push_back(*out_.truth[i]);
      }
    }
    const Pose3 gauge = out_.in_model_frame || from.empty() ? Pose3::Identity() : FitPoses(from, to, reach);
    for (size_t i = 0; i < out_.scans.size(); ++i) {
      ScanAlignmentRecord& record = out_.scans[i];
      record.has_error = false;
      if (!started_[i]) continue;
      if (!record.aligned) record.model_from_sensor = initial_[i];
      if (out_.truth[i]) SetErrors(record, *out_.truth[i], initial_[i], gauge);
    }
    return Status::Ok();
  }

  // The anchor keeps its known pose, which carries its own error (e.g. the arm's encoder noise):
  // the aligned set is moved to where it best agrees with every known initial pose instead. Scans
  // that disagree far more than the rest (a wrong alignment) are left out of that fit.
  void PlaceOnKnownPoses(double reach) {
    std::vector<Pose3> from, to;
    for (size_t i = 0; i < out_.scans.size(); ++i) {
      if (started_[i] && !features_[i] && out_.scans[i].aligned) {
        from.push_back(out_.scans[i].model_from_sensor);
        to.push_back(initial_[i]);
      }
    }
    if (from.size() < 3) return;
    Pose3 move = FitPoses(from, to, reach);
    std::vector<double> misfit;
    for (size_t k = 0; k < from.size(); ++k) {
      misfit.push_back(TranslationError(move * from[k], to[k]) +
                       reach * RotationErrorDeg(move * from[k], to[k]) * std::numbers::pi / 180.0);
    }
    const double bound = std::max(kOutlierMisfits * Median(misfit), 1e-9);
    std::vector<Pose3> kept_from, kept_to;
    for (size_t k = 0; k < from.size(); ++k) {
      if (misfit[k] <= bound) {
        kept_from.push_back(from[k]);
        kept_to.push_back(to[k]);
      }
    }
    if (kept_from.size() >= 3 && kept_from.size() < from.size()) move = FitPoses(kept_from, kept_to, reach);
    for (ScanAlignmentRecord& record : out_.scans) {
      if (record.aligned) record.model_from_sensor = move * record.model_from_sensor;
    }
  }

  const AlignmentSettings settings_;
  const ScanAlignedCallback on_scan_;
  const std::atomic<bool>* cancel_;
  double seconds_ = 0;  // spent aligning, not waiting for scans
  std::vector<ModelScan> unmatched_;
  registration::MultiviewOptions options_;
  std::optional<registration::MultiviewAligner> aligner_;
  AlignedScans out_;
  std::vector<Pose3> initial_;
  std::vector<bool> started_;
  std::vector<bool> features_;
  std::vector<size_t> added_;  // scan index of each Add
  std::vector<double> ranges_;
  bool anchored_ = false;
  bool any_known_ = false;
  bool any_features_ = false;
  bool any_prior_ = false;  // some scan's initial pose came with its firmness
  size_t done_ = 0;
};

ModelAligner::ModelAligner(const AlignmentSettings& settings, ScanAlignedCallback on_scan,
                           const std::atomic<bool>* cancel)
    : impl_(std::make_unique<Impl>(settings, std::move(on_scan), cancel)) {}
ModelAligner::~ModelAligner() = default;
Status ModelAligner::Add(ModelScan scan) { return impl_->Add(std::move(scan)); }
StatusOr<AlignedScans> ModelAligner::Finish() { return impl_->Finish(); }

double RotationErrorDeg(const Pose3& a, const Pose3& b) {
  const Eigen::AngleAxisd turn(a.linear().transpose() * b.linear());
  return std::abs(turn.angle()) * 180.0 / std::numbers::pi;
}

double TranslationError(const Pose3& a, const Pose3& b) { return (a.translation() - b.translation()).norm(); }

Pose3 FitPoses(const std::vector<Pose3>& from, const std::vector<Pose3>& to, double reach) {
  const auto n = static_cast<Eigen::Index>(from.size());
  if (n == 0) return Pose3::Identity();
  const Eigen::Vector3d ahead(0, 0, reach > 0 ? reach : 1.0);
  Eigen::Matrix3Xd src(3, 2 * n), dst(3, 2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    src.col(2 * i) = from[i].translation();
    src.col(2 * i + 1) = from[i] * ahead;
    dst.col(2 * i) = to[i].translation();
    dst.col(2 * i + 1) = to[i] * ahead;
  }
  Pose3 fit = Pose3::Identity();
  fit.matrix() = Eigen::umeyama(src, dst, false);
  return fit;
}

StatusOr<AlignedScans> AlignScans(const StoredClouds& clouds, const ModelPlan& plan, const ModelCrop& crop,
                                  const AlignmentSettings& settings, const ScanAlignedCallback& on_scan,
                                  const std::atomic<bool>* cancel) {
  ModelAligner aligner(settings, on_scan, cancel);
  for (size_t i = 0; i < plan.clouds.size(); ++i) {
    if (cancel && cancel->load()) return vscan::Cancelled("model job stopped");
    ASSIGN_OR_RETURN(ModelScan scan, LoadModelScan(clouds, plan, i, crop));
    RETURN_IF_ERROR(aligner.Add(std::move(scan)));
  }
  return aligner.Finish();
}

StatusOr<AlignedScans> TakeScansAsTheyAre(const StoredClouds& clouds, const ModelPlan& plan, const ModelCrop& crop,
                                          const std::atomic<bool>* cancel) {
  AlignedScans out;
  out.initial_pose = "known";
  for (size_t i = 0; i < plan.clouds.size(); ++i) {
    if (cancel && cancel->load()) return vscan::Cancelled("model job stopped");
    ASSIGN_OR_RETURN(const ModelScan scan, LoadModelScan(clouds, plan, i, crop));
    ScanAlignmentRecord record;
    record.cloud_id = scan.cloud_id;
    record.name = scan.name;
    record.index = static_cast<uint32_t>(i);
    record.aligned = true;
    record.model_from_sensor = scan.initial_model_from_sensor;
    record.fitness = 1;
    if (scan.true_model_from_sensor) {
      SetErrors(record, *scan.true_model_from_sensor, scan.initial_model_from_sensor, Pose3::Identity());
    }
    out.scans.push_back(record);
    out.truth.push_back(scan.true_model_from_sensor);
  }
  return out;
}

}  // namespace vscan::service
