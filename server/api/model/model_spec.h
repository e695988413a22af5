#pragma once
// A ModelSpec checked and turned into a model plan: the contract's fields read into the service
// layer's request (presence, enums and id syntax checked here), then checked against what the
// server holds. Errors name "spec.<field>", so that a bad request creates no job.

#include "service/model/campaign_records.h"
#include "service/model/model_plan.h"
#include "service/context/service_context.h"
#include "vscan/v1/job.pb.h"
#include "vscan/v1/model.pb.h"

namespace vscan::api {

StatusOr<service::ModelRequest> ModelRequestFromProto(const v1::ModelSpec& spec);

// The model stages a campaign asks for (align, reconstruct, evaluate and their options).
StatusOr<service::ModelRequest> ModelRequestFromCampaign(const v1::CampaignSpec& spec);

StatusOr<service::ModelPlan> ValidateModel(const v1::ModelSpec& spec, service::ServiceContext& context,
                                           service::CampaignRecords& campaigns);

}  // namespace vscan::api
