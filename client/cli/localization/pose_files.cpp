#include "localization/pose_files.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "session/text_format.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

// JSON is read with yaml-cpp (JSON is YAML's flow style).
StatusOr<YAML::Node> LoadJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open for reading");
  try {
    return YAML::Load(in);
  } catch (const YAML::Exception& e) {
    return InvalidArgument(path + ": not valid JSON (line " + std::to_string(e.mark.line + 1) + ")");
  }
}

template <typename T>
StatusOr<T> Scalar(const YAML::Node& node, const std::string& field) {
  if (!node || !node.IsScalar()) return InvalidArgument(field, "missing or not a number");
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    return InvalidArgument(field, "not a number: '" + node.Scalar() + "'");
  }
}

StatusOr<Pose3> MatrixPose(const YAML::Node& node, const std::string& field) {
  // A bare list of 16, or the Matrix4 message {"values": [...]}.
  const YAML::Node values = node && node.IsMap() ? node["values"] : node;
  if (!values || !values.IsSequence() || values.size() != 16) {
    return InvalidArgument(field, "need 16 numbers (row-major 4x4)");
  }
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) {
    const std::string element = field + "[" + std::to_string(i) + "]";
    ASSIGN_OR_RETURN(m(i / 4, i % 4), Scalar<double>(values[i], element));
  }
  return PoseFromMatrix(m, field);
}

StatusOr<Eigen::Vector3d> Vector(const YAML::Node& node, const std::string& field) {
  if (!node || !node.IsSequence() || node.size() != 3) return InvalidArgument(field, "need 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    ASSIGN_OR_RETURN(v[i], Scalar<double>(node[i], field));
  }
  return v;
}

std::string Prefixed(const std::string& path, const Status& status) { return path + ": " + status.message(); }

// Every digit a double holds, so a pose file reads back exactly.
std::string Number(double v) { return Format("%.17g", v); }

std::string Quote(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

StatusOr<SearchedPart> ReadSearchedPart(const YAML::Node& node, const std::string& field) {
  SearchedPart part;
  if (!node["mesh_id"] || !node["mesh_id"].IsScalar()) return InvalidArgument(field + ".mesh_id", "required");
  part.mesh_id = node["mesh_id"].Scalar();
  if (node["scale"]) {
    ASSIGN_OR_RETURN(part.scale, Scalar<double>(node["scale"], field + ".scale"));
  }
  if (node["max_instances"]) {
    ASSIGN_OR_RETURN(part.max_instances, Scalar<uint32_t>(node["max_instances"], field + ".max_instances"));
  }
  if (node["found"]) {
    ASSIGN_OR_RETURN(part.found, Scalar<uint64_t>(node["found"], field + ".found"));
  }
  if (node["stop_reason"] && node["stop_reason"].IsScalar()) part.stop_reason = node["stop_reason"].Scalar();
  if (node["voxel_size"]) {
    ASSIGN_OR_RETURN(part.voxel_size, Scalar<double>(node["voxel_size"], field + ".voxel_size"));
  }
  return part;
}

StatusOr<PoseRow> ReadEstimate(const YAML::Node& node, const std::string& field) {
  PoseRow row;
  if (node["part"]) {
    ASSIGN_OR_RETURN(row.part, Scalar<uint32_t>(node["part"], field + ".part"));
  }
  if (!node["mesh_id"] || !node["mesh_id"].IsScalar()) return InvalidArgument(field + ".mesh_id", "required");
  row.mesh_id = node["mesh_id"].Scalar();
  if (node["scale"]) {
    ASSIGN_OR_RETURN(row.scale, Scalar<double>(node["scale"], field + ".scale"));
  }
  ASSIGN_OR_RETURN(row.world_from_part, MatrixPose(node["world_from_part"], field + ".world_from_part"));
  ASSIGN_OR_RETURN(row.score, Scalar<double>(node["score"], field + ".score"));
  if (node["explained_points"]) {
    ASSIGN_OR_RETURN(row.explained_points, Scalar<uint64_t>(node["explained_points"], field + ".explained_points"));
  }
  return row;
}

std::vector<std::string> Split(const std::string& line, char separator) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string item;
  while (std::getline(in, item, separator)) out.push_back(item);
  return out;
}

StatusOr<std::vector<double>> Numbers(const std::string& text, size_t count, const std::string& field) {
  std::vector<double> out;
  std::stringstream in(text);
  double v = 0;
  while (in >> v) out.push_back(v);
  if (!in.eof() || out.size() != count) {
    return InvalidArgument(field, "need " + std::to_string(count) + " numbers separated by spaces");
  }
  return out;
}

}  // namespace

StatusOr<GroundTruthFile> ReadGroundTruth(const std::string& path) {
  ASSIGN_OR_RETURN(const YAML::Node root, LoadJson(path));
  GroundTruthFile file;
  if (root["world_from_sensor"]) {
    auto pose = MatrixPose(root["world_from_sensor"], "world_from_sensor");
    if (!pose.ok()) return InvalidArgument(Prefixed(path, pose.status()));
    file.world_from_sensor = *pose;
  }
  const YAML::Node objects = root["objects"];
  if (!objects || !objects.IsSequence()) return InvalidArgument(path + ": objects: required (a list)");
  for (size_t i = 0; i < objects.size(); ++i) {
    const std::string field = "objects[" + std::to_string(i) + "]";
    const YAML::Node object = objects[i];
    v1::ObjectTruth truth;
    if (!object["mesh_id"] || !object["mesh_id"].IsScalar()) return InvalidArgument(path + ": " + field + ".mesh_id: required");
    truth.set_mesh_id(object["mesh_id"].Scalar());
    if (object["object_id"]) truth.set_object_id(object["object_id"].Scalar());
    if (object["label"]) truth.set_label(object["label"].Scalar());
    auto pose = MatrixPose(object["world_from_object"], field + ".world_from_object");
    if (!pose.ok()) return InvalidArgument(Prefixed(path, pose.status()));
    ToProto(*pose, truth.mutable_world_from_object());
    const auto read = [&](const char* name, auto& value) -> Status {
      using T = std::decay_t<decltype(value)>;
      if (!object[name]) return Status::Ok();
      auto parsed = Scalar<T>(object[name], field + "." + name);
      if (!parsed.ok()) return InvalidArgument(Prefixed(path, parsed.status()));
      value = *parsed;
      return Status::Ok();
    };
    uint32_t instance_id = 0;
    uint64_t visible = 0, unoccluded = 0;
    double scale = 1, fraction = 1;
    RETURN_IF_ERROR(read("instance_id", instance_id));
    RETURN_IF_ERROR(read("visible_points", visible));
    RETURN_IF_ERROR(read("unoccluded_points", unoccluded));
    RETURN_IF_ERROR(read("scale", scale));
    RETURN_IF_ERROR(read("visible_fraction", fraction));
    truth.set_instance_id(instance_id);
    truth.set_visible_points(visible);
    truth.set_unoccluded_points(unoccluded);
    truth.set_scale(scale > 0 ? scale : 1);
    truth.set_visible_fraction(fraction);
    file.objects.push_back(std::move(truth));
  }
  return file;
}

StatusOr<EstimatesFile> ReadEstimates(const std::string& path) {
  ASSIGN_OR_RETURN(const YAML::Node root, LoadJson(path));
  EstimatesFile file;
  if (root["cloud"]) file.cloud = root["cloud"].Scalar();
  if (root["frame"]) file.frame = root["frame"].Scalar();
  if (root["localize_ms"]) {
    auto ms = Scalar<double>(root["localize_ms"], "localize_ms");
    if (!ms.ok()) return InvalidArgument(Prefixed(path, ms.status()));
    file.localize_ms = *ms;
  }
  if (const YAML::Node parts = root["parts"]; parts) {
    if (!parts.IsSequence()) return InvalidArgument(path + ": parts: must be a list");
    for (size_t i = 0; i < parts.size(); ++i) {
      auto part = ReadSearchedPart(parts[i], "parts[" + std::to_string(i) + "]");
      if (!part.ok()) return InvalidArgument(Prefixed(path, part.status()));
      file.parts.push_back(std::move(*part));
    }
  }
  const YAML::Node estimates = root["estimates"];
  if (!estimates || !estimates.IsSequence()) return InvalidArgument(path + ": estimates: required (a list)");
  for (size_t i = 0; i < estimates.size(); ++i) {
    const std::string field = "estimates[" + std::to_string(i) + "]";
    auto row = ReadEstimate(estimates[i], field);
    if (!row.ok()) return InvalidArgument(Prefixed(path, row.status()));
    if (!file.parts.empty()) {
      if (row->part >= file.parts.size()) {
        return InvalidArgument(path + ": " + field + ".part: no part " + std::to_string(row->part) + " (" +
                               std::to_string(file.parts.size()) + " parts)");
      }
      const SearchedPart& part = file.parts[row->part];
      if (part.mesh_id != row->mesh_id || part.scale != row->scale) {
        return InvalidArgument(path + ": " + field + ".part: parts[" + std::to_string(row->part) +
                               "] is another mesh or scale than this estimate's");
      }
    }
    file.estimates.push_back(std::move(*row));
  }
  return file;
}

std::string EstimatesJson(const EstimatesFile& file) {
  std::string out = "{\"cloud\": " + Quote(file.cloud) + ", \"frame\": " + Quote(file.frame) +
                    ", \"localize_ms\": " + Number(file.localize_ms) + ",\n \"parts\": [";
  for (size_t i = 0; i < file.parts.size(); ++i) {
    const SearchedPart& part = file.parts[i];
    out += std::string(i ? "," : "") + "\n  {\"part\": " + std::to_string(i) + ", \"mesh_id\": " +
           Quote(part.mesh_id) + ", \"scale\": " + Number(part.scale) +
           ", \"max_instances\": " + std::to_string(part.max_instances) + ", \"found\": " +
           std::to_string(part.found) + ", \"stop_reason\": " + Quote(part.stop_reason) +
           ", \"voxel_size\": " + Number(part.voxel_size) + "}";
  }
  out += std::string(file.parts.empty() ? "" : "\n ") + "],\n \"estimates\": [";
  for (size_t i = 0; i < file.estimates.size(); ++i) {
    const PoseRow& row = file.estimates[i];
    out += std::string(i ? "," : "") + "\n  {\"part\": " + std::to_string(row.part) + ", \"mesh_id\": " +
           Quote(row.mesh_id) + ", \"scale\": " + Number(row.scale) +
           ", \"score\": " + Number(row.score) + ", \"explained_points\": " + std::to_string(row.explained_points) +
           ", \"world_from_part\": [";
    const Eigen::Matrix4d m = row.world_from_part.matrix();
    for (int k = 0; k < 16; ++k) out += (k ? ", " : "") + Number(m(k / 4, k % 4));
    out += "]}";
  }
  return out + "\n]}\n";
}

StatusOr<std::vector<PoseRow>> ReadBopResults(const std::string& path, const Pose3& world_from_sensor,
                                              const std::map<int, PoseRow>& obj_ids) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open for reading");
  std::vector<PoseRow> rows;
  std::string line;
  size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || (number == 1 && line.starts_with("scene_id"))) continue;
    const std::string where = path + ":" + std::to_string(number);
    const std::vector<std::string> cells = Split(line, ',');
    if (cells.size() != 7) return InvalidArgument(where + ": need 7 columns scene_id,im_id,obj_id,score,R,t,time");
    int obj_id = 0;
    try {
      obj_id = std::stoi(cells[2]);
    } catch (const std::exception&) {
      return InvalidArgument(where + ": obj_id: not an integer");
    }
    const auto known = obj_ids.find(obj_id);
    if (known == obj_ids.end()) return InvalidArgument(where + ": obj_id " + cells[2] + ": no mesh given for it (--bop-obj)");
    ASSIGN_OR_RETURN(const auto score, Numbers(cells[3], 1, where + ": score"));
    ASSIGN_OR_RETURN(const auto r, Numbers(cells[4], 9, where + ": R"));
    ASSIGN_OR_RETURN(const auto t, Numbers(cells[5], 3, where + ": t"));
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int k = 0; k < 9; ++k) m(k / 3, k % 3) = r[k];
    for (int k = 0; k < 3; ++k) m(k, 3) = t[k] / 1000;  // BOP writes millimetres
    ASSIGN_OR_RETURN(const Pose3 sensor_from_part, PoseFromMatrix(m, where + ": R"));
    PoseRow row = known->second;
    row.world_from_part = world_from_sensor * sensor_from_part;
    row.score = score[0];
    rows.push_back(std::move(row));
  }
  return rows;
}

StatusOr<std::map<std::string, v1::PartSymmetry>> ReadSymmetries(const std::string& path) {
  ASSIGN_OR_RETURN(const YAML::Node root, LoadJson(path));
  if (!root.IsMap()) return InvalidArgument(path + ": need an object of mesh ids");
  std::map<std::string, v1::PartSymmetry> out;
  for (const auto& entry : root) {
    const std::string mesh_id = entry.first.Scalar();
    v1::PartSymmetry& symmetry = out[mesh_id];
    const YAML::Node continuous = entry.second["continuous"];
    for (size_t i = 0; continuous && i < continuous.size(); ++i) {
      const std::string field = mesh_id + ".continuous[" + std::to_string(i) + "]";
      auto axis = Vector(continuous[i]["axis"], field + ".axis");
      if (!axis.ok()) return InvalidArgument(Prefixed(path, axis.status()));
      v1::ContinuousSymmetry* out_axis = symmetry.add_continuous();
      *out_axis->mutable_axis() = ToProto(*axis);
      if (continuous[i]["point"]) {
        auto point = Vector(continuous[i]["point"], field + ".point");
        if (!point.ok()) return InvalidArgument(Prefixed(path, point.status()));
        *out_axis->mutable_point() = ToProto(*point);
      }
    }
    const YAML::Node discrete = entry.second["discrete"];
    for (size_t i = 0; discrete && i < discrete.size(); ++i) {
      auto pose = MatrixPose(discrete[i], mesh_id + ".discrete[" + std::to_string(i) + "]");
      if (!pose.ok()) return InvalidArgument(Prefixed(path, pose.status()));
      ToProto(*pose, symmetry.add_discrete()->mutable_matrix());
    }
  }
  return out;
}

v1::ScorePosesRequest BuildScoreRequest(const GroundTruthFile& truth, const std::vector<PoseRow>& estimates,
                                        const std::map<std::string, v1::PartSymmetry>& symmetries,
                                        const std::vector<SearchedPart>& searched) {
  v1::ScorePosesRequest request;
  std::map<std::pair<std::string, double>, uint32_t> parts;
  const auto part_of = [&](const std::string& mesh_id, double scale) -> uint32_t {
    const auto [it, added] = parts.emplace(std::make_pair(mesh_id, scale), static_cast<uint32_t>(parts.size()));
    if (added) {
      v1::ScoredPart* part = request.add_parts();
      part->set_mesh_id(mesh_id);
      part->set_scale(scale);
      if (const auto s = symmetries.find(mesh_id); s != symmetries.end()) *part->mutable_symmetry() = s->second;
    }
    return it->second;
  };
  for (const SearchedPart& part : searched) part_of(part.mesh_id, part.scale);
  for (const PoseRow& row : estimates) {
    v1::EstimatedPose* estimate = request.add_estimates();
    estimate->set_part(part_of(row.mesh_id, row.scale));
    *estimate->mutable_world_from_part() = PoseToProto(row.world_from_part);
    estimate->set_score(row.score);
  }
  for (const v1::ObjectTruth& object : truth.objects) {
    const auto part = parts.find({object.mesh_id(), object.scale()});
    if (part == parts.end()) continue;
    v1::TruePose* pose = request.add_truth();
    pose->set_part(part->second);
    pose->mutable_world_from_part()->mutable_matrix()->CopyFrom(object.world_from_object());
    pose->set_visible_fraction(object.visible_fraction());
    pose->set_instance_id(object.instance_id());
  }
  return request;
}

}  // namespace vscan::cli
