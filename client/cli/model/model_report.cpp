#include "model/model_report.h"

#include <cstdio>
#include <vector>

#include "session/text_format.h"
#include "vscan/common/report_json.h"

namespace vscan::cli {
namespace {

std::string Pad(const std::string& text, size_t width) {
  return text.size() >= width ? text : std::string(width - text.size(), ' ') + text;
}

std::string Mm(double metres) { return Format("%.3f", metres * 1000.0); }
std::string Percent(double share) { return Format("%.1f %%", share * 100.0); }
std::string Count(double n) { return Format("%.0f", n); }

std::string Point(const google::protobuf::RepeatedField<double>& xyz) {
  if (xyz.size() != 3) return "?";
  std::string out;
  for (int i = 0; i < 3; ++i) out += (i ? ", " : "") + Format("%.3f", xyz[i]);
  return out;
}

// "mean 0.012, max 0.034" of a figure's summary, scaled.
std::string MeanMax(const v1::ModelReportErrorSummary& stats, double scale, const char* format) {
  return std::string("mean ") + Format(format, stats.mean() * scale) + ", max " + Format(format, stats.max() * scale);
}

// A figure a report leaves at zero was not measured (a hand-made or older report's missing key).
void AppendHeader(const v1::ModelReport& report, std::string* out) {
  std::string line;
  if (report.clouds() > 0) line += Count(report.clouds()) + " clouds";
  if (!report.scene_id().empty()) line += " of scene " + report.scene_id();
  if (!report.frame().empty()) line += ", in the " + report.frame();
  if (report.has_crop()) line += "; crop: " + report.crop().kind();
  if (!line.empty()) *out += line + '\n';
}

void AppendAlignment(const v1::ModelReportAlignment& alignment, std::string* out) {
  std::string how = alignment.initial_pose() + " initial poses";
  if (alignment.voxel_size() > 0) how += ", voxel " + Mm(alignment.voxel_size()) + " mm";
  how += alignment.pose_graph() ? ", pose graph" : ", no pose graph";
  *out += "alignment: " + Count(alignment.aligned()) + " of " + Count(alignment.aligned() + alignment.unaligned()) +
          " scans aligned (" + how + ")";
  if (alignment.seconds() > 0) *out += " in " + Format("%.1f", alignment.seconds()) + " s";
  *out += '\n';
  if (alignment.has_rotation_error_deg()) {
    *out += "  pose error:    rotation " + MeanMax(alignment.rotation_error_deg(), 1.0, "%.3f") + " deg; translation " +
            MeanMax(alignment.translation_error_m(), 1000.0, "%.3f") + " mm\n";
  }
  if (alignment.has_initial_rotation_error_deg()) {
    *out += "  started from:  rotation " + MeanMax(alignment.initial_rotation_error_deg(), 1.0, "%.3f") +
            " deg; translation " + MeanMax(alignment.initial_translation_error_m(), 1000.0, "%.3f") + " mm\n";
  }
  for (const v1::ModelReportScan& scan : alignment.scans()) {
    if (scan.aligned()) continue;
    *out += "  scan " + Count(scan.index()) + " (" + scan.cloud_id() +
            (scan.name().empty() ? "" : " '" + scan.name() + "'") + ") NOT aligned: " + scan.reason() + '\n';
  }
  if (!alignment.artifact().empty()) *out += "  aligned scans: " + alignment.artifact() + '\n';
}

void AppendReconstruction(const v1::ModelReportReconstruction& reconstruction, std::string* out) {
  *out += "reconstruction: " + reconstruction.method();
  if (reconstruction.voxel_size() > 0) *out += ", voxel " + Mm(reconstruction.voxel_size()) + " mm";
  *out += ": " + Count(reconstruction.vertices()) + " vertices, " + Count(reconstruction.triangles()) + " triangles";
  if (reconstruction.seconds() > 0) *out += " in " + Format("%.1f", reconstruction.seconds()) + " s";
  if (!reconstruction.artifact().empty()) *out += ": " + reconstruction.artifact();
  *out += '\n';
}

// Widths of the metrics table's columns after the part's name.
constexpr size_t kMetricWidths[] = {11, 9, 9, 17, 17, 12};

std::string MetricsLine(const std::string& part, const std::vector<std::string>& cells) {
  std::string line = "  " + part + std::string(part.size() < 6 ? 6 - part.size() : 0, ' ');
  for (size_t i = 0; i < cells.size(); ++i) line += Pad(cells[i], kMetricWidths[i]);
  line.erase(line.find_last_not_of(' ') + 1);
  return line + '\n';
}

void AppendMetricsRow(const std::string& part, const v1::ModelReportMetrics& m, std::string* out) {
  *out += MetricsLine(part, {Percent(m.precision()), Percent(m.recall()), Percent(m.f_score()),
                             Mm(m.accuracy_mean()) + " / " + Mm(m.accuracy_median()),
                             Mm(m.completeness_mean()) + " / " + Mm(m.completeness_median()), Mm(m.chamfer())});
}

void AppendNextBestViews(const v1::ModelReportEvaluation& evaluation, std::string* out) {
  if (evaluation.next_best_views().empty()) {
    if (!evaluation.next_best_views_note().empty()) {
      *out += "next best views: none (" + evaluation.next_best_views_note() + ")\n";
    }
    return;
  }
  *out += "next best views (world frame, table at the angle given):\n";
  int rank = 0;
  for (const v1::ModelReportNextBestView& view : evaluation.next_best_views()) {
    *out += "  " + std::to_string(++rank) + ". position " + Point(view.position()) + "  target " +
            Point(view.target()) + "  table " + Format("%.1f", view.table_angle_deg()) + " deg  +" +
            Percent(view.coverage_gain()) + " -> " + Percent(view.coverage_after()) + '\n';
  }
}

void AppendEvaluation(const v1::ModelReportEvaluation& evaluation, std::string* out) {
  *out += "evaluation at tau " + Mm(evaluation.tau()) + " mm";
  if (evaluation.has_ground_truth()) {
    const v1::ModelReportGroundTruth& truth = evaluation.ground_truth();
    const int count = truth.objects_size();
    *out += " against " + std::to_string(count) + (count == 1 ? " object" : " objects") + " (" +
            Format("%.4f", truth.area_m2()) + " m2, " + Count(truth.samples()) + " samples)";
  }
  if (evaluation.seconds() > 0) *out += " in " + Format("%.1f", evaluation.seconds()) + " s";
  *out += ":\n";
  *out += MetricsLine("part", {"precision", "recall", "F-score", "accuracy mm", "completeness mm", "Chamfer mm"});
  *out += MetricsLine("", {"", "", "", "mean / median", "mean / median", ""});
  if (evaluation.has_union_()) AppendMetricsRow("union", evaluation.union_(), out);
  if (evaluation.has_mesh()) AppendMetricsRow("mesh", evaluation.mesh(), out);
  *out += "  coverage " + Percent(evaluation.coverage());
  std::string files = evaluation.uncovered_artifact();
  if (!evaluation.coverage_image().empty()) files += (files.empty() ? "" : ", ") + evaluation.coverage_image();
  if (!files.empty()) *out += " (" + files + ")";
  *out += '\n';
  AppendNextBestViews(evaluation, out);
}

}  // namespace

StatusOr<v1::ModelReport> ParseModelReport(std::string_view text) {
  v1::ModelReport report;
  RETURN_IF_ERROR(ParseReport(text, std::string(kModelReportName), &report));
  return report;
}

std::string FormatModelReport(const v1::ModelReport& report) {
  std::string out;
  AppendHeader(report, &out);
  if (report.has_alignment()) AppendAlignment(report.alignment(), &out);
  if (report.has_reconstruction()) AppendReconstruction(report.reconstruction(), &out);
  if (report.has_evaluation()) AppendEvaluation(report.evaluation(), &out);
  return out;
}

std::string ReportJson(const google::protobuf::Message& report) {
  std::string out = PrintReport(report);
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

std::string FormatScanAlignment(const v1::ScanAlignment& alignment) {
  // A campaign aligns its scans before they are stored as clouds: its events name the scan instead.
  const std::string& id = alignment.cloud_id().empty() ? alignment.name() : alignment.cloud_id();
  std::string line = "scan " + std::to_string(alignment.index() + 1) + " " + id + ": ";
  if (!alignment.aligned()) {
    return line + "NOT aligned: " + (alignment.reason().empty() ? "no reason given" : alignment.reason());
  }
  line += "fitness " + Format("%.3f", alignment.fitness()) + ", rmse " + Mm(alignment.inlier_rmse()) + " mm";
  if (alignment.has_error()) {
    line += ", rot err " + Format("%.3f", alignment.rotation_error_deg()) + " deg, trans err " +
            Mm(alignment.translation_error_m()) + " mm";
  }
  if (alignment.union_points() > 0) line += ", union " + std::to_string(alignment.union_points()) + " points";
  return line;
}

}  // namespace vscan::cli
