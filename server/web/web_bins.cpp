#include "web/web_bins.h"

#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "api/job/job_tracker.h"
#include "service/job/job_kind.h"
#include "store/blob_store.h"
#include "vscan/common/json_quote.h"
#include "web/web_json.h"
#include "vscan/common/report_json.h"
#include "vscan/v1/job.pb.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::web {
namespace {

constexpr std::string_view kReport = "bin.json";
constexpr std::string_view kReplay = "bin_replay.bin";

void Key(std::string& out, std::string_view key) {
  if (out.back() != '{') out += ',';
  out += JsonQuote(key);
  out += ':';
}

void String(std::string& out, std::string_view key, std::string_view value) {
  Key(out, key);
  out += JsonQuote(value);
}

void Real(std::string& out, std::string_view key, double value) {
  Key(out, key);
  AppendJsonNumber(out, value);
}

// 16 row-major numbers as 4 rows of 4 (the scene API's matrices); null unless there are 16.
void Matrix(std::string& out, std::string_view key, const google::protobuf::RepeatedField<double>& values) {
  Key(out, key);
  if (values.size() != 16) {
    out += "null";
    return;
  }
  out += '[';
  for (int r = 0; r < 4; ++r) {
    out += r ? ",[" : "[";
    for (int c = 0; c < 4; ++c) {
      if (c) out += ',';
      AppendJsonNumber(out, values[r * 4 + c]);
    }
    out += ']';
  }
  out += ']';
}

void List(std::string& out, std::string_view key, const google::protobuf::ListValue& list) {
  Key(out, key);
  out += '[';
  for (int i = 0; i < list.values_size(); ++i) {
    if (i) out += ',';
    AppendJsonNumber(out, list.values(i).number_value());
  }
  out += ']';
}

void Bin(std::string& out, const v1::BinReportBin& bin) {
  Key(out, "bin");
  out += '{';
  // A box bin's mesh (made when the pile was placed) is drawn from its sizes; a mesh bin is its mesh.
  const bool box = bin.inner_size().values_size() == 3;
  String(out, "kind", box ? "box" : "mesh");
  if (box) {
    List(out, "inner_size", bin.inner_size());
    Real(out, "wall_thickness", bin.wall_thickness());
  } else {
    List(out, "bounds_min", bin.bounds_min());
    List(out, "bounds_max", bin.bounds_max());
    Real(out, "scale", bin.has_scale() ? bin.scale() : 1.0);
  }
  String(out, "mesh_id", bin.mesh_id());
  Matrix(out, "world_from_bin", bin.world_from_bin());
  String(out, "object_id", bin.object_id());
  if (bin.has_instance_id()) Real(out, "instance_id", bin.instance_id());
  String(out, "label", bin.label());
  out += '}';
}

std::string BinJson(const store::JobRecord& job, const std::optional<v1::BinReport>& report, bool replay) {
  std::string out = "{";
  String(out, "job_id", job.job_id);
  String(out, "name", job.name);
  String(out, "state", store::JobStateName(job.state));
  String(out, "message", job.message);
  Real(out, "steps_done", job.steps_done);
  Real(out, "steps_total", job.steps_total);
  Key(out, "replay");
  out += replay ? "true" : "false";
  Key(out, "report");
  out += report ? "true" : "false";
  if (!report) {
    out += ",\"bin\":null,\"types\":[],\"parts\":[],\"outside\":[]}";
    return out;
  }
  String(out, "scene_id", report->scene_id());
  Key(out, "applied");
  out += report->applied() ? "true" : "false";
  if (report->has_scene_revision()) Real(out, "scene_revision", report->scene_revision());
  if (report->has_end()) String(out, "end", report->end());
  if (report->has_simulated_s()) Real(out, "simulated_s", report->simulated_s());
  Bin(out, report->bin());
  Key(out, "types");
  out += '[';
  for (int i = 0; i < report->types_size(); ++i) {
    const v1::BinReportType& type = report->types(i);
    out += i ? ",{" : "{";
    Real(out, "type", type.type());
    String(out, "name", type.name());
    String(out, "mesh_id", type.mesh_id());
    Real(out, "scale", type.scale());
    Real(out, "count", type.count());
    out += '}';
  }
  out += ']';
  Key(out, "parts");
  out += '[';
  for (int i = 0; i < report->parts_size(); ++i) {
    const v1::BinReportPart& part = report->parts(i);
    out += i ? ",{" : "{";
    Real(out, "type", part.type());
    String(out, "name", part.name());
    Real(out, "instance", part.instance());
    String(out, "label", part.label());
    String(out, "mesh_id", part.mesh_id());
    Real(out, "scale", part.scale());
    String(out, "object_id", part.object_id());
    Key(out, "instance_id");
    if (part.has_instance_id()) {
      AppendJsonNumber(out, part.instance_id());
    } else {
      out += "null";
    }
    Matrix(out, "world_from_part", part.world_from_part());
    out += '}';
  }
  out += ']';
  Key(out, "outside");
  out += '[';
  for (int i = 0; i < report->outside_size(); ++i) {
    const v1::BinReportOutside& part = report->outside(i);
    out += i ? ",{" : "{";
    Real(out, "type", part.type());
    String(out, "name", part.name());
    Real(out, "instance", part.instance());
    out += '}';
  }
  out += "]}";
  return out;
}

// The newest artifact of that name, or null.
const store::ArtifactRecord* Artifact(const store::JobRecord& job, std::string_view name) {
  const store::ArtifactRecord* found = nullptr;
  for (const store::ArtifactRecord& artifact : job.artifacts) {
    if (artifact.name == name) found = &artifact;
  }
  return found;
}

}  // namespace

WebReply ServeBins(const WebSources& sources, const WebRequest& request) {
  if (!sources.jobs) return TextReply(404, "bin fills are not served");
  const auto& segments = request.segments;
  const bool replay = segments.size() == 3 && segments[2] == "replay";
  if (segments.size() < 2 || !IsId(segments[1]) || (segments.size() == 3 && !replay) || segments.size() > 3) {
    return TextReply(404, fmt::format("no bin fill '{}'", segments.size() > 1 ? segments[1] : ""));
  }
  const std::string job_id(segments[1]);
  auto job = sources.jobs->catalogue().GetJob(job_id);
  if (!job.ok()) return FromStatus(job.status());
  if (job->kind != service::JobKindName(service::JobKind::kBinFill)) {
    return TextReply(404, fmt::format("job '{}' is a {} job, not a bin fill", job_id, job->kind));
  }
  store::BlobStore& blobs = sources.jobs->blobs();
  if (replay) {
    const store::ArtifactRecord* artifact = Artifact(*job, kReplay);
    if (!artifact) return TextReply(404, fmt::format("bin fill {} recorded no replay", job_id));
    auto bytes = blobs.Get(artifact->sha256);
    if (!bytes.ok()) return FromStatus(bytes.status());
    return {200, kBinaryType, std::move(bytes).value(), {}};
  }
  std::optional<v1::BinReport> report;
  if (const store::ArtifactRecord* artifact = Artifact(*job, kReport)) {
    auto text = blobs.Get(artifact->sha256);
    if (!text.ok()) return FromStatus(text.status());
    report.emplace();
    const Status parsed = ParseReport(*text, std::string(kReport), &*report);
    if (!parsed.ok()) return FromStatus(parsed);
  }
  return JsonReply(BinJson(*job, report, Artifact(*job, kReplay) != nullptr));
}

}  // namespace vscan::web
