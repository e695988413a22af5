#pragma once
// A CampaignSpec checked and turned into a campaign plan: every field checked up front (errors name
// "spec.<field>") so that a bad request creates no job.

#include "service/campaign/campaign_plan.h"
#include "service/context/service_context.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

// Checks the spec against the server's limits, the scene and the mount. validate_only (a dry run)
// skips the scene and mount checks when their ids are empty; every other check is the same.
StatusOr<service::CampaignPlan> ValidateCampaign(const v1::CampaignSpec& spec, service::ServiceContext& context,
                                        bool validate_only = false);

// Puts a field-naming error under the request field that holds the spec ("spec").
Status InSpec(const Status& status);

}  // namespace vscan::api
