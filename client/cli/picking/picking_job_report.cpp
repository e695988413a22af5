#include "picking/picking_job_report.h"

#include <algorithm>
#include <array>
#include <map>

#include "model/model_fetch.h"
#include "vscan/common/report_json.h"

namespace vscan::cli {
namespace {

// Outcomes in the order a summary lists them; others follow by name.
constexpr std::array<const char*, 5> kPickOutcomeOrder = {"picked", "collision", "wrong_pose", "nothing_found",
                                                      "nothing_pickable"};

std::string OutcomeWords(std::string name) {
  std::replace(name.begin(), name.end(), '_', ' ');
  return name;
}

}  // namespace

int FetchPickingReport(Context& ctx, const v1::Job& job, std::optional<v1::PickingReport>* report) {
  std::optional<std::string> text;
  if (const int rc = FetchArtifactText(ctx, job, "picking.json", &text); rc != kExitOk || !text) return rc;
  v1::PickingReport parsed;
  if (const Status status = ParseReport(*text, "picking.json", &parsed); !status.ok()) return ctx.ServerError(status);
  *report = std::move(parsed);
  return kExitOk;
}

std::string FormatPickingReport(const v1::PickingReport& report) {
  std::string out = std::to_string(report.picked()) + " of " + std::to_string(report.parts_at_start()) +
                    " parts picked in " + std::to_string(report.steps_size()) + " steps";
  const std::map<std::string, uint32_t> outcomes(report.outcomes().begin(), report.outcomes().end());
  std::string listed;
  auto add = [&listed](const std::string& name, uint32_t count) {
    if (count == 0) return;
    listed += (listed.empty() ? "" : ", ") + std::to_string(count) + " " + OutcomeWords(name);
  };
  for (const char* name : kPickOutcomeOrder) {
    if (const auto found = outcomes.find(name); found != outcomes.end()) add(found->first, found->second);
  }
  for (const auto& [name, count] : outcomes) {
    if (std::find(kPickOutcomeOrder.begin(), kPickOutcomeOrder.end(), name) == kPickOutcomeOrder.end()) add(name, count);
  }
  if (!listed.empty()) out += ": " + listed;
  if (report.fell_out() > 0) out += "; " + std::to_string(report.fell_out()) + " fell out";
  out += report.has_end() ? "; end: " + report.end() : "; no end (" + report.state() + ")";
  return out + "\n";
}

}  // namespace vscan::cli
