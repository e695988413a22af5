#include "bins/bin_report.h"

#include <cstdio>

#include <google/protobuf/util/json_util.h>

#include "model/model_fetch.h"
#include "session/text_format.h"

namespace vscan::cli {
namespace {

using google::protobuf::Struct;
using google::protobuf::Value;

double NumberOr(const Struct& object, const char* key) {
  const auto it = object.fields().find(key);
  return it != object.fields().end() && it->second.kind_case() == Value::kNumberValue ? it->second.number_value() : 0;
}

std::string Text(const Struct& object, const char* key) {
  const auto it = object.fields().find(key);
  return it != object.fields().end() && it->second.kind_case() == Value::kStringValue ? it->second.string_value() : "";
}

}  // namespace

int FetchBinReport(Context& ctx, const v1::Job& job, std::optional<Struct>* report) {
  std::optional<std::string> text;
  if (const int rc = FetchArtifactText(ctx, job, "bin.json", &text); rc != kExitOk || !text) return rc;
  Struct parsed;
  const auto status = google::protobuf::util::JsonStringToMessage(*text, &parsed);
  if (!status.ok()) return ctx.ServerError(DataLoss("bin.json: not a JSON object: " + std::string(status.message())));
  *report = std::move(parsed);
  return kExitOk;
}

std::string FormatBinReport(const Struct& report) {
  const std::string end = Text(report, "end");
  if (end.empty()) return "the fill did not run to an end: " + Text(report, "message") + "\n";
  std::string out = end + ": " + Format("%.0f", NumberOr(report, "in_bin")) + " of " +
                    Format("%.0f", NumberOr(report, "parts_asked")) + " parts in the bin, " +
                    Format("%.0f", NumberOr(report, "spawned") - NumberOr(report, "in_bin")) + " fell out; " +
                    Format("%.2f", NumberOr(report, "simulated_s")) + " s simulated in " +
                    Format("%.0f", NumberOr(report, "steps")) + " steps (" + Text(report, "end_message") + ")\n";
  out += "deepest overlap: part-part " + Format("%.2f", NumberOr(report, "max_part_part_penetration_m") * 1e3) +
         " mm, part-bin " + Format("%.2f", NumberOr(report, "max_part_bin_penetration_m") * 1e3) + " mm; wall time " +
         Format("%.2f", NumberOr(report, "setup_wall_s") + NumberOr(report, "step_wall_s")) + " s\n";
  const auto applied = report.fields().find("applied");
  if (applied != report.fields().end() && applied->second.bool_value()) {
    out += "scene " + Text(report, "scene_id") + " revision " + Format("%.0f", NumberOr(report, "scene_revision")) +
           ": the bin and its parts are objects of the scene\n";
  } else {
    out += "scene " + Text(report, "scene_id") + " unchanged\n";
  }
  return out;
}

}  // namespace vscan::cli
