#include "service/model/model_report.h"

#include <algorithm>

#include "service/job/json_writer.h"

namespace vscan::service {
namespace {

template <typename Get>
ErrorSummary Summarise(const std::vector<ScanAlignmentRecord>& scans, bool aligned_only, Get get) {
  ErrorSummary s;
  for (const ScanAlignmentRecord& scan : scans) {
    if (!scan.has_error || (aligned_only && !scan.aligned)) continue;
    const double x = get(scan);
    s.mean += x;
    s.max = std::max(s.max, x);
    ++s.count;
  }
  if (s.count) s.mean /= static_cast<double>(s.count);
  return s;
}

void Summary(JsonWriter& json, const char* key, const ErrorSummary& s) {
  json.Key(key).Open('{').Key("mean").Value(s.mean).Key("max").Value(s.max).Close('}');
}

void Crop(JsonWriter& json, const ModelCrop& crop) {
  json.Key("crop").Open('{');
  switch (crop.kind) {
    case ModelCrop::Kind::kNone: json.Key("kind").Value("none"); break;
    case ModelCrop::Kind::kBounds:
      json.Key("kind").Value("bounds");
      json.Key("min").Vector(crop.box.min);
      json.Key("max").Vector(crop.box.max);
      break;
    case ModelCrop::Kind::kCylinder:
      json.Key("kind").Value("cylinder");
      json.Key("base").Vector(crop.base);
      json.Key("axis").Vector(crop.axis);
      json.Key("radius").Value(crop.radius);
      json.Key("height").Value(crop.height);
      break;
  }
  json.Close('}');
}

void Alignment(JsonWriter& json, const ModelAlignmentReport& a) {
  json.Key("alignment").Open('{');
  json.Key("initial_pose").Value(a.initial_pose);
  json.Key("voxel_size").Value(a.voxel_size);
  json.Key("pose_graph").Value(a.pose_graph);
  json.Key("seconds").Value(a.seconds);
  const auto aligned = static_cast<uint64_t>(
      std::count_if(a.scans.begin(), a.scans.end(), [](const ScanAlignmentRecord& s) { return s.aligned; }));
  json.Key("aligned").Value(aligned);
  json.Key("unaligned").Value(uint64_t{a.scans.size()} - aligned);
  if (SummariseFinalRotation(a.scans).count > 0) {
    Summary(json, "rotation_error_deg", SummariseFinalRotation(a.scans));
    Summary(json, "translation_error_m", SummariseFinalTranslation(a.scans));
  }
  const auto initial_rotation =
      Summarise(a.scans, false, [](const ScanAlignmentRecord& s) { return s.initial_rotation_error_deg; });
  if (initial_rotation.count > 0) {
    Summary(json, "initial_rotation_error_deg", initial_rotation);
    Summary(json, "initial_translation_error_m",
            Summarise(a.scans, false, [](const ScanAlignmentRecord& s) { return s.initial_translation_error_m; }));
  }
  json.Key("scans").Open('[');
  for (const ScanAlignmentRecord& s : a.scans) {
    json.Open('{');
    json.Key("index").Value(uint64_t{s.index});
    json.Key("cloud_id").Value(s.cloud_id);
    json.Key("name").Value(s.name);
    json.Key("aligned").Value(s.aligned);
    json.Key("reason").Value(s.reason);
    json.Key("fitness").Value(s.fitness);
    json.Key("inlier_rmse").Value(s.inlier_rmse);
    json.Key("pose").Matrix(s.model_from_sensor);
    if (s.has_error) {
      json.Key("rotation_error_deg").Value(s.rotation_error_deg);
      json.Key("translation_error_m").Value(s.translation_error_m);
      json.Key("initial_rotation_error_deg").Value(s.initial_rotation_error_deg);
      json.Key("initial_translation_error_m").Value(s.initial_translation_error_m);
    }
    json.Close('}');
  }
  json.Close(']');
  json.Key("artifact").Value(a.artifact);
  json.Close('}');
}

void Reconstruction(JsonWriter& json, const ModelReconstructionReport& r) {
  json.Key("reconstruction").Open('{');
  json.Key("method").Value(r.method);
  json.Key("voxel_size").Value(r.voxel_size);
  json.Key("vertices").Value(uint64_t{r.vertices});
  json.Key("triangles").Value(uint64_t{r.triangles});
  json.Key("seconds").Value(r.seconds);
  json.Key("artifact").Value(r.artifact);
  json.Close('}');
}

void Metrics(JsonWriter& json, const char* key, const evaluation::Evaluation& e) {
  json.Key(key).Open('{');
  json.Key("precision").Value(e.precision);
  json.Key("recall").Value(e.recall);
  json.Key("f_score").Value(e.f_score);
  json.Key("accuracy_mean").Value(e.accuracy.mean);
  json.Key("accuracy_median").Value(e.accuracy.median);
  json.Key("completeness_mean").Value(e.completeness.mean);
  json.Key("completeness_median").Value(e.completeness.median);
  json.Key("chamfer").Value(e.chamfer);
  json.Close('}');
}

void Evaluation(JsonWriter& json, const ModelEvaluationReport& e) {
  json.Key("evaluation").Open('{');
  json.Key("tau").Value(e.tau);
  json.Key("ground_truth").Open('{');
  json.Key("objects").Open('[');
  for (const std::string& id : e.objects) json.Value(id);
  json.Close(']');
  json.Key("area_m2").Value(e.area_m2);
  json.Key("samples").Value(uint64_t{e.samples});
  json.Close('}');
  Metrics(json, "union", e.union_metrics);
  if (e.mesh_metrics) Metrics(json, "mesh", *e.mesh_metrics);
  json.Key("coverage").Value(e.coverage);
  if (!e.uncovered_artifact.empty()) json.Key("uncovered_artifact").Value(e.uncovered_artifact);
  if (!e.coverage_image.empty()) json.Key("coverage_image").Value(e.coverage_image);
  json.Key("next_best_views").Open('[');
  for (const NextBestViewReport& v : e.next_best_views) {
    json.Open('{');
    json.Key("position").Vector(v.position);
    json.Key("target").Vector(v.target);
    json.Key("table_angle_deg").Value(v.table_angle_deg);
    json.Key("coverage_gain").Value(v.coverage_gain);
    json.Key("coverage_after").Value(v.coverage_after);
    json.Close('}');
  }
  json.Close(']');
  if (!e.next_best_views_note.empty()) json.Key("next_best_views_note").Value(e.next_best_views_note);
  json.Key("seconds").Value(e.seconds);
  json.Close('}');
}

}  // namespace

ErrorSummary SummariseFinalRotation(const std::vector<ScanAlignmentRecord>& scans) {
  return Summarise(scans, true, [](const ScanAlignmentRecord& s) { return s.rotation_error_deg; });
}

ErrorSummary SummariseFinalTranslation(const std::vector<ScanAlignmentRecord>& scans) {
  return Summarise(scans, true, [](const ScanAlignmentRecord& s) { return s.translation_error_m; });
}

std::string ModelReportJson(const ModelReport& report) {
  JsonWriter json;
  json.Open('{');
  json.Key("job_id").Value(report.job_id);
  json.Key("kind").Value(report.kind);
  json.Key("state").Value(report.state);
  json.Key("frame").Value("model (world, table at 0 deg)");
  json.Key("scene_id").Value(report.scene_id);
  json.Key("clouds").Value(uint64_t{report.clouds});
  Crop(json, report.crop);
  if (report.alignment) Alignment(json, *report.alignment);
  if (report.reconstruction) Reconstruction(json, *report.reconstruction);
  if (report.evaluation) Evaluation(json, *report.evaluation);
  json.Close('}');
  return json.str() + "\n";
}

}  // namespace vscan::service
