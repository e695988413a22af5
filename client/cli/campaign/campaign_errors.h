#pragma once
// Server errors traced back to the plan: the field a server call names in its message is mapped to
// the plan key that gave the value, so that the error names the file and the line as a parse
// error does ("plan.yaml:31: rotations: at most 3600").

#include <cstddef>
#include <optional>
#include <string>

#include "campaign/campaign_plan.h"
#include "vscan/common/status.h"

namespace vscan::cli {

// The server calls a plan's values travel in.
enum class PlanCall { kStartCampaign, kCreateScene, kAddObject, kSetRotaryTable, kMountRobot };

// "source:line: key.path: what" when status is the server's verdict on a field the plan sets
// through call (object: which scene.objects item, for kAddObject); nullopt for other failures
// (the server unreachable, an internal error, a message that names no field of the call).
std::optional<std::string> LocateInPlan(const CampaignPlan& plan, PlanCall call, const Status& status,
                                        size_t object = 0);

}  // namespace vscan::cli
