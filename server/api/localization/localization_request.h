#pragma once
// LocalizeRequest and ScorePosesRequest checked against the contract (every error names its
// field) and turned into the service layer's plans.

#include "service/localization/localization_run.h"
#include "service/localization/localization_scoring.h"
#include "vscan/common/status.h"
#include "vscan/v1/localization.pb.h"

namespace vscan::api {

inline constexpr size_t kMaxInlinePoints = 131072;
inline constexpr uint32_t kMaxLocalizeInstances = 100;
inline constexpr int kMaxScoredParts = 64;
inline constexpr int kMaxScoredPoses = 10000;

StatusOr<service::LocalizePlan> ParseLocalizeRequest(const v1::LocalizeRequest& request);
StatusOr<service::ScoringPlan> ParseScorePosesRequest(const v1::ScorePosesRequest& request);

}  // namespace vscan::api
