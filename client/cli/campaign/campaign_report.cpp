#include "campaign/campaign_report.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <numbers>

#include "session/context.h"
#include "session/text_format.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

std::string Pad(const std::string& text, size_t width, bool right) {
  if (text.size() >= width) return text;
  const std::string fill(width - text.size(), ' ');
  return right ? fill + text : text + fill;
}

void FillPoseErrors(const v1::ScanArtifactInfo& scan, CampaignStepRow* row) {
  const auto commanded = PoseFromProto(scan.commanded_sensor_pose(), "commanded_sensor_pose");
  const auto reached = PoseFromProto(scan.sensor_pose(), "sensor_pose");
  if (!commanded.ok() || !reached.ok()) return;
  row->position_error_m = (reached->translation() - commanded->translation()).norm();
  const Eigen::AngleAxisd delta(commanded->linear().transpose() * reached->linear());
  row->orientation_error_deg = std::abs(delta.angle()) * 180.0 / std::numbers::pi;
}

}  // namespace

std::vector<CampaignStepRow> CampaignRows(const v1::Job& job, const std::map<uint32_t, StepNote>& notes) {
  const v1::CampaignSpec& spec = job.campaign();
  const uint32_t viewpoints = static_cast<uint32_t>(spec.viewpoints_size());
  const uint32_t rotations = std::max<uint32_t>(spec.rotations(), 1);
  std::vector<CampaignStepRow> rows;
  for (uint32_t r = 0; r < rotations; ++r) {
    for (uint32_t v = 0; v < viewpoints; ++v) {
      CampaignStepRow row;
      row.step = r * viewpoints + v;
      row.viewpoint = v;
      row.rotation = r;
      row.table_angle_deg = spec.start_angle_deg() + r * spec.rotation_step_deg();
      if (const auto note = notes.find(row.step); note != notes.end()) {
        row.note = note->second.message;
        row.pose_reached = note->second.pose_reached;
      } else if (row.step >= job.steps_done()) {
        row.note = "not run";
      }
      rows.push_back(row);
    }
  }
  for (const v1::Artifact& artifact : job.artifacts()) {
    if (!artifact.has_scan()) continue;
    const v1::ScanArtifactInfo& scan = artifact.scan();
    const size_t index = size_t{scan.rotation_index()} * viewpoints + scan.viewpoint_index();
    if (scan.viewpoint_index() >= viewpoints || index >= rows.size()) continue;
    CampaignStepRow& row = rows[index];
    row.captured = true;
    row.pose_reached = true;
    row.points = scan.points();
    row.file = artifact.name();
    row.table_angle_deg = scan.table_angle_deg();
    row.note.clear();
    FillPoseErrors(scan, &row);
  }
  return rows;
}

std::string CampaignTable(const std::vector<CampaignStepRow>& rows) {
  std::string out = "step  view  table deg  reached      points  pos err mm  rot err deg  file\n";
  for (const auto& row : rows) {
    out += Pad(std::to_string(row.step), 4, true) + "  " + Pad(std::to_string(row.viewpoint), 4, true) + "  " +
           Pad(Format("%.1f", row.table_angle_deg), 9, true) + "  " + Pad(row.pose_reached ? "yes" : "no", 7, false);
    if (row.captured) {
      out += Pad(std::to_string(row.points), 11, true) + "  " +
             Pad(Format("%.3f", row.position_error_m * 1000), 10, true) + "  " +
             Pad(Format("%.3f", row.orientation_error_deg), 11, true) + "  " + row.file;
    } else {
      out += Pad("-", 11, true) + "  " + Pad("-", 10, true) + "  " + Pad("-", 11, true) + "  " + row.note;
    }
    out += '\n';
  }
  return out;
}

std::string CampaignRowsJson(const std::vector<CampaignStepRow>& rows) {
  std::string out = "[";
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    out += std::string(i ? "," : "") + "{\"step\":" + std::to_string(row.step) +
           ",\"viewpoint\":" + std::to_string(row.viewpoint) + ",\"rotation\":" + std::to_string(row.rotation) +
           ",\"tableAngleDeg\":" + Format("%.17g", row.table_angle_deg) +
           ",\"poseReached\":" + (row.pose_reached ? "true" : "false") +
           ",\"captured\":" + (row.captured ? "true" : "false") + ",\"points\":" + std::to_string(row.points) +
           ",\"file\":" + JsonQuote(row.file) + ",\"positionErrorM\":" + Format("%.17g", row.position_error_m) +
           ",\"orientationErrorDeg\":" + Format("%.17g", row.orientation_error_deg) +
           ",\"note\":" + JsonQuote(row.note) + "}";
  }
  return out + "]";
}

std::string JobStateName(v1::JobState state) {
  const std::string name = v1::JobState_Name(state);
  return name.starts_with("JOB_STATE_") ? name.substr(10) : name;
}

bool JobFinished(v1::JobState state) {
  return state == v1::JOB_STATE_SUCCEEDED || state == v1::JOB_STATE_FAILED || state == v1::JOB_STATE_CANCELLED ||
         state == v1::JOB_STATE_INTERRUPTED;
}

int JobExitCode(v1::JobState state) { return state == v1::JOB_STATE_SUCCEEDED ? kExitOk : kExitServerError; }

std::string DescribeJob(const v1::Job& job) {
  std::string out = job.job_id() + "  " + Pad(JobStateName(job.state()), 11, false) + "  " +
                    std::to_string(job.steps_done()) + "/" + std::to_string(job.steps_total()) + " steps  " +
                    std::to_string(job.artifacts_size()) + " artifacts  " + FormatTime(job.create_time());
  const std::string& name = job.kind() == "model"      ? job.model().name()
                            : job.kind() == "bin_fill" ? job.bin_fill().name()
                            : job.kind() == "picking"  ? job.picking().name()
                                                       : job.campaign().name();
  if (!name.empty()) out += "  '" + name + "'";
  if (!job.message().empty()) out += "  " + job.message();
  return out;
}

std::string FormatTime(const google::protobuf::Timestamp& time) {
  if (time.seconds() == 0 && time.nanos() == 0) return "";
  const std::time_t seconds = static_cast<std::time_t>(time.seconds());
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%d %H:%M:%SZ", &utc);
  return buf;
}

}  // namespace vscan::cli
