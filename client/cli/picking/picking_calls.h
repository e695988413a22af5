#pragma once
// PickingService calls with the client's channel, token and deadlines.

#include "vscan/client/client.h"
#include "vscan/common/status.h"
#include "vscan/v1/picking.pb.h"

namespace vscan::cli {

StatusOr<v1::GenerateGraspsResponse> CallGenerateGrasps(const client::Client& client,
                                                        const v1::GenerateGraspsRequest& request);
// No deadline unless --timeout is given: inverse kinematics for every part can take seconds.
StatusOr<v1::CheckPicksResponse> CallCheckPicks(const client::Client& client, const v1::CheckPicksRequest& request);

}  // namespace vscan::cli
