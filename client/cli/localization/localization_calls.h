#pragma once
// LocalizationService calls with the client's channel, token and deadlines.

#include "vscan/client/client.h"
#include "vscan/common/status.h"
#include "vscan/v1/localization.pb.h"

namespace vscan::cli {

// No deadline unless --timeout is given: a search takes seconds per part instance.
StatusOr<v1::LocalizeResponse> CallLocalize(const client::Client& client, const v1::LocalizeRequest& request);
StatusOr<v1::ScorePosesResponse> CallScorePoses(const client::Client& client, const v1::ScorePosesRequest& request);

}  // namespace vscan::cli
