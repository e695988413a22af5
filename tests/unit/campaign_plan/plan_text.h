#pragma once
// The repository root that the test plans' relative paths resolve against, and a plan parsed from
// text as if read from plan.yaml there.

#include <filesystem>
#include <string>

#include "campaign/campaign_plan.h"

namespace vscan::cli::test {

inline const std::filesystem::path kRoot = VSCAN_SOURCE_DIR;

inline StatusOr<CampaignPlan> Parse(const std::string& text) { return ParseCampaignPlan(text, "plan.yaml", kRoot); }

}  // namespace vscan::cli::test
