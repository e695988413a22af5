#include <algorithm>

#include "api/reports/report_convert.h"

namespace vscan::api {
namespace {

void Summary(const service::ErrorSummary& s, v1::ModelReportErrorSummary* out) {
  out->set_mean(s.mean);
  out->set_max(s.max);
}

void Crop(const service::ModelCrop& crop, v1::ModelReportCrop* out) {
  switch (crop.kind) {
    case service::ModelCrop::Kind::kNone: out->set_kind("none"); break;
    case service::ModelCrop::Kind::kBounds:
      out->set_kind("bounds");
      SetList(Eigen::VectorXd(crop.box.min), out->mutable_min());
      SetList(Eigen::VectorXd(crop.box.max), out->mutable_max());
      break;
    case service::ModelCrop::Kind::kCylinder:
      out->set_kind("cylinder");
      SetList(Eigen::VectorXd(crop.base), out->mutable_base());
      SetList(Eigen::VectorXd(crop.axis), out->mutable_axis());
      out->set_radius(crop.radius);
      out->set_height(crop.height);
      break;
  }
}

void Scan(const service::ScanAlignmentRecord& s, v1::ModelReportScan* out) {
  out->set_index(s.index);
  out->set_cloud_id(s.cloud_id);
  out->set_name(s.name);
  out->set_aligned(s.aligned);
  out->set_reason(s.reason);
  out->set_fitness(s.fitness);
  out->set_inlier_rmse(s.inlier_rmse);
  AddMatrix(s.model_from_sensor, out->mutable_pose());
  if (!s.has_error) return;
  out->set_rotation_error_deg(s.rotation_error_deg);
  out->set_translation_error_m(s.translation_error_m);
  out->set_initial_rotation_error_deg(s.initial_rotation_error_deg);
  out->set_initial_translation_error_m(s.initial_translation_error_m);
}

void Alignment(const service::ModelAlignmentReport& a, v1::ModelReportAlignment* out) {
  out->set_initial_pose(a.initial_pose);
  out->set_voxel_size(a.voxel_size);
  out->set_pose_graph(a.pose_graph);
  out->set_seconds(a.seconds);
  const auto aligned = std::count_if(a.scans.begin(), a.scans.end(),
                                     [](const service::ScanAlignmentRecord& s) { return s.aligned; });
  out->set_aligned(static_cast<uint32_t>(aligned));
  out->set_unaligned(static_cast<uint32_t>(a.scans.size() - static_cast<size_t>(aligned)));
  if (const service::ErrorSummary rotation = service::SummariseFinalRotation(a.scans); rotation.count > 0) {
    Summary(rotation, out->mutable_rotation_error_deg());
    Summary(service::SummariseFinalTranslation(a.scans), out->mutable_translation_error_m());
  }
  if (const service::ErrorSummary rotation = service::SummariseInitialRotation(a.scans); rotation.count > 0) {
    Summary(rotation, out->mutable_initial_rotation_error_deg());
    Summary(service::SummariseInitialTranslation(a.scans), out->mutable_initial_translation_error_m());
  }
  for (const service::ScanAlignmentRecord& s : a.scans) Scan(s, out->add_scans());
  out->set_artifact(a.artifact);
}

void Reconstruction(const service::ModelReconstructionReport& r, v1::ModelReportReconstruction* out) {
  out->set_method(r.method);
  out->set_voxel_size(r.voxel_size);
  out->set_vertices(static_cast<uint32_t>(r.vertices));
  out->set_triangles(static_cast<uint32_t>(r.triangles));
  out->set_seconds(r.seconds);
  out->set_artifact(r.artifact);
}

void Metrics(const evaluation::Evaluation& e, v1::ModelReportMetrics* out) {
  out->set_precision(e.precision);
  out->set_recall(e.recall);
  out->set_f_score(e.f_score);
  out->set_accuracy_mean(e.accuracy.mean);
  out->set_accuracy_median(e.accuracy.median);
  out->set_completeness_mean(e.completeness.mean);
  out->set_completeness_median(e.completeness.median);
  out->set_chamfer(e.chamfer);
}

void Evaluation(const service::ModelEvaluationReport& e, v1::ModelReportEvaluation* out) {
  out->set_tau(e.tau);
  v1::ModelReportGroundTruth* truth = out->mutable_ground_truth();
  for (const std::string& id : e.objects) truth->add_objects(id);
  truth->set_area_m2(e.area_m2);
  truth->set_samples(static_cast<uint32_t>(e.samples));
  Metrics(e.union_metrics, out->mutable_union_());
  if (e.mesh_metrics) Metrics(*e.mesh_metrics, out->mutable_mesh());
  out->set_coverage(e.coverage);
  if (!e.uncovered_artifact.empty()) out->set_uncovered_artifact(e.uncovered_artifact);
  if (!e.coverage_image.empty()) out->set_coverage_image(e.coverage_image);
  for (const service::NextBestViewReport& v : e.next_best_views) {
    v1::ModelReportNextBestView* view = out->add_next_best_views();
    AddVector(v.position, view->mutable_position());
    AddVector(v.target, view->mutable_target());
    view->set_table_angle_deg(v.table_angle_deg);
    view->set_coverage_gain(v.coverage_gain);
    view->set_coverage_after(v.coverage_after);
  }
  if (!e.next_best_views_note.empty()) out->set_next_best_views_note(e.next_best_views_note);
  out->set_seconds(e.seconds);
}

}  // namespace

v1::ModelReport ModelReportMessage(const service::ModelReport& report) {
  v1::ModelReport out;
  out.set_job_id(report.job_id);
  out.set_kind(report.kind);
  out.set_state(report.state);
  out.set_frame("model (world, table at 0 deg)");
  out.set_scene_id(report.scene_id);
  out.set_clouds(static_cast<uint32_t>(report.clouds));
  Crop(report.crop, out.mutable_crop());
  if (report.alignment) Alignment(*report.alignment, out.mutable_alignment());
  if (report.reconstruction) Reconstruction(*report.reconstruction, out.mutable_reconstruction());
  if (report.evaluation) Evaluation(*report.evaluation, out.mutable_evaluation());
  return out;
}

}  // namespace vscan::api
