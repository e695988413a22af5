#pragma once
// A bin fill's bin.json read back from the server and summed up in a few lines.

#include <optional>
#include <string>

#include <google/protobuf/struct.pb.h>

#include "session/context.h"

namespace vscan::cli {

// Sets *report to the job's parsed bin.json, or leaves it empty when the job has none. Returns an
// exit code (3 for a report that cannot be read or parsed).
int FetchBinReport(Context& ctx, const v1::Job& job, std::optional<google::protobuf::Struct>* report);

// "settled: 20 of 20 parts in the bin, 0 outside; 6.3 s simulated in 1512 steps ..." and the
// deepest overlaps, one line each.
std::string FormatBinReport(const google::protobuf::Struct& report);

}  // namespace vscan::cli
