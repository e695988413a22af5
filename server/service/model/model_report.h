#pragma once
// model.json: what a model job did and found, section by section (alignment, reconstruction,
// evaluation); a section that did not run is left out. The job's ReportWriter prints it as
// proto/vscan/v1/reports.proto's ModelReport.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "evaluation/metrics.h"
#include "service/job/job_events.h"
#include "service/model/model_crop.h"
#include "service/job/job_kind.h"

namespace vscan::service {

struct ModelAlignmentReport {
  std::string initial_pose;  // "known", "features" or "known+features"
  double voxel_size = 0;
  bool pose_graph = true;
  double seconds = 0;
  std::vector<ScanAlignmentRecord> scans;
  std::string artifact;
};

struct ModelReconstructionReport {
  std::string method;  // "tsdf" or "poisson"
  double voxel_size = 0;
  size_t vertices = 0;
  size_t triangles = 0;
  double seconds = 0;
  std::string artifact;
};

struct NextBestViewReport {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world, table at table_angle_deg
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  double table_angle_deg = 0;
  double coverage_gain = 0;
  double coverage_after = 0;
};

struct ModelEvaluationReport {
  double tau = 0;
  std::vector<std::string> objects;
  double area_m2 = 0;
  size_t samples = 0;
  evaluation::Evaluation union_metrics;
  std::optional<evaluation::Evaluation> mesh_metrics;
  double coverage = 0;
  std::string uncovered_artifact;
  std::string coverage_image;
  std::vector<NextBestViewReport> next_best_views;
  std::string next_best_views_note;
  double seconds = 0;
};

struct ModelReport {
  std::string job_id;
  std::string kind{JobKindName(JobKind::kModel)};
  std::string state;
  std::string scene_id;
  size_t clouds = 0;
  ModelCrop crop;
  std::optional<ModelAlignmentReport> alignment;
  std::optional<ModelReconstructionReport> reconstruction;
  std::optional<ModelEvaluationReport> evaluation;
};

// Mean and largest of a per-scan figure over the scans that have it: the final errors over the
// aligned scans, the initial ones over all.
struct ErrorSummary {
  size_t count = 0;
  double mean = 0;
  double max = 0;
};
ErrorSummary SummariseFinalRotation(const std::vector<ScanAlignmentRecord>& scans);
ErrorSummary SummariseFinalTranslation(const std::vector<ScanAlignmentRecord>& scans);
ErrorSummary SummariseInitialRotation(const std::vector<ScanAlignmentRecord>& scans);
ErrorSummary SummariseInitialTranslation(const std::vector<ScanAlignmentRecord>& scans);

}  // namespace vscan::service
