#include "model/model_report.h"

#include <google/protobuf/util/json_util.h>

#include <cstdio>
#include <optional>
#include <vector>

#include "session/text_format.h"

namespace vscan::cli {
namespace {

using google::protobuf::ListValue;
using google::protobuf::Struct;
using google::protobuf::Value;

std::string Pad(const std::string& text, size_t width) {
  return text.size() >= width ? text : std::string(width - text.size(), ' ') + text;
}

std::string Mm(double metres) { return Format("%.3f", metres * 1000.0); }
std::string Percent(double share) { return Format("%.1f %%", share * 100.0); }

const Value* Field(const Struct& object, const char* key) {
  const auto it = object.fields().find(key);
  return it == object.fields().end() ? nullptr : &it->second;
}

std::optional<double> Number(const Struct& object, const char* key) {
  const Value* value = Field(object, key);
  if (value == nullptr || value->kind_case() != Value::kNumberValue) return std::nullopt;
  return value->number_value();
}

double NumberOr(const Struct& object, const char* key, double fallback = 0.0) {
  return Number(object, key).value_or(fallback);
}

std::string Text(const Struct& object, const char* key) {
  const Value* value = Field(object, key);
  return value != nullptr && value->kind_case() == Value::kStringValue ? value->string_value() : "";
}

bool Flag(const Struct& object, const char* key) {
  const Value* value = Field(object, key);
  return value != nullptr && value->kind_case() == Value::kBoolValue && value->bool_value();
}

const Struct* Object(const Struct& object, const char* key) {
  const Value* value = Field(object, key);
  return value != nullptr && value->kind_case() == Value::kStructValue ? &value->struct_value() : nullptr;
}

const ListValue* List(const Struct& object, const char* key) {
  const Value* value = Field(object, key);
  return value != nullptr && value->kind_case() == Value::kListValue ? &value->list_value() : nullptr;
}

std::string Count(double n) { return Format("%.0f", n); }

std::string Point(const ListValue* xyz) {
  if (xyz == nullptr || xyz->values_size() != 3) return "?";
  std::string out;
  for (int i = 0; i < 3; ++i) out += (i ? ", " : "") + Format("%.3f", xyz->values(i).number_value());
  return out;
}

// "mean 0.012  max 0.034" of a {"mean", "max"} object, scaled.
std::string MeanMax(const Struct* stats, double scale, const char* format) {
  if (stats == nullptr) return "";
  return std::string("mean ") + Format(format, NumberOr(*stats, "mean") * scale) + ", max " +
         Format(format, NumberOr(*stats, "max") * scale);
}

void AppendHeader(const Struct& report, std::string* out) {
  std::string line;
  if (const auto clouds = Number(report, "clouds")) line += Count(*clouds) + " clouds";
  if (const std::string scene = Text(report, "scene_id"); !scene.empty()) line += " of scene " + scene;
  if (const std::string frame = Text(report, "frame"); !frame.empty()) line += ", in the " + frame;
  if (const Struct* crop = Object(report, "crop")) line += "; crop: " + Text(*crop, "kind");
  if (!line.empty()) *out += line + '\n';
}

void AppendAlignment(const Struct& alignment, std::string* out) {
  const double aligned = NumberOr(alignment, "aligned");
  const double unaligned = NumberOr(alignment, "unaligned");
  std::string how = Text(alignment, "initial_pose") + " initial poses";
  if (const auto voxel = Number(alignment, "voxel_size")) how += ", voxel " + Mm(*voxel) + " mm";
  how += Flag(alignment, "pose_graph") ? ", pose graph" : ", no pose graph";
  *out += "alignment: " + Count(aligned) + " of " + Count(aligned + unaligned) + " scans aligned (" + how + ")";
  if (const auto seconds = Number(alignment, "seconds")) *out += " in " + Format("%.1f", *seconds) + " s";
  *out += '\n';
  if (const Struct* rotation = Object(alignment, "rotation_error_deg")) {
    *out += "  pose error:    rotation " + MeanMax(rotation, 1.0, "%.3f") + " deg; translation " +
            MeanMax(Object(alignment, "translation_error_m"), 1000.0, "%.3f") + " mm\n";
  }
  if (const Struct* rotation = Object(alignment, "initial_rotation_error_deg")) {
    *out += "  started from:  rotation " + MeanMax(rotation, 1.0, "%.3f") + " deg; translation " +
            MeanMax(Object(alignment, "initial_translation_error_m"), 1000.0, "%.3f") + " mm\n";
  }
  if (const ListValue* scans = List(alignment, "scans")) {
    for (const Value& item : scans->values()) {
      if (item.kind_case() != Value::kStructValue || Flag(item.struct_value(), "aligned")) continue;
      const Struct& scan = item.struct_value();
      const std::string name = Text(scan, "name");
      *out += "  scan " + Count(NumberOr(scan, "index")) + " (" + Text(scan, "cloud_id") +
              (name.empty() ? "" : " '" + name + "'") + ") NOT aligned: " + Text(scan, "reason") + '\n';
    }
  }
  if (const std::string artifact = Text(alignment, "artifact"); !artifact.empty()) {
    *out += "  aligned scans: " + artifact + '\n';
  }
}

void AppendReconstruction(const Struct& reconstruction, std::string* out) {
  *out += "reconstruction: " + Text(reconstruction, "method");
  if (const auto voxel = Number(reconstruction, "voxel_size")) *out += ", voxel " + Mm(*voxel) + " mm";
  *out += ": " + Count(NumberOr(reconstruction, "vertices")) + " vertices, " +
          Count(NumberOr(reconstruction, "triangles")) + " triangles";
  if (const auto seconds = Number(reconstruction, "seconds")) *out += " in " + Format("%.1f", *seconds) + " s";
  if (const std::string artifact = Text(reconstruction, "artifact"); !artifact.empty()) *out += ": " + artifact;
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

void AppendMetricsRow(const std::string& part, const Struct& metrics, std::string* out) {
  const auto pair = [&](const char* mean, const char* median) {
    return Mm(NumberOr(metrics, mean)) + " / " + Mm(NumberOr(metrics, median));
  };
  *out += MetricsLine(part, {Percent(NumberOr(metrics, "precision")), Percent(NumberOr(metrics, "recall")),
                             Percent(NumberOr(metrics, "f_score")), pair("accuracy_mean", "accuracy_median"),
                             pair("completeness_mean", "completeness_median"), Mm(NumberOr(metrics, "chamfer"))});
}

void AppendNextBestViews(const Struct& evaluation, std::string* out) {
  const ListValue* views = List(evaluation, "next_best_views");
  if (views == nullptr || views->values_size() == 0) {
    const std::string note = Text(evaluation, "next_best_views_note");
    if (!note.empty()) *out += "next best views: none (" + note + ")\n";
    return;
  }
  *out += "next best views (world frame, table at the angle given):\n";
  int rank = 0;
  for (const Value& item : views->values()) {
    if (item.kind_case() != Value::kStructValue) continue;
    const Struct& view = item.struct_value();
    *out += "  " + std::to_string(++rank) + ". position " + Point(List(view, "position")) + "  target " +
            Point(List(view, "target")) + "  table " + Format("%.1f", NumberOr(view, "table_angle_deg")) +
            " deg  +" + Percent(NumberOr(view, "coverage_gain")) + " -> " +
            Percent(NumberOr(view, "coverage_after")) + '\n';
  }
}

void AppendEvaluation(const Struct& evaluation, std::string* out) {
  *out += "evaluation at tau " + Mm(NumberOr(evaluation, "tau")) + " mm";
  if (const Struct* truth = Object(evaluation, "ground_truth")) {
    const ListValue* objects = List(*truth, "objects");
    const int count = objects == nullptr ? 0 : objects->values_size();
    *out += " against " + std::to_string(count) + (count == 1 ? " object" : " objects") + " (" +
            Format("%.4f", NumberOr(*truth, "area_m2")) + " m2, " + Count(NumberOr(*truth, "samples")) +
            " samples)";
  }
  if (const auto seconds = Number(evaluation, "seconds")) *out += " in " + Format("%.1f", *seconds) + " s";
  *out += ":\n";
  *out += MetricsLine("part", {"precision", "recall", "F-score", "accuracy mm", "completeness mm", "Chamfer mm"});
  *out += MetricsLine("", {"", "", "", "mean / median", "mean / median", ""});
  if (const Struct* metrics = Object(evaluation, "union")) AppendMetricsRow("union", *metrics, out);
  if (const Struct* metrics = Object(evaluation, "mesh")) AppendMetricsRow("mesh", *metrics, out);
  if (const auto coverage = Number(evaluation, "coverage")) {
    *out += "  coverage " + Percent(*coverage);
    std::string files = Text(evaluation, "uncovered_artifact");
    if (const std::string image = Text(evaluation, "coverage_image"); !image.empty()) {
      files += (files.empty() ? "" : ", ") + image;
    }
    if (!files.empty()) *out += " (" + files + ")";
    *out += '\n';
  }
  AppendNextBestViews(evaluation, out);
}

}  // namespace

StatusOr<Struct> ParseModelReport(std::string_view text) {
  Struct report;
  const auto parsed = google::protobuf::util::JsonStringToMessage(std::string(text), &report);
  if (!parsed.ok()) return DataLoss("model.json: not a JSON object: " + std::string(parsed.message()));
  return report;
}

std::string FormatModelReport(const Struct& report) {
  std::string out;
  AppendHeader(report, &out);
  if (const Struct* alignment = Object(report, "alignment")) AppendAlignment(*alignment, &out);
  if (const Struct* reconstruction = Object(report, "reconstruction")) AppendReconstruction(*reconstruction, &out);
  if (const Struct* evaluation = Object(report, "evaluation")) AppendEvaluation(*evaluation, &out);
  return out;
}

std::string ModelReportJson(const Struct& report) {
  std::string out;
  if (!google::protobuf::util::MessageToJsonString(report, &out).ok()) return "null";
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
