#include "campaign/campaign_errors.h"

#include <string_view>

#include "campaign/yaml_messages.h"

namespace vscan::cli {
namespace {

// Where each call's field paths live in a plan: a message "<server_prefix>field: what" is about
// the plan key "<plan_prefix>field" ('#' stands for the object's index).
struct CallFields {
  PlanCall call;
  std::string_view server_prefix;
  std::string_view plan_prefix;
};

constexpr CallFields kCalls[] = {
    {PlanCall::kStartCampaign, "spec.", ""},
    {PlanCall::kCreateScene, "", "scene."},
    {PlanCall::kAddObject, "", "scene.objects[#]."},
    {PlanCall::kSetRotaryTable, "table.", "scene.table."},
    {PlanCall::kMountRobot, "", "robot."},
};

// Spec fields a plan may leave out because another key sets them.
constexpr std::pair<std::string_view, std::string_view> kDefaultedBy[] = {
    {"rotation_step_deg", "rotations"},
};

bool IsPathChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
         c == '[' || c == ']';
}

// The field path a message starts with ("sensor.pinhole.width: ..." or "sensor.pinhole.width x
// sensor.pinhole.height: ..."), or "" when it starts with prose.
std::string_view LeadingField(std::string_view message) {
  size_t end = 0;
  while (end < message.size() && IsPathChar(message[end])) ++end;
  const std::string_view field = message.substr(0, end);
  if (end == 0 || end == message.size()) return {};
  if (message[end] == ':') return field;
  return message[end] == ' ' && field.find('.') != std::string_view::npos ? field : std::string_view();
}

const CallFields& Fields(PlanCall call) {
  for (const CallFields& fields : kCalls) {
    if (fields.call == call) return fields;
  }
  return kCalls[0];
}

}  // namespace

std::optional<std::string> LocateInPlan(const CampaignPlan& plan, PlanCall call, const Status& status,
                                        size_t object) {
  if (status.ok() || !NamesAField(status.code())) return std::nullopt;
  const CallFields& fields = Fields(call);
  const std::string& message = status.message();
  if (!message.starts_with(fields.server_prefix)) return std::nullopt;
  const std::string_view rest = std::string_view(message).substr(fields.server_prefix.size());
  const std::string_view field = LeadingField(rest);
  if (field.empty()) return std::nullopt;

  std::string prefix(fields.plan_prefix);
  if (const size_t hash = prefix.find('#'); hash != std::string::npos) prefix.replace(hash, 1, std::to_string(object));
  const std::string key = prefix + std::string(field);
  std::string at = key;
  if (!plan.key_marks.contains(key)) {
    for (const auto& [spec_field, plan_key] : kDefaultedBy) {
      if (key == spec_field && plan.key_marks.contains(std::string(plan_key))) at = plan_key;
    }
  }
  // The nearest key the plan has: a value the plan leaves out stands where its parent does.
  while (!at.empty() && !plan.key_marks.contains(at)) at = ParentKey(at);
  const auto mark = plan.key_marks.find(at);
  const YAML::Mark where = mark == plan.key_marks.end() ? YAML::Mark() : mark->second;
  return YamlReader(plan.source).Error(where, "", prefix + std::string(rest)).message();
}

}  // namespace vscan::cli
