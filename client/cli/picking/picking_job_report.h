#pragma once
// A picking job's picking.json read back from the server (into its message PickingReport,
// proto/vscan/v1/reports.proto) and summed up in a line.

#include <optional>
#include <string>

#include "session/context.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::cli {

// Sets *report to the job's parsed picking.json, or leaves it empty when the job has none. Returns
// an exit code (3 for a report that cannot be read or parsed).
int FetchPickingReport(Context& ctx, const v1::Job& job, std::optional<v1::PickingReport>* report);

// "5 of 8 parts picked in 7 steps: 5 picked, 1 collision, 1 nothing pickable; end: nothing pickable".
std::string FormatPickingReport(const v1::PickingReport& report);

}  // namespace vscan::cli
