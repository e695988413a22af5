#include "campaign/yaml_messages.h"

#include <google/protobuf/descriptor.h>

#include <cctype>
#include <set>

namespace vscan::cli {
namespace {

using google::protobuf::FieldDescriptor;

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

// The number of the enum value the scalar at names, written without the enum's prefix in any
// case ("features" for INITIAL_POSE_FEATURES); the zero value (unspecified) is not accepted.
StatusOr<int> EnumValue(const YamlReader& yaml, const YamlAt& at, const google::protobuf::EnumDescriptor& type) {
  const std::string prefix = EnumPrefix(type);
  std::string names;
  for (int i = 0; i < type.value_count(); ++i) {
    const std::string name = type.value(i)->name().substr(prefix.size());
    if (type.value(i)->number() == 0) continue;
    names += (names.empty() ? "" : ", ") + Lowered(name);
  }
  ASSIGN_OR_RETURN(const std::string text, yaml.String(at));
  for (int i = 0; i < type.value_count(); ++i) {
    const auto* value = type.value(i);
    if (value->number() != 0 && Lowered(value->name().substr(prefix.size())) == Lowered(text)) return value->number();
  }
  return yaml.Error(at, "unknown value '" + text + "' (" + names + ")");
}

Status FillField(const YamlReader& yaml, const YamlAt& at, const FieldDescriptor* field, google::protobuf::Message* message);

}  // namespace

Status FillMessage(const YamlReader& yaml, const YamlAt& at, google::protobuf::Message* message) {
  const auto* descriptor = message->GetDescriptor();
  std::string known;
  for (int i = 0; i < descriptor->field_count(); ++i) known += (i ? ", " : "") + descriptor->field(i)->name();
  if (!at.node.IsMap()) return yaml.Error(at, "expected a mapping with keys " + known + ", got " + YamlReader::Describe(at.node));
  std::set<std::string> seen;
  for (const auto& entry : at.node) {
    const std::string key = entry.first.Scalar();
    const YamlAt child{entry.second, at.path.empty() ? key : at.path + "." + key, entry.first.Mark()};
    const FieldDescriptor* field = descriptor->FindFieldByName(key);
    if (field == nullptr || field->is_repeated()) {
      return yaml.Error(entry.first.Mark(), child.path, "unknown key (expected one of " + known + ")");
    }
    if (!seen.insert(key).second) return yaml.Error(entry.first.Mark(), child.path, "given twice");
    if (const auto* oneof = field->real_containing_oneof()) {
      const FieldDescriptor* set = message->GetReflection()->GetOneofFieldDescriptor(*message, oneof);
      if (set != nullptr) return yaml.Error(entry.first.Mark(), child.path, "conflicts with " + set->name());
    }
    RETURN_IF_ERROR(FillField(yaml, child, field, message));
  }
  return Status::Ok();
}

namespace {

Status FillField(const YamlReader& yaml, const YamlAt& at, const FieldDescriptor* field, google::protobuf::Message* message) {
  const auto* reflection = message->GetReflection();
  switch (field->cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE: {
      ASSIGN_OR_RETURN(const double v, yaml.Number(at));
      reflection->SetDouble(message, field, v);
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_FLOAT: {
      ASSIGN_OR_RETURN(const double v, yaml.Number(at));
      reflection->SetFloat(message, field, static_cast<float>(v));
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_UINT32: {
      ASSIGN_OR_RETURN(const uint64_t v, yaml.Integer(at, 0, UINT32_MAX));
      reflection->SetUInt32(message, field, static_cast<uint32_t>(v));
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_UINT64: {
      ASSIGN_OR_RETURN(const uint64_t v, yaml.Integer(at, 0, UINT64_MAX));
      reflection->SetUInt64(message, field, v);
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_INT32: {
      ASSIGN_OR_RETURN(const uint64_t v, yaml.Integer(at, 0, INT32_MAX));
      reflection->SetInt32(message, field, static_cast<int32_t>(v));
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_BOOL: {
      ASSIGN_OR_RETURN(const bool v, yaml.Bool(at));
      reflection->SetBool(message, field, v);
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_STRING: {
      ASSIGN_OR_RETURN(std::string v, yaml.String(at));
      reflection->SetString(message, field, std::move(v));
      return Status::Ok();
    }
    case FieldDescriptor::CPPTYPE_MESSAGE: {
      google::protobuf::Message* child = reflection->MutableMessage(message, field);
      if (field->message_type()->full_name() == "vscan.v1.Vector3" && at.node.IsSequence()) {
        ASSIGN_OR_RETURN(const Eigen::Vector3d v, yaml.Vector3(at));
        const auto* d = child->GetDescriptor();
        const auto* r = child->GetReflection();
        r->SetDouble(child, d->FindFieldByName("x"), v.x());
        r->SetDouble(child, d->FindFieldByName("y"), v.y());
        r->SetDouble(child, d->FindFieldByName("z"), v.z());
        return Status::Ok();
      }
      return FillMessage(yaml, at, child);
    }
    case FieldDescriptor::CPPTYPE_ENUM: {
      ASSIGN_OR_RETURN(const int v, EnumValue(yaml, at, *field->enum_type()));
      reflection->SetEnumValue(message, field, v);
      return Status::Ok();
    }
    default: return yaml.Error(at, "cannot be set from a plan");
  }
}

}  // namespace

}  // namespace vscan::cli
