#include "vscan/plan/yaml_reader.h"

#include <fstream>
#include <sstream>

#include <cctype>
#include <cmath>
#include <set>

namespace vscan::plan {
namespace {

std::string JoinKeys(std::span<const char* const> keys) {
  std::string out;
  for (const char* key : keys) out += (out.empty() ? "" : ", ") + std::string(key);
  return out;
}

}  // namespace

std::string YamlReader::Describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar: return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Map: return "a mapping";
    default: return "nothing";
  }
}

namespace {

void IndexKeys(const YAML::Node& node, const std::string& path, std::map<std::string, YAML::Mark>* out) {
  if (node.IsMap()) {
    for (const auto& entry : node) {
      const std::string key = path.empty() ? entry.first.Scalar() : path + "." + entry.first.Scalar();
      out->emplace(key, entry.first.Mark());
      IndexKeys(entry.second, key, out);
    }
  } else if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) {
      const std::string key = path + "[" + std::to_string(i) + "]";
      out->emplace(key, node[i].Mark());
      IndexKeys(node[i], key, out);
    }
  }
}

}  // namespace

std::map<std::string, YAML::Mark> KeyMarks(const YAML::Node& root) {
  std::map<std::string, YAML::Mark> out{{"", root.Mark()}};
  IndexKeys(root, "", &out);
  return out;
}

std::string ParentKey(const std::string& path) {
  const size_t cut = path.back() == ']' ? path.rfind('[') : path.rfind('.');
  return cut == std::string::npos ? "" : path.substr(0, cut);
}

StatusOr<std::string> ReadPlanFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound(path + ": cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return DataLoss(path + ": read failed");
  return text.str();
}

Status YamlReader::Error(const YamlAt& at, const std::string& what) const {
  const YAML::Mark mark = at.node.IsDefined() && at.node.Mark().line >= 0 ? at.node.Mark() : at.mark;
  return Error(mark, at.path, what);
}

Status YamlReader::Error(const YAML::Mark& mark, const std::string& path, const std::string& what) const {
  const std::string line = mark.line >= 0 ? std::to_string(mark.line + 1) : "1";
  return InvalidArgument(source_ + ":" + line + ": " + (path.empty() ? "" : path + ": ") + what);
}

YamlAt YamlReader::Child(const YamlAt& map, const std::string& key) {
  YAML::Node child = map.node.IsMap() ? map.node[key] : YAML::Node(YAML::NodeType::Undefined);
  return {child, map.path.empty() ? key : map.path + "." + key, map.node.Mark()};
}

YamlAt YamlReader::Item(const YamlAt& seq, size_t index) {
  return {seq.node[index], seq.path + "[" + std::to_string(index) + "]", seq.node.Mark()};
}

Status YamlReader::ExpectMap(const YamlAt& at, std::initializer_list<const char*> allowed) const {
  return ExpectMap(at, std::span<const char* const>(allowed.begin(), allowed.size()));
}

Status YamlReader::ExpectMap(const YamlAt& at, std::span<const char* const> allowed) const {
  if (!at.node.IsMap())
    return Error(at, "expected a mapping with keys " + JoinKeys(allowed) + ", got " + Describe(at.node));
  std::set<std::string> seen;
  for (const auto& entry : at.node) {
    const std::string key = entry.first.Scalar();
    const std::string path = at.path.empty() ? key : at.path + "." + key;
    bool known = false;
    for (const char* name : allowed) known = known || key == name;
    if (!known) return Error(entry.first.Mark(), path, "unknown key (expected one of " + JoinKeys(allowed) + ")");
    if (!seen.insert(key).second) return Error(entry.first.Mark(), path, "given twice");
  }
  return Status::Ok();
}

Status YamlReader::ExpectSequence(const YamlAt& at, size_t min_size) const {
  if (!at.node.IsSequence()) return Error(at, "expected a list, got " + Describe(at.node));
  if (at.node.size() < min_size) return Error(at, "expected at least " + std::to_string(min_size) + " items");
  return Status::Ok();
}

StatusOr<double> YamlReader::Number(const YamlAt& at) const {
  if (!at.node.IsScalar()) return Error(at, "expected a number, got " + Describe(at.node));
  double value = 0;
  if (!YAML::convert<double>::decode(at.node, value)) return Error(at, "'" + at.node.Scalar() + "' is not a number");
  if (!std::isfinite(value)) return Error(at, "'" + at.node.Scalar() + "' is not finite");
  return value;
}

StatusOr<uint64_t> YamlReader::Integer(const YamlAt& at, uint64_t min, uint64_t max) const {
  ASSIGN_OR_RETURN(const double value, Number(at));
  if (value != std::floor(value)) return Error(at, "'" + at.node.Scalar() + "' is not a whole number");
  if (value < static_cast<double>(min) || value > static_cast<double>(max)) {
    return Error(at, "must be between " + std::to_string(min) + " and " + std::to_string(max));
  }
  // Large seeds lose digits through double; read those exactly.
  if (value >= 9.0e15) {
    uint64_t exact = 0;
    if (!YAML::convert<uint64_t>::decode(at.node, exact) || exact < min || exact > max) {
      return Error(at, "must be a whole number between " + std::to_string(min) + " and " + std::to_string(max));
    }
    return exact;
  }
  return static_cast<uint64_t>(value);
}

StatusOr<bool> YamlReader::Bool(const YamlAt& at) const {
  bool value = false;
  if (!at.node.IsScalar() || !YAML::convert<bool>::decode(at.node, value)) {
    return Error(at, "expected true or false, got " + Describe(at.node));
  }
  return value;
}

StatusOr<std::string> YamlReader::String(const YamlAt& at) const {
  if (!at.node.IsScalar() || at.node.Scalar().empty())
    return Error(at, "expected a non-empty string, got " + Describe(at.node));
  return at.node.Scalar();
}

StatusOr<std::vector<double>> YamlReader::Numbers(const YamlAt& at, size_t count) const {
  if (!at.node.IsSequence() || at.node.size() != count) {
    return Error(at, "expected " + std::to_string(count) + " numbers, got " +
                         (at.node.IsSequence() ? std::to_string(at.node.size()) + " items" : Describe(at.node)));
  }
  std::vector<double> out;
  for (size_t i = 0; i < count; ++i) {
    ASSIGN_OR_RETURN(const double v, Number(Item(at, i)));
    out.push_back(v);
  }
  return out;
}

StatusOr<Eigen::Vector3d> YamlReader::Vector3(const YamlAt& at) const {
  ASSIGN_OR_RETURN(const auto v, Numbers(at, 3));
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

StatusOr<std::vector<double>> YamlReader::NumberOrList(const YamlAt& at) const {
  if (at.node.IsScalar()) {
    ASSIGN_OR_RETURN(const double v, Number(at));
    return std::vector<double>{v};
  }
  RETURN_IF_ERROR(ExpectSequence(at, 1));
  return Numbers(at, at.node.size());
}

StatusOr<std::string> YamlReader::StringOrList(const YamlAt& at) const {
  if (at.node.IsScalar()) return String(at);
  RETURN_IF_ERROR(ExpectSequence(at, 1));
  std::string out;
  for (size_t i = 0; i < at.node.size(); ++i) {
    ASSIGN_OR_RETURN(const std::string item, String(Item(at, i)));
    out += (i ? "," : "") + item;
  }
  return out;
}

}  // namespace vscan::plan
