#include "service/campaign/campaign_summary.h"

#include <cmath>
#include <cstdio>

namespace vscan::service {
namespace {

// A minimal JSON writer: the caller opens and closes containers, the writer places commas.
class Json {
 public:
  std::string str() const { return out_; }
  Json& Open(char bracket) {
    Separate();
    out_ += bracket;
    first_ = true;
    return *this;
  }
  Json& Close(char bracket) {
    out_ += bracket;
    first_ = false;
    return *this;
  }
  Json& Key(const std::string& key) {
    Separate();
    String(key);
    out_ += ':';
    first_ = true;
    return *this;
  }
  Json& Value(const std::string& text) {
    Separate();
    String(text);
    return *this;
  }
  Json& Value(double x) {
    Separate();
    if (!std::isfinite(x)) {
      out_ += "null";
      return *this;
    }
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.17g", x);
    out_ += buffer;
    return *this;
  }
  Json& Value(uint64_t x) {
    Separate();
    out_ += std::to_string(x);
    return *this;
  }
  Json& Value(bool b) {
    Separate();
    out_ += b ? "true" : "false";
    return *this;
  }
  Json& Array(const Eigen::VectorXd& v) {
    Open('[');
    for (Eigen::Index i = 0; i < v.size(); ++i) Value(v[i]);
    return Close(']');
  }
  // Row-major 4x4, as the wire's Matrix4.
  Json& Matrix(const Pose3& pose) {
    Open('[');
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) Value(pose.matrix()(r, c));
    }
    return Close(']');
  }

 private:
  void Separate() {
    if (!first_) out_ += ',';
    first_ = false;
  }
  void String(const std::string& s) {
    out_ += '"';
    for (const char ch : s) {
      const auto c = static_cast<unsigned char>(ch);
      if (c == '"' || c == '\\') {
        out_ += '\\';
        out_ += ch;
      } else if (c < 0x20) {
        char buffer[8];
        std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
        out_ += buffer;
      } else {
        out_ += ch;
      }
    }
    out_ += '"';
  }

  std::string out_;
  bool first_ = true;
};

void Vector(Json& json, const char* key, const Eigen::Vector3d& v) {
  json.Key(key).Open('[').Value(v.x()).Value(v.y()).Value(v.z()).Close(']');
}

}  // namespace

std::string CampaignSummaryJson(const std::string& job_id, const std::string& final_state, const CampaignPlan& plan,
                                const std::vector<CampaignStepRecord>& steps) {
  Json json;
  json.Open('{');
  json.Key("job_id").Value(job_id);
  json.Key("state").Value(final_state);
  json.Key("name").Value(plan.name);
  json.Key("scene_id").Value(plan.scene_id);
  json.Key("mount_id").Value(plan.mount_id);
  json.Key("seed").Value(plan.seed);
  json.Key("rotations").Value(uint64_t{plan.rotations});
  json.Key("rotation_step_deg").Value(plan.rotation_step_deg);
  json.Key("start_angle_deg").Value(plan.start_angle_deg);
  json.Key("steps_total").Value(uint64_t{plan.scans_total()});
  json.Key("viewpoints").Open('[');
  for (const CampaignViewpoint& v : plan.viewpoints) {
    json.Open('{');
    Vector(json, "position", v.position);
    Vector(json, "target", v.target);
    json.Close('}');
  }
  json.Close(']');
  uint64_t captured = 0;
  for (const CampaignStepRecord& s : steps) captured += s.outcome == "captured";
  json.Key("steps_done").Value(uint64_t{steps.size()});
  json.Key("scans_captured").Value(captured);
  json.Key("steps").Open('[');
  for (const CampaignStepRecord& s : steps) {
    json.Open('{');
    json.Key("step").Value(uint64_t{s.step});
    json.Key("rotation_index").Value(uint64_t{s.rotation_index});
    json.Key("viewpoint_index").Value(uint64_t{s.viewpoint_index});
    json.Key("table_angle_deg").Value(s.table_angle_deg);
    json.Key("outcome").Value(s.outcome);
    json.Key("reached").Value(s.outcome != "unreachable");
    json.Key("message").Value(s.message);
    json.Key("seed").Value(s.seed);
    if (s.outcome == "unreachable") json.Key("miss_distance_m").Value(s.miss_distance);
    if (s.has_arm) {
      json.Key("commanded_joint_positions").Array(s.arm.commanded);
      json.Key("achieved_joint_positions").Array(s.arm.achieved);
      json.Key("commanded_sensor_pose").Matrix(s.arm.commanded_pose);
      json.Key("sensor_pose").Matrix(s.arm.achieved_pose);
    }
    if (!s.file.empty()) {
      json.Key("file").Value(s.file);
      json.Key("artifact_id").Value(s.artifact_id);
      json.Key("points").Value(s.points);
    }
    json.Close('}');
  }
  json.Close(']');
  json.Close('}');
  return json.str() + "\n";
}

ScanArtifact ScanArtifactOf(const CampaignStepRecord& record) {
  ScanArtifact scan;
  scan.rotation_index = record.rotation_index;
  scan.viewpoint_index = record.viewpoint_index;
  scan.table_angle_deg = record.table_angle_deg;
  scan.commanded_sensor_pose = record.arm.commanded_pose;
  scan.sensor_pose = record.arm.achieved_pose;
  scan.commanded_joint_positions = record.arm.commanded;
  scan.achieved_joint_positions = record.arm.achieved;
  scan.points = record.points;
  return scan;
}

}  // namespace vscan::service
