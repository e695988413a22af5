#include "service/model/model_run.h"

#include <algorithm>
#include <map>
#include <cstdio>
#include <optional>

#include <spdlog/spdlog.h>

#include "evaluation/surface_sampling.h"
#include "registration/feature_alignment.h"
#include "scenes/object_material.h"
#include "service/job/run_end.h"
#include "service/model/model_alignment.h"
#include "service/model/model_evaluation.h"
#include "service/model/model_ground_truth.h"
#include "service/model/model_mesh_ply.h"
#include "service/model/model_next_best_views.h"
#include "service/model/model_reconstruction.h"
#include "service/model/model_report.h"
#include "service/model/model_scans.h"
#include "service/model/model_union.h"
#include "vscan/common/cloud_io.h"
#include "service/job/message_numbers.h"
#include "service/job/job_kind.h"

namespace vscan::service {
namespace {

constexpr const char* kPlyMediaType = "model/ply";
constexpr const char* kJsonMediaType = "application/json";
constexpr const char* kPngMediaType = "image/png";
// Defaults picked from the object's size (its bounding-box diagonal).
constexpr double kTauPerSize = 1.0 / 200;
constexpr double kAlignmentVoxelPerSize = 1.0 / 100;
constexpr double kReconstructionVoxelPerSize = 1.0 / 250;
// Samples of the truth that scans aligned by features are laid onto.
constexpr size_t kPlacementSamples = 50'000;

std::string ScanMessage(const ScanAlignmentRecord& scan, size_t total) {
  std::string message = "scan " + std::to_string(scan.index + 1) + (total > 0 ? " of " + std::to_string(total) : "") +
                        " (" + scan.name + ") ";
  if (!scan.aligned) return message + "not aligned: " + scan.reason;
  message += "aligned, fitness " + Rounded(scan.fitness);
  if (scan.has_error) {
    message += ", error " + Rounded(scan.rotation_error_deg) + " deg / " + Rounded(scan.translation_error_m * 1e3) +
               " mm (from " + Rounded(scan.initial_rotation_error_deg) + " deg / " +
               Rounded(scan.initial_translation_error_m * 1e3) + " mm)";
  }
  return message;
}

}  // namespace

class ModelRun {
 public:
  ModelRun(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, ModelPlan plan,
           jobs::JobControl& control)
      : context_(context), clouds_(StoredCloudsOf(context)), recorder_(recorder), job_id_(job_id), plan_(std::move(plan)), control_(control) {
    report_.job_id = job_id;
    report_.clouds = plan_.clouds.size();
    if (plan_.scene) report_.scene_id = plan_.scene->scene_id;
  }

  void SetReportKind(std::string kind) { report_.kind = std::move(kind); }

  void Run() {
    Status status = Event(Intent());
    if (status.ok()) status = Stages();
    store::JobState state = store::JobState::kSucceeded;
    std::string message;
    if (control_.stop_requested()) {
      state = StoppedState(control_.reason());
      message = StoppedMessage(state) + " after " + std::to_string(steps_done_) + " of " + std::to_string(ModelStepsTotal(plan_)) + " steps";
    } else if (!status.ok()) {
      state = store::JobState::kFailed;
      message = status.message();
    } else {
      message = Summary();
      steps_done_ = ModelStepsTotal(plan_);
    }
    WriteReport(state);
    RecordEnd(recorder_, job_id_, Update(state, message));
  }

  // A campaign's part: the model's events count from the campaign's steps, and its scans are
  // aligned as they are captured.
  void SetStepBase(uint32_t base) { step_base_ = base; }
  const ModelPlan& plan() const { return plan_; }

  Status Prepare() {
    RETURN_IF_ERROR(PrepareTruth());
    if (!plan_.align) return Status::Ok();
    aligner_.emplace(Settings(), [this](const ScanAlignmentRecord& scan, size_t) { return OnScan(scan, 0); }, cancel());
    return Status::Ok();
  }

  Status AlignCaptured(ModelCloud cloud, const PointCloud& points) {
    const size_t index = plan_.clouds.size();
    plan_.clouds.push_back(std::move(cloud));
    if (!aligner_) return Status::Ok();
    return aligner_->Add(ModelScanFromPoints(plan_, plan_.clouds.back(), index, points, crop_));
  }

  // The stages after alignment, on the scans as the campaign stored them (job_id's clouds).
  Status Complete() {
    RETURN_IF_ERROR(AdoptStoredClouds());
    if (aligner_) {
      RETURN_IF_ERROR(Aligned(aligner_->Finish()));
    } else {
      RETURN_IF_ERROR(Align());
    }
    return AfterAlignment();
  }

  void WriteReport(store::JobState state) {
    report_.state = store::JobStateName(state);
    report_.clouds = plan_.clouds.size();
    if (report_.alignment) report_.alignment->artifact = placed_ ? "aligned.ply" : "";
    const std::string json = recorder_.reports().ModelJson(report_);
    auto written = recorder_.RecordArtifact("model.json", kJsonMediaType, json, nullptr, nullptr,
                                            Update(store::JobState::kRunning, "model.json written"));
    if (!written.ok()) spdlog::error("job {}: cannot store model.json: {}", job_id_, written.status().ToString());
  }

  std::string Summary() const {
    std::string text;
    if (report_.alignment) {
      const auto& scans = report_.alignment->scans;
      const auto aligned = std::count_if(scans.begin(), scans.end(), [](const auto& s) { return s.aligned; });
      text = std::to_string(aligned) + " of " + std::to_string(scans.size()) + " scans aligned";
      const ErrorSummary rotation = SummariseFinalRotation(scans);
      if (rotation.count > 0) {
        text += ", max error " + Rounded(rotation.max) + " deg / " +
                Rounded(SummariseFinalTranslation(scans).max * 1e3) + " mm";
      }
    } else {
      text = std::to_string(plan_.clouds.size()) + " clouds merged";
    }
    if (report_.reconstruction) {
      text += "; " + report_.reconstruction->method + " mesh of " + std::to_string(report_.reconstruction->triangles) +
              " triangles";
    }
    if (report_.evaluation) {
      const ModelEvaluationReport& e = *report_.evaluation;
      const double f = e.mesh_metrics ? e.mesh_metrics->f_score : e.union_metrics.f_score;
      text += "; coverage " + Rounded(e.coverage) + "; F " + Rounded(f) + " at " + Rounded(e.tau * 1e3) + " mm";
    }
    return text;
  }

 private:
  const std::atomic<bool>* cancel() const { return control_.flag(); }

  JobEventUpdate Update(store::JobState state, const std::string& message) const {
    JobEventUpdate update;
    update.state = state;
    update.message = message;
    update.steps_done = step_base_ + steps_done_;
    update.step = step_base_ + steps_done_;
    return update;
  }

  Status Event(const std::string& message) { return recorder_.Record(Update(store::JobState::kRunning, message)); }

  Status Artifact(const std::string& name, const char* media_type, const std::string& bytes,
                  const std::string& message) {
    auto stored = recorder_.RecordArtifact(name, media_type, bytes, nullptr, nullptr,
                                           Update(store::JobState::kRunning, message));
    if (!stored.ok()) return Status(stored.status().code(), "cannot store " + name + ": " + stored.status().message());
    return Status::Ok();
  }

  std::string Intent() const {
    std::string text = std::to_string(plan_.clouds.size()) + " clouds: " + (plan_.align ? "align" : "merge");
    if (plan_.reconstruct) text += plan_.reconstruction == ReconstructionKind::kTsdf ? ", TSDF" : ", Poisson";
    if (plan_.evaluate) text += ", evaluate";
    return text;
  }

  bool Stopped() const { return control_.stop_requested(); }
  // A stage that saw the stop flag returns CANCELLED; Run then reports the stop, not a failure.
  static Status Stop() { return Cancelled("model job stopped"); }

  Status Stages() {
    RETURN_IF_ERROR(PrepareTruth());
    RETURN_IF_ERROR(Align());
    return AfterAlignment();
  }

  Status AfterAlignment() {
    if (Stopped()) return Stop();
    RETURN_IF_ERROR(Merge());
    if (Stopped()) return Stop();
    if (plan_.reconstruct) RETURN_IF_ERROR(Reconstruct());
    if (Stopped()) return Stop();
    if (plan_.evaluate) RETURN_IF_ERROR(Evaluate());
    return Status::Ok();
  }

  // The ground truth defines the default crop and the sizes the defaults are picked from.
  Status PrepareTruth() {
    if (plan_.scene && !plan_.scene->objects.empty()) {
      auto truth = LoadGroundTruth(context_.registry, *plan_.scene);
      if (!truth.ok() && plan_.evaluate) return truth.status();
      if (truth.ok()) truth_ = std::move(truth).value();
    }
    if (plan_.crop) {
      crop_ = BoxCrop(*plan_.crop);
    } else if (truth_) {
      crop_ = DefaultCrop(*truth_, *plan_.scene);
    }
    report_.crop = crop_;
    size_ = truth_ ? truth_->diagonal : 0;
    return Status::Ok();
  }

  Status Align() {
    if (!plan_.align) {
      ASSIGN_OR_RETURN(aligned_, TakeScansAsTheyAre(clouds_, plan_, crop_, cancel()));
      steps_done_ = static_cast<uint32_t>(plan_.clouds.size());
      return Event(std::to_string(plan_.clouds.size()) + " clouds taken at their stored poses");
    }
    auto on_scan = [this](const ScanAlignmentRecord& scan, size_t done) { return OnScan(scan, done); };
    return Aligned(AlignScans(clouds_, plan_, crop_, Settings(), on_scan, cancel()));
  }

  AlignmentSettings Settings() const {
    AlignmentSettings settings;
    settings.voxel_size = plan_.voxel_size > 0   ? plan_.voxel_size
                           : size_ > 0 ? std::clamp(size_ * kAlignmentVoxelPerSize, 2e-4, 0.05)
                                       : 0.0;
    settings.max_correspondence_distance = plan_.max_correspondence_distance;
    settings.min_fitness = plan_.min_fitness;
    settings.pose_graph = plan_.pose_graph;
    return settings;
  }

  // done > 0 counts the scans as steps (a model job); a campaign counted them as it captured them.
  Status OnScan(const ScanAlignmentRecord& scan, size_t done) {
    if (done > 0) steps_done_ = static_cast<uint32_t>(done);
    const size_t total = done > 0 ? plan_.clouds.size() : 0;
    JobEventUpdate update = Update(store::JobState::kRunning, ScanMessage(scan, total));
    update.alignment = scan;
    return recorder_.Record(update);
  }

  // The campaign's scans as stored, in capture order: the later stages read them back by cloud id.
  Status AdoptStoredClouds() {
    ASSIGN_OR_RETURN(std::vector<store::CloudRecord> stored, ListJobClouds(context_, job_id_));
    std::map<std::string, store::CloudRecord> by_name;
    for (store::CloudRecord& record : stored) by_name.emplace(record.name, std::move(record));
    for (ModelCloud& cloud : plan_.clouds) {
      const auto it = by_name.find(cloud.record.name);
      if (it == by_name.end()) return Internal("campaign scan " + cloud.record.name + " was not stored as a cloud");
      cloud.record = it->second;
    }
    return Status::Ok();
  }

  Status Aligned(StatusOr<AlignedScans> aligned) {
    if (!aligned.ok()) return Stopped() ? Stop() : aligned.status();
    aligned_ = std::move(aligned).value();
    for (ScanAlignmentRecord& scan : aligned_->scans) {
      if (scan.index < plan_.clouds.size()) scan.cloud_id = plan_.clouds[scan.index].record.cloud_id;
    }
    ModelAlignmentReport& report = report_.alignment.emplace();
    report.initial_pose = aligned_->initial_pose;
    report.voxel_size = aligned_->voxel_size;
    report.pose_graph = plan_.pose_graph;
    report.seconds = aligned_->seconds;
    report.scans = aligned_->scans;
    const auto placed = std::find_if(aligned_->scans.begin(), aligned_->scans.end(),
                                     [](const ScanAlignmentRecord& scan) { return scan.aligned; });
    if (placed == aligned_->scans.end()) {
      const std::string reason = aligned_->scans.empty() ? "no scans" : aligned_->scans.front().reason;
      return FailedPrecondition("no scan could be aligned (the first: " + reason + ")");
    }
    if (!aligned_->in_model_frame && truth_) RETURN_IF_ERROR(PlaceOnTruth());
    report.scans = aligned_->scans;
    return Status::Ok();
  }

  // Scans aligned by features from an anchor of unknown pose sit in that anchor's frame: the whole
  // set is laid onto the truth by features too, so that crop and evaluation apply.
  Status PlaceOnTruth() {
    ModelCrop none;
    ASSIGN_OR_RETURN(const PlacedScans placed, PlaceScans(clouds_, plan_, *aligned_, none, cancel()));
    // Both sides' normals get their signs from outside the shape (the sensors that saw the points,
    // the mesh's faces): on flat machined faces a shape-made sign differs between the two clouds.
    const reconstruction::UnionCloud seen_union = ThinnedUnion(placed, aligned_->voxel_size);
    const TriangleMesh seen = ClipMesh(truth_->mesh, crop_);
    std::vector<Eigen::Vector3f> outward;
    const std::vector<Eigen::Vector3f> truth = evaluation::SampleSurface(seen, kPlacementSamples, 1, &outward);
    if (truth_->mesh.SignedVolume() < 0) {
      for (Eigen::Vector3f& n : outward) n = -n;
    }
    registration::FeatureAlignmentOptions options;
    options.voxel_size = 2 * aligned_->voxel_size;
    options.min_fitness = plan_.min_fitness;
    options.source_facing = seen_union.view_directions;
    options.target_facing = outward;
    ASSIGN_OR_RETURN(const registration::FeatureAlignmentResult match,
                     registration::AlignByFeatures(seen_union.positions, truth, options, cancel()));
    if (!match.found) {
      return FailedPrecondition("alignment.initial_pose", "the scans, aligned by their features, could not be placed "
                                                          "on the ground truth: " + match.reason);
    }
    for (ScanAlignmentRecord& scan : aligned_->scans) scan.model_from_sensor = match.target_from_source * scan.model_from_sensor;
    aligned_->in_model_frame = true;
    return Event("aligned scans placed on the ground truth by features (fitness " + Rounded(match.fitness) + ")");
  }

  Status Merge() {
    // Without a model frame (features, no truth) the crop, which lives in it, cannot apply.
    if (!aligned_->in_model_frame) crop_ = ModelCrop{};
    ASSIGN_OR_RETURN(placed_, PlaceScans(clouds_, plan_, *aligned_, crop_, cancel()));
    if (size_ <= 0) size_ = PlacedDiagonal(*placed_);
    if (plan_.evaluate) tau_ = plan_.tau > 0 ? plan_.tau : size_ * kTauPerSize;
    // Fine enough to keep every detail alignment resolves and, for evaluation, coverage at tau.
    double voxel = aligned_->voxel_size > 0 ? aligned_->voxel_size / 2 : size_ * kAlignmentVoxelPerSize / 2;
    if (tau_ > 0) voxel = std::min(voxel, tau_ / 4);
    union_ = ThinnedUnion(*placed_, std::max(voxel, 1e-5)).positions;
    PointCloud cloud;
    cloud.positions = union_;
    ASSIGN_OR_RETURN(const std::string ply, EncodePly(cloud));
    ++steps_done_;
    return Artifact("aligned.ply", kPlyMediaType, ply,
                    "aligned.ply written: " + std::to_string(union_.size()) + " points of " +
                        std::to_string(placed_->index.size()) + " scans");
  }

  Status Reconstruct() {
    const double voxel =
        plan_.reconstruction_voxel_size > 0 ? plan_.reconstruction_voxel_size
                                            : std::clamp(size_ * kReconstructionVoxelPerSize, 2e-4, 0.02);
    auto mesh = ReconstructModel(clouds_, context_.options, plan_, *aligned_, *placed_, crop_, voxel, cancel());
    if (!mesh.ok()) return Stopped() ? Stop() : mesh.status();
    mesh_ = std::move(mesh).value();
    ModelReconstructionReport& report = report_.reconstruction.emplace();
    report.method = mesh_->method;
    report.voxel_size = mesh_->voxel_size;
    report.vertices = mesh_->mesh.vertices.size();
    report.triangles = mesh_->mesh.triangles.size();
    report.seconds = mesh_->seconds;
    report.artifact = "mesh.ply";
    ++steps_done_;
    return Artifact("mesh.ply", kPlyMediaType, EncodeMeshPly(mesh_->mesh),
                    "mesh.ply written: " + mesh_->method + ", " + std::to_string(report.triangles) + " triangles");
  }

  Status Evaluate() {
    if (!truth_) return FailedPrecondition("scene_id", "no ground truth to evaluate against");
    const Eigen::Vector3d up = plan_.scene->table.enabled ? plan_.scene->table.axis : Eigen::Vector3d::UnitZ();
    ASSIGN_OR_RETURN(ModelVerdict verdict, EvaluateModel(*truth_, crop_, tau_, union_,
                                                         mesh_ ? &mesh_->mesh : nullptr, up));
    ModelEvaluationReport& report = report_.evaluation.emplace(std::move(verdict.report));
    report.next_best_views_note = plan_.next_best_views_note;
    ++steps_done_;
    RETURN_IF_ERROR(Artifact("uncovered.ply", kPlyMediaType, verdict.uncovered_ply,
                             "coverage " + Rounded(report.coverage) + " at tau " + Rounded(tau_ * 1e3) + " mm"));
    report.uncovered_artifact = "uncovered.ply";
    RETURN_IF_ERROR(Artifact("coverage.png", kPngMediaType, verdict.coverage_png, "coverage.png written"));
    report.coverage_image = "coverage.png";
    if (plan_.next_best_views == 0 || Stopped()) return Status::Ok();
    return NextBestViews(verdict);
  }

  // The material the next best views judge the object's surface by: its first object's (the truth
  // merges the objects on the table, which a campaign's plan gives one material).
  StatusOr<sensor::Material> TruthMaterial() {
    for (const store::ObjectRecord& object : plan_.scene->objects) {
      if (object.object_id != truth_->object_ids.front()) continue;
      ASSIGN_OR_RETURN(const store::MeshRecord mesh, context_.registry.catalogue().GetMesh(object.mesh_id));
      return scenes::EffectiveMaterial(object, mesh);
    }
    return sensor::DefaultMaterial();
  }

  Status NextBestViews(const ModelVerdict& verdict) {
    ModelEvaluationReport& report = *report_.evaluation;
    NextBestViewRequest request;
    request.mount_id = plan_.mount_id;
    request.count = plan_.next_best_views;
    request.tau = tau_;
    request.truth = &truth_->mesh;
    request.samples = verdict.samples;
    request.covered = verdict.covered;
    request.centre = truth_->centre;
    request.table = plan_.scene->table;
    std::optional<sensor::PinholeCamera> camera;
    for (size_t i = 0; i < aligned_->scans.size(); ++i) {
      if (!aligned_->scans[i].aligned) continue;
      request.scan_poses.push_back(aligned_->scans[i].model_from_sensor);
      if (!camera && plan_.clouds[i].record.camera) camera = CameraFromRecord(*plan_.clouds[i].record.camera);
    }
    if (!camera) {
      report.next_best_views_note = "no scan names its camera, so what a new view would see is unknown";
      return Status::Ok();
    }
    request.camera = *camera;
    if (plan_.returned_light) {
      ASSIGN_OR_RETURN(const sensor::Material material, TruthMaterial());
      request.light = evaluation::MeasurableLight{plan_.returned_light->emitter, plan_.returned_light->pixel, material,
                                                  plan_.returned_light->ambient_irradiance_w_per_m2};
    }
    auto proposed = ProposeNextBestViews(context_.robots, request, cancel());
    if (!proposed.ok()) return Stopped() ? Stop() : proposed.status();
    report.next_best_views = proposed->views;
    if (!proposed->note.empty()) report.next_best_views_note = proposed->note;
    ++steps_done_;
    std::string message = std::to_string(proposed->views.size()) + " next best views of " +
                          std::to_string(proposed->candidates) + " reachable candidates";
    if (!proposed->views.empty()) message += ", coverage up to " + Rounded(proposed->views.back().coverage_after);
    return Event(message);
  }

  ServiceContext& context_;
  const StoredClouds clouds_;
  JobRecorder& recorder_;
  const std::string job_id_;
  ModelPlan plan_;
  jobs::JobControl& control_;
  uint32_t steps_done_ = 0;
  uint32_t step_base_ = 0;
  std::optional<ModelAligner> aligner_;
  ModelReport report_;
  std::optional<ModelGroundTruth> truth_;
  ModelCrop crop_;
  double size_ = 0;
  double tau_ = 0;
  std::optional<AlignedScans> aligned_;
  std::optional<PlacedScans> placed_;
  std::vector<Eigen::Vector3f> union_;
  std::optional<ModelMesh> mesh_;
};

uint32_t ModelStepsTotal(const ModelPlan& plan) {
  return static_cast<uint32_t>(plan.clouds.size()) + 1 + (plan.reconstruct ? 1 : 0) + (plan.evaluate ? 1 : 0) +
         (plan.evaluate && plan.next_best_views > 0 ? 1 : 0);
}

void RunModel(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const ModelPlan& plan,
              jobs::JobControl& control) {
  ModelRun(context, recorder, job_id, plan, control).Run();
}

uint32_t CampaignModelSteps(const ModelPlan& plan) {
  return ModelStepsTotal(plan) - static_cast<uint32_t>(plan.clouds.size());
}

CampaignModel::CampaignModel(ServiceContext& context, JobRecorder& recorder, const std::string& job_id,
                             ModelPlan plan, jobs::JobControl& control)
    : run_(std::make_unique<ModelRun>(context, recorder, job_id, std::move(plan), control)) {
  run_->SetReportKind(std::string(JobKindName(JobKind::kCampaign)));
}
CampaignModel::~CampaignModel() = default;

Status CampaignModel::Prepare() { return run_->Prepare(); }

Status CampaignModel::AlignCaptured(ModelCloud cloud, const PointCloud& points, uint32_t steps_done) {
  run_->SetStepBase(steps_done);
  return run_->AlignCaptured(std::move(cloud), points);
}

Status CampaignModel::Complete(uint32_t steps_done) {
  run_->SetStepBase(steps_done);
  return run_->Complete();
}

void CampaignModel::WriteReport(store::JobState state) { run_->WriteReport(state); }

std::string CampaignModel::Summary() const { return run_->Summary(); }

const ModelPlan& CampaignModel::plan() const { return run_->plan(); }

}  // namespace vscan::service
