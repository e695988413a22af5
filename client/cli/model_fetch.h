#pragma once
// Reads a job's model.json from the server.

#include <optional>

#include <google/protobuf/struct.pb.h>

#include "context.h"

namespace vscan::cli {

// Sets *report to the job's parsed model.json, or leaves it empty when the job has none. Returns
// an exit code (3 for a report that cannot be read or parsed).
int FetchModelReport(Context& ctx, const v1::Job& job, std::optional<google::protobuf::Struct>* report);

}  // namespace vscan::cli
