#pragma once
// A BinFillSpec checked and turned into a bin fill plan: values checked here (errors name
// "spec.<field>"), the scene and the meshes by the service, so that a bad request creates no job.

#include "service/bins/bin_fill_plan.h"
#include "service/context/service_context.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

// validate_only accepts empty ids (a plan checked before its scene and meshes exist).
StatusOr<service::BinFillRequest> BinFillRequestFromProto(const v1::BinFillSpec& spec, bool validate_only);

// validate_only skips the scene and the meshes whose ids are empty; the ids given are looked up.
StatusOr<service::BinFillPlan> ValidateBinFill(const v1::BinFillSpec& spec, service::ServiceContext& context,
                                               bool validate_only);

}  // namespace vscan::api
