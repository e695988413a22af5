#pragma once
// LocalizationService calls with the client's channel, token and deadlines.

#include <functional>

#include "vscan/client/client.h"
#include "vscan/common/status.h"
#include "vscan/v1/localization.pb.h"

namespace vscan::cli {

// No deadline unless --timeout is given: a search takes seconds per part instance.
StatusOr<v1::LocalizeResponse> CallLocalize(const client::Client& client, const v1::LocalizeRequest& request);
// The same through LocalizeWithProgress: on_progress gets each progress update as it comes.
StatusOr<v1::LocalizeResponse> CallLocalizeWithProgress(
    const client::Client& client, const v1::LocalizeRequest& request,
    const std::function<void(const v1::LocalizeProgress&)>& on_progress);
StatusOr<v1::ScorePosesResponse> CallScorePoses(const client::Client& client, const v1::ScorePosesRequest& request);

}  // namespace vscan::cli
