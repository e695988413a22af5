#pragma once
// Reads a job's artifacts (model.json, or any by name) from the server.

#include <optional>
#include <string>
#include <string_view>

#include "session/context.h"
#include "vscan/v1/reports.pb.h"

namespace vscan::cli {

// Sets *text to the bytes of the job's artifact called name, or leaves it empty when the job has
// none. Returns an exit code (3 when the server cannot send it).
int FetchArtifactText(Context& ctx, const v1::Job& job, std::string_view name, std::optional<std::string>* text);

// Sets *report to the job's parsed model.json, or leaves it empty when the job has none. Returns
// an exit code (3 for a report that cannot be read or parsed).
int FetchModelReport(Context& ctx, const v1::Job& job, std::optional<v1::ModelReport>* report);

}  // namespace vscan::cli
