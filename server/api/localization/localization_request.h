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
// Each part's pair table may take up to 144 MiB while the search runs.
inline constexpr size_t kMaxLocalizeParts = 16;
// Over all parts of one request: a search's work grows with the instances it may accept.
inline constexpr size_t kMaxLocalizeTotalInstances = 200;
inline constexpr int kMaxScoredParts = 64;
inline constexpr int kMaxScoredPoses = 10000;

// The single-part form (mesh_id, scale) becomes one part; parts are checked one by one, then for
// repeats (the same mesh at the same scale) and for their instances added up.
StatusOr<service::LocalizePlan> ParseLocalizeRequest(const v1::LocalizeRequest& request);
StatusOr<service::ScoringPlan> ParseScorePosesRequest(const v1::ScorePosesRequest& request);

}  // namespace vscan::api
