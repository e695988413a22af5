#include "campaign/campaign_yaml.h"

#include <fstream>
#include <sstream>

#include <google/protobuf/descriptor.h>

#include <cctype>
#include <cmath>
#include <set>

namespace vscan::cli {
namespace {

using google::protobuf::FieldDescriptor;

std::string JoinKeys(std::initializer_list<const char*> keys) {
  std::string out;
  for (const char* key : keys) out += (out.empty() ? "" : ", ") + std::string(key);
  return out;
}

std::string Describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar: return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Map: return "a mapping";
    default: return "nothing";
  }
}

std::string Lowered(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// "INITIAL_POSE_" for enum InitialPose: the prefix its values carry by the proto style guide.
std::string EnumPrefix(const google::protobuf::EnumDescriptor& type) {
  std::string prefix;
  for (const char c : type.name()) {
    if (std::isupper(static_cast<unsigned char>(c)) && !prefix.empty()) prefix += '_';
    prefix += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  prefix += '_';
  for (int i = 0; i < type.value_count(); ++i) {
    if (!type.value(i)->name().starts_with(prefix)) return "";
  }
  return prefix;
}

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

StatusOr<int> YamlReader::EnumValue(const YamlAt& at, const google::protobuf::EnumDescriptor& type) const {
  const std::string prefix = EnumPrefix(type);
  std::string names;
  for (int i = 0; i < type.value_count(); ++i) {
    const std::string name = type.value(i)->name().substr(prefix.size());
    if (type.value(i)->number() == 0) continue;
    names += (names.empty() ? "" : ", ") + Lowered(name);
  }
  ASSIGN_OR_RETURN(const std::string text, String(at));
  for (int i = 0; i < type.value_count(); ++i) {
    const auto* value = type.value(i);
    if (value->number() != 0 && Lowered(value->name().substr(prefix.size())) == Lowered(text)) return value->number();
  }
  return Error(at, "unknown value '" + text + "' (" + names + ")");
}

Status YamlReader::FillMessage(const YamlAt& at, google::protobuf::Message* message) const {
  const auto* descriptor = message->GetDescriptor();
  std::string known;
  for (int i = 0; i < descriptor->field_count(); ++i) known += (i ? ", " : "") + descriptor->field(i)->name();
  if (!at.node.IsMap()) return Error(at, "expected a mapping with keys " + known + ", got " + Describe(at.node));
  std::set<std::string> seen;
  for (const auto& entry : at.node) {
    const std::string key = entry.first.Scalar();
    const YamlAt child{entry.second, at.path.empty() ? key : at.path + "." + key, entry.first.Mark()};
    const FieldDescriptor* field = descriptor->FindFieldByName(key);
    if (field == nullptr || field->is_repeated()) {
      return Error(entry.first.Mark(), child.path, "unknown key (expected one of " + known + ")");
    }
    if (!seen.insert(key).second) return Error(entry.first.Mark(), child.path, "given twice");
    if (const auto* oneof = field->real_containing_oneof()) {
      const FieldDescriptor* set = message->GetReflection()->GetOneofFieldDescriptor(*message, oneof);
      if (set != nullptr) return Error(entry.first.Mark(), child.path, "conflicts with " + set->name());
    }
    RETURN_IF_ERROR(FillField(child, field, message));
  }
  return Status::Ok();
}

Status YamlReader::FillField(const YamlAt& at, const FieldDescriptor* field, google::protobuf::Message* message) const {
  const auto* reflection = message->GetReflection();
  switch (field->cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE: {
      ASSIGN_OR_RETURN(const double v, Number(at));
      reflection->SetDouble(message, field, v);
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_FLOAT: {
      ASSIGN_OR_RETURN(const double v, Number(at));
      reflection->SetFloat(message, field, static_cast<float>(v));
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_UINT32: {
      ASSIGN_OR_RETURN(const uint64_t v, Integer(at, 0, UINT32_MAX));
      reflection->SetUInt32(message, field, static_cast<uint32_t>(v));
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_UINT64: {
      ASSIGN_OR_RETURN(const uint64_t v, Integer(at, 0, UINT64_MAX));
      reflection->SetUInt64(message, field, v);
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_INT32: {
      ASSIGN_OR_RETURN(const uint64_t v, Integer(at, 0, INT32_MAX));
      reflection->SetInt32(message, field, static_cast<int32_t>(v));
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_BOOL: {
      ASSIGN_OR_RETURN(const bool v, Bool(at));
      reflection->SetBool(message, field, v);
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_STRING: {
      ASSIGN_OR_RETURN(std::string v, String(at));
      reflection->SetString(message, field, std::move(v));
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_MESSAGE: {
      google::protobuf::Message* child = reflection->MutableMessage(message, field);
      if (field->message_type()->full_name() == "vscan.v1.Vector3" && at.node.IsSequence()) {
        ASSIGN_OR_RETURN(const Eigen::Vector3d v, Vector3(at));
        const auto* d = child->GetDescriptor();
        const auto* r = child->GetReflection();
        r->SetDouble(child, d->FindFieldByName("x"), v.x());
        r->SetDouble(child, d->FindFieldByName("y"), v.y());
        r->SetDouble(child, d->FindFieldByName("z"), v.z());
        return Status::Ok();
      }
      return FillMessage(at, child);
    }
    case FieldDescriptor::CPPTYPE_ENUM: {
      ASSIGN_OR_RETURN(const int v, EnumValue(at, *field->enum_type()));
      reflection->SetEnumValue(message, field, v);
      return Status::Ok();
    }
    default: return Error(at, "cannot be set from a plan");
  }
}

}  // namespace vscan::cli
